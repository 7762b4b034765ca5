/* Private to the quasi-static path's sources (quasistatic*.c): the solver (KINSOL and KLU on
 * the model), the state of a path run between its increments, and the functions the files
 * share. Not installed. */
#ifndef VOUSSOIR_QUASISTATIC_INTERNAL_H
#define VOUSSOIR_QUASISTATIC_INTERNAL_H

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "model_matrix.h"
#include "voussoir/quasistatic.h"
#include "stability.h"

typedef struct {
  vs_model *m;
  const vs_path_opts *o;
  double delta;
  int n;   /* unknowns: the blocks', then the pinned supports' rotations */
  int nb3; /* the blocks' unknowns, 3 n_blocks */
  SUNContext ctx;
  N_Vector u, uscale, fscale;
  SUNMatrix J, Jt;            /* KINSOL's Jacobian; the tangent at accepted states */
  SUNLinearSolver LS, LSt;
  vs_spd *spd;                /* the stability test: Cholesky of the tangent's symmetric part */
  void *kin;
  double *len;                /* per unknown: 1 for translations, block length for rotations */
  /* workspaces, allocated once: two vectors for the tangent's solves (never used by two callers
   * at once), a residual, and the marks of a permutation's cycles */
  N_Vector w1, w2;
  double *fwork;
  unsigned char *seen;
  vs_joint_state *js;         /* 2 n_joints: the joints' states at two states (slip onsets) */
  signed char *onset;         /* per joint: its slip begins, in the sense of T (+1, -1), or 0
                                 (vs_qs_slip_onsets) */
  double *slips;              /* a copy of the committed slips (n_joints) */
  double kmax, lmax, wmin;    /* stiffest joint k_n b t (N/m), longest joint (m), lightest
                                 block (N) */
  long iters, jac_evals, floor_limited;
  double max_residual;        /* largest scaled residual among accepted equilibria */
  int interrupted;            /* o->stop was seen raised */
  int nonfinite;              /* the last solve met a residual that is not finite */
  int evals;                  /* residuals since the last Jacobian (1 + line-search trials) */
  int backtracked_out;        /* the last solve was stopped by VS_MAX_LINESEARCH */
  char kin_msg[256];
  char fail_cause[320];       /* the last failed solve's cause, as messages state it (kept
                                 through the solves that converge after it) */
} vs_qs_solver;

struct vs_path_solver {
  vs_qs_solver s;
};

/* A path run between its increments (vs_path_run_with): the last accepted equilibrium and the
 * one before, what the next increment starts from, and the fold predictions. */
typedef struct {
  vs_qs_solver *s;
  const vs_path_opts *o;
  vs_path_step_fn step_fn;
  void *user;
  vs_path_result *res;
  double *q;                /* the last accepted equilibrium (the caller's array) */
  double *tan;              /* the path tangent dq/ddelta there */
  double *qtry, *qpred;     /* an increment's trial state and its predictor */
  double *qprev;            /* the accepted equilibrium before q */
  double *eig;              /* the tangent's eigenvector, carried from state to state */
  double *qloc;             /* vs_qs_locate_edges' workspace, 3 n */
  double delta, delta_prev; /* support displacements of q and of qprev, m */
  double h;                 /* the next increment, m */
  double lam, lam_prev;     /* smallest eigenvalue of the scaled tangent at q and qprev, N/m */
  double fold, fold_prev;   /* the fold predicted at this increment and at the last, m */
  int slid;                 /* joints in contact that slid into q (vs_model_commit) */
  double force;             /* the force on the moving support at q when joints slid into it
                               (vs_model_support_force), else NaN */
  double slide_from;        /* delta of the first equilibrium of the sliding under way, m */
} vs_qs_path;

/* Unknown i is a rotation: a block's theta or a pinned support's. */
static inline int is_rotation(const vs_qs_solver *s, int i) { return i >= s->nb3 || i % 3 == 2; }

/* quasistatic.c: the solver */
/* Solve G(q; delta) = 0 from the guess q. Returns 0 on convergence, else the KINSOL flag. */
int vs_qs_solve(vs_qs_solver *s, double delta, double *q, long *iters);
/* After a failed solve at delta: an error when the failure ends the path whatever follows (the
 * stop flag, a residual that is not finite), else VS_OK. */
vs_status vs_qs_fatal(const vs_qs_solver *s, double delta, vs_error *err);
/* What a KINSOL flag means, in words. */
const char *vs_qs_kin_cause(int flag);
/* A run starts as on a new solver: options o, counters at zero, the tangent factored afresh. */
vs_status vs_qs_rearm(vs_qs_solver *s, const vs_path_opts *o, vs_error *err);

/* quasistatic_tangent.c: the tangent stiffness */
/* Factor the tangent at (q, delta) (KLU, s->LSt); *det_sign = sign of det K. 0, else the
 * linear solver's flag. */
int vs_qs_tangent_factor(vs_qs_solver *s, const double *q, double delta, int *det_sign);
/* x <- K^-1 b with the factors of vs_qs_tangent_factor. */
int vs_qs_tangent_solve(vs_qs_solver *s, N_Vector x, N_Vector b);
/* Smallest |eigenvalue| of the scaled tangent (N/m) by inverse iteration from vec, which
 * receives the eigenvector; NaN if a solve fails. */
double vs_qs_tangent_min_eig(vs_qs_solver *s, double *vec, double rtol, int maxit);
/* Tangent of the path, dq/ddelta = -K^-1 dG/ddelta, with the factors of vs_qs_tangent_factor. */
int vs_qs_path_tangent(vs_qs_solver *s, const double *q, double delta, double *dq);
/* 1 if the tangent at (q, delta) is positive definite (the state is stable); its LU is kept. */
int vs_qs_stable_state(vs_qs_solver *s, const double *q, double delta);

/* quasistatic_start.c: the path's starting equilibrium */
/* The stable equilibrium at delta0 from the guess q (self-weight, by continuation when needed,
 * and an imperfect arch's misfit), into q; res->newton_iterations set. */
vs_status vs_qs_start(vs_qs_solver *s, double delta0, double *q, vs_path_result *res,
                      vs_error *err);

/* quasistatic_edges.c: hinge onsets located on the path */
/* Between the accepted equilibria (qa0, a0) and (qb0, b0), the equilibria on both sides of
 * every joint edge's opening or closing, passed to step_fn; work has 3 n doubles, *located
 * counts them. Non-zero if step_fn asked to stop. */
int vs_qs_locate_edges(vs_qs_solver *s, const double *qa0, double a0, const double *qb0,
                       double b0, vs_path_step_fn step_fn, void *user, double *work,
                       long *located);

/* quasistatic_slip.c: slip on the path */
/* The joints that slide at (q1, d1) but not at (q0, d0), with the committed slips, flagged in
 * s->onset by the sense of their shear at q1; returns how many. *frac (may be NULL): the fraction of the way from q0 to q1 where
 * the first of them reaches its Coulomb limit, the ratio |T| / (mu N) taken as linear. */
int vs_qs_slip_onsets(vs_qs_solver *s, const double *q0, double d0, const double *q1, double d1,
                      double *frac);
/* The predictor of an increment h from the equilibrium (q, delta) with path tangent tan when
 * the sticking predictor takes joints past their Coulomb limit: the sticking tangent up to the
 * first onset, the tangent with those joints on their sliding branch beyond. Into qpred (n);
 * 0, or -1 when no joint's limit is crossed (qpred then holds the sticking predictor) or the
 * sliding tangent could not be had. Uses s->fwork and the tangent's factors (s->LSt). */
int vs_qs_slide_predictor(vs_qs_solver *s, const double *q, double delta, double h,
                          const double *tan, double *qpred);
/* The path tangent tan at the equilibrium (q, delta) made consistent with the joints' loading:
 * computed with the joints that slid into (q, delta) on their sliding branch, it predicts each
 * one's slip over an increment h; a joint whose slip it turns back (against its shear) unloads
 * and sticks instead, and tan is solved again with it sticking (a few passes: sticking one may
 * turn back another). Returns how many it made stick. Uses s->fwork, s->onset, the tangent's
 * factors. */
int vs_qs_loading_tangent(vs_qs_solver *s, const double *q, double delta, double h,
                          double *tan);
/* The limit point at the onset of slip, once no increment found an equilibrium beyond on
 * either branch: the sticking predictor from the last equilibrium (q, delta; path tangent tan)
 * to delta_fail takes joints past their Coulomb limit, and with them on their sliding branch
 * the tangent at q is not positive definite (Hill's condition of stability fails; the
 * determinant is negative, or the smallest eigenvalues fell to nearly zero). Then those joints
 * are left committed on their sliding branch, the tangent factored there (s->LSt), ev's
 * det_sign, slip_onset and slip_joint set, and the number of joints returned; else 0 and
 * nothing changed. work: n doubles. */
int vs_qs_slip_corner(vs_qs_solver *s, const double *q, double delta, double delta_fail,
                      const double *tan, double *work, vs_limit_evidence *ev);

/* quasistatic_limit.c: the limit point */
/* Bound the increment w->h ahead of the fold predicted from the tangent's smallest eigenvalue
 * at the last two equilibria (w->fold: the prediction, INFINITY if none). */
void vs_qs_fold_limit(vs_qs_path *w);
/* The path's end once an increment at limit_tol still fails: a limit point between w->delta
 * and w->delta + w->h if the tangent confirms it (res->end = VS_PATH_LIMIT_POINT), else an
 * error saying why not. */
vs_status vs_qs_limit_end(vs_qs_path *w, vs_error *err);

#endif
