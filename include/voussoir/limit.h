/* Limit analysis of a rigid block assembly (Livesley; Gilbert): rigid blocks, interfaces with no
 * tension and Coulomb friction, as a linear program solved by COIN-OR CLP. The unknowns are the
 * normal and shear forces (N, T) at the two ends (intrados, extrados) of every interface; every
 * block is in equilibrium (two forces, one moment) under its weight and lambda x the live load;
 * N >= 0 and |T| <= mu N at each end. Its optimum is the load factor lambda at collapse, or the
 * least and greatest horizontal thrust under self-weight; the dual is the collapse mechanism.
 *
 * With friction the LP's flow rule is associative (a sliding joint would dilate), the masonry's
 * is not: the load factor is an upper bound of the true one, and it is exact when no interface
 * slides in the mechanism. A solution says whether any interface is at the friction limit
 * (vs_limit_solution.n_friction): none, and the bound is exact. SI units throughout. */
#ifndef VOUSSOIR_LIMIT_H
#define VOUSSOIR_LIMIT_H

#include "voussoir/api.h"

#include <stddef.h>

#include "voussoir/def.h"
#include "voussoir/geometry.h"
#include "voussoir/status.h"

/* One force of the reference live load (lambda = 1): (fx, fz) N on block `block` (0-based),
 * applied at (px, pz) m, reference configuration. */
typedef struct {
  int block;
  double fx, fz, px, pz;
} vs_limit_force;

/* What one solve optimises. */
typedef enum {
  VS_LIMIT_LOAD_FACTOR = 0, /* the largest lambda (a live load is needed) */
  VS_LIMIT_THRUST_MIN = 1,  /* the least thrust H under self-weight (lambda = 0) */
  VS_LIMIT_THRUST_MAX = 2,  /* the greatest */
  VS_LIMIT_GOAL_COUNT
} vs_limit_goal;

typedef enum {
  VS_LIMIT_OPTIMAL = 0,    /* solved */
  VS_LIMIT_INFEASIBLE = 1, /* no admissible forces: the assembly does not stand under its
                              weight (for the load factor: not even at lambda = 0) */
  VS_LIMIT_UNBOUNDED = 2,  /* the live load finds no mechanism (e.g. a load over a support) */
  VS_LIMIT_OUTCOME_COUNT
} vs_limit_outcome;

/* Settings, in vs_limit_opts_default's defaults. */
typedef struct {
  double mu;                           /* friction coefficient of every interface without its
                                          own (vs_joint_geom.mu: a blocks file's, a pier's
                                          base), > 0 */
  vs_support_kind left_kind, right_kind; /* a pinned support's interface carries its resultant
                                            at its centre (N_I = N_E) */
  double touch;         /* the thrust line touches an edge when its resultant lies within this
                           fraction of the joint's length of it; default 1e-6 */
  double hinge;         /* the mechanism opens (slides) an interface's end when its rate
                           exceeds this fraction of the largest; default 1e-6 */
  double thickness_tol; /* the thickness factor is bracketed to this; default 1e-5 */
  double thickness_max; /* thickness factors are tried up to this; default 16 */
} vs_limit_opts;

VS_API void vs_limit_opts_default(vs_limit_opts *o);

/* One solution. Its arrays are allocated by vs_limit_solve (zero the struct before its first
 * use) and freed by vs_limit_solution_free; joint k (1-based in output) is index k - 1. */
typedef struct {
  vs_limit_goal goal;
  vs_limit_outcome outcome;
  double value;    /* the optimum: lambda, or the thrust H (N); NaN unless optimal */
  double thrust;   /* H of this solution: the horizontal force the left support exerts on the
                      assembly (toward the right), N */
  int n_joints;
  double *force;   /* 4 per joint: N_I, T_I, N_E, T_E, N (the force of body a on body b along
                      the joint's normal and tangent) */
  double *eta;     /* per joint: where the resultant crosses the joint, from the intrados, as a
                      fraction of its length (NaN where the joint carries nothing) */
  double *px, *pz; /* per joint: that point (the thrust line), m */
  char *touch;     /* per joint: 'I' or 'E' where the resultant is on that edge (a hinge of the
                      thrust line), 'O' where the joint carries nothing, 0 elsewhere */
  char *hinge;     /* per joint, load factor only (NULL otherwise): the mechanism (the dual),
                      'I' or 'E' a hinge on that edge (the other end opens), 'O' both ends open,
                      'S' sliding without opening, 0 at rest */
  double *open;    /* load factor only: 2 per joint, the mechanism's opening rates at the
                      intrados and extrados ends, and ... */
  double *slip;    /* ... per joint its sliding rate (tangential, the same all along the joint),
                      both as fractions of the largest rate, 0 below opts.hinge */
  int n_touch;     /* joints with a touch ('I' or 'E') */
  int n_hinges;    /* joints with a hinge ('I', 'E' or 'O') */
  int n_sliding;   /* joints that slide in the mechanism */
  char *friction;  /* per joint: 1 where its resultant is at the friction limit, |T_I + T_E| >=
                      mu (N_I + N_E) (1 - 1e-7) with N_I + N_E > 0, else 0 */
  int n_friction;  /* joints at the friction limit: 0 means the load factor is exact, not only
                      an upper bound */
  int iterations;  /* simplex iterations */
  double cpu_s;    /* CPU time of the solve, s */
} vs_limit_solution;

VS_API void vs_limit_solution_free(vs_limit_solution *s);

/* The linear program over one geometry (borrowed: it must outlive the handle). */
typedef struct vs_limit vs_limit;

/* Assemble the LP of geometry g with options o (NULL: the defaults) and the reference live load
 * live[0 .. n_live-1] (NULL, 0: none; the load factor needs one). VS_ERR_INVALID on a block
 * index out of range or a force that is not finite, VS_ERR_NOMEM. */
VS_API vs_status vs_limit_create(const vs_geometry *g, const vs_limit_opts *o,
                                 const vs_limit_force *live, int n_live, vs_limit **out,
                                 vs_error *err);
/* Free l and NULL *l; NULL allowed. */
VS_API void vs_limit_destroy(vs_limit **l);

/* Add dead forces (besides the blocks' weight, e.g. the fill's: vs_limit_fill_load) to l's
 * equilibrium, before its solves. VS_ERR_INVALID on a block out of range or a force that is
 * not finite. */
VS_API vs_status vs_limit_add_dead(vs_limit *l, const vs_limit_force *dead, int n, vs_error *err);

/* Solve for goal into s (its previous arrays are freed). An infeasible or unbounded LP is a
 * result (s->outcome), not an error; errors: VS_ERR_INVALID (the load factor without a live
 * load), VS_ERR_SOLVER (CLP stopped without an answer), VS_ERR_NOMEM. */
VS_API vs_status vs_limit_solve(vs_limit *l, vs_limit_goal goal, vs_limit_solution *s,
                                vs_error *err);

/* The live load of definition ld on arch geometry g as forces (malloc'd into *out, *n of them;
 * NULL, 0 for none): point and line, value downward on the block whose extrados lies under x
 * (the horizontal distance from the left springing's intrados point; a line load across the
 * barrel is a point load in the plane); patch, value spread uniformly over [x - width/2,
 * x + width/2], each block's share at the middle of its part; tilt, each block's weight
 * horizontally (+x, toward the right support) at its centroid. With ld->spread > 0 a point,
 * line or patch load stands on the fill's surface (fd->level above the crown's extrados; fd
 * NULL: level 0) and reaches the extrados spread uniformly over width + 2 h tan(spread) centred
 * on x (width 0 for point and line), h the fill's depth over the extrados at x; each block's
 * share at the middle of its part, the part beyond the arch's extrados (into the ground beside
 * it) dropped. VS_ERR_INVALID (naming the case key) when the load does not lie over the
 * extrados, a patch has no width or (without spread) reaches beyond the extrados, the spread
 * is outside [0, 80] deg. */
VS_API vs_status vs_limit_live_load(const vs_geometry *g, const vs_load_def *ld,
                                    const vs_fill_def *fd, vs_limit_force **out, int *n,
                                    vs_error *err);

/* The fill of definition fd on arch geometry g as forces (malloc'd into *out, *n of them; NULL,
 * 0 without fill, unit_weight 0): on each block, the weight of the fill above its extrados chord
 * (between its joints' extrados ends) up to fd->level above the highest extrados point (the
 * crown's), unit_weight x depth x the area of that trapezoid, vertical at its centroid's x on
 * the chord; nothing over the supports. With fd->k_horizontal > 0, after the vertical forces,
 * the horizontal pressure k_horizontal x unit_weight x the depth below the surface on each
 * chord's vertical projection, inward (toward +x where the chord rises to the right, the left
 * haunch; -x where it falls), its resultant at the pressure diagram's centroid height on the
 * chord. VS_ERR_INVALID on a value that is not finite or negative, VS_ERR_NOMEM. */
VS_API vs_status vs_limit_fill_load(const vs_geometry *g, const vs_fill_def *fd,
                                    vs_limit_force **out, int *n, vs_error *err);

/* Everything the limit analysis of a run's definition reports. */
typedef struct {
  int have_load;                   /* d->load.kind != none: collapse was solved */
  int load_block;                  /* point and line: the loaded block (0-based); else (also
                                      when spread over several, load.spread_deg) -1 */
  vs_limit_solution collapse;      /* the largest load factor and its mechanism */
  vs_limit_solution thrust_min, thrust_max; /* self-weight: the least and greatest thrust */
  double thickness_factor;         /* the least factor on arch.thickness at which the arch
                                      stands (the upper end of the bracket); NaN if none up to
                                      thickness_max */
  double thickness_bracket[2];     /* infeasible, feasible factor */
  int thickness_solves;            /* LPs of the bisection */
  vs_limit_solution thickness;     /* at thickness_factor: the least thrust's solution, its
                                      thrust line and touches (within twice the bracket's
                                      width, relative, of an edge: the critical line's) */
  double cpu_s;                    /* CPU time of the whole analysis, s */
} vs_limit_analysis;

/* The limit analysis of definition d (its arch, with its imperfections; joints.mu; the supports'
 * kinds; the live load d->load) with options o (NULL: defaults, with mu and the kinds taken from
 * d): the load factor when a live load is given, the least and greatest thrust under
 * self-weight, and the geometric factor: the factor on arch.thickness (intrados radius kept,
 * the arch and its imperfections rebuilt each time) at which the self-weight LP turns
 * feasible, by bisection. *a is zeroed first; free it with vs_limit_analysis_free. Errors as
 * vs_limit_live_load and vs_limit_solve. */
VS_API vs_status vs_limit_analyse(const vs_run_def *d, const vs_limit_opts *o,
                                  vs_limit_analysis *a, vs_error *err);
VS_API void vs_limit_analysis_free(vs_limit_analysis *a);
/* The limit analysis of definition d (as vs_limit_analyse) in a deformed configuration: ref is
 * d's arch as built (vs_run_geometry: the geometry q refers to), each block moved rigidly by
 * q[3i .. 3i+2] (its centroid's displacement, m, and its rotation, rad, counter-clockwise: the
 * model's state, model.h), each support by qs[0..2] (left) and qs[3..5] (right) (ux, uz, theta
 * about the centre of the joint it carries: vs_model_support_position). A joint sits at the mean
 * of where its two bodies carry its centre, its normal turned by their mean rotation; the fill
 * and the live load, placed on the arch as built, move with their blocks, their directions kept
 * (the model's forces); the thickness factor's trial arches take the same motions about ref's
 * centroids. gap (NULL: every joint closed) gives each joint's opening at its intrados and
 * extrados ends (2 per joint, m, > 0 open: vs_joint_state's gap_i, gap_e): where a joint has
 * opened by more than d->hinges.open (a hinge) only the part of its face where the opening is
 * at most that carries force (opening affine along the face; a pinned support's joint whole),
 * the same fraction of the face in the thickness's trial arches; the solutions' thrust lines
 * (eta) and touches are given on the whole faces. A rigid motion of the whole assembly (the same translation for every body) leaves
 * the result unchanged; a rigid rotation is a tilt of gravity. VS_ERR_INVALID on NULL, a motion
 * that is not finite, a trial arch whose blocks and joints are not ref's; else as
 * vs_limit_analyse. */
VS_API vs_status vs_limit_analyse_moved(const vs_run_def *d, const vs_geometry *ref,
                                        const double *q, const double qs[6], const double *gap,
                                        const vs_limit_opts *o, vs_limit_analysis *a,
                                        vs_error *err);

/* The hinges of a solution as text, "9-I 27-E 40-I 56-E" (which: 'h' the mechanism's hinges,
 * 'x' its sliding joints, 't' the thrust line's touches, 'f' joints at the friction limit), into
 * buf (size bytes; a list that does not fit ends with "+K more"). */
VS_API void vs_limit_list(const vs_limit_solution *s, char which, char *buf, size_t size);

#endif
