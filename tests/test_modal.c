/* Natural frequencies (modal.h) and damping models (damping.h) against closed forms:
 *  - a rigid block B x H standing on one elastic joint: the vertical bounce omega^2 = k_n b B / m
 *    and the coupled sway-rocking pair from the 2x2 problem det(K - omega^2 M) = 0 with
 *    K = [[k_s A, k_s A h], [k_s A h, k_s A h^2 + k_n b B^3 / 12]], M = diag(m, I), h = H / 2;
 *  - Rayleigh coefficients: the target ratio at the two chosen frequencies, and the ratio the
 *    model's damping matrix actually gives each mode (phi^T C phi / 2 omega);
 *  - the same block as a Rayleigh-damped linear 2-DOF system (sway-rocking) integrated by IDA:
 *    each mode released alone decays with the logarithmic decrement 2 pi zeta / sqrt(1 - zeta^2)
 *    and does not excite the other (classical damping);
 *  - an arch of 110 voussoirs under self-weight: the lowest modes (found by shift-invert
 *    Lanczos) against LAPACK's dense dsygv on the same symmetrised tangent and masses, each
 *    shape satisfying K phi = omega^2 M phi.
 * SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "check.h"
#include "model_matrix.h"
#include "voussoir/damping.h"
#include "voussoir/dynamic.h"
#include "voussoir/geometry.h"
#include "voussoir/joint.h"
#include "voussoir/modal.h"
#include "voussoir/model.h"
#include "voussoir/run.h"

static const double PI = 3.14159265358979323846;
static const double GRAV = 9.81;

/* The block: B wide, H high, depth b, density rho, centred on x = 0 above a horizontal joint to
 * the fixed support. */
typedef struct {
  double B, H, b, rho, kn;
  vs_geometry *g;
  vs_model *m;
  double q0[3]; /* self-weight equilibrium: uniform closure m g / (k_n b B) */
} block;

static void block_make(block *k) {
  vs_error err;
  vs_error_clear(&err);
  if (vs_geometry_create(1, 1, &k->g, &err) != VS_OK) fail_msg("geometry: %s", err.msg);
  vs_block *blk = &k->g->blocks[0];
  blk->area = k->B * k->H;
  blk->mass = k->rho * k->b * k->B * k->H;
  blk->inertia = blk->mass * (k->B * k->B + k->H * k->H) / 12.0;
  blk->cz = 0.5 * k->H;
  vs_joint_geom *j = &k->g->joints[0];
  *j = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .nz = 1.0, .length = k->B, .depth = k->b};
  k->g->gravity = GRAV;
  vs_joint_law law = {.kn = k->kn, .ks = 0.5 * k->kn, .mu = 5.0};
  if (vs_model_create(k->g, &law, 0.0, &k->m, &err) != VS_OK) fail_msg("model: %s", err.msg);
  k->q0[0] = k->q0[2] = 0.0;
  k->q0[1] = -blk->mass * GRAV / (k->kn * k->b * k->B);
}

static void block_free(block *k) {
  vs_model_destroy(&k->m);
  vs_geometry_destroy(&k->g);
}

/* Closed-form circular frequencies, ascending: the sway-rocking pair and the bounce. */
static void block_omegas(const block *k, double w[3]) {
  const vs_block *blk = &k->g->blocks[0];
  const double A = k->b * k->B, ks = 0.5 * k->kn, h = 0.5 * k->H, m = blk->mass, I = blk->inertia;
  const double k11 = ks * A, k12 = ks * A * h, k22 = ks * A * h * h + k->kn * k->b * pow(k->B, 3) / 12.0;
  /* m I l^2 - (k11 I + k22 m) l + det K = 0 */
  const double a = m * I, bb = -(k11 * I + k22 * m), c = k11 * k22 - k12 * k12;
  const double disc = sqrt(bb * bb - 4.0 * a * c);
  double l[3] = {(-bb - disc) / (2.0 * a), (-bb + disc) / (2.0 * a), k->kn * A / m};
  for (int i = 0; i < 3; i++)
    for (int j = i + 1; j < 3; j++)
      if (l[j] < l[i]) {
        double t = l[i];
        l[i] = l[j];
        l[j] = t;
      }
  for (int i = 0; i < 3; i++) w[i] = sqrt(l[i]);
}

static void compute_modes(const block *k, vs_modal *md) {
  vs_error err;
  vs_error_clear(&err);
  vs_status st = vs_modal_compute(k->m, k->q0, 0.0, 3, md, &err);
  if (st != VS_OK) fail_msg("vs_modal_compute: %s: %s", vs_strerror(st), err.msg);
}

/* The closed form leaves out the geometric stiffness of the joint's precompression, which is
 * W h against the rocking stiffness k_n b B^3 / 12: 5e-5 here, so 1e-3 is a real check. */
static void test_block_frequencies(void **state) {
  (void)state;
  block k = {.B = 0.2, .H = 0.4, .b = 0.1, .rho = 2000.0, .kn = 1e10};
  block_make(&k);
  vs_modal md;
  compute_modes(&k, &md);
  double w[3];
  block_omegas(&k, w);
  const double W = k.g->blocks[0].mass * GRAV;
  print_message("block: omega %.6g %.6g %.6g rad/s (closed form %.6g %.6g %.6g), W h / k_r %.2g, "
                "asymmetry %.2g\n",
                md.omega[0], md.omega[1], md.omega[2], w[0], w[1], w[2],
                W * 0.5 * k.H / (k.kn * k.b * pow(k.B, 3) / 12.0), md.asymmetry);
  assert_int_equal(md.n_modes, 3);
  for (int i = 0; i < 3; i++) {
    CHECK(md.omega[i], w[i], 1e-3, 0.0);
    CHECK(md.freq_hz[i], w[i] / (2.0 * PI), 1e-3, 0.0);
    CHECK(md.zeta[i], 0.0, 0.0, 1e-15); /* no damping set */
    double mm = 0.0; /* mass-normalised */
    double mass[3];
    vs_model_mass(k.m, mass);
    for (int r = 0; r < 3; r++) mm += mass[r] * md.phi[3 * i + r] * md.phi[3 * i + r];
    CHECK(mm, 1.0, 1e-10, 0.0);
  }
  vs_modal_free(&md);
  assert_null(md.phi);
  block_free(&k);
}

static void test_rayleigh_ratios(void **state) {
  (void)state;
  vs_error err;
  double a = 0.0, b = 0.0;
  assert_int_equal(vs_damping_rayleigh_coefficients(0.05, 10.0, 30.0, &a, &b, &err), VS_OK);
  CHECK(vs_damping_rayleigh_ratio(a, b, 10.0), 0.05, 1e-14, 0.0);
  CHECK(vs_damping_rayleigh_ratio(a, b, 30.0), 0.05, 1e-14, 0.0);
  assert_true(vs_damping_rayleigh_ratio(a, b, 17.0) < 0.05); /* below between the two */
  assert_int_equal(vs_damping_rayleigh_coefficients(0.05, 30.0, 10.0, &a, &b, &err), VS_ERR_INVALID);
  assert_int_equal(vs_damping_rayleigh_coefficients(-0.1, 10.0, 30.0, &a, &b, &err), VS_ERR_INVALID);
  assert_string_equal(vs_damping_model_name(VS_DAMPING_RAYLEIGH), "rayleigh");
  assert_null(vs_damping_model_name((vs_damping_model)7));

  /* the model's damping matrix gives each mode the Rayleigh ratio */
  block k = {.B = 0.2, .H = 0.4, .b = 0.1, .rho = 2000.0, .kn = 1e10};
  block_make(&k);
  vs_modal md;
  compute_modes(&k, &md);
  assert_int_equal(vs_damping_apply(k.m, VS_DAMPING_RAYLEIGH, 0.03, md.omega[0], md.omega[1], &a,
                                    &b, &err),
                   VS_OK);
  assert_int_equal(vs_modal_damping_ratios(k.m, k.q0, 0.0, &md, &err), VS_OK);
  print_message("rayleigh 3 %% at modes 1-2: alpha %.4g 1/s, beta %.4g s; zeta %.5f %.5f %.5f\n", a,
                b, md.zeta[0], md.zeta[1], md.zeta[2]);
  CHECK(md.zeta[0], 0.03, 1e-3, 0.0);
  CHECK(md.zeta[1], 0.03, 1e-3, 0.0);
  CHECK(md.zeta[2], vs_damping_rayleigh_ratio(a, b, md.omega[2]), 1e-3, 0.0);
  /* joint dashpots at 5 % of each joint's critical damping: the bounce is exactly such an
   * oscillator (the block on its joint), so it gets 5 %; here it is the second mode */
  assert_int_equal(vs_damping_apply(k.m, VS_DAMPING_JOINT, 0.05, 0.0, 0.0, NULL, NULL, &err), VS_OK);
  assert_int_equal(vs_modal_damping_ratios(k.m, k.q0, 0.0, &md, &err), VS_OK);
  CHECK(md.omega[1], sqrt(k.kn * k.b * k.B / k.g->blocks[0].mass), 1e-9, 0.0);
  CHECK(md.zeta[1], 0.05, 1e-9, 0.0);
  assert_int_equal(vs_damping_apply(k.m, VS_DAMPING_NONE, 0.05, 0.0, 0.0, NULL, NULL, &err), VS_OK);
  assert_int_equal(vs_modal_damping_ratios(k.m, k.q0, 0.0, &md, &err), VS_OK);
  for (int i = 0; i < 3; i++) CHECK(md.zeta[i], 0.0, 0.0, 1e-15);
  vs_modal_free(&md);
  block_free(&k);
}

/* ------------------------------- the decay of each mode ------------------------------- */

typedef struct {
  const double *phi, *mass, *q0; /* the mode watched, the mass diagonal, the equilibrium */
  const double *phi_other;
  double t[4096], eta[4096]; /* modal coordinate phi^T M (q - q0) */
  double other_max;          /* largest |other modal coordinate| */
  int ns;
} decay_rec;

static int decay_sample(void *user, double t, double delta, const double *q, const double *v,
                        const vs_energy *e) {
  (void)delta;
  (void)v;
  (void)e;
  decay_rec *r = user;
  double eta = 0.0, other = 0.0;
  for (int i = 0; i < 3; i++) {
    eta += r->phi[i] * r->mass[i] * (q[i] - r->q0[i]);
    other += r->phi_other[i] * r->mass[i] * (q[i] - r->q0[i]);
  }
  r->other_max = fmax(r->other_max, fabs(other));
  if (r->ns < 4096) {
    r->t[r->ns] = t;
    r->eta[r->ns++] = eta;
  }
  return 0;
}

/* Peaks of eta by a parabola through each sampled maximum and its neighbours. */
static int decay_peaks(const decay_rec *r, double *peak, int cap) {
  int np = 0;
  for (int i = 1; i + 1 < r->ns && np < cap; i++) {
    const double y0 = r->eta[i - 1], y1 = r->eta[i], y2 = r->eta[i + 1];
    if (!(y1 > y0 && y1 >= y2 && y1 > 0.0)) continue;
    const double den = y0 - 2.0 * y1 + y2, x = 0.5 * (y0 - y2) / den;
    peak[np++] = y1 - 0.25 * (y0 - y2) * x;
  }
  return np;
}

static void decay_mode(block *k, const vs_modal *md, int mode, double zeta) {
  const double w = md->omega[mode], T = 2.0 * PI / w, periods = 10.0;
  double mass[3], q[3], v[3];
  vs_model_mass(k->m, mass);
  /* released with a velocity along the mode, small enough to keep the joint closed: the edges
   * move by 1 % of the static closure */
  const double *phi = md->phi + 3 * mode;
  const double scale = 0.01 * fabs(k->q0[1]) / (fabs(phi[1]) + 0.5 * k->B * fabs(phi[2]) + fabs(phi[0]));
  for (int i = 0; i < 3; i++) {
    q[i] = k->q0[i];
    v[i] = scale * w * phi[i];
  }
  vs_dyn_opts o = {.rate = 1e-3, .rtol = 1e-9, .atol_q = 1e-6 * scale, .open = 1.0,
                   .rest_ke = 0.0, .rest_time = INFINITY, .collapse_ke = 1e30, .fall_time = 0.0,
                   .max_delta = 1e-3 * periods * T, .sample_dt = T / 200.0, .settle = 0};
  decay_rec *r = calloc(1, sizeof *r);
  assert_non_null(r);
  r->phi = phi;
  r->phi_other = md->phi + 3 * (1 - mode);
  r->mass = mass;
  r->q0 = k->q0;
  vs_dynamic *d = NULL;
  vs_error err;
  vs_error_clear(&err);
  vs_dyn_result res;
  if (vs_dynamic_create(k->m, &o, &d, &err) != VS_OK) fail_msg("create: %s", err.msg);
  vs_status st = vs_dynamic_run(d, 0.0, q, v, decay_sample, NULL, r, &res, &err);
  vs_dynamic_destroy(&d);
  if (st != VS_OK) fail_msg("run: %s", err.msg);
  double peak[64];
  const int np = decay_peaks(r, peak, 64);
  assert_true(np >= 9);
  const double delta = log(peak[0] / peak[np - 1]) / (np - 1);
  const double zeta_got = delta / sqrt(4.0 * PI * PI + delta * delta);
  print_message("mode %d (%.5g rad/s): %d peaks, decrement %.5f -> zeta %.5f (target %.5f); other "
                "mode %.2g of %.2g; %ld steps\n",
                mode + 1, w, np, delta, zeta_got, zeta, r->other_max, peak[0], res.steps);
  CHECK(zeta_got, zeta, 0.02, 0.0);
  assert_true(r->other_max < 1e-3 * peak[0]);
  free(r);
}

static void test_rayleigh_decay(void **state) {
  (void)state;
  block k = {.B = 0.2, .H = 0.4, .b = 0.1, .rho = 2000.0, .kn = 1e10};
  block_make(&k);
  vs_modal md;
  compute_modes(&k, &md);
  vs_error err;
  const double zeta = 0.02;
  assert_int_equal(vs_damping_apply(k.m, VS_DAMPING_RAYLEIGH, zeta, md.omega[0], md.omega[1], NULL,
                                    NULL, &err),
                   VS_OK);
  decay_mode(&k, &md, 0, zeta);
  decay_mode(&k, &md, 1, zeta);
  vs_modal_free(&md);
  block_free(&k);
}

/* The Rayleigh joint dashpot of the equations of motion (vs_joint_eval_motion with
 * vs_joint_dashpot.beta = beta) between a at rest at qa and b at qb moving at vb: its force f,
 * its matrix C (NULL: not wanted) and its power *p (NULL: not wanted). */
static void tangent_dashpot(const vs_joint_geom *j, const vs_joint_law *law, double beta,
                            const double qa[3], const double qb[3], const double va[3],
                            const double vb[3], const double ra[2], const double rb[2], double f[6],
                            double C[36], double *p) {
  double ha[2], hb[2];
  vs_joint_half_angle(qa[2], ha);
  vs_joint_half_angle(qb[2], hb);
  const vs_joint_bodies bd = {qa, qb, ha, hb, va, vb, ra, rb};
  const vs_joint_dashpot dp = {.beta = beta};
  vs_joint_motion out = {.fd = f, .C = C};
  vs_joint_eval_motion(j, law, &bd, 0.0, &dp, &out);
  if (p != NULL) *p = out.power;
}

/* The Rayleigh joint dashpot (vs_joint_dashpot.beta) on a half-open joint: its matrix is
 * df/dv (central differences; f is linear in v), symmetric, and the power f . v it dissipates is
 * >= 0; a joint lifted clear keeps only the shear part (the elastic shear acts over the whole
 * joint), and it scales with beta. */
static void test_tangent_dashpot(void **state) {
  (void)state;
  const vs_joint_geom j = {.a = VS_SUPPORT_LEFT, .b = 0, .nz = 1.0, .length = 0.2, .depth = 0.1};
  const vs_joint_law law = {.kn = 1e10, .ks = 5e9, .mu = 0.7};
  const double ra[2] = {0.0, 0.0}, rb[2] = {0.0, -0.2}, qa[3] = {0.0, 0.0, 0.0};
  const double beta = 1e-4, qb[3] = {1e-6, -2e-6, 4e-5}; /* tilted: part of the joint opens */
  const double va[3] = {0.0, 0.0, 0.0};
  double f[6], C[36], p;
  for (int trial = 0; trial < 5; trial++) {
    const double vb[3] = {1e-3 * sin(trial + 1.0), 1e-3 * cos(2.0 * trial), 1e-2 * sin(3.0 * trial + 0.5)};
    tangent_dashpot(&j, &law, beta, qa, qb, va, vb, ra, rb, f, C, &p);
    double fv = 0.0;
    for (int i = 0; i < 3; i++) fv += f[3 + i] * vb[i];
    CHECK(p, fv, 1e-12, 1e-30);
    assert_true(p > 0.0);
    for (int c = 0; c < 3; c++) {
      double vp[3], vm[3], fp[6], fm[6];
      memcpy(vp, vb, sizeof vp);
      memcpy(vm, vb, sizeof vm);
      const double h = 1e-6;
      vp[c] += h;
      vm[c] -= h;
      tangent_dashpot(&j, &law, beta, qa, qb, va, vp, ra, rb, fp, NULL, NULL);
      tangent_dashpot(&j, &law, beta, qa, qb, va, vm, ra, rb, fm, NULL, NULL);
      for (int r = 0; r < 6; r++) {
        const double fd = (fp[r] - fm[r]) / (2.0 * h);
        CHECK(C[r * 6 + 3 + c], fd, 1e-7, 1e-9 * fabs(C[(3 + c) * 6 + 3 + c]));
      }
    }
    for (int r = 0; r < 6; r++)
      for (int c = 0; c < 6; c++) CHECK(C[r * 6 + c], C[c * 6 + r], 1e-12, 1e-20);
  }
  /* lifted: only the shear dashpot beta k_s b t remains */
  const double lifted[3] = {0.0, 1e-4, 0.0}, vz[3] = {0.0, 1e-3, 1e-2}, vx[3] = {1e-3, 0.0, 0.0};
  tangent_dashpot(&j, &law, beta, qa, lifted, va, vz, ra, rb, f, C, &p);
  CHECK(f[4], 0.0, 0.0, 1e-20);
  tangent_dashpot(&j, &law, beta, qa, lifted, va, vx, ra, rb, f, C, &p);
  CHECK(p, beta * law.ks * j.depth * j.length * 1e-6, 1e-12, 0.0);
}

static void test_modal_errors(void **state) {
  (void)state;
  block k = {.B = 0.2, .H = 0.4, .b = 0.1, .rho = 2000.0, .kn = 1e10};
  block_make(&k);
  vs_modal md;
  vs_error err;
  vs_error_clear(&err);
  /* lifted clear of its joint: no stiffness at all, not a stable equilibrium */
  const double lifted[3] = {0.0, 1e-3, 0.0};
  assert_int_equal(vs_modal_compute(k.m, lifted, 0.0, 2, &md, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "not a stable equilibrium"));
  assert_null(md.phi);
  assert_int_equal(vs_modal_compute(k.m, k.q0, 0.0, 0, &md, &err), VS_ERR_INVALID);
  block_free(&k);
}

/* A run of the reference arch with rayleigh damping: the coefficients are those of the two lowest
 * modes under self-weight, which get the ratio (within the 1 % of the undamped geometric
 * stiffness), and a higher mode gets alpha / 2w + beta w / 2 to the same accuracy. Too many
 * voussoirs for the eigensolver: refused at creation. */
static void test_run_rayleigh(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  assert_int_equal(vs_case_set(&c, "dynamic.damping_model=rayleigh", &err), VS_OK);
  c.follow = 0;
  c.max_mm = 1.0;
  vs_run *r = NULL;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  assert_int_equal(vs_run_execute(r, NULL, NULL, NULL, &err), VS_OK);
  const vs_modal *md = vs_run_modal(r);
  double a, b, a_want, b_want;
  vs_run_rayleigh(r, &a, &b);
  assert_int_equal(md->n_modes, VS_MODAL_MAX);
  assert_int_equal(vs_damping_rayleigh_coefficients(c.damping, md->omega[0], md->omega[1], &a_want,
                                                    &b_want, &err), VS_OK);
  CHECK(a, a_want, 1e-12, 0.0);
  CHECK(b, b_want, 1e-12, 0.0);
  for (int i = 0; i < md->n_modes; i++)
    CHECK(md->zeta[i], vs_damping_rayleigh_ratio(a, b, md->omega[i]), 0.01, 0.0);
  assert_true(md->omega[0] < md->omega[1]);
  vs_run_destroy(&r);
  c.voussoirs = VS_MODAL_MAX_DOF / 3 + 1;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "arch.voussoirs"));
  assert_null(r);
}

/* LAPACK's dense generalised symmetric eigensolver (gfortran ABI). */
extern void dsygv_(const int *itype, const char *jobz, const char *uplo, const int *n, double *a,
                   const int *lda, double *b, const int *ldb, double *w, double *work,
                   const int *lwork, int *info, size_t jobz_len, size_t uplo_len);

/* The symmetric part of the tangent K of m at (q, delta), dense column-major n x n. */
static double *dense_tangent(const vs_model *m, const double *q, double delta, int n) {
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix K = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  assert_non_null(K);
  vs_model_jacobian(m, q, delta, K);
  const sunindextype *kp = SUNSparseMatrix_IndexPointers(K), *ki = SUNSparseMatrix_IndexValues(K);
  const double *kx = SUNSparseMatrix_Data(K);
  double *S = calloc((size_t)n * (size_t)n, sizeof *S);
  assert_non_null(S);
  for (int c = 0; c < n; c++)
    for (sunindextype e = kp[c]; e < kp[c + 1]; e++) {
      S[(size_t)ki[e] + (size_t)c * (size_t)n] += 0.5 * kx[e];
      S[(size_t)c + (size_t)ki[e] * (size_t)n] += 0.5 * kx[e];
    }
  SUNMatDestroy(K);
  SUNContext_Free(&ctx);
  return S;
}

/* The modes of an arch of many voussoirs under self-weight against a dense solve of the same
 * problem (an independent algorithm: Householder tridiagonalisation of the whole matrix), and
 * each shape against the eigen-equation itself; clamped supports, and pinned ones (whose
 * rotations, last in the state, couple to the first and last blocks; their rotary inertia is the
 * mean voussoir's). */
static void arch_modes_dense(const char *kind) {
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  char set[64];
  snprintf(set, sizeof set, "support.left_kind=%s", kind);
  assert_int_equal(vs_case_set(&c, set, &err), VS_OK);
  snprintf(set, sizeof set, "support.right_kind=%s", kind);
  assert_int_equal(vs_case_set(&c, set, &err), VS_OK);
  c.voussoirs = 110;
  c.follow = 0;
  c.max_mm = 0.01;
  vs_run *r = NULL;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  assert_int_equal(vs_run_execute(r, NULL, NULL, NULL, &err), VS_OK);
  const vs_model *m = vs_run_model(r);
  const int n = vs_model_size(m);
  vs_modal md;
  assert_int_equal(vs_modal_compute(m, vs_run_state(r), vs_run_delta(r), VS_MODAL_MAX, &md, &err),
                   VS_OK);
  assert_int_equal(md.n_modes, VS_MODAL_MAX);
  double *S = dense_tangent(m, vs_run_state(r), vs_run_delta(r), n);
  double *A = malloc((size_t)n * (size_t)n * sizeof *A), *mass = malloc((size_t)n * sizeof *mass);
  double *M = calloc((size_t)n * (size_t)n, sizeof *M), *w = malloc((size_t)n * sizeof *w);
  assert_true(A != NULL && mass != NULL && M != NULL && w != NULL);
  memcpy(A, S, (size_t)n * (size_t)n * sizeof *A);
  vs_model_mass(m, mass);
  double inertia = 0.0;
  for (int i = 0; i < c.voussoirs; i++) inertia += mass[3 * i + 2] / c.voussoirs;
  for (int i = 3 * c.voussoirs; i < n; i++) mass[i] = inertia; /* pinned supports' rotations */
  assert_int_equal(n, 3 * c.voussoirs + (strcmp(kind, "pinned") == 0 ? 2 : 0));
  for (int i = 0; i < n; i++) M[(size_t)i * (size_t)(n + 1)] = mass[i];
  const int one = 1, lwork = 64 * n;
  int info = 0;
  double *work = malloc((size_t)lwork * sizeof *work);
  assert_non_null(work);
  dsygv_(&one, "N", "U", &n, A, &n, M, &n, w, work, &lwork, &info, 1, 1);
  assert_int_equal(info, 0);
  for (int i = 0; i < md.n_modes; i++) {
    CHECK(md.omega[i] * md.omega[i], w[i], 1e-8, 0.0);
    const double *phi = md.phi + (size_t)i * (size_t)n;
    double res = 0.0, ref = 0.0; /* |S phi - omega^2 M phi| against |omega^2 M phi| */
    for (int row = 0; row < n; row++) {
      double sp = 0.0;
      for (int col = 0; col < n; col++) sp += S[(size_t)row + (size_t)col * (size_t)n] * phi[col];
      const double mp = md.omega[i] * md.omega[i] * mass[row] * phi[row];
      res += (sp - mp) * (sp - mp);
      ref += mp * mp;
    }
    CHECK(sqrt(res / ref), 0.0, 0.0, 1e-6);
  }
  print_message("arch of 110, %s: omega_1..6 %.6g %.6g %.6g %.6g %.6g %.6g rad/s (dense %.6g .. %.6g)\n",
                kind, md.omega[0], md.omega[1], md.omega[2], md.omega[3], md.omega[4],
                md.omega[5], sqrt(w[0]), sqrt(w[5]));
  free(work);
  free(A);
  free(S);
  free(M);
  free(mass);
  free(w);
  vs_modal_free(&md);
  vs_run_destroy(&r);
}

static void test_arch_modes_dense(void **state) {
  (void)state;
  arch_modes_dense("fixed");
  arch_modes_dense("pinned");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_block_frequencies),
      cmocka_unit_test(test_rayleigh_ratios),
      cmocka_unit_test(test_rayleigh_decay),
      cmocka_unit_test(test_tangent_dashpot),
      cmocka_unit_test(test_modal_errors),
      cmocka_unit_test(test_run_rayleigh),
      cmocka_unit_test(test_arch_modes_dense),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
