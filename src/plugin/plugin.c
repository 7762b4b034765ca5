/* Loading the program's plugins (src/plugin/plugin.h): dlopen of libvoussoir-record, libvoussoir-plot
 * or libvoussoir-mpi from the directory the core library was loaded from, one dlsym for the
 * table, checks. */
#define _GNU_SOURCE /* dlinfo */
#include <dlfcn.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "exit_status.h"
#include "plugin.h"
#include "voussoir/version.h"

#ifndef VS_CORE_LIB_FILE
#error "VS_CORE_LIB_FILE (the core library's file name, its soname) must be defined"
#endif
#ifndef VS_RECORD_PLUGIN_FILE
#error "VS_RECORD_PLUGIN_FILE (the record plugin's file name) must be defined"
#endif
#ifndef VS_PLOT_PLUGIN_FILE
#error "VS_PLOT_PLUGIN_FILE (the plot plugin's file name) must be defined"
#endif
#ifndef VS_MPI_PLUGIN_FILE /* a build without MPI: no such plugin */
#define VS_MPI_PLUGIN_FILE NULL
#endif

/* The loaded tables. Process state because dlopen is: the forwarding functions of
 * src/plugin/plugin_calls.c have the record API's signatures, without a handle to pass them. */
static const vs_record_plugin *g_record = NULL;
static const vs_plot_plugin *g_plot = NULL;
static const vs_mpi_plugin *g_mpi = NULL;

const vs_record_plugin *vs_plugin_record(void) { return g_record; }
const vs_plot_plugin *vs_plugin_plot(void) { return g_plot; }
const vs_mpi_plugin *vs_plugin_mpi(void) { return g_mpi; }

int vs_plugin_mpi_launched(void) {
  const char *vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"};
  for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
    if (getenv(vars[i]) != NULL) return 1;
  return 0;
}

typedef struct {
  const char *file, *symbol, *what;
  int global; /* RTLD_GLOBAL: Open MPI's own components look up its symbols */
} plugin_info;

static const plugin_info PLUGINS[] = {
    {VS_RECORD_PLUGIN_FILE, "vs_record_plugin_table", "the HDF5 record", 0},
    {VS_PLOT_PLUGIN_FILE, "vs_plot_plugin_table", "pictures", 0},
    {VS_MPI_PLUGIN_FILE, "vs_mpi_plugin_table", "MPI ranks", 1},
};

/* DIR/file where DIR holds the core library this program runs with (found by its soname among
 * the loaded objects). */
static void plugin_path(const char *file, char *buf, size_t size) {
  char dir[PATH_MAX] = "";
  void *core = dlopen(VS_CORE_LIB_FILE, RTLD_LAZY | RTLD_NOLOAD);
  if (core != NULL) {
    if (dlinfo(core, RTLD_DI_ORIGIN, dir) != 0) dir[0] = '\0';
    dlclose(core); /* drops the reference just taken; the library stays */
  }
  if (dir[0] != '\0') snprintf(buf, size, "%s/%s", dir, file);
  else snprintf(buf, size, "%s", file); /* the dynamic linker's search path */
}

/* Open and check one plugin; its table, or NULL after printing why. */
static const vs_plugin_head *open_plugin(const plugin_info *p, const char *name) {
  char path[4096];
  plugin_path(p->file, path, sizeof path);
  void *h = dlopen(path, RTLD_NOW | (p->global ? RTLD_GLOBAL : RTLD_LOCAL));
  if (h == NULL) {
    fprintf(stderr, "%s: cannot load %s (%s): %s\n", name, path, p->what, dlerror());
    return NULL;
  }
  const vs_plugin_head *t = dlsym(h, p->symbol); /* every table starts with its head */
  if (t == NULL) {
    fprintf(stderr, "%s: cannot load %s (%s): no %s: not a voussoir plugin\n", name, path, p->what,
            p->symbol);
  } else if (t->abi != VS_PLUGIN_ABI || strcmp(t->version, VS_VERSION) != 0) {
    fprintf(stderr, "%s: cannot load %s (%s): it is voussoir %s (plugin interface %d), the "
                    "program is %s (interface %d)\n",
            name, path, p->what, t->version, t->abi, VS_VERSION, VS_PLUGIN_ABI);
    t = NULL;
  }
  if (t == NULL) dlclose(h);
  return t; /* the library stays loaded until the process ends */
}

int vs_plugin_load(vs_plugin_kind kind, const char *name) {
  if (kind == VS_PLUGIN_MPI) {
    if (g_mpi != NULL) return 0;
    if (PLUGINS[VS_PLUGIN_MPI].file == NULL) {
      fprintf(stderr, "%s: started by mpirun, but this voussoir was built without MPI\n", name);
      return VS_EXIT_FAILED;
    }
    g_mpi = (const vs_mpi_plugin *)open_plugin(&PLUGINS[VS_PLUGIN_MPI], name);
    return g_mpi != NULL ? 0 : VS_EXIT_FAILED;
  }
  if (g_record == NULL) {
    g_record = (const vs_record_plugin *)open_plugin(&PLUGINS[VS_PLUGIN_RECORD], name);
    if (g_record == NULL) return VS_EXIT_FAILED;
    g_record->output_process_init();
  }
  if (kind == VS_PLUGIN_PLOT && g_plot == NULL) {
    g_plot = (const vs_plot_plugin *)open_plugin(&PLUGINS[VS_PLUGIN_PLOT], name);
    if (g_plot == NULL) return VS_EXIT_FAILED;
  }
  return 0;
}

void vs_plugin_end(int h5_clean) {
  if (g_record != NULL) g_record->output_process_end(h5_clean);
}
