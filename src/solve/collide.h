/* Contact between bodies that share no joint during the fall: non-adjacent blocks, and a block
 * and a pier (a support body). Used by the dynamic phase (dynamic.c) with the ground
 * (contact.h); SI units.
 *
 * Every body (the blocks, then the left and the right support) has a convex outline, a polygon
 * that moves with it. A block's: the convex polygon of its outline (outline.h: vs_block_hull;
 * for an arch voussoir its four corners and its extrados arc's mid-point, the intrados arc
 * replaced by its chord); a pier's: its springing face and the vertical
 * drops from the face's two ends by the arch's span (a column under the face). Broad phase: the
 * outlines' axis-aligned bounding boxes, widened by a margin (the first joint's length), give
 * the candidate pairs of bodies that share no joint; narrow phase: a vertex of one outline
 * inside the other's meets it on the edge it is least deep behind (kept from step to step
 * while the vertex stays behind it, with its friction anchor: within a step the contact's
 * direction does not jump from edge to edge), with penetration p (its depth behind that edge) and the ground's law (contact.h): N = k_v p + c_v s(p) p',
 * k_v = k_n b t / 2, the dashpot c_v = 2 zeta sqrt(k_v m_r / 2) with the pair's reduced mass m_r
 * (a pier's mass infinite), faded in over p_f = m_r g / k_v; friction: a tangential spring
 * k_t = k_v k_s / k_n along the edge from an anchor held in the edge's body, capped by
 * mu k_v p (return mapping at commit; reset where the vertex leaves or changes edge). Both
 * bodies get the equal and opposite forces at the vertex: the forces are the gradient of the
 * springs' energy over both bodies' unknowns, so their Jacobian couples the two bodies. */
#ifndef VOUSSOIR_COLLIDE_H
#define VOUSSOIR_COLLIDE_H

#include "voussoir/model.h"
#include "voussoir/status.h"

typedef struct vs_collide vs_collide;

/* Create the contacts for model m (borrowed) with the coefficient of restitution e in (0, 1].
 * Outlines: count[i] vertices for body i (the n_blocks blocks, then the left and the right
 * support), their reference coordinates (m) concatenated in xz (x, z pairs), each outline convex
 * (either orientation; 0 vertices: the body takes no part); or count NULL: the arch's (above).
 * Starts disarmed. VS_ERR_INVALID on a bad e or outline. */
vs_status vs_collide_create(const vs_model *m, double restitution, const int *count,
                            const double *xz, vs_collide **out, vs_error *err);
void vs_collide_destroy(vs_collide **c);

/* The bodies of the contacts: the blocks, then the left and the right pier. The body of a joint's
 * end (a block index, VS_SUPPORT_LEFT or VS_SUPPORT_RIGHT). */
static inline int vs_collide_body(const vs_geometry *g, int end) {
  return end >= 0 ? end : end == VS_SUPPORT_LEFT ? g->n_blocks : g->n_blocks + 1;
}

/* Each body's reference point into ref (2 per body, m): a block's centroid, a pier's springing
 * joint's centre. Used by the fall (fall.h) too. */
void vs_collide_reference_points(const vs_geometry *g, double *ref);

/* The arch's outlines (above): per block its convex outline's vertices (5 for a voussoir of
 * the circular arch), per pier 4, into count (per body) and xz (m, reference configuration) as
 * vs_collide_create takes them; either may be NULL. Returns the number of vertices, -1 when a
 * block's outline cannot be made convex. Used by the fall (fall.h) too. */
int vs_collide_arch_outlines(const vs_geometry *g, int *count, double *xz);

/* Outlines from count and xz (as vs_collide_create takes them) into the caller's arrays: per
 * body its first vertex and count, per vertex its body and its offset (rx, rz) from the body's
 * reference point ref (2 per body), each outline made counter-clockwise, and per edge (numbered
 * as its first vertex) its outward unit normal (n0x, n0z), all in the reference configuration.
 * VS_ERR_INVALID, naming `who`, on a non-finite vertex, two that coincide, or an outline of 1,
 * 2 or more than max_vertices vertices or of no area. Used by the fall (fall.h) too. */
typedef struct {
  int *first, *count, *body;
  double *rx, *rz, *n0x, *n0z;
} vs_collide_outline;
vs_status vs_collide_outlines(int nb, const int *count, const double *xz, const double *ref,
                              int max_vertices, const char *who, const vs_collide_outline *o,
                              vs_error *err);

void vs_collide_arm(vs_collide *c, const double *qe); /* anchors from the state qe */
void vs_collide_disarm(vs_collide *c);
int vs_collide_armed(const vs_collide *c);
int vs_collide_bodies(const vs_collide *c);

/* Root functions, one per vertex: min(margin, the signed distance of the vertex from every
 * candidate outline) (the signed distance from a convex outline: the largest over its edges of
 * the distance in front of the edge's line; negative inside). Its sign is exact (a vertex inside
 * an outline is in its box): it crosses zero where the vertex enters or leaves an outline. */
int vs_collide_count(const vs_collide *c);
void vs_collide_roots(vs_collide *c, const double *qe, double *g);

/* Add the contact forces at (qe, ve) to F (may be NULL; gradient form, vs_model_ext_size
 * entries); *damped += dashpot power, *friction += slip power (W; either may be NULL). */
void vs_collide_forces(vs_collide *c, const double *qe, const double *ve, double *F,
                       double *damped, double *friction);

/* The broad phase at qe: pair[a * nb + b] = pair[b * nb + a] = 1 for the candidate pairs of
 * bodies (nb = vs_collide_bodies), 0 elsewhere. Every pair the forces couple at qe is a
 * candidate (their Jacobian stays inside the pattern this reserves). */
void vs_collide_pairs(vs_collide *c, const double *qe, unsigned char *pair);

/* Add dF/dqe into K and dF/dve into C (dense, column-major, ne x ne with ne =
 * vs_model_ext_size; either may be NULL). The dashpot's dependence on the positions is left
 * out, as for the joints. */
void vs_collide_jacobian(vs_collide *c, const double *qe, const double *ve, double *K,
                         double *C);

/* Elastic energy stored in the contacts (normal and tangential springs), J. */
double vs_collide_energy(vs_collide *c, const double *qe);

/* Accept qe as a converged state: anchors moved (return mapping), set or reset. */
void vs_collide_commit(vs_collide *c, const double *qe);

/* Largest penetration of a vertex into another body's outline at qe (m; 0 when none). */
double vs_collide_max_penetration(vs_collide *c, const double *qe);

#endif
