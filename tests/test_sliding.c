/* Sliding against statics in closed form, and named as it is:
 *  - a block on a support joint inclined at beta under gravity stands for tan beta < mu and
 *    slides for tan beta > mu, and the program says it slides, at which joint;
 *  - a block pushed sideways by the moving support slides when the push reaches mu W, and then
 *    the support drives a sliding mechanism: the push stays mu W while the slip grows with the
 *    support's travel, which the path detects and ends on (VS_PATH_SLIDING);
 *  - the reference arch at mu = 0.2 collapses by a mixed mechanism from the onset of slip at its
 *    left springing: the event, its direction (from the sense of the shear that the support
 *    reactions of a run without slip give there), the limit point's evidence, the mechanism in
 *    the collapse record and the JSON; at mu = 0.7 nothing slides and the mechanism is
 *    rotational. SI units. */
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
#include <unistd.h>

#include "test_support.h"
#include "voussoir/report.h"
#include "voussoir/run.h"

static double deg(double d) { return d * acos(-1.0) / 180; }

/* The path options of the reference case, with the given increments and largest travel (m). */
static void path_opts(vs_path_opts *o, double step, double max_delta) {
  vs_case c;
  vs_case_defaults(&c);
  vs_test_path_opts(&c, o);
  o->step = step;
  o->step_max = 10.0 * step;
  o->limit_tol = 1e-3 * step;
  o->max_delta = max_delta;
  o->open = 0.0;
}

/* ------------------------------- a block on an incline ----------------------------------
 * A block w x h (depth b) rests on the fixed support over a plane inclined at beta, rising to
 * the right; its centroid h/2 above the joint's centre along the normal. Statics: the joint
 * carries N = W cos(beta + theta/2), T = W sin(beta + theta/2) (its frame turns with half the
 * block's tilt theta), so it holds while tan(beta + theta/2) <= mu. The elastic law's
 * tolerance is that tilt: the weight's moment W (h/2) sin beta on the joint's rotational
 * stiffness k_n b w^3 / 12, a few microradians here; the test stays 1e-4 rad either side of
 * atan mu, far outside it. */
static const double BW = 0.1, BH = 0.04, BD = 0.1, RHO = 2000.0, KN = 3e9, KS = 1.5e9;

static void block_geometry(vs_geometry *g, double beta) {
  const double nx = -sin(beta), nz = cos(beta), mass = RHO * BW * BH * BD;
  g->blocks[0] = (vs_block){.mass = mass, .inertia = mass * (BW * BW + BH * BH) / 12,
                            .cx = 0.5 * BH * nx, .cz = 0.5 * BH * nz, .area = BW * BH};
  g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .nx = nx, .nz = nz,
                                 .length = BW, .depth = BD};
  g->gravity = 9.81;
  g->span = g->thickness = BW;
}

typedef struct {
  vs_status st;
  vs_path_result res;
  vs_error err;
  vs_joint_state js;
  double theta;
} incline_out;

static void incline(double beta, double mu, incline_out *out) {
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  vs_error err;
  assert_int_equal(vs_geometry_create(1, 1, &g, &err), VS_OK);
  block_geometry(g, beta);
  const vs_joint_law law = {.kn = KN, .ks = KS, .mu = mu};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  vs_path_opts o;
  path_opts(&o, 1e-6, 2e-6);
  double q[3] = {0, 0, 0};
  vs_error_clear(&out->err);
  out->st = vs_path_run(m, &o, 0.0, q, NULL, NULL, &out->res, &out->err);
  if (out->st == VS_OK) vs_model_joint_states(m, q, 0.0, &out->js);
  out->theta = q[2];
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

static void test_incline_threshold(void **s) {
  (void)s;
  const double mus[] = {0.3, 0.7};
  for (int i = 0; i < 2; i++) {
    const double mu = mus[i], crit = atan(mu);
    incline_out lo, hi;
    incline(crit - 1e-4, mu, &lo);
    if (lo.st != VS_OK) fail_msg("mu %g, beta = atan mu - 1e-4: %s", mu, lo.err.msg);
    /* the tilt is within the stated tolerance, the joint sticks below its limit */
    const double W = RHO * BW * BH * BD * 9.81;
    const double tilt = W * 0.5 * BH * sin(crit) / (KN * BD * BW * BW * BW / 12.0);
    assert_true(fabs(lo.theta) < 2.0 * tilt && tilt < 1e-5);
    assert_int_equal(lo.js.sliding, 0);
    assert_true(fabs(lo.js.T) < mu * lo.js.N);
    assert_true(fabs(lo.js.T / lo.js.N - tan(crit - 1e-4 + 0.5 * lo.theta)) < 1e-9);
    assert_int_equal(lo.res.evidence.slip_onset, 0);
    incline(crit + 1e-4, mu, &hi);
    print_message("mu %g: stands at beta = atan mu - 1e-4 (tilt %.3g rad); at + 1e-4: %s\n", mu,
                  lo.theta, hi.err.msg);
    assert_int_equal(hi.st, VS_ERR_NO_EQUILIBRIUM);
    assert_int_equal(hi.res.evidence.slip_onset, 1);
    assert_int_equal(hi.res.evidence.slip_joint, 0);
    assert_non_null(strstr(hi.err.msg, "cannot stand without sliding: its weight takes the "
                                       "shear at joint 1 past the Coulomb limit"));
  }
}

/* ------------------------------- a block pushed sideways --------------------------------
 * A block w x h on the fixed support (joint 1, horizontal, friction mu), its right face against
 * the moving support (joint 2, frictionless: mu_p = 1e-6), which moves left (alpha = -90 deg)
 * from a contact pressed by 1e-8 m. Statics of the block once the base slides: the push P (the
 * force on the support along its motion) balances the base's shear mu N and N balances the
 * weight W (the pusher's shear is at most mu_p of its force), in the base's frame turned by
 * half the block's tilt theta: P / W = tan(atan mu - theta / 2), so |P - mu W| <= ((1 + mu^2)
 * |theta| / 2 + 2 mu_p) W. */
static const double MU_BASE = 0.3, MU_PUSH = 1e-6;

typedef struct {
  int n;
  double delta[256], P[256], slip[256], theta[256];
  int sliding[256];
} push_track;

static int on_push(void *user, double delta, const double *q, const vs_model *m) {
  push_track *tr = user;
  vs_joint_state st[2];
  vs_model_joint_states(m, q, delta, st);
  if (tr->n < 256) {
    tr->delta[tr->n] = delta;
    tr->P[tr->n] = vs_model_support_force(m, q, delta);
    tr->slip[tr->n] = vs_model_slips(m)[0];
    tr->theta[tr->n] = q[2];
    tr->sliding[tr->n] = st[0].sliding;
    tr->n++;
  }
  return 0;
}

static void test_pushed_block(void **s) {
  (void)s;
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(1, 2, &g, &err), VS_OK);
  const double h = 0.05, mass = RHO * BW * h * BD, W = mass * 9.81;
  g->blocks[0] = (vs_block){.mass = mass, .inertia = mass * (BW * BW + h * h) / 12, .cz = 0.5 * h,
                            .area = BW * h};
  g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .nz = 1, .length = BW, .depth = BD};
  g->joints[1] = (vs_joint_geom){.a = 0, .b = VS_SUPPORT_RIGHT, .px = 0.5 * BW, .pz = 0.5 * h,
                                 .nx = 1, .length = h, .depth = BD};
  g->gravity = 9.81;
  g->span = g->thickness = BW;
  vs_joint_law law = {.kn = KN, .ks = KS, .mu = MU_BASE};
  assert_int_equal(vs_model_create(g, &law, deg(-90.0), &m, &err), VS_OK);
  law.mu = MU_PUSH;
  assert_int_equal(vs_model_set_joint_law(m, 1, &law, &err), VS_OK);
  const double pressed[2] = {-1e-8, 0.0};
  vs_model_set_support_offset(m, pressed);
  vs_path_opts o;
  path_opts(&o, 1e-7, 1e-4);
  double q[3] = {0, 0, 0};
  vs_path_result res;
  push_track *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  const vs_status st = vs_path_run(m, &o, 0.0, q, on_push, tr, &res, &err);
  if (st != VS_OK) fail_msg("path: %s", err.msg);
  /* the sliding mechanism that the support drives, detected and ended on */
  assert_int_equal(res.end, VS_PATH_SLIDING);
  assert_true(res.evidence.slip_onset >= 1 && res.evidence.slip_joint == 0);
  assert_true(res.delta_fail < o.max_delta && res.delta_limit < res.delta_fail);
  int first = -1;
  for (int i = 0; i < tr->n; i++) {
    if (!tr->sliding[i]) {
      assert_true(tr->P[i] < MU_BASE * W); /* below the friction force, it sticks */
      continue;
    }
    if (first < 0) first = i;
    const double tol = (0.5 * (1 + MU_BASE * MU_BASE) * fabs(tr->theta[i]) + 2 * MU_PUSH) * W;
    if (!(fabs(tr->P[i] - MU_BASE * W) <= tol))
      fail_msg("sliding at %.6g mm: push %.9g N, mu W = %.9g N (tolerance %.3g N)",
               tr->delta[i] * 1e3, tr->P[i], MU_BASE * W, tol);
  }
  assert_true(first > 0 && first < tr->n - 1);
  print_message("the base slides from %.4g mm at a push of %.7g N (mu W = %.7g N); path ended at "
                "%.4g mm\n", tr->delta[first] * 1e3, tr->P[first], MU_BASE * W,
                res.delta_fail * 1e3);
  assert_true(res.delta_limit == tr->delta[first]);
  /* on the plateau the block follows the support: the slip grows as the travel (the elastic
   * state stays put but for the tilt's second-order change) */
  const int a = first, b = tr->n - 1;
  assert_true(fabs((tr->slip[b] - tr->slip[a]) - (tr->delta[b] - tr->delta[a])) <=
              1e-4 * (tr->delta[b] - tr->delta[a]));
  free(tr);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* --------------------- the pushed block as a run, from a blocks file ---------------------
 * The same statics through the whole program: a case (arch.shape = file) whose blocks file puts
 * one block of 100 x 50 mm on the fixed base (friction 0.3) and the right support against its
 * side (an interface of its own, friction 1e-6), the support moving inward (alpha = -90 deg).
 * The run follows the slip of the base and ends on the sliding mechanism that the support drives
 * (VS_PATH_SLIDING): a collapse named sliding, without "Newton failed", the push at the base's
 * friction mu W, the block sliding along the push (toward -x: the extrados end of joint 1,
 * whose tangent from intrados to extrados is the normal +z turned +90 degrees). */
static const char PUSH_JSON[] =
    "{\"format\": \"voussoir-blocks 1\", \"units\": \"mm\", \"blocks\": [\n"
    " {\"name\": \"L\", \"support\": \"left\", \"polygon\": [[0,-50],[100,-50],[100,0],[0,0]]},\n"
    " {\"name\": \"a\", \"polygon\": [[0,0],[100,0],[100,50],[0,50]]},\n"
    " {\"name\": \"R\", \"support\": \"right\", \"polygon\": [[100,0],[150,0],[150,50],[100,50]]}],\n"
    " \"interfaces\": [{\"between\": [\"a\", \"R\"], \"friction\": 1e-6}],\n"
    " \"ring\": [\"L\", \"a\", \"R\"]}\n";

static void test_run_pushed_block_slides(void **s) {
  (void)s;
  char path[] = "/tmp/vs_test_push_XXXXXX";
  const int fd = mkstemp(path);
  assert_true(fd >= 0);
  FILE *f = fdopen(fd, "w");
  assert_non_null(f);
  fputs(PUSH_JSON, f);
  assert_int_equal(fclose(f), 0);
  static const char *const sets[] = {
      "arch.shape=file", "arch.depth_mm=100", "arch.density_kg_m3=2000", "joints.kn_N_mm3=3",
      "joints.friction=0.3", "support.alpha_deg=-90", "support.max_mm=5", "solver.step_mm=0.001",
      "solver.step_max_mm=0.01", "solver.limit_tol_mm=1e-5", "dynamic.fall_s=0"};
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  for (size_t i = 0; i < sizeof sets / sizeof sets[0]; i++)
    assert_int_equal(vs_case_set(&c, sets[i], &err), VS_OK);
  snprintf(c.blocks_file, sizeof c.blocks_file, "%s", path);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_run *r = NULL;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  const vs_status st = vs_run_execute(r, NULL, NULL, NULL, &err);
  unlink(path);
  if (st != VS_OK) fail_msg("the pushed block: %s", err.msg);
  const vs_collapse_record *col = vs_run_collapse(r);
  assert_true(col->found);
  assert_int_equal(vs_run_path_totals(r)->end, VS_PATH_SLIDING);
  assert_string_equal(col->mechanism, "sliding");
  const double W = vs_geometry_weight(vs_run_geometry(r)), mu = 0.3;
  assert_true(fabs(W - 2000.0 * 0.1 * 0.05 * 0.1 * 9.81) < 1e-9 * W);
  /* the base carries the weight and the push mu W (its moment tilts the block a few
   * microradians: the tolerance) */
  const double *R = col->reactions_limit;
  if (!(fabs(R[0] - mu * W) < 1e-3 * W && fabs(R[1] - W) < 1e-3 * W && fabs(R[3] + mu * W) < 1e-3 * W))
    fail_msg("reactions at the collapse: left (%g, %g) N, right Fx %g N; mu W = %g N, W = %g N",
             R[0], R[1], R[3], mu * W, W);
  int base = 0;
  for (int i = 0; i < col->n_slips; i++)
    if (col->slips[i].joint == 1) base = col->slips[i].side;
  assert_int_equal(base, 'E');
  /* where the base starts to slide: the push mu W through the side joint's closure and the
   * base's shear in series, k_n b h and k_s b w; the block's tilt under the push's moment adds
   * about a fifth, and the run ends the path within its increments (0.001 mm) */
  const double kn = 3e9, k_side = kn * 0.1 * 0.05, k_base = 0.5 * kn * 0.1 * 0.1;
  const double onset = mu * W * (1.0 / k_side + 1.0 / k_base);
  print_message("the pushed block slides from %.4g mm (statics: %.4g mm, before the tilt)\n",
                col->delta * 1e3, onset * 1e3);
  assert_true(col->delta > onset && col->delta < 1.5 * onset + 2e-6); /* + two steps */
  vs_run_destroy(&r);
}

/* ----------------------------- the reference arch, named -------------------------------- */

static vs_run *arch_run(double mu) {
  vs_case c;
  vs_case_defaults(&c);
  c.friction = mu;
  c.fall_s = 0.0;
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("mu %g: %s", mu, err.msg);
  assert_true(vs_run_collapse(r)->found);
  return r;
}

/* The sense of slip at the left springing where the run departs, from the statics of its
 * reactions there: the support's force on voussoir 1 is N n - T s (n from the support into the voussoir, s = n turned +90 degrees,
 * both turned by half the voussoir's rotation), and friction resists the slip, so the voussoir
 * slides along s (toward the extrados) when T > 0. */
static char left_springing_sense(const vs_run *r) {
  const vs_geometry *g = vs_run_geometry(r);
  const vs_joint_geom *j = &g->joints[0];
  const double th = 0.5 * vs_run_state(r)[2];
  const double n[2] = {cos(th) * j->nx - sin(th) * j->nz, sin(th) * j->nx + cos(th) * j->nz};
  const double sv[2] = {-n[1], n[0]};
  const double *R = vs_run_collapse(r)->reactions_limit;
  const double T = -(R[0] * sv[0] + R[1] * sv[1]);
  return T > 0.0 ? 'E' : 'I';
}

static void test_arch_mixed_mechanism_named(void **s) {
  (void)s;
  vs_run *r = arch_run(0.2);
  const vs_path_result *p = vs_run_path(r);
  const vs_collapse_record *col = vs_run_collapse(r);
  /* the first limit point is the onset of slip at joint 1, and the collapse departs there */
  assert_int_equal(p->end, VS_PATH_LIMIT_POINT);
  assert_true(p->evidence.slip_onset >= 1 && p->evidence.slip_joint == 0);
  assert_true(p->evidence.det_sign <= 0 && isnan(p->evidence.delta_extrap));
  assert_true(col->delta == p->delta_limit);
  /* the slip event, on the path at the limit point, in the sense the statics give */
  const vs_run_event *slip = NULL;
  for (int i = 0; i < vs_run_event_count(r) && slip == NULL; i++) {
    const vs_run_event *e = vs_run_event_get(r, i);
    if (e->kind == VS_EVENT_JOINT_SLIPPED) slip = e;
  }
  assert_non_null(slip);
  assert_int_equal(slip->joint, 1);
  assert_int_equal(slip->phase, VS_PHASE_QUASISTATIC);
  assert_true(slip->delta == col->delta);
  const char sense = left_springing_sense(r);
  assert_int_equal(slip->side, sense);
  /* the mechanism: hinges and the slip at joint 1, in that sense */
  assert_string_equal(col->mechanism, "mixed");
  assert_true(col->n_hinges >= 3 && col->n_slips >= 1);
  assert_int_equal(col->slips[0].joint, 1);
  assert_int_equal(col->slips[0].side, sense);
  assert_true(col->slips[0].slip > vs_run_hinge_opts(r)->open);
  /* ... and in the JSON */
  char *buf = NULL;
  size_t len = 0;
  FILE *f = open_memstream(&buf, &len);
  assert_non_null(f);
  vs_report_json(f, r, VS_OK, NULL, "case.ini");
  fclose(f);
  char want[96];
  snprintf(want, sizeof want, "\"mechanism\":\"mixed\",\"slips\":[{\"joint\":1,\"toward\":\"%s\"",
           sense == 'E' ? "extrados" : "intrados");
  assert_non_null(strstr(buf, want));
  assert_non_null(strstr(buf, "\"slip_onset\":{\"first_joint\":1,"));
  print_message("mu 0.2: slips at joint 1 toward the %s from %.4f mm; %s\n",
                sense == 'E' ? "extrados" : "intrados", col->delta * 1e3, want);
  free(buf);
  vs_run_destroy(&r);
}

/* At mu = 0.7 no joint slides before the collapse (the largest |T| / N of the path is about
 * 0.3): no slip event, a rotational mechanism. */
static void test_arch_rotational(void **s) {
  (void)s;
  vs_run *r = arch_run(0.7);
  const vs_collapse_record *col = vs_run_collapse(r);
  assert_string_equal(col->mechanism, "rotational");
  assert_int_equal(col->n_slips, 0);
  assert_int_equal(vs_run_path(r)->evidence.slip_onset, 0);
  for (int i = 0; i < vs_run_event_count(r); i++)
    assert_true(vs_run_event_get(r, i)->kind != VS_EVENT_JOINT_SLIPPED);
  vs_run_destroy(&r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_incline_threshold),
      cmocka_unit_test(test_pushed_block),
      cmocka_unit_test(test_run_pushed_block_slides),
      cmocka_unit_test(test_arch_mixed_mechanism_named),
      cmocka_unit_test(test_arch_rotational),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
