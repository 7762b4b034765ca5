/* voussoir plot RUN.h5: the arch pictures of a recorded run, at true scale: at the reference, at
 * each hinge's onset, at each limit point and settled snap, at the collapse and at the end.
 * Reads the HDF5 record written by record.c; draws with plot.c. The charts (curves against the
 * support displacement, a sweep's domain, a Monte Carlo study's fragility) are matplotlib's:
 * src/cli/cli_plot.c runs python3 -m voussoir.figures after this. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "h5util.h"
#include "plot_cmd.h"
#include "plot_plugin.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/imperfections.h"
#include "voussoir/model.h"
#include "outpath.h"
#include "voussoir/plot.h"
#include "voussoir/report.h"
#include "voussoir/support.h"
#include "voussoir/units.h"
#include "quote.h"

/* Start a picture's entry in plots.json: its file and title (the caller adds fields and '}'). */
static void json_picture(vs_plotrec *r, const char *path, const char *title) {
  if (r->json == NULL) return;
  const char *base = strrchr(path, '/');
  fputs(r->n_pictures++ ? ",\n  {\"file\": " : "\n  {\"file\": ", r->json);
  vs_json_string(r->json, base != NULL ? base + 1 : path);
  fputs(", \"title\": ", r->json);
  vs_json_string(r->json, title);
}

/* The labels an arch picture draws, in plots.json. */
static void json_arch(vs_plotrec *r, const char *path, const char *title, const state *st,
                      const vs_plot_arch_args *a, const vs_hinge *h, int nh) {
  if (r->json == NULL) return;
  json_picture(r, path, title);
  /* a finite delta in m may not be one in mm (1e306 m): every number through vs_plot_json_num */
  fputs(", \"delta_mm\": ", r->json);
  vs_plot_json_num(r->json, st->delta / VS_MM);
  for (int s = 0; s < 2; s++) {
    fputs(s ? ", " : ", \"support_theta_rad\": [", r->json);
    vs_plot_json_num(r->json, a->support_theta[s]);
  }
  fputc(']', r->json);
  if (a->block_thickness != NULL && r->n_pictures == 1) { /* once, with the first picture */
    fputs(", \"block_thickness_mm\": [", r->json);
    for (int i = 0; i < r->nb; i++) {
      fputs(i ? ", " : "", r->json);
      vs_plot_json_num(r->json, a->block_thickness[i] / VS_MM);
    }
    fputc(']', r->json);
  }
  fputs(", \"hinges\": [", r->json);
  for (int i = 0; i < nh; i++) {
    const char lab[2] = {h[i].label, '\0'}; /* beyond Z the letters run into punctuation */
    fputs(i ? ", {\"label\": " : "{\"label\": ", r->json);
    vs_json_string(r->json, lab);
    fprintf(r->json, ", \"side\": \"%c\", \"first\": %d, \"last\": %d}", h[i].side, h[i].first,
            h[i].last);
  }
  fputs("]}", r->json);
}

/* A pinned springer's rotation, which the record does not hold, from the springing joint: for
 * rigid faces the edge openings differ by t sin(relative rotation), so the springer turns by
 * the voussoir's rotation less asin((gap_e - gap_i) / t) (left: the voussoir is on the joint's
 * far side, so plus). */
static void springer_rotations(const vs_plotrec *r, const state *st, vs_plot_arch_args *a) {
  for (int s = 0; s < 2; s++) {
    if (!a->pinned[s]) continue;
    const int k = s ? r->nj - 1 : 0, b = s ? r->nb - 1 : 0;
    const double t = r->g->joints[k].length;
    const double rel = asin(fmax(-1.0, fmin(1.0, (st->gap_e[k] - st->gap_i[k]) / t)));
    a->support_theta[s] = st->pos[3 * b + 2] + (s ? -rel : rel);
  }
}

/* The picture of state st with the hinges h[0..nh) labelled. */
static int draw_labelled(vs_plotrec *r, const state *st, const char *dir, const char *name,
                         const char *ext, const char *title, const vs_hinge *h, int nh) {
  char path[1200];
  snprintf(path, sizeof path, "%s/arch_%s.%s", dir, name, ext);
  vs_error err;
  vs_error_clear(&err);
  /* the ground in the picture of the end, where the debris lies on it */
  const double ground = strcmp(name, "end") == 0 ? r->ground : NAN;
  vs_plot_arch_args a = {
      .g = r->g,
      .q = st->pos,
      .delta_m = st->delta,
      .alpha_rad = r->c.alpha_deg * VS_DEG,
      .hinges = h,
      .n_hinges = nh,
      .joint_gap_i = st->gap_i,
      .joint_gap_e = st->gap_e,
      .open_m = r->c.open_mm * VS_MM,
      .joint_N = st->N,
      .joint_M = st->M,
      .title = title,
      .block_thickness = r->thick,
      .pinned = {r->c.left_kind == VS_SUPPORT_PINNED, r->c.right_kind == VS_SUPPORT_PINNED},
      .has_ground = isfinite(ground),
      .ground_z = ground,
      .loads = r->loads,
      .n_loads = r->n_loads,
      .load_note = r->load_note};
  springer_rotations(r, st, &a);
  a.supports = st->sup;
  if (vs_plot_arch_draw(path, vs_plot_format_from_path(path), &a, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    return -1;
  }
  json_arch(r, path, title, st, &a, h, nh);
  printf("  %s\n", path);
  return 0;
}

/* The picture of state st with the hinges it labels (every one: vs_plotrec_hinges_at). */
static int draw_state(vs_plotrec *r, const state *st, const char *dir, const char *name,
                      const char *ext, const char *title) {
  vs_hinge *h = malloc((size_t)(r->nh > 0 ? r->nh : 1) * sizeof *h);
  const int nh =
      h != NULL ? vs_plotrec_hinges_at(r, st->hinge_row, st->delta, st->kind, st->focus, h) : -1;
  int rc = -1;
  if (nh < 0) fputs("voussoir plot: out of memory\n", stderr);
  else rc = draw_labelled(r, st, dir, name, ext, title, h, nh);
  free(h);
  return rc;
}

static int draw_row(vs_plotrec *r, int row, const char *dir, const char *name, const char *ext,
                    const char *what) {
  char title[200];
  snprintf(title, sizeof title, "%s (recorded state at delta = %.3f mm)", what,
           r->delta[row] / VS_MM);
  const state st = vs_plotrec_state(r, row);
  return draw_state(r, &st, dir, name, ext, title);
}

/* a + w (b - a), n values, into out. */
static void lerp(const double *a, const double *b, double w, size_t n, double *out) {
  for (size_t k = 0; k < n; k++) out[k] = a[k] + w * (b[k] - a[k]);
}

/* The state at support displacement delta: a recorded one if delta falls on a row, else
 * interpolated linearly between the two rows around it (the title says which); its hinges
 * labelled as kind and focus say. */
static int draw_at(vs_plotrec *r, double delta, pic_kind kind, int focus, const char *dir,
                   const char *name, const char *ext, const char *what) {
  const int j = vs_plotrec_row_at(r, delta);
  char title[240];
  state st = vs_plotrec_state(r, j);
  st.kind = kind, st.focus = focus;
  if (j == 0 || fabs(r->delta[j] - delta) <= 1e-9 || !(r->delta[j - 1] < delta)) {
    snprintf(title, sizeof title, "%s (recorded state at delta = %.3f mm)", what,
             r->delta[j] / VS_MM);
    return draw_state(r, &st, dir, name, ext, title);
  }
  const size_t nq = 3 * (size_t)r->nb, nj = (size_t)r->nj;
  double *buf = malloc((nq + 4 * nj + 6) * sizeof *buf);
  if (buf == NULL) return draw_state(r, &st, dir, name, ext, what);
  const state a = vs_plotrec_state(r, j - 1), b = vs_plotrec_state(r, j);
  const double w = (delta - a.delta) / (b.delta - a.delta);
  lerp(a.pos, b.pos, w, nq, buf);
  lerp(a.gap_i, b.gap_i, w, nj, buf + nq);
  lerp(a.gap_e, b.gap_e, w, nj, buf + nq + nj);
  lerp(a.N, b.N, w, nj, buf + nq + 2 * nj);
  lerp(a.M, b.M, w, nj, buf + nq + 3 * nj);
  double *sup = NULL;
  if (a.sup != NULL && b.sup != NULL) lerp(a.sup, b.sup, w, 6, sup = buf + nq + 4 * nj);
  st = (state){buf, buf + nq, buf + nq + nj, buf + nq + 2 * nj, buf + nq + 3 * nj, delta,
               j,   kind,     focus,         sup};
  snprintf(title, sizeof title, "%s at delta = %.3f mm (interpolated between the states at %.3f "
           "and %.3f mm)", what, delta / VS_MM, a.delta / VS_MM, b.delta / VS_MM);
  const int rc = draw_state(r, &st, dir, name, ext, title);
  free(buf);
  return rc;
}

/* plots.json in dir: what each picture shows, for checking and re-plotting; NULL (and a
 * warning) if it cannot be created. */
static FILE *json_open(const char *dir, const char *source) {
  char path[1200];
  snprintf(path, sizeof path, "%s/plots.json", dir);
  FILE *f;
  vs_error err;
  if (vs_outpath_fopen(path, &f, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    return NULL;
  }
  fputs("{\"source\": ", f);
  vs_json_string(f, source);
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

/* The charts python3 -m voussoir.figures may write in the same directory (any of its formats). */
static const char *const CHARTS[] = {"curves",      "hinges",         "load_deflection",
                                     "cracks",      "domain",         "sensitivity",
                                     "fragility",   "convergence",    "hinge_histogram"};
static const char *const CHART_EXTS[] = {"png", "pdf", "svg"};

/* Whether name is one this command (or the charts after it) may write: arch_*.EXT, a chart's
 * NAME.png, .pdf or .svg, plots.json; user: the arch pictures' extension, a const char **. */
static int picture_name(const char *name, void *user) {
  const char *ext = *(const char **)user;
  const size_t n = strlen(name), ne = strlen(ext);
  if (strcmp(name, "plots.json") == 0) return 1;
  if (strncmp(name, "arch_", 5) == 0 && n > ne + 1 && name[n - ne - 1] == '.' &&
      strcmp(name + n - ne, ext) == 0)
    return 1;
  for (size_t c = 0; c < sizeof CHARTS / sizeof *CHARTS; c++) {
    const size_t nc = strlen(CHARTS[c]);
    if (strncmp(name, CHARTS[c], nc) != 0 || name[nc] != '.') continue;
    for (size_t e = 0; e < sizeof CHART_EXTS / sizeof *CHART_EXTS; e++)
      if (strcmp(name + nc + 1, CHART_EXTS[e]) == 0) return 1;
  }
  return 0;
}

/* Every picture this command may write in dir is absent or a regular file, and dir is a
 * directory or absent: checked before anything is drawn. 0, or 2 with the reason printed. */
static int check_picture_dir(const char *dir, const char *ext) {
  vs_error err;
  if (vs_outpath_check_dir(dir, &err) != VS_OK ||
      vs_outpath_check_entries(dir, picture_name, &ext, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: -o %s\n", err.msg);
    return 2;
  }
  return 0;
}

/* When run is a sweep's or a Monte Carlo study's summary.h5 (charts only, no arch picture):
 * dir checked and created, the exit status in *status (0, 1 or 2). 0 when run is neither (nor
 * an HDF5 file). */
static int plot_if_study(const char *run, const char *dir, const char *ext, int *status) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t sf = H5Fopen(run, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (sf < 0) return 0;
  H5O_info_t info;
  const int is_sweep =
      H5Lexists(sf, "/summary", H5P_DEFAULT) > 0 &&
      H5Oget_info_by_name2(sf, "/summary", &info, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 &&
      info.type == H5O_TYPE_DATASET;
  const int is_mc = H5Lexists(sf, "/samples", H5P_DEFAULT) > 0 &&
                    H5Lexists(sf, "/fragility", H5P_DEFAULT) > 0;
  H5Fclose(sf);
  if (!is_sweep && !is_mc) return 0;
  *status = 0;
  if (check_picture_dir(dir, ext) != 0) {
    *status = 2;
  } else if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir plot: %s: cannot create: %s\n", dir, strerror(errno));
    *status = 1;
  } else {
    char q[1024];
    printf("%s %s: no arch picture (the charts follow)\n", is_sweep ? "sweep" : "Monte Carlo study",
           vs_quote(run, q, sizeof q));
  }
  return 1;
}

/* The pictures of the run recorded at run, in dir: the exit status. */
static int plot_run(const char *run, const char *dir, const char *ext) {
  vs_plotrec r;
  if (vs_plotrec_open(run, &r) != 0) {
    char q[sizeof r.msg];
    fprintf(stderr, "voussoir plot: %s\n", vs_quote(r.msg, q, sizeof q)); /* it names run */
    vs_plotrec_free(&r);
    return 2;
  }
  if (check_picture_dir(dir, ext) != 0) {
    vs_plotrec_free(&r);
    return 2;
  }
  if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir plot: %s: cannot create: %s\n", dir, strerror(errno));
    vs_plotrec_free(&r);
    return 1;
  }
  r.json = json_open(dir, run);
  char q[1024];
  printf("pictures of %s (%d recorded states):\n", vs_quote(run, q, sizeof q), r.rows);
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
      snprintf(what, sizeof what, "Collapse: the mechanism (limit point at %.3f mm)",
               r.collapse / VS_MM);
    bad |= draw_at(&r, dc, PIC_COLLAPSE, -1, dir, "collapse", ext, what);
  }
  bad |= draw_row(&r, r.rows - 1, dir, "end", ext, "End of the record");
  bad |= json_close(&r.json, dir);
  vs_plotrec_free(&r);
  vs_plot_release();
  return bad ? 1 : 0;
}

int vs_plot_command(const char *run, const char *dir, const char *ext) {
  int status;
  if (plot_if_study(run, dir, ext, &status)) return status;
  return plot_run(run, dir, ext);
}
