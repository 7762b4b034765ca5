/* Positive definiteness by a Cholesky attempt (LAPACK's banded dpbtrf) on the symmetric part
 * (stability.h).
 *
 * Why LAPACK's band Cholesky rather than CHOLMOD's sparse one (both measured on the reference
 * run, 71 tests of the 165-unknown tangent, half bandwidth 5): a test takes 88 k instructions
 * here (21 k to fill the band, 67 k in dpbtrf) against 163 k with CHOLMOD (simplicial LL', its
 * analysis kept and the symmetric part filled in place: 21 k to fill, 38 k to transpose, 97 k
 * to factor, 6 k for the first test's analysis), so the run takes 359 M instructions instead of
 * 365 M (callgrind); and CHOLMOD brings five libraries to the program's start-up (cholmod,
 * camd, ccolamd, metis, libgomp: 24 instead of 19), which made `voussoir --version` take 2.9 ms
 * of CPU instead of 1.9 (perf stat, medians of 7 rounds of -r 50). LAPACK is linked already,
 * for the natural frequencies (modal.c). */
#include "stability.h"

#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* LAPACK (Fortran ABI, gfortran: the hidden length of the character argument at the end). */
extern void dpbtrf_(const char *uplo, const int *n, const int *kd, double *ab, const int *ldab,
                    int *info, size_t uplo_len);

struct vs_spd {
  int n;
  int *inv;      /* the order: inv[old] = new */
  int kd, ld;    /* half bandwidth of the pattern in that order; ld = kd + 1 */
  size_t nnz;    /* entries of the tangent the map was built from */
  size_t *at;    /* per entry (r, c) of K: the place of the upper triangle's (r, c) or (c, r) */
  double *w;     /* ... and its weight: 1 on the diagonal, 1/2 off it (half of K + K^T) */
  double *ab;    /* the upper band, LAPACK's storage: (i, j), i <= j, at ab[kd + i - j + j ld] */
};

vs_status vs_spd_create(int n, const int *perm, vs_spd **out, vs_error *err) {
  *out = NULL;
  if (n < 1) return vs_error_set(err, VS_ERR_INVALID, "stability: %d unknowns (allowed: >= 1)", n);
  vs_spd *s = calloc(1, sizeof *s);
  if (s != NULL) s->inv = malloc((size_t)n * sizeof *s->inv);
  if (s == NULL || s->inv == NULL) {
    vs_spd_destroy(&s);
    return vs_error_set(err, VS_ERR_NOMEM, "stability: out of memory");
  }
  s->n = n;
  for (int i = 0; i < n; i++) s->inv[i] = -1;
  for (int i = 0; i < n; i++) {
    const int old = perm != NULL ? perm[i] : i;
    if (old < 0 || old >= n || s->inv[old] >= 0) {
      vs_spd_destroy(&s);
      return vs_error_set(err, VS_ERR_INVALID,
                          "stability: the order is not a permutation (entry %d: %d)", i, old);
    }
    s->inv[old] = i;
  }
  *out = s;
  return VS_OK;
}

void vs_spd_destroy(vs_spd **sp) {
  if (sp == NULL || *sp == NULL) return;
  vs_spd *s = *sp;
  free(s->inv), free(s->at), free(s->w), free(s->ab);
  free(s);
  *sp = NULL;
}

/* The first test: the half bandwidth in the order and where each entry of K goes in the band. */
static int build_map(vs_spd *s, SUNMatrix K) {
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(K), *ri = SUNSparseMatrix_IndexValues(K);
  const size_t nnz = (size_t)cp[s->n];
  int kd = 0;
  for (int c = 0; c < s->n; c++)
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++) {
      if (ri[e] < 0 || ri[e] >= s->n) return -1;
      const int d = abs(s->inv[ri[e]] - s->inv[c]);
      if (d > kd) kd = d;
    }
  s->at = malloc((nnz + 1) * sizeof *s->at);
  s->w = malloc((nnz + 1) * sizeof *s->w);
  s->ab = malloc((size_t)(kd + 1) * (size_t)s->n * sizeof *s->ab);
  if (s->at == NULL || s->w == NULL || s->ab == NULL) {
    free(s->at), free(s->w), free(s->ab);
    s->at = NULL, s->w = NULL, s->ab = NULL;
    return -1;
  }
  s->kd = kd, s->ld = kd + 1, s->nnz = nnz;
  for (int c0 = 0; c0 < s->n; c0++)
    for (sunindextype e = cp[c0]; e < cp[c0 + 1]; e++) {
      const int r = s->inv[ri[e]], c = s->inv[c0], lo = r < c ? r : c, hi = r < c ? c : r;
      s->at[e] = (size_t)(kd + lo - hi) + (size_t)hi * (size_t)s->ld;
      s->w[e] = lo == hi ? 1.0 : 0.5;
    }
  return 0;
}

int vs_spd_test(vs_spd *s, SUNMatrix K) {
  if (s->ab == NULL && build_map(s, K) != 0) return -1;
  const double *x = SUNSparseMatrix_Data(K);
  /* dpbtrf overwrites the band with its factor: cleared, then every entry adds its share */
  memset(s->ab, 0, (size_t)s->ld * (size_t)s->n * sizeof *s->ab);
  for (size_t e = 0; e < s->nnz; e++) s->ab[s->at[e]] += s->w[e] * x[e];
  int info = 0;
  dpbtrf_("U", &s->n, &s->kd, s->ab, &s->ld, &info, 1);
  /* info > 0: the leading minor of that order is not positive definite */
  return info == 0 ? 1 : info > 0 ? 0 : -1;
}
