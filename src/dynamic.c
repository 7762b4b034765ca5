/* Dynamic phase with IDA: F(t, y, y') = 0 for y = (q, v, W, D, Df) with
 *   q' - v = 0,   M v' + G(q, delta(t)) + C(q) v = 0,
 *   W' = support power,   D' = damping power,   Df' = friction power,
 * the last three being the energy bookkeeping (IDA in SUNDIALS 6 has no quadratures).
 * Jacobian dF/dy + cj dF/dy' in CSC with KLU; roots on the joints' edge openings and on the
 * collapse criterion; friction slips committed after every step. */
#include "voussoir/dynamic.h"

#include <ida/ida.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* KLU ordering: natural, the Jacobian is block-banded (see quasistatic.c). */
static const int VS_DYN_KLU_ORDERING = 2;
/* BDF order cap. The joints' contact modes are stiff, lightly damped oscillators (k_n b t over a
 * voussoir's mass: ~1e4 rad/s); BDF of order 3-5 is unstable near the imaginary axis, so it would
 * need steps of 1/omega throughout. BDF1-2 are A-stable and damp those modes at large steps. */
static const int VS_DYN_MAX_ORDER = 2;
/* A velocity error is judged by the position error it makes over this time (s), about the period
 * of the contact modes: tighter velocity tolerances would make IDA resolve those vibrations. */
static const double VS_DYN_VEL_TIME = 1e-4;
/* After the collapse criterion the fall is integrated with tolerances this many times looser:
 * it is recorded to be looked at, not measured. */
static const double VS_DYN_FALL_TOL = 100.0;

struct vs_dynamic {
  vs_model *m;
  vs_dyn_opts o;
  int n;  /* 3 per block */
  int N;  /* 2n + 3 */
  int nj; /* joints */
  SUNContext ctx;
  N_Vector y, yp, id, atol;
  SUNMatrix J, K, C;
  SUNLinearSolver LS;
  void *ida;
  double *mass, *work;    /* n each */
  vs_joint_state *js;
  int *roots;
  long jac_evals;
  char msg[256];
};

static double delta_at(const vs_dynamic *d, double t) { return d->o.rate * t; }

static int stopped(const vs_dynamic *d) { return d->o.stop != NULL && *d->o.stop; }

void vs_dynamic_set_stop(vs_dynamic *d, const volatile sig_atomic_t *stop) { d->o.stop = stop; }

/* A raised stop flag is fatal (-1): IDA returns at once. */
static int res_fn(double t, N_Vector yy, N_Vector yp, N_Vector rr, void *user) {
  vs_dynamic *d = user;
  if (stopped(d)) return -1;
  const int n = d->n;
  const double *y = N_VGetArrayPointer(yy), *ydot = N_VGetArrayPointer(yp);
  double *r = N_VGetArrayPointer(rr);
  const double *q = y, *v = y + n, *qd = ydot, *vd = ydot + n;
  const double delta = delta_at(d, t), rate = d->o.rate;
  for (int i = 0; i < n; i++) r[i] = qd[i] - v[i];
  vs_model_residual(d->m, q, delta, r + n);
  double diss = 0.0, sup_d = 0.0;
  vs_model_damping(d->m, q, v, delta, rate, d->work, &diss, &sup_d, NULL);
  for (int i = 0; i < n; i++) r[n + i] += d->mass[i] * vd[i] + d->work[i];
  const double sup = vs_model_support_force(d->m, q, delta) * rate + sup_d;
  r[2 * n] = ydot[2 * n] - sup;
  r[2 * n + 1] = ydot[2 * n + 1] - diss;
  r[2 * n + 2] = ydot[2 * n + 2] - vs_model_friction_power(d->m, q, v, delta, rate);
  return 0;
}

/* J = dF/dy + cj dF/dy': [[cj I, -I], [K, cj M + C]] and cj on the bookkeeping diagonal (their
 * dependence on q, v is left out: nothing depends on them, so Newton still converges). The
 * dependence of the damping forces on the positions is left out too (IDA's Newton is a
 * modified Newton already; it converges linearly with it). */
static int jac_fn(double t, double cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix Jac,
                  void *user, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)yp;
  (void)rr;
  (void)t1;
  (void)t2;
  if (stopped(user)) return -1;
  (void)t3;
  vs_dynamic *d = user;
  const int n = d->n;
  const double *y = N_VGetArrayPointer(yy);
  const double delta = delta_at(d, t);
  d->jac_evals++;
  vs_model_jacobian(d->m, y, delta, d->K);
  vs_model_damping(d->m, y, y + n, delta, d->o.rate, NULL, NULL, NULL, d->C);
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(d->K), *ki = SUNSparseMatrix_IndexValues(d->K);
  const double *kx = SUNSparseMatrix_Data(d->K), *cx = SUNSparseMatrix_Data(d->C);
  sunindextype *jp = SUNSparseMatrix_IndexPointers(Jac), *ji = SUNSparseMatrix_IndexValues(Jac);
  double *jx = SUNSparseMatrix_Data(Jac);
  sunindextype p = 0;
  for (int col = 0; col < n; col++) { /* q columns */
    jp[col] = p;
    ji[p] = col;
    jx[p++] = cj;
    for (sunindextype e = kp[col]; e < kp[col + 1]; e++) {
      ji[p] = n + ki[e];
      jx[p++] = kx[e];
    }
  }
  for (int col = 0; col < n; col++) { /* v columns */
    jp[n + col] = p;
    ji[p] = col;
    jx[p++] = -1.0;
    for (sunindextype e = kp[col]; e < kp[col + 1]; e++) {
      ji[p] = n + ki[e];
      jx[p++] = cx[e] + (ki[e] == col ? cj * d->mass[col] : 0.0);
    }
  }
  for (int col = 2 * n; col < d->N; col++) {
    jp[col] = p;
    ji[p] = col;
    jx[p++] = cj;
  }
  jp[d->N] = p;
  return 0;
}

/* Roots: for every joint, its intrados and extrados edge openings minus the hinge threshold;
 * last, the kinetic energy minus the collapse threshold. */
static int root_fn(double t, N_Vector yy, N_Vector yp, double *g, void *user) {
  (void)yp;
  vs_dynamic *d = user;
  const double *q = N_VGetArrayPointer(yy);
  vs_model_joint_states(d->m, q, delta_at(d, t), d->js);
  for (int k = 0; k < d->nj; k++) {
    g[2 * k] = d->js[k].gap_i - d->o.open;
    g[2 * k + 1] = d->js[k].gap_e - d->o.open;
  }
  g[2 * d->nj] = vs_model_kinetic_energy(d->m, q + d->n) - d->o.collapse_ke;
  return 0;
}

static void ida_err(int code, const char *module, const char *function, char *msg, void *user) {
  vs_dynamic *d = user;
  (void)code;
  snprintf(d->msg, sizeof d->msg, "%s/%s: %s", module, function, msg);
}

void vs_dynamic_destroy(vs_dynamic **dp) {
  if (dp == NULL || *dp == NULL) return;
  vs_dynamic *d = *dp;
  if (d->ida != NULL) IDAFree(&d->ida);
  if (d->LS != NULL) SUNLinSolFree(d->LS);
  if (d->J != NULL) SUNMatDestroy(d->J);
  if (d->K != NULL) SUNMatDestroy(d->K);
  if (d->C != NULL) SUNMatDestroy(d->C);
  if (d->y != NULL) N_VDestroy(d->y);
  if (d->yp != NULL) N_VDestroy(d->yp);
  if (d->id != NULL) N_VDestroy(d->id);
  if (d->atol != NULL) N_VDestroy(d->atol);
  if (d->ctx != NULL) SUNContext_Free(&d->ctx);
  free(d->mass);
  free(d->work);
  free(d->js);
  free(d->roots);
  free(d);
  *dp = NULL;
}

static vs_status dyn_fail(vs_dynamic **d, vs_error *err, const char *what, int flag) {
  vs_dynamic_destroy(d);
  return vs_error_set(err, VS_ERR_SOLVER, "dynamic solver setup: %s failed (flag %d)", what, flag);
}

vs_status vs_dynamic_create(vs_model *m, const vs_dyn_opts *o, vs_dynamic **out, vs_error *err) {
  *out = NULL;
  if (!(o->rate > 0.0) || !(o->rtol > 0.0) || !(o->atol_q > 0.0) || !(o->open > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "dynamic: rate %g m/s, rtol %g, atol %g m, open %g m (allowed: all > 0)",
                        o->rate, o->rtol, o->atol_q, o->open);
  vs_dynamic *d = calloc(1, sizeof *d);
  if (d == NULL) return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  d->m = m;
  d->o = *o;
  d->n = vs_model_size(m);
  d->N = 2 * d->n + 3;
  d->nj = vs_model_geometry(m)->n_joints;
  const int n = d->n, nnzK = vs_model_nnz(m);
  int flag = SUNContext_Create(NULL, &d->ctx);
  if (flag != 0) return dyn_fail(&d, err, "SUNContext_Create", flag);
  d->y = N_VNew_Serial(d->N, d->ctx);
  d->yp = N_VNew_Serial(d->N, d->ctx);
  d->id = N_VNew_Serial(d->N, d->ctx);
  d->atol = N_VNew_Serial(d->N, d->ctx);
  d->J = SUNSparseMatrix(d->N, d->N, 2 * n + 2 * nnzK + 3, CSC_MAT, d->ctx);
  d->K = SUNSparseMatrix(n, n, nnzK, CSC_MAT, d->ctx);
  d->C = SUNSparseMatrix(n, n, nnzK, CSC_MAT, d->ctx);
  d->mass = malloc((size_t)n * sizeof *d->mass);
  d->work = malloc((size_t)n * sizeof *d->work);
  d->js = malloc((size_t)d->nj * sizeof *d->js);
  d->roots = malloc((size_t)(2 * d->nj + 1) * sizeof *d->roots);
  if (d->y == NULL || d->yp == NULL || d->id == NULL || d->atol == NULL || d->J == NULL ||
      d->K == NULL || d->C == NULL || d->mass == NULL || d->work == NULL ||
      d->js == NULL || d->roots == NULL) {
    vs_dynamic_destroy(&d);
    return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  }
  vs_model_mass(m, d->mass);
  /* tolerances: positions atol_q (rotations atol_q / joint length), velocities the same over
   * VS_DYN_VEL_TIME, the energy bookkeeping the arch's weight times atol_q */
  double *scale = d->work, *at = N_VGetArrayPointer(d->atol);
  vs_model_residual_scale(m, scale);
  double wsum = 0.0;
  for (int i = 0; i < n; i += 3) {
    const double len = scale[i + 2] / scale[i];
    const double tv = VS_DYN_VEL_TIME;
    at[i] = at[i + 1] = o->atol_q;
    at[n + i] = at[n + i + 1] = o->atol_q / tv;
    at[i + 2] = o->atol_q / len;
    at[n + i + 2] = o->atol_q / len / tv;
    wsum += scale[i];
  }
  for (int i = 2 * n; i < d->N; i++) at[i] = wsum * o->atol_q;
  N_VConst(1.0, d->id); /* every component is differential */

  d->LS = SUNLinSol_KLU(d->y, d->J, d->ctx);
  if (d->LS == NULL) return dyn_fail(&d, err, "SUNLinSol_KLU", 0);
  if ((flag = SUNLinSol_KLUSetOrdering(d->LS, VS_DYN_KLU_ORDERING)) != 0)
    return dyn_fail(&d, err, "SUNLinSol_KLUSetOrdering", flag);
  d->ida = IDACreate(d->ctx);
  if (d->ida == NULL) return dyn_fail(&d, err, "IDACreate", 0);
  N_VConst(0.0, d->y);
  N_VConst(0.0, d->yp);
  if ((flag = IDAInit(d->ida, res_fn, 0.0, d->y, d->yp)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDAInit", flag);
  if ((flag = IDASetUserData(d->ida, d)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetUserData", flag);
  if ((flag = IDASetErrHandlerFn(d->ida, ida_err, d)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetErrHandlerFn", flag);
  if ((flag = IDASVtolerances(d->ida, o->rtol, d->atol)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASVtolerances", flag);
  if ((flag = IDASetId(d->ida, d->id)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetId", flag);
  if ((flag = IDASetLinearSolver(d->ida, d->LS, d->J)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetLinearSolver", flag);
  if ((flag = IDASetJacFn(d->ida, jac_fn)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetJacFn", flag);
  if ((flag = IDASetMaxOrd(d->ida, VS_DYN_MAX_ORDER)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetMaxOrd", flag);
  if ((flag = IDASetMaxNumSteps(d->ida, 100000)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetMaxNumSteps", flag);
  if ((flag = IDARootInit(d->ida, 2 * d->nj + 1, root_fn)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDARootInit", flag);
  if ((flag = IDASetNoInactiveRootWarn(d->ida)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetNoInactiveRootWarn", flag);
  *out = d;
  return VS_OK;
}

/* Energies at the current state; balance relative to e0 (the total at the phase's start). */
static void energies(vs_dynamic *d, double t, const double *y, double e0, vs_energy *e) {
  const int n = d->n;
  e->kinetic = vs_model_kinetic_energy(d->m, y + n);
  vs_model_energies(d->m, y, delta_at(d, t), &e->elastic, &e->gravity);
  e->support_work = y[2 * n];
  e->damped = y[2 * n + 1];
  e->friction = y[2 * n + 2];
  e->balance = e->kinetic + e->gravity + e->elastic - e->support_work + e->damped + e->friction - e0;
}

vs_status vs_dynamic_run(vs_dynamic *d, double t0, double *q, double *v, vs_dyn_sample_fn sample,
                         vs_dyn_event_fn event, void *user, vs_dyn_result *res, vs_error *err) {
  const int n = d->n;
  memset(res, 0, sizeof *res);
  res->t_collapse = NAN;
  double *y = N_VGetArrayPointer(d->y);
  memcpy(y, q, (size_t)n * sizeof *y);
  memcpy(y + n, v, (size_t)n * sizeof *y);
  y[2 * n] = y[2 * n + 1] = y[2 * n + 2] = 0.0;
  N_VConst(0.0, d->yp);
  d->msg[0] = '\0';
  int flag = IDAReInit(d->ida, t0, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDASVtolerances(d->ida, d->o.rtol, d->atol);
  if (flag == IDA_SUCCESS) flag = IDARootInit(d->ida, 2 * d->nj + 1, root_fn);
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDAReInit failed (flag %d)", flag);
  /* consistent initial derivatives: q' = v given, v' from the equations of motion */
  const double t_end = d->o.max_delta / d->o.rate;
  if (t_end <= t0) {
    res->end = VS_DYN_MAX_DELTA;
    res->t_end = t0;
    res->delta_end = delta_at(d, t0);
    return VS_OK;
  }
  flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t0 + 1e-6 * (t_end - t0));
  if (flag != IDA_SUCCESS && stopped(d)) return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDACalcIC failed (flag %d): %s", flag, d->msg);
  IDAGetConsistentIC(d->ida, d->y, d->yp);
  IDASetStopTime(d->ida, t_end);
  vs_energy e;
  energies(d, t0, y, 0.0, &e);
  const double e0 = e.kinetic + e.gravity + e.elastic;
  double scale = fabs(e0), t = t0, t_last_sample = -INFINITY, t_rest = t0, t_stop = t_end;
  int moving = 0, collapsed = 0;
  long base_steps = 0, base_newton = 0;
  vs_status st = VS_OK;
  e.balance = 0.0; /* the reference of the balance */
  if (sample != NULL && sample(user, t0, delta_at(d, t0), y, y + n, &e) != 0)
    return vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  t_last_sample = t0;
  res->t_motion = t0;
  res->delta_motion = delta_at(d, t0);
  for (long step = 0;; step++) {
    if (stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (step >= VS_DYN_MAX_STEPS) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA took %ld steps (the limit) and reached t = %.6g s "
                        "(delta = %.6g mm) of %.6g s", VS_DYN_MAX_STEPS, t, delta_at(d, t) * 1e3,
                        t_stop);
      break;
    }
    flag = IDASolve(d->ida, t_stop, &t, d->y, d->yp, IDA_ONE_STEP);
    if (flag < 0 && stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (flag < 0) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA failed at t = %.6g s (delta = %.6g mm): %s", t,
                        delta_at(d, t) * 1e3, d->msg[0] ? d->msg : "unknown cause");
      break;
    }
    const double delta = delta_at(d, t);
    vs_model_commit(d->m, y, delta); /* seamless: the return-mapped force is unchanged */
    energies(d, t, y, e0, &e);
    scale = fmax(scale, fmax(fabs(e.kinetic), fmax(fabs(e.gravity), fabs(e.elastic))));
    scale = fmax(scale, fmax(fabs(e.support_work), fabs(e.damped)));
    if (!collapsed) res->balance_error_rel = fmax(res->balance_error_rel, fabs(e.balance) / scale);
    else res->balance_error_fall = fmax(res->balance_error_fall, fabs(e.balance) / scale);
    res->max_kinetic = fmax(res->max_kinetic, e.kinetic);
    /* motion episodes: moving while the kinetic energy is above rest_ke; at rest once it has
     * stayed below for rest_time (a single mode passes through zero at its turning points) */
    if (e.kinetic >= d->o.rest_ke) {
      if (!moving && !collapsed) {
        moving = 1;
        res->t_motion = t;
        res->delta_motion = delta;
        res->onset_found = 1;
      }
      t_rest = t;
    } else {
      moving = 0;
    }
    const int at_rest = !moving && t - t_rest >= d->o.rest_time;
    int stop = 0;
    if (flag == IDA_ROOT_RETURN) {
      IDAGetRootInfo(d->ida, d->roots);
      res->root_events++;
      for (int k = 0; k < 2 * d->nj; k++) {
        if (d->roots[k] == 0 || event == NULL) continue;
        vs_dyn_event ev = {.t = t, .delta = delta, .joint = k / 2 + 1,
                           .side = (k % 2 == 0) ? 'E' : 'I', .opened = d->roots[k] > 0};
        if (event(user, &ev, y) != 0) stop = 1;
      }
      if (d->roots[2 * d->nj] > 0 && !collapsed) {
        collapsed = 1;
        res->t_collapse = t;
        t_stop = fmin(t_end, t + d->o.fall_time);
        /* the fall is followed for the record only: restart from here without events and
         * with looser tolerances (set on a restarted integrator: IDA re-reads them then) */
        long ns = 0, nn = 0; /* IDAReInit resets IDA's counters: carry the phase's */
        IDAGetNumSteps(d->ida, &ns);
        IDAGetNumNonlinSolvIters(d->ida, &nn);
        base_steps += ns;
        base_newton += nn;
        N_Vector at = N_VClone(d->atol);
        int rf = (at == NULL) ? -1 : IDAReInit(d->ida, t, d->y, d->yp);
        if (rf == IDA_SUCCESS) {
          N_VScale(VS_DYN_FALL_TOL, d->atol, at);
          rf = IDASVtolerances(d->ida, VS_DYN_FALL_TOL * d->o.rtol, at);
        }
        if (rf == IDA_SUCCESS) rf = IDARootInit(d->ida, 0, NULL);
        if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
        if (at != NULL) N_VDestroy(at);
        if (rf != IDA_SUCCESS) {
          st = vs_error_set(err, VS_ERR_SOLVER, "IDA restart for the fall failed (flag %d)", rf);
          break;
        }
      }
    }
    if (sample != NULL && (t - t_last_sample >= d->o.sample_dt || flag == IDA_ROOT_RETURN)) {
      t_last_sample = t;
      IDAGetNumSteps(d->ida, &res->steps); /* kept current for the callback */
      IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
      res->steps += base_steps;
      res->newton_iterations += base_newton;
      if (sample(user, t, delta, y, y + n, &e) != 0) stop = 1;
    }
    if (stop) {
      st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
      break;
    }
    if (collapsed && t >= t_stop * (1.0 - 1e-15)) {
      res->end = VS_DYN_COLLAPSED;
      break;
    }
    if (flag == IDA_TSTOP_RETURN || t >= t_end) {
      res->end = collapsed ? VS_DYN_COLLAPSED : VS_DYN_MAX_DELTA;
      break;
    }
    if (d->o.settle && !collapsed && at_rest) {
      res->end = VS_DYN_SETTLED;
      break;
    }
  }
  res->t_end = t;
  res->delta_end = delta_at(d, t);
  IDAGetNumSteps(d->ida, &res->steps);
  IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
  res->steps += base_steps;
  res->newton_iterations += base_newton;
  if (st == VS_OK && sample != NULL && t > t_last_sample &&
      sample(user, t, res->delta_end, y, y + n, &e) != 0) /* the final state */
    st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  res->jac_evals = d->jac_evals;
  memcpy(q, y, (size_t)n * sizeof *q);
  memcpy(v, y + n, (size_t)n * sizeof *v);
  return st;
}
