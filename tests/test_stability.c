/* The stability test (stability.h): a Cholesky attempt on the symmetric part decides positive
 * definiteness where the sign of det K cannot -- matrices whose definiteness is known by
 * construction, an unsymmetric one whose symmetric part is definite, and the arch's tangent at
 * self-weight (stable) against the same tangent negated (det > 0 for an even size, yet not
 * definite). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"
#include "voussoir/stability.h"

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
  assert_int_equal(vs_spd_create(n, &s, &err), VS_OK);
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

/* The reference arch (54 voussoirs: 162 unknowns) at self-weight: its tangent is definite;
 * negated, all 162 eigenvalues change sign (det(-K) = det K > 0) and it is not. */
static void test_arch_tangent(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = 54;
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  assert_int_equal(vs_geometry_create_arch(&c, &g, &err), VS_OK);
  vs_joint_law law = {.kn = c.kn_N_mm3 * 1e9, .ks = c.ks_ratio * c.kn_N_mm3 * 1e9, .mu = c.friction};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  const int n = vs_model_size(m);
  double *q = calloc((size_t)n, sizeof *q);
  assert_non_null(q);
  vs_path_opts po;
  vs_path_opts_from_case(&c, &po);
  po.max_delta = 0.0;
  vs_path_result pr;
  if (vs_path_run(m, &po, 0.0, q, NULL, NULL, &pr, &err) != VS_OK) fail_msg("%s", err.msg);
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix K = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  assert_non_null(K);
  vs_model_jacobian(m, q, 0.0, K);
  vs_spd *s = NULL;
  assert_int_equal(vs_spd_create(n, &s, &err), VS_OK);
  assert_int_equal(vs_spd_test(s, K), 1);
  double *x = SUNSparseMatrix_Data(K);
  for (sunindextype p = 0; p < SUNSparseMatrix_NNZ(K); p++) x[p] = -x[p];
  assert_int_equal(vs_spd_test(s, K), 0); /* the same pattern, analysed once */
  for (sunindextype p = 0; p < SUNSparseMatrix_NNZ(K); p++) x[p] = -x[p];
  assert_int_equal(vs_spd_test(s, K), 1);
  vs_spd_destroy(&s);
  SUNMatDestroy(K);
  SUNContext_Free(&ctx);
  free(q);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_small_matrices),
      cmocka_unit_test(test_arch_tangent),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
