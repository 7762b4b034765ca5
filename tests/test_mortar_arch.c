/* The mortared reference arch against independent limits: as f_t -> 0 (with the softening's end
 * opening 2 G_f / f_t held) it tends to the dry arch; with a tensile strength far above any
 * stress the settlement causes it neither cracks nor hinges; the cracking energy is G_f times
 * the area cracked through; the dynamic phase's energy balance holds with the cracking in it
 * (and fails without it). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "voussoir/case.h"
#include "voussoir/model.h"
#include "voussoir/run.h"
#include "voussoir/units.h"

/* The reference specimen (the case's defaults), no rigid fall after the collapse. */
static vs_case reference(double ft_MPa, double du_mm) {
  vs_case c;
  vs_case_defaults(&c);
  c.fall_s = 0.0;
  c.tensile_MPa = ft_MPa;
  c.gf_N_mm = 0.5 * ft_MPa * du_mm; /* du = 2 G_f / f_t */
  return c;
}

typedef struct {
  double max_abs_balance; /* largest |balance| over the dynamic phases' samples, J */
  double max_cracking;    /* largest cracking energy of a dynamic phase, J */
  double max_no_crack;    /* largest |balance - cracking|: the balance without it, J */
} dyn_energy;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  (void)run;
  dyn_energy *d = user;
  if (d == NULL || s->phase != VS_PHASE_DYNAMIC || s->energy == NULL) return 0;
  d->max_abs_balance = fmax(d->max_abs_balance, fabs(s->energy->balance));
  d->max_cracking = fmax(d->max_cracking, s->energy->cracking);
  d->max_no_crack = fmax(d->max_no_crack, fabs(s->energy->balance - s->energy->cracking));
  return 0;
}

/* Run c to its end (VS_OK); the run is the caller's to destroy. */
static vs_run *run_case(const vs_case *c, dyn_energy *d) {
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_run_create(c, &r, &err) != VS_OK) fail_msg("create: %s", err.msg);
  if (vs_run_execute(r, on_sample, NULL, d, &err) != VS_OK) fail_msg("run: %s", err.msg);
  return r;
}

static int count_events(const vs_run *r, vs_event_kind kind) {
  int n = 0;
  for (int i = 0; i < vs_run_event_count(r); i++) n += vs_run_event_get(r, i)->kind == kind;
  return n;
}

/* f_t -> 0 at a fixed softening length (du = 0.2 mm): delta_u approaches the dry arch's, its
 * distance shrinking at every halving of f_t, and the mortared arch collapses by the dry
 * arch's mode (I: four hinges E-I-E-E). */
static void test_dry_limit(void **state) {
  (void)state;
  vs_case c = reference(0.0, 0.0);
  vs_run *r = run_case(&c, NULL);
  const double dry = vs_run_collapse(r)->delta;
  assert_true(vs_run_collapse(r)->found);
  assert_int_equal(count_events(r, VS_EVENT_CRACK_INITIATED), 0);
  vs_run_destroy(&r);
  const double ft[3] = {1e-3, 5e-4, 2.5e-4};
  double prev = INFINITY;
  for (int i = 0; i < 3; i++) {
    c = reference(ft[i], 0.2);
    r = run_case(&c, NULL);
    const vs_collapse_record *col = vs_run_collapse(r);
    assert_true(col->found);
    const double diff = fabs(col->delta - dry);
    print_message("f_t %g MPa: delta_u %.4f mm (dry %.4f mm), cracks %d\n", ft[i],
                  col->delta / VS_MM, dry / VS_MM, count_events(r, VS_EVENT_CRACK_INITIATED));
    assert_true(diff < prev);
    assert_true(count_events(r, VS_EVENT_CRACK_INITIATED) > 0);
    assert_string_equal(vs_run_mode(r), "I");
    prev = diff;
    vs_run_destroy(&r);
  }
  assert_true(prev < 0.03 * dry);
}

/* A tensile strength far above any stress: f_t = 20 MPa against the joints' compressive stress
 * of about 0.005 MPa under the arch's weight, and against the largest bending stress a joint
 * can see, k_n w t / 2 <= k_n (t / 2) sin(theta) with the blocks turning by at most a few
 * hundredths of a radian over 60 mm of settlement: 3 N/mm^3 x 12 mm x 0.05 = 1.8 MPa. So no
 * joint cracks, none becomes a hinge and the arch does not collapse; the path is that of an
 * elastic curved beam, and no energy is dissipated by cracking. */
static void test_uncracked_limit(void **state) {
  (void)state;
  vs_case c = reference(20.0, 10.0);
  c.max_mm = 60.0;
  vs_run *r = run_case(&c, NULL);
  assert_false(vs_run_collapse(r)->found);
  assert_int_equal(count_events(r, VS_EVENT_CRACK_INITIATED), 0);
  assert_int_equal(vs_run_hinge_count(r), 0);
  CHECK(vs_model_cracking_energy(vs_run_model(r)), 0.0, 0, 0);
  CHECK(vs_run_delta(r), 60.0 * VS_MM, 1e-12, 0);
  vs_run_destroy(&r);
}

/* The cracking energy of the run is G_f times the area cracked through, joint by joint: the
 * crack lengths of every joint (from each edge, at most the joint's length in all) times the
 * depth and G_f; and the dynamic phases' energy balance holds with the cracking in it, to well
 * within the energy the cracking took there, which the balance without it would miss. */
static void test_cracking_energy_and_balance(void **state) {
  (void)state;
  vs_case c = reference(0.002, 0.2);
  dyn_energy d = {0};
  vs_run *r = run_case(&c, &d);
  const vs_model *m = vs_run_model(r);
  const vs_geometry *g = vs_run_geometry(r);
  double area = 0.0;
  int cracked = 0;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_law *l = vs_model_joint_law(m, k);
    const double len = fmin(g->joints[k].length, l->crack[0] + l->crack[1]);
    area += g->joints[k].depth * len;
    cracked += len > 0.0;
  }
  assert_true(cracked >= 3);
  const double gf = c.gf_N_mm * VS_N_MM;
  CHECK(vs_model_cracking_energy(m), gf * area, 1e-12, 0);
  print_message("cracked joints %d, area %.4g mm^2, cracking %.6g J; dynamic: cracking %.4g J, "
                "|balance| %.3g J, without the cracking %.3g J\n",
                cracked, area / (VS_MM * VS_MM), vs_model_cracking_energy(m), d.max_cracking,
                d.max_abs_balance, d.max_no_crack);
  assert_true(d.max_cracking > 0.0);
  assert_true(d.max_abs_balance < 0.1 * d.max_cracking);
  assert_true(d.max_no_crack > 0.5 * d.max_cracking);
  vs_run_destroy(&r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_dry_limit),
      cmocka_unit_test(test_uncracked_limit),
      cmocka_unit_test(test_cracking_energy_and_balance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
