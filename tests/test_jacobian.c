/* The analytic CSC Jacobian of the whole arch (model.h) against central differences of the
 * residual, in random deformed states with many partially open and sliding joints, for two
 * support directions and two support displacements; also dG/d(delta), the support motion and
 * the residual as the gradient of the potential energy. SI units. */
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

#include "test_support.h"
#include "dynamic_internal.h"
#include "voussoir/case.h"
#include "voussoir/dynamic.h"
#include "voussoir/geometry.h"
#include "voussoir/joint.h"
#include "voussoir/model.h"

#include "test_rng.h"

static double deg(double d) { return d * acos(-1.0) / 180; }

/* Central-difference steps: 1 nm on displacements (and delta), the rotation that moves a
 * joint edge by about 1 nm. With kn b t ~ 1e7 N/m and residuals up to ~1e4 N, rounding in
 * the differences is ~1e-3 N/m; the states keep every joint at least 1 um (in penetration)
 * and 0.05 N (in shear) away from a contact or stick/slip transition, so no stencil crosses
 * one (the law is only C1 at contact transitions and C0 at stick/slip). */
static const double HU = 1e-9;

typedef struct {
  vs_case c;
  vs_geometry *g;
  vs_model *m;
  vs_joint_law law;
  double alpha;
  int n, nb, nj;
  double t; /* joint length, m */
} fixture;

/* mu > 0 overrides the case's friction coefficient; left, right: the supports' kinds. */
static void fixture_init_kinds(fixture *fx, double alpha_deg, double mu, vs_support_kind left,
                               vs_support_kind right) {
  vs_case_defaults(&fx->c);
  if (mu > 0) fx->c.friction = mu;
  vs_error err;
  vs_error_clear(&err);
  fx->g = NULL;
  fx->m = NULL;
  vs_status s = vs_test_arch(&fx->c, &fx->g, &err);
  if (s != VS_OK) fail_msg("geometry: %s", err.msg);
  double kn = fx->c.kn_N_mm3 * 1e9;
  fx->law = (vs_joint_law){.kn = kn, .ks = fx->c.ks_ratio * kn, .mu = fx->c.friction};
  fx->alpha = deg(alpha_deg);
  s = vs_model_create(fx->g, &fx->law, fx->alpha, &fx->m, &err);
  if (s != VS_OK) fail_msg("model: %s", err.msg);
  s = vs_model_set_support_kinds(fx->m, left, right, &err);
  if (s != VS_OK) fail_msg("support kinds: %s", err.msg);
  fx->n = vs_model_size(fx->m);
  fx->nb = fx->g->n_blocks;
  fx->nj = fx->g->n_joints;
  fx->t = fx->c.thickness_mm * 1e-3;
  const int npin = (left == VS_SUPPORT_PINNED) + (right == VS_SUPPORT_PINNED);
  assert_int_equal(fx->n, 3 * fx->nb + npin);
  assert_int_equal(vs_model_support_dof(fx->m, 0), left == VS_SUPPORT_PINNED ? 3 * fx->nb : -1);
  assert_int_equal(vs_model_support_dof(fx->m, 1),
                   right == VS_SUPPORT_PINNED ? 3 * fx->nb + npin - 1 : -1);
  assert_ptr_equal(vs_model_geometry(fx->m), fx->g);
}

static void fixture_init_mu(fixture *fx, double alpha_deg, double mu) {
  fixture_init_kinds(fx, alpha_deg, mu, VS_SUPPORT_FIXED, VS_SUPPORT_FIXED);
}

static void fixture_init(fixture *fx, double alpha_deg) { fixture_init_mu(fx, alpha_deg, 0); }

static void fixture_free(fixture *fx) {
  vs_model_destroy(&fx->m);
  assert_null(fx->m);
  vs_model_destroy(&fx->m); /* NULL: no-op */
  vs_geometry_destroy(&fx->g);
}

static void rot(double th, const double v[2], double out[2]) {
  double c = cos(th), s = sin(th);
  out[0] = c * v[0] - s * v[1];
  out[1] = s * v[0] + c * v[1];
}

/* Support displacement from model.h's definition: delta (sin alpha, -cos alpha). */
static void support_u(const fixture *fx, double delta, double u[2]) {
  u[0] = delta * sin(fx->alpha);
  u[1] = -delta * cos(fx->alpha);
}

/* Generalised displacement of a joint end: a block's (ux, uz, theta) of its centroid, or a
 * support's; r is the vector from the body's reference point to the joint centre. */
static void body_q(const fixture *fx, const double *q, int body, double delta, double out[3]) {
  if (body >= 0) {
    for (int k = 0; k < 3; k++) out[k] = q[3 * body + k];
  } else if (body == VS_SUPPORT_LEFT) {
    out[0] = out[1] = out[2] = 0;
  } else {
    support_u(fx, delta, out);
    out[2] = 0;
  }
  const int k = body < 0 ? vs_model_support_dof(fx->m, body == VS_SUPPORT_RIGHT) : -1;
  if (k >= 0) out[2] = q[k]; /* a pinned support's rotation: an unknown */
}
static void body_r(const fixture *fx, const vs_joint_geom *jg, int body, double r[2]) {
  if (body >= 0) {
    r[0] = jg->px - fx->g->blocks[body].cx;
    r[1] = jg->pz - fx->g->blocks[body].cz;
  } else {
    r[0] = r[1] = 0;
  }
}

/* Place one body of a joint given the other so that the joint has penetration a, gap slope w
 * and slip (the exact kinematics of joint.h inverted): from_a = 1 places b from a, else a
 * from b. d_c = x_b - x_a with x = P + u + (R(theta) - I) r; n, s turned by the mean
 * rotation; d_c = -a n + slip s. */
static void place(const vs_joint_geom *jg, int from_a, const double qk[3], const double rk[2],
                  const double ru[2], double a, double w, double slip, double qu[3]) {
  double dth = 2 * asin(0.5 * w);
  qu[2] = from_a ? qk[2] + dth : qk[2] - dth;
  double thm = 0.5 * (qk[2] + qu[2]);
  double n0[2] = {jg->nx, jg->nz}, s0[2] = {-jg->nz, jg->nx}, n[2], s[2], Rk[2], Ru[2];
  rot(thm, n0, n);
  rot(thm, s0, s);
  rot(qk[2], rk, Rk);
  rot(qu[2], ru, Ru);
  for (int i = 0; i < 2; i++) {
    double dc = -a * n[i] + slip * s[i];
    double xk = qk[i] + Rk[i] - rk[i]; /* x - P of the known body */
    double off = Ru[i] - ru[i];
    qu[i] = from_a ? xk + dc - off : xk - dc - off;
  }
}

/* Normal force of the Winkler joint (closed form, for choosing slips). */
static double winkler_N(double kn, double b, double t, double a, double w) {
  double aw = fabs(w), e = a + 0.5 * aw * t;
  if (e <= 0) return 0;
  if (a >= 0.5 * aw * t) return kn * b * t * a;
  return 0.5 * kn * b * e * e / aw;
}

/* Choose a joint state: partial contact (half the joints), full contact or open; the slip a
 * random fraction of the sticking limit, below it (stick) or above it (slide) unless
 * all_stick (then open joints get no slip either). */
static void choose_joint(rng *r, const fixture *fx, int all_stick, double *a, double *w,
                         double *slip) {
  double t = fx->t, b = fx->g->joints[0].depth;
  *w = rsign(r) * urand(r, 1e-3, 5e-3);
  double half = 0.5 * fabs(*w) * t, u = urand(r, 0, 1);
  *a = u < 0.5 ? urand(r, -0.8, 0.8) * half
       : u < 0.75 ? urand(r, 1.2, 3.0) * half
                  : -urand(r, 1.2, 3.0) * half;
  double N = winkler_N(fx->law.kn, b, t, *a, *w);
  double lim = fx->law.mu * N / (fx->law.ks * b * t);
  double sf = (all_stick || urand(r, 0, 1) < 0.5) ? urand(r, 0.1, 0.8) : urand(r, 1.3, 4.0);
  *slip = N > 0 ? rsign(r) * sf * lim : all_stick ? 0.0 : urand(r, -1e-5, 1e-5);
}

/* State B: the left half built joint by joint from the left support, the right half from the
 * (moved) right support; the joint where they meet takes whatever state results. */
static void state_chain(rng *r, const fixture *fx, double delta, int all_stick, double *q) {
  int nb = fx->nb, mid = nb / 2;
  double a, w, slip, ra[2], rb[2], qk[3];
  for (int j = 0; j < mid; j++) { /* joint j: block j-1 (or left) -> block j */
    const vs_joint_geom *jg = &fx->g->joints[j];
    choose_joint(r, fx, all_stick, &a, &w, &slip);
    body_q(fx, q, jg->a, delta, qk);
    body_r(fx, jg, jg->a, ra);
    body_r(fx, jg, jg->b, rb);
    place(jg, 1, qk, ra, rb, a, w, slip, q + 3 * jg->b);
  }
  for (int j = nb; j > mid; j--) { /* joint j: block j (or right) -> block j-1 */
    const vs_joint_geom *jg = &fx->g->joints[j];
    choose_joint(r, fx, all_stick, &a, &w, &slip);
    body_q(fx, q, jg->b, delta, qk);
    body_r(fx, jg, jg->a, ra);
    body_r(fx, jg, jg->b, rb);
    place(jg, 0, qk, rb, ra, a, w, slip, q + 3 * jg->a);
  }
}

/* State A: independent random displacements 0.1-1 mm and rotations 1e-3-1e-2 rad. */
static void state_random(rng *r, const fixture *fx, double *q) {
  for (int i = 0; i < fx->nb; i++) {
    q[3 * i] = rsign(r) * urand(r, 1e-4, 1e-3);
    q[3 * i + 1] = rsign(r) * urand(r, 1e-4, 1e-3);
    q[3 * i + 2] = rsign(r) * urand(r, 1e-3, 1e-2);
  }
}

typedef struct {
  int partial, full, open, sliding, sticking_loaded;
} regime_count;

/* 1 when every joint is clear of the contact transitions (|a| = |w| t/2) and of the
 * stick/slip transition (|k_s b t (slip - slip_p_old)| = mu N). */
static int clear_of_transitions(const fixture *fx, const double *q, double delta,
                                regime_count *rc) {
  vs_joint_state *st = malloc((size_t)fx->nj * sizeof *st);
  assert_non_null(st);
  vs_model_joint_states(fx->m, q, delta, st);
  const double *sp = vs_model_slips(fx->m);
  int ok = 1;
  *rc = (regime_count){0};
  for (int j = 0; j < fx->nj; j++) {
    double half = 0.5 * fabs(st[j].w) * fx->t;
    if (fabs(fabs(st[j].a) - half) < 1e-6) ok = 0;
    double kst = fx->law.ks * fx->g->joints[j].depth * fx->t;
    double trial = fabs(kst * (st[j].slip - sp[j]));
    if (st[j].N > 0 && fabs(trial - fx->law.mu * st[j].N) < 0.05) ok = 0;
    if (st[j].a + half <= 0) rc->open++;
    else if (st[j].a - half >= 0) rc->full++;
    else rc->partial++;
    if (st[j].N > 0 && st[j].sliding) rc->sliding++;
    if (st[j].N > 0 && !st[j].sliding) rc->sticking_loaded++;
  }
  free(st);
  return ok;
}

/* Unknown i is a rotation: a block's or a pinned support's (after the blocks). */
static int is_rot(const fixture *fx, int i) { return i >= 3 * fx->nb || i % 3 == 2; }
/* Units: moment rows / t, rotation columns * t, so every entry is in N/m. */
static double row_scale(const fixture *fx, int i) { return is_rot(fx, i) ? 1.0 / fx->t : 1.0; }
static double col_scale(const fixture *fx, int j) { return is_rot(fx, j) ? fx->t : 1.0; }
static double step(const fixture *fx, int j) { return HU / col_scale(fx, j); }

/* Dense copy of the analytic Jacobian, column-major. */
static void analytic_dense(const fixture *fx, SUNContext ctx, const double *q, double delta,
                           double *Jd) {
  int n = fx->n, nnz = vs_model_nnz(fx->m);
  assert_true(nnz > 0 && nnz <= n * n);
  SUNMatrix J = SUNSparseMatrix(n, n, nnz, CSC_MAT, ctx);
  assert_non_null(J);
  assert_int_equal(vs_model_jacobian(fx->m, q, delta, J), 0);
  sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  realtype *v = SUNSparseMatrix_Data(J);
  for (int k = 0; k < n * n; k++) Jd[k] = 0;
  assert_int_equal(cp[0], 0);
  for (int j = 0; j < n; j++) {
    assert_true(cp[j + 1] >= cp[j] && cp[j + 1] <= nnz);
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      assert_true(ri[p] >= 0 && ri[p] < n);
      Jd[(size_t)j * (size_t)n + (size_t)ri[p]] += v[p];
    }
  }
  SUNMatDestroy(J);
}

/* Compare the analytic Jacobian and dG/ddelta with central differences at (q, delta). */
static void check_jacobian_at(const fixture *fx, SUNContext ctx, const double *q,
                              double delta, const char *label) {
  int n = fx->n;
  size_t nn = (size_t)n * (size_t)n;
  double *Jd = malloc(nn * sizeof(double)), *Jf = malloc(nn * sizeof(double));
  double *qp = malloc((size_t)n * sizeof(double)), *Gp = malloc((size_t)n * sizeof(double));
  double *Gm = malloc((size_t)n * sizeof(double)), *dd = malloc((size_t)n * sizeof(double));
  assert_true(Jd && Jf && qp && Gp && Gm && dd);
  analytic_dense(fx, ctx, q, delta, Jd);
  for (int i = 0; i < n; i++) qp[i] = q[i];
  double mx = 0;
  for (int j = 0; j < n; j++) {
    double h = step(fx, j);
    qp[j] = q[j] + h;
    vs_model_residual(fx->m, qp, delta, Gp);
    qp[j] = q[j] - h;
    vs_model_residual(fx->m, qp, delta, Gm);
    qp[j] = q[j];
    for (int i = 0; i < n; i++) {
      double d = (Gp[i] - Gm[i]) / (2 * h);
      Jf[(size_t)j * (size_t)n + (size_t)i] = d;
      mx = fmax(mx, fabs(d * row_scale(fx, i) * col_scale(fx, j)));
    }
  }
  assert_true(mx > 1e5); /* the state is loaded */
  int bad = 0;
  for (int j = 0; j < n; j++) {
    for (int i = 0; i < n; i++) {
      double sc = row_scale(fx, i) * col_scale(fx, j);
      size_t k = (size_t)j * (size_t)n + (size_t)i;
      double an = Jd[k] * sc, fd = Jf[k] * sc;
      if (!(fabs(an - fd) <= 1e-6 * fabs(fd) + 1e-8 * mx)) {
        if (bad++ < 10)
          print_message("%s: J[%d][%d] (block %d dof %d / block %d dof %d) analytic %.12g, "
                        "differences %.12g\n",
                        label, i, j, i / 3, i % 3, j / 3, j % 3, Jd[k], Jf[k]);
      }
    }
  }
  /* dG/ddelta */
  vs_model_dG_ddelta(fx->m, q, delta, dd);
  vs_model_residual(fx->m, q, delta + HU, Gp);
  vs_model_residual(fx->m, q, delta - HU, Gm);
  double mxd = 0;
  for (int i = 0; i < n; i++) mxd = fmax(mxd, fabs((Gp[i] - Gm[i]) / (2 * HU) * row_scale(fx, i)));
  for (int i = 0; i < n; i++) {
    double fd = (Gp[i] - Gm[i]) / (2 * HU) * row_scale(fx, i), an = dd[i] * row_scale(fx, i);
    if (!(fabs(an - fd) <= 1e-6 * fabs(fd) + 1e-8 * fmax(mxd, mx * 1e-3))) {
      if (bad++ < 20)
        print_message("%s: dG/ddelta[%d] analytic %.12g, differences %.12g\n", label, i, dd[i],
                      (Gp[i] - Gm[i]) / (2 * HU));
    }
  }
  free(Jd);
  free(Jf);
  free(qp);
  free(Gp);
  free(Gm);
  free(dd);
  if (bad) fail_msg("%s: %d entries of the Jacobian / dG/ddelta disagree", label, bad);
}

/* Draw a state clear of transitions (retrying), with enough joints in each regime. */
static void draw_state(rng *r, const fixture *fx, int kind, double delta, int all_stick,
                       double *q, regime_count *rc) {
  for (int attempt = 0; attempt < 200; attempt++) {
    for (int i = 0; i < fx->n; i++) q[i] = 0;
    for (int i = 3 * fx->nb; i < fx->n; i++) q[i] = rsign(r) * urand(r, 1e-4, 1e-3); /* pinned */
    if (kind == 0) state_random(r, fx, q);
    else state_chain(r, fx, delta, all_stick, q);
    if (clear_of_transitions(fx, q, delta, rc)) return;
  }
  fail_msg("no state clear of transitions found");
}

static void test_support_displacement(void **state) {
  (void)state;
  const double alphas[] = {0, 60, 90, -30};
  for (int k = 0; k < 4; k++) {
    fixture fx;
    fixture_init(&fx, alphas[k]);
    double u[2], want[2];
    vs_model_support_displacement(fx.m, 0.02, u);
    support_u(&fx, 0.02, want);
    assert_true(fabs(u[0] - want[0]) <= 1e-15 && fabs(u[1] - want[1]) <= 1e-15);
    fixture_free(&fx);
  }
}

static void test_jacobian_random_states(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  const double alphas[] = {0, 60}, deltas[] = {0, 0.02};
  rng r = {0x243F6A8885A308D3ULL};
  double *q = NULL;
  for (int ia = 0; ia < 2; ia++) {
    fixture fx;
    fixture_init(&fx, alphas[ia]);
    q = realloc(q, (size_t)fx.n * sizeof(double));
    assert_non_null(q);
    for (int id = 0; id < 2; id++) {
      for (int kind = 0; kind < 2; kind++) {
        regime_count rc;
        draw_state(&r, &fx, kind, deltas[id], 0, q, &rc);
        if (kind == 1) { /* the constructed states exercise every regime */
          assert_true(rc.partial >= 10);
          assert_true(rc.sliding >= 3 && rc.sticking_loaded >= 3);
        }
        char label[96];
        snprintf(label, sizeof label, "alpha %g delta %g state %s (partial %d full %d open %d "
                 "sliding %d)", alphas[ia], deltas[id], kind ? "chain" : "random", rc.partial,
                 rc.full, rc.open, rc.sliding);
        check_jacobian_at(&fx, ctx, q, deltas[id], label);
      }
    }
    fixture_free(&fx);
  }
  free(q);
  SUNContext_Free(&ctx);
}

/* A mortared arch (tension f_t softening by G_f, cohesion c by G_c; some joints cracked in
 * from an edge, some with cohesion already softened, some damaged from both edges): the
 * Jacobian against central differences of the residual, in states where joints are in elastic
 * tension, softening, unloading along the damaged mortar's secant, cracked through, partly in
 * contact, sticking and sliding; each drawn clear of the law's kinks (within 1e-7 m of
 * a breakpoint of the stress-opening curve at an edge, within 0.05 N of the shear limit, whose
 * own kink is where it reaches zero). */
static int mortar_clear(const fixture *fx, const double *q, double delta, int *soft, int *slid,
                        int *secant) {
  vs_joint_state *st = malloc((size_t)fx->nj * sizeof *st);
  assert_non_null(st);
  vs_model_joint_states(fx->m, q, delta, st);
  const double *sp = vs_model_slips(fx->m);
  int ok = 1;
  *soft = *slid = *secant = 0;
  for (int j = 0; j < fx->nj; j++) {
    const vs_joint_law *l = vs_model_joint_law(fx->m, j);
    const double t = fx->t, b = fx->g->joints[j].depth;
    const double d0 = l->ft / l->kn, du = 2 * l->gf / l->ft;
    for (int e = -1; e <= 1; e += 2) {
      const double p = st[j].a + e * 0.5 * st[j].w * t;
      /* the edge's largest opening so far (the envelope's end vertex; d0 undamaged) */
      const double km = l->env_n >= 2 ? l->env_k[e < 0 ? 0 : l->env_n - 1] : d0;
      if (fabs(p) < 1e-7 || fabs(p + d0) < 1e-7 || fabs(p + du) < 1e-7 || fabs(p + km) < 1e-7)
        ok = 0;
      if (p < -km && p > -du) (*soft)++;
      if (km > d0 && p < 0 && p > -km) (*secant)++;
    }
    const double ku = 2 * l->gc / l->c, bonded = t - l->crack[0] - l->crack[1];
    const double coh = l->kappa < ku ? l->c * b * bonded * (1 - l->kappa / ku) : 0;
    const double lim = fmax(0, coh + l->mu * st[j].N);
    const double trial = fabs(l->ks * b * t * (st[j].slip - sp[j]));
    if (fabs(trial - lim) < 0.05 || fabs(coh + l->mu * st[j].N) < 0.05) ok = 0;
    *slid += st[j].sliding;
  }
  free(st);
  return ok;
}

static void test_jacobian_mortar(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  rng r = {0x13198A2E03707344ULL};
  fixture fx;
  fixture_init(&fx, 30);
  vs_error err;
  for (int k = 0; k < fx.nj; k++) {
    vs_joint_law l = fx.law;
    l.ft = 1e4, l.gf = 0.5, l.c = 1e3, l.gc = 0.05; /* d0 3.3 um, du 100 um */
    if (k % 3 == 1) l.crack[0] = 0.3 * fx.t;
    if (k % 3 == 2) l.crack[1] = 0.2 * fx.t, l.kappa = 1e-5;
    if (k % 3 == 0) { /* damaged from both edges, its envelope in three pieces: 60 um at the
                         intrados, 40 um at the extrados, the floor between */
      vs_joint_damage_update(&l, fx.g->joints[k].depth, fx.t, -30e-6, 60e-6 / fx.t);
      vs_joint_damage_update(&l, fx.g->joints[k].depth, fx.t, -20e-6, -40e-6 / fx.t);
    }
    assert_int_equal(vs_model_set_joint_law(fx.m, k, &l, &err), VS_OK);
  }
  /* a damage envelope with a vertex count outside its storage is refused, naming the field */
  vs_joint_law bad = *vs_model_joint_law(fx.m, 0);
  const int counts[3] = {-1, 1, VS_JOINT_ENV_MAX + 1};
  for (int i = 0; i < 3; i++) {
    bad.env_n = counts[i];
    assert_int_equal(vs_model_set_joint_law(fx.m, 0, &bad, &err), VS_ERR_INVALID);
    assert_non_null(strstr(err.msg, "env_n"));
  }
  double *q = malloc((size_t)fx.n * sizeof(double));
  assert_non_null(q);
  int checked = 0, soft_all = 0, slid_all = 0, secant_all = 0;
  for (int attempt = 0; attempt < 400 && checked < 4; attempt++) {
    for (int i = 0; i < fx.n; i++) q[i] = 0;
    state_chain(&r, &fx, 0.01, attempt % 2, q);
    int soft, slid, secant;
    if (!mortar_clear(&fx, q, 0.01, &soft, &slid, &secant)) continue;
    char label[128];
    snprintf(label, sizeof label, "mortar state %d (softening edges %d, on the secant %d, "
             "sliding %d)", checked, soft, secant, slid);
    check_jacobian_at(&fx, ctx, q, 0.01, label);
    checked++, soft_all += soft, slid_all += slid, secant_all += secant;
  }
  assert_int_equal(checked, 4);
  assert_true(soft_all >= 10);  /* the softening branch is exercised */
  assert_true(secant_all >= 4); /* and the damaged edges' secant unloading */
  assert_true(slid_all >= 3);
  free(q);
  fixture_free(&fx);
  SUNContext_Free(&ctx);
}

/* With pinned supports (each alone and both) the static unknowns gain the supports' rotations
 * and their moment equations: the Jacobian, dG/ddelta and G = dE/dq (the rotation's equation is
 * the moment of the springing joint about the pivot) against central differences. */
static void test_jacobian_pinned(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  const vs_support_kind kinds[3][2] = {{VS_SUPPORT_PINNED, VS_SUPPORT_FIXED},
                                       {VS_SUPPORT_FIXED, VS_SUPPORT_PINNED},
                                       {VS_SUPPORT_PINNED, VS_SUPPORT_PINNED}};
  rng r = {0xA4093822299F31D0ULL};
  for (int k = 0; k < 3; k++) {
    fixture fx;
    fixture_init_kinds(&fx, 60, 0, kinds[k][0], kinds[k][1]);
    double *q = malloc((size_t)fx.n * sizeof(double));
    assert_non_null(q);
    for (int kind = 0; kind < 2; kind++) {
      regime_count rc;
      draw_state(&r, &fx, kind, 0.02, 0, q, &rc);
      char label[96];
      snprintf(label, sizeof label, "pinned (left %d, right %d) state %s", kinds[k][0],
               kinds[k][1], kind ? "chain" : "random");
      check_jacobian_at(&fx, ctx, q, 0.02, label);
    }
    free(q);
    fixture_free(&fx);
  }
  SUNContext_Free(&ctx);
}

/* After a commit the plastic slips are those of the return mapping (a sliding joint's a hair
 * behind it, by 1e-9 of its elastic slip, so that it still slides at the committed state: its
 * force is the same), and the Jacobian is still the derivative of the residual that uses them. */
static void test_jacobian_after_commit(void **state) {
  (void)state;
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  fixture fx;
  fixture_init(&fx, 30);
  rng r = {0xB7E151628AED2A6BULL};
  double *q = malloc((size_t)fx.n * sizeof(double)), *q2 = malloc((size_t)fx.n * sizeof(double));
  vs_joint_state *st = malloc((size_t)fx.nj * sizeof *st);
  assert_true(q && q2 && st);
  regime_count rc;
  draw_state(&r, &fx, 1, 0.01, 0, q, &rc);
  vs_model_joint_states(fx.m, q, 0.01, st);
  int slid = vs_model_commit(fx.m, q, 0.01);
  assert_true(slid >= rc.sliding && slid >= 1);
  const double *sp = vs_model_slips(fx.m);
  vs_joint_state *after = malloc((size_t)fx.nj * sizeof *after);
  assert_non_null(after);
  vs_model_joint_states(fx.m, q, 0.01, after);
  for (int j = 0; j < fx.nj; j++) {
    const double want = st[j].sliding ? st[j].slip_p - 1e-9 * (st[j].slip - st[j].slip_p)
                                      : st[j].slip_p;
    if (!(fabs(sp[j] - want) <= 1e-12 * fabs(st[j].slip_p) + 1e-18))
      fail_msg("joint %d: committed slip %.15g, return mapping gave %.15g (sliding %d)", j + 1,
               sp[j], st[j].slip_p, st[j].sliding);
    if (st[j].sliding && st[j].N > 0.0 && (!after[j].sliding || after[j].T != st[j].T))
      fail_msg("joint %d: sliding with T = %.17g before the commit, at the committed state "
               "sliding %d, T = %.17g", j + 1, st[j].T, after[j].sliding, after[j].T);
  }
  free(after);
  int found = 0;
  for (int attempt = 0; attempt < 200 && !found; attempt++) {
    for (int i = 0; i < fx.n; i++)
      q2[i] = q[i] + (i % 3 == 2 ? urand(&r, -2e-4, 2e-4) : urand(&r, -5e-6, 5e-6));
    found = clear_of_transitions(&fx, q2, 0.012, &rc);
  }
  assert_true(found);
  check_jacobian_at(&fx, ctx, q2, 0.012, "after commit");
  free(q);
  free(q2);
  free(st);
  fixture_free(&fx);
  SUNContext_Free(&ctx);
}

/* With every loaded joint sticking, G = d(potential energy)/dq (joint energy plus m g uz).
 * The joint where the two halves of a constructed state meet has a slip of millimetres, so a
 * high friction coefficient keeps it sticking; open joints carry no shear and no shear energy. */
static void energy_gradient_check(vs_support_kind left, vs_support_kind right) {
  fixture fx;
  fixture_init_kinds(&fx, 60, 100.0, left, right);
  rng r = {0x13198A2E03707344ULL};
  double *q = malloc((size_t)fx.n * sizeof(double)), *G = malloc((size_t)fx.n * sizeof(double));
  assert_true(q && G);
  const double deltas[] = {0, 0.02};
  for (int id = 0; id < 2; id++) {
    regime_count rc;
    int found = 0;
    for (int attempt = 0; attempt < 200 && !found; attempt++) {
      draw_state(&r, &fx, 1, deltas[id], 1, q, &rc);
      found = rc.sliding == 0;
    }
    assert_true(found);
    vs_model_residual(fx.m, q, deltas[id], G);
    double mx = 0;
    for (int i = 0; i < fx.n; i++) mx = fmax(mx, fabs(G[i] * row_scale(&fx, i)));
    for (int i = 0; i < fx.n; i++) {
      double h = step(&fx, i), qi = q[i];
      q[i] = qi + h;
      double Ep = vs_model_energy(fx.m, q, deltas[id]);
      q[i] = qi - h;
      double Em = vs_model_energy(fx.m, q, deltas[id]);
      q[i] = qi;
      double fd = (Ep - Em) / (2 * h) * row_scale(&fx, i), an = G[i] * row_scale(&fx, i);
      if (!(fabs(an - fd) <= 1e-6 * fabs(fd) + 1e-7 * mx))
        fail_msg("delta %g: G[%d] = %.12g, dE/dq = %.12g", deltas[id], i, G[i],
                 fd / row_scale(&fx, i));
    }
  }
  free(q);
  free(G);
  fixture_free(&fx);
}

/* ... also with both supports pinned: the equation of a pinned support's rotation is
 * dE/dtheta_s. */
static void test_residual_is_energy_gradient(void **state) {
  (void)state;
  energy_gradient_check(VS_SUPPORT_FIXED, VS_SUPPORT_FIXED);
  energy_gradient_check(VS_SUPPORT_PINNED, VS_SUPPORT_PINNED);
}

/* The dynamic phase's DAE (dynamic.h): its iteration matrix dF/dy + cj dF/dy' against central
 * differences of its residual, at a loaded chain state with the supports displaced off their
 * prescribed positions (so that the constraint rows are not trivially satisfied), random
 * multipliers and velocities, damping on. The matrix leaves out by design the energy
 * integrals' dependence on the state and the damping forces' on the positions: the velocities
 * are zero there (damping forces vanish) and the energy rows are checked on their diagonal. */
static void dae_jacobian_check(vs_support_kind left, vs_support_kind right) {
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  fixture fx;
  fixture_init_kinds(&fx, 60, 0, left, right);
  vs_model_set_damping(fx.m, 0.05);
  rng r = {0x13198A2E03707344ULL};
  const double delta = 0.02, rate = 1e-3, t = delta / rate, cj = 1e4;
  double *q = malloc((size_t)fx.n * sizeof(double));
  assert_non_null(q);
  regime_count rc;
  draw_state(&r, &fx, 1, delta, 0, q, &rc);
  vs_dyn_opts o = {.rate = rate, .rtol = 1e-6, .atol_q = 1e-9, .open = 1e-5, .rest_ke = 1e-9,
                   .rest_time = 1.0, .collapse_ke = 1.0, .fall_time = 1.0, .max_delta = 1.0,
                   .sample_dt = 1.0, .settle = 0};
  vs_dynamic *d = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_dynamic_create(fx.m, &o, &d, &err), VS_OK);
  const int N = vs_dynamic_size(d), n = 3 * fx.nb;
  int iv, il, imu, ie;
  vs_dynamic_layout(d, &iv, &il, &imu, &ie);
  assert_int_equal(iv, n + 6);
  assert_int_equal(N, ie + 3);
  const int nc = imu - il; /* a pinned support has no rotation constraint */
  assert_int_equal(nc, 6 - (fx.n - n));
  assert_int_equal(ie - imu, nc);
  double *y = calloc((size_t)N, sizeof(double)), *yp = calloc((size_t)N, sizeof(double));
  double *rp = malloc((size_t)N * sizeof(double)), *rm = malloc((size_t)N * sizeof(double));
  double *Jd = calloc((size_t)N * (size_t)N, sizeof(double));
  assert_true(y && yp && rp && rm && Jd);
  for (int i = 0; i < n; i++) y[i] = q[i];
  double qs[6], vs[6];
  vs_model_support_states(fx.m, delta, rate, qs, vs);
  for (int s = 0; s < 2; s++) /* a pinned support's rotation from the static state */
    if (vs_model_support_dof(fx.m, s) >= 0) qs[3 * s + 2] = q[vs_model_support_dof(fx.m, s)];
  for (int c = 0; c < 6; c++) y[n + c] = qs[c] + urand(&r, -1e-7, 1e-7) / (c % 3 == 2 ? fx.t : 1.0);
  for (int c = 0; c < nc; c++) {
    y[il + c] = urand(&r, -100.0, 100.0);
    y[imu + c] = urand(&r, -1e-6, 1e-6);
  }
  for (int i = 0; i < N; i++) yp[i] = urand(&r, -1e-3, 1e-3);
  SUNMatrix J = SUNSparseMatrix(N, N, vs_dynamic_nnz(d), CSC_MAT, ctx);
  assert_non_null(J);
  vs_dynamic_jacobian(d, t, cj, y, J);
  const sunindextype *cp = SUNSparseMatrix_IndexPointers(J), *ri = SUNSparseMatrix_IndexValues(J);
  const double *jx = SUNSparseMatrix_Data(J);
  for (int j = 0; j < N; j++)
    for (sunindextype p = cp[j]; p < cp[j + 1]; p++) {
      assert_true(ri[p] >= 0 && ri[p] < N);
      if (p > cp[j]) assert_true(ri[p] > ri[p - 1]); /* sorted, no duplicates */
      Jd[(size_t)j * (size_t)N + (size_t)ri[p]] += jx[p];
    }
  /* scales: rows of moments over a length, columns of rotations times a length */
  double mx = 0.0;
  int bad = 0, checked = 0;
  for (int j = 0; j < N; j++) {
    const double h = (j < 2 * iv && (j % iv) % 3 == 2) ? HU / fx.t : (j >= il && j < ie) ? 1e-3 : HU;
    const double y0 = y[j], p0 = yp[j];
    y[j] = y0 + h;
    vs_dynamic_residual(d, t, y, yp, rp);
    y[j] = y0 - h;
    vs_dynamic_residual(d, t, y, yp, rm);
    y[j] = y0;
    double *fd = malloc((size_t)N * sizeof(double));
    assert_non_null(fd);
    for (int i = 0; i < N; i++) fd[i] = (rp[i] - rm[i]) / (2 * h);
    yp[j] = p0 + 1.0; /* F is linear in y': a unit step has no truncation error */
    vs_dynamic_residual(d, t, y, yp, rp);
    yp[j] = p0 - 1.0;
    vs_dynamic_residual(d, t, y, yp, rm);
    yp[j] = p0;
    for (int i = 0; i < N; i++) fd[i] += cj * (rp[i] - rm[i]) / 2.0;
    const double cs = (j < 2 * iv && (j % iv) % 3 == 2) ? fx.t : 1.0;
    for (int i = 0; i < N; i++) {
      if (i >= ie && i != j) continue; /* the energy rows: diagonal only (see above) */
      const double rs = (i >= iv && i < 2 * iv && (i % iv) % 3 == 2) ? 1.0 / fx.t : 1.0;
      const double an = Jd[(size_t)j * (size_t)N + (size_t)i] * rs * cs, dv = fd[i] * rs * cs;
      mx = fmax(mx, fabs(dv));
      checked++;
      if (!(fabs(an - dv) <= 1e-6 * fabs(dv) + 1e-8 * 1e7)) { /* 1e7 N/m: k_n b t */
        if (bad++ < 10) print_message("DAE J[%d][%d]: analytic %.12g, differences %.12g\n", i, j,
                                      an / (rs * cs), dv / (rs * cs));
      }
    }
    free(fd);
  }
  print_message("DAE Jacobian: N = %d (%d algebraic), %d entries checked, largest %.3g, %d bad\n",
                N, ie - il, checked, mx, bad);
  assert_true(mx > 1e5);
  assert_int_equal(bad, 0);
  SUNMatDestroy(J);
  vs_dynamic_destroy(&d);
  free(y);
  free(yp);
  free(rp);
  free(rm);
  free(Jd);
  free(q);
  fixture_free(&fx);
  SUNContext_Free(&ctx);
}

/* ... with fixed supports, and with the right or both pinned (their rotations free). */
static void test_dae_jacobian(void **state) {
  (void)state;
  dae_jacobian_check(VS_SUPPORT_FIXED, VS_SUPPORT_FIXED);
  dae_jacobian_check(VS_SUPPORT_FIXED, VS_SUPPORT_PINNED);
  dae_jacobian_check(VS_SUPPORT_PINNED, VS_SUPPORT_PINNED);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_support_displacement),
      cmocka_unit_test(test_jacobian_random_states),
      cmocka_unit_test(test_jacobian_pinned),
      cmocka_unit_test(test_jacobian_mortar),
      cmocka_unit_test(test_jacobian_after_commit),
      cmocka_unit_test(test_residual_is_energy_gradient),
      cmocka_unit_test(test_dae_jacobian),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
