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
  e->cracking = vs_model_cracking_energy(d->m) - d->cracking0;
  e->balance = e->kinetic + e->gravity + e->elastic - e->support_work + e->damped + e->friction +
               e->cracking - e0;
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

/* One vs_dynamic_run's state, shared by the helpers of its loop. */
typedef struct {
  vs_dyn_sample_fn sample;
  vs_dyn_event_fn event;
  void *user;
  vs_dyn_result *res;
  vs_error *err;
  vs_status st;           /* the run's status: an error ends it */
  vs_energy e;            /* the energies at the current state */
  double e0;              /* the total energy at the start: the balance's reference */
  double scale;           /* the largest energy term so far: the balance's scale */
  double t, t_end, t_stop, t_last_sample, t_rest;
  int moving, collapsed;
  double wall_fall;       /* wall-clock time at the collapse criterion */
  long restarts;          /* vs_dyn_restart_roots so far */
  long base_steps, base_newton; /* IDA's counters up to its last restart */
  /* the ringing window (vs_dyn_opts's ring_window): its start, whether anything changed in it
   * (a crack grew, a joint slid, an edge crossed the hinge threshold, an impact), its kinetic
   * energy's peak and the previous window's */
  double ring_t0, ring_crack0, ring_peak, ring_peak_prev;
  int ring_changed;
} dyn_run;

/* What take_step did: an accepted step, a restart (take another), or the end of the run. */
enum { STEP_TAKEN, STEP_AGAIN, STEP_END };

/* The result cleared and IDA re-initialised at t0 from the static state q, v (the supports'
 * states driven, a pinned support's rotation its own), with the tolerances, the roots and the
 * Newton coefficient before the fall. */
static vs_status run_start(vs_dynamic *d, double t0, const double *q, const double *v,
                           vs_dyn_result *res, vs_error *err) {
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
  return VS_OK;
}

/* Consistent initial values: q, v given (the supports' from the constraints), v' from the
 * equations of motion, lambda and mu (algebraic) solved for: IDA_YA_YDP_INIT; IDA to stop at
 * t_end. */
static vs_status initial_conditions(vs_dynamic *d, double t0, double t_end, vs_error *err) {
  const int flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t0 + 1e-6 * (t_end - t0));
  if (flag != IDA_SUCCESS && vs_dyn_stopped(d))
    return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDACalcIC failed (flag %d): %s", flag, d->msg);
  IDAGetConsistentIC(d->ida, d->y, d->yp);
  IDASetStopTime(d->ida, t_end);
  return VS_OK;
}

/* The energies at t0 (the impact model armed there first), the balance's reference, and the
 * first sample. VS_ERR_STOPPED when the caller stops it. */
static vs_status first_sample(vs_dynamic *d, dyn_run *r, double t0) {
  double *y = N_VGetArrayPointer(d->y);
  if (d->imp != NULL) vs_dyn_impact_arm(d, y, 1);
  d->cracking0 = vs_model_cracking_energy(d->m);
  energies(d, y, 0.0, &r->e);
  r->e0 = r->e.kinetic + r->e.gravity + r->e.elastic;
  r->scale = fabs(r->e0);
  r->e.balance = 0.0; /* the reference of the balance */
  if (r->sample != NULL &&
      (static_state(d, y),
       r->sample(r->user, t0, vs_dyn_delta_at(d, t0), d->qst, d->vst, &r->e)) != 0)
    return vs_error_set(r->err, VS_ERR_STOPPED, "stopped by the caller");
  r->t_last_sample = t0;
  r->res->t_motion = t0;
  r->res->delta_motion = vs_dyn_delta_at(d, t0);
  return VS_OK;
}

/* One IDA step (the step-th). A "root found very near t" restarts IDA (STEP_AGAIN); a failure
 * after the collapse criterion ends the fall there (said so in the result), before it the run
 * (r->st); so do a stop flag and the step limit. *flag: IDASolve's flag of a STEP_TAKEN. */
static int take_step(vs_dynamic *d, dyn_run *r, long step, int *flag_out) {
  vs_dyn_result *res = r->res;
  if (vs_dyn_stopped(d) || vs_deadline_passed(d->o.deadline)) { /* the deadline: once a step */
    r->st = vs_error_set(r->err, VS_ERR_INTERRUPTED, "interrupted");
    return STEP_END;
  }
  if (step >= VS_DYN_MAX_STEPS) {
    r->st = vs_error_set(r->err, VS_ERR_SOLVER,
                         "IDA took %ld steps (the limit) and reached t = %.6g s "
                         "(delta = %.6g mm) of %.6g s", VS_DYN_MAX_STEPS, r->t,
                         vs_dyn_delta_at(d, r->t) * 1e3, r->t_stop);
    return STEP_END;
  }
  int flag = IDASolve(d->ida, r->t_stop, &r->t, d->y, d->yp, IDA_ONE_STEP);
  if (flag < 0 && vs_dyn_stopped(d)) {
    r->st = vs_error_set(r->err, VS_ERR_INTERRUPTED, "interrupted");
    return STEP_END;
  }
  if (flag < 0 && vs_dyn_close_roots(d, flag) && ++r->restarts <= VS_DYN_MAX_ROOT_RESTARTS) {
    vs_dyn_carry_counters(d, &r->base_steps, &r->base_newton);
    const int rf = vs_dyn_restart_roots(d, r->t, r->t_stop);
    if (rf == IDA_SUCCESS) return STEP_AGAIN;
    flag = rf;
  }
  if (flag < 0 && r->collapsed) { /* the collapse stands: the fall ends here, said so */
    res->end = VS_DYN_COLLAPSED;
    res->fall_failed_t = r->t;
    snprintf(res->fall_failure, sizeof res->fall_failure, "%s",
             d->msg[0] ? d->msg : "unknown cause");
    return STEP_END;
  }
  if (flag < 0) {
    r->st = vs_error_set(r->err, VS_ERR_SOLVER, "IDA failed at t = %.6g s (delta = %.6g mm): %s",
                         r->t, vs_dyn_delta_at(d, r->t) * 1e3,
                         d->msg[0] ? d->msg : "unknown cause");
    return STEP_END;
  }
  *flag_out = flag;
  return STEP_TAKEN;
}

/* The ringing window (vs_dyn_opts's ring_window) after an accepted step, r->e current: at the
 * end of a window, is the motion an elastic oscillation dying out? Nothing changed in the window
 * (no crack grew, no joint slid, no edge crossed the hinge threshold, no impact) and its kinetic
 * energy's peak fell below the previous window's (a decaying vibration; a departure, a collapse
 * or a snap still under way gains energy). The first window of a run never ends it. */
static int ringing_over(const vs_dynamic *d, dyn_run *r) {
  if (!(d->o.ring_window > 0.0) || !d->o.settle || r->collapsed) return 0;
  if (r->e.cracking != r->ring_crack0) r->ring_changed = 1;
  r->ring_peak = fmax(r->ring_peak, r->e.kinetic);
  if (r->t - r->ring_t0 < d->o.ring_window) return 0;
  const int over = !r->ring_changed && r->ring_peak < r->ring_peak_prev;
  r->ring_peak_prev = r->ring_peak;
  r->ring_peak = 0.0;
  r->ring_t0 = r->t;
  r->ring_crack0 = r->e.cracking;
  r->ring_changed = 0;
  return over;
}

/* The accepted step's state committed (the joints' slips, the impact model's arming, the
 * contacts' anchors), its energies, drift and extremes into the result, and the motion episodes
 * followed. Returns 1 when the arch is at rest: below rest_ke for the rest window. */
static int commit_step(vs_dynamic *d, dyn_run *r) {
  vs_dyn_result *res = r->res;
  double *y = N_VGetArrayPointer(d->y);
  const double t = r->t;
  vs_dyn_joint_states(d, y);
  /* seamless: the return-mapped force is unchanged */
  if (vs_model_commit_states(d->m, d->js) > 0) r->ring_changed = 1;
  if (d->imp != NULL) vs_dyn_impact_arm(d, y, 0);
  if (d->ct != NULL && vs_contact_armed(d->ct)) {
    vs_contact_commit(d->ct, y);
    res->max_penetration = fmax(res->max_penetration, vs_contact_max_penetration(d->ct, y, NULL));
  }
  if (d->cl != NULL && vs_collide_armed(d->cl)) {
    vs_collide_commit(d->cl, y);
    res->max_overlap = fmax(res->max_overlap, vs_collide_max_penetration(d->cl, y));
  }
  vs_energy *e = &r->e;
  energies(d, y, r->e0, e);
  d->max_drift = fmax(d->max_drift, vs_dyn_drift(d, t, y));
  r->scale = fmax(r->scale, fmax(fabs(e->kinetic), fmax(fabs(e->gravity), fabs(e->elastic))));
  r->scale = fmax(r->scale, fmax(fabs(e->support_work), fabs(e->damped)));
  if (!r->collapsed)
    res->balance_error_rel = fmax(res->balance_error_rel, fabs(e->balance) / r->scale);
  else
    res->balance_error_fall = fmax(res->balance_error_fall, fabs(e->balance) / r->scale);
  res->max_kinetic = fmax(res->max_kinetic, e->kinetic);
  /* motion episodes: moving while the kinetic energy is above rest_ke; at rest once it has
   * stayed below for rest_time (a single mode passes through zero at its turning points) */
  if (e->kinetic >= d->o.rest_ke) {
    r->moving = 1;
    r->t_rest = t;
  } else {
    r->moving = 0;
  }
  const double window = r->collapsed && d->ct != NULL ? fmin(d->o.rest_time, VS_DYN_FALL_REST)
                                                      : d->o.rest_time;
  return !r->moving && t - r->t_rest >= window;
}

/* The roots IDA returned at this step: the joints' events to the caller (joint_root: before the
 * collapse criterion; *stop set when the caller asks to stop), the impacts, the departure of a
 * motion, and the collapse criterion with the fall's restart. VS_OK, or the error that ends the
 * run (also in r->st). */
static vs_status on_roots(vs_dynamic *d, dyn_run *r, double delta, int joint_root, int *stop) {
  vs_dyn_result *res = r->res;
  double *y = N_VGetArrayPointer(d->y);
  const double t = r->t;
  IDAGetRootInfo(d->ida, d->roots);
  res->root_events++;
  for (int k = 0; k < 2 * d->nj && joint_root; k++) {
    if (d->roots[k] != 0) r->ring_changed = 1;
    if (d->roots[k] == 0 || r->event == NULL) continue;
    vs_dyn_event ev = {.t = t, .delta = delta, .joint = k / 2 + 1,
                       .side = (k % 2 == 0) ? 'E' : 'I', .opened = d->roots[k] > 0};
    static_state(d, y);
    if (r->event(r->user, &ev, d->qst) != 0) *stop = 1;
  }
  if (d->imp != NULL && !r->collapsed) { /* impacts: velocities jump, the energy is charged */
    const int ni = vs_dyn_impact_resolve(d, t, r->t_stop, &r->base_steps, &r->base_newton);
    if (ni < 0)
      return r->st = vs_dyn_stopped(d)
                         ? vs_error_set(r->err, VS_ERR_INTERRUPTED, "interrupted")
                         : vs_error_set(r->err, VS_ERR_SOLVER, "at t = %.6g s: %s", t, d->msg);
    res->impacts += ni;
    if (ni > 0) r->ring_changed = 1;
    energies(d, y, r->e0, &r->e);
  }
  if (d->roots[2 * d->nj + 1] > 0 && !r->collapsed) { /* a departure, located */
    res->t_motion = t;
    res->delta_motion = delta;
    res->onset_found = 1;
  }
  if (d->roots[2 * d->nj] > 0 && !r->collapsed) {
    r->collapsed = 1;
    res->t_collapse = t;
    r->t_stop = fmin(r->t_end, t + d->o.fall_time);
    const int rf =
        vs_dyn_start_fall(d, t, r->t_stop, &r->base_steps, &r->base_newton, &r->wall_fall);
    if (rf != IDA_SUCCESS)
      return r->st = vs_error_set(r->err, VS_ERR_SOLVER,
                                  "IDA restart for the fall failed (flag %d)", rf);
  }
  return VS_OK;
}

/* IDA's counters into the result: its own since the last restart and those carried. */
static void count_steps(vs_dynamic *d, dyn_run *r) {
  IDAGetNumSteps(d->ida, &r->res->steps);
  IDAGetNumNonlinSolvIters(d->ida, &r->res->newton_iterations);
  r->res->steps += r->base_steps;
  r->res->newton_iterations += r->base_newton;
}

/* Hand the current state at delta to the caller's sample function (the result's counters kept
 * current for it). Returns the callback's value. */
static int sample_now(vs_dynamic *d, dyn_run *r, double delta) {
  r->t_last_sample = r->t;
  count_steps(d, r); /* kept current for the callback */
  static_state(d, N_VGetArrayPointer(d->y));
  return r->sample(r->user, r->t, delta, d->qst, d->vst, &r->e);
}

/* Has the run ended after this step (flag: IDASolve's; at_rest: commit_step's, or 2 when the
 * ringing is over)? The end into the result: the debris at rest on the ground, the fall's time over, max_delta, or settled. */
static int run_over(const vs_dynamic *d, dyn_run *r, int flag, int at_rest) {
  vs_dyn_result *res = r->res;
  if (r->collapsed && d->ct != NULL && at_rest) { /* the debris at rest on the ground */
    res->end = VS_DYN_COLLAPSED;
    res->fall_at_rest = 1;
    return 1;
  }
  if (r->collapsed && r->t >= r->t_stop * (1.0 - 1e-15)) {
    res->end = VS_DYN_COLLAPSED;
    return 1;
  }
  if (flag == IDA_TSTOP_RETURN || r->t >= r->t_end) {
    res->end = r->collapsed ? VS_DYN_COLLAPSED : VS_DYN_MAX_DELTA;
    return 1;
  }
  if (d->o.settle && !r->collapsed && at_rest) {
    res->end = VS_DYN_SETTLED;
    res->ringing = at_rest == 2;
    return 1;
  }
  return 0;
}

/* Where the run ended into the result, the last sample (unless the last step had one), and the
 * static state back into q, v. Returns the run's status. */
static vs_status run_finish(vs_dynamic *d, dyn_run *r, double *q, double *v) {
  vs_dyn_result *res = r->res;
  double *y = N_VGetArrayPointer(d->y);
  res->t_end = r->t;
  res->delta_end = vs_dyn_delta_at(d, r->t);
  if (r->collapsed) res->fall_wall_s = vs_wall_now() - r->wall_fall;
  count_steps(d, r);
  if (r->st == VS_OK && r->sample != NULL && r->t > r->t_last_sample &&
      (static_state(d, y), r->sample(r->user, r->t, res->delta_end, d->qst, d->vst, &r->e)) != 0)
    r->st = vs_error_set(r->err, VS_ERR_STOPPED, "stopped by the caller");
  res->jac_evals = d->jac_evals;
  res->e_end = r->e;
  static_state(d, y);
  memcpy(q, d->qst, (size_t)d->nq * sizeof *q);
  memcpy(v, d->vst, (size_t)d->nq * sizeof *v);
  res->max_drift = d->max_drift;
  return r->st;
}

vs_status vs_dynamic_run(vs_dynamic *d, double t0, double *q, double *v, vs_dyn_sample_fn sample,
                         vs_dyn_event_fn event, void *user, vs_dyn_result *res, vs_error *err) {
  vs_status st = run_start(d, t0, q, v, res, err);
  if (st != VS_OK) return st;
  const double t_end = d->o.max_delta / d->o.rate;
  if (t_end <= t0) {
    res->end = VS_DYN_MAX_DELTA;
    res->t_end = t0;
    res->delta_end = vs_dyn_delta_at(d, t0);
    return VS_OK;
  }
  st = initial_conditions(d, t0, t_end, err);
  if (st != VS_OK) return st;
  dyn_run r = {.sample = sample, .event = event, .user = user, .res = res, .err = err,
               .st = VS_OK, .t = t0, .t_end = t_end, .t_stop = t_end,
               .t_last_sample = -INFINITY, .t_rest = t0, .wall_fall = NAN, .ring_t0 = t0};
  st = first_sample(d, &r, t0);
  if (st != VS_OK) return st;
  for (long step = 0;; step++) {
    int flag = 0;
    const int taken = take_step(d, &r, step, &flag);
    if (taken == STEP_AGAIN) continue;
    if (taken == STEP_END) break;
    const double delta = vs_dyn_delta_at(d, r.t);
    const int at_rest = commit_step(d, &r);
    int stop = 0;
    const int joint_root = flag == IDA_ROOT_RETURN && !r.collapsed; /* the fall's: contacts only */
    if (flag == IDA_ROOT_RETURN && on_roots(d, &r, delta, joint_root, &stop) != VS_OK) break;
    const int ended = at_rest ? 1 : ringing_over(d, &r) ? 2 : 0; /* after the step's roots */
    if (sample != NULL && (r.t - r.t_last_sample >= d->o.sample_dt || joint_root) &&
        sample_now(d, &r, delta) != 0)
      stop = 1;
    if (stop) {
      r.st = vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
      break;
    }
    if (run_over(d, &r, flag, ended)) break;
  }
  return run_finish(d, &r, q, v);
}
