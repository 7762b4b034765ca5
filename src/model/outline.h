/* Private to libvoussoir: the blocks' outlines as the contacts and the fall use them (a convex
 * polygon per block) and the circular arch's sectors (geometry.c, imperfections.c). Not
 * installed. */
#ifndef VOUSSOIR_OUTLINE_H
#define VOUSSOIR_OUTLINE_H

#include "voussoir/geometry.h"

/* The most vertices a block's convex outline may have. */
enum { VS_HULL_MAX = 64 };

/* A curved edge that turns by more than this (rad) gives its convex outline more than its
 * mid-point: one point more per this much turn. */
#define VS_HULL_TURN 0.5235987755982988 /* 30 degrees */

/* Block `block`'s convex outline, counter-clockwise (x, z pairs into xz, room for VS_HULL_MAX
 * points), and per vertex the edge it starts (edge index in g->edges) or, for a point inside
 * a curved edge, -1 - that edge (either array may be NULL): each edge's start, and inside an
 * edge that bulges outward its mid-point (its point at 0.5 (u0 + u1); more points, evenly
 * spaced, when it turns by more than VS_HULL_TURN); an edge that bulges inward is replaced by its
 * chord. Where that polygon is not convex (a notch between two edges), the corners turning
 * inward are dropped until it is. Returns the number of vertices: 0 for a block without an
 * outline, -1 when it cannot be made convex or has more than VS_HULL_MAX. */
int vs_block_hull(const vs_geometry *g, int block, double *xz, int *edge_of);

/* The convex hull of the n points xz (x, z pairs, sorted in place) into out (room for n + 1
 * points), counter-clockwise, without collinear points: Andrew's monotone chain. Returns its
 * number of vertices, 0 when the points enclose no area. */
int vs_convex_hull(double *xz, int n, double *out);

/* The annular sector ri..re over phi0..phi1 (from the crown, clockwise) of mass rho_b per unit
 * area: its exact area, mass, centroid and inertia into blk, and phi0, phi1 (not its outline). */
void vs_sector_block(double ri, double re, double phi0, double phi1, double rho_b, vs_block *blk);

/* The outline of the annular sector ri..re over phi0..phi1 (from the crown, clockwise) into
 * e[4]: the intrados arc phi0 -> phi1, the face on joint jr (phi1) outward, the extrados arc
 * back, the face on joint jl (phi0) inward. */
void vs_sector_edges(double ri, double re, double phi0, double phi1, int jl, int jr, vs_edge e[4]);

/* Exact area, centroid and polar second moment about the centroid of the region the closed
 * loop of n edges encloses (counter-clockwise), by Green's theorem: each segment in closed form,
 * each curve by Gauss-Legendre quadrature of order 20, its parameter range halved until two
 * levels agree to round-off (integrated, never a polygon). */
typedef struct {
  double area, cx, cz, j; /* m^2; m; m^4 about the centroid */
} vs_section;
void vs_outline_section(const vs_edge *e, int n, vs_section *s);

#endif
