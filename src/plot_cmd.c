/* voussoir plot RUN.h5: pictures of a recorded run. The arch at true scale at the reference, at
 * each hinge's onset, at each limit point and settled snap, at the collapse and at the end, and
 * the support reaction and hinge joints against the support displacement. Reads the HDF5 record
 * written by record.c; draws with plot.c. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "h5util.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/imperfections.h"
#include "voussoir/model.h"
#include "voussoir/outpath.h"
#include "voussoir/plot.h"
#include "voussoir/units.h"

int vs_cmd_plot(int argc, char **argv);

static const char *PLOT_USAGE =
    "usage: voussoir plot RUN.h5|SWEEP/summary.h5 [-o DIR] [--svg]\n"
    "Draws the recorded run at true scale: the reference state, each hinge's onset, each limit\n"
    "point and settled snap-through, the collapse and the end of the record (open joints shaded,\n"
    "hinges marked on their side with labels A-E, the support displacement annotated), and the\n"
    "support reaction and hinge joints against the support displacement. Files arch_*.png (or\n"
    ".svg) and curves.png go to DIR (default: RUN_plots next to the record).\n"
    "Given a sweep's summary.h5, draws domain.png: the support displacement at collapse, dx/L\n"
    "against dz/L, one line per k_n through the directions alpha, each point marked by its mode\n"
    "(I, II, III); and sensitivity.png: delta_u/L against alpha, one line per k_n (against k_n\n"
    "when the sweep varies only k_n).\n"
    "plots.json in DIR says what each picture shows: its title, the hinges labelled in each arch\n"
    "picture (label, side, joints), the points of a sweep's pictures.\n";

typedef struct {
  char label, side;
  int first, last, onset_first, onset_last, order, during_fall, open;
  double delta_onset;
} rec_hinge;

typedef struct {
  hid_t file;
  vs_case c;
  vs_geometry *g;
  int rows, nb, nj;
  double *delta, *pos, *gap_i, *gap_e, *react, *jN, *jM;
  signed char *hinge; /* rows x nj: 0 closed, 1 intrados, 2 extrados */
  rec_hinge *h;
  int nh;
  double *limits, *settled;
  int nl;
  double collapse; /* m, NaN if none */
  double ground;   /* the ground the fall landed on, z in m; NaN if none */
  char msg[512];
  double *thick;   /* per voussoir thickness, m, when the case scatters it; else NULL */
  FILE *json;      /* plots.json: what each picture shows (NULL: not written) */
  int n_pictures;  /* entries written to json so far */
} record;

/* The case from /parameters: every attribute of every section group, applied as a --set. */
static herr_t on_attr(hid_t loc, const char *name, const H5A_info_t *info, void *data) {
  (void)info;
  record *r = data;
  char section[64] = "", buf[256];
  ssize_t n = H5Iget_name(loc, section, sizeof section);
  if (n <= 0) return 0;
  const char *sec = strrchr(section, '/');
  sec = sec ? sec + 1 : section;
  hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  double v = NAN;
  if (a >= 0) {
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
  }
  if (!isfinite(v)) return 0;
  snprintf(buf, sizeof buf, "%s.%s=%.17g", sec, name, v);
  vs_error err;
  vs_case_set(&r->c, buf, &err); /* keys the case does not know are ignored */
  return 0;
}

static herr_t on_section(hid_t g, const char *name, const H5L_info_t *info, void *data) {
  (void)info;
  hid_t s = H5Gopen2(g, name, H5P_DEFAULT);
  if (s < 0) return 0;
  hsize_t idx = 0;
  H5Aiterate2(s, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, on_attr, data);
  H5Gclose(s);
  return 0;
}

static void record_free(record *r) {
  vs_geometry_destroy(&r->g);
  free(r->thick);
  free(r->delta);
  free(r->pos);
  free(r->gap_i);
  free(r->gap_e);
  free(r->jN);
  free(r->jM);
  free(r->react);
  free(r->hinge);
  free(r->h);
  free(r->limits);
  free(r->settled);
  if (r->file >= 0) H5Fclose(r->file);
}

static int read_hinges(record *r) {
  const char *path = "/summary/hinges";
  int n = vs_h5_rows(r->file, path);
  if (n <= 0) return 0;
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(rec_hinge)), c1 = H5Tcopy(H5T_C_S1);
  H5Tset_size(c1, 1);
  H5Tset_strpad(c1, H5T_STR_NULLPAD); /* one character, no terminator */
  H5Tinsert(t, "label", HOFFSET(rec_hinge, label), c1);
  H5Tinsert(t, "side", HOFFSET(rec_hinge, side), c1);
  H5Tinsert(t, "first", HOFFSET(rec_hinge, first), H5T_NATIVE_INT);
  H5Tinsert(t, "last", HOFFSET(rec_hinge, last), H5T_NATIVE_INT);
  H5Tinsert(t, "onset_first", HOFFSET(rec_hinge, onset_first), H5T_NATIVE_INT);
  H5Tinsert(t, "onset_last", HOFFSET(rec_hinge, onset_last), H5T_NATIVE_INT);
  H5Tinsert(t, "order", HOFFSET(rec_hinge, order), H5T_NATIVE_INT);
  H5Tinsert(t, "during_fall", HOFFSET(rec_hinge, during_fall), H5T_NATIVE_INT);
  H5Tinsert(t, "open", HOFFSET(rec_hinge, open), H5T_NATIVE_INT);
  H5Tinsert(t, "delta_onset", HOFFSET(rec_hinge, delta_onset), H5T_NATIVE_DOUBLE);
  r->h = calloc((size_t)n, sizeof *r->h);
  hid_t d = H5Dopen2(r->file, path, H5P_DEFAULT);
  int ok = r->h != NULL && d >= 0 && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, r->h) >= 0;
  if (d >= 0) H5Dclose(d);
  H5Tclose(c1);
  H5Tclose(t);
  r->nh = ok ? n : 0;
  return ok ? 0 : -1;
}

static int read_limits(record *r) {
  const char *path = "/summary/limit_points";
  int n = vs_h5_rows(r->file, path);
  if (n <= 0) return 0;
  typedef struct {
    double delta, settled;
  } lim;
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(lim));
  H5Tinsert(t, "delta", HOFFSET(lim, delta), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "delta_settled", HOFFSET(lim, settled), H5T_NATIVE_DOUBLE);
  lim *l = calloc((size_t)n, sizeof *l);
  r->limits = calloc((size_t)n, sizeof(double));
  r->settled = calloc((size_t)n, sizeof(double));
  hid_t d = H5Dopen2(r->file, path, H5P_DEFAULT);
  int ok = l && r->limits && r->settled && d >= 0 && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, l) >= 0;
  for (int i = 0; ok && i < n; i++) {
    r->limits[i] = l[i].delta;
    r->settled[i] = l[i].settled;
  }
  if (d >= 0) H5Dclose(d);
  H5Tclose(t);
  free(l);
  r->nl = ok ? n : 0;
  return ok ? 0 : -1;
}

/* /parameters/support's attribute `name` (a vs_support_kind); fixed when absent. */
static int support_kind(hid_t f, const char *name) {
  int v = VS_SUPPORT_FIXED;
  if (H5Aexists_by_name(f, "/parameters/support", name, H5P_DEFAULT) > 0) {
    hid_t a = H5Aopen_by_name(f, "/parameters/support", name, H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0 || H5Aread(a, H5T_NATIVE_INT, &v) < 0) v = VS_SUPPORT_FIXED;
    if (a >= 0) H5Aclose(a);
  }
  return v == VS_SUPPORT_PINNED ? VS_SUPPORT_PINNED : VS_SUPPORT_FIXED;
}

/* The arch the run simulated: the voussoirs' angles and thicknesses of /imperfections (written
 * when the case scatters them), else those the case's seed draws. */
static vs_status record_geometry(record *r, vs_error *err) {
  vs_imperfections *imp = NULL;
  vs_status st = vs_imperfections_draw(&r->c, &imp, err);
  const size_t nb = st == VS_OK ? (size_t)imp->n_blocks : 0;
  double *buf = st == VS_OK ? malloc((nb > 0 ? nb : 1) * sizeof *buf) : NULL;
  if (buf != NULL && vs_h5_read_doubles(r->file, "/imperfections/voussoir_angle", buf, nb) == 0)
    for (size_t i = 0; i < nb; i++) imp->angle_deg[i] = buf[i] / VS_DEG;
  if (buf != NULL && vs_h5_read_doubles(r->file, "/imperfections/voussoir_thickness", buf, nb) == 0)
    for (size_t i = 0; i < nb; i++) imp->thickness_mm[i] = buf[i] / VS_MM;
  free(buf);
  if (st == VS_OK) st = vs_imperfections_arch(&r->c, imp, &r->g, err);
  if (st == VS_OK && r->c.thickness_cov > 0.0) {
    r->thick = malloc((size_t)imp->n_blocks * sizeof *r->thick);
    if (r->thick == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "out of memory");
    for (int i = 0; r->thick != NULL && i < imp->n_blocks; i++) r->thick[i] = imp->thickness_mm[i] * VS_MM;
  }
  vs_imperfections_destroy(&imp);
  return st;
}

static int record_open(const char *path, record *r) {
  memset(r, 0, sizeof *r);
  r->file = -1;
  r->collapse = NAN;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* errors are reported here, not printed by HDF5 */
  r->file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (r->file < 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: cannot open as HDF5", path);
    return -1;
  }
  vs_case_defaults(&r->c);
  if (H5Lexists(r->file, "/parameters", H5P_DEFAULT) <= 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: not a voussoir record (no /parameters)", path);
    return -1;
  }
  hid_t pg = H5Gopen2(r->file, "/parameters", H5P_DEFAULT);
  hsize_t idx = 0;
  H5Literate(pg, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, on_section, r);
  H5Gclose(pg);
  r->c.left_kind = support_kind(r->file, "left_kind"); /* named choices: not applied as --set */
  r->c.right_kind = support_kind(r->file, "right_kind");
  vs_error err;
  if (record_geometry(r, &err) != VS_OK) {
    snprintf(r->msg, sizeof r->msg, "%.200s: %.300s", path, err.msg);
    return -1;
  }
  r->nb = r->g->n_blocks;
  r->nj = r->g->n_joints;
  r->rows = vs_h5_rows(r->file, "/observables/delta/value");
  if (r->rows <= 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record holds no state", path);
    return -1;
  }
  const size_t n = (size_t)r->rows;
  r->delta = malloc(n * sizeof(double));
  r->pos = malloc(n * 3 * (size_t)r->nb * sizeof(double));
  r->gap_i = malloc(n * (size_t)r->nj * sizeof(double));
  r->gap_e = malloc(n * (size_t)r->nj * sizeof(double));
  r->react = malloc(n * 6 * sizeof(double));
  r->jN = malloc(n * (size_t)r->nj * sizeof(double));
  r->jM = malloc(n * (size_t)r->nj * sizeof(double));
  r->hinge = malloc(n * (size_t)r->nj);
  if (!r->delta || !r->pos || !r->gap_i || !r->gap_e || !r->react || !r->hinge || !r->jN || !r->jM) {
    snprintf(r->msg, sizeof r->msg, "out of memory");
    return -1;
  }
  hid_t hd = H5Dopen2(r->file, "/observables/joint_hinge/value", H5P_DEFAULT);
  const int bad = vs_h5_read_doubles(r->file, "/observables/delta/value", r->delta, n) ||
                  vs_h5_read_doubles(r->file, "/observables/block_position/value", r->pos, n * 3 * (size_t)r->nb) ||
                  vs_h5_read_doubles(r->file, "/observables/joint_gap_i/value", r->gap_i, n * (size_t)r->nj) ||
                  vs_h5_read_doubles(r->file, "/observables/joint_gap_e/value", r->gap_e, n * (size_t)r->nj) ||
                  vs_h5_read_doubles(r->file, "/observables/reactions/value", r->react, n * 6) ||
                  vs_h5_read_doubles(r->file, "/observables/joint_N/value", r->jN, n * (size_t)r->nj) ||
                  vs_h5_read_doubles(r->file, "/observables/joint_M/value", r->jM, n * (size_t)r->nj) || hd < 0 ||
                  H5Dread(hd, H5T_NATIVE_SCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, r->hinge) < 0;
  if (hd >= 0) H5Dclose(hd);
  if (bad || read_hinges(r) || read_limits(r)) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record's time series are incomplete", path);
    return -1;
  }
  vs_h5_read_doubles(r->file, "/summary/collapse/delta", &r->collapse, 1);
  r->ground = NAN;
  if (H5Lexists(r->file, "/summary/ground", H5P_DEFAULT) > 0 &&
      H5Lexists(r->file, "/summary/ground/level", H5P_DEFAULT) > 0 &&
      vs_h5_read_doubles(r->file, "/summary/ground/level", &r->ground, 1) != 0)
    r->ground = NAN;
  return 0;
}

/* First row at or after delta (the last row if none). */
static int row_at(const record *r, double delta) {
  for (int i = 0; i < r->rows; i++)
    if (r->delta[i] >= delta - 1e-12) return i;
  return r->rows - 1;
}

/* Which recorded hinges a picture labels, and where. */
typedef enum {
  PIC_ROW,      /* a state: the open groups of joints, each named after a recorded hinge */
  PIC_ONSET,    /* hinge `focus` forming: it at its onset joints, earlier ones as PIC_ROW */
  PIC_COLLAPSE  /* the collapse: the record's hinges open at its onset, at their joints then */
} pic_kind;

static vs_hinge hinge_of(const rec_hinge *rh, int first, int last) {
  return (vs_hinge){.label = rh->label, .side = rh->side, .first = first, .last = last, .open = 1};
}

/* Distance in joints from a group [a, b] to the nearer of a recorded hinge's onset and collapse
 * positions. */
static int hinge_dist(const rec_hinge *rh, int a, int b) {
  const int m = (a + b) / 2, c = (rh->first + rh->last) / 2, c0 = (rh->onset_first + rh->onset_last) / 2;
  return abs(c - m) < abs(c0 - m) ? abs(c - m) : abs(c0 - m);
}

/* The labelled hinges of a picture of the state at support displacement delta whose open joints
 * are those of row `row`, every label one of /summary/hinges and none twice: PIC_COLLAPSE takes
 * them from the record; otherwise each group of consecutive open joints on one side is paired
 * with the nearest same-side recorded hinge formed by delta (within 6 joints of where it formed
 * or of where it was at the collapse), nearest pairs first; groups left unpaired are not labelled.
 * Hinges of the fall are not named (the end of a fall to rest opens dozens: they are in
 * /summary/hinges and /events); their open joints are shaded. */
static int hinges_at(const record *r, int row, double delta, pic_kind kind, int focus, vs_hinge *out,
                     int cap) {
  int n = 0;
  if (kind == PIC_COLLAPSE) {
    for (int i = 0; i < r->nh && n < cap; i++)
      if (!r->h[i].during_fall && r->h[i].open) out[n++] = hinge_of(&r->h[i], r->h[i].first, r->h[i].last);
    return n;
  }
  if (kind == PIC_ONSET && n < cap)
    out[n++] = hinge_of(&r->h[focus], r->h[focus].onset_first, r->h[focus].onset_last);
  const signed char *hj = r->hinge + (size_t)row * (size_t)r->nj;
  int ga[64], gb[64], ng = 0;
  for (int k = 0; k < r->nj && ng < 64;) {
    int e = k;
    while (hj[k] != 0 && e + 1 < r->nj && hj[e + 1] == hj[k]) e++;
    if (hj[k] != 0) {
      const char side = hj[k] == 1 ? 'I' : 'E';
      const int on_focus = kind == PIC_ONSET && side == r->h[focus].side &&
                           e + 1 >= r->h[focus].onset_first && k + 1 <= r->h[focus].onset_last;
      if (!on_focus) ga[ng] = k + 1, gb[ng++] = e + 1;
    }
    k = e + 1;
  }
  int used_h[64] = {0}, used_g[64] = {0};
  for (;;) { /* nearest pair first */
    int bi = -1, bg = -1, bd = 7;
    for (int g = 0; g < ng; g++)
      for (int i = 0; i < r->nh && i < 64; i++) {
        const rec_hinge *rh = &r->h[i];
        const char side = hj[ga[g] - 1] == 1 ? 'I' : 'E';
        if (used_g[g] || used_h[i] || i == focus || rh->side != side ||
            rh->delta_onset > delta + 1e-9 || rh->during_fall)
          continue;
        const int d = hinge_dist(rh, ga[g], gb[g]);
        if (d < bd) bd = d, bi = i, bg = g;
      }
    if (bi < 0 || n >= cap) break;
    used_h[bi] = used_g[bg] = 1;
    out[n++] = hinge_of(&r->h[bi], ga[bg], gb[bg]);
  }
  return n;
}

/* One state to draw: positions (3 nb), joint gaps, N, M (nj each), the support displacement,
 * the row whose open joints are labelled and how (pic_kind, the forming hinge). */
typedef struct {
  const double *pos, *gap_i, *gap_e, *N, *M;
  double delta;
  int hinge_row;
  pic_kind kind;
  int focus;
} state;

static state state_of_row(const record *r, int row) {
  const size_t o = (size_t)row * (size_t)r->nj;
  return (state){r->pos + (size_t)row * 3 * (size_t)r->nb, r->gap_i + o, r->gap_e + o,
                 r->jN + o, r->jM + o, r->delta[row], row, PIC_ROW, -1};
}

/* A JSON string: the characters of s, quotes and backslashes escaped, controls dropped. */
static void json_str(FILE *f, const char *s) {
  fputc('"', f);
  for (; *s != '\0'; s++)
    if (*s == '"' || *s == '\\') fprintf(f, "\\%c", *s);
    else if ((unsigned char)*s >= 0x20) fputc(*s, f);
  fputc('"', f);
}

/* Start a picture's entry in plots.json: its file and title (the caller adds fields and '}'). */
static void json_picture(record *r, const char *path, const char *title) {
  if (r->json == NULL) return;
  const char *base = strrchr(path, '/');
  fputs(r->n_pictures++ ? ",\n  {\"file\": " : "\n  {\"file\": ", r->json);
  json_str(r->json, base != NULL ? base + 1 : path);
  fputs(", \"title\": ", r->json);
  json_str(r->json, title);
}

/* The labels an arch picture draws, in plots.json. */
static void json_arch(record *r, const char *path, const char *title, const state *st,
                      const vs_plot_arch_args *a, const vs_hinge *h, int nh) {
  if (r->json == NULL) return;
  json_picture(r, path, title);
  fprintf(r->json, ", \"delta_mm\": %.9g, \"support_theta_rad\": [%.9g, %.9g]", st->delta / VS_MM,
          a->support_theta[0], a->support_theta[1]);
  if (a->block_thickness != NULL && r->n_pictures == 1) { /* once, with the first picture */
    fputs(", \"block_thickness_mm\": [", r->json);
    for (int i = 0; i < r->nb; i++) fprintf(r->json, "%s%.9g", i ? ", " : "", a->block_thickness[i] / VS_MM);
    fputc(']', r->json);
  }
  fputs(", \"hinges\": [", r->json);
  for (int i = 0; i < nh; i++) {
    const char lab[2] = {h[i].label, '\0'}; /* beyond Z the letters run into punctuation */
    fputs(i ? ", {\"label\": " : "{\"label\": ", r->json);
    json_str(r->json, lab);
    fprintf(r->json, ", \"side\": \"%c\", \"first\": %d, \"last\": %d}", h[i].side, h[i].first,
            h[i].last);
  }
  fputs("]}", r->json);
}

/* A pinned springer's rotation, which the record does not hold, from the springing joint: for
 * rigid faces the edge openings differ by t sin(relative rotation), so the springer turns by
 * the voussoir's rotation less asin((gap_e - gap_i) / t) (left: the voussoir is on the joint's
 * far side, so plus). */
static void springer_rotations(const record *r, const state *st, vs_plot_arch_args *a) {
  for (int s = 0; s < 2; s++) {
    if (!a->pinned[s]) continue;
    const int k = s ? r->nj - 1 : 0, b = s ? r->nb - 1 : 0;
    const double t = r->g->joints[k].length;
    const double rel = asin(fmax(-1.0, fmin(1.0, (st->gap_e[k] - st->gap_i[k]) / t)));
    a->support_theta[s] = st->pos[3 * b + 2] + (s ? -rel : rel);
  }
}

static int draw_state(record *r, const state *st, const char *dir, const char *name,
                      const char *ext, const char *title) {
  vs_hinge h[32];
  const int nh = hinges_at(r, st->hinge_row, st->delta, st->kind, st->focus, h, 32);
  char path[1200];
  snprintf(path, sizeof path, "%s/arch_%s.%s", dir, name, ext);
  vs_error err;
  vs_error_clear(&err);
  /* the ground in the picture of the end, where the debris lies on it */
  const double ground = strcmp(name, "end") == 0 ? r->ground : NAN;
  vs_plot_arch_args a = {.g = r->g, .q = st->pos, .delta_m = st->delta,
                         .alpha_rad = r->c.alpha_deg * VS_DEG, .hinges = h, .n_hinges = nh,
                         .joint_gap_i = st->gap_i, .joint_gap_e = st->gap_e,
                         .open_m = r->c.open_mm * VS_MM, .joint_N = st->N, .joint_M = st->M,
                         .title = title, .block_thickness = r->thick,
                         .pinned = {r->c.left_kind == VS_SUPPORT_PINNED, r->c.right_kind == VS_SUPPORT_PINNED},
                         .has_ground = isfinite(ground), .ground_z = ground};
  springer_rotations(r, st, &a);
  if (vs_plot_arch_draw(path, vs_plot_format_from_path(path), &a, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    return -1;
  }
  json_arch(r, path, title, st, &a, h, nh);
  printf("  %s\n", path);
  return 0;
}

static int draw_row(record *r, int row, const char *dir, const char *name, const char *ext,
                    const char *what) {
  char title[200];
  snprintf(title, sizeof title, "%s (recorded state at delta = %.3f mm)", what, r->delta[row] / VS_MM);
  const state st = state_of_row(r, row);
  return draw_state(r, &st, dir, name, ext, title);
}

/* a + w (b - a), n values, into out. */
static void lerp(const double *a, const double *b, double w, size_t n, double *out) {
  for (size_t k = 0; k < n; k++) out[k] = a[k] + w * (b[k] - a[k]);
}

/* The state at support displacement delta: a recorded one if delta falls on a row, else
 * interpolated linearly between the two rows around it (the title says which); its hinges
 * labelled as kind and focus say. */
static int draw_at(record *r, double delta, pic_kind kind, int focus, const char *dir,
                   const char *name, const char *ext, const char *what) {
  const int j = row_at(r, delta);
  char title[240];
  state st = state_of_row(r, j);
  st.kind = kind, st.focus = focus;
  if (j == 0 || fabs(r->delta[j] - delta) <= 1e-9 || !(r->delta[j - 1] < delta)) {
    snprintf(title, sizeof title, "%s (recorded state at delta = %.3f mm)", what, r->delta[j] / VS_MM);
    return draw_state(r, &st, dir, name, ext, title);
  }
  const size_t nq = 3 * (size_t)r->nb, nj = (size_t)r->nj;
  double *buf = malloc((nq + 4 * nj) * sizeof *buf);
  if (buf == NULL) return draw_state(r, &st, dir, name, ext, what);
  const state a = state_of_row(r, j - 1), b = state_of_row(r, j);
  const double w = (delta - a.delta) / (b.delta - a.delta);
  lerp(a.pos, b.pos, w, nq, buf);
  lerp(a.gap_i, b.gap_i, w, nj, buf + nq);
  lerp(a.gap_e, b.gap_e, w, nj, buf + nq + nj);
  lerp(a.N, b.N, w, nj, buf + nq + 2 * nj);
  lerp(a.M, b.M, w, nj, buf + nq + 3 * nj);
  st = (state){buf, buf + nq, buf + nq + nj, buf + nq + 2 * nj, buf + nq + 3 * nj, delta, j, kind, focus};
  snprintf(title, sizeof title, "%s at delta = %.3f mm (interpolated between the states at %.3f "
           "and %.3f mm)", what, delta / VS_MM, a.delta / VS_MM, b.delta / VS_MM);
  const int rc = draw_state(r, &st, dir, name, ext, title);
  free(buf);
  return rc;
}

static int draw_curves(record *r, const char *dir, const char *ext) {
  const size_t n = (size_t)r->rows;
  double *reac = malloc(4 * n * sizeof(double)), *joint[5];
  vs_plot_series hs[5];
  int ns = 0, rc = 0;
  static const int COL[4] = {0, 1, 3, 4}; /* left Fx, Fz, right Fx, Fz of the supports on the arch */
  for (size_t i = 0; reac && i < n; i++)
    for (int c = 0; c < 4; c++) reac[(size_t)c * n + i] = r->react[6 * i + (size_t)COL[c]];
  for (int l = 0; l < 5; l++) {
    joint[l] = malloc(n * sizeof(double));
    if (joint[l] == NULL) continue;
    int any = 0;
    for (size_t i = 0; i < n; i++) {
      vs_hinge h[32];
      const int nh = hinges_at(r, (int)i, r->delta[i], PIC_ROW, -1, h, 32);
      joint[l][i] = NAN;
      for (int k = 0; k < nh; k++)
        if (h[k].label == 'A' + l) {
          joint[l][i] = 0.5 * (h[k].first + h[k].last);
          any = 1;
        }
    }
    static const char *names[5] = {"A", "B", "C", "D", "E"};
    if (any) hs[ns++] = (vs_plot_series){names[l], joint[l]};
  }
  vs_plot_series rs[4] = {{"left support, horizontal H (x right)", reac},
                          {"left support, vertical V (z up)", reac + n},
                          {"right (moved) support, horizontal H", reac + 2 * n},
                          {"right (moved) support, vertical V", reac + 3 * n}};
  vs_plot_panel panels[2] = {{{"support reactions on the arch (N)", 1.0, 0}, rs, 4},
                             {{"hinge joint", 1.0, 1}, hs, ns}};
  vs_plot_axis x = {"support displacement delta (mm)", 1e3, 0};
  char lbl[8][32];
  const char *labels[8];
  double mx[8];
  int nm = 0;
  for (int i = 0; i < r->nl && nm < 8; i++, nm++) {
    snprintf(lbl[nm], sizeof lbl[nm], "limit %d", i + 1);
    labels[nm] = lbl[nm], mx[nm] = r->limits[i];
  }
  if (isfinite(r->collapse) && nm < 8) labels[nm] = "collapse", mx[nm++] = r->collapse;
  const double L = r->g->span, ca = cos(r->c.alpha_deg * VS_DEG);
  vs_plot_marks marks = {nm, mx, labels, {NULL, 1.0, 0}, NULL};
  if (fabs(ca) > 1e-9 && L > 0.0) marks.x2 = (vs_plot_axis){"dz/L (%)", 100.0 * ca / L, 0};
  char path[1200];
  snprintf(path, sizeof path, "%s/curves.%s", dir, ext);
  vs_error err;
  vs_error_clear(&err);
  if (reac == NULL ||
      vs_plot_curves_marked(path, vs_plot_format_from_path(path),
                            "Reactions and hinges against the support displacement", &x, r->delta,
                            (int)n, panels, ns > 0 ? 2 : 1, &marks, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", reac ? err.msg : "out of memory");
    rc = -1;
  } else {
    json_picture(r, path, "Reactions and hinges against the support displacement");
    if (r->json != NULL) {
      fputs(", \"series\": [", r->json);
      for (int i = 0; i < 4; i++) fprintf(r->json, "%s\"%s\"", i ? ", " : "", rs[i].name);
      for (int i = 0; i < ns; i++) fprintf(r->json, ", \"%s\"", hs[i].name);
      fputs("], \"marks_mm\": [", r->json);
      for (int i = 0; i < nm; i++) fprintf(r->json, "%s%.9g", i ? ", " : "", mx[i] / VS_MM);
      fputs("]}", r->json);
    }
    printf("  %s\n", path);
  }
  free(reac);
  for (int l = 0; l < 5; l++) free(joint[l]);
  return rc;
}

/* --- a sweep's summary table: the limit displacement domain, the k_n sensitivity --- */

typedef struct {
  double kn, alpha, dz, dx; /* N/mm^3, deg, % of L, % of L */
  char *status, *mode;
} sweep_pt;

static int cmp_pt(const void *pa, const void *pb) {
  const sweep_pt *a = pa, *b = pb;
  if (a->kn != b->kn) return a->kn < b->kn ? -1 : 1;
  return (a->alpha > b->alpha) - (a->alpha < b->alpha);
}

/* Rows of /summary (a compound dataset written by voussoir sweep); -1 if it is not one. Columns
 * the sweep did not vary (k_n, alpha) read as NaN. */
static int read_sweep(hid_t f, sweep_pt **out) {
  *out = NULL;
  H5O_info_t info;
  if (H5Lexists(f, "/summary", H5P_DEFAULT) <= 0 ||
      H5Oget_info_by_name2(f, "/summary", &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0 ||
      info.type != H5O_TYPE_DATASET)
    return -1;
  hid_t d = H5Dopen2(f, "/summary", H5P_DEFAULT), ft = H5Dget_type(d);
  const int n = vs_h5_rows(f, "/summary");
  hid_t str = H5Tcopy(H5T_C_S1);
  H5Tset_size(str, H5T_VARIABLE);
  H5Tset_cset(str, H5T_CSET_UTF8);
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(sweep_pt));
  if (H5Tget_member_index(ft, "joints.kn_N_mm3") >= 0)
    H5Tinsert(t, "joints.kn_N_mm3", HOFFSET(sweep_pt, kn), H5T_NATIVE_DOUBLE);
  if (H5Tget_member_index(ft, "support.alpha_deg") >= 0)
    H5Tinsert(t, "support.alpha_deg", HOFFSET(sweep_pt, alpha), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dz_over_L_pct", HOFFSET(sweep_pt, dz), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dx_over_L_pct", HOFFSET(sweep_pt, dx), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "status", HOFFSET(sweep_pt, status), str);
  H5Tinsert(t, "mode", HOFFSET(sweep_pt, mode), str);
  sweep_pt *p = n > 0 ? calloc((size_t)n, sizeof *p) : NULL;
  for (int i = 0; p != NULL && i < n; i++) p[i].kn = p[i].alpha = NAN;
  const int ok = p != NULL && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, p) >= 0;
  H5Tclose(t), H5Tclose(str), H5Tclose(ft), H5Dclose(d);
  if (!ok) {
    free(p);
    return -1;
  }
  *out = p;
  return n;
}

/* The modes a sweep's points are marked by; the last entry: a collapse no mode describes. */
static const char *const MODES[4] = {"I", "II", "III", ""};
static const char *const MODE_NAMES[4] = {"mode I", "mode II", "mode III", "no mode (sides match none)"};
static const vs_plot_style MODE_STYLE[4] = {VS_PLOT_CIRCLES, VS_PLOT_SQUARES, VS_PLOT_TRIANGLES,
                                            VS_PLOT_DIAMONDS};

static int mode_index(const char *m) {
  for (int i = 0; i < 3; i++)
    if (m != NULL && strcmp(m, MODES[i]) == 0) return i;
  return 3;
}

static int same_kn(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

/* Series of a sweep picture over the m points p (sorted by k_n, then alpha): one line per k_n
 * (per_kn = 0: one line through all) through value[i], then one marker series per mode present. y holds (lines + 4) m values;
 * names (VS_PLOT_MAX_SERIES x 48) the lines' names; style each series' style. Returns the
 * series count. */
static int sweep_series(const sweep_pt *p, int m, const double *value, int per_kn, double *y,
                        char (*names)[48], vs_plot_series *s, vs_plot_style *style) {
  int ns = 0;
  for (int i = 0; i < m; i++) {
    if (i == 0 || (per_kn && !same_kn(p[i].kn, p[i - 1].kn))) {
      if (ns == VS_PLOT_MAX_SERIES - 4) break;
      double *col = y + (size_t)ns * (size_t)m;
      for (int k = 0; k < m; k++) col[k] = NAN;
      if (!per_kn) names[ns][0] = '\0';
      else snprintf(names[ns], 48, isnan(p[i].kn) ? "k_n of the case" : "k_n = %g N/mm^3", p[i].kn);
      s[ns] = (vs_plot_series){names[ns], col};
      style[ns++] = VS_PLOT_LINE;
    }
    y[(size_t)(ns - 1) * (size_t)m + (size_t)i] = value[i];
  }
  for (int md = 0; md < 4; md++) {
    double *col = y + (size_t)ns * (size_t)m;
    int any = 0;
    for (int i = 0; i < m; i++) {
      col[i] = mode_index(p[i].mode) == md ? value[i] : NAN;
      any |= mode_index(p[i].mode) == md;
    }
    if (any) style[ns] = MODE_STYLE[md], s[ns++] = (vs_plot_series){MODE_NAMES[md], col};
  }
  return ns;
}

static int distinct(const sweep_pt *p, int m, int alpha) {
  int n = 0;
  for (int i = 0; i < m; i++) {
    int seen = 0;
    for (int k = 0; k < i && !seen; k++)
      seen = alpha ? same_kn(p[k].alpha, p[i].alpha) : same_kn(p[k].kn, p[i].kn);
    n += !seen;
  }
  return n;
}

/* plots.json of a sweep: every collapse point as drawn. */
static void sweep_json(FILE *f, const char *domain, const char *sens, const sweep_pt *p, int m,
                       const double *du) {
  if (f == NULL) return;
  const char *files[2] = {domain, sens};
  for (int pic = 0; pic < 2; pic++) {
    if (files[pic] == NULL) continue;
    const char *base = strrchr(files[pic], '/');
    fprintf(f, "%s\n  {\"file\": ", pic ? "," : "");
    json_str(f, base != NULL ? base + 1 : files[pic]);
    fputs(", \"points\": [", f);
    for (int i = 0; i < m; i++) {
      fprintf(f, "%s\n    {\"kn_N_mm3\": ", i ? "," : "");
      isnan(p[i].kn) ? fputs("null", f) : fprintf(f, "%.9g", p[i].kn);
      fputs(", \"alpha_deg\": ", f);
      isnan(p[i].alpha) ? fputs("null", f) : fprintf(f, "%.9g", p[i].alpha);
      if (pic == 0) fprintf(f, ", \"dz_over_L_pct\": %.9g, \"dx_over_L_pct\": %.9g", p[i].dz, p[i].dx);
      else fprintf(f, ", \"delta_u_over_L_pct\": %.9g", du[i]);
      fprintf(f, ", \"mode\": \"%s\"}", MODES[mode_index(p[i].mode)]);
    }
    fputs("]}", f);
  }
}

/* domain.EXT: collapse dx/L against dz/L, a line per k_n through the directions, the points
 * marked by mode; sensitivity.EXT: delta_u/L against alpha, a line per k_n (against k_n when
 * the sweep varies only k_n). */
static int plot_sweep(const char *path, hid_t f, const char *dir, const char *ext, FILE *json) {
  sweep_pt *p;
  const int n = read_sweep(f, &p);
  if (n < 0) {
    fprintf(stderr, "voussoir plot: %s: /summary is not a sweep's summary table\n", path);
    return -1;
  }
  int m = 0, rc = 0;
  for (int i = 0; i < n; i++) { /* collapses only */
    const int keep = p[i].status != NULL && strcmp(p[i].status, "collapse") == 0 && isfinite(p[i].dz);
    free(p[i].status); /* HDF5 allocates variable-length strings with malloc */
    p[i].status = NULL;
    if (keep) p[m++] = p[i];
    else free(p[i].mode);
  }
  qsort(p, (size_t)m, sizeof *p, cmp_pt);
  const size_t mm = (size_t)(m > 0 ? m : 1);
  double *x = malloc(mm * sizeof *x), *v = malloc(mm * sizeof *v), *du = malloc(mm * sizeof *du);
  double *y = malloc(VS_PLOT_MAX_SERIES * mm * sizeof *y);
  vs_plot_series s[VS_PLOT_MAX_SERIES];
  vs_plot_style style[VS_PLOT_MAX_SERIES];
  vs_plot_marks marks = {0, NULL, NULL, {NULL, 1.0, 0}, style};
  char names[VS_PLOT_MAX_SERIES][48];
  char out[1200], out2[1200];
  vs_error err;
  vs_error_clear(&err);
  const int by_alpha = distinct(p, m, 1) >= 2, by_kn = distinct(p, m, 0) >= 2;
  if (x == NULL || v == NULL || du == NULL || y == NULL || m == 0) {
    fprintf(stderr, "voussoir plot: %s: %s\n", path, m == 0 ? "no run of the sweep collapsed" : "out of memory");
    rc = -1;
  } else {
    for (int i = 0; i < m; i++) x[i] = p[i].dz, v[i] = p[i].dx, du[i] = hypot(p[i].dz, p[i].dx);
    vs_plot_panel panel = {{"collapse spreading dx/L (%)", 1.0, 0}, s, sweep_series(p, m, v, 1, y, names, s, style)};
    vs_plot_axis xa = {"collapse settlement dz/L (%)", 1.0, 0};
    snprintf(out, sizeof out, "%s/domain.%s", dir, ext);
    rc = vs_plot_curves_marked(out, vs_plot_format_from_path(out),
                               "Limit displacement domain: the support displacement at collapse, per k_n",
                               &xa, x, m, &panel, 1, &marks, &err) == VS_OK ? 0 : -1;
    out2[0] = '\0';
    if (rc == 0 && (by_alpha || by_kn)) {
      for (int i = 0; i < m; i++) x[i] = by_alpha ? p[i].alpha : p[i].kn;
      vs_plot_panel p2 = {{"collapse displacement delta_u/L (%)", 1.0, 0}, s,
                          sweep_series(p, m, du, by_alpha, y, names, s, style)};
      vs_plot_axis xb = {by_alpha ? "direction alpha of the support's motion, from the vertical (deg)"
                                  : "joint normal stiffness k_n (N/mm^3)", 1.0, 0};
      snprintf(out2, sizeof out2, "%s/sensitivity.%s", dir, ext);
      rc = vs_plot_curves_marked(out2, vs_plot_format_from_path(out2),
                                 by_alpha ? "Collapse displacement against the direction, per k_n"
                                          : "Collapse displacement against k_n",
                                 &xb, x, m, &p2, 1, &marks, &err) == VS_OK ? 0 : -1;
    }
    if (rc != 0) {
      fprintf(stderr, "voussoir plot: %s\n", err.msg);
    } else {
      sweep_json(json, out, out2[0] ? out2 : NULL, p, m, du);
      printf("sweep %s (%d collapses of %d runs):\n  %s\n", path, m, n, out);
      if (out2[0]) printf("  %s\n", out2);
      else printf("  (no sensitivity picture: the sweep varies neither alpha nor k_n)\n");
    }
  }
  for (int i = 0; i < m; i++) free(p[i].mode);
  free(p), free(x), free(v), free(du), free(y);
  return rc;
}

/* plots.json in dir: what each picture shows, for checking and re-plotting; NULL (and a
 * warning) if it cannot be created. */
static FILE *json_open(const char *dir, const char *source) {
  char path[1200];
  snprintf(path, sizeof path, "%s/plots.json", dir);
  FILE *f = fopen(path, "w");
  if (f == NULL) {
    fprintf(stderr, "voussoir plot: %s: cannot write: %s\n", path, strerror(errno));
    return NULL;
  }
  fputs("{\"source\": ", f);
  json_str(f, source);
  fputs(", \"pictures\": [", f);
  return f;
}

/* Close plots.json; 1 if it could not be written whole. */
static int json_close(FILE **f, const char *dir) {
  if (*f == NULL) return 1;
  fputs("\n]}\n", *f);
  const int bad = ferror(*f) != 0;
  const int rc = fclose(*f) != 0 || bad;
  *f = NULL;
  if (rc) fprintf(stderr, "voussoir plot: %s/plots.json: write error\n", dir);
  else printf("  %s/plots.json\n", dir);
  return rc;
}

/* Every picture this command may write in dir (arch_*.EXT, curves.EXT) is absent or a regular
 * file, and dir is a directory or absent: checked before anything is drawn. 0, or 2 with the
 * reason printed. */
static int check_picture_dir(const char *dir, const char *ext) {
  vs_error err;
  if (vs_outpath_check_dir(dir, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: -o %s\n", err.msg);
    return 2;
  }
  DIR *d = opendir(dir);
  if (d == NULL) return 0; /* absent: created later */
  const size_t ne = strlen(ext);
  int rc = 0;
  for (struct dirent *e = readdir(d); e != NULL && rc == 0; e = readdir(d)) {
    const size_t n = strlen(e->d_name);
    const int ours = ((strncmp(e->d_name, "arch_", 5) == 0 || strncmp(e->d_name, "curves.", 7) == 0 ||
                       strncmp(e->d_name, "domain.", 7) == 0 ||
                       strncmp(e->d_name, "sensitivity.", 12) == 0) &&
                      n > ne + 1 && e->d_name[n - ne - 1] == '.' && strcmp(e->d_name + n - ne, ext) == 0) ||
                     strcmp(e->d_name, "plots.json") == 0;
    struct stat st;
    if (ours && fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISREG(st.st_mode)) {
      fprintf(stderr, "voussoir plot: -o %s: %s exists and is not a regular file\n", dir, e->d_name);
      rc = 2;
    }
  }
  closedir(d);
  return rc;
}

int vs_cmd_plot(int argc, char **argv) {
  const char *run = NULL, *dir = NULL, *ext = "png";
  char defdir[1100];
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "-o") == 0 && i + 1 < argc) dir = argv[++i];
    else if (strcmp(argv[i], "--svg") == 0) ext = "svg";
    else if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
      fputs(PLOT_USAGE, stdout);
      return 0;
    } else if (argv[i][0] != '-' && run == NULL) run = argv[i];
    else {
      fprintf(stderr, "voussoir plot: unexpected argument %s\n%s", argv[i], PLOT_USAGE);
      return 2;
    }
  }
  if (run == NULL) {
    fprintf(stderr, "voussoir plot: needs a RUN.h5 record\n%s", PLOT_USAGE);
    return 2;
  }
  if (dir == NULL) {
    const char *dot = strrchr(run, '.');
    snprintf(defdir, sizeof defdir, "%.*s_plots", dot ? (int)(dot - run) : (int)strlen(run), run);
    dir = defdir;
  }
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t sf = H5Fopen(run, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (sf >= 0) { /* a sweep's summary.h5: the domain */
    H5O_info_t info;
    const int is_sweep = H5Lexists(sf, "/summary", H5P_DEFAULT) > 0 &&
                         H5Oget_info_by_name2(sf, "/summary", &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 &&
                         info.type == H5O_TYPE_DATASET;
    int rc = 0;
    if (is_sweep && check_picture_dir(dir, ext) != 0) {
      rc = -2;
    } else if (is_sweep && mkdir(dir, 0755) != 0 && errno != EEXIST) {
      fprintf(stderr, "voussoir plot: %s: cannot create: %s\n", dir, strerror(errno));
      rc = -1;
    } else if (is_sweep) {
      FILE *json = json_open(dir, run);
      rc = plot_sweep(run, sf, dir, ext, json);
      if (json_close(&json, dir) != 0 && rc == 0) rc = -1;
    }
    H5Fclose(sf);
    if (is_sweep) {
      vs_plot_release();
      return rc == 0 ? 0 : rc == -2 ? 2 : 1;
    }
  }
  record r;
  if (record_open(run, &r) != 0) {
    fprintf(stderr, "voussoir plot: %s\n", r.msg);
    record_free(&r);
    return 2;
  }
  if (check_picture_dir(dir, ext) != 0) {
    record_free(&r);
    return 2;
  }
  if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir plot: %s: cannot create: %s\n", dir, strerror(errno));
    record_free(&r);
    return 1;
  }
  r.json = json_open(dir, run);
  printf("pictures of %s (%d recorded states):\n", run, r.rows);
  int bad = draw_row(&r, 0, dir, "reference", ext, "Self-weight");
  for (int i = 0; i < r.nh; i++) {
    if (r.h[i].during_fall) continue;
    char name[32], what[96];
    snprintf(name, sizeof name, "hinge_%c", r.h[i].label);
    snprintf(what, sizeof what, "Hinge %c forms%s", r.h[i].label,
             r.h[i].order == 4 ? " (the fourth)" : r.h[i].order == 5 ? " (the fifth)" : "");
    bad |= draw_at(&r, r.h[i].delta_onset, PIC_ONSET, i, dir, name, ext, what);
  }
  for (int i = 0; i < r.nl; i++) {
    char name[32], what[96];
    snprintf(name, sizeof name, "limit_%d", i + 1);
    snprintf(what, sizeof what, "Limit point %d", i + 1);
    bad |= draw_at(&r, r.limits[i], PIC_ROW, -1, dir, name, ext, what);
    if (isfinite(r.settled[i])) {
      snprintf(name, sizeof name, "snap_%d_settled", i + 1);
      snprintf(what, sizeof what, "Snap-through %d settled", i + 1);
      bad |= draw_at(&r, r.settled[i], PIC_ROW, -1, dir, name, ext, what);
    }
  }
  if (isfinite(r.collapse)) {
    /* the mechanism the record names: hinges still forming as the motion starts from the
     * limit point are drawn open, at the state where the last of them formed */
    double dc = r.collapse;
    for (int i = 0; i < r.nh; i++)
      if (!r.h[i].during_fall && r.h[i].open && r.h[i].delta_onset > dc) dc = r.h[i].delta_onset;
    char what[160] = "Collapse";
    if (dc > r.collapse + 1e-9)
      snprintf(what, sizeof what, "Collapse: the mechanism (limit point at %.3f mm)", r.collapse / VS_MM);
    bad |= draw_at(&r, dc, PIC_COLLAPSE, -1, dir, "collapse", ext, what);
  }
  bad |= draw_row(&r, r.rows - 1, dir, "end", ext, "End of the record");
  bad |= draw_curves(&r, dir, ext);
  bad |= json_close(&r.json, dir);
  record_free(&r);
  vs_plot_release();
  return bad ? 1 : 0;
}
