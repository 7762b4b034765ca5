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
#include <dirent.h>
#include <signal.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <hdf5.h>

#include "record_status.h"
#include "study_procs.h"
#include "sweep_rows.h" /* the journal's row (vs_sweep_row) */
#include "voussoir/run.h"
#include "list.h"

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
 * the target, gives back k_n = 10 (within what the tolerance on dz/L allows). The arch of 21
 * voussoirs: the inversion holds for any arch, and a coarse one keeps the ~20 runs cheap. */
#define COARSE "arch.voussoirs=21"
static void test_calibrate_inverts(void **s) {
  (void)s;
  vs_case c;
  vs_case_defaults(&c);
  c.kn_N_mm3 = 10.0;
  c.voussoirs = 21;
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
  snprintf(cmd, sizeof cmd,
           "%s calibrate %s --set " COARSE " --target-dz-pct %.10f --kn-min 2 --kn-max 50 "
           "--tol-pct 1e-4 -q > %s",
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
  snprintf(cmd, sizeof cmd, "%s calibrate %s --set " COARSE " --target-dz-pct 60 --kn-min 1 "
           "--kn-max 10 -q > %s", VS_BINARY, REFERENCE, path);
  assert_int_equal(sh(cmd), 1);
  t = slurp(path);
  assert_non_null(strstr(t, "no k_n in [1, 10]"));
  free(t);
}

/* --kn-min and --kn-max take joints.kn_N_mm3's range from the case's key table, [1e-4, 1e6]:
 * the ends accepted (the run goes on to the case, whose bad --set is what stops it), the doubles
 * just outside refused with the option and the range named, exit 2 and nothing on stdout. Runs
 * that fail (at k_n 1e4 the 21-block reference arch's path finds no equilibrium beyond 0 mm)
 * are reported with their cause, not only as no value. */
static void test_calibrate_kn_range(void **s) {
  (void)s;
  double lo = 0.0, hi = 0.0;
  assert_int_equal(vs_case_key_range("joints", "kn_N_mm3", &lo, NULL, &hi, NULL), 0);
  char cmd[1024], out[256], err[256];
  snprintf(out, sizeof out, "%s/knr.out", g_dir);
  snprintf(err, sizeof err, "%s/knr.err", g_dir);
  const struct {
    const char *opts, *stderr_has;
  } cases[] = {
      {"--kn-max 1e6 --kn-min 1e-4 --set joints.nope=1", "joints.nope = 1: unknown key"},
      {"--kn-max 1000000.0000000001", "--kn-max 1000000.0000000001: out of range (allowed: [0.0001, 1e+06])"},
      {"--kn-max 2e6", "--kn-max 2e6: out of range (allowed: [0.0001, 1e+06])"},
      {"--kn-min 9.9999e-5", "--kn-min 9.9999e-5: out of range (allowed: [0.0001, 1e+06])"},
      {"--kn-min 1e6 --kn-max 1e6", "kn-min < kn-max <= 1e+06 N/mm^3"},
  };
  /* the message's range is the table's */
  char range[64];
  snprintf(range, sizeof range, "[%g, %g]", lo, hi);
  assert_string_equal(range, "[0.0001, 1e+06]");
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    snprintf(cmd, sizeof cmd, "%s calibrate %s --target-dz-pct 16 %s > %s 2> %s", VS_BINARY,
             REFERENCE, cases[i].opts, out, err);
    assert_int_equal(sh(cmd), 2);
    char *e = slurp(err), *o = slurp(out);
    if (strstr(e, cases[i].stderr_has) == NULL)
      fail_msg("calibrate %s: stderr lacks '%s':\n%s", cases[i].opts, cases[i].stderr_has, e);
    if (i == 0 && strstr(e, "--kn-") != NULL) fail_msg("--kn-max 1e6 refused:\n%s", e);
    assert_string_equal(o, "");
    free(e);
    free(o);
  }
  /* failed runs: their count and the first one's cause */
  snprintf(cmd, sizeof cmd, "%s calibrate %s --set " COARSE " --target-dz-pct 16 --kn-min 1e4 "
           "--kn-max 1.5e4 -q > %s", VS_BINARY, REFERENCE, out);
  assert_int_equal(sh(cmd), 1);
  char *t = slurp(out);
  if (strstr(t, "no run of the scan gives a collapse") == NULL ||
      strstr(t, "9 of the 9 runs failed, the first at k_n = 10000 N/mm^3: no equilibrium") == NULL)
    fail_msg("calibrate over failing runs:\n%s", t);
  free(t);
}

/* Options that atoi/atof read as a prefix ("2x" as 2), and sizes whose product overflowed an
 * int (65536 x 65536 ran 0 cases with exit 0): refused before anything is created. */
static void test_sweep_strict_options(void **s) {
  (void)s;
  char cmd[1024], path[256];
  snprintf(cmd, sizeof cmd, "%s sweep %s --alpha 0 -j 2x -o %s/strict1 2>%s/strict.err", VS_BINARY,
           REFERENCE, g_dir, g_dir);
  assert_int_equal(sh(cmd), 2);
  snprintf(path, sizeof path, "%s/strict.err", g_dir);
  char *t = slurp(path);
  assert_non_null(strstr(t, "-j 2x: unexpected characters after the number"));
  free(t);
  snprintf(cmd, sizeof cmd,
           "%s sweep %s --vary arch.radius_mm=1:65536:1 --vary arch.depth_mm=1:65536:1 -o "
           "%s/strict2 2>%s/strict.err",
           VS_BINARY, REFERENCE, g_dir, g_dir);
  assert_int_equal(sh(cmd), 2);
  t = slurp(path);
  assert_non_null(strstr(t, "more than 100000 runs"));
  free(t);
  snprintf(cmd, sizeof cmd, "%s calibrate %s --target-dz-pct 16x -q 2>%s/strict.err", VS_BINARY,
           REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 2);
  t = slurp(path);
  assert_non_null(strstr(t, "--target-dz-pct 16x: unexpected characters after the number"));
  free(t);
  snprintf(cmd, sizeof cmd, "%s calibrate %s --target-dz-pct 16 --kn-min 0x1 -q 2>/dev/null",
           VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 2);
  for (int i = 1; i <= 2; i++) {
    snprintf(path, sizeof path, "%s/strict%d", g_dir, i);
    assert_int_not_equal(access(path, F_OK), 0);
  }
}

/* Processes whose command line mentions text (the sweep's directory is in every run's -o). */
static int processes_with(const char *text) {
  DIR *d = opendir("/proc");
  assert_non_null(d);
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    if (e->d_name[0] < '1' || e->d_name[0] > '9') continue;
    char path[300], buf[4096];
    snprintf(path, sizeof path, "/proc/%s/cmdline", e->d_name);
    FILE *f = fopen(path, "rb");
    if (f == NULL) continue;
    size_t k = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    for (size_t i = 0; i < k; i++)
      if (buf[i] == '\0') buf[i] = ' ';
    buf[k] = '\0';
    n += strstr(buf, text) != NULL;
  }
  closedir(d);
  return n;
}

/* Field 3 (status) of the row of run r in the summary, copied to out. */
static void row_status(const char *table, int r, char *out, size_t size) {
  char head[16];
  snprintf(head, sizeof head, "\n%d,", r);
  const char *p = strstr(table, head);
  if (p == NULL) fail_msg("no row %d in:\n%s", r, table);
  p = strchr(strchr(p + 1, ',') + 1, ',') + 1; /* past run and the one axis */
  size_t k = 0;
  while (p[k] && p[k] != ',' && k + 1 < size) k++;
  snprintf(out, size, "%.*s", (int)k, p);
}

/* SIGINT to the sweep once its first run has finished (its JSON appears only then) and its second
 * has created its record: the run under way is stopped (no process left) and its record closed
 * as interrupted, the table lists the finished run and marks the others; then
 * --resume completes the rest without running the finished one again (and, -q, says nothing of
 * resuming on stderr). Run 2 is held under way
 * (VS_FAULT_HOLD=2: it waits, its record created, until the stop reaches it), so the signal
 * lands while it runs however fast the machine is; the resume runs without the hold. */
static void test_sweep_interrupt_resume(void **s) {
  (void)s;
  char dir[128], out[160], err[160], json1[160], table[160];
  snprintf(dir, sizeof dir, "%s/int", g_dir);
  snprintf(out, sizeof out, "%s/int.out", g_dir);
  snprintf(err, sizeof err, "%s/int.err", g_dir);
  snprintf(json1, sizeof json1, "%s/run_0001.json", dir);
  snprintf(table, sizeof table, "%s/summary.csv", dir);
  char *argv[] = {VS_BINARY, "sweep", REFERENCE, "--vary", "arch.voussoirs=21,120,23",
                  "-j", "1", "-q", "-o", dir, NULL};
  assert_int_equal(setenv("VS_FAULT_HOLD", "2", 1), 0);
  pid_t pid = spawn(argv, out, err);
  assert_int_equal(unsetenv("VS_FAULT_HOLD"), 0);
  struct stat st1;
  for (int i = 0; stat(json1, &st1) != 0; i++) {
    if (i > 60000) fail_msg("no %s after 600 s", json1);
    if (waitpid(pid, NULL, WNOHANG) == pid) fail_msg("the sweep ended before its first run's JSON");
    nanosleep(&(struct timespec){0, 10000000}, NULL);
  }
  /* and run 2 under way, its record created */
  char part2[200], h52[200]; /* the record is created as .part, renamed once its layout is in */
  snprintf(part2, sizeof part2, "%s/run_0002.h5.part", dir);
  snprintf(h52, sizeof h52, "%s/run_0002.h5", dir);
  for (int i = 0; access(part2, F_OK) != 0 && access(h52, F_OK) != 0; i++) {
    if (i > 60000) fail_msg("no %s after 600 s", h52);
    if (waitpid(pid, NULL, WNOHANG) == pid) fail_msg("the sweep ended before its second run");
    nanosleep(&(struct timespec){0, 10000000}, NULL);
  }
  assert_int_equal(kill(pid, SIGINT), 0);
  assert_int_equal(exit_code(pid), 130);
  assert_int_equal(processes_with(dir), 0); /* the runs were stopped and waited for */
  char *t = slurp(table), status[32];
  assert_non_null(t);
  row_status(t, 1, status, sizeof status);
  assert_string_equal(status, "collapse");
  row_status(t, 2, status, sizeof status); /* stopped: its record closed as interrupted */
  assert_string_equal(status, "interrupted");
  char h5[200], rec[64];
  snprintf(h5, sizeof h5, "%s/run_0002.h5", dir);
  vs_test_record_status(h5, rec, sizeof rec);
  assert_string_equal(rec, "failed: interrupted");
  row_status(t, 3, status, sizeof status);
  assert_string_equal(status, "not_run");
  free(t);
  t = slurp(out);
  assert_non_null(strstr(t, "interrupted:"));
  free(t);

  /* --resume: the finished run is kept as it is (same file, same time), the others run */
  char *resume[] = {VS_BINARY, "sweep", REFERENCE, "--vary", "arch.voussoirs=21,120,23",
                    "-j", "1", "-q", "-o", dir, "--resume", NULL};
  assert_int_equal(exit_code(spawn(resume, out, err)), 0);
  struct stat st2;
  assert_int_equal(stat(json1, &st2), 0);
  assert_true(st1.st_ino == st2.st_ino && st1.st_mtim.tv_sec == st2.st_mtim.tv_sec &&
              st1.st_mtim.tv_nsec == st2.st_mtim.tv_nsec);
  t = slurp(table);
  for (int r = 1; r <= 3; r++) {
    row_status(t, r, status, sizeof status);
    assert_string_equal(status, "collapse");
  }
  free(t);
  t = slurp(err); /* -q: no progress, the resume's note included (it is shown without -q) */
  if (strstr(t, "resuming") != NULL) fail_msg("-q, yet on stderr: %s", t);
  free(t);
  /* a --resume with other lists is refused: it would mix two sweeps */
  char *other[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,1,2", "-q", "-o", dir, "--resume", NULL};
  assert_int_equal(exit_code(spawn(other, out, err)), 2);
  t = slurp(err);
  assert_non_null(strstr(t, "sweep.manifest differs"));
  free(t);
}

/* The table without its wall_s column (the only one that differs between two runs of a case). */
static void strip_wall(char *t) {
  for (char *line = t; *line;) {
    char *end = strchr(line, '\n');
    if (end == NULL) break;
    int commas = 0;
    char *a = NULL, *b = NULL; /* wall_s: fields 11 and 12 counted from 1 (before error) */
    for (char *p = line; p < end; p++)
      if (*p == ',') {
        commas++;
        if (commas == 10) a = p;
        if (commas == 11) b = p;
      }
    if (a != NULL && b != NULL) {
      memmove(a, b, strlen(b) + 1);
      end -= b - a;
    }
    line = end + 1;
  }
}

/* A kill while a row is being appended leaves a torn last row in the journal: --resume ignores it
 * and runs that case again, and cuts the torn bytes away before appending, so that a second
 * --resume reads whole rows (it used to read the rows appended after the torn one out of line)
 * and the table is the uninterrupted sweep's. A FIFO where the journal goes is refused. */
static void test_sweep_torn_journal(void **s) {
  (void)s;
  char cmd[2048], path[600], table[600];
  snprintf(path, sizeof path, "%s/torn/sweep.journal", g_dir);
  snprintf(table, sizeof table, "%s/torn/summary.csv", g_dir);
  snprintf(cmd, sizeof cmd, "%s sweep %s --alpha 0,30,60 --first-limit -j 1 -q -o %s/torn",
           VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 0);
  char *whole = slurp(table);
  strip_wall(whole);
  struct stat st;
  assert_int_equal(stat(path, &st), 0);
  const off_t size = st.st_size;
  assert_int_equal(truncate(path, size - 10), 0); /* the last row torn */
  snprintf(cmd, sizeof cmd,
           "%s sweep %s --alpha 0,30,60 --first-limit -j 1 -q -o %s/torn --resume 2>/dev/null",
           VS_BINARY, REFERENCE, g_dir);
  for (int k = 0; k < 2; k++) {
    assert_int_equal(sh(cmd), 0);
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_size, size); /* three whole rows, no torn bytes between them */
    char *t = slurp(table);
    strip_wall(t);
    assert_string_equal(t, whole);
    free(t);
  }
  free(whole);
  /* a FIFO where the journal goes is refused before anything runs, and left as it was */
  snprintf(path, sizeof path, "%s/fifo", g_dir);
  assert_int_equal(mkdir(path, 0755), 0);
  snprintf(path, sizeof path, "%s/fifo/sweep.journal", g_dir);
  assert_int_equal(mkfifo(path, 0644), 0);
  snprintf(cmd, sizeof cmd, "%s sweep %s --alpha 0,30 --first-limit -q -o %s/fifo 2>/dev/null",
           VS_BINARY, REFERENCE, g_dir);
  assert_int_equal(sh(cmd), 2);
  assert_int_equal(lstat(path, &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  snprintf(path, sizeof path, "%s/fifo/summary.csv", g_dir);
  assert_int_not_equal(access(path, F_OK), 0);
}

/* --- the journal's rows: checksummed, and every field checked before its run counts as done --- */

static void save(const char *path, const unsigned char *b, size_t n) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(b, 1, n, f), n);
  assert_int_equal(fclose(f), 0);
}

/* The sweep journal j (n bytes): its header's length; its rows must be a vs_sweep_row and the
 * 8 bytes of its checksum (little endian), each whole and sound. *rows: how many. */
static size_t sweep_journal_layout(const unsigned char *j, size_t n, int *rows) {
  size_t stored = 0;
  if (sscanf((const char *)j, "voussoir sweep journal 2 row %zu bytes", &stored) != 1)
    fail_msg("journal header \"%.60s\"", (const char *)j);
  assert_int_equal(stored, sizeof(vs_sweep_row) + 8);
  const size_t head = (size_t)((const unsigned char *)memchr(j, '\n', n) + 1 - j);
  assert_int_equal((n - head) % stored, 0);
  *rows = (int)((n - head) / stored);
  for (int i = 0; i < *rows; i++)
    assert_true(sum_holds(j + head + (size_t)i * stored, sizeof(vs_sweep_row)));
  return head;
}

/* A damage done to the journal's row of run 2: what it changes (the first row, run 1's, at
 * hand), whether its checksum is then made right again (so that the row's fields are what gives
 * it away), and what stderr must say of it. */
typedef struct {
  void (*damage)(vs_sweep_row *r, const vs_sweep_row *first);
  int resum;
  const char *says;
} sweep_damage;

/* error, and every byte after it, without a NUL: a reader that trusts the row reads on past the
 * row's buffer (an ASan heap-buffer-overflow) and copies what follows into the table */
static void dmg_unterminated(vs_sweep_row *r, const vs_sweep_row *f) {
  (void)f;
  memset((char *)r + offsetof(vs_sweep_row, error), 'A', sizeof *r - offsetof(vs_sweep_row, error));
}
static void dmg_flip(vs_sweep_row *r, const vs_sweep_row *f) {
  (void)f;
  ((unsigned char *)&r->delta_u_mm)[3] ^= 0x10;
}
static void dmg_run(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->run = 4; }
static void dmg_code(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->code = 7; }
static void dmg_status(vs_sweep_row *r, const vs_sweep_row *f) {
  (void)f;
  snprintf(r->status, sizeof r->status, "running");
}
static void dmg_mode(vs_sweep_row *r, const vs_sweep_row *f) {
  (void)f;
  snprintf(r->mode, sizeof r->mode, "IV");
}
static void dmg_hinges(vs_sweep_row *r, const vs_sweep_row *f) {
  (void)f;
  r->hinges[2] = '"';
}
static void dmg_axis(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->axis[0] = 45.0; }
static void dmg_double(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->delta_u_mm = -1.0; }
static void dmg_nan(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->dz_pct = NAN; }
static void dmg_wall(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->wall_s = INFINITY; }
static void dmg_count(vs_sweep_row *r, const vs_sweep_row *f) { (void)f; r->snaps = -3; }
static void dmg_twice(vs_sweep_row *r, const vs_sweep_row *f) { *r = *f; }

/* The resumes are run without -q, which silences their "resuming: K of N runs" (stderr not a
 * terminal: no progress line either). */
#define JR_LISTS "--alpha 0,30,60 --set arch.voussoirs=21 -j 1"
#define JR_ARGS JR_LISTS " -q"

/* A sweep of 3 runs, then, for each damage, a copy of its directory with run 2's journal row
 * damaged and --resume there: the row is named once on stderr with what is wrong, run 2 (and it
 * alone) runs again, its row is appended after the others' (the damaged one is gone from the
 * journal), and the table is the uninterrupted sweep's. A journal of the layout before the
 * checksums is refused (exit 2) and the table left as it was. */
static void test_sweep_journal_rows(void **s) {
  (void)s;
  static const sweep_damage damages[] = {
      {dmg_unterminated, 1, "error is not NUL-terminated"},
      {dmg_flip, 0, "checksum does not match"},
      {dmg_run, 1, "run 4 is not one of this sweep's 1..3"},
      {dmg_code, 1, "code 7"},
      {dmg_status, 1, "status \"running\""},
      {dmg_mode, 1, "mode is not"},
      {dmg_hinges, 1, "hinges holds"},
      {dmg_axis, 1, "support.alpha_deg = 45 is not the run's 30"},
      {dmg_double, 1, "delta_u_mm -1"},
      {dmg_nan, 1, "must be finite, as delta_u_mm is"},
      {dmg_wall, 1, "wall_s inf"},
      {dmg_count, 1, "snaps -3"},
      {dmg_twice, 1, "a second row for run 1"},
  };
  char cmd[2048], path[600], err[600];
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_ARGS " -o %s/jr >/dev/null", VS_BINARY, REFERENCE,
           g_dir);
  assert_int_equal(sh(cmd), 0);
  snprintf(path, sizeof path, "%s/jr/summary.csv", g_dir);
  char *whole = slurp(path);
  strip_wall(whole);
  snprintf(err, sizeof err, "%s/jr.err", g_dir);
  for (size_t k = 0; k < sizeof damages / sizeof damages[0]; k++) {
    const sweep_damage *d = &damages[k];
    snprintf(cmd, sizeof cmd, "rm -rf %s/jr%zu && cp -a %s/jr %s/jr%zu", g_dir, k, g_dir, g_dir, k);
    assert_int_equal(sh(cmd), 0);
    snprintf(path, sizeof path, "%s/jr%zu/sweep.journal", g_dir, k);
    size_t n = 0;
    int rows = 0;
    unsigned char *j = load_file(path, &n);
    const size_t head = sweep_journal_layout(j, n, &rows), stored = sizeof(vs_sweep_row) + 8;
    assert_int_equal(rows, 3);
    vs_sweep_row first, r;
    memcpy(&first, j + head, sizeof first);
    memcpy(&r, j + head + stored, sizeof r);
    assert_int_equal(first.run, 1); /* -j 1: the rows in run order */
    assert_int_equal(r.run, 2);
    d->damage(&r, &first);
    memcpy(j + head + stored, &r, sizeof r);
    if (d->resum) set_sum(j + head + stored, sizeof r);
    save(path, j, n);
    free(j);
    snprintf(cmd, sizeof cmd, "%s sweep %s " JR_LISTS " -o %s/jr%zu --resume >/dev/null 2>%s",
             VS_BINARY, REFERENCE, g_dir, k, err);
    const int rc = sh(cmd);
    char *e = slurp(err);
    const char *at = strstr(e, "sweep.journal: row 2: ");
    if (rc != 0 || at == NULL || strstr(at + 1, "sweep.journal: row") != NULL ||
        strstr(at, d->says) == NULL ||
        strstr(e, "resuming: 2 of 3 runs already complete") == NULL)
      fail_msg("damage %zu: exit %d, stderr \"%s\": expected exit 0, row 2 named once with "
               "\"%s\", 2 of 3 runs kept", k, rc, e, d->says);
    free(e);
    j = load_file(path, &n); /* runs 1 and 3 kept, run 2 run again and appended */
    assert_int_equal(sweep_journal_layout(j, n, &rows), head);
    assert_int_equal(rows, 3);
    static const int order[] = {1, 3, 2};
    for (int i = 0; i < 3; i++) {
      memcpy(&r, j + head + (size_t)i * stored, sizeof r);
      assert_int_equal(r.run, order[i]);
    }
    free(j);
    snprintf(path, sizeof path, "%s/jr%zu/summary.csv", g_dir, k);
    char *t = slurp(path);
    strip_wall(t);
    if (strcmp(t, whole) != 0) fail_msg("damage %zu: table\n%s\nnot the sweep's\n%s", k, t, whole);
    free(t);
  }
  /* the layout before the checksums (journal 1): --resume refused, nothing rewritten */
  snprintf(path, sizeof path, "%s/jr/sweep.journal", g_dir);
  size_t n = 0;
  unsigned char *j = load_file(path, &n);
  int rows = 0;
  const size_t head = sweep_journal_layout(j, n, &rows);
  char old[64];
  const int hl =
      snprintf(old, sizeof old, "voussoir sweep journal 1 row %zu bytes\n", sizeof(vs_sweep_row));
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(old, 1, (size_t)hl, f), (size_t)hl);
  for (int i = 0; i < rows; i++) { /* its rows as they were: without their checksums */
    const unsigned char *r = j + head + (size_t)i * (sizeof(vs_sweep_row) + 8);
    assert_int_equal(fwrite(r, sizeof(vs_sweep_row), 1, f), 1);
  }
  assert_int_equal(fclose(f), 0);
  free(j);
  snprintf(path, sizeof path, "%s/jr/summary.csv", g_dir);
  char *before = slurp(path);
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_ARGS " -o %s/jr --resume >/dev/null 2>%s", VS_BINARY,
           REFERENCE, g_dir, err);
  assert_int_equal(sh(cmd), 2);
  char *e = slurp(err), *after = slurp(path);
  assert_non_null(strstr(e, "was not written by this build"));
  assert_string_equal(after, before);
  free(e), free(before), free(after), free(whole);
}

/* --- a killed sweep's workers, and one study at a time in a directory --- */

/* Whether the record at path ("DIR/run_NNNN.h5") is created: its .part first, renamed once its
 * layout is in. */
static int record_begun(const void *path) {
  char part[300];
  snprintf(part, sizeof part, "%s.part", (const char *)path);
  return access(path, F_OK) == 0 || access(part, F_OK) == 0;
}

/* The table (wall_s cut) of the uninterrupted sweep of JR_ARGS, run into g_dir/name. */
static char *uninterrupted_table(const char *name) {
  char cmd[1024], path[600];
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_ARGS " -o %s/%s >/dev/null", VS_BINARY, REFERENCE,
           g_dir, name);
  assert_int_equal(sh(cmd), 0);
  snprintf(path, sizeof path, "%s/%s/summary.csv", g_dir, name);
  char *t = slurp(path);
  assert_non_null(t);
  strip_wall(t);
  return t;
}

/* The table in dir (wall_s cut) must be whole, an uninterrupted sweep's. */
static void expect_table(const char *dir, const char *whole) {
  char path[300];
  snprintf(path, sizeof path, "%s/summary.csv", dir);
  char *t = slurp(path);
  if (t == NULL) fail_msg("%s: missing", path);
  strip_wall(t);
  if (strcmp(t, whole) != 0) fail_msg("%s:\n%s\nnot the uninterrupted sweep's\n%s", path, t, whole);
  free(t);
}

/* A run that cannot start (its record's lock held by another process, here this one) is not
 * journalled: the sweep says so on stderr, lists it as not_started with the cause and exits 1,
 * and --resume, once the lock is let go, runs it (it used to be journalled as a failed run,
 * which every later --resume kept); the table is then the uninterrupted sweep's. */
static void test_sweep_not_started(void **s) {
  (void)s;
  char *whole = uninterrupted_table("ns_ref");
  char dir[128], path[200], cmd[1024], err[160];
  snprintf(dir, sizeof dir, "%s/ns", g_dir);
  assert_int_equal(mkdir(dir, 0755), 0);
  snprintf(path, sizeof path, "%s/run_0002.h5.lock", dir);
  const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  assert_true(fd >= 0);
  assert_int_equal(flock(fd, LOCK_EX | LOCK_NB), 0);
  snprintf(err, sizeof err, "%s/ns.err", g_dir);
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_ARGS " -o %s >/dev/null 2>%s", VS_BINARY, REFERENCE,
           dir, err);
  assert_int_equal(sh(cmd), 1);
  char *e = slurp(err);
  if (strstr(e, "run 2 could not start") == NULL || strstr(e, "being written by another") == NULL)
    fail_msg("stderr \"%s\": expected run 2 named, and why", e);
  free(e);
  snprintf(path, sizeof path, "%s/summary.csv", dir);
  char *t = slurp(path), status[32];
  row_status(t, 2, status, sizeof status);
  assert_string_equal(status, "not_started");
  free(t);
  snprintf(path, sizeof path, "%s/sweep.journal", dir);
  size_t n = 0;
  int rows = 0;
  unsigned char *j = load_file(path, &n);
  const size_t head = sweep_journal_layout(j, n, &rows);
  assert_int_equal(rows, 2); /* runs 1 and 3 */
  for (int i = 0; i < rows; i++) {
    vs_sweep_row r;
    memcpy(&r, j + head + (size_t)i * (sizeof r + 8), sizeof r);
    assert_int_not_equal(r.run, 2);
  }
  free(j);
  close(fd); /* the lock let go */
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_LISTS " -o %s --resume >/dev/null 2>%s", VS_BINARY,
           REFERENCE, dir, err);
  assert_int_equal(sh(cmd), 0);
  e = slurp(err);
  assert_non_null(strstr(e, "resuming: 2 of 3 runs already complete"));
  free(e);
  expect_table(dir, whole);
  free(whole);
}

/* A run stopped by its wall-time limit is over: journalled (row status "stopped", counted as
 * failed) and not run again by --resume, which takes its row as sound (it used to refuse it as
 * "not a failed run's" and run it again). */
static void test_sweep_stopped_resumed(void **s) {
  (void)s;
  char dir[128], cmd[1024], err[160], path[200];
  snprintf(dir, sizeof dir, "%s/st", g_dir);
  snprintf(err, sizeof err, "%s/st.err", g_dir);
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_ARGS " --max-wall-s 1e-6 -o %s >/dev/null 2>%s",
           VS_BINARY, REFERENCE, dir, err);
  assert_int_equal(sh(cmd), 1); /* every run failed: stopped */
  snprintf(path, sizeof path, "%s/summary.csv", dir);
  char *t = slurp(path), status[32];
  for (int r = 1; r <= 3; r++) {
    row_status(t, r, status, sizeof status);
    assert_string_equal(status, "stopped");
  }
  free(t);
  snprintf(cmd, sizeof cmd, "%s sweep %s " JR_LISTS " --max-wall-s 1e-6 -o %s --resume "
           ">/dev/null 2>%s", VS_BINARY, REFERENCE, dir, err);
  assert_int_equal(sh(cmd), 1);
  char *e = slurp(err);
  if (strstr(e, "resuming: 3 of 3 runs already complete") == NULL || strstr(e, "runs again"))
    fail_msg("stderr \"%s\": expected the three stopped runs taken from the journal", e);
  free(e);
}

/* SIGKILL to a sweep while its run R is under way (held: VS_FAULT_HOLD, its record created and
 * locked), then --resume at once. The worker is stopped (SIGSTOP) before the kill, as slow to
 * react to its parent's death as a loaded machine may make it: it must die with the sweep all
 * the same (its parent-death signal was SIGTERM, under which it finished its step and closed its
 * record, holding its run's lock meanwhile), so that the resume runs run R instead of journalling
 * it as a failed run ("being written by another process"), which later resumes kept. This
 * process is the killed sweep's subreaper: its orphaned workers become its children, and it
 * sees how they ended. Three rounds, R = 1, 2, 3; the table each time the uninterrupted
 * sweep's. */
static void test_sweep_kill_resume(void **s) {
  (void)s;
  char *whole = uninterrupted_table("kill_ref");
  assert_int_equal(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  for (int round = 1; round <= 3; round++) {
    char dir[128], out[160], err[160], h5[200], hold[8];
    snprintf(dir, sizeof dir, "%s/kill%d", g_dir, round);
    snprintf(out, sizeof out, "%s/kill.out", g_dir);
    snprintf(err, sizeof err, "%s/kill.err", g_dir);
    snprintf(h5, sizeof h5, "%s/run_%04d.h5", dir, round);
    snprintf(hold, sizeof hold, "%d", round);
    char *argv[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30,60", "--set",
                    "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, NULL};
    assert_int_equal(setenv("VS_FAULT_HOLD", hold, 1), 0);
    const pid_t pid = spawn(argv, out, err);
    assert_int_equal(unsetenv("VS_FAULT_HOLD"), 0);
    wait_until(record_begun, h5, pid, "run R's record created");
    pid_t worker[4];
    assert_int_equal(children_of(pid, worker, 4), 1); /* -j 1: run R's, holding its lock */
    assert_int_equal(kill(worker[0], SIGSTOP), 0);
    assert_int_equal(kill(pid, SIGKILL), 0);
    int st = 0;
    assert_int_equal(waitpid(pid, &st, 0), pid);
    char *resume[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30,60", "--set",
                      "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, "--resume", NULL};
    const int rc = exit_code(spawn(resume, out, err));
    kill(worker[0], SIGCONT); /* if it still lives, let it end as it would */
    expect_table(dir, whole);
    if (rc != 0) fail_msg("round %d: resume exit %d", round, rc);
    pid_t p;
    while ((p = waitpid(-1, &st, 0)) > 0) /* the orphaned worker, now ours */
      if (p != worker[0] || !died_with_study(st))
        fail_msg("round %d: orphan %d ended %s %d, not killed with the sweep", round, (int)p,
                 WIFSIGNALED(st) ? "by signal" : "with status",
                 WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
  }
  assert_int_equal(prctl(PR_SET_CHILD_SUBREAPER, 0), 0);
  free(whole);
}

/* One study at a time in a directory: a sweep held with run 2 under way (VS_FAULT_HOLD, let go
 * by a file: VS_FAULT_RELEASE) holds the directory's lock; a second sweep there, fresh or
 * --resume, and a montecarlo there are refused with exit 2 and the first's pid, before they
 * write anything: the first's manifest, journal, table and run 1's JSON are as they were, and
 * once let go it finishes with the uninterrupted sweep's table. (A second sweep used to wipe the
 * first's journal and JSONs, and each failed the other's runs.) */
static void test_sweep_study_lock(void **s) {
  (void)s;
  char *whole = uninterrupted_table("lock_ref");
  char dir[128], out[160], err[160], h5[200], release[160], path[200];
  snprintf(dir, sizeof dir, "%s/lock", g_dir);
  snprintf(out, sizeof out, "%s/lock.out", g_dir);
  snprintf(err, sizeof err, "%s/lock.err", g_dir);
  snprintf(h5, sizeof h5, "%s/run_0002.h5", dir);
  snprintf(release, sizeof release, "%s/lock.release", g_dir);
  char *argv[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30,60", "--set",
                  "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, NULL};
  assert_int_equal(setenv("VS_FAULT_HOLD", "2", 1), 0);
  assert_int_equal(setenv("VS_FAULT_RELEASE", release, 1), 0);
  const pid_t first = spawn(argv, out, err);
  assert_int_equal(unsetenv("VS_FAULT_HOLD"), 0);
  assert_int_equal(unsetenv("VS_FAULT_RELEASE"), 0);
  wait_until(record_begun, h5, first, "run 2's record created");
  static const char *const names[] = {"sweep.manifest", "sweep.journal", "summary.csv",
                                      "run_0001.json"};
  char *before[4];
  struct stat st1, st2;
  for (int i = 0; i < 4; i++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    before[i] = slurp(path);
    assert_non_null(before[i]);
  }
  snprintf(path, sizeof path, "%s/run_0001.json", dir);
  assert_int_equal(stat(path, &st1), 0);
  char pid[32];
  snprintf(pid, sizeof pid, "pid %d", (int)first);
  char err2[160];
  snprintf(err2, sizeof err2, "%s/lock2.err", g_dir);
  char *second[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30", "--set",
                    "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, NULL};
  char *resume[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30,60", "--set",
                    "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, "--resume", NULL};
  char *mc[] = {VS_BINARY, "montecarlo", REFERENCE, "--samples", "2", "-q", "-o", dir, NULL};
  char **others[] = {second, resume, mc};
  for (int k = 0; k < 3; k++) {
    const int rc = exit_code(spawn(others[k], out, err2));
    char *e = slurp(err2);
    if (rc != 2 || strstr(e, pid) == NULL || strstr(e, "another study") == NULL)
      fail_msg("%s in the directory of a study under way: exit %d, stderr \"%s\" (expected 2 "
               "and %s)", others[k][1], rc, e, pid);
    free(e);
  }
  for (int i = 0; i < 4; i++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    char *now = slurp(path);
    if (now == NULL || strcmp(now, before[i]) != 0) fail_msg("%s changed", names[i]);
    free(now);
    free(before[i]);
  }
  snprintf(path, sizeof path, "%s/run_0001.json", dir);
  assert_int_equal(stat(path, &st2), 0);
  assert_true(st1.st_ino == st2.st_ino && st1.st_mtim.tv_sec == st2.st_mtim.tv_sec &&
              st1.st_mtim.tv_nsec == st2.st_mtim.tv_nsec);
  FILE *f = fopen(release, "w"); /* let the first go on */
  assert_non_null(f);
  fclose(f);
  assert_int_equal(exit_code(first), 0);
  expect_table(dir, whole);
  free(whole);
  snprintf(path, sizeof path, "%s/study.lock", dir); /* released: removed */
  assert_int_not_equal(access(path, F_OK), 0);
}

/* Whether the text (a C string) is in the file g_dir/lockwait.err. */
static int stderr_says(const void *text) {
  char path[200];
  snprintf(path, sizeof path, "%s/lockwait.err", g_dir);
  char *e = slurp(path);
  const int yes = e != NULL && strstr(e, text) != NULL;
  free(e);
  return yes;
}

/* Whether process pid is a zombie (ended, not waited for). */
static int zombie(const void *pid) {
  char path[64], buf[256] = "";
  snprintf(path, sizeof path, "/proc/%d/stat", *(const pid_t *)pid);
  FILE *f = fopen(path, "r");
  if (f == NULL) return 0;
  const size_t k = fread(buf, 1, sizeof buf - 1, f);
  fclose(f);
  buf[k] = '\0';
  const char *end = strrchr(buf, ')');
  return end != NULL && end[1] == ' ' && end[2] == 'Z';
}

/* A directory lock held, by a process other than the one its lock file names, which has ended
 * (here: this process holds it, and the file names a child of it that has ended and is not yet
 * waited for, as a killed study's workers hold its lock while they die): a sweep there says on
 * stderr that it waits for the workers of the study that ended, waits, and runs once the lock
 * is let go. (A zombie holds no file: it must not count as a study under way, which would be
 * refused with exit 2.) */
static void test_sweep_lock_wait(void **s) {
  (void)s;
  char *whole = uninterrupted_table("wait_ref");
  char dir[128], path[200], out[160], err[160], says[96];
  snprintf(dir, sizeof dir, "%s/wait", g_dir);
  assert_int_equal(mkdir(dir, 0755), 0);
  const pid_t z = fork();
  assert_true(z >= 0);
  if (z == 0) _exit(0);
  wait_until(zombie, &z, getpid(), "the child a zombie");
  snprintf(path, sizeof path, "%s/study.lock", dir);
  const int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0644); /* the sweep must not share it */
  assert_true(fd >= 0);
  assert_int_equal(flock(fd, LOCK_EX | LOCK_NB), 0);
  char pid[32];
  const int n = snprintf(pid, sizeof pid, "%d\n", (int)z);
  assert_int_equal(write(fd, pid, (size_t)n), n);
  snprintf(out, sizeof out, "%s/lockwait.out", g_dir);
  snprintf(err, sizeof err, "%s/lockwait.err", g_dir);
  char *argv[] = {VS_BINARY, "sweep", REFERENCE, "--alpha", "0,30,60", "--set",
                  "arch.voussoirs=21", "-j", "1", "-q", "-o", dir, NULL};
  const pid_t sweep = spawn(argv, out, err);
  snprintf(says, sizeof says, "waiting for the workers of a study that ended (pid %d)", (int)z);
  wait_until(stderr_says, says, sweep, "the sweep waiting for the lock");
  close(fd); /* let go */
  assert_int_equal(exit_code(sweep), 0);
  assert_int_equal(waitpid(z, NULL, 0), z);
  expect_table(dir, whole);
  free(whole);
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
      cmocka_unit_test(test_calibrate_kn_range),
      cmocka_unit_test(test_sweep_strict_options),
      cmocka_unit_test(test_sweep_interrupt_resume),
      cmocka_unit_test(test_sweep_torn_journal),
      cmocka_unit_test(test_sweep_journal_rows),
      cmocka_unit_test(test_sweep_not_started),
      cmocka_unit_test(test_sweep_stopped_resumed),
      cmocka_unit_test(test_sweep_kill_resume),
      cmocka_unit_test(test_sweep_study_lock),
      cmocka_unit_test(test_sweep_lock_wait),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
