/* Private to the dynamic phase (dynamic.h): the object and what its files share. dynamic.c: the
 * object, its tolerances and IDA's set-up; dynamic_residual.c: the forces, the residual and the
 * Jacobian; dynamic_events.c: the root functions, restarts and impacts; dynamic_run.c: the run. */
#ifndef VOUSSOIR_DYNAMIC_INTERNAL_H
#define VOUSSOIR_DYNAMIC_INTERNAL_H

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "collide.h"
#include "contact.h"
#include "model_matrix.h"
#include "voussoir/dynamic.h"
#include "impact.h"

/* Constraints: at most 3 per support (fixed: ux, uz, theta of the support body prescribed;
 * pinned: ux, uz only). */
enum { VS_DYN_NC = 6 };
/* A velocity error is judged by the position error it makes over this time (s), about the period
 * of the contact modes: tighter velocity tolerances would make IDA resolve those vibrations. */
static const double VS_DYN_VEL_TIME = 1e-4;
/* KLU's row scaling of IDA's iteration matrix: -1, none (nor its check of the pattern at each
 * factorisation), as the quasi-static path's, up to the collapse; measured against the scaled
 * factorisation on the seed domain: delta_u moves by 9e-10 relative at most, the mechanisms stay,
 * the reference run is 2.5 % faster. With the penalty fall's contacts (collide.h) armed, 2 (KLU's
 * default, rows scaled by their largest entry): unscaled, the penalty fall of alpha 90, k_n 48
 * took 1.5 times as long. A change of scaling is made only where the next factorisation is a
 * fresh one (the pattern's re-initialisation in vs_dyn_jacobian): a refactorisation keeps the
 * scale factors its factorisation made. */
static const int VS_DYN_KLU_SCALE = -1;
static const int VS_DYN_KLU_SCALE_CONTACTS = 2;
/* Newton's convergence test up to the collapse criterion: IDA stops iterating when the estimated
 * error of the iterate is below this fraction of the error-test tolerance (IDA's default 0.33).
 * The energy balance is the integral of the work of the residual that Newton leaves in the
 * blocks' equations of motion -- along the motion dE/dt = W' - D' + v . r -- and that residual is
 * about (cj M + C) times the velocity tolerance, which is loose (VS_DYN_VEL_TIME): with 0.33 the
 * balance error reaches 6e-4 of the largest energy term in the fast motion before a collapse,
 * with 1e-3 it stays below 1e-4 for about twice the Newton iterations before the fall (IDA's
 * default again in the fall, which is only recorded). */
static const double VS_DYN_NEWTON_COEF = 1e-3;
static const double VS_DYN_NEWTON_COEF_FALL = 0.33;

struct vs_dynamic {
  vs_model *m;
  double cracking0; /* vs_model_cracking_energy at the phase's start (vs_energy's cracking) */
  vs_dyn_opts o;
  int n;  /* 3 per block */
  int nq; /* the static state's length (vs_model_size): blocks, pinned supports' rotations */
  int ne; /* n + 6: blocks and supports */
  int nc; /* constraints */
  int cons[VS_DYN_NC]; /* constrained component (0..5, over the two supports) of each */
  int cidx[VS_DYN_NC]; /* ... and the constraint of each component, -1 if it is free */
  double *qst, *vst;   /* the static state (nq) handed to the callbacks */
  int iv, il, imu, ie; /* offsets of v, lambda, mu and the energy integrals in y */
  int N;  /* 2 ne + 2 nc + 3 */
  int nj; /* joints */
  SUNContext ctx;
  N_Vector y, yp, id, atol;
  SUNMatrix J, K, C;
  SUNLinearSolver LS;
  void *ida;
  double *mass, *work;    /* ne each */
  double *force;          /* ne: F(q, v) for the reported multipliers and accelerations */
  vs_joint_state *js;     /* the joints' states at the positions js_q (vs_dyn_joint_states) */
  double *js_q;
  int js_valid;
  int *roots;
  int nroots;             /* before the fall: 2 nj + 2, then the impact model's (the
                             contacts' follow them once armed) */
  int root_impact;        /* offset of the impact model's roots in g and roots */
  vs_impact *imp;         /* the impact damping model, NULL unless o.impact */
  long jac_evals;
  double max_drift;       /* max |g| over the accepted steps, m */
  double rtol;            /* o.rtol scaled as the absolute tolerances (set_tolerances) */
  vs_contact *ct;         /* the ground (borrowed; NULL: none), vs_dynamic_set_contact */
  double ground_offset;   /* ... armed at the fall this far above the lower springing base, m */
  int in_fall;            /* after the collapse criterion: only the contacts' roots */
  vs_collide *cl;         /* contact between bodies without a joint (borrowed; NULL: none) */
  unsigned char *pairs, *pairs_klu; /* its broad phase now, and the one KLU last analysed */
  double *Kd, *Cd;        /* ne x ne dense work: the Jacobian's K and C with its coupling */
  int klu_pairs;          /* pairs_klu holds an analysed pattern */
  char msg[256];
};

/* The support displacement at loading time t, m. */
static inline double vs_dyn_delta_at(const vs_dynamic *d, double t) { return d->o.rate * t; }

/* Has the caller's stop flag been raised? */
static inline int vs_dyn_stopped(const vs_dynamic *d) { return d->o.stop != NULL && *d->o.stop; }

/* dynamic_residual.c */
/* IDA's residual F(t, y, y') (IDAResFn); a raised stop flag is fatal (-1). */
int vs_dyn_residual(double t, N_Vector yy, N_Vector yp, N_Vector rr, void *user);
/* IDA's Jacobian dF/dy + cj dF/dy' (IDALsJacFn), its pattern written at every call. */
int vs_dyn_jacobian(double t, double cj, N_Vector yy, N_Vector yp, N_Vector rr, SUNMatrix Jac,
                    void *user, N_Vector t1, N_Vector t2, N_Vector t3);
/* Constraint drift max |g| at time t and state y (m for the translations, rad for the
 * rotations). */
double vs_dyn_drift(const vs_dynamic *d, double t, const double *y);

/* dynamic_events.c */
/* The joints' states at the positions of y into d->js, evaluated once per state. */
void vs_dyn_joint_states(vs_dynamic *d, const double *y);
/* IDA's root function (IDARootFn): the joints', the energy levels' and the impact model's before
 * the fall, then the ground's and the bodies' contacts once armed. */
int vs_dyn_roots(double t, N_Vector yy, N_Vector yp, double *g, void *user);
/* IDARootInit with the roots of the current phase. Returns IDA's flag. */
int vs_dyn_root_init(vs_dynamic *d);
/* Add IDA's step and Newton iteration counts to *bs, *bn (before an IDAReInit resets them). */
void vs_dyn_carry_counters(const vs_dynamic *d, long *bs, long *bn);
/* Is IDA's failure flag its "root found at and very near t", which a restart clears? */
int vs_dyn_close_roots(const vs_dynamic *d, int flag);
/* Restart IDA at t from its current state, roots and stop time t_stop set again. Returns IDA's
 * flag. */
int vs_dyn_restart_roots(vs_dynamic *d, double t, double t_stop);
/* The impact model: arm the edges that have opened at y (reset: at the start). */
void vs_dyn_impact_arm(vs_dynamic *d, const double *y, int reset);
/* The impact model: resolve the impacts among the roots just found and restart IDA at t (its
 * counters carried in *bs, *bn). Returns the impacts, or -1 (message in d->msg). */
int vs_dyn_impact_resolve(vs_dynamic *d, double t, double t_stop, long *bs, long *bn);
/* Restart IDA at the collapse criterion (time t) for the fall up to t_stop: looser tolerances,
 * only the contacts' roots, which are armed here (its counters carried in *bs, *bn; *wall_fall
 * the wall-clock time it starts at). Returns IDA's flag. */
int vs_dyn_start_fall(vs_dynamic *d, double t, double t_stop, long *bs, long *bn,
                      double *wall_fall);

/* The iteration matrix dF/dy + cj dF/dy' of vs_dynamic_residual into J (CSC, N x N, capacity
 * vs_dynamic_nnz; dynamic.h says what it leaves out). */
void vs_dynamic_jacobian(vs_dynamic *d, double t, double cj, double *y, SUNMatrix J);

#endif
