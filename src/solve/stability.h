/* Stability of an equilibrium as positive definiteness: a Cholesky attempt (LAPACK's banded
 * dpbtrf) on the symmetric part (K + K^T) / 2 of the tangent K. The sign of det K does not
 * establish definiteness (an even number of negative eigenvalues gives det K > 0); a Cholesky
 * factorisation exists exactly when the matrix is positive definite. With friction K is not
 * symmetric; a positive definite symmetric part means positive second-order work for every
 * perturbation (Hill's condition), a sufficient condition of stability. */
#ifndef VOUSSOIR_STABILITY_H
#define VOUSSOIR_STABILITY_H

#include <sundials/sundials_matrix.h>

#include "voussoir/status.h"

typedef struct vs_spd vs_spd;

/* A tester for n x n matrices, factored in the order perm (perm[new] = old, n entries, copied;
 * NULL: the natural order). Any order gives the same answer; the cost grows as n kd^2, kd the
 * half bandwidth of the pattern in that order, so pass one that keeps the band narrow (the
 * model's tangent: vs_model_band_order). The first test maps the pattern into band storage and
 * later ones reuse the map (the pattern must not change). Errors: VS_ERR_INVALID (n < 1, perm
 * not a permutation of 0..n-1), VS_ERR_NOMEM. */
vs_status vs_spd_create(int n, const int *perm, vs_spd **out, vs_error *err);
/* Frees s and NULLs the pointer; NULL does nothing. */
void vs_spd_destroy(vs_spd **s);

/* 1 if the symmetric part of K (a CSC SUNSparseMatrix, n x n) is positive definite, 0 if not,
 * -1 if the first test could not set up (out of memory, a row index out of range). */
int vs_spd_test(vs_spd *s, SUNMatrix K);

#endif
