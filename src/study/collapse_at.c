/* A study's view of a run's collapse (the sweep's table, calibrate's target): the span its
 * ratios are of, each support's own travel and their relative displacement, as the run's JSON
 * reports them (src/run/report.c: span_mm, collapse.left/right, dz_over_L_pct, dx_over_L_pct). */
#include <math.h>

#include "collapse_at.h"
#include "voussoir/model.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

double vs_study_span_mm(const vs_run *r) {
  const double L = vs_case_span_mm(vs_run_case(r));
  return isfinite(L) ? L : vs_run_geometry(r)->span / VS_MM;
}

void vs_study_travel(const vs_run *r, double delta, double t[4]) {
  double u[2][3];
  for (int s = 0; s < 2; s++)
    vs_support_motion_at(vs_model_support_motion(vs_run_model(r), s), delta, u[s], NULL);
  t[0] = -u[0][0] / VS_MM + 0.0; /* + 0.0: a support at rest gives 0, not -0 */
  t[1] = -u[0][1] / VS_MM + 0.0;
  t[2] = u[1][0] / VS_MM + 0.0;
  t[3] = -u[1][1] / VS_MM + 0.0;
}

/* Does the case move the right support alone, along alpha (every case before both could)? */
static int right_alone(const vs_case *c) {
  return c->left_rate_mm_s == 0.0 && c->left_path.n == 0 && c->right_path.n == 0 &&
         c->rate_mm_s > 0.0;
}

void vs_study_components_pct(const vs_run *r, double delta, double *dz, double *dx) {
  const vs_case *c = vs_run_case(r);
  const double L = vs_study_span_mm(r);
  if (right_alone(c)) { /* delta along alpha, as always */
    const vs_support_dir sd = vs_support_direction(c->alpha_deg * VS_DEG);
    *dz = 100.0 * (delta / VS_MM) * sd.dz / L;
    *dx = 100.0 * (delta / VS_MM) * sd.dx / L;
    return;
  }
  double t[4];
  vs_study_travel(r, delta, t);
  *dz = 100.0 * (t[3] - t[1]) / L; /* the right support's settlement below the left one's */
  *dx = 100.0 * (t[2] + t[0]) / L; /* the spreading of the span */
}
