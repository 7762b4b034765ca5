/* `voussoir plot SWEEP/summary.h5`: a sweep's pictures, the limit displacement domain (dx/L
 * against dz/L per k_n, each point marked by its mode) and the sensitivity of delta_u/L to
 * alpha or k_n, with their points in plots.json. */
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "h5util.h"
#include "plot_cmd.h"
#include "voussoir/plot.h"
#include "voussoir/report.h"
#include "quote.h"

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
  const int n = vs_h5_table_rows(f, "/summary"); /* a whole read fills n records */
  if (n < 0) return -1;
  hid_t d = H5Dopen2(f, "/summary", H5P_DEFAULT), ft = H5Dget_type(d);
  hid_t str = vs_h5_vlstr_type();
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
static const char *const MODE_NAMES[4] = {"mode I", "mode II", "mode III",
                                          "no mode (sides match none)"};
static const vs_plot_style MODE_STYLE[4] = {VS_PLOT_CIRCLES, VS_PLOT_SQUARES, VS_PLOT_TRIANGLES,
                                            VS_PLOT_DIAMONDS};

static int mode_index(const char *m) {
  for (int i = 0; i < 3; i++)
    if (m != NULL && strcmp(m, MODES[i]) == 0) return i;
  return 3;
}

static int same_kn(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

/* Series of a sweep picture over the m points p (sorted by k_n, then alpha): one line per k_n
 * (per_kn = 0: one line through all) through value[i], then one marker series per mode present. y
 * holds (lines + 4) m values; names (VS_PLOT_MAX_SERIES x 48) the lines' names; style each series'
 * style. Returns the series count. */
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
    vs_json_string(f, base != NULL ? base + 1 : files[pic]);
    fputs(", \"points\": [", f);
    for (int i = 0; i < m; i++) {
      fprintf(f, "%s\n    {\"kn_N_mm3\": ", i ? "," : "");
      vs_plot_json_num(f, p[i].kn); /* NaN: the column is absent, the case's k_n */
      fputs(", \"alpha_deg\": ", f);
      vs_plot_json_num(f, p[i].alpha);
      fputs(pic == 0 ? ", \"dz_over_L_pct\": " : ", \"delta_u_over_L_pct\": ", f);
      vs_plot_json_num(f, pic == 0 ? p[i].dz : du[i]);
      if (pic == 0) {
        fputs(", \"dx_over_L_pct\": ", f);
        vs_plot_json_num(f, p[i].dx);
      }
      fprintf(f, ", \"mode\": \"%s\"}", MODES[mode_index(p[i].mode)]);
    }
    fputs("]}", f);
  }
}

/* domain.EXT: collapse dx/L against dz/L, a line per k_n through the directions, the points
 * marked by mode; sensitivity.EXT: delta_u/L against alpha, a line per k_n (against k_n when
 * the sweep varies only k_n). */
int vs_plot_sweep(const char *path, hid_t f, const char *dir, const char *ext, FILE *json) {
  sweep_pt *p;
  const int n = read_sweep(f, &p);
  if (n < 0) {
    char q[1024];
    fprintf(stderr, "voussoir plot: %s: /summary is not a sweep's summary table\n",
            vs_quote(path, q, sizeof q));
    return -1;
  }
  int m = 0, rc = 0;
  for (int i = 0; i < n; i++) { /* collapses only */
    const int keep =
        p[i].status != NULL && strcmp(p[i].status, "collapse") == 0 && isfinite(p[i].dz);
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
    char q[1024];
    fprintf(stderr, "voussoir plot: %s: %s\n", vs_quote(path, q, sizeof q),
            m == 0 ? "no run of the sweep collapsed" : "out of memory");
    rc = -1;
  } else {
    for (int i = 0; i < m; i++) x[i] = p[i].dz, v[i] = p[i].dx, du[i] = hypot(p[i].dz, p[i].dx);
    vs_plot_panel panel = {
        {"collapse spreading dx/L (%)", 1.0, 0}, s, sweep_series(p, m, v, 1, y, names, s, style)};
    vs_plot_axis xa = {"collapse settlement dz/L (%)", 1.0, 0};
    snprintf(out, sizeof out, "%s/domain.%s", dir, ext);
    rc = vs_plot_curves_marked(
             out, vs_plot_format_from_path(out),
             "Limit displacement domain: the support displacement at collapse, per k_n", &xa, x, m,
             &panel, 1, &marks, &err) == VS_OK
             ? 0
             : -1;
    out2[0] = '\0';
    if (rc == 0 && (by_alpha || by_kn)) {
      for (int i = 0; i < m; i++) x[i] = by_alpha ? p[i].alpha : p[i].kn;
      vs_plot_panel p2 = {{"collapse displacement delta_u/L (%)", 1.0, 0}, s,
                          sweep_series(p, m, du, by_alpha, y, names, s, style)};
      vs_plot_axis xb = {by_alpha
                             ? "direction alpha of the support's motion, from the vertical (deg)"
                             : "joint normal stiffness k_n (N/mm^3)",
                         1.0, 0};
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
