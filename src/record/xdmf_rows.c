/* The rows a sidecar lists and the blocks' outlines moved to them: the sidecar computes those
 * of a record that lacks them (xdmf.c), the record's writer stores them (/xdmf/block_points). */
#include <math.h>
#include <stdlib.h>

#include "h5util.h"
#include "xdmf.h"
#include "xdmf_internal.h"

long vs_xdmf_stride(long rows, int max_grids) {
  const long k = (rows + max_grids - 1) / max_grids;
  return k > 1 ? k : 1;
}

long vs_xdmf_rows(const double *t, long rows, int max_grids, long *sel) {
  const long k = vs_xdmf_stride(rows, max_grids);
  long n = 0;
  double t_last = -INFINITY;
  for (long r = 0; r < rows; r++) {
    if ((r % k != 0 && r != rows - 1) || !(t[r] > t_last) || !isfinite(t[r])) continue;
    if (sel != NULL) sel[n] = r;
    n++;
    t_last = t[r];
  }
  return n;
}

/* The outline frame of block positions q (one row: nb x 3) into out (nb * np * 2). */
static void outline_frame(const double *q, int nb, int np, const double *ref,
                          const double *centroid, float *out) {
  for (int b = 0; b < nb; b++) {
    const double c = cos(q[3 * b + 2]), s = sin(q[3 * b + 2]);
    for (int k = 0; k < np; k++) {
      const size_t i = 2 * ((size_t)b * (size_t)np + (size_t)k);
      double p[2];
      vs_xdmf_move(centroid[2 * b], centroid[2 * b + 1], q[3 * b], q[3 * b + 1], c, s, ref[i],
                   ref[i + 1], p);
      out[i] = (float)p[0];
      out[i + 1] = (float)p[1];
    }
  }
}

int vs_xdmf_outlines(hid_t pos, const long *sel, long n, int nb, int np, const double *ref,
                     const double *centroid, float *out) {
  enum { BLOCK = 64 };
  const size_t w = 3 * (size_t)nb, frame = 2 * (size_t)nb * (size_t)np;
  double *q = malloc(BLOCK * (w > 0 ? w : 1) * sizeof *q);
  hid_t fs = H5Dget_space(pos);
  int rc = q != NULL && fs >= 0 ? 0 : -1;
  for (long i = 0, j; rc == 0 && i < n; i = j + 1) {
    for (j = i; j + 1 < n && sel[j + 1] - sel[i] < BLOCK;) j++; /* rows sel[i..j]: one read */
    const hsize_t start[3] = {(hsize_t)sel[i], 0, 0},
                  count[3] = {(hsize_t)(sel[j] - sel[i] + 1), (hsize_t)nb, 3};
    hid_t ms = H5Screate_simple(3, count, NULL);
    if (ms < 0 || H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) < 0 ||
        H5Dread(pos, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, q) < 0)
      rc = -1;
    vs_h5_close(ms);
    for (long k = i; rc == 0 && k <= j; k++)
      outline_frame(q + (size_t)(sel[k] - sel[i]) * w, nb, np, ref, centroid,
                    out + (size_t)k * frame);
  }
  vs_h5_close(fs);
  free(q);
  return rc;
}
