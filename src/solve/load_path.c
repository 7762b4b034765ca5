/* The live load's path to collapse (quasistatic.h, "load path"): the loads of the model
 * (vs_model_set_loads) grow by their factor lambda, under displacement control of their own
 * displacement u (vs_model_load_displacement, the pilot): KINSOL solves the bordered system
 * G(q, lambda) = 0, u(q) = u_target for (q, lambda), KLU on the model's Jacobian bordered by the
 * load vector, so the path goes through the peak of lambda (where load control would fail) and
 * down its falling branch. The peak is bracketed by cutting the increment that passes it. */
#include "load_internal.h"

#include <float.h>
#include <kinsol/kinsol.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/units.h"
#include "wall_clock.h"

/* Newton's scaled step tolerance, as the support's path's (quasistatic.c). */
static const double VS_LP_STEPTOL = 1e-14;
/* Round-off floor of the residual, as in quasistatic.c: a stall within this margin of
 * eps k_n b t (|u| + t) / (lightest weight) has converged as far as doubles allow. */
static const double VS_LP_FLOOR_MARGIN = 16.0;
/* The pilot's equation holds to this fraction of peak_tol (the smallest increment). */
static const double VS_LP_PILOT_TOL = 1e-3;
/* On the arc, the smallest increment is this fraction of the last step before it; past a fall
 * of drop, the arc is followed for this many steps without a larger lambda (a snap-back can
 * take lambda far down before it rises to a higher peak; the arc may also close on itself). */
static const long VS_LP_ARC_PATIENCE = 200;
static const double VS_LP_ARC_MIN = 1e-3;
/* The first increment, from the held state with no secant to predict from, may be cut down to
 * this fraction of the smallest increment (peak_tol): stiff joints (k_n = 1e4 N/mm^3 on the
 * reference specimen) converge only within a few nanometres of that state. */
static const double VS_LP_FIRST_CUT = 1e-3;
/* Newton iterations per increment at least: the secant predictor (none at the first increment)
 * is rougher than the support path's tangent, and stiff joints' contact zones, a few microns
 * wide, change under it (8, the support path's default, stalls the reference specimen's first
 * increment at k_n = 300 N/mm^3). */
static const long VS_LP_MIN_ITERS = 30;
/* Increments grow by this factor after a solve of at most VS_LP_EASY Newton iterations. */
static const double VS_LP_GROW = 2.0;
static const long VS_LP_EASY = 4;
/* Increments of one path at most (accepted and rejected). */
static const long VS_LP_MAX_INCREMENTS = 200000;

void vs_load_opts_from_def(const vs_run_def *d, vs_load_opts *o) {
  o->step = VS_LOAD_STEP_SCALE * d->path.step;
  o->step_max = VS_LOAD_STEP_SCALE * d->path.step_max;
  o->peak_tol = d->path.limit_tol;
  o->max_disp = d->support.max_delta;
  o->drop = VS_LOAD_DROP;
  o->follow = d->arch.thickness;
  o->newton_tol = d->path.newton_tol;
  o->newton_maxiter = d->path.newton_maxiter;
  o->stop = NULL;
  o->deadline = NULL;
}

/* --- the bordered system --- */

static int lp_stopped(vs_lp_solver *s) {
  if (s->o->stop != NULL && *s->o->stop) s->interrupted = 1;
  return s->interrupted;
}

/* The control's equation at x: the pilot's u(q) - target, or on the arc, the scaled projection
 * of the step from the anchor on the path's direction, less its length. */
static double lp_control(const vs_lp_solver *s, const double *x) {
  if (!s->arc) return vs_model_load_displacement(s->m, x) - s->target;
  double p = 0.0;
  for (int i = 0; i <= s->n; i++) p += s->a[i] * (x[i] - s->xa[i]);
  return p - s->target;
}

static int lp_sys(N_Vector x, N_Vector f, void *user) {
  vs_lp_solver *s = user;
  if (lp_stopped(s)) return -1;
  if (++s->evals > 6) { /* a diverging solve (as quasistatic.c's line-search cap) */
    s->backtracked_out = 1;
    return -1;
  }
  const double *xv = N_VGetArrayPointer(x);
  double *fv = N_VGetArrayPointer(f);
  vs_model_set_load_factor(s->m, xv[s->n]);
  vs_model_residual(s->m, xv, s->delta, fv);
  fv[s->n] = lp_control(s, xv);
  for (int i = 0; i <= s->n; i++)
    if (!isfinite(fv[i])) {
      s->nonfinite = 1;
      return -1;
    }
  return 0;
}

/* [K  -f; f^T/|f|  0]: the model's tangent, dG/dlambda = -f(q) (the load vector), and the
 * pilot's gradient (vs_model_load_displacement's). */
static int lp_jac(N_Vector x, N_Vector fx, SUNMatrix J, void *user, N_Vector t1, N_Vector t2) {
  (void)fx, (void)t1, (void)t2;
  vs_lp_solver *s = user;
  if (lp_stopped(s)) return -1;
  s->jac_evals++;
  s->evals = 0;
  const double *xv = N_VGetArrayPointer(x);
  const int n = s->n;
  vs_model_set_load_factor(s->m, xv[n]);
  vs_model_jacobian(s->m, xv, s->delta, s->Jm);
  vs_model_load_vector(s->m, xv, s->f);
  const sunindextype *mp = SUNSparseMatrix_IndexPointers(s->Jm);
  const sunindextype *mr = SUNSparseMatrix_IndexValues(s->Jm);
  const double *md = SUNSparseMatrix_Data(s->Jm);
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *rv = SUNSparseMatrix_IndexValues(J);
  double *d = SUNSparseMatrix_Data(J);
  sunindextype k = 0;
  for (int j = 0; j < n; j++) {
    cp[j] = k;
    for (sunindextype p = mp[j]; p < mp[j + 1]; p++, k++) {
      rv[k] = mr[p];
      d[k] = md[p];
    }
    rv[k] = n;
    d[k++] = s->arc ? s->a[j] : s->f[j] / s->size;
  }
  cp[n] = k;
  for (int i = 0; i < n; i++, k++) {
    rv[k] = i;
    d[k] = -s->f[i];
  }
  rv[k] = n;
  d[k++] = s->arc ? s->a[n] : 0.0;
  cp[n + 1] = k;
  return 0;
}

static void lp_kin_err(int code, const char *module, const char *function, char *msg,
                       void *user) {
  (void)code;
  vs_lp_solver *s = user;
  snprintf(s->kin_msg, sizeof s->kin_msg, "%s/%s: %s", module, function, msg);
}

void vs_lp_destroy(vs_lp_solver *s) {
  if (s->kin != NULL) KINFree(&s->kin);
  if (s->LS != NULL) SUNLinSolFree(s->LS);
  if (s->J != NULL) SUNMatDestroy(s->J);
  if (s->Jm != NULL) SUNMatDestroy(s->Jm);
  if (s->x != NULL) N_VDestroy(s->x);
  if (s->xscale != NULL) N_VDestroy(s->xscale);
  if (s->fscale != NULL) N_VDestroy(s->fscale);
  if (s->ctx != NULL) SUNContext_Free(&s->ctx);
  free(s->f);
  free(s->work);
  free(s->a);
  free(s->xa);
  free(s->sc);
  memset(s, 0, sizeof *s);
}

static vs_status lp_fail(vs_lp_solver *s, vs_error *err, const char *what, int flag) {
  vs_lp_destroy(s);
  return vs_error_set(err, VS_ERR_SOLVER, "load path solver setup: %s failed (flag %d)", what,
                      flag);
}

/* Scalings as the support's path's: residuals in units of each block's weight (moments times
 * the joint length), positions in units of that length; lambda as it is; the pilot's equation
 * in units of peak_tol: very stiff joints leave a round-off floor on the forces (quasistatic.c)
 * that a pilot in larger units would drown, and with it the line search. */
static void lp_scale(vs_lp_solver *s) {
  const int n = s->n;
  double *fs = N_VGetArrayPointer(s->fscale), *xs = N_VGetArrayPointer(s->xscale);
  vs_model_residual_scale(s->m, fs);
  const int nb3 = 3 * vs_model_geometry(s->m)->n_blocks;
  s->wmin = INFINITY;
  for (int i = 0; i < nb3; i += 3) {
    const double len = fs[i + 2] / fs[i];
    xs[i] = xs[i + 1] = 1.0 / len;
    xs[i + 2] = 1.0;
    s->wmin = fmin(s->wmin, fs[i]);
  }
  for (int i = nb3; i < n; i++) xs[i] = 1.0;
  const vs_geometry *g = vs_model_geometry(s->m);
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    const double kn = vs_model_joint_law(s->m, k)->kn;
    s->kmax = fmax(s->kmax, kn * j->depth * j->length);
    s->lmax = fmax(s->lmax, j->length);
  }
  for (int i = 0; i < n; i++) fs[i] = 1.0 / fs[i];
  fs[n] = 1.0 / s->o->peak_tol; /* the pilot dominates the noise of stiff joints' forces */
  xs[n] = 1.0;
}

vs_status vs_lp_create(vs_lp_solver *s, vs_model *m, const vs_load_opts *o, vs_error *err) {
  memset(s, 0, sizeof *s);
  s->m = m;
  s->o = o;
  s->n = vs_model_size(m);
  s->size = vs_model_load_size(m);
  if (vs_model_load_count(m) == 0 || !(s->size > 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "load path: the model carries no load");
  const sunindextype n = s->n, na = n + 1, nnz = vs_model_nnz(m);
  int flag = SUNContext_Create(NULL, &s->ctx);
  if (flag != 0) return lp_fail(s, err, "SUNContext_Create", flag);
  s->x = N_VNew_Serial(na, s->ctx);
  s->xscale = N_VNew_Serial(na, s->ctx);
  s->fscale = N_VNew_Serial(na, s->ctx);
  s->Jm = SUNSparseMatrix(n, n, nnz, CSC_MAT, s->ctx);
  s->J = SUNSparseMatrix(na, na, nnz + n + na, CSC_MAT, s->ctx);
  s->f = malloc((size_t)n * sizeof *s->f);
  s->work = malloc(4 * (size_t)na * sizeof *s->work);
  s->a = malloc((size_t)na * sizeof *s->a);
  s->xa = malloc((size_t)na * sizeof *s->xa);
  s->sc = malloc((size_t)na * sizeof *s->sc);
  if (s->x == NULL || s->xscale == NULL || s->fscale == NULL || s->Jm == NULL || s->J == NULL ||
      s->f == NULL || s->work == NULL || s->a == NULL || s->xa == NULL || s->sc == NULL) {
    vs_lp_destroy(s);
    return vs_error_set(err, VS_ERR_NOMEM, "load path solver: out of memory");
  }
  lp_scale(s);
  s->LS = SUNLinSol_KLU(s->x, s->J, s->ctx);
  if (s->LS == NULL) return lp_fail(s, err, "SUNLinSol_KLU", 0);
  s->kin = KINCreate(s->ctx);
  if (s->kin == NULL) return lp_fail(s, err, "KINCreate", 0);
  if ((flag = KINInit(s->kin, lp_sys, s->x)) != KIN_SUCCESS) return lp_fail(s, err, "KINInit", flag);
  if ((flag = KINSetUserData(s->kin, s)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetUserData", flag);
  if ((flag = KINSetErrHandlerFn(s->kin, lp_kin_err, s)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetErrHandlerFn", flag);
  if ((flag = KINSetLinearSolver(s->kin, s->LS, s->J)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetLinearSolver", flag);
  if ((flag = KINSetJacFn(s->kin, lp_jac)) != KIN_SUCCESS) return lp_fail(s, err, "KINSetJacFn", flag);
  if ((flag = KINSetMaxSetupCalls(s->kin, 1)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetMaxSetupCalls", flag);
  if ((flag = KINSetNumMaxIters(s->kin, o->newton_maxiter > VS_LP_MIN_ITERS ? o->newton_maxiter
                                                                              : VS_LP_MIN_ITERS)) !=
      KIN_SUCCESS)
    return lp_fail(s, err, "KINSetNumMaxIters", flag);
  if ((flag = KINSetFuncNormTol(s->kin, o->newton_tol)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetFuncNormTol", flag);
  if ((flag = KINSetScaledStepTol(s->kin, VS_LP_STEPTOL)) != KIN_SUCCESS)
    return lp_fail(s, err, "KINSetScaledStepTol", flag);
  return VS_OK;
}

/* Largest scaled residual of the equilibrium at x (lambda x[n]); the pilot's error into *du. */
static double lp_residual(vs_lp_solver *s, const double *x, double *du) {
  double *r = s->work + s->n + 1, worst = 0.0;
  vs_model_set_load_factor(s->m, x[s->n]);
  vs_model_residual(s->m, x, s->delta, r);
  *du = fabs(lp_control(s, x));
  const double *fs = N_VGetArrayPointer(s->fscale);
  for (int i = 0; i < s->n; i++) worst = fmax(worst, fabs(r[i]) * fs[i]);
  return worst;
}

int vs_lp_solve(vs_lp_solver *s, double target, double *x, long *iters) {
  s->target = target;
  s->kin_msg[0] = '\0';
  s->nonfinite = s->evals = s->backtracked_out = 0;
  if (vs_deadline_passed(s->o->deadline)) s->interrupted = 1;
  if (lp_stopped(s)) return KIN_SYSFUNC_FAIL;
  memcpy(N_VGetArrayPointer(s->x), x, (size_t)(s->n + 1) * sizeof *x);
  int flag = KINSol(s->kin, s->x, KIN_LINESEARCH, s->xscale, s->fscale);
  if (flag == KIN_SYSFUNC_FAIL && s->backtracked_out && !s->interrupted)
    flag = KIN_LINESEARCH_NONCONV;
  long nni = 0;
  KINGetNumNonlinSolvIters(s->kin, &nni);
  *iters = nni;
  /* a stall, or the iteration cap reached at the round-off floor (stiff joints: Newton wanders
   * there without its step falling below the step tolerance) */
  const int stalled = flag == KIN_STEP_LT_STPTOL || flag == KIN_LINESEARCH_NONCONV ||
                      flag == KIN_MAXITER_REACHED;
  if (flag != KIN_SUCCESS && flag != KIN_INITIAL_GUESS_OK && !stalled) return flag;
  const double *u = N_VGetArrayPointer(s->x);
  double du = 0.0;
  const double r = lp_residual(s, u, &du);
  if (!(du <= VS_LP_PILOT_TOL * (s->arc ? s->arc_min : s->o->peak_tol))) return flag == KIN_SUCCESS ? KIN_STEP_LT_STPTOL : flag;
  if (r > s->o->newton_tol) {
    double umax = 0.0;
    for (int i = 0; i < s->n; i++)
      if (i % 3 != 2) umax = fmax(umax, fabs(u[i]));
    const double floor = VS_LP_FLOOR_MARGIN * DBL_EPSILON * s->kmax * (umax + s->lmax) / s->wmin;
    if (!stalled || r > floor) return flag == KIN_SUCCESS ? KIN_STEP_LT_STPTOL : flag;
  }
  s->max_residual = fmax(s->max_residual, r);
  memcpy(x, u, (size_t)(s->n + 1) * sizeof *x);
  return 0;
}

/* --- the path --- */

/* A failed solve that ends the path whatever the increment: the stop flag, a residual that is
 * not finite. */
static vs_status lp_fatal(const vs_lp_solver *s, double u, vs_error *err) {
  if (s->interrupted) return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (s->nonfinite)
    return vs_error_set(err, VS_ERR_SOLVER,
                        "load path: the residual is not finite (NaN or infinity) at the load's "
                        "displacement %.6g mm",
                        u / VS_MM);
  return VS_OK;
}

/* The path's state between increments: the last two accepted (q, lambda) and their pilot. */
typedef struct {
  double *x, *xprev, *xtry; /* n + 1 each: q, then lambda */
  double u, uprev, h;       /* the pilot's u at x and xprev; the next increment (m, or on the
                               arc its scaled length) */
  double hmin, hmax;        /* the increment's bounds */
  int have_prev, bracketing;
  int bracketed; /* the peak at the largest lambda so far has been bracketed */
} lp_path;

static void lp_step_accept(vs_lp_solver *s, lp_path *w, double unew, int *slid) {
  const int na = s->n + 1;
  memcpy(w->xprev, w->x, (size_t)na * sizeof *w->x);
  memcpy(w->x, w->xtry, (size_t)na * sizeof *w->x);
  w->uprev = w->u;
  w->u = unew;
  w->have_prev = 1;
  vs_model_set_load_factor(s->m, w->x[s->n]);
  *slid = vs_model_commit(s->m, w->x, s->delta);
}

/* On the arc: the unit direction of the last step (xprev to x) in scaled units into s->a (times
 * the scales), anchored at x; its scaled length, 0 if none. */
static double lp_arc_direction(vs_lp_solver *s, const lp_path *w) {
  const int na = s->n + 1;
  double norm = 0.0;
  for (int i = 0; i < na; i++) {
    const double d = s->sc[i] * (w->x[i] - w->xprev[i]);
    norm += d * d;
  }
  norm = sqrt(norm);
  if (!(norm > 0.0)) return 0.0;
  for (int i = 0; i < na; i++) s->a[i] = s->sc[i] * s->sc[i] * (w->x[i] - w->xprev[i]) / norm;
  memcpy(s->xa, w->x, (size_t)na * sizeof *s->xa);
  return norm;
}

/* The pilot failed at its smallest increment (u turns back: a snap-back): go on by arc length
 * from the last two states, increments in units of the last step's scaled length. 0, or -1
 * when the last step has no length. */
static int lp_arc_start(vs_lp_solver *s, lp_path *w, double best) {
  const int n = s->n;
  const double *xs = N_VGetArrayPointer(s->xscale);
  for (int i = 0; i < n; i++) s->sc[i] = xs[i];
  s->sc[n] = 1.0 / fmax(fabs(best), 1e-12);
  const double len = lp_arc_direction(s, w);
  if (!(len > 0.0)) return -1;
  s->arc = 1;
  w->hmin = VS_LP_ARC_MIN * len;
  w->hmax = len * s->o->step_max / fmin(s->o->peak_tol, s->o->step);
  w->h = len;
  s->arc_min = w->hmin;
  N_VGetArrayPointer(s->fscale)[n] = 1.0 / w->hmin;
  return 0;
}

/* The predictor of an increment h: along the secant through the last two states, else the
 * last state. */
static void lp_predict(const vs_lp_solver *s, const lp_path *w, double h) {
  const int na = s->n + 1;
  double r = 0.0;
  if (s->arc) {
    double norm = 0.0;
    for (int i = 0; i < na; i++) {
      const double d = s->sc[i] * (w->x[i] - w->xprev[i]);
      norm += d * d;
    }
    r = norm > 0.0 ? h / sqrt(norm) : 0.0;
  } else if (w->have_prev && w->u > w->uprev) {
    r = h / (w->u - w->uprev);
  }
  for (int i = 0; i < na; i++) w->xtry[i] = w->x[i] + r * (w->x[i] - w->xprev[i]);
}

/* No equilibrium at the smallest increment: past a fall of drop from the peak the collapse
 * stands (its mechanism followed as far as it could be), else the path stalled. */
static void lp_stalled(const vs_lp_solver *s, const lp_path *w, double best, int flag,
                       vs_load_result *res) {
  res->end = res->peaked && w->x[s->n] < (1.0 - s->o->drop) * best ? VS_LOAD_END_PEAK
                                                                    : VS_LOAD_END_STALLED;
  snprintf(res->cause, sizeof res->cause,
           "no equilibrium beyond the load's displacement %.6g mm (from where loading began)%s "
           "at the smallest increment (%s, KINSOL flag %d)",
           (w->u - res->u_start) / VS_MM, s->arc ? ", by arc length," : "",
           vs_lp_kin_cause(flag), flag);
}

static vs_status lp_path_run(vs_lp_solver *s, lp_path *w, vs_load_step_fn fn, void *user,
                             vs_load_result *res, vs_error *err) {
  const vs_load_opts *o = s->o;
  const int n = s->n;
  const double u0 = w->u;
  double best = w->x[n];
  int slid_last = 0;
  long arc_since_best = 0;
  w->hmin = fmin(o->peak_tol, o->step);
  w->hmax = o->step_max;
  for (;;) {
    if (res->steps + res->rejected >= VS_LP_MAX_INCREMENTS)
      return vs_error_set(err, VS_ERR_SOLVER, "load path: %ld increments (the limit)",
                          VS_LP_MAX_INCREMENTS);
    const double h = w->h;
    lp_predict(s, w, h);
    long it = 0;
    const int flag = vs_lp_solve(s, s->arc ? h : w->u + h, w->xtry, &it);
    res->newton_iterations += it;
    if (flag != 0) {
      vs_status st = lp_fatal(s, w->u, err);
      if (st != VS_OK) return st;
      res->rejected++;
      /* the first increment, from no predictor, may be cut further (stiff joints) */
      const double hlow = res->steps == 0 ? VS_LP_FIRST_CUT * w->hmin : w->hmin;
      if (h > hlow) {
        w->h = fmax(0.5 * h, hlow);
        continue;
      }
      /* near the peak (lambda not yet down by drop), u may have turned back: arc length */
      if (!s->arc && w->have_prev && w->x[n] >= (1.0 - o->drop) * best &&
          lp_arc_start(s, w, best) == 0) {
        res->arc_from = w->u;
        continue;
      }
      lp_stalled(s, w, best, flag, res);
      return VS_OK;
    }
    const double lam = w->xtry[n], unew = vs_model_load_displacement(s->m, w->xtry);
    /* from the largest lambda so far, the peak lies within h: bracket it (each new peak) */
    if (lam < w->x[n] && w->x[n] >= best && !w->bracketed && h > w->hmin) {
      res->rejected++;
      w->bracketing = 1;
      w->h = fmax(0.5 * h, w->hmin);
      continue;
    }
    int slid = 0;
    lp_step_accept(s, w, unew, &slid);
    if (s->arc) lp_arc_direction(s, w);
    res->steps++;
    if (lam > best) {
      best = lam;
      res->lambda_peak = lam;
      res->u_peak = unew;
      w->bracketed = 0;
    } else if (!w->bracketed) {
      if (!res->peaked) { /* the first limit point of lambda: where load control would snap */
        res->lambda_first = best;
        res->u_first = res->u_peak;
      }
      res->peaked = 1;
      w->bracketing = 0;
      w->bracketed = 1;
    }
    res->lambda_last = lam;
    res->u_last = unew;
    if (fn != NULL && fn(user, lam, unew, w->x, s->m) != 0)
      return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
    /* past the peak, lambda down by drop: the collapse, once u has gone follow beyond the peak
     * (on the arc, where u need not grow, once VS_LP_ARC_PATIENCE steps found no larger
     * lambda). Not where lambda is gone: a held arch's snap under the load (a hinge jumping to
     * the next joint) can take the path through lambda <= 0 and up again beyond its first
     * peak, to where the arch carries more (the load control's snap lands there) */
    arc_since_best = lam >= best ? 0 : arc_since_best + s->arc;
    if (res->peaked && lam < (1.0 - o->drop) * best &&
        ((!s->arc && unew - res->u_peak >= o->follow) || arc_since_best >= VS_LP_ARC_PATIENCE)) {
      res->end = VS_LOAD_END_PEAK;
      return VS_OK;
    }
    /* sliding joints carry lambda without any stiffness against it: a plateau, as the support's
     * path's sliding mechanism (VS_PATH_PLATEAU_RTOL) */
    if (slid > 0 && slid_last > 0 && fabs(lam - w->xprev[n]) <= VS_PATH_PLATEAU_RTOL * fabs(lam)) {
      res->end = VS_LOAD_END_SLIDING;
      return VS_OK;
    }
    slid_last = slid;
    if (unew - u0 >= o->max_disp) {
      res->end = VS_LOAD_END_MAX_DISP;
      return VS_OK;
    }
    if (it <= VS_LP_EASY && !w->bracketing) w->h = fmin(VS_LP_GROW * h, w->hmax);
    if (!s->arc && unew + w->h - u0 > o->max_disp) w->h = u0 + o->max_disp - unew;
  }
}

const char *vs_lp_kin_cause(int flag) {
  switch (flag) {
  case KIN_LINESEARCH_NONCONV: return "line search could not reduce the residual";
  case KIN_MAXITER_REACHED: return "Newton iteration limit reached";
  case KIN_MXNEWT_5X_EXCEEDED: return "five consecutive maximum-length Newton steps (diverging)";
  case KIN_LSETUP_FAIL: return "the bordered Jacobian could not be factored";
  case KIN_LSOLVE_FAIL: return "the linear solve failed";
  case KIN_STEP_LT_STPTOL: return "Newton stalled with the residual above tolerance";
  default: return "KINSOL failure";
  }
}

vs_status vs_load_path_run(vs_model *m, const vs_load_opts *o, double delta, double *q,
                           vs_load_step_fn fn, void *user, vs_load_result *res, vs_error *err) {
  memset(res, 0, sizeof *res);
  res->lambda_peak = res->lambda_last = 0.0;
  if (!(o->step > 0.0 && o->step_max >= o->step && o->peak_tol > 0.0 && o->max_disp > 0.0 &&
        o->drop > 0.0 && o->drop < 1.0 && o->follow >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "load path: options out of range (step %g m, step_max %g m, peak_tol %g "
                        "m, max_disp %g m, drop %g, follow %g m; allowed: 0 < step <= step_max, "
                        "peak_tol > 0, max_disp > 0, 0 < drop < 1, follow >= 0)",
                        o->step, o->step_max, o->peak_tol, o->max_disp, o->drop, o->follow);
  vs_lp_solver s;
  vs_status st = vs_lp_create(&s, m, o, err);
  if (st != VS_OK) return st;
  s.delta = delta;
  const int na = s.n + 1;
  lp_path w = {0};
  w.x = malloc((size_t)na * sizeof *w.x);
  w.xprev = malloc((size_t)na * sizeof *w.xprev);
  w.xtry = malloc((size_t)na * sizeof *w.xtry);
  if (w.x == NULL || w.xprev == NULL || w.xtry == NULL) {
    st = vs_error_set(err, VS_ERR_NOMEM, "load path: out of memory");
  } else {
    memcpy(w.x, q, (size_t)s.n * sizeof *q);
    w.x[s.n] = 0.0;
    memcpy(w.xprev, w.x, (size_t)na * sizeof *w.x);
    vs_model_set_load_factor(m, 0.0);
    w.u = w.uprev = vs_model_load_displacement(m, q);
    w.h = o->step;
    res->u_start = res->u_peak = res->u_last = w.u;
    res->arc_from = res->lambda_first = res->u_first = NAN;
    st = lp_path_run(&s, &w, fn, user, res, err);
    memcpy(q, w.x, (size_t)s.n * sizeof *q);
    vs_model_set_load_factor(m, w.x[s.n]);
  }
  res->jacobian_evals = s.jac_evals;
  res->max_residual = s.max_residual;
  free(w.x), free(w.xprev), free(w.xtry);
  vs_lp_destroy(&s);
  return st;
}
