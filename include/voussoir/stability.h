/* Stability of an equilibrium as positive definiteness: a Cholesky attempt (band.h: in the
 * bandwidth-reducing order of K's pattern) on the symmetric part (K + K^T) / 2 of the tangent K.
 * The sign of det K does not establish definiteness (an even number of negative eigenvalues
 * gives det K > 0); a Cholesky factorisation exists exactly when the matrix is positive
 * definite. With friction K is not symmetric; a positive definite symmetric part means positive
 * second-order work for every perturbation (Hill's condition), a sufficient condition of
 * stability. */
#ifndef VOUSSOIR_STABILITY_H
#define VOUSSOIR_STABILITY_H

#include <sundials/sundials_matrix.h>

#include "voussoir/status.h"

typedef struct vs_spd vs_spd;

/* A tester for n x n matrices; the first test orders the pattern, later ones reuse it (the
 * pattern must not change). Errors: VS_ERR_NOMEM. */
vs_status vs_spd_create(int n, vs_spd **out, vs_error *err);
void vs_spd_destroy(vs_spd **s);

/* 1 if the symmetric part of K (a CSC SUNSparseMatrix, n x n) is positive definite, 0 if not,
 * -1 if the first test could not set up (out of memory, an index out of range). */
int vs_spd_test(vs_spd *s, SUNMatrix K);

#endif
