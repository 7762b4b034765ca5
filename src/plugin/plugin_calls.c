/* In the program: the plugins' functions under their usual names, each forwarding to the loaded
 * table (src/plugin/plugin.h; the MPI plugin's only when a build with MPI compiles the calls). The
 * program is built with hidden visibility, so these never take the place of a plugin's own
 * functions. A command loads its plugin (vs_plugin_load) before it calls
 * any of them; a call without it is a bug of the program and aborts. */
#include <stdio.h>
#include <stdlib.h>

#include "plugin.h"
#include "voussoir/plot.h"

static const vs_record_plugin *rec(void) {
  const vs_record_plugin *t = vs_plugin_record();
  if (t == NULL) {
    fputs("voussoir: internal error: the record plugin is used before it is loaded\n", stderr);
    abort();
  }
  return t;
}

static const vs_plot_plugin *plot(void) {
  const vs_plot_plugin *t = vs_plugin_plot();
  if (t == NULL) {
    fputs("voussoir: internal error: the plot plugin is used before it is loaded\n", stderr);
    abort();
  }
  return t;
}

void vs_output_opts_default(vs_output_opts *o) { rec()->output_opts_default(o); }

vs_status vs_output_create(const char *path, const vs_run *run, const char *case_text,
                           const vs_output_opts *opts, vs_output **out, vs_error *err) {
  return rec()->output_create(path, run, case_text, opts, out, err);
}

int vs_output_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  return rec()->output_sample(user, run, s);
}

int vs_output_event(void *user, const vs_run *run, const vs_run_event *e) {
  return rec()->output_event(user, run, e);
}

void vs_output_interrupt(vs_output *o) {
  if (o != NULL) rec()->output_interrupt(o);
}

vs_status vs_output_finish(vs_output *o, const vs_run *run, vs_status run_status,
                           const vs_error *run_err, vs_error *err) {
  return rec()->output_finish(o, run, run_status, run_err, err);
}

const vs_error *vs_output_error(const vs_output *o) { return rec()->output_error(o); }

long vs_output_rows(const vs_output *o) { return rec()->output_rows(o); }

const char *vs_output_xdmf_path(const vs_output *o) { return rec()->output_xdmf_path(o); }

int vs_output_xdmf_written(const vs_output *o) { return rec()->output_xdmf_written(o); }

char *vs_output_xdmf_path_for(const char *h5_path) { return rec()->output_xdmf_path_for(h5_path); }

void vs_output_destroy(vs_output **o) {
  if (o != NULL && *o != NULL) rec()->output_destroy(o);
}

vs_status vs_sweep_summary_h5(const char *dir, const vs_sweep_axis *ax, int nax,
                              const vs_sweep_row *rows, int n, vs_error *err) {
  return rec()->sweep_summary_h5(dir, ax, nax, rows, n, err);
}

vs_status vs_mc_write_summary(const char *dir, const vs_case *c, vs_mc_sample *s, int n,
                              vs_error *err) {
  return plot()->mc_write_summary(dir, c, s, n, err);
}

void vs_plot_release(void) {
  if (vs_plugin_plot() != NULL) vs_plugin_plot()->plot_release();
}

static const vs_mpi_plugin *mpi(void) {
  const vs_mpi_plugin *t = vs_plugin_mpi();
  if (t == NULL) {
    fputs("voussoir: internal error: the MPI plugin is used before it is loaded\n", stderr);
    abort();
  }
  return t;
}

int vs_mc_run_mpi(const vs_case *c, const vs_mc_server *s, int *opened, int *ranks) {
  return mpi()->mc_run(c, s, opened, ranks);
}

int vs_sweep_mpi_begin(int *size) { return mpi()->sweep_begin(size); }

void vs_sweep_mpi_serve(const vs_sweep_server *s, int size) { mpi()->sweep_serve(s, size); }

void vs_sweep_mpi_work(const void *job, vs_sweep_case_fn run_case,
                       const volatile sig_atomic_t *stop, int *h5_clean) {
  mpi()->sweep_work(job, run_case, stop, h5_clean);
}

void vs_sweep_mpi_end(void) { mpi()->sweep_end(); }
