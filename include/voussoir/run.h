/* A run: one case from self-weight along the quasi-static path; at every limit point the motion
 * is integrated dynamically until it either settles on another stable branch (a snap-through,
 * after which the quasi-static path resumes) or collapses (the fall is then followed). Hinges
 * are tracked throughout. Owns its geometry, model, integrators and records. */
#ifndef VOUSSOIR_RUN_H
#define VOUSSOIR_RUN_H

#include "voussoir/api.h"

#include "voussoir/case.h"
#include "voussoir/dynamic.h"
#include "voussoir/fall.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/modal.h"
#include "voussoir/imperfections.h"
#include "voussoir/limit.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"

typedef struct vs_run vs_run;

/* The fall after the collapse is VS_PHASE_FALL with the rigid scheme (fall.h: rigid blocks,
 * impulsive contacts), VS_PHASE_DYNAMIC with the penalty scheme (IDA, as before it). */
typedef enum { VS_PHASE_QUASISTATIC = 0, VS_PHASE_DYNAMIC = 1, VS_PHASE_FALL = 2 } vs_phase;

/* One recorded state: an equilibrium of the quasi-static path or a sample of the motion. */
typedef struct {
  vs_phase phase;
  double t, delta;         /* loading time (delta / rate), s; support displacement, m */
  const double *q, *v;     /* state (v is NULL on the quasi-static path: at rest) */
  const vs_energy *energy; /* NULL on the quasi-static path */
  const double *reactions; /* forces the supports exert on the arch: left (Fx, Fz N, M N m about
                              the springing joint's centre, counter-clockwise), right; from the
                              joint forces on the quasi-static path, the multipliers lambda in
                              the dynamic phase */
  const vs_joint_state *joints; /* every joint's state at (q, delta) (n_joints), with the
                                   committed slips: what the run evaluated there (in the rigid
                                   fall, the contact impulses' forces: vs_fall_joint_states) */
  double elastic, gravity; /* joint elastic energy and gravitational potential, J (on the
                              dynamic phase also in energy) */
  long newton_iterations;  /* solver statistics so far, cumulative over the run: KINSOL Newton */
  long ida_steps, ida_newton_iterations; /* iterations; IDA steps and Newton iterations */
  long fall_steps;         /* time steps of the rigid fall */
} vs_run_sample;

typedef enum {
  VS_EVENT_JOINT_OPENED = 0, /* an edge of a joint opened past hinges.open_mm (IDA root) */
  VS_EVENT_JOINT_CLOSED,     /* ... closed back */
  VS_EVENT_HINGE_FORMED,     /* a hinge formed (tracker); label and order are set */
  VS_EVENT_LIMIT_POINT,      /* a limit point of the quasi-static path */
  VS_EVENT_SNAP_SETTLED,     /* the motion after a limit point settled on a stable branch */
  VS_EVENT_COLLAPSE,         /* the collapse criterion fired */
  VS_EVENT_JOINT_SLIPPED,    /* a joint began to slide, or to slide the other way: on the path
                                at the equilibrium where it slides, at a limit point at the onset
                                of slip, in the motion (up to the collapse criterion) once its
                                plastic slip has moved by hinges.open_mm; side: the direction */
  VS_EVENT_PIER_ROCKED,      /* a pier's base (its foundation interface) opened past
                                hinges.open_mm: the pier rocks; side: the edge that stays in
                                contact (I: the inner face's, E: the outer face's) */
  VS_EVENT_COURSE_OPENED,    /* a course joint of a pier opened past hinges.open_mm; side as a
                                rocking pier's */
  VS_EVENT_CRACK_INITIATED   /* a mortared joint's tensile stress reached f_t at an edge: its
                                mortar begins to crack there (joints.tensile_MPa > 0); side: the
                                edge that cracks ('I' intrados, 'E' extrados -- the opposite of
                                the hinge side it may later become); delta interpolated between
                                the two states that bracket it */
} vs_event_kind;

typedef struct {
  vs_event_kind kind;
  vs_phase phase;
  double t, delta;  /* s, m */
  int joint;        /* 1-based, 0 if none */
  char side;        /* 'I', 'E' or 0. A slip (VS_EVENT_JOINT_SLIPPED): the edge toward which the
                       voussoir slides relative to the body across the joint (at joint k the
                       voussoir k relative to the one on its left or the left support; at the
                       right springing the last voussoir relative to the right support) */
  char label;       /* hinge label, or 0 */
  int order;        /* hinge order of appearance (4 = the fourth hinge), or 0 */
  double load_factor; /* analysis.type = load: lambda at the load path's equilibrium where the
                         event was found (the collapse: the peak's); NaN off the load path (delta
                         is then the held support displacement) */
} vs_run_event;

/* A joint's slip in the collapse's mechanism. */
typedef struct {
  int joint;    /* 1-based */
  char side;    /* the direction, as vs_run_event.side for a slip */
  double slip;  /* how far it slid, m (> 0) */
} vs_slip;

/* A limit point and what followed it. */
typedef struct {
  double delta;         /* m */
  int collapse;         /* 1 if the motion it started was the collapse, 0 a snap-through */
  double delta_settled; /* snap: where the quasi-static path resumed, m (NaN for a collapse) */
  char hinges_before[160], hinges_after[160]; /* open hinges, e.g. "A:8-I B:30-E C:56-E" (as
                                                vs_run_open_hinges: a longer list ends with
                                                "+K more") */
} vs_limit_record;

typedef struct {
  int found;
  double delta;        /* collapse displacement delta_u: where the arch departs from its last
                          stable equilibrium. On the quasi-static path, the collapsing limit
                          point (located to limit_tol_mm); with --dynamic, the last instant
                          before the detection at which the kinetic energy rose through the
                          rest level (an IDA root; NaN if the arch was never at rest), m */
  double t;            /* its time, s */
  double t_criterion;  /* the detection: when the kinetic energy passed the collapse threshold
                          (the arch is falling), s */
  double delta_detected; /* the support displacement then, m */
  double t_onset;      /* when the final motion began (the kinetic energy last rose above the
                          rest threshold), s; NaN where the arch was never at rest (fast loading) */
  int n_hinges;            /* hinges open at the criterion, all of them ... */
  const vs_hinge *hinges;  /* ... their copies, left to right (n_hinges; NULL without a
                              collapse; owned by the run, valid until vs_run_destroy) */
  double reactions_limit[6]; /* forces the supports exert on the arch at the collapsing limit
                                point (as vs_run_sample.reactions); NaN without one (--dynamic) */
  /* --- slip: what the mechanism is made of --- */
  const char *mechanism;   /* "rotational" (hinges alone), "sliding" (slips alone), "mixed"
                              (both); NULL without a collapse */
  int n_slips;             /* joints that slid in the mechanism: from the departure to the
                              collapse's onset (where its hinges are taken), by more than
                              hinges.open_mm; for a sliding mechanism that the support drives
                              (VS_PATH_SLIDING), those sliding at its end ... */
  const vs_slip *slips;    /* ... left to right (n_slips; owned by the run) */
} vs_collapse_record;

/* Called for every recorded state and every event (either may be NULL). Non-zero stops the run:
 * vs_run_execute returns VS_ERR_STOPPED ("stopped by the caller"). */
typedef int (*vs_run_sample_fn)(void *user, const vs_run *run, const vs_run_sample *s);
typedef int (*vs_run_event_fn)(void *user, const vs_run *run, const vs_run_event *e);

/* Build everything for case c (copied; vs_case_to_def gives the run's definition).
 * Errors: VS_ERR_INVALID / VS_ERR_NOMEM. */
VS_API vs_status vs_run_create(const vs_case *c, vs_run **out, vs_error *err);
/* The same from a definition (def.h, copied): a run no case file describes. vs_run_case is then
 * NULL, and the reports and the record, which echo a case, need one (vs_run_create). */
VS_API vs_status vs_run_create_def(const vs_run_def *d, vs_run **out, vs_error *err);
VS_API void vs_run_destroy(vs_run **r);

/* Stop flag of the run (NULL: none), e.g. set by a SIGINT handler: once non-zero, the solve
 * under way stops at its next residual evaluation (KINSOL or IDA) and vs_run_execute returns
 * VS_ERR_INTERRUPTED. The flag is borrowed and only read. */
VS_API void vs_run_set_stop(vs_run *r, const volatile sig_atomic_t *stop);

/* Bounds of a run: dynamic phases after one limit point (each ended by the arch at rest with no
 * equilibrium there), and limit points; reaching one is an error (VS_ERR_SOLVER) that says so. */
#define VS_RUN_MAX_RESTARTS 100000
#define VS_RUN_MAX_LIMITS 10000

/* Run the case. The status is that of the solvers (VS_OK when the run reached the collapse, the
 * first limit point with dynamic.follow = 0, or support.max_mm); VS_ERR_INTERRUPTED after the
 * stop flag; VS_ERR_WALL_TIME ("stopped: wall-time limit S s reached") when the run took longer
 * than run.max_wall_s (checked by every solver once a step: KINSOL's solves of the path, IDA's
 * steps, the rigid fall's steps); VS_ERR_STOPPED when sample or event returned non-zero;
 * everything recorded up to a failure or a stop stays available. */
VS_API vs_status vs_run_execute(vs_run *r, vs_run_sample_fn sample, vs_run_event_fn event,
                                void *user, vs_error *err);

/* The case the run was made from (NULL: made from a definition); its definition. */
VS_API const vs_case *vs_run_case(const vs_run *r);
VS_API const vs_run_def *vs_run_def_of(const vs_run *r);
VS_API const vs_geometry *vs_run_geometry(const vs_run *r);
/* The imperfections drawn for the case (all nominal when it asks for none). */
VS_API const vs_imperfections *vs_run_imperfections(const vs_run *r);
VS_API const vs_model *vs_run_model(const vs_run *r);
VS_API const vs_hinges *vs_run_hinges(const vs_run *r);
VS_API const vs_hinge_opts *vs_run_hinge_opts(const vs_run *r);

/* The first quasi-static segment (to the first limit point) and the totals of all segments. */
VS_API const vs_path_result *vs_run_path(const vs_run *r);
VS_API const vs_path_result *vs_run_path_totals(const vs_run *r);

/* Limit points in order; the collapse; the dynamic phases' totals (steps, Newton iterations,
 * root events, the worst energy balance). */
VS_API int vs_run_limit_count(const vs_run *r);
VS_API const vs_limit_record *vs_run_limit(const vs_run *r, int i);
VS_API const vs_collapse_record *vs_run_collapse(const vs_run *r);
/* The live load's path (analysis.type = load, issue 28): the support held at hold, then the
 * live load times lambda to collapse, through its peak (quasistatic.h, vs_load_path_run). */
typedef struct {
  int done;             /* the load path ran (analysis.type = load) */
  int end;              /* vs_load_end (quasistatic.h); 0 when it did not run or the arch
                           failed before it (held) */
  double hold;          /* the support displacement held, m */
  int held_limit;       /* 1: the arch did not stand still at the hold: it collapsed before
                           it (load_factor 0), or was still moving there (a snap-through under
                           way, no equilibrium found near: load_factor NaN), or met a limit
                           point not followed (dynamic.follow = 0: NaN) */
  double load_factor;   /* the largest lambda on the path: the load factor at collapse */
  double deflection;    /* the loads' displacement at the peak from where loading began, m */
  double first_peak;    /* the first peak of lambda, where load control would snap (a
                           snap-back may lead to the higher load_factor); NaN before one */
  int snap_back;        /* the loads' displacement turned back: followed by arc length */
  int settled;          /* the support reached the hold during a snap-through: the arch was
                           taken at the stable equilibrium Newton found from its moving state */
  int n;                /* points of the load-deflection curve ... */
  const double *lambda; /* ... lambda ... */
  const double *u;      /* ... and the loads' displacement from where loading began, m */
  char mechanism[160];  /* the hinges open where lambda first fell by VS_LOAD_DROP past its
                           peak (else at the end of the path), as vs_run_open_hinges */
  char cause[256];      /* why the path stopped, when it stalled */
  long steps, rejected, newton_iterations, jacobian_evals; /* the load path's solver */
} vs_run_load_result;
/* The run's load path (done = 0 unless analysis.type = load): owned by the run, its curve valid
 * until vs_run_destroy. */
VS_API const vs_run_load_result *vs_run_load(const vs_run *r);

/* The limit analysis of the held configuration (issue 28, item 5): for analysis.type = load,
 * and for analysis.type = limit with analysis.hold_mm > 0, the limit analysis
 * (vs_limit_analyse_moved, limit.h) of the arch in the equilibrium where the support was held,
 * its blocks where the path left them, before any live load. NULL when it was not computed (the
 * arch did not stand still at the hold, or another analysis); else *status (may be NULL) how it
 * ended and *err (may be NULL) its error (owned by the run). */
VS_API const vs_limit_analysis *vs_run_limit_held(const vs_run *r, vs_status *status,
                                                  const vs_error **err);

VS_API const vs_dyn_result *vs_run_dynamic_totals(const vs_run *r);

/* Hinges to report: all of them, or after a collapse those formed up to its onset (the falling
 * arch opens joints everywhere; they stay in the event log). */
VS_API int vs_run_hinge_count(const vs_run *r);
/* Hinge i (0-based, in order of appearance) as reported: after a collapse, as it was at the
 * collapse's onset (its joints and whether it was open then), not at the end of the fall; beyond
 * vs_run_hinge_count (hinges of the fall) and without a collapse, the tracker's current state. */
VS_API const vs_hinge *vs_run_hinge(const vs_run *r, int i);

/* Logged events in order. */
VS_API int vs_run_event_count(const vs_run *r);
VS_API const vs_run_event *vs_run_event_get(const vs_run *r, int i);

/* Evolution mode (docs/model.md, "Vocabulary"): "I", "II", "III", or NULL when the hinge sides
 * match none; and the side patterns it was read from (first three hinges, left to right; hinges at the collapse). */
VS_API const char *vs_run_mode(const vs_run *r);
VS_API const char *vs_run_pattern_initial(const vs_run *r);
VS_API const char *vs_run_pattern_collapse(const vs_run *r);
/* A mortared arch's collapse (joints.tensile_MPa or cohesion_MPa > 0; a dry run has none): the
 * hinges its motion turns about at the collapse criterion, read from the relative rotation
 * rates of the joints' bodies (docs/mortar.md, "The mode of a mortared arch"), left to right:
 * vs_run_mechanism_hinge(r, i) for i in 0 .. vs_run_mechanism_count(r) - 1 (NULL outside; 0 of
 * them without a collapse in motion); their sides "E-I-E-I" ("" for none); the time they were
 * read at (s; NaN for none); and whether vs_run_mode was read from them (1: the hinges open at
 * the collapse's onset fit no mode) or from those (0). */
VS_API int vs_run_mechanism_count(const vs_run *r);
VS_API const vs_active_hinge *vs_run_mechanism_hinge(const vs_run *r, int i);
VS_API const char *vs_run_pattern_mechanism(const vs_run *r);
VS_API double vs_run_mechanism_time(const vs_run *r);
VS_API int vs_run_mode_from_mechanism(const vs_run *r);

/* The first crack (the JSON's first_crack): the crack_initiated event of least support
 * displacement; NULL when no joint cracked (and for a dry run). */
VS_API const vs_run_event *vs_run_first_crack(const vs_run *r);

/* Each joint's lengths cracked through from its intrados and from its extrados edge (m; 0 for
 * dry joints), as committed now (a sample function's state: the record's joint_crack row), into
 * out[2 k], out[2 k + 1] for the geometry's joints k (2 n_joints entries; NULL: none written).
 * Returns n_joints. */
VS_API int vs_run_joint_cracks(const vs_run *r, double *out);

/* Last state: positions (vs_model_size entries), support displacement (m), time (s). */
VS_API const double *vs_run_state(const vs_run *r);
VS_API double vs_run_delta(const vs_run *r);
VS_API double vs_run_time(const vs_run *r);
/* Forces the supports exert on the arch at the last recorded state (as vs_run_sample.reactions). */
VS_API const double *vs_run_reactions(const vs_run *r);
/* The ground the fall landed on (contact.h): its height z (m, in the geometry's frame) and the
 * largest penetration (m) of a block vertex into it at the last recorded state; NaN when no
 * fall was followed. The largest during the fall and its cost: vs_run_dynamic_totals. */
VS_API double vs_run_ground(const vs_run *r);
VS_API double vs_run_penetration(const vs_run *r);
/* The rest level (J): the debris is at rest once its kinetic energy has stayed below it for the
 * rest window (dynamic.rest_factor times the kinetic energy of the arch moving bodily at the
 * support's rate, at most a hundredth of the collapse threshold). */
VS_API double vs_run_rest_ke(const vs_run *r);
/* The rigid fall after the collapse (fall.scheme = rigid), NULL when none was followed: its
 * steps, solver work, overlaps, energy balance and cost. The summary figures (at rest, deepest
 * penetration and overlap, wall time, balance) are also in vs_run_dynamic_totals, as for the
 * penalty scheme. */
VS_API const vs_fall_result *vs_run_fall(const vs_run *r);
/* Wall-clock time of vs_run_execute, s. */
VS_API double vs_run_wall_s(const vs_run *r);

/* Natural vibration under self-weight (computed at the first equilibrium; n_modes = 0 before,
 * or above VS_MODAL_MAX_DOF unknowns, or when the self-weight state was not stable) with the
 * damping ratio the case's damping model gives each mode; the Rayleigh coefficients (alpha 1/s,
 * beta s; 0 unless dynamic.damping_model = rayleigh). */
VS_API const vs_modal *vs_run_modal(const vs_run *r);
VS_API void vs_run_rayleigh(const vs_run *r, double *alpha, double *beta);

/* Name of the open hinges, "A:8-I B:30-E C:56-E", into buf (vs_hinges_list: a list longer than
 * size ends with "+K more"). */
VS_API void vs_run_open_hinges(const vs_run *r, char *buf, size_t size);

#endif
