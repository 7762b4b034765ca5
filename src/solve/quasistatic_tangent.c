/* The tangent stiffness of the quasi-static path at its states: KLU's factors of it and the sign
 * of its determinant, its smallest eigenvalue (inverse iteration), the path tangent dq/ddelta,
 * and the stability test that accepts a state (stability.h). */
#include "quasistatic_internal.h"

#include <klu.h>
#include <math.h>
#include <string.h>
#include <sunlinsol/sunlinsol_klu.h>

/* Sign of a permutation of n >= 0 entries (+1 even, -1 odd); seen has n bytes of scratch. */
static int perm_sign(const SuiteSparse_long *p, long n, unsigned char *seen) {
  if (n <= 0) return 1;
  memset(seen, 0, (size_t)n);
  long transpositions = 0;
  for (long i = 0; i < n; i++) {
    if (seen[i]) continue;
    long len = 0;
    for (long j = i; !seen[j]; j = p[j]) {
      seen[j] = 1;
      len++;
    }
    transpositions += len - 1;
  }
  return (transpositions % 2 == 0) ? 1 : -1;
}

/* Factor the tangent at (q, delta) with KLU (s->LSt); *det_sign = sign of det K from the
 * factors: KLU factors P (R\K) Q = L U with R > 0 (the identity here: VS_KLU_SCALE, in
 * quasistatic.c), so sign(det K) = sign(P) sign(Q) prod sign(U_ii). */
int vs_qs_tangent_factor(vs_qs_solver *s, const double *q, double delta, int *det_sign) {
  vs_model_jacobian(s->m, q, delta, s->Jt);
  const int flag = SUNLinSolSetup(s->LSt, s->Jt);
  if (flag != 0) {
    *det_sign = 0;
    return flag;
  }
  const sun_klu_symbolic *sym = SUNLinSol_KLUGetSymbolic(s->LSt);
  const sun_klu_numeric *num = SUNLinSol_KLUGetNumeric(s->LSt);
  const long n = s->n;
  int sign = perm_sign(num->Pnum, n, s->seen) * perm_sign(sym->Q, n, s->seen);
  const double *ud = num->Udiag;
  for (long i = 0; i < n; i++) {
    if (ud[i] == 0.0) sign = 0;
    else if (ud[i] < 0.0) sign = -sign;
  }
  *det_sign = sign;
  return 0;
}

/* x <- K^-1 b with the factors of vs_qs_tangent_factor. */
int vs_qs_tangent_solve(vs_qs_solver *s, N_Vector x, N_Vector b) {
  return SUNLinSolSolve(s->LSt, s->Jt, x, b, 0.0);
}

/* Smallest |eigenvalue| of the scaled tangent D K D (rotations scaled by the block length,
 * so that every entry is in N/m), by inverse iteration on the factored tangent. vec (n entries)
 * is the start vector and receives the eigenvector; all zeros means a fixed pseudo-random start.
 * rtol: relative change of the estimate that ends the iteration, maxit: the iteration cap.
 * NaN if a solve fails. */
double vs_qs_tangent_min_eig(vs_qs_solver *s, double *vec, double rtol, int maxit) {
  N_Vector y = s->w1, z = s->w2;
  double *py = N_VGetArrayPointer(y), *pz = N_VGetArrayPointer(z);
  memcpy(py, vec, (size_t)s->n * sizeof *py);
  double nrm = sqrt(N_VDotProd(y, y)), mu = 0.0;
  if (!(nrm > 0.0)) {
    unsigned long seed = 12345u;
    for (int i = 0; i < s->n; i++) {
      seed = seed * 6364136223846793005ul + 1442695040888963407ul;
      py[i] = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
    }
    nrm = sqrt(N_VDotProd(y, y));
  }
  N_VScale(1.0 / nrm, y, y);
  for (int it = 0; it < maxit; it++) {
    /* A = D K D with D = diag(1, 1, 1/len): A^-1 y = D^-1 K^-1 D^-1 y */
    for (int i = 0; i < s->n; i++) py[i] *= s->len[i];
    if (vs_qs_tangent_solve(s, z, y) != 0) {
      mu = NAN;
      break;
    }
    for (int i = 0; i < s->n; i++) pz[i] *= s->len[i];
    nrm = sqrt(N_VDotProd(z, z));
    const double mu_new = 1.0 / nrm;
    N_VScale(1.0 / nrm, z, y);
    if (it > 0 && fabs(mu_new - mu) <= rtol * mu_new) {
      mu = mu_new;
      break;
    }
    mu = mu_new;
  }
  memcpy(vec, py, (size_t)s->n * sizeof *vec);
  return mu;
}

/* Tangent of the path, dq/ddelta = -K^-1 dG/ddelta, with the factors of vs_qs_tangent_factor. */
int vs_qs_path_tangent(vs_qs_solver *s, const double *q, double delta, double *dq) {
  N_Vector b = s->w1, x = s->w2;
  vs_model_dG_ddelta(s->m, q, delta, N_VGetArrayPointer(b));
  N_VScale(-1.0, b, b);
  int flag = vs_qs_tangent_solve(s, x, b);
  if (flag == 0) memcpy(dq, N_VGetArrayPointer(x), (size_t)s->n * sizeof *dq);
  return flag;
}

/* 1 if a joint in contact slides at (q, delta) with the committed slips. */
static int any_sliding(vs_qs_solver *s, const double *q, double delta) {
  const int nj = vs_model_geometry(s->m)->n_joints;
  vs_model_joint_states(s->m, q, delta, s->js);
  for (int k = 0; k < nj; k++)
    if (s->js[k].sliding && s->js[k].N > 0.0) return 1;
  return 0;
}

/* Accept a converged state as on the followed stable branch: the tangent must be positive
 * definite, established by a Cholesky factorisation of its symmetric part (stability.h; the sign
 * of det K alone would not). Where joints slide, the tangent is their sliding branch's, which is
 * not symmetric (Coulomb friction is not associated: dT = mu dN, while N does not follow the
 * slip), and its symmetric part can be indefinite at a state that is stable; there a positive
 * determinant is enough, whose sign turns where the sliding branch folds or turns a corner.
 * The LU is kept for the eigenvalue tracking and the path tangent. */
int vs_qs_stable_state(vs_qs_solver *s, const double *q, double delta) {
  int sign = 0;
  if (vs_qs_tangent_factor(s, q, delta, &sign) != 0) return 0;
  if (vs_spd_test(s->spd, s->Jt) == 1) return 1;
  return sign > 0 && any_sliding(s, q, delta);
}
