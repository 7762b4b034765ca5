/* Contact of the falling blocks with the ground: a horizontal plane z = level meeting the
 * blocks' vertices through the joints' no-tension, frictional, elastic law, lumped at the
 * vertex. Used by the dynamic phase (dynamic.c) during the fall; SI units.
 *
 * A vertex is a corner of a block's convex outline (outline.h: vs_block_hull; for an arch
 * voussoir its four corners and the mid-point of its extrados arc, the only point of a convex
 * arc that can reach further than its chord). At penetration p = level - z_v > 0 the ground pushes the vertex up with
 *   N = k_v p + c_v s(p) p',   k_v = k_n b t / 2,   c_v = 2 zeta sqrt(k_v m_block / 2),
 * k_v being the stiffness of half a joint face (t the thickness, b the depth): a block lying on
 * a face rests on its two end vertices with the face's Winkler stiffness k_n b t. s(p) fades the
 * dashpot in over the first p_f = m g / k_v of penetration (so the force is continuous at
 * touch-down); zeta = -ln e / sqrt(pi^2 + ln^2 e) from the coefficient of restitution e of a
 * block landing flat on a face (two vertices, each carrying half its mass: a linear
 * spring-dashpot of ratio zeta, whose rebound speed is e times the landing speed). Friction: a tangential spring k_t = k_v k_s / k_n from an
 * anchor, capped by Coulomb |T| <= mu k_v p (the elastic normal force), the anchor moved by
 * return mapping when the vertex slides and reset where the vertex leaves the ground (as the
 * joints' shear, whose energy is then a function of the state). */
#ifndef VOUSSOIR_CONTACT_H
#define VOUSSOIR_CONTACT_H

#include <sundials/sundials_matrix.h>

#include "model_matrix.h"
#include "voussoir/model.h"
#include "voussoir/status.h"

typedef struct vs_contact vs_contact;

/* Create the ground contact for the blocks of model m (borrowed; its law gives k_n, k_s and mu)
 * with the coefficient of restitution e in (0, 1] of a vertex impact. The vertices: nv of them,
 * vertex k on block block[k] at (xz[2k], xz[2k+1]) in the reference configuration (m); or, when
 * nv is 0, the blocks' (the corners and bulges of each block's convex outline, outline.h),
 * leaving out the vertices on a support's face (the springer voussoirs' corners on their
 * supports): they sit on the pier.
 * The ground starts disarmed (no force, no roots). VS_ERR_INVALID on a bad e or vertex. */
vs_status vs_contact_create(const vs_model *m, double restitution, int nv, const int *block,
                            const double *xz, vs_contact **out, vs_error *err);
void vs_contact_destroy(vs_contact **c);

/* Arm the ground at height level (m, z up, in the geometry's frame) for the extended state qe
 * (vs_model_ext_size entries); the friction anchors start at the vertices' positions. */
void vs_contact_arm(vs_contact *c, double level, const double *qe);
/* Disarm: no force, no roots. */
void vs_contact_disarm(vs_contact *c);
int vs_contact_armed(const vs_contact *c);
double vs_contact_level(const vs_contact *c);

/* The height (m) of the lower of the two springings' bases (the intrados ends of the support
 * joints) for the supports' states in qe. */
double vs_contact_springing_base(const vs_model *m, const double *qe);

/* Number of vertices (and of root functions); the position of vertex k at qe. */
int vs_contact_count(const vs_contact *c);
void vs_contact_vertex(const vs_contact *c, const double *qe, int k, double *x, double *z);

/* Root functions: g[k] = z_k - level (a vertex crossing the ground), one per vertex. */
void vs_contact_roots(const vs_contact *c, const double *qe, double *g);

/* Add the contact forces at (qe, ve) to F (may be NULL; the gradient form of the equations of
 * motion: M v' + F = ..., vs_model_ext_size entries); *damped += power dissipated by the dashpots and
 * *friction += power dissipated by slip (W; either pointer may be NULL). Nothing when
 * disarmed. */
void vs_contact_forces(const vs_contact *c, const double *qe, const double *ve, double *F,
                       double *damped, double *friction);

/* Add dF/dqe into K and dF/dve into C (either may be NULL), CSC matrices with the pattern of
 * vs_model_ext_jacobian (K's is read, or C's without K; C's data is taken to share it): a vertex couples only its own block's three unknowns, which that
 * pattern holds, so the pattern (and KLU's analysis) never changes. The dashpot's dependence on
 * the positions is left out, as for the joints. */
void vs_contact_jacobian(const vs_contact *c, const double *qe, const double *ve, SUNMatrix K,
                         SUNMatrix C);

/* Elastic energy stored in the contacts (normal and tangential springs), J. */
double vs_contact_energy(const vs_contact *c, const double *qe);

/* Accept qe as a converged state: move the friction anchors (return mapping; reset off the
 * ground). */
void vs_contact_commit(vs_contact *c, const double *qe);

/* Largest penetration of any vertex at qe (m; <= 0 when none touches), and the vertex. */
double vs_contact_max_penetration(const vs_contact *c, const double *qe, int *which);

#endif
