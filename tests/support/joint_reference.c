/* The joint's dashpots and friction power from their definitions in joint.h, as matrices: the
 * rates of the joint's measures r = J v (J's rows the gradients of the penetration a = -g, the
 * gap slope w and the slip s), the dashpot matrix D on them, C = J^T D J. The kinematics and the
 * normal response are the library's (vs_joint_point_eval), checked on their own in test_joint. */
#include "joint_reference.h"

#include <math.h>

/* J (3 x 6, row-major: a, w, s) of the joint point, and its rates r = J v. */
static void rates(const vs_joint_point *pt, const double va[3], const double vb[3], double J[18],
                  double r[3]) {
  const double v[6] = {va[0], va[1], va[2], vb[0], vb[1], vb[2]};
  for (int i = 0; i < 6; i++) {
    J[i] = -pt->k.dg[i];
    J[6 + i] = pt->k.dw[i];
    J[12 + i] = pt->k.ds[i];
  }
  for (int k = 0; k < 3; k++) {
    r[k] = 0.0;
    for (int i = 0; i < 6; i++) r[k] += J[6 * k + i] * v[i];
  }
}

static void point(const vs_joint_geom *jg, const vs_joint_law *law, const double qa[3],
                  const double qb[3], const double ra[2], const double rb[2], double slip_p_old,
                  vs_joint_point *pt) {
  double ha[2], hb[2];
  vs_joint_half_angle(qa[2], ha);
  vs_joint_half_angle(qb[2], hb);
  vs_joint_point_eval(jg, law, qa, qb, ha, hb, ra, rb, slip_p_old, pt);
}

/* D of the dashpots dp at the joint point (joint.h, vs_joint_dashpot), 3 x 3 row-major. */
static void dashpot_matrix(const vs_joint_geom *jg, const vs_joint_law *law,
                           const vs_joint_dashpot *dp, const vs_joint_point *pt, double D[9]) {
  const double t = jg->length, b = jg->depth;
  const vs_normal_response *nr = &pt->ls.nr;
  for (int k = 0; k < 9; k++) D[k] = 0.0;
  if (dp->beta > 0.0) { /* beta times the material tangent */
    D[0] = dp->beta * nr->N_a;
    D[1] = D[3] = dp->beta * nr->N_w;
    D[4] = dp->beta * nr->M_w;
    D[8] = dp->beta * law->ks * b * t;
    return;
  }
  /* the full section's dashpots, faded below a contact of 2 % of t */
  const double fade = fmin(1.0, nr->contact / (0.02 * t));
  D[0] = fade * b * dp->cn * t;
  D[4] = fade * b * dp->cn * t * t * t / 12.0;
  D[8] = fade * b * dp->cs * t;
}

void vs_test_joint_dashpot(const vs_joint_geom *jg, const vs_joint_law *law,
                           const vs_joint_dashpot *dp, const double qa[3], const double qb[3],
                           const double va[3], const double vb[3], const double ra[2],
                           const double rb[2], double f[6], double C[36], double *power) {
  vs_joint_point pt;
  point(jg, law, qa, qb, ra, rb, 0.0, &pt);
  double J[18], r[3], D[9];
  rates(&pt, va, vb, J, r);
  dashpot_matrix(jg, law, dp, &pt, D);
  const double v[6] = {va[0], va[1], va[2], vb[0], vb[1], vb[2]};
  *power = 0.0;
  for (int i = 0; i < 6; i++) {
    f[i] = 0.0;
    for (int j = 0; j < 6; j++) {
      double c = 0.0;
      for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++) c += J[6 * k + i] * D[3 * k + l] * J[6 * l + j];
      C[6 * i + j] = c;
      f[i] += c * v[j];
    }
    *power += v[i] * f[i];
  }
}

double vs_test_joint_friction_power(const vs_joint_geom *jg, const vs_joint_law *law,
                                    const double qa[3], const double qb[3], const double va[3],
                                    const double vb[3], const double ra[2], const double rb[2],
                                    double slip_p_old) {
  vs_joint_point pt;
  point(jg, law, qa, qb, ra, rb, slip_p_old, &pt);
  if (!pt.ls.sliding) return 0.0;
  double J[18], r[3];
  rates(&pt, va, vb, J, r);
  /* sliding: T = sgn mu N(a, w), so Tdot = sgn mu (N_a adot + N_w wdot) */
  const double Tdot = pt.ls.sgn * law->mu * (pt.ls.nr.N_a * r[0] + pt.ls.nr.N_w * r[1]);
  return pt.ls.T * (r[2] - Tdot / pt.ls.kst);
}
