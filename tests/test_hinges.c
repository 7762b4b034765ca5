/* Unit tests of the hinge tracker (include/voussoir/hinges.h) on synthetic joint states: the open
 * threshold, sides, spread hinges, A-E labels, migration, closing and reopening, errors.
 * Expected values follow docs/model.md#vocabulary (labels and modes), not the tracker's own
 * output. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "voussoir/hinges.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Helpers */

enum { NJ = 56 }; /* joints of the reference specimen */

#define OPEN_M 5e-5 /* threshold of the tests, m (the case default, 0.05 mm) */

/* All joints closed: both edges slightly compressed. */
static void all_closed(vs_joint_state *st, int n) {
  memset(st, 0, (size_t)n * sizeof *st);
  for (int k = 0; k < n; k++) st[k].gap_i = st[k].gap_e = -1e-6;
}

/* Open joint j (1-based) so that its hinge is on side sd: 'I' = the extrados gap opens. */
static void open_joint(vs_joint_state *st, int j, char sd) {
  vs_joint_state *s = &st[j - 1];
  s->gap_i = (sd == 'I') ? -1e-6 : 4.0 * OPEN_M;
  s->gap_e = (sd == 'I') ? 4.0 * OPEN_M : -1e-6;
}

static void open_range(vs_joint_state *st, int j0, int j1, char sd) {
  for (int j = j0; j <= j1; j++) open_joint(st, j, sd);
}

static vs_hinges *make(int migrate) {
  vs_hinge_opts o = {OPEN_M, migrate};
  vs_hinges *h = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_hinges_create(NJ, &o, &h, &err), VS_OK);
  assert_non_null(h);
  return h;
}

static void expect_name(const vs_hinge *hg, int onset, const char *want) {
  char buf[128];
  vs_hinge_name(hg, onset, buf, sizeof buf);
  if (strcmp(buf, want) != 0) fail_msg("hinge name \"%s\", expected \"%s\"", buf, want);
}

/* Onset of a joint that was closed (gap -1e-6 m) at update d0 and opened (gap 4 OPEN_M) at d1:
 * the tracker interpolates linearly where the opening crossed OPEN_M. */
static double crossing(double d0, double d1) {
  const double before = -1e-6, now = 4.0 * OPEN_M;
  return d0 + (OPEN_M - before) / (now - before) * (d1 - d0);
}

static void expect_onset(const vs_hinge *hg, double want) {
  if (fabs(hg->delta_onset - want) > 1e-15)
    fail_msg("delta_onset %.17g, expected %.17g", hg->delta_onset, want);
}

/* The hinge whose current joints start at j, or NULL. */
static const vs_hinge *at_joint(const vs_hinges *h, int j) {
  for (int i = 0; i < vs_hinges_count(h); i++)
    if (vs_hinges_get(h, i)->first == j) return vs_hinges_get(h, i);
  return NULL;
}

/* ---------------------------------------------------------------------------------------------
 * Creation errors */

static void expect_create_error(int n, double open, int migrate) {
  vs_hinge_opts o = {open, migrate};
  vs_hinges *h = (vs_hinges *)&o; /* must be reset to NULL */
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_hinges_create(n, &o, &h, &err), VS_ERR_INVALID);
  assert_null(h);
  assert_int_equal(err.status, VS_ERR_INVALID);
  assert_true(strlen(err.msg) > 0);
}

static void test_create_errors(void **state) {
  (void)state;
  expect_create_error(0, OPEN_M, 3);
  expect_create_error(-5, OPEN_M, 3);
  expect_create_error(NJ, 0.0, 3);
  expect_create_error(NJ, -OPEN_M, 3);
  expect_create_error(NJ, NAN, 3);
  expect_create_error(NJ, OPEN_M, -1);
  /* the smallest valid values are accepted */
  vs_hinge_opts o = {1e-300, 0};
  vs_hinges *h = NULL;
  assert_int_equal(vs_hinges_create(1, &o, &h, NULL), VS_OK);
  assert_non_null(h);
  assert_int_equal(vs_hinges_count(h), 0);
  assert_int_equal(vs_hinges_open_count(h), 0);
  assert_null(vs_hinges_get(h, 0));
  assert_null(vs_hinges_get(h, -1));
  vs_hinges_destroy(&h);
  assert_null(h);
  vs_hinges_destroy(&h); /* destroying NULL is allowed */
  vs_hinges_destroy(NULL);
}

/* ---------------------------------------------------------------------------------------------
 * One joint: threshold and side */

static void test_threshold(void **state) {
  (void)state;
  const vs_hinge_opts o = {OPEN_M, 3};
  const double below = OPEN_M * (1.0 - 1e-9), above = OPEN_M * (1.0 + 1e-9);
  vs_joint_state s;
  memset(&s, 0, sizeof s);
  /* extrados edge opening */
  s.gap_i = -1e-6;
  s.gap_e = below;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 0);
  s.gap_e = OPEN_M; /* "beyond" the threshold: exactly at it is still closed */
  assert_int_equal(vs_hinges_joint_side(&o, &s), 0);
  s.gap_e = above;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 'I');
  /* intrados edge opening */
  s.gap_e = -1e-6;
  s.gap_i = below;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 0);
  s.gap_i = above;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 'E');
  /* fully compressed, and a fully closed joint exactly at contact */
  s.gap_i = s.gap_e = -1e-4;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 0);
  s.gap_i = s.gap_e = 0.0;
  assert_int_equal(vs_hinges_joint_side(&o, &s), 0);

  /* the same threshold through the tracker */
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  all_closed(st, NJ);
  st[8].gap_e = below;
  assert_int_equal(vs_hinges_update(h, 0.0, st), 0);
  assert_int_equal(vs_hinges_count(h), 0);
  st[8].gap_e = above;
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 1);
  assert_int_equal(vs_hinges_count(h), 1);
  expect_name(vs_hinges_get(h, 0), 0, "9-I");
  vs_hinges_destroy(&h);
}

static void test_side(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  all_closed(st, NJ);
  open_joint(st, 9, 'I');  /* extrados opened: hinge at the intrados */
  open_joint(st, 56, 'E'); /* intrados opened at the right support: hinge at the extrados */
  assert_int_equal(vs_hinges_update(h, 0.0, st), 2);
  const vs_hinge *a = at_joint(h, 9), *b = at_joint(h, 56);
  assert_non_null(a);
  assert_non_null(b);
  assert_int_equal(a->side, 'I');
  assert_int_equal(b->side, 'E');
  assert_true(st[8].gap_e > st[8].gap_i);
  expect_name(a, 0, "9-I");
  expect_name(b, 0, "56-E");
  expect_name(b, 1, "56-E");
  vs_hinges_destroy(&h);
}

/* ---------------------------------------------------------------------------------------------
 * Spread hinges */

static void test_spread(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  all_closed(st, NJ);
  open_range(st, 44, 46, 'I');
  assert_int_equal(vs_hinges_update(h, 0.0, st), 1);
  assert_int_equal(vs_hinges_count(h), 1);
  const vs_hinge *hg = vs_hinges_get(h, 0);
  assert_int_equal(hg->first, 44);
  assert_int_equal(hg->last, 46);
  assert_int_equal(hg->onset_first, 44);
  assert_int_equal(hg->onset_last, 46);
  expect_name(hg, 0, "44-45-46-I");
  expect_name(hg, 1, "44-45-46-I");

  /* a small buffer truncates and stays terminated */
  char small[5];
  memset(small, 'x', sizeof small);
  vs_hinge_name(hg, 0, small, sizeof small);
  assert_true(memchr(small, '\0', sizeof small) != NULL);
  assert_true(strncmp(small, "44-45-46-I", strlen(small)) == 0);

  /* adjacent joints opened on opposite sides are two hinges */
  vs_hinges *h2 = make(3);
  all_closed(st, NJ);
  open_range(st, 20, 21, 'I');
  open_range(st, 22, 23, 'E');
  assert_int_equal(vs_hinges_update(h2, 0.0, st), 2);
  assert_int_equal(vs_hinges_count(h2), 2);
  expect_name(at_joint(h2, 20), 0, "20-21-I");
  expect_name(at_joint(h2, 22), 0, "22-23-E");

  /* the ends of the joint range: joints 1..3 and 54..56 */
  vs_hinges *h3 = make(3);
  all_closed(st, NJ);
  open_range(st, 1, 3, 'E');
  open_range(st, 54, 56, 'E');
  assert_int_equal(vs_hinges_update(h3, 0.0, st), 2);
  expect_name(at_joint(h3, 1), 0, "1-2-3-E");
  expect_name(at_joint(h3, 54), 0, "54-55-56-E");
  assert_int_equal(vs_hinges_open_count(h3), 2);

  vs_hinges_destroy(&h3);
  vs_hinges_destroy(&h2);
  vs_hinges_destroy(&h);
}

/* ---------------------------------------------------------------------------------------------
 * Labels */

static void test_labels_left_to_right(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  all_closed(st, NJ);
  /* appearance order: right support, left haunch, crown: labels must not follow it */
  open_joint(st, 56, 'E');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 1);
  assert_int_equal(vs_hinges_get(h, 0)->label, '?');
  open_range(st, 8, 10, 'I');
  assert_int_equal(vs_hinges_update(h, 2e-3, st), 1);
  assert_int_equal(vs_hinges_get(h, 0)->label, '?');
  assert_int_equal(vs_hinges_get(h, 1)->label, '?');
  open_joint(st, 30, 'E');
  assert_int_equal(vs_hinges_update(h, 3e-3, st), 1);
  assert_int_equal(vs_hinges_count(h), 3);
  assert_int_equal(at_joint(h, 8)->label, 'A');
  assert_int_equal(at_joint(h, 30)->label, 'B');
  assert_int_equal(at_joint(h, 56)->label, 'C');
  for (int i = 0; i < 3; i++) assert_int_equal(vs_hinges_get(h, i)->order, i + 1);
  assert_true(at_joint(h, 56)->delta_onset == 1e-3);
  expect_onset(at_joint(h, 8), crossing(1e-3, 2e-3));
  expect_onset(at_joint(h, 30), crossing(2e-3, 3e-3));

  /* 4th and 5th in order of appearance, wherever they are */
  open_joint(st, 1, 'E');
  assert_int_equal(vs_hinges_update(h, 4e-3, st), 1);
  assert_int_equal(at_joint(h, 1)->label, 'D');
  assert_int_equal(at_joint(h, 1)->order, 4);
  open_joint(st, 45, 'I');
  assert_int_equal(vs_hinges_update(h, 5e-3, st), 1);
  assert_int_equal(at_joint(h, 45)->label, 'E');
  assert_int_equal(at_joint(h, 45)->order, 5);
  /* the first three keep their labels */
  assert_int_equal(at_joint(h, 8)->label, 'A');
  assert_int_equal(at_joint(h, 30)->label, 'B');
  assert_int_equal(at_joint(h, 56)->label, 'C');
  assert_int_equal(vs_hinges_count(h), 5);
  assert_int_equal(vs_hinges_open_count(h), 5);
  vs_hinges_destroy(&h);
}

/* Modes as docs/model.md#vocabulary defines them: the pattern of A, B, C read left to right (not in
 * order of appearance), then the hinges at the collapse. */
static void test_modes(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  char p0[16];
  all_closed(st, NJ);
  /* right support first, then the left haunch, then the crown: I-E-E left to right */
  open_joint(st, 56, 'E');
  vs_hinges_update(h, 1e-3, st);
  vs_hinges_pattern_first(h, p0, sizeof p0);
  assert_string_equal(p0, ""); /* fewer than three */
  open_joint(st, 9, 'I');
  vs_hinges_update(h, 2e-3, st);
  open_joint(st, 30, 'E');
  vs_hinges_update(h, 3e-3, st);
  vs_hinges_pattern_first(h, p0, sizeof p0);
  assert_string_equal(p0, "I-E-E");
  vs_hinges_destroy(&h);

  const vs_hinge four[4] = {{.side = 'E'}, {.side = 'I'}, {.side = 'E'}, {.side = 'I'}};
  char pu[16];
  vs_hinges_side_pattern(four, 4, pu, sizeof pu);
  assert_string_equal(pu, "E-I-E-I");
  vs_hinges_side_pattern(four, 4, pu, 4); /* cut after a '-', still NUL-ended */
  assert_string_equal(pu, "E-");
  /* eight sides fill 16 bytes exactly (15 and the NUL) and are whole; of nine, the first seven
   * and the '-' that says the pattern goes on */
  vs_hinge nine[9];
  for (int i = 0; i < 9; i++) nine[i] = (vs_hinge){.side = i % 2 ? 'I' : 'E'};
  vs_hinges_side_pattern(nine, 8, pu, sizeof pu);
  assert_string_equal(pu, "E-I-E-I-E-I-E-I");
  vs_hinges_side_pattern(nine, 9, pu, sizeof pu);
  assert_string_equal(pu, "E-I-E-I-E-I-E-");
  assert_string_equal(vs_hinges_mode("I-E-E", "E-I-E-E"), "I");
  assert_string_equal(vs_hinges_mode("I-E-E", "E-I-E-I"), "II");
  assert_string_equal(vs_hinges_mode("I-E-I", "E-I-E-I"), "III");
  assert_string_equal(vs_hinges_mode("I-E-I", "E-I-E-I-E"), "III");
  assert_null(vs_hinges_mode("I-E-I", "E-I-E-E"));
  assert_null(vs_hinges_mode("I-E-E", "E-I-E-I-E"));
  assert_null(vs_hinges_mode("E-I-E", "E-I-E-I"));
  assert_null(vs_hinges_mode("", ""));
}

/* Two hinges before the collapse (pinned springers): named A, B left to right when the run
 * says so (vs_hinges_name_first); a third, forming later, is C whatever its place, and the
 * names already given do not change. */
static void test_name_first_two(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  all_closed(st, NJ);
  open_joint(st, 47, 'I');
  vs_hinges_update(h, 1e-3, st);
  open_joint(st, 25, 'E');
  vs_hinges_update(h, 2e-3, st);
  assert_int_equal(at_joint(h, 47)->label, '?');
  vs_hinges_name_first(h, 2);
  assert_int_equal(at_joint(h, 25)->label, 'A');
  assert_int_equal(at_joint(h, 47)->label, 'B');
  open_joint(st, 10, 'E'); /* left of both: still C, by order of appearance */
  assert_int_equal(vs_hinges_update(h, 3e-3, st), 1);
  assert_int_equal(at_joint(h, 10)->label, 'C');
  assert_int_equal(at_joint(h, 25)->label, 'A');
  assert_int_equal(at_joint(h, 47)->label, 'B');
  vs_hinges_name_first(h, 0); /* no effect */
  assert_int_equal(at_joint(h, 10)->label, 'C');
  vs_hinges_destroy(&h);
}

/* Labels of the first three hinges left to right, 4th = D: holds whatever the grouping. */
static void expect_abc_then_d(const vs_hinges *h) {
  const vs_hinge *first[3] = {NULL, NULL, NULL}, *fourth = NULL;
  for (int i = 0; i < vs_hinges_count(h); i++) {
    const vs_hinge *hg = vs_hinges_get(h, i);
    if (hg->order <= 3) first[hg->order - 1] = hg;
    if (hg->order == 4) fourth = hg;
  }
  for (int i = 0; i < 3; i++) {
    assert_non_null(first[i]);
    int rank = 0; /* hinges of the first three to the left of this one */
    for (int j = 0; j < 3; j++) rank += first[j]->onset_first < first[i]->onset_first;
    assert_int_equal(first[i]->label, 'A' + rank);
  }
  if (fourth != NULL) assert_int_equal(fourth->label, 'D');
}

static void test_same_update(void **state) {
  (void)state;
  vs_joint_state st[NJ];
  /* three at once: right to left in the array does not matter */
  vs_hinges *h = make(3);
  all_closed(st, NJ);
  open_joint(st, 50, 'E');
  open_joint(st, 25, 'E');
  open_joint(st, 5, 'I');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 3);
  assert_int_equal(vs_hinges_count(h), 3);
  assert_int_equal(at_joint(h, 5)->label, 'A');
  assert_int_equal(at_joint(h, 25)->label, 'B');
  assert_int_equal(at_joint(h, 50)->label, 'C');
  for (int i = 0; i < 3; i++) assert_true(vs_hinges_get(h, i)->delta_onset == 1e-3);
  vs_hinges_destroy(&h);

  /* two exist, then two more form together: from '?' straight to A, B, C and D */
  h = make(3);
  all_closed(st, NJ);
  open_joint(st, 30, 'E');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 1);
  open_joint(st, 12, 'I');
  assert_int_equal(vs_hinges_update(h, 2e-3, st), 1);
  open_joint(st, 5, 'E');
  open_joint(st, 50, 'I');
  assert_int_equal(vs_hinges_update(h, 3e-3, st), 2);
  assert_int_equal(vs_hinges_count(h), 4);
  expect_onset(at_joint(h, 5), crossing(2e-3, 3e-3));
  expect_onset(at_joint(h, 50), crossing(2e-3, 3e-3));
  expect_abc_then_d(h);
  int n_d = 0;
  for (int i = 0; i < 4; i++) n_d += vs_hinges_get(h, i)->label == 'D';
  assert_int_equal(n_d, 1);
  vs_hinges_destroy(&h);
}

/* ---------------------------------------------------------------------------------------------
 * Migration */

/* Three hinges A (left haunch, I), B (crown, E), C (right support, E) at delta = 1 mm. */
static vs_hinges *three(int migrate, vs_joint_state *st, int a) {
  vs_hinges *h = make(migrate);
  all_closed(st, NJ);
  open_joint(st, a, 'I');
  open_joint(st, 30, 'E');
  open_joint(st, 56, 'E');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 3);
  assert_int_equal(at_joint(h, a)->label, 'A');
  return h;
}

static void expect_is_a(const vs_hinges *h, int j, int onset_j) {
  const vs_hinge *hg = at_joint(h, j);
  assert_non_null(hg);
  assert_int_equal(hg->label, 'A');
  assert_int_equal(hg->order, 1);
  assert_int_equal(hg->open, 1);
  assert_int_equal(hg->onset_first, onset_j);
  assert_int_equal(hg->onset_last, onset_j);
  assert_true(hg->delta_onset == 1e-3);
  assert_true(isnan(hg->delta_closed));
}

static void test_migrate_one_per_update(void **state) {
  (void)state;
  vs_joint_state st[NJ];
  vs_hinges *h = three(1, st, 9);
  /* A walks up toward the crown, one joint per update: joint k closes, k + 1 opens */
  for (int k = 9; k < 20; k++) {
    all_closed(st, NJ);
    open_joint(st, k + 1, 'I');
    open_joint(st, 30, 'E');
    open_joint(st, 56, 'E');
    assert_int_equal(vs_hinges_update(h, 1e-3 * (k - 7), st), 0);
    assert_int_equal(vs_hinges_count(h), 3);
    assert_int_equal(vs_hinges_open_count(h), 3);
    expect_is_a(h, k + 1, 9);
  }
  expect_name(at_joint(h, 20), 0, "20-I");
  expect_name(at_joint(h, 20), 1, "9-I");
  vs_hinges_destroy(&h);

  /* a spread hinge slides and widens: 8-9-10 -> 9-10-11 -> 10-11-12-13 */
  h = make(0);
  all_closed(st, NJ);
  open_range(st, 8, 10, 'I');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 1);
  all_closed(st, NJ);
  open_range(st, 9, 11, 'I');
  assert_int_equal(vs_hinges_update(h, 2e-3, st), 0);
  all_closed(st, NJ);
  open_range(st, 10, 13, 'I');
  assert_int_equal(vs_hinges_update(h, 3e-3, st), 0);
  assert_int_equal(vs_hinges_count(h), 1);
  expect_name(vs_hinges_get(h, 0), 0, "10-11-12-13-I");
  expect_name(vs_hinges_get(h, 0), 1, "8-9-10-I");
  assert_true(vs_hinges_get(h, 0)->delta_onset == 1e-3);
  vs_hinges_destroy(&h);
}

/* A at joint 20 jumps by `jump` joints (either way) in one update with the given migrate. */
static const vs_hinges *jump_a(vs_hinges **hp, vs_joint_state *st, int migrate, int jump) {
  *hp = three(migrate, st, 20);
  all_closed(st, NJ);
  open_joint(st, 20 + jump, 'I');
  open_joint(st, 30, 'E');
  open_joint(st, 56, 'E');
  vs_hinges_update(*hp, 2e-3, st);
  return *hp;
}

static void test_migrate_within(void **state) {
  (void)state;
  vs_joint_state st[NJ];
  vs_hinges *h = NULL;
  /* a jump of exactly `migrate` joints, and less, is still the same hinge */
  const int cases[][2] = {{3, 3}, {3, -3}, {3, 2}, {3, -1}, {1, 1}, {1, -1}, {5, 5}};
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    jump_a(&h, st, cases[c][0], cases[c][1]);
    assert_int_equal(vs_hinges_count(h), 3);
    expect_is_a(h, 20 + cases[c][1], 20);
    vs_hinges_destroy(&h);
  }
}

static void expect_new_hinge(int migrate, int jump) {
  vs_joint_state st[NJ];
  vs_hinges *h = NULL;
  jump_a(&h, st, migrate, jump);
  const int count = vs_hinges_count(h);
  if (count != 4) {
    vs_hinges_destroy(&h); /* before failing, so that the sanitizer build reports no leak */
    fail_msg("migrate = %d, A jumps from joint 20 to %d: %d hinges, expected 4 (a new one; "
             "the old A closed)",
             migrate, 20 + jump, count);
  }
  const vs_hinge *a = vs_hinges_get(h, 0), *d = vs_hinges_get(h, 3);
  assert_int_equal(a->label, 'A');
  assert_int_equal(a->open, 0);
  assert_true(a->delta_closed == 2e-3);
  assert_int_equal(a->first, 20);
  assert_int_equal(d->label, 'D');
  assert_int_equal(d->first, 20 + jump);
  assert_int_equal(d->onset_first, 20 + jump);
  expect_onset(d, crossing(1e-3, 2e-3));
  assert_int_equal(vs_hinges_open_count(h), 3);
  vs_hinges_destroy(&h);
}

/* A jump farther than `migrate` joints makes a new hinge. */
static void test_migrate_farther_far(void **state) {
  (void)state;
  expect_new_hinge(3, 6);
  expect_new_hinge(3, -6);
  expect_new_hinge(1, 5);
  expect_new_hinge(0, 2);
}

/* The boundary: a jump of migrate + 1 joints is farther than migrate. */
static void test_migrate_farther_by_one(void **state) {
  (void)state;
  expect_new_hinge(3, 4);
  expect_new_hinge(3, -4);
  expect_new_hinge(1, 2);
  expect_new_hinge(0, 1);
}

/* ---------------------------------------------------------------------------------------------
 * Closing and reopening */

static void test_close_reopen(void **state) {
  (void)state;
  vs_joint_state st[NJ];
  vs_hinges *h = three(3, st, 9);
  assert_int_equal(vs_hinges_open_count(h), 3);
  /* C closes at 2 mm */
  all_closed(st, NJ);
  open_joint(st, 9, 'I');
  open_joint(st, 30, 'E');
  assert_int_equal(vs_hinges_update(h, 2e-3, st), 0);
  const vs_hinge *c = at_joint(h, 56);
  assert_non_null(c);
  assert_int_equal(c->open, 0);
  assert_true(c->delta_closed == 2e-3);
  assert_int_equal(c->label, 'C');
  assert_int_equal(vs_hinges_count(h), 3);
  assert_int_equal(vs_hinges_open_count(h), 2);
  /* stays closed: delta_closed is when it closed, not the latest update */
  assert_int_equal(vs_hinges_update(h, 2.5e-3, st), 0);
  assert_true(c->delta_closed == 2e-3);
  /* reopens at the same place at 3 mm: the same hinge, same onset */
  open_joint(st, 56, 'E');
  assert_int_equal(vs_hinges_update(h, 3e-3, st), 0);
  c = at_joint(h, 56);
  assert_int_equal(vs_hinges_count(h), 3);
  assert_int_equal(c->label, 'C');
  assert_int_equal(c->open, 1);
  assert_true(isnan(c->delta_closed));
  assert_true(c->delta_onset == 1e-3);
  assert_int_equal(c->order, 3);
  assert_int_equal(vs_hinges_open_count(h), 3);
  /* everything closes */
  all_closed(st, NJ);
  assert_int_equal(vs_hinges_update(h, 4e-3, st), 0);
  assert_int_equal(vs_hinges_open_count(h), 0);
  assert_int_equal(vs_hinges_count(h), 3);
  for (int i = 0; i < 3; i++) assert_true(vs_hinges_get(h, i)->delta_closed == 4e-3);
  vs_hinges_destroy(&h);

  /* a joint that closes on one side and opens on the other is a different hinge */
  h = make(3);
  all_closed(st, NJ);
  open_joint(st, 56, 'E');
  assert_int_equal(vs_hinges_update(h, 1e-3, st), 1);
  open_joint(st, 56, 'I');
  assert_int_equal(vs_hinges_update(h, 2e-3, st), 1);
  assert_int_equal(vs_hinges_count(h), 2);
  assert_int_equal(vs_hinges_open_count(h), 1);
  assert_int_equal(vs_hinges_get(h, 0)->open, 0);
  assert_int_equal(vs_hinges_get(h, 1)->side, 'I');
  vs_hinges_destroy(&h);
}

/* An opening growing linearly with delta, gap_e = c (delta - d0), crosses the threshold at
 * d0 + open / c exactly; linear interpolation between two updates must recover it. */
static void test_onset_interpolated(void **state) {
  (void)state;
  vs_hinges *h = make(3);
  vs_joint_state st[NJ];
  const double c = 0.1, d0 = 0.7e-3;
  for (int u = 0; u <= 2; u++) {
    const double delta = u * 1e-3;
    all_closed(st, NJ);
    st[19].gap_e = c * (delta - d0);
    vs_hinges_update(h, delta, st);
  }
  assert_int_equal(vs_hinges_count(h), 1);
  expect_onset(vs_hinges_get(h, 0), d0 + OPEN_M / c);
  vs_hinges_destroy(&h);
}

/* docs/model.md#vocabulary: after Z come a to z, then # for every later hinge (never '[' or other
 * characters past 'Z'). 65 separate hinges open one per update, left to right. */
static void test_labels_past_z(void **state) {
  (void)state;
  enum { N = 131, H = 65 };
  vs_hinge_opts o = {OPEN_M, 0};
  vs_hinges *h = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_hinges_create(N, &o, &h, &err), VS_OK);
  vs_joint_state st[N];
  all_closed(st, N);
  assert_int_equal(vs_hinges_update(h, 0.0, st), 0);
  for (int k = 0; k < H; k++) {
    open_joint(st, 2 * k + 1, 'I');
    assert_int_equal(vs_hinges_update(h, 1e-3 * (k + 1), st), 1);
  }
  assert_int_equal(vs_hinges_count(h), H);
  for (int i = 0; i < H; i++) {
    const vs_hinge *hg = vs_hinges_get(h, i);
    const char want = i < 26 ? (char)('A' + i) : i < 52 ? (char)('a' + i - 26) : '#';
    if (hg->label != want)
      fail_msg("hinge %d (joint %d): label '%c', expected '%c'", i, hg->first, hg->label, want);
  }
  assert_int_equal(vs_hinges_label(-1), '?');
  vs_hinges_destroy(&h);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_create_errors),
      cmocka_unit_test(test_name_first_two),
      cmocka_unit_test(test_onset_interpolated),
      cmocka_unit_test(test_threshold),
      cmocka_unit_test(test_side),
      cmocka_unit_test(test_spread),
      cmocka_unit_test(test_labels_left_to_right),
      cmocka_unit_test(test_modes),
      cmocka_unit_test(test_same_update),
      cmocka_unit_test(test_migrate_one_per_update),
      cmocka_unit_test(test_migrate_within),
      cmocka_unit_test(test_migrate_farther_far),
      cmocka_unit_test(test_migrate_farther_by_one),
      cmocka_unit_test(test_close_reopen),
      cmocka_unit_test(test_labels_past_z),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
