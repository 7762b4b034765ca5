/* Tests of the mortared joint's normal law (joint.h, vs_joint_normal_mortar and
 * vs_joint_damage_update) against independent truth: the cracking moment of an elastic section
 * in closed form, the post-peak moment-rotation curve at constant N against the stress profile
 * integrated here by fine quadrature (the law written out again in the test), the work of a
 * joint pulled apart against G_f x area, the dry law bit for bit at f_t = 0, and the exact
 * derivatives against finite differences and against the energy. SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "check.h"
#include "voussoir/case.h"
#include "voussoir/joint.h"
#include "voussoir/run.h"
#include "voussoir/status.h"

/* The reference joint: k_n = 3 N/mm^3, b = 120 mm, t = 24 mm; mortar f_t = 0.1 MPa,
 * G_f = 0.05 N/mm (d0 = f_t / k_n = 0.033 mm, du = 2 G_f / f_t = 1 mm). */
static const double KN = 3e9;
static const double BD = 0.12;
static const double TL = 0.024;
static const double FT = 1e5;
static const double GF = 50.0;

static vs_joint_law mortar_law(void) {
  return (vs_joint_law){.kn = KN, .ks = 1.5e9, .mu = 0.7, .ft = FT, .gf = GF};
}

#include "test_rng.h"

/* ---- the law written out independently: stress (compression > 0) at penetration p ---- */
static double sigma_ref(double p, int cracked) {
  if (cracked) return p > 0 ? KN * p : 0.0;
  double d0 = FT / KN, du = 2 * GF / FT;
  if (p >= -d0) return KN * p;
  if (p > -du) return -FT * (1.0 - (-p - d0) / (du - d0)); /* from -f_t at d0 to 0 at du */
  return 0.0;
}

/* N and M of the profile p = a + w xi by the midpoint rule on n cells in each of the three
 * parts (cracked lengths ci, ce from the intrados and extrados edges, the intact part between),
 * so that no cell straddles a crack front. */
static void quad(double a, double w, double ci, double ce, int n, double *N, double *M) {
  double x0 = -0.5 * TL, xi = x0 + ci, xe = 0.5 * TL - ce;
  if (xi > 0.5 * TL) xi = 0.5 * TL;
  if (xe < xi) xe = xi;
  const double lo[3] = {x0, xi, xe}, hi[3] = {xi, xe, 0.5 * TL};
  double sn = 0, sm = 0;
  for (int part = 0; part < 3; part++) {
    double h = (hi[part] - lo[part]) / n;
    for (int i = 0; i < n && h > 0; i++) {
      double x = lo[part] + (i + 0.5) * h;
      double s = sigma_ref(a + w * x, part != 1);
      sn += s * h;
      sm += s * x * h;
    }
  }
  *N = BD * sn;
  *M = BD * sm;
}

/* The penetration a at which the joint carries N at slope w, by bisection on either the
 * program's N or the quadrature's (same bracket, same steps). */
static double a_at(double N, double w, int use_quad) {
  double lo = -0.5 * fabs(w) * TL - 1.0, hi = 0.5 * fabs(w) * TL + 1e-2;
  vs_joint_law law = mortar_law();
  const double crack[2] = {0, 0};
  for (int it = 0; it < 200; it++) {
    double mid = 0.5 * (lo + hi), Nm, Mm;
    if (use_quad) {
      quad(mid, w, 0, 0, 20000, &Nm, &Mm);
    } else {
      vs_normal_response r;
      vs_joint_normal_mortar(&law, BD, TL, mid, w, crack, &r);
      Nm = r.N;
    }
    if (Nm < N)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

/* ---- damage, written out independently: the committed states' openings kept as lines ---- */

/* The committed states (a, w): the largest opening at xi is kmax(xi) = max(d0, max over them of
 * -(a + w xi)), with no polyline, vertex or merge of the program's. */
typedef struct {
  int n;
  double a[256], w[256];
} history;

static void history_add(history *hs, double a, double w) {
  assert_true(hs->n < 256);
  hs->a[hs->n] = a;
  hs->w[hs->n++] = w;
}

static double kmax_ref(const history *hs, double x) {
  double k = FT / KN;
  for (int i = 0; i < hs->n; i++) k = fmax(k, -(hs->a[i] + hs->w[i] * x));
  return k;
}

/* Stress (compression > 0), its tangent in p and the potential at penetration p of a point
 * whose largest opening was k: compression kn p; below k the secant from the origin to the
 * softening line at k; from k to du the softening line; nothing beyond (or once k >= du). */
static void point_dmg(double p, double k, double *sig, double *tan, double *phi) {
  const double d0 = FT / KN, du = 2 * GF / FT, h = FT / (du - d0), dl = -p;
  if (k < d0) k = d0;
  const double rest = 0.5 * h * du * (du - fmin(k, du)); /* fracture energy still held */
  *sig = *tan = *phi = 0.0;
  if (p >= 0) {
    *sig = KN * p, *tan = KN, *phi = 0.5 * KN * p * p;
  } else if (k >= du) {
  } else if (dl < k) {
    const double S = (k == d0) ? KN : h * (du - k) / k;
    *sig = S * p, *tan = S, *phi = 0.5 * S * p * p;
  } else if (dl < du) {
    *sig = -h * (du - dl), *tan = -h, *phi = rest - 0.5 * h * (du - dl) * (du - dl);
  } else {
    *phi = rest;
  }
}

/* D(k): the energy a unit area dissipated once its largest opening was k, written out as the
 * work of the softening curve up to k less what the secant returns, by the trapezoid's exact
 * integral of the piecewise linear curve. */
static double dissipation_ref(double k) {
  const double d0 = FT / KN, du = 2 * GF / FT, h = FT / (du - d0);
  if (k <= d0) return 0.0;
  if (k >= du) return GF;
  const double work = 0.5 * FT * d0 + 0.5 * (FT + h * (du - k)) * (k - d0);
  return work - 0.5 * h * (du - k) / k * k * k;
}

/* N, M, N_a, N_w, M_w and the potential of the profile p = a + w xi with the history's damage,
 * by the midpoint rule on n cells (out[0..5]). */
static void quad_dmg(const history *hs, double a, double w, int n, double out[6]) {
  memset(out, 0, 6 * sizeof *out);
  const double dx = TL / n;
  for (int i = 0; i < n; i++) {
    const double x = -0.5 * TL + (i + 0.5) * dx;
    double sg, tg, ph;
    point_dmg(a + w * x, kmax_ref(hs, x), &sg, &tg, &ph);
    out[0] += sg * dx, out[1] += sg * x * dx;
    out[2] += tg * dx, out[3] += tg * x * dx, out[4] += tg * x * x * dx;
    out[5] += ph * dx;
  }
  for (int i = 0; i < 6; i++) out[i] *= BD;
}

/* f_t = c = 0 without cracks: the dry law, bit for bit; the whole joint cracked: the dry law to
 * rounding (the piecewise integration reproduces the closed form). */
static void test_dry_bit_for_bit(void **state) {
  (void)state;
  rng g = {0x9E3779B97F4A7C15ULL};
  vs_joint_law dry = {.kn = KN, .ks = 1.5e9, .mu = 0.7};
  vs_joint_law cracked = mortar_law();
  const double none[2] = {0, 0}, all[2] = {0.6 * TL, 0.5 * TL};
  for (int i = 0; i < 2000; i++) {
    double a = urand(&g, -2e-4, 2e-4), w = urand(&g, -2e-2, 2e-2);
    vs_normal_response r0, r1, r2;
    vs_joint_normal(KN, BD, TL, a, w, &r0);
    vs_joint_normal_mortar(&dry, BD, TL, a, w, none, &r1);
    assert_memory_equal(&r0, &r1, sizeof r0);
    vs_joint_normal_mortar(&cracked, BD, TL, a, w, all, &r2);
    double sN = KN * BD * TL * (fabs(a) + fabs(w) * TL);
    CHECK(r2.N, r0.N, 1e-12, 1e-12 * sN);
    CHECK(r2.M, r0.M, 1e-12, 1e-12 * sN * TL);
    CHECK(r2.N_a, r0.N_a, 1e-12, 1e-9 * KN * BD * TL);
    CHECK(r2.N_w, r0.N_w, 1e-12, 1e-9 * KN * BD * TL * TL);
    CHECK(r2.M_w, r0.M_w, 1e-12, 1e-9 * KN * BD * TL * TL * TL);
    CHECK(r2.energy, r0.energy, 1e-11, 1e-12 * sN * TL);
    CHECK(r2.contact, r0.contact, 1e-12, 1e-12 * TL);
  }
  /* and the joint evaluation with the new fields zero is the dry one (same bits) */
  vs_joint_geom jg = {0};
  jg.length = TL;
  jg.depth = BD;
  jg.nx = 1.0;
  jg.nz = 0.0;
  const double qa[3] = {0, 0, 0}, qb[3] = {-3e-5, 1e-6, 2e-3}, ra[2] = {0.1, 0}, rb[2] = {-0.1, 0};
  double ha[2], hb[2];
  vs_joint_half_angle(qa[2], ha);
  vs_joint_half_angle(qb[2], hb);
  vs_joint_law dry2 = dry;
  dry2.ft = dry2.c = dry2.gf = dry2.gc = 0.0;
  double f0[6], f1[6], K0[36], K1[36];
  vs_joint_eval_h(&jg, &dry, qa, qb, ha, hb, ra, rb, 0.0, NULL, f0, K0);
  vs_joint_eval_h(&jg, &dry2, qa, qb, ha, hb, ra, rb, 0.0, NULL, f1, K1);
  assert_memory_equal(f0, f1, sizeof f0);
  assert_memory_equal(K0, K1, sizeof K0);
}

/* Constant N, growing rotation: the extreme fibre reaches f_t at M_cr = N t / 6 + f_t b t^2 / 6
 * (elastic full section), and beyond it the program's M(w) at constant N follows the profile
 * integrated by quadrature. */
static void test_cracking_moment_and_post_peak(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  const double N = 500.0;
  /* the elastic section: a = N / (kn b t), intrados stress kn (a - w t/2) = -f_t */
  double a_el = N / (KN * BD * TL), w_cr = 2 * (a_el + FT / KN) / TL;
  double Mcr = N * TL / 6 + FT * BD * TL * TL / 6;
  double crack[2] = {0, 0};
  vs_normal_response r;
  vs_joint_normal_mortar(&law, BD, TL, a_el, w_cr, crack, &r);
  CHECK(r.N, N, 1e-12, 0);
  CHECK(r.M, Mcr, 1e-12, 0);
  /* just before: elastic, M = kn b t^3 w / 12 */
  vs_joint_normal_mortar(&law, BD, TL, a_el, 0.99 * w_cr, crack, &r);
  CHECK(r.M, KN * BD * TL * TL * TL * 0.99 * w_cr / 12, 1e-12, 0);
  CHECK(r.N_a, KN * BD * TL, 1e-12, 0);
  /* the post-peak curve, w up to 60 w_cr (the crack opens past du over part of the joint);
   * the program's state carries its crack fronts along (monotonic: they change nothing) */
  double Mmax = 0;
  int cracked_through = 0;
  for (int i = 0; i <= 60; i++) {
    double w = w_cr * (1.0 + i);
    double ap = a_at(N, w, 0), aq = a_at(N, w, 1), Nq, Mq;
    quad(aq, w, 0, 0, 20000, &Nq, &Mq);
    vs_joint_normal_mortar(&law, BD, TL, ap, w, crack, &r);
    assert_true(r.N_a > 0); /* N monotonic in a: the bisection's root is unique */
    CHECK(ap, aq, 1e-6, 1e-12);
    CHECK(r.M, Mq, 1e-6, 0);
    double dE = vs_joint_damage_update(&law, BD, TL, ap, w);
    memcpy(crack, law.crack, sizeof crack);
    assert_true(dE >= 0);
    if (crack[0] > 0) cracked_through = 1;
    if (r.M > Mmax) Mmax = r.M;
    /* the moment never exceeds the no-tension bound plus what f_t over the section can add */
    assert_true(r.M <= N * TL / 2 + FT * BD * TL * TL / 8 + 1e-9);
  }
  assert_true(cracked_through);
  assert_true(Mmax >= Mcr);
  /* the damage is irreversible: back at w = 0 under the same N, the cracked intrados part
   * carries no tension and the process zone unloads along its secant (quadrature over the
   * largest openings the loop's states reached, kept here) */
  history hs = {0};
  for (int i = 0; i <= 60; i++) history_add(&hs, a_at(N, w_cr * (1.0 + i), 0), w_cr * (1.0 + i));
  double q[6];
  quad_dmg(&hs, -1e-4, 0.0, 200000, q);
  vs_joint_normal_mortar(&law, BD, TL, -1e-4, 0.0, crack, &r);
  CHECK(r.N, q[0], 1e-6, 1e-9);
  CHECK(r.M, q[1], 1e-6, 1e-9);
  assert_true(r.N > -FT * BD * TL * (1 - crack[0] / TL) + 1e-9);
}

/* Pure tension: the work of the force along the opening, from closed to beyond du, is G_f b t;
 * the crack update dissipates exactly that and the joint carries no tension afterwards. */
static void test_tension_dissipates_gf(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  double du = 2 * GF / FT, d0 = FT / KN;
  const int n = 200000;
  double dmax = 1.2 * du, work = 0, Fprev = 0, Fpeak = 0;
  double crack[2] = {0, 0};
  vs_normal_response r;
  for (int i = 1; i <= n; i++) {
    double d = dmax * i / n;
    vs_joint_normal_mortar(&law, BD, TL, -d, 0.0, crack, &r);
    double F = -r.N; /* tension carried */
    work += 0.5 * (F + Fprev) * (dmax / n);
    Fprev = F;
    if (F > Fpeak) Fpeak = F;
  }
  CHECK(work, GF * BD * TL, 1e-6, 0);
  CHECK(Fpeak, FT * BD * TL, 1e-4, 0);
  vs_joint_normal_mortar(&law, BD, TL, -d0, 0.0, crack, &r);
  CHECK(-r.N, FT * BD * TL, 1e-12, 0);
  /* the potential at full separation is the work done: G_f b t */
  vs_joint_normal_mortar(&law, BD, TL, -dmax, 0.0, crack, &r);
  CHECK(r.energy, GF * BD * TL, 1e-12, 0);
  double dE = vs_joint_damage_update(&law, BD, TL, -dmax, 0.0);
  memcpy(crack, law.crack, sizeof crack);
  CHECK(dE, GF * BD * TL, 1e-12, 0);
  vs_joint_normal_mortar(&law, BD, TL, -d0, 0.0, crack, &r);
  CHECK(r.N, 0.0, 0, 0);
  CHECK(r.energy, 0.0, 0, 0);
  /* closing again: compression as the dry joint */
  vs_normal_response rd;
  vs_joint_normal_mortar(&law, BD, TL, 1e-5, 0.0, crack, &r);
  vs_joint_normal(KN, BD, TL, 1e-5, 0.0, &rd);
  CHECK(r.N, rd.N, 1e-12, 0);
  /* a second update dissipates nothing */
  CHECK(vs_joint_damage_update(&law, BD, TL, -dmax, 0.0), 0.0, 0, 0);
}

/* A joint under uniform opening (w = 0) loaded into the softening to k, unloaded to closed and
 * reloaded: on unloading and reloading below k the stress follows the secant h (du - k) / k x
 * opening, beyond k the softening line; the work over the cycle, and the damage update's
 * return, are D(k) b t (the softening curve's work up to k less the secant's, in closed form),
 * and opening on past du dissipates G_f b t in all. */
static void test_secant_cycle(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  const double d0 = FT / KN, du = 2 * GF / FT, h = FT / (du - d0), A = BD * TL;
  const double k = 0.4 * du, S = h * (du - k) / k;
  const int n = 4000;
  double work = 0, dissipated = 0, Fprev = 0, dprev = 0;
  vs_normal_response r;
  /* 0 -> k -> 0 -> 1.5 k -> 1.2 du, committing every state (as a path does) */
  const double legs[5] = {0, k, 0, 1.5 * k, 1.2 * du};
  for (int leg = 0; leg < 4; leg++)
    for (int i = 1; i <= n; i++) {
      const double d = legs[leg] + (legs[leg + 1] - legs[leg]) * i / n;
      vs_joint_normal_mortar(&law, BD, TL, -d, 0.0, law.crack, &r);
      const double F = -r.N; /* the tension carried */
      work += 0.5 * (F + Fprev) * (d - dprev);
      Fprev = F, dprev = d;
      if (leg == 1 || (leg == 2 && d < k)) CHECK(F, S * d * A, 1e-11, 1e-12 * FT * A);
      if (leg == 1 || (leg == 2 && d < k)) CHECK(r.energy, 0.5 * S * d * d * A, 1e-11, 0);
      if (leg == 2 && d > k * (1 + 1e-9)) CHECK(F, h * (du - d) * A, 1e-11, 0);
      if (leg == 0 && d > d0) CHECK(F, h * (du - d) * A, 1e-11, 0);
      dissipated += vs_joint_damage_update(&law, BD, TL, -d, 0.0);
      if (leg == 1 && i == n) {
        /* back at closed: the cycle's work is what the damage dissipated, D(k) b t */
        CHECK(work, dissipation_ref(k) * A, 1e-6, 0); /* the trapezoid across the peak */
        CHECK(dissipated, dissipation_ref(k) * A, 1e-12, 0);
        CHECK(dissipated, GF * (k - d0) / (du - d0) * A, 1e-12, 0);
        CHECK(r.energy, 0.0, 0, 0);
      }
    }
  CHECK(work, GF * A, 1e-6, 0);
  CHECK(dissipated, GF * A, 1e-12, 0);
  CHECK(fmin(TL, law.crack[0] + law.crack[1]), TL, 1e-12, 0); /* each edge's front across */
  vs_joint_normal_mortar(&law, BD, TL, -0.5 * k, 0.0, law.crack, &r);
  CHECK(r.N, 0.0, 0, 0);
}

/* Random histories of committed states (several rotations, so that the envelope has several
 * pieces, cracked-through parts and process zones on either edge): the envelope against the
 * committed lines' maximum kept here, each update's dissipation against the quadrature of
 * D(k_new) - D(k_old), and at random states N, M, N_a, N_w, M_w and the potential against the
 * fine quadrature of the law written out here; where no damaged point unloads, the forces are
 * the undamaged law's and the potential lower by the dissipation. */
static void test_damaged_profile(void **state) {
  (void)state;
  rng g = {0xC0FFEE1234ULL};
  const double d0 = FT / KN, du = 2 * GF / FT;
  const double sN = KN * BD * TL * 1e-4;
  int secant_states = 0;
  for (int trial = 0; trial < 150; trial++) {
    vs_joint_law law = mortar_law();
    history hs = {0};
    const int nc = 1 + trial % 6;
    for (int c = 0; c < nc; c++) {
      const double a = urand(&g, -0.8 * du, 1e-5), w = urand(&g, -0.1, 0.1);
      const int nq = 20000;
      double dq = 0;
      for (int i = 0; i < nq; i++) {
        const double x = -0.5 * TL + (i + 0.5) * TL / nq;
        const double k_old = kmax_ref(&hs, x), k_new = fmax(k_old, -(a + w * x));
        dq += BD * (TL / nq) * (dissipation_ref(k_new) - dissipation_ref(k_old));
      }
      history_add(&hs, a, w);
      const double dE = vs_joint_damage_update(&law, BD, TL, a, w);
      CHECK(dE, dq, 1e-6, 1e-9 * GF * BD * TL);
    }
    assert_int_equal(law.env_merged, 0);
    assert_true(law.env_n <= VS_JOINT_ENV_MAX);
    /* the envelope is the lines' maximum (where not cracked through: beyond du it may be cut) */
    for (int i = 0; i <= 200 && law.env_n >= 2; i++) {
      const double x = -0.5 * TL + TL * i / 200.0;
      int j = 0;
      while (j + 2 < law.env_n && x > law.env_x[j + 1]) j++;
      const double f = (x - law.env_x[j]) / (law.env_x[j + 1] - law.env_x[j]);
      const double k = law.env_k[j] + f * (law.env_k[j + 1] - law.env_k[j]);
      CHECK(fmin(k, du), fmin(kmax_ref(&hs, x), du), 1e-10, 1e-14);
    }
    for (int s = 0; s < 4; s++) {
      const double a = urand(&g, -1.2 * du, 2e-4), w = urand(&g, -0.12, 0.12);
      vs_normal_response r;
      vs_joint_normal_mortar(&law, BD, TL, a, w, law.crack, &r);
      double q[6];
      quad_dmg(&hs, a, w, 40000, q);
      CHECK(r.N, q[0], 1e-5, 1e-6 * sN);
      CHECK(r.M, q[1], 1e-5, 1e-6 * sN * TL);
      CHECK(r.N_a, q[2], 1e-3, 1e-3 * KN * BD * TL);
      CHECK(r.N_w, q[3], 1e-3, 1e-3 * KN * BD * TL * TL);
      CHECK(r.M_w, q[4], 1e-3, 1e-3 * KN * BD * TL * TL * TL);
      CHECK(r.energy, q[5], 1e-5, 1e-7 * GF * BD * TL);
      int unloading = 0;
      for (int i = 0; i < 100; i++) {
        const double x = -0.5 * TL + TL * (i + 0.5) / 100, dl = -(a + w * x), k = kmax_ref(&hs, x);
        unloading |= k > d0 && k < du && dl > 0 && dl < k;
      }
      secant_states += unloading;
      /* the derivatives against central differences, N and M against the potential's gradient */
      vs_normal_response rp, rm;
      const double ha = 1e-10, hw = 1e-10 / TL;
      vs_joint_normal_mortar(&law, BD, TL, a + ha, w, law.crack, &rp);
      vs_joint_normal_mortar(&law, BD, TL, a - ha, w, law.crack, &rm);
      CHECK(r.N_a, (rp.N - rm.N) / (2 * ha), 1e-5, 1e-6 * KN * BD * TL);
      CHECK(r.N_w, (rp.M - rm.M) / (2 * ha), 1e-5, 1e-6 * KN * BD * TL * TL);
      CHECK(r.N, (rp.energy - rm.energy) / (2 * ha), 1e-5, 1e-6 * sN);
      vs_joint_normal_mortar(&law, BD, TL, a, w + hw, law.crack, &rp);
      vs_joint_normal_mortar(&law, BD, TL, a, w - hw, law.crack, &rm);
      CHECK(r.N_w, (rp.N - rm.N) / (2 * hw), 1e-5, 1e-6 * KN * BD * TL * TL);
      CHECK(r.M_w, (rp.M - rm.M) / (2 * hw), 1e-5, 1e-6 * KN * BD * TL * TL * TL);
      CHECK(r.M, (rp.energy - rm.energy) / (2 * hw), 1e-5, 1e-6 * sN * TL);
    }
  }
  /* opening further than every committed state wherever it is damaged (a hinge opening on,
   * its commits at one slope, the last one unloading), nothing unloads: the forces are those of
   * the undamaged law, the potential lower by the dissipation D(kmax) */
  const double w0 = 0.05, as[3] = {-0.1 * du, -0.3 * du, -0.2 * du};
  vs_joint_law law = mortar_law(), fresh = mortar_law();
  history hs = {0};
  for (int c = 0; c < 3; c++) {
    vs_joint_damage_update(&law, BD, TL, as[c], w0);
    history_add(&hs, as[c], w0);
  }
  const double none[2] = {0, 0};
  for (int s = 0; s < 5; s++) {
    const double a = -0.3 * du - 0.1 * du * s;
    vs_normal_response r, r0;
    vs_joint_normal_mortar(&law, BD, TL, a, w0, law.crack, &r);
    vs_joint_normal_mortar(&fresh, BD, TL, a, w0, none, &r0);
    CHECK(r.N, r0.N, 1e-12, 1e-12 * sN);
    CHECK(r.M, r0.M, 1e-12, 1e-12 * sN * TL);
    CHECK(r.N_a, r0.N_a, 1e-12, 1e-12 * KN * BD * TL);
    CHECK(r.N_w, r0.N_w, 1e-12, 1e-12 * KN * BD * TL * TL);
    CHECK(r.M_w, r0.M_w, 1e-12, 1e-12 * KN * BD * TL * TL * TL);
    double dq = 0;
    for (int i = 0; i < 20000; i++)
      dq += BD * (TL / 20000) * dissipation_ref(kmax_ref(&hs, -0.5 * TL + (i + 0.5) * TL / 20000));
    CHECK(r0.energy - r.energy, dq, 1e-6, 1e-12 * GF * BD * TL);
  }
  assert_true(secant_states >= 100);
}

/* A hinge whose neutral axis wanders: every commit's line is tangent to a convex curve of
 * openings, so that the envelope gains a vertex each time and passes the cap. Past it the
 * merges keep it convex, within the cap and above the lines' maximum (conservative: more
 * damage, never less), and each update still dissipates (the potential only drops). */
static void test_envelope_cap(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  history hs = {0};
  const double du = 2 * GF / FT;
  double total = 0;
  for (int c = 0; c < 60; c++) {
    /* the tangent at xc of the opening f(x) = 0.9 du ((t/2 - x) / t)^2 (0 at the extrados) */
    const double xc = 0.5 * TL - TL * (0.1 + 0.8 * c / 59.0);
    const double u = (0.5 * TL - xc) / TL, f = 0.9 * du * u * u, fp = -1.8 * du * u / TL;
    const double w = -fp, a = -(f - fp * xc); /* opening -(a + w x) = f + fp (x - xc) */
    history_add(&hs, a, w);
    const double dE = vs_joint_damage_update(&law, BD, TL, a, w);
    assert_true(dE >= 0);
    total += dE;
    assert_true(law.env_n <= VS_JOINT_ENV_MAX && law.env_n >= 2);
    for (int j = 1; j + 1 < law.env_n; j++) { /* convex: slopes non-decreasing */
      const double s0 = (law.env_k[j] - law.env_k[j - 1]) / (law.env_x[j] - law.env_x[j - 1]);
      const double s1 = (law.env_k[j + 1] - law.env_k[j]) / (law.env_x[j + 1] - law.env_x[j]);
      assert_true(s1 >= s0 - 1e-9);
    }
    for (int i = 0; i <= 400; i++) {
      const double x = -0.5 * TL + TL * i / 400.0;
      int j = 0;
      while (j + 2 < law.env_n && x > law.env_x[j + 1]) j++;
      const double fr = (x - law.env_x[j]) / (law.env_x[j + 1] - law.env_x[j]);
      const double k = law.env_k[j] + fr * (law.env_k[j + 1] - law.env_k[j]);
      assert_true(k >= fmin(kmax_ref(&hs, x), du) - 1e-12 * du);
    }
  }
  print_message("60 commits: %d vertices, %d merges, dissipated %.6g J\n", law.env_n,
                law.env_merged, total);
  assert_true(law.env_merged > 0);
}

/* The exact derivatives against central differences, and N, M against the energy's gradient,
 * at random states with random crack fronts. */
static void test_derivatives(void **state) {
  (void)state;
  rng g = {0x1234567ULL};
  vs_joint_law law = mortar_law();
  double du = 2 * GF / FT;
  for (int i = 0; i < 3000; i++) {
    double a = urand(&g, -1.5 * du, 2e-4), w = urand(&g, -0.15, 0.15);
    double crack[2] = {0, 0};
    if (i % 3 == 1) crack[0] = urand(&g, 0, TL);
    if (i % 3 == 2) crack[1] = urand(&g, 0, 0.5 * TL);
    vs_normal_response r, rp, rm;
    vs_joint_normal_mortar(&law, BD, TL, a, w, crack, &r);
    double ha = 1e-9, hw = 1e-9 / TL;
    double sN = KN * BD * TL * 1e-4;
    vs_joint_normal_mortar(&law, BD, TL, a + ha, w, crack, &rp);
    vs_joint_normal_mortar(&law, BD, TL, a - ha, w, crack, &rm);
    CHECK(r.N_a, (rp.N - rm.N) / (2 * ha), 1e-5, 1e-6 * KN * BD * TL);
    CHECK(r.N_w, (rp.M - rm.M) / (2 * ha), 1e-5, 1e-6 * KN * BD * TL * TL);
    CHECK(r.N, (rp.energy - rm.energy) / (2 * ha), 1e-5, 1e-6 * sN);
    vs_joint_normal_mortar(&law, BD, TL, a, w + hw, crack, &rp);
    vs_joint_normal_mortar(&law, BD, TL, a, w - hw, crack, &rm);
    CHECK(r.N_w, (rp.N - rm.N) / (2 * hw), 1e-5, 1e-6 * KN * BD * TL * TL);
    CHECK(r.M_w, (rp.M - rm.M) / (2 * hw), 1e-5, 1e-6 * KN * BD * TL * TL * TL);
    CHECK(r.M, (rp.energy - rm.energy) / (2 * hw), 1e-5, 1e-6 * sN * TL);
  }
}

/* Shear with cohesion: under constant N the joint slips first at T = c A + mu N; the cohesion
 * softens over the slip 2 G_c / c, the work of T along the plastic slip is mu N x slip + G_c x
 * area; afterwards it slides at mu N. A cracked part adds no cohesion, tension lowers the limit. */
static void test_shear_cohesion(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  law.c = 2e5;  /* 0.2 MPa */
  law.gc = 500; /* 0.5 N/mm: kappa_u = 5 mm */
  const double N = 500.0, kst = law.ks * BD * TL, ku = 2 * law.gc / law.c;
  const double none[2] = {0, 0};
  double peak = law.c * BD * TL + law.mu * N, s_star = peak / kst;
  vs_shear_response r;
  vs_joint_shear_mortar(&law, BD, TL, none, N, s_star * (1 - 1e-9), 0, 0, &r);
  assert_int_equal(r.sliding, 0);
  CHECK(r.T, peak, 2e-9, 0);
  vs_joint_shear_mortar(&law, BD, TL, none, N, s_star * (1 + 1e-9), 0, 0, &r);
  assert_int_equal(r.sliding, 1);
  CHECK(r.T, peak, 2e-9, 0);
  /* monotonic slip to 1.5 kappa_u in fine steps, each committed */
  double sp = 0, kap = 0, work = 0, Tprev = 0, spprev = 0;
  const int n = 100000;
  double smax = 1.5 * ku + s_star;
  for (int i = 1; i <= n; i++) {
    double s = smax * i / n;
    vs_joint_shear_mortar(&law, BD, TL, none, N, s, sp, kap, &r);
    work += 0.5 * (r.T + Tprev) * (r.slip_p - spprev);
    Tprev = r.T;
    spprev = r.slip_p;
    sp = r.slip_p;
    kap = r.kappa;
  }
  CHECK(kap, sp, 1e-12, 0);
  CHECK(r.T, law.mu * N, 1e-12, 0);
  CHECK(work, law.mu * N * sp + law.gc * BD * TL, 1e-6, 0);
  /* cracked through over 10 mm: the cohesion acts on the bonded 14 mm only */
  const double cr[2] = {0.004, 0.006};
  double lim = law.c * BD * (TL - 0.010) + law.mu * N;
  vs_joint_shear_mortar(&law, BD, TL, cr, N, lim / kst * (1 + 1e-9), 0, 0, &r);
  assert_int_equal(r.sliding, 1);
  CHECK(r.T, lim, 2e-9, 0);
  /* tension lowers the limit; enough of it removes it */
  lim = law.c * BD * TL - law.mu * 100.0;
  vs_joint_shear_mortar(&law, BD, TL, none, -100.0, lim / kst * (1 + 1e-9), 0, 0, &r);
  assert_int_equal(r.sliding, 1);
  CHECK(r.T, lim, 2e-9, 0);
  vs_joint_shear_mortar(&law, BD, TL, none, -1e6, 1.0, 0, 0, &r);
  CHECK(r.T, 0.0, 0, 0);
  CHECK(r.T_N, 0.0, 0, 0);
  /* c = 0: the dry joint's Coulomb return mapping (vs_joint_eval_h) */
  vs_joint_law dry = {.kn = KN, .ks = 1.5e9, .mu = 0.7};
  vs_joint_geom jg = {0};
  jg.length = TL;
  jg.depth = BD;
  jg.nx = 1.0;
  const double qa[3] = {0, 0, 0}, ra[2] = {0, 0}, rb[2] = {0, 0};
  double ha[2], hb[2];
  vs_joint_half_angle(0.0, ha);
  vs_joint_half_angle(0.0, hb);
  rng g = {77};
  for (int i = 0; i < 1000; i++) {
    const double qb[3] = {-urand(&g, 0, 1e-4), urand(&g, -1e-4, 1e-4), 0};
    double sp_old = urand(&g, -5e-5, 5e-5);
    vs_joint_state st;
    vs_joint_eval_h(&jg, &dry, qa, qb, ha, hb, ra, rb, sp_old, &st, NULL, NULL);
    vs_joint_shear_mortar(&dry, BD, TL, none, st.N, st.slip, sp_old, 0, &r);
    assert_int_equal(r.sliding, st.sliding);
    CHECK(r.T, st.T, 1e-12, 1e-12 * fabs(st.N));
    CHECK(r.slip_p, st.slip_p, 1e-12, 1e-18);
  }
}

/* The shear's consistent tangent against central differences in the slip and in N. */
static void test_shear_derivatives(void **state) {
  (void)state;
  vs_joint_law law = mortar_law();
  law.c = 2e5;
  law.gc = 500;
  const double ku = 2 * law.gc / law.c;
  rng g = {4242};
  const double none[2] = {0, 0};
  int sliding = 0;
  for (int i = 0; i < 3000; i++) {
    double N = urand(&g, -800, 2000), sp_old = urand(&g, -1e-3, 1e-3);
    double kap = urand(&g, 0, 1.2 * ku), s = sp_old + urand(&g, -3e-4, 3e-4);
    vs_shear_response r, p, m;
    vs_joint_shear_mortar(&law, BD, TL, none, N, s, sp_old, kap, &r);
    sliding += r.sliding;
    double hs = 1e-12, hN = 1e-6;
    vs_joint_shear_mortar(&law, BD, TL, none, N, s + hs, sp_old, kap, &p);
    vs_joint_shear_mortar(&law, BD, TL, none, N, s - hs, sp_old, kap, &m);
    if (p.sliding != m.sliding || (p.T == 0) != (m.T == 0)) continue; /* astride a kink */
    double kst = law.ks * BD * TL;
    CHECK(r.T_s, (p.T - m.T) / (2 * hs), 1e-4, 1e-4 * kst);
    vs_joint_shear_mortar(&law, BD, TL, none, N + hN, s, sp_old, kap, &p);
    vs_joint_shear_mortar(&law, BD, TL, none, N - hN, s, sp_old, kap, &m);
    if (p.sliding != m.sliding || (p.T == 0) != (m.T == 0)) continue; /* astride a kink */
    CHECK(r.T_N, (p.T - m.T) / (2 * hN), 1e-5, 1e-6);
  }
  assert_true(sliding > 500);
}

/* A case's mortar keys reach the def in SI and a run takes them; out-of-range values are
 * refused by name with the allowed range, by the case and by the run's def alike. */
static void test_run_mortar_ranges(void **state) {
  (void)state;
  vs_case c;
  vs_error err;
  vs_case_defaults(&c);
  c.tensile_MPa = 0.1;
  c.cohesion_MPa = 0.2;
  c.gf_N_mm = 0.05;
  c.gc_N_mm = 0.5;
  vs_run_def d;
  vs_case_to_def(&c, &d);
  CHECK(d.joints.ft, 1e5, 1e-15, 0);
  CHECK(d.joints.c, 2e5, 1e-15, 0);
  CHECK(d.joints.gf, 50.0, 1e-15, 0);
  CHECK(d.joints.gc, 500.0, 1e-15, 0);
  vs_error_clear(&err);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_run *r = NULL;
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_OK);
  vs_run_destroy(&r);
  /* G_f below f_t^2 / (2 k_n) (= 0.1^2 / 6 N/mm here): refused, naming the key */
  c.gf_N_mm = 0.9 * 0.1 * 0.1 / (2.0 * c.kn_N_mm3);
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "joints.gf_N_mm"));
  vs_case_to_def(&c, &d);
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_ERR_INVALID);
  assert_null(r);
  assert_non_null(strstr(err.msg, "joints.gf_N_mm"));
  /* G_c below c^2 / (2 k_s) */
  c.gf_N_mm = 0.05;
  c.gc_N_mm = 0.9 * 0.2 * 0.2 / (2.0 * c.ks_ratio * c.kn_N_mm3);
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "joints.gc_N_mm"));
  vs_case_to_def(&c, &d);
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "joints.gc_N_mm"));
  /* a negative strength in a library caller's def */
  vs_case_defaults(&c);
  vs_case_to_def(&c, &d);
  d.joints.ft = -1.0;
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "joints.tensile_MPa"));
  assert_non_null(strstr(err.msg, "allowed"));
  /* dry: the same def runs */
  vs_case_defaults(&c);
  vs_case_to_def(&c, &d);
  assert_int_equal(d.joints.ft, 0.0);
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_OK);
  vs_run_destroy(&r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_run_mortar_ranges),
      cmocka_unit_test(test_dry_bit_for_bit),
      cmocka_unit_test(test_cracking_moment_and_post_peak),
      cmocka_unit_test(test_tension_dissipates_gf),
      cmocka_unit_test(test_secant_cycle),
      cmocka_unit_test(test_damaged_profile),
      cmocka_unit_test(test_envelope_cap),
      cmocka_unit_test(test_derivatives),
      cmocka_unit_test(test_shear_cohesion),
      cmocka_unit_test(test_shear_derivatives),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
