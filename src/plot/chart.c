/* Curves against one axis (cairo): stacked panels sharing the x axis, with ticks, legends,
 * markers, vertical marks (limit points, the collapse) and an optional second x axis. Drawing
 * only: the caller passes the data. */
#include "voussoir/plot.h"

#include "plot_draw.h"
#include "voussoir/units.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

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
  r.step = vs_plot_nice_step(hi - lo, 5);
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
  vs_plot_font(cr, 13.0, 0);
  cairo_set_line_width(cr, 1.0);
  for (int k = 0; k <= 200; k++) {
    double v = b->rx.first + k * b->rx.step;
    if (v > b->rx.hi + 1e-9 * b->rx.step) break;
    double px = b->x + (v - b->rx.lo) / (b->rx.hi - b->rx.lo) * b->w;
    vs_plot_set_rgb(cr, C_GRID);
    cairo_move_to(cr, px, b->y);
    cairo_line_to(cr, px, b->y + b->h);
    cairo_stroke(cr);
    vs_plot_set_rgb(cr, C_TEXT);
    cairo_move_to(cr, px, b->y + b->h);
    cairo_line_to(cr, px, b->y + b->h + 5.0);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, b->rx.step);
    if (xlabels) vs_plot_text_at(cr, buf, px, b->y + b->h + 9.0, 0.5, 0.0, C_TEXT, 0);
  }
  for (int k = 0; k <= 200; k++) {
    double v = b->ry.first + k * b->ry.step;
    if (v > b->ry.hi + 1e-9 * b->ry.step) break;
    double py = b->y + b->h - (v - b->ry.lo) / (b->ry.hi - b->ry.lo) * b->h;
    vs_plot_set_rgb(cr, C_GRID);
    cairo_move_to(cr, b->x, py);
    cairo_line_to(cr, b->x + b->w, py);
    cairo_stroke(cr);
    vs_plot_set_rgb(cr, C_TEXT);
    cairo_move_to(cr, b->x - 5.0, py);
    cairo_line_to(cr, b->x, py);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, b->ry.step);
    vs_plot_text_at(cr, buf, b->x - 9.0, py, 1.0, 0.5, C_TEXT, 0);
  }
  vs_plot_set_rgb(cr, C_BLACK);
  cairo_set_line_width(cr, 1.2);
  cairo_rectangle(cr, b->x, b->y, b->w, b->h);
  cairo_stroke(cr);
}

static vs_rgb series_colour(const vs_plot_series *s, int index) {
  static const vs_rgb other[6] = {{0.13, 0.13, 0.13}, {0.70, 0.09, 0.17}, {0.13, 0.40, 0.67},
                               {0.55, 0.34, 0.16}, {0.80, 0.30, 0.60}, {0.45, 0.45, 0.10}};
  if (s->name != NULL && s->name[0] >= 'A' && s->name[0] <= 'E' && s->name[1] == '\0')
    return vs_plot_label_colour(s->name[0]);
  return other[index % 6];
}

/* One series: lines between consecutive finite points, markers when the data are few. */
static void draw_series(cairo_t *cr, const panel_box *b, const double *x, const double *y,
                        int n, vs_rgb c) {
  vs_plot_set_rgb(cr, c);
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

/* A marker of a points-only style at (px, py): filled in c, outlined in black. */
static void marker(cairo_t *cr, vs_plot_style st, double px, double py, vs_rgb c) {
  const double r = 6.0;
  cairo_new_path(cr);
  if (st == VS_PLOT_SQUARES) {
    cairo_rectangle(cr, px - 0.85 * r, py - 0.85 * r, 1.7 * r, 1.7 * r);
  } else if (st == VS_PLOT_TRIANGLES) {
    cairo_move_to(cr, px, py - 1.15 * r);
    cairo_line_to(cr, px + r, py + 0.7 * r);
    cairo_line_to(cr, px - r, py + 0.7 * r);
    cairo_close_path(cr);
  } else if (st == VS_PLOT_DIAMONDS) {
    cairo_move_to(cr, px, py - 1.2 * r);
    cairo_line_to(cr, px + r, py);
    cairo_line_to(cr, px, py + 1.2 * r);
    cairo_line_to(cr, px - r, py);
    cairo_close_path(cr);
  } else {
    cairo_arc(cr, px, py, r, 0.0, 2.0 * VS_PI);
  }
  vs_plot_set_rgb(cr, c);
  cairo_fill_preserve(cr);
  vs_plot_set_rgb(cr, C_BLACK);
  cairo_set_line_width(cr, 1.2);
  cairo_stroke(cr);
}

static void draw_markers(cairo_t *cr, const panel_box *b, const double *x, const double *y,
                         int n, vs_plot_style st, vs_rgb c) {
  for (int k = 0; k < n; k++)
    if (isfinite(x[k]) && isfinite(y[k])) marker(cr, st, map_x(b, x[k]), map_y(b, y[k]), c);
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
                        int n, const vs_plot_style *style) {
  vs_plot_font(cr, 13.0, 0);
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
  vs_plot_set_rgb(cr, C_GRID);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  int r = 0;
  for (int s = 0; s < p->n_series; s++) {
    const char *nm = p->series[s].name;
    if (nm == NULL || nm[0] == '\0' || !has_data(x, p->series[s].y, n)) continue;
    double yy = ly + 4.0 + (r++ + 0.5) * row;
    if (style != NULL && style[s] != VS_PLOT_LINE) {
      marker(cr, style[s], lx + 20.0, yy, series_colour(&p->series[s], s));
    } else {
      vs_plot_set_rgb(cr, series_colour(&p->series[s], s));
      cairo_set_line_width(cr, 2.5);
      cairo_move_to(cr, lx + 8.0, yy);
      cairo_line_to(cr, lx + 32.0, yy);
      cairo_stroke(cr);
    }
    vs_plot_text_at(cr, nm, lx + 40.0, yy, 0.0, 0.5, C_TEXT, 0);
  }
}

/* The marks across the panels from y0 to y1, labelled above y0. */
static void draw_marks(cairo_t *cr, const panel_box *b, const vs_plot_marks *m, double y0,
                       double y1) {
  const double dash[2] = {5.0, 4.0};
  vs_plot_font(cr, 13.0, 0);
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
      vs_plot_text_at(cr, m->label[i], px + 3.0, y0 + 3.0 + 15.0 * (i % 2), 0.0, 0.0, C_TEXT, 0);
  }
}

/* The second x axis along the top of panel b: ticks of x * x2.scale, its label above. */
static void draw_x2(cairo_t *cr, const panel_box *b, const vs_plot_axis *x2) {
  const double s = axis_scale(x2), lo = b->rx.lo / b->rx.scale * s, hi = b->rx.hi / b->rx.scale * s;
  const double step = vs_plot_nice_step(fabs(hi - lo), 6);
  char buf[48];
  vs_plot_font(cr, 13.0, 0);
  vs_plot_set_rgb(cr, C_TEXT);
  cairo_set_line_width(cr, 1.0);
  for (double v = ceil(fmin(lo, hi) / step - 1e-9) * step; v <= fmax(lo, hi) + 1e-9 * step;
       v += step) {
    const double px = b->x + (v / s * b->rx.scale - b->rx.lo) / (b->rx.hi - b->rx.lo) * b->w;
    cairo_move_to(cr, px, b->y);
    cairo_line_to(cr, px, b->y - 5.0);
    cairo_stroke(cr);
    tick_label(buf, sizeof buf, v, step);
    vs_plot_text_at(cr, buf, px, b->y - 7.0, 0.5, 1.0, C_TEXT, 0);
  }
  vs_plot_font(cr, 15.0, 0);
  vs_plot_text_at(cr, x2->label, b->x + 0.5 * b->w, b->y - 26.0, 0.5, 1.0, C_TEXT, 0);
}

static void draw_curves(cairo_t *cr, const void *data) {
  const curves_data *d = data;
  const double W = VS_PLOT_CURVES_WIDTH, H = VS_PLOT_CURVES_HEIGHT;
  vs_plot_set_rgb(cr, C_WHITE);
  cairo_paint(cr);
  double top = d->title != NULL && d->title[0] != '\0' ? CV_TOP : 25.0;
  if (top > 25.0) {
    vs_plot_font_to_fit(cr, d->title, 21.0, 1, W - CV_LEFT - CV_RIGHT);
    vs_plot_text_at(cr, d->title, CV_LEFT, 36.0, 0.0, 1.0, C_TEXT, 0);
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
    const vs_plot_style *style = p == 0 && d->marks != NULL ? d->marks->style : NULL;
    for (int s = 0; s < pn->n_series; s++) /* lines first, markers over them */
      if (style == NULL || style[s] == VS_PLOT_LINE)
        draw_series(cr, &b, d->x, pn->series[s].y, d->n, series_colour(&pn->series[s], s));
    for (int s = 0; s < pn->n_series; s++)
      if (style != NULL && style[s] != VS_PLOT_LINE)
        draw_markers(cr, &b, d->x, pn->series[s].y, d->n, style[s],
                     series_colour(&pn->series[s], s));
    cairo_restore(cr);
    draw_legend(cr, &b, pn, d->x, d->n, style);
    if (pn->y.label != NULL) {
      vs_plot_font(cr, 15.0, 0);
      cairo_save(cr);
      cairo_translate(cr, 22.0, b.y + 0.5 * b.h);
      cairo_rotate(cr, -0.5 * VS_PI);
      vs_plot_text_at(cr, pn->y.label, 0.0, 0.0, 0.5, 0.5, C_TEXT, 0);
      cairo_restore(cr);
    }
  }
  if (d->marks != NULL) {
    panel_box all = {CV_LEFT, top, W - CV_LEFT - CV_RIGHT, H - top - CV_BOTTOM, rx, rx};
    draw_marks(cr, &all, d->marks, top, H - CV_BOTTOM);
  }
  if (d->xa != NULL && d->xa->label != NULL) {
    vs_plot_font(cr, 15.0, 0);
    vs_plot_text_at(cr, d->xa->label, CV_LEFT + 0.5 * (W - CV_LEFT - CV_RIGHT), H - 14.0, 0.5, 1.0,
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
    for (int s = 0; s < pn->n_series; s++) {
      if (pn->series[s].y == NULL)
        return vs_error_set(err, VS_ERR_INVALID, "plot: panel %d series %d has no data", p + 1,
                            s + 1);
      const int sty = p == 0 && marks != NULL && marks->style != NULL ? (int)marks->style[s] : 0;
      if (sty < VS_PLOT_LINE || sty > VS_PLOT_DIAMONDS)
        return vs_error_set(err, VS_ERR_INVALID, "plot: panel %d series %d style %d (allowed: "
                            "0..4)", p + 1, s + 1, sty);
    }
    st = check_axis(&pn->y, "y", err);
  }
  if (st != VS_OK) return st;
  curves_data d = {title, x_axis, x, n, panels, n_panels, marks};
  return vs_plot_emit(path, fmt, VS_PLOT_CURVES_WIDTH, VS_PLOT_CURVES_HEIGHT, draw_curves, &d, err);
}
