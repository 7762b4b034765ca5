/* Natural frequencies and mode shapes about an equilibrium: the tangent stiffness (from the
 * model's analytic CSC Jacobian, banded: blocks couple to their neighbours only) and the
 * diagonal mass matrix; the lowest eigenvalues by ARPACK (implicitly restarted Lanczos, dsaupd/
 * dseupd) on the inverted operator M^1/2 K^-1 M^1/2, applied through a banded Cholesky factor
 * (cost linear in the unknowns; LAPACK's banded dsbgvx, whose band reduction grows as n^2, only
 * where ARPACK cannot answer: K not positive definite, or no convergence), their mode
 * shapes by inverse iteration on a banded LU; the damping ratio of each mode from the damping
 * forces. */
#include "voussoir/modal.h"

#include <arpack.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "model_matrix.h"
#include "voussoir/units.h"

/* LAPACK (Fortran ABI, gfortran: hidden lengths of the character arguments at the end). */
extern void dsbgvx_(const char *jobz, const char *range, const char *uplo, const int *n,
                    const int *ka, const int *kb, double *ab, const int *ldab, double *bb,
                    const int *ldbb, double *q, const int *ldq, const double *vl, const double *vu,
                    const int *il, const int *iu, const double *abstol, int *m, double *w,
                    double *z, const int *ldz, double *work, int *iwork, int *ifail, int *info,
                    size_t jobz_len, size_t range_len, size_t uplo_len);
extern void dpbtrf_(const char *uplo, const int *n, const int *kd, double *ab, const int *ldab,
                    int *info, size_t uplo_len);
extern void dpbtrs_(const char *uplo, const int *n, const int *kd, const int *nrhs,
                    const double *ab, const int *ldab, double *b, const int *ldb, int *info,
                    size_t uplo_len);
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
/* ARPACK: Lanczos vectors kept (ncv; at least 2 nev + 1), implicit restarts allowed, and the
 * Ritz residual, relative to the Ritz value, below which a mode has converged (the lowest modes
 * of an arch converge in a few restarts: the inverted spectrum 1/omega^2 falls off fast; the
 * eigenvalue then has a relative error of the order of the square of this, far below the
 * round-off of dsbgvx's absolute tolerance). */
static const int VS_MODAL_ARPACK_NCV = 20;
static const int VS_MODAL_ARPACK_MAXIT = 300;
static const double VS_MODAL_ARPACK_TOL = 1e-11;

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

/* The mass diagonal of the static state: the blocks' (vs_model_mass), and for a pinned support's
 * rotation the rotary inertia the dynamic model gives it (vs_model_ext_mass: the mean voussoir's). */
static void state_mass(const vs_model *m, int n, double *mass) {
  const int left = vs_model_support_dof(m, 0), right = vs_model_support_dof(m, 1);
  const int nb = (n - (left >= 0) - (right >= 0)) / 3;
  vs_model_mass(m, mass);
  double inertia = 0.0;
  for (int i = 0; i < nb; i++) inertia += mass[3 * i + 2] / nb;
  if (left >= 0) mass[left] = inertia;
  if (right >= 0) mass[right] = inertia;
}

static vs_status band_stiffness(const vs_model *m, const double *q, double delta, const int *perm,
                                band *b, vs_error *err) {
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
    int *inv = malloc((size_t)n * sizeof *inv), kd = 0; /* inv[old] = new */
    if (inv == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
    for (int i = 0; st == VS_OK && i < n; i++) inv[perm[i]] = i;
    for (int c = 0; st == VS_OK && c < n; c++)
      for (sunindextype e = kp[c]; e < kp[c + 1]; e++) kd = (int)fmax(kd, abs(inv[ki[e]] - inv[c]));
    b->n = n;
    b->kd = kd;
    b->ld = 2 * kd + 1;
    b->sb = calloc((size_t)b->ld * (size_t)n, sizeof *b->sb);
    if (b->sb == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
    for (int c0 = 0; st == VS_OK && c0 < n; c0++)
      for (sunindextype e = kp[c0]; e < kp[c0 + 1]; e++) {
        const int r = inv[ki[e]], c = inv[c0];
        b->sb[bidx(kd + r - c, c, b->ld)] = kx[e];
      }
    free(inv);
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

/* ARPACK's workspace (dsaupd/dseupd, regular mode, reverse communication): the Cholesky factor
 * of S (upper band), sqrt of the masses, the residual (starting vector), the Lanczos basis
 * (n x ncv) and ARPACK's work arrays. */
typedef struct {
  int n, kd, ldab, ncv, lworkl;
  double *ab, *sm, *resid, *v, *workd, *workl, *d;
  int *select;
} arpack_ws;

static void arpack_free(arpack_ws *a) {
  free(a->ab);
  free(a->sm);
  free(a->resid);
  free(a->v);
  free(a->workd);
  free(a->workl);
  free(a->d);
  free(a->select);
}

/* 0, or -1 out of memory. */
static int arpack_alloc(arpack_ws *a, const band *b, int nm) {
  const int ncv = 2 * nm + 1 > VS_MODAL_ARPACK_NCV ? 2 * nm + 1 : VS_MODAL_ARPACK_NCV;
  *a = (arpack_ws){.n = b->n, .kd = b->kd, .ldab = b->kd + 1, .ncv = ncv < b->n ? ncv : b->n};
  a->lworkl = a->ncv * (a->ncv + 8);
  const size_t n = (size_t)a->n, m = (size_t)a->ncv;
  a->ab = malloc((size_t)a->ldab * n * sizeof *a->ab);
  a->sm = malloc(n * sizeof *a->sm);
  a->resid = malloc(n * sizeof *a->resid);
  a->v = malloc(n * m * sizeof *a->v);
  a->workd = malloc(3 * n * sizeof *a->workd);
  a->workl = malloc((size_t)a->lworkl * sizeof *a->workl);
  a->d = malloc(m * sizeof *a->d);
  a->select = malloc(m * sizeof *a->select);
  return (a->ab && a->sm && a->resid && a->v && a->workd && a->workl && a->d && a->select) ? 0
                                                                                          : -1;
}

/* w = M^1/2 S^-1 M^1/2 x (symmetric; its largest eigenvalues are 1/omega^2 of the lowest modes). */
static int arpack_apply(const arpack_ws *a, const double *x, double *w) {
  const int one = 1;
  int info = 0;
  for (int r = 0; r < a->n; r++) w[r] = a->sm[r] * x[r];
  dpbtrs_("U", &a->n, &a->kd, &one, a->ab, &a->ldab, w, &a->n, &info, 1);
  for (int r = 0; r < a->n; r++) w[r] *= a->sm[r];
  return info;
}

/* dsaupd's reverse-communication loop from a fixed starting vector (info = 1: the result does
 * not depend on ARPACK's random start), then dseupd for the Ritz values (no vectors) into a->d.
 * 1: nm converged values; 0: no convergence or an ARPACK error. */
static int arpack_run(arpack_ws *a, int nm) {
  for (int r = 0; r < a->n; r++) a->resid[r] = 1.0 + 0.5 * sin(1.0 + r); /* every mode in it */
  int iparam[11] = {0}, ipntr[11] = {0}, ido = 0, info = 1;
  iparam[0] = 1;                      /* exact shifts */
  iparam[2] = VS_MODAL_ARPACK_MAXIT; /* restarts */
  iparam[6] = 1;                      /* mode 1: standard problem, OP = M^1/2 S^-1 M^1/2 */
  for (;;) {
    dsaupd_c(&ido, "I", a->n, "LM", nm, VS_MODAL_ARPACK_TOL, a->resid, a->ncv, a->v, a->n, iparam,
             ipntr, a->workd, a->workl, a->lworkl, &info);
    if (ido != 1 && ido != -1) break;
    if (arpack_apply(a, a->workd + ipntr[0] - 1, a->workd + ipntr[1] - 1) != 0) return 0;
  }
  if (info != 0 || iparam[4] < nm) return 0;
  dseupd_c(0, "A", a->select, a->d, a->v, a->n, 0.0, "I", a->n, "LM", nm, VS_MODAL_ARPACK_TOL,
           a->resid, a->ncv, a->v, a->n, iparam, ipntr, a->workd, a->workl, a->lworkl, &info);
  return info == 0 ? 1 : 0;
}

/* The lowest nm eigenvalues of (S, diag(mass)), ascending, by ARPACK on the banded Cholesky
 * factor of S. 1: found; 0: ARPACK cannot answer (S not positive definite, fewer than nm + 2
 * unknowns, no convergence: the caller falls back on dsbgvx); -1 out of memory. */
static int arpack_eigenvalues(const band *b, const double *mass, int nm, double *w2) {
  if (b->n < nm + 2) return 0; /* dsaupd needs nev < ncv <= n */
  arpack_ws a;
  int found = 0, info = 0;
  if (arpack_alloc(&a, b, nm) != 0) found = -1;
  if (found == 0) {
    for (int c = 0; c < a.n; c++) /* upper band: AB(kd + r - c, c) = S(r, c), r <= c */
      for (int r = (c > a.kd ? c - a.kd : 0); r <= c; r++)
        a.ab[bidx(a.kd + r - c, c, a.ldab)] = b->sb[bidx(a.kd + r - c, c, b->ld)];
    dpbtrf_("U", &a.n, &a.kd, a.ab, &a.ldab, &info, 1);
  }
  if (found == 0 && info == 0) {
    for (int r = 0; r < a.n; r++) a.sm[r] = sqrt(mass[r]);
    /* ARPACK keeps the state of its reverse communication in Fortran SAVE variables: one
     * process-wide state, so runs in threads (the Python package's sweep) take turns here. */
    static pthread_mutex_t arpack_lock = PTHREAD_MUTEX_INITIALIZER;
    pthread_mutex_lock(&arpack_lock);
    found = arpack_run(&a, nm);
    pthread_mutex_unlock(&arpack_lock);
    for (int k = 0; found == 1 && k < nm; k++)
      if (!(a.d[k] > 0.0)) found = 0;
    for (int k = 0; found == 1 && k < nm; k++) { /* 1/theta, ascending (insertion sort) */
      const double x = 1.0 / a.d[k];
      int i = k;
      for (; i > 0 && w2[i - 1] > x; i--) w2[i] = w2[i - 1];
      w2[i] = x;
    }
  }
  arpack_free(&a);
  return found;
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
  const int lz = arpack_eigenvalues(b, mass, nm, w2);
  if (lz < 0) return vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  vs_status st = lz > 0 ? VS_OK : band_eigenvalues(b, mass, nm, w2, err);
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
  double *mass = malloc((size_t)n * sizeof *mass), *massb = malloc((size_t)n * sizeof *massb);
  double *phib = malloc((size_t)n * (size_t)nm * sizeof *phib); /* band order */
  int *perm = malloc((size_t)n * sizeof *perm);
  out->phi = malloc((size_t)n * (size_t)nm * sizeof *out->phi);
  vs_status st = VS_OK;
  if (mass == NULL || massb == NULL || phib == NULL || perm == NULL || out->phi == NULL)
    st = vs_error_set(err, VS_ERR_NOMEM, "modal: out of memory");
  if (st == VS_OK) {
    vs_model_band_order(m, perm); /* a pinned support's rotation next to its block */
    st = band_stiffness(m, q, delta, perm, &b, err);
  }
  double w2[VS_MODAL_MAX];
  if (st == VS_OK) {
    out->asymmetry = b.asym;
    state_mass(m, n, mass);
    for (int i = 0; i < n; i++) massb[i] = mass[perm[i]];
    st = band_modes(&b, massb, nm, w2, phib, err);
  }
  for (int i = 0; st == VS_OK && i < nm; i++) {
    out->omega[i] = sqrt(w2[i]);
    out->freq_hz[i] = out->omega[i] / (2.0 * VS_PI);
    for (int r = 0; r < n; r++)
      out->phi[(size_t)i * (size_t)n + (size_t)perm[r]] = phib[(size_t)i * (size_t)n + (size_t)r];
  }
  free(b.sb);
  free(mass);
  free(massb);
  free(phib);
  free(perm);
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
