/* Human-readable and JSON summaries of a run. */
#include "voussoir/report.h"

#include "voussoir/damping.h"
#include "voussoir/support.h"

#include <math.h>

#include "report_load.h"
#include "voussoir/units.h"
#include "voussoir/version.h"
#include "quote.h"
#include "report_piers.h"

/* --- both supports (docs/model.md, "Both supports move") --- */

/* Does the case move the right support alone, along alpha (every case before both could)? */
static int right_alone(const vs_case *c) {
  return c->left_rate_mm_s == 0.0 && c->left_path.n == 0 && c->right_path.n == 0 &&
         c->rate_mm_s > 0.0;
}

/* Support s's (0 left, 1 right) displacement at delta as the output gives it: dx outward, dz
 * down (mm), the prescribed rotation outward (deg; NaN for a pinned support, whose rotation is
 * free). The motion's own, without an imperfect arch's initial offset. */
static void support_outward(const vs_run *r, int s, double delta, double out[3]) {
  double u[3];
  vs_support_motion_at(vs_model_support_motion(vs_run_model(r), s), delta, u, NULL);
  out[0] = (s ? u[0] : -u[0]) / VS_MM;
  out[1] = -u[1] / VS_MM;
  out[2] = vs_model_support_kind(vs_run_model(r), s) == VS_SUPPORT_PINNED
               ? NAN
               : (s ? -u[2] : u[2]) / VS_DEG;
  for (int c = 0; c < 3; c++) out[c] += 0.0; /* a support at rest: 0, not -0 */
}

/* The relative displacement of the supports (the right one's relative to the left one: dx the
 * spreading of the span, dz the right one's settlement below the left one), mm. */
static void support_relative(const vs_run *r, double delta, double *dx, double *dz) {
  double lo[3], ro[3];
  support_outward(r, 0, delta, lo);
  support_outward(r, 1, delta, ro);
  *dx = ro[0] + lo[0];
  *dz = ro[1] - lo[1];
}

/* The span the displacements are normalised by, mm: the case's (vs_case_span_mm), or a blocks
 * file's arch's own when the case does not give it. */
static double run_span_mm(const vs_run *r) {
  const double L = vs_case_span_mm(vs_run_case(r));
  return isfinite(L) ? L : vs_run_geometry(r)->span / VS_MM;
}

/* Support displacement components over the span, in %: delta along alpha when the right support
 * moves alone (as always), else the supports' relative displacement. */
static void components_pct(const vs_run *r, double delta_m, double *dz, double *dx) {
  const vs_case *c = vs_run_case(r);
  const double L = run_span_mm(r), d = delta_m / VS_MM;
  if (!right_alone(c)) {
    support_relative(r, delta_m, dx, dz);
    *dz *= 100.0 / L;
    *dx *= 100.0 / L;
    return;
  }
  const vs_support_dir sd = vs_support_direction(c->alpha_deg * VS_DEG);
  *dz = 100.0 * d * sd.dz / L;
  *dx = 100.0 * d * sd.dx / L;
}

/* The supports' kinds as the case file names them (support.left_kind), by vs_support_kind. */
static const char *const SUPPORT_KINDS[] = {"fixed", "pinned"};
_Static_assert(sizeof SUPPORT_KINDS / sizeof SUPPORT_KINDS[0] == VS_SUPPORT_KIND_COUNT,
               "a name for every vs_support_kind");

/* The case file's names of the shapes (arch.shape). */
static const char *const SHAPES[] = {"circular", "pointed", "elliptical", "basket", "parabolic",
                                     "catenary", "file"};
_Static_assert(sizeof SHAPES / sizeof SHAPES[0] == VS_SHAPE_COUNT, "a name for every shape");

static const char *support_kind(int kind) {
  return kind >= 0 && kind < VS_SUPPORT_KIND_COUNT ? SUPPORT_KINDS[kind] : "?";
}

static const char *end_name(const vs_run *r, vs_status st) {
  if (st == VS_ERR_WALL_TIME || st == VS_ERR_STOPPED) return "stopped";
  if (st != VS_OK) return "failed";
  if (vs_run_load(r)->done) return vs_report_load_status(r);
  if (vs_run_collapse(r)->found) return "collapse";
  if (!vs_run_case(r)->follow && !vs_run_case(r)->full && vs_run_limit_count(r) > 0)
    return "limit_point";
  return "max_displacement";
}

/* Numbers in JSON: JSON has no inf or nan, so a value that is not finite is written as null. */
static void json_number_or_null(FILE *out, double x) {
  if (isfinite(x)) fprintf(out, "%.10g", x);
  else fputs("null", out);
}

/* ,"key":x (or "key":x first in an object) with x finite, else null; %.17g keeps every bit. */
static void jnum(FILE *out, const char *sep_key, double x, int digits) {
  fputs(sep_key, out);
  if (isfinite(x)) fprintf(out, "%.*g", digits, x);
  else fputs("null", out);
}

/* One hinge of a list (first: the list's first), its joints at onset too when with_onset. */
static void json_hinge(FILE *out, const vs_run *r, const vs_hinge *h, int first, int with_onset) {
  const double rate = vs_case_loading_rate_mm_s(vs_run_case(r)) * VS_MM;
  fprintf(out, "%s{\"label\":\"%c\",\"side\":\"%c\",\"joints\":[", first ? "" : ",", h->label,
          h->side);
  for (int j = h->first; j <= h->last; j++) fprintf(out, "%s%d", j > h->first ? "," : "", j);
  if (with_onset) {
    fputs("],\"joints_onset\":[", out);
    for (int j = h->onset_first; j <= h->onset_last; j++)
      fprintf(out, "%s%d", j > h->onset_first ? "," : "", j);
  }
  jnum(out, "],\"delta_onset_mm\":", h->delta_onset / VS_MM, 10);
  jnum(out, ",\"time_onset_s\":", h->delta_onset / rate, 10);
  if (vs_run_def_of(r)->analysis.type == VS_ANALYSIS_LOAD) { /* its onset's load factor */
    double lf = NAN;
    for (int i = 0; i < vs_run_event_count(r); i++) {
      const vs_run_event *e = vs_run_event_get(r, i);
      if (e->kind == VS_EVENT_HINGE_FORMED && e->order == h->order) lf = e->load_factor;
    }
    jnum(out, ",\"load_factor_onset\":", lf, 10);
  }
  fprintf(out, ",\"open\":%s,\"order\":%d}", h->open ? "true" : "false", h->order);
}

/* ,"left":{"dx_mm":..,"dz_mm":..,"rot_deg":..},"right":{..} at delta. */
static void json_supports_at(FILE *out, const vs_run *r, double delta) {
  for (int s = 0; s < 2; s++) {
    double o[3];
    support_outward(r, s, delta, o);
    jnum(out, s ? ",\"right\":{\"dx_mm\":" : ",\"left\":{\"dx_mm\":", o[0], 10);
    jnum(out, ",\"dz_mm\":", o[1], 10);
    jnum(out, ",\"rot_deg\":", o[2], 10);
    fputc('}', out);
  }
}

static void json_first_limit(FILE *out, const vs_run *r) {
  const vs_path_result *p = vs_run_path(r);
  double dz, dx;
  if (p->end != VS_PATH_LIMIT_POINT || vs_run_limit_count(r) == 0) {
    fputs("null", out);
    return;
  }
  components_pct(r, p->delta_limit, &dz, &dx);
  jnum(out, "{\"delta_mm\":", p->delta_limit / VS_MM, 10);
  jnum(out, ",\"dz_over_L_pct\":", dz, 10);
  jnum(out, ",\"dx_over_L_pct\":", dx, 10);
  jnum(out, ",\"bracket_mm\":[", p->delta_limit / VS_MM, 10);
  jnum(out, ",", p->delta_fail / VS_MM, 10);
  fprintf(out, "],\"det_sign\":%d", p->evidence.det_sign);
  jnum(out, ",\"lambda_start_N_m\":", p->evidence.lambda_start, 6);
  jnum(out, ",\"lambda_last_N_m\":", p->evidence.lambda_last, 6);
  jnum(out, ",\"delta_extrapolated_mm\":", p->evidence.delta_extrap / VS_MM, 10);
  if (p->evidence.slip_onset > 0) /* a limit point at the onset of slip */
    fprintf(out, ",\"slip_onset\":{\"first_joint\":%d,\"joints\":%d}}",
            p->evidence.slip_joint + 1, p->evidence.slip_onset);
  else
    fputs(",\"slip_onset\":null}", out);
}

/* {"left":[Fx,Fz,M],"right":[...]} (N, N, N m; null where NaN). */
static void json_reactions(FILE *out, const double rc[6]) {
  for (int s = 0; s < 2; s++) {
    fputs(s ? "],\"right\":[" : "{\"left\":[", out);
    for (int c = 0; c < 3; c++) {
      if (c) fputc(',', out);
      json_number_or_null(out, rc[3 * s + c]);
    }
  }
  fputs("]}", out);
}

/* A slip's direction in words: the edge its voussoir slides toward. */
static const char *slip_toward(char side) { return side == 'E' ? "extrados" : "intrados"; }

/* The collapse's slips: [{"joint":1,"toward":"intrados","slip_mm":3.2}, ...]. */
static void json_collapse_slips(FILE *out, const vs_collapse_record *col) {
  fputs(",\"slips\":[", out);
  for (int i = 0; i < col->n_slips; i++) {
    fprintf(out, "%s{\"joint\":%d,\"toward\":\"%s\"", i ? "," : "", col->slips[i].joint,
            slip_toward(col->slips[i].side));
    jnum(out, ",\"slip_mm\":", col->slips[i].slip / VS_MM, 10);
    fputc('}', out);
  }
  fputc(']', out);
}

/* Every slip event: [{"joint":1,"toward":"intrados","delta_mm":53.4,"phase":"quasistatic"}]. */
static void json_slip_events(FILE *out, const vs_run *r) {
  static const char *const phases[] = {"quasistatic", "dynamic", "fall"};
  fputs(",\"slips\":[", out);
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++) {
    const vs_run_event *e = vs_run_event_get(r, i);
    if (e->kind != VS_EVENT_JOINT_SLIPPED) continue;
    fprintf(out, "%s{\"joint\":%d,\"toward\":\"%s\"", n++ ? "," : "", e->joint,
            slip_toward(e->side));
    jnum(out, ",\"delta_mm\":", e->delta / VS_MM, 10);
    fprintf(out, ",\"phase\":\"%s\"}", phases[e->phase]);
  }
  fputc(']', out);
}

static void json_collapse(FILE *out, const vs_run *r) {
  const vs_collapse_record *col = vs_run_collapse(r);
  double dz, dx;
  if (!col->found) {
    fputs("null", out);
    return;
  }
  components_pct(r, col->delta, &dz, &dx);
  jnum(out, "{\"delta_mm\":", col->delta / VS_MM, 10);
  jnum(out, ",\"dz_over_L_pct\":", dz, 10);
  jnum(out, ",\"dx_over_L_pct\":", dx, 10);
  json_supports_at(out, r, col->delta);
  jnum(out, ",\"time_s\":", col->t, 10);
  jnum(out, ",\"delta_detected_mm\":", col->delta_detected / VS_MM, 10);
  jnum(out, ",\"time_detected_s\":", col->t_criterion, 10);
  jnum(out, ",\"onset_time_s\":", col->t_onset, 10);
  jnum(out, ",\"delta_onset_mm\":", col->t_onset * vs_case_loading_rate_mm_s(vs_run_case(r)), 10);
  fputs(",\"reactions_at_limit\":", out);
  json_reactions(out, col->reactions_limit);
  fputs(",\"hinges\":[", out);
  for (int i = 0; i < col->n_hinges; i++) json_hinge(out, r, &col->hinges[i], i == 0, 0);
  fprintf(out, "],\"mechanism\":\"%s\"", col->mechanism);
  json_collapse_slips(out, col);
  fputc('}', out);
}

static void json_limits(FILE *out, const vs_run *r) {
  fputc('[', out);
  for (int i = 0; i < vs_run_limit_count(r); i++) {
    const vs_limit_record *l = vs_run_limit(r, i);
    jnum(out, i ? ",{\"delta_mm\":" : "{\"delta_mm\":", l->delta / VS_MM, 10);
    fprintf(out, ",\"kind\":\"%s\",\"delta_settled_mm\":",
            l->collapse ? "collapse" : isfinite(l->delta_settled) ? "snap" : "unfollowed");
    json_number_or_null(out, l->delta_settled / VS_MM);
    fputs(",\"hinges_before\":", out);
    vs_json_string(out, l->hinges_before);
    fputs(",\"hinges_after\":", out);
    vs_json_string(out, l->hinges_after);
    fputc('}', out);
  }
  fputc(']', out);
}

/* The damping model and the modes under self-weight with the ratio it gives each. */
static void json_damping(FILE *out, const vs_run *r) {
  const vs_case *c = vs_run_case(r);
  const vs_modal *md = vs_run_modal(r);
  double alpha, beta;
  vs_run_rayleigh(r, &alpha, &beta);
  fprintf(out, ",\"damping\":{\"model\":\"%s\"",
          vs_damping_model_name((vs_damping_model)c->damping_model));
  jnum(out, ",\"ratio\":", c->damping, 10);
  jnum(out, ",\"rayleigh_alpha_per_s\":", alpha, 10);
  jnum(out, ",\"rayleigh_beta_s\":", beta, 10);
  fprintf(out, ",\"impacts\":%ld", vs_run_dynamic_totals(r)->impacts);
  fputs(",\"modes_self_weight\":[", out);
  for (int i = 0; i < md->n_modes; i++) {
    jnum(out, i ? ",{\"freq_hz\":" : "{\"freq_hz\":", md->freq_hz[i], 10);
    jnum(out, ",\"omega_rad_s\":", md->omega[i], 10);
    jnum(out, ",\"damping_ratio\":", md->zeta[i], 6);
    fputc('}', out);
  }
  fputs("]}", out);
}

static void text_damping(FILE *out, const vs_run *r) {
  const vs_case *c = vs_run_case(r);
  const vs_modal *md = vs_run_modal(r);
  double alpha, beta;
  vs_run_rayleigh(r, &alpha, &beta);
  const vs_damping_model dm = (vs_damping_model)c->damping_model;
  fprintf(out, "damping  %s", vs_damping_model_name(dm));
  if (dm == VS_DAMPING_JOINT)
    fprintf(out, ": joint dashpots at %g of each joint's own critical damping", c->damping);
  else if (dm == VS_DAMPING_RAYLEIGH)
    fprintf(out, ": %g at the two lowest modes, alpha = %.4g 1/s, beta = %.4g s", c->damping,
            alpha, beta);
  else if (dm == VS_DAMPING_IMPACT)
    fprintf(out, ": plastic impacts where opened joints close (Housner), %ld in this run; no "
                 "viscous damping, so 0 for every mode in steady contact",
            vs_run_dynamic_totals(r)->impacts);
  fputc('\n', out);
  if (md->n_modes == 0) return;
  fputs("modes    under self-weight, frequency (damping ratio):", out);
  for (int i = 0; i < md->n_modes; i++)
    fprintf(out, " %.2f Hz (%.3g %%)", md->freq_hz[i], 100.0 * md->zeta[i]);
  fputc('\n', out);
}

/* --- mortar (joints.tensile_MPa, cohesion_MPa > 0): nothing of it in a dry run's reports --- */

static int is_mortared(const vs_run *r) {
  const vs_joints_def *j = &vs_run_def_of(r)->joints;
  return j->ft > 0.0 || j->c > 0.0;
}

/* ,"first_crack":{delta_mm, joint, side} (null: no joint cracked), for a mortared run; on a
 * load path (delta the held support displacement) with the load factor where it cracked. */
static void json_first_crack(FILE *out, const vs_run *r) {
  if (!is_mortared(r)) return;
  const vs_run_event *f = vs_run_first_crack(r);
  fputs(",\"first_crack\":", out);
  if (f == NULL) {
    fputs("null", out);
    return;
  }
  jnum(out, "{\"delta_mm\":", f->delta / VS_MM, 10);
  fprintf(out, ",\"joint\":%d,\"side\":\"%c\"", f->joint, f->side);
  if (isfinite(f->load_factor)) jnum(out, ",\"load_factor\":", f->load_factor, 10);
  fputc('}', out);
}

/* ,"mechanism_turning":{time_s, sides, mode_from, hinges: [{label, side, joints, share, open,
 * closing}]} for a mortared run (null: no collapse in motion); docs/mortar.md. */
static void json_active(FILE *out, const vs_run *r) {
  if (!is_mortared(r)) return;
  const int n = vs_run_mechanism_count(r);
  fputs(",\"mechanism_turning\":", out);
  if (n == 0) {
    fputs("null", out);
    return;
  }
  jnum(out, "{\"time_s\":", vs_run_mechanism_time(r), 10);
  fputs(",\"sides\":", out);
  vs_json_string(out, vs_run_pattern_mechanism(r));
  fprintf(out, ",\"mode_from\":\"%s\",\"hinges\":[",
          vs_run_mode_from_mechanism(r) ? "turning" : "onset");
  for (int i = 0; i < n; i++) {
    const vs_active_hinge *a = vs_run_mechanism_hinge(r, i);
    fputs(i ? ",{\"label\":" : "{\"label\":", out);
    if (a->label) fprintf(out, "\"%c\"", a->label);
    else fputs("null", out);
    fprintf(out, ",\"side\":\"%c\",\"joints\":[", a->side);
    for (int j = a->first; j <= a->last; j++) fprintf(out, j > a->first ? ",%d" : "%d", j);
    jnum(out, "],\"share\":", a->share, 6);
    fprintf(out, ",\"open\":%s,\"closing\":%s}", a->open ? "true" : "false",
            a->closing ? "true" : "false");
  }
  fputs("]}", out);
}

static void text_mortar(FILE *out, const vs_run *r) {
  if (!is_mortared(r)) return;
  const vs_case *c = vs_run_case(r);
  fprintf(out, "\nmortar   f_t = %g MPa, c = %g MPa, G_f = %g N/mm, G_c = %g N/mm\n",
          c->tensile_MPa, c->cohesion_MPa, c->gf_N_mm, c->gc_N_mm);
  const vs_run_event *f = vs_run_first_crack(r);
  if (f != NULL)
    fprintf(out, "         first crack: joint %d at the %s at %.4f mm (tensile stress f_t)",
            f->joint, f->side == 'I' ? "intrados" : "extrados", f->delta / VS_MM);
  if (f != NULL && isfinite(f->load_factor))
    fprintf(out, ", load factor %.6g", f->load_factor);
  if (f != NULL) fputc('\n', out);
  else
    fputs("         no joint cracked\n", out);
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++)
    n += vs_run_event_get(r, i)->kind == VS_EVENT_CRACK_INITIATED;
  fprintf(out, "         %d joint edges reached f_t; energy dissipated by cracking %.6g J\n", n,
          vs_model_cracking_energy(vs_run_model(r)));
  const vs_dyn_result *d = vs_run_dynamic_totals(r);
  if (d->ring_settles > 0)
    fprintf(out, "         %ld snap%s ended ringing (dynamic.ring_periods), left with %.6g J of "
            "vibration\n", d->ring_settles, d->ring_settles > 1 ? "s" : "", d->ring_energy);
}

/* ,"damage_envelope":{joints, max_vertices, merges}, for a mortared run: how many joints the
 * mortar's damage reached (past f_t somewhere), the most vertices a joint's envelope held, and
 * how often an envelope passed VS_JOINT_ENV_MAX vertices and was merged into its chord (0: the
 * damage was kept exactly). */
static void json_damage_envelope(FILE *out, const vs_run *r) {
  if (!is_mortared(r)) return;
  const vs_model *m = vs_run_model(r);
  int joints = 0, vmax = 0, merges = 0;
  for (int k = 0; k < vs_model_geometry(m)->n_joints; k++) {
    const vs_joint_law *l = vs_model_joint_law(m, k);
    joints += l->env_n > 0;
    vmax = l->env_n > vmax ? l->env_n : vmax;
    merges += l->env_merged;
  }
  fprintf(out, ",\"damage_envelope\":{\"joints\":%d,\"max_vertices\":%d,\"merges\":%d}", joints,
          vmax, merges);
}

static void json_tail(FILE *out, const vs_run *r) {
  const vs_case *c = vs_run_case(r);
  const vs_dyn_result *d = vs_run_dynamic_totals(r);
  json_first_crack(out, r);
  json_active(out, r);
  json_damage_envelope(out, r);
  jnum(out, ",\"energy\":{\"balance_error_rel\":", d->balance_error_rel, 6);
  jnum(out, ",\"balance_error_fall_rel\":", d->balance_error_fall, 6);
  jnum(out, ",\"max_kinetic_J\":", d->max_kinetic, 6);
  if (is_mortared(r)) {
    jnum(out, ",\"cracking_J\":", vs_model_cracking_energy(vs_run_model(r)), 10);
    fprintf(out, ",\"ringing_snaps\":%ld", d->ring_settles);
    jnum(out, ",\"ringing_J\":", d->ring_energy, 10);
  }
  jnum(out, "},\"parameters\":{\"open_mm\":", c->open_mm, 10);
  fprintf(out, ",\"migrate_joints\":%d", c->migrate_joints);
  jnum(out, ",\"limit_tol_mm\":", c->limit_tol_mm, 10);
  jnum(out, ",\"newton_tol\":", c->newton_tol, 10);
  jnum(out, ",\"ks_ratio\":", c->ks_ratio, 10);
  jnum(out, ",\"friction\":", c->friction, 10);
  fprintf(out, ",\"voussoirs\":%d", c->voussoirs);
  jnum(out, ",\"damping\":", c->damping, 10);
  jnum(out, ",\"rate_mm_s\":", c->rate_mm_s, 10);
  jnum(out, ",\"rtol\":", c->rtol, 10);
  jnum(out, ",\"atol_mm\":", c->atol_mm, 10);
  const vs_path_result *p = vs_run_path_totals(r);
  fprintf(out,
          "},\"stats\":{\"steps\":%ld,\"rejected_steps\":%ld,\"located_equilibria\":%ld,"
          "\"newton_iterations\":%ld,\"jacobian_evaluations\":%ld",
          p->steps, p->rejected, p->located, p->newton_iterations, p->jacobian_evals);
  jnum(out, ",\"max_residual\":", p->max_residual, 3);
  fprintf(out,
          ",\"floor_limited\":%ld,\"dynamic_steps\":%ld,\"dynamic_newton_iterations\":%ld,"
          "\"root_events\":%ld",
          p->floor_limited, d->steps, d->newton_iterations, d->root_events);
  jnum(out, ",\"constraint_drift_m\":", d->max_drift, 3);
  const vs_fall_result *fr = vs_run_fall(r);
  fputs(",\"fall\":", out);
  if (fr != NULL) {
    fprintf(out, "{\"scheme\":\"rigid\",\"solver\":\"%s\",\"steps\":%ld,\"chain_steps\":%ld,"
                 "\"solves\":%ld,\"sweeps\":%ld,\"max_sweeps\":%d,\"capped_steps\":%ld,"
                 "\"calm_steps\":%ld,\"slow_steps\":%ld",
            vs_fall_solver_name(fr->solver), fr->steps, fr->chain_steps, fr->solves, fr->sweeps,
            fr->cap, fr->unconverged, fr->calm_steps, fr->slow_steps);
    jnum(out, ",\"step_s\":", fr->step, 10);
    jnum(out, ",\"slow_step_s\":", fr->slow_step, 10);
    jnum(out, ",\"last_change_m_s\":", fr->residual, 3);
    jnum(out, ",\"duration_s\":", fr->t_end - vs_run_collapse(r)->t_criterion, 6);
    fprintf(out, ",\"at_rest\":%s", fr->at_rest ? "true" : "false");
    jnum(out, ",\"penetration_max_m\":", fr->max_penetration, 3);
    jnum(out, ",\"overlap_max_m\":", fr->max_overlap, 3);
    jnum(out, ",\"joint_overlap_max_m\":", fr->max_joint_overlap, 3);
    jnum(out, ",\"released_J\":", fr->released, 6);
    jnum(out, ",\"recovered_J\":", fr->recovered, 6);
    jnum(out, ",\"balance_error_rel\":", fr->balance_error_rel, 6);
    jnum(out, ",\"wall_s\":", fr->wall_s, 6);
    jnum(out, ",\"cpu_s\":", fr->cpu_s, 6);
    fputc('}', out);
  } else {
    fputs("null", out);
  }
  fputs(",\"dae\":", out);
  if (d->dae_index > 0) /* null when no dynamic phase ran */
    fprintf(out, "{\"differential\":%d,\"algebraic\":%d,\"index\":%d}", d->dae_differential,
            d->dae_algebraic, d->dae_index);
  else
    fputs("null", out);
  jnum(out, ",\"wall_s\":", vs_run_wall_s(r), 6);
  fputs("}}\n", out);
}

void vs_report_json(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                    const char *case_path) {
  const vs_case *c = vs_run_case(r);
  const vs_hinges *h = vs_run_hinges(r);
  fprintf(out, "{\"program\":\"voussoir\",\"version\":\"%s\",\"case\":", VS_VERSION);
  vs_json_string(out, case_path ? case_path : "");
  fprintf(out, ",\"status\":\"%s\",\"error\":", end_name(r, status));
  if (status != VS_OK && err != NULL) vs_json_string(out, err->msg);
  else fputs("null", out);
  jnum(out, ",\"alpha_deg\":", c->alpha_deg, 17);
  jnum(out, ",\"kn_N_mm3\":", c->kn_N_mm3, 17);
  jnum(out, ",\"span_mm\":", run_span_mm(r), 17);
  fprintf(out, ",\"shape\":\"%s\"", c->shape >= 0 && c->shape < VS_SHAPE_COUNT ? SHAPES[c->shape] : "?");
  jnum(out, ",\"rise_mm\":", vs_run_geometry(r)->rise / VS_MM, 17);
  fprintf(out, ",\"mode_of_run\":\"%s\"",
          c->full ? "dynamic" : c->follow ? "quasistatic+dynamic" : "quasistatic");
  fprintf(out, ",\"supports\":{\"left\":\"%s\",\"right\":\"%s\"}", support_kind(c->left_kind),
          support_kind(c->right_kind));
  fputs(",\"first_limit\":", out);
  json_first_limit(out, r);
  fputs(",\"collapse\":", out);
  json_collapse(out, r);
  fputs(",\"limit_points\":", out);
  json_limits(out, r);
  const char *mode = vs_run_mode(r);
  fputs(",\"mode\":", out);
  if (mode) fprintf(out, "\"%s\"", mode);
  else fputs("null", out);
  fputs(",\"hinge_sides_initial\":", out);
  vs_json_string(out, vs_run_pattern_initial(r));
  fputs(",\"hinge_sides_collapse\":", out);
  vs_json_string(out, vs_run_pattern_collapse(r));
  jnum(out, ",\"last_delta_mm\":", vs_run_delta(r) / VS_MM, 10);
  jnum(out, ",\"last_time_s\":", vs_run_time(r), 10);
  fputs(",\"reactions_last\":", out);
  json_reactions(out, vs_run_reactions(r));
  fputs(",\"hinges\":[", out); /* every one, however many */
  for (int i = 0; i < vs_run_hinge_count(r); i++) json_hinge(out, r, vs_run_hinge(r, i), i == 0, 1);
  fputc(']', out);
  fprintf(out, ",\"hinges_in_fall\":%d", vs_hinges_count(h) - vs_run_hinge_count(r));
  json_slip_events(out, r);
  vs_report_piers_json(out, r);
  json_damping(out, r);
  if (vs_run_load(r)->done) vs_report_load_json(out, r);
  json_tail(out, r);
}

/* One support's motion as the case gives it. */
static void text_motion(FILE *out, const vs_case *c, int right) {
  const vs_case_path *p = right ? &c->right_path : &c->left_path;
  const double rate = right ? c->rate_mm_s : c->left_rate_mm_s;
  fprintf(out, "%s ", right ? "right" : "left");
  if (p->n > 0) {
    fprintf(out, "on a path (outward, down):");
    for (int i = 0; i < p->n; i++) {
      fprintf(out, "%s at %g s %g, %g mm", i ? "," : "", p->t_s[i], p->dx_mm[i], p->dz_mm[i]);
      if (p->rot_deg[i] != 0.0) fprintf(out, " turned %g deg", p->rot_deg[i]);
    }
  } else if (rate > 0.0) {
    fprintf(out, "moved at alpha = %g deg from the vertical (90 outward), %g mm/s",
            right ? c->alpha_deg : c->left_alpha_deg, rate);
  } else {
    fprintf(out, "in place");
  }
}

/* The header's support lines when more than the right support moves. */
static void text_motions(FILE *out, const vs_case *c) {
  fprintf(out, "support  ");
  text_motion(out, c, 0);
  fprintf(out, ";\n         ");
  text_motion(out, c, 1);
  fprintf(out, ";\n         delta = %g mm/s x t (left %s", vs_case_loading_rate_mm_s(c),
          support_kind(c->left_kind));
}

/* The arch line of a shape other than the circle of radius and embrace. */
static void text_shape(FILE *out, const vs_case *c, const vs_geometry *g) {
  char q[1100];
  fprintf(out, "arch     %s", c->shape >= 0 && c->shape < VS_SHAPE_COUNT ? SHAPES[c->shape] : "?");
  if (c->shape == VS_SHAPE_FILE) {
    fprintf(out, " %s, %d blocks, %d joints\n", vs_quote(c->blocks_file, q, sizeof q),
            g->n_blocks, g->n_joints);
    return;
  }
  if (c->shape == VS_SHAPE_POINTED) fprintf(out, ", eccentricity %g", c->eccentricity);
  if (c->shape == VS_SHAPE_BASKET) fprintf(out, ", haunch arcs %g deg", c->haunch_deg);
  fprintf(out, ", t = %g mm", c->thickness_mm);
  if (c->thickness_springing_mm > 0.0) fprintf(out, " (%g mm at the springings)",
                                               c->thickness_springing_mm);
  fprintf(out, ", %d voussoirs", c->voussoirs);
  if (c->keystone_mm > 0.0) fprintf(out, " (keystone %g mm)", c->keystone_mm);
  if (c->n_joint_positions > 0) fputs(" (joints at given positions)", out);
  fprintf(out, ", %s joints, b = %g mm\n", c->joints == VS_JOINTS_VERTICAL ? "vertical" : "normal",
          c->depth_mm);
}

static void text_header(FILE *out, const vs_run *r, const char *case_path) {
  const vs_case *c = vs_run_case(r);
  const vs_geometry *g = vs_run_geometry(r);
  char q[1024]; /* the case's path, quoted: it may hold anything */
  fprintf(out, "voussoir %s  case %s\n", VS_VERSION,
          case_path ? vs_quote(case_path, q, sizeof q) : "(defaults)");
  if (c->shape == VS_SHAPE_CIRCULAR && c->span_mm == 0.0)
    fprintf(out, "arch     R = %g mm, t = %g mm, embrace %g deg, %d voussoirs, b = %g mm\n",
            c->radius_mm, c->thickness_mm, c->embrace_deg, c->voussoirs, c->depth_mm);
  else
    text_shape(out, c, g);
  fprintf(out, "         span L = %.2f mm, rise %.2f mm, weight %.3f N\n", g->span / VS_MM,
          g->rise / VS_MM, vs_geometry_weight(g));
  fprintf(out, "joints   k_n = %g N/mm^3, k_s = %g k_n, mu = %g\n", c->kn_N_mm3, c->ks_ratio,
          c->friction);
  vs_report_piers_header(out, r);
  if (!right_alone(c)) text_motions(out, c);
  else
    fprintf(out, "support  right support moved at alpha = %g deg from the vertical, %g mm/s (left %s",
            c->alpha_deg, c->rate_mm_s, support_kind(c->left_kind));
  if (c->left_kind != VS_SUPPORT_FIXED || c->right_kind != VS_SUPPORT_FIXED)
    fprintf(out, ", right %s;\n         pinned: free to rotate about the centre of its springing face",
            support_kind(c->right_kind));
  fprintf(out, ")\n");
  fprintf(out,
          "criteria hinge: edge opening > %g mm, migration within %d joints;\n"
          "         limit point bracketed to %g mm; Newton tolerance %g x voussoir weight;\n"
          "         at rest below %g x the kinetic energy of the arch at the support rate for %g s;\n",
          c->open_mm, c->migrate_joints, c->limit_tol_mm, c->newton_tol, c->rest_factor, c->rest_s);
  if (is_mortared(r) && c->ring_periods > 0.0) /* dynamic.ring_periods: mortar only */
    fprintf(out, "         with mortar, a snap also over once rung out for %g period%s of the "
            "lowest mode;\n", c->ring_periods, c->ring_periods == 1.0 ? "" : "s");
  fprintf(out, "         collapsing beyond a kinetic energy of %g x weight x thickness\n\n",
          c->collapse_ke);
}

static void text_hinge_row(FILE *out, const vs_run *r, const vs_hinge *hg, int onset_name) {
  const vs_case *c = vs_run_case(r);
  char a[96];
  vs_hinge_name(hg, onset_name, a, sizeof a);
  double dz, dx;
  components_pct(r, hg->delta_onset, &dz, &dx);
  const char *nth = hg->order == 4 ? " (4th hinge)" : hg->order == 5 ? " (5th hinge)" : "";
  fprintf(out, "  %c  %-16s %9.3f mm %9.2f s  %6.3f %%  %6.3f %%%s\n", hg->label, a,
          hg->delta_onset / VS_MM, hg->delta_onset / (vs_case_loading_rate_mm_s(c) * VS_MM), dz,
          dx, nth);
}

/* The first limit point and the evidence that it is one. */
static void text_first_limit(FILE *out, const vs_run *r) {
  const vs_path_result *p = vs_run_path(r);
  double dz, dx;
  if (p->end == VS_PATH_LIMIT_POINT && vs_run_limit_count(r) > 0) {
    components_pct(r, p->delta_limit, &dz, &dx);
    fprintf(out, "first limit point  delta = %.4f mm   dz/L = %.3f %%   dx/L = %.3f %%\n",
            p->delta_limit / VS_MM, dz, dx);
    if (p->evidence.slip_onset > 0)
      fprintf(out,
              "  confirmed: the onset of slip; before %.4f mm joint %d%s reaches its Coulomb "
              "limit |T| = mu N,\n  and with it sliding the tangent has det sign %+d (smallest "
              "eigenvalue %.3g N/m; %.3g N/m after self-weight)\n",
              p->delta_fail / VS_MM, p->evidence.slip_joint + 1,
              p->evidence.slip_onset > 1 ? " and others" : "", p->evidence.det_sign,
              p->evidence.lambda_last, p->evidence.lambda_start);
    else
      fprintf(out,
              "  confirmed: no equilibrium at %.4f mm; smallest tangent eigenvalue %.3g N/m "
              "(%.3g N/m after self-weight),\n  extrapolated to zero at %.4f mm; tangent "
              "positive definite on the path (Cholesky of its symmetric part)\n",
              p->delta_fail / VS_MM, p->evidence.lambda_last, p->evidence.lambda_start,
              p->evidence.delta_extrap / VS_MM);
  }
}

/* Every limit point: snap (where it settled), collapse, or not followed. */
static void text_limits(FILE *out, const vs_run *r) {
  if (vs_run_limit_count(r) > 0) {
    fprintf(out, "\nlimit points\n");
    for (int i = 0; i < vs_run_limit_count(r); i++) {
      const vs_limit_record *l = vs_run_limit(r, i);
      fprintf(out, "  %9.4f mm  %-8s", l->delta / VS_MM,
              l->collapse ? "collapse" : isfinite(l->delta_settled) ? "snap" : "limit");
      if (isfinite(l->delta_settled))
        fprintf(out, " settled at %.4f mm: %s  ->  %s", l->delta_settled / VS_MM, l->hinges_before,
                l->hinges_after);
      else if (!l->collapse)
        fprintf(out, " (not followed)");
      fputc('\n', out);
    }
  }
}

/* Each support's displacement and the relative one at delta (a case that moves more than the
 * right support alone). */
static void text_supports_at(FILE *out, const vs_run *r, double delta) {
  double o[2][3], dx, dz;
  support_outward(r, 0, delta, o[0]);
  support_outward(r, 1, delta, o[1]);
  support_relative(r, delta, &dx, &dz);
  fprintf(out, "  supports (outward, down):");
  for (int s = 0; s < 2; s++) {
    fprintf(out, "%s dx = %.4f mm, dz = %.4f mm", s ? "; right" : " left", o[s][0], o[s][1]);
    if (isfinite(o[s][2]) && o[s][2] != 0.0) fprintf(out, ", turned %.4f deg", o[s][2]);
  }
  fprintf(out, ";\n  relative (the right one's from the left one's): dx = %.4f mm spreading, dz = "
               "%.4f mm settlement\n", dx, dz);
}

/* The collapse's mechanism: rotational, sliding or mixed, and its slips. */
static void text_mechanism(FILE *out, const vs_collapse_record *col) {
  fprintf(out, "  mechanism %s", col->mechanism);
  for (int i = 0; i < col->n_slips; i++)
    fprintf(out, "%s joint %d (toward the %s, %.3f mm)", i ? "," : ": slips at", col->slips[i].joint,
            slip_toward(col->slips[i].side), col->slips[i].slip / VS_MM);
  fputc('\n', out);
}

/* Every slip event: joint, direction, where. */
static void text_slips(FILE *out, const vs_run *r) {
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++) {
    const vs_run_event *e = vs_run_event_get(r, i);
    if (e->kind != VS_EVENT_JOINT_SLIPPED) continue;
    if (n++ == 0)
      fprintf(out, "\nslips (a joint began to slide, or to slide the other way; toward: the edge "
                   "its voussoir slides toward)\n");
    fprintf(out, "  joint %-3d toward the %-8s at %9.4f mm (%s)\n", e->joint, slip_toward(e->side),
            e->delta / VS_MM, e->phase == VS_PHASE_QUASISTATIC ? "on the path" : "in the motion");
  }
}

/* "9-10-I": an active hinge's joints and side, into buf. */
static void active_name(const vs_active_hinge *a, char *buf, size_t size) {
  const vs_hinge h = {.side = a->side, .first = a->first, .last = a->last};
  vs_hinge_name(&h, 0, buf, size);
}

/* A mortared arch's mechanism at the collapse criterion: the hinges turning, each with the
 * label of the tracked hinge it is and its share of the fastest one's rate. */
static void text_active(FILE *out, const vs_run *r) {
  const int n = vs_run_mechanism_count(r);
  if (n == 0) return;
  fprintf(out, "  turning at the criterion (t = %.2f s; share of the fastest hinge's rotation rate):",
          vs_run_mechanism_time(r));
  for (int i = 0; i < n; i++) {
    const vs_active_hinge *a = vs_run_mechanism_hinge(r, i);
    char name[96];
    active_name(a, name, sizeof name);
    fprintf(out, " %c:%s %.2f%s", a->label ? a->label : '-', name, a->share,
            a->closing ? " closing" : "");
  }
  fprintf(out, ";  sides %s\n", vs_run_pattern_mechanism(r));
}

/* The collapse (delta_u, its components, mode, reactions, hinges at its onset), or how far the
 * support moved without one. */
static void text_collapse(FILE *out, const vs_run *r, vs_status status) {
  const vs_case *c = vs_run_case(r);
  const vs_collapse_record *col = vs_run_collapse(r);
  double dz, dx;
  if (col->found) {
    components_pct(r, col->delta, &dz, &dx);
    fprintf(out, "\nCOLLAPSE  delta_u = %.4f mm   dz/L = %.3f %%   dx/L = %.3f %%   at t = %.2f s\n",
            col->delta / VS_MM, dz, dx, col->t);
    if (!right_alone(c)) text_supports_at(out, r, col->delta);
    if (vs_run_path_totals(r)->end == VS_PATH_SLIDING)
      fprintf(out, "  a sliding mechanism that the support drives: from where its joints all slid, "
                   "the force on the support stays put (seen at %.4f mm); no motion follows\n",
              col->delta_detected / VS_MM);
    else
      fprintf(out, "  departure from the last stable equilibrium (%s); detected (kinetic energy "
                   "past the collapse threshold) at %.4f mm, t = %.2f s\n",
              c->full ? "the kinetic energy's last rise through the rest level"
                      : "the collapsing limit point",
              col->delta_detected / VS_MM, col->t_criterion);
    const char *mode = vs_run_mode(r);
    fprintf(out, "  hinges at collapse (left to right): %s;  first three: %s;  mode %s%s\n",
            vs_run_pattern_collapse(r)[0] ? vs_run_pattern_collapse(r) : "none",
            vs_run_pattern_initial(r)[0] ? vs_run_pattern_initial(r) : "none",
            mode ? mode : "unclassified",
            vs_run_mode_from_mechanism(r) ? " (from the hinges turning at the criterion)" : "");
    text_active(out, r);
    text_mechanism(out, col);
    const double *rc = col->reactions_limit;
    if (isfinite(rc[0]))
      fprintf(out, "  reactions on the arch at the collapsing limit point: left Fx %.3f N, Fz %.3f N, "
                   "M %.4f N m; right Fx %.3f N, Fz %.3f N, M %.4f N m\n",
              rc[0], rc[1], rc[2], rc[3], rc[4], rc[5]);
    fprintf(out, "  label  joints          onset delta   onset time    dz/L     dx/L\n");
    for (int i = 0; i < col->n_hinges; i++) text_hinge_row(out, r, &col->hinges[i], 0);
    if (col->n_hinges == 0) fprintf(out, "  (none open by hinges.open_mm)\n");
  } else if (status == VS_OK && (c->follow || c->full)) {
    components_pct(r, vs_run_delta(r), &dz, &dx);
    fprintf(out, "\nno collapse up to delta = %.4f mm (dz/L = %.3f %%, dx/L = %.3f %%)\n",
            vs_run_delta(r) / VS_MM, dz, dx);
    if (!right_alone(c)) text_supports_at(out, r, vs_run_delta(r));
  }
}

/* Every hinge in order of appearance. */
static void text_hinges(FILE *out, const vs_run *r) {
  const vs_hinges *h = vs_run_hinges(r);
  fprintf(out, "\nhinges in order of appearance (side = edge that stays in contact; joints at onset)\n");
  fprintf(out, "  label  joints          onset delta   onset time    dz/L     dx/L\n");
  int spread = 0;
  for (int i = 0; i < vs_run_hinge_count(r); i++) {
    const vs_hinge *hg = vs_run_hinge(r, i);
    text_hinge_row(out, r, hg, 1);
    spread |= (hg->last > hg->first) || (hg->onset_last > hg->onset_first);
  }
  if (vs_hinges_count(h) == 0) fprintf(out, "  (none)\n");
  if (vs_hinges_count(h) > vs_run_hinge_count(r))
    fprintf(out, "  (%d more opened as the arch fell; see /events in the record)\n",
            vs_hinges_count(h) - vs_run_hinge_count(r));
  if (spread)
    fprintf(out, "  a name like 44-45-46-I is one hinge spread over consecutive joints that are "
                 "each slightly open\n");
}

/* Solver statistics, the fall, the wall time. */
static void text_stats(FILE *out, const vs_run *r, vs_status status) {
  const vs_path_result *t = vs_run_path_totals(r);
  const vs_dyn_result *d = vs_run_dynamic_totals(r);
  fprintf(out, "\nstats    quasi-static: %ld equilibria (%ld rejected increments) + %ld locating hinge "
               "onsets, %ld Newton iterations, largest residual %.2g x voussoir weight\n",
          t->steps, t->rejected, t->located, t->newton_iterations, t->max_residual);
  const vs_fall_result *fr = vs_run_fall(r);
  if (d->steps > 0) {
    fprintf(out, "         dynamic: %ld IDA steps, %ld Newton iterations, %ld root events, "
                 "energy balance %.2g (relative",
            d->steps, d->newton_iterations, d->root_events, d->balance_error_rel);
    if (fr == NULL && isfinite(vs_run_ground(r))) /* the penalty fall: IDA's too */
      fprintf(out, "; %.2g in the fall", d->balance_error_fall);
    fprintf(out, ")\n         DAE of index %d: %d differential, %d algebraic unknowns; "
                 "constraint drift %.2g m\n",
            d->dae_index, d->dae_differential, d->dae_algebraic, d->max_drift);
  }
  if (fr != NULL)
    fprintf(out, "         fall: rigid blocks, impulsive contacts, steps of %g ms (%g ms while "
                 "slow): %ld steps (%ld slow; %ld of the arch in the air solved as a chain, %ld "
                 "solves; %ld near rest, to a tenth of the tolerance), %ld Gauss-Seidel "
                 "sweeps%s, %ld steps stopped at their cap (%d sweeps, %d near rest; last change "
                 "up to %.3g mm/s); energy balance %.2g; joint faces overlapping up to %.3g mm\n",
            1e3 * fr->step, 1e3 * fr->slow_step, fr->steps, fr->slow_steps, fr->chain_steps,
            fr->solves, fr->calm_steps, fr->sweeps,
            fr->solver == VS_FALL_NNCG ? " with NNCG steps" : "",
            fr->unconverged, fr->cap, fr->calm_cap, fr->residual / VS_MM,
            fr->balance_error_rel, fr->max_joint_overlap / VS_MM);
  if (isfinite(vs_run_ground(r)))
    fprintf(out, "         fall: onto the ground at z = %.3f mm, %s; deepest vertex %.3g mm below "
                 "it at the end (%.3g mm during the fall), %.3g mm inside another block or a pier "
                 "during the fall; %.3f s wall\n",
            vs_run_ground(r) / VS_MM, d->fall_at_rest ? "the debris at rest"
            : isfinite(d->fall_failed_t) ? "stopped early (below)"
            : status != VS_OK            ? "still moving when the run stopped"
                                         : "still moving at fall_s",
            vs_run_penetration(r) / VS_MM, d->max_penetration / VS_MM, d->max_overlap / VS_MM,
            d->fall_wall_s);
  if (isfinite(d->fall_failed_t))
    fprintf(out, "         fall: IDA failed at t = %.6g s and the fall was not followed further "
                 "(the collapse above stands): %s\n", d->fall_failed_t, d->fall_failure);
  fprintf(out, "         wall time %.3f s\n", vs_run_wall_s(r));
}

void vs_report_text(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                    const char *case_path) {
  text_header(out, r, case_path);
  text_damping(out, r);
  fputc('\n', out);
  if (vs_run_load(r)->done) {
    vs_report_load_text(out, r);
    text_limits(out, r);
  } else {
    text_first_limit(out, r);
    text_limits(out, r);
    text_collapse(out, r, status);
  }
  /* a stop is not a failure: the results so far stand, as far as they go */
  if (status == VS_ERR_WALL_TIME || status == VS_ERR_STOPPED)
    fprintf(out, "\n%s at delta = %.4f mm, t = %.6g s (the results above are the run's so far)\n",
            err != NULL ? err->msg : vs_strerror(status), vs_run_delta(r) / VS_MM, vs_run_time(r));
  else if (status != VS_OK)
    fprintf(out, "\nFAILED at delta = %.4f mm: %s\n", vs_run_delta(r) / VS_MM,
            err != NULL ? err->msg : vs_strerror(status));
  text_hinges(out, r);
  text_mortar(out, r);
  text_slips(out, r);
  vs_report_piers_text(out, r);
  text_stats(out, r, status);
}
