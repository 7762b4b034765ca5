/* The mechanism a motion turns about (src/model/mechanism.h) against rigid four-bar kinematics
 * solved in the test: the reference arch cut by four hinges at chosen joints and edges into
 * three links between the fixed supports, the links' angular velocities from the closure of the
 * chain (the pivots' velocities agree), each block turning with its link. Which joints turn,
 * which way, and whether a hinge opens or closes follow from the pivots' geometry, here from the
 * velocity of each hinge's other edge relative to the body across it (not from the sign rule
 * the code uses); elastic noise on the other joints, a spread and a migrating hinge. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mechanism.h"
#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/model.h"

#define OPEN_M 5e-5 /* the hinge threshold of the tests, m */

typedef struct {
  vs_case c;
  vs_geometry *g;
  vs_model *m;
  int nb, nj;
} fixture;

static void fixture_init(fixture *fx) {
  vs_case_defaults(&fx->c);
  vs_error err;
  vs_error_clear(&err);
  if (vs_test_arch(&fx->c, &fx->g, &err) != VS_OK) fail_msg("geometry: %s", err.msg);
  const double kn = fx->c.kn_N_mm3 * 1e9;
  const vs_joint_law law = {.kn = kn, .ks = fx->c.ks_ratio * kn, .mu = fx->c.friction};
  if (vs_model_create(fx->g, &law, 0.0, &fx->m, &err) != VS_OK) fail_msg("model: %s", err.msg);
  fx->nb = fx->g->n_blocks;
  fx->nj = fx->g->n_joints;
}

static void fixture_free(fixture *fx) {
  vs_model_destroy(&fx->m);
  vs_geometry_destroy(&fx->g);
}

/* The edge point of joint j (1-based): 'I' its intrados end, 'E' its extrados end. */
static void edge_point(const vs_geometry *g, int j, char side, double p[2]) {
  const vs_joint_geom *jg = &g->joints[j - 1];
  double sx, sz;
  vs_joint_tangent(jg, &sx, &sz);
  const double h = (side == 'I' ? -0.5 : 0.5) * jg->length;
  p[0] = jg->px + h * sx;
  p[1] = jg->pz + h * sz;
}

/* Counter-clockwise rate w about the origin of offset r: w (-r_z, r_x). */
static void cross(double w, const double r[2], double out[2]) {
  out[0] = -w * r[1];
  out[1] = w * r[0];
}

/* Four hinges at joints j[0] < .. < j[3], turning about the edges side[0..3]: the three links'
 * angular velocities (link 1 at 1 rad/s about its pivot on the left, link 3 about its pivot on
 * the right, link 2 from the pivots' velocities agreeing: a 2 x 2 solve). */
static void four_bar(const vs_geometry *g, const int j[4], const char side[4], double om[3]) {
  double P[4][2];
  for (int i = 0; i < 4; i++) edge_point(g, j[i], side[i], P[i]);
  om[0] = 1.0;
  double v2[2], r12[2] = {P[1][0] - P[0][0], P[1][1] - P[0][1]};
  cross(om[0], r12, v2);
  /* v(P3) = om3 x (P3 - P4) = v2 + om2 x (P3 - P2): unknowns om2, om3 */
  const double a[2] = {P[2][0] - P[3][0], P[2][1] - P[3][1]};
  const double b[2] = {P[2][0] - P[1][0], P[2][1] - P[1][1]};
  /* om3 (-a_z, a_x) - om2 (-b_z, b_x) = v2 */
  const double A[2][2] = {{b[1], -a[1]}, {-b[0], a[0]}}; /* columns om2, om3 */
  const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
  assert_true(fabs(det) > 1e-12);
  om[1] = (v2[0] * A[1][1] - A[0][1] * v2[1]) / det;
  om[2] = (A[0][0] * v2[1] - A[1][0] * v2[0]) / det;
}

/* The blocks' angular velocities in v (3 per block; translations 0, unused): blocks between
 * joints j[i] and j[i+1] turn with link i + 1, those outside the hinges stay fixed. */
static void block_rates(const fixture *fx, const int j[4], const double om[3], double *v) {
  memset(v, 0, (size_t)vs_model_size(fx->m) * sizeof *v);
  for (int i = 0; i < 3; i++) /* joint k lies between blocks k - 2 and k - 1 (0-based) */
    for (int b = j[i] - 1; b <= j[i + 1] - 2; b++) v[3 * b + 2] = om[i];
}

/* The opening rate of joint j's edge opposite its pivot (side): the velocity of body b's point
 * there relative to body a's along the joint's normal (a to b), both bodies agreeing at the
 * pivot; > 0 the edge opens. */
static double opening_rate(const vs_geometry *g, int j, char side, double wa, double wb) {
  double P[2], Q[2], dv[2];
  edge_point(g, j, side, P);
  edge_point(g, j, side == 'I' ? 'E' : 'I', Q);
  const double r[2] = {Q[0] - P[0], Q[1] - P[1]};
  cross(wb - wa, r, dv);
  return dv[0] * g->joints[j - 1].nx + dv[1] * g->joints[j - 1].nz;
}

static void all_closed(vs_joint_state *st, int n) {
  memset(st, 0, (size_t)n * sizeof *st);
  for (int k = 0; k < n; k++) st[k].gap_i = st[k].gap_e = -1e-6;
}

/* Joint j open about its side's edge: the other edge 4 thresholds open. */
static void open_about(vs_joint_state *st, int j, char side) {
  st[j - 1].gap_i = side == 'I' ? -1e-6 : 4.0 * OPEN_M;
  st[j - 1].gap_e = side == 'I' ? 4.0 * OPEN_M : -1e-6;
}

static const vs_hinge_opts OPTS = {.open = OPEN_M, .migrate = 3};

/* The angular velocity of the body on either side of joint k: link rates, 0 outside. */
static double link_of_block(const int j[4], const double om[3], int b) {
  for (int i = 0; i < 3; i++)
    if (b >= j[i] - 1 && b <= j[i + 1] - 2) return om[i];
  return 0.0;
}

static void check_four_bar(const int j[4], const char side[4]) {
  fixture fx;
  fixture_init(&fx);
  double om[3];
  four_bar(fx.g, j, side, om);
  double *v = calloc((size_t)vs_model_size(fx.m), sizeof *v);
  double *w = calloc((size_t)fx.nj, sizeof *w);
  vs_joint_state *st = calloc((size_t)fx.nj, sizeof *st);
  vs_active_hinge *a = calloc((size_t)fx.nj, sizeof *a);
  assert_non_null(v);
  assert_non_null(w);
  assert_non_null(st);
  assert_non_null(a);
  block_rates(&fx, j, om, v);
  vs_mechanism_joint_rates(fx.m, v, 0.0, 0.0, w);
  /* a rigid chain between fixed supports: the relative rotations add up to none */
  double sum = 0.0;
  for (int k = 0; k < fx.nj; k++) sum += w[k];
  assert_true(fabs(sum) < 1e-12);

  /* (1) every hinge open about its pivot: the four, their sides; closing where the other edge
   * closes */
  all_closed(st, fx.nj);
  for (int i = 0; i < 4; i++) open_about(st, j[i], side[i]);
  int n = vs_mechanism_active(fx.nj, w, st, &OPTS, a);
  assert_int_equal(n, 4);
  for (int i = 0; i < 4; i++) {
    assert_int_equal(a[i].first, j[i]);
    assert_int_equal(a[i].last, j[i]);
    assert_int_equal(a[i].side, side[i]);
    assert_true(a[i].open);
    const double wa = link_of_block(j, om, j[i] - 2), wb = link_of_block(j, om, j[i] - 1);
    assert_int_equal(a[i].closing, opening_rate(fx.g, j[i], side[i], wa, wb) < 0.0);
  }

  /* (2) no joint open yet (a bonded arch): the hinges turning at a tenth of the fastest at
   * least, each about the edge that lets its other edge open */
  all_closed(st, fx.nj);
  n = vs_mechanism_active(fx.nj, w, st, &OPTS, a);
  double fastest = 0.0;
  for (int i = 0; i < 4; i++) fastest = fmax(fastest, fabs(w[j[i] - 1]));
  int m = 0;
  for (int i = 0; i < 4; i++) {
    if (fabs(w[j[i] - 1]) < 0.1 * fastest) continue;
    assert_true(m < n);
    assert_int_equal(a[m].first, j[i]);
    const double wa = link_of_block(j, om, j[i] - 2), wb = link_of_block(j, om, j[i] - 1);
    const char want = opening_rate(fx.g, j[i], 'I', wa, wb) > 0.0 ? 'I' : 'E';
    assert_int_equal(a[m].side, want);
    assert_false(a[m].open);
    assert_false(a[m].closing);
    m++;
  }
  assert_int_equal(n, m);

  /* (3) the closed joints turning elastically, alternately either way, at up to 5 % of the
   * fastest hinge (above the slowest hinge's rate in mode I): ignored */
  for (int k = 0; k < fx.nj; k++)
    if (w[k] == 0.0) w[k] = 0.05 * fastest * ((k % 3) - 1.0);
  all_closed(st, fx.nj);
  for (int i = 0; i < 4; i++) open_about(st, j[i], side[i]);
  n = vs_mechanism_active(fx.nj, w, st, &OPTS, a);
  assert_int_equal(n, 4); /* (a neighbour turning the hinge's way spreads it) */
  for (int i = 0; i < 4; i++) {
    assert_true(a[i].first <= j[i] && a[i].last >= j[i] && a[i].last - a[i].first <= 2);
    assert_int_equal(a[i].side, side[i]);
  }

  free(v);
  free(w);
  free(st);
  free(a);
  fixture_free(&fx);
}

/* The dry arch's mode I collapse (E-I-E-E: D 1-E, A 9-I, B 27-E, C 56-E) and mode III's
 * (E-I-E-I), and a bonded springing turning about its intrados (I-I-E-I). */
static void test_four_bar_mode_i(void **state) {
  (void)state;
  check_four_bar((const int[4]){1, 9, 27, 56}, (const char[4]){'E', 'I', 'E', 'E'});
}

static void test_four_bar_mode_iii(void **state) {
  (void)state;
  check_four_bar((const int[4]){1, 11, 28, 45}, (const char[4]){'E', 'I', 'E', 'I'});
}

static void test_four_bar_springing_intrados(void **state) {
  (void)state;
  check_four_bar((const int[4]){5, 12, 33, 48}, (const char[4]){'I', 'I', 'E', 'I'});
}

/* Mode I's four-bar: the right springing's hinge C (56-E) closes as the arch falls in (its
 * intrados gap shrinks), as the dry arch's collapse shows; A, B, D open. */
static void test_mode_i_closing_c(void **state) {
  (void)state;
  fixture fx;
  fixture_init(&fx);
  const int j[4] = {1, 9, 27, 56};
  const char side[4] = {'E', 'I', 'E', 'E'};
  double om[3];
  four_bar(fx.g, j, side, om);
  /* the settling support lets the crown fall: the link over the crown turns so that A opens
   * (om[0] sense chosen so); take the sense in which hinge A (9-I) opens */
  double wa = link_of_block(j, om, 7), wb = link_of_block(j, om, 8);
  const double s = opening_rate(fx.g, 9, 'I', wa, wb) > 0.0 ? 1.0 : -1.0;
  for (int i = 0; i < 3; i++) om[i] *= s;
  int closing[4];
  for (int i = 0; i < 4; i++) {
    wa = link_of_block(j, om, j[i] - 2);
    wb = link_of_block(j, om, j[i] - 1);
    closing[i] = opening_rate(fx.g, j[i], side[i], wa, wb) < 0.0;
  }
  assert_int_equal(closing[0], 0);
  assert_int_equal(closing[1], 0);
  assert_int_equal(closing[2], 0);
  assert_int_equal(closing[3], 1);
  fixture_free(&fx);
}

/* A hinge spread over joints 9-10 (its rate shared) is one hinge; a hinge migrating from 9
 * (closing) to 11 (opening) on the same side is one hinge of their net rate. */
static void test_spread_and_migrating(void **state) {
  (void)state;
  enum { N = 56 };
  double w[N] = {0};
  vs_joint_state st[N];
  vs_active_hinge a[N];
  w[0] = 0.5;
  w[8] = -0.6;
  w[9] = -0.4;
  w[28] = 0.9;
  w[46] = -0.4;
  all_closed(st, N);
  open_about(st, 1, 'E');
  open_about(st, 9, 'I');
  open_about(st, 10, 'I');
  open_about(st, 29, 'E');
  open_about(st, 47, 'I');
  int n = vs_mechanism_active(N, w, st, &OPTS, a);
  assert_int_equal(n, 4);
  assert_int_equal(a[1].first, 9);
  assert_int_equal(a[1].last, 10);
  assert_true(fabs(a[1].rate - -1.0) < 1e-15);
  assert_true(fabs(a[1].share - 1.0) < 1e-15);
  assert_true(fabs(a[2].share - 0.9) < 1e-15);
  /* migrating: 9 closing (+0.2 on an I hinge), 11 opening (-1.0), joint 10 still */
  w[8] = 0.2;
  w[9] = 0.0;
  w[10] = -1.0;
  open_about(st, 11, 'I');
  st[9].gap_e = -1e-6;
  n = vs_mechanism_active(N, w, st, &OPTS, a);
  assert_int_equal(n, 4);
  assert_int_equal(a[1].first, 9);
  assert_int_equal(a[1].last, 11);
  assert_int_equal(a[1].side, 'I');
  assert_true(fabs(a[1].rate - -0.8) < 1e-15);
  assert_false(a[1].closing);
  /* beyond hinges.migrate joints apart they stay two: 9 closing, 13 opening */
  w[10] = 0.0;
  w[12] = -1.0;
  open_about(st, 13, 'I');
  n = vs_mechanism_active(N, w, st, &OPTS, a);
  assert_int_equal(n, 5);
  assert_int_equal(a[1].first, 9);
  assert_true(a[1].closing);
  assert_int_equal(a[2].first, 13);
  /* nothing turns: no mechanism */
  memset(w, 0, sizeof w);
  assert_int_equal(vs_mechanism_active(N, w, st, &OPTS, a), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_four_bar_mode_i),
      cmocka_unit_test(test_four_bar_mode_iii),
      cmocka_unit_test(test_four_bar_springing_intrados),
      cmocka_unit_test(test_mode_i_closing_c),
      cmocka_unit_test(test_spread_and_migrating),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
