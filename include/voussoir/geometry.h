/* Geometry of a block assembly: rigid blocks (mass, inertia, centroid, outline) and the
 * zero-thickness joints between them or between a block and a support. SI units throughout.
 * A block's outline is a closed loop of edges (segments and stretches of smooth curves), which
 * every consumer (contacts, the fall, the record, the pictures) samples through the functions
 * below. The arch builder makes the segmental circular arch of docs/model.md; tests build others. */
#ifndef VOUSSOIR_GEOMETRY_H
#define VOUSSOIR_GEOMETRY_H

#include "voussoir/api.h"

#include "voussoir/def.h"
#include "voussoir/status.h"

/* Joint ends that are not blocks. The left support is fixed; the right one is moved. */
#define VS_SUPPORT_LEFT (-1)
#define VS_SUPPORT_RIGHT (-2)

/* The smooth curves an edge can follow: a base curve B(u) of parameter u, in the arch's frame
 * (x right, z up), offset along its unit normal n(u) (its tangent B'(u) turned +90 degrees: up,
 * away from the void, on a curve run from left to right) by d(u) = d0 + d2 (B_x(u) - xc)^2. */
typedef enum {
  VS_CURVE_CIRCLE = 0,   /* B = (cx + a sin u, cz + a cos u): u the angle from the top, clockwise */
  VS_CURVE_ELLIPSE = 1,  /* B = (cx + a sin u, cz + b cos u): semi-axes a across, b up */
  VS_CURVE_PARABOLA = 2, /* B = (cx + u, cz - b (u / a)^2): vertex (cx, cz), b lower at u = +-a */
  VS_CURVE_CATENARY = 3, /* B = (cx + u, cz - a (cosh(u / a) - 1)): vertex (cx, cz) */
  VS_CURVE_KIND_COUNT
} vs_curve_kind;

typedef struct {
  vs_curve_kind kind;
  double cx, cz; /* centre (circle, ellipse) or vertex (parabola, catenary), m */
  double a, b;   /* as above, m */
  double d0, d2, xc; /* the offset d(u) = d0 + d2 (B_x(u) - xc)^2: m, 1/m, m */
} vs_curve;

/* One edge of a block's outline, run in the outline's direction (counter-clockwise). */
typedef struct {
  int curved;    /* 0: the segment from (x0, z0) to (x1, z1), u from 0 to 1; 1: curve c */
  vs_curve c;
  double u0, u1; /* the parameter at the edge's start and end (a segment: 0, 1) */
  double x0, z0, x1, z1; /* its start and end, m (a curve's: its points at u0 and u1) */
  int joint;     /* the joint (0-based) whose face the edge lies on, -1 when none */
} vs_edge;

typedef struct {
  double mass;       /* kg */
  double inertia;    /* kg m^2, about the centroid, for rotation in the plane */
  double cx, cz;     /* centroid in the reference configuration, m (x right, z up) */
  double area;       /* m^2, in the plane */
  double phi0, phi1; /* circular arch blocks: angular extent from the crown, rad (0 for other
                        blocks); the outline below is what describes any block */
  int edge0, n_edges; /* the outline: edges[edge0 .. edge0 + n_edges - 1] of the geometry, a
                         closed loop, counter-clockwise (n_edges 0: none given) */
} vs_block;

/* A planar joint face: the segment from its intrados end (eta = 0) to its extrados end
 * (eta = length). (nx, nz) is the unit normal pointing from body a to body b; the tangent along
 * the joint, from intrados to extrados, is the normal turned +90 degrees (vs_joint_tangent). */
typedef struct {
  int a, b;           /* bodies on each side: block index 0..n-1 or VS_SUPPORT_LEFT/RIGHT */
  double px, pz;      /* centre of the joint segment, reference configuration, m */
  double nx, nz;      /* unit normal from a to b */
  double length;      /* joint length t (intrados to extrados), m */
  double depth;       /* out-of-plane depth b, m */
  double kn, ks_ratio, mu; /* this interface's own law (a blocks file's): k_n (N/m^3), k_s /
                              k_n, friction; each 0: the run's (def.h: vs_joints_def) */
} vs_joint_geom;

/* A support's polygon (a blocks file's pier): its outline is edges[edge0 .. edge0 + n_edges - 1]
 * of the geometry, counter-clockwise, fixed to the support's body. */
typedef struct {
  int body; /* VS_SUPPORT_LEFT or VS_SUPPORT_RIGHT */
  int edge0, n_edges;
} vs_support_outline;

typedef struct {
  int n_blocks;
  int n_joints;
  vs_block *blocks;      /* n_blocks */
  vs_joint_geom *joints; /* n_joints, joint k (1-based in output) is joints[k-1] */
  int n_edges;           /* the blocks' outlines, each block's a run of these */
  vs_edge *edges;
  int ring;              /* joints[0 .. ring - 1] are the arch ring from the left springing
                            (on the left support) to the right one (on the right support); the
                            other joints follow (a blocks file's). 0: every joint */
  int n_supports;        /* the supports' polygons (a blocks file's; 0: none, a pier is drawn
                            and met under each springing face) */
  vs_support_outline *supports;
  double span;           /* intrados span L, m (arch) */
  double rise;           /* intrados rise, m (arch) */
  double radius, thickness, embrace; /* arch: intrados radius (m), thickness (m), embrace (rad) */
  double gravity;        /* m/s^2 */
  /* piers (def.h: vs_piers_def; docs/model.md, "Piers"), pier_courses blocks under each
   * springing (0: none). Pier p (0 left, 1 right): its course c (0 the bottom one) is block
   * pier_block[p] + c; joint pier_joint[p] + c is its base (c = 0: the foundation interface, on
   * the support) or the course joint under course c. The springing joints (the ring's first and
   * last) join the top courses to the arch. */
  int pier_courses;
  int pier_block[2], pier_joint[2];
} vs_geometry;

/* Tangent along joint j from intrados to extrados: the normal turned +90 degrees
 * (counter-clockwise), s = (-nz, nx). For an arch joint n is along the arch, s radial outward. */
static inline void vs_joint_tangent(const vs_joint_geom *j, double *sx, double *sz) {
  *sx = -j->nz;
  *sz = j->nx;
}

/* The joint of the left (right = 0) or right springing: the ring's first or last. */
static inline int vs_geometry_springing(const vs_geometry *g, int right) {
  return right ? (g->ring > 0 ? g->ring : g->n_joints) - 1 : 0;
}

/* What joint k is in a pier: 0 none (the arch ring's, or a blocks file's), 1 a pier's base
 * (the foundation interface), 2 a course joint; *pier (0 left, 1 right) and *course (the course
 * above it, 1 the bottom one) are set for 1 and 2 (either may be NULL). */
static inline int vs_geometry_pier_joint(const vs_geometry *g, int k, int *pier, int *course) {
  for (int p = 0; p < 2 && g->pier_courses > 0; p++) {
    const int c = k - g->pier_joint[p];
    if (c < 0 || c >= g->pier_courses) continue;
    if (pier != NULL) *pier = p;
    if (course != NULL) *course = c + 1;
    return c == 0 ? 1 : 2;
  }
  return 0;
}

/* The joint of the left (right = 0) or right support, about whose centre the support turns:
 * the springing joint, or with piers the pier's base (the foundation interface). */
static inline int vs_geometry_support_joint(const vs_geometry *g, int right) {
  return g->pier_courses > 0 ? g->pier_joint[right ? 1 : 0] : vs_geometry_springing(g, right);
}

/* Build arch a (def.h; docs/model.md, "Shapes"). By default (a's shape fields 0) the
 * segmental circular arch: voussoirs of equal angular size, radial joints, joint 1 on the left
 * springing plane, joint n+1 on the right one, the circle's centre at the origin, the crown on
 * the +z axis, exact annular-sector mass, centroid and inertia. Other shapes: their generator;
 * VS_SHAPE_FILE: the blocks of a->blocks_file (docs/blocks-file.md). With a->piers.height > 0,
 * a pier under each springing (vs_piers_def; the geometry's pier_* fields). VS_ERR_INVALID
 * (naming the case key, or the file's field and block) for a shape that cannot be built;
 * VS_ERR_IO for a file that cannot be read; VS_ERR_NOMEM. */
VS_API vs_status vs_geometry_create_arch(const vs_arch_def *a, vs_geometry **out, vs_error *err);

/* The blocks of g as a blocks file (docs/blocks-file.md) into *text (malloc'd, the caller
 * frees): each block a polygon (a curved edge sampled every 2 degrees of its turn, 6 segments
 * at most), in mm, named v1 .. vn; a pier under each springing face (its face, a level top
 * outward, an outer vertical, a base two thicknesses below), the supports; the ring from the
 * left pier to the right one; every joint's own law. An arch on piers (pier_courses > 0): the
 * piers' courses are blocks too (after the voussoirs), the foundations the supports, the ring
 * from the left foundation up the left pier, along the arch and down the right pier.
 * VS_ERR_INVALID for a geometry whose blocks have no outline or whose first and last joints
 * are not on the supports; VS_ERR_NOMEM. */
VS_API vs_status vs_geometry_blocks_json(const vs_geometry *g, char **text, vs_error *err);

/* Allocate an empty geometry with room for n_blocks blocks and n_joints joints (tests, other
 * shapes); the caller fills the arrays. */
VS_API vs_status vs_geometry_create(int n_blocks, int n_joints, vs_geometry **out, vs_error *err);

/* Free g and NULL *g; NULL and *g == NULL are allowed. */
VS_API void vs_geometry_destroy(vs_geometry **g);

/* Total weight of the blocks, N. */
VS_API double vs_geometry_weight(const vs_geometry *g);

/* Block `block`'s outline: n edges (a closed loop, counter-clockwise, each starting where the
 * previous one ends, within 1e-9 of the outline's size), appended to g's edges. A curve's ends
 * (x0, z0, x1, z1) are recomputed from u0 and u1. VS_ERR_INVALID for a bad block, n < 1, an
 * edge of no length or a loop that does not close; VS_ERR_NOMEM. */
VS_API vs_status vs_geometry_set_outline(vs_geometry *g, int block, int n, const vs_edge *edges,
                                         vs_error *err);

/* A polygon of support body (VS_SUPPORT_LEFT or VS_SUPPORT_RIGHT): n edges, a closed loop
 * counter-clockwise, appended to g's edges and its supports. Errors as vs_geometry_set_outline. */
VS_API vs_status vs_geometry_add_support(vs_geometry *g, int body, int n, const vs_edge *edges,
                                         vs_error *err);

/* Point p (m) and derivative dp = dp/du of curve c at parameter u (either may be NULL). */
VS_API void vs_curve_eval(const vs_curve *c, double u, double p[2], double dp[2]);

/* Point p and derivative dp/du of edge e at parameter u (a segment: u in [0, 1]). */
VS_API void vs_edge_eval(const vs_edge *e, double u, double p[2], double dp[2]);

/* The angle (rad, >= 0) by which edge e's tangent turns from its start to its end (0 for a
 * segment): the sum over eight equal parts of the parameter of each part's turn. */
VS_API double vs_edge_turn(const vs_edge *e);

/* Block `block`'s outline as points (x, z pairs into xz, room for max points), counter-clockwise
 * from its first edge's start: a curved edge gives m = max(min_points, ceil(turn / max_turn) + 1)
 * points (at most VS_OUTLINE_CURVE_MAX) evenly spaced in its parameter, both ends included; a
 * segment gives its start, unless the edge before it is curved (whose end it is). Returns the
 * number of points (more than max: only max written), 0 for a block without an outline. */
#define VS_OUTLINE_CURVE_MAX 1024
VS_API int vs_block_outline(const vs_geometry *g, int block, int min_points, double max_turn,
                            double *xz, int max);

#endif
