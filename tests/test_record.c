/* The record from the command line: a run writes an HDF5 file whose status says how it ended and
 * whose last state is the one the run reports; SIGINT stops a run cleanly (exit 130, status
 * "failed: interrupted", everything recorded so far readable); bad input creates no file; and
 * `voussoir plot` draws the pictures of a record (PNG of the documented size). */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <hdf5.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "voussoir/plot.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static char g_dir[64];

static int sh(const char *cmd) {
  int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The string attribute name of object obj of an HDF5 record (variable-length string). */
static void read_attr(const char *path, const char *obj, const char *name, char *out,
                      size_t size) {
  out[0] = '\0';
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t a = H5Aopen_by_name(f, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(a >= 0);
  hid_t t = H5Aget_type(a);
  char *s = NULL;
  if (H5Tis_variable_str(t) > 0) {
    hid_t mt = H5Tcopy(H5T_C_S1);
    H5Tset_size(mt, H5T_VARIABLE);
    H5Tset_cset(mt, H5T_CSET_UTF8);
    assert_true(H5Aread(a, mt, &s) >= 0);
    snprintf(out, size, "%s", s);
    H5free_memory(s);
    H5Tclose(mt);
  }
  H5Tclose(t);
  H5Aclose(a);
  H5Fclose(f);
}

/* The root attribute "status" of an HDF5 record. */
static void read_status(const char *path, char *out, size_t size) {
  read_attr(path, "/", "status", out, size);
}

static long rows_of(const char *path, const char *dset) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t d = H5Dopen2(f, dset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[3] = {0};
  H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  return (long)dims[0];
}

static void test_completed_record(void **s) {
  (void)s;
  char cmd[1024], h5[256], status[256];
  snprintf(h5, sizeof h5, "%s/ref.h5", g_dir);
  snprintf(cmd, sizeof cmd, "%s run %s -q -o %s > %s/ref.txt", VS_BINARY, REFERENCE, h5, g_dir);
  assert_int_equal(sh(cmd), 0);
  read_status(h5, status, sizeof status);
  assert_string_equal(status, "completed");
  assert_true(rows_of(h5, "/observables/delta/value") > 10);
  snprintf(cmd, sizeof cmd, "%s/ref.xmf", g_dir);
  assert_int_equal(access(cmd, F_OK), 0);
  /* solver statistics: cumulative, so never decreasing, and both phases at work */
  {
    hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
    hid_t d = H5Dopen2(f, "/observables/solver/value", H5P_DEFAULT);
    assert_true(d >= 0);
    const long n = rows_of(h5, "/observables/solver/value");
    long long *v = malloc((size_t)n * 3 * sizeof *v);
    assert_non_null(v);
    assert_true(H5Dread(d, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
    for (long i = 1; i < n; i++)
      for (int c = 0; c < 3; c++)
        if (v[3 * i + c] < v[3 * (i - 1) + c]) fail_msg("solver column %d decreases at row %ld", c, i);
    assert_true(v[3 * (n - 1)] > 0 && v[3 * (n - 1) + 1] > 0 && v[3 * (n - 1) + 2] > 0);
    free(v);
    H5Dclose(d);
    H5Fclose(f);
  }
  /* h5dump (Debian hdf5-tools) lists the layout docs/record.md documents */
  snprintf(cmd, sizeof cmd, "h5dump -n %s > %s/layout.txt 2>&1", h5, g_dir);
  assert_int_equal(sh(cmd), 0);
  {
    char lp[256];
    snprintf(lp, sizeof lp, "%s/layout.txt", g_dir);
    FILE *f = fopen(lp, "r");
    assert_non_null(f);
    static char text[1 << 16];
    const size_t n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    const char *documented[] = {
        "group      /parameters/arch", "group      /geometry", "dataset    /events",
        "dataset    /observables/delta/step", "dataset    /observables/delta/time",
        "dataset    /observables/delta/value", "dataset    /observables/phase/value",
        "dataset    /observables/block_position/value", "dataset    /observables/block_velocity/value",
        "dataset    /observables/joint_N/value", "dataset    /observables/joint_T/value",
        "dataset    /observables/joint_M/value", "dataset    /observables/joint_contact/value",
        "dataset    /observables/joint_gap_i/value", "dataset    /observables/joint_gap_e/value",
        "dataset    /observables/joint_slip_plastic/value", "dataset    /observables/joint_hinge/value",
        "dataset    /observables/reactions/value", "dataset    /observables/energy/value",
        "dataset    /observables/solver/value",
        "group      /summary", "dataset    /summary/limit_points", "dataset    /summary/hinges",
        "dataset    /summary/damping/freq", "dataset    /summary/damping/damping_ratio"};
    for (size_t i = 0; i < sizeof documented / sizeof documented[0]; i++)
      if (strstr(text, documented[i]) == NULL) fail_msg("h5dump -n lacks \"%s\"", documented[i]);
  }
  /* the arch pictures of the record, drawn without the charts' Python (exit status 3: no
   * charts; test_python_figures runs them) */
  snprintf(cmd, sizeof cmd,
           "VOUSSOIR_PYTHON=/nonexistent/python3 %s plot %s -o %s/pics > /dev/null 2>&1",
           VS_BINARY, h5, g_dir);
  assert_int_equal(sh(cmd), 3);
  const char *names[] = {"arch_reference.png", "arch_hinge_A.png", "arch_hinge_D.png",
                         "arch_collapse.png", "arch_end.png"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    char path[512];
    snprintf(path, sizeof path, "%s/pics/%s", g_dir, names[i]);
    FILE *f = fopen(path, "rb");
    if (f == NULL) fail_msg("%s not drawn", path);
    unsigned char hdr[24];
    assert_int_equal(fread(hdr, 1, 24, f), 24);
    fclose(f);
    assert_memory_equal(hdr + 1, "PNG", 3);
    const unsigned w = (unsigned)hdr[16] << 24 | (unsigned)hdr[17] << 16 | (unsigned)hdr[18] << 8 | hdr[19];
    const unsigned h = (unsigned)hdr[20] << 24 | (unsigned)hdr[21] << 16 | (unsigned)hdr[22] << 8 | hdr[23];
    assert_int_equal(w, VS_PLOT_ARCH_WIDTH);
    assert_int_equal(h, VS_PLOT_ARCH_HEIGHT);
  }
  /* not a record */
  snprintf(cmd, sizeof cmd, "%s plot %s/ref.txt -o %s/nopics 2>/dev/null", VS_BINARY, g_dir, g_dir);
  assert_int_equal(sh(cmd), 2);
}

/* Lines in a file (0 if it cannot be read). */
static int lines_of(const char *path) {
  FILE *f = fopen(path, "r");
  if (f == NULL) return 0;
  int n = 0, ch;
  while ((ch = fgetc(f)) != EOF) n += ch == '\n';
  fclose(f);
  return n;
}

/* A long run (880 voussoirs) interrupted by SIGINT once it has recorded a state: the test waits
 * for a first data row in the run's CSV (written and flushed at every state), an observable
 * state rather than a sleep that races the run under load. */
/* The rigid fall's solver (fall.solver) is named in the record (/summary/fall, attribute
 * solver) and in the JSON (stats.fall.solver): nncg by default, gauss_seidel when chosen. */
static void test_fall_solver_recorded(void **s) {
  (void)s;
  const char *const solvers[] = {"", "gauss_seidel"};
  for (int i = 0; i < 2; i++) {
    char cmd[1024], h5[256], json[256], want[64], got[64];
    snprintf(h5, sizeof h5, "%s/solver%d.h5", g_dir, i);
    snprintf(json, sizeof json, "%s/solver%d.json", g_dir, i);
    snprintf(cmd, sizeof cmd, "%s run %s -q --json -o %s %s%s > %s", VS_BINARY, REFERENCE, h5,
             i > 0 ? "--set fall.solver=" : "", solvers[i], json);
    assert_int_equal(sh(cmd), 0);
    snprintf(want, sizeof want, "%s", i > 0 ? solvers[i] : "nncg");
    read_attr(h5, "/summary/fall", "solver", got, sizeof got);
    assert_string_equal(got, want);
    snprintf(cmd, sizeof cmd, "grep -q '\"fall\":{\"scheme\":\"rigid\",\"solver\":\"%s\"' %s",
             want, json);
    assert_int_equal(sh(cmd), 0);
  }
}

static void test_sigint(void **s) {
  (void)s;
  char h5[256], csv[256], status[256];
  snprintf(h5, sizeof h5, "%s/int.h5", g_dir);
  snprintf(csv, sizeof csv, "%s/int.csv", g_dir);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    if (freopen("/dev/null", "w", stdout) == NULL || freopen("/dev/null", "w", stderr) == NULL)
      _exit(126);
    execl(VS_BINARY, VS_BINARY, "run", REFERENCE, "-q", "--set", "arch.voussoirs=880", "-o", h5,
          "--csv", csv, (char *)NULL);
    _exit(127);
  }
  for (long i = 0; lines_of(csv) < 2; i++) {
    int st;
    if (waitpid(pid, &st, WNOHANG) == pid) fail_msg("the run ended before its first row");
    if (i > 60000) fail_msg("no first row after 600 s");
    struct timespec ts = {0, 10 * 1000 * 1000};
    nanosleep(&ts, NULL); /* polling interval only: the condition is the row */
  }
  kill(pid, SIGINT);
  int st = 0;
  assert_int_equal(waitpid(pid, &st, 0), pid);
  assert_true(WIFEXITED(st));
  assert_int_equal(WEXITSTATUS(st), 130);
  read_status(h5, status, sizeof status);
  assert_string_equal(status, "failed: interrupted");
  assert_true(rows_of(h5, "/observables/delta/value") >= 1);
}

/* Bad input: exit 2 and no record. */
static void test_bad_input_no_record(void **s) {
  (void)s;
  char cmd[1024], h5[256];
  snprintf(h5, sizeof h5, "%s/bad.h5", g_dir);
  snprintf(cmd, sizeof cmd, "%s run %s -q --kn -3 -o %s 2>/dev/null", VS_BINARY, REFERENCE, h5);
  assert_int_equal(sh(cmd), 2);
  assert_int_not_equal(access(h5, F_OK), 0);
}

static int setup(void **s) {
  (void)s;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_record_XXXXXX");
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
      cmocka_unit_test(test_completed_record),
      cmocka_unit_test(test_fall_solver_recorded),
      cmocka_unit_test(test_sigint),
      cmocka_unit_test(test_bad_input_no_record),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
