/* The live load drawn (issue 28, item 7): a load run's record holds the load as applied
 * (/summary/load/forces), its XDMF sidecar a "load" grid with an arrow's shaft ending on the
 * extrados at x_mm from the left springing's intrados point (that point taken from the record's
 * own /geometry/joint_points, the springing joint's inner end), pointing down, Fz the load; a
 * patch's arrows share its value and lie within its width; `voussoir plot` draws the record; the
 * load path's events carry the load factor (on the load-deflection curve; the collapse's the
 * peak), the support path's none. The
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

/* /events' kind and load_factor columns (read by name): n rows into kind (16 bytes each, NUL
 * added) and lf; the count. */
typedef struct {
  char kind[16];
  double lf;
} ev_row;

static int read_events(hid_t f, ev_row **out) {
  hid_t d = H5Dopen2(f, "/events", H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  const int n = (int)H5Sget_simple_extent_npoints(sp);
  hid_t s16 = H5Tcopy(H5T_C_S1);
  H5Tset_size(s16, 16);
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(ev_row));
  H5Tinsert(mt, "kind", HOFFSET(ev_row, kind), s16);
  H5Tinsert(mt, "load_factor", HOFFSET(ev_row, lf), H5T_NATIVE_DOUBLE);
  *out = calloc((size_t)(n > 0 ? n : 1), sizeof **out);
  assert_non_null(*out);
  assert_true(n == 0 || H5Dread(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, *out) >= 0);
  H5Tclose(mt), H5Tclose(s16), H5Sclose(sp), H5Dclose(d);
  return n;
}

/* The load path's events carry the load factor: each hinge's is one of the curve's equilibria
 * (the one where it was found), at most the peak; the collapse's is the peak (the summary's
 * load_factor); the JSON's hinges give the same as load_factor_onset. */
static void test_event_load_factor(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=point "
           "--set load.x_mm=133.05 -o e.h5 --json >e.json 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  hid_t f = H5Fopen(in_dir("e.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  double peak = NAN;
  hid_t s1 = H5Dopen2(f, "/summary/load/load_factor", H5P_DEFAULT);
  assert_true(H5Dread(s1, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &peak) >= 0);
  H5Dclose(s1);
  hid_t c = H5Dopen2(f, "/summary/load/curve", H5P_DEFAULT);
  hid_t csp = H5Dget_space(c);
  const size_t nc = (size_t)H5Sget_simple_extent_npoints(csp);
  double *curve = malloc(nc * sizeof *curve);
  assert_non_null(curve);
  assert_true(H5Dread(c, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, curve) >= 0);
  H5Sclose(csp), H5Dclose(c);
  ev_row *ev = NULL;
  const int n = read_events(f, &ev);
  H5Fclose(f);
  const char *json = slurp(in_dir("e.json"), NULL);
  int hinges = 0, collapses = 0;
  for (int i = 0; i < n; i++) {
    if (strncmp(ev[i].kind, "hinge_formed", 12) == 0) {
      int on_curve = 0;
      for (size_t k = 0; k < nc; k += 2) on_curve |= curve[k] == ev[i].lf;
      assert_true(on_curve && ev[i].lf <= peak);
      char key[64];
      snprintf(key, sizeof key, "\"load_factor_onset\":%.10g", ev[i].lf);
      if (strstr(json, key) == NULL) fail_msg("%s not in the JSON", key);
      hinges++;
    } else if (strncmp(ev[i].kind, "collapse", 8) == 0) {
      assert_true(ev[i].lf == peak);
      collapses++;
    }
  }
  print_message("%d hinges on the load path, collapse at lambda %.6g\n", hinges, peak);
  assert_true(hinges >= 4 && collapses == 1);
  free(ev);
  free(curve);
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

/* The first dimension of a dataset of any rank. */
static int first_dim(hid_t f, const char *path) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[3] = {0, 0, 0};
  assert_true(H5Sget_simple_extent_dims(sp, dims, NULL) >= 1);
  H5Sclose(sp);
  H5Dclose(d);
  return (int)dims[0];
}

/* A load run's sidecar lists every state (its load path's rows all share the held support
 * displacement, so that they are timed by their number), and each row's load grid ends on the
 * loaded point moved with its block to that row (the record's block position: turned by theta
 * about the centroid, which moved by ux, uz), its Fz the row's load factor x the load. */
static void xmf_rows_moved(const char *h5, const char *xmf_path, double value) {
  hid_t f = H5Fopen(h5, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  const int rows = first_dim(f, "/observables/block_position/value");
  const int nb = first_dim(f, "/geometry/block_centroid");
  const int nc = first_dim(f, "/summary/load/curve");
  double *q = calloc((size_t)rows * 3 * (size_t)nb, sizeof *q), *cen = calloc(2 * (size_t)nb, sizeof *cen);
  double *curve = calloc(2 * (size_t)nc, sizeof *curve), force[5];
  assert_true(q != NULL && cen != NULL && curve != NULL);
  read_doubles(f, "/observables/block_position/value", q, (size_t)rows * 3 * (size_t)nb);
  read_doubles(f, "/geometry/block_centroid", cen, 2 * (size_t)nb);
  read_doubles(f, "/summary/load/curve", curve, 2 * (size_t)nc);
  read_doubles(f, "/summary/load/forces", force, 5);
  H5Fclose(f);
  const char *xmf = slurp(xmf_path, NULL);
  int times = 0;
  for (const char *p = strstr(xmf, "<Time "); p != NULL; p = strstr(p + 1, "<Time ")) times++;
  assert_int_equal(times, rows); /* below the sidecar's 500 grids */
  const int r = rows - 1, b = (int)force[0];
  char key[64];
  snprintf(key, sizeof key, "<Grid Name=\"row %d\"", r);
  const char *g = strstr(xmf, key);
  assert_non_null(g);
  g = strstr(g, "<Grid Name=\"load\">");
  assert_non_null(g);
  g = strstr(g, "Format=\"XML\">");
  char *e = (char *)g + strlen("Format=\"XML\">");
  double pts[4];
  for (int i = 0; i < 4; i++) pts[i] = strtod(e, &e);
  const double *qb = q + ((size_t)r * (size_t)nb + (size_t)b) * 3;
  const double dx = force[3] - cen[2 * b], dz = force[4] - cen[2 * b + 1];
  const double px = cen[2 * b] + qb[0] + cos(qb[2]) * dx - sin(qb[2]) * dz;
  const double pz = cen[2 * b + 1] + qb[1] + sin(qb[2]) * dx + cos(qb[2]) * dz;
  print_message("last row %d: the load's point moved by (%.4g, %.4g) mm\n", r,
                (px - force[3]) * 1e3, (pz - force[4]) * 1e3);
  assert_true(fabs(pts[2] - px) <= 1e-12 && fabs(pts[3] - pz) <= 1e-12);
  assert_true(fabs(pz - force[4]) > 1e-5); /* it did move */
  assert_true(fabs(pts[0] - px) <= 1e-12 && pts[1] > pts[3]); /* vertical, from above */
  g = strstr(g, "Name=\"Fz_N\"");
  assert_non_null(g);
  g = strstr(g, "Format=\"XML\">");
  const double fz = strtod(g + strlen("Format=\"XML\">"), NULL);
  assert_true(fabs(fz - curve[2 * (nc - 1)] * -value) <= 1e-12 * value * fabs(curve[2 * (nc - 1)]));
  free(q), free(cen), free(curve);
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
  xmf_rows_moved(in_dir("p.h5"), in_dir("p.xmf"), value);
  /* the pictures of the record draw it (test_plot checks the arrow's pixels) */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && VOUSSOIR_PYTHON=/nonexistent/python3 '%s' plot p.h5 -o pics >out.txt "
           "2>err.txt", g_dir, VS_BINARY);
  assert_int_equal(sh(cmd), 3); /* the arch pictures, without the charts' Python */
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
  /* off a load path the events carry no load factor */
  hid_t f2 = H5Fopen(in_dir("s.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f2 >= 0);
  ev_row *ev = NULL;
  const int ne = read_events(f2, &ev);
  H5Fclose(f2);
  assert_true(ne > 0);
  for (int i = 0; i < ne; i++) assert_true(isnan(ev[i].lf));
  free(ev);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_point_load),
      cmocka_unit_test(test_patch_load),
      cmocka_unit_test(test_event_load_factor),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
