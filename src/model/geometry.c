/* Block-assembly geometry: creation, destruction, weight (the arch builder is arch.c). */
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
  free((*g)->supports);
  free(*g);
  *g = NULL;
}

double vs_geometry_weight(const vs_geometry *g) {
  double m = 0.0;
  for (int i = 0; i < g->n_blocks; i++) m += g->blocks[i].mass;
  return m * g->gravity;
}
