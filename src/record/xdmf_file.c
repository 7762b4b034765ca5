/* The reading of the record a sidecar is written from (the shapes of the datasets it refers
 * to, the rows' times, where the blocks' outlines come from, /xdmf/nan), the sidecar's
 * temporary file, its commit and its name (xdmf.h). Below xdmf.c, which writes the sidecar. */
#define _POSIX_C_SOURCE 200809L /* lstat */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "h5util.h"
#include "outpath.h"
#include "voussoir/output.h"
#include "xdmf.h"
#include "xdmf_internal.h"

/* X_BPTS, the blocks' moved outlines, is found by xdmf_outline_source. */
static const char *const XDMF_PATHS[] = {NULL,
                                         "/geometry/block_connectivity",
                                         "/observables/joint_points/value",
                                         "/geometry/joint_connectivity",
                                         "/observables/delta/time",
                                         "/observables/block_position/value",
                                         "/observables/block_speed/value",
                                         "/observables/joint_N/value",
                                         "/observables/joint_T/value",
                                         "/observables/joint_M/value",
                                         "/observables/joint_gap_i/value",
                                         "/observables/joint_gap_e/value",
                                         "/observables/joint_hinge/value",
                                         "/observables/reactions/value",
                                         "/observables/support_displacement/value",
                                         "/observables/joint_crack/value"};
static const int XDMF_RANKS[] = {3, 2, 3, 2, 1, 3, 2, 2, 2, 2, 2, 2, 2, 2, 2, 3};
_Static_assert(sizeof XDMF_PATHS / sizeof XDMF_PATHS[0] == X_COUNT &&
                   sizeof XDMF_RANKS / sizeof XDMF_RANKS[0] == X_COUNT,
               "a path and a rank for every dataset the sidecar refers to");

/* The dimensions of the dataset at path into dims: 0, or -1 if it is missing, not of rank
 * `rank`, or declares more values than the file holds (vs_h5_read_budget: what is allocated
 * for the sidecar follows from these dimensions). */
static int xdmf_dims_of(hid_t file, const char *path, int rank, hsize_t *dims) {
  hid_t ds = H5Dopen2(file, path, H5P_DEFAULT);
  hid_t sp = ds >= 0 ? H5Dget_space(ds) : H5I_INVALID_HID;
  const int r = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
  if (r == rank) H5Sget_simple_extent_dims(sp, dims, NULL);
  const hssize_t np = r == rank ? H5Sget_simple_extent_npoints(sp) : -1;
  vs_h5_close(sp);
  vs_h5_close(ds);
  return np >= 0 && (size_t)np <= vs_h5_read_budget(file) / sizeof(double) ? 0 : -1;
}

/* 1 if the record's status is "running" (a killed run's, or one being written), or unreadable. */
static int xdmf_running(hid_t file) {
  hid_t a = H5Aexists(file, "status") > 0 ? H5Aopen(file, "status", H5P_DEFAULT) : H5I_INVALID_HID;
  hid_t t = a >= 0 ? vs_h5_vlstr_type() : H5I_INVALID_HID;
  char *v = NULL;
  const int ok = t >= 0 && H5Aread(a, t, &v) >= 0 && v != NULL;
  const int running = !ok || strcmp(v, "running") == 0;
  if (v != NULL) H5free_memory(v);
  vs_h5_close(t);
  vs_h5_close(a);
  return running;
}

/* Where the blocks' outlines come from (see BP_STATES); -1 if the record has none of them and
 * not what they are computed from. rows: lowered to the rows of a per-state dataset. */
static int xdmf_outline_source(hid_t file, xdmf_ctx *x, long *rows) {
  const hsize_t nb = x->ds[X_BCONN].dims[0], pts = nb * x->ds[X_BCONN].dims[1];
  xdmf_ds *d = &x->ds[X_BPTS];
  hsize_t a[3], b[3];
  d->rank = 3;
  d->path = XDMF_BPTS_STATES;
  if (H5Lexists(file, "/observables/block_points", H5P_DEFAULT) > 0) {
    if (xdmf_dims_of(file, d->path, 3, d->dims) < 0 || d->dims[1] != pts || d->dims[2] != 2)
      return -1;
    if ((long)d->dims[0] < *rows) *rows = (long)d->dims[0];
    x->bp_source = BP_STATES;
    return 0;
  }
  if (xdmf_dims_of(file, "/geometry/block_points", 2, a) < 0 || a[0] != pts || a[1] != 2 ||
      xdmf_dims_of(file, "/geometry/block_centroid", 2, b) < 0 || b[0] != nb || b[1] != 2)
    return -1;
  d->path = XDMF_BPTS_FRAMES;
  /* the frames are vouched for by the status, written after them (and flushed) */
  x->bp_source = !xdmf_running(file) && H5Lexists(file, "/xdmf", H5P_DEFAULT) > 0 &&
                         xdmf_dims_of(file, XDMF_BPTS_FRAMES, 3, d->dims) == 0 &&
                         d->dims[1] == pts && d->dims[2] == 2 &&
                         xdmf_dims_of(file, XDMF_BPTS_ROWS, 1, a) == 0 && a[0] == d->dims[0]
                     ? BP_FRAMES
                     : BP_INLINE;
  return 0;
}

long vs_xdmf_shapes(hid_t file, xdmf_ctx *x) {
  long rows = -1;
  for (int i = 0; i < X_COUNT; i++) {
    if (i == X_BPTS) continue; /* see xdmf_outline_source */
    xdmf_ds *d = &x->ds[i];
    d->path = XDMF_PATHS[i];
    d->rank = XDMF_RANKS[i];
    d->dims[1] = d->dims[2] = 1;
    if (xdmf_dims_of(file, d->path, d->rank, d->dims) < 0) return -1;
    if (i != X_BCONN && i != X_JCONN && (rows < 0 || (long)d->dims[0] < rows))
      rows = (long)d->dims[0];
  }
  const hsize_t nb = x->ds[X_BCONN].dims[0], nj = x->ds[X_JCONN].dims[0];
  if (x->ds[X_JCONN].dims[1] != 2 || x->ds[X_JPTS].dims[1] != 2 * nj ||
      x->ds[X_JPTS].dims[2] != 2 || x->ds[X_BPOS].dims[1] != nb || x->ds[X_BPOS].dims[2] != 3 ||
      x->ds[X_BSPEED].dims[1] != nb)
    return -1;
  for (int i = X_N; i <= X_HINGE; i++)
    if (x->ds[i].dims[1] != nj) return -1;
  if (nj < 2 || x->ds[X_REACT].dims[1] != 6 || x->ds[X_SUPPORT].dims[1] != 2 ||
      x->ds[X_CRACK].dims[1] != nj || x->ds[X_CRACK].dims[2] != 2)
    return -1;
  return xdmf_outline_source(file, x, &rows) < 0 ? -1 : rows;
}

/* x->geo for the n listed rows sel: each row's frame of /xdmf/block_points, or its inline frame,
 * whose outlines xdmf_outline computes (the positions' dataset opened, the reference outlines
 * read). Returns 0, or -1 (read error, out of memory). */
static int xdmf_outline_frames(hid_t file, xdmf_ctx *x, const long *sel, long n) {
  if (x->bp_source == BP_STATES) return 0;
  const hsize_t nb = x->ds[X_BCONN].dims[0], np = x->ds[X_BCONN].dims[1];
  const long nf = x->bp_source == BP_FRAMES ? (long)x->ds[X_BPTS].dims[0] : 0;
  int64_t *fr = malloc((size_t)(nf > 0 ? nf : 1) * sizeof *fr);
  x->need = malloc((size_t)(n > 0 ? n : 1) * sizeof *x->need);
  x->geo = malloc((size_t)(n > 0 ? n : 1) * sizeof *x->geo);
  int rc = fr != NULL && x->need != NULL && x->geo != NULL ? 0 : -1;
  if (rc == 0 && nf > 0) {
    hid_t d = H5Dopen2(file, XDMF_BPTS_ROWS, H5P_DEFAULT);
    rc = d >= 0 && H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, fr) >= 0 ? 0 : -1;
    vs_h5_close(d);
  }
  for (long i = 0, f = 0; rc == 0 && i < n; i++) {
    while (f < nf && fr[f] < sel[i]) f++;
    if (f < nf && fr[f] == sel[i]) {
      x->geo[i] = f;
    } else {
      x->geo[i] = -1 - x->n_inl;
      x->need[x->n_inl++] = sel[i];
    }
  }
  if (rc == 0 && x->n_inl > 0) {
    x->ref = malloc(2 * nb * np * sizeof *x->ref);
    x->cen = malloc(2 * nb * sizeof *x->cen);
    x->inl = malloc(XDMF_INLINE_BLOCK * 2 * nb * np * sizeof *x->inl);
    x->pos = H5Dopen2(file, x->ds[X_BPOS].path, H5P_DEFAULT);
    rc = x->ref != NULL && x->cen != NULL && x->inl != NULL && x->pos >= 0 &&
                 vs_h5_read_doubles(file, "/geometry/block_points", x->ref, 2 * nb * np) == 0 &&
                 vs_h5_read_doubles(file, "/geometry/block_centroid", x->cen, 2 * nb) == 0
             ? 0
             : -1;
  }
  free(fr);
  return rc;
}

/* Times of rows [0, rows) of /observables/delta/time into t. */
static herr_t xdmf_read_times(hid_t file, xdmf_ctx *x, long rows, double *t) {
  hid_t td = H5Dopen2(file, x->ds[X_TIME].path, H5P_DEFAULT);
  hid_t fs = td >= 0 ? H5Dget_space(td) : H5I_INVALID_HID;
  hsize_t start[1] = {0}, count[1] = {(hsize_t)rows};
  hid_t ms = H5Screate_simple(1, count, NULL);
  herr_t rc =
      (fs >= 0 && ms >= 0) ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) : -1;
  if (rc >= 0 && rows > 0) rc = H5Dread(td, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, t);
  vs_h5_close(ms);
  vs_h5_close(fs);
  vs_h5_close(td);
  return rc;
}

void vs_xdmf_support_joints(hid_t file, xdmf_ctx *x) {
  const hsize_t nj = x->ds[X_JCONN].dims[0];
  x->sup_joint[0] = 0;
  x->sup_joint[1] = nj > 0 ? nj - 1 : 0;
  double *b = nj > 0 ? malloc(2 * nj * sizeof *b) : NULL;
  if (b != NULL && H5Lexists(file, "/geometry/joint_bodies", H5P_DEFAULT) > 0 &&
      vs_h5_read_doubles(file, "/geometry/joint_bodies", b, 2 * nj) == 0) {
    for (int s = 0; s < 2; s++)
      for (hsize_t k = 0; k < nj; k++)
        if (b[2 * k] == -1.0 - s || b[2 * k + 1] == -1.0 - s) {
          x->sup_joint[s] = k;
          break;
        }
  }
  free(b);
}

int vs_xdmf_has_ground(hid_t file) {
  hsize_t d[2];
  return H5Lexists(file, "/summary", H5P_DEFAULT) > 0 &&
         H5Lexists(file, "/summary/ground", H5P_DEFAULT) > 0 &&
         H5Lexists(file, "/summary/ground/points", H5P_DEFAULT) > 0 &&
         xdmf_dims_of(file, "/summary/ground/points", 2, d) == 0 && d[0] == 2 && d[1] == 2;
}

/* x->curve_lambda, x->n_curve, and x->load_pos, load_q, load_cen (the load's n_loads set to 0
 * when these cannot be read). */
static void xdmf_load_motion(hid_t file, xdmf_ctx *x) {
  hsize_t d[2];
  const hsize_t nb = x->ds[X_BPOS].dims[1];
  if (H5Lexists(file, "/summary/load/curve", H5P_DEFAULT) > 0 &&
      xdmf_dims_of(file, "/summary/load/curve", 2, d) == 0 && d[1] == 2 && d[0] > 0 &&
      (long)d[0] <= x->rows) {
    double *c = malloc(2 * d[0] * sizeof *c);
    x->curve_lambda = malloc(d[0] * sizeof *x->curve_lambda);
    if (c != NULL && x->curve_lambda != NULL &&
        vs_h5_read_doubles(file, "/summary/load/curve", c, 2 * d[0]) == 0) {
      for (hsize_t i = 0; i < d[0]; i++) x->curve_lambda[i] = c[2 * i];
      x->n_curve = (long)d[0];
    }
    free(c);
  }
  x->load_q = malloc(3 * (nb > 0 ? nb : 1) * sizeof *x->load_q);
  x->load_cen = malloc(2 * (nb > 0 ? nb : 1) * sizeof *x->load_cen);
  x->load_pos = H5Dopen2(file, x->ds[X_BPOS].path, H5P_DEFAULT);
  int ok = x->load_q != NULL && x->load_cen != NULL && x->load_pos >= 0 &&
           vs_h5_read_doubles(file, "/geometry/block_centroid", x->load_cen, 2 * nb) == 0;
  for (int i = 0; ok && i < x->n_loads; i++)
    ok = x->loads[5 * i] >= 0.0 && x->loads[5 * i] < (double)nb;
  if (!ok) x->n_loads = 0; /* not drawn */
}

int vs_xdmf_load_row(xdmf_ctx *x, hsize_t r) {
  const hsize_t nb = x->ds[X_BPOS].dims[1], start[3] = {r, 0, 0}, count[3] = {1, nb, 3};
  hid_t fs = H5Dget_space(x->load_pos), ms = H5Screate_simple(3, count, NULL);
  int rc = fs >= 0 && ms >= 0 &&
                   H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
                   H5Dread(x->load_pos, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, x->load_q) >= 0
               ? 0
               : -1;
  vs_h5_close(ms);
  vs_h5_close(fs);
  return rc;
}

void vs_xdmf_loads(hid_t file, xdmf_ctx *x) {
  hsize_t d[2];
  x->n_loads = 0;
  x->loads = NULL;
  x->n_curve = 0;
  x->curve_lambda = x->load_q = x->load_cen = NULL;
  x->load_pos = H5I_INVALID_HID;
  if (H5Lexists(file, "/summary", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "/summary/load", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "/summary/load/forces", H5P_DEFAULT) <= 0 ||
      xdmf_dims_of(file, "/summary/load/forces", 2, d) != 0 || d[1] != 5 || d[0] == 0 ||
      d[0] > 1000000)
    return;
  x->loads = malloc(5 * d[0] * sizeof *x->loads);
  if (x->loads != NULL && vs_h5_read_doubles(file, "/summary/load/forces", x->loads, 5 * d[0]) == 0)
    x->n_loads = (int)d[0];
  else {
    free(x->loads);
    x->loads = NULL;
  }
  if (x->n_loads > 0) xdmf_load_motion(file, x);
}

double vs_xdmf_joint_length(hid_t file) {
  hsize_t d[1];
  if (H5Lexists(file, "/geometry", H5P_DEFAULT) <= 0 ||
      H5Lexists(file, "/geometry/joint_length", H5P_DEFAULT) <= 0 ||
      xdmf_dims_of(file, "/geometry/joint_length", 1, d) != 0 || d[0] == 0)
    return 0.0;
  double *v = malloc(d[0] * sizeof *v), len = 0.0;
  if (v != NULL && vs_h5_read_doubles(file, "/geometry/joint_length", v, d[0]) == 0 && v[0] > 0.0)
    len = v[0];
  free(v);
  return len;
}

hsize_t vs_xdmf_nan_count(hid_t file) {
  hsize_t n = 0;
  if (H5Lexists(file, "/xdmf", H5P_DEFAULT) <= 0 || H5Lexists(file, XDMF_NAN, H5P_DEFAULT) <= 0)
    return 0;
  hid_t ds = H5Dopen2(file, XDMF_NAN, H5P_DEFAULT);
  hid_t sp = ds >= 0 ? H5Dget_space(ds) : H5I_INVALID_HID;
  if (sp < 0 || H5Sget_simple_extent_ndims(sp) != 1 || H5Sget_simple_extent_dims(sp, &n, NULL) < 0)
    n = 0;
  vs_h5_close(sp);
  vs_h5_close(ds);
  return n;
}

vs_status vs_xdmf_open_tmp(const char *xmf_path, char *tmp, size_t size, FILE **f,
                           vs_error *err) {
  snprintf(tmp, size, "%s" VS_XDMF_TMP, xmf_path);
  struct stat sb;
  if (lstat(xmf_path, &sb) == 0 && !S_ISREG(sb.st_mode))
    return vs_error_set(err, VS_ERR_INVALID, "output: %s: exists and is not a regular file",
                        xmf_path);
  vs_error e; /* the working file: created anew, whatever is in its way refused */
  const vs_status st = vs_outpath_fopen(tmp, f, &e);
  return st == VS_OK ? st : vs_error_set(err, st, "output: %.500s", e.msg);
}

vs_status vs_xdmf_close_tmp(FILE *f, const char *tmp, const char *xmf_path, vs_error *err) {
  const int bad = ferror(f);
  errno = 0;
  const int rc = fflush(f) != 0 || bad ? -1 : 0;
  const int e = errno;
  if (fclose(f) == 0 && rc == 0) return VS_OK;
  remove(tmp);
  return vs_error_set(err, VS_ERR_IO, "output: %s: cannot write: %s", xmf_path,
                      rc == 0 ? strerror(errno) : e != 0 ? strerror(e) : "write error");
}

vs_status vs_xdmf_publish(const char *tmp, const char *xmf_path, vs_error *err) {
  const int rc = vs_outpath_replace(tmp, xmf_path);
  const int e = errno;
  if (rc != 0) remove(tmp);
  if (rc == 2)
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: %s: became something other than a regular file during the run; "
                        "not renamed over %s", tmp, xmf_path);
  if (rc > 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: %s: became something other than a regular file; not replaced",
                        xmf_path);
  if (rc < 0)
    return vs_error_set(err, VS_ERR_IO, "output: %s: cannot write: %s", xmf_path, strerror(e));
  return VS_OK;
}

vs_status vs_xdmf_listing(hid_t file, xdmf_ctx *x, long rows, int max_grids,
                          const char *h5_path, double **t, long **sel, long *n,
                          vs_error *err) {
  *t = malloc((size_t)(rows > 0 ? rows : 1) * sizeof **t);
  if (*t == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  if (xdmf_read_times(file, x, rows, *t) < 0)
    return vs_h5_fail(err, h5_path, "cannot read /observables/delta/time");
  if (x->n_curve > 0) /* a load run: its path's rows share the held time; each row its number */
    for (long r = 0; r < rows; r++) (*t)[r] = (double)r;
  *n = vs_xdmf_rows(*t, rows, max_grids, NULL);
  *sel = malloc((size_t)(*n > 0 ? *n : 1) * sizeof **sel);
  if (*sel == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  vs_xdmf_rows(*t, rows, max_grids, *sel);
  if (xdmf_outline_frames(file, x, *sel, *n) < 0)
    return vs_h5_fail(err, h5_path, "cannot compute the blocks' outlines (out of memory, or "
                                    "/geometry or /observables/block_position unreadable)");
  return VS_OK;
}

/* The record's extension (".h5", ".hdf5", ".hdf") replaced by ".xmf", or ".xmf" appended. */
char *vs_output_xdmf_path_for(const char *path) {
  const char *exts[] = {".h5", ".hdf5", ".hdf"};
  size_t n = strlen(path), keep = n;
  for (size_t i = 0; i < sizeof exts / sizeof exts[0]; i++) {
    size_t e = strlen(exts[i]);
    if (n > e && strcmp(path + n - e, exts[i]) == 0) keep = n - e;
  }
  char *x = malloc(keep + 5);
  if (x == NULL) return NULL;
  memcpy(x, path, keep);
  memcpy(x + keep, ".xmf", 5);
  return x;
}
