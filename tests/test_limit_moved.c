/* The limit analysis of a deformed configuration (vs_limit_analyse_moved, limit.h) against truths
 * that need no LP:
 *  - a rigid translation of the whole assembly (every block and both supports) changes nothing:
 *    the load factor, the least and greatest thrust, the thickness factor;
 *  - a rigid rotation by phi of the whole assembly is gravity turned by -phi: since the LP's
 *    admissibility is homogeneous in the loads, the rotated arch under a horizontal body force
 *    lambda' x weight collapses where tan(beta - phi) = lambda_t, beta = atan lambda' and
 *    lambda_t the unrotated arch's tilt factor, lambda' = tan(atan(lambda_t) + phi); without the
 *    tilt it stands iff |phi| <= atan(lambda_t) (the symmetric arch tilts alike both ways);
 *  - the motion of no block (q = 0) is the initial analysis. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/limit.h"

#define near(a, b, tol)                                                                        \
  do {                                                                                         \
    const double a_ = (a), b_ = (b);                                                           \
    if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.17g, %s = %.17g", #a, a_, #b, b_);         \
  } while (0)

/* The whole assembly of g moved by the rigid motion x -> R(phi) x + t: each block's centroid
 * displacement and rotation, each support's about its joint's centre. */
static void rigid(const vs_geometry *g, double phi, double tx, double tz, double *q, double qs[6]) {
  const double c = cos(phi), s = sin(phi);
  for (int i = 0; i < g->n_blocks; i++) {
    const double x = g->blocks[i].cx, z = g->blocks[i].cz;
    q[3 * i] = c * x - s * z + tx - x;
    q[3 * i + 1] = s * x + c * z + tz - z;
    q[3 * i + 2] = phi;
  }
  for (int r = 0; r < 2; r++) {
    const vs_joint_geom *j = &g->joints[vs_geometry_support_joint(g, r)];
    qs[3 * r] = c * j->px - s * j->pz + tx - j->px;
    qs[3 * r + 1] = s * j->px + c * j->pz + tz - j->pz;
    qs[3 * r + 2] = phi;
  }
}

typedef struct {
  vs_case c;
  vs_run_def d;
  vs_geometry *g;
  double *q;
} fixture;

static void setup(fixture *f, int kind) {
  vs_case_defaults(&f->c);
  f->c.kind = kind;
  f->c.value_N = 1.0;
  f->c.x_mm = 0.25 * vs_case_span_mm(&f->c);
  vs_case_to_def(&f->c, &f->d);
  vs_error err;
  vs_error_clear(&err);
  f->g = NULL;
  assert_int_equal(vs_test_arch(&f->c, &f->g, &err), VS_OK);
  f->q = calloc(3 * (size_t)f->g->n_blocks, sizeof *f->q);
  assert_non_null(f->q);
}

static void teardown(fixture *f) {
  free(f->q);
  vs_geometry_destroy(&f->g);
}

static void moved(fixture *f, double phi, double tx, double tz, vs_limit_analysis *a) {
  double qs[6];
  rigid(f->g, phi, tx, tz, f->q, qs);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse_moved(&f->d, f->g, f->q, qs, NULL, a, &err), VS_OK);
}

static void test_translation(void **state) {
  (void)state;
  fixture f;
  setup(&f, VS_LOAD_POINT);
  vs_limit_analysis a0, a1, a2;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&f.d, NULL, &a0, &err), VS_OK);
  moved(&f, 0.0, 0.0, 0.0, &a1);       /* no motion */
  moved(&f, 0.0, 0.037, -0.081, &a2);  /* 37 mm right, 81 mm down */
  const vs_limit_analysis *as[2] = {&a1, &a2};
  for (int i = 0; i < 2; i++) {
    const vs_limit_analysis *a = as[i];
    near(a->collapse.value, a0.collapse.value, 1e-7 * a0.collapse.value);
    near(a->thrust_min.value, a0.thrust_min.value, 1e-7 * a0.thrust_min.value);
    near(a->thrust_max.value, a0.thrust_max.value, 1e-7 * a0.thrust_max.value);
    near(a->thickness_factor, a0.thickness_factor, 1e-9);
    assert_int_equal(a->collapse.n_hinges, a0.collapse.n_hinges);
    for (int k = 0; k < f.g->n_joints; k++) assert_int_equal(a->collapse.hinge[k], a0.collapse.hinge[k]);
  }
  vs_limit_analysis_free(&a0);
  vs_limit_analysis_free(&a1);
  vs_limit_analysis_free(&a2);
  teardown(&f);
}

static void test_rotation_is_tilt(void **state) {
  (void)state;
  fixture f;
  setup(&f, VS_LOAD_TILT);
  vs_limit_analysis a0;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&f.d, NULL, &a0, &err), VS_OK);
  const double lt = a0.collapse.value;
  assert_true(lt > 0.1 && lt < 1.0);
  const double phis[4] = {0.05, -0.05, 0.2, -0.2};
  for (int i = 0; i < 4; i++) {
    vs_limit_analysis a;
    moved(&f, phis[i], 0.01, 0.02, &a);
    assert_int_equal(a.collapse.outcome, VS_LIMIT_OPTIMAL);
    near(a.collapse.value, tan(atan(lt) + phis[i]), 1e-6 * lt);
    vs_limit_analysis_free(&a);
  }
  /* standing under self-weight alone: up to atan(lt) either way */
  const double edge = atan(lt), phi2[4] = {0.99 * edge, -0.99 * edge, 1.01 * edge, -1.01 * edge};
  for (int i = 0; i < 4; i++) {
    vs_limit_analysis a;
    moved(&f, phi2[i], 0.0, 0.0, &a);
    assert_int_equal(a.thrust_min.outcome, i < 2 ? VS_LIMIT_OPTIMAL : VS_LIMIT_INFEASIBLE);
    /* the thickness factor crosses 1 there */
    assert_true(i < 2 ? a.thickness_factor < 1.0 : a.thickness_factor > 1.0);
    vs_limit_analysis_free(&a);
  }
  vs_limit_analysis_free(&a0);
  teardown(&f);
}

static void test_errors(void **state) {
  (void)state;
  fixture f;
  setup(&f, VS_LOAD_POINT);
  vs_limit_analysis a;
  vs_error err;
  vs_error_clear(&err);
  double qs[6] = {0};
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, NULL, qs, NULL, &a, &err), VS_ERR_INVALID);
  f.q[4] = NAN;
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, f.q, qs, NULL, &a, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "block 2"));
  teardown(&f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_translation),
      cmocka_unit_test(test_rotation_is_tilt),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
