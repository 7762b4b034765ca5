/* The dynamic phase's equations (dynamic_internal.h): the forces, the supports' constraints,
 * IDA's residual and its analytic Jacobian in CSC, and what they give at IDA's state (the
 * reported accelerations, reactions and multipliers). */
#include "voussoir/dynamic.h"

#include <math.h>
#include <string.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "dynamic_internal.h"

/* The generalised forces F(q, v) of the equations of motion M v' + F - G^T lambda = 0 over
 * the blocks and supports (ne entries): joint forces minus gravity plus damping forces, from one
 * pass over the joints; *diss gets the damping power, *fric (may be NULL) the joints' friction
 * power. Kept apart so that further force models add here. */
static void dyn_forces(vs_dynamic *d, const double *q, const double *v, double *F, double *diss,
                       double *fric) {
  vs_model_ext_motion(d->m, q, v, F, diss, fric, NULL, NULL);
  if (d->ct != NULL) vs_contact_forces(d->ct, q, v, F, diss, NULL);
  if (d->cl != NULL) vs_collide_forces(d->cl, q, v, F, diss, NULL);
}

/* The constraints g(q, t) (VS_DYN_NC) and their velocity form G v + g_t. */
static void constraints(const vs_dynamic *d, double t, const double *q, const double *v,
                        double *g, double *gv) {
  double qs[6], vs[6];
  vs_model_support_states(d->m, vs_dyn_delta_at(d, t), d->o.rate, qs, vs);
  for (int c = 0; c < d->nc; c++) {
    const int i = d->cons[c];
    if (g != NULL) g[c] = q[d->n + i] - qs[i];
    if (gv != NULL) gv[c] = v[d->n + i] - vs[i];
  }
}

/* A raised stop flag is fatal (-1): IDA returns at once. */
int vs_dyn_residual(double t, N_Vector yy, N_Vector yp, N_Vector rr, void *user) {
  vs_dynamic *d = user;
  if (vs_dyn_stopped(d)) return -1;
  const int n = d->n, ne = d->ne;
  const double *y = N_VGetArrayPointer(yy), *ydot = N_VGetArrayPointer(yp);
  double *r = N_VGetArrayPointer(rr);
  const double *q = y, *v = y + d->iv, *lam = y + d->il, *mu = y + d->imu;
  const double *qd = ydot, *vd = ydot + d->iv;
  double diss = 0.0, fric = 0.0;
  dyn_forces(d, q, v, r + d->iv, &diss, &fric);
  for (int i = 0; i < ne; i++) {
    r[i] = qd[i] - v[i];
    r[d->iv + i] += d->mass[i] * vd[i];
  }
  double sup = 0.0;
  for (int c = 0; c < d->nc; c++) { /* G: rows of the identity on the supports' components */
    const int i = n + d->cons[c];
    r[i] -= mu[c];
    r[d->iv + i] -= lam[c];
    sup += lam[c] * v[i];
  }
  constraints(d, t, q, v, r + d->il, r + d->imu);
  r[d->ie] = ydot[d->ie] - sup;
  r[d->ie + 1] = ydot[d->ie + 1] - diss;
  if (d->ct != NULL) vs_contact_forces(d->ct, q, v, NULL, NULL, &fric);
  if (d->cl != NULL) vs_collide_forces(d->cl, q, v, NULL, NULL, &fric);
  r[d->ie + 2] = ydot[d->ie + 2] - fric;
  return 0;
}

/* Append one entry to column-major CSC storage. */
static void put(sunindextype *ji, double *jx, sunindextype *p, sunindextype row, double val) {
  ji[*p] = row;
  jx[(*p)++] = val;
}

/* The Jacobian with the bodies' contacts (collide.h) armed: K and C (the joints', the ground's,
 * the contacts') gathered dense, the pattern the joints' plus a 3x3 block for every pair of
 * bodies of the broad phase at y. When those pairs differ from the ones KLU analysed, its
 * analysis is redone (SUNKLU_REINIT_PARTIAL: the next factorisation is a fresh one):
 * vs_dyn_jacobian is called by IDA's linear solver setup, right before that factorisation. */
static sunindextype fill_dense(vs_dynamic *d, double cj, sunindextype *jp, sunindextype *ji,
                               double *jx);
static int jac_dense(vs_dynamic *d, double cj, const double *y, SUNMatrix Jac);

/* put, or only count the entry when jx is NULL */
static void put_or_count(sunindextype *ji, double *jx, sunindextype *p, sunindextype row,
                         double val) {
  if (jx != NULL) put(ji, jx, p, row, val);
  else (*p)++;
}

static int jac_dense(vs_dynamic *d, double cj, const double *y, SUNMatrix Jac) {
  const int ne = d->ne, nb = vs_collide_bodies(d->cl);
  const size_t NE = (size_t)ne; /* Kd, Cd are zero outside the calls (fill_dense clears them) */
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(d->K), *ki = SUNSparseMatrix_IndexValues(d->K);
  const double *kx = SUNSparseMatrix_Data(d->K), *cx = SUNSparseMatrix_Data(d->C);
  for (int col = 0; col < ne; col++)
    for (sunindextype e = kp[col]; e < kp[col + 1]; e++) {
      d->Kd[(size_t)col * NE + (size_t)ki[e]] += kx[e];
      d->Cd[(size_t)col * NE + (size_t)ki[e]] += cx[e];
    }
  vs_collide_jacobian(d->cl, y, y + d->iv, d->Kd, d->Cd);
  vs_collide_pairs(d->cl, y, d->pairs);
  if (!d->klu_pairs || memcmp(d->pairs, d->pairs_klu, (size_t)(nb * nb)) != 0) {
    memcpy(d->pairs_klu, d->pairs, (size_t)(nb * nb));
    d->klu_pairs = 1;
    /* J's storage to the new pattern's size: IDA zeroes all of it before every evaluation */
    if (SUNSparseMatrix_Reallocate(Jac, fill_dense(d, cj, NULL, NULL, NULL)) != 0 ||
        SUNLinSol_KLUReInit(d->LS, Jac, SUNSparseMatrix_NNZ(Jac), SUNKLU_REINIT_PARTIAL) != 0)
      return -1;
    SUNLinSol_KLUGetCommon(d->LS)->scale = VS_DYN_KLU_SCALE_CONTACTS; /* a fresh factorisation */
  }
  fill_dense(d, cj, SUNSparseMatrix_IndexPointers(Jac), SUNSparseMatrix_IndexValues(Jac),
             SUNSparseMatrix_Data(Jac));
  return 0;
}

/* Lay out J from Kd, Cd and the pattern (jac_dense) into jp, ji, jx; or, with jx NULL, only
 * count its entries. Returns the count. */
static sunindextype fill_dense(vs_dynamic *d, double cj, sunindextype *jp, sunindextype *ji,
                               double *jx) {
  const int n = d->n, ne = d->ne, nb = vs_collide_bodies(d->cl);
  const size_t NE = (size_t)ne;
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(d->K), *ki = SUNSparseMatrix_IndexValues(d->K);
  sunindextype p = 0;
  for (int half = 0; half < 2; half++) /* q columns, then v columns */
    for (int col = 0; col < ne; col++) {
      double *A = (half == 0 ? d->Kd : d->Cd) + (size_t)col * NE;
      if (jx != NULL) jp[half * d->iv + col] = p;
      put_or_count(ji, jx, &p, col, half == 0 ? cj : -1.0);
      sunindextype e = kp[col];
      const sunindextype end = kp[col + 1];
      for (int b = 0; b < nb; b++) { /* rows by body: all 3 of a pair's, else the joints' */
        const int whole = b == col / 3 || d->pairs[b * nb + col / 3];
        if (!whole && (e >= end || ki[e] >= 3 * b + 3)) continue;
        for (int row = 3 * b; row < 3 * b + 3; row++) {
          while (e < end && ki[e] < row) e++;
          if (!whole && !(e < end && ki[e] == row)) continue;
          put_or_count(ji, jx, &p, d->iv + row,
                       A[row] + (half == 1 && row == col ? cj * d->mass[col] : 0.0));
          if (jx != NULL) A[row] = 0.0;
        }
      }
      if (col >= n && d->cidx[col - n] >= 0)
        put_or_count(ji, jx, &p, (half == 0 ? d->il : d->imu) + d->cidx[col - n], 1.0);
    }
  for (int c = 0; c < d->nc; c++) { /* lambda columns */
    if (jx != NULL) jp[d->il + c] = p;
    put_or_count(ji, jx, &p, d->iv + n + d->cons[c], -1.0);
  }
  for (int c = 0; c < d->nc; c++) { /* mu columns */
    if (jx != NULL) jp[d->imu + c] = p;
    put_or_count(ji, jx, &p, n + d->cons[c], -1.0);
  }
  for (int col = d->ie; col < d->N; col++) {
    if (jx != NULL) jp[col] = p;
    put_or_count(ji, jx, &p, col, cj);
  }
  if (jx != NULL) jp[d->N] = p;
  return p;
}

/* J = dF/dy + cj dF/dy', rows and columns in the order of y:
 *   q rows:  [cj I, -I, 0, -G^T],  v rows: [K, cj M + C, -G^T, 0],
 *   lambda rows: [G, 0, 0, 0],     mu rows: [0, G, 0, 0],
 * and cj on the bookkeeping diagonal (their dependence on the state is left out: nothing
 * depends on them, so Newton still converges). G is constant and G^T mu, G^T lambda are
 * linear, so there are no constraint Hessian terms. The dependence of the damping forces on the
 * positions is left out too (IDA's Newton is a modified Newton already). */
int vs_dyn_jacobian(double t, double cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix Jac,
                    void *user, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t;
  (void)yp;
  (void)rr;
  (void)t1;
  (void)t2;
  if (vs_dyn_stopped(user)) return -1;
  (void)t3;
  vs_dynamic *d = user;
  const int n = d->n, ne = d->ne;
  const double *y = N_VGetArrayPointer(yy);
  d->jac_evals++;
  vs_model_ext_motion(d->m, y, y + d->iv, NULL, NULL, NULL, d->K, d->C);
  if (d->ct != NULL) vs_contact_jacobian(d->ct, y, y + d->iv, d->K, d->C);
  if (d->cl != NULL && vs_collide_armed(d->cl)) return jac_dense(d, cj, y, Jac);
  if (d->klu_pairs) { /* back from the contacts' pattern (a later run): the joints' again */
    d->klu_pairs = 0;
    const sunindextype nnz = 2 * ne + 2 * vs_model_ext_nnz(d->m) + 4 * d->nc + 3;
    if (SUNSparseMatrix_Reallocate(Jac, nnz) != 0 ||
        SUNLinSol_KLUReInit(d->LS, Jac, nnz, SUNKLU_REINIT_PARTIAL) != 0)
      return -1;
    SUNLinSol_KLUGetCommon(d->LS)->scale = VS_DYN_KLU_SCALE; /* a fresh factorisation */
  }
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(d->K), *ki = SUNSparseMatrix_IndexValues(d->K);
  const double *kx = SUNSparseMatrix_Data(d->K), *cx = SUNSparseMatrix_Data(d->C);
  sunindextype *jp = SUNSparseMatrix_IndexPointers(Jac), *ji = SUNSparseMatrix_IndexValues(Jac);
  double *jx = SUNSparseMatrix_Data(Jac);
  sunindextype p = 0;
  for (int col = 0; col < ne; col++) { /* q columns */
    jp[col] = p;
    put(ji, jx, &p, col, cj);
    for (sunindextype e = kp[col]; e < kp[col + 1]; e++) put(ji, jx, &p, d->iv + ki[e], kx[e]);
    if (col >= n && d->cidx[col - n] >= 0) put(ji, jx, &p, d->il + d->cidx[col - n], 1.0);
  }
  for (int col = 0; col < ne; col++) { /* v columns */
    jp[d->iv + col] = p;
    put(ji, jx, &p, col, -1.0);
    for (sunindextype e = kp[col]; e < kp[col + 1]; e++)
      put(ji, jx, &p, d->iv + ki[e], cx[e] + (ki[e] == col ? cj * d->mass[col] : 0.0));
    if (col >= n && d->cidx[col - n] >= 0) put(ji, jx, &p, d->imu + d->cidx[col - n], 1.0);
  }
  for (int c = 0; c < d->nc; c++) { /* lambda columns */
    jp[d->il + c] = p;
    put(ji, jx, &p, d->iv + n + d->cons[c], -1.0);
  }
  for (int c = 0; c < d->nc; c++) { /* mu columns */
    jp[d->imu + c] = p;
    put(ji, jx, &p, n + d->cons[c], -1.0);
  }
  for (int col = d->ie; col < d->N; col++) {
    jp[col] = p;
    put(ji, jx, &p, col, cj);
  }
  jp[d->N] = p;
  return 0;
}

/* Constraint drift max |g| at the current state (m for the translations, rad for the
 * rotations: both stay at round-off). */
double vs_dyn_drift(const vs_dynamic *d, double t, const double *y) {
  double g[VS_DYN_NC], worst = 0.0;
  constraints(d, t, y, y + d->iv, g, NULL);
  for (int c = 0; c < d->nc; c++) worst = fmax(worst, fabs(g[c]));
  return worst;
}

void vs_dynamic_residual(vs_dynamic *d, double t, double *y, double *yp, double *r) {
  N_Vector vy = N_VMake_Serial(d->N, y, d->ctx), vp = N_VMake_Serial(d->N, yp, d->ctx);
  N_Vector vr = N_VMake_Serial(d->N, r, d->ctx);
  if (vy != NULL && vp != NULL && vr != NULL) vs_dyn_residual(t, vy, vp, vr, d);
  N_VDestroy(vy);
  N_VDestroy(vp);
  N_VDestroy(vr);
}

void vs_dynamic_jacobian(vs_dynamic *d, double t, double cj, double *y, SUNMatrix J) {
  N_Vector vy = N_VMake_Serial(d->N, y, d->ctx);
  if (vy != NULL) vs_dyn_jacobian(t, cj, vy, NULL, NULL, J, d, NULL, NULL, NULL);
  N_VDestroy(vy);
}

/* The reported multipliers and accelerations are those the DAE gives at IDA's state (q, v):
 * on the constraint manifold the equations of motion and the hidden constraint G v' = d/dt of
 * the supports' prescribed velocities (zero: they move at a constant rate) fix v' and lambda
 * uniquely, M v' + F(q, v) = G^T lambda -- a support body's constrained rows give lambda = F
 * there, a block's rows v' = -F / m. IDA's own lambda and v' are the last Newton iterate
 * and the BDF formula's derivative: they satisfy those equations only to the Newton iteration's
 * tolerance, which is loose on the velocities by design (VS_DYN_VEL_TIME), so IDA's lambda is off
 * by up to ~1e-2 of the arch's weight in the fast motion before a collapse. Evaluated on demand:
 * one force evaluation. */
static void implied_forces(vs_dynamic *d) {
  double diss = 0.0;
  dyn_forces(d, N_VGetArrayPointer(d->y), N_VGetArrayPointer(d->y) + d->iv, d->force, &diss, NULL);
}

void vs_dynamic_accelerations(vs_dynamic *d, double *a) {
  implied_forces(d);
  for (int i = 0; i < d->n; i++) a[i] = -d->force[i] / d->mass[i];
}

void vs_dynamic_reactions(vs_dynamic *d, double out[6]) {
  const double *f = d->force + d->n;
  double fs[6];
  if (d->cl != NULL && vs_collide_armed(d->cl)) { /* bodies' contacts act on the piers too */
    implied_forces(d);
  } else { /* only the joints at the supports act on them */
    vs_model_ext_support_forces(d->m, N_VGetArrayPointer(d->y), N_VGetArrayPointer(d->y) + d->iv, fs);
    f = fs;
  }
  for (int i = 0; i < VS_DYN_NC; i++) out[i] = d->cidx[i] >= 0 ? f[i] : 0.0;
}

void vs_dynamic_multipliers(const vs_dynamic *d, double out[6]) {
  const double *lam = N_VGetArrayPointer(d->y) + d->il;
  for (int i = 0; i < VS_DYN_NC; i++) out[i] = d->cidx[i] >= 0 ? lam[d->cidx[i]] : 0.0;
}

void vs_dynamic_derivatives(const vs_dynamic *d, double *a) {
  memcpy(a, N_VGetArrayPointer(d->yp) + d->iv, (size_t)d->n * sizeof *a);
}
