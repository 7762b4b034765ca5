/* Each support's own travel at a displacement as a case moves them (vs_mc_travel,
 * montecarlo.h): the last four columns of samples.csv, apart from the run so that what reads
 * and writes the tables links without the engine. */
#include "voussoir/montecarlo.h"

#include <math.h>
#include <stdlib.h>

#include "voussoir/support.h"
#include "voussoir/units.h"

void vs_mc_travel(const vs_case *c, double delta_mm, double t[4]) {
  vs_run_def *d = malloc(sizeof *d);
  vs_support_motion mo[2];
  vs_error e;
  int ok = d != NULL && isfinite(delta_mm);
  if (ok) vs_case_to_def(c, d);
  for (int s = 0; ok && s < 2; s++) ok = vs_support_motion_from_def(&d->support, s, &mo[s], &e) == VS_OK;
  free(d);
  for (int s = 0; s < 2; s++) {
    double u[3];
    if (!ok) { /* (NAN, not -NAN: the table says nan) */
      t[2 * s] = t[2 * s + 1] = NAN;
      continue;
    }
    vs_support_motion_at(&mo[s], delta_mm * VS_MM, u, NULL);
    t[2 * s] = (s ? u[0] : -u[0]) / VS_MM + 0.0; /* + 0.0: at rest 0, not -0 */
    t[2 * s + 1] = -u[1] / VS_MM + 0.0;
  }
}
