/* The model: equilibrium of the rigid voussoirs under gravity and the joint forces, with the
 * right support moved by delta along a fixed direction (or both supports each along its own
 * motion in delta: vs_model_set_support_motion). Residual and analytic CSC Jacobian share
 * one evaluation of the joint law; the sparsity pattern is built once. SI units. */
#ifndef VOUSSOIR_MODEL_H
#define VOUSSOIR_MODEL_H

#include "voussoir/api.h"

#include "voussoir/geometry.h"
#include "voussoir/joint.h"
#include "voussoir/status.h"
#include "voussoir/support.h"

typedef struct vs_model vs_model;

/* Create a model over geometry g (borrowed: it must outlive the model) with joint law law and
 * the right support moving along alpha_rad measured from the vertical: the support
 * displacement is delta (sin alpha, -cos alpha). Fails with VS_ERR_INVALID on a bad law. */
VS_API vs_status vs_model_create(const vs_geometry *g, const vs_joint_law *law, double alpha_rad,
                                 vs_model **out, vs_error *err);

/* Free m and NULL *m; NULL allowed. */
VS_API void vs_model_destroy(vs_model **m);

/* Support kinds. fixed: the springer is clamped (no rotation). pinned: the springer rotates
 * freely about its pivot, the centre of its joint with the arch (the mid-point of the springing
 * face; a pier on a hinge), while the pivot follows the prescribed motion. */

/* Set the two supports' kinds (default both fixed); call before any other use of m, since it
 * changes the unknowns: each pinned support's rotation theta_s (rad, counter-clockwise) becomes
 * a static unknown after the blocks' (left first), whose equation dE/dtheta_s = 0 is the moment
 * of the springing joint's forces about the pivot. VS_ERR_INVALID on an unknown kind. */
VS_API vs_status vs_model_set_support_kinds(vs_model *m, vs_support_kind left,
                                            vs_support_kind right, vs_error *err);
VS_API vs_support_kind vs_model_support_kind(const vs_model *m, int right);
/* Index in q of the support's rotation (right = 0: left, 1: right), -1 if it is fixed. */
VS_API int vs_model_support_dof(const vs_model *m, int right);
/* The unknowns in an order in which the Jacobian is a narrow band (perm[new] = old; perm has
 * vs_model_size entries): the blocks' in q's order, and a pinned support's rotation, which q
 * keeps after the blocks, next to the block it carries (left first, right last). In q's own
 * order those rotations couple the first and last blocks to the last rows, and a band
 * factorisation (LAPACK's) would take the whole matrix as its band. */
VS_API void vs_model_band_order(const vs_model *m, int *perm);

/* Number of unknowns and Jacobian non-zeros. The state q is block-major: q[3i], q[3i+1] are the
 * displacement (m) of block i's centroid (its reference point) and q[3i+2] its rotation (rad,
 * counter-clockwise); then the rotations of the pinned supports (vs_model_support_dof). */
VS_API int vs_model_size(const vs_model *m);
VS_API int vs_model_nnz(const vs_model *m);
VS_API const vs_geometry *vs_model_geometry(const vs_model *m);
VS_API const vs_joint_law *vs_model_law(const vs_model *m);

/* Displacement of the right support (ux, uz, m) for support displacement delta (m). */
VS_API void vs_model_support_displacement(const vs_model *m, double delta, double u[2]);

/* Both supports' motions (support.h). The model is created with the left support fixed and the
 * right one moving by delta along alpha; vs_model_set_support_motion gives support right (0:
 * left, 1: right) motion mo instead (copied), so that delta becomes a loading parameter along
 * which each support follows its own path, and the load vector dG/d(delta) is the sum of both
 * supports' (a fixed support's rotation included). A pinned support's rotation stays free: its
 * motion's theta is not used. VS_ERR_INVALID on segments that do not start at 0 or increase. */
VS_API vs_status vs_model_set_support_motion(vs_model *m, int right, const vs_support_motion *mo,
                                             vs_error *err);
VS_API const vs_support_motion *vs_model_support_motion(const vs_model *m, int right);
/* Both supports' (ux, uz, theta) at delta (m, m, rad: left, then right; the right support's
 * initial offset included, as vs_model_support_displacement), a pinned support's rotation from
 * the static state q (NULL: zero). */
VS_API void vs_model_support_position(const vs_model *m, const double *q, double delta,
                                      double u[6]);
/* The first point beyond delta + tol (m) where a support's motion changes its rate: the path
 * solver lands there, INFINITY if there is none. */
VS_API double vs_model_support_next_kink(const vs_model *m, double delta, double tol);

/* Imperfections. vs_model_set_joint_law replaces the law of joint k (0-based; every joint starts
 * with the law given at creation) and recomputes its damping coefficients; VS_ERR_INVALID on a
 * bad k or law. vs_model_set_support_offset sets an initial offset (m) of the right support; the
 * loading delta adds to it, and vs_model_support_displacement includes it. Default: none.
 * The misfit (the joints' initial gaps and the support offset) is applied times the misfit
 * factor s (default 1), which the quasi-static solver grows from 0 to 1 after self-weight: the
 * arch stands on its nominal faces and supports, then settles into its misfit (a face touching
 * at one edge has no stiffness, so the stress-free reference is no place to start from).
 * vs_model_has_misfit: 1 if there is any misfit to apply. */
VS_API vs_status vs_model_set_joint_law(vs_model *m, int k, const vs_joint_law *law, vs_error *err);
VS_API const vs_joint_law *vs_model_joint_law(const vs_model *m, int k);
VS_API void vs_model_set_support_offset(vs_model *m, const double offset[2]);
VS_API int vs_model_has_misfit(const vs_model *m);
VS_API void vs_model_set_misfit_scale(vs_model *m, double s);

/* Residual G(q; delta) = joint forces - gravity, per block (Fx, Fz in N, moment in N m).
 * Equilibrium is G = 0. Uses the committed plastic slips. */
VS_API void vs_model_residual(const vs_model *m, const double *q, double delta, double *G);

/* dG/d(delta) at (q, delta), the load vector of the support motion. */
VS_API void vs_model_dG_ddelta(const vs_model *m, const double *q, double delta, double *out);

/* States of all joints at (q, delta) with the committed plastic slips; st has n_joints entries. */
VS_API void vs_model_joint_states(const vs_model *m, const double *q, double delta,
                                  vs_joint_state *st);

/* Accept (q, delta) as a converged state: the plastic slips of sliding joints are updated.
 * Returns the number of joints in contact (N > 0) that slid in this step. */
VS_API int vs_model_commit(vs_model *m, const double *q, double delta);

/* vs_model_commit from the joint states st (n_joints) at the state accepted, as
 * vs_model_joint_states or vs_model_ext_joint_states gave them with the committed slips: the
 * commit then takes no evaluation of its own. Returns as vs_model_commit. */
VS_API int vs_model_commit_states(vs_model *m, const vs_joint_state *st);

/* Plastic slip of every joint (m), committed; n_joints entries. */
VS_API const double *vs_model_slips(const vs_model *m);

/* Energy dissipated by the mortared joints' cracking since the model was created, J: the sum of
 * vs_joint_damage_update's over every commit (vs_model_commit, vs_model_commit_states,
 * vs_model_ext_commit), which also grow each joint's damage envelope, cracks and cohesion slip
 * (vs_joint_law's env_*, crack and kappa, vs_model_joint_law). 0 for dry joints. */
VS_API double vs_model_cracking_energy(const vs_model *m);

/* --- slip: a joint at the Coulomb limit put on its sliding branch --- */
/* A joint that slid is committed a hair behind its return-mapped slip (by 1e-9 of its elastic
 * slip), so that at the committed state it still evaluates as sliding, with its force mu N and
 * the sliding branch's tangent. vs_model_set_branches puts joints on a branch at (q, delta) by
 * their committed slips (branch: n_joints entries): VS_BRANCH_SLIDE_POS (slide with T > 0, b
 * moving along s relative to a) or _NEG (the other way): the trial shear just past the Coulomb
 * limit in that sense, so that the joint carries mu N (instead of its elastic shear) with the
 * sliding branch's tangent; VS_BRANCH_STICK: a joint sliding there gets its trial just inside
 * the limit, its force unchanged and its tangent elastic; VS_BRANCH_KEEP: left alone. Returns
 * how many it changed. vs_model_set_slips sets every committed slip (n_joints, m), e.g. back to
 * a copy of vs_model_slips. Both drop what the model kept of the joints' evaluation. */
enum { VS_BRANCH_SLIDE_NEG = -1, VS_BRANCH_KEEP = 0, VS_BRANCH_SLIDE_POS = 1, VS_BRANCH_STICK = 2 };
VS_API int vs_model_set_branches(vs_model *m, const double *q, double delta,
                                 const signed char *branch);
VS_API void vs_model_set_slips(vs_model *m, const double *slips);

/* Forces exerted by the arch on the left and right supports (Fx, Fz in N). */
VS_API void vs_model_reactions(const vs_model *m, const double *q, double delta, double left[2],
                               double right[2]);

/* Forces and moments the supports exert on the arch at an equilibrium (q, delta): left (Fx, Fz
 * in N, M in N m counter-clockwise about the centre of the springing joint), then right. The
 * quasi-static phase's reactions; in the dynamic phase they are the multipliers lambda
 * (vs_dynamic_reactions), which add the joints' damping forces. */
VS_API void vs_model_support_reactions(const vs_model *m, const double *q, double delta,
                                       double out[6]);
/* Total potential energy: joint elastic energy minus the work of gravity, J. */
VS_API double vs_model_energy(const vs_model *m, const double *q, double delta);

/* Typical force (N) and moment (N m) of each equation, for scaling: the block's weight and its
 * weight times the joint length. scale has vs_model_size entries. */
VS_API void vs_model_residual_scale(const vs_model *m, double *scale);

/* Gravity load factor lambda (default 1: the arch's own weight), for the self-weight
 * continuation; residual and energies use lambda m g. */
VS_API void vs_model_set_gravity_scale(vs_model *m, double lambda);
VS_API double vs_model_gravity_scale(const vs_model *m);

/* --- external loads ---
 * Dead forces on the blocks besides their weight (a live load, issue 28; a fill's load), each of
 * fixed size and direction (fx, fz; N) applied at the material point of its block that lies at
 * (px, pz) (m) in the reference configuration, so that its arm turns with the block. They act
 * times the load factor lambda (default 0: none) in the residual (generalised forces on the
 * block: Fx, Fz, and the moment about its moving centroid), the Jacobian, the dynamic phase and
 * the potential energy (vs_model_gravity_energy adds -lambda f . u). */
typedef struct {
  int block; /* 0-based */
  double fx, fz, px, pz;
} vs_model_force;
/* Set the loads (copied; n = 0 removes them). VS_ERR_INVALID on a block out of range or a value
 * that is not finite, VS_ERR_NOMEM. */
VS_API vs_status vs_model_set_loads(vs_model *m, const vs_model_force *f, int n, vs_error *err);
VS_API int vs_model_load_count(const vs_model *m);
/* Dead forces besides the weight (a fill's), as the loads but always at factor 1 (also in the
 * residual, the Jacobian, the dynamics and the energy; not in the load vector or the loads'
 * displacement). Errors as vs_model_set_loads'. */
VS_API vs_status vs_model_set_dead_loads(vs_model *m, const vs_model_force *f, int n,
                                         vs_error *err);
VS_API void vs_model_set_load_factor(vs_model *m, double lambda);
VS_API double vs_model_load_factor(const vs_model *m);
/* The loads' generalised forces at lambda = 1 at state q (vs_model_size entries; a pinned
 * support's rotation gets 0): dG/dlambda = -out. */
VS_API void vs_model_load_vector(const vs_model *m, const double *q, double *out);
/* The loads' displacement at q: the work of the loads at lambda = 1 on the displacements of
 * their points, over the sum of their sizes |f| (m): for a single force, its point's
 * displacement along it (a vertical point load's deflection). Its gradient in q is
 * vs_model_load_vector / vs_model_load_size. 0 without loads. */
VS_API double vs_model_load_displacement(const vs_model *m, const double *q);
/* The sum of the loads' sizes |f| at lambda = 1, N. */
VS_API double vs_model_load_size(const vs_model *m);

/* --- dynamics --- */

/* Joint damping as a fraction zeta (>= 0) of each joint's own critical damping: for a joint of
 * area A = b t with normal stiffness k_n A between blocks of masses m_a, m_b (reduced mass
 * m = m_a m_b / (m_a + m_b); the block's mass at a support), c_n = 2 zeta sqrt(k_n A m) / A and
 * likewise c_s with k_s. Acts only where the joint is in contact (joint.h, vs_joint_dashpot).
 * Default 0 (no damping) until set. */
VS_API void vs_model_set_damping(vs_model *m, double zeta);
VS_API double vs_model_damping_ratio(const vs_model *m);

/* Rayleigh damping C = alpha M + beta K_c (alpha 1/s, beta s, both >= 0), replacing the joint
 * damping: K_c is the joints' current material tangent stiffness (vs_joint_dashpot's beta: no
 * damping force across an open gap, a hinge damped by what its compressed part carries); the
 * mass part acts on absolute velocities. vs_model_set_damping(m, 0) removes it. */
VS_API void vs_model_set_rayleigh(vs_model *m, double alpha, double beta);

/* Power dissipated by frictional slip in all joints at (q, v), W (vs_joint_motion.friction). */
VS_API double vs_model_friction_power(const vs_model *m, const double *q, const double *v,
                                      double delta, double ddelta_dt);

/* Diagonal of the mass matrix (3n: m, m, I per block; constant for centroid coordinates). */
VS_API void vs_model_mass(const vs_model *m, double *mdiag);

/* Kinetic energy of velocities v, J. */
VS_API double vs_model_kinetic_energy(const vs_model *m, const double *v);

/* Force (N) the moving supports exert on the arch along their motion: the generalised force
 * conjugate to delta (each support's force and moment on the arch dotted with its motion's rate
 * d(ux, uz, theta)/d(delta)), through the joints' elastic and frictional forces; times
 * d(delta)/dt it is the supports' power. */
VS_API double vs_model_support_force(const vs_model *m, const double *q, double delta);

/* Gravitational potential of the blocks at q (J; zero in the reference configuration): the
 * first 3 n_blocks entries of q, so a static state or an extended one. With the joints' energies
 * (vs_joint_state.energy) it makes vs_model_energies without another evaluation. */
VS_API double vs_model_gravity_energy(const vs_model *m, const double *q);

/* Joint elastic energy and gravitational potential separately (J; potential zero in the
 * reference configuration). */
VS_API void vs_model_energies(const vs_model *m, const double *q, double delta, double *elastic,
                              double *gravity);

/* --- driven supports (the dynamic phase's semi-explicit DAE) ---
 * The two springers as bodies: the extended state qe has vs_model_ext_size = 3 n_blocks + 6
 * entries, the blocks' (as q) followed by the left and the right support's (ux, uz, theta) (m,
 * rad) of its reference point, the centre of its joint with the arch (a support's rotation
 * turns it about that point). The ext functions evaluate the joints at the supports' states
 * taken from qe instead of prescribed by delta; forces and matrices cover all 3 n_blocks + 6
 * unknowns (gravity acts on the blocks only). */
VS_API int vs_model_ext_size(const vs_model *m);
VS_API int vs_model_ext_nnz(const vs_model *m);
/* Supports' states (qs: left (ux, uz, theta), right) prescribed by delta and their velocities
 * (vs) at the loading rate d(delta)/dt = rate (m/s): each on its motion (by default the left
 * fixed, the right moving along alpha, no rotation; a pinned support's rotation is not
 * prescribed: the caller sets it). */
VS_API void vs_model_support_states(const vs_model *m, double delta, double rate, double qs[6],
                                    double vs[6]);
/* Mass diagonal over qe: the blocks' (vs_model_mass), then each support body with the mean
 * voussoir's mass and inertia (for a pinned support, its rotary inertia about the pivot). Driven at constant speed, a support has no acceleration, so its
 * mass only keeps the equations of motion regular; it does not enter the reactions. */
VS_API void vs_model_ext_mass(const vs_model *m, double *mdiag);
/* Ge = dE/dqe (joint forces minus the load) over qe; the supports' rows are the joint forces'
 * gradients with respect to the supports' coordinates. */
VS_API void vs_model_ext_residual(const vs_model *m, const double *qe, double *Ge);
VS_API double vs_model_ext_friction_power(const vs_model *m, const double *qe, const double *ve);
/* The supports' rows of vs_model_ext_motion's F (left ux, uz, theta, then right; elastic and
 * damping forces of the joints at the supports, the only ones acting there) from those joints
 * alone. */
VS_API void vs_model_ext_support_forces(const vs_model *m, const double *qe, const double *ve,
                                        double out[6]);
VS_API void vs_model_ext_joint_states(const vs_model *m, const double *qe, vs_joint_state *st);
VS_API int vs_model_ext_commit(vs_model *m, const double *qe);
VS_API void vs_model_ext_energies(const vs_model *m, const double *qe, double *elastic,
                                  double *gravity);

#endif
