/* The direction of the right support's motion: it moves by delta along alpha, measured from the
 * vertical (0 = settlement down, 90 = outward spreading; x right, z up). The one place where
 * alpha becomes components: the model's support displacement, the pictures, and the settlement
 * dz and spreading dx every report, record, sweep and calibration gives. */
#ifndef VOUSSOIR_SUPPORT_H
#define VOUSSOIR_SUPPORT_H

#include "voussoir/api.h"

typedef struct {
  double dx; /* sin alpha: the outward (x) share of delta, the spreading */
  double dz; /* cos alpha: the downward share of delta, the settlement */
} vs_support_dir;

/* The direction alpha_rad (rad). */
VS_API vs_support_dir vs_support_direction(double alpha_rad);

/* The right support's displacement for delta (m) along d: u = (delta dx, -delta dz), m. */
VS_API void vs_support_displacement(vs_support_dir d, double delta, double u[2]);

#endif
