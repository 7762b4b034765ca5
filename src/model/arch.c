/* The arch builder (geometry.h: vs_geometry_create_arch): by shape, the circular arch of annular
 * sectors in closed form (exact properties, radial joints, joint k between voussoir k-1 and
 * voussoir k), the other shapes and cuts from the generator (shape.c). */
#include "voussoir/geometry.h"

#include "blocks.h"
#include "outline.h"
#include "piers.h"
#include "shape.h"

#include <math.h>
#include <stdlib.h>

/* The joints' angles from the crown of the circular arch of half-embrace beta (n + 1 of them):
 * equal voussoirs, or at the positions' (or the keystone's) fractions of the centre line. */
static vs_status sector_angles(const vs_arch_def *a, double ri, double beta, double *phi,
                               vs_error *err) {
  const int n = a->voussoirs;
  const double dphi = 2.0 * beta / n;
  for (int k = 0; k <= n; k++) phi[k] = -beta + k * dphi;
  if (a->n_positions == 0 && a->keystone == 0.0) return VS_OK;
  vs_status st = vs_shape_positions(a, (ri + 0.5 * a->thickness) * 2.0 * beta, phi + 1, err);
  for (int k = 1; st == VS_OK && k < n; k++) phi[k] = -beta + phi[k] * 2.0 * beta;
  phi[n] = beta;
  return st;
}

/* The circular arch of annular sectors (shape.h: vs_shape_is_sectors): closed forms. */
static vs_status create_sectors(const vs_arch_def *a, vs_geometry **out, vs_error *err) {
  const int n = a->voussoirs;
  double ri = 0.0, beta = 0.0;
  vs_status st = vs_shape_circle(a, &ri, &beta, err);
  double *phi = st == VS_OK ? malloc((size_t)(n + 1) * sizeof *phi) : NULL;
  if (st == VS_OK && phi == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  if (st == VS_OK) st = sector_angles(a, ri, beta, phi, err);
  if (st == VS_OK) st = vs_geometry_create(n, n + 1, out, err);
  if (st != VS_OK) {
    free(phi);
    return st;
  }
  vs_geometry *g = *out;
  const double t = a->thickness, b = a->depth;
  g->radius = ri;
  g->thickness = t;
  g->embrace = 2.0 * beta;
  g->span = 2.0 * ri * sin(beta);
  g->rise = ri * (1.0 - cos(beta));
  g->gravity = a->gravity;
  for (int i = 0; i < n && st == VS_OK; i++) {
    vs_edge e[4];
    vs_sector_block(ri, ri + t, phi[i], phi[i + 1], a->density * b, &g->blocks[i]);
    vs_sector_edges(ri, ri + t, phi[i], phi[i + 1], i, i + 1, e);
    st = vs_geometry_set_outline(g, i, 4, e, err);
  }
  for (int k = 0; k <= n && st == VS_OK; k++) {
    double rm = ri + 0.5 * t;
    vs_joint_geom *j = &g->joints[k];
    j->a = (k == 0) ? VS_SUPPORT_LEFT : k - 1;
    j->b = (k == n) ? VS_SUPPORT_RIGHT : k;
    j->px = rm * sin(phi[k]);
    j->pz = rm * cos(phi[k]);
    j->nx = cos(phi[k]);
    j->nz = -sin(phi[k]);
    j->length = t;
    j->depth = b;
  }
  free(phi);
  if (st != VS_OK) vs_geometry_destroy(out);
  return st;
}

vs_status vs_arch_ring(const vs_arch_def *a, vs_geometry **out, vs_error *err) {
  *out = NULL;
  if (a->voussoirs < 1)
    return vs_error_set(err, VS_ERR_INVALID, "arch.voussoirs = %d (allowed: >= 1)", a->voussoirs);
  if (a->shape == VS_SHAPE_FILE && a->piers.height != 0.0)
    return vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %g with arch.shape = file "
                        "(allowed: 0; a blocks file draws its own piers)", a->piers.height * 1e3);
  if (a->shape == VS_SHAPE_FILE) return vs_blocks_read(a, out, err);
  if (!vs_shape_is_sectors(a)) return vs_shape_build(a, NULL, NULL, out, err);
  return create_sectors(a, out, err);
}

vs_status vs_geometry_create_arch(const vs_arch_def *a, vs_geometry **out, vs_error *err) {
  vs_status st = vs_arch_ring(a, out, err);
  if (st == VS_OK) st = vs_piers_add(out, &a->piers, a->density, a->depth, err);
  return st;
}
