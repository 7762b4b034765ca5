/* Natural frequencies and mode shapes about an equilibrium: the tangent stiffness (from the
 * model's analytic CSC Jacobian) and the diagonal mass matrix, densely, into LAPACK's dsygvx
 * for the lowest modes only; the damping ratio of each mode from the damping forces at rest. */
#include "voussoir/modal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/units.h"

/* LAPACK (Fortran ABI, gfortran: hidden lengths of the character arguments at the end). */
extern void dsygvx_(const int *itype, const char *jobz, const char *range, const char *uplo,
                    const int *n, double *a, const int *lda, double *b, const int *ldb,
                    const double *vl, const double *vu, const int *il, const int *iu,
                    const double *abstol, int *m, double *w, double *z, const int *ldz,
                    double *work, const int *lwork, int *iwork, int *ifail, int *info,
                    size_t jobz_len, size_t range_len, size_t uplo_len);

void vs_modal_free(vs_modal *out) {
  if (out == NULL) return;
  free(out->phi);
  out->phi = NULL;
}

/* Dense, symmetrised tangent stiffness into Kd (n x n column-major); returns the asymmetry. */
static vs_status dense_stiffness(const vs_model *m, const double *q, double delta, double *Kd,
                                 double *asym, vs_error *err) {
  const int n = vs_model_size(m);
  SUNContext ctx = NULL;
  if (SUNContext_Create(NULL, &ctx) != 0) return vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  SUNMatrix K = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  if (K == NULL) {
    SUNContext_Free(&ctx);
    return vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  }
  vs_model_jacobian(m, q, delta, K);
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(K), *ki = SUNSparseMatrix_IndexValues(K);
  const double *kx = SUNSparseMatrix_Data(K);
  memset(Kd, 0, (size_t)n * (size_t)n * sizeof *Kd);
  for (int c = 0; c < n; c++)
    for (sunindextype e = kp[c]; e < kp[c + 1]; e++) Kd[(size_t)c * (size_t)n + (size_t)ki[e]] = kx[e];
  SUNMatDestroy(K);
  SUNContext_Free(&ctx);
  double dmax = 0.0, kmax = 0.0;
  for (int c = 0; c < n; c++)
    for (int r = 0; r <= c; r++) {
      double *a = &Kd[(size_t)c * (size_t)n + (size_t)r], *b = &Kd[(size_t)r * (size_t)n + (size_t)c];
      dmax = fmax(dmax, fabs(*a - *b));
      kmax = fmax(kmax, fmax(fabs(*a), fabs(*b)));
      *a = *b = 0.5 * (*a + *b);
    }
  *asym = kmax > 0.0 ? dmax / kmax : 0.0;
  return VS_OK;
}

/* The lowest nm eigenpairs of (Kd, diag(mass)); Kd is destroyed. */
static vs_status solve_lowest(int n, int nm, double *Kd, const double *mass, double *w,
                              double *phi, vs_error *err) {
  double *B = calloc((size_t)n * (size_t)n, sizeof *B);
  double *wall = malloc((size_t)n * sizeof *wall);
  int *iwork = malloc(5 * (size_t)n * sizeof *iwork), *ifail = malloc((size_t)n * sizeof *ifail);
  const int itype = 1, il = 1, iu = nm, lwork = 8 * n;
  double *work = malloc((size_t)lwork * sizeof *work);
  vs_status st = VS_OK;
  if (B == NULL || wall == NULL || iwork == NULL || ifail == NULL || work == NULL) {
    st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  } else {
    for (int i = 0; i < n; i++) B[(size_t)i * (size_t)n + (size_t)i] = mass[i];
    const double vl = 0.0, vu = 0.0, abstol = 0.0;
    int found = 0, info = 0;
    dsygvx_(&itype, "V", "I", "U", &n, Kd, &n, B, &n, &vl, &vu, &il, &iu, &abstol, &found, wall,
            phi, &n, work, &lwork, iwork, ifail, &info, 1, 1, 1);
    if (info > n)
      st = vs_error_set(err, VS_ERR_INVALID, "modal: mass matrix not positive definite");
    else if (info != 0 || found != nm)
      st = vs_error_set(err, VS_ERR_SOLVER, "modal: dsygvx failed (info %d, %d of %d modes)", info,
                        found, nm);
    else
      memcpy(w, wall, (size_t)nm * sizeof *w);
  }
  free(B);
  free(wall);
  free(iwork);
  free(ifail);
  free(work);
  return st;
}

vs_status vs_modal_compute(const vs_model *m, const double *q, double delta, int n_modes,
                           vs_modal *out, vs_error *err) {
  memset(out, 0, sizeof *out);
  const int n = vs_model_size(m);
  const int nm = n_modes < VS_MODAL_MAX ? (n_modes < n ? n_modes : n) : (VS_MODAL_MAX < n ? VS_MODAL_MAX : n);
  if (n > VS_MODAL_MAX_DOF)
    return vs_error_set(err, VS_ERR_INVALID,
                        "modal: %d unknowns, the dense eigensolver takes at most %d (%d voussoirs)",
                        n, VS_MODAL_MAX_DOF, VS_MODAL_MAX_DOF / 3);
  if (nm < 1) return vs_error_set(err, VS_ERR_INVALID, "modal: %d modes asked (allowed: >= 1)", n_modes);
  double *Kd = malloc((size_t)n * (size_t)n * sizeof *Kd), *mass = malloc((size_t)n * sizeof *mass);
  out->phi = malloc((size_t)n * (size_t)nm * sizeof *out->phi);
  vs_status st = VS_OK;
  if (Kd == NULL || mass == NULL || out->phi == NULL)
    st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  if (st == VS_OK) st = dense_stiffness(m, q, delta, Kd, &out->asymmetry, err);
  if (st == VS_OK) {
    vs_model_mass(m, mass);
    double w2[VS_MODAL_MAX];
    st = solve_lowest(n, nm, Kd, mass, w2, out->phi, err);
    if (st == VS_OK && !(w2[0] > 0.0))
      st = vs_error_set(err, VS_ERR_INVALID,
                        "modal: lowest eigenvalue omega^2 = %g s^-2 <= 0: not a stable equilibrium",
                        w2[0]);
    for (int i = 0; st == VS_OK && i < nm; i++) {
      out->omega[i] = sqrt(w2[i]);
      out->freq_hz[i] = out->omega[i] / (2.0 * VS_PI);
    }
  }
  free(Kd);
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
