/* The stability test (stability.h): a Cholesky attempt on the symmetric part decides positive
 * definiteness where the sign of det K cannot -- matrices whose definiteness is known by
 * construction, an unsymmetric one whose symmetric part is definite, and the arch's tangent at
 * self-weight (stable) against the same tangent negated (det > 0 for an even size, yet not
 * definite), with fixed and with pinned supports, in the model's band order and in q's own;
 * orders that are not permutations refused. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "test_support.h"
#include "model_matrix.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"
#include "stability.h"

/* vs_spd_test of the n x n row-major matrix a. */
static int spd_of(SUNContext ctx, int n, const double *a) {
  SUNMatrix D = SUNDenseMatrix(n, n, ctx);
  assert_non_null(D);
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) SM_ELEMENT_D(D, i, j) = a[i * n + j];
  SUNMatrix S = SUNSparseFromDenseMatrix(D, 0.0, CSC_MAT);
  assert_non_null(S);
  vs_spd *s = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_spd_create(n, NULL, &s, &err), VS_OK);
  const int r = vs_spd_test(s, S);
  vs_spd_destroy(&s);
  assert_null(s);
  SUNMatDestroy(S);
  SUNMatDestroy(D);
  return r;
}

static void test_small_matrices(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  const double laplace[9] = {2, -1, 0, -1, 2, -1, 0, -1, 2}; /* eigenvalues 2 -+ sqrt 2, 2 */
  const double negdiag[4] = {-1, 0, 0, -1};                  /* det 1 > 0, not definite */
  const double skew[4] = {1, 3, -3, 1};                      /* symmetric part I */
  const double indef[4] = {1, 3, 3, 1};                      /* eigenvalues 4, -2 */
  const double singular[4] = {1, 1, 1, 1};                   /* eigenvalues 2, 0: semi-definite */
  assert_int_equal(spd_of(ctx, 3, laplace), 1);
  assert_int_equal(spd_of(ctx, 2, negdiag), 0);
  assert_int_equal(spd_of(ctx, 2, skew), 1);
  assert_int_equal(spd_of(ctx, 2, indef), 0);
  assert_int_equal(spd_of(ctx, 2, singular), 0);
  SUNContext_Free(&ctx);
}

/* Half bandwidth of K's pattern in the order perm (perm[new] = old). */
static int half_bandwidth(SUNMatrix K, int n, const int *perm) {
  int *inv = malloc((size_t)n * sizeof *inv), kd = 0;
  assert_non_null(inv);
  for (int i = 0; i < n; i++) inv[perm[i]] = i;
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(K), *ri = SUNSparseMatrix_IndexValues(K);
  for (int c = 0; c < n; c++)
    for (sunindextype e = cp[c]; e < cp[c + 1]; e++)
      kd = abs(inv[ri[e]] - inv[c]) > kd ? abs(inv[ri[e]] - inv[c]) : kd;
  free(inv);
  return kd;
}

/* The reference arch (54 voussoirs: 162 unknowns, 164 with both supports pinned) at self-weight:
 * its tangent is definite; negated, all its eigenvalues (an even number) change sign
 * (det(-K) = det K > 0) and it is not. The same answers in the model's band order and in q's own
 * order, whose band a pinned support's rotation widens to the whole matrix (the model's order
 * keeps it at the blocks' half bandwidth, 5). */
static void arch_tangent(vs_support_kind kind) {
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = 54;
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  vs_joint_law law = {.kn = c.kn_N_mm3 * 1e9, .ks = c.ks_ratio * c.kn_N_mm3 * 1e9, .mu = c.friction};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  assert_int_equal(vs_model_set_support_kinds(m, kind, kind, &err), VS_OK);
  const int n = vs_model_size(m);
  assert_int_equal(n, kind == VS_SUPPORT_PINNED ? 164 : 162);
  double *q = calloc((size_t)n, sizeof *q);
  int *perm = malloc((size_t)n * sizeof *perm), *natural = malloc((size_t)n * sizeof *natural);
  assert_non_null(q);
  assert_non_null(perm);
  assert_non_null(natural);
  vs_path_opts po;
  vs_test_path_opts(&c, &po);
  po.max_delta = 0.0;
  vs_path_result pr;
  if (vs_path_run(m, &po, 0.0, q, NULL, NULL, &pr, &err) != VS_OK) fail_msg("%s", err.msg);
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix K = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  assert_non_null(K);
  vs_model_jacobian(m, q, 0.0, K);
  vs_model_band_order(m, perm);
  for (int i = 0; i < n; i++) natural[i] = i;
  assert_int_equal(half_bandwidth(K, n, perm), 5);
  if (kind == VS_SUPPORT_PINNED) assert_true(half_bandwidth(K, n, natural) > n - 8);
  for (int order = 0; order < 2; order++) {
    vs_spd *s = NULL;
    assert_int_equal(vs_spd_create(n, order == 0 ? perm : NULL, &s, &err), VS_OK);
    assert_int_equal(vs_spd_test(s, K), 1);
    double *x = SUNSparseMatrix_Data(K);
    for (sunindextype p = 0; p < SUNSparseMatrix_NNZ(K); p++) x[p] = -x[p];
    assert_int_equal(vs_spd_test(s, K), 0); /* the same pattern, mapped once */
    for (sunindextype p = 0; p < SUNSparseMatrix_NNZ(K); p++) x[p] = -x[p];
    assert_int_equal(vs_spd_test(s, K), 1);
    vs_spd_destroy(&s);
    assert_null(s);
  }
  SUNMatDestroy(K);
  SUNContext_Free(&ctx);
  free(q);
  free(perm);
  free(natural);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

static void test_arch_tangent(void **state) {
  (void)state;
  arch_tangent(VS_SUPPORT_FIXED);
}

static void test_arch_tangent_pinned(void **state) {
  (void)state;
  arch_tangent(VS_SUPPORT_PINNED);
}

/* Refusals: no unknowns, an order that repeats or leaves the range; nothing is created. */
static void test_bad_order(void **state) {
  (void)state;
  vs_error err;
  vs_error_clear(&err);
  vs_spd *s = NULL;
  const int repeats[3] = {0, 0, 2}, outside[3] = {0, 1, 3}, negative[3] = {-1, 1, 2};
  assert_int_equal(vs_spd_create(0, NULL, &s, &err), VS_ERR_INVALID);
  assert_null(s);
  assert_int_equal(vs_spd_create(3, repeats, &s, &err), VS_ERR_INVALID);
  assert_null(s);
  assert_non_null(strstr(err.msg, "not a permutation"));
  assert_int_equal(vs_spd_create(3, outside, &s, &err), VS_ERR_INVALID);
  assert_null(s);
  assert_int_equal(vs_spd_create(3, negative, &s, &err), VS_ERR_INVALID);
  assert_null(s);
  vs_spd_destroy(&s); /* NULL does nothing */
  vs_spd_destroy(NULL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_small_matrices),
      cmocka_unit_test(test_arch_tangent),
      cmocka_unit_test(test_arch_tangent_pinned),
      cmocka_unit_test(test_bad_order),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
