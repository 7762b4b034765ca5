/* The joint law's evaluations as the tests call them: the elastic law of a joint from the
 * bodies' rotations (half angles taken here), and its dashpots and friction power written again
 * from their documented formulas (joint.h: vs_joint_dashpot, vs_joint_motion.friction) on the
 * library's kinematics, to check the one evaluation the equations of motion make
 * (vs_joint_eval_motion) against. SI units. */
#ifndef VS_TEST_JOINT_REFERENCE_H
#define VS_TEST_JOINT_REFERENCE_H

#include "voussoir/joint.h"

/* vs_joint_eval_h with the half angles of qa[2] and qb[2]: a joint evaluated from the bodies'
 * positions alone. Outputs as there (any may be NULL). */
static inline void vs_test_joint_eval(const vs_joint_geom *jg, const vs_joint_law *law,
                                      const double qa[3], const double qb[3], const double ra[2],
                                      const double rb[2], double slip_p_old, vs_joint_state *st,
                                      double f[6], double K[36]) {
  double ha[2], hb[2];
  vs_joint_half_angle(qa[2], ha);
  vs_joint_half_angle(qb[2], hb);
  vs_joint_eval_h(jg, law, qa, qb, ha, hb, ra, rb, slip_p_old, st, f, K);
}

/* The dashpots dp (joint damping, or stiffness-proportional when dp->beta > 0) of the joint at
 * positions qa, qb and velocities va, vb (3 entries each: the reference points' and the angular
 * velocities) as joint.h defines them: C = J^T D J, f = C v, power = v . C v. Outputs: f[6],
 * C[36] (row-major), *power; none may be NULL. */
void vs_test_joint_dashpot(const vs_joint_geom *jg, const vs_joint_law *law,
                           const vs_joint_dashpot *dp, const double qa[3], const double qb[3],
                           const double va[3], const double vb[3], const double ra[2],
                           const double rb[2], double f[6], double C[36], double *power);

/* The friction power as joint.h defines it (vs_joint_motion.friction), W: T (sdot - Tdot / k_s b t)
 * while the joint slides, 0 while it sticks; arguments as vs_test_joint_dashpot, slip_p_old as
 * vs_joint_eval_h. */
double vs_test_joint_friction_power(const vs_joint_geom *jg, const vs_joint_law *law,
                                    const double qa[3], const double qb[3], const double va[3],
                                    const double vb[3], const double ra[2], const double rb[2],
                                    double slip_p_old);

#endif
