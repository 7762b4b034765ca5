/* Banded LU and Cholesky factorisations of a sparse (CSC) matrix whose pattern, in a
 * bandwidth-reducing order, is a narrow band: the quasi-static tangent of a chain of blocks, which
 * couples each block to its neighbours only (kl = ku = 5 in the natural order; a pinned support's
 * rotation, kept after the blocks, is moved next to its block by the reverse Cuthill-McKee order).
 * For matrices of a few hundred unknowns a general sparse LU (KLU) spent most of its time in
 * per-entry bookkeeping; a band factorisation is a few loops over the band. Also a SUNDIALS
 * linear solver (direct, on a SUNSparseMatrix) for KINSOL. */
#ifndef VOUSSOIR_BAND_H
#define VOUSSOIR_BAND_H

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "voussoir/status.h"

typedef struct vs_band vs_band;

/* A factoriser for the n x n CSC pattern (colptr, rowind; rowind need not be sorted, entries must
 * not repeat): it chooses the order (natural, or reverse Cuthill-McKee when that band is
 * narrower) and maps every entry into band storage. The arrays are not kept. Errors:
 * VS_ERR_NOMEM, VS_ERR_INVALID (an index out of range). */
vs_status vs_band_create(int n, const sunindextype *colptr, const sunindextype *rowind,
                         vs_band **out, vs_error *err);
/* Frees b and NULLs the pointer; NULL does nothing. */
void vs_band_destroy(vs_band **b);

/* Lower and upper bandwidths in the chosen order. */
void vs_band_widths(const vs_band *b, int *kl, int *ku);

/* LU factorisation with partial pivoting of the matrix with the creation's pattern and the
 * values x (CSC order). Returns 0, or j + 1 when pivot j is exactly zero (the matrix is
 * singular; the factors are then unusable). */
int vs_band_factor(vs_band *b, const double *x);

/* x <- A^-1 x (n entries, original order) with the last successful factorisation. */
void vs_band_solve(vs_band *b, double *x);

/* Sign of det A from the last factorisation: +1, -1, or 0 when it was singular. */
int vs_band_det_sign(const vs_band *b);

/* 1 if the symmetric part (A + A^T) / 2 of the matrix with values x is positive definite (a
 * Cholesky factorisation of it exists: every pivot positive), else 0. Leaves the LU alone. */
int vs_band_spd(vs_band *b, const double *x);

/* A SUNDIALS direct linear solver on CSC SUNSparseMatrix systems of size n: each setup factors
 * the matrix (vs_band_factor; the band is built at the first setup, from that matrix's pattern,
 * which must not change afterwards), each solve applies the factors. A zero pivot is a
 * recoverable setup failure (SUNLS_PACKAGE_FAIL_REC). NULL when out of memory. */
SUNLinearSolver vs_band_linsol(int n, SUNContext ctx);
/* The factoriser of such a solver (NULL before its first setup). */
vs_band *vs_band_linsol_band(SUNLinearSolver S);

#endif
