/* Private to the live load's path (load_path.c): its solver, KINSOL and KLU on the model's
 * equilibrium bordered by the pilot's equation. Not installed. */
#ifndef VOUSSOIR_LOAD_INTERNAL_H
#define VOUSSOIR_LOAD_INTERNAL_H

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include "model_matrix.h"
#include "voussoir/quasistatic.h"

typedef struct {
  vs_model *m;
  const vs_load_opts *o;
  double delta;  /* the support displacement, held, m */
  double target; /* the pilot's value sought, m */
  int n;         /* the model's unknowns; lambda is unknown n */
  double size;   /* the loads' total size, N */
  SUNContext ctx;
  N_Vector x, xscale, fscale;
  SUNMatrix Jm, J; /* the model's Jacobian; the bordered one */
  SUNLinearSolver LS;
  void *kin;
  double *f;    /* the load vector (n) */
  /* the arc (pseudo-arclength) control, where the pilot fails (arc = 1): per unknown its scale
   * sc (1 / block length for translations, 1 for rotations, 1 / the peak lambda for lambda),
   * the path's unit direction in those units times sc (a), the anchor state xa; the target is
   * the step's length, arc_min the smallest */
  int arc;
  double *a, *xa, *sc;
  double arc_min;
  double *work; /* 4 (n + 1) */
  double kmax, lmax, wmin;
  double max_residual;
  long jac_evals;
  int interrupted, nonfinite, evals, backtracked_out;
  char kin_msg[256];
} vs_lp_solver;

/* A solver of the bordered system over model m (it must carry loads), options o (borrowed). */
vs_status vs_lp_create(vs_lp_solver *s, vs_model *m, const vs_load_opts *o, vs_error *err);
void vs_lp_destroy(vs_lp_solver *s);
/* Solve for x = (q, lambda) with the pilot at target (m), from the guess x. 0, else the KINSOL
 * flag. */
int vs_lp_solve(vs_lp_solver *s, double target, double *x, long *iters);
const char *vs_lp_kin_cause(int flag);

#endif
