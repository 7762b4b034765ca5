/* The piers in a run's summaries (report_piers.h): their dimensions and the events that name
 * what happened where: pier p rocking on its base, a course joint of pier p opening, a base
 * sliding. */
#include "report_piers.h"

#include "voussoir/units.h"

#include <math.h>

static const char *const PHASES[] = {"quasistatic", "dynamic", "fall"};

/* What event e says of a pier: "rocking", "course_opening", "sliding"; NULL when it is not a
 * pier's (pier and course set: pier 1 left, 2 right; course 1 the bottom one). */
static const char *pier_event(const vs_geometry *g, const vs_run_event *e, int *pier, int *course) {
  if (e->joint < 1 || e->joint > g->n_joints) return NULL;
  const int kind = vs_geometry_pier_joint(g, e->joint - 1, pier, course);
  *pier += 1;
  if (kind == 0) return NULL;
  if (e->kind == VS_EVENT_PIER_ROCKED) return "rocking";
  if (e->kind == VS_EVENT_COURSE_OPENED) return "course_opening";
  if (e->kind == VS_EVENT_JOINT_SLIPPED && kind == 1) return "sliding";
  return NULL;
}

static double pier_weight(const vs_geometry *g, int p) {
  double m = 0.0;
  for (int c = 0; c < g->pier_courses; c++) m += g->blocks[g->pier_block[p] + c].mass;
  return m * g->gravity;
}

void vs_report_piers_header(FILE *out, const vs_run *r) {
  const vs_geometry *g = vs_run_geometry(r);
  const vs_case *c = vs_run_case(r);
  if (g == NULL || g->pier_courses == 0) return;
  fprintf(out, "piers    %g mm high, %g mm wide, %d courses each, %g kg/m^3, base friction %g; "
          "weight %.3f N + %.3f N\n", c->pier_height_mm, c->pier_width_mm, g->pier_courses,
          c->pier_density_kg_m3 > 0.0 ? c->pier_density_kg_m3 : c->density_kg_m3,
          c->pier_base_friction > 0.0 ? c->pier_base_friction : c->friction, pier_weight(g, 0),
          pier_weight(g, 1));
}

void vs_report_piers_text(FILE *out, const vs_run *r) {
  const vs_geometry *g = vs_run_geometry(r);
  if (g == NULL || g->pier_courses == 0) return;
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++) {
    const vs_run_event *e = vs_run_event_get(r, i);
    int p = 0, c = 0;
    const char *what = pier_event(g, e, &p, &c);
    if (what == NULL) continue;
    if (n++ == 0)
      fprintf(out, "\npiers (1 left, 2 right; courses from the bottom; inner: the face under the "
                   "springing)\n");
    const char *side = e->side == 'I' ? "inner" : "outer";
    if (e->kind == VS_EVENT_PIER_ROCKED)
      fprintf(out, "  pier %d rocks on its base about its %s edge", p, side);
    else if (e->kind == VS_EVENT_COURSE_OPENED)
      fprintf(out, "  pier %d: the joint under course %d opens, hinged at its %s edge", p, c, side);
    else
      fprintf(out, "  pier %d slides on its base, %s", p, e->side == 'I' ? "inward" : "outward");
    fprintf(out, " at %.4f mm (%s)\n", e->delta / VS_MM,
            e->phase == VS_PHASE_QUASISTATIC ? "on the path" : "in the motion");
  }
  if (n == 0) fprintf(out, "\npiers: no joint of either pier opened or slid\n");
}

void vs_report_piers_json(FILE *out, const vs_run *r) {
  const vs_geometry *g = vs_run_geometry(r);
  const vs_case *c = vs_run_case(r);
  if (g == NULL || g->pier_courses == 0) return;
  fprintf(out, ",\"piers\":{\"height_mm\":%.17g,\"width_mm\":%.17g,\"courses\":%d,"
          "\"weight_N\":[%.17g,%.17g],\"events\":[", c->pier_height_mm, c->pier_width_mm,
          g->pier_courses, pier_weight(g, 0), pier_weight(g, 1));
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++) {
    const vs_run_event *e = vs_run_event_get(r, i);
    int p = 0, k = 0;
    const char *what = pier_event(g, e, &p, &k);
    if (what == NULL) continue;
    fprintf(out, "%s{\"kind\":\"%s\",\"pier\":%d,\"course\":%d,\"joint\":%d,", n++ ? "," : "",
            what, p, k, e->joint);
    if (e->kind == VS_EVENT_JOINT_SLIPPED)
      fprintf(out, "\"toward\":\"%s\"", e->side == 'I' ? "inward" : "outward");
    else
      fprintf(out, "\"about\":\"%s\"", e->side == 'I' ? "inner" : "outer");
    fprintf(out, ",\"delta_mm\":%.10g,\"phase\":\"%s\"}", e->delta / VS_MM,
            PHASES[e->phase >= 0 && e->phase <= 2 ? e->phase : 0]);
  }
  fputs("]}", out);
}
