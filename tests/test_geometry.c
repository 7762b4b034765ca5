/* Tests of the arch builder (geometry.h): block mass, centroid and inertia against Gauss
 * quadrature of the annular sectors done here, total weight, span and rise, joint placement and
 * orientation, and mirror symmetry about the crown. And of the blocks' outlines (geometry.h,
 * outline.h): the curves and their offsets against their definitions (points, derivatives by
 * central differences, the offset's distance and direction), the circular arch's outlines
 * against its closed forms (sampled points, the convex outline the contacts use), and the exact
 * area, centroid and second moment of a region bounded by curves (Green's theorem, integrated,
 * not faceted) against closed forms (annular sector, rectangle) and a dense quadrature over an
 * elliptical ring segment done here. SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "check.h"
#include "outline.h"
#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"


/* Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n from the Chebyshev guess). */
#define NGL 16
static void gauss_legendre(double x[NGL], double wt[NGL]) {
  const double pi = acos(-1.0);
  for (int i = 0; i < NGL; i++) {
    double z = cos(pi * (i + 0.75) / (NGL + 0.5)), dp = 1;
    for (int it = 0; it < 100; it++) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= NGL; k++) {
        double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = NGL * (z * p1 - p0) / (z * z - 1);
      double dz = p1 / dp;
      z -= dz;
      if (fabs(dz) < 1e-16) break;
    }
    x[i] = z;
    wt[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

typedef struct {
  double area, cx, cz, J; /* J: polar second moment of area about the centroid */
} sector_props;

/* Annular sector ri <= r <= re, p0 <= phi <= p1, phi from the +z axis towards +x
 * (x = r sin phi, z = r cos phi), dA = r dr dphi; a composite 16x16-point Gauss rule on
 * 4 x 4 panels. The second moment is taken about the centroid directly (no parallel-axis
 * subtraction, which would lose digits). */
static void sector_quadrature(double ri, double re, double p0, double p1, sector_props *sp) {
  double x[NGL], wt[NGL];
  gauss_legendre(x, wt);
  const int P = 4;
  double A = 0, Sx = 0, Sz = 0;
  *sp = (sector_props){0, 0, 0, 0};
  for (int pass = 0; pass < 2; pass++) {
    double J = 0;
    for (int ir = 0; ir < P; ir++) {
      double ra = ri + (re - ri) * ir / P, rb = ri + (re - ri) * (ir + 1) / P;
      for (int ip = 0; ip < P; ip++) {
        double pa = p0 + (p1 - p0) * ip / P, pb = p0 + (p1 - p0) * (ip + 1) / P;
        for (int i = 0; i < NGL; i++) {
          double r = 0.5 * (ra + rb) + 0.5 * (rb - ra) * x[i];
          for (int j = 0; j < NGL; j++) {
            double ph = 0.5 * (pa + pb) + 0.5 * (pb - pa) * x[j];
            double dA = wt[i] * wt[j] * 0.25 * (rb - ra) * (pb - pa) * r;
            double px = r * sin(ph), pz = r * cos(ph);
            if (pass == 0) {
              A += dA;
              Sx += px * dA;
              Sz += pz * dA;
            } else {
              double dx = px - sp->cx, dz = pz - sp->cz;
              J += (dx * dx + dz * dz) * dA;
            }
          }
        }
      }
    }
    if (pass == 0) {
      sp->area = A;
      sp->cx = Sx / A;
      sp->cz = Sz / A;
    } else {
      sp->J = J;
    }
  }
}

static vs_case make_case(double R_mm, double t_mm, double emb_deg, int n, double b_mm) {
  vs_case c;
  vs_case_defaults(&c);
  c.radius_mm = R_mm;
  c.thickness_mm = t_mm;
  c.embrace_deg = emb_deg;
  c.voussoirs = n;
  c.depth_mm = b_mm;
  return c;
}

static vs_geometry *build(const vs_case *c) {
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  vs_status s = vs_test_arch(c, &g, &err);
  if (s != VS_OK || !g) fail_msg("vs_geometry_create_arch: %s: %s", vs_strerror(s), err.msg);
  return g;
}

/* The cases: the reference specimen, a semicircle with few thick voussoirs, a shallow arch
 * with an even voussoir count. */
static const double CASES[][5] = {{300, 24, 125, 55, 120},
                                   {1000, 200, 180, 7, 500},
                                   {2500, 80, 40, 12, 300},
                                   {300, 24, 90, 1, 120}};
#define NCASES (sizeof CASES / sizeof CASES[0])

static void test_blocks_against_quadrature(void **state) {
  (void)state;
  for (size_t k = 0; k < NCASES; k++) {
    vs_case c = make_case(CASES[k][0], CASES[k][1], CASES[k][2], (int)CASES[k][3], CASES[k][4]);
    vs_geometry *g = build(&c);
    double Ri = c.radius_mm * 1e-3, Re = Ri + c.thickness_mm * 1e-3;
    double E = c.embrace_deg * acos(-1.0) / 180, b = c.depth_mm * 1e-3, rho = c.density_kg_m3;
    int n = c.voussoirs;
    double dphi = E / n;
    assert_int_equal(g->n_blocks, n);
    double msum = 0;
    for (int i = 0; i < n; i++) {
      double p0 = -0.5 * E + i * dphi, p1 = p0 + dphi;
      sector_props sp;
      sector_quadrature(Ri, Re, p0, p1, &sp);
      const vs_block *bl = &g->blocks[i];
      CHECK(bl->area, sp.area, 1e-12, 0);
      CHECK(bl->mass, rho * b * sp.area, 1e-12, 0);
      CHECK(bl->cx, sp.cx, 0, 1e-12 * Re);
      CHECK(bl->cz, sp.cz, 0, 1e-12 * Re);
      CHECK(bl->inertia, rho * b * sp.J, 1e-9, 0);
      CHECK(bl->phi0, p0, 0, 1e-12);
      CHECK(bl->phi1, p1, 0, 1e-12);
      msum += bl->mass;
    }
    /* Total weight: rho b g (E/2)(Re^2 - Ri^2). */
    double W = rho * b * c.gravity_m_s2 * 0.5 * E * (Re * Re - Ri * Ri);
    CHECK(vs_geometry_weight(g), W, 1e-12, 0);
    CHECK(msum * c.gravity_m_s2, W, 1e-12, 0);
    vs_geometry_destroy(&g);
    assert_null(g);
  }
}

static void test_arch_dimensions(void **state) {
  (void)state;
  for (size_t k = 0; k < NCASES; k++) {
    vs_case c = make_case(CASES[k][0], CASES[k][1], CASES[k][2], (int)CASES[k][3], CASES[k][4]);
    vs_geometry *g = build(&c);
    double R = c.radius_mm * 1e-3, t = c.thickness_mm * 1e-3;
    double E = c.embrace_deg * acos(-1.0) / 180;
    CHECK(g->span, 2 * R * sin(0.5 * E), 1e-13, 0);
    CHECK(g->rise, R * (1 - cos(0.5 * E)), 1e-12, 0);
    CHECK(g->radius, R, 1e-15, 0);
    CHECK(g->thickness, t, 1e-15, 0);
    CHECK(g->embrace, E, 1e-15, 0);
    CHECK(g->gravity, c.gravity_m_s2, 1e-15, 0);
    CHECK(vs_case_span_mm(&c), 2 * c.radius_mm * sin(0.5 * E), 1e-13, 0);
    vs_geometry_destroy(&g);
  }
  /* The reference specimen: span 532-533 mm, rise about 162 mm (docs/model.md). */
  vs_case c;
  vs_case_defaults(&c);
  vs_geometry *g = build(&c);
  assert_true(g->span > 0.532 && g->span < 0.533);
  assert_true(g->rise > 0.161 && g->rise < 0.163);
  assert_int_equal(g->n_blocks, 55);
  assert_int_equal(g->n_joints, 56);
  vs_geometry_destroy(&g);
  vs_geometry_destroy(&g); /* NULL pointer: no-op */
  vs_geometry_destroy(NULL);
}

/* Joint k (0-based j = k-1) lies on the radial plane phi_j = -E/2 + j dphi, between block j-1
 * (or the left support) and block j (or the right support); its centre is at radius R + t/2;
 * the normal is the circle's tangent in the direction of increasing phi,
 * n = (cos phi, -sin phi), so that s = n turned +90 degrees is radial outward. */
static void test_joints(void **state) {
  (void)state;
  for (size_t k = 0; k < NCASES; k++) {
    vs_case c = make_case(CASES[k][0], CASES[k][1], CASES[k][2], (int)CASES[k][3], CASES[k][4]);
    vs_geometry *g = build(&c);
    double R = c.radius_mm * 1e-3, t = c.thickness_mm * 1e-3, b = c.depth_mm * 1e-3;
    double E = c.embrace_deg * acos(-1.0) / 180;
    int n = c.voussoirs;
    assert_int_equal(g->n_joints, n + 1);
    for (int j = 0; j <= n; j++) {
      const vs_joint_geom *jg = &g->joints[j];
      double ph = -0.5 * E + j * E / n;
      assert_int_equal(jg->a, j == 0 ? VS_SUPPORT_LEFT : j - 1);
      assert_int_equal(jg->b, j == n ? VS_SUPPORT_RIGHT : j);
      CHECK(hypot(jg->nx, jg->nz), 1.0, 1e-14, 0);
      CHECK(jg->nx, cos(ph), 0, 1e-14);
      CHECK(jg->nz, -sin(ph), 0, 1e-14);
      CHECK(hypot(jg->px, jg->pz), R + 0.5 * t, 1e-14, 0);
      CHECK(jg->px, (R + 0.5 * t) * sin(ph), 0, 1e-14);
      CHECK(jg->pz, (R + 0.5 * t) * cos(ph), 0, 1e-14);
      CHECK(jg->length, t, 1e-14, 0);
      CHECK(jg->depth, b, 1e-14, 0);
      /* Tangent from intrados to extrados: radial outward. */
      double sx, sz;
      vs_joint_tangent(jg, &sx, &sz);
      CHECK(sx, sin(ph), 0, 1e-14);
      CHECK(sz, cos(ph), 0, 1e-14);
      /* The normal points from a into b: b's centroid is on the +n side, a's on the -n side. */
      if (jg->b >= 0) {
        const vs_block *bl = &g->blocks[jg->b];
        assert_true((bl->cx - jg->px) * jg->nx + (bl->cz - jg->pz) * jg->nz > 0);
      }
      if (jg->a >= 0) {
        const vs_block *bl = &g->blocks[jg->a];
        assert_true((bl->cx - jg->px) * jg->nx + (bl->cz - jg->pz) * jg->nz < 0);
      }
    }
    /* Springing joints on the planes at -+E/2. */
    CHECK(atan2(g->joints[0].px, g->joints[0].pz), -0.5 * E, 0, 1e-13);
    CHECK(atan2(g->joints[n].px, g->joints[n].pz), 0.5 * E, 0, 1e-13);
    vs_geometry_destroy(&g);
  }
}

/* Mirror x -> -x maps block i to block n-1-i and joint j to joint n-j (the normal, which runs
 * left to right, keeps its x component and flips its z component). */
static void test_symmetry(void **state) {
  (void)state;
  for (size_t k = 0; k < NCASES; k++) {
    vs_case c = make_case(CASES[k][0], CASES[k][1], CASES[k][2], (int)CASES[k][3], CASES[k][4]);
    vs_geometry *g = build(&c);
    int n = g->n_blocks;
    double L = c.radius_mm * 1e-3;
    for (int i = 0; i < n; i++) {
      const vs_block *p = &g->blocks[i], *m = &g->blocks[n - 1 - i];
      CHECK(p->cx, -m->cx, 0, 1e-14 * L);
      CHECK(p->cz, m->cz, 0, 1e-14 * L);
      CHECK(p->mass, m->mass, 1e-13, 0);
      CHECK(p->inertia, m->inertia, 1e-11, 0);
      CHECK(p->area, m->area, 1e-13, 0);
    }
    if (n % 2 == 1) CHECK(g->blocks[n / 2].cx, 0, 0, 1e-14 * L);
    for (int j = 0; j <= n; j++) {
      const vs_joint_geom *p = &g->joints[j], *m = &g->joints[n - j];
      CHECK(p->px, -m->px, 0, 1e-14 * L);
      CHECK(p->pz, m->pz, 0, 1e-14 * L);
      CHECK(p->nx, m->nx, 0, 1e-14);
      CHECK(p->nz, -m->nz, 0, 1e-14);
    }
    vs_geometry_destroy(&g);
  }
}

/* An empty geometry of the requested size. */
static void test_create_empty(void **state) {
  (void)state;
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(vs_geometry_create(3, 4, &g, &err), VS_OK);
  assert_non_null(g);
  assert_int_equal(g->n_blocks, 3);
  assert_int_equal(g->n_joints, 4);
  assert_non_null(g->blocks);
  assert_non_null(g->joints);
  vs_geometry_destroy(&g);
  assert_null(g);
}

static const double PI = 3.14159265358979323846;

/* Every kind of curve, bare and offset by a constant and a varying distance. */
static vs_curve curve_of(int kind, int offset) {
  vs_curve c = {.kind = (vs_curve_kind)kind, .cx = 0.1, .cz = -0.2, .a = 0.4, .b = 0.25};
  if (kind == VS_CURVE_CATENARY) c.a = 0.3;
  if (offset >= 1) c.d0 = 0.03;
  if (offset == 2) c.d2 = 0.2, c.xc = 0.05;
  return c;
}

/* The derivative against central differences, and the offset point at distance d(u) from the
 * base curve's point along the base's normal (its tangent turned +90 degrees). */
static void test_curves(void **state) {
  (void)state;
  for (int kind = 0; kind < VS_CURVE_KIND_COUNT; kind++)
    for (int off = 0; off < 3; off++) {
      const vs_curve c = curve_of(kind, off);
      vs_curve base = c;
      base.d0 = base.d2 = 0.0;
      for (int i = 0; i < 7; i++) {
        const double u = -0.6 + 0.2 * i, h = 1e-6;
        double p[2], d[2], pa[2], pb[2], b[2], bd[2];
        vs_curve_eval(&c, u, p, d);
        vs_curve_eval(&c, u - h, pa, NULL);
        vs_curve_eval(&c, u + h, pb, NULL);
        CHECK(d[0], (pb[0] - pa[0]) / (2 * h), 1e-7, 1e-8);
        CHECK(d[1], (pb[1] - pa[1]) / (2 * h), 1e-7, 1e-8);
        vs_curve_eval(&base, u, b, bd);
        const double s = hypot(bd[0], bd[1]), nx = -bd[1] / s, nz = bd[0] / s;
        const double w = b[0] - c.xc, dist = c.d0 + c.d2 * w * w;
        CHECK(p[0], b[0] + dist * nx, 0, 1e-15);
        CHECK(p[1], b[1] + dist * nz, 0, 1e-15);
      }
    }
  /* the base curves' definitions */
  double p[2];
  vs_curve c = curve_of(VS_CURVE_CIRCLE, 0);
  vs_curve_eval(&c, 0.3, p, NULL);
  CHECK(p[0], 0.1 + 0.4 * sin(0.3), 0, 1e-16);
  CHECK(p[1], -0.2 + 0.4 * cos(0.3), 0, 1e-16);
  c = curve_of(VS_CURVE_ELLIPSE, 0);
  vs_curve_eval(&c, 0.3, p, NULL);
  CHECK(p[0], 0.1 + 0.4 * sin(0.3), 0, 1e-16);
  CHECK(p[1], -0.2 + 0.25 * cos(0.3), 0, 1e-16);
  c = curve_of(VS_CURVE_PARABOLA, 0);
  vs_curve_eval(&c, 0.4, p, NULL); /* b below the vertex at u = a */
  CHECK(p[0], 0.5, 0, 1e-16);
  CHECK(p[1], -0.45, 0, 1e-16);
  c = curve_of(VS_CURVE_CATENARY, 0);
  vs_curve_eval(&c, 0.3, p, NULL);
  CHECK(p[1], -0.2 - 0.3 * (cosh(1.0) - 1.0), 0, 1e-15);
  /* a circle offset by d is the circle of radius a + d */
  c = curve_of(VS_CURVE_CIRCLE, 1);
  vs_curve_eval(&c, 0.3, p, NULL);
  CHECK(p[0], 0.1 + 0.43 * sin(0.3), 0, 1e-15);
  CHECK(p[1], -0.2 + 0.43 * cos(0.3), 0, 1e-15);
}

/* The reference arch's voussoirs: outlines sampled at closed-form points, the convex outline
 * of four corners and the extrados arc's mid-point, a turn of one voussoir's angle. */
static void test_arch_outlines(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  const double ri = 0.3, re = 0.324, E = 125.0 * PI / 180.0, dphi = E / 55;
  for (int i = 0; i < g->n_blocks; i++) {
    const vs_block *b = &g->blocks[i];
    const double p0 = -0.5 * E + i * dphi, p1 = p0 + dphi;
    assert_int_equal(b->n_edges, 4);
    CHECK(vs_edge_turn(&g->edges[b->edge0]), dphi, 1e-12, 0);
    CHECK(vs_edge_turn(&g->edges[b->edge0 + 1]), 0.0, 0, 0);
    double xz[2 * 16];
    assert_int_equal(vs_block_outline(g, i, 4, INFINITY, xz, 16), 8);
    for (int k = 0; k < 4; k++) {
      const double f = k / 3.0, pi = p0 + f * dphi, pe = p1 - f * dphi;
      CHECK(xz[2 * k], ri * sin(pi), 0, 1e-15);
      CHECK(xz[2 * k + 1], ri * cos(pi), 0, 1e-15);
      CHECK(xz[2 * (4 + k)], re * sin(pe), 0, 1e-15);
      CHECK(xz[2 * (4 + k) + 1], re * cos(pe), 0, 1e-15);
    }
    /* one point per degree of turn at least: a 2.27 degree voussoir gets 4 per arc */
    assert_int_equal(vs_block_outline(g, i, 2, PI / 180.0, NULL, 0), 8);
    int eo[VS_HULL_MAX];
    assert_int_equal(vs_block_hull(g, i, xz, eo), 5);
    const double ph[5] = {p0, p1, p1, 0.5 * (p0 + p1), p0}, rr[5] = {ri, ri, re, re, re};
    for (int k = 0; k < 5; k++) {
      CHECK(xz[2 * k], rr[k] * sin(ph[k]), 0, 1e-15);
      CHECK(xz[2 * k + 1], rr[k] * cos(ph[k]), 0, 1e-15);
    }
    assert_int_equal(eo[3], -1 - (b->edge0 + 2)); /* the mid-point of the extrados */
    /* the faces lie on joints i and i + 1 */
    assert_int_equal(g->edges[b->edge0 + 1].joint, i + 1);
    assert_int_equal(g->edges[b->edge0 + 3].joint, i);
  }
  vs_geometry_destroy(&g);
}

/* Exact properties of an annular sector ri..re over p0..p1 (closed forms), by Green's theorem
 * over its outline, for sectors small and large, near the origin and far from it. */
static void test_sector_section(void **state) {
  (void)state;
  const double cases[][4] = {{0.3, 0.324, -0.3, -0.25}, {1.0, 1.2, -1.5, 1.5}, {50.0, 50.5, 0.1, 0.1001},
                             {0.3, 0.6, 0.0, PI}};
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    const double ri = cases[k][0], re = cases[k][1], p0 = cases[k][2], p1 = cases[k][3];
    vs_edge e[4];
    vs_sector_edges(ri, re, p0, p1, 0, 1, e);
    vs_section s;
    vs_outline_section(e, 4, &s);
    const double A = 0.5 * (p1 - p0) * (re * re - ri * ri), h = 0.5 * (p1 - p0);
    const double rc = 2.0 / 3.0 * (pow(re, 3) - pow(ri, 3)) / (re * re - ri * ri) * sin(h) / h;
    const double J0 = (p1 - p0) * (pow(re, 4) - pow(ri, 4)) / 4.0;
    CHECK(s.area, A, 1e-13, 0);
    CHECK(s.cx, rc * sin(0.5 * (p0 + p1)), 0, 1e-14 * re);
    CHECK(s.cz, rc * cos(0.5 * (p0 + p1)), 0, 1e-14 * re);
    CHECK(s.j, J0 - A * rc * rc, 1e-8, 0);
  }
}

/* A rectangle w x h at (x0, z0), by four segments: A = w h, J = A (w^2 + h^2) / 12. */
static void test_rectangle_section(void **state) {
  (void)state;
  const double x0 = 2.0, z0 = -1.0, w = 0.3, h = 0.1;
  const double px[4] = {x0, x0 + w, x0 + w, x0}, pz[4] = {z0, z0, z0 + h, z0 + h};
  vs_edge e[4];
  for (int k = 0; k < 4; k++)
    e[k] = (vs_edge){.x0 = px[k], .z0 = pz[k], .x1 = px[(k + 1) % 4], .z1 = pz[(k + 1) % 4],
                     .u1 = 1.0, .joint = -1};
  vs_section s;
  vs_outline_section(e, 4, &s);
  CHECK(s.area, w * h, 1e-14, 0);
  CHECK(s.cx, x0 + 0.5 * w, 0, 1e-15);
  CHECK(s.cz, z0 + 0.5 * h, 0, 1e-15);
  CHECK(s.j, w * h * (w * w + h * h) / 12.0, 1e-12, 0);
}

/* A segment of an elliptical ring: the half-ellipse x = a sin u, z = b cos u from u0 to u1 and
 * its offset by t along the normal, closed by the normals at u0 and u1. Against a dense
 * quadrature of the region as the map (u, s) -> B(u) + s n(u), written here from the ellipse's
 * own formulas (Jacobian |dP/du x dP/ds|, 400 x 40 Gauss points). */
static void ellipse_point(double a, double b, double u, double s, double p[2], double *jac) {
  const double bx = a * sin(u), bz = b * cos(u), dx = a * cos(u), dz = -b * sin(u);
  const double ddx = -a * sin(u), ddz = -b * cos(u), q = hypot(dx, dz);
  const double nx = -dz / q, nz = dx / q;
  const double dq = (dx * ddx + dz * ddz) / q; /* d|B'|/du */
  const double dnx = -ddz / q + dz * dq / (q * q), dnz = ddx / q - dx * dq / (q * q);
  p[0] = bx + s * nx, p[1] = bz + s * nz;
  const double pux = dx + s * dnx, puz = dz + s * dnz; /* dP/du; dP/ds = n */
  *jac = fabs(pux * nz - puz * nx);
}

static void test_ellipse_ring_section(void **state) {
  (void)state;
  const double a = 0.6, b = 0.35, t = 0.05, u0 = -1.2, u1 = -0.7;
  const vs_curve in = {.kind = VS_CURVE_ELLIPSE, .a = a, .b = b};
  vs_curve out = in;
  out.d0 = t;
  vs_edge e[4] = {{.curved = 1, .c = in, .u0 = u0, .u1 = u1, .joint = -1},
                  {.u1 = 1.0, .joint = 1},
                  {.curved = 1, .c = out, .u0 = u1, .u1 = u0, .joint = -1},
                  {.u1 = 1.0, .joint = 0}};
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(vs_geometry_create(1, 2, &g, &err), VS_OK);
  double p[2];
  vs_curve_eval(&in, u1, p, NULL);
  e[1].x0 = p[0], e[1].z0 = p[1];
  vs_curve_eval(&out, u1, p, NULL);
  e[1].x1 = p[0], e[1].z1 = p[1];
  vs_curve_eval(&out, u0, p, NULL);
  e[3].x0 = p[0], e[3].z0 = p[1];
  vs_curve_eval(&in, u0, p, NULL);
  e[3].x1 = p[0], e[3].z1 = p[1];
  assert_int_equal(vs_geometry_set_outline(g, 0, 4, e, &err), VS_OK);
  vs_section s;
  vs_outline_section(g->edges, 4, &s);
  /* the dense quadrature: Gauss-Legendre 4 points on 100 x 10 panels */
  const double gx[4] = {-0.86113631159405258, -0.33998104358485626, 0.33998104358485626,
                        0.86113631159405258};
  const double gw[4] = {0.34785484513745386, 0.65214515486254614, 0.65214515486254614,
                        0.34785484513745386};
  double A = 0, Sx = 0, Sz = 0;
  for (int pass = 0; pass < 2; pass++) {
    double J = 0;
    for (int iu = 0; iu < 100; iu++)
      for (int is = 0; is < 10; is++)
        for (int i = 0; i < 4; i++)
          for (int j = 0; j < 4; j++) {
            const double du = (u1 - u0) / 100, ds = t / 10;
            const double u = u0 + du * (iu + 0.5 + 0.5 * gx[i]), sv = ds * (is + 0.5 + 0.5 * gx[j]);
            double q[2], jac;
            ellipse_point(a, b, u, sv, q, &jac);
            const double w = 0.25 * du * ds * gw[i] * gw[j] * jac;
            if (pass == 0) A += w, Sx += w * q[0], Sz += w * q[1];
            else J += w * ((q[0] - Sx / A) * (q[0] - Sx / A) + (q[1] - Sz / A) * (q[1] - Sz / A));
          }
    if (pass == 1) CHECK(s.j, J, 1e-10, 0);
  }
  CHECK(s.area, A, 1e-12, 0);
  CHECK(s.cx, Sx / A, 0, 1e-13);
  CHECK(s.cz, Sz / A, 0, 1e-13);
  /* a faceted outline would be off by far more: the polygon through 4 points an arc */
  double xz[2 * 8], poly = 0.0;
  assert_int_equal(vs_block_outline(g, 0, 4, INFINITY, xz, 8), 8);
  for (int k = 0; k < 8; k++)
    poly += 0.5 * (xz[2 * k] * xz[2 * ((k + 1) % 8) + 1] - xz[2 * ((k + 1) % 8)] * xz[2 * k + 1]);
  assert_true(fabs(poly - A) > 1e-4 * A);
  vs_geometry_destroy(&g);
}

/* An outline that does not close, an edge of no length, a block out of range: refused. */
static void test_outline_errors(void **state) {
  (void)state;
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(vs_geometry_create(1, 1, &g, &err), VS_OK);
  vs_edge e[3] = {{.x0 = 0, .z0 = 0, .x1 = 1, .z1 = 0, .joint = -1},
                  {.x0 = 1, .z0 = 0, .x1 = 0, .z1 = 1, .joint = -1},
                  {.x0 = 0, .z0 = 1, .x1 = 0, .z1 = 0.5, .joint = -1}};
  assert_int_equal(vs_geometry_set_outline(g, 0, 3, e, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "a closed loop"));
  e[2].z1 = 0.0;
  assert_int_equal(vs_geometry_set_outline(g, 1, 3, e, &err), VS_ERR_INVALID);
  e[1].x1 = 1.0, e[1].z1 = 0.0, e[2].x0 = 1.0, e[2].z0 = 0.0;
  assert_int_equal(vs_geometry_set_outline(g, 0, 3, e, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "a length"));
  e[1] = (vs_edge){.x0 = 1, .z0 = 0, .x1 = 0, .z1 = 1, .joint = -1};
  e[2] = (vs_edge){.x0 = 0, .z0 = 1, .x1 = 0, .z1 = 0, .joint = -1};
  assert_int_equal(vs_geometry_set_outline(g, 0, 3, e, &err), VS_OK);
  assert_int_equal(g->blocks[0].n_edges, 3);
  double xz[8];
  assert_int_equal(vs_block_hull(g, 0, xz, NULL), 3);
  vs_geometry_destroy(&g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_blocks_against_quadrature),
      cmocka_unit_test(test_arch_dimensions),
      cmocka_unit_test(test_joints),
      cmocka_unit_test(test_symmetry),
      cmocka_unit_test(test_create_empty),
      cmocka_unit_test(test_curves),
      cmocka_unit_test(test_arch_outlines),
      cmocka_unit_test(test_sector_section),
      cmocka_unit_test(test_rectangle_section),
      cmocka_unit_test(test_ellipse_ring_section),
      cmocka_unit_test(test_outline_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
