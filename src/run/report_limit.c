/* The reports of a limit analysis (analysis.type = limit: limit.h): a readable summary and one
 * JSON object, in the units engineers use (mm, N). */
#include "voussoir/report.h"
#include "report_load.h"

#include <math.h>
#include <string.h>

#include "quote.h"
#include "voussoir/units.h"
#include "voussoir/version.h"

static const char *const OUTCOMES[] = {"optimal", "infeasible", "unbounded"};
_Static_assert(sizeof OUTCOMES / sizeof OUTCOMES[0] == VS_LIMIT_OUTCOME_COUNT,
               "a name for every vs_limit_outcome");

static const char *support_name(int kind) { return kind == VS_SUPPORT_PINNED ? "pinned" : "fixed"; }

/* ,"key":x with x finite, else null */
static void jnum(FILE *out, const char *sep_key, double x) {
  fputs(sep_key, out);
  if (isfinite(x)) fprintf(out, "%.10g", x);
  else fputs("null", out);
}

/* Joint k (0-based) of n as reported, with side (I, E; O open at both ends; 0 none): "9-I" on
 * the ring; a pier's joint (courses > 0: the last 2 x courses joints, the left pier's from its
 * base up, then the right's) as the run's pier events name it, "pier1-base-inner",
 * "pier2-course3-outer" (the joint under course 3; inner: the edge on the face under the
 * springing). */
static void joint_token(int courses, int n, int k, char side, char *buf, size_t size) {
  const int first = n - 2 * courses, pier = courses > 0 && k >= first;
  char name[48];
  if (!pier) {
    snprintf(name, sizeof name, "%d", k + 1);
  } else {
    const int p = (k - first) / courses + 1, c = (k - first) % courses + 1;
    if (c == 1) snprintf(name, sizeof name, "pier%d-base", p);
    else snprintf(name, sizeof name, "pier%d-course%d", p, c);
  }
  if (side == 'I' || side == 'E')
    snprintf(buf, size, "%s-%s", name, !pier ? (side == 'I' ? "I" : "E")
                                             : (side == 'I' ? "inner" : "outer"));
  else if (side == 'O') snprintf(buf, size, "%s-open", name);
  else snprintf(buf, size, "%s", name);
}

/* Which joints `which` selects (vs_limit_list's letters): joint k's side, '-' for a joint
 * without one (sliding, at the friction limit), 0 for a joint not selected. */
static char selected(const vs_limit_solution *s, char which, int k) {
  if (which == 'h' && s->hinge != NULL) return s->hinge[k] == 'S' ? 0 : s->hinge[k];
  if (which == 'x' && s->slip != NULL) return s->slip[k] != 0.0 ? '-' : 0;
  if (which == 't') return s->touch[k] == 'I' || s->touch[k] == 'E' ? s->touch[k] : 0;
  if (which == 'f') return s->friction[k] ? '-' : 0;
  return 0;
}

/* The case's pier courses, 0 without piers. */
static int courses_of(const vs_case *c) { return c->pier_height_mm > 0.0 ? c->pier_courses : 0; }

/* The joints of a solution that `which` selects as a JSON array of names, every one of them. */
static void json_joints(FILE *out, const vs_limit_solution *s, char which, int courses) {
  fputc('[', out);
  int first = 1;
  for (int k = 0; k < s->n_joints; k++) {
    const char side = selected(s, which, k);
    if (side == 0) continue;
    char name[64];
    joint_token(courses, s->n_joints, k, side, name, sizeof name);
    fprintf(out, "%s\"%s\"", first ? "" : ",", name);
    first = 0;
  }
  fputc(']', out);
}

/* One solution: its outcome, its value, the thrust line (where each joint's resultant crosses
 * it, as a fraction of the joint from the intrados) and what touches; the mechanism if any. */
static void json_solution(FILE *out, const vs_limit_solution *s, int courses) {
  if (s->touch == NULL) {
    fprintf(out, "{\"outcome\":\"%s\"}",
            s->outcome >= 0 && s->outcome < VS_LIMIT_OUTCOME_COUNT ? OUTCOMES[s->outcome] : "?");
    return;
  }
  fprintf(out, "{\"outcome\":\"%s\"", OUTCOMES[s->outcome]);
  jnum(out, ",\"value\":", s->value);
  jnum(out, ",\"thrust_N\":", s->thrust);
  fputs(",\"touches\":", out);
  json_joints(out, s, 't', courses);
  fputs(",\"at_friction_limit\":", out);
  json_joints(out, s, 'f', courses);
  if (s->hinge != NULL) {
    fputs(",\"mechanism\":", out);
    json_joints(out, s, 'h', courses);
    fputs(",\"sliding\":", out);
    json_joints(out, s, 'x', courses);
  }
  fputs(",\"thrust_line_eta\":[", out);
  for (int k = 0; k < s->n_joints; k++) {
    if (k) fputc(',', out);
    if (isfinite(s->eta[k])) fprintf(out, "%.8g", s->eta[k]);
    else fputs("null", out);
  }
  fprintf(out, "],\"iterations\":%d", s->iterations);
  jnum(out, ",\"cpu_s\":", s->cpu_s);
  fputc('}', out);
}

static double optimum(const vs_limit_solution *s) {
  return s->outcome == VS_LIMIT_OPTIMAL ? s->value : NAN;
}

void vs_report_limit_json(FILE *out, const vs_case *c, const vs_limit_analysis *a,
                          vs_status status, const vs_error *err, const char *case_path) {
  fprintf(out, "{\"program\":\"voussoir\",\"version\":\"%s\",\"case\":", VS_VERSION);
  vs_json_string(out, case_path ? case_path : "");
  fprintf(out, ",\"analysis\":\"limit\",\"status\":\"%s\",\"error\":",
          status == VS_OK ? "ok" : "failed");
  if (status != VS_OK && err != NULL) vs_json_string(out, err->msg);
  else fputs("null", out);
  jnum(out, ",\"span_mm\":", vs_case_span_mm(c));
  jnum(out, ",\"friction\":", c->friction);
  fprintf(out, ",\"supports\":{\"left\":\"%s\",\"right\":\"%s\"}", support_name(c->left_kind),
          support_name(c->right_kind));
  fprintf(out, ",\"load\":{\"kind\":\"%s\"", vs_load_kind_name((vs_load_kind)c->kind));
  jnum(out, ",\"value_N\":", c->value_N);
  jnum(out, ",\"x_mm\":", c->x_mm);
  jnum(out, ",\"width_mm\":", c->width_mm);
  if (c->spread_deg > 0.0) jnum(out, ",\"spread_deg\":", c->spread_deg);
  fputs(",\"voussoir\":", out);
  if (status == VS_OK && a->load_block >= 0) fprintf(out, "%d}", a->load_block + 1);
  else fputs("null}", out);
  jnum(out, ",\"hold_mm\":", c->hold_mm);
  fprintf(out, ",\"configuration\":\"%s\"", c->hold_mm > 0.0 ? "held" : "initial");
  fputs(",\"limit\":", out);
  if (status != VS_OK) {
    fputs("null}\n", out);
    return;
  }
  vs_report_limit_object(out, a, c->kind, c->value_N, c->thickness_mm, courses_of(c));
  fputs("}\n", out);
}

void vs_report_limit_object(FILE *out, const vs_limit_analysis *a, int kind, double value_N,
                            double thickness_mm, int courses) {
  const double lam = a->have_load ? optimum(&a->collapse) : NAN;
  jnum(out, "{\"load_factor\":", lam);
  const int by_value = kind != VS_LOAD_TILT;
  jnum(out, ",\"collapse_load_N\":", by_value ? lam * value_N : NAN);
  fputs(",\"load_factor_exact\":", out);
  if (isfinite(lam)) fputs(a->collapse.n_friction == 0 ? "true" : "false", out);
  else fputs("null", out);
  jnum(out, ",\"thickness_factor\":", a->thickness_factor);
  jnum(out, ",\"min_thickness_mm\":", a->thickness_factor * thickness_mm);
  jnum(out, ",\"geometric_safety_factor\":", 1.0 / a->thickness_factor);
  jnum(out, ",\"thrust_min_N\":", optimum(&a->thrust_min));
  jnum(out, ",\"thrust_max_N\":", optimum(&a->thrust_max));
  fputs(",\"collapse\":", out);
  if (a->have_load) json_solution(out, &a->collapse, courses);
  else fputs("null", out);
  fputs(",\"thrust_min\":", out);
  json_solution(out, &a->thrust_min, courses);
  fputs(",\"thrust_max\":", out);
  json_solution(out, &a->thrust_max, courses);
  fputs(",\"thickness\":", out);
  json_solution(out, &a->thickness, courses);
  jnum(out, ",\"thickness_bracket\":[", a->thickness_bracket[0]);
  jnum(out, ",", a->thickness_bracket[1]);
  fprintf(out, "],\"thickness_solves\":%d", a->thickness_solves);
  jnum(out, ",\"cpu_s\":", a->cpu_s);
  fputc('}', out);
}

/* The joints of a solution that `which` selects, "9-I 27-E pier2-base-outer", into buf (a list
 * that does not fit ends with "+K more"), or "none". */
static const char *list_or_none(const vs_limit_solution *s, char which, int courses, char *buf,
                                size_t size) {
  buf[0] = '\0';
  size_t used = 0;
  int left = 0;
  for (int k = 0; s->touch != NULL && k < s->n_joints; k++) {
    const char side = selected(s, which, k);
    if (side == 0) continue;
    char item[72];
    joint_token(courses, s->n_joints, k, side, item + 1, sizeof item - 1);
    item[0] = ' ';
    const char *it = used ? item : item + 1;
    if (left == 0 && used + strlen(it) + 16 < size) { /* room for it and " +K more" */
      memcpy(buf + used, it, strlen(it) + 1);
      used += strlen(it);
    } else {
      left++;
    }
  }
  if (left > 0) snprintf(buf + used, size - used, "%s+%d more", used ? " " : "", left);
  return buf[0] ? buf : "none";
}

static void text_load(FILE *out, const vs_case *c, const vs_limit_analysis *a) {
  const vs_limit_solution *s = &a->collapse;
  char list[512];
  switch ((vs_load_kind)c->kind) {
  case VS_LOAD_NONE: fputs("live load    none (load.kind): no load factor\n", out); return;
  case VS_LOAD_TILT:
    fputs("live load    tilt: lambda x each block's weight, horizontal, toward the right\n", out);
    break;
  case VS_LOAD_PATCH:
    fprintf(out, "live load    patch of %g N down over %g mm centred at x = %g mm\n", c->value_N,
            c->width_mm, c->x_mm);
    break;
  default:
    if (a->load_block < 0) { /* spread through the fill over several voussoirs */
      fprintf(out, "live load    %s load of %g N down at x = %g mm\n",
              vs_load_kind_name((vs_load_kind)c->kind), c->value_N, c->x_mm);
      break;
    }
    fprintf(out, "live load    %s load of %g N down at x = %g mm, on voussoir %d\n",
            vs_load_kind_name((vs_load_kind)c->kind), c->value_N, c->x_mm, a->load_block + 1);
    break;
  }
  if (c->kind != VS_LOAD_TILT && c->spread_deg > 0.0)
    fprintf(out, "             on the fill's surface, spread through it at %g deg\n", c->spread_deg);
  if (s->outcome != VS_LIMIT_OPTIMAL) {
    fprintf(out, "load factor  none: %s\n",
            s->outcome == VS_LIMIT_UNBOUNDED ? "unbounded (the load finds no mechanism)"
                                             : "the arch does not stand under its own weight");
    return;
  }
  fprintf(out, "load factor  lambda = %.6g", s->value);
  if (c->kind != VS_LOAD_TILT) fprintf(out, "  (collapse load %.6g N)", s->value * c->value_N);
  fprintf(out, "\n  mechanism  hinges %s (%d)", list_or_none(s, 'h', courses_of(c), list, sizeof list), s->n_hinges);
  fprintf(out, "; sliding %s\n", list_or_none(s, 'x', courses_of(c), list, sizeof list));
  if (s->n_friction == 0)
    fputs("  exact: no joint is at the friction limit (the LP's associative friction does not "
          "enter)\n", out);
  else
    fprintf(out, "  an UPPER BOUND: %d joints at the friction limit (%s); the LP's friction is "
                 "associative, the masonry's is not\n",
            s->n_friction, list_or_none(s, 'f', courses_of(c), list, sizeof list));
}

static void text_thrust(FILE *out, const vs_case *c, const char *what, const vs_limit_solution *s) {
  char list[512];
  if (s->outcome != VS_LIMIT_OPTIMAL) {
    fprintf(out, "  %-10s %s\n", what,
            s->outcome == VS_LIMIT_UNBOUNDED ? "unbounded" : "none: the arch does not stand");
    return;
  }
  fprintf(out, "  %-10s H = %.6g N; its thrust line touches %s\n", what, s->value,
          list_or_none(s, 't', courses_of(c), list, sizeof list));
}

static void text_thickness(FILE *out, const vs_case *c, const vs_limit_analysis *a) {
  char list[512];
  if (!isfinite(a->thickness_factor)) {
    fprintf(out, "thickness    the arch does not stand at any thickness up to %g t\n",
            a->thickness_bracket[0]);
    return;
  }
  fprintf(out, "thickness    the arch stands down to %.5g t = %.4g mm, a geometric factor of "
               "safety of %.4g\n",
          a->thickness_factor, a->thickness_factor * c->thickness_mm, 1.0 / a->thickness_factor);
  fprintf(out, "  (bracket [%.6g, %.6g] t); its thrust line there touches %s\n",
          a->thickness_bracket[0], a->thickness_bracket[1],
          list_or_none(&a->thickness, 't', courses_of(c), list, sizeof list));
}

void vs_report_limit_text(FILE *out, const vs_case *c, const vs_limit_analysis *a,
                          vs_status status, const vs_error *err, const char *case_path) {
  char q[1024];
  fprintf(out, "voussoir %s  case %s\n", VS_VERSION,
          case_path ? vs_quote(case_path, q, sizeof q) : "(defaults)");
  fprintf(out, "arch         R = %g mm, t = %g mm, embrace %g deg, %d voussoirs, b = %g mm, "
               "span L = %.2f mm\n",
          c->radius_mm, c->thickness_mm, c->embrace_deg, c->voussoirs, c->depth_mm,
          vs_case_span_mm(c));
  fprintf(out, "joints       rigid blocks, no tension, mu = %g; supports left %s, right %s\n",
          c->friction, support_name(c->left_kind), support_name(c->right_kind));
  if (c->pier_height_mm > 0.0)
    fprintf(out, "piers        %g mm high, %g mm wide, %d courses each, base friction %g\n",
            c->pier_height_mm, c->pier_width_mm, c->pier_courses,
            c->pier_base_friction > 0.0 ? c->pier_base_friction : c->friction);
  if (c->hold_mm > 0.0) {
    /* the motion that took the arch there: the paths in time when given, else the directions */
    char how[160];
    if (c->left_path.n > 0 || c->right_path.n > 0)
      snprintf(how, sizeof how, "%s%s%s", c->left_path.n > 0 ? "support.left_path" : "",
               c->left_path.n > 0 && c->right_path.n > 0 ? " and " : "",
               c->right_path.n > 0 ? "support.right_path" : "");
    else if (c->left_rate_mm_s != 0.0 && c->rate_mm_s > 0.0)
      snprintf(how, sizeof how, "alpha = %g deg, left_alpha = %g deg", c->alpha_deg,
               c->left_alpha_deg);
    else if (c->left_rate_mm_s != 0.0)
      snprintf(how, sizeof how, "left_alpha = %g deg", c->left_alpha_deg);
    else
      snprintf(how, sizeof how, "alpha = %g deg", c->alpha_deg);
    fprintf(out, "held         the arch where the support's path (%s) left it at %g mm, its "
                 "blocks moved rigidly, loads moved with them\n",
            how, c->hold_mm);
  }
  fputc('\n', out);
  fputs("LIMIT ANALYSIS  rigid blocks, no-tension frictional joints: a linear program (COIN-OR "
        "CLP)\n", out);
  if (status != VS_OK) {
    fprintf(out, "FAILED: %s\n", err != NULL ? err->msg : vs_strerror(status));
    return;
  }
  text_load(out, c, a);
  fputs("thrust       under self-weight, the left support's horizontal reaction:\n", out);
  text_thrust(out, c, "least", &a->thrust_min);
  text_thrust(out, c, "greatest", &a->thrust_max);
  text_thickness(out, c, a);
  fprintf(out, "\nstats        %d LPs (%d for the thickness), CPU %.3f s in all",
          a->thickness_solves + 2 + a->have_load, a->thickness_solves, a->cpu_s);
  if (a->have_load) fprintf(out, "; the load factor's LP %.4f s", a->collapse.cpu_s);
  fputs("\n(hinges and touches: joints 1..n+1 from the left, named by the edge they turn on)\n",
        out);
  if (c->pier_height_mm > 0.0)
    fputs("(the piers' joints: pier1 the left, pier2 the right; base its foundation, courseK the "
          "joint under course K from the bottom; inner the edge on the face under the "
          "springing)\n", out);
}
