#define _POSIX_C_SOURCE 200809L
/* The limit analysis of a deformed configuration (vs_limit_analyse_moved, limit.h) against truths
 * that need no LP:
 *  - a rigid translation of the whole assembly (every block and both supports) changes nothing:
 *    the load factor, the least and greatest thrust, the thickness factor;
 *  - a rigid rotation by phi of the whole assembly is gravity turned by -phi: since the LP's
 *    admissibility is homogeneous in the loads, the rotated arch under a horizontal body force
 *    lambda' x weight collapses where tan(beta - phi) = lambda_t, beta = atan lambda' and
 *    lambda_t the unrotated arch's tilt factor, lambda' = tan(atan(lambda_t) + phi); without the
 *    tilt it stands iff |phi| <= atan(lambda_t) (the symmetric arch tilts alike both ways);
 *  - the motion of no block (q = 0) is the initial analysis;
 *  - a joint open at one end (gap) carries force only where it is open by at most the hinges'
 *    threshold: the admissible part of the face found by hand from the affine opening, the thrust
 *    line kept inside it, the least thrust up and the greatest down (a constraint added);
 *  - the arch held on its path (analysis.type = limit, hold_mm; vs_run_limit_held): near zero
 *    hold it is the initial analysis; under settlement, on stiff joints, its thickness factor
 *    grows with the hold toward 1 at the collapse displacement delta_u of the same arch's
 *    support run, and its load factor (a point load at quarter span) is below the initial one;
 *    the report names what moved the support there (alpha, left_alpha, the paths in time). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/limit.h"
#include "voussoir/report.h"
#include "voussoir/run.h"

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
  assert_int_equal(vs_limit_analyse_moved(&f->d, f->g, f->q, qs, NULL, NULL, a, &err), VS_OK);
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
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, NULL, qs, NULL, NULL, &a, &err), VS_ERR_INVALID);
  f.q[4] = NAN;
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, f.q, qs, NULL, NULL, &a, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "block 2"));
  teardown(&f);
}

/* Joint 1 (the left springing) open at its extrados by 2 x open, penetrating by open at its
 * intrados: the opening is <= open on [0, 2/3] of the face. */
static void test_open_joint(void **state) {
  (void)state;
  fixture f;
  setup(&f, VS_LOAD_POINT);
  const int nj = f.g->n_joints;
  double *gap = calloc(2 * (size_t)nj, sizeof *gap), qs[6] = {0};
  assert_non_null(gap);
  const double open = f.d.hinges.open;
  gap[0] = -open, gap[1] = 2.0 * open;
  vs_limit_analysis a0, a;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, f.q, qs, NULL, NULL, &a0, &err), VS_OK);
  assert_int_equal(vs_limit_analyse_moved(&f.d, f.g, f.q, qs, gap, NULL, &a, &err), VS_OK);
  /* the initial greatest thrust's line touches 1-E; now it cannot */
  near(a0.thrust_max.eta[0], 1.0, 1e-6);
  assert_true(a.thrust_min.eta[0] <= 2.0 / 3.0 + 1e-9);
  assert_true(a.thrust_max.eta[0] <= 2.0 / 3.0 + 1e-9);
  assert_true(a.thrust_max.touch[0] != 'E');
  assert_true(a.thrust_min.value >= a0.thrust_min.value - 1e-9);
  assert_true(a.thrust_max.value <= a0.thrust_max.value + 1e-9);
  assert_true(a.thrust_max.value < a0.thrust_max.value - 1e-3); /* it did bind */
  assert_true(a.thickness_factor >= a0.thickness_factor);
  vs_limit_analysis_free(&a0);
  vs_limit_analysis_free(&a);
  free(gap);
  teardown(&f);
}

/* A run of the reference case at k_n (N/mm^3) with the extra assignments. */
static vs_run *run_case(double kn, const char *const *set, int n) {
  vs_case c;
  vs_case_defaults(&c);
  c.kn_N_mm3 = kn;
  vs_error err;
  vs_error_clear(&err);
  for (int i = 0; i < n; i++) assert_int_equal(vs_case_set(&c, set[i], &err), VS_OK);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_run *r = NULL;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  assert_int_equal(vs_run_execute(r, NULL, NULL, NULL, &err), VS_OK);
  return r;
}

/* The held arch's analysis at hold_mm (a quarter-span point load of 1 N). */
static void held(double kn, double hold_mm, double *thickness, double *lambda) {
  char h[64], x[64];
  snprintf(h, sizeof h, "analysis.hold_mm=%.10g", hold_mm);
  snprintf(x, sizeof x, "load.x_mm=%.10g", 0.25 * 2.0 * 300.0 * sin(62.5 * 3.14159265358979323846 / 180.0));
  const char *set[] = {"analysis.type=limit", h, "load.kind=point", x};
  vs_run *r = run_case(kn, set, 4);
  vs_status st = VS_ERR_INTERNAL;
  const vs_limit_analysis *a = vs_run_limit_held(r, &st, NULL);
  assert_non_null(a);
  assert_int_equal(st, VS_OK);
  *thickness = a->thickness_factor;
  *lambda = a->collapse.value;
  vs_run_destroy(&r);
}

static void test_held_on_the_path(void **state) {
  (void)state;
  const double kn = 1000.0;
  /* near zero hold: the initial analysis (the self-weight state's rotations are ~1e-6) */
  fixture f;
  setup(&f, VS_LOAD_POINT);
  vs_limit_analysis a0;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&f.d, NULL, &a0, &err), VS_OK);
  double t, lam;
  held(kn, 1e-3, &t, &lam);
  near(t, a0.thickness_factor, 1e-3 * a0.thickness_factor);
  near(lam, a0.collapse.value, 1e-3 * a0.collapse.value);
  vs_limit_analysis_free(&a0);
  teardown(&f);
  /* the support run's collapse displacement */
  vs_run *r = run_case(kn, NULL, 0);
  const vs_collapse_record *col = vs_run_collapse(r);
  assert_true(col->found);
  const double du = col->delta / 1e-3; /* mm */
  vs_run_destroy(&r);
  /* the thickness factor grows toward 1, the load factor falls */
  const double frac[5] = {0.2, 0.5, 0.8, 0.95, 0.998};
  double t_prev = t;
  const double l_prev = lam;
  for (int i = 0; i < 5; i++) {
    held(kn, frac[i] * du, &t, &lam);
    print_message("hold %.4g mm of delta_u %.4g: thickness factor %.6g, load factor %.6g\n",
                  frac[i] * du, du, t, lam);
    assert_true(t > t_prev);
    assert_true(lam < l_prev); /* below the initial one (not monotone: past mid-way the
                                  quarter-span load also holds back the settlement's mechanism) */
    assert_true(lam > 0.0);
    assert_true(t < 1.0);
    t_prev = t;
  }
  assert_true(t > 0.97); /* within the hinges' threshold's cut (docs/model.md) */
}

/* The report's "held" line names what moved the support to the hold: its directions, or the
 * paths in time when the case gives them (alpha is then not the motion). */
static void held_line(const char *const *set, int n, char *line, size_t size) {
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_case_set(&c, "analysis.type=limit", &err), VS_OK);
  assert_int_equal(vs_case_set(&c, "analysis.hold_mm=1", &err), VS_OK);
  for (int i = 0; i < n; i++)
    if (vs_case_set(&c, set[i], &err) != VS_OK) fail_msg("%s: %s", set[i], err.msg);
  vs_run_def d;
  vs_case_to_def(&c, &d);
  vs_limit_analysis a;
  assert_int_equal(vs_limit_analyse(&d, NULL, &a, &err), VS_OK);
  char *text = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&text, &len);
  assert_non_null(f);
  vs_report_limit_text(f, &c, &a, VS_OK, NULL, "x.ini");
  fclose(f);
  const char *h = strstr(text, "\nheld ");
  assert_non_null(h);
  snprintf(line, size, "%.*s", (int)strcspn(h + 1, "\n"), h + 1);
  free(text);
  vs_limit_analysis_free(&a);
}

static void test_held_line(void **state) {
  (void)state;
  char line[512];
  const char *alpha[] = {"support.alpha_deg=30"};
  held_line(alpha, 1, line, sizeof line);
  assert_non_null(strstr(line, "(alpha = 30 deg)"));
  const char *path[] = {"support.right_path=0:0:0,100:0:4"};
  held_line(path, 1, line, sizeof line);
  print_message("%s\n", line);
  assert_non_null(strstr(line, "(support.right_path)"));
  assert_null(strstr(line, "alpha"));
  const char *both[] = {"support.right_path=0:0:0,100:0:4", "support.left_path=0:0:0,100:1:0"};
  held_line(both, 2, line, sizeof line);
  assert_non_null(strstr(line, "(support.left_path and support.right_path)"));
  const char *left[] = {"support.rate_mm_s=0", "support.left_rate_mm_s=0.04",
                        "support.left_alpha_deg=90"};
  held_line(left, 3, line, sizeof line);
  assert_non_null(strstr(line, "(left_alpha = 90 deg)"));
}

/* The report names a pier's joints as the run's pier events do: on the reference arch on 100 mm
 * piers 150 mm wide (4 courses), tilt opens the right pier's top course joint (the joints' last,
 * right pier course 4) at both ends: "pier2-course4-open"; the ring's joints keep their numbers. */
static void test_pier_names(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  const char *set[] = {"analysis.type=limit", "piers.height_mm=100", "piers.width_mm=150",
                       "load.kind=tilt"};
  for (int i = 0; i < 4; i++) assert_int_equal(vs_case_set(&c, set[i], &err), VS_OK);
  vs_run_def d;
  vs_case_to_def(&c, &d);
  vs_limit_analysis a;
  assert_int_equal(vs_limit_analyse(&d, NULL, &a, &err), VS_OK);
  const int nj = a.collapse.n_joints;
  assert_int_equal(nj, c.voussoirs + 1 + 2 * 4);
  assert_int_equal(a.collapse.hinge[nj - 1], 'O');
  char *text = NULL;
  size_t size = 0;
  FILE *f = open_memstream(&text, &size);
  assert_non_null(f);
  vs_report_limit_json(f, &c, &a, VS_OK, NULL, "x.ini");
  fclose(f);
  assert_non_null(strstr(text, "\"pier2-course4-open\""));
  char ring_last[32]; /* no joint beyond the ring by number */
  snprintf(ring_last, sizeof ring_last, "\"%d-", c.voussoirs + 2);
  assert_null(strstr(text, ring_last));
  free(text);
  vs_limit_analysis_free(&a);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_translation),
      cmocka_unit_test(test_rotation_is_tilt),
      cmocka_unit_test(test_errors),
      cmocka_unit_test(test_open_joint),
      cmocka_unit_test(test_held_on_the_path),
      cmocka_unit_test(test_held_line),
      cmocka_unit_test(test_pier_names),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
