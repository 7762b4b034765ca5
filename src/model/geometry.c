/* Block-assembly geometry and the segmental circular arch builder: exact annular-sector
 * properties, radial joints, joint k between voussoir k-1 and voussoir k. */
#include "voussoir/geometry.h"

#include "outline.h"
#include "voussoir/units.h"

#include <math.h>
#include <stdlib.h>

vs_status vs_geometry_create(int n_blocks, int n_joints, vs_geometry **out, vs_error *err) {
  *out = NULL;
  if (n_blocks < 1 || n_joints < 1)
    return vs_error_set(err, VS_ERR_INVALID, "geometry: %d blocks, %d joints (allowed: >= 1 each)",
                        n_blocks, n_joints);
  vs_geometry *g = calloc(1, sizeof *g);
  if (g == NULL) return vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  g->blocks = calloc((size_t)n_blocks, sizeof *g->blocks);
  g->joints = calloc((size_t)n_joints, sizeof *g->joints);
  if (g->blocks == NULL || g->joints == NULL) {
    vs_geometry_destroy(&g);
    return vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  }
  g->n_blocks = n_blocks;
  g->n_joints = n_joints;
  g->gravity = 9.81;
  *out = g;
  return VS_OK;
}

void vs_geometry_destroy(vs_geometry **g) {
  if (g == NULL || *g == NULL) return;
  free((*g)->blocks);
  free((*g)->joints);
  free((*g)->edges);
  free(*g);
  *g = NULL;
}

double vs_geometry_weight(const vs_geometry *g) {
  double m = 0.0;
  for (int i = 0; i < g->n_blocks; i++) m += g->blocks[i].mass;
  return m * g->gravity;
}

vs_status vs_geometry_create_arch(const vs_arch_def *a, vs_geometry **out, vs_error *err) {
  const int n = a->voussoirs;
  vs_status st = vs_geometry_create(n, n + 1, out, err);
  if (st != VS_OK) return st;
  vs_geometry *g = *out;
  const double ri = a->radius, t = a->thickness, b = a->depth;
  const double beta = 0.5 * a->embrace, dphi = 2.0 * beta / n;
  g->radius = ri;
  g->thickness = t;
  g->embrace = 2.0 * beta;
  g->span = 2.0 * ri * sin(beta);
  g->rise = ri * (1.0 - cos(beta));
  g->gravity = a->gravity;
  for (int i = 0; i < n && st == VS_OK; i++) {
    const double phi0 = -beta + i * dphi, phi1 = -beta + (i + 1) * dphi;
    vs_edge e[4];
    vs_sector_block(ri, ri + t, phi0, phi1, a->density * b, &g->blocks[i]);
    vs_sector_edges(ri, ri + t, phi0, phi1, i, i + 1, e);
    st = vs_geometry_set_outline(g, i, 4, e, err);
  }
  if (st != VS_OK) {
    vs_geometry_destroy(out);
    return st;
  }
  for (int k = 0; k <= n; k++) {
    double phi = -beta + k * dphi, rm = ri + 0.5 * t;
    vs_joint_geom *j = &g->joints[k];
    j->a = (k == 0) ? VS_SUPPORT_LEFT : k - 1;
    j->b = (k == n) ? VS_SUPPORT_RIGHT : k;
    j->px = rm * sin(phi);
    j->pz = rm * cos(phi);
    j->nx = cos(phi);
    j->nz = -sin(phi);
    j->length = t;
    j->depth = b;
  }
  return VS_OK;
}
