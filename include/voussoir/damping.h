/* Damping models of the dynamic phase, each with a meaning in modal terms:
 *   none      no viscous damping (friction still dissipates where joints slide);
 *   joint     a dashpot in every joint, acting where it is in contact, tuned to a fraction of
 *             the critical damping of that joint's own contact oscillator (a voussoir bouncing
 *             on its joint stiffness, ~1e4 rad/s); on the arch's lowest modes it gives far less
 *             than the ratio (vs_modal reports how much);
 *   rayleigh  C = alpha M + beta K_c with alpha, beta giving the ratio at two frequencies (by
 *             default the two lowest natural frequencies under self-weight);
 *   impact    no viscous damping; a plastic impulse where a joint edge that had opened closes
 *             again, calibrated on Housner's rocking block (impact.h): energy is lost only at
 *             impacts, so every mode in steady contact gets ratio 0. */
#ifndef VOUSSOIR_DAMPING_H
#define VOUSSOIR_DAMPING_H

#include "voussoir/api.h"

#include "voussoir/model.h"
#include "voussoir/status.h"

/* "none", "joint", "rayleigh", "impact"; NULL for an unknown value. */
VS_API const char *vs_damping_model_name(vs_damping_model model);

/* Rayleigh coefficients giving ratio zeta (>= 0) at circular frequencies w1 < w2 (rad/s, > 0):
 * alpha = 2 zeta w1 w2 / (w1 + w2) (1/s), beta = 2 zeta / (w1 + w2) (s). Between w1 and w2 the
 * ratio is below zeta, outside above it. Errors: VS_ERR_INVALID. */
VS_API vs_status vs_damping_rayleigh_coefficients(double zeta, double w1, double w2, double *alpha,
                                                  double *beta, vs_error *err);

/* The ratio Rayleigh damping gives a mode of circular frequency w: alpha / (2 w) + beta w / 2. */
VS_API double vs_damping_rayleigh_ratio(double alpha, double beta, double w);

/* Set model m's viscous damping for model `model` with ratio zeta: joint -> vs_model_set_damping
 * (zeta), rayleigh -> the coefficients at w1, w2 (rad/s), none and impact -> no viscous damping
 * (impact's impulses are the dynamic phase's: vs_dyn_opts.impact).
 * alpha and beta (may be NULL) receive the Rayleigh coefficients (0 otherwise). */
VS_API vs_status vs_damping_apply(vs_model *m, vs_damping_model model, double zeta, double w1,
                                  double w2, double *alpha, double *beta, vs_error *err);

#endif
