/* The blocks' outlines: curves and their offsets evaluated exactly, an outline set and
 * sampled, its convex polygon for the contacts, and the exact area, centroid and second moment
 * of the region it encloses (Green's theorem, the curves integrated by Gauss-Legendre). */
#include "outline.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double VS_PI = 3.14159265358979323846;

/* ------------------------------------------------------------------------------------------ */
/* Curves                                                                                      */

/* The base curve's point, first and second derivatives at u. */
static void base_eval(const vs_curve *c, double u, double p[2], double d1[2], double d2[2]) {
  switch (c->kind) {
  case VS_CURVE_CIRCLE:
  case VS_CURVE_ELLIPSE: {
    const double a = c->a, b = c->kind == VS_CURVE_CIRCLE ? c->a : c->b;
    const double s = sin(u), co = cos(u);
    p[0] = c->cx + a * s, p[1] = c->cz + b * co;
    d1[0] = a * co, d1[1] = -b * s;
    d2[0] = -a * s, d2[1] = -b * co;
    return;
  }
  case VS_CURVE_PARABOLA: {
    const double k = c->b / (c->a * c->a);
    p[0] = c->cx + u, p[1] = c->cz - k * u * u;
    d1[0] = 1.0, d1[1] = -2.0 * k * u;
    d2[0] = 0.0, d2[1] = -2.0 * k;
    return;
  }
  case VS_CURVE_CATENARY:
  default: {
    const double a = c->a, ch = cosh(u / a);
    p[0] = c->cx + u, p[1] = c->cz - a * (ch - 1.0);
    d1[0] = 1.0, d1[1] = -sinh(u / a);
    d2[0] = 0.0, d2[1] = -ch / a;
    return;
  }
  }
}

void vs_curve_eval(const vs_curve *c, double u, double p[2], double dp[2]) {
  double b[2], b1[2], b2[2];
  base_eval(c, u, b, b1, b2);
  if (c->d0 == 0.0 && c->d2 == 0.0) { /* the base curve itself, bit for bit */
    if (p != NULL) p[0] = b[0], p[1] = b[1];
    if (dp != NULL) dp[0] = b1[0], dp[1] = b1[1];
    return;
  }
  /* n = J B' / s (J: +90 degrees), n' = J B'' / s - J B' (B'.B'') / s^3 */
  const double s = hypot(b1[0], b1[1]), n[2] = {-b1[1] / s, b1[0] / s};
  const double w = b[0] - c->xc;
  const double d = c->d0 + c->d2 * w * w, dd = 2.0 * c->d2 * w * b1[0];
  if (p != NULL) p[0] = b[0] + d * n[0], p[1] = b[1] + d * n[1];
  if (dp != NULL) {
    const double bb = (b1[0] * b2[0] + b1[1] * b2[1]) / (s * s * s);
    const double n1[2] = {-b2[1] / s + b1[1] * bb, b2[0] / s - b1[0] * bb};
    dp[0] = b1[0] + dd * n[0] + d * n1[0];
    dp[1] = b1[1] + dd * n[1] + d * n1[1];
  }
}

void vs_edge_eval(const vs_edge *e, double u, double p[2], double dp[2]) {
  if (e->curved) {
    vs_curve_eval(&e->c, u, p, dp);
    return;
  }
  if (p != NULL) p[0] = e->x0 + u * (e->x1 - e->x0), p[1] = e->z0 + u * (e->z1 - e->z0);
  if (dp != NULL) dp[0] = e->x1 - e->x0, dp[1] = e->z1 - e->z0;
}

/* The signed turn of e's tangent along it (rad, counter-clockwise positive). */
static double signed_turn(const vs_edge *e) {
  if (!e->curved) return 0.0;
  if (e->c.kind == VS_CURVE_CIRCLE && e->c.d0 == 0.0 && e->c.d2 == 0.0)
    return e->u0 - e->u1; /* clockwise in u: turning by -du */
  double turn = 0.0, ta[2];
  vs_curve_eval(&e->c, e->u0, NULL, ta);
  for (int k = 1; k <= 8; k++) {
    double tb[2];
    vs_curve_eval(&e->c, e->u0 + (e->u1 - e->u0) * k / 8.0, NULL, tb);
    turn += atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1]);
    ta[0] = tb[0], ta[1] = tb[1];
  }
  return turn;
}

double vs_edge_turn(const vs_edge *e) { return fabs(signed_turn(e)); }

/* ------------------------------------------------------------------------------------------ */
/* Outlines                                                                                    */

static double loop_size(const vs_edge *e, int n) {
  double s = 0.0;
  for (int k = 0; k < n; k++) s = fmax(s, fabs(e[k].x0) + fabs(e[k].z0) + hypot(e[k].x1 - e[k].x0, e[k].z1 - e[k].z0));
  return s;
}

/* Append n edges (a closed loop) to g's edges; who names the outline in messages. */
static vs_status append_loop(vs_geometry *g, const char *who, int n, const vs_edge *edges,
                             vs_error *err) {
  vs_edge *all = realloc(g->edges, (size_t)(g->n_edges + n) * sizeof *all);
  if (all == NULL) return vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  g->edges = all;
  vs_edge *e = all + g->n_edges;
  memcpy(e, edges, (size_t)n * sizeof *e);
  for (int k = 0; k < n; k++)
    if (e[k].curved) {
      double p[2];
      vs_curve_eval(&e[k].c, e[k].u0, p, NULL);
      e[k].x0 = p[0], e[k].z0 = p[1];
      vs_curve_eval(&e[k].c, e[k].u1, p, NULL);
      e[k].x1 = p[0], e[k].z1 = p[1];
    } else {
      e[k].u0 = 0.0, e[k].u1 = 1.0;
    }
  const double tol = 1e-9 * loop_size(e, n);
  for (int k = 0; k < n; k++) {
    const vs_edge *a = &e[k], *b = &e[(k + 1) % n];
    const double len = hypot(a->x1 - a->x0, a->z1 - a->z0);
    if (!isfinite(a->x0) || !isfinite(a->z0) || !isfinite(a->x1) || !isfinite(a->z1) ||
        !(len > tol || (a->curved && vs_edge_turn(a) > 0.0)))
      return vs_error_set(err, VS_ERR_INVALID, "geometry: %s edge %d from (%g, %g) to (%g, %g) m "
                          "(allowed: finite ends, a length)", who, k, a->x0, a->z0, a->x1, a->z1);
    if (!(hypot(b->x0 - a->x1, b->z0 - a->z1) <= tol))
      return vs_error_set(err, VS_ERR_INVALID, "geometry: %s edge %d ends at (%g, %g) m, edge %d "
                          "starts at (%g, %g) m (allowed: a closed loop)", who, k, a->x1, a->z1,
                          (k + 1) % n, b->x0, b->z0);
  }
  g->n_edges += n;
  return VS_OK;
}

vs_status vs_geometry_set_outline(vs_geometry *g, int block, int n, const vs_edge *edges,
                                  vs_error *err) {
  if (block < 0 || block >= g->n_blocks || n < 1 || edges == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "geometry: outline of block %d with %d edges "
                        "(allowed: a block 0..%d, >= 1 edge)", block, n, g->n_blocks - 1);
  char who[32];
  snprintf(who, sizeof who, "block %d", block);
  const int first = g->n_edges;
  vs_status st = append_loop(g, who, n, edges, err);
  if (st != VS_OK) return st;
  g->blocks[block].edge0 = first;
  g->blocks[block].n_edges = n;
  return VS_OK;
}

vs_status vs_geometry_add_support(vs_geometry *g, int body, int n, const vs_edge *edges,
                                  vs_error *err) {
  if ((body != VS_SUPPORT_LEFT && body != VS_SUPPORT_RIGHT) || n < 3 || edges == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "geometry: support polygon of body %d with %d edges "
                        "(allowed: VS_SUPPORT_LEFT or VS_SUPPORT_RIGHT, >= 3 edges)", body, n);
  vs_support_outline *s = realloc(g->supports, (size_t)(g->n_supports + 1) * sizeof *s);
  if (s == NULL) return vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  g->supports = s;
  const int first = g->n_edges;
  vs_status st = append_loop(g, body == VS_SUPPORT_LEFT ? "the left support" : "the right support",
                             n, edges, err);
  if (st != VS_OK) return st;
  g->supports[g->n_supports++] = (vs_support_outline){.body = body, .edge0 = first, .n_edges = n};
  return VS_OK;
}

/* Write point (x, z) as number k of a list with room for max. */
static void put(double *xz, int max, int k, double x, double z) {
  if (k < max) xz[2 * k] = x, xz[2 * k + 1] = z;
}

int vs_block_outline(const vs_geometry *g, int block, int min_points, double max_turn,
                     double *xz, int max) {
  const vs_block *b = &g->blocks[block];
  int k = 0;
  for (int i = 0; i < b->n_edges; i++) {
    const vs_edge *e = &g->edges[b->edge0 + i];
    if (!e->curved) {
      const vs_edge *prev = &g->edges[b->edge0 + (i + b->n_edges - 1) % b->n_edges];
      if (!prev->curved) put(xz, max, k++, e->x0, e->z0);
      continue;
    }
    const double want = ceil(vs_edge_turn(e) / max_turn - 1e-9) + 1.0;
    int m = want > (double)min_points ? (int)fmin(want, VS_OUTLINE_CURVE_MAX) : min_points;
    if (m < 2) m = 2;
    for (int p = 0; p < m; p++) {
      const double f = (double)p / (double)(m - 1);
      double pt[2];
      vs_curve_eval(&e->c, e->u0 + f * (e->u1 - e->u0), pt, NULL);
      put(xz, max, k++, pt[0], pt[1]);
    }
  }
  return k;
}

/* ------------------------------------------------------------------------------------------ */
/* The convex outline                                                                          */

static double cross3(const double *a, const double *b, const double *c) {
  return (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
}

/* Drop the corners of the polygon (n points) that turn inward until none does; 1 when the
 * result is a convex polygon turning once round, else 0. */
static int make_convex(double *xz, int *edge_of, int *n, double size) {
  const double eps = 1e-12 * size * size;
  for (int changed = 1; changed && *n >= 3;) {
    changed = 0;
    for (int i = 0; i < *n && *n >= 3; i++) {
      const int p = (i + *n - 1) % *n, q = (i + 1) % *n;
      if (!(cross3(xz + 2 * p, xz + 2 * i, xz + 2 * q) < -eps)) continue;
      memmove(xz + 2 * i, xz + 2 * (i + 1), (size_t)(2 * (*n - i - 1)) * sizeof *xz);
      if (edge_of != NULL) memmove(edge_of + i, edge_of + i + 1, (size_t)(*n - i - 1) * sizeof *edge_of);
      (*n)--;
      changed = 1;
      i--;
    }
  }
  if (*n < 3) return 0;
  double turn = 0.0;
  for (int i = 0; i < *n; i++) {
    const double *a = xz + 2 * ((i + *n - 1) % *n), *b = xz + 2 * i, *c = xz + 2 * ((i + 1) % *n);
    const double ux = b[0] - a[0], uz = b[1] - a[1], vx = c[0] - b[0], vz = c[1] - b[1];
    turn += atan2(ux * vz - uz * vx, ux * vx + uz * vz);
  }
  return fabs(turn - 2.0 * VS_PI) < 1e-6;
}

int vs_block_hull(const vs_geometry *g, int block, double *xz, int *edge_of) {
  const vs_block *b = &g->blocks[block];
  double pts[2 * VS_HULL_MAX];
  int eo[VS_HULL_MAX], n = 0;
  for (int i = 0; i < b->n_edges; i++) {
    const int ei = b->edge0 + i;
    const vs_edge *e = &g->edges[ei];
    if (n == VS_HULL_MAX) return -1;
    pts[2 * n] = e->x0, pts[2 * n + 1] = e->z0, eo[n++] = ei;
    const double turn = signed_turn(e);
    if (!(turn > 0.0)) continue; /* a segment, or bulging inward: its chord */
    const int k = (int)fmax(1.0, ceil(turn / VS_HULL_TURN - 1e-9));
    for (int j = 1; j <= k; j++) {
      double p[2];
      const double u = k == 1 ? 0.5 * (e->u0 + e->u1) : e->u0 + (e->u1 - e->u0) * j / (k + 1.0);
      vs_curve_eval(&e->c, u, p, NULL);
      if (n == VS_HULL_MAX) return -1;
      pts[2 * n] = p[0], pts[2 * n + 1] = p[1], eo[n++] = -1 - ei;
    }
  }
  if (n == 0) return 0;
  if (!make_convex(pts, eo, &n, loop_size(g->edges + b->edge0, b->n_edges))) return -1;
  if (xz != NULL) memcpy(xz, pts, (size_t)(2 * n) * sizeof *xz);
  if (edge_of != NULL) memcpy(edge_of, eo, (size_t)n * sizeof *edge_of);
  return n;
}

/* Annular sector ri..re over the angle phi0..phi1 (from the crown, clockwise positive). */
void vs_sector_block(double ri, double re, double phi0, double phi1, double rho_b,
                     vs_block *blk) {
  double dphi = phi1 - phi0, half = 0.5 * dphi, mid = 0.5 * (phi0 + phi1);
  double area = half * (re * re - ri * ri);
  double rc = (2.0 / 3.0) * (re * re * re - ri * ri * ri) / (re * re - ri * ri) * sin(half) / half;
  double jo = dphi * (pow(re, 4) - pow(ri, 4)) / 4.0; /* polar second moment about the centre */
  blk->area = area;
  blk->mass = rho_b * area;
  blk->inertia = rho_b * (jo - area * rc * rc);
  blk->cx = rc * sin(mid);
  blk->cz = rc * cos(mid);
  blk->phi0 = phi0;
  blk->phi1 = phi1;
}

static int cmp_point(const void *a, const void *b) {
  const double *p = a, *q = b;
  return p[0] < q[0] ? -1 : p[0] > q[0] ? 1 : p[1] < q[1] ? -1 : p[1] > q[1] ? 1 : 0;
}

int vs_convex_hull(double *xz, int n, double *out) {
  qsort(xz, (size_t)n, 2 * sizeof *xz, cmp_point);
  int k = 0;
#define PUSH(i, least)                                                                           \
  do {                                                                                           \
    while (k >= (least) && cross3(out + 2 * (k - 2), out + 2 * (k - 1), xz + 2 * (i)) <= 0.0) k--; \
    out[2 * k] = xz[2 * (i)], out[2 * k + 1] = xz[2 * (i) + 1];                                   \
    k++;                                                                                         \
  } while (0)
  for (int i = 0; i < n; i++) PUSH(i, 2); /* Andrew's monotone chain: the lower hull */
  const int lower = k + 1;
  for (int i = n - 2; i >= 0; i--) PUSH(i, lower); /* the upper, back to the first point */
#undef PUSH
  k--; /* the first point, twice */
  return k < 3 ? 0 : k;
}

void vs_sector_edges(double ri, double re, double phi0, double phi1, int jl, int jr,
                     vs_edge e[4]) {
  const vs_curve in = {.kind = VS_CURVE_CIRCLE, .a = ri, .b = ri};
  const vs_curve out = {.kind = VS_CURVE_CIRCLE, .a = re, .b = re};
  e[0] = (vs_edge){.curved = 1, .c = in, .u0 = phi0, .u1 = phi1, .joint = -1};
  e[2] = (vs_edge){.curved = 1, .c = out, .u0 = phi1, .u1 = phi0, .joint = -1};
  for (int k = 0; k < 4; k += 2) {
    double p[2];
    vs_curve_eval(&e[k].c, e[k].u0, p, NULL);
    e[k].x0 = p[0], e[k].z0 = p[1];
    vs_curve_eval(&e[k].c, e[k].u1, p, NULL);
    e[k].x1 = p[0], e[k].z1 = p[1];
  }
  e[1] = (vs_edge){.x0 = e[0].x1, .z0 = e[0].z1, .x1 = e[2].x0, .z1 = e[2].z0, .u1 = 1.0,
                   .joint = jr};
  e[3] = (vs_edge){.x0 = e[2].x1, .z0 = e[2].z1, .x1 = e[0].x0, .z1 = e[0].z0, .u1 = 1.0,
                   .joint = jl};
}

/* ------------------------------------------------------------------------------------------ */
/* Area, centroid, second moment                                                               */

/* Gauss-Legendre of order 20 on [-1, 1]: the positive nodes and their weights. */
static const double GL20[10][2] = {
    {0.076526521133497338, 0.15275338713072584}, {0.22778585114164507, 0.14917298647260374},
    {0.37370608871541955, 0.14209610931838204},  {0.51086700195082713, 0.13168863844917664},
    {0.63605368072651502, 0.11819453196151841},  {0.7463319064601508, 0.10193011981724044},
    {0.83911697182221878, 0.083276741576704755}, {0.91223442825132595, 0.062672048334109068},
    {0.96397192727791381, 0.040601429800386939}, {0.99312859918509488, 0.017614007139152118},
};

/* The five loop integrals of Green's theorem, from the reference point (xr, zr):
 * A = int X dZ, Sx = int X^2/2 dZ, Sz = -int Z^2/2 dX, J = int X^3/3 dZ - int Z^3/3 dX. */
typedef struct {
  double v[4];
} moments;

static void integrand(const vs_edge *e, double u, double xr, double zr, double w, moments *m) {
  double p[2], d[2];
  vs_curve_eval(&e->c, u, p, d);
  const double X = p[0] - xr, Z = p[1] - zr;
  m->v[0] += w * X * d[1];
  m->v[1] += w * 0.5 * X * X * d[1];
  m->v[2] -= w * 0.5 * Z * Z * d[0];
  m->v[3] += w * (X * X * X * d[1] - Z * Z * Z * d[0]) / 3.0;
}

static moments gl20(const vs_edge *e, double a, double b, double xr, double zr) {
  moments m = {{0, 0, 0, 0}};
  const double c = 0.5 * (a + b), h = 0.5 * (b - a);
  for (int i = 0; i < 10; i++) {
    integrand(e, c - h * GL20[i][0], xr, zr, h * GL20[i][1], &m);
    integrand(e, c + h * GL20[i][0], xr, zr, h * GL20[i][1], &m);
  }
  return m;
}

/* Over [a, b]: the rule on the whole against the rule on the halves, halved until they agree
 * to scale^k round-off (k the power of length of each integral). */
static moments curve_moments(const vs_edge *e, double a, double b, double xr, double zr,
                             moments whole, double scale, int depth) {
  const double mid = 0.5 * (a + b);
  moments l = gl20(e, a, mid, xr, zr), r = gl20(e, mid, b, xr, zr), s;
  int ok = 1;
  double sc = scale * scale;
  for (int k = 0; k < 4; k++, sc *= scale) {
    s.v[k] = l.v[k] + r.v[k];
    if (!(fabs(s.v[k] - whole.v[k]) <= 1e-15 * sc)) ok = 0;
  }
  if (ok || depth >= 24) return s;
  l = curve_moments(e, a, mid, xr, zr, l, scale, depth + 1);
  r = curve_moments(e, mid, b, xr, zr, r, scale, depth + 1);
  for (int k = 0; k < 4; k++) s.v[k] = l.v[k] + r.v[k];
  return s;
}

static void segment_moments(const vs_edge *e, double xr, double zr, moments *m) {
  const double X0 = e->x0 - xr, Z0 = e->z0 - zr, X1 = e->x1 - xr, Z1 = e->z1 - zr;
  const double dX = X1 - X0, dZ = Z1 - Z0;
  m->v[0] += dZ * 0.5 * (X0 + X1);
  m->v[1] += dZ * (X0 * X0 + X0 * X1 + X1 * X1) / 6.0;
  m->v[2] -= dX * (Z0 * Z0 + Z0 * Z1 + Z1 * Z1) / 6.0;
  m->v[3] += (dZ * (X0 + X1) * (X0 * X0 + X1 * X1) - dX * (Z0 + Z1) * (Z0 * Z0 + Z1 * Z1)) / 12.0;
}

void vs_outline_section(const vs_edge *e, int n, vs_section *s) {
  const double xr = e[0].x0, zr = e[0].z0, scale = loop_size(e, n);
  moments m = {{0, 0, 0, 0}};
  for (int k = 0; k < n; k++) {
    if (!e[k].curved) {
      segment_moments(&e[k], xr, zr, &m);
      continue;
    }
    const moments c = curve_moments(&e[k], e[k].u0, e[k].u1, xr, zr,
                                    gl20(&e[k], e[k].u0, e[k].u1, xr, zr), scale, 0);
    for (int i = 0; i < 4; i++) m.v[i] += c.v[i];
  }
  const double A = m.v[0], cx = m.v[1] / A, cz = m.v[2] / A;
  s->area = A;
  s->cx = xr + cx;
  s->cz = zr + cz;
  s->j = m.v[3] - A * (cx * cx + cz * cz);
}
