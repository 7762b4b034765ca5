/* Quasi-static path: self-weight, then displacement control of the right support, each
 * equilibrium solved by KINSOL (Newton with line search, KLU on the analytic CSC Jacobian).
 * Increments adapt; a limit point is bracketed by bisecting the increment and confirmed as a
 * loss of stability of the tangent stiffness, never inferred from a failed Newton alone. */
#ifndef VOUSSOIR_QUASISTATIC_H
#define VOUSSOIR_QUASISTATIC_H

#include "voussoir/api.h"

#include <signal.h>

#include "voussoir/model.h"
#include "voussoir/status.h"

typedef struct {
  double step;       /* initial increment of delta, m */
  double step_max;   /* largest increment, m */
  double limit_tol;  /* bisection tolerance on a limit point, m */
  double max_delta;  /* stop when delta reaches this, m */
  double newton_tol; /* scaled residual tolerance (residual / typical force) */
  int newton_maxiter;
  double open;       /* edge opening of a hinge (m): every joint edge crossing it within an
                        increment is located on the path (secant steps bracketed by re-solved
                        equilibria, bisection where the gap is not linear in delta),
                        to limit_tol, and the equilibria on both sides are passed to the
                        callback; 0: no location */
  const volatile sig_atomic_t *stop; /* NULL, or a flag (e.g. set by a signal handler) that,
                                        once non-zero, stops the solve under way at its next
                                        residual evaluation: VS_ERR_INTERRUPTED */
  const double *deadline; /* NULL, or a deadline (CLOCK_MONOTONIC seconds, 0: none; borrowed,
                             read once a solve): once passed, the path stops as after the stop
                             flag, VS_ERR_INTERRUPTED (the run's wall-time limit) */
} vs_path_opts;

/* Increments (accepted and rejected) of one vs_path_run at most: reaching it is an error
 * (VS_ERR_SOLVER) that says so. */
#define VS_PATH_MAX_INCREMENTS 1000000L

/* Options from a run's definition: its path, the support's largest displacement and the hinges'
 * opening; no stop flag. */
VS_API void vs_path_opts_from_def(const vs_run_def *d, vs_path_opts *o);

typedef enum {
  VS_PATH_LIMIT_POINT = 1,      /* stopped at a confirmed limit point */
  VS_PATH_MAX_DISPLACEMENT = 2, /* reached max_delta without one */
  VS_PATH_SLIDING = 3           /* a sliding mechanism that the support drives: at two successive
                                   equilibria joints slide and the force on the moving support
                                   (vs_model_support_force) is the same to VS_PATH_PLATEAU_RTOL,
                                   so the slip would grow without bound at that force */
} vs_path_end;

/* Relative change of the support's force over an increment below which sliding joints make a
 * sliding mechanism that the support drives (VS_PATH_SLIDING): a slip held back by any
 * stiffness changes the force by the increment times it. */
#define VS_PATH_PLATEAU_RTOL 1e-6

/* Tangent-stiffness evidence at the limit point. A limit point is a fold of the path (the
 * tangent's smallest eigenvalue vanishes like the square root of the distance to it) or the
 * onset of slip (a corner: joints reach their Coulomb limit |T| = mu N within the bracket, no
 * equilibrium is found beyond on the sticking or the sliding branch, and with them sliding the
 * tangent's symmetric part is not positive definite, while the sticking one's is; the evidence
 * is then the sliding branch's tangent at the last equilibrium, and no extrapolation). */
typedef struct {
  double lambda_start;  /* smallest |eigenvalue| of the scaled tangent after self-weight, N/m */
  double lambda_last;   /* the same at the last equilibrium before the limit, N/m */
  double delta_extrap;  /* delta (m) where lambda^2, linear in delta near a fold, reaches 0
                           (NaN at the onset of slip) */
  int det_sign;         /* sign of det K at the last equilibrium (KLU factors) */
  int slip_onset;       /* joints whose slip begins at the limit point (0: a fold); at the end
                           of the path they are committed on their sliding branch. Without an
                           equilibrium under self-weight: the joints the failed step would have
                           made slide. VS_PATH_SLIDING: the joints sliding at its end */
  int slip_joint;       /* the first of them (0-based), when slip_onset > 0 */
} vs_limit_evidence;

typedef struct {
  vs_path_end end;
  double delta_limit;    /* last equilibrium delta, m (the limit point within limit_tol); with
                            VS_PATH_SLIDING, the first equilibrium at which the joints slid */
  double delta_fail;     /* smallest delta tried beyond it with no equilibrium nearby, m; with
                            VS_PATH_SLIDING, the equilibrium that showed the force stationary
                            (the last one, q) */
  vs_limit_evidence evidence;
  long steps;            /* accepted increments (self-weight included) */
  long rejected;         /* rejected increments (bisection) */
  long located;          /* equilibria added on the path to locate hinge onsets (open) */
  long newton_iterations;/* all Newton iterations, accepted or not */
  long jacobian_evals;
  long floor_limited;    /* equilibria whose residual stalled at the round-off floor, above
                            newton_tol (accepted: Newton could not improve them further) */
  double max_residual;   /* largest scaled residual (x voussoir weight) accepted */
} vs_path_result;

/* Called after every accepted equilibrium (delta = 0 is the self-weight state) and, with
 * vs_path_opts.open, every equilibrium located on both sides of a joint edge's opening; the path
 * result given to vs_path_run then holds the Newton iterations so far. q has vs_model_size
 * entries. Return non-zero to stop the path: vs_path_run then returns VS_ERR_STOPPED
 * ("stopped by the caller"), with res and q as far as the path got. */
typedef int (*vs_path_step_fn)(void *user, double delta, const double *q, const vs_model *m);

/* Follow the path of model m from support displacement delta0 (m) to a limit point, a sliding
 * mechanism that the support drives or max_delta (res->end): 0 starts with self-weight
 * from the reference configuration, > 0 resumes from a state near an equilibrium there (after a
 * snap-through), with the model's committed slips. q (vs_model_size entries) is the start guess
 * on entry (zeros: the reference configuration) and the last equilibrium on return. Errors:
 * VS_ERR_NO_EQUILIBRIUM when the start has no stable equilibrium (under self-weight: the arch
 * cannot stand) or a Newton failure is not a limit point (cause in err); VS_ERR_SOLVER when
 * SUNDIALS fails, the residual is not finite (NaN or infinity) or VS_PATH_MAX_INCREMENTS is
 * reached; VS_ERR_INTERRUPTED when o->stop was raised; VS_ERR_STOPPED when step_fn returned
 * non-zero. res is filled as far as the path got. */
VS_API vs_status vs_path_run(vs_model *m, const vs_path_opts *o, double delta0, double *q,
                             vs_path_step_fn step_fn, void *user, vs_path_result *res,
                             vs_error *err);

/* A quasi-static solver (KINSOL and KLU over model m's fixed Jacobian pattern) kept for several
 * paths: a run makes one and passes it to every vs_path_run_with (segments, rest probes), so the
 * solver is created and its pattern analysed once. o gives the first options (each run re-reads
 * its own). vs_path_run is vs_path_run_with on a solver of its own. */
typedef struct vs_path_solver vs_path_solver;
VS_API vs_status vs_path_solver_create(vs_model *m, const vs_path_opts *o, vs_path_solver **out,
                                       vs_error *err);
VS_API void vs_path_solver_destroy(vs_path_solver **p);
/* vs_path_run on solver p (its model); results as with a new solver. */
VS_API vs_status vs_path_run_with(vs_path_solver *p, const vs_path_opts *o, double delta0,
                                  double *q, vs_path_step_fn step_fn, void *user,
                                  vs_path_result *res, vs_error *err);

/* One equilibrium solve at support displacement delta from the guess q (replaced by the
 * solution). Used by tests and the dynamic phase. *iters receives the Newton iterations. */
VS_API vs_status vs_equilibrium_solve(vs_model *m, const vs_path_opts *o, double delta, double *q,
                                      long *iters, vs_error *err);

/* --- the live load's path (issue 28) ---
 * The model's loads (vs_model_set_loads) times a growing factor lambda, at a held support
 * displacement, under displacement control of the loads' own displacement u
 * (vs_model_load_displacement: a point load's deflection along it), the "pilot": each
 * equilibrium solves G(q, lambda) = 0 with u(q) prescribed, so the path passes the peak of
 * lambda, where load control would fail, and follows its falling branch. */
typedef struct {
  double step;       /* first increment of u, m */
  double step_max;   /* largest increment, m */
  double peak_tol;   /* the peak is bracketed to this increment of u (and no increment is
                        smaller), m */
  double max_disp;   /* stop once u has grown by this, m */
  double drop;       /* stop once, past the peak, lambda has fallen below (1 - drop) x the
                        peak's; in (0, 1) ... */
  double follow;     /* ... and u has grown by at least this beyond the peak (m, >= 0): a
                        first peak may be a snap-through, after which lambda rises again */
  double newton_tol; /* scaled residual tolerance, as vs_path_opts' */
  int newton_maxiter; /* at least 30 are allowed */
  const volatile sig_atomic_t *stop; /* as vs_path_opts' */
  const double *deadline;
} vs_load_opts;

/* The default fall of lambda past the peak that ends a load path: a tenth. */
#define VS_LOAD_DROP 0.1
/* The load path's increments against the support path's (solver.step_mm, step_max_mm): a load
 * deflects the arch by a millimetre or so to its peak, where a support moves by tens. */
#define VS_LOAD_STEP_SCALE 0.1

/* Options from a run's definition: its path's step and step_max times VS_LOAD_STEP_SCALE,
 * limit_tol (peak_tol) and Newton settings, the support's largest displacement (max_disp),
 * VS_LOAD_DROP, the arch's thickness (follow); no stop flag. */
VS_API void vs_load_opts_from_def(const vs_run_def *d, vs_load_opts *o);

typedef enum {
  VS_LOAD_END_PEAK = 1,     /* past the peak, lambda fell by drop (and u grew by follow, or no
                               equilibrium was found further on: cause): the collapse */
  VS_LOAD_END_SLIDING = 2,  /* joints slide at a constant lambda (VS_PATH_PLATEAU_RTOL between
                               two equilibria): a sliding mechanism, the collapse */
  VS_LOAD_END_MAX_DISP = 3, /* max_disp reached with lambda still at or near its peak */
  VS_LOAD_END_STALLED = 4   /* no equilibrium found beyond at the smallest increment (cause) */
} vs_load_end;

typedef struct {
  vs_load_end end;
  int peaked;            /* lambda has fallen at least once (the peak is bracketed) */
  double lambda_peak;    /* the largest lambda on the path: the load factor at collapse */
  double lambda_first, u_first; /* the first peak of lambda (NaN before one): where load
                                   control would snap; a snap-back may lead on to a higher one */
  double u_peak;         /* u there, m */
  double lambda_last, u_last; /* the last equilibrium */
  double u_start;        /* u at lambda = 0 (the held support's state), m */
  double arc_from;       /* where the pilot failed and arc length took over (u turned back:
                            a snap-back), m; NaN if it never did */
  long steps, rejected, newton_iterations, jacobian_evals;
  double max_residual;   /* largest scaled residual accepted */
  char cause[256];       /* why the path stopped where no equilibrium was found further on
                            (VS_LOAD_END_STALLED, or _PEAK short of follow); else "" */
} vs_load_result;

/* Called after every accepted equilibrium: lambda, the pilot u (m), the state q (the committed
 * slips updated). Non-zero stops the path (VS_ERR_STOPPED). */
typedef int (*vs_load_step_fn)(void *user, double lambda, double u, const double *q,
                               const vs_model *m);

/* Follow the load path of model m (with loads) at support displacement delta (m) from q, an
 * equilibrium at lambda = 0 (vs_model_size entries; the last equilibrium on return, and the
 * model's load factor its lambda). Errors: VS_ERR_INVALID (no loads, options out of range),
 * VS_ERR_NOMEM, VS_ERR_SOLVER (setup, a residual that is not finite, too many increments),
 * VS_ERR_INTERRUPTED, VS_ERR_STOPPED. A path that stalls is a result (res->end). */
VS_API vs_status vs_load_path_run(vs_model *m, const vs_load_opts *o, double delta, double *q,
                                  vs_load_step_fn fn, void *user, vs_load_result *res,
                                  vs_error *err);

#endif
