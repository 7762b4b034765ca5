/* The live load's path (quasistatic.h, vs_load_path_run) against independent truth:
 *  - a block on its base under a horizontal force P at its centroid slides when lambda P =
 *    mu W (Coulomb, by hand), and the path ends on that plateau;
 *  - a two-block column under tilt (lambda x each block's weight, horizontal) overturns about
 *    the base's edge at lambda = b / H (statics of the rigid column, by hand) as k_n grows, and
 *    below it by the rocking of a block on an elastic no-tension base (by hand, asymptotic);
 *  - the reference specimen with a point load at quarter span: the incremental load factor
 *    rises toward the limit analysis' (CLP, an independent method) as k_n grows, monotonically,
 *    within 1 % at k_n = 1e5 N/mm^3, the gap falling as k_n^(-1/3) as the column's (its log-log
 *    slope near -1/3);
 *  - analysis.hold_mm: the residual load factor falls as the support settles or spreads;
 *  - the case's rules for a load path;
 *  - the loads' Jacobian and the pilot's gradient against central differences;
 *  - the fill's weight on the extrados against the geometry by hand, and carried by the run. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <hdf5.h>

#include "model_matrix.h"
#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/limit.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"
#include "voussoir/run.h"
#include "voussoir/units.h"

#define VS_SCRATCH "load"
#include "scratch.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

#define near(a, b, tol)                                                                        \
  do {                                                                                         \
    const double a_ = (a), b_ = (b);                                                           \
    if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.17g, %s = %.17g", #a, a_, #b, b_);         \
  } while (0)

/* Blocks of width b stacked on the left support, x in [0, b]. */
static vs_geometry *column(int n, double b, double h, double mass) {
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(n, n, &g, &err), VS_OK);
  for (int i = 0; i < n; i++) {
    g->joints[i] = (vs_joint_geom){.a = i == 0 ? VS_SUPPORT_LEFT : i - 1, .b = i,
                                   .px = 0.5 * b, .pz = i * h, .nx = 0.0, .nz = 1.0,
                                   .length = b, .depth = 1.0};
    g->blocks[i] = (vs_block){.mass = mass, .inertia = mass * (b * b + h * h) / 12.0,
                              .cx = 0.5 * b, .cz = (i + 0.5) * h, .area = b * h};
  }
  g->gravity = 9.81;
  return g;
}

static vs_load_opts opts(double step, double step_max, double tol, double max_disp) {
  vs_load_opts o = {.step = step, .step_max = step_max, .peak_tol = tol, .max_disp = max_disp,
                    .drop = VS_LOAD_DROP, .follow = 0.0, .newton_tol = 1e-9,
                    .newton_maxiter = 20};
  return o;
}

static vs_path_opts popts(void) {
  vs_path_opts p = {.step = 1e-4, .step_max = 1e-3, .limit_tol = 1e-7, .max_delta = 1e-3,
                    .newton_tol = 1e-9, .newton_maxiter = 20};
  return p;
}

/* The model of g with law (kn, ks = kn / 2, mu), at its self-weight equilibrium in q. */
static vs_model *at_rest(const vs_geometry *g, double kn, double mu, double **q) {
  vs_error err;
  vs_error_clear(&err);
  const vs_joint_law law = {.kn = kn, .ks = 0.5 * kn, .mu = mu};
  vs_model *m = NULL;
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  *q = calloc((size_t)vs_model_size(m), sizeof **q);
  const vs_path_opts p = popts();
  long it = 0;
  if (vs_equilibrium_solve(m, &p, 0.0, *q, &it, &err) != VS_OK) fail_msg("%s", err.msg);
  return m;
}

static void run_load(vs_model *m, const vs_load_opts *o, double *q, vs_load_result *r) {
  vs_error err;
  vs_error_clear(&err);
  if (vs_load_path_run(m, o, 0.0, q, NULL, NULL, r, &err) != VS_OK) fail_msg("%s", err.msg);
}

/* A squat block (b = 0.4 m, h = 0.1 m: it would tip at lambda = b / h = 4) pushed sideways at
 * its centroid by P = 10 N: it slides at lambda = mu W / P, and the path ends sliding. */
static void test_block_slides(void **state) {
  (void)state;
  const double mass = 2.0, mu = 0.3, P = 10.0;
  vs_geometry *g = column(1, 0.4, 0.1, mass);
  double *q = NULL;
  vs_model *m = at_rest(g, 1e9, mu, &q);
  const vs_model_force f = {.block = 0, .fx = P, .fz = 0.0, .px = 0.2, .pz = 0.05};
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_model_set_loads(m, &f, 1, &err), VS_OK);
  const vs_load_opts o = opts(1e-6, 1e-4, 1e-9, 0.05);
  vs_load_result r;
  run_load(m, &o, q, &r);
  const double hand = mu * mass * 9.81 / P;
  print_message("block: lambda %.12f, by hand mu W / P = %.12f; end %d after %ld steps, slid "
                "%.6g mm\n",
                r.lambda_peak, hand, r.end, r.steps, (r.u_last - r.u_start) / VS_MM);
  near(r.lambda_peak, hand, 1e-6 * hand); /* the plateau's test: to 1e-6 */
  assert_int_equal(r.end, VS_LOAD_END_SLIDING);
  near(vs_model_slips(m)[0], q[0], 1e-6); /* the slip is the block's motion, less its elastic shear */
  free(q);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* Two blocks b = 0.2 m by h = 0.3 m, tilted; mu = 2 (no sliding): the rigid column overturns
 * about the base's downhill edge at lambda = b / H, H = 2 h. On elastic no-tension joints
 * (k_n per unit area, depth d) it rocks earlier, by hand: turned by theta, the base touches
 * over c = sqrt(2 W / (k_n d theta)) with its resultant c / 3 from the edge, and the weight's
 * arm shrinks by theta H / 2, so lambda = (b/2 - c/3 - theta H/2) / (H/2), largest at
 * theta = (sqrt(2 W / (k_n d)) / (3 H))^(2/3): the gap to b / H falls as k_n^(-1/3). */
static double rocking_gap(double W, double kd, double b, double H) {
  const double a = sqrt(2.0 * W / kd), th = pow(a / (3.0 * H), 2.0 / 3.0);
  const double c = a / sqrt(th);
  return (c / 3.0 + th * H / 2.0) / (b / 2.0);
}

static void test_column_tilt(void **state) {
  (void)state;
  const double b = 0.2, h = 0.3, mass = 5.0, hand = b / (2.0 * h);
  double prev = 0.0;
  const double kn[] = {1e7, 1e9, 1e11, 1e13};
  for (size_t i = 0; i < sizeof kn / sizeof kn[0]; i++) {
    vs_geometry *g = column(2, b, h, mass);
    double *q = NULL;
    vs_model *m = at_rest(g, kn[i], 2.0, &q);
    vs_limit_force *lf = NULL;
    int nf = 0;
    vs_error err;
    vs_error_clear(&err);
    const vs_load_def tilt = {.kind = VS_LOAD_TILT};
    assert_int_equal(vs_limit_live_load(g, &tilt, NULL, &lf, &nf, &err), VS_OK);
    vs_model_force f[2];
    for (int k = 0; k < nf; k++)
      f[k] = (vs_model_force){lf[k].block, lf[k].fx, lf[k].fz, lf[k].px, lf[k].pz};
    assert_int_equal(vs_model_set_loads(m, f, nf, &err), VS_OK);
    const vs_load_opts o = opts(1e-6, 1e-3, 1e-10, 0.05);
    vs_load_result r;
    run_load(m, &o, q, &r);
    const double gap = 1.0 - r.lambda_peak / hand, by_hand = rocking_gap(2.0 * mass * 9.81, kn[i], b, 2.0 * h);
    print_message("column, k_n %.0e N/m^3: lambda %.10f (b / H = %.10f), %.4f %% below; rocking "
                  "on the elastic base by hand %.4f %%; end %d, %ld steps\n",
                  kn[i], r.lambda_peak, hand, 100.0 * gap, 100.0 * by_hand, r.end, r.steps);
    if (r.end != VS_LOAD_END_PEAK) fail_msg("end %d: %s", r.end, r.cause);
    assert_true(r.lambda_peak > prev);
    prev = r.lambda_peak;
    if (kn[i] >= 1e11) near(gap, by_hand, 0.1 * by_hand); /* asymptotics: small c and theta */
    free(lf);
    free(q);
    vs_model_destroy(&m);
    vs_geometry_destroy(&g);
  }
}

/* The reference specimen, 1 N at quarter span: lambda from the path for k_n rising against
 * the limit analysis (CLP): monotone, within 1 % at k_n = 1e5 N/mm^3 (issue 28), the gap's
 * log-log slope near the elastic hinge's -1/3 (runs/load_convergence.sh has the table). With the
 * stiffest point, 1e5, the whole of test_load takes 1 s in Release, 3 s under the sanitizers. */
static void test_reference_converges(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.kind = VS_LOAD_POINT;
  c.x_mm = 0.25 * vs_case_span_mm(&c);
  c.value_N = 1.0;
  vs_run_def d;
  vs_case_to_def(&c, &d);
  vs_error err;
  vs_error_clear(&err);
  vs_limit_analysis a;
  assert_int_equal(vs_limit_analyse(&d, NULL, &a, &err), VS_OK);
  const double clp = a.collapse.value;
  vs_limit_analysis_free(&a);
  const double kn[] = {3.0, 30.0, 300.0, 1e4, 1e5}; /* N/mm^3 */
  double prev = 0.0, gap = NAN, gap300 = NAN, gap1e4 = NAN;
  for (size_t i = 0; i < sizeof kn / sizeof kn[0]; i++) {
    vs_geometry *g = NULL;
    assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
    double *q = NULL;
    vs_model *m = at_rest(g, kn[i] * 1e9, c.friction, &q);
    vs_limit_force *lf = NULL;
    int nf = 0;
    assert_int_equal(vs_limit_live_load(g, &d.load, NULL, &lf, &nf, &err), VS_OK);
    assert_int_equal(nf, 1);
    const vs_model_force f = {lf[0].block, lf[0].fx, lf[0].fz, lf[0].px, lf[0].pz};
    assert_int_equal(vs_model_set_loads(m, &f, 1, &err), VS_OK);
    const vs_load_opts o = opts(1e-5, 5e-4, 1e-8, 0.05);
    vs_load_result r;
    run_load(m, &o, q, &r);
    gap = 1.0 - r.lambda_peak / clp;
    if (kn[i] == 300.0) gap300 = gap;
    if (kn[i] == 1e4) gap1e4 = gap;
    print_message("reference, 1 N at L/4, k_n %g N/mm^3: lambda %.6f (CLP %.6f, %.3f %% below), "
                  "deflection at the peak %.4f mm, end %d, %ld steps %ld rejected\n",
                  kn[i], r.lambda_peak, clp, 100.0 * gap, (r.u_peak - r.u_start) / VS_MM, r.end,
                  r.steps, r.rejected);
    if (r.end != VS_LOAD_END_PEAK) fail_msg("end %d: %s", r.end, r.cause);
    assert_true(r.lambda_peak > prev);
    prev = r.lambda_peak;
    free(lf);
    free(q);
    vs_model_destroy(&m);
    vs_geometry_destroy(&g);
  }
  /* the hinges of elastic no-tension joints sit c/3 inside the edge, c ~ k_n^(-1/3) (the column
   * above): the gap shrinks as k_n^(-1/3), 2 % at k_n = 1e4 N/mm^3 on voussoirs this small,
   * 1 % near 5e4 (the joints' forces there above their round-off floor, within its margin) */
  const double scaled = gap300 * cbrt(300.0 / 1e4);
  print_message("gap at 1e4: %.3f %%; from 300 by k_n^(-1/3): %.3f %%\n", 100.0 * gap1e4,
                100.0 * scaled);
  assert_true(gap1e4 > 0.0 && gap1e4 < 0.02);
  near(gap1e4, scaled, 0.15 * scaled);
  /* issue 28: within 1 % at the stiffest, 1e5; from 1e4 to 1e5 the slope on log-log is the
   * elastic hinge's -1/3 but for the law's higher-order terms (-0.35 measured; they fade as k_n
   * grows: -0.34 from 3e5 to 1e6 in runs/load_convergence.sh) */
  const double slope = log(gap / gap1e4) / log(1e5 / 1e4);
  print_message("gap at 1e5: %.3f %%; log-log slope from 1e4: %.4f (elastic hinge: -1/3)\n",
                100.0 * gap, slope);
  assert_true(gap > 0.0 && gap < 0.01);
  near(slope, -1.0 / 3.0, 0.04);
}

/* The load factor of the reference specimen, 1 N at quarter span, after the right support has
 * settled by hold (mm) and been held: the case, the run, its load result. */
static double residual(double hold_mm, double alpha_deg, vs_run_load_result *out) {
  vs_case c;
  vs_case_defaults(&c);
  c.type = VS_ANALYSIS_LOAD;
  c.kind = VS_LOAD_POINT;
  c.x_mm = 0.25 * vs_case_span_mm(&c);
  c.hold_mm = hold_mm;
  c.alpha_deg = alpha_deg;
  vs_error err;
  vs_error_clear(&err);
  if (vs_case_validate(&c, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_run *r = NULL;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_run_load_result *l = vs_run_load(r);
  assert_true(l->done);
  assert_true(l->n >= 3);
  assert_true(l->lambda[0] == 0.0 && l->u[0] == 0.0); /* the curve starts where loading began */
  near(l->hold, hold_mm * VS_MM, 1e-12);
  *out = *l;
  out->lambda = out->u = NULL; /* owned by the run */
  const double lf = l->load_factor;
  vs_run_destroy(&r);
  return lf;
}

/* analysis.hold_mm: the residual capacity falls as the support settles (alpha = 0) or spreads
 * (90), before the snap-throughs of its path; the mechanism has four hinges. */
static void test_hold(void **state) {
  (void)state;
  /* spreading meets its first snap-through at 9.58 mm: holds before it */
  const double holds[2][3] = {{0.0, 10.0, 20.0}, {0.0, 4.0, 8.0}};
  for (int a = 0; a <= 90; a += 90) {
    double prev = INFINITY;
    for (size_t i = 0; i < 3; i++) {
      vs_run_load_result l;
      const double lf = residual(holds[a / 90][i], a, &l);
      print_message("alpha %d, hold %4.1f mm: load factor %.5f, deflection %.4f mm, end %d, %s\n",
                    a, holds[a / 90][i], lf, l.deflection / VS_MM, l.end, l.mechanism);
      assert_int_equal(l.end, VS_LOAD_END_PEAK);
      assert_true(lf < prev);
      prev = lf;
    }
  }
}

/* The case's rules: a load path needs a live load, a hold needs a load path. */
static void test_case_rules(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  c.type = VS_ANALYSIS_LOAD;
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "load.kind"));
  vs_case_defaults(&c);
  c.hold_mm = 5.0;
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "analysis.hold_mm"));
  vs_case_defaults(&c);
  c.type = VS_ANALYSIS_LOAD;
  c.kind = VS_LOAD_TILT;
  c.hold_mm = c.max_mm;
  assert_int_equal(vs_case_validate(&c, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "support.max_mm"));
  c.hold_mm = 0.0;
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  assert_int_equal(vs_case_check_path(&c, "sweep", &err), VS_OK);
  assert_int_equal(vs_case_check_path(&c, "calibrate", &err), VS_ERR_INVALID);
}

/* The loads' part of the analytic Jacobian (J at lambda = 1 less J at lambda = 0) against
 * central differences of their part of the residual, at a turned state: forces off their
 * blocks' centroids turn their arms with the blocks; and their energy's gradient is minus the
 * load vector. */
static void test_jacobian(void **state) {
  (void)state;
  vs_geometry *g = column(2, 0.2, 0.3, 5.0);
  double *q = NULL;
  vs_model *m = at_rest(g, 1e9, 0.7, &q);
  const vs_model_force f[3] = {{0, 3.0, -7.0, 0.05, 0.27}, {1, -2.0, 4.0, 0.18, 0.4},
                               {1, 1.5, 0.0, 0.02, 0.59}};
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_model_set_loads(m, f, 3, &err), VS_OK);
  const int n = vs_model_size(m);
  q[2] += 0.3, q[5] -= 0.2; /* turned far: the arms matter */
  SUNContext ctx = NULL;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix J0 = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  SUNMatrix J1 = SUNSparseMatrix(n, n, vs_model_nnz(m), CSC_MAT, ctx);
  vs_model_set_load_factor(m, 0.0);
  vs_model_jacobian(m, q, 0.0, J0);
  vs_model_set_load_factor(m, 1.0);
  vs_model_jacobian(m, q, 0.0, J1);
  double *gp = calloc((size_t)n, sizeof *gp), *gm = calloc((size_t)n, sizeof *gm);
  double *hp = calloc((size_t)n, sizeof *hp), *hm = calloc((size_t)n, sizeof *hm);
  double *lv = calloc((size_t)n, sizeof *lv);
  const double h = 1e-6;
  double worst = 0.0, big = 0.0;
  for (int j = 0; j < n; j++) {
    const double qj = q[j];
    q[j] = qj + h;
    vs_model_set_load_factor(m, 1.0), vs_model_residual(m, q, 0.0, gp);
    vs_model_set_load_factor(m, 0.0), vs_model_residual(m, q, 0.0, hp);
    const double ep = vs_model_load_displacement(m, q);
    q[j] = qj - h;
    vs_model_set_load_factor(m, 1.0), vs_model_residual(m, q, 0.0, gm);
    vs_model_set_load_factor(m, 0.0), vs_model_residual(m, q, 0.0, hm);
    const double em = vs_model_load_displacement(m, q);
    q[j] = qj;
    for (int i = 0; i < n; i++) {
      const double fd = ((gp[i] - hp[i]) - (gm[i] - hm[i])) / (2.0 * h);
      double a1 = 0.0, a0 = 0.0;
      const sunindextype *cp1 = SUNSparseMatrix_IndexPointers(J1), *rv1 = SUNSparseMatrix_IndexValues(J1);
      for (sunindextype p = cp1[j]; p < cp1[j + 1]; p++)
        if (rv1[p] == i) a1 = SUNSparseMatrix_Data(J1)[p];
      const sunindextype *cp0 = SUNSparseMatrix_IndexPointers(J0), *rv0 = SUNSparseMatrix_IndexValues(J0);
      for (sunindextype p = cp0[j]; p < cp0[j + 1]; p++)
        if (rv0[p] == i) a0 = SUNSparseMatrix_Data(J0)[p];
      worst = fmax(worst, fabs((a1 - a0) - fd));
      big = fmax(big, fabs(a1 - a0));
    }
    /* the pilot's gradient is the load vector over the loads' size */
    vs_model_load_vector(m, q, lv);
    near((ep - em) / (2.0 * h), lv[j] / vs_model_load_size(m), 1e-6);
  }
  /* the joints' forces at so turned a state (1e7 N) leave a rounding of eps 1e7 / h ~ 1e-3 in
   * each difference, less where they cancel */
  print_message("loads' Jacobian against central differences: largest error %.3g (largest "
                "entry %.3g)\n", worst, big);
  assert_true(big > 0.5);
  assert_true(worst < 1e-4 * big);
  free(gp), free(gm), free(hp), free(hm), free(lv);
  SUNMatDestroy(J0), SUNMatDestroy(J1);
  SUNContext_Free(&ctx);
  free(q);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* The command line: the reference specimen tilted to collapse (its load factor below the limit
 * analysis' 0.368, by the elastic hinges), in the JSON and the summary (the curve); bad input
 * refused, exit 2, nothing written. */
static void test_cli(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=tilt --json "
           "--no-record >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  const char *j = slurp(in_dir("out.txt"), NULL);
  assert_non_null(strstr(j, "\"status\":\"collapse\""));
  const char *p = strstr(j, "\"load_factor\":");
  assert_non_null(p);
  const double lf = strtod(p + strlen("\"load_factor\":"), NULL);
  print_message("reference under tilt: load factor %.5f (limit analysis 0.368)\n", lf);
  assert_true(lf > 0.2 && lf < 0.368);
  assert_non_null(strstr(j, "\"curve\":{\"load_factor\":[0,"));
  /* the record has the same load factor and curve (one point per comma in the JSON's list) */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=tilt -o r.h5 "
           ">out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  const char *c0 = strstr(j, "\"curve\":{\"load_factor\":[");
  int points = 1;
  for (const char *k = c0 + 24; *k != ']'; k++) points += *k == ',';
  hid_t f = H5Fopen(in_dir("r.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t d = H5Dopen2(f, "/summary/load/curve", H5P_DEFAULT);
  hid_t sp = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  assert_int_equal(H5Sget_simple_extent_dims(sp, dims, NULL), 2);
  assert_int_equal((int)dims[0], points);
  assert_int_equal((int)dims[1], 2);
  double lf_rec = NAN;
  hid_t s1 = H5Dopen2(f, "/summary/load/load_factor", H5P_DEFAULT);
  assert_true(H5Dread(s1, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, &lf_rec) >= 0);
  near(lf_rec, lf, 1e-9 * lf);
  H5Dclose(s1), H5Sclose(sp), H5Dclose(d), H5Fclose(f);
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=load --set load.kind=tilt --no-record "
           ">out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  const char *t = slurp(in_dir("out.txt"), NULL);
  assert_non_null(strstr(t, "load factor  lambda = "));
  assert_non_null(strstr(t, "load-deflection curve"));
  const char *bad[] = {"--set analysis.type=load", "--set analysis.hold_mm=5 --set load.kind=tilt",
                       "--set analysis.type=load --set load.kind=tilt --set analysis.hold_mm=300",
                       "--set analysis.type=load --set load.kind=point --set load.x_mm=900"};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(cmd, sizeof cmd, "cd '%s' && rm -f o.h5 && '%s' run '%s' %s -o o.h5 >out.txt 2>err.txt",
             g_dir, VS_BINARY, REFERENCE, bad[i]);
    assert_int_equal(sh(cmd), 2);
    const char *e = slurp(in_dir("err.txt"), NULL);
    print_message("%s: %s", bad[i], e);
    assert_true(strstr(e, "analysis.") != NULL || strstr(e, "load.") != NULL);
    FILE *fo = fopen(in_dir("o.h5"), "r");
    assert_null(fo);
  }
}

/* The fill (vs_limit_fill_load) on the reference specimen against the geometry by hand: over
 * the extrados chords, up to level above the highest chord ends (the crown voussoir's corners,
 * at Re cos(theta / 2) over the centre), its weight is gamma b [(Re cos(theta/2) + level) 2a -
 * (the area under the extrados circle over [-a, a], less the n circular segments the chords cut
 * off, Re^2 / 2 (theta - sin theta) each)], a = Re sin(beta); symmetric about the crown; and the
 * run puts it on the model: the self-weight state then carries it (the supports' vertical
 * reactions are the arch's weight plus the fill's). */
static void test_fill(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.unit_weight_kN_m3 = 18.0;
  vs_run_def d;
  vs_error err;
  vs_error_clear(&err);
  const double PI = acos(-1.0), Re = (c.radius_mm + c.thickness_mm) * 1e-3;
  const double beta = 0.5 * c.embrace_deg * PI / 180.0, th = 2.0 * beta / c.voussoirs;
  const double a = Re * sin(beta), b = c.depth_mm * 1e-3, gamma = c.unit_weight_kN_m3 * 1e3;
  const double under = a * sqrt(Re * Re - a * a) + Re * Re * asin(a / Re) -
                       c.voussoirs * 0.5 * Re * Re * (th - sin(th));
  for (int k = 0; k < 2; k++) {
    c.level_mm = k ? 40.0 : 0.0;
    vs_case_to_def(&c, &d);
    vs_geometry *g = NULL;
    assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
    vs_limit_force *f = NULL;
    int n = 0;
    assert_int_equal(vs_limit_fill_load(g, &d.fill, &f, &n, &err), VS_OK);
    assert_int_equal(n, g->n_blocks - (k == 0)); /* at level 0 none over the crown voussoir */
    double W = 0.0, M = 0.0;
    for (int i = 0; i < n; i++) W -= f[i].fz, M -= f[i].fz * f[i].px;
    const double hand = gamma * b * ((Re * cos(0.5 * th) + d.fill.level) * 2.0 * a - under);
    double x0 = INFINITY, x1 = -INFINITY; /* the extrados' ends: the centre's x between them */
    for (int j = 0; j < g->n_joints; j++) {
      double sx, sz;
      vs_joint_tangent(&g->joints[j], &sx, &sz);
      const double x = g->joints[j].px + 0.5 * g->joints[j].length * sx;
      x0 = fmin(x0, x), x1 = fmax(x1, x);
    }
    print_message("fill 18 kN/m^3 to %g mm above the crown: %.6f N, by hand %.6f N; resultant "
                  "at %.3g mm from the middle\n",
                  c.level_mm, W, hand, (M / W - 0.5 * (x0 + x1)) * 1e3);
    near(W, hand, 1e-9 * hand);
    near(M / W, 0.5 * (x0 + x1), 1e-9);
    free(f);
    vs_geometry_destroy(&g);
    /* the run: the self-weight state carries the fill */
    c.type = VS_ANALYSIS_SUPPORT;
    c.max_mm = 1.0;
    c.step_mm = 0.5;
    vs_run *r = NULL;
    if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
    if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
    const vs_geometry *rg = vs_run_geometry(r);
    double left[2], right[2];
    vs_model_reactions(vs_run_model(r), vs_run_state(r), vs_run_delta(r), left, right);
    const double total = vs_geometry_weight(rg) + hand;
    near(left[1] + right[1], -total, 1e-6 * total); /* the arch pushes down on its supports */
    vs_run_destroy(&r);
  }
}

/* The fill's horizontal pressure (fill.k_horizontal) on the reference specimen against the
 * geometry by hand: on the left half the extrados chords rise from the springing's extrados end
 * (Re cos(beta) over the centre) to the crown voussoir's corner (Re cos(theta/2)), so the
 * pressure K gamma h on their vertical projection adds to K gamma b [h_s^2 - h_c^2] / 2 toward
 * +x, h_c = level and h_s = level + Re (cos(theta/2) - cos(beta)) the depths there, its moment
 * about the surface K gamma b [h_s^3 - h_c^3] / 3 (each chord's resultant at its own pressure
 * diagram's centroid: exact); the right half its mirror image; the net horizontal force zero,
 * also on the model's supports; K = 0 no horizontal force at all. */
static void test_fill_horizontal(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.unit_weight_kN_m3 = 18.0;
  c.level_mm = 40.0;
  vs_error err;
  vs_error_clear(&err);
  const double PI = acos(-1.0), Re = (c.radius_mm + c.thickness_mm) * 1e-3;
  const double beta = 0.5 * c.embrace_deg * PI / 180.0, th = 2.0 * beta / c.voussoirs;
  const double b = c.depth_mm * 1e-3, gamma = c.unit_weight_kN_m3 * 1e3, level = 0.04;
  const double hc = level, hs = level + Re * (cos(0.5 * th) - cos(beta));
  const double Ks[] = {0.0, 0.5, 3.0};
  for (size_t k = 0; k < sizeof Ks / sizeof Ks[0]; k++) {
    c.k_horizontal = Ks[k];
    vs_run_def d;
    vs_case_to_def(&c, &d);
    vs_geometry *g = NULL;
    assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
    vs_limit_force *f = NULL;
    int n = 0;
    assert_int_equal(vs_limit_fill_load(g, &d.fill, &f, &n, &err), VS_OK);
    double top = -INFINITY;
    for (int j = 0; j < g->n_joints; j++) {
      double sx, sz;
      vs_joint_tangent(&g->joints[j], &sx, &sz);
      top = fmax(top, g->joints[j].pz + 0.5 * g->joints[j].length * sz);
    }
    const double S = top + level;
    double HL = 0.0, ML = 0.0, HR = 0.0, net = 0.0;
    int nh = 0;
    for (int i = 0; i < n; i++) {
      if (f[i].fx == 0.0) continue;
      assert_true(f[i].fz == 0.0);
      nh++;
      net += f[i].fx;
      if (f[i].px < 0.0) HL += f[i].fx, ML += f[i].fx * (S - f[i].pz);
      else HR += f[i].fx;
      /* its mirror image: on the mirror block, the opposite force at the mirrored point */
      int m = -1;
      for (int j = 0; j < n; j++)
        if (f[j].block == g->n_blocks - 1 - f[i].block && f[j].fx != 0.0) m = j;
      assert_true(m >= 0);
      near(f[m].fx, -f[i].fx, 1e-9 * fabs(f[i].fx));
      near(f[m].px, -f[i].px, 1e-12);
      near(f[m].pz, f[i].pz, 1e-12);
    }
    const double K = Ks[k], H = K * gamma * b * 0.5 * (hs * hs - hc * hc);
    const double M = K * gamma * b * (hs * hs * hs - hc * hc * hc) / 3.0;
    print_message("fill K = %g: left half %.6f N toward the crown, by hand %.6f N; moment about "
                  "the surface %.6f N m, by hand %.6f N m; net %.3g N\n",
                  K, HL, H, ML, M, net);
    if (K == 0.0) assert_int_equal(nh, 0);
    else assert_int_equal(nh, g->n_blocks - 1); /* none on the crown voussoir's level chord */
    near(HL, H, 1e-9 * fmax(H, 1.0));
    near(HR, -H, 1e-9 * fmax(H, 1.0));
    near(ML, M, 1e-9 * fmax(M, 1.0));
    near(net, 0.0, 1e-9 * fmax(H, 1.0));
    free(f);
    vs_geometry_destroy(&g);
  }
  /* the run: the supports' horizontal reactions balance (the net fill force is zero) and the
   * limit analysis solves with it (K = 3 squeezes the haunches in: the arch cannot stand) */
  c.k_horizontal = 0.5;
  c.type = VS_ANALYSIS_SUPPORT;
  c.max_mm = 1.0;
  c.step_mm = 0.5;
  vs_run *r = NULL;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  double left[2], right[2];
  vs_model_reactions(vs_run_model(r), vs_run_state(r), vs_run_delta(r), left, right);
  near(left[0] + right[0], 0.0, 1e-9 * fabs(left[0]));
  vs_run_destroy(&r);
  /* a negative coefficient through the library: refused, naming the key */
  vs_run_def d;
  vs_case_to_def(&c, &d);
  d.fill.k_horizontal = -1.0;
  vs_geometry *g = NULL;
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
  vs_limit_force *f = NULL;
  int n = 0;
  assert_int_equal(vs_limit_fill_load(g, &d.fill, &f, &n, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "fill.k_horizontal = -1"));
  vs_geometry_destroy(&g);
}

/* A live load spread through the fill (load.spread_deg) on the reference specimen against the
 * geometry by hand: the fill's depth over the extrados chord at x (the chords between the
 * joints' extrados ends Re (sin phi_j, cos phi_j), phi_j = -beta + j theta) under the surface
 * level above the crown voussoir's corners; the load uniform over w = width + 2 h tan(angle):
 * the shares add to the load, a voussoir wholly under it carries value x its chord's width / w,
 * the first share's part starts at x - w/2; spread 0 puts the load exactly as without. */
static void test_spread(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.level_mm = 100.0;
  vs_run_def d;
  vs_case_to_def(&c, &d);
  vs_error err;
  vs_error_clear(&err);
  const double PI = acos(-1.0), Re = (c.radius_mm + c.thickness_mm) * 1e-3;
  const double beta = 0.5 * c.embrace_deg * PI / 180.0, th = 2.0 * beta / c.voussoirs;
  const double x0 = -c.radius_mm * 1e-3 * sin(beta); /* the left springing's intrados point */
  vs_geometry *g = NULL;
  assert_int_equal(vs_geometry_create_arch(&d.arch, &g, &err), VS_OK);
  const double xs[] = {0.2, 0.29, 0.37};
  const vs_load_kind kinds[] = {VS_LOAD_POINT, VS_LOAD_LINE, VS_LOAD_PATCH};
  for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
    vs_load_def ld = {.kind = kinds[i], .value = 10.0, .x = xs[i], .width = 0.03 * (i == 2)};
    /* spread 0: exactly the load without spread */
    vs_limit_force *f0 = NULL, *f1 = NULL;
    int n0 = 0, n1 = 0;
    assert_int_equal(vs_limit_live_load(g, &ld, NULL, &f0, &n0, &err), VS_OK);
    assert_int_equal(vs_limit_live_load(g, &ld, &d.fill, &f1, &n1, &err), VS_OK);
    assert_int_equal(n0, n1);
    for (int k = 0; k < n0; k++)
      assert_true(f0[k].block == f1[k].block && f0[k].fx == f1[k].fx && f0[k].fz == f1[k].fz &&
                  f0[k].px == f1[k].px && f0[k].pz == f1[k].pz);
    free(f0), free(f1);
    /* spread 30 deg */
    ld.spread = 30.0 * PI / 180.0;
    vs_limit_force *f = NULL;
    int n = 0;
    assert_int_equal(vs_limit_live_load(g, &ld, &d.fill, &f, &n, &err), VS_OK);
    const double x = x0 + xs[i];
    int j = 0;
    while (Re * sin(-beta + (j + 1) * th) < x) j++;
    const double xa = Re * sin(-beta + j * th), za = Re * cos(-beta + j * th);
    const double xb = Re * sin(-beta + (j + 1) * th), zb = Re * cos(-beta + (j + 1) * th);
    const double h = Re * cos(0.5 * th) + 0.1 - (za + (x - xa) / (xb - xa) * (zb - za));
    const double w = ld.width + 2.0 * h * tan(ld.spread);
    double sum = 0.0, moment = 0.0;
    for (int k = 0; k < n; k++) sum += f[k].fz, moment += f[k].fz * f[k].px;
    int at = -1;
    for (int k = 0; k < n; k++)
      if (f[k].block == j) at = k;
    assert_true(at >= 0);
    const double w_at = 10.0 * (xb - xa) / -f[at].fz;
    const double start = 2.0 * f[0].px - Re * sin(-beta + (f[0].block + 1) * th);
    print_message("%s at %g mm spread 30 deg through %.2f mm of fill: %d shares, total %.9f N, "
                  "width %.6f mm (by hand %.6f), from %.6f mm (by hand %.6f)\n",
                  vs_load_kind_name(ld.kind), xs[i] * 1e3, h * 1e3, n, -sum, w_at * 1e3, w * 1e3,
                  (start - x0) * 1e3, (x - 0.5 * w - x0) * 1e3);
    near(sum, -10.0, 1e-12);
    near(w_at, w, 1e-9);
    near(start, x - 0.5 * w, 1e-9);
    assert_true(n >= 3);
    free(f);
  }
  /* near the springing the part beyond the extrados goes into the ground: less on the arch */
  const vs_load_def edge = {.kind = VS_LOAD_POINT, .value = 10.0, .x = 0.01, .spread = 0.5};
  vs_limit_force *f = NULL;
  int n = 0;
  assert_int_equal(vs_limit_live_load(g, &edge, &d.fill, &f, &n, &err), VS_OK);
  double sum = 0.0;
  for (int k = 0; k < n; k++) sum -= f[k].fz;
  assert_true(sum > 0.0 && sum < 10.0);
  free(f);
  const vs_load_def steep = {.kind = VS_LOAD_POINT, .value = 1.0, .x = 0.2, .spread = 1.5};
  assert_int_equal(vs_limit_live_load(g, &steep, &d.fill, &f, &n, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "load.spread_deg"));
  vs_geometry_destroy(&g);
  /* the limit analysis: a point load spread over several voussoirs names none; spread 0 the
   * voussoir under it; the spread load carries more (it reaches more voussoirs) */
  d.load = (vs_load_def){.kind = VS_LOAD_POINT, .value = 1.0, .x = 0.133};
  vs_limit_analysis a0, a1;
  assert_int_equal(vs_limit_analyse(&d, NULL, &a0, &err), VS_OK);
  d.load.spread = 30.0 * PI / 180.0;
  assert_int_equal(vs_limit_analyse(&d, NULL, &a1, &err), VS_OK);
  assert_true(a0.load_block >= 0 && a1.load_block == -1);
  assert_true(a1.collapse.value > a0.collapse.value);
  vs_limit_analysis_free(&a0);
  vs_limit_analysis_free(&a1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_block_slides),
      cmocka_unit_test(test_column_tilt),
      cmocka_unit_test(test_reference_converges),
      cmocka_unit_test(test_hold),
      cmocka_unit_test(test_case_rules),
      cmocka_unit_test(test_jacobian),
      cmocka_unit_test(test_cli),
      cmocka_unit_test(test_fill),
      cmocka_unit_test(test_fill_horizontal),
      cmocka_unit_test(test_spread),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
