/* The program's plugins (private to the program and its plugin libraries). The voussoir
 * program links only the core library (libvoussoir: the model, the solvers, the run); what
 * needs HDF5, cairo or MPI lives in more libraries that the program loads with dlopen only when a
 * command needs them, so that `voussoir --version` or `voussoir run CASE --no-record` never load
 * HDF5 (and curl, ssl, krb5, ldap with it), cairo or Open MPI:
 *   libvoussoir-record.so.0  the HDF5 record (writer, sidecar) and a sweep's summary.h5;
 *   libvoussoir-plot.so.0    pictures (cairo), the plot command, a Monte Carlo summary; it
 *                            needs the record library (the program loads that first);
 *   libvoussoir-mpi.so.0     sweep and montecarlo across the ranks of an MPI job (only in a
 *                            build with MPI; loaded when the process was started by mpirun).
 * They are ordinary shared libraries, installed next to libvoussoir (library users link them
 * like any other: pkg-config voussoir lists them). The program finds them in the directory its
 * libvoussoir was loaded from. Each exports one symbol, a table of function pointers (below),
 * found with one dlsym and checked against the program's interface number and version.
 *
 * In the program, src/plugin_calls.c defines every function of these tables under its usual
 * name (vs_output_create, ...; hidden, never exported) forwarding to the loaded table, so the
 * commands call the record API as library users do. */
#ifndef VS_PLUGIN_H
#define VS_PLUGIN_H

#include "montecarlo_mpi.h"
#include "sweep_private.h"
#include "voussoir/montecarlo.h"
#include "voussoir/output.h"

/* Bumped whenever a table below changes. */
#define VS_PLUGIN_ABI 4

/* What every table starts with. */
typedef struct {
  int abi;             /* VS_PLUGIN_ABI */
  const char *version; /* VS_VERSION of its build */
} vs_plugin_head;

/* libvoussoir-record: exported as vs_record_plugin_table. */
typedef struct {
  vs_plugin_head head;
  void (*output_opts_default)(vs_output_opts *o);
  vs_status (*output_create)(const char *path, const vs_run *run, const char *case_text,
                             const vs_output_opts *opts, vs_output **out, vs_error *err);
  int (*output_sample)(void *user, const vs_run *run, const vs_run_sample *s);
  int (*output_event)(void *user, const vs_run *run, const vs_run_event *e);
  void (*output_interrupt)(vs_output *o);
  vs_status (*output_finish)(vs_output *o, const vs_run *run, vs_status run_status,
                             const vs_error *run_err, vs_error *err);
  const vs_error *(*output_error)(const vs_output *o);
  long (*output_rows)(const vs_output *o);
  const char *(*output_xdmf_path)(const vs_output *o);
  int (*output_xdmf_written)(const vs_output *o);
  char *(*output_xdmf_path_for)(const char *h5_path);
  void (*output_destroy)(vs_output **o);
  void (*output_process_init)(void);
  void (*output_process_end)(int clean);
  vs_status (*sweep_summary_h5)(const char *dir, const vs_sweep_axis *ax, int nax,
                                const vs_sweep_row *rows, int n, vs_error *err);
} vs_record_plugin;

/* libvoussoir-plot: exported as vs_plot_plugin_table. */
typedef struct {
  vs_plugin_head head;
  /* the plot command's work: the pictures of a record or of a sweep's summary.h5 into dir
   * (ext "png" or "svg"); an exit status */
  int (*plot_command)(const char *record, const char *dir, const char *ext);
  vs_status (*mc_write_summary)(const char *dir, const vs_case *base, vs_mc_sample *samples,
                                int n, vs_error *err);
  void (*plot_release)(void);
} vs_plot_plugin;

/* libvoussoir-mpi: exported as vs_mpi_plugin_table (montecarlo_mpi.h, sweep_private.h). */
typedef struct {
  vs_plugin_head head;
  int (*mc_run)(const vs_case *c, const vs_mc_server *s, int *opened, int *ranks);
  int (*sweep_begin)(int *size);
  void (*sweep_serve)(const vs_sweep_server *s, int size);
  void (*sweep_work)(const vs_sweep_job *job, vs_sweep_case_fn run_case,
                     const volatile sig_atomic_t *stop, int *h5_clean);
  void (*sweep_end)(void);
} vs_mpi_plugin;

/* The summary table of a sweep as DIR/summary.h5 (src/sweep_summary.c, in the record library).
 * Errors: VS_ERR_INVALID (something other than a regular file in the way), VS_ERR_IO,
 * VS_ERR_NOMEM, the path in err. */
vs_status vs_sweep_summary_h5(const char *dir, const vs_sweep_axis *ax, int nax,
                              const vs_sweep_row *rows, int n, vs_error *err);

/* The plot command's work (src/plot_cmd.c, in the plot library), as in vs_plot_plugin. */
int vs_plot_command(const char *record, const char *dir, const char *ext);

/* --- in the program (src/plugin.c) --- */

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
