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
    "usage: voussoir plot RUN.h5 [-o DIR] [--svg]\n"
    "Draws the recorded run at true scale: the reference state, each hinge's onset, each limit\n"
    "point and settled snap-through, the collapse and the end of the record (open joints shaded,\n"
    "hinges marked on their side with labels A-E, the support displacement annotated), and the\n"
    "support reaction and hinge joints against the support displacement. Files arch_*.png (or\n"
    ".svg) and curves.png go to DIR (default: RUN_plots next to the record).\n";

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
  double *delta, *pos, *gap_i, *gap_e, *react;
  signed char *hinge; /* rows x nj: 0 closed, 1 intrados, 2 extrados */
  rec_hinge *h;
  int nh;
  double *limits, *settled;
  int nl;
  double collapse; /* m, NaN if none */
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
  r->hinge = malloc(n * (size_t)r->nj);
  if (!r->delta || !r->pos || !r->gap_i || !r->gap_e || !r->react || !r->hinge) {
    snprintf(r->msg, sizeof r->msg, "out of memory");
    return -1;
  }
  hid_t hd = H5Dopen2(r->file, "/observables/joint_hinge/value", H5P_DEFAULT);
  const int bad = read_doubles(r->file, "/observables/delta/value", r->delta, n) ||
                  read_doubles(r->file, "/observables/block_position/value", r->pos, n * 3 * (size_t)r->nb) ||
                  read_doubles(r->file, "/observables/joint_gap_i/value", r->gap_i, n * (size_t)r->nj) ||
                  read_doubles(r->file, "/observables/joint_gap_e/value", r->gap_e, n * (size_t)r->nj) ||
                  read_doubles(r->file, "/observables/reactions/value", r->react, n * 6) || hd < 0 ||
                  H5Dread(hd, H5T_NATIVE_SCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, r->hinge) < 0;
  if (hd >= 0) H5Dclose(hd);
  if (bad || read_hinges(r) || read_limits(r)) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record's time series are incomplete", path);
    return -1;
  }
  read_doubles(r->file, "/summary/collapse/delta", &r->collapse, 1);
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

static int draw_row(const record *r, int row, const char *dir, const char *name, const char *ext,
                    const char *what) {
  vs_hinge h[32];
  const int nh = hinges_at(r, row, h, 32);
  char path[1200], title[160];
  snprintf(path, sizeof path, "%s/arch_%s.%s", dir, name, ext);
  snprintf(title, sizeof title, "%s (row %d)", what, row);
  vs_error err;
  vs_error_clear(&err);
  if (vs_plot_arch(path, vs_plot_format_from_path(path), r->g, r->pos + (size_t)row * 3 * (size_t)r->nb,
                   r->delta[row], r->c.alpha_deg * VS_DEG, h, nh, r->gap_i + (size_t)row * (size_t)r->nj,
                   r->gap_e + (size_t)row * (size_t)r->nj, r->c.open_mm * VS_MM, title, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", err.msg);
    return -1;
  }
  printf("  %s\n", path);
  return 0;
}

static int draw_curves(const record *r, const char *dir, const char *ext) {
  const size_t n = (size_t)r->rows;
  double *reac = malloc(n * sizeof(double)), *joint[5];
  vs_plot_series hs[5];
  int ns = 0, rc = 0;
  for (size_t i = 0; reac && i < n; i++) reac[i] = r->react[6 * i + 4]; /* upward on the arch */
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
  vs_plot_series rs = {"right support, vertical", reac};
  vs_plot_panel panels[2] = {{{"support reaction (N)", 1.0, 0}, &rs, 1}, {{"hinge joint", 1.0, 1}, hs, ns}};
  vs_plot_axis x = {"support displacement delta (mm)", 1e3, 0};
  char path[1200];
  snprintf(path, sizeof path, "%s/curves.%s", dir, ext);
  vs_error err;
  vs_error_clear(&err);
  if (reac == NULL || vs_plot_curves(path, vs_plot_format_from_path(path), "Reaction and hinges against the support displacement",
                                     &x, r->delta, (int)n, panels, ns > 0 ? 2 : 1, &err) != VS_OK) {
    fprintf(stderr, "voussoir plot: %s\n", reac ? err.msg : "out of memory");
    rc = -1;
  } else {
    printf("  %s\n", path);
  }
  free(reac);
  for (int l = 0; l < 5; l++) free(joint[l]);
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
  record r;
  if (record_open(run, &r) != 0) {
    fprintf(stderr, "voussoir plot: %s\n", r.msg);
    record_free(&r);
    return 2;
  }
  if (dir == NULL) {
    const char *dot = strrchr(run, '.');
    snprintf(defdir, sizeof defdir, "%.*s_plots", dot ? (int)(dot - run) : (int)strlen(run), run);
    dir = defdir;
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
    snprintf(what, sizeof what, "Hinge %c forms (%s)", r.h[i].label,
             r.h[i].order == 4 ? "the fourth" : r.h[i].order == 5 ? "the fifth" : "hinge onset");
    bad |= draw_row(&r, row_at(&r, r.h[i].delta_onset), dir, name, ext, what);
  }
  for (int i = 0; i < r.nl; i++) {
    char name[32], what[96];
    snprintf(name, sizeof name, "limit_%d", i + 1);
    snprintf(what, sizeof what, "Limit point %d", i + 1);
    bad |= draw_row(&r, row_at(&r, r.limits[i]), dir, name, ext, what);
    if (isfinite(r.settled[i])) {
      snprintf(name, sizeof name, "snap_%d_settled", i + 1);
      snprintf(what, sizeof what, "Snap-through %d settled", i + 1);
      bad |= draw_row(&r, row_at(&r, r.settled[i]), dir, name, ext, what);
    }
  }
  if (isfinite(r.collapse)) bad |= draw_row(&r, row_at(&r, r.collapse), dir, "collapse", ext, "Collapse");
  bad |= draw_row(&r, r.rows - 1, dir, "end", ext, "End of the record");
  bad |= draw_curves(&r, dir, ext);
  record_free(&r);
  vs_plot_release();
  return bad ? 1 : 0;
}
