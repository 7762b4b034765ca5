/* Natural vibration of the arch about an equilibrium: the generalised symmetric eigenproblem
 * K phi = omega^2 M phi on the tangent stiffness K = dG/dq and the (diagonal) mass matrix M,
 * solved by ARPACK and LAPACK; and the damping ratio a damping matrix C gives each mode,
 * zeta_i = phi_i^T C phi_i / (2 omega_i) with phi_i mass-normalised. K is banded: the eigenvalues
 * by ARPACK (shift-invert Lanczos) on its banded Cholesky factor, the shapes by inverse
 * iteration, both linear in n (LAPACK's dsbgvx, ~n^2, only when ARPACK cannot answer). SI. */
#ifndef VOUSSOIR_MODAL_H
#define VOUSSOIR_MODAL_H

#include "voussoir/api.h"

#include "voussoir/model.h"
#include "voussoir/status.h"

/* Modes reported (the lowest ones). */
#define VS_MODAL_MAX 6

/* The eigensolver is used up to this many unknowns (5000 voussoirs; the case allows 2000). */
#define VS_MODAL_MAX_DOF 15000

typedef struct {
  int n_modes;                     /* modes computed, <= VS_MODAL_MAX (0: not computed) */
  double omega[VS_MODAL_MAX];      /* circular frequencies, rad/s, ascending */
  double freq_hz[VS_MODAL_MAX];    /* omega / 2 pi */
  double zeta[VS_MODAL_MAX];       /* damping ratio the model's damping gives each mode */
  double asymmetry;                /* max |K - K^T| / max |K|: K is symmetrised before solving;
                                      this says by how much it was not (0 for a conservative
                                      state) */
  double *phi;                     /* mass-normalised mode shapes, n x n_modes column-major
                                      (owned; vs_modal_free) */
  int n;                           /* unknowns */
} vs_modal;

/* Lowest min(n_modes, VS_MODAL_MAX) modes of model m at (q, delta) with the current gravity
 * scale (a pinned support's rotation has the mean voussoir's rotary inertia, as in the dynamic
 * model); the damping ratios from the model's damping at rest (vs_model_damping with v = 0, so
 * joint dashpots act where the joints are in contact). out->phi is allocated. Errors:
 * VS_ERR_INVALID (more than VS_MODAL_MAX_DOF unknowns, or K not positive definite: the state is
 * not a stable equilibrium), VS_ERR_SOLVER (LAPACK failed), VS_ERR_NOMEM. */
VS_API vs_status vs_modal_compute(const vs_model *m, const double *q, double delta, int n_modes,
                                  vs_modal *out, vs_error *err);

/* Recompute out->zeta with the model's current damping (after changing it). */
VS_API vs_status vs_modal_damping_ratios(const vs_model *m, const double *q, double delta,
                                         vs_modal *out, vs_error *err);

/* Free out->phi; the frequencies stay. NULL allowed. */
VS_API void vs_modal_free(vs_modal *out);

#endif
