/* SUNDIALS' KLU linear solver re-analysed at every KINSol call and every IDA restart (both call
 * SUNLinSolInitialize, which makes the next setup free the factors and analyse the pattern
 * again). The model's Jacobian patterns are fixed at its creation, so one analysis serves every
 * solve: later setups refactor numerically, with SUNDIALS' own fall-back to a fresh
 * factorisation when the condition estimate degrades. */
#ifndef VOUSSOIR_KLU_REUSE_H
#define VOUSSOIR_KLU_REUSE_H

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

/* Make LS (a SUNLinSol_KLU whose matrix pattern never changes) keep its symbolic analysis and
 * numeric factors across re-initialisations. */
void vs_klu_keep_analysis(SUNLinearSolver LS);

/* Make SUNMatZero on A (a CSC SUNSparseMatrix) do nothing: KINSOL and IDA zero the Jacobian
 * before every evaluation, and SUNDIALS' version clears the index arrays one entry at a time too,
 * which cost more than the evaluation's own work on the pattern. Only for matrices whose Jacobian
 * function writes the whole pattern and every value (every one in this library). */
void vs_sparse_zero_none(SUNMatrix A);

#endif
