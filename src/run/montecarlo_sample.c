/* Monte Carlo over imperfect arches: one sample's run (the core library; its statistics and
 * summary files are in src/plot/montecarlo.c, in the plot plugin). */
#define _POSIX_C_SOURCE 200809L
#include "voussoir/montecarlo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/model.h"
#include "voussoir/run.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

static void fill_hinges(const vs_run *r, vs_mc_sample *o) {
  const vs_collapse_record *cr = vs_run_collapse(r);
  for (int i = 0; i < cr->n_hinges; i++) {
    const vs_hinge *h = &cr->hinges[i];
    const int l = h->label - 'A';
    if (l < 0 || l >= VS_MC_LABELS) continue;
    o->hinge_joint[l] = (h->first + h->last) / 2;
    o->hinge_side[l] = h->side;
  }
  /* as vs_run_pattern_collapse, cut visibly (a trailing '-') when too long for the field */
  vs_hinges_side_pattern(cr->hinges, cr->n_hinges, o->pattern, sizeof o->pattern);
  const char *mode = vs_run_mode(r);
  o->mode = mode == NULL ? 0 : strcmp(mode, "I") == 0 ? 1 : strcmp(mode, "II") == 0 ? 2
                                                        : strcmp(mode, "III") == 0 ? 3 : 0;
}

/* The supports' relative displacement at delta (m) into dz_u_mm (the right one's settlement
 * below the left one) and dx_u_mm (the spreading), as the run's JSON gives it when both move. */
static void relative(const vs_run *r, double delta, vs_mc_sample *o) {
  double u[2][3];
  for (int s = 0; s < 2; s++)
    vs_support_motion_at(vs_model_support_motion(vs_run_model(r), s), delta, u[s], NULL);
  o->dx_u_mm = (u[1][0] - u[0][0]) / VS_MM;
  o->dz_u_mm = (u[0][1] - u[1][1]) / VS_MM;
}

void vs_mc_run_sample(const vs_case *base, int sample, vs_mc_sample *o) {
  memset(o, 0, sizeof *o);
  o->sample = sample;
  o->first_limit_mm = o->delta_u_mm = o->dz_u_mm = o->dx_u_mm = o->load_factor = NAN;
  o->first_crack_mm = NAN;
  o->mortared = base->tensile_MPa > 0.0 || base->cohesion_MPa > 0.0;
  vs_case c = *base;
  c.sample = sample;
  c.fall_s = 0.0; /* delta_u and the mechanism are read before the fall, which costs the most */
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  vs_status st = vs_run_create(&c, &r, &err);
  if (st == VS_OK) st = vs_run_execute(r, NULL, NULL, NULL, &err);
  if (r != NULL && vs_run_load(r)->done) o->load_factor = vs_run_load(r)->load_factor;
  if (r != NULL && vs_run_limit_count(r) > 0) o->first_limit_mm = vs_run_limit(r, 0)->delta / VS_MM;
  const vs_run_event *fc = r != NULL && o->mortared ? vs_run_first_crack(r) : NULL;
  if (fc != NULL) {
    o->first_crack_mm = fc->delta / VS_MM;
    o->first_crack_joint = fc->joint;
    o->first_crack_side = fc->side;
  }
  if (st != VS_OK) {
    o->status = VS_MC_FAILED;
    snprintf(o->error, sizeof o->error, "%.399s", err.msg);
  } else if (vs_run_collapse(r)->found) {
    const double d = vs_run_collapse(r)->delta / VS_MM;
    const vs_support_dir sd = vs_support_direction(c.alpha_deg * VS_DEG);
    o->status = VS_MC_COLLAPSE;
    o->delta_u_mm = d;
    o->dz_u_mm = d * sd.dz;
    o->dx_u_mm = d * sd.dx;
    if (c.left_rate_mm_s != 0.0 || c.left_path.n > 0 || c.right_path.n > 0 || c.rate_mm_s == 0.0)
      relative(r, vs_run_collapse(r)->delta, o); /* more than the right support moves */
    fill_hinges(r, o);
  } else {
    o->status = VS_MC_NO_COLLAPSE;
  }
  vs_run_destroy(&r);
}
