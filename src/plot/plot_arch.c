/* The arch picture (cairo): the deformed arch at true scale with its open joints, hinges and
 * their labels, the supports, the thrust line, the ground of a fall, a scale bar and a key.
 * Drawing only: the caller passes the state. */
#include "voussoir/plot.h"

#include "plot_draw.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Arch: drawing */

typedef struct {
  const vs_geometry *g;
  const double *q;
  double delta, alpha, su[4]; /* the supports' displacements: left ux, uz, right ux, uz */
  const vs_hinge *hinges;
  int n_hinges;
  const double *gap_i, *gap_e;
  double open;
  const double *N, *M; /* joint forces for the thrust line, or NULL */
  double ground;       /* the ground's level z, m (NaN: none) */
  const char *title;
  const double *thick;  /* per block thickness, m, or NULL: the geometry's */
  int pinned[2];        /* left, right support pinned: its springer drawn turned by srot */
  double srot[2];       /* springer rotations, rad (0 for fixed supports) */
  const vs_limit_force *loads; /* the live load, n_loads forces (reference configuration) */
  int n_loads;
  const char *load_note;
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
  static const vs_rgb stone[2] = {{0.85, 0.69, 0.48}, {0.79, 0.60, 0.38}};
  static const vs_rgb ref_fill = {0.93, 0.93, 0.93}, ref_line = {0.72, 0.72, 0.72};
  double x[OUTLINE_MAX], z[OUTLINE_MAX];
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  for (int i = 0; i < d->g->n_blocks; i++) {
    model_path(cr, &d->f, x, z, vs_plot_block_outline(d->g, q, d->thick, i, x, z));
    vs_plot_set_rgb(cr, faint ? ref_fill : stone[i % 2]);
    cairo_fill_preserve(cr);
    cairo_set_line_width(cr, faint ? 0.8 : 0.7);
    if (faint)
      vs_plot_set_rgb(cr, ref_line);
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

/* A pinned support's springer: a plate under the springing face, turned with it about the pin
 * at the face's centre (drawn as a ring). */
static void draw_springer(cairo_t *cr, const arch_data *d, int left) {
  const vs_joint_geom *j = &d->g->joints[vs_geometry_support_joint(d->g, !left)];
  const int body = left ? VS_SUPPORT_LEFT : VS_SUPPORT_RIGHT;
  const double in = left ? -1.0 : 1.0, h = 0.6 * d->g->thickness; /* into the support */
  double e[4], X[4], Z[4], x[4], z[4];
  vs_plot_joint_ends(j, e);
  X[0] = e[0], Z[0] = e[1], X[1] = e[2], Z[1] = e[3];
  X[2] = e[2] + in * h * j->nx, Z[2] = e[3] + in * h * j->nz;
  X[3] = e[0] + in * h * j->nx, Z[3] = e[1] + in * h * j->nz;
  for (int k = 0; k < 4; k++)
    vs_plot_body_point(d->g, NULL, d->su, d->srot, body, X[k], Z[k], &x[k], &z[k]);
  model_path(cr, &d->f, x, z, 4);
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.60);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_set_line_width(cr, 1.2);
  cairo_stroke(cr);
  double px, py, cx, cz;
  vs_plot_body_point(d->g, NULL, d->su, d->srot, body, j->px, j->pz, &cx, &cz);
  vs_plot_to_px(&d->f, cx, cz, &px, &py);
  vs_plot_dot(cr, px, py, 5.0, C_WHITE);
  cairo_new_path(cr);
  cairo_arc(cr, px, py, 5.0, 0.0, 2.0 * VS_PI);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
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
  vs_plot_font(cr, 14.0, 0);
  vs_plot_text_at(cr, "ground", d->f.width - ARCH_SIDE, py + 4.0, 1.0, 0.0, C_TEXT, 0);
}

/* A blocks file's supports: each polygon, the right support's dashed where it was and drawn
 * where it went. */
static void draw_support_polygons(cairo_t *cr, const arch_data *d) {
  double x[OUTLINE_MAX], z[OUTLINE_MAX];
  const double zero[4] = {0.0, 0.0, 0.0, 0.0}, dash[2] = {6.0, 4.0};
  for (int pass = 0; pass < 2; pass++)
    for (int s = 0; s < d->g->n_supports; s++) {
      const int moved = d->g->supports[s].body == VS_SUPPORT_RIGHT;
      if (pass == 0 && !moved) continue;
      model_path(cr, &d->f, x, z, vs_plot_support_polygon(d->g, s, pass ? d->su : zero,
                                                           pass ? d->srot : NULL, x, z));
      if (pass == 0) {
        cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
        cairo_set_line_width(cr, 1.0);
        cairo_set_dash(cr, dash, 2, 0.0);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0.0);
        continue;
      }
      cairo_set_source_rgb(cr, 0.70, 0.70, 0.70);
      cairo_fill_preserve(cr);
      cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
      cairo_set_line_width(cr, 1.2);
      cairo_stroke(cr);
    }
}

static void draw_supports(cairo_t *cr, const arch_data *d) {
  double x[SUPPORT_PTS], z[SUPPORT_PTS];
  const double zero[4] = {0.0, 0.0, 0.0, 0.0};
  const double dash[2] = {6.0, 4.0};
  if (d->g->n_supports > 0) {
    draw_support_polygons(cr, d);
    return;
  }
  /* the right support's fixed position, dashed, under everything (and the left one's if it
   * moves) */
  for (int left = 0; left < 2; left++) {
    if (left && d->su[0] == 0.0 && d->su[1] == 0.0) continue;
    model_path(cr, &d->f, x, z, vs_plot_support_outline(d->g, left, zero, x, z));
    cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
    cairo_set_line_width(cr, 1.0);
    cairo_set_dash(cr, dash, 2, 0.0);
    cairo_stroke(cr);
    cairo_set_dash(cr, NULL, 0, 0.0);
  }
  for (int left = 1; left >= 0; left--) {
    vs_plot_support_outline(d->g, left, left ? d->su : d->su + 2, x, z);
    model_path(cr, &d->f, x, z, SUPPORT_PTS);
    cairo_set_source_rgb(cr, 0.70, 0.70, 0.70);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
    ground(cr, &d->f, x[3], x[4], z[3]);
    if (d->pinned[!left] || d->srot[!left] != 0.0) draw_springer(cr, d, left);
  }
}

/* The arrow of each support's displacement, from the fixed face centre to the moved one. */
static void draw_support_arrow(cairo_t *cr, const arch_data *d) {
  for (int s = 1; s >= 0; s--) {
    const vs_joint_geom *j = &d->g->joints[vs_geometry_support_joint(d->g, s)];
    double ax, ay, bx, by;
    vs_plot_to_px(&d->f, j->px, j->pz, &ax, &ay);
    vs_plot_to_px(&d->f, j->px + d->su[2 * s], j->pz + d->su[2 * s + 1], &bx, &by);
    if (hypot(bx - ax, by - ay) > 6.0)
      vs_plot_arrow(cr, ax, ay, bx, by, 10.0, (vs_rgb){0.2, 0.2, 0.2});
  }
}

/* Moved ends of joint k (0-based) on faces a and b: fa, fb = intrados x, z, extrados x, z. */
static void joint_faces(const arch_data *d, int k, double fa[4], double fb[4]) {
  const vs_joint_geom *j = &d->g->joints[k];
  double e[4];
  vs_plot_joint_ends(j, e);
  for (int p = 0; p < 2; p++) {
    vs_plot_body_point(d->g, d->q, d->su, d->srot, j->a, e[2 * p], e[2 * p + 1], &fa[2 * p],
                       &fa[2 * p + 1]);
    vs_plot_body_point(d->g, d->q, d->su, d->srot, j->b, e[2 * p], e[2 * p + 1], &fb[2 * p],
                       &fb[2 * p + 1]);
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
    vs_plot_set_rgb(cr, C_CRACK);
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
  vs_plot_font(cr, 17.0, 1);
  for (int h = 0; h < d->n_hinges; h++) {
    const vs_hinge *hg = &d->hinges[h];
    if (!hg->open) continue;
    vs_rgb c = vs_plot_label_colour(hg->label);
    /* the middle joint, or half-way between the two middle ones of an even spread */
    int m0 = (hg->first + hg->last) / 2, m1 = (hg->first + hg->last + 1) / 2;
    double px, py, ux, uy, qx, qy, vx, vy;
    for (int j = hg->first; j <= hg->last; j++) {
      hinge_point(d, j - 1, hg->side, &px, &py, &ux, &uy);
      if (j != m0 || m1 != m0) vs_plot_dot(cr, px, py, 4.0, c);
    }
    hinge_point(d, m0 - 1, hg->side, &px, &py, &ux, &uy);
    hinge_point(d, m1 - 1, hg->side, &qx, &qy, &vx, &vy);
    px = 0.5 * (px + qx), py = 0.5 * (py + qy);
    vs_plot_dot(cr, px, py, 7.0, c);
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
    vs_plot_text_at(cr, text, tx, ty, 0.5, 0.5, c, 1);
  }
}

/* Centre of pressure of joint k (model coordinates, m): e = M / N from the centre of the moved
 * joint (the mean of its two faces) towards its extrados; 0 (no point) where the joint carries
 * no compression (N <= 0 or M not finite). */
static int thrust_point(const arch_data *d, int k, double *x, double *z) {
  if (!(d->N[k] > 0.0) || !isfinite(d->M[k])) return 0;
  double fa[4], fb[4];
  joint_faces(d, k, fa, fb);
  const double ix = 0.5 * (fa[0] + fb[0]), iz = 0.5 * (fa[1] + fb[1]);
  const double ex = 0.5 * (fa[2] + fb[2]), ez = 0.5 * (fa[3] + fb[3]);
  const double len = hypot(ex - ix, ez - iz), e = d->M[k] / d->N[k];
  *x = 0.5 * (ix + ex) + e * (ex - ix) / len;
  *z = 0.5 * (iz + ez) + e * (ez - iz) / len;
  return 1;
}

/* The i-th joint along the thrust line: the joints in order, or with piers from the left
 * pier's base up its courses, along the ring, and down the right pier to its base. */
static int thrust_joint(const vs_geometry *g, int i) {
  const int C = g->pier_courses;
  if (C == 0) return i;
  if (i < C) return g->pier_joint[0] + i;
  if (i < C + g->ring) return i - C;
  return g->pier_joint[1] + C - 1 - (i - C - g->ring);
}

/* The thrust line: through the centre of pressure of every compressed joint, where the resultant
 * of the contact stresses acts. Broken where a joint carries no compression. */
static void draw_thrust(cairo_t *cr, const arch_data *d) {
  if (d->N == NULL || d->M == NULL) return;
  int pen = 0;
  cairo_new_path(cr);
  for (int i = 0; i < d->g->n_joints; i++) {
    const int k = thrust_joint(d->g, i);
    double x, z, px, py;
    if (!thrust_point(d, k, &x, &z)) {
      pen = 0;
      continue;
    }
    vs_plot_to_px(&d->f, x, z, &px, &py);
    if (pen) cairo_line_to(cr, px, py);
    else cairo_move_to(cr, px, py);
    pen = 1;
  }
  cairo_set_source_rgb(cr, C_THRUST.r, C_THRUST.g, C_THRUST.b);
  cairo_set_line_width(cr, 2.0);
  cairo_stroke(cr);
}

/* The live load: an arrow down onto each vertical force's point, moved with its block, its
 * length from 24 px (the least force) to 60 px (the greatest). */
static void draw_loads(cairo_t *cr, const arch_data *d) {
  static const vs_rgb c = {0.10, 0.55, 0.15};
  double big = 0.0;
  for (int i = 0; i < d->n_loads; i++)
    if (d->loads[i].fz != 0.0) big = fmax(big, fabs(d->loads[i].fz));
  if (!(big > 0.0)) return;
  for (int i = 0; i < d->n_loads; i++) {
    const vs_limit_force *f = &d->loads[i];
    if (f->fz == 0.0) continue;
    double x, z, px, py;
    vs_plot_body_point(d->g, d->q, d->su, d->srot, f->block, f->px, f->pz, &x, &z);
    vs_plot_to_px(&d->f, x, z, &px, &py);
    const double len = 24.0 + 36.0 * fabs(f->fz) / big;
    const double s = f->fz < 0.0 ? 1.0 : -1.0; /* down: from above */
    vs_plot_arrow(cr, px, py - s * (len + 2.0), px, py - s * 2.0, 9.0, c);
  }
}

/* The scale bar: four alternating segments of a round length in mm, bottom left. */
static void draw_scale_bar(cairo_t *cr, const vs_plot_frame *f) {
  double len_mm = vs_plot_nice_step(0.2 * (f->width - 2.0 * ARCH_SIDE) / f->scale / VS_MM, 1);
  double len = len_mm * VS_MM * f->scale, x = ARCH_SIDE, y = f->height - 32.0, hh = 7.0;
  for (int s = 0; s < 4; s++) {
    cairo_rectangle(cr, x + s * len / 4, y, len / 4, hh);
    vs_plot_set_rgb(cr, s % 2 ? C_WHITE : C_TEXT);
    cairo_fill_preserve(cr);
    vs_plot_set_rgb(cr, C_TEXT);
    cairo_set_line_width(cr, 1.0);
    cairo_stroke(cr);
  }
  char buf[64];
  vs_plot_font(cr, 14.0, 0);
  vs_plot_text_at(cr, "0", x, y - 5.0, 0.5, 1.0, C_TEXT, 0);
  snprintf(buf, sizeof buf, "%g mm", len_mm);
  vs_plot_text_at(cr, buf, x + len, y - 5.0, 0.5, 1.0, C_TEXT, 0);
  vs_plot_text_at(cr, "true scale (x and z)", x + len + 30.0, y + 0.5 * hh, 0.0, 0.5, C_TEXT, 0);
}

/* The key, bottom right: hinge dot, open joint, fixed position. */
static void draw_key(cairo_t *cr, const vs_plot_frame *f, int thrust) {
  vs_plot_font(cr, 14.0, 0);
  double y = f->height - 28.0, x = f->width - ARCH_SIDE;
  x -= vs_plot_text_at(cr, "fixed position of the moved support", x, y, 1.0, 0.5, C_TEXT, 0) + 8.0;
  const double dash[2] = {6.0, 4.0};
  cairo_set_dash(cr, dash, 2, 0.0);
  cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
  cairo_rectangle(cr, x - 22.0, y - 6.0, 22.0, 12.0);
  cairo_stroke(cr);
  cairo_set_dash(cr, NULL, 0, 0.0);
  x -= 40.0;
  x -= vs_plot_text_at(cr, "open joint", x, y, 1.0, 0.5, C_TEXT, 0) + 8.0;
  cairo_rectangle(cr, x - 6.0, y - 8.0, 6.0, 16.0);
  vs_plot_set_rgb(cr, C_CRACK);
  cairo_fill(cr);
  /* second row: the thrust line and the hinge */
  y -= 24.0;
  x = f->width - ARCH_SIDE;
  if (thrust) {
    x -= vs_plot_text_at(cr, "thrust line (centres of pressure, e = M/N)", x, y, 1.0, 0.5, C_TEXT,
                         0) +
         8.0;
    vs_plot_set_rgb(cr, C_THRUST);
    cairo_set_line_width(cr, 2.0);
    cairo_move_to(cr, x - 24.0, y);
    cairo_line_to(cr, x, y);
    cairo_stroke(cr);
    x -= 40.0;
  }
  x -= vs_plot_text_at(cr, "hinge, on the side in contact (I intrados, E extrados)", x, y, 1.0, 0.5,
               C_TEXT, 0) + 12.0;
  vs_plot_dot(cr, x, y, 6.0, vs_plot_label_colour('?'));
}

static void draw_arch(cairo_t *cr, const void *data) {
  const arch_data *d = data;
  vs_plot_set_rgb(cr, C_WHITE);
  cairo_paint(cr);
  draw_ground(cr, d);
  draw_supports(cr, d);
  draw_blocks(cr, d, NULL, 1);
  draw_blocks(cr, d, d->q, 0);
  draw_open_joints(cr, d);
  draw_thrust(cr, d);
  draw_support_arrow(cr, d);
  draw_loads(cr, d);
  draw_hinges(cr, d);

  double y = 36.0;
  if (d->title != NULL && d->title[0] != '\0') {
    vs_plot_font_to_fit(cr, d->title, 21.0, 1, d->f.width - 2.0 * ARCH_SIDE);
    vs_plot_text_at(cr, d->title, ARCH_SIDE, y, 0.0, 1.0, C_TEXT, 0);
    y += 28.0;
  }
  char buf[200];
  if (d->su[0] != 0.0 || d->su[1] != 0.0) /* both supports moved: each one's, outward, down */
    snprintf(buf, sizeof buf,
             "delta = %.2f mm; left support dx %.2f mm, dz %.2f mm; right dx %.2f mm, dz %.2f mm",
             d->delta / VS_MM, -d->su[0] / VS_MM, -d->su[1] / VS_MM, d->su[2] / VS_MM,
             -d->su[3] / VS_MM);
  else
    snprintf(buf, sizeof buf, "delta = %.2f mm (dz %.2f mm, dx %.2f mm), alpha = %.1f deg",
             d->delta / VS_MM, d->delta * cos(d->alpha) / VS_MM, d->delta * sin(d->alpha) / VS_MM,
             d->alpha / VS_DEG);
  vs_plot_font(cr, 16.0, 0);
  vs_plot_text_at(cr, buf, ARCH_SIDE, y, 0.0, 1.0, C_TEXT, 0);
  if (d->load_note != NULL && d->load_note[0] != '\0')
    vs_plot_text_at(cr, d->load_note, ARCH_SIDE, y + 22.0, 0.0, 1.0, C_TEXT, 0);
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

/* a checked and turned into the drawing's data, its frame included. */
static vs_status arch_data_of(const vs_plot_arch_args *a, arch_data *d, vs_error *err) {
  if (a == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no arch");
  const vs_geometry *g = a->g;
  vs_status st = vs_plot_check_arch(g, a->q, a->delta_m, a->alpha_rad, err);
  if (st == VS_OK) st = check_hinges(g, a->hinges, a->n_hinges, err);
  if (st != VS_OK) return st;
  if (!(a->open_m >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "plot: open = %g m (allowed: >= 0)", a->open_m);
  for (int i = 0; a->block_thickness != NULL && i < g->n_blocks; i++)
    if (!(a->block_thickness[i] > 0.0 && isfinite(a->block_thickness[i])))
      return vs_error_set(err, VS_ERR_INVALID, "plot: block %d thickness %g m (allowed: > 0)",
                          i + 1, a->block_thickness[i]);
  for (int i = 0; a->supports != NULL && i < 6; i++)
    if (!isfinite(a->supports[i]))
      return vs_error_set(err, VS_ERR_INVALID, "plot: support %d: value %d is %g (allowed: finite)",
                          i / 3 + 1, i % 3 + 1, a->supports[i]);
  for (int s = 0; s < 2; s++)
    if (!isfinite(a->support_theta[s]) ||
        (!a->pinned[s] && a->support_theta[s] != 0.0 && a->supports == NULL))
      return vs_error_set(err, VS_ERR_INVALID, "plot: support %d rotation %g rad (allowed: finite, "
                          "0 unless pinned)", s + 1, a->support_theta[s]);
  if (a->n_loads < 0 || (a->n_loads > 0 && a->loads == NULL))
    return vs_error_set(err, VS_ERR_INVALID, "plot: %d loads%s (allowed: >= 0)", a->n_loads,
                        a->n_loads < 0 ? "" : " but no array");
  for (int i = 0; i < a->n_loads; i++) {
    const vs_limit_force *f = &a->loads[i];
    if (f->block < 0 || f->block >= g->n_blocks || !isfinite(f->fx) || !isfinite(f->fz) ||
        !isfinite(f->px) || !isfinite(f->pz))
      return vs_error_set(err, VS_ERR_INVALID, "plot: load %d on block %d, force (%g, %g) N at "
                          "(%g, %g) m (allowed: a block 0..%d, finite values)", i + 1, f->block,
                          f->fx, f->fz, f->px, f->pz, g->n_blocks - 1);
  }
  if (a->has_ground && !isfinite(a->ground_z))
    return vs_error_set(err, VS_ERR_INVALID, "plot: ground z = %g m (allowed: finite)",
                        a->ground_z);
  *d = (arch_data){.g = g, .q = a->q, .delta = a->delta_m, .alpha = a->alpha_rad,
                   .hinges = a->hinges, .n_hinges = a->n_hinges, .gap_i = a->joint_gap_i,
                   .gap_e = a->joint_gap_e, .open = a->open_m, .N = a->joint_N, .M = a->joint_M,
                   .title = a->title, .thick = a->block_thickness,
                   .pinned = {a->pinned[0] != 0, a->pinned[1] != 0},
                   .srot = {a->support_theta[0], a->support_theta[1]},
                   .ground = a->has_ground ? a->ground_z : NAN,
                   .loads = a->loads, .n_loads = a->n_loads, .load_note = a->load_note};
  if (a->supports != NULL) { /* both, as given; a fixed one's rotation its own */
    const double *u = a->supports;
    d->su[0] = u[0], d->su[1] = u[1], d->su[2] = u[3], d->su[3] = u[4];
    for (int s = 0; s < 2; s++)
      if (!a->pinned[s]) d->srot[s] = u[3 * s + 2];
  } else {
    d->su[0] = d->su[1] = 0.0;
    vs_support_displacement(vs_support_direction(a->alpha_rad), a->delta_m, d->su + 2);
  }
  vs_plot_frame_of(g, a->q, d->thick, d->su, d->ground, &d->f);
  return VS_OK;
}

vs_status vs_plot_arch_draw(const char *path, vs_plot_format fmt, const vs_plot_arch_args *a,
                            vs_error *err) {
  if (path == NULL) return vs_error_set(err, VS_ERR_INVALID, "plot: no file name");
  arch_data d;
  vs_status st = arch_data_of(a, &d, err);
  if (st != VS_OK) return st;
  return vs_plot_emit(path, fmt, d.f.width, d.f.height, draw_arch, &d, err);
}

vs_status vs_plot_arch_frame(const vs_plot_arch_args *a, vs_plot_frame *f, vs_error *err) {
  arch_data d;
  vs_status st = arch_data_of(a, &d, err);
  if (st == VS_OK) *f = d.f;
  return st;
}

vs_status vs_plot_thrust_points(const vs_plot_arch_args *a, double *x, double *z,
                                vs_error *err) {
  arch_data d;
  vs_status st = arch_data_of(a, &d, err);
  if (st != VS_OK) return st;
  if (a->joint_N == NULL || a->joint_M == NULL || x == NULL || z == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "plot: thrust points need N, M, x and z");
  for (int k = 0; k < d.g->n_joints; k++)
    if (!thrust_point(&d, k, &x[k], &z[k])) x[k] = z[k] = NAN;
  return VS_OK;
}
