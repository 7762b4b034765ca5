/* One case of a sweep, run in this process (a forked worker or an MPI rank): the case built from
 * the sweep's base and the run's axis values, its record and JSON written as `voussoir run`
 * writes them, and its summary row taken from the run itself (no output is read back). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "collapse_at.h"
#include "pipe_io.h"
#include "sweep_private.h"
#include "outpath.h"
#include "voussoir/output.h"
#include "voussoir/quasistatic.h"
#include "voussoir/report.h"
#include "voussoir/run.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

void vs_sweep_pick(const vs_sweep_job *job, int run, int *pick) {
  for (int x = job->nax - 1, rem = run - 1; x >= 0; x--) {
    pick[x] = rem % job->ax[x].n;
    rem /= job->ax[x].n;
  }
}

/* The case of run `run`: the base, every axis's value, then the mode; validated. */
static vs_status build_case(const vs_sweep_job *job, int run, vs_sweep_row *row, vs_case *c,
                            vs_error *err) {
  int pick[VS_SWEEP_MAX_AXES];
  vs_sweep_pick(job, run, pick);
  *c = *job->base;
  vs_status st = VS_OK;
  for (int x = 0; x < job->nax && st == VS_OK; x++) {
    char set[160];
    row->axis[x] = job->ax[x].v[pick[x]];
    snprintf(set, sizeof set, "%.95s=%.17g", job->ax[x].key, row->axis[x]);
    st = vs_case_set(c, set, err);
  }
  if (st == VS_OK && job->mode_set != NULL) st = vs_case_set(c, job->mode_set, err);
  return st == VS_OK ? vs_case_validate(c, err) : st;
}

/* The results of a run that ended with status st, into the row (as its JSON reports them). */
static void fill_row(const vs_run *r, vs_status st, const vs_error *err, vs_sweep_row *row) {
  const vs_case *c = vs_run_case(r);
  const vs_collapse_record *col = vs_run_collapse(r);
  const vs_path_result *p = vs_run_path(r);
  const char *status = st == VS_ERR_WALL_TIME                               ? "stopped"
                       : st != VS_OK                                          ? "failed"
                       : col->found                                           ? "collapse"
                       : !c->follow && !c->full && vs_run_limit_count(r) > 0 ? "limit_point"
                                                                             : "max_displacement";
  snprintf(row->status, sizeof row->status, "%s", status);
  const vs_run_load_result *ld = vs_run_load(r);
  if (ld->done) { /* the load path: its status, load factor and mechanism, as its JSON's */
    if (st == VS_OK)
      snprintf(row->status, sizeof row->status, "%s",
               ld->held_limit ? "limit_point"
               : ld->end == VS_LOAD_END_PEAK || ld->end == VS_LOAD_END_SLIDING
                   ? "collapse"
                   : "max_displacement");
    row->load_factor = ld->load_factor;
    snprintf(row->hinges, sizeof row->hinges, "%s", ld->mechanism);
  }
  if (st != VS_OK) snprintf(row->error, sizeof row->error, "%s", err->msg);
  if (p->end == VS_PATH_LIMIT_POINT && vs_run_limit_count(r) > 0)
    row->first_limit_mm = p->delta_limit / VS_MM;
  if (col->found) {
    double t[4];
    row->delta_u_mm = col->delta / VS_MM;
    vs_study_travel(r, col->delta, t);
    row->left_dx_mm = t[0];
    row->left_dz_mm = t[1];
    row->right_dx_mm = t[2];
    row->right_dz_mm = t[3];
    vs_study_components_pct(r, col->delta, &row->dz_pct, &row->dx_pct);
    vs_hinges_list(col->hinges, col->n_hinges, 0, row->hinges, sizeof row->hinges);
  }
  const char *mode = vs_run_mode(r);
  snprintf(row->mode, sizeof row->mode, "%s", mode != NULL ? mode : "");
  for (int i = 0; i < vs_run_limit_count(r); i++) {
    const vs_limit_record *l = vs_run_limit(r, i);
    row->snaps += !l->collapse && isfinite(l->delta_settled);
  }
  row->wall_s = vs_run_wall_s(r);
  const vs_run_event *fc = row->mortared ? vs_run_first_crack(r) : NULL;
  if (fc != NULL) {
    row->first_crack_mm = fc->delta / VS_MM;
    row->first_crack_joint = fc->joint;
    row->first_crack_side[0] = fc->side;
  }
}

/* The run's JSON, as `voussoir run --json` prints it, into path (created anew). VS_OK, or the
 * reason in why. */
static vs_status write_json(const char *path, const vs_run *r, vs_status st, const vs_error *err,
                            const char *case_path, vs_error *why) {
  FILE *f;
  const vs_status s = vs_outpath_fopen(path, &f, why);
  if (s != VS_OK) return s;
  vs_report_json(f, r, st, err, case_path);
  if (fclose(f) == 0) return VS_OK;
  return vs_error_set(why, VS_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
}

/* A sweep run's XDMF sidecar lists at most this many of its states (every k-th and the last; a
 * `voussoir run` record's lists 2000): writing the sidecar's XML was 14 % of the seed domain's
 * CPU, and an animation of a case among many needs no more frames. With the NaN padding by
 * reference (/xdmf/nan), listing up to 2000 still writes 171 MB of XML for the domain instead of
 * 57 MB and adds 6 % to its CPU (each state's 54 HDF references, not the padding, dominate). */
static const int VS_SWEEP_XDMF_GRIDS = 200;

/* Execute r into its record (created at h5), closing the record with the run's status.
 * *started becomes 0 when the record could not be created: nothing of the case ran. */
static vs_status execute(const vs_sweep_job *job, int run, vs_run *r, const char *h5,
                         const volatile sig_atomic_t *stop, int *h5_clean, int *started,
                         vs_error *err) {
  vs_output *rec = NULL;
  vs_output_opts opts;
  vs_output_opts_default(&opts);
  opts.xdmf_max_grids = VS_SWEEP_XDMF_GRIDS;
  vs_status st = vs_output_create(h5, r, job->case_text, &opts, &rec, err);
  if (st != VS_OK) {
    if (st == VS_ERR_IO) *h5_clean = 0;
    *started = 0;
    return st;
  }
  vs_fault_hold(run, stop); /* tests only */
  st = vs_run_execute(r, vs_output_sample, vs_output_event, rec, err);
  if (st != VS_OK && stop != NULL && *stop) {
    st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
    vs_output_interrupt(rec);
  }
  if (st != VS_OK && vs_output_error(rec)->status != VS_OK) {
    *err = *vs_output_error(rec); /* the run stopped because the record failed: */
    st = err->status;             /* that is the run's status, not VS_ERR_STOPPED */
  }
  vs_error oerr;
  vs_error_clear(&oerr);
  if (vs_output_finish(rec, r, st, err, &oerr) != VS_OK && st == VS_OK) {
    *err = oerr;
    st = oerr.status;
  }
  if (vs_output_error(rec)->status != VS_OK) *h5_clean = 0;
  vs_output_destroy(&rec);
  return st;
}

void vs_sweep_run_case(const vs_sweep_job *job, int run, const volatile sig_atomic_t *stop,
                       vs_sweep_row *row, int *h5_clean) {
  memset(row, 0, sizeof *row);
  row->run = run;
  row->first_limit_mm = row->delta_u_mm = row->dz_pct = row->dx_pct = row->wall_s = NAN;
  row->left_dx_mm = row->left_dz_mm = row->right_dx_mm = row->right_dz_mm = NAN;
  row->load_factor = row->first_crack_mm = NAN;
  char h5[1100], json[1100];
  snprintf(h5, sizeof h5, "%s/run_%04d.h5", job->dir, run);
  snprintf(json, sizeof json, "%s/run_%04d.json.part", job->dir, run);
  vs_case c;
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  vs_status st = build_case(job, run, row, &c, &err);
  row->mortared = c.tensile_MPa > 0.0 || c.cohesion_MPa > 0.0;
  if (st == VS_OK) st = vs_run_create(&c, &r, &err);
  int started = st != VS_ERR_NOMEM; /* out of memory says nothing of the case */
  if (st == VS_OK) {
    vs_run_set_stop(r, stop);
    st = stop != NULL && *stop ? vs_error_set(&err, VS_ERR_INTERRUPTED, "interrupted")
                               : execute(job, run, r, h5, stop, h5_clean, &started, &err);
  }
  /* a run stopped by its wall-time limit is over (journalled, not run again by --resume): it
   * counts as failed, its row says "stopped" */
  row->code = !started ? VS_SWEEP_NOT_STARTED
              : st == VS_OK ? VS_SWEEP_OK
              : st == VS_ERR_INTERRUPTED ? VS_SWEEP_INTERRUPTED : VS_SWEEP_FAILED;
  if (r == NULL || !started) { /* no run (the case itself was refused), or it could not start */
    snprintf(row->status, sizeof row->status, "%s", started ? "failed" : "not_started");
    snprintf(row->error, sizeof row->error, "%s", err.msg);
    vs_run_destroy(&r);
    return;
  }
  fill_row(r, st, &err, row);
  vs_error why;
  if (row->code != VS_SWEEP_INTERRUPTED &&
      write_json(json, r, st, &err, job->case_path, &why) != VS_OK) {
    row->code = VS_SWEEP_FAILED;
    snprintf(row->status, sizeof row->status, "failed");
    snprintf(row->error, sizeof row->error, "%s", why.msg);
  }
  vs_run_destroy(&r);
}
