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
 * impulse and a restart where one closes); friction slips committed after every step.
 * This file: the object, its tolerances and IDA's set-up (the equations in dynamic_residual.c,
 * the roots and restarts in dynamic_events.c, the integration in dynamic_run.c). */
#include "voussoir/dynamic.h"

#include <ida/ida.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "dynamic_internal.h"
#include "klu_reuse.h"
#include "nvector_ops.h"

/* KLU ordering: AMD (0). The iteration matrix is a saddle-point matrix -- the constraint rows
 * have zero diagonals -- with a structurally symmetric pattern, which AMD orders for fill on
 * A + A^T; KLU's partial pivoting (threshold 0.001 by default) then takes the off-diagonal
 * pivots that the zero block needs. Natural ordering would pivot too but leaves the fill. */
static const int VS_DYN_KLU_ORDERING = 0;
/* BDF order cap. The joints' contact modes are stiff, lightly damped oscillators (k_n b t over a
 * voussoir's mass: ~1e4 rad/s); BDF of order 3-5 is unstable near the imaginary axis, so it would
 * need steps of 1/omega throughout. BDF1-2 are A-stable and damp those modes at large steps. */
static const int VS_DYN_MAX_ORDER = 2;

void vs_dynamic_set_ring_window(vs_dynamic *d, double window_s) {
  d->o.ring_window = window_s > 0.0 ? window_s : 0.0;
}

void vs_dynamic_set_stop(vs_dynamic *d, const volatile sig_atomic_t *stop) { d->o.stop = stop; }

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

/* The error of a set-up call that failed (its name, its flag); the caller destroys the object. */
static vs_status setup_fail(vs_error *err, const char *what, int flag) {
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

/* The sizes and the layout of y for model m: the supports' constrained components (a pinned
 * support's rotation is free), the offsets of v, lambda, mu and the energy integrals. */
static void set_layout(vs_dynamic *d, vs_model *m) {
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
}

/* The vectors, matrices and work arrays, and the impact model (o->impact) with its roots:
 * VS_ERR_NOMEM when one could not be had. */
static vs_status alloc_work(vs_dynamic *d, const vs_dyn_opts *o, vs_error *err) {
  const int ne = d->ne, nnzK = vs_model_ext_nnz(d->m);
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
  if (o->impact && (d->imp = vs_impact_create(d->m, o->open)) != NULL)
    d->nroots += vs_impact_nroots(d->imp);
  d->roots = malloc((size_t)d->nroots * sizeof *d->roots);
  if (d->y == NULL || d->yp == NULL || d->id == NULL || d->atol == NULL || d->J == NULL ||
      d->K == NULL || d->C == NULL || d->mass == NULL || d->work == NULL || d->force == NULL ||
      d->js == NULL || d->js_q == NULL || d->roots == NULL || d->qst == NULL || d->vst == NULL ||
      (o->impact && d->imp == NULL))
    return vs_error_set(err, VS_ERR_NOMEM, "dynamic: out of memory");
  return VS_OK;
}

/* The vectors' operations, the masses, the absolute tolerances and which components are
 * differential. */
static void init_vectors(vs_dynamic *d) {
  /* IDA clones its workspace from y: every vector of the integration gets the optimised
   * operations */
  N_Vector vecs[] = {d->y, d->yp, d->id, d->atol};
  for (size_t i = 0; i < sizeof vecs / sizeof vecs[0]; i++) vs_nvector_fast_ops(vecs[i]);
  vs_model_ext_mass(d->m, d->mass);
  set_tolerances(d, N_VGetArrayPointer(d->atol));
  /* differential: q, v and the energy integrals; algebraic: lambda and mu */
  N_VConst(1.0, d->id);
  double *id = N_VGetArrayPointer(d->id);
  for (int i = d->il; i < d->ie; i++) id[i] = 0.0;
}

/* KLU on J, its analysis kept for every restart; VS_ERR_SOLVER naming the call that failed. */
static vs_status setup_klu(vs_dynamic *d, vs_error *err) {
  int flag;
  d->LS = SUNLinSol_KLU(d->y, d->J, d->ctx);
  if (d->LS == NULL) return setup_fail(err, "SUNLinSol_KLU", 0);
  if ((flag = SUNLinSol_KLUSetOrdering(d->LS, VS_DYN_KLU_ORDERING)) != 0)
    return setup_fail(err, "SUNLinSol_KLUSetOrdering", flag);
  SUNLinSol_KLUGetCommon(d->LS)->scale = VS_DYN_KLU_SCALE;
  vs_klu_keep_analysis(d->LS); /* one analysis for every restart (IDAReInit) */
  vs_sparse_zero_none(d->J); /* vs_dyn_jacobian writes the pattern */
  return VS_OK;
}

/* IDA with the residual, the Jacobian, the roots and every option; VS_ERR_SOLVER naming the
 * call that failed. */
static vs_status setup_ida(vs_dynamic *d, vs_error *err) {
  int flag;
  d->ida = IDACreate(d->ctx);
  if (d->ida == NULL) return setup_fail(err, "IDACreate", 0);
  N_VConst(0.0, d->y);
  N_VConst(0.0, d->yp);
  if ((flag = IDAInit(d->ida, vs_dyn_residual, 0.0, d->y, d->yp)) != IDA_SUCCESS)
    return setup_fail(err, "IDAInit", flag);
  if ((flag = IDASetUserData(d->ida, d)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetUserData", flag);
  if ((flag = IDASetErrHandlerFn(d->ida, ida_err, d)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetErrHandlerFn", flag);
  if ((flag = IDASVtolerances(d->ida, d->rtol, d->atol)) != IDA_SUCCESS)
    return setup_fail(err, "IDASVtolerances", flag);
  if ((flag = IDASetId(d->ida, d->id)) != IDA_SUCCESS) return setup_fail(err, "IDASetId", flag);
  if ((flag = IDASetSuppressAlg(d->ida, SUNTRUE)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetSuppressAlg", flag);
  if ((flag = IDASetLinearSolver(d->ida, d->LS, d->J)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetLinearSolver", flag);
  if ((flag = IDASetJacFn(d->ida, vs_dyn_jacobian)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetJacFn", flag);
  if ((flag = IDASetNonlinConvCoef(d->ida, VS_DYN_NEWTON_COEF)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetNonlinConvCoef", flag);
  if ((flag = IDASetMaxOrd(d->ida, VS_DYN_MAX_ORDER)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetMaxOrd", flag);
  if ((flag = IDASetMaxNumSteps(d->ida, 100000)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetMaxNumSteps", flag);
  if ((flag = IDARootInit(d->ida, d->nroots, vs_dyn_roots)) != IDA_SUCCESS)
    return setup_fail(err, "IDARootInit", flag);
  if ((flag = IDASetNoInactiveRootWarn(d->ida)) != IDA_SUCCESS)
    return setup_fail(err, "IDASetNoInactiveRootWarn", flag);
  return VS_OK;
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
  set_layout(d, m);
  const int flag = SUNContext_Create(NULL, &d->ctx);
  vs_status st = flag != 0 ? setup_fail(err, "SUNContext_Create", flag) : VS_OK;
  if (st == VS_OK) st = alloc_work(d, o, err);
  if (st == VS_OK) {
    init_vectors(d);
    st = setup_klu(d, err);
  }
  if (st == VS_OK) st = setup_ida(d, err);
  if (st != VS_OK) {
    vs_dynamic_destroy(&d);
    return st;
  }
  *out = d;
  return VS_OK;
}

int vs_dynamic_size(const vs_dynamic *d) { return d->N; }
int vs_dynamic_nnz(const vs_dynamic *d) { return (int)SUNSparseMatrix_NNZ(d->J); }

void vs_dynamic_layout(const vs_dynamic *d, int *iv, int *il, int *imu, int *ie) {
  *iv = d->iv;
  *il = d->il;
  *imu = d->imu;
  *ie = d->ie;
}
