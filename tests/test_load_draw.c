/* The live load drawn (issue 28, item 7): a load run's record holds the load as applied
 * (/summary/load/forces), its XDMF sidecar a "load" grid with an arrow's shaft ending on the
 * extrados at x_mm from the left springing's intrados point (that point taken from the record's
 * own /geometry/joint_points, the springing joint's inner end), pointing down, Fz the load; a
 * patch's arrows share its value and lie within its width; `voussoir plot` draws the record. The
 * picture's arrow itself is tested in test_plot (test_live_load_arrow). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
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

#define VS_SCRATCH "load_draw"
#include "scratch.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static void read_doubles(hid_t f, const char *path, double *v, size_t n) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  assert_int_equal((size_t)H5Sget_simple_extent_npoints(sp), n);
  assert_true(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  H5Sclose(sp);
  H5Dclose(d);
}

static int rows_of(hid_t f, const char *path) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  assert_int_equal(H5Sget_simple_extent_dims(sp, dims, NULL), 2);
  assert_int_equal((int)dims[1], 5);
  H5Sclose(sp);
  H5Dclose(d);
  return (int)dims[0];
}

/* The left springing's intrados point, x: of joint 1's two ends the inner one (the larger x). */
static double springing_x(hid_t f) {
  double jp[4];
  hid_t d = H5Dopen2(f, "/geometry/joint_points", H5P_DEFAULT);
  assert_true(d >= 0);
  hsize_t start[2] = {0, 0}, count[2] = {2, 2};
  hid_t fs = H5Dget_space(d), ms = H5Screate_simple(2, count, NULL);
  H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
  assert_true(H5Dread(d, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, jp) >= 0);
  H5Sclose(ms), H5Sclose(fs), H5Dclose(d);
  return fmax(jp[0], jp[2]);
}

/* The sidecar's load grid: its points (x0 z0 x1 z1 per force, 4 n values) and Fz. */
static void xmf_load(const char *xmf, int n, double *pts, double *fz) {
  const char *g = strstr(xmf, "xml:id=\"lg\"");
  assert_non_null(g);
  g = strstr(g, "Format=\"XML\">");
  assert_non_null(g);
  char *e = (char *)g + strlen("Format=\"XML\">");
  for (int i = 0; i < 4 * n; i++) pts[i] = strtod(e, &e);
  const char *a = strstr(xmf, "xml:id=\"lfz\" Name=\"Fz_N\"");
  assert_non_null(a);
  a = strstr(a, "Format=\"XML\">");
  e = (char *)a + strlen("Format=\"XML\">");
  for (int i = 0; i < n; i++) fz[i] = strtod(e, &e);
  assert_non_null(strstr(xmf, "<Grid Name=\"load\">"));
}

static void test_point_load(void **state) {
  (void)state;
  char cmd[1024];
  const double x_mm = 133.05, value = 2.5;
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=point "
           "--set load.x_mm=%g --set load.value_N=%g -o p.h5 >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE, x_mm, value);
  assert_int_equal(sh(cmd), 0);
  hid_t f = H5Fopen(in_dir("p.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  assert_int_equal(rows_of(f, "/summary/load/forces"), 1);
  double row[5];
  read_doubles(f, "/summary/load/forces", row, 5);
  const double x0 = springing_x(f);
  H5Fclose(f);
  const double want = x0 + x_mm * 1e-3;
  print_message("point load at %.6f m (springing %.6f m + %.2f mm)\n", row[3], x0, x_mm);
  assert_true(fabs(row[3] - want) <= 1e-9);
  assert_true(row[1] == 0.0 && row[2] == -value);
  double pts[4], fz[1];
  xmf_load(slurp(in_dir("p.xmf"), NULL), 1, pts, fz);
  assert_true(fabs(pts[0] - want) <= 1e-12 && fabs(pts[2] - want) <= 1e-12); /* vertical */
  assert_true(fabs(pts[3] - row[4]) <= 1e-12); /* ends on the point */
  assert_true(pts[1] > pts[3]);                 /* from above: the load points down */
  assert_true(fz[0] == -value);
  /* the pictures of the record draw it (test_plot checks the arrow's pixels) */
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' plot p.h5 -o pics >out.txt 2>err.txt", g_dir,
           VS_BINARY);
  assert_int_equal(sh(cmd), 0);
  assert_non_null(strstr(slurp(in_dir("out.txt"), NULL), "arch_end.png"));
}

/* A patch of width w centred on x: its forces sum to the load, each within [x - w/2, x + w/2];
 * a support-path record (no live load) has no load grid. */
static void test_patch_load(void **state) {
  (void)state;
  char cmd[1024];
  const double x_mm = 200.0, w_mm = 60.0, value = 3.0;
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=patch "
           "--set load.x_mm=%g --set load.width_mm=%g --set load.value_N=%g -o q.h5 "
           ">out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE, x_mm, w_mm, value);
  assert_int_equal(sh(cmd), 0);
  hid_t f = H5Fopen(in_dir("q.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  const int n = rows_of(f, "/summary/load/forces");
  assert_true(n >= 2);
  double *v = calloc(5 * (size_t)n, sizeof *v), *pts = calloc(4 * (size_t)n, sizeof *pts),
         *fz = calloc((size_t)n, sizeof *fz);
  assert_true(v != NULL && pts != NULL && fz != NULL);
  read_doubles(f, "/summary/load/forces", v, 5 * (size_t)n);
  const double x0 = springing_x(f);
  H5Fclose(f);
  xmf_load(slurp(in_dir("q.xmf"), NULL), n, pts, fz);
  double sum = 0.0;
  for (int i = 0; i < n; i++) {
    const double x = pts[4 * i + 2] - x0;
    assert_true(x >= (x_mm - 0.5 * w_mm) * 1e-3 - 1e-12 && x <= (x_mm + 0.5 * w_mm) * 1e-3 + 1e-12);
    assert_true(fabs(pts[4 * i + 2] - v[5 * i + 3]) <= 1e-12);
    assert_true(fz[i] == v[5 * i + 2] && fz[i] < 0.0);
    sum += fz[i];
  }
  assert_true(fabs(sum + value) <= 1e-12 * value);
  free(v), free(pts), free(fz);
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' run '%s' --first-limit -o s.h5 >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  assert_null(strstr(slurp(in_dir("s.xmf"), NULL), "<Grid Name=\"load\">"));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_point_load),
      cmocka_unit_test(test_patch_load),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
