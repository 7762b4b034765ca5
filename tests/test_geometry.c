/* Tests of the arch builder (geometry.h): block mass, centroid and inertia against Gauss
 * quadrature of the annular sectors done here, total weight, span and rise, joint placement and
 * orientation, and mirror symmetry about the crown. SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>

#include "check.h"
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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_blocks_against_quadrature),
      cmocka_unit_test(test_arch_dimensions),
      cmocka_unit_test(test_joints),
      cmocka_unit_test(test_symmetry),
      cmocka_unit_test(test_create_empty),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
