/* Natural frequencies and mode shapes about an equilibrium: the tangent stiffness (from the
 * model's analytic CSC Jacobian, banded: blocks couple to their neighbours only) and the
 * diagonal mass matrix; the lowest eigenvalues by LAPACK's banded dsbgvx, their mode shapes by
 * inverse iteration on a banded LU; the damping ratio of each mode from the damping forces. */
#include "voussoir/modal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/units.h"

/* LAPACK (Fortran ABI, gfortran: hidden lengths of the character arguments at the end). */
extern void dsbgvx_(const char *jobz, const char *range, const char *uplo, const int *n,
                    const int *ka, const int *kb, double *ab, const int *ldab, double *bb,
                    const int *ldbb, double *q, const int *ldq, const double *vl, const double *vu,
                    const int *il, const int *iu, const double *abstol, int *m, double *w,
                    double *z, const int *ldz, double *work, int *iwork, int *ifail, int *info,
                    size_t jobz_len, size_t range_len, size_t uplo_len);
extern void dgbtrf_(const int *m, const int *n, const int *kl, const int *ku, double *ab,
                    const int *ldab, int *ipiv, int *info);
extern void dgbtrs_(const char *trans, const int *n, const int *kl, const int *ku,
                    const int *nrhs, const double *ab, const int *ldab, const int *ipiv, double *b,
                    const int *ldb, int *info, size_t trans_len);

/* Index of (row offset i >= 0, column j) in LAPACK band storage of leading dimension ld. */
static size_t bidx(int i, int j, int ld) { return (size_t)i + (size_t)j * (size_t)ld; }

/* Inverse iterations per mode (from the eigenvalue itself, one or two already converge). */
static const int VS_MODAL_INVIT = 3;
/* Relative shift off the eigenvalue for inverse iteration (keeps the factorisation regular). */
static const double VS_MODAL_SHIFT = 1e-10;

void vs_modal_free(vs_modal *out) {
  if (out == NULL) return;
  free(out->phi);
  out->phi = NULL;
}

/* The tangent stiffness, symmetrised, in LAPACK general band storage with kl = ku = kd
 * (S(r, c) at sb[kd + r - c + c * (2 kd + 1)]); its half-bandwidth and asymmetry. */
typedef struct {
  int n, kd, ld;
  double *sb;
  double asym;
} band;

static vs_status band_stiffness(const vs_model *m, const double *q, double delta, band *b,
                                vs_error *err) {
  const int n = vs_model_size(m);
  SUNContext ctx = NULL;
  if (SUNContext_Create(NULL, &ctx) != 0) return vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  SUNMatrix K = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  vs_status st = VS_OK;
  if (K == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  if (st == VS_OK) {
    vs_model_jacobian(m, q, delta, K);
    const sunindextype *kp = SUNSparseMatrix_IndexPointers(K), *ki = SUNSparseMatrix_IndexValues(K);
    const double *kx = SUNSparseMatrix_Data(K);
    int kd = 0;
    for (int c = 0; c < n; c++)
      for (sunindextype e = kp[c]; e < kp[c + 1]; e++) kd = (int)fmax(kd, fabs((double)(ki[e] - c)));
    b->n = n;
    b->kd = kd;
    b->ld = 2 * kd + 1;
    b->sb = calloc((size_t)b->ld * (size_t)n, sizeof *b->sb);
    if (b->sb == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
    for (int c = 0; st == VS_OK && c < n; c++)
      for (sunindextype e = kp[c]; e < kp[c + 1]; e++) {
        const int r = (int)ki[e];
        b->sb[bidx(kd + r - c, c, b->ld)] = kx[e];
      }
  }
  if (K != NULL) SUNMatDestroy(K);
  SUNContext_Free(&ctx);
  if (st != VS_OK) return st;
  double dmax = 0.0, kmax = 0.0;
  for (int c = 0; c < n; c++)
    for (int r = (c > b->kd ? c - b->kd : 0); r < c; r++) {
      double *x = &b->sb[bidx(b->kd + r - c, c, b->ld)];
      double *y = &b->sb[bidx(b->kd + c - r, r, b->ld)];
      dmax = fmax(dmax, fabs(*x - *y));
      kmax = fmax(kmax, fmax(fabs(*x), fabs(*y)));
      *x = *y = 0.5 * (*x + *y);
    }
  b->asym = kmax > 0.0 ? dmax / kmax : 0.0;
  return VS_OK;
}

/* The lowest nm eigenvalues of (S, diag(mass)) by dsbgvx (banded, no vectors). */
static vs_status band_eigenvalues(const band *b, const double *mass, int nm, double *w2,
                                  vs_error *err) {
  const int n = b->n, kd = b->kd, ldab = kd + 1, kb = 0, ldbb = 1, one = 1, il = 1, iu = nm;
  double *ab = malloc((size_t)ldab * (size_t)n * sizeof *ab), *bb = malloc((size_t)n * sizeof *bb);
  double *w = malloc((size_t)n * sizeof *w), *work = malloc(7 * (size_t)n * sizeof *work);
  int *iwork = malloc(5 * (size_t)n * sizeof *iwork), *ifail = malloc((size_t)n * sizeof *ifail);
  vs_status st = VS_OK;
  if (ab == NULL || bb == NULL || w == NULL || work == NULL || iwork == NULL || ifail == NULL) {
    st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  } else {
    for (int c = 0; c < n; c++) /* upper band: AB(kd + r - c, c) = S(r, c), r <= c */
      for (int r = (c > kd ? c - kd : 0); r <= c; r++)
        ab[bidx(kd + r - c, c, ldab)] = b->sb[bidx(kd + r - c, c, b->ld)];
    memcpy(bb, mass, (size_t)n * sizeof *bb);
    const double vl = 0.0, vu = 0.0, abstol = 0.0;
    double qdummy = 0.0, zdummy = 0.0;
    int found = 0, info = 0;
    dsbgvx_("N", "I", "U", &n, &kd, &kb, ab, &ldab, bb, &ldbb, &qdummy, &one, &vl, &vu, &il, &iu,
            &abstol, &found, w, &zdummy, &one, work, iwork, ifail, &info, 1, 1, 1);
    if (info > n)
      st = vs_error_set(err, VS_ERR_INVALID, "modal: mass matrix not positive definite");
    else if (info != 0 || found != nm)
      st = vs_error_set(err, VS_ERR_SOLVER, "modal: dsbgvx failed (info %d, %d of %d modes)", info,
                        found, nm);
    else
      memcpy(w2, w, (size_t)nm * sizeof *w2);
  }
  free(ab);
  free(bb);
  free(w);
  free(work);
  free(iwork);
  free(ifail);
  return st;
}

/* M-orthonormalise x against the modes found so far (phi, k of them) and itself. */
static void m_orthonormalise(int n, const double *mass, const double *phi, int k, double *x) {
  for (int j = 0; j < k; j++) {
    const double *p = phi + (size_t)j * (size_t)n;
    double d = 0.0;
    for (int r = 0; r < n; r++) d += p[r] * mass[r] * x[r];
    for (int r = 0; r < n; r++) x[r] -= d * p[r];
  }
  double nn = 0.0;
  for (int r = 0; r < n; r++) nn += x[r] * mass[r] * x[r];
  const double s = nn > 0.0 ? 1.0 / sqrt(nn) : 0.0;
  for (int r = 0; r < n; r++) x[r] *= s;
}

/* Mode shape k by inverse iteration on S - sigma M, sigma next to eigenvalue w2 (banded LU). */
static vs_status band_vector(const band *b, const double *mass, double w2, const double *phi,
                             int k, double *x, double *lu, int *ipiv, vs_error *err) {
  const int n = b->n, kd = b->kd, ldlu = 3 * kd + 1, one = 1;
  const double sigma = w2 * (1.0 - VS_MODAL_SHIFT);
  memset(lu, 0, (size_t)ldlu * (size_t)n * sizeof *lu);
  for (int c = 0; c < n; c++) /* dgbtrf layout: A(r, c) at lu[2 kd + r - c + c ldlu] */
    for (int r = (c > kd ? c - kd : 0); r <= (c + kd < n - 1 ? c + kd : n - 1); r++)
      lu[bidx(2 * kd + r - c, c, ldlu)] =
          b->sb[bidx(kd + r - c, c, b->ld)] - (r == c ? sigma * mass[r] : 0.0);
  int info = 0;
  dgbtrf_(&n, &n, &kd, &kd, lu, &ldlu, ipiv, &info);
  if (info < 0) return vs_error_set(err, VS_ERR_SOLVER, "modal: dgbtrf failed (info %d)", info);
  for (int r = 0; r < n; r++) x[r] = 1.0 + 0.5 * sin(1.0 + r); /* any start with all modes in it */
  m_orthonormalise(n, mass, phi, k, x);
  for (int it = 0; it < VS_MODAL_INVIT; it++) {
    for (int r = 0; r < n; r++) x[r] *= mass[r];
    dgbtrs_("N", &n, &kd, &kd, &one, lu, &ldlu, ipiv, x, &n, &info, 1);
    if (info != 0) return vs_error_set(err, VS_ERR_SOLVER, "modal: dgbtrs failed (info %d)", info);
    m_orthonormalise(n, mass, phi, k, x);
  }
  return VS_OK;
}

/* The lowest nm eigenpairs of (S, diag(mass)). */
static vs_status band_modes(const band *b, const double *mass, int nm, double *w2, double *phi,
                            vs_error *err) {
  vs_status st = band_eigenvalues(b, mass, nm, w2, err);
  if (st != VS_OK) return st;
  if (!(w2[0] > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "modal: lowest eigenvalue omega^2 = %g s^-2 <= 0: not a stable equilibrium",
                        w2[0]);
  double *lu = malloc((size_t)(3 * b->kd + 1) * (size_t)b->n * sizeof *lu);
  int *ipiv = malloc((size_t)b->n * sizeof *ipiv);
  if (lu == NULL || ipiv == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  for (int k = 0; st == VS_OK && k < nm; k++)
    st = band_vector(b, mass, w2[k], phi, k, phi + (size_t)k * (size_t)b->n, lu, ipiv, err);
  free(lu);
  free(ipiv);
  return st;
}

vs_status vs_modal_compute(const vs_model *m, const double *q, double delta, int n_modes,
                           vs_modal *out, vs_error *err) {
  memset(out, 0, sizeof *out);
  const int n = vs_model_size(m);
  int nm = n_modes < VS_MODAL_MAX ? n_modes : VS_MODAL_MAX;
  if (nm > n) nm = n;
  if (n > VS_MODAL_MAX_DOF)
    return vs_error_set(err, VS_ERR_INVALID,
                        "modal: %d unknowns, the eigensolver takes at most %d (%d voussoirs)", n,
                        VS_MODAL_MAX_DOF, VS_MODAL_MAX_DOF / 3);
  if (nm < 1) return vs_error_set(err, VS_ERR_INVALID, "modal: %d modes asked (allowed: >= 1)", n_modes);
  band b = {0};
  double *mass = malloc((size_t)n * sizeof *mass);
  out->phi = malloc((size_t)n * (size_t)nm * sizeof *out->phi);
  vs_status st = VS_OK;
  if (mass == NULL || out->phi == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  if (st == VS_OK) st = band_stiffness(m, q, delta, &b, err);
  double w2[VS_MODAL_MAX];
  if (st == VS_OK) {
    out->asymmetry = b.asym;
    vs_model_mass(m, mass);
    st = band_modes(&b, mass, nm, w2, out->phi, err);
  }
  for (int i = 0; st == VS_OK && i < nm; i++) {
    out->omega[i] = sqrt(w2[i]);
    out->freq_hz[i] = out->omega[i] / (2.0 * VS_PI);
  }
  free(b.sb);
  free(mass);
  if (st != VS_OK) {
    vs_modal_free(out);
    return st;
  }
  out->n_modes = nm;
  out->n = n;
  return vs_modal_damping_ratios(m, q, delta, out, err);
}

/* The damping force is linear in the velocity at fixed positions (dashpots act where the joints
 * are in contact, a property of q), so C phi is the damping force at v = phi. */
vs_status vs_modal_damping_ratios(const vs_model *m, const double *q, double delta, vs_modal *out,
                                  vs_error *err) {
  const int n = out->n;
  if (out->phi == NULL) return vs_error_set(err, VS_ERR_INVALID, "modal: no mode shapes");
  double *f = malloc((size_t)n * sizeof *f);
  if (f == NULL) return vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  for (int i = 0; i < out->n_modes; i++) {
    const double *phi = out->phi + (size_t)i * (size_t)n;
    vs_model_damping(m, q, phi, delta, 0.0, f, NULL, NULL, NULL);
    double c = 0.0;
    for (int r = 0; r < n; r++) c += phi[r] * f[r];
    out->zeta[i] = c / (2.0 * out->omega[i]);
  }
  free(f);
  return VS_OK;
}
