/* Tests of the pictures (include/voussoir/plot.h): PNG files read back with cairo have the
 * documented size, are not blank, and show stone at the voussoirs' centroids (mapped with the
 * module's frame), the open joint's wedge and the hinge dots on the side in contact; SVG files
 * are SVG; unwritable paths and bad arguments fail cleanly and create nothing. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, access, rmdir, setrlimit */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/plot.h"

#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* ---------------------------------------------------------------------------------------------
 * Fixture: a temporary directory and the reference arch */

typedef struct {
  char dir[64];
  vs_geometry *g;
  int n;        /* voussoirs */
  double *q;    /* 3 n, zeros */
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  assert_non_null(f);
  snprintf(f->dir, sizeof f->dir, "/tmp/vs_plot_XXXXXX");
  assert_non_null(mkdtemp(f->dir));
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_test_arch(&c, &f->g, &err), VS_OK);
  f->n = f->g->n_blocks;
  f->q = calloc((size_t)(3 * f->n), sizeof *f->q);
  assert_non_null(f->q);
  *state = f;
  return 0;
}

static void path_in(const fixture *f, const char *name, char *buf, size_t size) {
  snprintf(buf, size, "%s/%s", f->dir, name);
}

static const char *const FILES[] = {"ref.png", "ref.svg", "open.png", "open.svg", "one.png", "bad.png",
                                    "big.png",
                                    "big.svg", "load.png", "noload.png"};

static int teardown(void **state) {
  fixture *f = *state;
  char p[128];
  for (size_t k = 0; k < sizeof FILES / sizeof FILES[0]; k++) {
    path_in(f, FILES[k], p, sizeof p);
    remove(p);
  }
  rmdir(f->dir);
  vs_geometry_destroy(&f->g);
  free(f->q);
  free(f);
  vs_plot_release(); /* cairo's and fontconfig's caches, for the leak checker */
  return 0;
}

static int file_exists(const char *path) { return access(path, F_OK) == 0; }

/* The picture of f's arch in state q with nothing else (no hinges, joints, thrust line, title);
 * a test sets what it draws. */
static vs_plot_arch_args arch_args(const fixture *f, const double *q) {
  return (vs_plot_arch_args){.g = f->g, .q = q};
}

/* ---------------------------------------------------------------------------------------------
 * Reading a PNG back */

typedef struct {
  cairo_surface_t *sf;
  const unsigned char *data;
  int w, h, stride;
} image;

static image load_png(const char *path) {
  image im;
  im.sf = cairo_image_surface_create_from_png(path);
  if (cairo_surface_status(im.sf) != CAIRO_STATUS_SUCCESS)
    fail_msg("%s: %s", path, cairo_status_to_string(cairo_surface_status(im.sf)));
  cairo_surface_flush(im.sf);
  im.data = cairo_image_surface_get_data(im.sf);
  im.w = cairo_image_surface_get_width(im.sf);
  im.h = cairo_image_surface_get_height(im.sf);
  im.stride = cairo_image_surface_get_stride(im.sf);
  return im;
}

/* Colour of the pixel containing picture point (px, py): r, g, b in 0..255. */
static void pixel(const image *im, double px, double py, int rgb[3]) {
  int x = (int)floor(px), y = (int)floor(py);
  assert_true(x >= 0 && x < im->w && y >= 0 && y < im->h);
  uint32_t v;
  memcpy(&v, im->data + (size_t)y * (size_t)im->stride + 4 * (size_t)x, sizeof v);
  rgb[0] = (int)((v >> 16) & 255);
  rgb[1] = (int)((v >> 8) & 255);
  rgb[2] = (int)(v & 255);
}

/* Fraction of pixels that are not the white background. */
static double ink_fraction(const image *im) {
  long ink = 0;
  for (int y = 0; y < im->h; y++)
    for (int x = 0; x < im->w; x++) {
      int c[3];
      pixel(im, x, y, c);
      ink += (c[0] < 250 || c[1] < 250 || c[2] < 250);
    }
  return (double)ink / ((double)im->w * im->h);
}

/* Stone: a warm tan, well away from white, grey, red and the hinge colours. */
static int is_stone(const int c[3]) {
  return c[0] > 170 && c[0] < 235 && c[1] > 125 && c[1] < 195 && c[2] > 70 && c[2] < 145 &&
         c[0] - c[2] > 60;
}

static void expect_stone_at(const image *im, const vs_plot_frame *fr, double x, double z) {
  double px, py;
  int c[3];
  vs_plot_to_px(fr, x, z, &px, &py);
  pixel(im, px, py, c);
  if (!is_stone(c))
    fail_msg("pixel (%.1f, %.1f) for (%.4f, %.4f) m is (%d, %d, %d), not stone", px, py, x, z,
             c[0], c[1], c[2]);
}

static void expect_svg(const char *path) {
  FILE *fp = fopen(path, "rb");
  assert_non_null(fp);
  char head[8] = {0};
  size_t got = fread(head, 1, 5, fp);
  fseek(fp, 0, SEEK_END);
  long size = ftell(fp);
  fclose(fp);
  assert_int_equal(got, 5);
  assert_true(size > 1000);
  assert_true(strncmp(head, "<?xml", 5) == 0 || strncmp(head, "<svg", 4) == 0);
}

/* ---------------------------------------------------------------------------------------------
 * The arch */

static void test_reference_png_svg(void **state) {
  fixture *f = *state;
  char png[128], svg[128];
  path_in(f, "ref.png", png, sizeof png);
  path_in(f, "ref.svg", svg, sizeof svg);
  vs_error err;
  vs_error_clear(&err);
  vs_plot_arch_args a = arch_args(f, f->q);
  a.open_m = 5e-5;
  a.title = "reference";
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_OK);
  assert_int_equal(vs_plot_arch_draw(svg, VS_PLOT_SVG, &a, &err), VS_OK);
  expect_svg(svg);

  vs_plot_frame fr;
  assert_int_equal(vs_plot_arch_frame(&a, &fr, &err), VS_OK);
  assert_int_equal(fr.width, VS_PLOT_ARCH_WIDTH);
  assert_int_equal(fr.height, VS_PLOT_ARCH_HEIGHT);
  /* the span (with the abutments) fills most of the width: at least 1.5 px per mm */
  assert_true(fr.scale > 1500.0);

  image im = load_png(png);
  assert_int_equal(im.w, VS_PLOT_ARCH_WIDTH);
  assert_int_equal(im.h, VS_PLOT_ARCH_HEIGHT);
  assert_true(ink_fraction(&im) > 0.05);
  /* stone at the centroids of the crown voussoir and of both springers: three points not on a
   * line, so a wrong scale in x or in z would miss one of them */
  const int idx[3] = {0, f->n / 2, f->n - 1};
  for (int k = 0; k < 3; k++) expect_stone_at(&im, &fr, f->g->blocks[idx[k]].cx,
                                              f->g->blocks[idx[k]].cz);
  /* background: under the crown, half-way down to the springings, and a corner */
  int c[3];
  double px, py;
  const double ri = f->g->radius, beta = 0.5 * f->g->embrace;
  vs_plot_to_px(&fr, 0.0, 0.5 * ri * (1.0 + cos(beta)), &px, &py);
  pixel(&im, px, py, c);
  assert_true(c[0] == 255 && c[1] == 255 && c[2] == 255);
  pixel(&im, im.w - 3, 3, c);
  assert_true(c[0] == 255 && c[1] == 255 && c[2] == 255);
  cairo_surface_destroy(im.sf);
}

/* The right half (voussoirs 28..55, from joint 28) turned clockwise by a rigid rotation about
 * the intrados end of joint 28: joint 28 opens at the extrados, its hinge is at the intrados. */
static void open_crown(const fixture *f, double theta, int joint, double pivot[2]) {
  const vs_joint_geom *j = &f->g->joints[joint - 1];
  double sx, sz;
  vs_joint_tangent(j, &sx, &sz);
  pivot[0] = j->px - 0.5 * j->length * sx;
  pivot[1] = j->pz - 0.5 * j->length * sz;
  const double c = cos(theta), s = sin(theta);
  for (int i = joint - 1; i < f->n; i++) {
    double dx = f->g->blocks[i].cx - pivot[0], dz = f->g->blocks[i].cz - pivot[1];
    f->q[3 * i] = pivot[0] + c * dx - s * dz - f->g->blocks[i].cx;
    f->q[3 * i + 1] = pivot[1] + s * dx + c * dz - f->g->blocks[i].cz;
    f->q[3 * i + 2] = theta;
  }
}

static vs_hinge hinge(char label, char side, int first, int last) {
  vs_hinge h;
  memset(&h, 0, sizeof h);
  h.label = label;
  h.side = side;
  h.first = h.onset_first = first;
  h.last = h.onset_last = last;
  h.open = 1;
  h.order = label - 'A' + 1;
  h.delta_closed = NAN;
  return h;
}

static void test_open_joint_and_hinges(void **state) {
  fixture *f = *state;
  const int J = 28; /* the joint at the crown's left face */
  const double theta = -0.1, t = f->g->thickness, open_m = 5e-5;
  double pivot[2];
  open_crown(f, theta, J, pivot);
  double *gi = calloc((size_t)f->g->n_joints, sizeof *gi);
  double *ge = calloc((size_t)f->g->n_joints, sizeof *ge);
  assert_non_null(gi);
  assert_non_null(ge);
  ge[J - 1] = t * fabs(theta); /* the extrados edge of joint 28 opened */
  vs_hinge hs[3] = {hinge('A', 'I', J, J), hinge('B', 'E', 1, 3), hinge('C', 'I', 50, 50)};
  hs[2].open = 0; /* a closed hinge is not drawn */

  char png[128], svg[128];
  path_in(f, "open.png", png, sizeof png);
  path_in(f, "open.svg", svg, sizeof svg);
  vs_error err;
  vs_error_clear(&err);
  const double delta = 0.02, alpha = 30.0 * 3.14159265358979 / 180.0;
  vs_plot_arch_args a = arch_args(f, f->q);
  a.delta_m = delta;
  a.alpha_rad = alpha;
  a.hinges = hs;
  a.n_hinges = 3;
  a.joint_gap_i = gi;
  a.joint_gap_e = ge;
  a.open_m = open_m;
  a.title = "half turned about joint 28";
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_OK);
  assert_int_equal(vs_plot_arch_draw(svg, VS_PLOT_SVG, &a, &err), VS_OK);
  expect_svg(svg);

  vs_plot_frame fr;
  assert_int_equal(vs_plot_arch_frame(&a, &fr, &err), VS_OK);
  image im = load_png(png);
  assert_int_equal(im.w, VS_PLOT_ARCH_WIDTH);
  assert_int_equal(im.h, VS_PLOT_ARCH_HEIGHT);
  assert_true(ink_fraction(&im) > 0.05);

  /* stone at the moved centroids of the crown voussoir (turned) and of the left springer */
  for (int i = 0; i < f->n; i += f->n / 2)
    expect_stone_at(&im, &fr, f->g->blocks[i].cx + f->q[3 * i],
                    f->g->blocks[i].cz + f->q[3 * i + 1]);

  /* the wedge of joint 28 near the extrados, half-way between its faces: red */
  const vs_joint_geom *j = &f->g->joints[J - 1];
  double sx, sz, px, py;
  int c[3];
  vs_joint_tangent(j, &sx, &sz);
  const double eta = 0.85 * t; /* from the intrados */
  double ax = pivot[0] + eta * sx, az = pivot[1] + eta * sz; /* face of the left half */
  double bx = pivot[0] + cos(theta) * eta * sx - sin(theta) * eta * sz;
  double bz = pivot[1] + sin(theta) * eta * sx + cos(theta) * eta * sz; /* turned face */
  vs_plot_to_px(&fr, 0.5 * (ax + bx), 0.5 * (az + bz), &px, &py);
  pixel(&im, px, py, c);
  if (!(c[0] > 150 && c[1] < 90 && c[2] < 110))
    fail_msg("open joint at (%.1f, %.1f): (%d, %d, %d), not red", px, py, c[0], c[1], c[2]);

  /* hinge A on the intrados of joint 28 (the pivot): a blue dot */
  vs_plot_to_px(&fr, pivot[0], pivot[1], &px, &py);
  pixel(&im, px, py, c);
  if (!(c[2] > 150 && c[0] < 90))
    fail_msg("hinge A at (%.1f, %.1f): (%d, %d, %d), not blue", px, py, c[0], c[1], c[2]);
  /* spread hinge B (joints 1-3) on the extrados: its big dot at joint 2's extrados end, orange;
   * the intrados end of joint 2 has no dot */
  const vs_joint_geom *j2 = &f->g->joints[1];
  vs_joint_tangent(j2, &sx, &sz);
  vs_plot_to_px(&fr, j2->px + 0.5 * t * sx, j2->pz + 0.5 * t * sz, &px, &py);
  pixel(&im, px, py, c);
  if (!(c[0] > 190 && c[1] > 90 && c[1] < 160 && c[2] < 50))
    fail_msg("hinge B at (%.1f, %.1f): (%d, %d, %d), not orange", px, py, c[0], c[1], c[2]);
  vs_plot_to_px(&fr, j2->px - 0.5 * t * sx, j2->pz - 0.5 * t * sz, &px, &py);
  pixel(&im, px, py, c);
  assert_false(c[0] > 190 && c[1] > 90 && c[1] < 160 && c[2] < 50);
  /* the closed hinge C (joint 50, intrados) is not drawn: no green there */
  const vs_joint_geom *j50 = &f->g->joints[49];
  double jx, jz;
  vs_joint_tangent(j50, &sx, &sz);
  jx = j50->px - 0.5 * t * sx - pivot[0];
  jz = j50->pz - 0.5 * t * sz - pivot[1];
  vs_plot_to_px(&fr, pivot[0] + cos(theta) * jx - sin(theta) * jz,
                pivot[1] + sin(theta) * jx + cos(theta) * jz, &px, &py);
  pixel(&im, px, py, c);
  assert_false(c[1] > 120 && c[0] < 60 && c[2] < 100);
  cairo_surface_destroy(im.sf);
  free(gi);
  free(ge);
  memset(f->q, 0, (size_t)(3 * f->n) * sizeof *f->q);
}

/* Also: drawing works after the caches were released. */
static void test_reference_without_state(void **state) {
  fixture *f = *state;
  char png[128];
  path_in(f, "one.png", png, sizeof png);
  vs_error err;
  vs_error_clear(&err);
  vs_plot_release();
  const vs_plot_arch_args a = arch_args(f, NULL);
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_OK);
  vs_plot_frame fr;
  assert_int_equal(vs_plot_arch_frame(&a, &fr, &err), VS_OK);
  image im = load_png(png);
  const vs_block *b = &f->g->blocks[f->n / 2];
  expect_stone_at(&im, &fr, b->cx, b->cz);
  cairo_surface_destroy(im.sf);
}

/* ---------------------------------------------------------------------------------------------
 * Errors */

/* The extrados chord's midpoint of voussoir k (0-based), reference configuration: the mean of
 * the extrados ends of its two joints (centre + t/2 along the tangent (-n_z, n_x)). */
static void extrados_mid(const vs_geometry *g, int k, double *x, double *z) {
  *x = *z = 0.0;
  for (int j = k; j <= k + 1; j++) {
    const vs_joint_geom *J = &g->joints[j];
    *x += 0.5 * (J->px - 0.5 * J->length * J->nz);
    *z += 0.5 * (J->pz + 0.5 * J->length * J->nx);
  }
}

/* A live load drawn: an arrow down onto the extrados of the loaded voussoir, so the picture
 * differs from the unloaded one just above that point and nowhere above another voussoir; a
 * load on a block that does not exist is refused. */
static void test_live_load_arrow(void **state) {
  fixture *f = *state;
  const int k = 16;
  double x, z;
  extrados_mid(f->g, k, &x, &z);
  const vs_limit_force load = {k, 0.0, -1.0, x, z};
  char with[128], without[128];
  path_in(f, "load.png", with, sizeof with);
  path_in(f, "noload.png", without, sizeof without);
  vs_error err;
  vs_error_clear(&err);
  vs_plot_arch_args a = arch_args(f, f->q);
  assert_int_equal(vs_plot_arch_draw(without, VS_PLOT_PNG, &a, &err), VS_OK);
  a.loads = &load;
  a.n_loads = 1;
  a.load_note = "live load: a point load";
  assert_int_equal(vs_plot_arch_draw(with, VS_PLOT_PNG, &a, &err), VS_OK);
  vs_plot_frame fr;
  assert_int_equal(vs_plot_arch_frame(&a, &fr, &err), VS_OK);
  image im1 = load_png(with), im0 = load_png(without);
  double px, py;
  vs_plot_to_px(&fr, x, z, &px, &py);
  int c0[3], c1[3], hits = 0;
  for (double dy = 8.0; dy <= 50.0; dy += 6.0) { /* the shaft above the point */
    pixel(&im1, px, py - dy, c1);
    pixel(&im0, px, py - dy, c0);
    hits += c1[1] > c1[0] + 40 && c1[1] > c1[2] + 40 && memcmp(c0, c1, sizeof c0) != 0;
  }
  assert_true(hits >= 6);
  /* above the mirror voussoir nothing changed */
  extrados_mid(f->g, f->n - 1 - k, &x, &z);
  vs_plot_to_px(&fr, x, z, &px, &py);
  for (double dy = 8.0; dy <= 50.0; dy += 6.0) {
    pixel(&im1, px, py - dy, c1);
    pixel(&im0, px, py - dy, c0);
    assert_memory_equal(c0, c1, sizeof c0);
  }
  cairo_surface_destroy(im1.sf);
  cairo_surface_destroy(im0.sf);
  const vs_limit_force bad = {f->n, 0.0, -1.0, x, z};
  a.loads = &bad;
  assert_int_equal(vs_plot_arch_draw(with, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "load 1"));
}

static void test_unwritable_path(void **state) {
  fixture *f = *state;
  char bad[160], dirfile[160];
  snprintf(bad, sizeof bad, "%s/no/such/dir/arch.png", f->dir);
  vs_error err;
  vs_error_clear(&err);
  const vs_plot_arch_args a = arch_args(f, f->q);
  for (int fmt = 0; fmt < 2; fmt++) {
    vs_error_clear(&err);
    assert_int_equal(vs_plot_arch_draw(bad, (vs_plot_format)fmt, &a, &err), VS_ERR_IO);
    assert_int_equal(err.status, VS_ERR_IO);
    assert_non_null(strstr(err.msg, bad));
    assert_false(file_exists(bad));
  }
  /* the directory itself is not a file */
  snprintf(dirfile, sizeof dirfile, "%s", f->dir);
  assert_int_equal(vs_plot_arch_draw(dirfile, VS_PLOT_SVG, &a, &err), VS_ERR_IO);
}

/* A write that fails half-way (the file size limit, like a full disk): VS_ERR_IO with the
 * system's reason, and the partial file is removed. */
static void test_write_error(void **state) {
  fixture *f = *state;
  struct rlimit old, lim;
  assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
  lim = old;
  lim.rlim_cur = 2000; /* bytes: far less than any picture */
  void (*prev)(int) = signal(SIGXFSZ, SIG_IGN); /* the write fails with EFBIG instead */
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
  char png[128], svg[128];
  path_in(f, "big.png", png, sizeof png);
  path_in(f, "big.svg", svg, sizeof svg);
  vs_error e1, e2;
  vs_error_clear(&e1);
  vs_error_clear(&e2);
  vs_plot_arch_args a = arch_args(f, f->q);
  a.title = "too big";
  vs_status s1 = vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &e1);
  vs_status s2 = vs_plot_arch_draw(svg, VS_PLOT_SVG, &a, &e2);
  assert_int_equal(setrlimit(RLIMIT_FSIZE, &old), 0);
  signal(SIGXFSZ, prev);
  assert_int_equal(s1, VS_ERR_IO);
  assert_int_equal(s2, VS_ERR_IO);
  assert_non_null(strstr(e1.msg, png));
  assert_non_null(strstr(e2.msg, svg));
  assert_non_null(strstr(e1.msg, strerror(EFBIG)));
  assert_false(file_exists(png));
  assert_false(file_exists(svg));
}

static void test_invalid_arguments(void **state) {
  fixture *f = *state;
  char png[128];
  path_in(f, "bad.png", png, sizeof png);
  vs_error err;
  vs_error_clear(&err);
  vs_hinge h = hinge('A', 'I', 0, 0);
  const vs_plot_arch_args ok = arch_args(f, f->q);
  vs_plot_arch_args a = ok;
  assert_int_equal(vs_plot_arch_draw(NULL, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, NULL, &err), VS_ERR_INVALID);
  a.g = NULL;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  a = ok;
  a.hinges = &h;
  a.n_hinges = 1;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  h = hinge('A', 'X', 3, 3);
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  a = ok;
  a.n_hinges = -1;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  a = ok;
  a.delta_m = NAN;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  a = ok;
  a.open_m = -1.0;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &a, &err), VS_ERR_INVALID);
  f->q[5] = INFINITY;
  assert_int_equal(vs_plot_arch_draw(png, VS_PLOT_PNG, &ok, &err), VS_ERR_INVALID);
  f->q[5] = 0.0;
  assert_int_equal(vs_plot_arch_draw(png, (vs_plot_format)7, &ok, &err), VS_ERR_INVALID);

  assert_false(file_exists(png));

  assert_int_equal(vs_plot_format_from_path("a/b.SVG"), VS_PLOT_SVG);
  assert_int_equal(vs_plot_format_from_path("b.svg"), VS_PLOT_SVG);
  assert_int_equal(vs_plot_format_from_path("b.png"), VS_PLOT_PNG);
  assert_int_equal(vs_plot_format_from_path("svg"), VS_PLOT_PNG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reference_png_svg),
      cmocka_unit_test(test_open_joint_and_hinges),
      cmocka_unit_test(test_reference_without_state),
      cmocka_unit_test(test_live_load_arrow),
      cmocka_unit_test(test_unwritable_path),
      cmocka_unit_test(test_write_error),
      cmocka_unit_test(test_invalid_arguments),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
