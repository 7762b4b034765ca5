/* Private to the pictures (plot.c, plot_arch.c, plot_limit.c): the output of one drawing
 * function to a file, colours, text and the small marks the arch pictures draw. Picture
 * coordinates in px. Not installed. */
#ifndef VS_PLOT_DRAW_H
#define VS_PLOT_DRAW_H

#include <cairo.h>

#include "voussoir/plot.h"

/* Draws one picture on cr from data. */
typedef void (*vs_plot_draw_fn)(cairo_t *cr, const void *data);

typedef struct {
  double r, g, b;
} vs_rgb;

static const vs_rgb C_THRUST = {0.05, 0.35, 0.85};
static const vs_rgb C_BLACK = {0.0, 0.0, 0.0}, C_WHITE = {1.0, 1.0, 1.0}, C_TEXT = {0.1, 0.1, 0.1},
                 C_GRID = {0.88, 0.88, 0.88}, C_CRACK = {0.80, 0.05, 0.15};

/* Draw a w x h px picture with draw(data) into path as fmt (PNG: drawn first, so that a
 * drawing failure creates no file; a failed write removes a regular file). */
vs_status vs_plot_emit(const char *path, vs_plot_format fmt, int w, int h, vs_plot_draw_fn draw,
                       const void *data, vs_error *err);

/* Hinge label colours A..E (matplotlib's figures take theirs); '?' and beyond: grey. */
vs_rgb vs_plot_label_colour(char label);
void vs_plot_set_rgb(cairo_t *cr, vs_rgb c);
/* Sans-serif of size px, bold or not. */
void vs_plot_font(cairo_t *cr, double size, int bold);
/* vs_plot_font(size, bold), smaller if s would be wider than w px (a long title stays whole). */
void vs_plot_font_to_fit(cairo_t *cr, const char *s, double size, int bold, double w);
/* Text s with its ink box aligned at (x, y): ax, ay = 0 left/top, 0.5 centre, 1 right/bottom.
 * halo: a white outline under the text, legible over the drawing. Returns the ink width. */
double vs_plot_text_at(cairo_t *cr, const char *s, double x, double y, double ax, double ay,
                       vs_rgb c, int halo);
/* A filled dot of radius r with a white rim. */
void vs_plot_dot(cairo_t *cr, double x, double y, double r, vs_rgb c);
/* An arrow from (x0, y0) to (x1, y1) with a head of size hs. */
void vs_plot_arrow(cairo_t *cr, double x0, double y0, double x1, double y1, double hs, vs_rgb c);
/* 1, 2 or 5 times a power of ten, near range / target. */
double vs_plot_nice_step(double range, int target);

/* The arch's geometry in model coordinates, m (plot_frame.c) */
enum { OUTLINE_MAX = 2048 }; /* points of a block's outline (one per degree of its curves) */
enum { SUPPORT_PTS = 5 };
enum { ARCH_SIDE = 50, ARCH_TOP = 95, ARCH_BOTTOM = 75 }; /* margins, px */

/* Point X, Z of body `body` (a block index or a support) moved: x = c + u + R(theta)(X - c);
 * q NULL: the reference; su the supports' displacements (left ux, uz, right ux, uz), srot
 * the springers' rotations
 * (NULL: none). */
void vs_plot_body_point(const vs_geometry *g, const double *q, const double su[4],
                        const double *srot, int body, double X, double Z, double *x, double *z);
/* Reference ends of joint j: intrados (eta = 0) and extrados (eta = length). */
void vs_plot_joint_ends(const vs_joint_geom *j, double e[4]);
/* Outline of block i moved by q (NULL: reference): its outline (vs_block_outline) with a point
 * at least every degree of a curved edge, at the block's own thickness (thick is not used). x,
 * z hold OUTLINE_MAX points; returns the number written. */
int vs_plot_block_outline(const vs_geometry *g, const double *q, const double *thick, int i,
                          double *x, double *z);
/* A skewback abutment under the springing face of the left (left = 1) or right support,
 * translated by u. Returns SUPPORT_PTS. */
int vs_plot_support_outline(const vs_geometry *g, int left, const double u[2], double *x,
                            double *z);
/* A blocks file's support polygon s (geometry.h: g->supports[s]) moved as its body: the right
 * support by su, a pinned one turned by srot (NULL: none) as vs_plot_body_point. x, z hold
 * OUTLINE_MAX points; returns the number written. */
int vs_plot_support_polygon(const vs_geometry *g, int s, const double su[4], const double *srot,
                            double *x, double *z);
/* The arguments every arch picture checks (geometry, state, delta, alpha). */
vs_status vs_plot_check_arch(const vs_geometry *g, const double *q, double delta, double alpha,
                             vs_error *err);
/* The frame (scale, origin) that shows the arch in state q, its supports and the ground (NaN:
 * none). */
void vs_plot_frame_of(const vs_geometry *g, const double *q, const double *thick,
                      const double su[4], double ground, vs_plot_frame *f);

#endif
