/* One KLU analysis per solver (klu_reuse.h). */
#include "klu_reuse.h"

#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

/* The first initialisation is SUNDIALS' own; a later one keeps the analysis and the factors: the
 * next setup refactors on the last pivot order (SUNDIALS' setup factors afresh, choosing pivots
 * again, when the condition estimate of the refactored matrix degrades). A fresh factorisation
 * at every KINSol call cost twice a refactorisation; the solutions move at round-off only. */
static int keep_initialize(SUNLinearSolver S) {
  SUNLinearSolverContent_KLU c = S->content;
  if (c->symbolic == NULL) return SUNLinSolInitialize_KLU(S);
  c->first_factorize = 0;
  c->last_flag = SUNLS_SUCCESS;
  return SUNLS_SUCCESS;
}

/* With an analysis but no factors (a factorisation failed): a fresh one on it; otherwise
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

/* Nothing to clear: the Jacobian function writes every value (and the pattern). */
static int zero_none(SUNMatrix A) {
  (void)A;
  return 0;
}

void vs_sparse_zero_none(SUNMatrix A) {
  if (A != NULL && A->ops != NULL) A->ops->zero = zero_none;
}
