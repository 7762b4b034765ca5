/* The band factorisations (band.h) against independent answers:
 *  - solutions and determinant signs of random banded systems that need row interchanges, and
 *    of diagonally dominant ones that need none (the unrolled steps), against dense Gaussian
 *    elimination with partial pivoting written out here; one factoriser refactored with and
 *    without interchanges in turn;
 *  - a block chain with two extra unknowns coupled to its two ends (as pinned supports' rotations
 *    kept after the blocks): the chosen order brings the band back to the chain's width;
 *  - positive definiteness of the symmetric part against closed-form eigenvalues (the
 *    second-difference matrix, shifted just below and just above its smallest eigenvalue; a
 *    skew-symmetric part added changes nothing), and a matrix with det > 0 and two negative
 *    eigenvalues;
 *  - a singular matrix: the zero pivot reported, the solver's setup failing recoverably;
 *  - the SUNDIALS linear solver interface, and bad input refused. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/band.h"

enum { NMAX = 64 };

/* A dense n x n matrix (row-major) as CSC over its non-zero pattern plus the entries in pat. */
typedef struct {
  int n;
  sunindextype cp[NMAX + 1], ri[NMAX * NMAX];
  double x[NMAX * NMAX];
} csc;

static void to_csc(int n, const double *a, const unsigned char *pat, csc *m) {
  m->n = n;
  sunindextype p = 0;
  for (int c = 0; c < n; c++) {
    m->cp[c] = p;
    for (int r = 0; r < n; r++)
      if (pat[r * n + c]) m->ri[p] = r, m->x[p++] = a[r * n + c];
  }
  m->cp[n] = p;
}

/* Dense Gaussian elimination with partial pivoting: x <- A^-1 b, returns sign(det A). */
static int dense_solve(int n, const double *a0, double *x) {
  double a[NMAX * NMAX];
  memcpy(a, a0, (size_t)(n * n) * sizeof *a);
  int sign = 1;
  for (int k = 0; k < n; k++) {
    int p = k;
    for (int i = k + 1; i < n; i++)
      if (fabs(a[i * n + k]) > fabs(a[p * n + k])) p = i;
    if (p != k) {
      sign = -sign;
      for (int j = 0; j < n; j++) {
        const double t = a[k * n + j];
        a[k * n + j] = a[p * n + j], a[p * n + j] = t;
      }
      const double t = x[k];
      x[k] = x[p], x[p] = t;
    }
    if (a[k * n + k] < 0.0) sign = -sign;
    for (int i = k + 1; i < n; i++) {
      const double f = a[i * n + k] / a[k * n + k];
      for (int j = k; j < n; j++) a[i * n + j] -= f * a[k * n + j];
      x[i] -= f * x[k];
    }
  }
  for (int k = n - 1; k >= 0; k--) {
    for (int j = k + 1; j < n; j++) x[k] -= a[k * n + j] * x[j];
    x[k] /= a[k * n + k];
  }
  return sign;
}

static double urand(unsigned long *s) {
  *s = *s * 6364136223846793005ul + 1442695040888963407ul;
  return (double)(*s >> 11) / 9007199254740992.0 - 0.5;
}

/* Factor and solve m with the band code; compare with the dense answer. */
static void check_solve(const csc *m, const double *a, const double *rhs) {
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(m->n, m->cp, m->ri, &b, &err), VS_OK);
  assert_int_equal(vs_band_factor(b, m->x), 0);
  double x[NMAX], xd[NMAX];
  memcpy(x, rhs, (size_t)m->n * sizeof *x);
  memcpy(xd, rhs, (size_t)m->n * sizeof *xd);
  vs_band_solve(b, x);
  const int sign = dense_solve(m->n, a, xd);
  double scale = 0.0;
  for (int i = 0; i < m->n; i++) scale = fmax(scale, fabs(xd[i]));
  for (int i = 0; i < m->n; i++) assert_true(fabs(x[i] - xd[i]) <= 1e-11 * scale);
  assert_int_equal(vs_band_det_sign(b), sign);
  vs_band_destroy(&b);
  assert_null(b);
}

static void test_random(void **state) {
  (void)state;
  unsigned long s = 42;
  for (int trial = 0; trial < 20; trial++) {
    const int n = 5 + trial * 2, kl = 1 + trial % 4, ku = 1 + (trial / 2) % 4;
    double a[NMAX * NMAX] = {0}, rhs[NMAX];
    unsigned char pat[NMAX * NMAX] = {0};
    for (int r = 0; r < n; r++) {
      rhs[r] = urand(&s);
      for (int c = r - kl; c <= r + ku; c++)
        if (c >= 0 && c < n) {
          pat[r * n + c] = 1;
          /* small diagonals: partial pivoting must interchange rows */
          a[r * n + c] = (r == c ? 0.01 : 1.0) * urand(&s);
        }
    }
    csc m;
    to_csc(n, a, pat, &m);
    check_solve(&m, a, rhs);
  }
}

/* One factoriser, refactored: values that need row interchanges (which fill the rows above the
 * band), then values that need none on the same pattern (the fill must be gone), then the first
 * again: each solve against the dense answer. */
static void test_refactor(void **state) {
  (void)state;
  unsigned long s = 5;
  const int n = 24, k = 3;
  double a[3][NMAX * NMAX] = {{0}}, rhs[NMAX];
  unsigned char pat[NMAX * NMAX] = {0};
  for (int r = 0; r < n; r++) {
    rhs[r] = urand(&s);
    for (int c = r - k; c <= r + k; c++)
      if (c >= 0 && c < n) {
        pat[r * n + c] = 1;
        a[0][r * n + c] = (r == c ? 1e-4 : 1.0) * urand(&s); /* interchanges */
        a[1][r * n + c] = (r == c ? 4.0 * k : 0.0) + urand(&s); /* none */
        a[2][r * n + c] = a[0][r * n + c];
      }
  }
  csc m[3];
  for (int v = 0; v < 3; v++) to_csc(n, a[v], pat, &m[v]);
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(n, m[0].cp, m[0].ri, &b, &err), VS_OK);
  for (int v = 0; v < 3; v++) {
    assert_int_equal(vs_band_factor(b, m[v].x), 0);
    double x[NMAX], xd[NMAX];
    memcpy(x, rhs, (size_t)n * sizeof *x);
    memcpy(xd, rhs, (size_t)n * sizeof *xd);
    vs_band_solve(b, x);
    assert_int_equal(vs_band_det_sign(b), dense_solve(n, a[v], xd));
    double scale = 0.0;
    for (int i = 0; i < n; i++) scale = fmax(scale, fabs(xd[i]));
    for (int i = 0; i < n; i++) assert_true(fabs(x[i] - xd[i]) <= 1e-10 * scale);
  }
  vs_band_destroy(&b);
}

/* Diagonally dominant symmetric bands of half width 1 to 9: no interchange, so the unrolled steps
 * of half width 2 to 8 factor and solve them (9: the general ones), against the dense answer. */
static void test_no_interchange(void **state) {
  (void)state;
  unsigned long s = 99;
  for (int k = 1; k <= 9; k++) {
    const int n = 30 + k;
    double a[NMAX * NMAX] = {0}, rhs[NMAX];
    unsigned char pat[NMAX * NMAX] = {0};
    for (int r = 0; r < n; r++) {
      rhs[r] = urand(&s);
      for (int c = r - k; c <= r + k; c++)
        if (c >= 0 && c < n) {
          pat[r * n + c] = 1;
          a[r * n + c] = (r == c ? 4.0 * k : 0.0) + urand(&s);
        }
    }
    csc m;
    to_csc(n, a, pat, &m);
    check_solve(&m, a, rhs);
  }
}

/* n_blocks blocks of 3 coupled to their neighbours, then two unknowns coupled to the first and
 * the last block. */
static void test_order(void **state) {
  (void)state;
  const int nb = 15, n = 3 * nb + 2;
  double a[NMAX * NMAX] = {0}, rhs[NMAX];
  unsigned char pat[NMAX * NMAX] = {0};
  unsigned long s = 7;
  for (int i = 0; i < nb; i++)
    for (int j = i - 1; j <= i + 1; j++)
      if (j >= 0 && j < nb)
        for (int r = 3 * i; r < 3 * i + 3; r++)
          for (int c = 3 * j; c < 3 * j + 3; c++) pat[r * n + c] = 1;
  for (int k = 0; k < 3; k++) {
    pat[(n - 2) * n + k] = pat[k * n + n - 2] = 1;                  /* with the first block */
    pat[(n - 1) * n + 3 * nb - 3 + k] = pat[(3 * nb - 3 + k) * n + n - 1] = 1; /* the last */
  }
  pat[(n - 2) * n + n - 2] = pat[(n - 1) * n + n - 1] = 1;
  for (int r = 0; r < n; r++) {
    rhs[r] = urand(&s);
    for (int c = 0; c < n; c++)
      if (pat[r * n + c]) a[r * n + c] = (r == c ? 4.0 : 0.0) + urand(&s);
  }
  csc m;
  to_csc(n, a, pat, &m);
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(n, m.cp, m.ri, &b, &err), VS_OK);
  int kl = 0, ku = 0;
  vs_band_widths(b, &kl, &ku);
  print_message("order: kl %d ku %d (natural: %d)\n", kl, ku, n - 2);
  assert_true(kl <= 6 && ku <= 6);
  vs_band_destroy(&b);
  check_solve(&m, a, rhs);
}

/* The second-difference matrix minus shift, plus skew times an antisymmetric part. */
static int spd_of(int n, double shift, double skew) {
  double a[NMAX * NMAX] = {0};
  unsigned char pat[NMAX * NMAX] = {0};
  for (int i = 0; i < n; i++) {
    a[i * n + i] = 2.0 - shift;
    pat[i * n + i] = 1;
    if (i + 1 < n) {
      a[i * n + i + 1] = -1.0 + skew, a[(i + 1) * n + i] = -1.0 - skew;
      pat[i * n + i + 1] = pat[(i + 1) * n + i] = 1;
    }
  }
  csc m;
  to_csc(n, a, pat, &m);
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(n, m.cp, m.ri, &b, &err), VS_OK);
  const int r = vs_band_spd(b, m.x);
  vs_band_destroy(&b);
  return r;
}

static void test_spd(void **state) {
  (void)state;
  const int n = 30;
  const double lmin = 2.0 - 2.0 * cos(acos(-1.0) / (n + 1)); /* smallest eigenvalue */
  assert_int_equal(spd_of(n, 0.99 * lmin, 0.0), 1);
  assert_int_equal(spd_of(n, 1.01 * lmin, 0.0), 0);
  assert_int_equal(spd_of(n, 0.99 * lmin, 0.7), 1); /* the symmetric part is what counts */
  assert_int_equal(spd_of(n, 1.01 * lmin, 0.7), 0);
  /* diag(-1, -1, 1, 1): det > 0, not positive definite */
  double a[16] = {-1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  unsigned char pat[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  csc m;
  to_csc(4, a, pat, &m);
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(4, m.cp, m.ri, &b, &err), VS_OK);
  assert_int_equal(vs_band_factor(b, m.x), 0);
  assert_int_equal(vs_band_det_sign(b), 1);
  assert_int_equal(vs_band_spd(b, m.x), 0);
  vs_band_destroy(&b);
}

static void test_singular_and_linsol(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  const int n = 3;
  SUNMatrix A = SUNSparseMatrix(n, n, 7, CSC_MAT, ctx);
  sunindextype *cp = SUNSparseMatrix_IndexPointers(A), *ri = SUNSparseMatrix_IndexValues(A);
  double *x = SUNSparseMatrix_Data(A);
  /* [[2, 1, 0], [1, 3, 1], [0, 1, 4]] */
  const sunindextype p[4] = {0, 2, 5, 7}, r[7] = {0, 1, 0, 1, 2, 1, 2};
  const double v[7] = {2, 1, 1, 3, 1, 1, 4};
  memcpy(cp, p, sizeof p), memcpy(ri, r, sizeof r), memcpy(x, v, sizeof v);
  SUNLinearSolver LS = vs_band_linsol(n, ctx);
  assert_non_null(LS);
  assert_null(vs_band_linsol_band(LS));
  assert_int_equal(SUNLinSolInitialize(LS), SUNLS_SUCCESS);
  assert_int_equal(SUNLinSolSetup(LS, A), SUNLS_SUCCESS);
  assert_non_null(vs_band_linsol_band(LS));
  N_Vector xv = N_VNew_Serial(n, ctx), bv = N_VNew_Serial(n, ctx);
  double *bb = N_VGetArrayPointer(bv), *xx = N_VGetArrayPointer(xv);
  bb[0] = 3.0, bb[1] = 5.0, bb[2] = 5.0; /* A (1, 1, 1) */
  assert_int_equal(SUNLinSolSolve(LS, A, xv, bv, 0.0), SUNLS_SUCCESS);
  for (int i = 0; i < n; i++) assert_true(fabs(xx[i] - 1.0) < 1e-14);
  /* the middle column zero: singular at the second pivot */
  x[2] = x[3] = x[4] = 0.0;
  assert_int_equal(SUNLinSolSetup(LS, A), SUNLS_PACKAGE_FAIL_REC);
  assert_int_equal(vs_band_det_sign(vs_band_linsol_band(LS)), 0);
  assert_int_equal(vs_band_factor(vs_band_linsol_band(LS), x), 2);
  N_VDestroy(xv);
  N_VDestroy(bv);
  SUNLinSolFree(LS);
  SUNMatDestroy(A);
  SUNContext_Free(&ctx);
}

static void test_invalid(void **state) {
  (void)state;
  const sunindextype cp[3] = {0, 1, 2}, ri[2] = {0, 5};
  vs_band *b = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_band_create(2, cp, ri, &b, &err), VS_ERR_INVALID);
  assert_null(b);
  assert_int_equal(vs_band_create(0, cp, ri, &b, &err), VS_ERR_INVALID);
  vs_band_destroy(NULL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_random), cmocka_unit_test(test_refactor),
      cmocka_unit_test(test_no_interchange),
      cmocka_unit_test(test_order), cmocka_unit_test(test_spd),
      cmocka_unit_test(test_singular_and_linsol), cmocka_unit_test(test_invalid)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
