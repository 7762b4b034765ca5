/* Pictures with cairo (PNG, SVG): the deformed arch at true scale, and curves against the
 * support displacement. Drawing only: the caller passes the data; nothing is read or printed.
 * Every picture is drawn by one function on a cairo context; emit() owns the file and surface. */
#define _POSIX_C_SOURCE 200809L /* stat */
#include "voussoir/plot.h"

#include "voussoir/units.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <ctype.h>
#include <errno.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* ---------------------------------------------------------------------------------------------
 * Output: a file, a surface, one drawing function */

typedef void (*draw_fn)(cairo_t *cr, const void *data);

typedef struct {
  FILE *fp;
  int err_no; /* errno of the first failed write, 0 if none */
} sink;

static cairo_status_t sink_write(void *closure, const unsigned char *data, unsigned int length) {
  sink *s = closure;
  if (fwrite(data, 1, length, s->fp) != length) {
    if (s->err_no == 0) s->err_no = errno ? errno : EIO;
    return CAIRO_STATUS_WRITE_ERROR;
  }
  return CAIRO_STATUS_SUCCESS;
}

static vs_status cairo_fail(vs_error *err, const char *path, const char *what,
                            cairo_status_t cst, int err_no) {
  vs_status st = (cst == CAIRO_STATUS_NO_MEMORY) ? VS_ERR_NOMEM : VS_ERR_IO;
  if (err_no != 0)
    return vs_error_set(err, st, "%s: cannot %s: %s (%s)", path, what,
                        cairo_status_to_string(cst), strerror(err_no));
  return vs_error_set(err, st, "%s: cannot %s: %s", path, what, cairo_status_to_string(cst));
}

/* Close the file; on failure (or if st already failed) remove it if it is a regular file (not
 * a device such as /dev/full). */
static vs_status sink_close(sink *s, const char *path, vs_status st, vs_error *err) {
  if (fclose(s->fp) != 0 && st == VS_OK)
    st = vs_error_set(err, VS_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
  struct stat sb;
  if (st != VS_OK && stat(path, &sb) == 0 && S_ISREG(sb.st_mode)) remove(path);
  return st;
}

static vs_status open_sink(sink *s, const char *path, vs_error *err) {
  s->err_no = 0;
  s->fp = fopen(path, "wb");
  if (s->fp == NULL)
    return vs_error_set(err, VS_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
  return VS_OK;
}

/* PNG: draw into an image surface first, so that a drawing failure creates no file. */
static vs_status emit_png(const char *path, int w, int h, draw_fn draw, const void *data,
                          vs_error *err) {
  cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_t *cr = cairo_create(sf);
  draw(cr, data);
  cairo_status_t cst = cairo_status(cr);
  cairo_destroy(cr);
  if (cst != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(sf);
    return cairo_fail(err, path, "draw", cst, 0);
  }
  sink s;
  vs_status st = open_sink(&s, path, err);
  if (st == VS_OK) {
    cst = cairo_surface_write_to_png_stream(sf, sink_write, &s);
    if (cst != CAIRO_STATUS_SUCCESS) st = cairo_fail(err, path, "write PNG", cst, s.err_no);
    st = sink_close(&s, path, st, err);
  }
  cairo_surface_destroy(sf);
  return st;
}

static vs_status emit_svg(const char *path, int w, int h, draw_fn draw, const void *data,
                          vs_error *err) {
  sink s;
  vs_status st = open_sink(&s, path, err);
  if (st != VS_OK) return st;
  cairo_surface_t *sf = cairo_svg_surface_create_for_stream(sink_write, &s, w, h);
  cairo_svg_surface_set_document_unit(sf, CAIRO_SVG_UNIT_PX); /* the PNG's size in a browser */
  cairo_t *cr = cairo_create(sf);
  draw(cr, data);
  cairo_status_t cst = cairo_status(cr);
  cairo_destroy(cr);
  cairo_surface_finish(sf);
  if (cst == CAIRO_STATUS_SUCCESS) cst = cairo_surface_status(sf);
  cairo_surface_destroy(sf);
  if (cst != CAIRO_STATUS_SUCCESS) st = cairo_fail(err, path, "write SVG", cst, s.err_no);
  return sink_close(&s, path, st, err);
}

static vs_status emit(const char *path, vs_plot_format fmt, int w, int h, draw_fn draw,
                      const void *data, vs_error *err) {
  if (fmt == VS_PLOT_SVG) return emit_svg(path, w, h, draw, data, err);
  if (fmt == VS_PLOT_PNG) return emit_png(path, w, h, draw, data, err);
  return vs_error_set(err, VS_ERR_INVALID, "%s: unknown picture format %d", path, (int)fmt);
}

vs_plot_format vs_plot_format_from_path(const char *path) {
  size_t n = path ? strlen(path) : 0;
  if (n >= 4 && path[n - 4] == '.' && tolower((unsigned char)path[n - 3]) == 's' &&
      tolower((unsigned char)path[n - 2]) == 'v' && tolower((unsigned char)path[n - 1]) == 'g')
    return VS_PLOT_SVG;
  return VS_PLOT_PNG;
}

void vs_plot_release(void) {
  cairo_debug_reset_static_data(); /* first: cairo's font caches hold fontconfig patterns */
  FcFini();
}

/* ---------------------------------------------------------------------------------------------
 * Drawing helpers (picture coordinates, px) */

typedef struct {
  double r, g, b;
} rgb;

static const rgb C_THRUST = {0.05, 0.35, 0.85};
static const rgb C_BLACK = {0.0, 0.0, 0.0}, C_WHITE = {1.0, 1.0, 1.0}, C_TEXT = {0.1, 0.1, 0.1},
                 C_GRID = {0.88, 0.88, 0.88}, C_CRACK = {0.80, 0.05, 0.15};

/* Hinge label colours A..E, shared by the arch and the curves; '?' and beyond: grey. */
static rgb label_colour(char label) {
  static const rgb c[5] = {{0.12, 0.37, 0.75}, {0.88, 0.48, 0.0}, {0.10, 0.59, 0.25},
                           {0.48, 0.20, 0.58}, {0.0, 0.55, 0.55}};
  if (label >= 'A' && label <= 'E') return c[label - 'A'];
  return (rgb){0.35, 0.35, 0.35};
}

static void set_rgb(cairo_t *cr, rgb c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

static void font(cairo_t *cr, double size, int bold) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

/* Text s with its ink box aligned at (x, y): ax, ay = 0 left/top, 0.5 centre, 1 right/bottom.
 * halo: a white outline under the text, legible over the drawing. Returns the ink width. */
static double text_at(cairo_t *cr, const char *s, double x, double y, double ax, double ay,
                      rgb c, int halo) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s, &e);
  cairo_move_to(cr, x - (e.x_bearing + ax * e.width), y - (e.y_bearing + ay * e.height));
  cairo_text_path(cr, s);
  if (halo) {
    set_rgb(cr, C_WHITE);
    cairo_set_line_width(cr, 3.5);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke_preserve(cr);
  }
  set_rgb(cr, c);
  cairo_fill(cr);
  return e.width;
}

static void dot(cairo_t *cr, double x, double y, double r, rgb c) {
  cairo_new_path(cr);
  cairo_arc(cr, x, y, r, 0.0, 2.0 * VS_PI);
  set_rgb(cr, c);
  cairo_fill_preserve(cr);
  set_rgb(cr, C_WHITE);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
}

/* An arrow from (x0, y0) to (x1, y1) with a head of size hs. */
static void arrow(cairo_t *cr, double x0, double y0, double x1, double y1, double hs, rgb c) {
  double dx = x1 - x0, dy = y1 - y0, l = hypot(dx, dy);
  if (l <= 0.0) return;
  dx /= l;
  dy /= l;
  set_rgb(cr, c);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1 - 0.8 * hs * dx, y1 - 0.8 * hs * dy);
  cairo_stroke(cr);
  cairo_move_to(cr, x1, y1);
  cairo_line_to(cr, x1 - hs * dx - 0.45 * hs * dy, y1 - hs * dy + 0.45 * hs * dx);
  cairo_line_to(cr, x1 - hs * dx + 0.45 * hs * dy, y1 - hs * dy - 0.45 * hs * dx);
  cairo_close_path(cr);
  cairo_fill(cr);
}

/* 1, 2 or 5 times a power of ten, near range / target. */
static double nice_step(double range, int target) {
  double raw = range / target, p = pow(10.0, floor(log10(raw))), f = raw / p;
  return (f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0) * p;
}

/* ---------------------------------------------------------------------------------------------
 * Arch kinematics (model coordinates, m) */

enum { ARC_MAX = 182 }; /* points per arc: one per degree over at most 180 degrees, plus one */
enum { SUPPORT_PTS = 5 };

/* Point X, Z of body `body` (a block index or a support) moved: x = c + u + R(theta)(X - c). */
static void body_point(const vs_geometry *g, const double *q, const double su[2], int body,
                       double X, double Z, double *x, double *z) {
  if (body < 0 || q == NULL) {
    int moved = body == VS_SUPPORT_RIGHT;
    *x = X + (moved ? su[0] : 0.0);
    *z = Z + (moved ? su[1] : 0.0);
    return;
  }
  const vs_block *b = &g->blocks[body];
  const double *qi = q + 3 * body, c = cos(qi[2]), s = sin(qi[2]);
  double dx = X - b->cx, dz = Z - b->cz;
  *x = b->cx + qi[0] + c * dx - s * dz;
  *z = b->cz + qi[1] + s * dx + c * dz;
}

/* Reference ends of joint j: intrados (eta = 0) and extrados (eta = length). */
static void joint_ends(const vs_joint_geom *j, double e[4]) {
  double sx, sz, h = 0.5 * j->length;
  vs_joint_tangent(j, &sx, &sz);
  e[0] = j->px - h * sx;
  e[1] = j->pz - h * sz;
  e[2] = j->px + h * sx;
  e[3] = j->pz + h * sz;
}

static int arc_points(double dphi) {
  int m = (int)ceil(fabs(dphi) / VS_DEG - 1e-9) + 1;
  if (m < 2) m = 2;
  return m > ARC_MAX ? ARC_MAX : m;
}

/* Outline of block i moved by q (NULL: reference): the intrados arc phi0 -> phi1, then the
 * extrados arc back. x, z hold 2 ARC_MAX points; returns the number written. */
static int block_outline(const vs_geometry *g, const double *q, int i, double *x, double *z) {
  const vs_block *b = &g->blocks[i];
  const double r[2] = {g->radius, g->radius + g->thickness}, su[2] = {0.0, 0.0};
  int m = arc_points(b->phi1 - b->phi0), k = 0;
  for (int side = 0; side < 2; side++)
    for (int p = 0; p < m; p++, k++) {
      double f = (double)(side ? m - 1 - p : p) / (m - 1);
      double phi = b->phi0 + f * (b->phi1 - b->phi0);
      body_point(g, q, su, i, r[side] * sin(phi), r[side] * cos(phi), &x[k], &z[k]);
    }
  return k;
}

/* A skewback abutment under the springing face of the left (left = 1) or right support,
 * translated by u: the face, a level top outward, an outer vertical, a base 2t below the
 * intrados end, an inner vertical back up. Returns SUPPORT_PTS. */
static int support_outline(const vs_geometry *g, int left, const double u[2], double *x,
                           double *z) {
  double e[4];
  joint_ends(&g->joints[left ? 0 : g->n_joints - 1], e);
  const double t = g->thickness, out = (e[2] < e[0]) ? -1.0 : 1.0;
  const double xo = e[2] + out * 1.5 * t, zb = e[1] - 2.0 * t;
  const double px[SUPPORT_PTS] = {e[0], e[2], xo, xo, e[0]};
  const double pz[SUPPORT_PTS] = {e[1], e[3], e[3], zb, zb};
  for (int k = 0; k < SUPPORT_PTS; k++) x[k] = px[k] + u[0], z[k] = pz[k] + u[1];
  return SUPPORT_PTS;
}

static void support_displacement(double delta, double alpha, double su[2]) {
  su[0] = delta * sin(alpha);
  su[1] = -delta * cos(alpha);
}

/* ---------------------------------------------------------------------------------------------
 * Arch: validation and frame */

enum { ARCH_SIDE = 50, ARCH_TOP = 95, ARCH_BOTTOM = 75 }; /* margins, px */

static vs_status check_arch(const vs_geometry *g, const double *q, double delta, double alpha,
                            vs_error *err) {
  if (g == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no geometry");
  if (!(g->radius > 0.0 && g->thickness > 0.0) || g->n_blocks < 1 ||
      g->n_joints != g->n_blocks + 1 || g->joints[0].a != VS_SUPPORT_LEFT ||
      g->joints[g->n_blocks].b != VS_SUPPORT_RIGHT)
    return vs_error_set(err, VS_ERR_INVALID,
                        "plot: the geometry is not an arch (radius, thickness, n + 1 joints)");
  for (int i = 0; i < g->n_blocks; i++) {
    double d = g->blocks[i].phi1 - g->blocks[i].phi0;
    if (!(d > 0.0 && d <= VS_PI + 1e-9))
      return vs_error_set(err, VS_ERR_INVALID, "plot: block %d spans %g rad (allowed: (0, pi])",
                          i + 1, d);
  }
  if (!isfinite(delta) || !isfinite(alpha))
    return vs_error_set(err, VS_ERR_INVALID, "plot: delta = %g m, alpha = %g rad: not finite",
                        delta, alpha);
  for (int k = 0; q != NULL && k < 3 * g->n_blocks; k++)
    if (!isfinite(q[k]))
      return vs_error_set(err, VS_ERR_INVALID, "plot: state entry %d is not finite", k);
  return VS_OK;
}

typedef struct {
  double x0, x1, z0, z1;
} box;

static void box_add(box *b, const double *x, const double *z, int n) {
  for (int k = 0; k < n; k++) {
    b->x0 = fmin(b->x0, x[k]);
    b->x1 = fmax(b->x1, x[k]);
    b->z0 = fmin(b->z0, z[k]);
    b->z1 = fmax(b->z1, z[k]);
  }
}

static void arch_frame(const vs_geometry *g, const double *q, const double su[2], double ground,
                       vs_plot_frame *f) {
  double x[2 * ARC_MAX], z[2 * ARC_MAX];
  const double zero[2] = {0.0, 0.0};
  box b = {INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (int i = 0; i < g->n_blocks; i++) {
    box_add(&b, x, z, block_outline(g, NULL, i, x, z));
    if (q != NULL) box_add(&b, x, z, block_outline(g, q, i, x, z));
  }
  box_add(&b, x, z, support_outline(g, 1, zero, x, z));
  box_add(&b, x, z, support_outline(g, 0, zero, x, z));
  box_add(&b, x, z, support_outline(g, 0, su, x, z));
  if (isfinite(ground)) box_add(&b, &b.x0, &ground, 1);
  const int w = VS_PLOT_ARCH_WIDTH, h = VS_PLOT_ARCH_HEIGHT;
  const double aw = w - 2.0 * ARCH_SIDE, ah = h - ARCH_TOP - ARCH_BOTTOM;
  const double bw = fmax(b.x1 - b.x0, 1e-9), bh = fmax(b.z1 - b.z0, 1e-9);
  f->width = w;
  f->height = h;
  f->scale = fmin(aw / bw, ah / bh);
  f->x0 = ARCH_SIDE + 0.5 * (aw - f->scale * bw) - f->scale * b.x0;
  f->y0 = ARCH_TOP + 0.5 * (ah - f->scale * bh) + f->scale * b.z1;
}

vs_status vs_plot_arch_frame(const vs_geometry *g, const double *q, double delta_m,
                             double alpha_rad, vs_plot_frame *f, vs_error *err) {
  vs_status st = check_arch(g, q, delta_m, alpha_rad, err);
  if (st != VS_OK) return st;
  double su[2];
  support_displacement(delta_m, alpha_rad, su);
  arch_frame(g, q, su, NAN, f);
  return VS_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Arch: drawing */

typedef struct {
  const vs_geometry *g;
  const double *q;
  double delta, alpha, su[2];
  const vs_hinge *hinges;
  int n_hinges;
  const double *gap_i, *gap_e;
  double open;
  const double *N, *M; /* joint forces for the thrust line, or NULL */
  double ground;       /* the ground's level z, m (NaN: none) */
  const char *title;
  vs_plot_frame f;
} arch_data;

/* Path through model points (m) mapped to the picture. */
static void model_path(cairo_t *cr, const vs_plot_frame *f, const double *x, const double *z,
                       int n) {
  cairo_new_path(cr);
  for (int k = 0; k < n; k++) {
    double px, py;
    vs_plot_to_px(f, x[k], z[k], &px, &py);
    cairo_line_to(cr, px, py);
  }
  cairo_close_path(cr);
}

/* The voussoirs in state q (NULL: the reference configuration); faint: the background copy. */
static void draw_blocks(cairo_t *cr, const arch_data *d, const double *q, int faint) {
  static const rgb stone[2] = {{0.85, 0.69, 0.48}, {0.79, 0.60, 0.38}};
  static const rgb ref_fill = {0.93, 0.93, 0.93}, ref_line = {0.72, 0.72, 0.72};
  double x[2 * ARC_MAX], z[2 * ARC_MAX];
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (int i = 0; i < d->g->n_blocks; i++) {
    model_path(cr, &d->f, x, z, block_outline(d->g, q, i, x, z));
    set_rgb(cr, faint ? ref_fill : stone[i % 2]);
    cairo_fill_preserve(cr);
    cairo_set_line_width(cr, faint ? 0.8 : 0.7);
    if (faint)
      set_rgb(cr, ref_line);
    else
      cairo_set_source_rgb(cr, 0.42, 0.31, 0.18);
    cairo_stroke(cr);
  }
}

/* Hatching under a support's base (the ground), from model points (xa, z) to (xb, z). */
static void ground(cairo_t *cr, const vs_plot_frame *f, double xa, double xb, double z) {
  double pa, pb, py;
  vs_plot_to_px(f, fmin(xa, xb), z, &pa, &py);
  vs_plot_to_px(f, fmax(xa, xb), z, &pb, &py);
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  cairo_set_line_width(cr, 1.0);
  for (double px = pa + 4.0; px <= pb + 8.0; px += 7.0) {
    cairo_move_to(cr, px, py);
    cairo_line_to(cr, px - 8.0, py + 8.0);
  }
  cairo_stroke(cr);
}

/* The ground the fall landed on: a line across the picture, hatched below, named. */
static void draw_ground(cairo_t *cr, const arch_data *d) {
  if (!isfinite(d->ground)) return;
  double px, py;
  vs_plot_to_px(&d->f, 0.0, d->ground, &px, &py);
  cairo_set_source_rgb(cr, 0.93, 0.91, 0.86);
  cairo_rectangle(cr, 0.0, py, d->f.width, d->f.height - py);
  cairo_fill(cr);
  cairo_set_source_rgb(cr, 0.62, 0.58, 0.50);
  cairo_set_line_width(cr, 1.0);
  for (double x = 4.0; x <= d->f.width + 12.0; x += 9.0) {
    cairo_move_to(cr, x, py);
    cairo_line_to(cr, x - 12.0, py + 12.0);
  }
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
  cairo_set_line_width(cr, 1.6);
  cairo_move_to(cr, 0.0, py);
  cairo_line_to(cr, d->f.width, py);
  cairo_stroke(cr);
  font(cr, 14.0, 0);
  text_at(cr, "ground", d->f.width - ARCH_SIDE, py + 4.0, 1.0, 0.0, C_TEXT, 0);
}

static void draw_supports(cairo_t *cr, const arch_data *d) {
  double x[SUPPORT_PTS], z[SUPPORT_PTS];
  const double zero[2] = {0.0, 0.0};
  const double dash[2] = {6.0, 4.0};
  /* the right support's fixed position, dashed, under everything */
  model_path(cr, &d->f, x, z, support_outline(d->g, 0, zero, x, z));
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
  cairo_set_line_width(cr, 1.0);
  cairo_set_dash(cr, dash, 2, 0.0);
  cairo_stroke(cr);
  cairo_set_dash(cr, NULL, 0, 0.0);
  for (int left = 1; left >= 0; left--) {
    support_outline(d->g, left, left ? zero : d->su, x, z);
    model_path(cr, &d->f, x, z, SUPPORT_PTS);
    cairo_set_source_rgb(cr, 0.70, 0.70, 0.70);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
    ground(cr, &d->f, x[3], x[4], z[3]);
  }
}

/* The arrow of the right support's displacement, from the fixed face centre to the moved one. */
static void draw_support_arrow(cairo_t *cr, const arch_data *d) {
  const vs_joint_geom *j = &d->g->joints[d->g->n_joints - 1];
  double ax, ay, bx, by;
  vs_plot_to_px(&d->f, j->px, j->pz, &ax, &ay);
  vs_plot_to_px(&d->f, j->px + d->su[0], j->pz + d->su[1], &bx, &by);
  if (hypot(bx - ax, by - ay) > 6.0) arrow(cr, ax, ay, bx, by, 10.0, (rgb){0.2, 0.2, 0.2});
}

/* Moved ends of joint k (0-based) on faces a and b: fa, fb = intrados x, z, extrados x, z. */
static void joint_faces(const arch_data *d, int k, double fa[4], double fb[4]) {
  const vs_joint_geom *j = &d->g->joints[k];
  double e[4];
  joint_ends(j, e);
  for (int p = 0; p < 2; p++) {
    body_point(d->g, d->q, d->su, j->a, e[2 * p], e[2 * p + 1], &fa[2 * p], &fa[2 * p + 1]);
    body_point(d->g, d->q, d->su, j->b, e[2 * p], e[2 * p + 1], &fb[2 * p], &fb[2 * p + 1]);
  }
}

static void draw_open_joints(cairo_t *cr, const arch_data *d) {
  if (d->gap_i == NULL || d->gap_e == NULL) return;
  for (int k = 0; k < d->g->n_joints; k++) {
    if (!(d->gap_i[k] > d->open || d->gap_e[k] > d->open)) continue;
    double fa[4], fb[4], x[4], z[4];
    joint_faces(d, k, fa, fb);
    x[0] = fa[0], z[0] = fa[1], x[1] = fa[2], z[1] = fa[3];
    x[2] = fb[2], z[2] = fb[3], x[3] = fb[0], z[3] = fb[1];
    model_path(cr, &d->f, x, z, 4);
    cairo_set_source_rgba(cr, C_CRACK.r, C_CRACK.g, C_CRACK.b, 0.85);
    cairo_fill(cr);
    double p[4];
    for (int c = 0; c < 4; c++) p[c] = 0.5 * (fa[c] + fb[c]);
    double x0, y0, x1, y1;
    vs_plot_to_px(&d->f, p[0], p[1], &x0, &y0);
    vs_plot_to_px(&d->f, p[2], p[3], &x1, &y1);
    set_rgb(cr, C_CRACK);
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
  }
}

/* Contact point of joint k (0-based) on side 'I' or 'E' (mean of the two moved faces, px), and
 * the picture direction from intrados to extrados there. */
static void hinge_point(const arch_data *d, int k, char side, double *px, double *py,
                        double *ux, double *uy) {
  double fa[4], fb[4];
  joint_faces(d, k, fa, fb);
  int o = side == 'E' ? 2 : 0;
  vs_plot_to_px(&d->f, 0.5 * (fa[o] + fb[o]), 0.5 * (fa[o + 1] + fb[o + 1]), px, py);
  double ix, iy, ex, ey;
  vs_plot_to_px(&d->f, 0.5 * (fa[0] + fb[0]), 0.5 * (fa[1] + fb[1]), &ix, &iy);
  vs_plot_to_px(&d->f, 0.5 * (fa[2] + fb[2]), 0.5 * (fa[3] + fb[3]), &ex, &ey);
  double l = hypot(ex - ix, ey - iy);
  *ux = l > 0.0 ? (ex - ix) / l : 0.0;
  *uy = l > 0.0 ? (ey - iy) / l : -1.0;
}

/* A hinge's name in the picture: "9-I", "44-45-46-I"; beyond four joints "12-...-40-E". */
static void hinge_label(const vs_hinge *hg, char *buf, size_t size) {
  char name[96];
  if (hg->last - hg->first < 4)
    vs_hinge_name(hg, 0, name, sizeof name);
  else
    snprintf(name, sizeof name, "%d-...-%d-%c", hg->first, hg->last, hg->side);
  snprintf(buf, size, "%c  %s", hg->label, name);
}

static void draw_hinges(cairo_t *cr, const arch_data *d) {
  font(cr, 17.0, 1);
  for (int h = 0; h < d->n_hinges; h++) {
    const vs_hinge *hg = &d->hinges[h];
    if (!hg->open) continue;
    rgb c = label_colour(hg->label);
    /* the middle joint, or half-way between the two middle ones of an even spread */
    int m0 = (hg->first + hg->last) / 2, m1 = (hg->first + hg->last + 1) / 2;
    double px, py, ux, uy, qx, qy, vx, vy;
    for (int j = hg->first; j <= hg->last; j++) {
      hinge_point(d, j - 1, hg->side, &px, &py, &ux, &uy);
      if (j != m0 || m1 != m0) dot(cr, px, py, 4.0, c);
    }
    hinge_point(d, m0 - 1, hg->side, &px, &py, &ux, &uy);
    hinge_point(d, m1 - 1, hg->side, &qx, &qy, &vx, &vy);
    px = 0.5 * (px + qx), py = 0.5 * (py + qy);
    dot(cr, px, py, 7.0, c);
    /* the label outside the section on the hinge's side: beyond the extrados for 'E', inside
     * the intrados for 'I'; kept inside the picture */
    double sgn = hg->side == 'E' ? 1.0 : -1.0, dx = sgn * ux, dy = sgn * uy;
    char text[112];
    hinge_label(hg, text, sizeof text);
    cairo_text_extents_t e;
    cairo_text_extents(cr, text, &e);
    double reach = 14.0 + fabs(dx) * 0.5 * e.width + fabs(dy) * 0.5 * e.height;
    double tx = px + dx * reach, ty = py + dy * reach;
    tx = fmax(4.0 + 0.5 * e.width, fmin(d->f.width - 4.0 - 0.5 * e.width, tx));
    ty = fmax(4.0 + 0.5 * e.height, fmin(d->f.height - 4.0 - 0.5 * e.height, ty));
    text_at(cr, text, tx, ty, 0.5, 0.5, c, 1);
  }
}

/* The scale bar: four alternating segments of a round length in mm, bottom left. */
/* The thrust line: through the centre of pressure of every compressed joint, e = M / N from the
 * joint's centre towards the extrados along the moved joint (the mean of its two faces); the
 * resultant of the contact stresses acts there. Broken where a joint carries no compression. */
static void draw_thrust(cairo_t *cr, const arch_data *d) {
  if (d->N == NULL || d->M == NULL) return;
  int pen = 0;
  cairo_new_path(cr);
  for (int k = 0; k < d->g->n_joints; k++) {
    if (!(d->N[k] > 0.0) || !isfinite(d->M[k])) {
      pen = 0;
      continue;
    }
    double fa[4], fb[4];
    joint_faces(d, k, fa, fb);
    const double ix = 0.5 * (fa[0] + fb[0]), iz = 0.5 * (fa[1] + fb[1]);
    const double ex = 0.5 * (fa[2] + fb[2]), ez = 0.5 * (fa[3] + fb[3]);
    const double len = hypot(ex - ix, ez - iz), e = d->M[k] / d->N[k];
    const double x = 0.5 * (ix + ex) + e * (ex - ix) / len, z = 0.5 * (iz + ez) + e * (ez - iz) / len;
    double px, py;
    vs_plot_to_px(&d->f, x, z, &px, &py);
    if (pen) cairo_line_to(cr, px, py);
    else cairo_move_to(cr, px, py);
    pen = 1;
  }
  cairo_set_source_rgb(cr, C_THRUST.r, C_THRUST.g, C_THRUST.b);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);
}

static void draw_scale_bar(cairo_t *cr, const vs_plot_frame *f) {
  double len_mm = nice_step(0.2 * (f->width - 2.0 * ARCH_SIDE) / f->scale / VS_MM, 1);
  double len = len_mm * VS_MM * f->scale, x = ARCH_SIDE, y = f->height - 32.0, hh = 7.0;
  for (int s = 0; s < 4; s++) {
    cairo_rectangle(cr, x + s * len / 4, y, len / 4, hh);
    set_rgb(cr, s % 2 ? C_WHITE : C_TEXT);
    cairo_fill_preserve(cr);
    set_rgb(cr, C_TEXT);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
  }
  char buf[64];
  font(cr, 14.0, 0);
  text_at(cr, "0", x, y - 5.0, 0.5, 1.0, C_TEXT, 0);
  snprintf(buf, sizeof buf, "%g mm", len_mm);
  text_at(cr, buf, x + len, y - 5.0, 0.5, 1.0, C_TEXT, 0);
  text_at(cr, "true scale (x and z)", x + len + 30.0, y + 0.5 * hh, 0.0, 0.5, C_TEXT, 0);
}

/* The key, bottom right: hinge dot, open joint, fixed position. */
static void draw_key(cairo_t *cr, const vs_plot_frame *f, int thrust) {
  font(cr, 14.0, 0);
  double y = f->height - 28.0, x = f->width - ARCH_SIDE;
  x -= text_at(cr, "fixed position of the moved support", x, y, 1.0, 0.5, C_TEXT, 0) + 8.0;
  const double dash[2] = {6.0, 4.0};
  cairo_set_dash(cr, dash, 2, 0.0);
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
  cairo_rectangle(cr, x - 22.0, y - 6.0, 22.0, 12.0);
  cairo_stroke(cr);
  cairo_set_dash(cr, NULL, 0, 0.0);
  x -= 40.0;
  x -= text_at(cr, "open joint", x, y, 1.0, 0.5, C_TEXT, 0) + 8.0;
  cairo_rectangle(cr, x - 6.0, y - 8.0, 6.0, 16.0);
  set_rgb(cr, C_CRACK);
  cairo_fill(cr);
  /* second row: the thrust line and the hinge */
  y -= 24.0;
  x = f->width - ARCH_SIDE;
  if (thrust) {
    x -= text_at(cr, "thrust line (centres of pressure, e = M/N)", x, y, 1.0, 0.5, C_TEXT, 0) + 8.0;
    set_rgb(cr, C_THRUST);
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, x - 24.0, y);
    cairo_line_to(cr, x, y);
    cairo_stroke(cr);
    x -= 40.0;
  }
  x -= text_at(cr, "hinge, on the side in contact (I intrados, E extrados)", x, y, 1.0, 0.5,
               C_TEXT, 0) + 12.0;
  dot(cr, x, y, 6.0, label_colour('?'));
}

static void draw_arch(cairo_t *cr, const void *data) {
  const arch_data *d = data;
  set_rgb(cr, C_WHITE);
  cairo_paint(cr);
  draw_ground(cr, d);
  draw_supports(cr, d);
  draw_blocks(cr, d, NULL, 1);
  draw_blocks(cr, d, d->q, 0);
  draw_open_joints(cr, d);
  draw_thrust(cr, d);
  draw_support_arrow(cr, d);
  draw_hinges(cr, d);

  double y = 36.0;
  if (d->title != NULL && d->title[0] != '\0') {
    font(cr, 21.0, 1);
    text_at(cr, d->title, ARCH_SIDE, y, 0.0, 1.0, C_TEXT, 0);
    y += 28.0;
  }
  char buf[160];
  snprintf(buf, sizeof buf, "delta = %.2f mm (dz %.2f mm, dx %.2f mm), alpha = %.1f deg",
           d->delta / VS_MM, d->delta * cos(d->alpha) / VS_MM, d->delta * sin(d->alpha) / VS_MM,
           d->alpha / VS_DEG);
  font(cr, 16.0, 0);
  text_at(cr, buf, ARCH_SIDE, y, 0.0, 1.0, C_TEXT, 0);
  draw_scale_bar(cr, &d->f);
  draw_key(cr, &d->f, d->N != NULL && d->M != NULL);
}

static vs_status check_hinges(const vs_geometry *g, const vs_hinge *hinges, int n,
                              vs_error *err) {
  if (n < 0 || (n > 0 && hinges == NULL))
    return vs_error_set(err, VS_ERR_INVALID, "plot: %d hinges%s", n,
                        n < 0 ? " (allowed: >= 0)" : " but no array");
  for (int h = 0; h < n; h++) {
    const vs_hinge *hg = &hinges[h];
    if (hg->first < 1 || hg->last < hg->first || hg->last > g->n_joints)
      return vs_error_set(err, VS_ERR_INVALID, "plot: hinge %d at joints %d..%d (allowed: 1..%d)",
                          h + 1, hg->first, hg->last, g->n_joints);
    if (hg->side != 'I' && hg->side != 'E')
      return vs_error_set(err, VS_ERR_INVALID, "plot: hinge %d on side '%c' (allowed: I, E)",
                          h + 1, hg->side);
  }
  return VS_OK;
}

vs_status vs_plot_arch(const char *path, vs_plot_format fmt, const vs_geometry *g,
                       const double *q, double delta_m, double alpha_rad, const vs_hinge *hinges,
                       int n_hinges, const double *joint_gap_i, const double *joint_gap_e,
                       double open_m, const char *title, vs_error *err) {
  return vs_plot_arch_thrust(path, fmt, g, q, delta_m, alpha_rad, hinges, n_hinges, joint_gap_i,
                             joint_gap_e, open_m, NULL, NULL, title, err);
}

vs_status vs_plot_arch_thrust(const char *path, vs_plot_format fmt, const vs_geometry *g,
                              const double *q, double delta_m, double alpha_rad,
                              const vs_hinge *hinges, int n_hinges, const double *joint_gap_i,
                              const double *joint_gap_e, double open_m, const double *joint_N,
                              const double *joint_M, const char *title, vs_error *err) {
  return vs_plot_arch_landed(path, fmt, g, q, delta_m, alpha_rad, hinges, n_hinges, joint_gap_i,
                             joint_gap_e, open_m, joint_N, joint_M, NAN, title, err);
}

vs_status vs_plot_arch_landed(const char *path, vs_plot_format fmt, const vs_geometry *g,
                              const double *q, double delta_m, double alpha_rad,
                              const vs_hinge *hinges, int n_hinges, const double *joint_gap_i,
                              const double *joint_gap_e, double open_m, const double *joint_N,
                              const double *joint_M, double ground_z, const char *title,
                              vs_error *err) {
  if (path == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no file name");
  vs_status st = check_arch(g, q, delta_m, alpha_rad, err);
  if (st == VS_OK) st = check_hinges(g, hinges, n_hinges, err);
  if (st != VS_OK) return st;
  if (!(open_m >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "plot: open = %g m (allowed: >= 0)", open_m);
  arch_data d = {.g = g, .q = q, .delta = delta_m, .alpha = alpha_rad, .hinges = hinges,
                 .n_hinges = n_hinges, .gap_i = joint_gap_i, .gap_e = joint_gap_e,
                 .open = open_m, .N = joint_N, .M = joint_M, .ground = ground_z, .title = title};
  support_displacement(delta_m, alpha_rad, d.su);
  arch_frame(g, q, d.su, ground_z, &d.f);
  return emit(path, fmt, d.f.width, d.f.height, draw_arch, &d, err);
}

/* ---------------------------------------------------------------------------------------------
 * Curves */

enum { CV_LEFT = 95, CV_RIGHT = 30, CV_TOP = 60, CV_BOTTOM = 70, CV_GAP = 40 }; /* px */

typedef struct {
  double lo, hi, step; /* bounds and tick spacing, shown units */
  double first;        /* the first tick, a multiple of step */
  double scale;
  int integer;
} range;

static double axis_scale(const vs_plot_axis *a) {
  return (a == NULL || a->scale == 0.0) ? 1.0 : a->scale;
}

/* The range of the shown values v = data * scale, padded by pad of its width and rounded out to
 * ticks; integer axes step by whole numbers. */
static range make_range(double lo, double hi, const vs_plot_axis *a, double pad) {
  range r = {0.0, 1.0, 0.2, 0.0, axis_scale(a), a != NULL && a->integer};
  if (!(lo <= hi)) lo = 0.0, hi = r.integer ? 2.0 : 1.0;
  if (hi - lo < 1e-12 * fmax(1.0, fabs(lo))) {
    double h = r.integer ? 1.0 : fmax(0.1 * fabs(lo), 1.0);
    lo -= h, hi += h;
  }
  double w = hi - lo;
  lo -= pad * w, hi += pad * w;
  r.step = nice_step(hi - lo, 5);
  if (r.integer && r.step < 1.0) r.step = 1.0;
  r.lo = floor(lo / r.step + 1e-9) * r.step;
  r.hi = ceil(hi / r.step - 1e-9) * r.step;
  if (r.hi <= r.lo) r.hi = r.lo + r.step;
  r.first = r.lo;
  return r;
}

static void data_range(const double *v, int n, double scale, double *lo, double *hi) {
  for (int k = 0; k < n; k++)
    if (isfinite(v[k])) {
      *lo = fmin(*lo, v[k] * scale);
      *hi = fmax(*hi, v[k] * scale);
    }
}

typedef struct {
  const char *title;
  const vs_plot_axis *xa;
  const double *x;
  int n;
  const vs_plot_panel *panels;
  int n_panels;
  const vs_plot_marks *marks;
} curves_data;

typedef struct {
  double x, y, w, h; /* plot rectangle, px */
  range rx, ry;
} panel_box;

static double map_x(const panel_box *b, double v) {
  return b->x + (v * b->rx.scale - b->rx.lo) / (b->rx.hi - b->rx.lo) * b->w;
}
static double map_y(const panel_box *b, double v) {
  return b->y + b->h - (v * b->ry.scale - b->ry.lo) / (b->ry.hi - b->ry.lo) * b->h;
}

static void tick_label(char *buf, size_t size, double v, double step) {
  int dec = step >= 1.0 ? 0 : (int)ceil(-log10(step) - 1e-9);
  if (fabs(v) < 1e-9 * step) v = 0.0;
  snprintf(buf, size, "%.*f", dec, v);
}

/* Grid, frame, ticks and tick labels (x labels only if xlabels). */
static void draw_axes(cairo_t *cr, const panel_box *b, int xlabels) {
  char buf[48];
  font(cr, 13.0, 0);
  cairo_set_line_width(cr, 1.0);
  for (int k = 0; k <= 200; k++) {
    double v = b->rx.first + k * b->rx.step;
    if (v > b->rx.hi + 1e-9 * b->rx.step) break;
    double px = b->x + (v - b->rx.lo) / (b->rx.hi - b->rx.lo) * b->w;
    set_rgb(cr, C_GRID);
    cairo_move_to(cr, px, b->y);
    cairo_line_to(cr, px, b->y + b->h);
    cairo_stroke(cr);
    set_rgb(cr, C_TEXT);
    cairo_move_to(cr, px, b->y + b->h);
    cairo_line_to(cr, px, b->y + b->h + 5.0);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, b->rx.step);
    if (xlabels) text_at(cr, buf, px, b->y + b->h + 9.0, 0.5, 0.0, C_TEXT, 0);
  }
  for (int k = 0; k <= 200; k++) {
    double v = b->ry.first + k * b->ry.step;
    if (v > b->ry.hi + 1e-9 * b->ry.step) break;
    double py = b->y + b->h - (v - b->ry.lo) / (b->ry.hi - b->ry.lo) * b->h;
    set_rgb(cr, C_GRID);
    cairo_move_to(cr, b->x, py);
    cairo_line_to(cr, b->x + b->w, py);
    cairo_stroke(cr);
    set_rgb(cr, C_TEXT);
    cairo_move_to(cr, b->x - 5.0, py);
    cairo_line_to(cr, b->x, py);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, b->ry.step);
    text_at(cr, buf, b->x - 9.0, py, 1.0, 0.5, C_TEXT, 0);
  }
  set_rgb(cr, C_BLACK);
  cairo_set_line_width(cr, 1.2);
  cairo_rectangle(cr, b->x, b->y, b->w, b->h);
  cairo_stroke(cr);
}

static rgb series_colour(const vs_plot_series *s, int index) {
  static const rgb other[6] = {{0.13, 0.13, 0.13}, {0.70, 0.09, 0.17}, {0.13, 0.40, 0.67},
                               {0.55, 0.34, 0.16}, {0.80, 0.30, 0.60}, {0.45, 0.45, 0.10}};
  if (s->name != NULL && s->name[0] >= 'A' && s->name[0] <= 'E' && s->name[1] == '\0')
    return label_colour(s->name[0]);
  return other[index % 6];
}

/* One series: lines between consecutive finite points, markers when the data are few. */
static void draw_series(cairo_t *cr, const panel_box *b, const double *x, const double *y,
                        int n, rgb c) {
  set_rgb(cr, c);
  cairo_set_line_width(cr, 2.0);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  int pen = 0;
  for (int k = 0; k < n; k++) {
    if (!isfinite(x[k]) || !isfinite(y[k])) {
      pen = 0;
      continue;
    }
    double px = map_x(b, x[k]), py = map_y(b, y[k]);
    if (pen)
      cairo_line_to(cr, px, py);
    else
      cairo_move_to(cr, px, py);
    pen = 1;
  }
  cairo_stroke(cr);
  int finite = 0;
  for (int k = 0; k < n; k++) finite += isfinite(x[k]) && isfinite(y[k]);
  for (int k = 0; k < n && finite <= 80; k++)
    if (isfinite(x[k]) && isfinite(y[k])) {
      cairo_new_path(cr);
      cairo_arc(cr, map_x(b, x[k]), map_y(b, y[k]), finite == 1 ? 4.0 : 2.8, 0.0, 2.0 * VS_PI);
      cairo_fill(cr);
    }
}

static int has_data(const double *x, const double *y, int n) {
  for (int k = 0; k < n; k++)
    if (isfinite(x[k]) && isfinite(y[k])) return 1;
  return 0;
}

/* Points of the panel's curves inside the picture rectangle (x, y, w, h). */
static int points_in(const panel_box *b, const vs_plot_panel *p, const double *x, int n,
                     double rx, double ry, double rw, double rh) {
  int count = 0;
  for (int s = 0; s < p->n_series; s++)
    for (int k = 0; k < n; k++) {
      const double *y = p->series[s].y;
      if (!isfinite(x[k]) || !isfinite(y[k])) continue;
      double px = map_x(b, x[k]), py = map_y(b, y[k]);
      count += px >= rx && px <= rx + rw && py >= ry && py <= ry + rh;
    }
  return count;
}

/* Legend of the named series that have data, in the corner of the plot with the fewest points. */
static void draw_legend(cairo_t *cr, const panel_box *b, const vs_plot_panel *p, const double *x,
                        int n) {
  font(cr, 13.0, 0);
  double wmax = 0.0;
  int rows = 0;
  for (int s = 0; s < p->n_series; s++) {
    const char *nm = p->series[s].name;
    if (nm == NULL || nm[0] == '\0' || !has_data(x, p->series[s].y, n)) continue;
    cairo_text_extents_t e;
    cairo_text_extents(cr, nm, &e);
    wmax = fmax(wmax, e.x_advance);
    rows++;
  }
  if (rows == 0) return;
  const double row = 18.0, bw = wmax + 48.0, bh = rows * row + 8.0;
  double lx = b->x + b->w - bw - 8.0, ly = b->y + 8.0;
  int best = -1;
  for (int corner = 0; corner < 4; corner++) { /* top right, top left, bottom right, left */
    double cx = corner % 2 ? b->x + 8.0 : b->x + b->w - bw - 8.0;
    double cy = corner < 2 ? b->y + 8.0 : b->y + b->h - bh - 8.0;
    int c = points_in(b, p, x, n, cx - 4.0, cy - 4.0, bw + 8.0, bh + 8.0);
    if (best < 0 || c < best) best = c, lx = cx, ly = cy;
  }
  cairo_rectangle(cr, lx, ly, bw, bh);
  cairo_set_source_rgba(cr, 1.0, 1.0, 1.0, 0.9);
  cairo_fill_preserve(cr);
  set_rgb(cr, C_GRID);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  int r = 0;
  for (int s = 0; s < p->n_series; s++) {
    const char *nm = p->series[s].name;
    if (nm == NULL || nm[0] == '\0' || !has_data(x, p->series[s].y, n)) continue;
    double yy = ly + 4.0 + (r++ + 0.5) * row;
    set_rgb(cr, series_colour(&p->series[s], s));
    cairo_set_line_width(cr, 2.5);
    cairo_move_to(cr, lx + 8.0, yy);
    cairo_line_to(cr, lx + 32.0, yy);
    cairo_stroke(cr);
    text_at(cr, nm, lx + 40.0, yy, 0.0, 0.5, C_TEXT, 0);
  }
}

/* The marks across the panels from y0 to y1, labelled above y0. */
static void draw_marks(cairo_t *cr, const panel_box *b, const vs_plot_marks *m, double y0,
                       double y1) {
  const double dash[2] = {5.0, 4.0};
  font(cr, 13.0, 0);
  for (int i = 0; i < m->n; i++) {
    if (!isfinite(m->x[i])) continue;
    const double px = map_x(b, m->x[i]);
    if (px < b->x || px > b->x + b->w) continue;
    cairo_set_dash(cr, dash, 2, 0.0);
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    cairo_set_line_width(cr, 1.2);
    cairo_move_to(cr, px, y0);
    cairo_line_to(cr, px, y1);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0.0);
    if (m->label != NULL && m->label[i] != NULL)
      text_at(cr, m->label[i], px + 3.0, y0 + 3.0 + 15.0 * (i % 2), 0.0, 0.0, C_TEXT, 0);
  }
}

/* The second x axis along the top of panel b: ticks of x * x2.scale, its label above. */
static void draw_x2(cairo_t *cr, const panel_box *b, const vs_plot_axis *x2) {
  const double s = axis_scale(x2), lo = b->rx.lo / b->rx.scale * s, hi = b->rx.hi / b->rx.scale * s;
  const double step = nice_step(fabs(hi - lo), 6);
  char buf[48];
  font(cr, 13.0, 0);
  set_rgb(cr, C_TEXT);
  cairo_set_line_width(cr, 1.0);
  for (double v = ceil(fmin(lo, hi) / step - 1e-9) * step; v <= fmax(lo, hi) + 1e-9 * step; v += step) {
    const double px = b->x + (v / s * b->rx.scale - b->rx.lo) / (b->rx.hi - b->rx.lo) * b->w;
    cairo_move_to(cr, px, b->y);
    cairo_line_to(cr, px, b->y - 5.0);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, step);
    text_at(cr, buf, px, b->y - 7.0, 0.5, 1.0, C_TEXT, 0);
  }
  font(cr, 15.0, 0);
  text_at(cr, x2->label, b->x + 0.5 * b->w, b->y - 26.0, 0.5, 1.0, C_TEXT, 0);
}

static void draw_curves(cairo_t *cr, const void *data) {
  const curves_data *d = data;
  const double W = VS_PLOT_CURVES_WIDTH, H = VS_PLOT_CURVES_HEIGHT;
  set_rgb(cr, C_WHITE);
  cairo_paint(cr);
  double top = d->title != NULL && d->title[0] != '\0' ? CV_TOP : 25.0;
  if (top > 25.0) {
    font(cr, 21.0, 1);
    text_at(cr, d->title, CV_LEFT, 36.0, 0.0, 1.0, C_TEXT, 0);
  }
  const int x2 = d->marks != NULL && d->marks->x2.label != NULL;
  if (x2) top += 45.0;
  double xlo = INFINITY, xhi = -INFINITY;
  range rx;
  data_range(d->x, d->n, axis_scale(d->xa), &xlo, &xhi);
  rx = make_range(xlo, xhi, d->xa, 0.0);
  const double ph = (H - top - CV_BOTTOM - (d->n_panels - 1) * CV_GAP) / d->n_panels;
  if (d->marks != NULL) {
    panel_box all = {CV_LEFT, top, W - CV_LEFT - CV_RIGHT, H - top - CV_BOTTOM, rx, rx};
    if (x2) draw_x2(cr, &all, &d->marks->x2);
  }
  for (int p = 0; p < d->n_panels; p++) {
    const vs_plot_panel *pn = &d->panels[p];
    double lo = INFINITY, hi = -INFINITY;
    for (int s = 0; s < pn->n_series; s++)
      data_range(pn->series[s].y, d->n, axis_scale(&pn->y), &lo, &hi);
    panel_box b = {CV_LEFT, top + p * (ph + CV_GAP), W - CV_LEFT - CV_RIGHT, ph, rx,
                   make_range(lo, hi, &pn->y, pn->y.integer ? 0.0 : 0.03)};
    if (pn->y.integer) b.ry.lo -= 0.5, b.ry.hi += 0.5; /* joints off the frame */
    draw_axes(cr, &b, p == d->n_panels - 1);
    cairo_save(cr);
    cairo_rectangle(cr, b.x, b.y, b.w, b.h);
    cairo_clip(cr);
    for (int s = 0; s < pn->n_series; s++)
      draw_series(cr, &b, d->x, pn->series[s].y, d->n, series_colour(&pn->series[s], s));
    cairo_restore(cr);
    draw_legend(cr, &b, pn, d->x, d->n);
    if (pn->y.label != NULL) {
      font(cr, 15.0, 0);
      cairo_save(cr);
      cairo_translate(cr, 22.0, b.y + 0.5 * b.h);
      cairo_rotate(cr, -0.5 * VS_PI);
      text_at(cr, pn->y.label, 0.0, 0.0, 0.5, 0.5, C_TEXT, 0);
      cairo_restore(cr);
    }
  }
  if (d->marks != NULL) {
    panel_box all = {CV_LEFT, top, W - CV_LEFT - CV_RIGHT, H - top - CV_BOTTOM, rx, rx};
    draw_marks(cr, &all, d->marks, top, H - CV_BOTTOM);
  }
  if (d->xa != NULL && d->xa->label != NULL) {
    font(cr, 15.0, 0);
    text_at(cr, d->xa->label, CV_LEFT + 0.5 * (W - CV_LEFT - CV_RIGHT), H - 14.0, 0.5, 1.0,
            C_TEXT, 0);
  }
}

static vs_status check_axis(const vs_plot_axis *a, const char *what, vs_error *err) {
  if (a != NULL && !(isfinite(a->scale) && a->scale >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "plot: %s axis scale %g (allowed: >= 0, 0 = 1)",
                        what, a->scale);
  return VS_OK;
}

vs_status vs_plot_curves(const char *path, vs_plot_format fmt, const char *title,
                         const vs_plot_axis *x_axis, const double *x, int n,
                         const vs_plot_panel *panels, int n_panels, vs_error *err) {
  return vs_plot_curves_marked(path, fmt, title, x_axis, x, n, panels, n_panels, NULL, err);
}

vs_status vs_plot_curves_marked(const char *path, vs_plot_format fmt, const char *title,
                                const vs_plot_axis *x_axis, const double *x, int n,
                                const vs_plot_panel *panels, int n_panels,
                                const vs_plot_marks *marks, vs_error *err) {
  if (marks != NULL && (marks->n < 0 || (marks->n > 0 && marks->x == NULL)))
    return vs_error_set(err, VS_ERR_INVALID, "plot: %d marks (allowed: >= 0, with x)", marks->n);
  if (marks != NULL && check_axis(&marks->x2, "second x", err) != VS_OK) return err->status;
  if (path == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no file name");
  if (x == NULL || n < 1)
    return vs_error_set(err, VS_ERR_INVALID, "plot: %d points (allowed: >= 1, with x)", n);
  if (panels == NULL || n_panels < 1 || n_panels > VS_PLOT_MAX_PANELS)
    return vs_error_set(err, VS_ERR_INVALID, "plot: %d panels (allowed: 1..%d)", n_panels,
                        VS_PLOT_MAX_PANELS);
  vs_status st = check_axis(x_axis, "x", err);
  for (int p = 0; p < n_panels && st == VS_OK; p++) {
    const vs_plot_panel *pn = &panels[p];
    if (pn->series == NULL || pn->n_series < 1 || pn->n_series > VS_PLOT_MAX_SERIES)
      return vs_error_set(err, VS_ERR_INVALID, "plot: panel %d has %d series (allowed: 1..%d)",
                          p + 1, pn->n_series, VS_PLOT_MAX_SERIES);
    for (int s = 0; s < pn->n_series; s++)
      if (pn->series[s].y == NULL)
        return vs_error_set(err, VS_ERR_INVALID, "plot: panel %d series %d has no data", p + 1,
                            s + 1);
    st = check_axis(&pn->y, "y", err);
  }
  if (st != VS_OK) return st;
  curves_data d = {title, x_axis, x, n, panels, n_panels, marks};
  return emit(path, fmt, VS_PLOT_CURVES_WIDTH, VS_PLOT_CURVES_HEIGHT, draw_curves, &d, err);
}
