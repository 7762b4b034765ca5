/* The program's plugins (private to the program and its plugin libraries). The voussoir
 * program links only the core library (libvoussoir: the model, the solvers, the run); what
 * needs HDF5, cairo or MPI lives in more libraries that the program loads with dlopen only when a
 * command needs them, so that `voussoir --version` or `voussoir run CASE --no-record` never load
 * HDF5 (and curl, ssl, krb5, ldap with it), cairo or Open MPI:
 *   libvoussoir-record.so.4  the HDF5 record (writer, sidecar) and a sweep's summary.h5;
 *   libvoussoir-plot.so.4    pictures (cairo), the plot command, a Monte Carlo summary; it
 *                            needs the record library (the program loads that first);
 *   libvoussoir-mpi.so.4     sweep and montecarlo across the ranks of an MPI job (only in a
 *                            build with MPI; loaded when the process was started by mpirun).
 * They are ordinary shared libraries, installed next to libvoussoir (library users link them
 * like any other: pkg-config voussoir lists them). The program finds them in the directory its
 * libvoussoir was loaded from. Each exports one symbol, a table of function pointers (below),
 * found with one dlsym and checked against the program's interface number and version.
 *
 * The tables: record_plugin.h, plot_plugin.h, mpi_plugin.h (each in its library's folder).
 * In the program, src/plugin/plugin_calls.c defines every function of these tables under its usual
 * name (vs_output_create, ...; hidden, never exported) forwarding to the loaded table, so the
 * commands call the record API as library users do. */
#ifndef VS_PLUGIN_H
#define VS_PLUGIN_H

#include "mpi_plugin.h"
#include "plot_plugin.h"
#include "record_plugin.h"

/* --- in the program (src/plugin/plugin.c) --- */

typedef enum { VS_PLUGIN_RECORD = 0, VS_PLUGIN_PLOT = 1, VS_PLUGIN_MPI = 2 } vs_plugin_kind;

/* Load plugin `kind` unless it is loaded (the plot plugin loads the record plugin first); the
 * record plugin's HDF5 is then set up (vs_output_process_init). 0, or VS_EXIT_FAILED after
 * printing "NAME: cannot load FILE (what it is for): the reason" (a missing file, not a
 * library, no table, another interface or version; the MPI plugin in a build without MPI). */
int vs_plugin_load(vs_plugin_kind kind, const char *name);

/* The loaded tables, or NULL. */
const vs_record_plugin *vs_plugin_record(void);
const vs_plot_plugin *vs_plugin_plot(void);
const vs_mpi_plugin *vs_plugin_mpi(void);

/* Whether this process was started by mpirun (its environment says so): the sweep and the
 * montecarlo then run across the ranks (the MPI plugin). */
int vs_plugin_mpi_launched(void);

/* Before the process exits: HDF5 shut down (vs_output_process_end(h5_clean)) if the record
 * plugin was loaded. The libraries stay loaded until the process ends. */
void vs_plugin_end(int h5_clean);

#endif
