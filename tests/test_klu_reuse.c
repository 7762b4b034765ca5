/* The kept KLU analysis (klu_reuse.h) against exact solutions of small systems:
 *  - a refactorisation on the last factorisation's pivots meets a zero pivot when the entry that
 *    was the pivot becomes zero (as a contact of the fall that is released leaves its pattern
 *    entries at zero): the setup must still succeed, factoring afresh, and the solve be exact.
 *    (SUNDIALS' own setup refactors on the same pivots at every retry: IDA then cuts its step
 *    down to the minimum and fails, as the fall at alpha 45, k_n 48 did.)
 *  - a refactorisation that meets no zero pivot keeps working (the usual path). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "klu_reuse.h"

/* A 2 x 2 dense-pattern CSC matrix [[a00, a01], [a10, a11]]. */
static void set2(SUNMatrix A, double a00, double a01, double a10, double a11) {
  sunindextype *p = SUNSparseMatrix_IndexPointers(A), *i = SUNSparseMatrix_IndexValues(A);
  double *x = SUNSparseMatrix_Data(A);
  p[0] = 0, p[1] = 2, p[2] = 4;
  i[0] = 0, x[0] = a00, i[1] = 1, x[1] = a10;
  i[2] = 0, x[2] = a01, i[3] = 1, x[3] = a11;
}

/* Setup with A, solve A x = (1, 2); x must be the exact solution by Cramer's rule. */
static void solve_check(SUNLinearSolver LS, SUNMatrix A, N_Vector b, N_Vector x, double a00,
                        double a01, double a10, double a11) {
  set2(A, a00, a01, a10, a11);
  const int flag = SUNLinSolSetup(LS, A);
  print_message("setup [[%g, %g], [%g, %g]]: flag %d\n", a00, a01, a10, a11, flag);
  assert_int_equal(flag, SUNLS_SUCCESS);
  double *bb = N_VGetArrayPointer(b);
  bb[0] = 1.0, bb[1] = 2.0;
  assert_int_equal(SUNLinSolSolve(LS, A, x, b, 0.0), SUNLS_SUCCESS);
  const double det = a00 * a11 - a01 * a10, *xx = N_VGetArrayPointer(x);
  const double x0 = (1.0 * a11 - a01 * 2.0) / det, x1 = (a00 * 2.0 - a10 * 1.0) / det;
  assert_true(fabs(xx[0] - x0) < 1e-14 * (1.0 + fabs(x0)));
  assert_true(fabs(xx[1] - x1) < 1e-14 * (1.0 + fabs(x1)));
}

static void test_zero_pivot(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix A = SUNSparseMatrix(2, 2, 4, CSC_MAT, ctx);
  N_Vector b = N_VNew_Serial(2, ctx), x = N_VNew_Serial(2, ctx);
  set2(A, 1.0, 1.0, 1.0, 0.0);
  SUNLinearSolver LS = SUNLinSol_KLU(x, A, ctx);
  assert_non_null(LS);
  vs_klu_keep_analysis(LS);
  assert_int_equal(SUNLinSolInitialize(LS), SUNLS_SUCCESS);
  solve_check(LS, A, b, x, 4.0, 1.0, 1.0, 0.0); /* first: pivot on a00 */
  solve_check(LS, A, b, x, 3.0, 1.0, 2.0, 0.0); /* refactorised on the same pivots */
  solve_check(LS, A, b, x, 0.0, 1.0, 1.0, 0.0); /* a00, the pivot, is now zero */
  solve_check(LS, A, b, x, 2.0, 1.0, 1.0, 2.0); /* and back */
  assert_int_equal(SUNLinSolInitialize(LS), SUNLS_SUCCESS); /* a restart keeps the analysis */
  solve_check(LS, A, b, x, 0.0, 3.0, 1.0, 0.0);
  SUNLinSolFree(LS);
  N_VDestroy(b);
  N_VDestroy(x);
  SUNMatDestroy(A);
  SUNContext_Free(&ctx);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_zero_pivot)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
