/* The joint law: a zero-thickness, no-tension, frictional, elastic interface between two rigid
 * bodies, with exact large-rotation kinematics. One evaluation returns the joint forces, their
 * exact derivatives (for the Jacobian) and the diagnostics the hinge detector reads.
 *
 * Kinematics. Let d(eta) be the displacement of the face of b relative to the face of a at the
 * joint point eta, and let the joint frame rotate with the mean rotation (theta_a + theta_b)/2:
 * n (from a to b) and s (along the joint, intrados to extrados). Then, exactly,
 *   gap(xi)  = d_c . n - w xi,  w = 2 sin((theta_b - theta_a)/2),  xi = eta - t/2 in [-t/2, t/2],
 *   slip     = d_c . s          (uniform along the joint),
 * where d_c is d at the joint centre. A common rigid motion of a and b gives d = 0: the law is
 * objective. The penetration p(xi) = a + w xi with a = -d_c . n.
 *
 * Normal law: sigma = k_n <p>, integrated in closed form over the compressed length (Winkler,
 * no tension). Shear: T = k_s b t (slip - slip_p) over the whole joint, so that its energy is a
 * function of the state and opening/reclosing creates no energy; Coulomb |T| <= mu N with the
 * plastic slip slip_p updated by return mapping (irreversible). SI units. */
#ifndef VOUSSOIR_JOINT_H
#define VOUSSOIR_JOINT_H

#include "voussoir/api.h"

#include "voussoir/geometry.h"

/* Vertices the damage envelope of a mortared joint keeps exactly (vs_joint_law's env_x, env_k).
 * A build may set it (-DVS_JOINT_ENV_MAX=N) for the convergence study runs/mortar_cap.sh; it
 * sets vs_joint_law's layout, so a library and its callers must be built with the same. */
#ifndef VS_JOINT_ENV_MAX
#define VS_JOINT_ENV_MAX 16
#endif

typedef struct {
  double kn; /* normal stiffness per unit area, N/m^3 */
  double ks; /* shear stiffness per unit area, N/m^3 */
  double mu; /* Coulomb friction coefficient */
  /* As-built misfit of the two faces (non-coplanar faces, [imperfections] face_mm): the initial
   * gap gap0 + gap1 xi (m; gap1 dimensionless) adds to the kinematic gap, so the penetration is
   * p(xi) = (a - gap0) + (w - gap1) xi and the closed form stays exact (0, 0: coplanar faces). */
  double gap0, gap1;
  /* Mortar (vs_joint_normal_mortar; all 0: a dry joint, the law above bit for bit): tensile
   * strength ft (Pa), cohesion c (Pa), mode-I and mode-II fracture energies gf, gc (N/m, J/m^2).
   * With ft > 0, gf must exceed ft^2 / (2 kn) (the softening branch then ends beyond the peak's
   * opening). */
  double ft, c, gf, gc;
  /* A mortared joint's damage, the state its law carries from one converged state to the next
   * (all 0: undamaged; a model commits it, vs_model_commit): crack[0], crack[1], the lengths
   * cracked through from the intrados and the extrados edge (m, vs_joint_damage_update), and
   * kappa, the accumulated plastic slip that softens the cohesion (m, vs_joint_shear_mortar).
   * vs_joint_eval_h and the functions below evaluate the mortar law with them when ft, c or a
   * crack is non-zero, else the dry law (bit for bit). */
  double crack[2], kappa;
  /* The mortar's damage along the joint: kmax(xi), the largest opening each point reached at a
   * committed state, with f_t / k_n as its floor, as the polyline through env_n vertices
   * (env_x increasing from -t/2 to t/2, xi as vs_normal_response's; env_k, m); env_n = 0:
   * undamaged (kmax = f_t / k_n everywhere). A maximum of the affine committed openings, it
   * is convex; vs_joint_damage_update keeps it exactly up to VS_JOINT_ENV_MAX vertices and
   * beyond merges vertices into the chord above (conservative: more damage), counting the
   * merges in env_merged. env_n is 0 or 2..VS_JOINT_ENV_MAX (vs_model_set_joint_law refuses
   * others). */
  int env_n, env_merged;
  double env_x[VS_JOINT_ENV_MAX], env_k[VS_JOINT_ENV_MAX];
} vs_joint_law;

/* Normal response of a no-tension Winkler joint of length t and depth b to the affine
 * penetration p(xi) = a + w xi, xi in [-t/2, t/2] (xi > 0 towards the extrados). */
typedef struct {
  double N;       /* normal force, compression > 0, N */
  double M;       /* moment of the contact stresses about the joint centre, N m
                     (> 0 when the extrados side carries more) */
  double N_a, N_w, M_w; /* exact partial derivatives (M_a = N_w) */
  double energy;  /* elastic energy stored, J */
  double contact; /* compressed length, m, in [0, t]. A joint that just touches everywhere
                     (a = w = 0) counts as closed: contact t and the full-contact tangent, so
                     that the stress-free reference state has a stiffness */
} vs_normal_response;

/* Closed-form normal response (see vs_normal_response). kn in N/m^3, b and t in m, a in m,
 * w dimensionless (the gap slope). Never fails. */
VS_API void vs_joint_normal(double kn, double b, double t, double a, double w,
                            vs_normal_response *r);

/* Normal response of a mortared joint (law->kn, ft, gf, its damage env_*; b, t, a, w as
 * vs_joint_normal, the law's initial gap left to the caller). Stress per unit area,
 * compression > 0, as a function of the opening delta = -p at a point whose largest committed
 * opening is k = max(kmax, d0) (vs_joint_law's env_*; d0 = ft / kn, du = 2 gf / ft,
 * h = ft / (du - d0)):
 *   sigma = kn p                     for p >= 0 (compression; a damaged point recloses fully)
 *   sigma = -S(k) delta              for 0 < delta < k, S(k) = h (du - k) / k (secant unloading
 *                                    and reloading; S(d0) = kn: the elastic branch undamaged)
 *   sigma = -h (du - delta)          for k <= delta < du (the softening envelope)
 *   sigma = 0                        for delta >= du, or for p < 0 where k >= du (cracked)
 * so that opening a unit area from closed to du takes gf, and a point unloaded from k has
 * dissipated D(k) = gf (k - d0) / (du - d0). crack[0], crack[1]: lengths from the intrados and
 * the extrados edge (m) cracked through besides (compression only there). The profile is
 * integrated piecewise in closed form: polynomials on the elastic, envelope and open pieces,
 * and on a secant piece, where k is affine in xi, the moments int s^m / k ds (m = 0..2) by
 * log1p or, where k varies little over the piece, by their series. N_a, N_w, M_w are the exact
 * derivatives (sigma is continuous in p and across the pieces' ends, so only the pieces'
 * tangents enter). energy is the potential int b phi(p) dxi with phi' = sigma (phi(0) = 0; on a
 * point opened beyond du, the fracture energy gf - D(k) still held). contact: the length where
 * p >= 0. ft = 0 with no crack: vs_joint_normal, bit for bit; crack[0] + crack[1] >= t: the
 * dry law (to rounding). */
VS_API void vs_joint_normal_mortar(const vs_joint_law *law, double b, double t, double a, double w,
                                   const double crack[2], vs_normal_response *r);

/* Irreversible damage after a converged state at (a, w): the law's envelope kmax(xi) becomes
 * max(kmax, -(a + w xi)) (env_*; merged into the chord above it, and env_merged counted, past
 * VS_JOINT_ENV_MAX vertices), and each edge's cracked length law->crack grows to the part of
 * the joint next to it where kmax reaches du (crack fronts move along eta, never back). Returns
 * the energy the damage dissipated, J: the drop of the joint's potential at (a, w)
 * (vs_joint_normal_mortar's energy, with law->crack), which is int b (D(k_new) - D(k_old)) dxi
 * (gf b per unit length cracked through from intact) unless vertices were merged. ft = 0:
 * nothing changes, returns 0. */
VS_API double vs_joint_damage_update(vs_joint_law *law, double b, double t, double a, double w);

/* Shear of a mortared joint (vs_joint_shear_mortar). */
typedef struct {
  double T;        /* shear force along s, N */
  double slip_p;   /* plastic slip after the return mapping, m */
  double kappa;    /* accumulated plastic slip |d slip_p|, the cohesion's softening variable, m */
  double limit;    /* the slip limit at the returned state, c(kappa) A_c + mu N (>= 0), N */
  double T_s, T_N; /* exact derivatives of T in the slip and in N (consistent tangent) */
  int sliding;     /* 1 when the limit is active */
} vs_shear_response;

/* Elastic shear T = k_s b t (slip - slip_p) with Coulomb's limit and cohesion, tension cut off:
 * |T| <= max(0, c(kappa) A_c + mu N), A_c = b (t - crack[0] - crack[1]) the bonded area (the
 * mortar not cracked through, vs_joint_normal_mortar), N the normal force (compression > 0;
 * tension lowers the limit, to zero at most). The cohesion softens linearly with the
 * accumulated plastic slip: c(kappa) = c (1 - kappa / kappa_u), kappa_u = 2 G_c / c, zero
 * beyond, so that sliding a bonded unit area through dissipates G_c beyond the friction's
 * mu N per unit slip. Return mapping from (slip_p_old, kappa_old), exact (the limit is piecewise
 * linear in kappa); T_s, T_N its consistent tangent. Needs k_s > c^2 / (2 G_c) (no snap-back;
 * the case checks it). c = 0: Coulomb's |T| <= mu N of vs_joint_eval_h (N >= 0). */
VS_API void vs_joint_shear_mortar(const vs_joint_law *law, double b, double t, const double crack[2],
                                  double N, double slip, double slip_p_old, double kappa_old,
                                  vs_shear_response *r);

/* Everything one joint evaluation yields. */
typedef struct {
  double N, T, M;     /* normal force (compression > 0), shear along s, moment about the centre */
  double a, w;        /* penetration at the centre (m) and gap slope (see above) */
  double slip;        /* total tangential displacement of b relative to a, m */
  double slip_p;      /* plastic slip after the return mapping, m */
  double contact;     /* compressed length, m */
  double gap_i;       /* opening at the intrados edge, m (> 0 open, < 0 penetration), measured
                         from the as-built fit (the law's initial gap gap0 + gap1 xi excluded) */
  double gap_e;       /* opening at the extrados edge, m (likewise) */
  int sliding;        /* 1 when the Coulomb limit is active */
  double energy;      /* elastic energy (normal + shear), J; a mortared joint's includes the
                         potential of its softening (vs_joint_normal_mortar) */
  double kappa;       /* accumulated plastic slip after the return mapping, m (mortar's
                         cohesion; a dry joint's: the law's kappa, unchanged) */
} vs_joint_state;

/* A body's rotation theta (rad) as the cosine and sine of theta / 2, h[0], h[1]: the joint
 * kinematics need R(theta_a), R(theta_b), the mean rotation and sin of the half difference, all
 * products of the two bodies' half angles, so that a model takes one sincos per body and
 * evaluation instead of two per joint. */
VS_API void vs_joint_half_angle(double theta, double h[2]);

/* Evaluate the joint between bodies a and b.
 * qa, qb: displacement of each body's reference point (ux, uz, m) and rotation (theta, rad,
 * counter-clockwise); ha, hb: their half angles (vs_joint_half_angle of qa[2], qb[2]); ra, rb:
 * vector from each body's reference point to the joint centre in the reference configuration
 * (m); slip_p_old: plastic slip at the last converged state.
 * Outputs (any may be NULL): st, the state; f[6], the gradient of the joint energy with respect
 * to (qa, qb) -- the internal generalised force, so that equilibrium reads sum f = external
 * load; K[36], row-major df/d(qa, qb), exact (consistent tangent of the return mapping). */
VS_API void vs_joint_eval_h(const vs_joint_geom *jg, const vs_joint_law *law, const double qa[3],
                            const double qb[3], const double ha[2], const double hb[2],
                            const double ra[2], const double rb[2], double slip_p_old,
                            vs_joint_state *st, double f[6], double K[36]);

/* --- a joint at one configuration, kept --- */

/* The joint's kinematic measures at one configuration: gap at the centre g, slip sl, gap slope
 * w, their gradients in (qa, qb), and their Hessians by their non-zeros (symmetric; none between
 * two translations): a translation t (0, 1, 3, 4) with either rotation (2, 5), hg_t[t] and
 * hs_t[t] (w's none); the rotations' (2,2), (5,5), (2,5) entries h*_rr[0..2]. */
typedef struct {
  double g, sl, w;
  double dg[6], ds[6], dw[6];
  double hg_t[6], hs_t[6];
  double hg_rr[3], hs_rr[3], hw_rr[3];
} vs_joint_kinematics;

/* The law at one kinematic state: the normal response and the return-mapped shear (the shear
 * stiffness k_s b t, the force T, the plastic slip, the sign of a sliding T, sliding or not). */
typedef struct {
  vs_normal_response nr;
  double kst, T, slip_p, sgn;
  int sliding;
  /* a mortared joint (the law's ft, c or a crack non-zero; else 0 and unused): the shear's
   * tangent dT = T_s dslip + T_N dN (vs_shear_response), the accumulated slip kappa and the
   * bonded length t - crack[0] - crack[1] (m), over which the mortar holds the faces together
   * whether compressed or not: the joint dashpots act over it as over a contact */
  int mortar;
  double T_s, T_N, kappa, bonded;
} vs_joint_law_state;

/* One evaluation of a joint kept: its state, forces and stiffness then follow from it without
 * evaluating the joint again (a model keeps its joints' points from a residual for the Jacobian
 * at the same state). */
typedef struct {
  vs_joint_kinematics k;
  vs_joint_law_state ls;
} vs_joint_point;

/* The point of the joint at (qa, qb) with the bodies' half angles ha, hb, arguments as
 * vs_joint_eval_h; the kinematics include their second derivatives. */
VS_API void vs_joint_point_eval(const vs_joint_geom *jg, const vs_joint_law *law,
                                const double qa[3], const double qb[3], const double ha[2],
                                const double hb[2], const double ra[2], const double rb[2],
                                double slip_p_old, vs_joint_point *pt);

/* The outputs of vs_joint_eval_h at the point's configuration (the same values, bit for bit;
 * any may be NULL). law: the one the point was evaluated with. */
VS_API void vs_joint_point_out(const vs_joint_geom *jg, const vs_joint_law *law,
                               const vs_joint_point *pt, vs_joint_state *st, double f[6],
                               double K[36]);

/* --- one evaluation for the equations of motion --- */

/* The two bodies of a joint at one state: positions (ux, uz, theta), half angles
 * (vs_joint_half_angle), velocities of the reference points and angular velocities (va, vb:
 * 3 entries each; NULL: no rates wanted) and reference-point-to-joint-centre vectors, as in
 * vs_joint_eval_h. */
typedef struct {
  const double *qa, *qb, *ha, *hb, *va, *vb, *ra, *rb;
} vs_joint_bodies;

/* A joint's dashpots, acting on the rates adot, wdot, sdot of its measures (the penetration at
 * the centre, the gap slope and the slip) with a matrix D: the damping force is f = C v with
 * C = J^T D J (J: the measures' gradients in (qa, qb), v the bodies' velocities), symmetric
 * positive semi-definite, so it only dissipates, the power v . C v >= 0; C leaves out its own
 * dependence on the positions.
 * Joint damping c_n, c_s (N s/m^3), when beta = 0: the full section's dashpots, D =
 * diag(b c_n t, b c_n t^3/12, b c_s t), acting while the joint is in contact and fading
 * linearly to zero as the contact length drops below 2 % of t (continuous at separation); a
 * mortared joint's contact here is at least its bonded length (vs_joint_law_state), so that
 * its dashpots act until it cracks through. A
 * hinge thus damps its rotation as the closed joint would, which is what makes a rocking
 * mechanism lose energy; a law on the compressed part only would damp a hinge like c^3 and leave
 * rocking undamped.
 * Stiffness-proportional damping beta (s), when beta > 0, instead: D = beta times the joint's
 * material tangent stiffness (the normal law's [[N_a, N_w], [N_w, M_w]] over the compressed
 * length, and k_s b t in shear; no geometric terms). A closed joint gets beta k_n b t,
 * beta k_n b t^3 / 12, beta k_s b t; a hinge only what its compressed part carries, an open
 * joint nothing in the normal direction; the power is >= 0 (the tangent is the Hessian of a
 * convex energy). */
typedef struct {
  double cn, cs, beta;
} vs_joint_dashpot;

/* Outputs of vs_joint_eval_motion: set the pointers wanted (NULL: not computed). */
typedef struct {
  double *f, *K;     /* elastic force [6] and tangent [36] (vs_joint_eval_h) */
  double *fd, *C;    /* damping force [6] and C = df/dv [36], row-major (vs_joint_dashpot) */
  int want_friction; /* compute the friction power */
  double power;      /* out: damping power, W (0 without dashpots or velocities) */
  double friction;   /* out: power dissipated by frictional slip, W: T (sdot - Tdot / (k_s b t))
                        for a sliding joint (the shear power T sdot minus the rate of the shear
                        energy T^2 / (2 k_s b t)), 0 when it sticks, without velocities or
                        unless wanted */
} vs_joint_motion;

/* Everything the equations of motion take from a joint at one state, from one evaluation of
 * its kinematics and its law: the elastic force and tangent of vs_joint_eval_h, the dashpots'
 * force, matrix and power (vs_joint_dashpot; dp NULL: no damping) and the friction power at the
 * same state. */
VS_API void vs_joint_eval_motion(const vs_joint_geom *jg, const vs_joint_law *law,
                                 const vs_joint_bodies *bd, double slip_p_old,
                                 const vs_joint_dashpot *dp, vs_joint_motion *out);

#endif
