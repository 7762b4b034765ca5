/* vs_model_set_branches (model.h) on a cohesive joint: the left springing of the reference arch
 * pressed onto its support (its first voussoir moved into it along the joint's normal) with a
 * mortar of cohesion c. Its shear limit is c b t + mu N (an intact joint, no slip yet: the
 * mortar law's, docs/model.md "Mortar joints"), written out here from N, the joint's size and
 * the law's constants. Put on its sliding branch it must slide at that limit; put back on its
 * sticking branch it must stick just inside it. The dry limit mu N, which the branches used to
 * take for every joint, lies inside the cohesive one: a joint put "past" mu N still sticks. The
 * dry joint is checked the same way against mu N. */
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
#include "voussoir/joint.h"
#include "voussoir/model.h"

typedef struct {
  vs_geometry *g;
  vs_model *m;
  double *q;
  vs_joint_state *st;
  signed char *branch;
  double N, limit; /* the springing's normal force and its shear limit written out, N */
} fixture;

/* The reference arch (k_n = 3 N/mm^3, k_s / k_n = 0.5, mu = 0.7), the springing joint given
 * cohesion c (Pa; 0: dry) and pressed 10 um onto its support. */
static void setup(fixture *fx, double c) {
  vs_case cs;
  vs_case_defaults(&cs);
  vs_error err;
  vs_error_clear(&err);
  if (vs_test_arch(&cs, &fx->g, &err) != VS_OK) fail_msg("geometry: %s", err.msg);
  const double kn = cs.kn_N_mm3 * 1e9;
  vs_joint_law law = {.kn = kn, .ks = cs.ks_ratio * kn, .mu = cs.friction};
  if (vs_model_create(fx->g, &law, 0.0, &fx->m, &err) != VS_OK) fail_msg("model: %s", err.msg);
  if (c > 0.0) {
    law.c = c;
    law.gc = 10.0 * c * c / (2.0 * law.ks) + 1.0; /* well beyond the snap-back bound */
    if (vs_model_set_joint_law(fx->m, 0, &law, &err) != VS_OK) fail_msg("law: %s", err.msg);
  }
  const int n = vs_model_size(fx->m);
  fx->q = calloc((size_t)n, sizeof *fx->q);
  fx->st = calloc((size_t)fx->g->n_joints, sizeof *fx->st);
  fx->branch = calloc((size_t)fx->g->n_joints, 1);
  assert_non_null(fx->q);
  assert_non_null(fx->st);
  assert_non_null(fx->branch);
  const vs_joint_geom *j = &fx->g->joints[0];
  assert_int_equal(j->a, VS_SUPPORT_LEFT);
  assert_int_equal(j->b, 0);
  const double p = 1e-5; /* the first voussoir moved against the normal: into the support */
  fx->q[0] = -p * j->nx;
  fx->q[1] = -p * j->nz;
  fx->N = kn * j->depth * j->length * p; /* a uniform penetration p over b t */
  fx->limit = c * j->depth * j->length + cs.friction * fx->N;
  vs_model_joint_states(fx->m, fx->q, 0.0, fx->st);
  assert_true(fabs(fx->st[0].N - fx->N) <= 1e-9 * fx->N);
  assert_false(fx->st[0].sliding);
}

static void teardown(fixture *fx) {
  free(fx->q);
  free(fx->st);
  free(fx->branch);
  vs_model_destroy(&fx->m);
  vs_geometry_destroy(&fx->g);
}

/* Slide the springing each way, then stick it again: at the limit, then just inside it. */
static void check_branches(double c) {
  fixture fx;
  setup(&fx, c);
  for (int sense = -1; sense <= 1; sense += 2) {
    fx.branch[0] = (signed char)(sense > 0 ? VS_BRANCH_SLIDE_POS : VS_BRANCH_SLIDE_NEG);
    assert_int_equal(vs_model_set_branches(fx.m, fx.q, 0.0, fx.branch), 1);
    vs_model_joint_states(fx.m, fx.q, 0.0, fx.st);
    assert_true(fx.st[0].sliding);
    assert_true(sense * fx.st[0].T > 0.0);
    /* at the limit (a cohesion softening by the hair it slid: 1e-6 of it at most) */
    assert_true(fabs(fabs(fx.st[0].T) - fx.limit) <= 1e-6 * fx.limit);
    fx.branch[0] = VS_BRANCH_STICK;
    assert_int_equal(vs_model_set_branches(fx.m, fx.q, 0.0, fx.branch), 1);
    vs_model_joint_states(fx.m, fx.q, 0.0, fx.st);
    assert_false(fx.st[0].sliding);
    assert_true(fabs(fx.st[0].T) < fx.limit);
    assert_true(fabs(fx.st[0].T) >= (1.0 - 1e-6) * fx.limit);
    /* sticking already: left alone */
    assert_int_equal(vs_model_set_branches(fx.m, fx.q, 0.0, fx.branch), 0);
  }
  teardown(&fx);
}

static void test_dry_joint(void **state) {
  (void)state;
  check_branches(0.0);
}

/* c = 10 kPa: c b t = 28.8 N against mu N = 60.5 N. */
static void test_cohesive_joint(void **state) {
  (void)state;
  check_branches(1e4);
}

/* What the branches did before: the trial put past mu N alone (the commit's margin, and a hair of
 * the joint's length besides) stays inside the cohesive limit, so the joint sticks with about mu
 * N where the branch wanted it sliding at c b t + mu N. */
static void test_dry_limit_misses_cohesion(void **state) {
  (void)state;
  fixture fx;
  setup(&fx, 1e4);
  const vs_joint_geom *j = &fx.g->joints[0];
  const double kst = 0.5 * 3e9 * j->depth * j->length;
  const double mu_n = 0.7 * fx.N;
  double *slips = calloc((size_t)fx.g->n_joints, sizeof *slips);
  assert_non_null(slips);
  /* the old sliding trial: past mu N by the commit's margin (1e-9 of it) and 1e-9 of the
   * joint's length, as slip_p = slip - over */
  slips[0] = fx.st[0].slip - (mu_n / kst * (1.0 + 1e-9) + 1e-9 * j->length);
  vs_model_set_slips(fx.m, slips);
  vs_model_joint_states(fx.m, fx.q, 0.0, fx.st);
  assert_false(fx.st[0].sliding); /* on the wrong side of its limit */
  assert_true(fabs(fx.st[0].T) < 0.7 * fx.limit);
  free(slips);
  teardown(&fx);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dry_joint),
      cmocka_unit_test(test_cohesive_joint),
      cmocka_unit_test(test_dry_limit_misses_cohesion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
