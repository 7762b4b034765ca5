/* The arch picture's geometry in model coordinates (m): blocks and supports moved by a state,
 * the picture's checks and its frame (scale and origin). */
#include "voussoir/plot.h"

#include "plot_draw.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Point X, Z of body `body` (a block index or a support) moved: x = c + u + R(theta)(X - c). */
void vs_plot_body_point(const vs_geometry *g, const double *q, const double su[4],
                        const double *srot, int body, double X, double Z, double *x, double *z) {
  if (body < 0 || q == NULL) {
    const int moved = body == VS_SUPPORT_RIGHT;
    const double th = body < 0 && srot != NULL ? srot[moved] : 0.0;
    if (th != 0.0) { /* a support turns about the centre of its face (a pier's base) */
      const vs_joint_geom *j = &g->joints[vs_geometry_support_joint(g, moved)];
      const double c = cos(th), s = sin(th), dx = X - j->px, dz = Z - j->pz;
      X = j->px + c * dx - s * dz;
      Z = j->pz + s * dx + c * dz;
    }
    *x = X + su[moved ? 2 : 0];
    *z = Z + su[moved ? 3 : 1];
    return;
  }
  const vs_block *b = &g->blocks[body];
  const double *qi = q + 3 * body, c = cos(qi[2]), s = sin(qi[2]);
  double dx = X - b->cx, dz = Z - b->cz;
  *x = b->cx + qi[0] + c * dx - s * dz;
  *z = b->cz + qi[1] + s * dx + c * dz;
}

/* Reference ends of joint j: intrados (eta = 0) and extrados (eta = length). */
void vs_plot_joint_ends(const vs_joint_geom *j, double e[4]) {
  double sx, sz, h = 0.5 * j->length;
  vs_joint_tangent(j, &sx, &sz);
  e[0] = j->px - h * sx;
  e[1] = j->pz - h * sz;
  e[2] = j->px + h * sx;
  e[3] = j->pz + h * sz;
}

/* Outline of block i moved by q (NULL: reference): vs_block_outline with a point at least every
 * degree of each curved edge (for an arch voussoir the intrados arc phi0 -> phi1, then the
 * extrados arc back). The outline is the geometry's own, each block at its own thickness (thick
 * is not used: vs_imperfections_arch builds a scattered arch's outlines). x, z hold
 * OUTLINE_MAX points; returns the number written. */
int vs_plot_block_outline(const vs_geometry *g, const double *q, const double *thick, int i,
                          double *x, double *z) {
  (void)thick;
  double xz[2 * OUTLINE_MAX];
  const double su[4] = {0.0, 0.0, 0.0, 0.0};
  int k = vs_block_outline(g, i, 2, VS_DEG, xz, OUTLINE_MAX);
  if (k > OUTLINE_MAX) k = OUTLINE_MAX;
  for (int p = 0; p < k; p++)
    vs_plot_body_point(g, q, su, NULL, i, xz[2 * p], xz[2 * p + 1], &x[p], &z[p]);
  return k;
}

/* A skewback abutment under the springing face of the left (left = 1) or right support,
 * translated by u: the face, a level top outward, an outer vertical, a base 2t below the
 * intrados end, an inner vertical back up. Returns SUPPORT_PTS. */
int vs_plot_support_outline(const vs_geometry *g, int left, const double u[2], double *x,
                            double *z) {
  double e[4];
  vs_plot_joint_ends(&g->joints[vs_geometry_springing(g, !left)], e);
  const double t = g->thickness, out = (e[2] < e[0]) ? -1.0 : 1.0;
  const double xo = e[2] + out * 1.5 * t, zb = e[1] - 2.0 * t;
  const double px[SUPPORT_PTS] = {e[0], e[2], xo, xo, e[0]};
  const double pz[SUPPORT_PTS] = {e[1], e[3], e[3], zb, zb};
  for (int k = 0; k < SUPPORT_PTS; k++) x[k] = px[k] + u[0], z[k] = pz[k] + u[1];
  return SUPPORT_PTS;
}

int vs_plot_support_polygon(const vs_geometry *g, int s, const double su[4], const double *srot,
                            double *x, double *z) {
  const vs_support_outline *o = &g->supports[s];
  const int n = o->n_edges < OUTLINE_MAX ? o->n_edges : OUTLINE_MAX;
  for (int k = 0; k < n; k++) {
    const vs_edge *e = &g->edges[o->edge0 + k];
    vs_plot_body_point(g, NULL, su, srot, o->body, e->x0, e->z0, &x[k], &z[k]);
  }
  return n;
}

vs_status vs_plot_check_arch(const vs_geometry *g, const double *q, double delta, double alpha,
                             vs_error *err) {
  if (g == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no geometry");
  if (!(g->thickness > 0.0) || g->n_blocks < 1 || g->n_joints < 2 ||
      g->joints[vs_geometry_support_joint(g, 0)].a != VS_SUPPORT_LEFT ||
      g->joints[vs_geometry_support_joint(g, 1)].b != VS_SUPPORT_RIGHT)
    return vs_error_set(err, VS_ERR_INVALID,
                        "plot: the geometry is not an arch (thickness, joints 1 and n on the "
                        "left and right supports)");
  for (int i = 0; i < g->n_blocks; i++)
    if (g->blocks[i].n_edges < 1)
      return vs_error_set(err, VS_ERR_INVALID, "plot: block %d has no outline (allowed: an "
                          "outline, vs_geometry_set_outline)", i + 1);
  if (!isfinite(delta) || !isfinite(alpha))
    return vs_error_set(err, VS_ERR_INVALID, "plot: delta = %g m, alpha = %g rad: not finite",
                        delta, alpha);
  for (int k = 0; q != NULL && k < 3 * g->n_blocks; k++)
    if (!isfinite(q[k]))
      return vs_error_set(err, VS_ERR_INVALID, "plot: state entry %d is not finite", k);
  return VS_OK;
}

typedef struct {
  double x0, x1, z0, z1;
} box;

static void box_add(box *b, const double *x, const double *z, int n) {
  for (int k = 0; k < n; k++) {
    b->x0 = fmin(b->x0, x[k]);
    b->x1 = fmax(b->x1, x[k]);
    b->z0 = fmin(b->z0, z[k]);
    b->z1 = fmax(b->z1, z[k]);
  }
}

void vs_plot_frame_of(const vs_geometry *g, const double *q, const double *thick,
                      const double su[4], double ground, vs_plot_frame *f) {
  double x[OUTLINE_MAX], z[OUTLINE_MAX];
  const double zero[4] = {0.0, 0.0, 0.0, 0.0};
  box b = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (int i = 0; i < g->n_blocks; i++) {
    box_add(&b, x, z, vs_plot_block_outline(g, NULL, thick, i, x, z));
    if (q != NULL) box_add(&b, x, z, vs_plot_block_outline(g, q, thick, i, x, z));
  }
  for (int s = 0; s < g->n_supports; s++) {
    box_add(&b, x, z, vs_plot_support_polygon(g, s, zero, NULL, x, z));
    box_add(&b, x, z, vs_plot_support_polygon(g, s, su, NULL, x, z));
  }
  if (g->n_supports == 0) {
    box_add(&b, x, z, vs_plot_support_outline(g, 1, zero, x, z));
    box_add(&b, x, z, vs_plot_support_outline(g, 0, zero, x, z));
    box_add(&b, x, z, vs_plot_support_outline(g, 0, su + 2, x, z));
    box_add(&b, x, z, vs_plot_support_outline(g, 1, su, x, z));
  }
  if (isfinite(ground)) box_add(&b, &b.x0, &ground, 1);
  const int w = VS_PLOT_ARCH_WIDTH, h = VS_PLOT_ARCH_HEIGHT;
  const double aw = w - 2.0 * ARCH_SIDE, ah = h - ARCH_TOP - ARCH_BOTTOM;
  const double bw = fmax(b.x1 - b.x0, 1e-9), bh = fmax(b.z1 - b.z0, 1e-9);
  f->width = w;
  f->height = h;
  f->scale = fmin(aw / bw, ah / bh);
  f->x0 = ARCH_SIDE + 0.5 * (aw - f->scale * bw) - f->scale * b.x0;
  f->y0 = ARCH_TOP + 0.5 * (ah - f->scale * bh) + f->scale * b.z1;
}
