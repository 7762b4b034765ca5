/* Quasi-static equilibrium solver: KINSOL (Newton + line search, KLU on the analytic Jacobian)
 * at a support displacement, with the residual's round-off floor; the solver a path runs on
 * (vs_path_solver). The path itself: quasistatic_path.c (its start, hinge onsets, tangent and
 * limit point in quasistatic_start.c, _edges.c, _tangent.c, _limit.c; quasistatic_internal.h). */
#include "quasistatic_internal.h"

#include <float.h>
#include <kinsol/kinsol.h>
#include <klu.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "klu_reuse.h"
#include "nvector_ops.h"
#include "voussoir/units.h"
#include "wall_clock.h"

/* KLU's fill-reducing ordering (0 AMD, 1 COLAMD, 2 natural), paid once per path (its analysis
 * is kept): AMD. The blocks form a chain, whose Jacobian is block-banded in the natural order:
 * the reference run takes as many instructions with AMD as with it (callgrind; COLAMD 0.6 %
 * more); with pinned supports, whose rotations q keeps after the blocks (an arrow in the natural
 * order), runs/pinned.ini takes 3 % fewer with AMD than with the natural order. */
static const int VS_KLU_ORDERING = 0;
/* KLU's row scaling: -1, none, and none of its check of the pattern at each factorisation (the
 * first analysis checked it; the model builds it once). The default (2: each row by its largest
 * entry) was over a third of a refactorisation of the reference tangent (107 k instructions
 * scaled, 68 k not; 24 M of the run's 383 M; about 4 ms of 35, perf stat). The rows are forces
 * and moments, apart by a joint length (a rotation's column: k L in the force rows against
 * k L^2 on the diagonal, L ~ 0.02 m), well within KLU's pivot tolerance (1e-3), so its
 * preference for the diagonal holds unscaled: no off-diagonal pivot in the reference run either
 * way, and the seed domain's results stay within rounding. */
static const int VS_KLU_SCALE = -1;
/* Newton stops when its scaled step (in units of the joint length) falls below this: about
 * a hundred ulps of a position, the resolution of double precision. */
static const double VS_NEWTON_STEPTOL = 1e-14;
/* KINSOL's line search backtracks down to the step tolerance (13 to 20 trials when a Newton
 * direction leads nowhere); a solve whose line search has tried this many steps without an
 * acceptable one is stopped as if the search had failed (the path then cuts its increment). */
static const int VS_MAX_LINESEARCH = 5;
/* Round-off floor of the residual: positions carry a relative error of eps, which the joint
 * stiffness k_n b t turns into a force error of about eps k_n b t (|u| + t); a Newton iteration
 * that stalls within this margin times that floor has converged as far as doubles allow. */
static const double VS_FLOOR_MARGIN = 16.0;

/* The stop flag was raised (now or before): the solver is interrupted. */
static int qs_stopped(vs_qs_solver *s) {
  if (s->o->stop != NULL && *s->o->stop) s->interrupted = 1;
  return s->interrupted;
}

/* KINSOL's residual. A raised stop flag and a residual that is not finite are fatal (-1): KINSOL
 * then returns KIN_SYSFUNC_FAIL at once (its line search never ends on NaN). */
static int sys_fn(N_Vector u, N_Vector f, void *user) {
  vs_qs_solver *s = user;
  if (qs_stopped(s)) return -1;
  if (++s->evals > VS_MAX_LINESEARCH + 1) { /* a diverging solve: stop it here */
    s->backtracked_out = 1;
    return -1;
  }
  double *fv = N_VGetArrayPointer(f);
  vs_model_residual(s->m, N_VGetArrayPointer(u), s->delta, fv);
  for (int i = 0; i < s->n; i++)
    if (!isfinite(fv[i])) {
      s->nonfinite = 1;
      return -1;
    }
  return 0;
}

static int jac_fn(N_Vector u, N_Vector fu, SUNMatrix J, void *user, N_Vector t1, N_Vector t2) {
  (void)fu;
  (void)t1;
  (void)t2;
  vs_qs_solver *s = user;
  if (qs_stopped(s)) return -1;
  s->jac_evals++;
  s->evals = 0;
  return vs_model_jacobian(s->m, N_VGetArrayPointer(u), s->delta, J);
}

/* KINSOL's messages go to the error detail, never to stderr. */
static void kin_err(int code, const char *module, const char *function, char *msg, void *user) {
  vs_qs_solver *s = user;
  (void)code;
  snprintf(s->kin_msg, sizeof s->kin_msg, "%s/%s: %s", module, function, msg);
}

/* Free what s holds (any part may be missing: a failed creation) and zero it. */
static void qs_destroy(vs_qs_solver *s) {
  if (s->kin != NULL) KINFree(&s->kin);
  if (s->LS != NULL) SUNLinSolFree(s->LS);
  if (s->LSt != NULL) SUNLinSolFree(s->LSt);
  if (s->J != NULL) SUNMatDestroy(s->J);
  if (s->Jt != NULL) SUNMatDestroy(s->Jt);
  if (s->u != NULL) N_VDestroy(s->u);
  if (s->uscale != NULL) N_VDestroy(s->uscale);
  if (s->fscale != NULL) N_VDestroy(s->fscale);
  if (s->w1 != NULL) N_VDestroy(s->w1);
  if (s->w2 != NULL) N_VDestroy(s->w2);
  if (s->ctx != NULL) SUNContext_Free(&s->ctx);
  vs_spd_destroy(&s->spd);
  free(s->fwork);
  free(s->seen);
  free(s->js);
  free(s->onset);
  free(s->slips);
  free(s->len);
  memset(s, 0, sizeof *s);
}

/* A setup call failed: s destroyed, the error names the call and its flag. */
static vs_status qs_fail(vs_qs_solver *s, vs_error *err, const char *what, int flag) {
  qs_destroy(s);
  return vs_error_set(err, VS_ERR_SOLVER, "quasi-static solver setup: %s failed (flag %d)", what,
                      flag);
}

/* The solver's vectors, matrices and workspaces over its n unknowns (Jacobians with the model's
 * nnz entries), every vector with the optimised operations. */
static vs_status qs_alloc(vs_qs_solver *s, vs_error *err) {
  const sunindextype n = s->n, nnz = vs_model_nnz(s->m);
  int flag = SUNContext_Create(NULL, &s->ctx);
  if (flag != 0) return qs_fail(s, err, "SUNContext_Create", flag);
  s->u = N_VNew_Serial(n, s->ctx);
  s->uscale = N_VNew_Serial(n, s->ctx);
  s->fscale = N_VNew_Serial(n, s->ctx);
  s->J = SUNSparseMatrix(n, n, nnz, CSC_MAT, s->ctx);
  s->Jt = SUNSparseMatrix(n, n, nnz, CSC_MAT, s->ctx);
  s->len = malloc((size_t)n * sizeof *s->len);
  s->w1 = N_VNew_Serial(n, s->ctx);
  s->w2 = N_VNew_Serial(n, s->ctx);
  s->fwork = malloc((size_t)n * sizeof *s->fwork);
  s->seen = malloc((size_t)n);
  const size_t nj = (size_t)vs_model_geometry(s->m)->n_joints;
  s->js = malloc(2 * (nj > 0 ? nj : 1) * sizeof *s->js);
  s->onset = calloc(nj > 0 ? nj : 1, 1);
  s->slips = malloc((nj > 0 ? nj : 1) * sizeof *s->slips);
  if (s->u == NULL || s->uscale == NULL || s->fscale == NULL || s->J == NULL || s->Jt == NULL ||
      s->len == NULL || s->w1 == NULL || s->w2 == NULL || s->fwork == NULL || s->seen == NULL ||
      s->js == NULL || s->onset == NULL || s->slips == NULL) {
    qs_destroy(s);
    return vs_error_set(err, VS_ERR_NOMEM, "quasi-static solver: out of memory");
  }
  /* KINSOL clones its workspace from u: every vector of the solve gets the optimised operations */
  N_Vector vecs[] = {s->u, s->uscale, s->fscale, s->w1, s->w2};
  for (size_t i = 0; i < sizeof vecs / sizeof vecs[0]; i++) vs_nvector_fast_ops(vecs[i]);
  return VS_OK;
}

/* The stability test (vs_spd): it factors the tangent's symmetric part as a band, in the model's
 * band order, which keeps a pinned support's rotation next to its block. */
static vs_status qs_spd_create(vs_qs_solver *s, vs_error *err) {
  int *perm = malloc((size_t)s->n * sizeof *perm);
  if (perm == NULL) {
    qs_destroy(s);
    return vs_error_set(err, VS_ERR_NOMEM, "quasi-static solver: out of memory");
  }
  vs_model_band_order(s->m, perm);
  const vs_status st = vs_spd_create(s->n, perm, &s->spd, err);
  free(perm);
  if (st != VS_OK) qs_destroy(s);
  return st;
}

/* KLU factors the Jacobian at every Newton iteration (LS) and the tangent at every accepted
 * state (LSt); both keep one analysis of the fixed pattern and refactor on its last pivots. */
static vs_status qs_klu_create(vs_qs_solver *s, vs_error *err) {
  int flag;
  s->LS = SUNLinSol_KLU(s->u, s->J, s->ctx);
  s->LSt = SUNLinSol_KLU(s->u, s->Jt, s->ctx);
  if (s->LS == NULL || s->LSt == NULL) return qs_fail(s, err, "SUNLinSol_KLU", 0);
  if ((flag = SUNLinSol_KLUSetOrdering(s->LS, VS_KLU_ORDERING)) != 0 ||
      (flag = SUNLinSol_KLUSetOrdering(s->LSt, VS_KLU_ORDERING)) != 0)
    return qs_fail(s, err, "SUNLinSol_KLUSetOrdering", flag);
  SUNLinSol_KLUGetCommon(s->LS)->scale = VS_KLU_SCALE;
  SUNLinSol_KLUGetCommon(s->LSt)->scale = VS_KLU_SCALE;
  vs_klu_keep_analysis(s->LS);  /* KINSol re-initialises its solver at every call */
  vs_klu_keep_analysis(s->LSt); /* re-initialised by every run (vs_qs_rearm) */
  vs_sparse_zero_none(s->J);    /* jac_fn writes the pattern */
  return VS_OK;
}

/* Scalings: residuals in units of each block's weight (moments: weight x joint length);
 * unknowns in units of that length (rotations in rad). And what the round-off floor of the
 * residual needs (vs_qs_solve): the stiffest joint, the longest, the lightest block. */
static void qs_scale(vs_qs_solver *s) {
  vs_model *const m = s->m;
  double *fs = N_VGetArrayPointer(s->fscale), *us = N_VGetArrayPointer(s->uscale);
  vs_model_residual_scale(m, fs);
  for (int i = 0; i < s->nb3; i += 3) {
    const double len = fs[i + 2] / fs[i];
    s->len[i] = s->len[i + 1] = 1.0;
    s->len[i + 2] = len;
    us[i] = us[i + 1] = 1.0 / len;
    us[i + 2] = 1.0;
  }
  for (int i = s->nb3; i < s->n; i++) s->len[i] = us[i] = 1.0; /* pinned supports' rotations */
  s->wmin = INFINITY;
  for (int i = 0; i < s->nb3; i += 3) s->wmin = fmin(s->wmin, fs[i]);
  for (int i = 0; i < s->n; i++) fs[i] = 1.0 / fs[i];
  const vs_geometry *g = vs_model_geometry(m);
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    s->kmax = fmax(s->kmax, vs_model_law(m)->kn * j->depth * j->length);
    s->lmax = fmax(s->lmax, j->length);
  }
}

/* KINSOL: Newton with line search on sys_fn, the exact Jacobian (jac_fn) at every iteration
 * factored by KLU (s->LS), messages into s->kin_msg, the options' tolerance and iteration cap. */
static vs_status qs_kinsol_create(vs_qs_solver *s, vs_error *err) {
  const vs_path_opts *const o = s->o;
  int flag;
  s->kin = KINCreate(s->ctx);
  if (s->kin == NULL) return qs_fail(s, err, "KINCreate", 0);
  if ((flag = KINInit(s->kin, sys_fn, s->u)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINInit", flag);
  if ((flag = KINSetUserData(s->kin, s)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetUserData", flag);
  if ((flag = KINSetErrHandlerFn(s->kin, kin_err, s)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetErrHandlerFn", flag);
  if ((flag = KINSetLinearSolver(s->kin, s->LS, s->J)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetLinearSolver", flag);
  if ((flag = KINSetJacFn(s->kin, jac_fn)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetJacFn", flag);
  if ((flag = KINSetMaxSetupCalls(s->kin, 1)) != KIN_SUCCESS) /* exact Newton: J every iteration */
    return qs_fail(s, err, "KINSetMaxSetupCalls", flag);
  if ((flag = KINSetNumMaxIters(s->kin, o->newton_maxiter)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetNumMaxIters", flag);
  if ((flag = KINSetFuncNormTol(s->kin, o->newton_tol)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetFuncNormTol", flag);
  if ((flag = KINSetScaledStepTol(s->kin, VS_NEWTON_STEPTOL)) != KIN_SUCCESS)
    return qs_fail(s, err, "KINSetScaledStepTol", flag);
  return VS_OK;
}

/* A solver of the model m's equilibrium with options o (borrowed); on failure s is left
 * destroyed (zeroed). */
static vs_status qs_create(vs_qs_solver *s, vs_model *m, const vs_path_opts *o, vs_error *err) {
  memset(s, 0, sizeof *s);
  s->m = m;
  s->o = o;
  s->n = vs_model_size(m);
  s->nb3 = 3 * vs_model_geometry(m)->n_blocks;
  vs_status st = qs_alloc(s, err);
  if (st == VS_OK) st = qs_spd_create(s, err);
  if (st == VS_OK) st = qs_klu_create(s, err);
  if (st != VS_OK) return st;
  qs_scale(s);
  return qs_kinsol_create(s, err);
}

/* Largest scaled residual |G_i| / scale_i at (q, delta). */
static double scaled_residual(vs_qs_solver *s, const double *q, double delta) {
  double *f = s->fwork, r = 0.0;
  vs_model_residual(s->m, q, delta, f);
  const double *fs = N_VGetArrayPointer(s->fscale);
  for (int i = 0; i < s->n; i++) r = fmax(r, fabs(f[i]) * fs[i]);
  return r;
}

/* The cause of the solve at delta that failed with flag, into s->fail_cause. A line search cut
 * short by VS_MAX_LINESEARCH is said as such: KINSOL itself reports it as its system function
 * failing "in an unrecoverable manner" (the residual's -1 by which it is cut). */
static int note_failure(vs_qs_solver *s, double delta, int flag) {
  if (s->backtracked_out && !s->interrupted)
    snprintf(s->fail_cause, sizeof s->fail_cause, "the line search found no lower residual in "
             "%d trial steps along the Newton direction at %.6g mm (stopped there)",
             VS_MAX_LINESEARCH, delta / VS_MM);
  else
    snprintf(s->fail_cause, sizeof s->fail_cause, "%s at %.6g mm", vs_qs_kin_cause(flag),
             delta / VS_MM);
  return flag;
}

/* Solve G(q; delta) = 0 from the guess q. Returns 0 on convergence, else the KINSOL flag (the
 * cause in s->fail_cause). */
int vs_qs_solve(vs_qs_solver *s, double delta, double *q, long *iters) {
  s->delta = delta;
  s->kin_msg[0] = '\0';
  s->nonfinite = 0;
  s->evals = 0;
  s->backtracked_out = 0;
  if (vs_deadline_passed(s->o->deadline)) s->interrupted = 1; /* once a solve: a clock read */
  if (qs_stopped(s)) return note_failure(s, delta, KIN_SYSFUNC_FAIL);
  memcpy(N_VGetArrayPointer(s->u), q, (size_t)s->n * sizeof *q);
  int flag = KINSol(s->kin, s->u, KIN_LINESEARCH, s->uscale, s->fscale);
  if (flag == KIN_SYSFUNC_FAIL && s->backtracked_out && !s->interrupted)
    flag = KIN_LINESEARCH_NONCONV; /* u holds the last accepted iterate */
  long nni = 0;
  KINGetNumNonlinSolvIters(s->kin, &nni);
  s->iters += nni;
  if (iters != NULL) *iters = nni;
  /* a stall is a tiny Newton step or a line search finding no distinct iterate */
  const int stalled = (flag == KIN_STEP_LT_STPTOL || flag == KIN_LINESEARCH_NONCONV);
  if (flag == KIN_SUCCESS || flag == KIN_INITIAL_GUESS_OK || stalled) {
    const double *u = N_VGetArrayPointer(s->u);
    const double r = scaled_residual(s, u, delta);
    if (r > s->o->newton_tol) {
      /* stalled: accept only at the round-off floor of the residual */
      double umax = 0.0;
      for (int i = 0; i < s->n; i++)
        if (!is_rotation(s, i)) umax = fmax(umax, fabs(u[i]));
      const double floor = VS_FLOOR_MARGIN * DBL_EPSILON * s->kmax * (umax + s->lmax) / s->wmin;
      if (!stalled || r > floor)
        return note_failure(s, delta, flag == KIN_SUCCESS ? KIN_STEP_LT_STPTOL : flag);
      s->floor_limited++;
    }
    s->max_residual = fmax(s->max_residual, r);
    memcpy(q, u, (size_t)s->n * sizeof *q);
    return 0;
  }
  return note_failure(s, delta, flag);
}

void vs_path_opts_from_def(const vs_run_def *d, vs_path_opts *o) {
  o->step = d->path.step;
  o->step_max = d->path.step_max;
  o->limit_tol = d->path.limit_tol;
  o->max_delta = d->support.max_delta;
  o->newton_tol = d->path.newton_tol;
  o->newton_maxiter = d->path.newton_maxiter;
  o->open = d->hinges.open;
  o->stop = NULL;
  o->deadline = NULL;
}

/* After a failed solve at delta: an error when the failure ends the path whatever follows (the
 * stop flag, a residual that is not finite), else VS_OK. */
vs_status vs_qs_fatal(const vs_qs_solver *s, double delta, vs_error *err) {
  if (s->interrupted) return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (s->nonfinite)
    return vs_error_set(err, VS_ERR_SOLVER,
                        "the residual is not finite (NaN or infinity) at support displacement "
                        "%.6g mm: the case's values are beyond double precision",
                        delta / VS_MM);
  return VS_OK;
}

const char *vs_qs_kin_cause(int flag) {
  switch (flag) {
  case KIN_LINESEARCH_NONCONV: return "line search could not reduce the residual";
  case KIN_MAXITER_REACHED: return "Newton iteration limit reached";
  case KIN_MXNEWT_5X_EXCEEDED: return "five consecutive maximum-length Newton steps (diverging)";
  case KIN_LINESEARCH_BCFAIL: return "line search could not satisfy the beta condition";
  case KIN_LSETUP_FAIL: return "the Jacobian could not be factored (singular tangent)";
  case KIN_LSOLVE_FAIL: return "the linear solve failed";
  case KIN_STEP_LT_STPTOL: return "Newton stalled with the residual above tolerance";
  case KIN_SYSFUNC_FAIL: return "the residual is not finite (NaN or infinity)";
  default: return "KINSOL failure";
  }
}

vs_status vs_equilibrium_solve(vs_model *m, const vs_path_opts *o, double delta, double *q,
                               long *iters, vs_error *err) {
  vs_qs_solver s;
  vs_status st = qs_create(&s, m, o, err);
  if (st != VS_OK) return st;
  int flag = vs_qs_solve(&s, delta, q, iters);
  if (flag != 0) st = vs_qs_fatal(&s, delta, err);
  if (flag != 0 && st == VS_OK)
    st = vs_error_set(err, VS_ERR_NO_EQUILIBRIUM, "no equilibrium: %s (KINSOL flag %d)",
                      s.fail_cause, flag);
  qs_destroy(&s);
  return st;
}

vs_status vs_path_solver_create(vs_model *m, const vs_path_opts *o, vs_path_solver **out,
                                vs_error *err) {
  *out = NULL;
  vs_path_solver *p = malloc(sizeof *p);
  if (p == NULL) return vs_error_set(err, VS_ERR_NOMEM, "quasi-static solver: out of memory");
  vs_status st = qs_create(&p->s, m, o, err);
  if (st != VS_OK) {
    free(p);
    return st;
  }
  *out = p;
  return VS_OK;
}

void vs_path_solver_destroy(vs_path_solver **p) {
  if (p == NULL || *p == NULL) return;
  qs_destroy(&(*p)->s);
  free(*p);
  *p = NULL;
}

/* A run starts as on a new solver: options o, counters at zero, the tangent factored afresh. */
vs_status vs_qs_rearm(vs_qs_solver *s, const vs_path_opts *o, vs_error *err) {
  s->o = o;
  s->delta = 0.0;
  s->iters = s->jac_evals = s->floor_limited = 0;
  s->max_residual = 0.0;
  s->interrupted = s->nonfinite = s->evals = s->backtracked_out = 0;
  s->kin_msg[0] = s->fail_cause[0] = '\0';
  int flag = KINSetNumMaxIters(s->kin, o->newton_maxiter);
  if (flag == KIN_SUCCESS) flag = KINSetFuncNormTol(s->kin, o->newton_tol);
  if (flag == KIN_SUCCESS) flag = SUNLinSolInitialize(s->LSt);
  return flag == 0 ? VS_OK
                   : vs_error_set(err, VS_ERR_SOLVER,
                                  "quasi-static solver: re-arming failed (flag %d)", flag);
}

