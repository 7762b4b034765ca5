/* Quasi-static path following (quasistatic.h): from the starting equilibrium, the loading
 * parameter delta (the right support's displacement, or the supports' paths' parameter) grows
 * by adaptive increments, each a tangent predictor corrected by Newton and accepted when it
 * stayed on the branch and is stable; cut when not, until the limit point
 * (quasistatic_limit.c), a sliding mechanism that the support drives, or the largest
 * displacement. Slip: quasistatic_slip.c. */
#include "quasistatic_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/units.h"

/* A converged corrector may move the state away from the tangent predictor by at most this
 * multiple of the predictor's own length: a larger jump means Newton left the branch being
 * followed (for instance across a snap), and the increment is cut instead. */
static const double VS_CORRECTOR_RATIO = 1.0;
/* Inverse iteration on the tangent along the path, where the estimate only steers the increment
 * towards a fold: relative change of the eigenvalue estimate that stops it, and the iteration
 * cap. */
static const double VS_EIG_TRACK_RTOL = 1e-4;
static const int VS_EIG_TRACK_MAXIT = 6;
/* A support's path turns "here" when within this fraction of limit_tol: no increment shorter. */
static const double VS_KINK_TOL = 1e-3;

/* Scaled distance between two states: translations / block length, rotations in rad. */
static double scaled_norm(const vs_qs_solver *s, const double *a, const double *b) {
  double r = 0.0;
  for (int i = 0; i < s->n; i++) {
    const double len = is_rotation(s, i) ? 1.0 : s->len[i - i % 3 + 2];
    r = fmax(r, fabs(a[i] - b[i]) / len);
  }
  return r;
}

/* The run's state vectors (n unknowns each; the edges' location 3 n). Returns -1 when out of
 * memory (path_free frees what was allocated). */
static int path_alloc(vs_qs_path *w) {
  const size_t bytes = (size_t)w->s->n * sizeof(double);
  w->tan = malloc(bytes);
  w->qtry = malloc(bytes);
  w->qpred = malloc(bytes);
  w->qprev = malloc(bytes);
  w->eig = calloc((size_t)w->s->n, sizeof(double));
  w->qloc = malloc(3 * bytes); /* vs_qs_locate_edges' workspace */
  if (w->tan == NULL || w->qtry == NULL || w->qpred == NULL || w->qprev == NULL ||
      w->eig == NULL || w->qloc == NULL)
    return -1;
  return 0;
}

/* Free the run's state vectors. */
static void path_free(vs_qs_path *w) {
  free(w->tan);
  free(w->qtry);
  free(w->qpred);
  free(w->qprev);
  free(w->eig);
  free(w->qloc);
}

/* 1. The starting equilibrium at delta0 (vs_qs_start), with the tangent's smallest eigenvalue
 * there, committed and passed to step_fn as the path's first state; then the path tangent
 * there, from which the displacement control of the right support starts. */
static vs_status path_begin(vs_qs_path *w, double delta0, vs_error *err) {
  vs_qs_solver *const sp = w->s;
  vs_path_result *const res = w->res;
  vs_status st = vs_qs_start(sp, delta0, w->q, res, err);
  if (st != VS_OK) return st;
  w->lam = vs_qs_tangent_min_eig(sp, w->eig, VS_EIG_TRACK_RTOL, VS_EIG_TRACK_MAXIT);
  w->lam_prev = NAN;
  w->fold = INFINITY;
  w->fold_prev = INFINITY;
  res->evidence.lambda_start = w->lam;
  w->slid = vs_model_commit(sp->m, w->q, delta0);
  w->force = w->slid > 0 ? vs_model_support_force(sp->m, w->q, delta0) : NAN;
  w->slide_from = delta0;
  memcpy(w->qprev, w->q, (size_t)sp->n * sizeof(double));
  w->delta_prev = delta0;
  res->steps = 1;
  res->delta_limit = delta0;
  res->newton_iterations = sp->iters; /* kept current for the callback */
  if (w->step_fn != NULL && w->step_fn(w->user, delta0, w->q, sp->m) != 0)
    return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  /* 2. displacement control of the right support */
  w->delta = delta0;
  w->h = w->o->step;
  if (vs_qs_path_tangent(sp, w->q, w->delta, w->tan) != 0)
    return vs_error_set(err, VS_ERR_SOLVER, "the path tangent could not be solved for");
  if (w->slid > 0) vs_qs_loading_tangent(sp, w->q, w->delta, w->h, w->tan);
  return VS_OK;
}

/* The trial state of increment h: the tangent predictor from q (also kept in qpred), corrected
 * by Newton at delta + h. Returns vs_qs_solve's flag; *it its Newton iterations. */
static int path_try(vs_qs_path *w, long *it) {
  vs_qs_solver *const sp = w->s;
  for (int i = 0; i < sp->n; i++) w->qtry[i] = w->qpred[i] = w->q[i] + w->h * w->tan[i];
  return vs_qs_solve(sp, w->delta + w->h, w->qtry, it);
}

/* What became of a trial: accepted; missed (no convergence, or a converged state that left the
 * followed branch); or unstable (it passed a limit point). */
enum { TRIAL_OK = 0, TRIAL_MISSED = 1, TRIAL_UNSTABLE = 2 };

/* A trial is accepted when it converged (flag 0), stayed on the followed branch (the corrector
 * moved it from the predictor by at most VS_CORRECTOR_RATIO of the predictor's own length) and
 * is stable (else it passed a limit point). */
static int path_trial_check(vs_qs_path *w, int flag) {
  vs_qs_solver *const sp = w->s;
  if (flag != 0) return TRIAL_MISSED; /* its cause in sp->fail_cause */
  const double jump = scaled_norm(sp, w->qtry, w->qpred);
  const double reach = scaled_norm(sp, w->qpred, w->q);
  if (jump > VS_CORRECTOR_RATIO * reach + 10.0 * w->o->newton_tol) { /* left the branch */
    char by[64] = "from a predictor that did not move";
    if (reach > 0.0) snprintf(by, sizeof by, "%.3g times as far as the predictor", jump / reach);
    snprintf(sp->fail_cause, sizeof sp->fail_cause, "Newton converged at %.6g mm to a state off "
             "the followed branch, the corrector moving it %s", (w->delta + w->h) / VS_MM, by);
    return TRIAL_MISSED;
  }
  if (!vs_qs_stable_state(sp, w->qtry, w->delta + w->h)) {
    snprintf(sp->fail_cause, sizeof sp->fail_cause, "the equilibrium found at %.6g mm is not "
             "stable", (w->delta + w->h) / VS_MM);
    return TRIAL_UNSTABLE;
  }
  return TRIAL_OK;
}

/* A trial that missed may have crossed joints' Coulomb limits: beyond them the path turns onto
 * their sliding branch, away from the sticking predictor, by as much as the slip (a kink, which
 * no increment makes small relative to the predictor). The increment is tried once more from the
 * predictor that slides beyond the onset (vs_qs_slide_predictor).
 * Returns that trial's check (*it: its Newton iterations), or TRIAL_MISSED when no limit is
 * crossed; an error only when the solve failed for good (vs_qs_fatal). */
static int path_retry_sliding(vs_qs_path *w, long *it, vs_status *st, vs_error *err) {
  vs_qs_solver *const sp = w->s;
  if (vs_qs_slide_predictor(sp, w->q, w->delta, w->h, w->tan, w->qpred) != 0) return TRIAL_MISSED;
  memcpy(w->qtry, w->qpred, (size_t)sp->n * sizeof(double));
  const int flag = vs_qs_solve(sp, w->delta + w->h, w->qtry, it);
  if (flag != 0 && (*st = vs_qs_fatal(sp, w->delta + w->h, err)) != VS_OK) return TRIAL_MISSED;
  return path_trial_check(w, flag);
}

/* The accepted trial becomes the path's state: the hinge onsets between the two located (when
 * step_fn wants them), the state committed, the tangent's smallest eigenvalue and the path
 * tangent at it, step_fn called; the next increment grows when Newton converged fast (it: its
 * iterations). */
static vs_status path_accept(vs_qs_path *w, long it, vs_error *err) {
  vs_qs_solver *const sp = w->s;
  const vs_path_opts *const o = w->o;
  vs_path_result *const res = w->res;
  const size_t bytes = (size_t)sp->n * sizeof(double);
  /* the tangent is factored at the new state by vs_qs_stable_state (the location below
   * solves with KINSOL's own matrix and keeps that factorisation) */
  if (w->step_fn != NULL && o->open > 0.0 &&
      vs_qs_locate_edges(sp, w->q, w->delta, w->qtry, w->delta + w->h, w->step_fn, w->user,
                         w->qloc, &res->located) != 0)
    return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  memcpy(w->qprev, w->q, bytes);
  w->delta_prev = w->delta;
  memcpy(w->q, w->qtry, bytes);
  w->delta += w->h;
  const int slid_prev = w->slid;
  w->slid = vs_model_commit(sp->m, w->q, w->delta);
  w->force = w->slid > 0 ? vs_model_support_force(sp->m, w->q, w->delta) : NAN;
  if (w->slid != slid_prev) w->slide_from = w->delta; /* other joints slide from here */
  res->steps++;
  res->delta_limit = w->delta;
  w->lam_prev = w->lam;
  w->fold_prev = w->fold;
  /* the tangent factored by vs_qs_stable_state */
  w->lam = vs_qs_tangent_min_eig(sp, w->eig, VS_EIG_TRACK_RTOL, VS_EIG_TRACK_MAXIT);
  if (vs_qs_path_tangent(sp, w->q, w->delta, w->tan) != 0)
    return vs_error_set(err, VS_ERR_SOLVER, "the path tangent could not be solved for at %.6g mm",
                        w->delta / VS_MM);
  res->newton_iterations = sp->iters;
  if (w->step_fn != NULL && w->step_fn(w->user, w->delta, w->q, sp->m) != 0)
    return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  if (it <= 3) w->h = fmin(2.0 * w->h, o->step_max);
  else if (it <= 6) w->h = fmin(1.25 * w->h, o->step_max);
  if (w->slid > 0) vs_qs_loading_tangent(sp, w->q, w->delta, w->h, w->tan);
  return VS_OK;
}

/* The end of a path on which the support drives a sliding mechanism (VS_PATH_SLIDING): the
 * equilibria from the first of the sliding to the last, the joints that slide at the last. */
static void path_sliding_end(vs_qs_path *w) {
  vs_path_result *const res = w->res;
  res->end = VS_PATH_SLIDING;
  res->delta_limit = w->slide_from;
  res->delta_fail = w->delta;
  const int nj = vs_model_geometry(w->s->m)->n_joints;
  vs_joint_state *js = w->s->js;
  vs_model_joint_states(w->s->m, w->q, w->delta, js);
  res->evidence.slip_onset = 0;
  for (int k = nj - 1; k >= 0; k--)
    if (js[k].sliding && js[k].N > 0.0) {
      res->evidence.slip_onset++;
      res->evidence.slip_joint = k;
    }
}

/* The fraction of the accepted trial's increment at which the arch's first crack begins: an
 * edge of a mortared joint reaches its tensile strength (its opening, less the initial gap,
 * passes f_t / k_n), interpolated linearly in the edges' openings; 1 when none does, or when an
 * edge had cracked before (a dry arch: 1). The mortar's stress-opening law has its peak there:
 * past it the edge softens and the path's response changes, so the first crack's onset ends an
 * increment (path_follow), as a support's kink does, and the path resolves it rather than
 * stepping over it (the reported first crack is then the elastic arch's, not an interpolation
 * across softening joints). Later onsets are not cut for: each costs an increment more, and
 * together they doubled the quasi-static path's Newton iterations on the reference arch. */
static double crack_onset(const vs_qs_path *w) {
  vs_model *const m = w->s->m;
  if (!(vs_model_law(m)->ft > 0.0)) return 1.0;
  const vs_geometry *g = vs_model_geometry(m);
  const int nj = g->n_joints;
  vs_joint_state *a = w->s->js, *b = w->s->js + nj;
  vs_model_joint_states(m, w->q, w->delta, a);
  vs_model_joint_states(m, w->qtry, w->delta + w->h, b);
  double f = 1.0;
  for (int k = 0; k < nj; k++) {
    const vs_joint_law *l = vs_model_joint_law(m, k);
    if (!(l->ft > 0.0)) continue;
    const double d0 = l->ft / l->kn, h = 0.5 * g->joints[k].length;
    for (int e = 0; e < 2; e++) {
      if (l->crack[e] > 0.0) return 1.0; /* cracked before */
      const double x = e ? h : -h;
      const double m0 = d0 + (a[k].a - l->gap0) + x * (a[k].w - l->gap1);
      const double m1 = d0 + (b[k].a - l->gap0) + x * (b[k].w - l->gap1);
      if (!(m0 > 0.0)) return 1.0; /* cracked before */
      if (m1 <= 0.0) f = fmin(f, m0 / (m0 - m1));
    }
  }
  return f;
}

/* 2. Increments from the starting equilibrium until the largest displacement (VS_OK), the limit
 * point (vs_qs_limit_end), a sliding mechanism that the support drives (path_sliding_end) or an
 * error: a failed or rejected trial halves the increment, down to limit_tol. */
static vs_status path_follow(vs_qs_path *w, vs_error *err) {
  const vs_path_opts *const o = w->o;
  vs_path_result *const res = w->res;
  for (;;) {
    if (w->delta >= o->max_delta * (1.0 - 1e-12)) {
      res->end = VS_PATH_MAX_DISPLACEMENT;
      return VS_OK;
    }
    if (res->steps + res->rejected >= VS_PATH_MAX_INCREMENTS)
      return vs_error_set(err, VS_ERR_SOLVER,
                          "the quasi-static path took %ld increments (the limit) and reached only "
                          "%.6g mm of %.6g mm",
                          VS_PATH_MAX_INCREMENTS, w->delta / VS_MM, o->max_delta / VS_MM);
    w->h = fmin(w->h, o->max_delta - w->delta);
    /* an increment ends where a support's path turns, so that the tangent predictor follows one
     * segment of the load at a time (none on a straight motion) */
    const double kink = vs_model_support_next_kink(w->s->m, w->delta, VS_KINK_TOL * o->limit_tol);
    if (kink < INFINITY) w->h = fmin(w->h, kink - w->delta);
    vs_qs_fold_limit(w);
    long it = 0;
    const int flag = path_try(w, &it);
    if (flag != 0) {
      const vs_status st = vs_qs_fatal(w->s, w->delta + w->h, err);
      if (st != VS_OK) return st;
    }
    int check = path_trial_check(w, flag);
    if (check != TRIAL_OK) {
      res->rejected++;
      if (w->h > o->limit_tol) {
        w->h *= 0.5;
        continue;
      }
      /* an increment at the tolerance still misses: where it crosses joints' Coulomb limits,
       * the onset of slip is bracketed now, and the increment is tried on the sliding branch;
       * else the path ends at a limit point */
      vs_status st = VS_OK;
      if (check == TRIAL_MISSED) check = path_retry_sliding(w, &it, &st, err);
      if (st != VS_OK) return st;
      if (check != TRIAL_OK) return vs_qs_limit_end(w, err);
    }
    /* the first crack's onset inside the increment: the increment ends just past it (by half
     * the bisection tolerance), tried again */
    if (w->h > o->limit_tol) {
      const double h_cut = w->h * crack_onset(w) + 0.5 * o->limit_tol;
      if (h_cut < w->h) {
        res->rejected++;
        w->h = h_cut;
        continue;
      }
    }
    const double force_prev = w->force;
    const int slid_prev = w->slid;
    const vs_status st = path_accept(w, it, err);
    if (st != VS_OK) return st;
    if (w->slid == slid_prev &&
        fabs(w->force - force_prev) <= VS_PATH_PLATEAU_RTOL * fabs(w->force)) {
      path_sliding_end(w); /* NaN, when either state did not slide, compares false */
      return VS_OK;
    }
  }
}

vs_status vs_path_run(vs_model *m, const vs_path_opts *o, double delta0, double *q,
                      vs_path_step_fn step_fn, void *user, vs_path_result *res, vs_error *err) {
  memset(res, 0, sizeof *res);
  res->evidence.delta_extrap = NAN;
  vs_path_solver *p = NULL;
  vs_status st = vs_path_solver_create(m, o, &p, err);
  if (st == VS_OK) st = vs_path_run_with(p, o, delta0, q, step_fn, user, res, err);
  vs_path_solver_destroy(&p);
  return st;
}

vs_status vs_path_run_with(vs_path_solver *p, const vs_path_opts *o, double delta0, double *q,
                           vs_path_step_fn step_fn, void *user, vs_path_result *res,
                           vs_error *err) {
  memset(res, 0, sizeof *res);
  res->evidence.delta_extrap = NAN;
  vs_qs_solver *const sp = &p->s;
  vs_status st = vs_qs_rearm(sp, o, err);
  if (st != VS_OK) return st;
  vs_qs_path w = {.s = sp, .o = o, .step_fn = step_fn, .user = user, .res = res, .q = q};
  if (path_alloc(&w) != 0) st = vs_error_set(err, VS_ERR_NOMEM, "path: out of memory");
  if (st == VS_OK) st = path_begin(&w, delta0, err);
  if (st == VS_OK) st = path_follow(&w, err);
  res->newton_iterations = sp->iters;
  res->jacobian_evals = sp->jac_evals;
  res->floor_limited = sp->floor_limited;
  res->max_residual = sp->max_residual;
  path_free(&w);
  return st;
}
