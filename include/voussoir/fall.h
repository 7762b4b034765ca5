/* The fall after the collapse as nonsmooth contact dynamics: the voussoirs as rigid bodies
 * meeting one another, the piers and the ground through unilateral contacts with Coulomb
 * friction and perfectly plastic impacts, integrated by a time-stepping scheme whose cost does
 * not grow with the number of impacts. SI units; t is the loading time (delta = rate t).
 *
 * Scheme (Moreau's sweeping process, in the form of Jean's "nonsmooth contact dynamics"): at
 * each step of length h the contacts are found at the start positions q_k and the impulses P
 * over the step solve, with the free velocity v_f = v_k + h M^-1 f (f: gravity),
 *   v+ = v_f + M^-1 sum_c H_c^T P_c,   q_k+1 = q_k + h v+,
 * and at each contact c, with u = H_c v+ its relative velocity (normal n, tangent t):
 *   - Signorini: u_n >= b_c, P_n >= 0, P_n (u_n - b_c) = 0, with b_c = -g_c / h where the gap
 *     g_c > 0 (the contact may close within the step but not pass through) and b_c = 0 where
 *     the bodies touch or overlap (an impact stops the approach: restitution 0, the value that
 *     gives Housner's rocking law, and an existing overlap does not deepen);
 *   - Coulomb: |P_t| <= mu P_n, and P_t = -mu P_n sign(u_t) where the contact slides.
 * The impulses are solved by nonsmooth Gauss-Seidel over the contacts (each contact's 2 x 2
 * problem exactly), each sweep followed by a nonsmooth nonlinear conjugate gradient step (NNCG:
 * fewer sweeps to the same stopping tolerance), warm-started from the previous step's impulses
 * (scaled by the ratio of the steps where the step changes: what a contact carries is a
 * force). The step is h while any point of a block moves faster than a set speed, a longer one
 * while none does (the debris settling): both bound how far a point moves in a step, and so how
 * deep an impact can overlap. Bodies and contacts:
 *  - every body has a convex outline (collide.h: a voussoir's four corners and its extrados
 *    mid-point; a pier's springing face and the vertical drops from its ends); the piers move
 *    as the supports do (the right one at the loading rate, a pinned one keeping its rotation);
 *  - a vertex meets another body's outline on the feature nearest to it, an edge it is in
 *    front of or a corner whose region it is in (the normal from the corner to it), or, inside
 *    it, the edge it is least deep behind; found by a broad phase on bounding boxes (sort and
 *    sweep along x) and that narrow phase; the ground is the plane z = level;
 *  - two bodies that share a joint meet on their joint faces: at each edge the face end of one
 *    on the other's face (two contact points per joint, which carry any distribution of the
 *    joint's normal force and moment between its two edges). What the joints' elastic,
 *    no-tension law does before the collapse, these rigid contacts do in the fall: a joint
 *    opens as a hinge about an edge, closes by an impact, and slides at mu. Where a joint has
 *    folded (its faces turned from each other by about 45 degrees at an edge), its corners
 *    there meet the other body's outline as any vertex does.
 * Energy: the kinetic and gravitational energies with the work of the impulses give
 * kinetic + gravity + dissipated - support_work = const, up to the scheme's own error (the
 * positions advance with v+: O(h) of the energy, measured and reported as the balance). The
 * joints' elastic energy at the switch is released into the dissipated energy (rigid contacts
 * store none). */
#ifndef VOUSSOIR_FALL_H
#define VOUSSOIR_FALL_H

#include "voussoir/api.h"

#include <signal.h>

#include "voussoir/dynamic.h"
#include "voussoir/joint.h"
#include "voussoir/model.h"
#include "voussoir/status.h"

/* How the contacts' impulses are solved in an island of bodies (fall.c: solve_island). */
typedef struct {
  double step;        /* time step h, s (> 0), while the debris moves fast ... */
  double slow_step;   /* ... and this one (>= step, <= 0.1 s) while no point of any block moves
                         faster than slow_speed: a step then moves a point at most slow_step
                         slow_speed, plus what gravity adds in it */
  double slow_speed;  /* m/s (>= 0; 0: always step) */
  double rate;        /* support speed, m/s (the right pier moves on at it) */
  double rest_ke;     /* the debris is at rest once the kinetic energy stays below this, J ... */
  double rest_time;   /* ... for this long, s */
  double duration;    /* the fall is followed at most this long, s */
  double sample_dt;   /* at most one sample per this interval, s (and the last state) */
  double ground;      /* the ground's height above the lower springing's base at the start, m;
                         NAN: no ground */
  double tol;         /* Gauss-Seidel stops once no contact's velocity changes by more than tol
                         times g h in a sweep (dimensionless, > 0) */
  int max_sweeps;     /* ... or after this many sweeps (the step is then counted unconverged) */
  int solver;         /* vs_fall_solver */
  double calm;        /* near rest, while the kinetic energy is below calm times rest_ke (>= 0;
                         0: never), Gauss-Seidel stops at VS_FALL_CALM_TOL times tol g step (the
                         short step's, whatever the step), or after VS_FALL_CALM_SWEEPS sweeps
                         if that is more than max_sweeps */
  int joints;         /* 1: bodies that share a joint meet on its faces (the arch); 0: no joint
                         contact (tests with a free block on a dummy joint) */
  const double *deadline; /* NULL, or a deadline (CLOCK_MONOTONIC seconds, 0: none; borrowed,
                             read once a step): once passed, the fall stops as after the stop
                             flag, VS_ERR_INTERRUPTED (the run's wall-time limit) */
  const volatile sig_atomic_t *stop; /* NULL, or a flag that, once non-zero, stops the fall at
                                        its next step: VS_ERR_INTERRUPTED */
} vs_fall_opts;

/* The default cap on Gauss-Seidel sweeps per step. Where a step reaches it, its contacts are
 * a chain of bodies that passes a force one contact per sweep, and the change per sweep falls
 * slowly: in the capped steps of a fall of the reference arch, sweeps 16-30 cut it by a median
 * of 29 % only (docs/fall.md, "The fall's cost"), and the next step starts from where these
 * stopped (the warm start). */
#define VS_FALL_MAX_SWEEPS 15
/* Near rest (vs_fall_opts.calm): the tolerance's fraction and the cap on sweeps. Gauss-Seidel's
 * tolerance lets a resting contact sink by up to tol g h^2 a step, which the overlaps' recovery
 * moves back out through the positions; that lift, repeated every step, feeds the debris a
 * little energy, enough to keep blocks rocking just above the rest level (docs/fall.md, "The
 * fall's cost"). Near rest the tolerance is tightened so that the sink and its lift are a tenth. */
#define VS_FALL_CALM_TOL 0.1
#define VS_FALL_CALM_SWEEPS 100
/* The default of vs_fall_opts.calm: near rest below 100 times the rest level. */
#define VS_FALL_CALM 100.0

/* Defaults: h = 1 ms, 2 ms below 0.5 m/s, tol = 1e-2, VS_FALL_MAX_SWEEPS sweeps, calm
 * VS_FALL_CALM, NNCG, joints on; the rest from the caller. */
VS_API void vs_fall_opts_default(vs_fall_opts *o);

/* The solver's name as the case file writes it (fall.solver): "nncg", "gauss_seidel"; "?" for
 * a value that is no vs_fall_solver. */
VS_API const char *vs_fall_solver_name(int solver);

typedef struct {
  double t_end, delta_end; /* where it stopped (s, m) */
  double step;             /* the time step, s ... */
  double slow_step;        /* ... and the slow one (vs_fall_opts), s */
  int at_rest;             /* 1: the kinetic energy stayed below rest_ke for rest_time */
  long steps;              /* time steps ... */
  long slow_steps;         /* ... of which of slow_step (where that is longer than step) */
  double cpu_s;            /* CPU time of the process over the fall (its samples included), s */
  long sweeps;             /* Gauss-Seidel sweeps, all steps together (a step's: those of the
                              island of bodies, solved on its own, that took the most) */
  long chain_steps;        /* steps whose contacts were all joints' (the arch in the air),
                              their impulses solved together ... */
  long solves;             /* ... in this many solves of the joints' system */
  long redone;             /* steps solved again: the impulses sped a body beyond what its
                              contacts had been looked for */
  long calm_steps;         /* steps near rest (vs_fall_opts.calm), solved to the tighter
                              tolerance */
  int solver;              /* vs_fall_solver */
  int cap, calm_cap;       /* Gauss-Seidel's caps on sweeps per step, and near rest */
  long unconverged;        /* steps where an island's Gauss-Seidel stopped at its cap ... */
  double residual;         /* ... the largest change of a body's velocity (at its outline's
                              reach) in their last sweep, m/s (0: none stopped there) */
  long contacts;           /* contact points solved, all steps together */
  int max_contacts;        /* the most in one step */
  double level;            /* the ground's height z (m; NAN: none) */
  double max_penetration;  /* deepest vertex below the ground over the steps, m (0: none) */
  double max_overlap;      /* deepest vertex inside another body's outline over the steps (a
                              vertex the narrow phase meets: not a joint's face contact), m */
  double max_joint_overlap; /* deepest face end behind the other face of its joint, m */
  double released;         /* the joints' elastic energy at the switch, released, J */
  double recovered;        /* work of the overlaps' recovery against gravity over the fall, J */
  double balance_error_rel; /* max |balance| / the largest energy term over the fall */
  double wall_s;           /* wall-clock time of the fall, s */
} vs_fall_result;

typedef struct vs_fall vs_fall;

/* Create the fall of model m (borrowed) with options o. Outlines: count[i] vertices for body i
 * (the n_blocks blocks, then the left and the right support), their reference coordinates (m)
 * concatenated in xz, each convex (0 vertices: the body takes no part); or count NULL: the
 * arch's (collide.h). VS_ERR_INVALID on a bad option or outline. */
VS_API vs_status vs_fall_create(vs_model *m, const vs_fall_opts *o, const int *count,
                                const double *xz, vs_fall **out, vs_error *err);
VS_API void vs_fall_destroy(vs_fall **f);

/* Replace the stop flag (NULL: none). */
VS_API void vs_fall_set_stop(vs_fall *f, const volatile sig_atomic_t *stop);

/* Follow the fall from time t0 with the extended state qe, ve (vs_model_ext_size entries: the
 * blocks, then the supports' (ux, uz, theta) as vs_model_support_states gives them, a pinned
 * support's rotation its own) until the debris is at rest or for o->duration. e0: the energies
 * at t0 (continued: kinetic and gravity recomputed, the joints' elastic energy released into
 * damped, work and dissipation accumulated on top; NULL: from zero). js0: the joints' states at
 * t0 (NULL: none), whose forces start the first step's joint impulses where they were (each
 * joint's N and M as the forces at its two edges, its T shared in proportion). The sample
 * callback gets
 * the static state (vs_model_size entries: blocks, then pinned supports' rotations) every
 * sample_dt after t0 (the caller has the state at t0) and at the end; inside it
 * vs_fall_joint_states and vs_fall_reactions
 * describe that state. qe, ve are updated to the last state. Errors: VS_ERR_INTERRUPTED;
 * VS_ERR_STOPPED when sample returned non-zero; VS_ERR_NOMEM. */
VS_API vs_status vs_fall_run(vs_fall *f, double t0, double *qe, double *ve, const vs_energy *e0,
                             const vs_joint_state *js0, vs_dyn_sample_fn sample, void *user,
                             vs_fall_result *res, vs_error *err);

/* The joints at the current state (n_joints entries, owned by f, valid until the next call
 * into f): openings, slips and contact from the geometry (vs_model_ext_joint_states); N, T and
 * M the mean forces of the last step's contact impulses on the joint's faces (P / h; M about
 * the joint's centre, > 0 when the extrados end carries more), contact the length between the
 * outermost loaded face ends (0 for a single point, the joint's length for both ends), energy
 * 0 (rigid contacts store none). */
VS_API const vs_joint_state *vs_fall_joint_states(vs_fall *f);

/* Forces the supports exert on the arch at the current state (as vs_dynamic_reactions: left
 * Fx, Fz, M about the centre of the springing joint, then right): the last step's impulses on
 * the piers over h. */
VS_API void vs_fall_reactions(const vs_fall *f, double out[6]);

/* The ground's height z (m; NAN: none) and the deepest vertex below it at the current state
 * (m; <= 0: none touches). */
VS_API double vs_fall_level(const vs_fall *f);
VS_API double vs_fall_penetration(vs_fall *f);

#endif
