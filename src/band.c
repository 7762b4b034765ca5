/* Banded LU (partial pivoting) and Cholesky of a CSC matrix in a bandwidth-reducing order, and
 * a SUNDIALS linear solver on it (band.h). LU storage follows LAPACK's dgbtrf: entry (r, c) of
 * the permuted matrix at ab[kl + ku + r - c + c ld], ld = 2 kl + ku + 1, the top kl rows
 * taking the fill of the row interchanges; the symmetric part's upper triangle at
 * sb[ks + r - c + c (ks + 1)], r <= c. */
#include "voussoir/band.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* Threshold partial pivoting (KLU's default tolerance): the diagonal stays the pivot unless it
 * is below this fraction of the largest entry of its column. Every interchange widens U by the
 * distance of the rows swapped, and the tangent's rows differ in units (forces and moments), so
 * plain partial pivoting interchanged rows at most steps and doubled the work; with the
 * threshold the growth of the factors stays bounded by 1 / tolerance per step, as in KLU. */
static const double VS_BAND_PIVOT_TOL = 1e-3;

struct vs_band {
  int n, kl, ku, ld; /* LU band */
  int ks;            /* the symmetric part's half bandwidth, max(kl, ku) */
  int *perm, *inv;   /* the order: perm[new] = old, inv[old] = new */
  size_t nnz;
  size_t *lu_at;     /* per CSC entry: its place in ab (entries do not repeat: set, not added) */
  size_t *zero_at;   /* the places of ab no entry sets, cleared before a factorisation: first */
  size_t nzero, nhole; /* the nhole inside the band, then the top kl rows of the interchanges */
  int fill_clean;    /* those top rows are still zero (no interchange since they were cleared) */
  size_t *s_at;      /* ... in sb (the upper triangle's place of (r, c) and (c, r)) */
  double *s_w;       /* ... and its weight there: 1 on the diagonal, else 1/2 */
  double *ab, *sb, *w;
  double *rdiag;     /* 1 / U(j, j) of the last factorisation: the solve multiplies */
  int *ipiv;         /* row interchanged with row j at step j */
  int ub;            /* U's upper bandwidth in the last factorisation (ku up to kl + ku) */
  int natural;       /* the order is the natural one: solves need no permutation */
  int swapped;       /* the last factorisation interchanged rows */
  int singular;      /* the last factorisation met a zero pivot */
};

/* --- the order: reverse Cuthill-McKee on the symmetric closure of the pattern --- */

typedef struct {
  int n;
  int *start, *adj, *deg; /* CSR adjacency without self loops or repeats */
} graph;

static void graph_free(graph *g) {
  free(g->start), free(g->adj), free(g->deg);
}

static int graph_build(int n, const sunindextype *cp, const sunindextype *ri, graph *g) {
  const size_t nnz = (size_t)cp[n];
  g->n = n;
  g->start = calloc((size_t)n + 1, sizeof *g->start);
  g->adj = malloc((2 * nnz + 1) * sizeof *g->adj);
  g->deg = calloc((size_t)n + 1, sizeof *g->deg);
  int *mark = malloc(((size_t)n + 1) * sizeof *mark);
  if (g->start == NULL || g->adj == NULL || g->deg == NULL || mark == NULL) {
    free(mark);
    return -1;
  }
  for (int c = 0; c < n; c++) /* counts of both directions, repeats included */
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++)
      if (ri[e] != c) g->start[ri[e] + 1]++, g->start[c + 1]++;
  for (int i = 0; i < n; i++) g->start[i + 1] += g->start[i];
  int *fill = g->deg; /* fill positions, then the degrees */
  for (int i = 0; i < n; i++) fill[i] = g->start[i];
  for (int c = 0; c < n; c++)
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++) {
      const int r = (int)ri[e];
      if (r == c) continue;
      g->adj[fill[r]++] = c;
      g->adj[fill[c]++] = r;
    }
  for (int i = 0; i < n; i++) mark[i] = -1;
  for (int i = 0; i < n; i++) { /* drop repeats in place, keeping the first of each */
    int k = g->start[i];
    const int end = fill[i];
    for (int e = g->start[i]; e < end; e++)
      if (mark[g->adj[e]] != i) mark[g->adj[e]] = i, g->adj[k++] = g->adj[e];
    g->deg[i] = k - g->start[i];
  }
  free(mark);
  return 0;
}

/* Breadth-first levels from s over the unvisited nodes (level[] -1): the order into q (from
 * q[0]), its count returned; *last the lowest-degree node of the last level. With cm, each
 * node's new neighbours are taken by increasing degree (Cuthill-McKee). */
static int bfs(const graph *g, int s, int *level, int *q, int cm, int *last) {
  int head = 0, tail = 0;
  q[tail++] = s;
  level[s] = 0;
  while (head < tail) {
    const int u = q[head++], first = tail;
    for (int e = g->start[u]; e < g->start[u] + g->deg[u]; e++) {
      const int v = g->adj[e];
      if (level[v] >= 0) continue;
      level[v] = level[u] + 1;
      q[tail++] = v;
    }
    if (!cm) continue;
    for (int i = first + 1; i < tail; i++) { /* insertion sort by (degree, index) */
      const int v = q[i];
      int j = i;
      for (; j > first && (g->deg[q[j - 1]] > g->deg[v] ||
                           (g->deg[q[j - 1]] == g->deg[v] && q[j - 1] > v));
           j--)
        q[j] = q[j - 1];
      q[j] = v;
    }
  }
  int best = q[tail - 1];
  for (int i = tail - 1; i >= 0 && level[q[i]] == level[q[tail - 1]]; i--)
    if (g->deg[q[i]] < g->deg[best] || (g->deg[q[i]] == g->deg[best] && q[i] < best)) best = q[i];
  *last = best;
  return tail;
}

/* perm[new] = old by reverse Cuthill-McKee, each connected part from a pseudo-peripheral node
 * (the far end of repeated breadth-first searches). */
static int rcm(const graph *g, int *perm) {
  const int n = g->n;
  int *level = malloc(((size_t)n + 1) * sizeof *level), *q = malloc(((size_t)n + 1) * sizeof *q);
  if (level == NULL || q == NULL) {
    free(level), free(q);
    return -1;
  }
  for (int i = 0; i < n; i++) level[i] = -1;
  int done = 0;
  while (done < n) {
    int s = -1; /* the unvisited node of least degree */
    for (int i = 0; i < n; i++)
      if (level[i] < 0 && (s < 0 || g->deg[i] < g->deg[s])) s = i;
    int depth = -1;
    for (int it = 0; it < 8; it++) { /* move s to the far end while the part gets deeper */
      int far = s;
      const int cnt = bfs(g, s, level, q + done, 0, &far);
      const int d = level[q[done + cnt - 1]];
      for (int i = 0; i < cnt; i++) level[q[done + i]] = -1;
      if (d <= depth) break;
      depth = d;
      s = far;
    }
    int far = s;
    const int cnt = bfs(g, s, level, q + done, 1, &far);
    done += cnt;
  }
  for (int i = 0; i < n; i++) perm[i] = q[n - 1 - i];
  free(level), free(q);
  return 0;
}

/* Lower and upper bandwidths of the pattern in the order inv (inv[old] = new). */
static void widths(int n, const sunindextype *cp, const sunindextype *ri, const int *inv, int *kl,
                   int *ku) {
  *kl = *ku = 0;
  for (int c = 0; c < n; c++)
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++) {
      const int d = inv[ri[e]] - inv[c];
      if (d > *kl) *kl = d;
      if (-d > *ku) *ku = -d;
    }
}

/* --- creation --- */

void vs_band_destroy(vs_band **bp) {
  if (bp == NULL || *bp == NULL) return;
  vs_band *b = *bp;
  free(b->perm), free(b->inv), free(b->lu_at), free(b->zero_at), free(b->s_at), free(b->s_w);
  free(b->ab), free(b->sb), free(b->w), free(b->rdiag), free(b->ipiv);
  free(b);
  *bp = NULL;
}

static vs_status nomem(vs_band **b, vs_error *err) {
  vs_band_destroy(b);
  return vs_error_set(err, VS_ERR_NOMEM, "band factorisation: out of memory");
}

vs_status vs_band_create(int n, const sunindextype *cp, const sunindextype *ri, vs_band **out,
                         vs_error *err) {
  *out = NULL;
  if (n < 1) return vs_error_set(err, VS_ERR_INVALID, "band factorisation: %d unknowns", n);
  for (int c = 0; c < n; c++)
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++)
      if (ri[e] < 0 || ri[e] >= n)
        return vs_error_set(err, VS_ERR_INVALID, "band factorisation: row %ld of %d",
                            (long)ri[e], n);
  vs_band *b = calloc(1, sizeof *b);
  if (b == NULL) return vs_error_set(err, VS_ERR_NOMEM, "band factorisation: out of memory");
  const size_t un = (size_t)n;
  b->n = n;
  b->nnz = (size_t)cp[n];
  b->perm = malloc(un * sizeof *b->perm);
  b->inv = malloc(un * sizeof *b->inv);
  int *rperm = malloc(un * sizeof *rperm), *rinv = malloc(un * sizeof *rinv);
  graph g = {0};
  if (b->perm == NULL || b->inv == NULL || rperm == NULL || rinv == NULL ||
      graph_build(n, cp, ri, &g) != 0 || rcm(&g, rperm) != 0) {
    free(rperm), free(rinv), graph_free(&g);
    return nomem(&b, err);
  }
  graph_free(&g);
  /* the natural order unless reverse Cuthill-McKee's band is narrower */
  for (int i = 0; i < n; i++) b->perm[i] = b->inv[i] = i, rinv[rperm[i]] = i;
  int kl, ku, rkl, rku;
  widths(n, cp, ri, b->inv, &kl, &ku);
  widths(n, cp, ri, rinv, &rkl, &rku);
  if (rkl + rku < kl + ku) {
    memcpy(b->perm, rperm, un * sizeof *rperm);
    memcpy(b->inv, rinv, un * sizeof *rinv);
    kl = rkl, ku = rku;
  }
  free(rperm), free(rinv);
  b->natural = 1;
  for (int i = 0; i < n; i++) b->natural &= b->perm[i] == i;
  b->kl = kl, b->ku = ku, b->ld = 2 * kl + ku + 1;
  b->ks = kl > ku ? kl : ku;
  b->ab = malloc((size_t)b->ld * un * sizeof *b->ab);
  b->sb = malloc((size_t)(b->ks + 1) * un * sizeof *b->sb);
  b->w = malloc(un * sizeof *b->w);
  b->rdiag = malloc(un * sizeof *b->rdiag);
  b->ipiv = malloc(un * sizeof *b->ipiv);
  b->lu_at = malloc((b->nnz + 1) * sizeof *b->lu_at);
  b->s_at = malloc((b->nnz + 1) * sizeof *b->s_at);
  b->s_w = malloc((b->nnz + 1) * sizeof *b->s_w);
  if (b->ab == NULL || b->sb == NULL || b->w == NULL || b->rdiag == NULL || b->ipiv == NULL ||
      b->lu_at == NULL ||
      b->s_at == NULL || b->s_w == NULL)
    return nomem(&b, err);
  const size_t size = (size_t)b->ld * un;
  unsigned char *set = calloc(size, 1);
  if (set == NULL) return nomem(&b, err);
  for (int c0 = 0; c0 < n; c0++)
    for (sunindextype e = cp[c0]; e < cp[c0 + 1]; e++) {
      const int r = b->inv[ri[e]], c = b->inv[c0];
      b->lu_at[e] = (size_t)(kl + ku + r - c) + (size_t)c * (size_t)b->ld;
      const int lo = r < c ? r : c, hi = r < c ? c : r;
      b->s_at[e] = (size_t)(b->ks + lo - hi) + (size_t)hi * (size_t)(b->ks + 1);
      b->s_w[e] = lo == hi ? 1.0 : 0.5;
      if (set[b->lu_at[e]]++) {
        free(set);
        vs_band_destroy(&b);
        return vs_error_set(err, VS_ERR_INVALID, "band factorisation: entry (%ld, %d) repeated",
                            (long)ri[e], c0);
      }
    }
  for (size_t i = 0; i < size; i++) b->nzero += !set[i];
  b->zero_at = malloc((b->nzero + 1) * sizeof *b->zero_at);
  if (b->zero_at == NULL) {
    free(set);
    return nomem(&b, err);
  }
  size_t z = 0; /* the band's holes first (elimination fills them), then the top kl rows */
  for (size_t i = 0; i < size; i++)
    if (!set[i] && i % (size_t)b->ld >= (size_t)kl) b->zero_at[z++] = i;
  b->nhole = z;
  for (size_t i = 0; i < size; i++)
    if (!set[i] && i % (size_t)b->ld < (size_t)kl) b->zero_at[z++] = i;
  free(set);
  b->singular = 1; /* nothing factored yet */
  *out = b;
  return VS_OK;
}

void vs_band_widths(const vs_band *b, int *kl, int *ku) {
  *kl = b->kl;
  *ku = b->ku;
}

/* --- LU --- */

/* y <- y - a x over m entries; restrict: the two never overlap (distinct columns of the band, or
 * the band and a vector), so the compiler need not reload or check. */
static inline void sub_scaled(int m, double a, const double *restrict x, double *restrict y) {
  /* fixed lengths for the short runs of a narrow band, which the compiler unrolls */
#define VS_BAND_SUB(len)                                                                           \
  case len:                                                                                        \
    for (int i = 0; i < len; i++) y[i] -= a * x[i];                                                \
    return;
  switch (m) {
    VS_BAND_SUB(1)
    VS_BAND_SUB(2)
    VS_BAND_SUB(3)
    VS_BAND_SUB(4)
    VS_BAND_SUB(5)
    VS_BAND_SUB(6)
    VS_BAND_SUB(7)
    VS_BAND_SUB(8)
  default:
    for (int i = 0; i < m; i++) y[i] -= a * x[i];
  }
#undef VS_BAND_SUB
}

/* One elimination step in the usual case: a symmetric band of half width k (kl = ku = k), k rows
 * below the diagonal, no earlier interchange reaching past column j + k, and the diagonal kept as
 * the pivot. The same operations as the general step below, with k a constant where it is
 * inlined (fast_step_k), so that the compiler unrolls the short loops. Returns 0, or 1 when the
 * general step must take it (a pivot to choose, or a zero one). */
static inline int fast_step(int k, double *col, size_t ld, double *rdiag) {
  double cmax = 0.0;
  for (int i = 1; i <= k; i++) cmax = fabs(col[i]) > cmax ? fabs(col[i]) : cmax;
  if (!(fabs(col[0]) >= VS_BAND_PIVOT_TOL * cmax) || col[0] == 0.0) return 1;
  const double rpiv = 1.0 / col[0];
  *rdiag = rpiv;
  for (int i = 1; i <= k; i++) col[i] *= rpiv;
  double *cc = col + ld - 1; /* entry (j, j + 1); the next column's is ld - 1 further */
  for (int c = 1; c <= k; c++, cc += ld - 1) {
    const double u = cc[0];
    if (u != 0.0) sub_scaled(k, u, col + 1, cc + 1);
  }
  return 0;
}

/* fast_step with the common half widths as constants; 1 for the others */
static int fast_step_k(int k, double *col, size_t ld, double *rdiag) {
  switch (k) {
  case 2: return fast_step(2, col, ld, rdiag);
  case 3: return fast_step(3, col, ld, rdiag);
  case 4: return fast_step(4, col, ld, rdiag);
  case 5: return fast_step(5, col, ld, rdiag);
  case 6: return fast_step(6, col, ld, rdiag);
  case 7: return fast_step(7, col, ld, rdiag);
  case 8: return fast_step(8, col, ld, rdiag);
  default: return 1;
  }
}

int vs_band_factor(vs_band *b, const double *x) {
  const int n = b->n, kl = b->kl, ku = b->ku, ld = b->ld, kv = kl + ku;
  double *ab = b->ab;
  /* the top kl rows take only the interchanges' fill: clean unless the last factorisation had
   * any (or none was made yet) */
  const size_t nz = b->fill_clean ? b->nhole : b->nzero;
  for (size_t z = 0; z < nz; z++) ab[b->zero_at[z]] = 0.0;
  for (size_t e = 0; e < b->nnz; e++) ab[b->lu_at[e]] = x[e];
  int info = 0, ju = 0, ub = 0; /* ju: the last column the row interchanges have reached */
  for (int j = 0; j < n; j++) {
    const int km = kl < n - 1 - j ? kl : n - 1 - j;
    double *col = ab + kv + (size_t)j * (size_t)ld; /* col[i]: entry (j + i, j) */
    if (kl == ku && km == kl && ju <= j + kl &&
        fast_step_k(kl, col, (size_t)ld, &b->rdiag[j]) == 0) {
      b->ipiv[j] = j;
      ju = j + kl;
      if (kl > ub) ub = kl;
      continue;
    }
    double cmax = 0.0; /* the largest below the diagonal: the diagonal stays unless it is small */
    for (int i = 1; i <= km; i++) cmax = fabs(col[i]) > cmax ? fabs(col[i]) : cmax;
    int jp = 0;
    if (fabs(col[0]) < VS_BAND_PIVOT_TOL * cmax)
      while (fabs(col[++jp]) < cmax) {
      }
    b->ipiv[j] = j + jp;
    if (col[jp] == 0.0) {
      if (info == 0) info = j + 1;
      continue;
    }
    const int reach = j + ku + jp < n - 1 ? j + ku + jp : n - 1;
    if (reach > ju) ju = reach;
    if (ju - j > ub) ub = ju - j;
    if (jp != 0) /* swap rows j and j + jp over columns j..ju: row r is strided by ld - 1 */
      for (int c = j; c <= ju; c++) {
        double *p = ab + kv + j + (size_t)c * (size_t)(ld - 1), t = p[0];
        p[0] = p[jp];
        p[jp] = t;
      }
    const double rpiv = 1.0 / col[0]; /* multipliers by the reciprocal, as LAPACK's dgbtf2 */
    b->rdiag[j] = rpiv;
    for (int i = 1; i <= km; i++) col[i] *= rpiv;
    for (int c = j + 1; c <= ju; c++) {
      double *cc = ab + (size_t)(kv + j - c) + (size_t)c * (size_t)ld; /* cc[i]: (j + i, c) */
      const double u = cc[0];
      if (u == 0.0) continue;
      sub_scaled(km, u, col + 1, cc + 1);
    }
  }
  b->singular = info != 0;
  b->ub = ub;
  b->swapped = 0;
  for (int j = 0; j < n && !b->swapped; j++) b->swapped = b->ipiv[j] != j;
  b->fill_clean = !b->swapped;
  return info;
}

/* The solve of a symmetric band of half width k factored without interchanges and without U
 * growing past k: the same operations as the general solve below, with k a constant where it
 * is inlined (solve_fixed_k) for the rows whose k neighbours are all inside the matrix. */
static inline void solve_fixed(int k, int n, const double *ab, size_t ld, int kv,
                               const double *rdiag, double *y) {
  for (int j = 0; j < n - 1; j++) { /* L */
    const double *col = ab + kv + (size_t)j * ld;
    const double yj = y[j];
    if (j + k < n)
      for (int i = 1; i <= k; i++) y[j + i] -= col[i] * yj;
    else
      sub_scaled(n - 1 - j, yj, col + 1, y + j + 1);
  }
  for (int j = n - 1; j >= 0; j--) { /* U */
    const double *col = ab + kv + (size_t)j * ld;
    y[j] *= rdiag[j];
    const double yj = y[j];
    if (j >= k)
      for (int i = 1; i <= k; i++) y[j - i] -= col[-i] * yj;
    else
      sub_scaled(j, yj, col - j, y);
  }
}

static int solve_fixed_k(int k, int n, const double *ab, size_t ld, int kv, const double *rdiag,
                         double *y) {
  switch (k) {
  case 2: solve_fixed(2, n, ab, ld, kv, rdiag, y); return 0;
  case 3: solve_fixed(3, n, ab, ld, kv, rdiag, y); return 0;
  case 4: solve_fixed(4, n, ab, ld, kv, rdiag, y); return 0;
  case 5: solve_fixed(5, n, ab, ld, kv, rdiag, y); return 0;
  case 6: solve_fixed(6, n, ab, ld, kv, rdiag, y); return 0;
  case 7: solve_fixed(7, n, ab, ld, kv, rdiag, y); return 0;
  case 8: solve_fixed(8, n, ab, ld, kv, rdiag, y); return 0;
  default: return 1;
  }
}

void vs_band_solve(vs_band *b, double *x) {
  const int n = b->n, kl = b->kl, ld = b->ld, kv = b->kl + b->ku;
  const double *ab = b->ab;
  double *y = b->natural ? x : b->w;
  if (!b->natural)
    for (int i = 0; i < n; i++) y[i] = x[b->perm[i]];
  if (!b->swapped && kl == b->ku && b->ub == kl &&
      solve_fixed_k(kl, n, ab, (size_t)ld, kv, b->rdiag, y) == 0) {
    if (!b->natural)
      for (int i = 0; i < n; i++) x[b->perm[i]] = y[i];
    return;
  }
  for (int j = 0; j < n - 1; j++) { /* L, with the row interchanges */
    const int km = kl < n - 1 - j ? kl : n - 1 - j, l = b->ipiv[j];
    if (l != j) {
      const double t = y[l];
      y[l] = y[j];
      y[j] = t;
    }
    const double *col = ab + kv + (size_t)j * (size_t)ld;
    sub_scaled(km, y[j], col + 1, y + j + 1);
  }
  for (int j = n - 1; j >= 0; j--) { /* U: bandwidth ub <= kl + ku */
    const double *col = ab + kv + (size_t)j * (size_t)ld; /* col[-i]: entry (j - i, j) */
    y[j] *= b->rdiag[j];
    const int m = b->ub < j ? b->ub : j; /* entries (j - m .. j - 1, j) */
    sub_scaled(m, y[j], col - m, y + j - m);
  }
  if (!b->natural)
    for (int i = 0; i < n; i++) x[b->perm[i]] = y[i];
}

int vs_band_det_sign(const vs_band *b) {
  if (b->singular) return 0;
  int sign = 1;
  for (int j = 0; j < b->n; j++) {
    if (b->ipiv[j] != j) sign = -sign;
    if (b->ab[(size_t)(b->kl + b->ku) + (size_t)j * (size_t)b->ld] < 0.0) sign = -sign;
  }
  return sign; /* the symmetric permutation of the order leaves the determinant alone */
}

/* --- Cholesky of the symmetric part --- */

int vs_band_spd(vs_band *b, const double *x) {
  const int n = b->n, ks = b->ks, ld = ks + 1;
  double *sb = b->sb;
  memset(sb, 0, (size_t)ld * (size_t)n * sizeof *sb);
  /* (r, c) adds half of itself to (r, c) and (c, r); a diagonal entry all of itself */
  for (size_t e = 0; e < b->nnz; e++) sb[b->s_at[e]] += b->s_w[e] * x[e];
  /* S = U^T U column by column: U(i, j) at sb[ks + i - j + j ld] */
  for (int j = 0; j < n; j++) {
    double *cj = sb + ks + (size_t)j * (size_t)ld; /* cj[i - j]: entry (i, j), i <= j */
    const int i0 = j - ks > 0 ? j - ks : 0;
    for (int i = i0; i < j; i++) {
      const double *ci = sb + ks + (size_t)i * (size_t)ld;
      const int k0 = i0 > i - ks ? i0 : i - ks;
      double s = cj[i - j];
      for (int k = k0; k < i; k++) s -= ci[k - i] * cj[k - j];
      cj[i - j] = s / ci[0];
    }
    double d = cj[0];
    for (int k = i0; k < j; k++) d -= cj[k - j] * cj[k - j];
    if (!(d > 0.0)) return 0; /* a non-positive (or NaN) pivot: not positive definite */
    cj[0] = sqrt(d);
  }
  return 1;
}

/* --- the SUNDIALS linear solver --- */

typedef struct {
  int n;
  vs_band *b;
  sunindextype last_flag;
} linsol;

static SUNLinearSolver_Type ls_type(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_DIRECT;
}

static SUNLinearSolver_ID ls_id(SUNLinearSolver S) {
  (void)S;
  return SUNLINEARSOLVER_CUSTOM;
}

static int ls_initialize(SUNLinearSolver S) {
  ((linsol *)S->content)->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

static int ls_setup(SUNLinearSolver S, SUNMatrix A) {
  linsol *c = S->content;
  if (c->b == NULL) {
    vs_error err;
    vs_error_clear(&err);
    if (vs_band_create(c->n, SUNSparseMatrix_IndexPointers(A), SUNSparseMatrix_IndexValues(A),
                       &c->b, &err) != VS_OK)
      return (int)(c->last_flag = SUNLS_MEM_FAIL);
  }
  c->last_flag = vs_band_factor(c->b, SUNSparseMatrix_Data(A)) == 0 ? SUNLS_SUCCESS
                                                                      : SUNLS_PACKAGE_FAIL_REC;
  return (int)c->last_flag;
}

static int ls_solve(SUNLinearSolver S, SUNMatrix A, N_Vector x, N_Vector b, realtype tol) {
  (void)A;
  (void)tol;
  linsol *c = S->content;
  if (c->b == NULL || c->b->singular) return (int)(c->last_flag = SUNLS_PACKAGE_FAIL_UNREC);
  double *xd = N_VGetArrayPointer(x);
  if (x != b) memcpy(xd, N_VGetArrayPointer(b), (size_t)c->n * sizeof *xd);
  vs_band_solve(c->b, xd);
  return (int)(c->last_flag = SUNLS_SUCCESS);
}

static sunindextype ls_last_flag(SUNLinearSolver S) { return ((linsol *)S->content)->last_flag; }

static int ls_free(SUNLinearSolver S) {
  if (S == NULL) return SUNLS_SUCCESS;
  if (S->content != NULL) {
    vs_band_destroy(&((linsol *)S->content)->b);
    free(S->content);
    S->content = NULL;
  }
  SUNLinSolFreeEmpty(S);
  return SUNLS_SUCCESS;
}

SUNLinearSolver vs_band_linsol(int n, SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  linsol *c = calloc(1, sizeof *c);
  if (S == NULL || c == NULL) {
    free(c);
    if (S != NULL) SUNLinSolFreeEmpty(S);
    return NULL;
  }
  c->n = n;
  S->content = c;
  S->ops->gettype = ls_type;
  S->ops->getid = ls_id;
  S->ops->initialize = ls_initialize;
  S->ops->setup = ls_setup;
  S->ops->solve = ls_solve;
  S->ops->lastflag = ls_last_flag;
  S->ops->free = ls_free;
  return S;
}

vs_band *vs_band_linsol_band(SUNLinearSolver S) {
  return S != NULL && S->content != NULL ? ((linsol *)S->content)->b : NULL;
}
