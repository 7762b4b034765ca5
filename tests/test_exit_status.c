/* Exit statuses that say what happened: an output name too long for its lock file or working copy
 * ("<name>.lock", "<name>.part", the sidecar's "<name>.xmf.tmp") is bad input, refused before
 * anything is written (exit 2), for every command that takes -o; a sweep whose runs all failed
 * says so on stderr, with the first cause, even with -q (exit 1), and so does one with some
 * failed runs. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define VS_SCRATCH "exit"
#include "scratch.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"
#define VS VS_BINARY

/* A name of n bytes: 'x' repeated, then suffix. */
static const char *long_name(char *buf, size_t n, const char *suffix) {
  const size_t k = strlen(suffix);
  assert_true(n > k && n < PATH_MAX);
  memset(buf, 'x', n - k);
  memcpy(buf + n - k, suffix, k + 1);
  return buf;
}

/* The command refused with exit 2 and "too long" in its message, nothing written. */
static void expect_refused(char *const argv[], const char *what) {
  char before[8192], after[8192];
  listing(before, sizeof before);
  const int rc = run_argv(argv);
  const char *err = slurp(in_dir("err.txt"), NULL);
  if (rc != 2) fail_msg("%s: exit status %d, expected 2: %.300s", what, rc, err);
  if (strstr(err, "too long") == NULL) fail_msg("%s: the message does not say why: %s", what, err);
  listing(after, sizeof after);
  if (strcmp(before, after) != 0) fail_msg("%s: files written:\n%.1000s", what, after);
}

/* NAME_MAX is 255 on the file systems the tests run on; the working names add at most 5 bytes
 * (".lock", ".part", ".snap"): a record of 251 to 255 bytes used to fail at its lock (exit 1),
 * and one whose sidecar name cannot take ".tmp" after the whole run (exit 1, a record left). */
static void test_long_output_names(void **s) {
  (void)s;
  assert_int_equal(pathconf(g_dir, _PC_NAME_MAX), 255);
  char name[PATH_MAX];
  const size_t record_lengths[] = {251, 253, 255};
  for (size_t i = 0; i < 3; i++) {
    char what[48];
    snprintf(what, sizeof what, "run -o (%zu bytes)", record_lengths[i]);
    char *argv[] = {VS, "run", REFERENCE, "-q", "--first-limit", "-o",
                    (char *)long_name(name, record_lengths[i], ".h5"), NULL};
    expect_refused(argv, what);
  }
  /* no extension: its sidecar is NAME.xmf, written as NAME.xmf.tmp (254 + 4 bytes) */
  char *no_ext[] = {VS, "run", REFERENCE, "-q", "--first-limit", "-o",
                    (char *)long_name(name, 250, "x"), NULL};
  expect_refused(no_ext, "run -o (250 bytes, no extension)");
  char *csv[] = {VS, "run", REFERENCE, "-q", "--first-limit", "--no-record", "--csv",
                 (char *)long_name(name, 252, ".csv"), NULL};
  expect_refused(csv, "run --csv (252 bytes)");
  /* the directories of the other commands: beyond NAME_MAX itself */
  char *sweep[] = {VS, "sweep", REFERENCE, "--alpha", "0", "--first-limit", "-q", "-o",
                   (char *)long_name(name, 256, "d"), NULL};
  expect_refused(sweep, "sweep -o (256 bytes)");
  char *mc[] = {VS, "montecarlo", REFERENCE, "--samples", "1", "-q", "-o",
                (char *)long_name(name, 256, "d"), NULL};
  expect_refused(mc, "montecarlo -o (256 bytes)");
  char *merge[] = {VS, "merge", "a", "-o", (char *)long_name(name, 256, "d"), NULL};
  expect_refused(merge, "merge -o (256 bytes)");
  /* a record to plot, then plot -o with a directory name beyond NAME_MAX */
  char *rec[] = {VS, "run", REFERENCE, "-q", "--first-limit", "-o", "r.h5", NULL};
  assert_int_equal(run_argv(rec), 0);
  char *plot[] = {VS, "plot", "r.h5", "-o", (char *)long_name(name, 256, "d"), NULL};
  expect_refused(plot, "plot -o (256 bytes)");
  /* the longest record name that fits: 249 bytes with ".h5" (its sidecar's is one longer) */
  char *fits[] = {VS, "run", REFERENCE, "-q", "--first-limit", "-o",
                  (char *)long_name(name, 249, ".h5"), NULL};
  assert_int_equal(run_argv(fits), 0);
}

/* An output directory longer than VS_OUTPATH_DIR_MAX (1000 bytes), made of nested directories of
 * 200-byte names in the scratch directory: refused up front (exit 2, "too long"), nothing
 * written anywhere below. montecarlo used to cut its paths at 1200 bytes and write every file of
 * the study into one truncated name, exit 0 (issue 25, defect 6). */
static void test_long_output_dirs(void **s) {
  (void)s;
  char deep[1400] = "deep", cmd[1600];
  for (int k = 0; k < 6; k++) {
    const size_t n = strlen(deep);
    deep[n] = '/';
    memset(deep + n + 1, 'a' + k, 200);
    deep[n + 201] = '\0';
  }
  snprintf(cmd, sizeof cmd, "mkdir -p '%s/%s'", g_dir, deep);
  assert_int_equal(sh(cmd), 0);
  char out[1500]; /* deep/.../out: 1215 bytes */
  snprintf(out, sizeof out, "%s/out", deep);
  assert_true(strlen(out) > 1000);
  char *mc[] = {VS, "montecarlo", REFERENCE, "--samples", "2", "--set", "arch.voussoirs=11", "-q",
                "-o", out, NULL};
  char *sweep[] = {VS, "sweep", REFERENCE, "--alpha", "0", "--first-limit", "-q", "-o", out, NULL};
  char *merge[] = {VS, "merge", "a", "-o", out, NULL};
  char *rec[] = {VS, "run", REFERENCE, "-q", "--first-limit", "-o", "r.h5", NULL};
  assert_int_equal(run_argv(rec), 0);
  char *plot[] = {VS, "plot", "r.h5", "-o", out, NULL};
  char *const *cmds[] = {mc, sweep, merge, plot};
  const char *what[] = {"montecarlo", "sweep", "merge", "plot"};
  for (int i = 0; i < 4; i++) {
    expect_refused(cmds[i], what[i]);
    snprintf(cmd, sizeof cmd, "test -z \"$(find '%s/deep' -type f)\"", g_dir);
    if (sh(cmd) != 0) fail_msg("%s -o (%zu bytes): a file written below the scratch directory",
                               what[i], strlen(out));
  }
}

/* Every run of a quiet sweep fails (the arch cannot stand under its own weight): stderr says
 * so and names the cause; with one run of two failing, it says how many. */
static void test_sweep_failures_said(void **s) {
  (void)s;
  char *all[] = {VS, "sweep", REFERENCE, "--kn", "1e-4,2e-4", "--set", "arch.thickness_mm=2",
                 "--set", "arch.density_kg_m3=1e5", "--first-limit", "-q", "-j", "2", "-o",
                 "all_failed", NULL};
  assert_int_equal(run_argv(all), 1);
  const char *err = slurp(in_dir("err.txt"), NULL);
  if (strstr(err, "every run failed (2 of 2)") == NULL || strstr(err, "cannot stand") == NULL)
    fail_msg("every run failed, stderr: \"%s\"", err);
  char *some[] = {VS, "sweep", REFERENCE, "--vary", "arch.thickness_mm=2,24", "--first-limit",
                  "-q", "-j", "2", "-o", "some_failed", NULL};
  assert_int_equal(run_argv(some), 1);
  err = slurp(in_dir("err.txt"), NULL);
  if (strstr(err, "1 of 2 runs failed") == NULL || strstr(err, "run 1: ") == NULL)
    fail_msg("one run of two failed, stderr: \"%s\"", err);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_long_output_names),
      cmocka_unit_test(test_long_output_dirs),
      cmocka_unit_test(test_sweep_failures_said),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
