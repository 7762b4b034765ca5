/* Human-readable and JSON summaries of a run. */
#include "voussoir/report.h"

#include <math.h>

#include "voussoir/units.h"
#include "voussoir/version.h"

void vs_json_string(FILE *out, const char *s) {
  fputc('"', out);
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    if (*p == '"' || *p == '\\') fprintf(out, "\\%c", *p);
    else if (*p == '\n') fputs("\\n", out);
    else if (*p < 0x20) fprintf(out, "\\u%04x", *p);
    else fputc(*p, out);
  }
  fputc('"', out);
}

/* Support displacement components over the span, in %. */
static void components_pct(const vs_case *c, double delta_m, double *dz, double *dx) {
  const double L = vs_case_span_mm(c), d = delta_m / VS_MM, a = c->alpha_deg * VS_DEG;
  *dz = 100.0 * d * cos(a) / L;
  *dx = 100.0 * d * sin(a) / L;
}

static const char *end_name(const vs_path_result *p, vs_status st) {
  if (st != VS_OK) return "failed";
  return p->end == VS_PATH_LIMIT_POINT ? "limit_point" : "max_displacement";
}

void vs_report_json(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                    const char *case_path) {
  const vs_case *c = vs_run_case(r);
  const vs_path_result *p = vs_run_path(r);
  const vs_hinges *h = vs_run_hinges(r);
  fprintf(out, "{\"program\":\"voussoir\",\"version\":\"%s\",\"case\":", VS_VERSION);
  vs_json_string(out, case_path ? case_path : "");
  fprintf(out, ",\"status\":\"%s\",\"error\":", end_name(p, status));
  if (status != VS_OK && err != NULL) vs_json_string(out, err->msg);
  else fputs("null", out);
  fprintf(out, ",\"alpha_deg\":%.17g,\"kn_N_mm3\":%.17g,\"span_mm\":%.17g", c->alpha_deg,
          c->kn_N_mm3, vs_case_span_mm(c));
  fputs(",\"first_limit\":", out);
  if (status == VS_OK && p->end == VS_PATH_LIMIT_POINT) {
    double dz, dx;
    components_pct(c, p->delta_limit, &dz, &dx);
    fprintf(out,
            "{\"delta_mm\":%.10g,\"dz_over_L_pct\":%.10g,\"dx_over_L_pct\":%.10g,"
            "\"bracket_mm\":[%.10g,%.10g],\"det_sign\":%d,\"lambda_start_N_m\":%.6g,"
            "\"lambda_last_N_m\":%.6g,\"delta_extrapolated_mm\":%.10g}",
            p->delta_limit / VS_MM, dz, dx, p->delta_limit / VS_MM, p->delta_fail / VS_MM,
            p->evidence.det_sign, p->evidence.lambda_start, p->evidence.lambda_last,
            p->evidence.delta_extrap / VS_MM);
  } else {
    fputs("null", out);
  }
  fprintf(out, ",\"last_delta_mm\":%.10g,\"hinges\":[", vs_run_delta(r) / VS_MM);
  for (int i = 0; i < vs_hinges_count(h); i++) {
    const vs_hinge *hg = vs_hinges_get(h, i);
    fprintf(out, "%s{\"label\":\"%c\",\"side\":\"%c\",\"joints\":[", i ? "," : "", hg->label,
            hg->side);
    for (int j = hg->first; j <= hg->last; j++) fprintf(out, "%s%d", j > hg->first ? "," : "", j);
    fputs("],\"joints_onset\":[", out);
    for (int j = hg->onset_first; j <= hg->onset_last; j++)
      fprintf(out, "%s%d", j > hg->onset_first ? "," : "", j);
    fprintf(out, "],\"delta_onset_mm\":%.10g,\"open\":%s,\"order\":%d}", hg->delta_onset / VS_MM,
            hg->open ? "true" : "false", hg->order);
  }
  fprintf(out,
          "],\"parameters\":{\"open_mm\":%.10g,\"migrate_joints\":%d,\"limit_tol_mm\":%.10g,"
          "\"newton_tol\":%.10g,\"ks_ratio\":%.10g,\"friction\":%.10g,\"voussoirs\":%d}",
          c->open_mm, c->migrate_joints, c->limit_tol_mm, c->newton_tol, c->ks_ratio, c->friction,
          c->voussoirs);
  fprintf(out,
          ",\"stats\":{\"steps\":%ld,\"rejected_steps\":%ld,\"newton_iterations\":%ld,"
          "\"jacobian_evaluations\":%ld,\"max_residual\":%.3g,\"floor_limited\":%ld,"
          "\"wall_s\":%.6g}}\n",
          p->steps, p->rejected, p->newton_iterations, p->jacobian_evals, p->max_residual,
          p->floor_limited, vs_run_wall_s(r));
}

void vs_report_text(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                    const char *case_path) {
  const vs_case *c = vs_run_case(r);
  const vs_geometry *g = vs_run_geometry(r);
  const vs_path_result *p = vs_run_path(r);
  const vs_hinges *h = vs_run_hinges(r);
  fprintf(out, "voussoir %s  case %s\n", VS_VERSION, case_path ? case_path : "(defaults)");
  fprintf(out,
          "arch     R = %g mm, t = %g mm, embrace %g deg, %d voussoirs, b = %g mm\n"
          "         span L = %.2f mm, rise %.2f mm, weight %.3f N\n",
          c->radius_mm, c->thickness_mm, c->embrace_deg, c->voussoirs, c->depth_mm,
          g->span / VS_MM, g->rise / VS_MM, vs_geometry_weight(g));
  fprintf(out, "joints   k_n = %g N/mm^3, k_s = %g k_n, mu = %g\n", c->kn_N_mm3, c->ks_ratio,
          c->friction);
  fprintf(out, "support  right support moved at alpha = %g deg from the vertical (left fixed)\n",
          c->alpha_deg);
  fprintf(out,
          "criteria hinge: edge opening > %g mm, migration within %d joints;\n"
          "         limit point bracketed to %g mm; Newton tolerance %g x voussoir weight\n\n",
          c->open_mm, c->migrate_joints, c->limit_tol_mm, c->newton_tol);
  if (status == VS_OK && p->end == VS_PATH_LIMIT_POINT) {
    double dz, dx;
    components_pct(c, p->delta_limit, &dz, &dx);
    fprintf(out, "first limit point  delta = %.4f mm   dz/L = %.3f %%   dx/L = %.3f %%\n",
            p->delta_limit / VS_MM, dz, dx);
    fprintf(out,
            "  confirmed: no equilibrium at %.4f mm; smallest tangent eigenvalue %.3g N/m "
            "(%.3g after self-weight),\n  extrapolated to zero at %.4f mm; det K %s 0 on the path\n",
            p->delta_fail / VS_MM, p->evidence.lambda_last, p->evidence.lambda_start,
            p->evidence.delta_extrap / VS_MM, p->evidence.det_sign > 0 ? ">" : "<=");
  } else if (status == VS_OK) {
    double dz, dx;
    components_pct(c, vs_run_delta(r), &dz, &dx);
    fprintf(out, "no limit point up to delta = %.4f mm (dz/L = %.3f %%, dx/L = %.3f %%)\n",
            vs_run_delta(r) / VS_MM, dz, dx);
  } else {
    fprintf(out, "FAILED at delta = %.4f mm: %s\n", vs_run_delta(r) / VS_MM,
            err != NULL ? err->msg : vs_strerror(status));
  }
  fprintf(out, "\nhinges (in order of appearance; side = edge that stays in contact)\n");
  fprintf(out, "  label  at onset        now             delta_onset    dz/L     dx/L\n");
  int spread = 0;
  for (int i = 0; i < vs_hinges_count(h); i++) {
    const vs_hinge *hg = vs_hinges_get(h, i);
    char a[64], b[64];
    vs_hinge_name(hg, 1, a, sizeof a);
    if (hg->open) vs_hinge_name(hg, 0, b, sizeof b);
    else snprintf(b, sizeof b, "closed@%.2fmm", hg->delta_closed / VS_MM);
    double dz, dx;
    components_pct(c, hg->delta_onset, &dz, &dx);
    fprintf(out, "  %c      %-15s %-15s %8.3f mm  %6.3f %%  %6.3f %%\n", hg->label, a, b,
            hg->delta_onset / VS_MM, dz, dx);
    spread |= (hg->last > hg->first) || (hg->onset_last > hg->onset_first);
  }
  if (vs_hinges_count(h) == 0) fprintf(out, "  (none)\n");
  if (spread)
    fprintf(out, "  a name like 44-45-46-I is one hinge spread over consecutive joints that are "
                 "each slightly open\n");
  fprintf(out, "\nstats    %ld equilibria (%ld rejected increments), %ld Newton iterations, "
               "%ld Jacobians, %.3f s\n",
          p->steps, p->rejected, p->newton_iterations, p->jacobian_evals, vs_run_wall_s(r));
  fprintf(out, "         largest residual %.2g x voussoir weight", p->max_residual);
  if (p->floor_limited > 0)
    fprintf(out, " (%ld equilibria limited by round-off, above the tolerance)", p->floor_limited);
  fputc('\n', out);
  if (status == VS_OK && p->end == VS_PATH_LIMIT_POINT)
    fprintf(out, "note     the run stops at the first limit point; what follows it (snap-through "
                 "or collapse) is not followed yet\n");
}
