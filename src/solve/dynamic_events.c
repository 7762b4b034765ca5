/* The dynamic phase's events (dynamic_internal.h): the joints' states shared by the callbacks,
 * the root functions, IDA's restarts (roots found very near, the fall after the collapse
 * criterion) and the impact damping model's impulses. */
#include "voussoir/dynamic.h"

#include <ida/ida.h>
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

/* The joints' states at the positions of y into d->js, evaluated once per state: the root
 * function at the end of a step, the commit, the energies and the impact model's arming share
 * one evaluation. A commit at y leaves them valid: the return-mapped states are its own. */
void vs_dyn_joint_states(vs_dynamic *d, const double *y) {
  const size_t bytes = (size_t)d->ne * sizeof *y;
  if (d->js_valid && memcmp(d->js_q, y, bytes) == 0) return;
  vs_model_ext_joint_states(d->m, y, d->js);
  memcpy(d->js_q, y, bytes);
  d->js_valid = 1;
}

const vs_joint_state *vs_dynamic_joint_states(vs_dynamic *d) {
  vs_dyn_joint_states(d, N_VGetArrayPointer(d->y));
  return d->js;
}

/* Root functions: the joints', the energy levels' and the impact model's (before the fall),
 * then the vertices' (the ground's, then the bodies'). */
static int n_ground_roots(const vs_dynamic *d) {
  return (d->ct != NULL && vs_contact_armed(d->ct)) ? vs_contact_count(d->ct) : 0;
}

static int n_roots(const vs_dynamic *d) {
  const int nb = (d->cl != NULL && vs_collide_armed(d->cl)) ? vs_collide_count(d->cl) : 0;
  return (d->in_fall ? 0 : d->nroots) + n_ground_roots(d) + nb;
}

/* Roots: for every joint, its intrados and extrados edge openings minus the hinge threshold;
 * then the kinetic energy minus the collapse threshold, and minus the rest level (the departure
 * of a motion: where it rises through it). */
int vs_dyn_roots(double t, N_Vector yy, N_Vector yp, double *g, void *user) {
  (void)yp;
  (void)t;
  vs_dynamic *d = user;
  const double *q = N_VGetArrayPointer(yy);
  const int r0 = d->in_fall ? 0 : d->nroots;
  if (d->ct != NULL && vs_contact_armed(d->ct)) /* then a vertex crossing the ground */
    vs_contact_roots(d->ct, q, g + r0);
  if (d->cl != NULL && vs_collide_armed(d->cl)) /* then one entering another body */
    vs_collide_roots(d->cl, q, g + r0 + n_ground_roots(d));
  if (d->in_fall) return 0;
  vs_dyn_joint_states(d, q);
  for (int k = 0; k < d->nj; k++) {
    g[2 * k] = d->js[k].gap_i - d->o.open;
    g[2 * k + 1] = d->js[k].gap_e - d->o.open;
  }
  const double ke = vs_model_kinetic_energy(d->m, q + d->iv);
  g[2 * d->nj] = ke - d->o.collapse_ke;
  g[2 * d->nj + 1] = ke - d->o.rest_ke;
  if (d->imp != NULL) vs_impact_roots(d->imp, d->js, g + d->root_impact);
  return 0;
}

int vs_dyn_root_init(vs_dynamic *d) {
  const int nr = n_roots(d);
  return IDARootInit(d->ida, nr, nr > 0 ? vs_dyn_roots : NULL);
}

/* IDAReInit resets IDA's counters: carry them. */
void vs_dyn_carry_counters(const vs_dynamic *d, long *bs, long *bn) {
  long ns = 0, nn = 0;
  IDAGetNumSteps(d->ida, &ns);
  IDAGetNumNonlinSolvIters(d->ida, &nn);
  *bs += ns;
  *bn += nn;
}

/* IDA stops with "root found at and very near t" when a root function is exactly zero at the
 * root it just returned and a round-off later (a vertex crossing the ground at a crawl: its
 * height is resolved to ~1e-17 m). A restart from the returned state clears it: IDA's first-step
 * check then leaves such roots inactive until they move away from zero. */
int vs_dyn_close_roots(const vs_dynamic *d, int flag) {
  return flag == IDA_ILL_INPUT && strstr(d->msg, "very near") != NULL;
}

int vs_dyn_restart_roots(vs_dynamic *d, double t, double t_stop) {
  d->msg[0] = '\0';
  int rf = IDAReInit(d->ida, t, d->y, d->yp);
  if (rf == IDA_SUCCESS) rf = vs_dyn_root_init(d);
  if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
  return rf;
}

/* --- the impact damping model (impact.h): arming after each step, impulses at its roots --- */

/* Arm the edges that have opened (every accepted step; at the start with reset). */
void vs_dyn_impact_arm(vs_dynamic *d, const double *y, int reset) {
  vs_dyn_joint_states(d, y);
  if (reset) vs_impact_reset(d->imp, d->js);
  else vs_impact_arm(d->imp, d->js);
}

/* The impacts among the roots just found: plastic impulses on the velocities, their energy loss
 * into the damped energy (positions unchanged, so the balance holds), then IDA restarted from
 * the new velocities with consistent multipliers and derivatives (IDAReInit + IDACalcIC; IDA's
 * counters carried in *bs, *bn). Returns the impacts, or -1 (message in d->msg) if the restart
 * failed. */
int vs_dyn_impact_resolve(vs_dynamic *d, double t, double t_stop, long *bs, long *bn) {
  double *y = N_VGetArrayPointer(d->y);
  int count = 0;
  const double lost = vs_impact_resolve(d->imp, y, y + d->iv, d->roots + d->root_impact, &count);
  if (count == 0) return 0;
  y[d->ie + 1] += lost;
  vs_dyn_carry_counters(d, bs, bn);
  int flag = IDAReInit(d->ida, t, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t + VS_DYN_VEL_TIME);
  if (flag == IDA_SUCCESS) flag = IDAGetConsistentIC(d->ida, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDASetStopTime(d->ida, t_stop);
  if (flag == IDA_SUCCESS) return count;
  char cause[160];
  snprintf(cause, sizeof cause, "%.159s", d->msg);
  snprintf(d->msg, sizeof d->msg, "IDA restart after an impact failed (flag %d): %.159s", flag, cause);
  return -1;
}

/* --- the fall after the collapse criterion --- */

int vs_dyn_start_fall(vs_dynamic *d, double t, double t_stop, long *bs, long *bn,
                      double *wall_fall) {
  const double *y = N_VGetArrayPointer(d->y);
  /* the fall is followed for the record only: restart from here without events and
   * with looser tolerances (set on a restarted integrator: IDA re-reads them then) */
  vs_dyn_carry_counters(d, bs, bn); /* IDAReInit resets IDA's counters: carry the phase's */
  N_Vector at = N_VClone(d->atol);
  int rf = (at == NULL) ? -1 : IDAReInit(d->ida, t, d->y, d->yp);
  const double loose = d->ct != NULL ? VS_DYN_FALL_TOL_GROUND : VS_DYN_FALL_TOL;
  if (rf == IDA_SUCCESS) {
    N_VScale(loose, d->atol, at);
    rf = IDASVtolerances(d->ida, loose * d->rtol, at);
  }
  d->in_fall = 1;
  *wall_fall = vs_wall_now();
  if (d->ct != NULL && !vs_contact_armed(d->ct))
    vs_contact_arm(d->ct, vs_contact_springing_base(d->m, y) + d->ground_offset, y);
  if (d->cl != NULL && !vs_collide_armed(d->cl)) vs_collide_arm(d->cl, y);
  if (rf == IDA_SUCCESS) rf = vs_dyn_root_init(d);
  if (rf == IDA_SUCCESS) rf = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF_FALL);
  if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
  if (at != NULL) N_VDestroy(at);
  return rf;
}
