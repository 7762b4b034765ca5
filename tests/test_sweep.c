/* Lists, sweeps and calibration. Lists against their definition; the sweep's table against the
 * runs it ran (order, a failing run with its cause, exit status); calibration as the inverse of
 * the forward map: the k_n it finds for the collapse of a run at a known k_n is that k_n. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "voussoir/run.h"
#include "voussoir/sweep.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static void expect_list(const char *text, const double *want, int n) {
  double *v = NULL;
  int m = 0;
  vs_error err;
  vs_error_clear(&err);
  if (vs_parse_list("--x", text, &v, &m, &err) != VS_OK) fail_msg("%s: %s", text, err.msg);
  if (m != n) fail_msg("%s: %d values, expected %d", text, m, n);
  for (int i = 0; i < n; i++)
    if (fabs(v[i] - want[i]) > 1e-12 * fmax(1.0, fabs(want[i]))) fail_msg("%s[%d] = %g", text, i, v[i]);
  free(v);
}

static void expect_bad_list(const char *text) {
  double *v = (double *)&text;
  int m = 7;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_parse_list("--alpha", text, &v, &m, &err), VS_ERR_USAGE);
  assert_null(v);
  assert_int_equal(m, 0);
  assert_non_null(strstr(err.msg, "--alpha"));
}

static void test_lists(void **s) {
  (void)s;
  expect_list("0:90:45", (double[]){0, 45, 90}, 3);
  expect_list("0:45:5,60,75,90", (double[]){0, 5, 10, 15, 20, 25, 30, 35, 40, 45, 60, 75, 90}, 13);
  expect_list("3", (double[]){3}, 1);
  expect_list("0.1:0.3:0.1", (double[]){0.1, 0.2, 0.3}, 3); /* the end on the grid, despite rounding */
  expect_list("0:1:0.3", (double[]){0, 0.3, 0.6, 0.9}, 4);
  expect_list("-5,5", (double[]){-5, 5}, 2);
  expect_bad_list("");
  expect_bad_list("0:x:5");
  expect_bad_list("0:90");
  expect_bad_list("0:90:0");
  expect_bad_list("90:0:5");
  expect_bad_list("1,,2");
  expect_bad_list("nan");
  expect_bad_list("3mm");
  double *v = NULL;
  vs_error err;
  assert_int_equal(vs_logspace(0.1, 100.0, 4, &v, &err), VS_OK);
  for (int i = 0; i < 4; i++) assert_true(fabs(v[i] - 0.1 * pow(10.0, i)) < 1e-12 * v[i]);
  free(v);
  assert_int_equal(vs_logspace(0.0, 1.0, 4, &v, &err), VS_ERR_USAGE);
}

static char g_dir[64];

static int sh(const char *cmd) {
  int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  char *b = calloc(1, 1 << 16);
  size_t n = fread(b, 1, (1 << 16) - 1, f);
  b[n] = '\0';
  fclose(f);
  return b;
}

/* A sweep with a failing value: every run in the table, in order, the failure with its cause. */
static void test_sweep_table(void **s) {
  (void)s;
  char cmd[1024], path[256];
  snprintf(cmd, sizeof cmd,
           "%s sweep %s --alpha 0,90 --vary arch.thickness_mm=4,24 --first-limit -j 2 -q -o %s/sw "
           ">/dev/null 2>&1",
           VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 1); /* some runs failed */
  snprintf(path, sizeof path, "%s/sw/summary.csv", g_dir);
  char *t = slurp(path);
  assert_non_null(t);
  assert_true(strncmp(t, "run,support.alpha_deg,arch.thickness_mm,status,", 47) == 0);
  int rows = 0, failed = 0;
  for (char *line = strtok(strchr(t, '\n') + 1, "\n"); line; line = strtok(NULL, "\n")) {
    rows++;
    assert_int_equal(atoi(line), rows); /* in run order */
    const double alpha = strtod(strchr(line, ',') + 1, NULL);
    const double thick = strtod(strchr(strchr(line, ',') + 1, ',') + 1, NULL);
    assert_true(alpha == (rows <= 2 ? 0.0 : 90.0)); /* the last axis varies fastest */
    assert_true(thick == (rows % 2 ? 4.0 : 24.0));
    if (strstr(line, ",failed,") != NULL) {
      failed++;
      assert_non_null(strstr(line, "cannot stand"));
      assert_true(thick == 4.0);
    } else {
      assert_non_null(strstr(line, ",limit_point,"));
    }
  }
  assert_int_equal(rows, 4);
  assert_int_equal(failed, 2);
  free(t);
  for (int i = 1; i <= 4; i++) {
    snprintf(path, sizeof path, "%s/sw/run_%04d.json", g_dir, i);
    assert_int_equal(access(path, F_OK), 0);
  }
}

/* Bad lists and bad values stop the sweep before it creates anything. */
static void test_sweep_bad_input(void **s) {
  (void)s;
  char cmd[1024], path[256];
  snprintf(cmd, sizeof cmd, "%s sweep %s --alpha 0:x:5 -o %s/bad1 2>/dev/null", VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 2);
  snprintf(cmd, sizeof cmd, "%s sweep %s --kn -1,3 -o %s/bad2 2>/dev/null", VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 2);
  snprintf(cmd, sizeof cmd, "%s sweep %s --vary joints.nokey=1 -o %s/bad3 2>/dev/null", VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 2);
  for (int i = 1; i <= 3; i++) {
    snprintf(path, sizeof path, "%s/bad%d", g_dir, i);
    assert_int_not_equal(access(path, F_OK), 0);
  }
}

/* Calibration inverts the forward map: the collapse dz/L of a run at k_n = 10 N/mm^3, given as
 * the target, gives back k_n = 10 (within what the tolerance on dz/L allows). */
static void test_calibrate_inverts(void **s) {
  (void)s;
  vs_case c;
  vs_case_defaults(&c);
  c.kn_N_mm3 = 10.0;
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  assert_int_equal(vs_run_execute(r, NULL, NULL, NULL, &err), VS_OK);
  assert_true(vs_run_collapse(r)->found);
  const double dz = 100.0 * vs_run_collapse(r)->delta * 1e3 / vs_case_span_mm(&c);
  vs_run_destroy(&r);
  char cmd[1024], path[256];
  snprintf(path, sizeof path, "%s/cal.txt", g_dir);
  snprintf(cmd, sizeof cmd, "%s calibrate %s --target-dz-pct %.10f --kn-min 2 --kn-max 50 --tol-pct 1e-4 -q > %s",
           VS_BINARY, REFERENCE, dz, path);
  assert_int_equal(sh(cmd), 0);
  char *t = slurp(path);
  assert_non_null(t);
  const char *k = strstr(t, "\nk_n = ");
  assert_non_null(k);
  const double kn = strtod(k + 7, NULL);
  if (fabs(kn - 10.0) > 0.02) fail_msg("calibrated k_n = %g for the collapse of k_n = 10:\n%s", kn, t);
  assert_non_null(strstr(t, "sensitivity"));
  free(t);
  /* out of reach */
  snprintf(cmd, sizeof cmd, "%s calibrate %s --target-dz-pct 60 --kn-min 1 --kn-max 10 -q > %s",
           VS_BINARY, REFERENCE, path);
  assert_int_equal(sh(cmd), 1);
  t = slurp(path);
  assert_non_null(strstr(t, "no k_n in [1, 10]"));
  free(t);
}

static int setup(void **s) {
  (void)s;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_sweep_XXXXXX");
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

static int teardown(void **s) {
  (void)s;
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
  return sh(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_lists),
      cmocka_unit_test(test_sweep_table),
      cmocka_unit_test(test_sweep_bad_input),
      cmocka_unit_test(test_calibrate_inverts),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
