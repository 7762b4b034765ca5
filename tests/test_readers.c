/* The readers of a record (`voussoir plot`, the XDMF sidecar) on records the writer would not
 * make, each one edit away from a real one (the cases tests/fuzz/fuzz_record.c found): a table
 * of rank 2 (/summary/hinges, /summary/limit_points, a sweep's /summary), a hinge series of
 * more columns than joints or a hinge beyond the arch's joints is refused, not read past its
 * buffer, and a series of rank 6 is read; a number for plots.json that is NaN or infinite
 * (perhaps only once in mm) is written as null, JSON having neither; the sidecar leaves out a
 * ground of another shape than the 2 x 2 points it names, and a row whose time is not finite;
 * dimensions declared far beyond what the file holds are refused before they are allocated.
 * The arch pictures are drawn without the charts' Python (exit status 3); the charts' own
 * readers (python/voussoir/figures) meet a sweep's table of rank 2 and a NaN in it, and a
 * limit point at NaN, when /usr/bin/python3 has matplotlib and h5py. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "voussoir/output.h"

static char g_dir[64];

static int sh(const char *cmd) {
  int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* The whole file at DIR/name (NUL-terminated, malloc'd), or NULL if it is missing. */
static char *slurp(const char *name) {
  char path[256];
  snprintf(path, sizeof path, "%s/%s", g_dir, name);
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  fseek(f, 0, SEEK_END);
  const long n = ftell(f);
  rewind(f);
  char *s = malloc((size_t)n + 1);
  assert_non_null(s);
  assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
  s[n] = '\0';
  fclose(f);
  return s;
}

/* DIR/name.h5: a copy of the reference record (7 voussoirs: it collapses, falls and lands). */
static void copy_record(const char *name) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "cp '%s/ref.h5' '%s/%s.h5'", g_dir, g_dir, name);
  assert_int_equal(sh(cmd), 0);
}

static hid_t open_rw(const char *name) {
  char path[256];
  snprintf(path, sizeof path, "%s/%s.h5", g_dir, name);
  hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  return f;
}

/* Dataset dset of file f replaced by one of the same type and of rank `rank` with dimensions
 * dims (its values the fill value). */
static void reshape(hid_t f, const char *dset, int rank, const hsize_t *dims) {
  hid_t d = H5Dopen2(f, dset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t t = H5Dget_type(d);
  H5Dclose(d);
  assert_true(H5Ldelete(f, dset, H5P_DEFAULT) >= 0);
  hid_t sp = H5Screate_simple(rank, dims, NULL);
  d = H5Dcreate2(f, dset, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(d >= 0);
  H5Dclose(d);
  H5Sclose(sp);
  H5Tclose(t);
}

/* The first dimension of dataset dset of f. */
static hsize_t rows_of(hid_t f, const char *dset) {
  hid_t d = H5Dopen2(f, dset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[3] = {0};
  H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  return dims[0];
}

/* The whole of dataset dset of f in memory type mtype (elem bytes a value; the dataset of
 * rank 1, or its other dimensions 1), malloc'd; *n its values. */
static void *read_whole(hid_t f, const char *dset, hid_t mtype, size_t elem, hsize_t *n) {
  *n = rows_of(f, dset);
  void *v = malloc(*n * elem);
  assert_non_null(v);
  hid_t d = H5Dopen2(f, dset, H5P_DEFAULT);
  assert_true(d >= 0 && H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  H5Dclose(d);
  return v;
}

/* v (memory type mtype) written over the whole of dataset dset of f, and freed. */
static void write_whole(hid_t f, const char *dset, hid_t mtype, void *v) {
  hid_t d = H5Dopen2(f, dset, H5P_DEFAULT);
  assert_true(d >= 0 && H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  H5Dclose(d);
  free(v);
}

/* `voussoir plot DIR/name.h5 -o DIR/name_plots` with the charts' interpreter python (a path
 * that does not exist: the arch pictures only, exit status 3 when they are drawn): its exit
 * status; its stderr in DIR/err.txt. */
static int plot_with(const char *name, const char *python) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "VOUSSOIR_PYTHON=%s %s plot %s/%s.h5 -o %s/%s_plots > /dev/null 2> %s/err.txt",
           python, VS_BINARY, g_dir, name, g_dir, name, g_dir);
  return sh(cmd);
}

static const char *const NO_PYTHON = "/nonexistent/python3", *const PYTHON = "/usr/bin/python3";

static int plot(const char *name) { return plot_with(name, NO_PYTHON); }

/* Whether PYTHON can draw the charts (matplotlib, h5py, numpy). */
static int have_python(void) {
  return sh("/usr/bin/python3 -c 'import matplotlib, h5py, numpy' 2>/dev/null") == 0;
}

/* Whether JSON text holds a bare NaN or infinity where a number goes (printf's nan, inf). */
static int bare_non_finite(const char *json) {
  for (const char *p = json; (p = strpbrk(p, "ni")) != NULL; p++) {
    const char *q = p;
    if (strncmp(p, "nan", 3) != 0 && strncmp(p, "inf", 3) != 0) continue;
    if (q > json && q[-1] == '-') q--;
    while (q > json && q[-1] == ' ') q--;
    if (q > json && (q[-1] == ':' || q[-1] == ',' || q[-1] == '[')) return 1;
  }
  return 0;
}

static void expect_plot_with(const char *name, const char *python, int status, const char *said) {
  const int rc = plot_with(name, python);
  char *err = slurp("err.txt");
  if (rc != status || err == NULL || strstr(err, said) == NULL)
    fail_msg("%s: exit %d, stderr \"%s\": expected %d and \"%s\"", name, rc, err ? err : "",
             status, said);
  free(err);
}

static void expect_plot(const char *name, int status, const char *said) {
  expect_plot_with(name, NO_PYTHON, status, said);
}

/* A table of rank 2 is n x m records where the reader took n: refused (its rows alone are the
 * table); so is a hinge series with a column more than the record has joints. */
static void test_tables_of_another_rank(void **s) {
  (void)s;
  static const char *const tables[] = {"/summary/hinges", "/summary/limit_points"};
  for (int i = 0; i < 2; i++) {
    char name[32];
    snprintf(name, sizeof name, "rank2_%d", i);
    copy_record(name);
    hid_t f = open_rw(name);
    const hsize_t dims[2] = {rows_of(f, tables[i]), 3};
    reshape(f, tables[i], 2, dims);
    H5Fclose(f);
    expect_plot(name, 2, "/summary/hinges or /summary/limit_points is not a table of rank 1");
  }
  copy_record("wide_hinges");
  hid_t f = open_rw("wide_hinges");
  const hsize_t dims[2] = {rows_of(f, "/observables/joint_hinge/value"), 7 + 2};
  reshape(f, "/observables/joint_hinge/value", 2, dims);
  H5Fclose(f);
  expect_plot("wide_hinges", 2, "the record's time series are incomplete");
}

/* A hinge of /summary/hinges at joint 2147483647 (the arch has 8): refused, as a table not of
 * the record's layout (the pairing of hinges with open joints summed joint numbers: a signed
 * overflow, UBSan's report). */
static void test_hinge_beyond_the_joints(void **s) {
  (void)s;
  copy_record("hinge_far");
  hid_t f = open_rw("hinge_far");
  const char *dset = "/summary/hinges";
  typedef struct {
    int first, last;
  } span;
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(span)); /* those members only */
  H5Tinsert(t, "first", HOFFSET(span, first), H5T_NATIVE_INT);
  H5Tinsert(t, "last", HOFFSET(span, last), H5T_NATIVE_INT);
  hsize_t n;
  span *v = read_whole(f, dset, t, sizeof *v, &n);
  v[0].first = v[0].last = 2147483647;
  write_whole(f, dset, t, v);
  H5Tclose(t);
  H5Fclose(f);
  expect_plot("hinge_far", 2, "hinges within joints 1..8, on side I or E");
}

/* The support displacement's series (one value per row) of rank 6, rows x 1 x 1 x 1 x 1 x 1:
 * its rows are read as such (HDF5 wrote the 6 dimensions into room for 4, past the stack
 * buffer: a segfault; seen reading the code the fuzzer led to, as ASan does not see a write
 * from within HDF5). */
static void test_series_of_rank_6(void **s) {
  (void)s;
  copy_record("rank6");
  hid_t f = open_rw("rank6");
  const char *dset = "/observables/delta/value";
  hsize_t n;
  double *v = read_whole(f, dset, H5T_NATIVE_DOUBLE, sizeof *v, &n);
  const hsize_t dims[6] = {n, 1, 1, 1, 1, 1};
  reshape(f, dset, 6, dims);
  write_whole(f, dset, H5T_NATIVE_DOUBLE, v);
  H5Fclose(f);
  expect_plot("rank6", 3, "no charts"); /* drawn: the same values as the reference's */
}

/* A sweep's summary table (as voussoir sweep writes it: compound rows, UTF-8 strings) of
 * `rank`, its second row's dx/L NaN; at DIR/name.h5. */
static void sweep_table(const char *name, int rank) {
  typedef struct {
    double dz, dx;
    const char *status, *mode;
  } row;
  const row rows[4] = {{20.0, 0.0, "collapse", "I"}, {15.0, NAN, "collapse", "II"},
                       {20.0, 0.0, "collapse", "I"}, {15.0, NAN, "collapse", "II"}};
  char path[256];
  snprintf(path, sizeof path, "%s/%s.h5", g_dir, name);
  hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t str = H5Tcopy(H5T_C_S1);
  H5Tset_size(str, H5T_VARIABLE);
  H5Tset_cset(str, H5T_CSET_UTF8);
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(row));
  H5Tinsert(t, "dz_over_L_pct", HOFFSET(row, dz), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dx_over_L_pct", HOFFSET(row, dx), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "status", HOFFSET(row, status), str);
  H5Tinsert(t, "mode", HOFFSET(row, mode), str);
  const hsize_t dims[2] = {2, 2};
  hid_t sp = H5Screate_simple(rank, dims, NULL);
  hid_t d = H5Dcreate2(f, "/summary", t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(d >= 0);
  assert_true(H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows) >= 0);
  H5Dclose(d);
  H5Sclose(sp);
  H5Tclose(t);
  H5Tclose(str);
  H5Fclose(f);
}

static void test_sweep_table(void **s) {
  (void)s;
  sweep_table("sweep_rank2", 2);
  sweep_table("sweep_nan", 1);
  /* a sweep's table: no arch picture, so without the charts' Python only exit status 3 */
  expect_plot("sweep_rank2", 3, "no charts");
  if (!have_python()) {
    print_message("no %s with matplotlib and h5py: the charts' readers not checked\n", PYTHON);
    return;
  }
  expect_plot_with("sweep_rank2", PYTHON, 1, "/summary is not a sweep's summary table");
  /* rank 1: drawn, the point whose dx/L is NaN left out of its line */
  expect_plot_with("sweep_nan", PYTHON, 0, "");
  char *svg = slurp("sweep_nan_plots/domain.svg");
  assert_non_null(svg);
  free(svg);
}

/* A limit point at NaN (the record's /summary/limit_points): its mark in plots.json is null. */
static void test_limit_point_nan(void **s) {
  (void)s;
  copy_record("limit_nan");
  hid_t f = open_rw("limit_nan");
  const char *dset = "/summary/limit_points";
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(double)); /* that member only */
  H5Tinsert(t, "delta", 0, H5T_NATIVE_DOUBLE);
  hsize_t n;
  double *v = read_whole(f, dset, t, sizeof *v, &n);
  assert_true(n >= 1);
  for (hsize_t i = 0; i < n; i++) v[i] = NAN;
  write_whole(f, dset, t, v);
  H5Tclose(t);
  H5Fclose(f);
  plot("limit_nan"); /* whatever becomes of the limit point's picture, plots.json is JSON */
  char *json = slurp("limit_nan_plots/plots.json");
  assert_non_null(json);
  if (bare_non_finite(json)) fail_msg("plots.json: a NaN not written as null:\n%s", json);
  free(json);
  if (!have_python()) return;
  /* the charts: the limit point at NaN is not marked, the curves drawn */
  const int rc = plot_with("limit_nan", PYTHON);
  char *svg = slurp("limit_nan_plots/curves.svg");
  if (svg == NULL || rc == 3) fail_msg("limit_nan: charts not drawn (exit %d)", rc);
  free(svg);
}

/* The last state at a support displacement of 1e306 m, finite but not in mm: its picture's
 * delta_mm in plots.json is null (it was inf). */
static void test_delta_beyond_mm(void **s) {
  (void)s;
  copy_record("delta_far");
  hid_t f = open_rw("delta_far");
  const char *dset = "/observables/delta/value";
  hsize_t n;
  double *v = read_whole(f, dset, H5T_NATIVE_DOUBLE, sizeof *v, &n);
  v[n - 1] = 1e306;
  write_whole(f, dset, H5T_NATIVE_DOUBLE, v);
  H5Fclose(f);
  plot("delta_far");
  char *json = slurp("delta_far_plots/plots.json");
  assert_non_null(json);
  const char *end = strstr(json, "\"file\": \"arch_end.png\"");
  if (end == NULL || bare_non_finite(json) || strstr(end, "\"delta_mm\": null") == NULL)
    fail_msg("plots.json: the last state's delta_mm not null:\n%s", json);
  free(json);
}

/* The sidecar names the ground as 2 x 2 points: a record whose ground is another shape gets a
 * sidecar without it (the record's own is listed). */
static void test_ground_of_another_shape(void **s) {
  (void)s;
  vs_error err;
  char h5[256];
  copy_record("ground");
  snprintf(h5, sizeof h5, "%s/ground.h5", g_dir);
  assert_int_equal(vs_output_write_xdmf(h5, 0, &err), VS_OK);
  char *xmf = slurp("ground.xmf");
  assert_non_null(xmf);
  assert_non_null(strstr(xmf, ":/summary/ground/points<")); /* the control: it has a ground */
  free(xmf);
  hid_t f = open_rw("ground");
  const hsize_t three = 3;
  reshape(f, "/summary/ground/points", 1, &three);
  H5Fclose(f);
  assert_int_equal(vs_output_write_xdmf(h5, 0, &err), VS_OK);
  xmf = slurp("ground.xmf");
  assert_non_null(xmf);
  if (strstr(xmf, "/summary/ground/points") != NULL)
    fail_msg("the sidecar names /summary/ground/points, which holds 3 values, as 2 x 2");
  free(xmf);
}

/* A row whose time is infinite (the record's /observables/delta/time) is not listed: a
 * sidecar's times are numbers, strictly increasing. */
static void test_time_not_finite(void **s) {
  (void)s;
  vs_error err;
  char h5[256];
  copy_record("time_inf");
  hid_t f = open_rw("time_inf");
  const char *dset = "/observables/delta/time";
  hsize_t n;
  double *t = read_whole(f, dset, H5T_NATIVE_DOUBLE, sizeof *t, &n);
  t[n - 1] = INFINITY; /* the last row, which is always listed */
  write_whole(f, dset, H5T_NATIVE_DOUBLE, t);
  H5Fclose(f);
  snprintf(h5, sizeof h5, "%s/time_inf.h5", g_dir);
  assert_int_equal(vs_output_write_xdmf(h5, 0, &err), VS_OK);
  char *xmf = slurp("time_inf.xmf");
  assert_non_null(xmf);
  assert_non_null(strstr(xmf, "<Time Value=\"")); /* the control: rows are listed */
  if (strstr(xmf, "<Time Value=\"inf\"") != NULL) fail_msg("the sidecar lists a time inf");
  free(xmf);
}

/* Dimensions far beyond what the file holds (a crafted record: a dataset declared anew without
 * data reads as its fill value): refused before anything is allocated for them, the budget
 * being 2100 x the file's size + 16 MiB (h5util.h, docs/record.md). The states of 2^24 rows
 * (9 GiB with their series), a hinges table of 2^30 rows (48 GiB) and a sweep's table of as
 * many: refused, exit 2 (1 for the sweep, as for any table not a sweep's); the sidecar's joint
 * length of 2^28 values (2 GiB) is left out, not read (the process grows by less than 256 MiB). */
static void test_declared_beyond_the_file(void **s) {
  (void)s;
  copy_record("huge_states");
  hid_t f = open_rw("huge_states");
  const hsize_t rows = (hsize_t)1 << 24;
  reshape(f, "/observables/delta/value", 1, &rows);
  H5Fclose(f);
  expect_plot("huge_states", 2, "/observables/delta/value declares 16777216 states (");
  expect_plot("huge_states", 2, "MiB in memory): more than a file of ");
  copy_record("huge_hinges");
  f = open_rw("huge_hinges");
  const hsize_t hinges = (hsize_t)1 << 30;
  reshape(f, "/summary/hinges", 1, &hinges);
  H5Fclose(f);
  expect_plot("huge_hinges", 2, "/summary/hinges or /summary/limit_points declares more rows "
                                "than the file holds (allowed: at most 2100 x its size + 16 MiB)");
  sweep_table("huge_sweep", 1);
  f = open_rw("huge_sweep");
  reshape(f, "/summary", 1, &hinges);
  H5Fclose(f);
  expect_plot("huge_sweep", 3, "no charts"); /* the C side reads no sweep table */
  if (have_python())
    expect_plot_with("huge_sweep", PYTHON, 1, "/summary declares more rows than the file holds");
  copy_record("huge_length");
  f = open_rw("huge_length");
  const hsize_t lengths = (hsize_t)1 << 28;
  reshape(f, "/geometry/joint_length", 1, &lengths);
  H5Fclose(f);
  char h5[256];
  snprintf(h5, sizeof h5, "%s/huge_length.h5", g_dir);
  struct rusage before, after;
  getrusage(RUSAGE_SELF, &before);
  vs_error err;
  assert_int_equal(vs_output_write_xdmf(h5, 0, &err), VS_OK);
  getrusage(RUSAGE_SELF, &after);
  if (after.ru_maxrss - before.ru_maxrss > 256 * 1024)
    fail_msg("the sidecar's writer grew by %ld KiB reading a joint length of 2^28 values",
             after.ru_maxrss - before.ru_maxrss);
}

static int setup(void **s) {
  (void)s;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_readers_XXXXXX");
  if (mkdtemp(g_dir) == NULL) return -1;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "%s run %s/runs/reference.ini --set arch.voussoirs=7 -q -o %s/ref.h5 > /dev/null",
           VS_BINARY, VS_SOURCE_DIR, g_dir);
  return sh(cmd) == 0 ? 0 : -1;
}

static int teardown(void **s) {
  (void)s;
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
  return sh(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_tables_of_another_rank),
      cmocka_unit_test(test_hinge_beyond_the_joints),
      cmocka_unit_test(test_series_of_rank_6),
      cmocka_unit_test(test_sweep_table),
      cmocka_unit_test(test_limit_point_nan),
      cmocka_unit_test(test_delta_beyond_mm),
      cmocka_unit_test(test_ground_of_another_shape),
      cmocka_unit_test(test_time_not_finite),
      cmocka_unit_test(test_declared_beyond_the_file),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
