/* The limit analysis' picture (`voussoir run` with analysis.type = limit and --plot): the
 * thrust line of one LP solution over its arch, its hinges marked. The LP gives each joint's
 * normal forces at its two ends (N_I, N_E); their resultant N = N_I + N_E acts at
 * e = M / N from the joint's centre, M = (N_E - N_I) t / 2, which is what the arch picture's
 * thrust line joins (plot_arch.c). */
#include "plot_limit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/imperfections.h"

vs_status vs_plot_limit_pick(const vs_run_def *d, const vs_limit_analysis *la,
                             vs_plot_limit *out, vs_error *err) {
  memset(out, 0, sizeof *out);
  const vs_limit_solution *s = NULL;
  double factor = 1.0;
  if (la->have_load && la->collapse.outcome == VS_LIMIT_OPTIMAL) {
    s = &la->collapse;
    snprintf(out->title, sizeof out->title,
             "Limit analysis: collapse at load factor %.5g, the thrust line over the mechanism",
             s->value);
  } else if (isfinite(la->thickness_factor) && la->thickness.outcome == VS_LIMIT_OPTIMAL) {
    s = &la->thickness;
    factor = la->thickness_factor;
    snprintf(out->title, sizeof out->title,
             "Limit analysis: the arch at its least thickness (%.5g t), its thrust line", factor);
  } else if (la->thrust_min.outcome == VS_LIMIT_OPTIMAL) {
    s = &la->thrust_min;
    snprintf(out->title, sizeof out->title,
             "Limit analysis: the least thrust under self-weight, H = %.5g N", s->value);
  } else {
    return vs_error_set(err, VS_ERR_INVALID, "limit picture: no optimal solution to draw");
  }
  out->s = s;
  out->factor = factor;
  vs_arch_def a = d->arch;
  a.thickness *= factor;
  vs_imperfections *imp = NULL;
  vs_status st = vs_imperfections_draw(&d->imperfections, &a, &imp, err);
  if (st == VS_OK) st = vs_imperfections_arch(&d->imperfections, &a, imp, &out->g, err);
  vs_imperfections_destroy(&imp);
  if (st != VS_OK) return st;
  const int nj = out->g->n_joints;
  if (s->n_joints != nj) {
    vs_plot_limit_free(out);
    return vs_error_set(err, VS_ERR_INVALID, "limit picture: %d joints solved, %d drawn",
                        s->n_joints, nj);
  }
  out->N = calloc((size_t)nj, sizeof *out->N);
  out->M = calloc((size_t)nj, sizeof *out->M);
  out->hinges = calloc((size_t)nj, sizeof *out->hinges);
  out->q = calloc(3 * (size_t)out->g->n_blocks, sizeof *out->q);
  if (out->N == NULL || out->M == NULL || out->hinges == NULL || out->q == NULL) {
    vs_plot_limit_free(out);
    return vs_error_set(err, VS_ERR_NOMEM, "limit picture: out of memory");
  }
  for (int k = 0; k < nj; k++) {
    const double ni = s->force[4 * k], ne = s->force[4 * k + 2];
    out->N[k] = ni + ne;
    out->M[k] = 0.5 * (ne - ni) * out->g->joints[k].length;
    /* the mechanism's hinges (the collapse), else where the thrust line touches an edge */
    const char c = s->hinge != NULL ? s->hinge[k] : s->touch[k];
    if (c != 'I' && c != 'E') continue;
    vs_hinge *h = &out->hinges[out->n_hinges];
    *h = (vs_hinge){.label = (char)('A' + (out->n_hinges < 26 ? out->n_hinges : 25)),
                    .side = c, .first = k + 1, .last = k + 1, .onset_first = k + 1,
                    .onset_last = k + 1, .order = out->n_hinges + 1, .open = 1,
                    .delta_closed = NAN};
    out->n_hinges++;
  }
  return VS_OK;
}

void vs_plot_limit_free(vs_plot_limit *p) {
  vs_geometry_destroy(&p->g);
  free(p->N);
  free(p->M);
  free(p->hinges);
  free(p->q);
  p->N = p->M = p->q = NULL;
  p->hinges = NULL;
}

vs_plot_arch_args vs_plot_limit_args(const vs_plot_limit *p) {
  return (vs_plot_arch_args){.g = p->g, .q = p->q, .hinges = p->hinges,
                             .n_hinges = p->n_hinges, .joint_N = p->N, .joint_M = p->M,
                             .title = p->title};
}

vs_status vs_plot_limit_picture(const char *path, const vs_run_def *d,
                                const vs_limit_analysis *la, vs_error *err) {
  vs_plot_limit p;
  vs_status st = vs_plot_limit_pick(d, la, &p, err);
  if (st != VS_OK) return st;
  vs_limit_force *loads = NULL;
  int n_loads = 0;
  if (p.s == &la->collapse) st = vs_limit_live_load(p.g, &d->load, &d->fill, &loads, &n_loads, err);
  vs_plot_arch_args a = vs_plot_limit_args(&p);
  a.loads = loads;
  a.n_loads = n_loads;
  if (st == VS_OK) st = vs_plot_arch_draw(path, vs_plot_format_from_path(path), &a, err);
  free(loads);
  vs_plot_limit_free(&p);
  return st;
}
