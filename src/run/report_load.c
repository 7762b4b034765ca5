/* The report of the live load's path (analysis.type = load; report.h): its load factor at
 * collapse, the mechanism, the load-deflection curve, in JSON and text. */
#include <math.h>
#include <stdio.h>

#include "run_internal.h"
#include "voussoir/limit.h"
#include "voussoir/quasistatic.h"
#include "voussoir/report.h"
#include "report_load.h"
#include "voussoir/units.h"

static const char *load_end_name(const vs_run_load_result *l) {
  if (l->held_limit) return "held_limit";
  switch (l->end) {
  case VS_LOAD_END_PEAK: return "peak";
  case VS_LOAD_END_SLIDING: return "sliding";
  case VS_LOAD_END_MAX_DISP: return "max_displacement";
  case VS_LOAD_END_STALLED: return "stalled";
  default: return "none";
  }
}

const char *vs_report_load_status(const vs_run *r) {
  const vs_run_load_result *l = vs_run_load(r);
  if (l->held_limit) return "limit_point";
  return l->end == VS_LOAD_END_PEAK || l->end == VS_LOAD_END_SLIDING ? "collapse"
                                                                      : "max_displacement";
}

static void jnum(FILE *out, const char *key, double x) {
  fputs(key, out);
  if (isfinite(x)) fprintf(out, "%.10g", x);
  else fputs("null", out);
}

void vs_report_load_json(FILE *out, const vs_run *r) {
  const vs_run_load_result *l = vs_run_load(r);
  const vs_run_def *d = vs_run_def_of(r);
  jnum(out, ",\"load_factor\":", l->load_factor);
  fprintf(out, ",\"load\":{\"kind\":\"%s\"", vs_load_kind_name(d->load.kind));
  jnum(out, ",\"value_N\":", d->load.value);
  jnum(out, ",\"x_mm\":", d->load.x / VS_MM);
  jnum(out, ",\"width_mm\":", d->load.width / VS_MM);
  jnum(out, ",\"hold_mm\":", l->hold / VS_MM);
  fprintf(out, ",\"end\":\"%s\"", load_end_name(l));
  jnum(out, ",\"deflection_mm\":", l->deflection / VS_MM);
  jnum(out, ",\"first_peak\":", l->first_peak);
  fprintf(out, ",\"snap_back\":%s,\"settled\":%s", l->snap_back ? "true" : "false",
          l->settled ? "true" : "false");
  fputs(",\"mechanism\":", out);
  vs_json_string(out, l->mechanism);
  fputs(",\"cause\":", out);
  vs_json_string(out, l->cause);
  fprintf(out, ",\"steps\":%ld,\"rejected\":%ld,\"newton_iterations\":%ld", l->steps,
          l->rejected, l->newton_iterations);
  fputs(",\"curve\":{\"load_factor\":[", out);
  for (int i = 0; i < l->n; i++) fprintf(out, "%s%.10g", i ? "," : "", l->lambda[i]);
  fputs("],\"deflection_mm\":[", out);
  for (int i = 0; i < l->n; i++) fprintf(out, "%s%.10g", i ? "," : "", l->u[i] / VS_MM);
  fputs("]}}", out);
  /* beside it, the limit analysis of the configuration the load started from */
  vs_status st = VS_OK;
  const vs_limit_analysis *a = vs_run_limit_held(r, &st, NULL);
  fputs(",\"limit\":", out);
  if (a != NULL && st == VS_OK)
    vs_report_limit_object(out, a, d->load.kind, d->load.value, d->arch.thickness / VS_MM,
                           d->arch.piers.height > 0.0 ? d->arch.piers.courses : 0);
  else
    fputs("null", out);
}

/* The limit analysis of the held configuration, beside the path's load factor. */
static void text_limit(FILE *out, const vs_run *r) {
  vs_status st = VS_OK;
  const vs_error *err = NULL;
  const vs_limit_analysis *a = vs_run_limit_held(r, &st, &err);
  if (a == NULL) return;
  if (st != VS_OK) {
    fprintf(out, "limit analysis of the held arch: failed: %s\n", err->msg);
    return;
  }
  const vs_limit_solution *s = &a->collapse;
  fputs("limit analysis of the held arch (rigid blocks where the path left them): ", out);
  if (s->outcome == VS_LIMIT_OPTIMAL) fprintf(out, "lambda = %.6g", s->value);
  else fprintf(out, "lambda %s", s->outcome == VS_LIMIT_UNBOUNDED ? "unbounded" : "none");
  fprintf(out, ", thickness factor %.5g\n", a->thickness_factor);
}

void vs_report_load_text(FILE *out, const vs_run *r) {
  const vs_run_load_result *l = vs_run_load(r);
  const vs_run_def *d = vs_run_def_of(r);
  const vs_load_def *ld = &d->load;
  fprintf(out, "live load  %s", vs_load_kind_name(ld->kind));
  if (ld->kind == VS_LOAD_TILT) fputs(" (lambda x each block's weight, horizontal)", out);
  else fprintf(out, " %g N at x = %g mm", ld->value, ld->x / VS_MM);
  if (ld->kind == VS_LOAD_PATCH) fprintf(out, " over %g mm", ld->width / VS_MM);
  fprintf(out, "; the support held at %.4f mm%s\n", l->hold / VS_MM,
          l->settled ? " (reached during a snap-through: the arch taken at the equilibrium "
                       "Newton found from its motion)"
                     : "");
  if (l->held_limit) {
    fprintf(out, "load factor  %s: %s\n", isnan(l->load_factor) ? "unknown" : "0", l->cause);
    return;
  }
  text_limit(out, r);
  const char *how = l->end == VS_LOAD_END_PEAK      ? "past the peak"
                    : l->end == VS_LOAD_END_SLIDING ? "a sliding mechanism"
                                                    : "no collapse";
  fprintf(out, "load factor  lambda = %.6g at collapse (%s; deflection %.4f mm at the peak)\n",
          l->load_factor, how, l->deflection / VS_MM);
  if (isfinite(l->first_peak) && l->first_peak < l->load_factor)
    fprintf(out, "             lambda first peaked at %.6g (under load control the arch snaps "
                 "there)%s\n",
            l->first_peak, l->snap_back ? "; the path turned back and was followed by arc length"
                                        : "");
  if (l->end == VS_LOAD_END_MAX_DISP)
    fprintf(out, "             the path reached support.max_mm of the loads' displacement "
                 "before lambda fell: the largest lambda so far\n");
  if (l->end == VS_LOAD_END_STALLED) fprintf(out, "             the path stalled: %s\n", l->cause);
  fprintf(out, "mechanism    %s\n", l->mechanism[0] ? l->mechanism : "(no hinge open)");
  fprintf(out, "\nload-deflection curve (deflection: the loads' displacement along them)\n"
               "  load factor   deflection mm\n");
  for (int i = 0; i < l->n; i++) fprintf(out, "  %11.6g   %13.6g\n", l->lambda[i], l->u[i] / VS_MM);
  fprintf(out, "load path    %ld equilibria (%ld rejected increments), %ld Newton iterations, %ld "
               "Jacobians (the support's path to the hold: stats below)\n",
          l->steps, l->rejected, l->newton_iterations, l->jacobian_evals);
}
