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

#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"
#define VS VS_BINARY

static char g_dir[64]; /* scratch directory; every run's working directory */

static int setup(void **state) {
  (void)state;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_exit_XXXXXX");
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

/* argv run in g_dir, stdout and stderr into g_dir/out.txt, err.txt; the exit status or -1. */
static int run_argv(char *const argv[]) {
  const pid_t pid = fork();
  if (pid == 0) {
    char out[128], err[128];
    snprintf(out, sizeof out, "%s/out.txt", g_dir);
    snprintf(err, sizeof err, "%s/err.txt", g_dir);
    const int fo = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fo < 0 || fe < 0 || dup2(fo, 1) < 0 || dup2(fe, 2) < 0 || chdir(g_dir) != 0) _exit(126);
    execv(argv[0], argv);
    _exit(127);
  }
  int st = 0;
  if (pid < 0 || waitpid(pid, &st, 0) != pid) return -1;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int teardown(void **state) {
  (void)state;
  char *rm[] = {"/bin/rm", "-rf", "--", g_dir, NULL};
  return run_argv(rm) == 0 ? 0 : -1;
}

static char *slurp_err(void) {
  char path[128];
  snprintf(path, sizeof path, "%s/err.txt", g_dir);
  FILE *f = fopen(path, "rb");
  assert_non_null(f);
  static char text[1 << 16];
  const size_t n = fread(text, 1, sizeof text - 1, f);
  text[n] = '\0';
  fclose(f);
  return text;
}

/* The names in g_dir but the captured outputs, one a line. */
static void listing(char *buf, size_t size) {
  buf[0] = '\0';
  DIR *d = opendir(g_dir);
  assert_non_null(d);
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d))
    if (strcmp(e->d_name, "out.txt") != 0 && strcmp(e->d_name, "err.txt") != 0) {
      strncat(buf, e->d_name, size - strlen(buf) - 2);
      strcat(buf, "\n");
    }
  closedir(d);
}

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
  const char *err = slurp_err();
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

/* Every run of a quiet sweep fails (the arch cannot stand under its own weight): stderr says
 * so and names the cause; with one run of two failing, it says how many. */
static void test_sweep_failures_said(void **s) {
  (void)s;
  char *all[] = {VS, "sweep", REFERENCE, "--kn", "1e-4,2e-4", "--set", "arch.thickness_mm=2",
                 "--set", "arch.density_kg_m3=1e5", "--first-limit", "-q", "-j", "2", "-o",
                 "all_failed", NULL};
  assert_int_equal(run_argv(all), 1);
  const char *err = slurp_err();
  if (strstr(err, "every run failed (2 of 2)") == NULL || strstr(err, "cannot stand") == NULL)
    fail_msg("every run failed, stderr: \"%s\"", err);
  char *some[] = {VS, "sweep", REFERENCE, "--vary", "arch.thickness_mm=2,24", "--first-limit",
                  "-q", "-j", "2", "-o", "some_failed", NULL};
  assert_int_equal(run_argv(some), 1);
  err = slurp_err();
  if (strstr(err, "1 of 2 runs failed") == NULL || strstr(err, "run 1: ") == NULL)
    fail_msg("one run of two failed, stderr: \"%s\"", err);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_long_output_names),
      cmocka_unit_test(test_sweep_failures_said),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
