/* Private to the model: the piers under an arch's springings (piers.c), which the arch builder
 * (arch.c) and the imperfect arches (imperfections.c) add to the ring they build. Not installed. */
#ifndef VOUSSOIR_PIERS_H
#define VOUSSOIR_PIERS_H

#include "voussoir/def.h"
#include "voussoir/geometry.h"
#include "voussoir/status.h"

/* Arch a without its piers (vs_geometry_create_arch less vs_piers_add): the ring of blocks from
 * the left support to the right one, or a blocks file's assembly. Errors as
 * vs_geometry_create_arch. */
vs_status vs_arch_ring(const vs_arch_def *a, vs_geometry **out, vs_error *err);

/* Add a pier under each springing of the ring in *g (its first joint on the left support, its
 * last on the right one) as p (def.h: vs_piers_def) asks, the blocks of density p->density (0:
 * density) and depth `depth`: the blocks, the course joints and the foundation interfaces
 * appended after the ring's, the springing joints moved onto the top courses, a foundation slab
 * drawn under each pier (a support polygon), the geometry's pier_* fields set. p->height 0:
 * nothing. VS_ERR_INVALID naming the piers.* key for a pier that cannot be built; VS_ERR_NOMEM
 * (*g is then destroyed). */
vs_status vs_piers_add(vs_geometry **g, const vs_piers_def *p, double density, double depth,
                       vs_error *err);

#endif
