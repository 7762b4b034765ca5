/* Positive definiteness by a CHOLMOD Cholesky attempt on the symmetric part (stability.h). */
#include "voussoir/stability.h"

#include <cholmod.h>
#include <stdlib.h>
#include <sunmatrix/sunmatrix_sparse.h>

struct vs_spd {
  int n;
  cholmod_common c;
  cholmod_factor *L; /* symbolic analysis, kept */
  cholmod_sparse *A; /* the symmetric part's lower triangle, its pattern built at the first test */
  size_t nnz_k;      /* entries of the tangent the pattern was built from */
  size_t *to;        /* per entry of the tangent: the entry of A it adds to */
  unsigned char *first; /* ... and whether it is the first to, which sets instead of adding */
};

vs_status vs_spd_create(int n, vs_spd **out, vs_error *err) {
  *out = NULL;
  vs_spd *s = calloc(1, sizeof *s);
  if (s == NULL) return vs_error_set(err, VS_ERR_NOMEM, "stability: out of memory");
  s->n = n;
  cholmod_start(&s->c);
  s->c.print = 0;        /* errors are returned, not printed */
  s->c.error_handler = NULL;
  s->c.quick_return_if_not_posdef = 1;
  s->c.supernodal = CHOLMOD_SIMPLICIAL; /* small matrices; the simplicial LL' stops at the minor */
  s->c.final_ll = 1;
  *out = s;
  return VS_OK;
}

void vs_spd_destroy(vs_spd **sp) {
  if (sp == NULL || *sp == NULL) return;
  vs_spd *s = *sp;
  if (s->L != NULL) cholmod_free_factor(&s->L, &s->c);
  if (s->A != NULL) cholmod_free_sparse(&s->A, &s->c);
  free(s->to);
  free(s->first);
  cholmod_finish(&s->c);
  free(s);
  *sp = NULL;
}

/* The lower triangle of (K + K^T) / 2 as a CHOLMOD symmetric matrix (stype -1). */
static cholmod_sparse *sym_part(vs_spd *s, SUNMatrix K) {
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(K), *ri = SUNSparseMatrix_IndexValues(K);
  const double *x = SUNSparseMatrix_Data(K);
  const size_t nnz = (size_t)cp[s->n];
  cholmod_triplet *T = cholmod_allocate_triplet((size_t)s->n, (size_t)s->n, 2 * nnz, -1,
                                                CHOLMOD_REAL, &s->c);
  if (T == NULL) return NULL;
  int *ti = T->i, *tj = T->j;
  double *tx = T->x;
  size_t k = 0;
  for (int j = 0; j < s->n; j++)
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      const int i = (int)ri[p];
      /* entry (i, j) adds half to (i, j) and half to (j, i): both land in the lower triangle */
      ti[k] = i > j ? i : j;
      tj[k] = i > j ? j : i;
      tx[k++] = i == j ? x[p] : 0.5 * x[p];
    }
  T->nnz = k;
  cholmod_sparse *A = cholmod_triplet_to_sparse(T, k, &s->c); /* sums duplicates */
  cholmod_free_triplet(&T, &s->c);
  return A;
}

/* The position in A (sorted columns) of entry (row, col) of K's lower-triangle image. */
static size_t lower_pos(const cholmod_sparse *A, int row, int col) {
  const int *ap = A->p, *ai = A->i;
  const int r = row > col ? row : col, c = row > col ? col : row;
  int lo = ap[c], hi = ap[c + 1] - 1;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    if (ai[mid] < r) lo = mid + 1;
    else hi = mid;
  }
  return (size_t)lo;
}

/* The first test: A from the triplets (sym_part), and where each entry of K goes in it. */
static int build_map(vs_spd *s, SUNMatrix K) {
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(K), *ri = SUNSparseMatrix_IndexValues(K);
  s->nnz_k = (size_t)cp[s->n];
  s->A = sym_part(s, K);
  s->to = malloc((s->nnz_k > 0 ? s->nnz_k : 1) * sizeof *s->to);
  s->first = malloc(s->nnz_k > 0 ? s->nnz_k : 1);
  unsigned char *seen = calloc(s->A != NULL ? (size_t)((int *)s->A->p)[s->n] + 1 : 1, 1);
  if (s->A == NULL || s->to == NULL || s->first == NULL || seen == NULL) {
    free(seen);
    return -1;
  }
  for (int j = 0; j < s->n; j++)
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      const size_t e = lower_pos(s->A, (int)ri[p], j);
      s->to[p] = e;
      s->first[p] = !seen[e];
      seen[e] = 1;
    }
  free(seen);
  return 0;
}

/* A's values from K's through the map: an entry set by its first contribution, the other (the
 * transposed entry) added, as the triplets summed them: the same bits. */
static void fill_values(vs_spd *s, SUNMatrix K) {
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(K), *ri = SUNSparseMatrix_IndexValues(K);
  const double *x = SUNSparseMatrix_Data(K);
  double *ax = s->A->x;
  for (int j = 0; j < s->n; j++)
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      const double v = ri[p] == j ? x[p] : 0.5 * x[p];
      if (s->first[p]) ax[s->to[p]] = v;
      else ax[s->to[p]] += v;
    }
}

int vs_spd_test(vs_spd *s, SUNMatrix K) {
  /* the pattern is fixed (stability.h): A and the map are built once */
  if (s->A == NULL || s->nnz_k != (size_t)SUNSparseMatrix_IndexPointers(K)[s->n]) {
    if (s->A != NULL) cholmod_free_sparse(&s->A, &s->c);
    if (s->L != NULL) cholmod_free_factor(&s->L, &s->c);
    free(s->to), free(s->first);
    s->to = NULL, s->first = NULL;
    if (build_map(s, K) != 0) return -1;
  } else {
    fill_values(s, K);
  }
  if (s->L == NULL) s->L = cholmod_analyze(s->A, &s->c);
  int result = -1;
  if (s->L != NULL) {
    cholmod_factorize(s->A, s->L, &s->c);
    if (s->c.status == CHOLMOD_OK && s->L->minor == (size_t)s->n) result = 1;
    else if (s->c.status == CHOLMOD_NOT_POSDEF || s->L->minor < (size_t)s->n) result = 0;
  }
  return result;
}
