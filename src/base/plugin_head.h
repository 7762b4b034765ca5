/* What every plugin library's table starts with (the record, plot and MPI libraries that the
 * program loads with dlopen: src/plugin/plugin.h): the interface number and the version of its
 * build, which the program checks before it calls anything in the table. */
#ifndef VS_PLUGIN_HEAD_H
#define VS_PLUGIN_HEAD_H

/* Bumped whenever a table (record_plugin.h, plot_plugin.h, mpi_plugin.h) changes. */
#define VS_PLUGIN_ABI 6

typedef struct {
  int abi;             /* VS_PLUGIN_ABI */
  const char *version; /* VS_VERSION of its build */
} vs_plugin_head;

/* The table is the one symbol a plugin exports beyond its API. */
#define VS_PLUGIN_TABLE __attribute__((visibility("default")))

#endif
