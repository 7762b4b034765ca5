/* The live load's path of a run (analysis.type = load, issue 28): the load of the definition
 * (load.*) put on the model as forces, and, once the support has been moved to analysis.hold
 * and held (run.c), the load factor raised to collapse through its peak (vs_load_path_run),
 * each equilibrium tracked and recorded as the support's path's are, the load-deflection curve
 * kept. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"
#include "voussoir/limit.h"
#include "voussoir/quasistatic.h"

/* The limit analysis' forces lf[0..n) (freed here) on the model: its live loads, or (dead) its
 * dead loads. */
static vs_status model_forces(vs_run *r, vs_limit_force *lf, int n, int dead, vs_error *err) {
  vs_status st = VS_OK;
  vs_model_force *f = malloc((size_t)(n > 0 ? n : 1) * sizeof *f);
  if (f == NULL) {
    free(lf);
    return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  }
  for (int i = 0; i < n; i++)
    f[i] = (vs_model_force){.block = lf[i].block, .fx = lf[i].fx, .fz = lf[i].fz, .px = lf[i].px,
                            .pz = lf[i].pz};
  st = dead ? vs_model_set_dead_loads(r->m, f, n, err) : vs_model_set_loads(r->m, f, n, err);
  free(f);
  free(lf);
  return st;
}

vs_status vs_run_load_setup(vs_run *r, vs_error *err) {
  const vs_run_def *d = &r->def;
  vs_limit_force *lf = NULL;
  int n = 0;
  vs_status st = vs_limit_fill_load(r->g, &d->fill, &lf, &n, err); /* every analysis */
  if (st == VS_OK && n > 0) st = model_forces(r, lf, n, 1, err);
  else free(lf);
  if (st != VS_OK || d->analysis.type != VS_ANALYSIS_LOAD) return st;
  st = vs_limit_live_load(r->g, &d->load, &d->fill, &lf, &n, err);
  return st == VS_OK ? model_forces(r, lf, n, 0, err) : st;
}

void vs_run_load_free(vs_run *r) {
  vs_limit_analysis_free(&r->held_la);
  free(r->load_lambda);
  free(r->load_u);
  r->load_lambda = r->load_u = NULL;
}

/* One equilibrium of the load path: the curve grows by it; hinges, slips and the sample as on
 * the support's path, at the held support displacement. */
static int on_load_step(void *user, double lambda, double u, const double *q, const vs_model *m) {
  vs_run *r = user;
  vs_run_load_result *l = &r->load;
  if (l->n == r->cap_load) {
    const int cap = r->cap_load ? 2 * r->cap_load : 64;
    double *a = realloc(r->load_lambda, (size_t)cap * sizeof *a);
    if (a == NULL) return vs_run_out_of_memory(r);
    r->load_lambda = a;
    double *b = realloc(r->load_u, (size_t)cap * sizeof *b);
    if (b == NULL) return vs_run_out_of_memory(r);
    r->load_u = b;
    r->cap_load = cap;
  }
  r->load_lambda[l->n] = lambda;
  r->load_u[l->n] = u - r->load_u0;
  l->n++;
  l->lambda = r->load_lambda;
  l->u = r->load_u;
  r->load_now = lambda;
  const int stop = vs_run_on_equilibrium(r, l->hold, q, m);
  /* the mechanism: the hinges open where lambda has first fallen by VS_LOAD_DROP from its
   * largest value so far (later, the mechanism's motion opens more) */
  if (lambda > r->load_best) {
    r->load_best = lambda;
    r->load_taken = 0;
  } else if (!r->load_taken && lambda < (1.0 - VS_LOAD_DROP) * r->load_best) {
    vs_run_open_hinges(r, l->mechanism, sizeof l->mechanism);
    r->load_taken = 1;
  }
  return stop;
}

vs_status vs_run_load_path(vs_run *r, vs_error *err) {
  vs_run_load_result *l = &r->load;
  l->hold = r->delta; /* where the support's path stopped: analysis.hold */
  vs_load_opts o;
  vs_load_opts_from_def(&r->def, &o);
  o.stop = r->popts.stop;
  o.deadline = &r->deadline;
  r->load_u0 = vs_model_load_displacement(r->m, r->q);
  /* the curve starts at lambda = 0, the state held */
  if (on_load_step(r, 0.0, r->load_u0, r->q, r->m) != 0)
    return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  vs_load_result res;
  vs_status st = vs_load_path_run(r->m, &o, l->hold, r->q, on_load_step, r, &res, err);
  r->load_res = res;
  l->end = (int)res.end;
  l->load_factor = res.lambda_peak;
  l->deflection = res.u_peak - r->load_u0;
  l->first_peak = res.lambda_first;
  l->steps = res.steps;
  l->rejected = res.rejected;
  l->newton_iterations = res.newton_iterations;
  l->jacobian_evals = res.jacobian_evals;
  l->snap_back = isfinite(res.arc_from);
  snprintf(l->cause, sizeof l->cause, "%s", res.cause);
  if (!r->load_taken) vs_run_open_hinges(r, l->mechanism, sizeof l->mechanism);
  r->load_now = res.lambda_peak;
  if (st == VS_OK && (res.end == VS_LOAD_END_PEAK || res.end == VS_LOAD_END_SLIDING) &&
      vs_run_log_event(r, VS_EVENT_COLLAPSE, r->t, r->delta, 0, 0, 0, 0) != 0)
    st = vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  r->load_now = NAN;
  return st;
}

const vs_run_load_result *vs_run_load(const vs_run *r) { return &r->load; }

void vs_run_limit_at_hold(vs_run *r) {
  double qs[6];
  const int nj = r->g->n_joints;
  vs_model_support_position(r->m, r->q, r->delta, qs);
  vs_error_clear(&r->held_la_err);
  r->held_la_done = 1;
  double *gap = malloc(2 * (size_t)nj * sizeof *gap);
  if (gap == NULL) {
    r->held_la_st = vs_error_set(&r->held_la_err, VS_ERR_NOMEM, "run: out of memory");
    return;
  }
  vs_model_joint_states(r->m, r->q, r->delta, r->js);
  for (int k = 0; k < nj; k++) gap[2 * k] = r->js[k].gap_i, gap[2 * k + 1] = r->js[k].gap_e;
  r->held_la_st =
      vs_limit_analyse_moved(&r->def, r->g, r->q, qs, gap, NULL, &r->held_la, &r->held_la_err);
  free(gap);
}

const vs_limit_analysis *vs_run_limit_held(const vs_run *r, vs_status *status,
                                           const vs_error **err) {
  if (!r->held_la_done) return NULL;
  if (status != NULL) *status = r->held_la_st;
  if (err != NULL) *err = &r->held_la_err;
  return &r->held_la;
}
