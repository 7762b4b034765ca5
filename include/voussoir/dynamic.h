/* Dynamic phase: the arch and its two springers as a semi-explicit index-2 DAE (the supports
 * driven by constraints, their reactions the Lagrange multipliers; see dynamic.c) integrated
 * by IDA (BDF, KLU on the analytic sparse Jacobian dF/dy + cj dF/dy'), with the right support
 * still moving at its rate,
 * root finding on the joints' edge openings and on the collapse criterion (and plastic impacts
 * where opened edges close, with the impact damping model), and an energy balance. SI units; time t is the loading time, delta(t) = rate t. */
#ifndef VOUSSOIR_DYNAMIC_H
#define VOUSSOIR_DYNAMIC_H

#include "voussoir/api.h"

#include <signal.h>

#include "voussoir/model.h"
#include "voussoir/status.h"

typedef struct {
  double rate;          /* support speed, m/s */
  double rtol;          /* IDA relative tolerance */
  double atol_q;        /* absolute tolerance on positions, m (rotations: atol_q / joint length) */
  double open;          /* edge opening of a hinge event, m (as the hinge detector) */
  double rest_ke;       /* kinetic energy below which the arch is at rest, J */
  double rest_time;     /* ... for this long, s */
  double collapse_ke;   /* kinetic energy (J) beyond which the arch is collapsing: a falling
                           mechanism releases far more than any snap-through */
  double fall_time;     /* after a collapse, the fall is followed this long, s */
  double max_delta;     /* stop when the support displacement reaches this, m */
  double sample_dt;     /* at most one sample per this interval (and one per event), s */
  int settle;           /* 1: return VS_DYN_SETTLED whenever the arch has been at rest for
                           rest_time (the caller then looks for an equilibrium and calls again
                           if there is none); 0: never (full-dynamic loading) */
  double ring_window;   /* s; > 0: the motion is also over (VS_DYN_SETTLED, ringing set) at the end
                           of a window this long in which nothing cracked, slid or crossed the
                           hinge threshold and the kinetic energy's peak fell below the previous
                           window's: an elastic oscillation that is dying out, which the caller
                           ends at the equilibrium it oscillates about (if it finds a stable one
                           there); 0: never (the rest criterion alone) */
  int impact;           /* 1: the `impact` damping model (impact.h): a plastic impulse where a
                           joint edge that had opened beyond `open` closes (an IDA root on its
                           gap), its energy loss added to the damped energy */
  const volatile sig_atomic_t *stop; /* NULL, or a flag (e.g. set by a signal handler) that,
                                        once non-zero, stops the integration at its next
                                        residual evaluation: VS_ERR_INTERRUPTED */
  const double *deadline; /* NULL, or a deadline (CLOCK_MONOTONIC seconds, 0: none; borrowed,
                             read once an IDA step): once passed, the integration stops as
                             after the stop flag, VS_ERR_INTERRUPTED (the run's wall-time
                             limit) */
} vs_dyn_opts;

/* IDA steps of one vs_dynamic_run at most: reaching it is an error (VS_ERR_SOLVER) that says
 * so. */
#define VS_DYN_MAX_STEPS 10000000L

typedef enum {
  VS_DYN_SETTLED = 1,   /* at rest: kinetic energy < rest_ke for rest_time (or ringing, below) */
  VS_DYN_COLLAPSED = 2, /* the kinetic energy passed collapse_ke; the fall was then followed */
  VS_DYN_MAX_DELTA = 3  /* reached max_delta */
} vs_dyn_end;

/* Energies at one instant, J. balance = kinetic + gravity + elastic - support_work + damped
 * + friction + cracking - (its value at the start) should stay at integrator tolerance. */
typedef struct {
  double kinetic, gravity, elastic;
  double support_work; /* work done on the arch by the moving support */
  double damped;       /* dissipated by joint damping (viscous, or at impacts) */
  double friction;     /* dissipated by frictional slip */
  double balance;      /* energy balance residual */
  double cracking;     /* dissipated by the mortar's cracking (vs_model_cracking_energy), from the
                          phase's start: the softening potential the cracked parts had (G_f per
                          unit area), released as each accepted step commits the cracks; 0 in
                          the rigid fall and for dry joints */
} vs_energy;

/* A joint edge crossing the opening threshold (a located IDA root). */
typedef struct {
  double t, delta; /* s, m */
  int joint;       /* 1-based */
  char side;       /* hinge side: 'I' when the extrados edge opened, 'E' when the intrados did */
  int opened;      /* 1 opened, 0 closed */
} vs_dyn_event;

typedef struct {
  vs_dyn_end end;
  double t_end, delta_end;     /* where it stopped */
  double t_motion, delta_motion; /* departure of the last motion: the last instant before the
                                    collapse criterion (or the end) at which the kinetic energy
                                    rose through rest_ke, located as an IDA root */
  int onset_found;             /* 0 if it never rose through rest_ke (fast loading: the arch
                                  never was at rest) */
  double t_collapse;           /* when the collapse criterion fired (NaN if not) */
  double max_kinetic;          /* J */
  double balance_error_rel;    /* max |balance| / max(|energy terms|) up to the collapse
                                  criterion (or the end) */
  double balance_error_fall;   /* the same during the fall after it (looser tolerances) */
  long steps, newton_iterations, root_events, jac_evals;
  long impacts;                /* plastic impacts resolved (the impact damping model) */
  int dae_differential;        /* components of y that are differential (q, v, energy integrals) */
  int dae_algebraic;           /* ... and algebraic (lambda, mu); the DAE has index 2 */
  int dae_index;
  double max_drift;            /* max |g(q, t)| over the accepted steps (m; rad for rotations) */
  double max_penetration;      /* largest penetration of a vertex into the ground over the
                                  accepted steps with the ground armed, m (0: none) */
  double max_overlap;          /* largest penetration of a vertex into another body's outline
                                  (collide.h) over the accepted steps with it armed, m */
  double fall_wall_s;          /* wall-clock time spent in the fall, s */
  int fall_at_rest;            /* 1: the fall ended with the debris at rest on the ground (kinetic
                                  energy below rest_ke for rest_time), 0: at fall_time */
  double fall_failed_t;        /* IDA failed in the fall at this time (s; NaN: it did not): the
                                  run ends there, the collapse found before it standing */
  char fall_failure[256];      /* ... and IDA's message */
  vs_energy e_end;             /* the energies at the last state */
  int ringing;                 /* VS_DYN_SETTLED by ring_window (an elastic oscillation dying
                                  out), not at rest */
  long ring_settles;           /* snaps the caller ended by ring_window (its tallies) */
  double ring_energy;          /* ... and the vibration energy they left (J): kinetic + potential
                                  above the equilibrium the caller settled at */
} vs_dyn_result;

/* Called at samples (at most every sample_dt, at each event, at the start and at the end) and at
 * joint events; the result given to vs_dynamic_run then holds the steps and Newton iterations so
 * far. Non-zero stops the integration: vs_dynamic_run (vs_fall_run) returns VS_ERR_STOPPED
 * ("stopped by the caller"). */
typedef int (*vs_dyn_sample_fn)(void *user, double t, double delta, const double *q,
                                const double *v, const vs_energy *e);
typedef int (*vs_dyn_event_fn)(void *user, const vs_dyn_event *ev, const double *q);

typedef struct vs_dynamic vs_dynamic;

/* Create the integrator for model m (borrowed; its damping ratio set beforehand). */
VS_API vs_status vs_dynamic_create(vs_model *m, const vs_dyn_opts *o, vs_dynamic **out,
                                   vs_error *err);
VS_API void vs_dynamic_destroy(vs_dynamic **d);

/* The ground (contact.h; borrowed, NULL: none). If c is armed when vs_dynamic_run starts, it
 * acts from the start; otherwise it is armed when the collapse criterion fires, offset (m) above
 * the lower of the two springings' bases there, and the fall then ends as soon as the debris is
 * at rest (kinetic energy below rest_ke for rest_time) or after fall_time. Its vertices crossing
 * the ground are IDA roots (counted in root_events, not reported as events). */
struct vs_contact;
VS_API vs_status vs_dynamic_set_contact(vs_dynamic *d, struct vs_contact *c, double offset,
                                        vs_error *err);

/* Contact between bodies without a joint (collide.h; borrowed, NULL: none); call after
 * vs_dynamic_set_contact. Armed with the ground at the collapse criterion if it is not armed
 * when vs_dynamic_run starts. Its vertices entering or leaving another body's outline are IDA
 * roots. Its forces couple two bodies: the Jacobian's pattern is the joints' plus the pairs of
 * its broad phase, and KLU's analysis is redone when those pairs change (jac_fn). */
struct vs_collide;
VS_API vs_status vs_dynamic_set_collide(vs_dynamic *d, struct vs_collide *c, vs_error *err);

/* Replace the ringing window of the options d was created with (s, >= 0; vs_dyn_opts's
 * ring_window): a run sets it once it knows its arch's lowest natural frequency. */
VS_API void vs_dynamic_set_ring_window(vs_dynamic *d, double window_s);

/* Replace the stop flag of the options d was created with (NULL: none). */
VS_API void vs_dynamic_set_stop(vs_dynamic *d, const volatile sig_atomic_t *stop);

/* Integrate from time t0 (delta = rate t0) with positions q and velocities v (updated to the
 * final state). Friction slips are committed after every step. Energies accumulate from zero
 * at t0. Errors: VS_ERR_SOLVER with IDA's cause (or VS_DYN_MAX_STEPS reached);
 * VS_ERR_INTERRUPTED when o->stop was raised; VS_ERR_STOPPED when sample or event returned
 * non-zero (q, v, res as far as the integration got). */
VS_API vs_status vs_dynamic_run(vs_dynamic *d, double t0, double *q, double *v,
                                vs_dyn_sample_fn sample, vs_dyn_event_fn event, void *user,
                                vs_dyn_result *res, vs_error *err);

/* The DAE as IDA sees it, for checks: the length N of y, y = (q, v, lambda, mu, W, D, Df) with
 * q, v over the blocks then the left and right support bodies (3 n_blocks + 6 each; offsets
 * of v, lambda, mu and the energy integrals in *iv, *il, *imu, *ie); the residual F(t, y, y')
 * into r (N entries) and the iteration matrix dF/dy + cj dF/dy' into J (CSC, N x N, capacity
 * vs_dynamic_nnz). The matrix leaves out the energy integrals' dependence on the state and the
 * damping forces' dependence on the positions (IDA's Newton is a modified Newton). */
VS_API int vs_dynamic_size(const vs_dynamic *d);
VS_API int vs_dynamic_nnz(const vs_dynamic *d);
VS_API void vs_dynamic_layout(const vs_dynamic *d, int *iv, int *il, int *imu, int *ie);
VS_API void vs_dynamic_residual(vs_dynamic *d, double t, double *y, double *yp, double *r);

/* The Lagrange multipliers lambda at the current state of d (after vs_dynamic_run or inside its
 * callbacks): per support (left, right) the force (Fx, Fz, N) and moment (about the support
 * body's reference point, the centre of its joint with the arch, N m, counter-clockwise) that
 * the support exerts on the arch; 0 for a pinned support's free rotation. These are the
 * multipliers the DAE gives at IDA's state (q, v): the support bodies' equations of motion with
 * their prescribed (constant-rate, so unaccelerated) motion, lambda = F(q, v) on their
 * constrained rows. They equal the springing joints' forces to round-off; IDA's own iterate
 * (vs_dynamic_multipliers) agrees to its Newton tolerance. One force evaluation. */
VS_API void vs_dynamic_reactions(vs_dynamic *d, double out[6]);
/* The blocks' accelerations at the current state of d (3 n_blocks), from the equations of
 * motion at (q, v) as vs_dynamic_reactions: a = -F(q, v) / m. One force evaluation. */
VS_API void vs_dynamic_accelerations(vs_dynamic *d, double *a);
/* IDA's own iterates, for checks: the algebraic unknowns lambda (laid out as
 * vs_dynamic_reactions) and the blocks' v' of the BDF formula (3 n_blocks). */
VS_API void vs_dynamic_multipliers(const vs_dynamic *d, double out[6]);
/* The joints' states at the current state of d (n_joints entries, owned by d, valid until the
 * next call into d), as vs_model_ext_joint_states gives them with the committed slips: the
 * evaluation the step's commit, energies and root function shared, not a new one. */
VS_API const vs_joint_state *vs_dynamic_joint_states(vs_dynamic *d);
VS_API void vs_dynamic_derivatives(const vs_dynamic *d, double *a);

#endif
