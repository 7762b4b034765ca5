/* The joint law: closed-form no-tension Winkler normal response, elastic-frictional shear with
 * return mapping, and exact large-rotation kinematics with first and second derivatives. */
#include "voussoir/joint.h"

#include "joint_law.h"

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

/* --- mortar: tension, softening, damage, cracks (joint.h, vs_joint_normal_mortar) --- */

/* One linear piece of the stress law: sigma = s0 + s1 p, potential phi = e0 + e1 p + e2 p^2. */
typedef struct {
  double s0, s1, e0, e1, e2;
} mortar_piece;

typedef struct {
  double kn, ft, gf, d0, du, h; /* h = ft / (du - d0), the softening slope */
} mortar_curve;

/* The piece in force at penetration p: intact mortar (cracked = 0) or a cracked-through part. */
static mortar_piece mortar_piece_at(const mortar_curve *mc, int cracked, double p) {
  mortar_piece q = {0.0, 0.0, 0.0, 0.0, 0.0};
  if (cracked || mc->ft <= 0.0) {
    if (p > 0.0) q.s1 = mc->kn, q.e2 = 0.5 * mc->kn;
    return q;
  }
  if (p >= -mc->d0) {
    q.s1 = mc->kn, q.e2 = 0.5 * mc->kn;
  } else if (p > -mc->du) { /* phi = gf - h (p + du)^2 / 2 */
    q.s0 = -mc->h * mc->du, q.s1 = -mc->h;
    q.e0 = mc->gf - 0.5 * mc->h * mc->du * mc->du, q.e1 = -mc->h * mc->du, q.e2 = -0.5 * mc->h;
  } else {
    q.e0 = mc->gf;
  }
  return q;
}

/* Sorts the interior cuts cut[1..n-2] (a handful) in place. */
static void sort_cuts(double *cut, int n) {
  for (int i = 1; i < n - 1; i++)
    for (int j = i + 1; j < n - 1; j++)
      if (cut[j] < cut[i]) {
        const double tmp = cut[i];
        cut[i] = cut[j];
        cut[j] = tmp;
      }
}

/* Adds the integral over [u0, u1] of sigma = g0 + g1 xi (tangent s1 in p) and of the potential
 * c0 + c1 xi + c2 xi^2 to r (without the factor b); contact: the piece is compressed. */
static void add_poly(double u0, double u1, double g0, double g1, double s1, double c0,
                     double c1, double c2, int contact, vs_normal_response *r) {
  const double m0 = u1 - u0, m1 = 0.5 * (u1 * u1 - u0 * u0),
               m2 = (u1 * u1 * u1 - u0 * u0 * u0) / 3.0;
  r->N += g0 * m0 + g1 * m1;
  r->M += g0 * m1 + g1 * m2;
  r->N_a += s1 * m0;
  r->N_w += s1 * m1;
  r->M_w += s1 * m2;
  r->energy += c0 * m0 + c1 * m1 + c2 * m2;
  if (contact) r->contact += m0;
}

/* Adds the integral over xi in [x0, x1] of the law (region intact or cracked) to r (without the
 * factor b), splitting where p = a + w xi crosses the law's breakpoints. */
static void mortar_region(const mortar_curve *mc, int cracked, double a, double w, double x0,
                          double x1, vs_normal_response *r) {
  if (!(x1 > x0)) return;
  double cut[5];
  int n = 0;
  cut[n++] = x0;
  const double bp[3] = {0.0, -mc->d0, -mc->du};
  const int nbp = (cracked || mc->ft <= 0.0) ? 1 : 3;
  if (w != 0.0)
    for (int i = 0; i < nbp; i++) {
      const double x = (bp[i] - a) / w;
      if (x > x0 && x < x1) cut[n++] = x;
    }
  cut[n++] = x1;
  sort_cuts(cut, n);
  for (int i = 0; i + 1 < n; i++) {
    const double u0 = cut[i], u1 = cut[i + 1];
    if (!(u1 > u0)) continue;
    const mortar_piece q = mortar_piece_at(mc, cracked, a + w * 0.5 * (u0 + u1));
    /* sigma = (s0 + s1 a) + s1 w xi; phi = c0 + c1 xi + c2 xi^2 */
    add_poly(u0, u1, q.s0 + q.s1 * a, q.s1 * w, q.s1, q.e0 + q.e1 * a + q.e2 * a * a,
             q.e1 * w + 2.0 * q.e2 * a * w, q.e2 * w * w, a + w * 0.5 * (u0 + u1) >= 0.0, r);
  }
}

/* Below this |beta L / k0| the moments int_0^L s^m / (k0 + beta s) ds are summed as their
 * series (log1p's recurrence would cancel); its terms fall as 0.3^n, some 30 reach round-off. */
static const double VS_SECANT_SERIES = 0.3;

/* I[m] = int_0^L s^m / (k0 + beta s) ds, m = 0, 1, 2, for k0 > 0 and k0 + beta L > 0. */
static void inv_moments(double k0, double beta, double L, double I[3]) {
  const double r = beta * L / k0;
  if (fabs(r) < VS_SECANT_SERIES) {
    /* 1 / (k0 (1 + r s / L)) = sum_n (-r s / L)^n / k0: I[m] = L^(m+1) / k0 sum (-r)^n / (m+n+1) */
    double Lp = L / k0;
    for (int m = 0; m < 3; m++) {
      double sum = 0.0, term = 1.0;
      for (int n = 0; n < 60; n++) {
        const double c = term / (double)(m + n + 1);
        sum += c;
        if (fabs(c) <= 1e-17 * fabs(sum)) break;
        term *= -r;
      }
      I[m] = Lp * sum;
      Lp *= L;
    }
    return;
  }
  I[0] = log1p(r) / beta;
  I[1] = (L - k0 * I[0]) / beta;
  I[2] = (0.5 * L * L - k0 * I[1]) / beta;
}

/* A secant piece, xi in [u0, u1], k = k0 + beta (xi - u0) in (d0, du), p = a + w xi < 0:
 * sigma = h (du / k - 1) p, phi = h (du / k - 1) p^2 / 2. */
static void secant_piece(const mortar_curve *mc, double a, double w, double u0, double u1,
                         double k0, double beta, vs_normal_response *r) {
  const double L = u1 - u0, p0 = a + w * u0;
  double I[3];
  inv_moments(k0, beta, L, I);
  const double P[3] = {L, 0.5 * L * L, L * L * L / 3.0};
  double A[3]; /* int_0^L h (du / k - 1) s^m ds */
  for (int m = 0; m < 3; m++) A[m] = mc->h * (mc->du * I[m] - P[m]);
  const double Nn = p0 * A[0] + w * A[1];
  r->N += Nn;
  r->M += u0 * Nn + p0 * A[1] + w * A[2];
  r->N_a += A[0];
  r->N_w += u0 * A[0] + A[1];
  r->M_w += u0 * u0 * A[0] + 2.0 * u0 * A[1] + A[2];
  r->energy += 0.5 * (p0 * p0 * A[0] + 2.0 * p0 * w * A[1] + w * w * A[2]);
}

/* A point whose opening lies within this fraction of du below its envelope counts as on the
 * envelope (loading): at a committed state the opening that set the envelope lies on it up to
 * the round-off of the polyline, and the tangent there is the loading one, whatever that
 * round-off (the stresses of the two branches agree there to kn du times this). */
static const double VS_ENV_ON = 1e-12;

/* A damaged part of the joint, xi in [x0, x1], where the envelope is k = kc0 + kc1 xi (> d0
 * somewhere on it): split where p = 0, p = -k, p = -du and k = du, each piece integrated in
 * closed form. */
static void damaged_region(const mortar_curve *mc, double a, double w, double kc0, double kc1,
                           double x0, double x1, vs_normal_response *r) {
  if (!(x1 > x0)) return;
  double cut[6];
  int n = 0;
  cut[n++] = x0;
  double c[4];
  int nc = 0;
  if (w != 0.0) c[nc++] = -a / w, c[nc++] = (-mc->du - a) / w;
  if (w + kc1 != 0.0) c[nc++] = -(a + kc0) / (w + kc1);
  if (kc1 != 0.0) c[nc++] = (mc->du - kc0) / kc1;
  for (int i = 0; i < nc; i++)
    if (c[i] > x0 && c[i] < x1) cut[n++] = c[i];
  cut[n++] = x1;
  sort_cuts(cut, n);
  const double h = mc->h, du = mc->du, kn = mc->kn;
  for (int i = 0; i + 1 < n; i++) {
    const double u0 = cut[i], u1 = cut[i + 1];
    if (!(u1 > u0)) continue;
    const double xm = 0.5 * (u0 + u1), pm = a + w * xm, km = kc0 + kc1 * xm;
    if (pm >= 0.0) { /* compression, damaged or not */
      add_poly(u0, u1, kn * a, kn * w, kn, 0.5 * kn * a * a, kn * a * w, 0.5 * kn * w * w, 1, r);
    } else if (km >= du) { /* cracked through: nothing in tension */
    } else if (-pm < km - VS_ENV_ON * du) {
      secant_piece(mc, a, w, u0, u1, kc0 + kc1 * u0, kc1, r);
    } else {
      /* the fracture energy still held, h du (du - k) / 2 = gf - D(k), affine in xi */
      const double e0 = 0.5 * h * du * (du - kc0), e1 = -0.5 * h * du * kc1;
      if (-pm < du) /* the envelope: sigma = -h (du + p), phi = e - h (du + p)^2 / 2 */
        add_poly(u0, u1, -h * (du + a), -h * w, -h, e0 - 0.5 * h * (du + a) * (du + a),
                 e1 - h * (du + a) * w, -0.5 * h * w * w, 0, r);
      else
        add_poly(u0, u1, 0.0, 0.0, 0.0, e0, e1, 0.0, 0, r);
    }
  }
}

static mortar_curve mortar_curve_of(const vs_joint_law *law) {
  mortar_curve mc = {law->kn, law->ft, law->gf, 0.0, 0.0, 0.0};
  if (law->ft > 0.0) {
    mc.d0 = law->ft / law->kn;
    mc.du = 2.0 * law->gf / law->ft;
    if (!(mc.du > mc.d0)) mc.du = mc.d0 * (1.0 + 1e-9); /* outside the documented range: near brittle */
    mc.h = law->ft / (mc.du - mc.d0);
  }
  return mc;
}

/* The law's envelope vertices, 0 (undamaged) or 2..VS_JOINT_ENV_MAX: a count outside (a
 * caller's law not through vs_model_set_joint_law, which refuses it) is read within the
 * storage, never past it. */
static int env_count(const vs_joint_law *law) {
  return law->env_n < 2 ? 0 : (law->env_n > VS_JOINT_ENV_MAX ? VS_JOINT_ENV_MAX : law->env_n);
}

/* The intact part [x0, x1] (not cracked through by the fronts): undamaged where the envelope
 * is at its floor d0 (the curve of mortar_region), the secant law where it is above. */
static void intact_region(const mortar_curve *mc, const vs_joint_law *law, double a, double w,
                          double x0, double x1, vs_normal_response *r) {
  const int n = env_count(law);
  if (n == 0 || mc->ft <= 0.0) {
    mortar_region(mc, 0, a, w, x0, x1, r);
    return;
  }
  for (int j = 0; j + 1 < n; j++) {
    const double xa = law->env_x[j], xb = law->env_x[j + 1];
    const double u0 = fmax(x0, xa), u1 = fmin(x1, xb);
    if (!(u1 > u0)) continue;
    const double ka = law->env_k[j], kb = law->env_k[j + 1];
    if (ka <= mc->d0 && kb <= mc->d0) {
      mortar_region(mc, 0, a, w, u0, u1, r);
      continue;
    }
    const double kc1 = (kb - ka) / (xb - xa), kc0 = ka - kc1 * xa;
    damaged_region(mc, a, w, kc0, kc1, u0, u1, r);
  }
}

void vs_joint_normal_mortar(const vs_joint_law *law, double b, double t, double a, double w,
                            const double crack[2], vs_normal_response *r) {
  const double ci = fmax(0.0, crack[0]), ce = fmax(0.0, crack[1]);
  if (law->ft <= 0.0 && ci == 0.0 && ce == 0.0) {
    vs_joint_normal(law->kn, b, t, a, w, r);
    return;
  }
  const mortar_curve mc = mortar_curve_of(law);
  memset(r, 0, sizeof *r);
  const double h = 0.5 * t;
  const double xi = fmin(h, -h + ci), xe = fmax(xi, h - ce); /* intact: [xi, xe] */
  mortar_region(&mc, 1, a, w, -h, xi, r);
  intact_region(&mc, law, a, w, xi, xe, r);
  mortar_region(&mc, 1, a, w, xe, h, r);
  r->N *= b;
  r->M *= b;
  r->N_a *= b;
  r->N_w *= b;
  r->M_w *= b;
  r->energy *= b;
}

/* The envelope after a commit: max(P, l) of the polyline P (n vertices x, y) and the line
 * l(x) = l0 + l1 x, into (xo, yo) (at most n + 2 vertices); on[i]: the vertex lies on l. */
static int envelope_max(const double *x, const double *y, int n, double l0, double l1, double *xo,
                        double *yo, unsigned char *on) {
  int m = 0;
  double dprev = 0.0;
  for (int i = 0; i < n; i++) {
    const double d = l0 + l1 * x[i] - y[i];
    if (i > 0 && ((dprev > 0.0 && d < 0.0) || (dprev < 0.0 && d > 0.0))) {
      const double f = dprev / (dprev - d);
      xo[m] = x[i - 1] + f * (x[i] - x[i - 1]);
      yo[m] = y[i - 1] + f * (y[i] - y[i - 1]);
      on[m++] = 1;
    }
    xo[m] = x[i];
    yo[m] = d > 0.0 ? l0 + l1 * x[i] : y[i];
    on[m++] = d >= 0.0;
    dprev = d;
  }
  return m;
}

/* Drops the interior vertices that change nothing: inside the stretch now on the line, inside
 * a stretch at the floor d0, inside a stretch cracked through (>= du). Returns the new count. */
static int envelope_prune(double *x, double *y, unsigned char *on, int n, double d0, double du) {
  int m = 1;
  for (int i = 1; i < n; i++) {
    if (i + 1 < n) {
      const int lp = m - 1; /* the last kept */
      const int line = on[lp] && on[i] && on[i + 1];
      const int flat = y[lp] <= d0 && y[i] <= d0 && y[i + 1] <= d0;
      const int gone = y[lp] >= du && y[i] >= du && y[i + 1] >= du;
      if (line || flat || gone) continue;
    }
    x[m] = x[i], y[m] = y[i], on[m] = on[i];
    m++;
  }
  return m;
}

/* Past VS_JOINT_ENV_MAX vertices: drops the interior vertex whose chord adds the least area
 * (a convex polyline's chord lies above it: the damage only grows), until n fit. */
static int envelope_merge(double *x, double *y, int n, int *merged) {
  while (n > VS_JOINT_ENV_MAX) {
    int best = 1;
    double least = INFINITY;
    for (int i = 1; i + 1 < n; i++) {
      const double area = fabs((x[i + 1] - x[i - 1]) * (y[i] - y[i - 1]) -
                               (x[i] - x[i - 1]) * (y[i + 1] - y[i - 1]));
      if (area < least) least = area, best = i;
    }
    for (int i = best; i + 1 < n; i++) x[i] = x[i + 1], y[i] = y[i + 1];
    n--;
    (*merged)++;
  }
  return n;
}

/* How far in from the edge (side 0: xi = -t/2, 1: t/2) the envelope stays at or above du. */
static double envelope_front(const vs_joint_law *law, double du, int side) {
  const int n = law->env_n, step = side ? -1 : 1;
  const double *x = law->env_x, *k = law->env_k;
  int o = side ? n - 1 : 0; /* the last vertex at or above du, from the edge */
  if (k[o] < du) return 0.0;
  for (int i = o + step; i >= 0 && i < n; o = i, i += step)
    if (k[i] < du) {
      const double xf = x[o] + (k[o] - du) / (k[o] - k[i]) * (x[i] - x[o]);
      return side ? x[n - 1] - xf : xf - x[0];
    }
  return x[n - 1] - x[0];
}

double vs_joint_damage_update(vs_joint_law *law, double b, double t, double a, double w) {
  if (law->ft <= 0.0) return 0.0;
  const mortar_curve mc = mortar_curve_of(law);
  const double h = 0.5 * t;
  /* the opening -(a + w xi) reaches beyond d0 nowhere new: nothing changes */
  double x[VS_JOINT_ENV_MAX + 2] = {-h, h}, y[VS_JOINT_ENV_MAX + 2] = {mc.d0, mc.d0};
  int n = 2;
  if (env_count(law) > 0) {
    n = env_count(law);
    memcpy(x, law->env_x, (size_t)n * sizeof *x);
    memcpy(y, law->env_k, (size_t)n * sizeof *y);
  }
  int above = 0;
  for (int i = 0; i < n; i++) above |= -(a + w * x[i]) > y[i];
  if (!above) return 0.0;
  vs_normal_response before, after;
  vs_joint_normal_mortar(law, b, t, a, w, law->crack, &before);
  double xo[VS_JOINT_ENV_MAX + 4], yo[VS_JOINT_ENV_MAX + 4];
  unsigned char on[VS_JOINT_ENV_MAX + 4];
  int m = envelope_max(x, y, n, -a, -w, xo, yo, on);
  m = envelope_prune(xo, yo, on, m, mc.d0, mc.du);
  m = envelope_merge(xo, yo, m, &law->env_merged);
  law->env_n = m;
  memcpy(law->env_x, xo, (size_t)m * sizeof *xo);
  memcpy(law->env_k, yo, (size_t)m * sizeof *yo);
  for (int s = 0; s < 2; s++) law->crack[s] = fmax(law->crack[s], envelope_front(law, mc.du, s));
  vs_joint_normal_mortar(law, b, t, a, w, law->crack, &after);
  return before.energy - after.energy;
}

/* The cohesive-frictional limit at accumulated slip kappa and its slope in kappa (<= 0). */
static double shear_limit(double cA, double ku, double muN, double kappa, double *slope) {
  double coh = 0.0, dcoh = 0.0;
  if (cA > 0.0 && kappa < ku) coh = cA * (1.0 - kappa / ku), dcoh = -cA / ku;
  const double y = coh + muN;
  if (y <= 0.0) {
    *slope = 0.0;
    return 0.0;
  }
  *slope = dcoh;
  return y;
}

void vs_joint_shear_mortar(const vs_joint_law *law, double b, double t, const double crack[2],
                           double N, double slip, double slip_p_old, double kappa_old,
                           vs_shear_response *r) {
  const double kst = law->ks * b * t;
  const double bonded = fmax(0.0, t - fmax(0.0, crack[0]) - fmax(0.0, crack[1]));
  const double cA = law->c * b * bonded;
  const double ku = (law->c > 0.0) ? 2.0 * law->gc / law->c : 0.0;
  const double muN = law->mu * N;
  const double T_tr = kst * (slip - slip_p_old);
  double slope;
  const double y0 = shear_limit(cA, ku, muN, kappa_old, &slope);
  memset(r, 0, sizeof *r);
  r->T = T_tr;
  r->slip_p = slip_p_old;
  r->kappa = kappa_old;
  r->limit = y0;
  r->T_s = kst;
  if (fabs(T_tr) <= y0) return;
  /* sliding: |T_tr| - kst D = Y(kappa_old + D), Y piecewise linear in kappa; walk its pieces */
  const double sgn = (T_tr > 0.0) ? 1.0 : -1.0;
  double k0 = kappa_old, y = y0, T_abs = 0.0, D = 0.0, H = 0.0;
  for (int piece = 0; piece < 4; piece++) {
    H = -slope; /* the limit falls by H per unit slip on this piece */
    /* from kappa_old to k0 the plastic slip is k0 - kappa_old; on the piece, Y = y - H (k - k0) */
    const double rem = fabs(T_tr) - kst * (k0 - kappa_old) - y; /* > 0: slides further */
    const double d = rem / (kst - H);
    /* where this piece ends: the cohesion's end (kappa_u) or the limit reaching zero */
    double k_end = INFINITY;
    if (H > 0.0) k_end = fmin(ku, k0 + y / H);
    if (k0 + d <= k_end || piece == 3) {
      D = k0 + d - kappa_old;
      T_abs = (y > 0.0) ? fabs(T_tr) - kst * D : 0.0; /* the zero piece: no shear left */
      break;
    }
    k0 = k_end;
    y = shear_limit(cA, ku, muN, k0, &slope);
  }
  r->T = sgn * T_abs;
  r->slip_p = slip_p_old + sgn * D;
  r->kappa = kappa_old + D;
  r->limit = T_abs;
  r->sliding = 1;
  r->T_s = -kst * H / (kst - H);
  /* N enters the limit with mu unless the limit is the zero piece */
  r->T_N = (T_abs > 0.0) ? sgn * kst * law->mu / (kst - H) : 0.0;
}

/* J v: v turned +90 degrees. */
static inline void perp(const double v[2], double out[2]) {
  out[0] = -v[1];
  out[1] = v[0];
}

static inline double dot(const double u[2], const double v[2]) { return u[0] * v[0] + u[1] * v[1]; }

/* Kinematic measures of the joint and their gradients/Hessians in (qa, qb) (joint.h). */
typedef vs_joint_kinematics kinematics;

static void rot_cs(double c, double sn, const double v[2], double out[2]) {
  out[0] = c * v[0] - sn * v[1];
  out[1] = sn * v[0] + c * v[1];
}

void vs_joint_half_angle(double theta, double h[2]) {
  h[0] = cos(0.5 * theta);
  h[1] = sin(0.5 * theta);
}

/* hess = 0 computes values and gradients only (residual evaluations); 1 adds the Hessians.
 * ha, hb: the bodies' half-angle rotations (vs_joint_half_angle), so that no sincos is taken per
 * joint: R(theta_a), R(theta_b), the mean rotation and the half difference all follow from them. */
static void joint_kinematics(const vs_joint_geom *jg, const double qa[3], const double qb[3],
                             const double ha[2], const double hb[2], const double ra[2],
                             const double rb[2], int hess, kinematics *k) {
  const double n0[2] = {jg->nx, jg->nz};
  double pa[2], pb[2], va[2], vb[2], n[2], s[2], d[2];
  /* half = (theta_b - theta_a) / 2; R(theta_a) = R(theta_a / 2)^2, R(theta_m) = R(theta_a / 2) R(theta_b / 2) */
  const double ch = hb[0] * ha[0] + hb[1] * ha[1], sh = hb[1] * ha[0] - hb[0] * ha[1];
  const double ca = 1.0 - 2.0 * ha[1] * ha[1], sa = 2.0 * ha[0] * ha[1];
  const double cm = ha[0] * hb[0] - ha[1] * hb[1], sm = ha[1] * hb[0] + ha[0] * hb[1];
  rot_cs(ca, sa, ra, pa);
  rot_cs(1.0 - 2.0 * hb[1] * hb[1], 2.0 * hb[0] * hb[1], rb, pb);
  rot_cs(cm, sm, n0, n);
  perp(pa, va);
  perp(pb, vb);
  perp(n, s);
  for (int i = 0; i < 2; i++) d[i] = qb[i] - qa[i] + (pb[i] - rb[i]) - (pa[i] - ra[i]);
  memset(k->dw, 0, sizeof k->dw);
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
    k->hg_t[i] = -0.5 * s[i];
    k->hg_t[3 + i] = 0.5 * s[i];
    k->hs_t[i] = 0.5 * n[i];
    k->hs_t[3 + i] = -0.5 * n[i];
  }
  k->hg_t[2] = k->hg_t[5] = k->hs_t[2] = k->hs_t[5] = 0.0; /* unused: rotations are in h*_rr */
  k->hg_rr[0] = dot(pa, n) - dot(va, s) - 0.25 * dn;
  k->hg_rr[1] = -dot(pb, n) + dot(vb, s) - 0.25 * dn;
  k->hg_rr[2] = 0.5 * (dot(vb, s) - dot(va, s)) - 0.25 * dn;
  k->hs_rr[0] = dot(pa, s) + dot(va, n) - 0.25 * ds_;
  k->hs_rr[1] = -dot(pb, s) - dot(vb, n) - 0.25 * ds_;
  k->hs_rr[2] = 0.5 * (dot(va, n) - dot(vb, n)) - 0.25 * ds_;
  k->hw_rr[0] = -0.5 * sh;
  k->hw_rr[1] = -0.5 * sh;
  k->hw_rr[2] = 0.5 * sh;
}

/* Component i of (qa, qb) is a rotation (2, 5): the gap slope w depends on those alone, so its
 * gradient is zero on the translations, and the terms it multiplies there are left out below:
 * they only added zeros (the results differ at most in the sign of a zero). */
static inline int is_rot(int i) { return i == 2 || i == 5; }

/* Rates of the joint measures (penetration a, gap slope w, slip) from the bodies' velocities. */
static void joint_rates(const kinematics *k, const double va[3], const double vb[3], double *adot,
                        double *wdot, double *sdot) {
  const double vel[6] = {va[0], va[1], va[2], vb[0], vb[1], vb[2]};
  *adot = *wdot = *sdot = 0.0;
  for (int i = 0; i < 6; i++) {
    *adot -= k->dg[i] * vel[i];
    if (is_rot(i)) *wdot += k->dw[i] * vel[i];
    *sdot += k->ds[i] * vel[i];
  }
}

/* The law at one kinematic state: the normal response and the return-mapped shear. */
typedef vs_joint_law_state law_state;

/* law_eval for a mortared joint: vs_joint_normal_mortar and vs_joint_shear_mortar with the
 * law's damage. */
static void law_eval_mortar(const vs_joint_geom *jg, const vs_joint_law *law, const kinematics *k,
                            double slip_p_old, law_state *ls) {
  const double t = jg->length, b = jg->depth;
  vs_joint_normal_mortar(law, b, t, -k->g - law->gap0, k->w - law->gap1, law->crack, &ls->nr);
  vs_shear_response sr;
  vs_joint_shear_mortar(law, b, t, law->crack, ls->nr.N, k->sl, slip_p_old, law->kappa, &sr);
  ls->kst = law->ks * b * t;
  ls->T = sr.T;
  ls->slip_p = sr.slip_p;
  ls->sliding = sr.sliding;
  ls->sgn = (sr.T < 0.0) ? -1.0 : 1.0;
  ls->mortar = 1;
  ls->T_s = sr.T_s;
  ls->T_N = sr.T_N;
  ls->kappa = sr.kappa;
  ls->bonded = fmax(0.0, t - fmax(0.0, law->crack[0]) - fmax(0.0, law->crack[1]));
}

static void law_eval(const vs_joint_geom *jg, const vs_joint_law *law, const kinematics *k,
                     double slip_p_old, law_state *ls) {
  if (vs_joint_law_is_mortar(law)) {
    law_eval_mortar(jg, law, k, slip_p_old, ls);
    return;
  }
  const double t = jg->length, b = jg->depth;
  ls->mortar = 0;
  ls->T_s = ls->T_N = 0.0;
  ls->kappa = law->kappa;
  ls->bonded = 0.0;
  /* the initial gap is a constant offset: the derivatives are unchanged */
  vs_joint_normal(law->kn, b, t, -k->g - law->gap0, k->w - law->gap1, &ls->nr);
  /* shear over the whole joint, Coulomb limit by return mapping */
  ls->kst = law->ks * b * t;
  const double T_trial = ls->kst * (k->sl - slip_p_old);
  const double T_max = law->mu * ls->nr.N;
  ls->T = T_trial;
  ls->slip_p = slip_p_old;
  ls->sliding = 0;
  ls->sgn = 1.0;
  if (fabs(T_trial) > T_max) {
    ls->sgn = (T_trial > 0.0) ? 1.0 : -1.0;
    ls->T = ls->sgn * T_max;
    ls->slip_p = k->sl - ls->T / ls->kst;
    ls->sliding = 1;
  }
}

static void state_out(const vs_joint_geom *jg, const kinematics *k, const law_state *ls,
                      vs_joint_state *st) {
  const double t = jg->length, a = -k->g;
  st->N = ls->nr.N;
  st->T = ls->T;
  st->M = ls->nr.M;
  st->a = a;
  st->w = k->w;
  st->slip = k->sl;
  st->slip_p = ls->slip_p;
  st->contact = ls->nr.contact;
  st->gap_i = -(a - 0.5 * k->w * t);
  st->gap_e = -(a + 0.5 * k->w * t);
  st->sliding = ls->sliding;
  st->energy = ls->nr.energy + 0.5 * ls->kst * (k->sl - ls->slip_p) * (k->sl - ls->slip_p);
  st->kappa = ls->kappa;
}

/* f = N grad(a) + M grad(w) + T grad(slip), grad(a) = -grad(g) */
static void force_out(const kinematics *k, const law_state *ls, double f[6]) {
  for (int i = 0; i < 6; i++)
    f[i] = is_rot(i) ? -ls->nr.N * k->dg[i] + ls->nr.M * k->dw[i] + ls->T * k->ds[i]
                     : -ls->nr.N * k->dg[i] + ls->T * k->ds[i];
}

/* K = grad(a) dN^T + grad(w) dM^T + grad(s) dT^T + N H_a + M H_w + T H_s (k with Hessians) */
static void tangent_out(const vs_joint_law *law, const kinematics *k, const law_state *ls,
                        double K[36]) {
  const vs_normal_response *nr = &ls->nr;
  double dN[6], dM[6], dT[6];
  for (int j = 0; j < 6; j++) {
    const double da_j = -k->dg[j], dw_j = k->dw[j];
    dN[j] = is_rot(j) ? nr->N_a * da_j + nr->N_w * dw_j : nr->N_a * da_j;
    dM[j] = is_rot(j) ? nr->N_w * da_j + nr->M_w * dw_j : nr->N_w * da_j;
    if (ls->mortar) dT[j] = ls->T_s * k->ds[j] + ls->T_N * dN[j];
    else dT[j] = ls->sliding ? ls->sgn * law->mu * dN[j] : ls->kst * k->ds[j];
  }
  /* Action and reaction: the translations of b (3, 4) enter every measure and every one of its
   * Hessian terms with the opposite sign of a's (0, 1), exactly (the gradients are -n, n and -s,
   * s), so their rows and columns are the negated ones of a's -- negation is exact, the entries
   * are the same bits as computing them. The independent rows and columns: */
  static const int ind[4] = {0, 1, 2, 5};
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++) {
      const int i = ind[a], j = ind[b];
      K[i * 6 + j] = is_rot(i) ? -k->dg[i] * dN[j] + k->dw[i] * dM[j] + k->ds[i] * dT[j]
                               : -k->dg[i] * dN[j] + k->ds[i] * dT[j];
    }
  /* the Hessians' terms where they are non-zero: rows and columns of the rotations 2, 5 */
  const double N = nr->N, M = nr->M, T = ls->T;
  for (int t = 0; t < 2; t++) {
    const double h = -N * k->hg_t[t] + T * k->hs_t[t];
    K[t * 6 + 2] += h;
    K[t * 6 + 5] += h;
    K[2 * 6 + t] += h;
    K[5 * 6 + t] += h;
  }
  const int rr[3][2] = {{2, 2}, {5, 5}, {2, 5}};
  for (int e = 0; e < 3; e++) {
    const double h = -N * k->hg_rr[e] + M * k->hw_rr[e] + T * k->hs_rr[e];
    K[rr[e][0] * 6 + rr[e][1]] += h;
    if (e == 2) K[5 * 6 + 2] += h;
  }
  for (int a = 0; a < 4; a++) {
    const int i = ind[a];
    K[i * 6 + 3] = -K[i * 6 + 0];
    K[i * 6 + 4] = -K[i * 6 + 1];
  }
  for (int j = 0; j < 6; j++) {
    K[3 * 6 + j] = -K[0 * 6 + j];
    K[4 * 6 + j] = -K[1 * 6 + j];
  }
}

void vs_joint_eval_h(const vs_joint_geom *jg, const vs_joint_law *law, const double qa[3],
                     const double qb[3], const double ha[2], const double hb[2],
                     const double ra[2], const double rb[2], double slip_p_old, vs_joint_state *st,
                     double f[6], double K[36]) {
  kinematics k;
  joint_kinematics(jg, qa, qb, ha, hb, ra, rb, K != NULL, &k);
  law_state ls;
  law_eval(jg, law, &k, slip_p_old, &ls);
  if (st != NULL) state_out(jg, &k, &ls, st);
  if (f != NULL) force_out(&k, &ls, f);
  if (K != NULL) tangent_out(law, &k, &ls, K);
}

void vs_joint_point_eval(const vs_joint_geom *jg, const vs_joint_law *law, const double qa[3],
                         const double qb[3], const double ha[2], const double hb[2],
                         const double ra[2], const double rb[2], double slip_p_old,
                         vs_joint_point *pt) {
  joint_kinematics(jg, qa, qb, ha, hb, ra, rb, 1, &pt->k);
  law_eval(jg, law, &pt->k, slip_p_old, &pt->ls);
}

void vs_joint_point_out(const vs_joint_geom *jg, const vs_joint_law *law, const vs_joint_point *pt,
                        vs_joint_state *st, double f[6], double K[36]) {
  if (st != NULL) state_out(jg, &pt->k, &pt->ls, st);
  if (f != NULL) force_out(&pt->k, &pt->ls, f);
  if (K != NULL) tangent_out(law, &pt->k, &pt->ls, K);
}

/* Below this contact length, as a fraction of the joint length, the damping fades linearly to
 * zero, so that it vanishes continuously when the joint separates completely. */
static const double VS_DAMP_RAMP = 0.02;

/* Full-section viscous damping (joint.h, vs_joint_dashpot with beta = 0) from the kinematics
 * and normal response. */
static void dashpot_out(const vs_joint_geom *jg, double cn, double cs, const kinematics *k,
                        const law_state *ls, const double va[3], const double vb[3],
                        double f[6], double C[36], double *power) {
  const double t = jg->length, b = jg->depth;
  const double held = ls->mortar ? fmax(ls->nr.contact, ls->bonded) : ls->nr.contact;
  const double phi = fmin(1.0, held / (VS_DAMP_RAMP * t));
  /* full-section viscous damping: normal b c_n t, rotational b c_n t^3/12, shear b c_s t */
  const double ca = phi * b * cn * t, cw = phi * b * cn * t * t * t / 12.0, csl = phi * b * cs * t;
  double adot, wdot, sdot;
  joint_rates(k, va, vb, &adot, &wdot, &sdot);
  const double Nd = ca * adot, Md = cw * wdot, Td = csl * sdot;
  if (f != NULL)
    for (int i = 0; i < 6; i++)
      f[i] = is_rot(i) ? -Nd * k->dg[i] + Md * k->dw[i] + Td * k->ds[i]
                       : -Nd * k->dg[i] + Td * k->ds[i];
  if (power != NULL) *power = Nd * adot + Md * wdot + Td * sdot;
  if (C != NULL) {
    /* b's translations' rows and columns are a's negated, as in tangent_out */
    static const int ind[4] = {0, 1, 2, 5};
    for (int a = 0; a < 4; a++)
      for (int c = 0; c < 4; c++) {
        const int i = ind[a], j = ind[c];
        C[i * 6 + j] = is_rot(i) && is_rot(j)
                           ? ca * k->dg[i] * k->dg[j] + cw * k->dw[i] * k->dw[j] +
                                 csl * k->ds[i] * k->ds[j]
                           : ca * k->dg[i] * k->dg[j] + csl * k->ds[i] * k->ds[j];
      }
    for (int a = 0; a < 4; a++) {
      const int i = ind[a];
      C[i * 6 + 3] = -C[i * 6 + 0];
      C[i * 6 + 4] = -C[i * 6 + 1];
    }
    for (int j = 0; j < 6; j++) {
      C[3 * 6 + j] = -C[0 * 6 + j];
      C[4 * 6 + j] = -C[1 * 6 + j];
    }
  }
}

/* Stiffness-proportional damping (vs_joint_dashpot with beta > 0) likewise. */
static void tangent_dashpot_out(const vs_joint_geom *jg, const vs_joint_law *law, double beta,
                                const kinematics *k, const vs_normal_response *nr,
                                const double va[3], const double vb[3], double f[6], double C[36],
                                double *power) {
  const double cs = beta * law->ks * jg->depth * jg->length;
  const double caa = beta * nr->N_a, caw = beta * nr->N_w, cww = beta * nr->M_w;
  double adot, wdot, sdot;
  joint_rates(k, va, vb, &adot, &wdot, &sdot);
  const double Nd = caa * adot + caw * wdot, Md = caw * adot + cww * wdot, Td = cs * sdot;
  if (f != NULL)
    for (int i = 0; i < 6; i++) f[i] = -Nd * k->dg[i] + Md * k->dw[i] + Td * k->ds[i];
  if (power != NULL) *power = Nd * adot + Md * wdot + Td * sdot;
  if (C != NULL)
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++)
        C[i * 6 + j] = caa * k->dg[i] * k->dg[j] - caw * (k->dg[i] * k->dw[j] + k->dw[i] * k->dg[j]) +
                       cww * k->dw[i] * k->dw[j] + cs * k->ds[i] * k->ds[j];
}

/* Friction power (vs_joint_motion.friction) from the kinematics and the law's state. */
static double friction_out(const vs_joint_law *law, const kinematics *k, const law_state *ls,
                           const double va[3], const double vb[3]) {
  if (!ls->sliding) return 0.0;
  double adot, wdot, sdot;
  joint_rates(k, va, vb, &adot, &wdot, &sdot);
  const double Ndot = ls->nr.N_a * adot + ls->nr.N_w * wdot;
  const double Tdot = ls->mortar ? ls->T_s * sdot + ls->T_N * Ndot : ls->sgn * law->mu * Ndot;
  return ls->T * (sdot - Tdot / ls->kst);
}

void vs_joint_eval_motion(const vs_joint_geom *jg, const vs_joint_law *law,
                          const vs_joint_bodies *bd, double slip_p_old, const vs_joint_dashpot *dp,
                          vs_joint_motion *out) {
  kinematics k;
  joint_kinematics(jg, bd->qa, bd->qb, bd->ha, bd->hb, bd->ra, bd->rb, out->K != NULL, &k);
  law_state ls;
  law_eval(jg, law, &k, slip_p_old, &ls);
  if (out->f != NULL) force_out(&k, &ls, out->f);
  if (out->K != NULL) tangent_out(law, &k, &ls, out->K);
  out->power = out->friction = 0.0;
  if (bd->va == NULL) return;
  if (dp != NULL && dp->beta > 0.0)
    tangent_dashpot_out(jg, law, dp->beta, &k, &ls.nr, bd->va, bd->vb, out->fd, out->C, &out->power);
  else if (dp != NULL)
    dashpot_out(jg, dp->cn, dp->cs, &k, &ls, bd->va, bd->vb, out->fd, out->C, &out->power);
  if (out->want_friction) out->friction = friction_out(law, &k, &ls, bd->va, bd->vb);
}
