/* The model's CSC patterns (model_internal.h), built once at creation: the dof maps of the static
 * and the extended unknowns, every body's and every joint's couplings sorted into CSC, the scatter
 * map of each joint's 6x6 matrix, and the CSC helpers the assembly uses. */
#include "model_internal.h"

#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* Free p's arrays and zero it. */
void vs_model_pattern_free(vs_pattern *p) {
  free(p->scatter);
  free(p->jdof);
  free(p->full);
  free(p->colptr);
  free(p->rowind);
  free(p->dof);
  memset(p, 0, sizeof *p);
}

/* Sort the np (column, row) pairs by column, then row: counting sort on the columns (0..n-1),
 * insertion sort of each column's few rows -- linear in the pairs, where a comparison sort
 * was the largest cost of creating a model. Returns -1 when out of memory. */
static int sort_pairs(sunindextype *pairs, size_t np, int n) {
  size_t *start = calloc((size_t)n + 1, sizeof *start);
  sunindextype *out = malloc((np > 0 ? 2 * np : 1) * sizeof *out);
  if (start == NULL || out == NULL) {
    free(start);
    free(out);
    return -1;
  }
  for (size_t e = 0; e < np; e++) start[pairs[2 * e] + 1]++;
  for (int c = 0; c < n; c++) start[c + 1] += start[c];
  for (size_t e = 0; e < np; e++) { /* stable: start[c] runs over column c's slots */
    const size_t at = start[pairs[2 * e]]++;
    out[2 * at] = pairs[2 * e];
    out[2 * at + 1] = pairs[2 * e + 1];
  }
  for (size_t e = 1; e < np; e++) { /* rows within a column (columns are in order already) */
    const sunindextype c = out[2 * e], r = out[2 * e + 1];
    size_t i = e;
    for (; i > 0 && out[2 * i - 2] == c && out[2 * i - 1] > r; i--) out[2 * i + 1] = out[2 * i - 1];
    out[2 * i + 1] = r;
  }
  memcpy(pairs, out, 2 * np * sizeof *pairs);
  free(start);
  free(out);
  return 0;
}

/* Add the couplings among n unknowns d[] (entries < 0 skipped) to the pair list. */
static void add_pairs(const int *d, int n, sunindextype *pairs, size_t *np) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      if (d[i] >= 0 && d[j] >= 0) {
        pairs[2 * *np] = d[j];
        pairs[2 * *np + 1] = d[i];
        (*np)++;
      }
}

/* The scatter map of p: where each entry of every joint's 6x6 matrix adds in the CSC values. */
static vs_status build_scatter(const vs_model *m, vs_pattern *p, vs_error *err) {
  const int nj = m->g->n_joints;
  p->scatter = malloc(36 * (size_t)(nj > 0 ? nj : 1) * sizeof *p->scatter);
  p->jdof = malloc(6 * (size_t)(nj > 0 ? nj : 1) * sizeof *p->jdof);
  p->full = malloc((size_t)(nj > 0 ? nj : 1));
  if (p->scatter == NULL || p->jdof == NULL || p->full == NULL)
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  for (int k = 0; k < nj; k++) {
    int *d = p->jdof + 6 * k;
    vs_model_joint_dofs(m, p, k, d);
    p->full[k] = d[0] >= 0 && d[1] >= 0 && d[2] >= 0 && d[3] >= 0 && d[4] >= 0 && d[5] >= 0;
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++)
        p->scatter[36 * k + 6 * i + j] =
            (d[i] >= 0 && d[j] >= 0) ? vs_model_csc_pos(p, d[i], d[j]) : -1;
  }
  return VS_OK;
}

/* CSC pattern of p (p->n, p->dof set by the caller): every body's components with each other
 * and every joint's two bodies' components with each other. */
static vs_status build_pattern(const vs_model *m, vs_pattern *p, vs_error *err) {
  const vs_geometry *g = m->g;
  const size_t cap = 9 * (size_t)(g->n_blocks + 2) + 36 * (size_t)g->n_joints;
  sunindextype *pairs = malloc(2 * cap * sizeof *pairs);
  p->colptr = malloc(((size_t)p->n + 1) * sizeof *p->colptr);
  if (pairs == NULL || p->colptr == NULL) {
    free(pairs);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
  size_t np = 0;
  for (int b = 0; b < g->n_blocks + 2; b++) add_pairs(p->dof + 3 * b, 3, pairs, &np);
  for (int k = 0; k < g->n_joints; k++) {
    const int sa = body_slot(m, g->joints[k].a), sb = body_slot(m, g->joints[k].b);
    int d[6];
    for (int c = 0; c < 3; c++) {
      d[c] = p->dof[3 * sa + c];
      d[3 + c] = p->dof[3 * sb + c];
    }
    add_pairs(d, 6, pairs, &np);
  }
  if (sort_pairs(pairs, np, p->n) != 0) {
    free(pairs);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
  p->rowind = malloc((np > 0 ? np : 1) * sizeof *p->rowind);
  if (p->rowind == NULL) {
    free(pairs);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
  int w = 0, col = 0;
  for (size_t e = 0; e < np; e++) {
    if (e > 0 && pairs[2 * e] == pairs[2 * e - 2] && pairs[2 * e + 1] == pairs[2 * e - 1]) continue;
    while (col <= pairs[2 * e]) p->colptr[col++] = w;
    p->rowind[w++] = pairs[2 * e + 1];
  }
  while (col <= p->n) p->colptr[col++] = w;
  p->nnz = w;
  free(pairs);
  return build_scatter(m, p, err);
}

/* Dof maps: statics (blocks, then the pinned supports' rotations) and the extended system
 * (blocks, then all six components of the two supports). */
vs_status vs_model_build_patterns(vs_model *m, vs_error *err) {
  const int nb = m->g->n_blocks, nslot = 3 * (nb + 2);
  vs_model_pattern_free(&m->pat);
  vs_model_pattern_free(&m->pate);
  m->pat.dof = malloc((size_t)nslot * sizeof(int));
  m->pate.dof = malloc((size_t)nslot * sizeof(int));
  if (m->pat.dof == NULL || m->pate.dof == NULL)
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  for (int i = 0; i < nslot; i++) {
    m->pate.dof[i] = i;
    m->pat.dof[i] = i < 3 * nb ? i : -1;
  }
  m->pat.n = 3 * nb;
  for (int s = 0; s < 2; s++)
    if (m->pinned[s]) m->pat.dof[3 * (nb + s) + 2] = m->pat.n++;
  m->pate.n = nslot;
  m->n = m->pat.n;
  vs_status st = build_pattern(m, &m->pat, err);
  return st == VS_OK ? build_pattern(m, &m->pate, err) : st;
}

/* The unknowns of joint k's six components (body a's, then b's) in pattern p, -1 if prescribed. */
void vs_model_joint_dofs(const vs_model *m, const vs_pattern *p, int k, int d[6]) {
  const int sa = body_slot(m, m->g->joints[k].a), sb = body_slot(m, m->g->joints[k].b);
  for (int c = 0; c < 3; c++) {
    d[c] = p->dof[3 * sa + c];
    d[3 + c] = p->dof[3 * sb + c];
  }
}

/* Position in the CSC data of entry (row, col); the rows of a column are sorted. */
sunindextype vs_model_csc_pos(const vs_pattern *p, int row, int col) {
  sunindextype lo = p->colptr[col], hi = p->colptr[col + 1] - 1;
  while (lo < hi) {
    const sunindextype mid = (lo + hi) / 2;
    if (p->rowind[mid] < row) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

/* Write the CSC pattern into A, zero its values and return them. */
double *vs_model_csc_reset(const vs_pattern *p, SUNMatrix A) {
  memcpy(SUNSparseMatrix_IndexPointers(A), p->colptr, ((size_t)p->n + 1) * sizeof(sunindextype));
  memcpy(SUNSparseMatrix_IndexValues(A), p->rowind, (size_t)p->nnz * sizeof(sunindextype));
  double *data = SUNSparseMatrix_Data(A);
  memset(data, 0, (size_t)p->nnz * sizeof *data);
  return data;
}
