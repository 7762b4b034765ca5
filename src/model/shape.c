/* The arch shapes (def.h, docs/model.md "Shapes"): each intrados as smooth pieces of circles,
 * an ellipse, a parabola or a catenary; the centre line and the extrados as its offsets along
 * the normal (half the thickness, the thickness); the joints cut through the centre line at
 * positions along its length, normal to it or vertical; the blocks between consecutive joints
 * with their outlines (intrados, face, extrados back, face) and exact mass properties. */
#include "shape.h"

#include "outline.h"
#include "voussoir/units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A smooth piece of a curve of the ring, run from u0 to u1, left to right. */
typedef struct {
  vs_curve c;
  double u0, u1;
} piece;

/* A curve of the ring from the left springing to the right, in up to three smooth pieces
 * (pointed: two arcs; basket: three). */
typedef struct {
  piece p[3];
  int n;
} ring;

/* A point on a ring: its piece and parameter, and the point. */
typedef struct {
  int k;
  double u, x, z;
} ring_point;

/* ------------------------------------------------------------------------------------------ */
/* The intrados of each shape                                                                  */

int vs_shape_is_sectors(const vs_arch_def *a) {
  return a->shape == VS_SHAPE_CIRCULAR && a->joints == VS_JOINTS_NORMAL &&
         (a->thickness_springing == 0.0 || a->thickness_springing == a->thickness);
}

vs_status vs_shape_circle(const vs_arch_def *a, double *radius, double *half_embrace,
                          vs_error *err) {
  if (a->span == 0.0 && a->rise == 0.0) {
    *radius = a->radius;
    *half_embrace = 0.5 * a->embrace;
    return VS_OK;
  }
  if (!(a->span > 0.0 && a->rise > 0.0 && a->rise <= 0.5 * a->span))
    return vs_error_set(err, VS_ERR_INVALID, "arch.span_mm = %g, arch.rise_mm = %g: a circular "
                        "arch takes both or neither (allowed: 0 < rise_mm <= span_mm / 2; neither: "
                        "radius_mm and embrace_deg)", a->span / VS_MM, a->rise / VS_MM);
  const double h = 0.5 * a->span, f = a->rise;
  *radius = (h * h + f * f) / (2.0 * f);
  *half_embrace = asin(fmin(1.0, h / *radius));
  if (f > *radius) *half_embrace = VS_PI - *half_embrace; /* never: f <= h */
  return VS_OK;
}

/* The span and rise a shape other than the circle takes: the keys', or those of the circle of
 * radius_mm and embrace_deg. */
static void span_rise(const vs_arch_def *a, double *h, double *f) {
  *h = a->span > 0.0 ? 0.5 * a->span : a->radius * sin(0.5 * a->embrace);
  *f = a->rise > 0.0 ? a->rise : a->radius * (1.0 - cos(0.5 * a->embrace));
}

static piece arc(double cx, double cz, double r, double u0, double u1) {
  return (piece){.c = {.kind = VS_CURVE_CIRCLE, .cx = cx, .cz = cz, .a = r, .b = r},
                 .u0 = u0, .u1 = u1};
}

/* The catenary's parameter a with a (cosh(h / a) - 1) = f (bisection in log a: the left side
 * falls from infinity to 0 as a grows). */
static double catenary_a(double h, double f) {
  double lo = h * 1e-6, hi = h * 1e6;
  for (int i = 0; i < 200; i++) {
    const double m = sqrt(lo * hi), v = m * (cosh(h / m) - 1.0);
    if (v > f) lo = m;
    else hi = m;
  }
  return sqrt(lo * hi);
}

static vs_status intrados(const vs_arch_def *a, ring *r, double *h, double *f, vs_error *err) {
  memset(r, 0, sizeof *r);
  r->n = 1;
  if (a->shape == VS_SHAPE_CIRCULAR) {
    double R, beta;
    vs_status st = vs_shape_circle(a, &R, &beta, err);
    if (st != VS_OK) return st;
    r->p[0] = arc(0.0, 0.0, R, -beta, beta);
    *h = R * sin(beta), *f = R * (1.0 - cos(beta));
    return VS_OK;
  }
  span_rise(a, h, f);
  const double hh = *h, ff = *f;
  switch (a->shape) {
  case VS_SHAPE_POINTED: {
    if (a->rise != 0.0)
      return vs_error_set(err, VS_ERR_INVALID, "arch.rise_mm = %g: a pointed arch's rise follows "
                          "from its span and arch.eccentricity (allowed: 0)", a->rise / VS_MM);
    const double c = a->eccentricity * hh, R = hh + c, ua = asin(c / R);
    r->n = 2;
    r->p[0] = arc(c, 0.0, R, -0.5 * VS_PI, -ua);
    r->p[1] = arc(-c, 0.0, R, ua, 0.5 * VS_PI);
    *f = sqrt(R * R - c * c);
    return VS_OK;
  }
  case VS_SHAPE_ELLIPTICAL:
    r->p[0] = (piece){.c = {.kind = VS_CURVE_ELLIPSE, .a = hh, .b = ff}, .u0 = -0.5 * VS_PI,
                      .u1 = 0.5 * VS_PI};
    return VS_OK;
  case VS_SHAPE_BASKET: {
    const double th = a->haunch, den = sin(th) + cos(th) - 1.0, D = (hh - ff) / den;
    const double R1 = ff + D * sin(th), R2 = hh - D * cos(th);
    if (!(ff <= hh && R2 > 0.0 && den > 0.0))
      return vs_error_set(err, VS_ERR_INVALID, "arch.rise_mm = %g: a basket-handle arch of span "
                          "%g mm and haunch arcs of %g deg (allowed: rise in (%g, %g] mm)", ff / VS_MM,
                          2.0 * hh / VS_MM, th / VS_DEG, hh * (1.0 - sin(th)) / cos(th) / VS_MM,
                          hh / VS_MM);
    r->n = 3;
    r->p[0] = arc(-hh + R2, 0.0, R2, -0.5 * VS_PI, -0.5 * VS_PI + th);
    r->p[1] = arc(0.0, ff - R1, R1, -0.5 * VS_PI + th, 0.5 * VS_PI - th);
    r->p[2] = arc(hh - R2, 0.0, R2, 0.5 * VS_PI - th, 0.5 * VS_PI);
    return VS_OK;
  }
  case VS_SHAPE_PARABOLIC:
    r->p[0] = (piece){.c = {.kind = VS_CURVE_PARABOLA, .cz = ff, .a = hh, .b = ff}, .u0 = -hh,
                      .u1 = hh};
    return VS_OK;
  case VS_SHAPE_CATENARY:
    r->p[0] = (piece){.c = {.kind = VS_CURVE_CATENARY, .cz = ff, .a = catenary_a(hh, ff)},
                      .u0 = -hh, .u1 = hh};
    return VS_OK;
  default:
    return vs_error_set(err, VS_ERR_INVALID, "arch.shape = %d: not a generated shape", (int)a->shape);
  }
}

/* ------------------------------------------------------------------------------------------ */
/* Offsets: the centre line and the extrados                                                   */

static void piece_point(const piece *p, double u, double pt[2], double d[2]) {
  vs_curve_eval(&p->c, u, pt, d);
}

/* The u in [lo, hi] where piece p's x is x0 (x(lo) - x0 and x(hi) - x0 of opposite signs). */
static double solve_x(const piece *p, double lo, double hi, double x0) {
  double pt[2];
  piece_point(p, lo, pt, NULL);
  const double slo = pt[0] - x0;
  for (int i = 0; i < 200 && hi - lo > 0.0; i++) {
    const double m = 0.5 * (lo + hi);
    if (m <= lo || m >= hi) break;
    piece_point(p, m, pt, NULL);
    if ((pt[0] - x0 < 0.0) == (slo < 0.0)) lo = m;
    else hi = m;
  }
  return 0.5 * (lo + hi);
}

/* The intrados offset by k t(x) along its normal, t(x) = s (t_c + (t_s - t_c) (x / h)^2): the
 * centre line (k = 1/2), the extrados (k = 1). Where two pieces meet at an angle (the pointed
 * arch's crown) the offsets are carried on to where they cross, on the crown line x = 0. */
static void offset(const ring *in, double h, double tc, double ts, double k, double s, ring *out) {
  *out = *in;
  for (int i = 0; i < in->n; i++) {
    out->p[i].c.d0 = k * s * tc;
    out->p[i].c.d2 = k * s * (ts - tc) / (h * h);
    out->p[i].c.xc = 0.0;
  }
  for (int i = 0; i + 1 < in->n; i++) {
    double ta[2], tb[2];
    piece_point(&in->p[i], in->p[i].u1, NULL, ta);
    piece_point(&in->p[i + 1], in->p[i + 1].u0, NULL, tb);
    if (fabs(atan2(ta[0] * tb[1] - ta[1] * tb[0], ta[0] * tb[0] + ta[1] * tb[1])) < 1e-9) continue;
    /* the circles of a pointed arch: x rises with u over [-pi/2, pi/2] */
    out->p[i].u1 = solve_x(&out->p[i], out->p[i].u0, 0.5 * VS_PI, 0.0);
    out->p[i + 1].u0 = solve_x(&out->p[i + 1], -0.5 * VS_PI, out->p[i + 1].u1, 0.0);
  }
}

/* ------------------------------------------------------------------------------------------ */
/* Lengths along the centre line                                                               */

/* Gauss-Legendre of order 10 on [-1, 1]: the positive nodes and their weights. */
static const double GL10[5][2] = {
    {0.14887433898163122, 0.29552422471475287}, {0.43339539412924721, 0.26926671930999635},
    {0.67940956829902444, 0.21908636251598204}, {0.86506336668898454, 0.14945134915058059},
    {0.97390652851717174, 0.066671344308688138}};

static double speed(const piece *p, double u) {
  double d[2];
  piece_point(p, u, NULL, d);
  return hypot(d[0], d[1]);
}

static double gl10(const piece *p, double a, double b) {
  const double c = 0.5 * (a + b), w = 0.5 * (b - a);
  double s = 0.0;
  for (int i = 0; i < 5; i++) s += GL10[i][1] * (speed(p, c - w * GL10[i][0]) + speed(p, c + w * GL10[i][0]));
  return w * s;
}

/* The length of piece p from a to b: Gauss-Legendre 10, halved until it agrees to round-off. */
static double arc_length(const piece *p, double a, double b, double whole, int depth) {
  const double m = 0.5 * (a + b), l = gl10(p, a, m), r = gl10(p, m, b);
  if (fabs(l + r - whole) <= 1e-14 * fabs(whole) || depth >= 30) return l + r;
  return arc_length(p, a, m, l, depth + 1) + arc_length(p, m, b, r, depth + 1);
}

static double length_to(const piece *p, double u) {
  return arc_length(p, p->u0, u, gl10(p, p->u0, u), 0);
}

static double ring_length(const ring *r) {
  double s = 0.0;
  for (int i = 0; i < r->n; i++) s += length_to(&r->p[i], r->p[i].u1);
  return s;
}

/* The point of ring r at length s from its start (Newton on the length, kept in its bracket).
 * Within round-off (1e-12 of the ring's length) of the end of a piece: that end. */
static ring_point at_length(const ring *r, double s, double total) {
  int k = 0;
  double len = length_to(&r->p[0], r->p[0].u1);
  while (k + 1 < r->n && s > len + 1e-12 * total) {
    s -= len;
    k++;
    len = length_to(&r->p[k], r->p[k].u1);
  }
  const piece *p = &r->p[k];
  double lo = p->u0, hi = p->u1, u = p->u0 + (p->u1 - p->u0) * fmin(1.0, fmax(0.0, s / len));
  if (fabs(s - len) <= 1e-12 * total) u = p->u1;
  else
    for (int i = 0; i < 100; i++) {
      const double g = length_to(p, u) - s;
      if (g > 0.0) hi = u;
      else lo = u;
      double next = u - g / speed(p, u);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (fabs(next - u) <= 1e-15 * (fabs(p->u1 - p->u0))) {
        u = next;
        break;
      }
      u = next;
    }
  double pt[2];
  piece_point(p, u, pt, NULL);
  return (ring_point){.k = k, .u = u, .x = pt[0], .z = pt[1]};
}

/* ------------------------------------------------------------------------------------------ */
/* Joints                                                                                      */

/* Take the point of piece k at u as a crossing on the side sign of m if it is the nearest. */
static void keep(const ring *r, int k, double u, const double m[2], const double d[2], int sign,
                 double *best, ring_point *o) {
  double pt[2];
  piece_point(&r->p[k], u, pt, NULL);
  const double along = (pt[0] - m[0]) * d[0] + (pt[1] - m[1]) * d[1];
  if (sign * along > 0.0 && fabs(along) < *best) {
    *best = fabs(along);
    *o = (ring_point){.k = k, .u = u, .x = pt[0], .z = pt[1]};
  }
}

/* Where the line through m along the unit direction d (from the intrados out) crosses ring r on
 * the side sign (-1: behind m, the intrados; +1: ahead, the extrados), nearest m: a sign change
 * of the distance from the line between 64 samples of a piece, bisected; or a piece's end within
 * round-off of the line (where two pieces meet at the line, their ends may lie a rounding apart
 * on either side of it). 0, or -1 when it does not. */
static int crossing(const ring *r, const double m[2], const double d[2], int sign, ring_point *o) {
  double best = INFINITY;
  for (int k = 0; k < r->n; k++) {
    const piece *p = &r->p[k];
    const int N = 64;
    double ga = 0.0, ua = p->u0;
    for (int i = 0; i <= N; i++) {
      const double u = i == N ? p->u1 : p->u0 + (p->u1 - p->u0) * i / N;
      double pt[2];
      piece_point(p, u, pt, NULL);
      const double g = d[0] * (pt[1] - m[1]) - d[1] * (pt[0] - m[0]);
      const double eps = 1e-13 * (fabs(pt[0]) + fabs(pt[1]) + fabs(m[0]) + fabs(m[1]));
      if ((i == 0 || i == N) && fabs(g) <= eps) keep(r, k, u, m, d, sign, &best, o);
      if (i > 0 && (g == 0.0 || (g < 0.0) != (ga < 0.0))) {
        double lo = ua, hi = u, glo = ga;
        for (int it = 0; it < 200; it++) {
          const double c = 0.5 * (lo + hi);
          if (c <= lo || c >= hi) break;
          piece_point(p, c, pt, NULL);
          const double gc = d[0] * (pt[1] - m[1]) - d[1] * (pt[0] - m[0]);
          if ((gc < 0.0) == (glo < 0.0)) lo = c, glo = gc;
          else hi = c;
        }
        keep(r, k, 0.5 * (lo + hi), m, d, sign, &best, o);
      }
      ga = g, ua = u;
    }
  }
  return isfinite(best) ? 0 : -1;
}

/* A ring point's place along its ring, for ordering: piece, then parameter. */
static int before(const ring_point *a, const ring_point *b) {
  return a->k < b->k || (a->k == b->k && a->u < b->u);
}

static ring_point end_point(const ring *r, int right) {
  const piece *p = &r->p[right ? r->n - 1 : 0];
  const double u = right ? p->u1 : p->u0;
  double pt[2];
  piece_point(p, u, pt, NULL);
  return (ring_point){.k = right ? r->n - 1 : 0, .u = u, .x = pt[0], .z = pt[1]};
}

/* The line of interior joint at centre-line point c: through it, along d (unit, outward). */
static void cut_line(const vs_arch_def *a, const ring *mid, const ring_point *c, double d[2]) {
  if (a->joints == VS_JOINTS_VERTICAL) {
    d[0] = 0.0, d[1] = 1.0;
    return;
  }
  double t[2], t2[2];
  piece_point(&mid->p[c->k], c->u, NULL, t);
  const double s = hypot(t[0], t[1]);
  t[0] /= s, t[1] /= s;
  if (c->k + 1 < mid->n && c->u >= mid->p[c->k].u1) { /* at a corner: the bisector */
    piece_point(&mid->p[c->k + 1], mid->p[c->k + 1].u0, NULL, t2);
    const double s2 = hypot(t2[0], t2[1]);
    t[0] += t2[0] / s2, t[1] += t2[1] / s2;
    const double sb = hypot(t[0], t[1]);
    t[0] /= sb, t[1] /= sb;
  }
  d[0] = -t[1], d[1] = t[0];
}

/* ------------------------------------------------------------------------------------------ */
/* Positions                                                                                   */

vs_status vs_shape_positions(const vs_arch_def *a, double length, double *f, vs_error *err) {
  const int n = a->voussoirs;
  if (a->n_positions > 0 && a->keystone > 0.0)
    return vs_error_set(err, VS_ERR_INVALID, "arch.keystone_mm = %g with arch.joint_positions: "
                        "the positions place every joint (allowed: one or the other)",
                        a->keystone / VS_MM);
  if (a->n_positions > 0) {
    if (a->n_positions != n - 1)
      return vs_error_set(err, VS_ERR_INVALID, "arch.joint_positions: %d positions for %d "
                          "voussoirs (allowed: arch.voussoirs - 1 = %d, increasing in (0, 1))",
                          a->n_positions, n, n - 1);
    for (int k = 0; k < n - 1; k++)
      if (!(a->positions[k] > (k > 0 ? a->positions[k - 1] : 0.0) && a->positions[k] < 1.0))
        return vs_error_set(err, VS_ERR_INVALID, "arch.joint_positions: position %d = %g "
                            "(allowed: increasing in (0, 1))", k + 1, a->positions[k]);
    memcpy(f, a->positions, (size_t)(n - 1) * sizeof *f);
    return VS_OK;
  }
  if (a->keystone > 0.0) {
    const double w = a->keystone / length;
    if (n % 2 == 0 || n < 3 || !(w < 1.0))
      return vs_error_set(err, VS_ERR_INVALID, "arch.keystone_mm = %g with arch.voussoirs = %d "
                          "(allowed: an odd number of voussoirs, >= 3, and a keystone narrower "
                          "than the %s's %g mm)", a->keystone / VS_MM, n,
                          a->joints == VS_JOINTS_VERTICAL ? "span" : "centre line", length / VS_MM);
    const int m = (n - 1) / 2;
    for (int k = 1; k <= m; k++) {
      f[k - 1] = 0.5 * (1.0 - w) * k / m;
      f[n - 1 - k] = 1.0 - f[k - 1];
    }
    return VS_OK;
  }
  for (int k = 1; k < n; k++) f[k - 1] = (double)k / n;
  return VS_OK;
}

/* Voussoir sizes scaled by size[] and rescaled to fill (0, 1) again. */
static void scale_sizes(int n, const double *size, double *f) {
  double *cum = f; /* in place: f[k - 1] is joint k's fraction */
  double prev = 0.0, total = 0.0;
  for (int i = 0; i < n; i++) {
    const double next = i < n - 1 ? cum[i] : 1.0, w = (next - prev) * size[i];
    prev = next;
    if (i < n - 1) cum[i] = total + w;
    total += w;
  }
  for (int i = 0; i < n - 1; i++) cum[i] /= total;
}

/* ------------------------------------------------------------------------------------------ */
/* Blocks                                                                                      */

/* The edges of ring r from point a to point b (forward) or from b back to a, one per piece. */
static int ring_edges(const ring *r, const ring_point *a, const ring_point *b, int forward,
                      vs_edge *e) {
  int n = 0;
  vs_edge tmp[3];
  for (int k = a->k; k <= b->k; k++) {
    const double lo = k == a->k ? a->u : r->p[k].u0, hi = k == b->k ? b->u : r->p[k].u1;
    if (!(hi - lo > 1e-13 * fabs(r->p[k].u1 - r->p[k].u0))) continue;
    tmp[n++] = (vs_edge){.curved = 1, .c = r->p[k].c, .u0 = lo, .u1 = hi, .joint = -1};
  }
  for (int i = 0; i < n; i++) {
    e[i] = tmp[forward ? i : n - 1 - i];
    if (!forward) {
      const double t = e[i].u0;
      e[i].u0 = e[i].u1, e[i].u1 = t;
    }
  }
  return n;
}

/* One joint: its intrados point, and its extrados point on each side (0: the block before, 1:
 * the block after). */
typedef struct {
  ring_point in, ex[2];
} cut;

typedef struct {
  const vs_arch_def *a;
  double h, f, tc, ts, centre;
  ring in, mid;
  ring *ext; /* per block: its extrados (its own thickness) */
  cut *cuts; /* n + 1 */
} builder;

static vs_status cut_joint(builder *b, int k, double frac, vs_error *err) {
  const int n = b->a->voussoirs;
  cut *c = &b->cuts[k];
  if (k == 0 || k == n) { /* the springing faces: normal to the intrados at its ends */
    c->in = end_point(&b->in, k == n);
    for (int s = 0; s < 2; s++) {
      const int blk = k == 0 ? 0 : n - 1;
      c->ex[s] = end_point(&b->ext[blk], k == n);
    }
    return VS_OK;
  }
  double mp[2], d[2];
  if (b->a->joints == VS_JOINTS_VERTICAL) { /* up from below the arch at its fraction of the span */
    const ring_point l = end_point(&b->in, 0), r = end_point(&b->in, 1);
    mp[0] = l.x + frac * (r.x - l.x);
    mp[1] = fmin(l.z, r.z) - 10.0 * (r.x - l.x + b->f);
    d[0] = 0.0, d[1] = 1.0;
  } else { /* normal to the centre line at its fraction of the centre line's length */
    const ring_point m = at_length(&b->mid, frac * b->centre, b->centre);
    cut_line(b->a, &b->mid, &m, d);
    mp[0] = m.x, mp[1] = m.z;
  }
  const int vertical = b->a->joints == VS_JOINTS_VERTICAL;
  const int bad_in = crossing(&b->in, mp, d, vertical ? 1 : -1, &c->in);
  if (vertical && bad_in == 0) mp[0] = c->in.x, mp[1] = c->in.z; /* the extrados above it */
  int bad_ex = 0;
  for (int s = 0; s < 2 && bad_ex == 0 && bad_in == 0; s++)
    bad_ex = crossing(&b->ext[k - 1 + s], mp, d, 1, &c->ex[s]);
  if (bad_in != 0 || bad_ex != 0)
    return vs_error_set(err, VS_ERR_INVALID, "arch.joints = %s: joint %d, at %g of the %s (x = "
                        "%g mm), misses the %s (allowed: joints that cross the ring from intrados "
                        "to extrados; a thickness that varies less, or other positions)",
                        vertical ? "vertical" : "normal", k + 1, frac,
                        vertical ? "span" : "centre line", mp[0] / VS_MM,
                        bad_in ? "intrados" : "extrados");
  return VS_OK;
}

static vs_status check_order(const builder *b, vs_error *err) {
  const int n = b->a->voussoirs;
  for (int k = 0; k < n; k++) {
    const cut *c0 = &b->cuts[k], *c1 = &b->cuts[k + 1];
    if (!before(&c0->in, &c1->in) || !before(&c0->ex[1], &c1->ex[0]))
      return vs_error_set(err, VS_ERR_INVALID, "arch: joints %d and %d cross or meet (on the "
                          "%s; allowed: joints in order along the ring: fewer voussoirs, other "
                          "positions, a wider keystone (arch.keystone_mm) or a crown joint (an "
                          "even number of voussoirs) where a pointed arch's faces converge at "
                          "its apex, or arch.joints = %s)", k + 1, k + 2,
                          before(&c0->in, &c1->in) ? "extrados" : "intrados",
                          b->a->joints == VS_JOINTS_VERTICAL ? "normal" : "vertical");
  }
  return VS_OK;
}

static void set_joint(const builder *b, vs_geometry *g, int k) {
  const int n = b->a->voussoirs;
  const cut *c = &b->cuts[k];
  const ring_point *e = &c->ex[0];
  if (k == 0 || (k < n && hypot(c->ex[1].x - c->in.x, c->ex[1].z - c->in.z) <
                              hypot(c->ex[0].x - c->in.x, c->ex[0].z - c->in.z)))
    e = &c->ex[1]; /* the shorter face of the two blocks' */
  const double dx = e->x - c->in.x, dz = e->z - c->in.z, len = hypot(dx, dz);
  vs_joint_geom *j = &g->joints[k];
  j->a = k == 0 ? VS_SUPPORT_LEFT : k - 1;
  j->b = k == n ? VS_SUPPORT_RIGHT : k;
  j->px = 0.5 * (c->in.x + e->x);
  j->pz = 0.5 * (c->in.z + e->z);
  j->nx = dz / len; /* s = (dx, dz) / len = n turned +90 degrees */
  j->nz = -dx / len;
  j->length = len;
  j->depth = b->a->depth;
}

static vs_status set_block(const builder *b, vs_geometry *g, int i, vs_error *err) {
  const cut *c0 = &b->cuts[i], *c1 = &b->cuts[i + 1];
  vs_edge e[8];
  int n = ring_edges(&b->in, &c0->in, &c1->in, 1, e);
  e[n++] = (vs_edge){.x0 = c1->in.x, .z0 = c1->in.z, .x1 = c1->ex[0].x, .z1 = c1->ex[0].z,
                     .u1 = 1.0, .joint = i + 1};
  n += ring_edges(&b->ext[i], &c0->ex[1], &c1->ex[0], 0, e + n);
  e[n++] = (vs_edge){.x0 = c0->ex[1].x, .z0 = c0->ex[1].z, .x1 = c0->in.x, .z1 = c0->in.z,
                     .u1 = 1.0, .joint = i};
  vs_status st = vs_geometry_set_outline(g, i, n, e, err);
  if (st != VS_OK) return st;
  vs_section s;
  vs_outline_section(g->edges + g->blocks[i].edge0, n, &s);
  vs_block *blk = &g->blocks[i];
  const double rho_b = b->a->density * b->a->depth;
  blk->area = s.area;
  blk->mass = rho_b * s.area;
  blk->inertia = rho_b * s.j;
  blk->cx = s.cx, blk->cz = s.cz;
  blk->phi0 = blk->phi1 = 0.0;
  if (!(s.area > 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "arch: voussoir %d has an area of %g mm^2 "
                        "(allowed: > 0; fewer voussoirs or other positions)", i + 1,
                        s.area / (VS_MM * VS_MM));
  return VS_OK;
}

static vs_status check_def(const vs_arch_def *a, vs_error *err) {
  if (a->voussoirs < 1 || !(a->thickness > 0.0) || !(a->depth > 0.0) || !(a->density > 0.0) ||
      !(a->thickness_springing >= 0.0) || !(a->eccentricity >= 0.0) || !(a->keystone >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "arch: voussoirs %d, thickness %g mm, springing "
                        "thickness %g mm, depth %g mm, density %g kg/m^3, eccentricity %g, "
                        "keystone %g mm (allowed: >= 1, > 0, >= 0, > 0, > 0, >= 0, >= 0)",
                        a->voussoirs, a->thickness / VS_MM, a->thickness_springing / VS_MM,
                        a->depth / VS_MM, a->density, a->eccentricity, a->keystone / VS_MM);
  if (a->joints != VS_JOINTS_NORMAL && a->joints != VS_JOINTS_VERTICAL)
    return vs_error_set(err, VS_ERR_INVALID, "arch.joints = %d (allowed: normal, vertical)",
                        (int)a->joints);
  return VS_OK;
}

/* The builder's rings: intrados, centre line, each block's extrados. */
static vs_status rings(builder *b, const double *thick, vs_error *err) {
  const vs_arch_def *a = b->a;
  vs_status st = check_def(a, err);
  if (st == VS_OK) st = intrados(a, &b->in, &b->h, &b->f, err);
  if (st != VS_OK) return st;
  b->tc = a->thickness;
  b->ts = a->thickness_springing > 0.0 ? a->thickness_springing : a->thickness;
  offset(&b->in, b->h, b->tc, b->ts, 0.5, 1.0, &b->mid);
  b->centre = ring_length(&b->mid);
  b->ext = malloc((size_t)a->voussoirs * sizeof *b->ext);
  if (b->ext == NULL) return vs_error_set(err, VS_ERR_NOMEM, "arch: out of memory");
  for (int i = 0; i < a->voussoirs; i++)
    offset(&b->in, b->h, b->tc, b->ts, 1.0, thick != NULL ? thick[i] : 1.0, &b->ext[i]);
  return VS_OK;
}

vs_status vs_shape_centre_length(const vs_arch_def *a, double *length, vs_error *err) {
  builder b = {.a = a};
  vs_status st = rings(&b, NULL, err);
  if (st == VS_OK) *length = b.centre;
  free(b.ext);
  return st;
}

vs_status vs_shape_build(const vs_arch_def *a, const double *size, const double *thick,
                         vs_geometry **out, vs_error *err) {
  *out = NULL;
  const int n = a->voussoirs;
  builder b = {.a = a};
  vs_status st = rings(&b, thick, err);
  double *f = NULL;
  if (st == VS_OK) {
    f = malloc((size_t)(n > 1 ? n : 2) * sizeof *f);
    b.cuts = calloc((size_t)n + 1, sizeof *b.cuts);
    if (f == NULL || b.cuts == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "arch: out of memory");
  }
  /* positions along the centre line (normal joints) or across the span (vertical ones) */
  if (st == VS_OK)
    st = vs_shape_positions(a, a->joints == VS_JOINTS_VERTICAL ? 2.0 * b.h : b.centre, f, err);
  if (st == VS_OK && size != NULL) scale_sizes(n, size, f);
  for (int k = 0; st == VS_OK && k <= n; k++)
    st = cut_joint(&b, k, k == 0 ? 0.0 : k == n ? 1.0 : f[k - 1], err);
  if (st == VS_OK) st = check_order(&b, err);
  if (st == VS_OK) st = vs_geometry_create(n, n + 1, out, err);
  for (int i = 0; st == VS_OK && i < n; i++) st = set_block(&b, *out, i, err);
  for (int k = 0; st == VS_OK && k <= n; k++) set_joint(&b, *out, k);
  if (st == VS_OK) {
    vs_geometry *g = *out;
    g->span = 2.0 * b.h;
    g->rise = b.f;
    g->thickness = b.tc;
    g->gravity = a->gravity;
    if (a->shape == VS_SHAPE_CIRCULAR) {
      g->radius = b.in.p[0].c.a;
      g->embrace = b.in.p[0].u1 - b.in.p[0].u0;
    }
  } else {
    vs_geometry_destroy(out);
  }
  free(f), free(b.cuts), free(b.ext);
  return st;
}
