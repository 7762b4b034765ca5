/* The direction of the right support's motion and its components (support.h). */
#include "voussoir/support.h"

#include <math.h>

vs_support_dir vs_support_direction(double alpha_rad) {
  return (vs_support_dir){.dx = sin(alpha_rad), .dz = cos(alpha_rad)};
}

void vs_support_displacement(vs_support_dir d, double delta, double u[2]) {
  u[0] = delta * d.dx;
  u[1] = -delta * d.dz;
}
