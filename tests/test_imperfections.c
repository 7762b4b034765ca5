/* Tests of the imperfections (imperfections.h): zero amplitudes give the perfect arch bit for bit;
 * the lognormal draws have the mean, CoV and correlation they are defined with (statistical
 * bounds); a joint with a tilted face closes (opens) at the closed-form load; the tangent of a
 * joint with an initial gap agrees with central differences; the scattered arch still closes. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "joint_reference.h"
#include "voussoir/imperfections.h"
#include "voussoir/joint.h"
#include "voussoir/run.h"
#include "voussoir/units.h"

/* The imperfections case c asks for (on its arch). */
static vs_status draw(const vs_case *c, vs_imperfections **p, vs_error *err) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  return vs_imperfections_draw(&d.imperfections, &d.arch, p, err);
}

static void set(vs_case *c, const char *a) {
  vs_error err;
  if (vs_case_set(c, a, &err) != VS_OK) fail_msg("%s: %s", a, err.msg);
}

/* Run case c to the first limit point; return its delta (m) and copy the final state into q. */
static double first_limit(const vs_case *c, double *q, int n) {
  vs_run *r = NULL;
  vs_error err;
  if (vs_run_create(c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  assert_int_equal(vs_model_size(vs_run_model(r)), n);
  memcpy(q, vs_run_state(r), (size_t)n * sizeof *q);
  double d = vs_run_path(r)->delta_limit;
  vs_run_destroy(&r);
  return d;
}

/* Every imperfection at zero amplitude (other seed, sample and a correlation length set) gives
 * exactly the perfect arch's path; a non-zero amplitude of each changes it (the test can fail). */
static void test_zero_amplitude_is_perfect(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.follow = 0;
  const int n = 3 * c.voussoirs;
  double q0[3 * 55], q1[3 * 55];
  const double d0 = first_limit(&c, q0, n);
  vs_case z = c;
  set(&z, "imperfections.seed=987654");
  set(&z, "imperfections.sample=41");
  set(&z, "imperfections.kn_corr_mm=120");
  const double d1 = first_limit(&z, q1, n);
  assert_true(d0 == d1);
  assert_memory_equal(q0, q1, sizeof(double) * (size_t)n);
  const char *each[] = {"imperfections.kn_cov=0.2", "imperfections.face_mm=0.002",
                        "imperfections.angle_cov=0.05", "imperfections.thickness_cov=0.05",
                        "imperfections.support_dx_mm=0.5", "imperfections.support_dz_mm=0.5"};
  for (size_t i = 0; i < sizeof each / sizeof each[0]; i++) {
    vs_case w = z;
    set(&w, each[i]);
    const double d2 = first_limit(&w, q1, n);
    if (d2 == d0) fail_msg("%s: first limit point unchanged (%.17g m)", each[i], d0);
  }
}

/* Lognormal k_n factors: mean 1 and CoV kn_cov, their logs normal with sd sqrt(ln(1 + CoV^2)),
 * within 5 standard errors over 4000 samples x 56 joints; with a correlation length, the lag-1
 * correlation of the logs is exp(-spacing / l_c). */
static void test_lognormal_moments(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  const double cov = 0.3, s2 = log1p(cov * cov);
  set(&c, "imperfections.kn_cov=0.3");
  double sum = 0, sum2 = 0, sl = 0, sl2 = 0;
  double n = 0;
  for (int smp = 0; smp < 4000; smp++) {
    c.sample = smp;
    vs_imperfections *p = NULL;
    vs_error err;
    assert_int_equal(draw(&c, &p, &err), VS_OK);
    for (int k = 0; k < p->n_joints; k++, n++) {
      const double f = p->kn_factor[k], l = log(f);
      sum += f;
      sum2 += f * f;
      sl += l;
      sl2 += l * l;
    }
    vs_imperfections_destroy(&p);
  }
  const double mean = sum / n, sd = sqrt(sum2 / n - mean * mean);
  const double lmean = sl / n, lsd = sqrt(sl2 / n - lmean * lmean);
  const double se_mean = cov / sqrt(n);
  if (fabs(mean - 1.0) > 5 * se_mean) fail_msg("mean %.6f (5 se %.2g)", mean, 5 * se_mean);
  /* sd of a sample sd ~ sd sqrt((kurtosis - 1) / 4n); the lognormal's kurtosis at CoV 0.3 < 6 */
  const double se_sd = cov * sqrt(5.0 / (4.0 * n));
  if (fabs(sd - cov) > 5 * se_sd) fail_msg("CoV %.6f (5 se %.2g)", sd, 5 * se_sd);
  if (fabs(lmean + 0.5 * s2) > 5 * sqrt(s2 / n)) fail_msg("log mean %.6f", lmean);
  if (fabs(lsd - sqrt(s2)) > 5 * sqrt(s2 / (2.0 * n))) fail_msg("log sd %.6f", lsd);

  /* correlation: l_c equal to twice the joint spacing gives rho = exp(-1/2) */
  const double ds = (c.radius_mm + 0.5 * c.thickness_mm) * c.embrace_deg * VS_DEG / c.voussoirs;
  char a[64];
  snprintf(a, sizeof a, "imperfections.kn_corr_mm=%.17g", 2.0 * ds);
  set(&c, a);
  double sxy = 0, sxx = 0;
  double m = 0;
  for (int smp = 0; smp < 4000; smp++) {
    c.sample = smp;
    vs_imperfections *p = NULL;
    vs_error err;
    assert_int_equal(draw(&c, &p, &err), VS_OK);
    for (int k = 1; k < p->n_joints; k++, m++) {
      const double x = (log(p->kn_factor[k - 1]) + 0.5 * s2) / sqrt(s2);
      const double y = (log(p->kn_factor[k]) + 0.5 * s2) / sqrt(s2);
      sxy += x * y;
      sxx += 0.5 * (x * x + y * y);
    }
    vs_imperfections_destroy(&p);
  }
  const double rho = sxy / sxx, want = exp(-0.5);
  /* neighbouring pairs overlap: allow 5 x the iid standard error times 3 */
  if (fabs(rho - want) > 15.0 * (1 - want * want) / sqrt(m))
    fail_msg("lag-1 correlation %.5f, expected %.5f", rho, want);
}

/* The same (seed, sample) gives the same draws; another sample other draws. */
static void test_draws_depend_on_key_only(void **state) {
  (void)state;
  const double u = vs_rng_uniform(5, 9, 1, 17);
  for (int i = 0; i < 100; i++) (void)vs_rng_uniform(5, (uint64_t)i, 1, 3);
  assert_true(vs_rng_uniform(5, 9, 1, 17) == u);
  assert_true(vs_rng_uniform(5, 10, 1, 17) != u);
  assert_true(vs_rng_uniform(6, 9, 1, 17) != u);
  assert_true(u > 0.0 && u < 1.0);
}

/* A face tilted so that it touches at the intrados and gaps by A at the extrados, pressed
 * without rotation by d: contact over t d / A carrying N = k_n b t d^2 / (2 A) until the far
 * edge touches at d = A, i.e. N* = k_n b t A / 2; beyond, N = k_n b t (d - A/2). Unloading, the
 * joint opens at N*. */
static void test_tilted_face_closed_form(void **state) {
  (void)state;
  const double kn = 48e9, b = 0.12, t = 0.024, A = 0.05e-3;
  const vs_joint_geom jg = {.a = VS_SUPPORT_LEFT, .b = 0, .nz = 1.0, .length = t, .depth = b};
  const vs_joint_law law = {.kn = kn, .ks = 0.5 * kn, .mu = 0.7, .gap0 = 0.5 * A, .gap1 = A / t};
  const double r0[2] = {0, 0}, qa[3] = {0, 0, 0};
  for (int i = 1; i <= 40; i++) {
    const double d = A * i / 20.0;
    const double qb[3] = {0, -d, 0};
    vs_joint_state st;
    vs_test_joint_eval(&jg, &law, qa, qb, r0, r0, 0.0, &st, NULL, NULL);
    const double Nw = d < A ? kn * b * t * d * d / (2 * A) : kn * b * t * (d - 0.5 * A);
    const double cw = d < A ? t * d / A : t;
    if (fabs(st.N - Nw) > 1e-9 * Nw) fail_msg("d = %g: N = %.15g, closed form %.15g", d, st.N, Nw);
    if (fabs(st.contact - cw) > 1e-12) fail_msg("d = %g: contact %.15g, expected %.15g", d, st.contact, cw);
  }
  /* the opening load: full contact just above N*, partial just below */
  const double Nstar = 0.5 * kn * b * t * A;
  for (int sgn = -1; sgn <= 1; sgn += 2) {
    const double N = Nstar * (1 + sgn * 1e-6);
    const double d = N >= Nstar ? N / (kn * b * t) + 0.5 * A : sqrt(2 * A * N / (kn * b * t));
    const double qb[3] = {0, -d, 0};
    vs_joint_state st;
    vs_test_joint_eval(&jg, &law, qa, qb, r0, r0, 0.0, &st, NULL, NULL);
    assert_true(fabs(st.N - N) <= 1e-9 * N);
    if (sgn > 0) assert_true(st.contact == t);
    else assert_true(st.contact < t * (1 - 1e-7));
  }
}

/* The tangent of a joint with an initial gap is the exact derivative of its forces. */
static void test_gap_jacobian_central_differences(void **state) {
  (void)state;
  const double t = 0.024, b = 0.12, kn = 3e9;
  const vs_joint_geom jg = {.a = 0, .b = 1, .px = 0.1, .pz = 0.3, .nx = cos(0.4), .nz = -sin(0.4),
                            .length = t, .depth = b};
  const vs_joint_law law = {.kn = kn, .ks = 0.5 * kn, .mu = 0.7, .gap0 = 1.5e-6, .gap1 = -2e-4};
  const double ra[2] = {-0.005, 0.002}, rb[2] = {0.006, -0.001};
  /* a partly open state and a closed one (penetrations of a few microns, a rotation) */
  const double qs[2][6] = {{1e-6, -2e-6, 1e-4, -3e-6, -1e-6, -2e-4},
                           {2e-6, 1e-6, 0.0, -4e-6, -3e-6, 2e-5}};
  for (int c = 0; c < 2; c++) {
    double K[36], f0[6];
    vs_test_joint_eval(&jg, &law, qs[c], qs[c] + 3, ra, rb, 0.0, NULL, f0, K);
    for (int j = 0; j < 6; j++) {
      double qp[6], qm[6], fp[6], fm[6];
      const double h = j % 3 == 2 ? 1e-9 : 1e-11;
      memcpy(qp, qs[c], sizeof qp);
      memcpy(qm, qs[c], sizeof qm);
      qp[j] += h;
      qm[j] -= h;
      vs_test_joint_eval(&jg, &law, qp, qp + 3, ra, rb, 0.0, NULL, fp, NULL);
      vs_test_joint_eval(&jg, &law, qm, qm + 3, ra, rb, 0.0, NULL, fm, NULL);
      for (int i = 0; i < 6; i++) {
        const double fd = (fp[i] - fm[i]) / (2 * h);
        const double sc = (i % 3 == 2 ? 1.0 / t : 1.0) * (j % 3 == 2 ? t : 1.0);
        if (fabs((K[i * 6 + j] - fd) * sc) > 1e-5 * kn * b * t + 1e-6 * fabs(fd * sc))
          fail_msg("state %d: K[%d][%d] = %.10g, central difference %.10g", c, i, j, K[i * 6 + j], fd);
      }
    }
  }
}

/* Scattered angles still fill the embrace between the springings; a joint is the overlap of its
 * voussoirs' faces. */
static void test_scattered_arch_closes(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  set(&c, "imperfections.angle_cov=0.2");
  set(&c, "imperfections.thickness_cov=0.1");
  vs_imperfections *p = NULL;
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(draw(&c, &p, &err), VS_OK);
  vs_run_def d;
  vs_case_to_def(&c, &d);
  assert_int_equal(vs_imperfections_arch(&d.imperfections, &d.arch, p, &g, &err), VS_OK);
  const double beta = 0.5 * c.embrace_deg * VS_DEG;
  double total = 0;
  int differs = 0;
  for (int i = 0; i < g->n_blocks; i++) {
    total += g->blocks[i].phi1 - g->blocks[i].phi0;
    if (i > 0) assert_true(g->blocks[i].phi0 == g->blocks[i - 1].phi1);
    if (fabs(p->angle[i] - d.arch.embrace / c.voussoirs) > 1e-8) differs++;
  }
  assert_true(g->blocks[0].phi0 == -beta);
  assert_true(g->blocks[g->n_blocks - 1].phi1 == beta);
  assert_true(fabs(total - 2 * beta) < 1e-12);
  assert_true(differs > g->n_blocks / 2);
  for (int k = 0; k < g->n_joints; k++) {
    const double ta = k > 0 ? p->thickness[k - 1] : INFINITY;
    const double tb = k < g->n_blocks ? p->thickness[k] : INFINITY;
    assert_true(fabs(g->joints[k].length - fmin(ta, tb)) < 1e-15);
  }
  vs_geometry_destroy(&g);
  vs_imperfections_destroy(&p);
}

/* A support that stands off by d0 along the loading direction when the weight comes on is the
 * perfect arch's path entered at delta = d0 (the misfit is followed as an equilibrium path): the
 * first limit point comes d0 earlier, within the bisection tolerance of each. */
static void test_support_offset_is_a_head_start(void **state) {
  (void)state;
  const char *dir[2][2] = {{"support.alpha_deg=0", "imperfections.support_dz_mm=5"},
                           {"support.alpha_deg=90", "imperfections.support_dx_mm=3"}};
  const double d0[2] = {5e-3, 3e-3};
  for (int k = 0; k < 2; k++) {
    vs_case c;
    vs_case_defaults(&c);
    c.follow = 0;
    set(&c, dir[k][0]);
    double q[3 * 55];
    const double perfect = first_limit(&c, q, 3 * c.voussoirs);
    set(&c, dir[k][1]);
    const double moved = first_limit(&c, q, 3 * c.voussoirs);
    if (fabs(moved + d0[k] - perfect) > 2 * c.limit_tol_mm * VS_MM)
      fail_msg("%s: first limit %.7g mm, perfect %.7g mm, offset %.3g mm", dir[k][1], moved / VS_MM,
               perfect / VS_MM, d0[k] / VS_MM);
  }
}

/* Mortar as an imperfection: over 2000 samples x 56 joints the debonded share is the asked
 * probability (within 5 binomial standard errors), the f_t factors of the bonded joints and the
 * G_f factors have mean 1 and their CoV (5 standard errors), the other streams are untouched
 * (k_n's factors as without the mortar's scatter); and a run's joint laws are the nominal ones
 * times the factors, a debonded joint dry (f_t = c = 0), every G_f beyond f_t^2 / (2 k_n). */
static void test_mortar_scatter(void **state) {
  (void)state;
  vs_case c, k0;
  vs_case_defaults(&c);
  set(&c, "joints.tensile_MPa=0.002");
  set(&c, "joints.gf_N_mm=0.0002");
  set(&c, "joints.cohesion_MPa=0.001");
  set(&c, "joints.gc_N_mm=0.01");
  set(&c, "imperfections.kn_cov=0.2");
  k0 = c;
  set(&c, "imperfections.tensile_cov=0.4");
  set(&c, "imperfections.gf_cov=0.5");
  set(&c, "imperfections.debonded=0.3");
  double n = 0, off = 0, sf = 0, sf2 = 0, nf = 0, sg = 0, sg2 = 0;
  for (int smp = 0; smp < 2000; smp++) {
    c.sample = k0.sample = smp;
    vs_imperfections *p = NULL, *q = NULL;
    vs_error err;
    assert_int_equal(draw(&c, &p, &err), VS_OK);
    assert_int_equal(draw(&k0, &q, &err), VS_OK);
    assert_memory_equal(p->kn_factor, q->kn_factor, (size_t)p->n_joints * sizeof(double));
    for (int k = 0; k < q->n_joints; k++) assert_true(q->ft_factor[k] == 1.0 && q->gf_factor[k] == 1.0);
    for (int k = 0; k < p->n_joints; k++, n++) {
      const double f = p->ft_factor[k], g = p->gf_factor[k];
      sg += g, sg2 += g * g;
      if (f == 0.0) {
        off++;
        continue;
      }
      sf += f, sf2 += f * f, nf++;
    }
    vs_imperfections_destroy(&p);
    vs_imperfections_destroy(&q);
  }
  const double share = off / n, se = sqrt(0.3 * 0.7 / n);
  if (fabs(share - 0.3) > 5 * se) fail_msg("debonded share %.5f (5 se %.2g)", share, 5 * se);
  const double mf = sf / nf, cf = sqrt(sf2 / nf - mf * mf), mg = sg / n, cg = sqrt(sg2 / n - mg * mg);
  if (fabs(mf - 1) > 5 * 0.4 / sqrt(nf)) fail_msg("f_t factor mean %.5f", mf);
  if (fabs(cf - 0.4) > 5 * 0.4 * sqrt(6.0 / (4.0 * nf))) fail_msg("f_t factor CoV %.5f", cf);
  if (fabs(mg - 1) > 5 * 0.5 / sqrt(n)) fail_msg("G_f factor mean %.5f", mg);
  if (fabs(cg - 0.5) > 5 * 0.5 * sqrt(12.0 / (4.0 * n))) fail_msg("G_f factor CoV %.5f", cg);
  /* the laws of one sample's run */
  c.sample = 7;
  vs_run *r = NULL;
  vs_error err;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_imperfections *p = vs_run_imperfections(r);
  int seen_off = 0;
  for (int k = 0; k < p->n_joints; k++) {
    const vs_joint_law *l = vs_model_joint_law(vs_run_model(r), k);
    const double ft = 0.002 * VS_MPA * p->ft_factor[k], bound = ft * ft / (2 * l->kn);
    CHECK(l->ft, ft, 1e-15, 0);
    if (p->ft_factor[k] == 0.0) {
      seen_off++;
      assert_true(l->ft == 0.0 && l->c == 0.0);
    } else {
      CHECK(l->c, 0.001 * VS_MPA, 1e-15, 0);
      CHECK(l->gf, fmax(0.0002 * VS_N_MM * p->gf_factor[k], bound * 1.000001), 1e-15, 0);
      assert_true(l->gf > bound);
    }
  }
  assert_true(seen_off > 0);
  vs_run_destroy(&r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_draws_depend_on_key_only),
      cmocka_unit_test(test_lognormal_moments),
      cmocka_unit_test(test_mortar_scatter),
      cmocka_unit_test(test_tilted_face_closed_form),
      cmocka_unit_test(test_gap_jacobian_central_differences),
      cmocka_unit_test(test_scattered_arch_closes),
      cmocka_unit_test(test_zero_amplitude_is_perfect),
      cmocka_unit_test(test_support_offset_is_a_head_start),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
