/* voussoir plot RUN.h5: pictures of a recorded run. The arch at true scale at the reference, at
 * each hinge's onset, at each limit point and settled snap, at the collapse and at the end, and
 * the support reaction and hinge joints against the support displacement. Reads the HDF5 record
 * written by output.c; draws with plot.c. */
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

#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
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
    "Given a sweep's summary.h5, draws domain.png: the support displacement at collapse, dz/L\n"
    "against dx/L, one line per k_n through the directions alpha.\n";

typedef struct {
  char label, side;
  int first, last, onset_first, onset_last, order, during_fall;
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
} record;

/* Read a whole float64 dataset of n values; -1 if missing or of another size. */
static int read_doubles(hid_t f, const char *path, double *out, size_t n) {
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  int rc = (np == (hssize_t)n && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0) ? 0 : -1;
  H5Sclose(sp);
  H5Dclose(d);
  return rc;
}

static int dataset_rows(hid_t f, const char *path) {
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t sp = H5Dget_space(d);
  hsize_t dims[4] = {0};
  int nd = H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  return nd >= 1 ? (int)dims[0] : -1;
}

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
  int n = dataset_rows(r->file, path);
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
  int n = dataset_rows(r->file, path);
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
  vs_error err;
  if (vs_geometry_create_arch(&r->c, &r->g, &err) != VS_OK) {
    snprintf(r->msg, sizeof r->msg, "%.200s: %.300s", path, err.msg);
    return -1;
  }
  r->nb = r->g->n_blocks;
  r->nj = r->g->n_joints;
  r->rows = dataset_rows(r->file, "/observables/delta/value");
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
  const int bad = read_doubles(r->file, "/observables/delta/value", r->delta, n) ||
                  read_doubles(r->file, "/observables/block_position/value", r->pos, n * 3 * (size_t)r->nb) ||
                  read_doubles(r->file, "/observables/joint_gap_i/value", r->gap_i, n * (size_t)r->nj) ||
                  read_doubles(r->file, "/observables/joint_gap_e/value", r->gap_e, n * (size_t)r->nj) ||
                  read_doubles(r->file, "/observables/reactions/value", r->react, n * 6) ||
                  read_doubles(r->file, "/observables/joint_N/value", r->jN, n * (size_t)r->nj) ||
                  read_doubles(r->file, "/observables/joint_M/value", r->jM, n * (size_t)r->nj) || hd < 0 ||
                  H5Dread(hd, H5T_NATIVE_SCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, r->hinge) < 0;
  if (hd >= 0) H5Dclose(hd);
  if (bad || read_hinges(r) || read_limits(r)) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record's time series are incomplete", path);
    return -1;
  }
  read_doubles(r->file, "/summary/collapse/delta", &r->collapse, 1);
  r->ground = NAN;
  if (H5Lexists(r->file, "/summary/ground", H5P_DEFAULT) > 0 &&
      H5Lexists(r->file, "/summary/ground/level", H5P_DEFAULT) > 0 &&
      read_doubles(r->file, "/summary/ground/level", &r->ground, 1) != 0)
    r->ground = NAN;
  return 0;
}

/* First row at or after delta (the last row if none). */
static int row_at(const record *r, double delta) {
  for (int i = 0; i < r->rows; i++)
    if (r->delta[i] >= delta - 1e-12) return i;
  return r->rows - 1;
}

/* The hinges open at a row: groups of consecutive open joints on one side, each named after the
 * recorded hinge of that side nearest to it (formed by then, not during the fall). */
static int hinges_at(const record *r, int row, vs_hinge *out, int cap) {
  const signed char *hj = r->hinge + (size_t)row * (size_t)r->nj;
  int n = 0;
  for (int k = 0; k < r->nj && n < cap;) {
    if (hj[k] == 0) {
      k++;
      continue;
    }
    int e = k;
    while (e + 1 < r->nj && hj[e + 1] == hj[k]) e++;
    vs_hinge h = {.label = '?', .side = hj[k] == 1 ? 'I' : 'E', .first = k + 1, .last = e + 1, .open = 1};
    int best = -1, dist = 1 << 30;
    for (int i = 0; i < r->nh; i++) {
      const rec_hinge *rh = &r->h[i];
      if (rh->side != h.side || rh->during_fall || rh->delta_onset > r->delta[row] + 1e-9) continue;
      const int c = (rh->first + rh->last) / 2, d = abs(c - (h.first + h.last) / 2);
      const int c0 = (rh->onset_first + rh->onset_last) / 2, d0 = abs(c0 - (h.first + h.last) / 2);
      if ((d < d0 ? d : d0) < dist) {
        dist = d < d0 ? d : d0;
        best = i;
      }
    }
    if (best >= 0 && dist <= 6) h.label = r->h[best].label;
    if (h.label != '?') out[n++] = h;
    k = e + 1;
  }
  return n;
}

/* One state to draw: positions (3 nb), joint gaps, N, M (nj each), the support displacement and
 * the row whose open hinges are labelled. */
typedef struct {
  const double *pos, *gap_i, *gap_e, *N, *M;
  double delta;
  int hinge_row;
} state;

static state state_of_row(const record *r, int row) {
  const size_t o = (size_t)row * (size_t)r->nj;
  return (state){r->pos + (size_t)row * 3 * (size_t)r->nb, r->gap_i + o, r->gap_e + o,
                 r->jN + o, r->jM + o, r->delta[row], row};
}

static int draw_state(const record *r, const state *st, const char *dir, const char *name,
                      const char *ext, const char *title) {
  vs_hinge h[32];
  const int nh = hinges_at(r, st->hinge_row, h, 32);
  char path[1200];
  snprintf(path, sizeof path, "%s/arch_%s.%s", dir, name, ext);
  vs_error err;
  vs_error_clear(&err);
  /* the ground in the picture of the end, where the debris lies on it */
  const double ground = strcmp(name, "end") == 0 ? r->ground : NAN;
  if (vs_plot_arch_landed(path, vs_plot_format_from_path(path), r->g, st->pos, st->delta,
                          r->c.alpha_deg * VS_DEG, h, nh, st->gap_i, st->gap_e,
                          r->c.open_mm * VS_MM, st->N, st->M, ground, title, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    return -1;
  }
  printf("  %s\n", path);
  return 0;
}

static int draw_row(const record *r, int row, const char *dir, const char *name, const char *ext,
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
 * interpolated linearly between the two rows around it (the title says which). */
static int draw_at(const record *r, double delta, const char *dir, const char *name,
                   const char *ext, const char *what) {
  const int j = row_at(r, delta);
  if (j == 0 || fabs(r->delta[j] - delta) <= 1e-9 || !(r->delta[j - 1] < delta))
    return draw_row(r, j, dir, name, ext, what);
  const size_t nq = 3 * (size_t)r->nb, nj = (size_t)r->nj;
  double *buf = malloc((nq + 4 * nj) * sizeof *buf);
  if (buf == NULL) return draw_row(r, j, dir, name, ext, what);
  const state a = state_of_row(r, j - 1), b = state_of_row(r, j);
  const double w = (delta - a.delta) / (b.delta - a.delta);
  lerp(a.pos, b.pos, w, nq, buf);
  lerp(a.gap_i, b.gap_i, w, nj, buf + nq);
  lerp(a.gap_e, b.gap_e, w, nj, buf + nq + nj);
  lerp(a.N, b.N, w, nj, buf + nq + 2 * nj);
  lerp(a.M, b.M, w, nj, buf + nq + 3 * nj);
  const state st = {buf, buf + nq, buf + nq + nj, buf + nq + 2 * nj, buf + nq + 3 * nj, delta, j};
  char title[240];
  snprintf(title, sizeof title, "%s at delta = %.3f mm (interpolated between the states at %.3f "
           "and %.3f mm)", what, delta / VS_MM, a.delta / VS_MM, b.delta / VS_MM);
  const int rc = draw_state(r, &st, dir, name, ext, title);
  free(buf);
  return rc;
}

static int draw_curves(const record *r, const char *dir, const char *ext) {
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
      const int nh = hinges_at(r, (int)i, h, 32);
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
  vs_plot_marks marks = {nm, mx, labels, {NULL, 1.0, 0}};
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
    printf("  %s\n", path);
  }
  free(reac);
  for (int l = 0; l < 5; l++) free(joint[l]);
  return rc;
}

/* --- a sweep's summary table: the limit displacement domain --- */

typedef struct {
  double kn, alpha, dz, dx;
  char *status;
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
  const int n = dataset_rows(f, "/summary");
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

/* domain.png: collapse dz/L against dx/L, one line per k_n through the directions alpha. */
static int plot_sweep(const char *path, hid_t f, const char *dir, const char *ext) {
  sweep_pt *p;
  const int n = read_sweep(f, &p);
  if (n < 0) {
    fprintf(stderr, "voussoir plot: %s: /summary is not a sweep's summary table\n", path);
    return -1;
  }
  int m = 0, ns = 0, rc = 0;
  for (int i = 0; i < n; i++) { /* collapses only */
    const int keep = p[i].status != NULL && strcmp(p[i].status, "collapse") == 0 && isfinite(p[i].dz);
    free(p[i].status); /* HDF5 allocates variable-length strings with malloc */
    p[i].status = NULL;
    if (keep) p[m++] = p[i];
  }
  qsort(p, (size_t)m, sizeof *p, cmp_pt);
  double *x = malloc((size_t)(m > 0 ? m : 1) * sizeof *x), *y = malloc(VS_PLOT_MAX_SERIES * (size_t)(m > 0 ? m : 1) * sizeof *y);
  vs_plot_series s[VS_PLOT_MAX_SERIES];
  char names[VS_PLOT_MAX_SERIES][48];
  for (int i = 0; x != NULL && y != NULL && i < m; i++) {
    x[i] = p[i].dz;
    if (i == 0 || !(p[i].kn == p[i - 1].kn || (isnan(p[i].kn) && isnan(p[i - 1].kn)))) {
      if (ns == VS_PLOT_MAX_SERIES) break;
      double *col = y + (size_t)ns * (size_t)m;
      for (int k = 0; k < m; k++) col[k] = NAN;
      snprintf(names[ns], sizeof names[ns], isnan(p[i].kn) ? "k_n of the case" : "k_n = %g N/mm^3", p[i].kn);
      s[ns] = (vs_plot_series){names[ns], col};
      ns++;
    }
    y[(size_t)(ns - 1) * (size_t)m + (size_t)i] = p[i].dx;
  }
  char out[1200];
  snprintf(out, sizeof out, "%s/domain.%s", dir, ext);
  vs_error err;
  vs_error_clear(&err);
  vs_plot_panel panel = {{"collapse spreading dx/L (%)", 1.0, 0}, s, ns};
  vs_plot_axis xa = {"collapse settlement dz/L (%)", 1.0, 0};
  if (x == NULL || y == NULL || m == 0) {
    fprintf(stderr, "voussoir plot: %s: %s\n", path, m == 0 ? "no run of the sweep collapsed" : "out of memory");
    rc = -1;
  } else if (vs_plot_curves(out, vs_plot_format_from_path(out),
                            "Limit displacement domain: the support displacement at collapse, per k_n",
                            &xa, x, m, &panel, 1, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    rc = -1;
  } else {
    printf("domain of %s (%d collapses of %d runs):\n  %s\n", path, m, n, out);
  }
  free(p), free(x), free(y);
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
    const int ours = (strncmp(e->d_name, "arch_", 5) == 0 || strncmp(e->d_name, "curves.", 7) == 0) &&
                     n > ne + 1 && e->d_name[n - ne - 1] == '.' && strcmp(e->d_name + n - ne, ext) == 0;
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
      rc = plot_sweep(run, sf, dir, ext);
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
  printf("pictures of %s (%d recorded states):\n", run, r.rows);
  int bad = draw_row(&r, 0, dir, "reference", ext, "Self-weight");
  for (int i = 0; i < r.nh; i++) {
    if (r.h[i].during_fall) continue;
    char name[32], what[96];
    snprintf(name, sizeof name, "hinge_%c", r.h[i].label);
    snprintf(what, sizeof what, "Hinge %c forms%s", r.h[i].label,
             r.h[i].order == 4 ? " (the fourth)" : r.h[i].order == 5 ? " (the fifth)" : "");
    bad |= draw_at(&r, r.h[i].delta_onset, dir, name, ext, what);
  }
  for (int i = 0; i < r.nl; i++) {
    char name[32], what[96];
    snprintf(name, sizeof name, "limit_%d", i + 1);
    snprintf(what, sizeof what, "Limit point %d", i + 1);
    bad |= draw_at(&r, r.limits[i], dir, name, ext, what);
    if (isfinite(r.settled[i])) {
      snprintf(name, sizeof name, "snap_%d_settled", i + 1);
      snprintf(what, sizeof what, "Snap-through %d settled", i + 1);
      bad |= draw_at(&r, r.settled[i], dir, name, ext, what);
    }
  }
  if (isfinite(r.collapse)) bad |= draw_at(&r, r.collapse, dir, "collapse", ext, "Collapse");
  bad |= draw_row(&r, r.rows - 1, dir, "end", ext, "End of the record");
  bad |= draw_curves(&r, dir, ext);
  record_free(&r);
  vs_plot_release();
  return bad ? 1 : 0;
}
