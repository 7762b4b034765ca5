/* Slip on the path of the reference arch, through the run's public API, against statics the
 * test does itself: from the support reactions at the equilibria of a run whose friction is
 * never reached (mu = 0.7), the springing joint's shear ratio |T| / N in the joint's own frame;
 * where that ratio reaches a lower friction coefficient, a run with it must slide there, and
 * the path is the same up to it (friction does not enter a joint that sticks). Above every
 * ratio of the path a friction coefficient changes nothing at all. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/run.h"

/* |T| / N at a springing joint from the force R = (Fx, Fz) its support exerts on the arch: the
 * joint's normal n (from body a to body b) and its tangent s = n turned +90 degrees, both turned
 * by the joint's mean rotation, half the voussoir's (the support does not turn). On the
 * voussoir the joint's force is N n - T s when the voussoir is body b (the left support), and
 * the opposite when it is body a (the right one). */
static double springing_ratio(const vs_joint_geom *j, double theta_voussoir, const double R[2]) {
  const double c = cos(0.5 * theta_voussoir), sn = sin(0.5 * theta_voussoir);
  const double n[2] = {c * j->nx - sn * j->nz, sn * j->nx + c * j->nz};
  const double s[2] = {-n[1], n[0]};
  const double sign = j->b >= 0 ? 1.0 : -1.0; /* the voussoir is b (left) or a (right) */
  const double N = sign * (R[0] * n[0] + R[1] * n[1]);
  const double T = -sign * (R[0] * s[0] + R[1] * s[1]);
  return fabs(T) / N;
}

enum { MAX_POINTS = 4096 };

/* The quasi-static equilibria of a run: delta and the ratio at the left and right springings. */
typedef struct {
  int n;
  double delta[MAX_POINTS], left[MAX_POINTS], right[MAX_POINTS];
} ratio_track;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  ratio_track *tr = user;
  if (s->phase != VS_PHASE_QUASISTATIC || tr->n >= MAX_POINTS) return 0;
  const vs_geometry *g = vs_run_geometry(run);
  const int nb = g->n_blocks, nj = g->n_joints;
  tr->delta[tr->n] = s->delta;
  tr->left[tr->n] = springing_ratio(&g->joints[0], s->q[2], s->reactions);
  tr->right[tr->n] = springing_ratio(&g->joints[nj - 1], s->q[3 * (nb - 1) + 2], s->reactions + 3);
  tr->n++;
  return 0;
}

/* The reference case at (alpha, k_n, mu), small increments so that the ratio is well sampled,
 * no fall after the collapse. */
static void reference(vs_case *c, double alpha, double kn, double mu) {
  vs_case_defaults(c);
  c->alpha_deg = alpha;
  c->kn_N_mm3 = kn;
  c->friction = mu;
  c->step_mm = 0.1;
  c->step_max_mm = 0.25;
  c->fall_s = 0.0;
}

static vs_run *run(const vs_case *c, ratio_track *tr, vs_status *st, vs_error *err) {
  vs_run *r = NULL;
  vs_error_clear(err);
  if (vs_case_validate(c, err) != VS_OK) fail_msg("case: %s", err->msg);
  assert_int_equal(vs_run_create(c, &r, err), VS_OK);
  if (tr != NULL) tr->n = 0;
  *st = vs_run_execute(r, tr != NULL ? on_sample : NULL, NULL, tr, err);
  return r;
}

/* The first delta at which the ratio (left: 1, right: 0) reaches mu, interpolated linearly
 * between the equilibria on either side; NaN if it never does. */
static double first_crossing(const ratio_track *tr, int left, double mu) {
  const double *r = left ? tr->left : tr->right;
  for (int i = 1; i < tr->n; i++)
    if (r[i - 1] < mu && r[i] >= mu)
      return tr->delta[i - 1] +
             (mu - r[i - 1]) / (r[i] - r[i - 1]) * (tr->delta[i] - tr->delta[i - 1]);
  return NAN;
}

/* Below the largest ratio of the path the springing slides where the ratio reaches mu: the run
 * follows the path to there (the same equilibria as with mu = 0.7 before it) and its arch
 * departs there, at the limit point of the onset of slip (within the bracket, 0.001 mm, and
 * the interpolation between equilibria 0.25 mm apart). Before the fix this run stopped with
 * "Newton failed ... not a limit point". Settlement, k_n = 3: the left springing (joint 1);
 * spreading, k_n = 48: the right one (joint 56). */
static void slides_where_ratio_reaches(double alpha, double kn, double mu, int left) {
  vs_case c;
  ratio_track *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_status st;
  vs_error err;
  reference(&c, alpha, kn, 0.7);
  vs_run *r = run(&c, tr, &st, &err);
  if (st != VS_OK) fail_msg("mu = 0.7: %s", err.msg);
  const double d_star = first_crossing(tr, left, mu);
  print_message("alpha %g, k_n %g: |T|/N at the %s springing reaches %g at %.4f mm (mu = 0.7 "
                "collapses at %.4f mm)\n",
                alpha, kn, left ? "left" : "right", mu, d_star * 1e3,
                vs_run_collapse(r)->delta * 1e3);
  assert_true(isfinite(d_star) && d_star < vs_run_collapse(r)->delta);
  vs_run_destroy(&r);
  reference(&c, alpha, kn, mu);
  r = run(&c, NULL, &st, &err);
  if (st != VS_OK) fail_msg("mu = %g: %s", mu, err.msg);
  const vs_collapse_record *col = vs_run_collapse(r);
  if (!col->found) fail_msg("mu = %g: no collapse", mu);
  print_message("  mu = %g: collapse departs at %.4f mm\n", mu, col->delta * 1e3);
  if (!(fabs(col->delta - d_star) <= 0.002e-3))
    fail_msg("mu = %g: the collapse departs at %.6f mm, the springing reaches the Coulomb limit at "
             "%.6f mm", mu, col->delta * 1e3, d_star * 1e3);
  vs_run_destroy(&r);
  free(tr);
}

static void test_settlement_slides_at_left_springing(void **s) {
  (void)s;
  slides_where_ratio_reaches(0.0, 3.0, 0.2, 1);
}

static void test_spreading_slides_at_right_springing(void **s) {
  (void)s;
  slides_where_ratio_reaches(90.0, 48.0, 0.2, 0);
}

/* Friction above every ratio of the path (and of its snaps) does not enter the run: mu = 0.4
 * and mu = 0.7 give the same collapse, bit for bit, and the same hinges. */
static void test_friction_above_every_ratio(void **s) {
  (void)s;
  vs_case c;
  ratio_track *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_status st;
  vs_error err;
  reference(&c, 0.0, 3.0, 0.7);
  vs_run *a = run(&c, tr, &st, &err);
  assert_int_equal(st, VS_OK);
  double worst = 0.0;
  for (int i = 0; i < tr->n; i++) worst = fmax(worst, fmax(tr->left[i], tr->right[i]));
  print_message("largest |T|/N at a springing on the path: %.4f\n", worst);
  assert_true(worst < 0.4);
  reference(&c, 0.0, 3.0, 0.4);
  vs_run *b = run(&c, NULL, &st, &err);
  assert_int_equal(st, VS_OK);
  const vs_collapse_record *ca = vs_run_collapse(a), *cb = vs_run_collapse(b);
  assert_true(ca->found && cb->found);
  assert_memory_equal(&ca->delta, &cb->delta, sizeof ca->delta);
  assert_int_equal(ca->n_hinges, cb->n_hinges);
  for (int i = 0; i < ca->n_hinges; i++) {
    assert_int_equal(ca->hinges[i].first, cb->hinges[i].first);
    assert_int_equal(ca->hinges[i].side, cb->hinges[i].side);
  }
  vs_run_destroy(&a);
  vs_run_destroy(&b);
  free(tr);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_settlement_slides_at_left_springing),
      cmocka_unit_test(test_spreading_slides_at_right_springing),
      cmocka_unit_test(test_friction_above_every_ratio),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
