/* The joint law: closed-form no-tension Winkler normal response, elastic-frictional shear with
 * return mapping, and exact large-rotation kinematics with first and second derivatives. */
#include "voussoir/joint.h"

#include <math.h>
#include <string.h>

/* Response for w >= 0 (extrados side at least as compressed as the intrados). */
static void normal_pos(double kn, double b, double t, double a, double w, vs_normal_response *r) {
  const double K = kn * b;
  const double pmax = a + 0.5 * w * t, pmin = a - 0.5 * w * t;
  memset(r, 0, sizeof *r);
  if (pmax < 0.0) return; /* fully open; p == 0 everywhere (just touching) counts as closed, so
                              that the reference configuration has the contact tangent */
  if (pmin >= 0.0) {       /* full contact */
    r->N = K * t * a;
    r->M = K * w * t * t * t / 12.0;
    r->N_a = K * t;
    r->N_w = 0.0;
    r->M_w = K * t * t * t / 12.0;
    r->energy = 0.5 * K * (a * a * t + w * w * t * t * t / 12.0);
    r->contact = t;
    return;
  }
  /* partial contact: p > 0 over the length c = pmax / w next to the extrados (w > 0 here) */
  const double c = pmax / w;
  r->N = 0.5 * K * w * c * c;
  r->M = r->N * (0.5 * t - c / 3.0);
  r->N_a = K * c;
  r->N_w = 0.5 * K * c * (t - c);
  r->M_w = K * (c * t * t / 4.0 - c * c * t / 2.0 + c * c * c / 3.0);
  r->energy = K * w * w * c * c * c / 6.0;
  r->contact = c;
}

void vs_joint_normal(double kn, double b, double t, double a, double w, vs_normal_response *r) {
  if (w >= 0.0) {
    normal_pos(kn, b, t, a, w, r);
    return;
  }
  /* mirror xi -> -xi: N(a, w) = N+(a, -w), M(a, w) = -M+(a, -w) */
  normal_pos(kn, b, t, a, -w, r);
  r->M = -r->M;
  r->N_w = -r->N_w;
  /* M_w: d(-M+(a,-w))/dw = M+_w, unchanged */
}

/* J v: v turned +90 degrees. */
static inline void perp(const double v[2], double out[2]) {
  out[0] = -v[1];
  out[1] = v[0];
}

static inline double dot(const double u[2], const double v[2]) { return u[0] * v[0] + u[1] * v[1]; }

/* Kinematic measures of the joint and their gradients/Hessians in (qa, qb). */
typedef struct {
  double g, sl, w;            /* gap at the centre, slip, gap slope */
  double dg[6], ds[6], dw[6]; /* gradients */
  double Hg[36], Hs[36], Hw[36];
} kinematics;

static void sym_set(double *H, int i, int j, double v) {
  H[i * 6 + j] = v;
  H[j * 6 + i] = v;
}

static void rot_cs(double c, double sn, const double v[2], double out[2]) {
  out[0] = c * v[0] - sn * v[1];
  out[1] = sn * v[0] + c * v[1];
}

/* hess = 0 computes values and gradients only (residual evaluations); 1 adds the Hessians. */
static void joint_kinematics(const vs_joint_geom *jg, const double qa[3], const double qb[3],
                             const double ra[2], const double rb[2], int hess, kinematics *k) {
  const double n0[2] = {jg->nx, jg->nz};
  double pa[2], pb[2], va[2], vb[2], n[2], s[2], d[2];
  /* two sincos per joint: R(theta_b) = R(theta_a) R(2 half), R(theta_m) = R(theta_a) R(half) */
  const double half = 0.5 * (qb[2] - qa[2]);
  const double ca = cos(qa[2]), sa = sin(qa[2]), ch = cos(half), sh = sin(half);
  const double c2 = 1.0 - 2.0 * sh * sh, s2 = 2.0 * sh * ch;
  rot_cs(ca, sa, ra, pa);
  rot_cs(ca * c2 - sa * s2, sa * c2 + ca * s2, rb, pb);
  rot_cs(ca * ch - sa * sh, sa * ch + ca * sh, n0, n);
  perp(pa, va);
  perp(pb, vb);
  perp(n, s);
  for (int i = 0; i < 2; i++) d[i] = qb[i] - qa[i] + (pb[i] - rb[i]) - (pa[i] - ra[i]);
  if (hess) memset(k, 0, sizeof *k);
  else memset(k->dw, 0, sizeof k->dw);
  k->g = dot(d, n);
  k->sl = dot(d, s);
  k->w = 2.0 * sh;
  const double dn = k->g, ds_ = k->sl;
  for (int i = 0; i < 2; i++) {
    k->dg[i] = -n[i];
    k->dg[3 + i] = n[i];
    k->ds[i] = -s[i];
    k->ds[3 + i] = s[i];
  }
  k->dg[2] = -dot(va, n) + 0.5 * ds_;
  k->dg[5] = dot(vb, n) + 0.5 * ds_;
  k->ds[2] = -dot(va, s) - 0.5 * dn;
  k->ds[5] = dot(vb, s) - 0.5 * dn;
  k->dw[2] = -ch;
  k->dw[5] = ch;
  if (!hess) return;
  /* mixed translation-rotation terms come from the rotating frame n(theta_m), s(theta_m) */
  for (int i = 0; i < 2; i++) {
    sym_set(k->Hg, i, 2, -0.5 * s[i]);
    sym_set(k->Hg, i, 5, -0.5 * s[i]);
    sym_set(k->Hg, 3 + i, 2, 0.5 * s[i]);
    sym_set(k->Hg, 3 + i, 5, 0.5 * s[i]);
    sym_set(k->Hs, i, 2, 0.5 * n[i]);
    sym_set(k->Hs, i, 5, 0.5 * n[i]);
    sym_set(k->Hs, 3 + i, 2, -0.5 * n[i]);
    sym_set(k->Hs, 3 + i, 5, -0.5 * n[i]);
  }
  sym_set(k->Hg, 2, 2, dot(pa, n) - dot(va, s) - 0.25 * dn);
  sym_set(k->Hg, 5, 5, -dot(pb, n) + dot(vb, s) - 0.25 * dn);
  sym_set(k->Hg, 2, 5, 0.5 * (dot(vb, s) - dot(va, s)) - 0.25 * dn);
  sym_set(k->Hs, 2, 2, dot(pa, s) + dot(va, n) - 0.25 * ds_);
  sym_set(k->Hs, 5, 5, -dot(pb, s) - dot(vb, n) - 0.25 * ds_);
  sym_set(k->Hs, 2, 5, 0.5 * (dot(va, n) - dot(vb, n)) - 0.25 * ds_);
  sym_set(k->Hw, 2, 2, -0.5 * sh);
  sym_set(k->Hw, 5, 5, -0.5 * sh);
  sym_set(k->Hw, 2, 5, 0.5 * sh);
}

/* Rates of the joint measures (penetration a, gap slope w, slip) from the bodies' velocities. */
static void joint_rates(const kinematics *k, const double va[3], const double vb[3], double *adot,
                        double *wdot, double *sdot) {
  const double vel[6] = {va[0], va[1], va[2], vb[0], vb[1], vb[2]};
  *adot = *wdot = *sdot = 0.0;
  for (int i = 0; i < 6; i++) {
    *adot -= k->dg[i] * vel[i];
    *wdot += k->dw[i] * vel[i];
    *sdot += k->ds[i] * vel[i];
  }
}

void vs_joint_eval(const vs_joint_geom *jg, const vs_joint_law *law, const double qa[3],
                   const double qb[3], const double ra[2], const double rb[2], double slip_p_old,
                   vs_joint_state *st, double f[6], double K[36]) {
  kinematics k;
  joint_kinematics(jg, qa, qb, ra, rb, K != NULL, &k);
  const double t = jg->length, b = jg->depth, a = -k.g;
  vs_normal_response nr; /* the initial gap is a constant offset: the derivatives are unchanged */
  vs_joint_normal(law->kn, b, t, a - law->gap0, k.w - law->gap1, &nr);

  /* shear over the whole joint, Coulomb limit by return mapping */
  const double kst = law->ks * b * t;
  const double T_trial = kst * (k.sl - slip_p_old);
  const double T_max = law->mu * nr.N;
  double T = T_trial, slip_p = slip_p_old;
  int sliding = 0;
  double sgn = 1.0;
  if (fabs(T_trial) > T_max) {
    sgn = (T_trial > 0.0) ? 1.0 : -1.0;
    T = sgn * T_max;
    slip_p = k.sl - T / kst;
    sliding = 1;
  }

  if (st != NULL) {
    st->N = nr.N;
    st->T = T;
    st->M = nr.M;
    st->a = a;
    st->w = k.w;
    st->slip = k.sl;
    st->slip_p = slip_p;
    st->contact = nr.contact;
    st->gap_i = -(a - 0.5 * k.w * t);
    st->gap_e = -(a + 0.5 * k.w * t);
    st->sliding = sliding;
    st->energy = nr.energy + 0.5 * kst * (k.sl - slip_p) * (k.sl - slip_p);
  }
  /* f = N grad(a) + M grad(w) + T grad(slip), grad(a) = -grad(g) */
  if (f != NULL)
    for (int i = 0; i < 6; i++) f[i] = -nr.N * k.dg[i] + nr.M * k.dw[i] + T * k.ds[i];
  if (K != NULL) {
    /* K = grad(a) dN^T + grad(w) dM^T + grad(s) dT^T + N H_a + M H_w + T H_s */
    double dN[6], dM[6], dT[6];
    for (int j = 0; j < 6; j++) {
      const double da_j = -k.dg[j], dw_j = k.dw[j];
      dN[j] = nr.N_a * da_j + nr.N_w * dw_j;
      dM[j] = nr.N_w * da_j + nr.M_w * dw_j;
      dT[j] = sliding ? sgn * law->mu * dN[j] : kst * k.ds[j];
    }
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++)
        K[i * 6 + j] = -k.dg[i] * dN[j] + k.dw[i] * dM[j] + k.ds[i] * dT[j] -
                       nr.N * k.Hg[i * 6 + j] + nr.M * k.Hw[i * 6 + j] + T * k.Hs[i * 6 + j];
  }
}

/* Below this contact length, as a fraction of the joint length, the damping fades linearly to
 * zero, so that it vanishes continuously when the joint separates completely. */
static const double VS_DAMP_RAMP = 0.02;

void vs_joint_damping(const vs_joint_geom *jg, const vs_joint_law *law, double cn, double cs,
                      const double qa[3], const double qb[3], const double va[3],
                      const double vb[3], const double ra[2], const double rb[2], double f[6],
                      double C[36], double *power) {
  kinematics k;
  joint_kinematics(jg, qa, qb, ra, rb, 0, &k);
  const double t = jg->length, b = jg->depth;
  vs_normal_response nr;
  vs_joint_normal(law->kn, b, t, -k.g - law->gap0, k.w - law->gap1, &nr);
  const double phi = fmin(1.0, nr.contact / (VS_DAMP_RAMP * t));
  /* full-section viscous damping: normal b c_n t, rotational b c_n t^3/12, shear b c_s t */
  const double ca = phi * b * cn * t, cw = phi * b * cn * t * t * t / 12.0, csl = phi * b * cs * t;
  double adot, wdot, sdot;
  joint_rates(&k, va, vb, &adot, &wdot, &sdot);
  const double Nd = ca * adot, Md = cw * wdot, Td = csl * sdot;
  if (f != NULL)
    for (int i = 0; i < 6; i++) f[i] = -Nd * k.dg[i] + Md * k.dw[i] + Td * k.ds[i];
  if (power != NULL) *power = Nd * adot + Md * wdot + Td * sdot;
  if (C != NULL)
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++)
        C[i * 6 + j] = ca * k.dg[i] * k.dg[j] + cw * k.dw[i] * k.dw[j] + csl * k.ds[i] * k.ds[j];
}

void vs_joint_damping_tangent(const vs_joint_geom *jg, const vs_joint_law *law, double beta,
                              const double qa[3], const double qb[3], const double va[3],
                              const double vb[3], const double ra[2], const double rb[2],
                              double f[6], double C[36], double *power) {
  kinematics k;
  joint_kinematics(jg, qa, qb, ra, rb, 0, &k);
  const double t = jg->length, b = jg->depth;
  vs_normal_response nr;
  vs_joint_normal(law->kn, b, t, -k.g - law->gap0, k.w - law->gap1, &nr); /* as the law itself */
  const double cs = beta * law->ks * b * t;
  const double caa = beta * nr.N_a, caw = beta * nr.N_w, cww = beta * nr.M_w;
  double adot, wdot, sdot;
  joint_rates(&k, va, vb, &adot, &wdot, &sdot);
  const double Nd = caa * adot + caw * wdot, Md = caw * adot + cww * wdot, Td = cs * sdot;
  if (f != NULL)
    for (int i = 0; i < 6; i++) f[i] = -Nd * k.dg[i] + Md * k.dw[i] + Td * k.ds[i];
  if (power != NULL) *power = Nd * adot + Md * wdot + Td * sdot;
  if (C != NULL)
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++)
        C[i * 6 + j] = caa * k.dg[i] * k.dg[j] - caw * (k.dg[i] * k.dw[j] + k.dw[i] * k.dg[j]) +
                       cww * k.dw[i] * k.dw[j] + cs * k.ds[i] * k.ds[j];
}

double vs_joint_friction_power(const vs_joint_geom *jg, const vs_joint_law *law,
                               const double qa[3], const double qb[3], const double va[3],
                               const double vb[3], const double ra[2], const double rb[2],
                               double slip_p_old) {
  kinematics k;
  joint_kinematics(jg, qa, qb, ra, rb, 0, &k);
  const double t = jg->length, b = jg->depth, a = -k.g, kst = law->ks * b * t;
  vs_normal_response nr;
  vs_joint_normal(law->kn, b, t, a - law->gap0, k.w - law->gap1, &nr);
  const double T_trial = kst * (k.sl - slip_p_old), T_max = law->mu * nr.N;
  if (!(fabs(T_trial) > T_max)) return 0.0;
  double adot, wdot, sdot;
  joint_rates(&k, va, vb, &adot, &wdot, &sdot);
  const double sgn = T_trial > 0.0 ? 1.0 : -1.0, T = sgn * T_max;
  const double Tdot = sgn * law->mu * (nr.N_a * adot + nr.N_w * wdot);
  return T * (sdot - Tdot / kst);
}
