/* voussoir plot RUN.h5: pictures of a recorded run. The arch at true scale at the reference, at
 * each hinge's onset, at each limit point and settled snap, at the collapse and at the end, and
 * the support reaction and hinge joints against the support displacement. Reads the HDF5 record
 * written by record.c; draws with plot.c. */
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

static int draw_curves(vs_plotrec *r, const char *dir, const char *ext) {
  const size_t n = (size_t)r->rows;
  double *reac = malloc(4 * n * sizeof(double)), *joint[5];
  vs_plot_series hs[5];
  int ns = 0, rc = 0, oom = 0;
  static const int COL[4] = {0, 1, 3,
                             4}; /* left Fx, Fz, right Fx, Fz of the supports on the arch */
  for (size_t i = 0; reac && i < n; i++)
    for (int c = 0; c < 4; c++) reac[(size_t)c * n + i] = r->react[6 * i + (size_t)COL[c]];
  vs_hinge *h = malloc((size_t)(r->nh > 0 ? r->nh : 1) * sizeof *h); /* every one it labels */
  for (int l = 0; l < 5; l++) {
    joint[l] = h != NULL ? malloc(n * sizeof(double)) : NULL;
    if (joint[l] == NULL) continue;
    int any = 0;
    for (size_t i = 0; i < n; i++) {
      const int nh = vs_plotrec_hinges_at(r, (int)i, r->delta[i], PIC_ROW, -1, h);
      oom |= nh < 0;
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
  const double L = r->g->span, ca = vs_support_direction(r->c.alpha_deg * VS_DEG).dz;
  vs_plot_marks marks = {nm, mx, labels, {NULL, 1.0, 0}, NULL};
  if (fabs(ca) > 1e-9 && L > 0.0) marks.x2 = (vs_plot_axis){"dz/L (%)", 100.0 * ca / L, 0};
  char path[1200];
  snprintf(path, sizeof path, "%s/curves.%s", dir, ext);
  vs_error err;
  vs_error_clear(&err);
  oom |= reac == NULL || h == NULL;
  if (oom ||
      vs_plot_curves_marked(path, vs_plot_format_from_path(path),
                            "Reactions and hinges against the support displacement", &x, r->delta,
                            (int)n, panels, ns > 0 ? 2 : 1, &marks, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", oom ? "out of memory" : err.msg);
    rc = -1;
  } else {
    json_picture(r, path, "Reactions and hinges against the support displacement");
    if (r->json != NULL) {
      fputs(", \"series\": [", r->json);
      for (int i = 0; i < 4; i++) fprintf(r->json, "%s\"%s\"", i ? ", " : "", rs[i].name);
      for (int i = 0; i < ns; i++) fprintf(r->json, ", \"%s\"", hs[i].name);
      fputs("], \"marks_mm\": [", r->json);
      for (int i = 0; i < nm; i++) { /* a limit point's delta is the record's: any value */
        fputs(i ? ", " : "", r->json);
        vs_plot_json_num(r->json, mx[i] / VS_MM);
      }
      fputs("]}", r->json);
    }
    printf("  %s\n", path);
  }
  free(reac);
  free(h);
  for (int l = 0; l < 5; l++) free(joint[l]);
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

/* Whether name is one this command may write (arch_*.EXT, curves.EXT, domain.EXT,
 * sensitivity.EXT, plots.json); user: the pictures' extension, as a const char **. */
static int picture_name(const char *name, void *user) {
  const char *ext = *(const char **)user;
  const size_t n = strlen(name), ne = strlen(ext);
  return ((strncmp(name, "arch_", 5) == 0 || strncmp(name, "curves.", 7) == 0 ||
           strncmp(name, "domain.", 7) == 0 || strncmp(name, "sensitivity.", 12) == 0) &&
          n > ne + 1 && name[n - ne - 1] == '.' && strcmp(name + n - ne, ext) == 0) ||
         strcmp(name, "plots.json") == 0;
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

/* When run is a sweep's summary.h5: its pictures in dir, and the exit status in *status (1). 0
 * when run is not one (nor an HDF5 file). */
static int plot_if_sweep(const char *run, const char *dir, const char *ext, int *status) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t sf = H5Fopen(run, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (sf < 0) return 0;
  H5O_info_t info;
  const int is_sweep =
      H5Lexists(sf, "/summary", H5P_DEFAULT) > 0 &&
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
    rc = vs_plot_sweep(run, sf, dir, ext, json);
    if (json_close(&json, dir) != 0 && rc == 0) rc = -1;
  }
  H5Fclose(sf);
  if (!is_sweep) return 0;
  vs_plot_release();
  *status = rc == 0 ? 0 : rc == -2 ? 2 : 1;
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
  bad |= draw_curves(&r, dir, ext);
  bad |= json_close(&r.json, dir);
  vs_plotrec_free(&r);
  vs_plot_release();
  return bad ? 1 : 0;
}

int vs_plot_command(const char *run, const char *dir, const char *ext) {
  char defdir[VS_OUTPATH_DIR_MAX + 1];
  if (dir == NULL) { /* RUN without its extension, and "_plots" */
    const char *dot = strrchr(run, '.'), *slash = strrchr(run, '/');
    const size_t n = dot != NULL && (slash == NULL || dot > slash) ? (size_t)(dot - run)
                                                                   : strlen(run);
    if (n + sizeof "_plots" > sizeof defdir) {
      fprintf(stderr, "voussoir plot: %s: name too long for the default -o %.*s..._plots (at "
              "most %d bytes): give -o DIR\n", vs_q(run).s, 32, run, (int)VS_OUTPATH_DIR_MAX);
      return 2;
    }
    snprintf(defdir, sizeof defdir, "%.*s_plots", (int)n, run);
    dir = defdir;
  }
  int status;
  if (plot_if_sweep(run, dir, ext, &status)) return status;
  return plot_run(run, dir, ext);
}
