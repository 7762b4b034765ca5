/* Pictures with cairo (PNG, SVG): the deformed arch at true scale (the charts are matplotlib's,
 * python/voussoir/figures). Drawing only: the caller passes the data; nothing is read or
 * printed. Every picture is drawn by one function on a cairo context; vs_plot_emit() owns the
 * file and surface. This file: the output and the drawing helpers (plot_draw.h); the arch is
 * drawn by plot_arch.c and plot_limit.c. */
#define _POSIX_C_SOURCE 200809L
#include "voussoir/plot.h"

#include "plot_draw.h"

#include "outpath.h"
#include "voussoir/units.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <ctype.h>
#include <errno.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Output: a file, a surface, one drawing function */

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

/* Close the file; on failure (or if st already failed) remove it. */
static vs_status sink_close(sink *s, const char *path, vs_status st, vs_error *err) {
  if (fclose(s->fp) != 0 && st == VS_OK)
    st = vs_error_set(err, VS_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
  if (st != VS_OK) vs_outpath_discard(path);
  return st;
}

/* The picture's file, created anew: a picture there before is replaced, nothing else (a file
 * that cannot be created, as plot.h says: VS_ERR_IO). */
static vs_status open_sink(sink *s, const char *path, vs_error *err) {
  s->err_no = 0;
  const vs_status st = vs_outpath_fopen(path, &s->fp, err);
  if (st == VS_ERR_INVALID && err != NULL) err->status = VS_ERR_IO;
  return st == VS_ERR_INVALID ? VS_ERR_IO : st;
}

/* PNG: draw into an image surface first, so that a drawing failure creates no file. */
static vs_status emit_png(const char *path, int w, int h, vs_plot_draw_fn draw, const void *data,
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

static vs_status emit_svg(const char *path, int w, int h, vs_plot_draw_fn draw, const void *data,
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

vs_status vs_plot_emit(const char *path, vs_plot_format fmt, int w, int h, vs_plot_draw_fn draw,
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

/* Hinge label colours A..E; '?' and beyond: grey. */
vs_rgb vs_plot_label_colour(char label) {
  static const vs_rgb c[5] = {{0.12, 0.37, 0.75}, {0.88, 0.48, 0.0}, {0.10, 0.59, 0.25},
                           {0.48, 0.20, 0.58}, {0.0, 0.55, 0.55}};
  if (label >= 'A' && label <= 'E') return c[label - 'A'];
  return (vs_rgb){0.35, 0.35, 0.35};
}

void vs_plot_set_rgb(cairo_t *cr, vs_rgb c) { cairo_set_source_rgb(cr, c.r, c.g, c.b); }

void vs_plot_font(cairo_t *cr, double size, int bold) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

/* vs_plot_font(size, bold), smaller if s would be wider than w px (a long title stays whole). */
void vs_plot_font_to_fit(cairo_t *cr, const char *s, double size, int bold, double w) {
  vs_plot_font(cr, size, bold);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s, &e);
  if (e.x_advance > w && e.x_advance > 0.0)
    vs_plot_font(cr, fmax(9.0, size * w / e.x_advance), bold);
}

double vs_plot_text_at(cairo_t *cr, const char *s, double x, double y, double ax, double ay,
                      vs_rgb c, int halo) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, s, &e);
  cairo_move_to(cr, x - (e.x_bearing + ax * e.width), y - (e.y_bearing + ay * e.height));
  cairo_text_path(cr, s);
  if (halo) {
    vs_plot_set_rgb(cr, C_WHITE);
    cairo_set_line_width(cr, 3.5);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke_preserve(cr);
  }
  vs_plot_set_rgb(cr, c);
  cairo_fill(cr);
  return e.width;
}

void vs_plot_dot(cairo_t *cr, double x, double y, double r, vs_rgb c) {
  cairo_new_path(cr);
  cairo_arc(cr, x, y, r, 0.0, 2.0 * VS_PI);
  vs_plot_set_rgb(cr, c);
  cairo_fill_preserve(cr);
  vs_plot_set_rgb(cr, C_WHITE);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
}

/* An arrow from (x0, y0) to (x1, y1) with a head of size hs. */
void vs_plot_arrow(cairo_t *cr, double x0, double y0, double x1, double y1, double hs, vs_rgb c) {
  double dx = x1 - x0, dy = y1 - y0, l = hypot(dx, dy);
  if (l <= 0.0) return;
  dx /= l;
  dy /= l;
  vs_plot_set_rgb(cr, c);
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
double vs_plot_nice_step(double range, int target) {
  double raw = range / target, p = pow(10.0, floor(log10(raw))), f = raw / p;
  return (f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0) * p;
}