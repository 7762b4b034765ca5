/* The dynamic phase's integration (dynamic.h: vs_dynamic_run): from consistent initial values,
 * IDA one step at a time, each step committed and its energies balanced, the roots' events, the
 * samples, and the end (at rest, the fall over, max_delta). */
#include "voussoir/dynamic.h"

#include <ida/ida.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "dynamic_internal.h"
#include "wall_clock.h"

/* After the collapse criterion the fall is integrated with tolerances this many times looser:
 * it is recorded to be looked at, not measured. */
static const double VS_DYN_FALL_TOL = 100.0;
/* ... and this many when the fall lands on the ground (contact.h): its impacts need more. On the
 * reference run (runs/reference.ini, fall to rest), 100x looser left the energy balance of the
 * fall at 9 % (6556 IDA steps), 10x at 0.56 % (11160 steps), 1x at 0.044 % (24924 steps). */
static const double VS_DYN_FALL_TOL_GROUND = 10.0;

/* The debris is at rest on the ground when its kinetic energy has stayed below rest_ke for
 * this long (s), or rest_time if shorter. rest_time (1 s by default) is the quasi-static path's
 * window, long enough for a slow mode of the arch to pass a turning point; the debris lies on
 * contact springs whose periods are below a millisecond (2 pi sqrt(m / (2 k_v)), 0.5 ms for the
 * reference's voussoirs), and a block still rocking or sliding keeps its kinetic energy above
 * the rest level but for instants at its turning points: 0.1 s is a hundred of those periods.
 * On the reference run the last second of the fall, at rest but for the window, took ~10 % of
 * its steps and ~30 % of its Jacobian evaluations. */
static const double VS_DYN_FALL_REST = 0.1;
/* Restarts after IDA's "root found at and very near t" (vs_dyn_restart_roots) in one run at
 * most. */
static const long VS_DYN_MAX_ROOT_RESTARTS = 1000;

/* Energies at the current state; balance relative to e0 (the total at the phase's start). */
static void energies(vs_dynamic *d, const double *y, double e0, vs_energy *e) {
  e->kinetic = vs_model_kinetic_energy(d->m, y + d->iv);
  for (int i = 0; i < VS_DYN_NC; i++) /* a pinned support's rotation: its own kinetic energy */
    if (d->cidx[i] < 0) e->kinetic += 0.5 * d->mass[d->n + i] * y[d->iv + d->n + i] * y[d->iv + d->n + i];
  vs_dyn_joint_states(d, y);
  e->elastic = 0.0;
  for (int k = 0; k < d->nj; k++) e->elastic += d->js[k].energy;
  e->gravity = vs_model_gravity_energy(d->m, y);
  if (d->ct != NULL) e->elastic += vs_contact_energy(d->ct, y);
  if (d->cl != NULL) e->elastic += vs_collide_energy(d->cl, y);
  e->support_work = y[d->ie];
  e->damped = y[d->ie + 1];
  e->friction = y[d->ie + 2];
  e->balance = e->kinetic + e->gravity + e->elastic - e->support_work + e->damped + e->friction - e0;
}

/* The static state (blocks, pinned supports' rotations) of y into d->qst, d->vst. */
static void static_state(vs_dynamic *d, const double *y) {
  memcpy(d->qst, y, (size_t)d->n * sizeof *d->qst);
  memcpy(d->vst, y + d->iv, (size_t)d->n * sizeof *d->vst);
  for (int s = 0; s < 2; s++) {
    const int k = vs_model_support_dof(d->m, s);
    if (k < 0) continue;
    d->qst[k] = y[d->n + 3 * s + 2];
    d->vst[k] = y[d->iv + d->n + 3 * s + 2];
  }
}

vs_status vs_dynamic_run(vs_dynamic *d, double t0, double *q, double *v, vs_dyn_sample_fn sample,
                         vs_dyn_event_fn event, void *user, vs_dyn_result *res, vs_error *err) {
  const int n = d->n;
  memset(res, 0, sizeof *res);
  res->t_collapse = NAN;
  res->fall_failed_t = NAN;
  res->dae_differential = d->N - 2 * d->nc;
  res->dae_algebraic = 2 * d->nc;
  res->dae_index = 2;
  d->max_drift = 0.0;
  d->js_valid = 0; /* the slips may have moved since (the quasi-static path) */
  double *y = N_VGetArrayPointer(d->y);
  N_VConst(0.0, d->y);
  memcpy(y, q, (size_t)n * sizeof *y);
  memcpy(y + d->iv, v, (size_t)n * sizeof *y);
  vs_model_support_states(d->m, vs_dyn_delta_at(d, t0), d->o.rate, y + n, y + d->iv + n);
  for (int s = 0; s < 2; s++) { /* a pinned support's rotation: the static state's */
    const int k = vs_model_support_dof(d->m, s);
    if (k < 0) continue;
    y[n + 3 * s + 2] = q[k];
    y[d->iv + n + 3 * s + 2] = v[k];
  }
  N_VConst(0.0, d->yp);
  d->msg[0] = '\0';
  int flag = IDAReInit(d->ida, t0, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDASVtolerances(d->ida, d->rtol, d->atol);
  d->in_fall = 0;
  if (flag == IDA_SUCCESS) flag = vs_dyn_root_init(d);
  if (flag == IDA_SUCCESS) flag = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF);
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDAReInit failed (flag %d)", flag);
  /* consistent initial values: q, v given (the supports' from the constraints), v' from the
   * equations of motion, lambda and mu (algebraic) solved for: IDA_YA_YDP_INIT */
  const double t_end = d->o.max_delta / d->o.rate;
  if (t_end <= t0) {
    res->end = VS_DYN_MAX_DELTA;
    res->t_end = t0;
    res->delta_end = vs_dyn_delta_at(d, t0);
    return VS_OK;
  }
  flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t0 + 1e-6 * (t_end - t0));
  if (flag != IDA_SUCCESS && vs_dyn_stopped(d)) return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDACalcIC failed (flag %d): %s", flag, d->msg);
  IDAGetConsistentIC(d->ida, d->y, d->yp);
  IDASetStopTime(d->ida, t_end);
  if (d->imp != NULL) vs_dyn_impact_arm(d, y, 1);
  vs_energy e;
  energies(d, y, 0.0, &e);
  const double e0 = e.kinetic + e.gravity + e.elastic;
  double scale = fabs(e0), t = t0, t_last_sample = -INFINITY, t_rest = t0, t_stop = t_end;
  int moving = 0, collapsed = 0;
  double wall_fall = NAN; /* wall-clock time at the collapse criterion */
  long restarts = 0;      /* vs_dyn_restart_roots so far */
  long base_steps = 0, base_newton = 0;
  vs_status st = VS_OK;
  e.balance = 0.0; /* the reference of the balance */
  if (sample != NULL && (static_state(d, y), sample(user, t0, vs_dyn_delta_at(d, t0), d->qst, d->vst, &e)) != 0)
    return vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  t_last_sample = t0;
  res->t_motion = t0;
  res->delta_motion = vs_dyn_delta_at(d, t0);
  for (long step = 0;; step++) {
    if (vs_dyn_stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (step >= VS_DYN_MAX_STEPS) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA took %ld steps (the limit) and reached t = %.6g s "
                        "(delta = %.6g mm) of %.6g s", VS_DYN_MAX_STEPS, t, vs_dyn_delta_at(d, t) * 1e3,
                        t_stop);
      break;
    }
    flag = IDASolve(d->ida, t_stop, &t, d->y, d->yp, IDA_ONE_STEP);
    if (flag < 0 && vs_dyn_stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (flag < 0 && vs_dyn_close_roots(d, flag) && ++restarts <= VS_DYN_MAX_ROOT_RESTARTS) {
      long ns = 0, nn = 0; /* IDAReInit resets IDA's counters: carry them */
      IDAGetNumSteps(d->ida, &ns);
      IDAGetNumNonlinSolvIters(d->ida, &nn);
      base_steps += ns;
      base_newton += nn;
      const int rf = vs_dyn_restart_roots(d, t, t_stop);
      if (rf == IDA_SUCCESS) continue;
      flag = rf;
    }
    if (flag < 0 && collapsed) { /* the collapse stands: the fall ends here, said so */
      res->end = VS_DYN_COLLAPSED;
      res->fall_failed_t = t;
      snprintf(res->fall_failure, sizeof res->fall_failure, "%s",
               d->msg[0] ? d->msg : "unknown cause");
      break;
    }
    if (flag < 0) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA failed at t = %.6g s (delta = %.6g mm): %s", t,
                        vs_dyn_delta_at(d, t) * 1e3, d->msg[0] ? d->msg : "unknown cause");
      break;
    }
    const double delta = vs_dyn_delta_at(d, t);
    vs_dyn_joint_states(d, y);
    vs_model_commit_states(d->m, d->js); /* seamless: the return-mapped force is unchanged */
    if (d->imp != NULL) vs_dyn_impact_arm(d, y, 0);
    if (d->ct != NULL && vs_contact_armed(d->ct)) {
      vs_contact_commit(d->ct, y);
      res->max_penetration = fmax(res->max_penetration, vs_contact_max_penetration(d->ct, y, NULL));
    }
    if (d->cl != NULL && vs_collide_armed(d->cl)) {
      vs_collide_commit(d->cl, y);
      res->max_overlap = fmax(res->max_overlap, vs_collide_max_penetration(d->cl, y));
    }
    energies(d, y, e0, &e);
    d->max_drift = fmax(d->max_drift, vs_dyn_drift(d, t, y));
    scale = fmax(scale, fmax(fabs(e.kinetic), fmax(fabs(e.gravity), fabs(e.elastic))));
    scale = fmax(scale, fmax(fabs(e.support_work), fabs(e.damped)));
    if (!collapsed) res->balance_error_rel = fmax(res->balance_error_rel, fabs(e.balance) / scale);
    else res->balance_error_fall = fmax(res->balance_error_fall, fabs(e.balance) / scale);
    res->max_kinetic = fmax(res->max_kinetic, e.kinetic);
    /* motion episodes: moving while the kinetic energy is above rest_ke; at rest once it has
     * stayed below for rest_time (a single mode passes through zero at its turning points) */
    if (e.kinetic >= d->o.rest_ke) {
      moving = 1;
      t_rest = t;
    } else {
      moving = 0;
    }
    const double window = collapsed && d->ct != NULL ? fmin(d->o.rest_time, VS_DYN_FALL_REST)
                                                     : d->o.rest_time;
    const int at_rest = !moving && t - t_rest >= window;
    int stop = 0;
    const int joint_root = flag == IDA_ROOT_RETURN && !collapsed; /* the fall's: contacts only */
    if (flag == IDA_ROOT_RETURN) {
      IDAGetRootInfo(d->ida, d->roots);
      res->root_events++;
      for (int k = 0; k < 2 * d->nj && joint_root; k++) {
        if (d->roots[k] == 0 || event == NULL) continue;
        vs_dyn_event ev = {.t = t, .delta = delta, .joint = k / 2 + 1,
                           .side = (k % 2 == 0) ? 'E' : 'I', .opened = d->roots[k] > 0};
        static_state(d, y);
        if (event(user, &ev, d->qst) != 0) stop = 1;
      }
      if (d->imp != NULL && !collapsed) { /* impacts: velocities jump, the energy is charged */
        const int ni = vs_dyn_impact_resolve(d, t, t_stop, &base_steps, &base_newton);
        if (ni < 0) {
          st = vs_dyn_stopped(d) ? vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted")
                          : vs_error_set(err, VS_ERR_SOLVER, "at t = %.6g s: %s", t, d->msg);
          break;
        }
        res->impacts += ni;
        energies(d, y, e0, &e);
      }
      if (d->roots[2 * d->nj + 1] > 0 && !collapsed) { /* a departure, located */
        res->t_motion = t;
        res->delta_motion = delta;
        res->onset_found = 1;
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
        const double loose = d->ct != NULL ? VS_DYN_FALL_TOL_GROUND : VS_DYN_FALL_TOL;
        if (rf == IDA_SUCCESS) {
          N_VScale(loose, d->atol, at);
          rf = IDASVtolerances(d->ida, loose * d->rtol, at);
        }
        d->in_fall = 1;
        wall_fall = vs_wall_now();
        if (d->ct != NULL && !vs_contact_armed(d->ct))
          vs_contact_arm(d->ct, vs_contact_springing_base(d->m, y) + d->ground_offset, y);
        if (d->cl != NULL && !vs_collide_armed(d->cl)) vs_collide_arm(d->cl, y);
        if (rf == IDA_SUCCESS) rf = vs_dyn_root_init(d);
        if (rf == IDA_SUCCESS) rf = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF_FALL);
        if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
        if (at != NULL) N_VDestroy(at);
        if (rf != IDA_SUCCESS) {
          st = vs_error_set(err, VS_ERR_SOLVER, "IDA restart for the fall failed (flag %d)", rf);
          break;
        }
      }
    }
    if (sample != NULL && (t - t_last_sample >= d->o.sample_dt || joint_root)) {
      t_last_sample = t;
      IDAGetNumSteps(d->ida, &res->steps); /* kept current for the callback */
      IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
      res->steps += base_steps;
      res->newton_iterations += base_newton;
      static_state(d, y);
      if (sample(user, t, delta, d->qst, d->vst, &e) != 0) stop = 1;
    }
    if (stop) {
      st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
      break;
    }
    if (collapsed && d->ct != NULL && at_rest) { /* the debris at rest on the ground */
      res->end = VS_DYN_COLLAPSED;
      res->fall_at_rest = 1;
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
  res->delta_end = vs_dyn_delta_at(d, t);
  if (collapsed) res->fall_wall_s = vs_wall_now() - wall_fall;
  IDAGetNumSteps(d->ida, &res->steps);
  IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
  res->steps += base_steps;
  res->newton_iterations += base_newton;
  if (st == VS_OK && sample != NULL && t > t_last_sample &&
      (static_state(d, y), sample(user, t, res->delta_end, d->qst, d->vst, &e)) != 0)
    st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  res->jac_evals = d->jac_evals;
  res->e_end = e;
  static_state(d, y);
  memcpy(q, d->qst, (size_t)d->nq * sizeof *q);
  memcpy(v, d->vst, (size_t)d->nq * sizeof *v);
  res->max_drift = d->max_drift;
  return st;
}
