/* Private to the run (run.h): the object and what its files share. run.c: the run's objects,
 * its phases (the quasi-static path, the motion, the rigid fall) and the accessors; run_sample.c:
 * the solvers' callbacks (each equilibrium, sample and event), the hinges and events they log,
 * and the mechanism of the collapse. */
#ifndef VOUSSOIR_RUN_INTERNAL_H
#define VOUSSOIR_RUN_INTERNAL_H

#include "collide.h"
#include "contact.h"
#include "voussoir/quasistatic.h"
#include "voussoir/run.h"

struct vs_run {
  vs_run_def def; /* what the run is (SI): the engine reads this */
  vs_case c;      /* the case it was made from, for the reports (have_case; else zero) */
  int have_case;
  vs_geometry *g;
  vs_imperfections *imp; /* the drawn imperfections ([imperfections]; none: the perfect arch) */
  vs_model *m;
  vs_hinges *h;
  vs_dynamic *dyn;
  vs_path_solver *ps; /* the quasi-static solver of every path segment and rest probe */
  vs_contact *ground; /* the ground the fall lands on (NULL: no fall followed) */
  vs_collide *bodies; /* ... and the blocks' and piers' contacts in the fall */
  vs_fall *fall;      /* the rigid fall after the collapse (NULL: none, or the penalty scheme) */
  vs_fall_result fres;
  int fall_done;
  vs_hinge_opts hopts;
  vs_path_opts popts;
  vs_dyn_opts dopts;
  double ke_move; /* kinetic energy of the whole arch moving at the support's rate, J */
  vs_path_result first, totals;
  int have_first;
  vs_dyn_result dtot;
  double *q, *v;
  double *q_rest; /* the equilibrium found where the motion came to rest (dynamic_phase) */
  vs_joint_state *js; /* the joints' states at the state tracked (n_joints), then the hinge
                         tracker's view of them (run_sample.c, hinge_view; n_joints) */
  double delta, t, wall_s;
  double deadline; /* of case.max_wall_s: vs_monotonic_s seconds, 0 none; every solver's
                      options point here (set when vs_run_execute starts) */
  vs_phase phase;
  double react[6];    /* reactions at the last recorded state (vs_run_sample.reactions) */
  double react_eq[6]; /* ... at the last equilibrium of the quasi-static path (NaN: none) */
  vs_limit_record *limits;
  int n_limits, cap_limits;
  vs_run_event *events;
  int n_events, cap_events;
  vs_collapse_record collapse;
  vs_hinge *onset;     /* open hinges early in the current motion (collapse candidates); at the
                          collapse, left to right, the collapse record's */
  int n_onset, onset_taken, frozen;
  int hinges_at_onset; /* hinges formed up to the snapshot of the collapse's onset ... */
  vs_hinge *onset_all; /* ... all of them as they were then (joints, open) */
  int cap_onset;       /* entries of onset and onset_all */
  int pending_snap;    /* limit record waiting for the equilibrium its snap settled in, or -1 */
  const vs_path_result *live_path; /* the segment or phase under way (its counters so far) */
  const vs_dyn_result *live_dyn;
  /* --- a mortared arch's mechanism (run_sample.c, track_mechanism), per hinge-tracked joint:
   * the hinges the motion turns about at the last sample of the motion before the collapse
   * froze it (at the collapse criterion) --- */
  double *mech_w;          /* the joints' relative rotation rates there, rad/s */
  vs_active_hinge *mech;   /* its hinges, left to right (n_mech) */
  int *mech_hinge;         /* the tracked hinge each is (its index, -1 none), matched there */
  int n_mech;
  double mech_t;           /* the time of that sample, s (NaN: none) */
  char *pattern_m;         /* their sides, "E-I-E-I" (2 n_joints + 1 bytes) */
  int mode_from_mech;      /* 1 when mode was read from them (the onset's hinges fit no mode) */
  char pattern0[16];
  char *pattern_u; /* the sides at the collapse (2 collapse.n_hinges bytes; NULL: none) */
  const char *mode;
  vs_run_sample_fn sample_fn;
  vs_run_event_fn event_fn;
  void *user;
  int nomem; /* a callback ran out of memory logging what it saw: the solver it stopped says
                VS_ERR_STOPPED, the run VS_ERR_NOMEM */
  /* --- slip (run_slip.c), per joint --- */
  signed char *slip_dir; /* sense of its last slip event (+1: body b along s), 0 none */
  double *slip_anchor;   /* committed slip at the last equilibrium or event, m */
  double *slip_from;     /* ... at the departure (a limit point, rest, the last state where
                            every joint stuck) */
  double *slip_onset;   /* ... at the collapse's onset (its hinges' snapshot) */
  vs_slip *mech_slips;   /* the collapse's slips (collapse.slips) */
  char *pier_side;       /* per joint, a pier's (run_sample.c): its open side when last
                            tracked ('I', 'E', 0 closed) */
  /* --- mortar (run_sample.c, track_cracks), per joint --- */
  double *crack_margin;  /* each edge's (intrados, extrados) opening short of f_t / k_n at the
                            last state tracked, m (> 0: below the tensile strength) */
  unsigned char *cracked; /* bit 0: the intrados edge has reached f_t, bit 1: the extrados */
  double crack_delta;     /* the support displacement of that state, m (NaN: none yet) */
  /* --- the live load's path (run_load.c) --- */
  vs_run_load_result load;
  double *load_lambda, *load_u; /* the curve (load.n points) */
  int cap_load;
  double load_u0;               /* the loads' displacement where loading began, m */
  double load_now;              /* lambda of the load path's current equilibrium (events carry
                                   it); NaN off the load path */
  vs_load_result load_res;      /* the load path's statistics */
  double load_best;             /* the largest lambda so far ... */
  int load_taken;               /* ... and whether the mechanism was taken past it */
  /* --- the limit analysis of the held configuration (run_load.c) --- */
  int held_la_done;             /* computed (type limit with a hold, type load) */
  vs_status held_la_st;
  vs_error held_la_err;
  vs_limit_analysis held_la;
  /* --- damping (damping.h, modal.h): modes under self-weight, set at the first equilibrium --- */
  vs_modal modal;
  double ray_alpha, ray_beta;
  int modal_done;
  vs_status modal_st;
  vs_error modal_err;
};

/* run_events.c */
/* A callback's allocation failed: its solver stops, and the run says why (r->nomem); -1. */
int vs_run_out_of_memory(vs_run *r);
/* Log an event of the run (phase: the current one) and hand it to the caller's event function.
 * Returns non-zero when out of memory (r->nomem set) or when the caller asks to stop. */
int vs_run_log_event(vs_run *r, vs_event_kind kind, double t, double delta, int joint, char side,
                     char label, int order);

/* run_sample.c */
/* Record a limit point at delta (the hinges open before it) and log its event; as
 * vs_run_log_event. */
int vs_run_add_limit(vs_run *r, double delta);
/* Name the first n hinges (n < 3: A, B from left to right, later ones in order) and the
 * events of those hinges. */
void vs_run_name_first(vs_run *r, int n);
/* The solvers' callbacks (user: the run): an equilibrium of the quasi-static path
 * (vs_path_step_fn), a sample of the motion and a joint's event (vs_dyn_sample_fn,
 * vs_dyn_event_fn), a sample of the rigid fall (vs_dyn_sample_fn). Non-zero stops the solver. */
int vs_run_on_equilibrium(void *user, double delta, const double *q, const vs_model *m);
int vs_run_on_dyn_sample(void *user, double t, double delta, const double *q, const double *v,
                         const vs_energy *e);
int vs_run_on_dyn_event(void *user, const vs_dyn_event *ev, const double *q);
int vs_run_on_fall_sample(void *user, double t, double delta, const double *q, const double *v,
                          const vs_energy *e);
/* The collapse of the IDA phase d into r->collapse: its times, the departure, the hinges of the
 * mechanism (frozen at the criterion), the reactions at the limit point. 0, or -1 when out of
 * memory (r->nomem set). */
int vs_run_record_collapse(vs_run *r, const vs_dyn_result *d);
/* The collapse of a sliding mechanism that the support drives (the path p ended with
 * VS_PATH_SLIDING; r->q, r->delta its last equilibrium): no motion follows, the mechanism is
 * the hinges open and the joints sliding there. 0, or -1 when out of memory. */
int vs_run_record_sliding(vs_run *r, const vs_path_result *p);
/* The run's initial hinge pattern, the pattern at the collapse and the mode they make. */
void vs_run_classify(vs_run *r);

/* run_load.c */
/* The fill's dead load (any analysis) and the live load (analysis.type = load) of the
 * definition on the model. */
vs_status vs_run_load_setup(vs_run *r, vs_error *err);
/* analysis.type = load, the support held (r->q the equilibrium there, r->load.hold): load to
 * collapse. */
vs_status vs_run_load_path(vs_run *r, vs_error *err);
/* The limit analysis of the arch held at r->delta in equilibrium r->q (r->held_la*). */
void vs_run_limit_at_hold(vs_run *r);
void vs_run_load_free(vs_run *r);

/* run_slip.c */
/* The per-joint arrays (0, or -1 when out of memory) and their release. */
int vs_run_slips_create(vs_run *r);
void vs_run_slips_free(vs_run *r);
/* At an equilibrium of the path with its joints' states js (the slips committed): a slip event
 * for each joint sliding in a sense it has not slid in last; the anchors of the motion set; the
 * departure marked when every joint sticks. 0, or non-zero when an event stopped the run. */
int vs_run_slips_at_equilibrium(vs_run *r, double delta, const vs_joint_state *js);
/* In the motion: a slip event for each joint whose committed slip moved by more than
 * hinges.open_mm from its anchor (in a sense it has not slid in last). As above. */
int vs_run_slips_in_motion(vs_run *r, double t, double delta);
/* The committed slips now: the departure's (vs_run_slips_mark), the collapse's onset's, where
 * its hinges are taken (vs_run_slips_onset). */
void vs_run_slips_mark(vs_run *r);
void vs_run_slips_onset(vs_run *r);
/* The collapse's slips and mechanism name, from the departure to its onset: the joints that
 * slid by more than hinges.open_mm; or, given the joints' states at the end of a sliding
 * mechanism the support drives (sliding_now), those sliding there. After the hinges. */
void vs_run_slips_mechanism(vs_run *r, const vs_joint_state *sliding_now);

#endif
