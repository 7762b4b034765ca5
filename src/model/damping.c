/* Damping models: names, Rayleigh coefficients from a target ratio at two frequencies, and
 * setting a model's viscous damping accordingly. */
#include "voussoir/damping.h"

#include <math.h>

static const char *const names[] = {"none", "joint", "rayleigh", "impact"};
_Static_assert(sizeof names / sizeof names[0] == VS_DAMPING_MODEL_COUNT,
               "a name for every vs_damping_model");

const char *vs_damping_model_name(vs_damping_model model) {
  return ((int)model >= 0 && (int)model < VS_DAMPING_MODEL_COUNT) ? names[model] : NULL;
}

vs_status vs_damping_rayleigh_coefficients(double zeta, double w1, double w2, double *alpha,
                                           double *beta, vs_error *err) {
  if (!(zeta >= 0.0) || !isfinite(zeta) || !(w1 > 0.0) || !(w2 > w1) || !isfinite(w2))
    return vs_error_set(err, VS_ERR_INVALID,
                        "rayleigh damping: ratio %g, frequencies %g and %g rad/s (allowed: ratio "
                        ">= 0, 0 < w1 < w2)",
                        zeta, w1, w2);
  *alpha = 2.0 * zeta * w1 * w2 / (w1 + w2);
  *beta = 2.0 * zeta / (w1 + w2);
  return VS_OK;
}

double vs_damping_rayleigh_ratio(double alpha, double beta, double w) {
  return alpha / (2.0 * w) + 0.5 * beta * w;
}

vs_status vs_damping_apply(vs_model *m, vs_damping_model model, double zeta, double w1, double w2,
                           double *alpha, double *beta, vs_error *err) {
  double a = 0.0, b = 0.0;
  vs_status st = VS_OK;
  switch (model) {
  case VS_DAMPING_JOINT: vs_model_set_damping(m, zeta); break;
  case VS_DAMPING_RAYLEIGH:
    st = vs_damping_rayleigh_coefficients(zeta, w1, w2, &a, &b, err);
    if (st == VS_OK) vs_model_set_rayleigh(m, a, b);
    break;
  case VS_DAMPING_NONE:
  case VS_DAMPING_IMPACT: vs_model_set_damping(m, 0.0); break;
  default: st = vs_error_set(err, VS_ERR_INVALID, "damping model %d unknown", (int)model);
  }
  if (alpha != NULL) *alpha = a;
  if (beta != NULL) *beta = b;
  return st;
}
