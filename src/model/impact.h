/* The `impact` damping model: energy lost where a joint edge that had opened closes again.
 * At that instant (an IDA root on the edge's physical gap) a perfectly plastic impulse P acts
 * at the closing edge, on the two bodies of the joint (equal and opposite), such that the edge
 * points of both bodies move together afterwards (relative velocity zero, normal and tangential,
 * as long as |P_t| <= mu P_n; beyond it the edge slides: P_t = mu P_n and only the normal
 * relative velocity is zeroed). Positions do not change; the kinetic energy lost,
 * 1/2 w . W^-1 w for a sticking impact (w the relative velocity of the edge, W the bodies'
 * mobility at it), is charged to the dissipated energy. For a rigid block rocking on a rigid
 * base this is Housner's impact: the impulse passes through the new pivot, so the angular
 * momentum about it is conserved, and the old pivot lifts off. The other joints are elastic
 * (finite forces) and transmit no impulse; a support body is immovable for the impulse (it is
 * driven at a constant speed; a pinned springer's rotation included). No viscous damping: a
 * joint in steady contact dissipates nothing, so every mode under self-weight gets ratio 0.
 * SI units. */
#ifndef VOUSSOIR_IMPACT_H
#define VOUSSOIR_IMPACT_H

#include "voussoir/model.h"

/* Physical gap of joint k's edge (side 0: intrados, eta = 0; 1: extrados) in state st, m
 * (> 0 open): the kinematic gap plus the as-built misfit (the law's gap0 + gap1 xi), so that
 * it is zero where the faces touch. */
double vs_impact_edge_gap(const vs_model *m, int k, int side, const vs_joint_state *st);

/* Apply the plastic impulse of joint k's edge `side` to the extended velocities ve (blocks then
 * supports, vs_model_ext_size entries; only the blocks' change) at the extended positions qe.
 * Returns the kinetic energy lost, J (>= 0; 0 and ve unchanged when the edge is not closing). */
double vs_impact_apply(const vs_model *m, const double *qe, double *ve, int k, int side);

/* Which joint edges count for impacts: an edge is armed once its gap has exceeded `open`
 * (the hinge threshold: the joint had opened) and disarmed by its impact, so that edges in
 * steady contact, or barely parting, never dissipate. */
typedef struct vs_impact vs_impact;

/* For model m (borrowed), edges armed beyond `open` (m, > 0). NULL when out of memory. */
vs_impact *vs_impact_create(const vs_model *m, double open);
void vs_impact_destroy(vs_impact **imp);

/* Number of root functions (2 per joint). */
int vs_impact_nroots(const vs_impact *imp);
/* Disarm every edge, then arm those open beyond `open` in the joint states st. */
void vs_impact_reset(vs_impact *imp, const vs_joint_state *st);
/* Arm the edges open beyond `open` in st (after every accepted step). */
void vs_impact_arm(vs_impact *imp, const vs_joint_state *st);
/* Root functions into g: an armed edge's physical gap, 1 (never a root) for the others. */
void vs_impact_roots(const vs_impact *imp, const vs_joint_state *st, double *g);
/* Resolve the impacts of the roots found (roots: IDA's root info for the vs_impact_nroots
 * functions, < 0 where a gap fell through zero): a plastic impulse at each such armed edge,
 * which is then disarmed. Returns the kinetic energy lost (J) and sets *count to the impacts. */
double vs_impact_resolve(vs_impact *imp, const double *qe, double *ve, const int *roots,
                         int *count);

#endif
