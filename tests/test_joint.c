/* Tests of the joint law (joint.h) against independent closed forms: the no-tension Winkler
 * joint integrated by hand, exact rigid-body kinematics written out here, objectivity, energy
 * consistency of the forces and tangent, Newton's third law and Coulomb friction. SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>

#include "check.h"
#include "joint_reference.h"
#include "voussoir/joint.h"

/* The reference joint: k_n = 3 N/mm^3, b = 120 mm, t = 24 mm; k_s = 0.5 k_n; mu = 0.7. */
static const double KN = 3e9;
static const double BD = 0.12;
static const double TL = 0.024;
static const double KS = 1.5e9;
static const double MU = 0.7;

#include "test_rng.h"

/* ---- closed forms of the Winkler joint (derived in the test, not taken from the library) ----
 * p(xi) = a + w xi on xi in [-t/2, t/2]; sigma = kn <p>.
 * Full contact (a >= |w| t/2): N = kn b t a, M = kn b t^3 w / 12, E = kn b (a^2 t + w^2 t^3/12)/2.
 * Partial (|a| < |w| t/2): e = a + |w| t/2 is the largest penetration, c = e/|w| the contact
 * length; N = kn b |w| c^2 / 2, M = sign(w) N (t/2 - c/3) (the triangle's centroid),
 * E = kn b w^2 c^3 / 6, N_a = kn b c, N_w = sign(w) kn b c (t - c)/2,
 * M_w = kn b (t^3/8 - (t/2 - c)^3)/3 (integral of xi^2 over the contact). Open: all zero. */
typedef struct {
  double N, M, contact, energy, N_a, N_w, M_w;
} closed_normal;

static void winkler(double a, double w, closed_normal *c) {
  double aw = fabs(w);
  double e = a + 0.5 * aw * TL;
  double sg = w < 0 ? -1.0 : 1.0;
  if (e <= 0) {
    *c = (closed_normal){0, 0, 0, 0, 0, 0, 0};
  } else if (a - 0.5 * aw * TL >= 0) {
    c->N = KN * BD * TL * a;
    c->M = KN * BD * TL * TL * TL * w / 12;
    c->contact = TL;
    c->energy = 0.5 * KN * BD * (a * a * TL + w * w * TL * TL * TL / 12);
    c->N_a = KN * BD * TL;
    c->N_w = 0;
    c->M_w = KN * BD * TL * TL * TL / 12;
  } else {
    double cl = e / aw;
    double x0 = 0.5 * TL - cl;
    c->N = 0.5 * KN * BD * aw * cl * cl;
    c->M = sg * c->N * (0.5 * TL - cl / 3);
    c->contact = cl;
    c->energy = KN * BD * w * w * cl * cl * cl / 6;
    c->N_a = KN * BD * cl;
    c->N_w = sg * 0.5 * KN * BD * cl * (TL - cl);
    c->M_w = KN * BD * (TL * TL * TL / 8 - x0 * x0 * x0) / 3;
  }
}

/* Penetration a at the centre that makes the joint carry normal force N at gap slope w. */
static double a_for_N(double N, double w) {
  double aw = fabs(w);
  double wlift = 2 * N / (KN * BD * TL * TL);
  if (aw <= wlift) return N / (KN * BD * TL);
  double e = sqrt(2 * N * aw / (KN * BD));
  return e - 0.5 * aw * TL;
}

/* ---------------------------------- vs_joint_normal ---------------------------------- */

/* At fixed N, M(theta) is linear up to the lift-off slope, then N (t/2 - c/3) with
 * c = sqrt(2N/(kn b theta)). */
static void test_normal_fixed_N(void **state) {
  (void)state;
  const double Ns[] = {0.5, 10.0, 3000.0};
  const double fr[] = {0.0, 0.25, 0.5, 0.999, 1.0, 1.001, 1.5, 2.0, 10.0, 1000.0};
  for (size_t i = 0; i < sizeof Ns / sizeof Ns[0]; i++) {
    double N = Ns[i];
    double wlift = 2 * N / (KN * BD * TL * TL);
    for (size_t j = 0; j < sizeof fr / sizeof fr[0]; j++) {
      for (int sg = -1; sg <= 1; sg += 2) {
        double w = sg * fr[j] * wlift;
        double a = a_for_N(N, w);
        vs_normal_response r;
        vs_joint_normal(KN, BD, TL, a, w, &r);
        CHECK(r.N, N, 1e-12, 0);
        double Mw, cw;
        if (fr[j] <= 1.0) {
          Mw = KN * BD * TL * TL * TL * w / 12;
          cw = TL;
        } else {
          cw = sqrt(2 * N / (KN * BD * fabs(w)));
          Mw = sg * N * (TL / 2 - cw / 3);
        }
        CHECK(r.M, Mw, 1e-12, 1e-14 * N * TL);
        CHECK(r.contact, cw, 1e-12, 0);
        closed_normal c;
        winkler(a, w, &c);
        CHECK(r.energy, c.energy, 1e-11, 0);
        CHECK(r.N_a, c.N_a, 1e-11, 0);
        CHECK(r.N_w, c.N_w, 1e-11, 1e-12 * KN * BD * TL * TL);
        CHECK(r.M_w, c.M_w, 1e-11, 0);
      }
    }
  }
}

/* M as a function of theta at fixed N is C1 at the lift-off slope: value N t / 6 and slope
 * kn b t^3 / 12 from both sides. dM/dtheta at fixed N = M_w - N_w^2 / N_a (M_a = N_w). */
static double M_at_N(double N, double w, double *dMdw_N) {
  vs_normal_response r;
  vs_joint_normal(KN, BD, TL, a_for_N(N, w), w, &r);
  if (dMdw_N) *dMdw_N = r.M_w - r.N_w * r.N_w / r.N_a;
  return r.M;
}

static void test_normal_C1_at_lift(void **state) {
  (void)state;
  double N = 25.0;
  double wl = 2 * N / (KN * BD * TL * TL);
  double slope = KN * BD * TL * TL * TL / 12;
  double dl, dr;
  double Ml = M_at_N(N, wl * (1 - 1e-9), &dl);
  double Mr = M_at_N(N, wl * (1 + 1e-9), &dr);
  CHECK(Ml, N * TL / 6, 1e-8, 0);
  CHECK(Mr, N * TL / 6, 1e-8, 0);
  CHECK(dl, slope, 1e-7, 0);
  CHECK(dr, slope, 1e-7, 0);
  /* One-sided differences of M itself (not of the library's derivatives). */
  double h = 1e-6 * wl;
  double M0 = M_at_N(N, wl, NULL);
  CHECK((M0 - M_at_N(N, wl - h, NULL)) / h, slope, 1e-5, 0);
  CHECK((M_at_N(N, wl + h, NULL) - M0) / h, slope, 1e-5, 0);
  /* Beyond lift-off the closed-form slope is N c / (6 w); second derivative -N c / (4 w^2). */
  double w2 = 3 * wl, d2;
  M_at_N(N, w2, &d2);
  double c2 = sqrt(2 * N / (KN * BD * w2));
  CHECK(d2, N * c2 / (6 * w2), 1e-10, 0);
}

static void test_normal_symmetry_and_open(void **state) {
  (void)state;
  const double as[] = {2e-5, 1e-6, -3e-6, 0.0};
  const double ws[] = {1e-4, 1e-3, 2e-3, 5e-4};
  for (size_t i = 0; i < 4; i++) {
    vs_normal_response p, m;
    vs_joint_normal(KN, BD, TL, as[i], ws[i], &p);
    vs_joint_normal(KN, BD, TL, as[i], -ws[i], &m);
    CHECK(m.N, p.N, 1e-14, 0);
    CHECK(m.M, -p.M, 1e-14, 0);
    CHECK(m.contact, p.contact, 1e-14, 0);
    CHECK(m.energy, p.energy, 1e-14, 0);
    CHECK(m.N_a, p.N_a, 1e-14, 0);
    CHECK(m.N_w, -p.N_w, 1e-14, 1e-300);
    CHECK(m.M_w, p.M_w, 1e-14, 0);
  }
  /* Fully open: a + |w| t/2 <= 0, including exactly 0 and w = 0 with a <= 0. At a = w = 0
   * (faces just touching) the law has a kink (N_a jumps from 0 to kn b t) and the contact
   * length is a convention (the library counts it as closed, contact = t), so only the
   * forces and energy are checked there. */
  const double oa[] = {-1e-5, -1e-5, -1.2e-5, 0.0, -1e-9, -1e-3};
  const double ow[] = {1e-4, -1e-4, 1e-3, 0.0, 0.0, 0.05};
  for (size_t i = 0; i < sizeof oa / sizeof oa[0]; i++) {
    vs_normal_response r;
    vs_joint_normal(KN, BD, TL, oa[i], ow[i], &r);
    double sc = KN * BD * TL * TL * 1e-3 * 1e-12; /* negligible force */
    CHECK(r.N, 0, 0, sc);
    CHECK(r.M, 0, 0, sc * TL);
    CHECK(r.energy, 0, 0, sc * 1e-6);
    if (ow[i] == 0.0 && oa[i] == 0.0) continue;
    CHECK(r.contact, 0, 0, 1e-12 * TL);
    CHECK(r.N_a, 0, 0, 1e-12 * KN * BD * TL);
    CHECK(r.N_w, 0, 0, 1e-12 * KN * BD * TL * TL);
    CHECK(r.M_w, 0, 0, 1e-12 * KN * BD * TL * TL * TL);
  }
}

/* Derivatives against central differences of N and M, in full contact, partial contact (both
 * signs of w) and fully open. The closed-form values are checked too, and M_a = N_w. */
static void test_normal_derivatives(void **state) {
  (void)state;
  const double as[] = {1e-5, 1e-6, -5e-6, 4e-6, -2e-5};
  const double ws[] = {1e-4, 1e-3, -1e-3, -2e-4, 1e-3};
  for (size_t i = 0; i < sizeof as / sizeof as[0]; i++) {
    double a = as[i], w = ws[i];
    vs_normal_response r, p, m;
    vs_joint_normal(KN, BD, TL, a, w, &r);
    closed_normal c;
    winkler(a, w, &c);
    double Nsc = KN * BD * TL * (fabs(a) + fabs(w) * TL);
    CHECK(r.N, c.N, 1e-12, 1e-14 * Nsc);
    CHECK(r.M, c.M, 1e-12, 1e-14 * Nsc * TL);
    CHECK(r.contact, c.contact, 1e-12, 1e-14 * TL);
    CHECK(r.energy, c.energy, 1e-11, 1e-16 * Nsc * TL);

    double ha = 1e-9, hw = 1e-6 * fabs(w);
    vs_joint_normal(KN, BD, TL, a + ha, w, &p);
    vs_joint_normal(KN, BD, TL, a - ha, w, &m);
    double Na = (p.N - m.N) / (2 * ha), Ma = (p.M - m.M) / (2 * ha);
    double Ea = (p.energy - m.energy) / (2 * ha);
    vs_joint_normal(KN, BD, TL, a, w + hw, &p);
    vs_joint_normal(KN, BD, TL, a, w - hw, &m);
    double Nw = (p.N - m.N) / (2 * hw), Mw = (p.M - m.M) / (2 * hw);
    double Ew = (p.energy - m.energy) / (2 * hw);
    double Ksc = KN * BD * TL;
    CHECK(r.N_a, Na, 1e-7, 1e-9 * Ksc);
    CHECK(r.N_w, Nw, 1e-7, 1e-9 * Ksc * TL);
    CHECK(r.N_w, Ma, 1e-7, 1e-9 * Ksc * TL); /* M_a = N_w */
    CHECK(r.M_w, Mw, 1e-7, 1e-9 * Ksc * TL * TL);
    CHECK(r.N_a, c.N_a, 1e-11, 1e-14 * Ksc);
    CHECK(r.N_w, c.N_w, 1e-11, 1e-14 * Ksc * TL);
    CHECK(r.M_w, c.M_w, 1e-11, 1e-14 * Ksc * TL * TL);
    /* The energy is the potential of the normal law: dE/da = N, dE/dw = M. */
    CHECK(Ea, r.N, 1e-7, 1e-9 * Nsc);
    CHECK(Ew, r.M, 1e-7, 1e-9 * Nsc * TL);
  }
}

/* ----------------------------------- vs_joint_eval_h ----------------------------------- */

static void rot(double th, const double v[2], double out[2]) {
  double c = cos(th), s = sin(th);
  out[0] = c * v[0] - s * v[1];
  out[1] = s * v[0] + c * v[1];
}

static double cross(const double r[2], const double f[2]) { return r[0] * f[1] - r[1] * f[0]; }

/* Exact kinematics written from joint.h's definition: the joint point is P = O_a + r_a =
 * O_b + r_b in the reference configuration; its images on a and b are
 * x_a = P + u_a + (R(th_a) - I) r_a, x_b = P + u_b + (R(th_b) - I) r_b, d_c = x_b - x_a;
 * n, s are the reference normal and tangent turned by the mean rotation. */
static void my_kin(const vs_joint_geom *jg, const double qa[3], const double qb[3],
                   const double ra[2], const double rb[2], double *a, double *w, double *slip) {
  double Ra[2], Rb[2];
  rot(qa[2], ra, Ra);
  rot(qb[2], rb, Rb);
  double dc[2] = {qb[0] + Rb[0] - rb[0] - (qa[0] + Ra[0] - ra[0]),
                  qb[1] + Rb[1] - rb[1] - (qa[1] + Ra[1] - ra[1])};
  double thm = 0.5 * (qa[2] + qb[2]);
  double n0[2] = {jg->nx, jg->nz}, s0[2] = {-jg->nz, jg->nx}, n[2], s[2];
  rot(thm, n0, n);
  rot(thm, s0, s);
  *a = -(dc[0] * n[0] + dc[1] * n[1]);
  *w = 2 * sin(0.5 * (qb[2] - qa[2]));
  *slip = dc[0] * s[0] + dc[1] * s[1];
}

/* Independent energy with plastic slip sp held fixed. */
static double my_energy(const vs_joint_geom *jg, const double q[6], const double ra[2],
                        const double rb[2], double sp) {
  double a, w, slip;
  my_kin(jg, q, q + 3, ra, rb, &a, &w, &slip);
  closed_normal c;
  winkler(a, w, &c);
  return c.energy + 0.5 * KS * BD * TL * (slip - sp) * (slip - sp);
}

/* Body b's generalised displacement that gives the joint the state (a, w, slip) when body a
 * is at qa (inverse of my_kin). */
static void make_qb(const vs_joint_geom *jg, const double qa[3], const double ra[2],
                    const double rb[2], double a, double w, double slip, double qb[3]) {
  qb[2] = qa[2] + 2 * asin(0.5 * w);
  double thm = 0.5 * (qa[2] + qb[2]);
  double n0[2] = {jg->nx, jg->nz}, s0[2] = {-jg->nz, jg->nx}, n[2], s[2];
  rot(thm, n0, n);
  rot(thm, s0, s);
  double Ra[2], Rb[2];
  rot(qa[2], ra, Ra);
  rot(qb[2], rb, Rb);
  for (int k = 0; k < 2; k++) {
    double dc = -a * n[k] + slip * s[k];
    qb[k] = dc + qa[k] + (Ra[k] - ra[k]) - (Rb[k] - rb[k]);
  }
}

static const vs_joint_geom JG = {.a = 0, .b = 1, .px = 0.12, .pz = 0.29, .nx = 0.0, .nz = 0.0,
                                 .length = TL, .depth = BD};
static const double RA[2] = {-0.0052, 0.0021};
static const double RB[2] = {0.0061, -0.0013};

static vs_joint_geom joint_geom(void) {
  vs_joint_geom g = JG;
  g.nx = cos(0.4);
  g.nz = -sin(0.4);
  return g;
}
static vs_joint_law joint_law(void) { return (vs_joint_law){.kn = KN, .ks = KS, .mu = MU}; }

/* Scaled comparison of 6-vectors / 6x6 matrices: rotations and moments are scaled by the joint
 * length so that all entries share units. */
static double dscale(int i) { return i % 3 == 2 ? 1.0 / TL : 1.0; }

static void check_vec6(const double *got, const double *want, double rtol, const char *what,
                       int line) {
  double mx = 0;
  for (int i = 0; i < 6; i++) mx = fmax(mx, fabs(want[i] * dscale(i)));
  for (int i = 0; i < 6; i++) {
    double g = got[i] * dscale(i), w = want[i] * dscale(i);
    if (!(fabs(g - w) <= rtol * (fabs(w) + 1e-3 * mx) + 1e-12))
      fail_msg("line %d: %s[%d] = %.15g, expected %.15g", line, what, i, got[i], want[i]);
  }
}

/* K[i][j] in N/m: moment rows divided by t, rotation columns multiplied by t. */
static double kscale(int ij) {
  return (ij / 6 % 3 == 2 ? 1.0 / TL : 1.0) * (ij % 6 % 3 == 2 ? TL : 1.0);
}

static void check_mat6(const double *got, const double *want, double rtol, const char *what,
                       int line) {
  double mx = 0;
  for (int i = 0; i < 36; i++) mx = fmax(mx, fabs(want[i] * kscale(i)));
  for (int i = 0; i < 36; i++) {
    double sc = kscale(i);
    double g = got[i] * sc, w = want[i] * sc;
    if (!(fabs(g - w) <= rtol * (fabs(w) + 1e-3 * mx) + 1e-9))
      fail_msg("line %d: %s[%d][%d] = %.15g, expected %.15g", line, what, i / 6, i % 6, got[i],
               want[i]);
  }
}

static double step_for(int i) { return i % 3 == 2 ? 1e-7 : 1e-9; }

/* f and K of vs_joint_eval_h at q (6 entries) with slip_p_old sp. */
static void eval_q(const double q[6], double sp, vs_joint_state *st, double f[6], double K[36]) {
  vs_joint_geom jg = joint_geom();
  vs_joint_law law = joint_law();
  vs_test_joint_eval(&jg, &law, q, q + 3, RA, RB, sp, st, f, K);
}

/* Check kinematics, forces and state fields of one evaluation against the closed forms. */
static void check_state_closed_form(const double q[6], double sp) {
  vs_joint_geom jg = joint_geom();
  vs_joint_state st;
  double f[6], K[36];
  eval_q(q, sp, &st, f, K);
  double a, w, slip;
  my_kin(&jg, q, q + 3, RA, RB, &a, &w, &slip);
  double len = fabs(a) + fabs(w) * TL;
  CHECK(st.a, a, 1e-9, 1e-13 * len);
  CHECK(st.w, w, 1e-12, 1e-15);
  CHECK(st.slip, slip, 1e-9, 1e-13 * len);
  CHECK(st.gap_i, -(a - 0.5 * w * TL), 1e-9, 1e-13 * len);
  CHECK(st.gap_e, -(a + 0.5 * w * TL), 1e-9, 1e-13 * len);
  closed_normal c;
  winkler(a, w, &c);
  double Nsc = KN * BD * TL * len;
  CHECK(st.N, c.N, 1e-8, 1e-12 * Nsc);
  CHECK(st.M, c.M, 1e-8, 1e-12 * Nsc * TL);
  CHECK(st.contact, c.contact, 1e-8, 1e-12 * TL);
  double kst = KS * BD * TL;
  double Ttrial = kst * (slip - sp);
  if (fabs(Ttrial) <= MU * c.N) {
    CHECK(st.T, Ttrial, 1e-8, 1e-12 * Nsc);
    assert_int_equal(st.sliding, 0);
    CHECK(st.slip_p, sp, 1e-12, 1e-18);
  } else {
    CHECK(st.T, copysign(MU * c.N, Ttrial), 1e-8, 1e-12 * Nsc);
    assert_int_equal(st.sliding, 1);
    CHECK(st.slip_p, slip - st.T / kst, 1e-8, 1e-13 * len);
  }
  CHECK(st.energy, c.energy + 0.5 * kst * (slip - st.slip_p) * (slip - st.slip_p), 1e-8,
        1e-12 * Nsc * len);
}

/* A random state: qa with rotation up to 0.1 rad, b placed so that the joint has gap slope w
 * with |w| in [3e-3, 2e-2] and the contact partial (kind 0), full (1) or open (2); the slip is
 * a multiple sf of the sticking limit mu N / (k_s b t). */
static void random_state(rng *r, int kind, double sf, double q[6]) {
  vs_joint_geom jg = joint_geom();
  q[0] = urand(r, -2e-3, 2e-3);
  q[1] = urand(r, -2e-3, 2e-3);
  q[2] = urand(r, -0.1, 0.1);
  double w = rsign(r) * urand(r, 3e-3, 2e-2);
  double half = 0.5 * fabs(w) * TL;
  double a = kind == 0 ? urand(r, -0.7, 0.7) * half
             : kind == 1 ? urand(r, 1.2, 3.0) * half
                         : -urand(r, 1.2, 3.0) * half;
  closed_normal c;
  winkler(a, w, &c);
  double slip = kind == 2 ? urand(r, -1e-4, 1e-4) : sf * MU * c.N / (KS * BD * TL);
  make_qb(&jg, q, RA, RB, a, w, slip, q + 3);
}

static void test_eval_closed_form(void **state) {
  (void)state;
  rng r = {0x9E3779B97F4A7C15ULL};
  for (int k = 0; k < 30; k++) {
    double q[6];
    int kind = k % 3;
    double sf = k % 2 ? rsign(&r) * urand(&r, 0.1, 0.9) : rsign(&r) * urand(&r, 1.2, 4.0);
    random_state(&r, kind, sf, q);
    check_state_closed_form(q, 0.0);
    check_state_closed_form(q, urand(&r, -1e-4, 1e-4));
  }
  /* NULL outputs are allowed. */
  double q[6];
  random_state(&r, 0, 0.5, q);
  vs_joint_geom jg = joint_geom();
  vs_joint_law law = joint_law();
  vs_joint_state st;
  double f[6];
  vs_test_joint_eval(&jg, &law, q, q + 3, RA, RB, 0.0, NULL, NULL, NULL);
  vs_test_joint_eval(&jg, &law, q, q + 3, RA, RB, 0.0, &st, NULL, NULL);
  vs_test_joint_eval(&jg, &law, q, q + 3, RA, RB, 0.0, NULL, f, NULL);
}

/* A common rigid motion (rotation psi about C, then translation) of both bodies produces no
 * force, gap or slip; superposed on a deformed state it leaves the joint state unchanged and
 * turns the forces with the bodies (moments unchanged). */
static void rigid_motion(const double C[2], double psi, const double tr[2], const double r[2],
                         const double q[3], double out[3]) {
  const double P[2] = {JG.px, JG.pz};
  double O[2] = {P[0] - r[0], P[1] - r[1]}; /* reference point of the body */
  double x[2] = {O[0] + q[0] - C[0], O[1] + q[1] - C[1]}, Rx[2];
  rot(psi, x, Rx);
  out[0] = C[0] + Rx[0] + tr[0] - O[0];
  out[1] = C[1] + Rx[1] + tr[1] - O[1];
  out[2] = q[2] + psi;
}

static void test_eval_objectivity(void **state) {
  (void)state;
  const double C[2] = {0.5, -0.2}, tr[2] = {0.01, -0.02};
  const double psis[] = {0.7, -2.5, 3.0};
  for (size_t i = 0; i < 3; i++) {
    double zero[3] = {0, 0, 0}, q[6];
    rigid_motion(C, psis[i], tr, RA, zero, q);
    rigid_motion(C, psis[i], tr, RB, zero, q + 3);
    vs_joint_state st;
    double f[6];
    eval_q(q, 0.0, &st, f, NULL);
    CHECK(st.a, 0, 0, 1e-14);
    CHECK(st.w, 0, 0, 1e-15);
    CHECK(st.slip, 0, 0, 1e-14);
    CHECK(st.gap_i, 0, 0, 1e-14);
    CHECK(st.gap_e, 0, 0, 1e-14);
    CHECK(st.N, 0, 0, 1e-4);
    CHECK(st.T, 0, 0, 1e-4);
    CHECK(st.M, 0, 0, 1e-6);
    for (int k = 0; k < 6; k++) CHECK(f[k], 0, 0, 1e-4);
  }
  rng r = {12345};
  for (int k = 0; k < 12; k++) {
    double q[6], q2[6];
    random_state(&r, k % 3, k % 2 ? 0.5 : 2.5, q);
    double psi = psis[k % 3];
    rigid_motion(C, psi, tr, RA, q, q2);
    rigid_motion(C, psi, tr, RB, q + 3, q2 + 3);
    vs_joint_state s1, s2;
    double f1[6], f2[6];
    eval_q(q, 1e-5, &s1, f1, NULL);
    eval_q(q2, 1e-5, &s2, f2, NULL);
    double len = fabs(s1.a) + fabs(s1.w) * TL;
    double Fs = KN * BD * TL * len;
    CHECK(s2.a, s1.a, 1e-8, 1e-13 * len);
    CHECK(s2.w, s1.w, 1e-10, 1e-15);
    CHECK(s2.slip, s1.slip, 1e-8, 1e-13 * len);
    CHECK(s2.N, s1.N, 1e-8, 1e-12 * Fs);
    CHECK(s2.T, s1.T, 1e-8, 1e-12 * Fs);
    CHECK(s2.M, s1.M, 1e-8, 1e-12 * Fs * TL);
    assert_int_equal(s2.sliding, s1.sliding);
    for (int b = 0; b < 2; b++) {
      double Rf[2];
      rot(psi, f1 + 3 * b, Rf);
      CHECK(f2[3 * b], Rf[0], 1e-8, 1e-12 * Fs);
      CHECK(f2[3 * b + 1], Rf[1], 1e-8, 1e-12 * Fs);
      CHECK(f2[3 * b + 2], f1[3 * b + 2], 1e-8, 1e-12 * Fs * TL);
    }
  }
}

/* f = dE/dq while sticking (E = st.energy and the test's own energy), K = df/dq. */
static void check_f_and_K(const double q[6], double sp, int expect_sliding) {
  vs_joint_state st;
  double f[6], K[36], fd[6], Kfd[36];
  eval_q(q, sp, &st, f, K);
  assert_int_equal(st.sliding, expect_sliding);
  /* While sliding, f is the gradient of the energy with the plastic slip frozen at its new
   * value (T = k_s b t (slip - slip_p_new) = +-mu N); while sticking slip_p_new = sp. */
  double spn = st.slip_p;
  double fmine[6];
  for (int i = 0; i < 6; i++) {
    double h = step_for(i), qp[6], qm[6];
    for (int k = 0; k < 6; k++) qp[k] = qm[k] = q[k];
    qp[i] += h;
    qm[i] -= h;
    vs_joint_state sp_, sm_;
    double fp[6], fm[6];
    eval_q(qp, sp, &sp_, fp, NULL);
    eval_q(qm, sp, &sm_, fm, NULL);
    assert_int_equal(sp_.sliding, expect_sliding);
    assert_int_equal(sm_.sliding, expect_sliding);
    fd[i] = (sp_.energy - sm_.energy) / (2 * h);
    vs_joint_geom jg = joint_geom();
    fmine[i] = (my_energy(&jg, qp, RA, RB, spn) - my_energy(&jg, qm, RA, RB, spn)) / (2 * h);
    for (int k = 0; k < 6; k++) Kfd[k * 6 + i] = (fp[k] - fm[k]) / (2 * h);
  }
  check_vec6(f, fmine, 1e-6, "f vs dE/dq (test's energy)", __LINE__);
  if (!expect_sliding) check_vec6(f, fd, 1e-6, "f vs d(st.energy)/dq", __LINE__);
  check_mat6(K, Kfd, 1e-6, "K vs df/dq", __LINE__);
}

static void test_eval_gradients_sticking(void **state) {
  (void)state;
  rng r = {777};
  for (int k = 0; k < 24; k++) {
    double q[6];
    random_state(&r, k % 3 == 2 ? 1 : 0, rsign(&r) * urand(&r, 0.1, 0.8), q);
    check_f_and_K(q, 0.0, 0);
  }
}

static void test_eval_gradients_sliding(void **state) {
  (void)state;
  rng r = {4242};
  for (int k = 0; k < 24; k++) {
    double q[6];
    random_state(&r, k % 3 == 2 ? 1 : 0, rsign(&r) * urand(&r, 1.3, 5.0), q);
    check_f_and_K(q, 0.0, 1);
  }
}

/* Newton's third law and balance of moments about arbitrary points, current configuration. */
static void test_eval_equilibrium(void **state) {
  (void)state;
  rng r = {99};
  const double X[3][2] = {{0, 0}, {1.0, -2.0}, {-0.3, 0.7}};
  for (int k = 0; k < 24; k++) {
    double q[6];
    random_state(&r, k % 3, k % 2 ? 0.5 : 3.0, q);
    vs_joint_state st;
    double f[6];
    eval_q(q, 0.0, &st, f, NULL);
    double F = fmax(fmax(fabs(f[0]), fabs(f[1])), 1e-9);
    CHECK(f[0] + f[3], 0, 0, 1e-11 * F);
    CHECK(f[1] + f[4], 0, 0, 1e-11 * F);
    const double P[2] = {JG.px, JG.pz};
    double xa[2] = {P[0] - RA[0] + q[0], P[1] - RA[1] + q[1]};
    double xb[2] = {P[0] - RB[0] + q[3], P[1] - RB[1] + q[4]};
    for (int i = 0; i < 3; i++) {
      double da[2] = {xa[0] - X[i][0], xa[1] - X[i][1]};
      double db[2] = {xb[0] - X[i][0], xb[1] - X[i][1]};
      double mom = f[2] + cross(da, f) + f[5] + cross(db, f + 3);
      double lever = fabs(da[0]) + fabs(da[1]) + TL;
      CHECK(mom, 0, 0, 1e-10 * F * lever);
    }
  }
}

/* Coulomb: a trial shear above mu N is returned to |T| = mu N, in the direction of the trial;
 * below it the joint sticks; an open joint carries no shear. */
static void test_eval_friction(void **state) {
  (void)state;
  vs_joint_geom jg = joint_geom();
  double qa[3] = {1e-4, -3e-4, 0.05}, q[6];
  double w = 0.01, a = 0.2 * 0.5 * w * TL;
  closed_normal c;
  winkler(a, w, &c);
  double kst = KS * BD * TL, lim = MU * c.N / kst;
  const double sfs[] = {3.0, -3.0, 1.01, -1.01, 0.99, 0.5, -0.99};
  for (size_t i = 0; i < sizeof sfs / sizeof sfs[0]; i++) {
    for (int k = 0; k < 3; k++) q[k] = qa[k];
    make_qb(&jg, qa, RA, RB, a, w, sfs[i] * lim, q + 3);
    vs_joint_state st;
    eval_q(q, 0.0, &st, NULL, NULL);
    CHECK(st.N, c.N, 1e-8, 0);
    if (fabs(sfs[i]) > 1) {
      assert_int_equal(st.sliding, 1);
      CHECK(st.T, copysign(MU * c.N, sfs[i]), 1e-8, 0);
      CHECK(fabs(st.T), MU * st.N, 1e-12, 0);
      CHECK(st.slip_p, st.slip - st.T / kst, 1e-8, 1e-15);
      CHECK(st.slip_p, (sfs[i] - copysign(1.0, sfs[i])) * lim, 1e-6, 1e-15);
    } else {
      assert_int_equal(st.sliding, 0);
      CHECK(st.T, sfs[i] * MU * c.N, 1e-8, 0);
      CHECK(st.slip_p, 0, 0, 1e-300);
    }
  }
  /* Old plastic slip: the elastic part is measured from it; a reversed trial slides back. */
  make_qb(&jg, qa, RA, RB, a, w, 0.5 * lim, q + 3);
  for (int k = 0; k < 3; k++) q[k] = qa[k];
  vs_joint_state st;
  eval_q(q, 0.2 * lim, &st, NULL, NULL);
  assert_int_equal(st.sliding, 0);
  CHECK(st.T, 0.3 * MU * c.N, 1e-8, 0);
  eval_q(q, 3.5 * lim, &st, NULL, NULL);
  assert_int_equal(st.sliding, 1);
  CHECK(st.T, -MU * c.N, 1e-8, 0);
  CHECK(st.slip_p, 1.5 * lim, 1e-6, 0);
  /* Open joint with a slip: no normal force, no shear, no force at all. */
  make_qb(&jg, qa, RA, RB, -2.0 * 0.5 * w * TL, w, 1e-4, q + 3);
  double f[6];
  eval_q(q, 0.0, &st, f, NULL);
  CHECK(st.N, 0, 0, 1e-12);
  CHECK(st.T, 0, 0, 1e-12);
  for (int k = 0; k < 6; k++) CHECK(f[k], 0, 0, 1e-12);
}

/* One evaluation for the equations of motion (vs_joint_eval_motion) gives, at the same state,
 * the elastic force and tangent of vs_joint_eval_h, and the joint or stiffness-proportional
 * damping and the friction power as joint.h defines them (written again as matrices in
 * tests/support/joint_reference.c); its damping force is C v with the power v . C v >= 0. */
static void check_motion(const double q[6], const double v[6], double sp, const vs_joint_dashpot *dp) {
  vs_joint_geom jg = joint_geom();
  vs_joint_law law = joint_law();
  double ha[2], hb[2], f[6], K[36], fd[6], C[36], f1[6], K1[36], fd1[6], C1[36], pw1;
  vs_joint_half_angle(q[2], ha);
  vs_joint_half_angle(q[5], hb);
  CHECK(ha[0] * ha[0] - ha[1] * ha[1], cos(q[2]), 1e-15, 1e-15);
  CHECK(2.0 * ha[0] * ha[1], sin(q[2]), 1e-15, 1e-15);
  const vs_joint_bodies bd = {q, q + 3, ha, hb, v, v + 3, RA, RB};
  vs_joint_motion jm = {f, K, fd, C, 1, 0.0, 0.0};
  vs_joint_eval_motion(&jg, &law, &bd, sp, dp, &jm);
  vs_test_joint_eval(&jg, &law, q, q + 3, RA, RB, sp, NULL, f1, K1);
  vs_test_joint_dashpot(&jg, &law, dp, q, q + 3, v, v + 3, RA, RB, fd1, C1, &pw1);
  const double fr1 = vs_test_joint_friction_power(&jg, &law, q, q + 3, v, v + 3, RA, RB, sp);
  check_vec6(f, f1, 1e-12, "motion f vs vs_joint_eval_h", __LINE__);
  check_mat6(K, K1, 1e-12, "motion K vs vs_joint_eval_h", __LINE__);
  double cv[6] = {0}, vcv = 0.0, fsc = 0.0; /* fsc: the largest force (moments over TL) */
  for (int i = 0; i < 6; i++) {
    for (int j = 0; j < 6; j++) cv[i] += C[6 * i + j] * v[j];
    vcv += v[i] * cv[i];
    fsc = fmax(fsc, fabs(fd[i]) / (i % 3 == 2 ? TL : 1.0));
  }
  for (int i = 0; i < 6; i++) {
    const double sc = i % 3 == 2 ? TL : 1.0;
    CHECK(fd[i], fd1[i], 1e-12, 1e-15 * fsc * sc);
    CHECK(fd[i], cv[i], 1e-9, 1e-12 * fsc * sc);
    for (int j = 0; j < 6; j++) CHECK(C[6 * i + j], C1[6 * i + j], 1e-12, 0);
  }
  CHECK(jm.power, pw1, 1e-12, 0);
  CHECK(jm.power, vcv, 1e-9, 1e-15);
  assert_true(jm.power >= 0.0);
  CHECK(jm.friction, fr1, 1e-12, 0);
}

static void test_eval_motion(void **state) {
  (void)state;
  rng r = {0xC0FFEEULL};
  const vs_joint_dashpot joint_dp = {2e6, 1e6, 0.0}, tangent_dp = {0.0, 0.0, 1e-4};
  for (int k = 0; k < 36; k++) {
    double q[6], v[6];
    /* partial, full and open contact; sticking and sliding slips */
    random_state(&r, k % 3, (k / 3) % 2 ? rsign(&r) * urand(&r, 0.1, 0.8) : rsign(&r) * urand(&r, 1.3, 4.0), q);
    for (int i = 0; i < 6; i++) v[i] = urand(&r, -1e-3, 1e-3) * (i % 3 == 2 ? 1.0 / TL : 1.0);
    check_motion(q, v, 0.0, k % 2 ? &joint_dp : &tangent_dp);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_normal_fixed_N),
      cmocka_unit_test(test_normal_C1_at_lift),
      cmocka_unit_test(test_normal_symmetry_and_open),
      cmocka_unit_test(test_normal_derivatives),
      cmocka_unit_test(test_eval_closed_form),
      cmocka_unit_test(test_eval_objectivity),
      cmocka_unit_test(test_eval_gradients_sticking),
      cmocka_unit_test(test_eval_gradients_sliding),
      cmocka_unit_test(test_eval_equilibrium),
      cmocka_unit_test(test_eval_friction),
      cmocka_unit_test(test_eval_motion),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
