/* The direction of the right support's motion and its components (support.h). */
#include "voussoir/support.h"

#include <math.h>

#include "voussoir/units.h"

vs_support_dir vs_support_direction(double alpha_rad) {
  return (vs_support_dir){.dx = sin(alpha_rad), .dz = cos(alpha_rad)};
}

vs_support_dir vs_support_case_direction(const vs_case *c) {
  return vs_support_direction(c->alpha_deg * VS_DEG);
}

void vs_support_displacement(vs_support_dir d, double delta, double u[2]) {
  u[0] = delta * d.dx;
  u[1] = -delta * d.dz;
}
