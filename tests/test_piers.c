/* Piers against independent truth (docs/model.md, "Piers"):
 *  - the generated piers' blocks: mass = density x area x depth with the areas worked out here
 *    from the springing's geometry (R, t, the half-embrace), rectangles' centroids and inertias,
 *    the mirror image of the left pier in the right one on every generated shape;
 *  - a stack of courses pushed at its top by the moving support rocks on its base when the push
 *    reaches the closed-form overturning force W b / (2 h) (rigid limit, large k_n);
 *  - a stack whose base is less rough slides on it when the push reaches mu_base W;
 *  - the reference arch on two equal piers under symmetric spreading stays a mirror image;
 *  - in a run the events name what the piers did: slender piers rock on their bases about their
 *    outer edges, a smooth base slides outward when the arch's thrust on the pier's foundation
 *    reaches base_friction times the vertical force (Coulomb, from the support's reactions);
 *  - bad pier keys are refused naming the key. SI units. */
#define _POSIX_C_SOURCE 200809L /* open_memstream */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "blocks.h"
#include "test_support.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/limit.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"
#include "voussoir/report.h"
#include "voussoir/run.h"

static double deg(double d) { return d * acos(-1.0) / 180; }

/* The reference specimen's definition with piers h high, w wide, of c courses (mm). */
static void piers_def(vs_case *c, vs_run_def *d, double h, double w, int courses) {
  vs_case_defaults(c);
  c->pier_height_mm = h;
  c->pier_width_mm = w;
  c->pier_courses = courses;
  vs_case_to_def(c, d);
}

/* ------------------------------ the generated piers' blocks ------------------------------ */

static void test_pier_mass(void **s) {
  (void)s;
  vs_case c;
  vs_run_def d;
  const double H = 0.3, W = 0.15, rho = 1640.0, b = 0.12, R = 0.3, t = 0.024;
  const int C = 4;
  piers_def(&c, &d, H * 1e3, W * 1e3, C);
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_geometry_create_arch(&d.arch, &g, &err) != VS_OK) fail_msg("%s", err.msg);
  assert_int_equal(g->pier_courses, C);
  assert_int_equal(g->n_blocks, 55 + 2 * C);
  assert_int_equal(g->n_joints, 56 + 2 * C);
  assert_int_equal(g->ring, 56);
  /* the springing face: intrados point (R sin beta, R cos beta), extrados end (R + t) along it */
  const double beta = deg(62.5), dz = H / C;
  const double rise = t * cos(beta), reach = t * sin(beta);
  /* above the intrados point's level: a band (W - reach) x rise and the triangle under the face */
  const double top_extra = rise * (W - reach) + 0.5 * reach * rise;
  double pier_mass = 0.0;
  for (int c0 = 0; c0 < C; c0++) {
    const vs_block *bl = &g->blocks[g->pier_block[0] + c0];
    const double area = W * dz + (c0 == C - 1 ? top_extra : 0.0);
    assert_true(fabs(bl->mass - rho * area * b) < 1e-12 * rho * area * b + 1e-15);
    pier_mass += bl->mass;
    if (c0 < C - 1) { /* a rectangle: its centre, m (w^2 + h^2) / 12 */
      assert_true(fabs(bl->cx - (-R * sin(beta) - 0.5 * W)) < 1e-12);
      assert_true(fabs(bl->cz - (R * cos(beta) - H + (c0 + 0.5) * dz)) < 1e-12);
      assert_true(fabs(bl->inertia - bl->mass * (W * W + dz * dz) / 12.0) < 1e-12 * bl->inertia);
    }
  }
  const double expect = rho * b * (W * H + top_extra);
  assert_true(fabs(pier_mass - expect) < 1e-12 * expect);
  /* the arch's own mass: the annular sector of 125 degrees */
  const double arch = rho * b * 0.5 * ((R + t) * (R + t) - R * R) * 2.0 * beta;
  assert_true(fabs(vs_geometry_weight(g) / g->gravity - (arch + 2.0 * expect)) <
              1e-12 * (arch + 2.0 * expect));
  print_message("each pier %.6g kg (density x area x depth: %.6g kg), the arch %.6g kg\n",
                pier_mass, expect, arch);
  /* the foundations: a support joint under each pier, the supports' polygons */
  assert_int_equal(g->joints[g->pier_joint[0]].a, VS_SUPPORT_LEFT);
  assert_int_equal(g->joints[g->pier_joint[1]].b, VS_SUPPORT_RIGHT);
  assert_int_equal(g->joints[0].a, g->pier_block[0] + C - 1);
  assert_int_equal(g->joints[55].b, g->pier_block[1] + C - 1);
  assert_int_equal(g->n_supports, 2);
  vs_geometry_destroy(&g);
}

/* On every generated shape the right pier is the left one mirrored, and its top course's
 * skewback carries the springing joint. */
static void test_pier_shapes_mirror(void **s) {
  (void)s;
  static const vs_arch_shape shapes[] = {VS_SHAPE_CIRCULAR, VS_SHAPE_POINTED, VS_SHAPE_ELLIPTICAL,
                                         VS_SHAPE_BASKET, VS_SHAPE_PARABOLIC, VS_SHAPE_CATENARY};
  for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
    vs_case c;
    vs_run_def d;
    piers_def(&c, &d, 250.0, 200.0, 3);
    d.arch.shape = shapes[k];
    d.arch.thickness = 0.04;
    if (shapes[k] != VS_SHAPE_CIRCULAR) d.arch.span = 0.5322;
    if (shapes[k] == VS_SHAPE_POINTED) d.arch.eccentricity = 0.25;
    if (shapes[k] >= VS_SHAPE_ELLIPTICAL) d.arch.rise = shapes[k] == VS_SHAPE_BASKET ? 0.2 : 0.25;
    vs_geometry *g = NULL;
    vs_error err;
    vs_error_clear(&err);
    if (vs_geometry_create_arch(&d.arch, &g, &err) != VS_OK) fail_msg("shape %zu: %s", k, err.msg);
    const double xm = 0.5 * (g->joints[0].px + g->joints[g->ring - 1].px);
    for (int c0 = 0; c0 < 3; c0++) {
      const vs_block *l = &g->blocks[g->pier_block[0] + c0], *r = &g->blocks[g->pier_block[1] + c0];
      assert_true(l->mass > 0.0 && fabs(l->mass - r->mass) < 1e-12 * l->mass);
      assert_true(fabs(l->inertia - r->inertia) < 1e-12 * l->inertia);
      assert_true(fabs((l->cx - xm) + (r->cx - xm)) < 1e-12 && fabs(l->cz - r->cz) < 1e-12);
      /* every course's base is on the ground's level plus whole courses */
      const vs_joint_geom *jl = &g->joints[g->pier_joint[0] + c0];
      double sx, sz;
      vs_joint_tangent(&g->joints[0], &sx, &sz);
      const double zi = g->joints[0].pz - 0.5 * g->joints[0].length * sz;
      assert_true(fabs(jl->pz - (zi - 0.25 + c0 * 0.25 / 3)) < 1e-12);
    }
    vs_geometry_destroy(&g);
  }
}

/* The blocks file of an arch on piers (voussoir blocks) holds the same blocks: read back, its
 * mass, its blocks' and joints' counts; its ring runs through the piers' courses. */
static void test_pier_blocks_file(void **s) {
  (void)s;
  vs_case c;
  vs_run_def d;
  piers_def(&c, &d, 300.0, 150.0, 4);
  d.arch.piers.base_friction = 0.5;
  vs_geometry *g = NULL, *h = NULL;
  vs_error err;
  vs_error_clear(&err);
  char *text = NULL;
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
  if (vs_geometry_blocks_json(g, &text, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_arch_def a = d.arch;
  a.shape = VS_SHAPE_FILE;
  a.piers.height = 0.0;
  if (vs_blocks_parse("piers.json", text, strlen(text), &a, &h, &err) != VS_OK)
    fail_msg("%s", err.msg);
  assert_int_equal(h->n_blocks, g->n_blocks);
  assert_int_equal(h->n_joints, g->n_joints);
  assert_int_equal(h->ring, g->n_joints); /* every joint on the ring, through the piers */
  /* the piers' courses are polygons, written exactly; the voussoirs' arcs as chords (a few
   * 1e-6 of their area) */
  for (int i = g->pier_block[0]; i < g->n_blocks; i++)
    assert_true(fabs(h->blocks[i].mass - g->blocks[i].mass) < 1e-9 * g->blocks[i].mass);
  const double m0 = vs_geometry_weight(g), m1 = vs_geometry_weight(h);
  assert_true(fabs(m1 - m0) < 1e-4 * m0);
  assert_true(h->joints[0].a == VS_SUPPORT_LEFT && h->joints[0].mu == 0.5);
  free(text);
  vs_geometry_destroy(&g);
  vs_geometry_destroy(&h);
}

static void test_pier_errors(void **s) {
  (void)s;
  vs_case c;
  vs_run_def d;
  vs_geometry *g = NULL;
  vs_error err;
  piers_def(&c, &d, 300.0, 20.0, 4); /* the face reaches 21.3 mm outward */
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_ERR_INVALID);
  assert_null(g);
  assert_non_null(strstr(err.msg, "piers.width_mm = 20"));
  piers_def(&c, &d, 300.0, 150.0, 0);
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "piers.courses = 0"));
  vs_case_defaults(&c);
  assert_int_equal(vs_case_set(&c, "arch.shape=file", &err), VS_OK);
  assert_int_equal(vs_case_set(&c, "arch.blocks_file=x.json", &err), VS_OK);
  assert_int_equal(vs_case_set(&c, "piers.height_mm=100", &err), VS_OK);
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "piers.height_mm"));
  vs_case_defaults(&c);
  assert_int_equal(vs_case_set(&c, "piers.height_mm=100", &err), VS_OK);
  assert_int_equal(vs_case_set(&c, "support.right_kind=pinned", &err), VS_OK);
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "support.right_kind = pinned"));
}

/* ------------------------------- a stack pushed at its top -------------------------------
 * C courses b wide, H high in all (depth D), on the fixed support (joint 1, horizontal); the
 * top course's right face, over its top E, against the moving support (a frictionless pusher:
 * mu 1e-6), which moves left from a contact pressed by 1e-8 m. The push acts at h = H - E / 2.
 * Rigid statics: about the base's far edge the stack stands while P h <= W b / 2 (every course
 * joint above carries less: P (h - z) against W (H - z) / H b / 2); its base slides while
 * P <= mu_base W. */
static const double SB = 0.1, SD = 0.12, RHO = 1640.0, SE = 0.002, MU_PUSH = 1e-6;

static void stack_geometry(vs_geometry *g, int C, double b, double H) {
  const double dz = H / C, mass = RHO * b * dz * SD;
  for (int c = 0; c < C; c++) {
    g->blocks[c] = (vs_block){.mass = mass, .inertia = mass * (b * b + dz * dz) / 12,
                              .cz = (c + 0.5) * dz, .area = b * dz};
    g->joints[c] = (vs_joint_geom){.a = c == 0 ? VS_SUPPORT_LEFT : c - 1, .b = c, .pz = c * dz,
                                   .nz = 1, .length = b, .depth = SD};
  }
  g->joints[C] = (vs_joint_geom){.a = C - 1, .b = VS_SUPPORT_RIGHT, .px = 0.5 * b,
                                 .pz = H - 0.5 * SE, .nx = 1, .length = SE, .depth = SD};
  g->gravity = 9.81;
  g->span = g->thickness = b;
}

typedef struct {
  int n;
  double Pmax, delta_max;
  int base_slid_first, course_slid;
  double P_slide, theta_slide;
} stack_track;

static int on_stack(void *user, double delta, const double *q, const vs_model *m) {
  stack_track *tr = user;
  vs_joint_state st[8];
  vs_model_joint_states(m, q, delta, st);
  const double P = vs_model_support_force(m, q, delta);
  if (P > tr->Pmax) tr->Pmax = P, tr->delta_max = delta;
  if (st[0].sliding && tr->base_slid_first < 0) {
    tr->base_slid_first = tr->n;
    tr->P_slide = P;
    tr->theta_slide = q[2];
  }
  if (st[1].sliding) tr->course_slid = 1;
  tr->n++;
  return 0;
}

/* Push a stack of C courses, b x H, base friction mu_base (the course joints' 0.7), k_n kn,
 * up to max_delta; the track and the model's joints at the end into st. */
static void push_stack(int C, double b, double H, double mu_base, double kn, double max_delta,
                       stack_track *tr, vs_joint_state *st) {
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(C, C + 1, &g, &err), VS_OK);
  stack_geometry(g, C, b, H);
  vs_joint_law law = {.kn = kn, .ks = 0.5 * kn, .mu = 0.7};
  assert_int_equal(vs_model_create(g, &law, deg(-90.0), &m, &err), VS_OK);
  law.mu = mu_base;
  assert_int_equal(vs_model_set_joint_law(m, 0, &law, &err), VS_OK);
  law.mu = MU_PUSH;
  assert_int_equal(vs_model_set_joint_law(m, C, &law, &err), VS_OK);
  const double pressed[2] = {-1e-8, 0.0};
  vs_model_set_support_offset(m, pressed);
  vs_case c;
  vs_case_defaults(&c);
  vs_path_opts o;
  vs_test_path_opts(&c, &o);
  o.step = max_delta / 400;
  o.step_max = max_delta / 100;
  o.limit_tol = 1e-3 * o.step;
  o.max_delta = max_delta;
  o.open = 0.0;
  double q[3 * 8] = {0};
  vs_path_result res;
  memset(tr, 0, sizeof *tr);
  tr->base_slid_first = -1;
  const vs_status s = vs_path_run(m, &o, 0.0, q, on_stack, tr, &res, &err);
  if (s != VS_OK) fail_msg("path: %s", err.msg);
  vs_model_joint_states(m, q, res.delta_limit, st); /* the last equilibrium */
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* The largest push on a stack of C courses pushed at its top, k_n kn; its lever-arm deficit
 * 1 - P / (W b / (2 h)) and the elastic estimate of it: the base turned by phi carries its
 * resultant c/3 inside the edge (N = k_n D phi c^2 / 2) while the tilt costs A phi of lever arm
 * (A = H/2 + b^2 / (2 h), the centroid's and the push's arms); the push peaks where the sum is
 * least, at phi* = (s / (6 A))^(2/3), s = sqrt(2 W / (k_n D)): a deficit of 3 A phi* / (b / 2),
 * which falls as k_n^(-1/3) to the rigid limit (an upper estimate: the tilt's cost is taken
 * whole, as if the base's resultant were at its edge). */
static double rock_deficit(int C, double H, double kn, double *estimate, vs_joint_state *st) {
  const double W = RHO * SB * H * SD * 9.81, h = H - 0.5 * SE, Prock = W * SB / (2.0 * h);
  const double A = 0.5 * H + SB * SB / (2.0 * h), sq = sqrt(2.0 * W / (kn * SD));
  const double phi = pow(sq / (6.0 * A), 2.0 / 3.0);
  *estimate = 3.0 * A * phi / (0.5 * SB);
  stack_track tr;
  push_stack(C, SB, H, 0.7, kn, 20.0 * h * phi, &tr, st);
  assert_true(tr.delta_max < 10.0 * h * phi); /* then it rocks: the push falls as it tilts */
  assert_int_equal(tr.base_slid_first, -1);
  print_message("stack of %d courses, k_n %.3g N/mm^3: largest push %.7g N at %.4g mm; W b / (2 h) "
                "= %.7g N; deficit %.3g (estimate %.3g)\n", C, kn * 1e-9, tr.Pmax,
                tr.delta_max * 1e3, Prock, 1.0 - tr.Pmax / Prock, *estimate);
  assert_true(tr.Pmax <= Prock * (1.0 + 1e-9));
  return 1.0 - tr.Pmax / Prock;
}

static void test_stack_rocks(void **s) {
  (void)s;
  enum { C = 4 };
  const double H = 0.3;
  vs_joint_state st[C + 1];
  double est_lo = 0.0, est_hi = 0.0;
  const double d_lo = rock_deficit(C, H, 1e11, &est_lo, st);
  const double d_hi = rock_deficit(C, H, 1e13, &est_hi, st); /* 1e4 N/mm^3: the rigid limit */
  assert_true(d_hi > 0.0 && d_hi <= est_hi && d_lo <= est_lo);
  /* toward the rigid limit: 100 times stiffer, at most 100^(-1/3) = 0.215 the deficit (the
   * estimate's rate; the peak found on a path of finite steps comes a little closer) */
  assert_true(d_hi / d_lo > 0.0 && d_hi / d_lo < 0.3);
  assert_true(d_hi < 5e-3);
  vs_hinge_opts ho = {.open = 1e-5, .migrate = 3}; /* 10 um: beyond the elastic openings */
  assert_int_equal(vs_hinges_joint_side(&ho, &st[0]), 'E'); /* about the far (left) edge */
  for (int c = 1; c < C; c++) assert_int_equal(vs_hinges_joint_side(&ho, &st[c]), 0);
}

static void test_stack_slides(void **s) {
  (void)s;
  const int C = 2;
  const double b = 0.15, H = 0.1, mu = 0.3, kn = 3e9; /* b / (2 H) = 0.75 > mu: it slides */
  const double W = RHO * b * H * SD * 9.81;
  stack_track tr;
  vs_joint_state st[C + 1];
  push_stack(C, b, H, mu, kn, 1e-4, &tr, st);
  assert_true(tr.base_slid_first > 0);
  const double tol = (0.5 * (1 + mu * mu) * fabs(tr.theta_slide) + 2 * MU_PUSH) * W + 1e-9 * W;
  print_message("the base slides at a push of %.7g N (mu W = %.7g N, tolerance %.2g N)\n",
                tr.P_slide, mu * W, tol);
  assert_true(fabs(tr.P_slide - mu * W) <= tol);
  assert_true(tr.Pmax <= mu * W + tol);
  assert_int_equal(tr.course_slid, 0);
}

/* ------------------------- the arch on two piers, spread symmetrically ------------------- */

static void test_arch_on_piers_symmetric(void **s) {
  (void)s;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  const char *const sets[] = {"piers.height_mm=300", "piers.width_mm=150", "piers.courses=4",
                              "joints.kn_N_mm3=48", "support.alpha_deg=90",
                              "support.left_alpha_deg=90", "support.left_rate_mm_s=0.04",
                              "support.max_mm=2", "dynamic.follow=0"};
  for (size_t i = 0; i < sizeof sets / sizeof sets[0]; i++)
    assert_int_equal(vs_case_set(&c, sets[i], &err), VS_OK);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_run *r = NULL;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_status st = vs_run_execute(r, NULL, NULL, NULL, &err);
  if (st != VS_OK) fail_msg("run: %s", err.msg);
  const vs_geometry *g = vs_run_geometry(r);
  const double *q = vs_run_state(r);
  assert_true(vs_run_delta(r) > 1e-3);
  double big = 0.0, worst = 0.0;
  for (int k = 0; k < 3 * g->n_blocks; k++) big = fmax(big, fabs(q[k]));
  const int n = 55;
  for (int i = 0; i < g->n_blocks; i++) {
    const int p = g->pier_courses;
    const int j = i < n ? n - 1 - i
                        : i < g->pier_block[1] ? i + p : i - p; /* the mirror image's block */
    worst = fmax(worst, fabs(q[3 * i] + q[3 * j]));
    worst = fmax(worst, fabs(q[3 * i + 1] - q[3 * j + 1]));
    worst = fmax(worst, fabs(q[3 * i + 2] + q[3 * j + 2]) * g->span);
  }
  print_message("spread by 2 x %.3g mm: the largest state %.3g m, the largest departure from "
                "the mirror image %.3g m\n", vs_run_delta(r) * 1e3, big, worst);
  assert_true(big > 1e-3 && worst < 1e-7 * big);
  vs_run_destroy(&r);
}

/* Run the reference specimen with the settings sets; the run (the caller destroys it), its
 * JSON and text summaries into json and text (malloc'd). */
static vs_run *run_case(const char *const *sets, size_t n, char **json, char **text) {
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  for (size_t i = 0; i < n; i++)
    if (vs_case_set(&c, sets[i], &err) != VS_OK) fail_msg("%s: %s", sets[i], err.msg);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_run *r = NULL;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_status st = vs_run_execute(r, NULL, NULL, NULL, &err);
  if (st != VS_OK) fail_msg("run: %s", err.msg);
  size_t len = 0;
  FILE *f = open_memstream(json, &len);
  vs_report_json(f, r, st, &err, "piers.ini");
  fclose(f);
  f = open_memstream(text, &len);
  vs_report_text(f, r, st, &err, "piers.ini");
  fclose(f);
  return r;
}

/* The first event of kind k at joint (1-based), or NULL. */
static const vs_run_event *event_at(const vs_run *r, vs_event_kind k, int joint) {
  for (int i = 0; i < vs_run_event_count(r); i++)
    if (vs_run_event_get(r, i)->kind == k && vs_run_event_get(r, i)->joint == joint)
      return vs_run_event_get(r, i);
  return NULL;
}

static void test_run_piers_rock(void **s) {
  (void)s;
  const char *const sets[] = {"piers.height_mm=300", "piers.width_mm=110", "joints.kn_N_mm3=3",
                              "support.alpha_deg=90"};
  char *json = NULL, *text = NULL;
  vs_run *r = run_case(sets, 4, &json, &text);
  const vs_geometry *g = vs_run_geometry(r);
  assert_true(vs_run_collapse(r)->found);
  for (int p = 0; p < 2; p++) {
    const vs_run_event *e = event_at(r, VS_EVENT_PIER_ROCKED, g->pier_joint[p] + 1);
    if (e == NULL) fail_msg("pier %d did not rock", p + 1);
    assert_int_equal(e->side, 'E'); /* about its outer edge: the thrust pushes it outward */
  }
  assert_non_null(strstr(text, "pier 1 rocks on its base about its outer edge"));
  assert_non_null(strstr(text, "pier 2 rocks on its base about its outer edge"));
  assert_non_null(strstr(json, "\"piers\":{\"height_mm\":300,"));
  assert_non_null(strstr(json, "{\"kind\":\"rocking\",\"pier\":2,\"course\":1,\"joint\":61,"
                               "\"about\":\"outer\""));
  /* the arch's hinges are the ring's: none at a pier's joint */
  for (int i = 0; i < vs_run_hinge_count(r); i++) assert_true(vs_run_hinge(r, i)->last <= g->ring);
  free(json), free(text);
  vs_run_destroy(&r);
}

static void test_run_pier_slides(void **s) {
  (void)s;
  const double mu = 0.12;
  const char *const sets[] = {"piers.height_mm=300", "piers.width_mm=150",
                              "piers.base_friction=0.12", "joints.kn_N_mm3=3"};
  char *json = NULL, *text = NULL;
  vs_run *r = run_case(sets, 4, &json, &text);
  const vs_geometry *g = vs_run_geometry(r);
  const vs_collapse_record *col = vs_run_collapse(r);
  const vs_run_event *e = event_at(r, VS_EVENT_JOINT_SLIPPED, g->pier_joint[0] + 1);
  if (e == NULL) fail_msg("the left pier's base did not slide");
  assert_int_equal(e->side, 'E'); /* outward: the arch's thrust pushes the left pier left */
  assert_true(col->found);
  /* the left support carries the left pier's base alone: its force on the structure at the
   * collapsing limit point, the base sliding, is on the Coulomb cone */
  const double Fx = col->reactions_limit[0], Fz = col->reactions_limit[1];
  print_message("the left base slides at %.4f mm: |Fx| / Fz = %.6f (mu %.2f)\n", e->delta * 1e3,
                fabs(Fx) / Fz, mu);
  assert_true(fabs(fabs(Fx) / Fz - mu) < 1e-3 * mu);
  assert_non_null(strstr(text, "pier 1 slides on its base, outward"));
  assert_non_null(strstr(json, "{\"kind\":\"sliding\",\"pier\":1,\"course\":1,\"joint\":57,"
                               "\"toward\":\"outward\""));
  free(json), free(text);
  vs_run_destroy(&r);
}

/* The support under a pier is its foundation: a path that turns the right support outward
 * by 0.2 degrees, about the centre of the pier's base, leans the pier with it (its courses
 * turned by as much, clockwise, their base's centre still where the path puts it) while the
 * left pier stays put. */
static void test_foundation_turns(void **s) {
  (void)s;
  const char *const sets[] = {"piers.height_mm=300", "piers.width_mm=150", "joints.kn_N_mm3=48",
                              "support.right_path=0:0:0:0,100:0:0:0.2", "support.rate_mm_s=0.04",
                              "support.max_mm=4", "dynamic.follow=0"};
  char *json = NULL, *text = NULL;
  vs_run *r = run_case(sets, 7, &json, &text);
  const vs_geometry *g = vs_run_geometry(r);
  const double *q = vs_run_state(r), rot = -0.2 * acos(-1.0) / 180.0;
  assert_true(fabs(vs_run_delta(r) - 4e-3) < 1e-9); /* the whole path: t = 100 s */
  for (int c = 0; c < g->pier_courses; c++) {
    const int b = g->pier_block[1] + c, a = g->pier_block[0] + c;
    assert_true(fabs(q[3 * b + 2] - rot) < 0.02 * fabs(rot)); /* the joints' compliance */
    assert_true(fabs(q[3 * a + 2]) < 0.02 * fabs(rot));
  }
  /* the bottom course's centroid turned about the base's centre */
  const vs_block *b0 = &g->blocks[g->pier_block[1]];
  const vs_joint_geom *jb = &g->joints[g->pier_joint[1]];
  const double dx = b0->cx - jb->px, dz = b0->cz - jb->pz;
  const double ux = cos(rot) * dx - sin(rot) * dz - dx, uz = sin(rot) * dx + cos(rot) * dz - dz;
  const double *qb = q + 3 * g->pier_block[1];
  print_message("bottom course of the right pier: turned %.6g rad (support %.6g), moved (%.4g, "
                "%.4g) mm against (%.4g, %.4g) mm\n", qb[2], rot, qb[0] * 1e3, qb[1] * 1e3,
                ux * 1e3, uz * 1e3);
  assert_true(hypot(qb[0] - ux, qb[1] - uz) < 0.02 * hypot(ux, uz));
  free(json), free(text);
  vs_run_destroy(&r);
}

/* ------------------------------ the limit analysis on piers ------------------------------
 * The thrust states of the arch on piers are those of the arch alone whose thrust the piers
 * also carry: the least thrust is at least, the greatest at most the arch's own. With a smooth
 * base the greatest is the friction's: every thrust state has one H at both bases, and by
 * symmetry (the mean of a state and its mirror image is one) it can load each base with half
 * the weight of the whole, so H_max = mu_base W / 2 when that is below the arch's own bound. */
static void analyse(double w, double mu_base, vs_limit_analysis *a, double *weight) {
  vs_case c;
  vs_run_def d;
  piers_def(&c, &d, w > 0.0 ? 300.0 : 0.0, w > 0.0 ? w : 150.0, 4);
  d.arch.piers.base_friction = mu_base;
  vs_error err;
  vs_error_clear(&err);
  if (vs_limit_analyse(&d, NULL, a, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_geometry *g = NULL;
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
  *weight = vs_geometry_weight(g);
  vs_geometry_destroy(&g);
}

static void test_limit_on_piers(void **s) {
  (void)s;
  vs_limit_analysis a0, a1, a2, a3;
  double w0, w1, w2, w3;
  analyse(0.0, 0.0, &a0, &w0);   /* rigid springers */
  analyse(150.0, 0.0, &a1, &w1); /* piers that stand well */
  analyse(90.0, 0.0, &a2, &w2);  /* slender piers: they limit the thrust by rocking */
  analyse(150.0, 0.1, &a3, &w3); /* smooth bases: the friction limits it */
  const double h0 = a0.thrust_min.value, H0 = a0.thrust_max.value, tol = 1e-6 * H0;
  print_message("thrust (N): springers %.6g .. %.6g; piers 150 mm %.6g .. %.6g; 90 mm %.6g .. "
                "%.6g; 150 mm, base friction 0.1: %.6g .. %.6g (mu W / 2 = %.6g)\n", h0, H0,
                a1.thrust_min.value, a1.thrust_max.value, a2.thrust_min.value,
                a2.thrust_max.value, a3.thrust_min.value, a3.thrust_max.value, 0.1 * w3 / 2);
  const vs_limit_analysis *on[3] = {&a1, &a2, &a3};
  for (int i = 0; i < 3; i++) {
    assert_true(on[i]->thrust_min.value >= h0 - tol);
    assert_true(on[i]->thrust_max.value <= H0 + tol);
  }
  /* the slender piers rock: their bases are hinges of the greatest thrust's line, outer edges */
  assert_true(a2.thrust_max.value < 0.95 * H0);
  assert_int_equal(a2.thrust_max.touch[56], 'E');
  assert_int_equal(a2.thrust_max.touch[60], 'E');
  assert_true(fabs(a3.thrust_max.value - 0.1 * w3 / 2) < 1e-6 * w3);
  assert_int_equal(a3.thrust_max.friction[56] + a3.thrust_max.friction[60], 2);
  vs_limit_analysis_free(&a0), vs_limit_analysis_free(&a1);
  vs_limit_analysis_free(&a2), vs_limit_analysis_free(&a3);
  /* piers too narrow for the arch's thrust under its own weight: it does not stand, and the
   * thickness search ends where a thicker ring's springing face no longer fits (4 t here) */
  vs_limit_analysis a4;
  double w4;
  analyse(70.0, 0.0, &a4, &w4);
  assert_int_equal(a4.thrust_min.outcome, VS_LIMIT_INFEASIBLE);
  assert_true(isnan(a4.thickness_factor) && a4.thickness_bracket[0] == 2.0);
  vs_limit_analysis_free(&a4);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_pier_mass),        cmocka_unit_test(test_pier_shapes_mirror),
      cmocka_unit_test(test_pier_errors),      cmocka_unit_test(test_stack_rocks),
      cmocka_unit_test(test_pier_blocks_file), cmocka_unit_test(test_limit_on_piers),
      cmocka_unit_test(test_foundation_turns),
      cmocka_unit_test(test_stack_slides),     cmocka_unit_test(test_arch_on_piers_symmetric),
      cmocka_unit_test(test_run_piers_rock),   cmocka_unit_test(test_run_pier_slides),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
