/* Positive definiteness by a CHOLMOD Cholesky attempt on the symmetric part (stability.h). */
#include "voussoir/stability.h"

#include <cholmod.h>
#include <stdlib.h>
#include <sunmatrix/sunmatrix_sparse.h>

struct vs_spd {
  int n;
  cholmod_common c;
  cholmod_factor *L; /* symbolic analysis, kept */
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

int vs_spd_test(vs_spd *s, SUNMatrix K) {
  cholmod_sparse *A = sym_part(s, K);
  if (A == NULL) return -1;
  if (s->L == NULL) s->L = cholmod_analyze(A, &s->c);
  int result = -1;
  if (s->L != NULL) {
    cholmod_factorize(A, s->L, &s->c);
    if (s->c.status == CHOLMOD_OK && s->L->minor == (size_t)s->n) result = 1;
    else if (s->c.status == CHOLMOD_NOT_POSDEF || s->L->minor < (size_t)s->n) result = 0;
  }
  cholmod_free_sparse(&A, &s->c);
  return result;
}
