/* One KLU analysis per solver (klu_reuse.h). */
#include "voussoir/klu_reuse.h"

#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* The first initialisation is SUNDIALS' own; a later one keeps the analysis and frees the factors:
 * the next setup factors afresh (pivots chosen again, as after a new analysis, which would be the
 * same: the pattern has not changed). */
static int keep_initialize(SUNLinearSolver S) {
  SUNLinearSolverContent_KLU c = S->content;
  if (c->symbolic == NULL) return SUNLinSolInitialize_KLU(S);
  if (c->numeric != NULL) sun_klu_free_numeric(&c->numeric, &c->common);
  c->first_factorize = 0;
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

/* After keep_initialize: a fresh numeric factorisation on the kept analysis; otherwise
 * SUNDIALS' setup (the first analysis, then refactorisations). */
static int keep_setup(SUNLinearSolver S, SUNMatrix A) {
  SUNLinearSolverContent_KLU c = S->content;
  if (c->symbolic == NULL || c->numeric != NULL) {
    const int flag = SUNLinSolSetup_KLU(S, A);
    if (flag != SUNLS_PACKAGE_FAIL_REC || c->numeric == NULL) return flag;
    /* the refactorisation on the last factorisation's pivots met a zero pivot (an entry that
     * was one is now zero: a contact of the fall released): SUNDIALS would refactor on the same
     * pivots at every retry, and IDA cut its step down to the minimum; factor afresh instead */
    sun_klu_free_numeric(&c->numeric, &c->common);
  }
  c->numeric = sun_klu_factor(SUNSparseMatrix_IndexPointers(A), SUNSparseMatrix_IndexValues(A),
                              SUNSparseMatrix_Data(A), c->symbolic, &c->common);
  c->last_flag = c->numeric != NULL ? SUNLS_SUCCESS : SUNLS_PACKAGE_FAIL_UNREC;
  return c->last_flag;
}

void vs_klu_keep_analysis(SUNLinearSolver LS) {
  if (LS == NULL) return;
  LS->ops->initialize = keep_initialize;
  LS->ops->setup = keep_setup;
}
