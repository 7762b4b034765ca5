/* Geometry of a block assembly: rigid blocks (mass, inertia, centroid, outline) and the
 * zero-thickness joints between them or between a block and a support. SI units throughout.
 * The arch builder makes the segmental circular arch of docs/model.md; tests build others. */
#ifndef VOUSSOIR_GEOMETRY_H
#define VOUSSOIR_GEOMETRY_H

#include "voussoir/api.h"

#include "voussoir/def.h"
#include "voussoir/status.h"

/* Joint ends that are not blocks. The left support is fixed; the right one is moved. */
#define VS_SUPPORT_LEFT (-1)
#define VS_SUPPORT_RIGHT (-2)

typedef struct {
  double mass;       /* kg */
  double inertia;    /* kg m^2, about the centroid, for rotation in the plane */
  double cx, cz;     /* centroid in the reference configuration, m (x right, z up) */
  double area;       /* m^2, in the plane */
  double phi0, phi1; /* arch blocks: angular extent from the crown, rad (0 for other blocks) */
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
} vs_joint_geom;

typedef struct {
  int n_blocks;
  int n_joints;
  vs_block *blocks;      /* n_blocks */
  vs_joint_geom *joints; /* n_joints, joint k (1-based in output) is joints[k-1] */
  double span;           /* intrados span L, m (arch) */
  double rise;           /* intrados rise, m (arch) */
  double radius, thickness, embrace; /* arch: intrados radius (m), thickness (m), embrace (rad) */
  double gravity;        /* m/s^2 */
} vs_geometry;

/* Tangent along joint j from intrados to extrados: the normal turned +90 degrees
 * (counter-clockwise), s = (-nz, nx). For an arch joint n is along the arch, s radial outward. */
static inline void vs_joint_tangent(const vs_joint_geom *j, double *sx, double *sz) {
  *sx = -j->nz;
  *sz = j->nx;
}

/* Build the segmental circular arch a: voussoirs of equal angular size, radial joints,
 * joint 1 on the left springing plane, joint n+1 on the right one. The circle's centre is the
 * origin; the crown is on the +z axis. Exact annular-sector mass, centroid and inertia. */
VS_API vs_status vs_geometry_create_arch(const vs_arch_def *a, vs_geometry **out, vs_error *err);

/* Allocate an empty geometry with room for n_blocks blocks and n_joints joints (tests, other
 * shapes); the caller fills the arrays. */
VS_API vs_status vs_geometry_create(int n_blocks, int n_joints, vs_geometry **out, vs_error *err);

/* Free g and NULL *g; NULL and *g == NULL are allowed. */
VS_API void vs_geometry_destroy(vs_geometry **g);

/* Total weight of the blocks, N. */
VS_API double vs_geometry_weight(const vs_geometry *g);

#endif
