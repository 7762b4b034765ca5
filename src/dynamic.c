/* Dynamic phase with IDA: the arch and its two springers as a semi-explicit DAE of index 2 in
 * the stabilised (Gear-Gupta-Leimkuhler) form. Unknowns y = (q, v, lambda, mu, W, D, Df), q and v
 * over the blocks and the two support bodies (3 each), lambda and mu one per constraint:
 *   q' - v - G^T mu = 0,   M v' + F(q, v) - G^T lambda = 0,   g(q, t) = 0,   G v + g_t = 0,
 *   W' = lambda . v_s,   D' = damping power,   Df' = friction power,
 * F = dE/dq + C v the joints' elastic, frictional and damping forces minus gravity, g the
 * supports' rheonomic constraints (left fixed, right moved by delta(t) = rate t along alpha; a
 * fixed support without rotation, a pinned one free to rotate about its pivot -- its reference
 * point, so the pivot's constraints are linear too; G = dg/dq, constant, rows of the identity)
 * and lambda the forces the supports' constraints exert:
 * on a support body moving at constant speed they equal the force the support exerts on the
 * arch. The last three are the energy bookkeeping (IDA in SUNDIALS 6 has no quadratures).
 * lambda and mu are algebraic (IDASetId 0) and left out of the error test (IDASetSuppressAlg).
 * Jacobian dF/dy + cj dF/dy' in CSC with KLU; roots on the joints' edge openings and on the
 * collapse criterion (and, for the impact damping model, on the gaps of opened edges: a plastic
 * impulse and a restart where one closes); friction slips committed after every step. */
#include "voussoir/dynamic.h"
#include "voussoir/impact.h"

#include "voussoir/collide.h"
#include "voussoir/contact.h"

#include <ida/ida.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "voussoir/klu_reuse.h"
#include "voussoir/nvector_ops.h"
#include "wall_clock.h"

/* KLU ordering: AMD (0). The iteration matrix is a saddle-point matrix -- the constraint rows
 * have zero diagonals -- with a structurally symmetric pattern, which AMD orders for fill on
 * A + A^T; KLU's partial pivoting (threshold 0.001 by default) then takes the off-diagonal
 * pivots that the zero block needs. Natural ordering would pivot too but leaves the fill. */
static const int VS_DYN_KLU_ORDERING = 0;
/* Constraints: at most 3 per support (fixed: ux, uz, theta of the support body prescribed;
 * pinned: ux, uz only). */
enum { VS_DYN_NC = 6 };
/* BDF order cap. The joints' contact modes are stiff, lightly damped oscillators (k_n b t over a
 * voussoir's mass: ~1e4 rad/s); BDF of order 3-5 is unstable near the imaginary axis, so it would
 * need steps of 1/omega throughout. BDF1-2 are A-stable and damp those modes at large steps. */
static const int VS_DYN_MAX_ORDER = 2;
/* A velocity error is judged by the position error it makes over this time (s), about the period
 * of the contact modes: tighter velocity tolerances would make IDA resolve those vibrations. */
static const double VS_DYN_VEL_TIME = 1e-4;
/* Newton's convergence test up to the collapse criterion: IDA stops iterating when the estimated
 * error of the iterate is below this fraction of the error-test tolerance (IDA's default 0.33).
 * The energy balance is the integral of the work of the residual that Newton leaves in the
 * blocks' equations of motion -- along the motion dE/dt = W' - D' + v . r -- and that residual is
 * about (cj M + C) times the velocity tolerance, which is loose (VS_DYN_VEL_TIME): with 0.33 the
 * balance error reaches 6e-4 of the largest energy term in the fast motion before a collapse,
 * with 1e-3 it stays below 1e-4 for about twice the Newton iterations before the fall (IDA's
 * default again in the fall, which is only recorded). */
static const double VS_DYN_NEWTON_COEF = 1e-3;
static const double VS_DYN_NEWTON_COEF_FALL = 0.33;
/* After the collapse criterion the fall is integrated with tolerances this many times looser:
 * it is recorded to be looked at, not measured. */
static const double VS_DYN_FALL_TOL = 100.0;
/* ... and this many when the fall lands on the ground (contact.h): its impacts need more. On the
 * reference run (runs/reference.ini, fall to rest), 100x looser left the energy balance of the
 * fall at 9 % (6556 IDA steps), 10x at 0.56 % (11160 steps), 1x at 0.044 % (24924 steps). */
static const double VS_DYN_FALL_TOL_GROUND = 10.0;
/* The debris is at rest on the ground when its kinetic energy has stayed below rest_ke for
 * this long (s), or rest_time if shorter. rest_time (1 s by default) is the quasi-static path's
 * window, long enough for a slow mode of the arch to pass a turning point; the debris lies on
 * contact springs whose periods are below a millisecond (2 pi sqrt(m / (2 k_v)), 0.5 ms for the
 * reference's voussoirs), and a block still rocking or sliding keeps its kinetic energy above
 * the rest level but for instants at its turning points: 0.1 s is a hundred of those periods.
 * On the reference run the last second of the fall, at rest but for the window, took ~10 % of
 * its steps and ~30 % of its Jacobian evaluations. */
static const double VS_DYN_FALL_REST = 0.1;
/* Restarts after IDA's "root found at and very near t" (restart_roots) in one run at most. */
static const long VS_DYN_MAX_ROOT_RESTARTS = 1000;

struct vs_dynamic {
  vs_model *m;
  vs_dyn_opts o;
  int n;  /* 3 per block */
  int nq; /* the static state's length (vs_model_size): blocks, pinned supports' rotations */
  int ne; /* n + 6: blocks and supports */
  int nc; /* constraints */
  int cons[VS_DYN_NC]; /* constrained component (0..5, over the two supports) of each */
  int cidx[VS_DYN_NC]; /* ... and the constraint of each component, -1 if it is free */
  double *qst, *vst;   /* the static state (nq) handed to the callbacks */
  int iv, il, imu, ie; /* offsets of v, lambda, mu and the energy integrals in y */
  int N;  /* 2 ne + 2 nc + 3 */
  int nj; /* joints */
  SUNContext ctx;
  N_Vector y, yp, id, atol;
  SUNMatrix J, K, C;
  SUNLinearSolver LS;
  void *ida;
  double *mass, *work;    /* ne each */
  double *force;          /* ne: F(q, v) for the reported multipliers and accelerations */
  vs_joint_state *js;     /* the joints' states at the positions js_q (joint_states) */
  double *js_q;
  int js_valid;
  int *roots;
  int nroots;             /* before the fall: 2 nj + 2, then the impact model's (the
                             contacts' follow them once armed) */
  int root_impact;        /* offset of the impact model's roots in g and roots */
  vs_impact *imp;         /* the impact damping model, NULL unless o.impact */
  long jac_evals;
  double max_drift;       /* max |g| over the accepted steps, m */
  double rtol;            /* o.rtol scaled as the absolute tolerances (set_tolerances) */
  vs_contact *ct;         /* the ground (borrowed; NULL: none), vs_dynamic_set_contact */
  double ground_offset;   /* ... armed at the fall this far above the lower springing base, m */
  int in_fall;            /* after the collapse criterion: only the contacts' roots */
  vs_collide *cl;         /* contact between bodies without a joint (borrowed; NULL: none) */
  unsigned char *pairs, *pairs_klu; /* its broad phase now, and the one KLU last analysed */
  double *Kd, *Cd;        /* ne x ne dense work: the Jacobian's K and C with its coupling */
  int klu_pairs;          /* pairs_klu holds an analysed pattern */
  char msg[256];
};

static double delta_at(const vs_dynamic *d, double t) { return d->o.rate * t; }

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
  vs_model_support_states(d->m, delta_at(d, t), d->o.rate, qs, vs);
  for (int c = 0; c < d->nc; c++) {
    const int i = d->cons[c];
    if (g != NULL) g[c] = q[d->n + i] - qs[i];
    if (gv != NULL) gv[c] = v[d->n + i] - vs[i];
  }
}

static int stopped(const vs_dynamic *d) { return d->o.stop != NULL && *d->o.stop; }

void vs_dynamic_set_stop(vs_dynamic *d, const volatile sig_atomic_t *stop) { d->o.stop = stop; }

/* Root functions: the joints', the energy levels' and the impact model's (before the fall),
 * then the vertices' (the ground's, then the bodies'). */
static int n_ground_roots(const vs_dynamic *d) {
  return (d->ct != NULL && vs_contact_armed(d->ct)) ? vs_contact_count(d->ct) : 0;
}

static int n_roots(const vs_dynamic *d) {
  const int nb = (d->cl != NULL && vs_collide_armed(d->cl)) ? vs_collide_count(d->cl) : 0;
  return (d->in_fall ? 0 : d->nroots) + n_ground_roots(d) + nb;
}

static int root_fn(double t, N_Vector yy, N_Vector yp, double *g, void *user);

static int root_init(vs_dynamic *d) {
  const int nr = n_roots(d);
  return IDARootInit(d->ida, nr, nr > 0 ? root_fn : NULL);
}

vs_status vs_dynamic_set_contact(vs_dynamic *d, vs_contact *c, double offset, vs_error *err) {
  const int nr = d->nroots + (c != NULL ? vs_contact_count(c) : 0) +
                 (d->cl != NULL ? vs_collide_count(d->cl) : 0);
  int *roots = realloc(d->roots, (size_t)nr * sizeof *roots);
  if (roots == NULL) return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  d->roots = roots;
  d->ct = c;
  d->ground_offset = offset;
  return VS_OK;
}

vs_status vs_dynamic_set_collide(vs_dynamic *d, vs_collide *c, vs_error *err) {
  const int nr = d->nroots + (d->ct != NULL ? vs_contact_count(d->ct) : 0) +
                 (c != NULL ? vs_collide_count(c) : 0);
  const size_t ne = (size_t)d->ne, nb = (size_t)(c != NULL ? vs_collide_bodies(c) : 0);
  int *roots = realloc(d->roots, (size_t)nr * sizeof *roots);
  if (roots != NULL) d->roots = roots;
  free(d->pairs), free(d->pairs_klu), free(d->Kd), free(d->Cd);
  d->pairs = calloc(nb * nb + 1, 1), d->pairs_klu = calloc(nb * nb + 1, 1);
  d->Kd = calloc(ne * ne, sizeof *d->Kd), d->Cd = calloc(ne * ne, sizeof *d->Cd);
  if (roots == NULL || d->pairs == NULL || d->pairs_klu == NULL || d->Kd == NULL ||
      d->Cd == NULL)
    return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  d->cl = c;
  d->klu_pairs = 0;
  return VS_OK;
}

/* A raised stop flag is fatal (-1): IDA returns at once. */
static int res_fn(double t, N_Vector yy, N_Vector yp, N_Vector rr, void *user) {
  vs_dynamic *d = user;
  if (stopped(d)) return -1;
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

/* J = dF/dy + cj dF/dy', rows and columns in the order of y:
 *   q rows:  [cj I, -I, 0, -G^T],  v rows: [K, cj M + C, -G^T, 0],
 *   lambda rows: [G, 0, 0, 0],     mu rows: [0, G, 0, 0],
 * and cj on the bookkeeping diagonal (their dependence on the state is left out: nothing
 * depends on them, so Newton still converges). G is constant and G^T mu, G^T lambda are
 * linear, so there are no constraint Hessian terms. The dependence of the damping forces on the
 * positions is left out too (IDA's Newton is a modified Newton already). */
/* The Jacobian with the bodies' contacts (collide.h) armed: K and C (the joints', the ground's,
 * the contacts') gathered dense, the pattern the joints' plus a 3x3 block for every pair of
 * bodies of the broad phase at y. When those pairs differ from the ones KLU analysed, its
 * analysis is redone (SUNKLU_REINIT_PARTIAL: the next factorisation is a fresh one): jac_fn is
 * called by IDA's linear solver setup, right before that factorisation. */
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

static int jac_fn(double t, double cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix Jac,
                  void *user, N_Vector t1, N_Vector t2, N_Vector t3) {
  (void)t;
  (void)yp;
  (void)rr;
  (void)t1;
  (void)t2;
  if (stopped(user)) return -1;
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

/* Roots: for every joint, its intrados and extrados edge openings minus the hinge threshold;
 * then the kinetic energy minus the collapse threshold, and minus the rest level (the departure
 * of a motion: where it rises through it). */
/* The joints' states at the positions of y into d->js, evaluated once per state: the root
 * function at the end of a step, the commit, the energies and the impact model's arming share
 * one evaluation. A commit at y leaves them valid: the return-mapped states are its own. */
static void joint_states(vs_dynamic *d, const double *y) {
  const size_t bytes = (size_t)d->ne * sizeof *y;
  if (d->js_valid && memcmp(d->js_q, y, bytes) == 0) return;
  vs_model_ext_joint_states(d->m, y, d->js);
  memcpy(d->js_q, y, bytes);
  d->js_valid = 1;
}

static int root_fn(double t, N_Vector yy, N_Vector yp, double *g, void *user) {
  (void)yp;
  (void)t;
  vs_dynamic *d = user;
  const double *q = N_VGetArrayPointer(yy);
  const int r0 = d->in_fall ? 0 : d->nroots;
  if (d->ct != NULL && vs_contact_armed(d->ct)) /* then a vertex crossing the ground */
    vs_contact_roots(d->ct, q, g + r0);
  if (d->cl != NULL && vs_collide_armed(d->cl)) /* then one entering another body */
    vs_collide_roots(d->cl, q, g + r0 + n_ground_roots(d));
  if (d->in_fall) return 0;
  joint_states(d, q);
  for (int k = 0; k < d->nj; k++) {
    g[2 * k] = d->js[k].gap_i - d->o.open;
    g[2 * k + 1] = d->js[k].gap_e - d->o.open;
  }
  const double ke = vs_model_kinetic_energy(d->m, q + d->iv);
  g[2 * d->nj] = ke - d->o.collapse_ke;
  g[2 * d->nj + 1] = ke - d->o.rest_ke;
  if (d->imp != NULL) vs_impact_roots(d->imp, d->js, g + d->root_impact);
  return 0;
}

static void ida_err(int code, const char *module, const char *function, char *msg, void *user) {
  vs_dynamic *d = user;
  (void)code;
  snprintf(d->msg, sizeof d->msg, "%s/%s: %s", module, function, msg);
}

void vs_dynamic_destroy(vs_dynamic **dp) {
  if (dp == NULL || *dp == NULL) return;
  vs_dynamic *d = *dp;
  if (d->ida != NULL) IDAFree(&d->ida);
  if (d->LS != NULL) SUNLinSolFree(d->LS);
  if (d->J != NULL) SUNMatDestroy(d->J);
  if (d->K != NULL) SUNMatDestroy(d->K);
  if (d->C != NULL) SUNMatDestroy(d->C);
  if (d->y != NULL) N_VDestroy(d->y);
  if (d->yp != NULL) N_VDestroy(d->yp);
  if (d->id != NULL) N_VDestroy(d->id);
  if (d->atol != NULL) N_VDestroy(d->atol);
  if (d->ctx != NULL) SUNContext_Free(&d->ctx);
  free(d->mass);
  free(d->work);
  free(d->force);
  free(d->js);
  free(d->js_q);
  free(d->roots);
  free(d->pairs);
  free(d->pairs_klu);
  free(d->Kd);
  free(d->Cd);
  vs_impact_destroy(&d->imp);
  free(d->qst);
  free(d->vst);
  free(d);
  *dp = NULL;
}

static vs_status dyn_fail(vs_dynamic **d, vs_error *err, const char *what, int flag) {
  vs_dynamic_destroy(d);
  return vs_error_set(err, VS_ERR_SOLVER, "dynamic solver setup: %s failed (flag %d)", what, flag);
}

/* Absolute tolerances: positions atol_q (rotations atol_q / joint length; the supports' as the
 * last block's), velocities the same over
 * VS_DYN_VEL_TIME, mu as velocities, the energy bookkeeping the weight times atol_q. lambda
 * (out of the error test: its tolerance only ends Newton's iterations) gets the force that the
 * stiffest support joint makes of a position error atol_q, k_n b t atol_q (moments: times the
 * joint length): the positions are resolved to atol_q, so the reactions cannot be resolved
 * more finely, and a tighter tolerance makes Newton fail at contact changes. */
static void set_tolerances(vs_dynamic *d, double *at) {
  const int n = d->n, ne = d->ne;
  const double tv = VS_DYN_VEL_TIME, aq = d->o.atol_q;
  double *scale = d->work;
  vs_model_residual_scale(d->m, scale);
  double wsum = 0.0, len = 0.0, kmax = 0.0;
  const vs_geometry *g = vs_model_geometry(d->m);
  for (int k = 0; k < g->n_joints; k++)
    if (g->joints[k].a < 0 || g->joints[k].b < 0)
      kmax = fmax(kmax, vs_model_law(d->m)->kn * g->joints[k].depth * g->joints[k].length);
  for (int i = 0; i < n; i += 3) {
    len = scale[i + 2] / scale[i];
    at[i] = at[i + 1] = aq;
    at[ne + i] = at[ne + i + 1] = aq / tv;
    at[i + 2] = aq / len;
    at[ne + i + 2] = aq / len / tv;
    wsum += scale[i];
  }
  for (int i = n; i < ne; i += 3) {
    at[i] = at[i + 1] = aq;
    at[i + 2] = aq / len;
    at[ne + i] = at[ne + i + 1] = aq / tv;
    at[ne + i + 2] = aq / len / tv;
  }
  for (int c = 0; c < d->nc; c++) {
    at[d->il + c] = kmax * aq * (d->cons[c] % 3 == 2 ? len : 1.0);
    at[d->imu + c] = at[ne + n + d->cons[c]];
  }
  for (int i = d->ie; i < d->N; i++) at[i] = wsum * aq;
  /* IDA's error norm is a WRMS norm divided by the full length N, masked components included.
   * The supports' states and the multipliers carry no truncation error of their own (the
   * constraints fix them), so the tolerances are scaled by sqrt(N_arch / N), N_arch = 2n + 3:
   * the test on the arch's components is then the one the user's rtol and atol ask for. */
  const double sc = sqrt((double)(2 * n + 3) / d->N);
  for (int i = 0; i < d->N; i++) at[i] *= sc;
  d->rtol = d->o.rtol * sc;
}

vs_status vs_dynamic_create(vs_model *m, const vs_dyn_opts *o, vs_dynamic **out, vs_error *err) {
  *out = NULL;
  if (!(o->rate > 0.0) || !(o->rtol > 0.0) || !(o->atol_q > 0.0) || !(o->open > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "dynamic: rate %g m/s, rtol %g, atol %g m, open %g m (allowed: all > 0)",
                        o->rate, o->rtol, o->atol_q, o->open);
  vs_dynamic *d = calloc(1, sizeof *d);
  if (d == NULL) return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  d->m = m;
  d->o = *o;
  d->n = 3 * vs_model_geometry(m)->n_blocks;
  d->nq = vs_model_size(m);
  d->ne = vs_model_ext_size(m);
  for (int i = 0; i < VS_DYN_NC; i++) {
    const int free_rot = i % 3 == 2 && vs_model_support_kind(m, i / 3) == VS_SUPPORT_PINNED;
    d->cidx[i] = free_rot ? -1 : d->nc;
    if (!free_rot) d->cons[d->nc++] = i;
  }
  d->iv = d->ne;
  d->il = 2 * d->ne;
  d->imu = d->il + d->nc;
  d->ie = d->imu + d->nc;
  d->N = d->ie + 3;
  d->nj = vs_model_geometry(m)->n_joints;
  const int ne = d->ne, nnzK = vs_model_ext_nnz(m);
  int flag = SUNContext_Create(NULL, &d->ctx);
  if (flag != 0) return dyn_fail(&d, err, "SUNContext_Create", flag);
  d->y = N_VNew_Serial(d->N, d->ctx);
  d->yp = N_VNew_Serial(d->N, d->ctx);
  d->id = N_VNew_Serial(d->N, d->ctx);
  d->atol = N_VNew_Serial(d->N, d->ctx);
  d->J = SUNSparseMatrix(d->N, d->N, 2 * ne + 2 * nnzK + 4 * d->nc + 3, CSC_MAT, d->ctx);
  d->K = SUNSparseMatrix(ne, ne, nnzK, CSC_MAT, d->ctx);
  d->C = SUNSparseMatrix(ne, ne, nnzK, CSC_MAT, d->ctx);
  d->mass = malloc((size_t)ne * sizeof *d->mass);
  d->work = malloc((size_t)ne * sizeof *d->work);
  d->force = malloc((size_t)ne * sizeof *d->force);
  d->js = malloc((size_t)d->nj * sizeof *d->js);
  d->js_q = malloc((size_t)ne * sizeof *d->js_q);
  d->qst = malloc((size_t)d->nq * sizeof *d->qst);
  d->vst = malloc((size_t)d->nq * sizeof *d->vst);
  d->nroots = 2 * d->nj + 2;
  d->root_impact = d->nroots;
  if (o->impact && (d->imp = vs_impact_create(m, o->open)) != NULL)
    d->nroots += vs_impact_nroots(d->imp);
  d->roots = malloc((size_t)d->nroots * sizeof *d->roots);
  if (d->y == NULL || d->yp == NULL || d->id == NULL || d->atol == NULL || d->J == NULL ||
      d->K == NULL || d->C == NULL || d->mass == NULL || d->work == NULL || d->force == NULL ||
      d->js == NULL || d->js_q == NULL || d->roots == NULL || d->qst == NULL || d->vst == NULL ||
      (o->impact && d->imp == NULL)) {
    vs_dynamic_destroy(&d);
    return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  }
  /* IDA clones its workspace from y: every vector of the integration gets the optimised
   * operations */
  N_Vector vecs[] = {d->y, d->yp, d->id, d->atol};
  for (size_t i = 0; i < sizeof vecs / sizeof vecs[0]; i++) vs_nvector_fast_ops(vecs[i]);
  vs_model_ext_mass(m, d->mass);
  set_tolerances(d, N_VGetArrayPointer(d->atol));
  /* differential: q, v and the energy integrals; algebraic: lambda and mu */
  N_VConst(1.0, d->id);
  double *id = N_VGetArrayPointer(d->id);
  for (int i = d->il; i < d->ie; i++) id[i] = 0.0;
  d->LS = SUNLinSol_KLU(d->y, d->J, d->ctx);
  if (d->LS == NULL) return dyn_fail(&d, err, "SUNLinSol_KLU", 0);
  if ((flag = SUNLinSol_KLUSetOrdering(d->LS, VS_DYN_KLU_ORDERING)) != 0)
    return dyn_fail(&d, err, "SUNLinSol_KLUSetOrdering", flag);
  vs_klu_keep_analysis(d->LS); /* one analysis for every restart (IDAReInit) */
  vs_sparse_zero_none(d->J); /* jac_fn writes the pattern */
  d->ida = IDACreate(d->ctx);
  if (d->ida == NULL) return dyn_fail(&d, err, "IDACreate", 0);
  N_VConst(0.0, d->y);
  N_VConst(0.0, d->yp);
  if ((flag = IDAInit(d->ida, res_fn, 0.0, d->y, d->yp)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDAInit", flag);
  if ((flag = IDASetUserData(d->ida, d)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetUserData", flag);
  if ((flag = IDASetErrHandlerFn(d->ida, ida_err, d)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetErrHandlerFn", flag);
  if ((flag = IDASVtolerances(d->ida, d->rtol, d->atol)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASVtolerances", flag);
  if ((flag = IDASetId(d->ida, d->id)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetId", flag);
  if ((flag = IDASetSuppressAlg(d->ida, SUNTRUE)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetSuppressAlg", flag);
  if ((flag = IDASetLinearSolver(d->ida, d->LS, d->J)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetLinearSolver", flag);
  if ((flag = IDASetJacFn(d->ida, jac_fn)) != IDA_SUCCESS) return dyn_fail(&d, err, "IDASetJacFn", flag);
  if ((flag = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetNonlinConvCoef", flag);
  if ((flag = IDASetMaxOrd(d->ida, VS_DYN_MAX_ORDER)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetMaxOrd", flag);
  if ((flag = IDASetMaxNumSteps(d->ida, 100000)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetMaxNumSteps", flag);
  if ((flag = IDARootInit(d->ida, d->nroots, root_fn)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDARootInit", flag);
  if ((flag = IDASetNoInactiveRootWarn(d->ida)) != IDA_SUCCESS)
    return dyn_fail(&d, err, "IDASetNoInactiveRootWarn", flag);
  *out = d;
  return VS_OK;
}

/* Energies at the current state; balance relative to e0 (the total at the phase's start). */
static void energies(vs_dynamic *d, const double *y, double e0, vs_energy *e) {
  e->kinetic = vs_model_kinetic_energy(d->m, y + d->iv);
  for (int i = 0; i < VS_DYN_NC; i++) /* a pinned support's rotation: its own kinetic energy */
    if (d->cidx[i] < 0) e->kinetic += 0.5 * d->mass[d->n + i] * y[d->iv + d->n + i] * y[d->iv + d->n + i];
  joint_states(d, y);
  e->elastic = 0.0;
  for (int k = 0; k < d->nj; k++) e->elastic += d->js[k].energy;
  e->gravity = vs_model_gravity_energy(d->m, y);
  if (d->ct != NULL) e->elastic += vs_contact_energy(d->ct, y);
  if (d->cl != NULL) e->elastic += vs_collide_energy(d->cl, y);
  e->support_work = y[d->ie];
  e->damped = y[d->ie + 1];
  e->friction = y[d->ie + 2];
  e->balance = e->kinetic + e->gravity + e->elastic - e->support_work + e->damped + e->friction - e0;
}

/* Constraint drift max |g| at the current state (m for the translations, rad for the
 * rotations: both stay at round-off). */
static double drift(const vs_dynamic *d, double t, const double *y) {
  double g[VS_DYN_NC], worst = 0.0;
  constraints(d, t, y, y + d->iv, g, NULL);
  for (int c = 0; c < d->nc; c++) worst = fmax(worst, fabs(g[c]));
  return worst;
}

int vs_dynamic_size(const vs_dynamic *d) { return d->N; }
int vs_dynamic_nnz(const vs_dynamic *d) { return (int)SUNSparseMatrix_NNZ(d->J); }

void vs_dynamic_layout(const vs_dynamic *d, int *iv, int *il, int *imu, int *ie) {
  *iv = d->iv;
  *il = d->il;
  *imu = d->imu;
  *ie = d->ie;
}

void vs_dynamic_residual(vs_dynamic *d, double t, double *y, double *yp, double *r) {
  N_Vector vy = N_VMake_Serial(d->N, y, d->ctx), vp = N_VMake_Serial(d->N, yp, d->ctx);
  N_Vector vr = N_VMake_Serial(d->N, r, d->ctx);
  if (vy != NULL && vp != NULL && vr != NULL) res_fn(t, vy, vp, vr, d);
  N_VDestroy(vy);
  N_VDestroy(vp);
  N_VDestroy(vr);
}

void vs_dynamic_jacobian(vs_dynamic *d, double t, double cj, double *y, SUNMatrix J) {
  N_Vector vy = N_VMake_Serial(d->N, y, d->ctx);
  if (vy != NULL) jac_fn(t, cj, vy, NULL, NULL, J, d, NULL, NULL, NULL);
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

const vs_joint_state *vs_dynamic_joint_states(vs_dynamic *d) {
  joint_states(d, N_VGetArrayPointer(d->y));
  return d->js;
}

void vs_dynamic_multipliers(const vs_dynamic *d, double out[6]) {
  const double *lam = N_VGetArrayPointer(d->y) + d->il;
  for (int i = 0; i < VS_DYN_NC; i++) out[i] = d->cidx[i] >= 0 ? lam[d->cidx[i]] : 0.0;
}

void vs_dynamic_derivatives(const vs_dynamic *d, double *a) {
  memcpy(a, N_VGetArrayPointer(d->yp) + d->iv, (size_t)d->n * sizeof *a);
}

/* The static state (blocks, pinned supports' rotations) of y into d->qst, d->vst. */
static void static_state(vs_dynamic *d, const double *y) {
  memcpy(d->qst, y, (size_t)d->n * sizeof *d->qst);
  memcpy(d->vst, y + d->iv, (size_t)d->n * sizeof *d->vst);
  for (int s = 0; s < 2; s++) {
    const int k = vs_model_support_dof(d->m, s);
    if (k < 0) continue;
    d->qst[k] = y[d->n + 3 * s + 2];
    d->vst[k] = y[d->iv + d->n + 3 * s + 2];
  }
}

/* IDA stops with "root found at and very near t" when a root function is exactly zero at the
 * root it just returned and a round-off later (a vertex crossing the ground at a crawl: its
 * height is resolved to ~1e-17 m). A restart from the returned state clears it: IDA's first-step
 * check then leaves such roots inactive until they move away from zero. */
static int close_roots(const vs_dynamic *d, int flag) {
  return flag == IDA_ILL_INPUT && strstr(d->msg, "very near") != NULL;
}

static int restart_roots(vs_dynamic *d, double t, double t_stop) {
  d->msg[0] = '\0';
  int rf = IDAReInit(d->ida, t, d->y, d->yp);
  if (rf == IDA_SUCCESS) rf = root_init(d);
  if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
  return rf;
}

/* --- the impact damping model (impact.h): arming after each step, impulses at its roots --- */

/* Arm the edges that have opened (every accepted step; at the start with reset). */
static void impact_arm(vs_dynamic *d, const double *y, int reset) {
  joint_states(d, y);
  if (reset) vs_impact_reset(d->imp, d->js);
  else vs_impact_arm(d->imp, d->js);
}

/* The impacts among the roots just found: plastic impulses on the velocities, their energy loss
 * into the damped energy (positions unchanged, so the balance holds), then IDA restarted from
 * the new velocities with consistent multipliers and derivatives (IDAReInit + IDACalcIC; IDA's
 * counters carried in *bs, *bn). Returns the impacts, or -1 (message in d->msg) if the restart
 * failed. */
static int impact_resolve(vs_dynamic *d, double t, double t_stop, long *bs, long *bn) {
  double *y = N_VGetArrayPointer(d->y);
  int count = 0;
  const double lost = vs_impact_resolve(d->imp, y, y + d->iv, d->roots + d->root_impact, &count);
  if (count == 0) return 0;
  y[d->ie + 1] += lost;
  long ns = 0, nn = 0;
  IDAGetNumSteps(d->ida, &ns);
  IDAGetNumNonlinSolvIters(d->ida, &nn);
  *bs += ns;
  *bn += nn;
  int flag = IDAReInit(d->ida, t, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t + VS_DYN_VEL_TIME);
  if (flag == IDA_SUCCESS) flag = IDAGetConsistentIC(d->ida, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDASetStopTime(d->ida, t_stop);
  if (flag == IDA_SUCCESS) return count;
  char cause[160];
  snprintf(cause, sizeof cause, "%.159s", d->msg);
  snprintf(d->msg, sizeof d->msg, "IDA restart after an impact failed (flag %d): %.159s", flag, cause);
  return -1;
}

vs_status vs_dynamic_run(vs_dynamic *d, double t0, double *q, double *v, vs_dyn_sample_fn sample,
                         vs_dyn_event_fn event, void *user, vs_dyn_result *res, vs_error *err) {
  const int n = d->n;
  memset(res, 0, sizeof *res);
  res->t_collapse = NAN;
  res->fall_failed_t = NAN;
  res->dae_differential = d->N - 2 * d->nc;
  res->dae_algebraic = 2 * d->nc;
  res->dae_index = 2;
  d->max_drift = 0.0;
  d->js_valid = 0; /* the slips may have moved since (the quasi-static path) */
  double *y = N_VGetArrayPointer(d->y);
  N_VConst(0.0, d->y);
  memcpy(y, q, (size_t)n * sizeof *y);
  memcpy(y + d->iv, v, (size_t)n * sizeof *y);
  vs_model_support_states(d->m, delta_at(d, t0), d->o.rate, y + n, y + d->iv + n);
  for (int s = 0; s < 2; s++) { /* a pinned support's rotation: the static state's */
    const int k = vs_model_support_dof(d->m, s);
    if (k < 0) continue;
    y[n + 3 * s + 2] = q[k];
    y[d->iv + n + 3 * s + 2] = v[k];
  }
  N_VConst(0.0, d->yp);
  d->msg[0] = '\0';
  int flag = IDAReInit(d->ida, t0, d->y, d->yp);
  if (flag == IDA_SUCCESS) flag = IDASVtolerances(d->ida, d->rtol, d->atol);
  d->in_fall = 0;
  if (flag == IDA_SUCCESS) flag = root_init(d);
  if (flag == IDA_SUCCESS) flag = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF);
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDAReInit failed (flag %d)", flag);
  /* consistent initial values: q, v given (the supports' from the constraints), v' from the
   * equations of motion, lambda and mu (algebraic) solved for: IDA_YA_YDP_INIT */
  const double t_end = d->o.max_delta / d->o.rate;
  if (t_end <= t0) {
    res->end = VS_DYN_MAX_DELTA;
    res->t_end = t0;
    res->delta_end = delta_at(d, t0);
    return VS_OK;
  }
  flag = IDACalcIC(d->ida, IDA_YA_YDP_INIT, t0 + 1e-6 * (t_end - t0));
  if (flag != IDA_SUCCESS && stopped(d)) return vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
  if (flag != IDA_SUCCESS)
    return vs_error_set(err, VS_ERR_SOLVER, "IDACalcIC failed (flag %d): %s", flag, d->msg);
  IDAGetConsistentIC(d->ida, d->y, d->yp);
  IDASetStopTime(d->ida, t_end);
  if (d->imp != NULL) impact_arm(d, y, 1);
  vs_energy e;
  energies(d, y, 0.0, &e);
  const double e0 = e.kinetic + e.gravity + e.elastic;
  double scale = fabs(e0), t = t0, t_last_sample = -INFINITY, t_rest = t0, t_stop = t_end;
  int moving = 0, collapsed = 0;
  double wall_fall = NAN; /* wall-clock time at the collapse criterion */
  long restarts = 0;      /* restart_roots so far */
  long base_steps = 0, base_newton = 0;
  vs_status st = VS_OK;
  e.balance = 0.0; /* the reference of the balance */
  if (sample != NULL && (static_state(d, y), sample(user, t0, delta_at(d, t0), d->qst, d->vst, &e)) != 0)
    return vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  t_last_sample = t0;
  res->t_motion = t0;
  res->delta_motion = delta_at(d, t0);
  for (long step = 0;; step++) {
    if (stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (step >= VS_DYN_MAX_STEPS) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA took %ld steps (the limit) and reached t = %.6g s "
                        "(delta = %.6g mm) of %.6g s", VS_DYN_MAX_STEPS, t, delta_at(d, t) * 1e3,
                        t_stop);
      break;
    }
    flag = IDASolve(d->ida, t_stop, &t, d->y, d->yp, IDA_ONE_STEP);
    if (flag < 0 && stopped(d)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    if (flag < 0 && close_roots(d, flag) && ++restarts <= VS_DYN_MAX_ROOT_RESTARTS) {
      long ns = 0, nn = 0; /* IDAReInit resets IDA's counters: carry them */
      IDAGetNumSteps(d->ida, &ns);
      IDAGetNumNonlinSolvIters(d->ida, &nn);
      base_steps += ns;
      base_newton += nn;
      const int rf = restart_roots(d, t, t_stop);
      if (rf == IDA_SUCCESS) continue;
      flag = rf;
    }
    if (flag < 0 && collapsed) { /* the collapse stands: the fall ends here, said so */
      res->end = VS_DYN_COLLAPSED;
      res->fall_failed_t = t;
      snprintf(res->fall_failure, sizeof res->fall_failure, "%s",
               d->msg[0] ? d->msg : "unknown cause");
      break;
    }
    if (flag < 0) {
      st = vs_error_set(err, VS_ERR_SOLVER, "IDA failed at t = %.6g s (delta = %.6g mm): %s", t,
                        delta_at(d, t) * 1e3, d->msg[0] ? d->msg : "unknown cause");
      break;
    }
    const double delta = delta_at(d, t);
    joint_states(d, y);
    vs_model_commit_states(d->m, d->js); /* seamless: the return-mapped force is unchanged */
    if (d->imp != NULL) impact_arm(d, y, 0);
    if (d->ct != NULL && vs_contact_armed(d->ct)) {
      vs_contact_commit(d->ct, y);
      res->max_penetration = fmax(res->max_penetration, vs_contact_max_penetration(d->ct, y, NULL));
    }
    if (d->cl != NULL && vs_collide_armed(d->cl)) {
      vs_collide_commit(d->cl, y);
      res->max_overlap = fmax(res->max_overlap, vs_collide_max_penetration(d->cl, y));
    }
    energies(d, y, e0, &e);
    d->max_drift = fmax(d->max_drift, drift(d, t, y));
    scale = fmax(scale, fmax(fabs(e.kinetic), fmax(fabs(e.gravity), fabs(e.elastic))));
    scale = fmax(scale, fmax(fabs(e.support_work), fabs(e.damped)));
    if (!collapsed) res->balance_error_rel = fmax(res->balance_error_rel, fabs(e.balance) / scale);
    else res->balance_error_fall = fmax(res->balance_error_fall, fabs(e.balance) / scale);
    res->max_kinetic = fmax(res->max_kinetic, e.kinetic);
    /* motion episodes: moving while the kinetic energy is above rest_ke; at rest once it has
     * stayed below for rest_time (a single mode passes through zero at its turning points) */
    if (e.kinetic >= d->o.rest_ke) {
      moving = 1;
      t_rest = t;
    } else {
      moving = 0;
    }
    const double window = collapsed && d->ct != NULL ? fmin(d->o.rest_time, VS_DYN_FALL_REST)
                                                     : d->o.rest_time;
    const int at_rest = !moving && t - t_rest >= window;
    int stop = 0;
    const int joint_root = flag == IDA_ROOT_RETURN && !collapsed; /* the fall's: contacts only */
    if (flag == IDA_ROOT_RETURN) {
      IDAGetRootInfo(d->ida, d->roots);
      res->root_events++;
      for (int k = 0; k < 2 * d->nj && joint_root; k++) {
        if (d->roots[k] == 0 || event == NULL) continue;
        vs_dyn_event ev = {.t = t, .delta = delta, .joint = k / 2 + 1,
                           .side = (k % 2 == 0) ? 'E' : 'I', .opened = d->roots[k] > 0};
        static_state(d, y);
        if (event(user, &ev, d->qst) != 0) stop = 1;
      }
      if (d->imp != NULL && !collapsed) { /* impacts: velocities jump, the energy is charged */
        const int ni = impact_resolve(d, t, t_stop, &base_steps, &base_newton);
        if (ni < 0) {
          st = stopped(d) ? vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted")
                          : vs_error_set(err, VS_ERR_SOLVER, "at t = %.6g s: %s", t, d->msg);
          break;
        }
        res->impacts += ni;
        energies(d, y, e0, &e);
      }
      if (d->roots[2 * d->nj + 1] > 0 && !collapsed) { /* a departure, located */
        res->t_motion = t;
        res->delta_motion = delta;
        res->onset_found = 1;
      }
      if (d->roots[2 * d->nj] > 0 && !collapsed) {
        collapsed = 1;
        res->t_collapse = t;
        t_stop = fmin(t_end, t + d->o.fall_time);
        /* the fall is followed for the record only: restart from here without events and
         * with looser tolerances (set on a restarted integrator: IDA re-reads them then) */
        long ns = 0, nn = 0; /* IDAReInit resets IDA's counters: carry the phase's */
        IDAGetNumSteps(d->ida, &ns);
        IDAGetNumNonlinSolvIters(d->ida, &nn);
        base_steps += ns;
        base_newton += nn;
        N_Vector at = N_VClone(d->atol);
        int rf = (at == NULL) ? -1 : IDAReInit(d->ida, t, d->y, d->yp);
        const double loose = d->ct != NULL ? VS_DYN_FALL_TOL_GROUND : VS_DYN_FALL_TOL;
        if (rf == IDA_SUCCESS) {
          N_VScale(loose, d->atol, at);
          rf = IDASVtolerances(d->ida, loose * d->rtol, at);
        }
        d->in_fall = 1;
        wall_fall = vs_wall_now();
        if (d->ct != NULL && !vs_contact_armed(d->ct))
          vs_contact_arm(d->ct, vs_contact_springing_base(d->m, y) + d->ground_offset, y);
        if (d->cl != NULL && !vs_collide_armed(d->cl)) vs_collide_arm(d->cl, y);
        if (rf == IDA_SUCCESS) rf = root_init(d);
        if (rf == IDA_SUCCESS) rf = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF_FALL);
        if (rf == IDA_SUCCESS) rf = IDASetStopTime(d->ida, t_stop);
        if (at != NULL) N_VDestroy(at);
        if (rf != IDA_SUCCESS) {
          st = vs_error_set(err, VS_ERR_SOLVER, "IDA restart for the fall failed (flag %d)", rf);
          break;
        }
      }
    }
    if (sample != NULL && (t - t_last_sample >= d->o.sample_dt || joint_root)) {
      t_last_sample = t;
      IDAGetNumSteps(d->ida, &res->steps); /* kept current for the callback */
      IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
      res->steps += base_steps;
      res->newton_iterations += base_newton;
      static_state(d, y);
      if (sample(user, t, delta, d->qst, d->vst, &e) != 0) stop = 1;
    }
    if (stop) {
      st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
      break;
    }
    if (collapsed && d->ct != NULL && at_rest) { /* the debris at rest on the ground */
      res->end = VS_DYN_COLLAPSED;
      res->fall_at_rest = 1;
      break;
    }
    if (collapsed && t >= t_stop * (1.0 - 1e-15)) {
      res->end = VS_DYN_COLLAPSED;
      break;
    }
    if (flag == IDA_TSTOP_RETURN || t >= t_end) {
      res->end = collapsed ? VS_DYN_COLLAPSED : VS_DYN_MAX_DELTA;
      break;
    }
    if (d->o.settle && !collapsed && at_rest) {
      res->end = VS_DYN_SETTLED;
      break;
    }
  }
  res->t_end = t;
  res->delta_end = delta_at(d, t);
  if (collapsed) res->fall_wall_s = vs_wall_now() - wall_fall;
  IDAGetNumSteps(d->ida, &res->steps);
  IDAGetNumNonlinSolvIters(d->ida, &res->newton_iterations);
  res->steps += base_steps;
  res->newton_iterations += base_newton;
  if (st == VS_OK && sample != NULL && t > t_last_sample &&
      (static_state(d, y), sample(user, t, res->delta_end, d->qst, d->vst, &e)) != 0)
    st = vs_error_set(err, VS_ERR_INTERNAL, "stopped by caller");
  res->jac_evals = d->jac_evals;
  res->e_end = e;
  static_state(d, y);
  memcpy(q, d->qst, (size_t)d->nq * sizeof *q);
  memcpy(v, d->vst, (size_t)d->nq * sizeof *v);
  res->max_drift = d->max_drift;
  return st;
}
