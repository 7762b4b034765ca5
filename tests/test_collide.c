/* Contact between bodies without a joint (collide.h) against independent references:
 *  - its forces are the gradient of its stored energy while the vertices stick, and its analytic
 *    Jacobians dF/dq and dF/dv (coupling the two bodies of a contact) match central
 *    differences, sticking and sliding;
 *  - a block dropped flat on a pier (a support body with an outline) comes to rest on it with
 *    the static penetration m g / (2 k_v) under each of its two bottom vertices, the energy
 *    balance (kinetic + gravity + elastic + dissipated) held throughout;
 *  - two blocks dropped on the pier, the upper one offset so that a vertex of each is inside
 *    the other, come to rest pressed together: no vertex deeper than twice the static
 *    penetration of the pile's weight on two vertices, the energy balance held.
 * The reference run's last state is checked for overlaps in test_contact (it runs it). SI. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "voussoir/dynamic.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"

static const double GRAV = 9.81;
static const double B = 0.2, H = 0.1, DEPTH = 0.1, RHO = 2000.0, KN = 1e10;

/* n (1 or 2) blocks B wide and H high, block i centred on x = 0 with its bottom at z = i H in the
 * reference configuration, each with a joint to the right support given an as-built gap of 1 m
 * (never closing: the blocks are free); the left support is the pier, the slab
 * -0.3 <= x <= 0.3, -0.2 <= z <= 0, with no joint. */
typedef struct {
  vs_geometry *g;
  vs_model *m;
  vs_collide *cl;
  double mass, kv;
} stack;

static void stack_make(stack *s, int n) {
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(n, n, &s->g, &err), VS_OK);
  for (int i = 0; i < n; i++) {
    vs_block *blk = &s->g->blocks[i];
    blk->area = B * H;
    blk->mass = RHO * DEPTH * B * H;
    blk->inertia = blk->mass * (B * B + H * H) / 12.0;
    blk->cz = (i + 0.5) * H;
    s->g->joints[i] = (vs_joint_geom){.a = i, .b = VS_SUPPORT_RIGHT, .px = 0.5 * B,
                                      .pz = (i + 0.5) * H, .nx = 1.0, .nz = 0.0, .length = H,
                                      .depth = DEPTH};
  }
  s->g->gravity = GRAV;
  vs_joint_law law = {.kn = KN, .ks = 0.5 * KN, .mu = 0.7, .gap0 = 1.0};
  assert_int_equal(vs_model_create(s->g, &law, 0.0, &s->m, &err), VS_OK);
  int count[4] = {4, 4, 4, 0};
  double xz[24];
  int k = 0;
  for (int i = 0; i < n; i++) {
    const double z0 = i * H, v[8] = {-0.5 * B, z0, 0.5 * B, z0, 0.5 * B, z0 + H, -0.5 * B, z0 + H};
    memcpy(xz + k, v, sizeof v);
    k += 8;
  }
  const double pier[8] = {-0.3, -0.2, 0.3, -0.2, 0.3, 0.0, -0.3, 0.0};
  memcpy(xz + k, pier, sizeof pier);
  count[n] = 4, count[n + 1] = 0;
  assert_int_equal(vs_collide_create(s->m, 0.5, count, xz, &s->cl, &err), VS_OK);
  s->mass = RHO * DEPTH * B * H;
  s->kv = 0.5 * KN * DEPTH * H;
}

static void stack_free(stack *s) {
  vs_collide_destroy(&s->cl);
  vs_model_destroy(&s->m);
  vs_geometry_destroy(&s->g);
}

static double urand(unsigned *s, double lo, double hi) {
  *s = *s * 1103515245u + 12345u;
  return lo + (hi - lo) * (double)((*s >> 8) & 0xffffff) / (double)0xffffff;
}

/* ------------------------------- 1. forces and Jacobian ------------------------------- */

static int check_jacobian(stack *s, double *q, double *v, int pass) {
  const int ne = vs_model_ext_size(s->m), n = 3 * s->g->n_blocks;
  double *K = calloc((size_t)(ne * ne), sizeof *K), *C = calloc((size_t)(ne * ne), sizeof *C);
  double *Fp = calloc((size_t)ne, sizeof *Fp), *Fm = calloc((size_t)ne, sizeof *Fm);
  double *zv = calloc((size_t)ne, sizeof *zv);
  assert_true(K && C && Fp && Fm && zv);
  vs_collide_jacobian(s->cl, q, zv, K, NULL); /* at v = 0: no dashpot force */
  vs_collide_jacobian(s->cl, q, v, NULL, C);
  int bad = 0;
  for (int j = 0; j < ne; j++) {
    const double hq = (j % 3 == 2) ? 1e-7 / H : 1e-7;
    for (int w = 0; w < 2; w++) {
      double *x = w ? v : q;
      const double x0 = x[j], h = w ? 1e3 * hq : hq;
      memset(Fp, 0, (size_t)ne * sizeof *Fp);
      memset(Fm, 0, (size_t)ne * sizeof *Fm);
      x[j] = x0 + h;
      vs_collide_forces(s->cl, q, w ? v : zv, Fp, NULL, NULL);
      x[j] = x0 - h;
      vs_collide_forces(s->cl, q, w ? v : zv, Fm, NULL, NULL);
      x[j] = x0;
      for (int i = 0; i < ne; i++) {
        const double an = (w ? C : K)[(size_t)j * (size_t)ne + (size_t)i];
        const double fd = (Fp[i] - Fm[i]) / (2 * h);
        const double sc = ((i % 3 == 2) ? 1.0 / H : 1.0) * ((j % 3 == 2) ? H : 1.0);
        const double tol = w ? 1e-6 * fabs(fd * sc) + 1e-3 : 1e-5 * fabs(fd * sc) + 1e-8 * s->kv;
        if (!(fabs(an - fd) * sc <= tol) && bad++ < 10)
          print_message("pass %d %s[%d][%d]: analytic %.10g, differences %.10g\n", pass,
                        w ? "C" : "K", i, j, an, fd);
      }
    }
  }
  (void)n;
  free(K), free(C), free(Fp), free(Fm), free(zv);
  return bad;
}

/* Both blocks and the pier in contact (block 0 sunk 1 mm into the pier, block 1 1 mm into block
 * 0 and offset 30 mm so that block 0's top corner is inside it too), turned and moving a little:
 * pass 0 sticking at the anchors set there, pass 1 moved past the friction cap (sliding). */
static void test_jacobian(void **state) {
  (void)state;
  stack s;
  stack_make(&s, 2);
  const int ne = vs_model_ext_size(s.m);
  double q[12] = {0}, v[12] = {0};
  unsigned seed = 11;
  q[0] = 0.0, q[1] = -1e-3, q[2] = 0.002;
  q[3] = 0.03, q[4] = -2e-3, q[5] = -0.003;
  for (int i = 0; i < 6; i++) v[i] = urand(&seed, -0.1, 0.1);
  assert_int_equal(ne, 12);
  vs_collide_arm(s.cl, q);
  const double pen = vs_collide_max_penetration(s.cl, q);
  print_message("collide jacobian: deepest vertex %.4g mm\n", pen * 1e3);
  assert_true(pen > 0.5e-3 && pen < 2e-3);
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) q[3] += 2e-3, q[0] -= 2e-3; /* beyond mu N / k_t at 1 mm */
    else q[3] += 1e-5;                        /* sticking, springs stretched */
    const int bad = check_jacobian(&s, q, v, pass);
    print_message("collide jacobian pass %d: %d x %d x 2 entries checked, %d off\n", pass, ne, ne,
                  bad);
    assert_int_equal(bad, 0);
    if (pass == 0) { /* sticking: F (at v = 0) is the gradient of the stored energy */
      double F[12] = {0};
      vs_collide_forces(s.cl, q, NULL, F, NULL, NULL);
      double fbig = 0.0;
      for (int j = 0; j < 6; j++) {
        const double h = (j % 3 == 2) ? 1e-7 / H : 1e-7, x0 = q[j];
        q[j] = x0 + h;
        const double ep = vs_collide_energy(s.cl, q);
        q[j] = x0 - h;
        const double em = vs_collide_energy(s.cl, q);
        q[j] = x0;
        fbig = fmax(fbig, fabs(F[j]));
        assert_true(fabs((ep - em) / (2 * h) - F[j]) <= 1e-6 * fabs(F[j]) + 1e-3);
      }
      assert_true(fbig > 1e3); /* the springs are loaded */
    }
  }
  stack_free(&s);
}

/* ------------------------------- 2. dropped on the pier ------------------------------- */

typedef struct {
  double max_bal;
  vs_energy last;
} trace;

static int on_sample(void *user, double t, double delta, const double *q, const double *v,
                     const vs_energy *e) {
  (void)t, (void)delta, (void)q, (void)v;
  trace *tr = user;
  tr->max_bal = fmax(tr->max_bal, fabs(e->balance));
  tr->last = *e;
  return 0;
}

static void drop(stack *s, double *q, double *v, double t_end, trace *tr, vs_dyn_result *res) {
  vs_dyn_opts o;
  memset(&o, 0, sizeof o);
  o.rate = 1e-3;
  o.rtol = 1e-7;
  o.atol_q = 1e-9;
  o.open = 1e-5;
  o.rest_ke = 1e-12;
  o.rest_time = INFINITY;
  o.collapse_ke = 1e30;
  o.max_delta = o.rate * t_end;
  o.sample_dt = 1e-3;
  vs_error err;
  vs_error_clear(&err);
  vs_dynamic *d = NULL;
  assert_int_equal(vs_dynamic_create(s->m, &o, &d, &err), VS_OK);
  assert_int_equal(vs_dynamic_set_collide(d, s->cl, &err), VS_OK);
  double qe[12] = {0};
  memcpy(qe, q, (size_t)(3 * s->g->n_blocks) * sizeof *q);
  vs_collide_arm(s->cl, qe);
  vs_status st = vs_dynamic_run(d, 0.0, q, v, on_sample, NULL, tr, res, &err);
  if (st != VS_OK) fail_msg("vs_dynamic_run: %s: %s", vs_strerror(st), err.msg);
  vs_dynamic_destroy(&d);
}

static void test_drop_on_pier(void **state) {
  (void)state;
  stack s;
  stack_make(&s, 1);
  const double h0 = 0.01;
  double q[3] = {0.0, h0, 0.0}, v[3] = {0.0, 0.0, 0.0};
  trace tr = {0};
  vs_dyn_result res;
  drop(&s, q, v, 0.6, &tr, &res);
  const double ke = 0.5 * s.mass * (v[0] * v[0] + v[1] * v[1]);
  const double p_static = s.mass * GRAV / (2.0 * s.kv), e_in = s.mass * GRAV * h0;
  double qe[9] = {q[0], q[1], q[2]};
  const double pen = vs_collide_max_penetration(s.cl, qe);
  print_message("drop on pier: at %.2f s: kinetic %.3g J, penetration %.4g um (static %.4g um), "
                "largest %.4g um; %ld steps, %ld root events; max |balance| %.3g J (%.3g m g h0), "
                "dashpots %.4g J\n", res.t_end, ke, pen * 1e6, p_static * 1e6,
                res.max_overlap * 1e6, res.steps, res.root_events, tr.max_bal, tr.max_bal / e_in,
                tr.last.damped);
  assert_true(res.root_events >= 4);
  assert_true(ke < 1e-9 * e_in);
  assert_true(fabs(pen - p_static) <= 1e-3 * p_static);
  assert_true(fabs(q[2]) < 1e-9);
  assert_true(tr.max_bal < 1e-3 * e_in);
  assert_true(fabs(tr.last.damped - e_in) < 1e-3 * e_in); /* the dashpots took the drop */
  stack_free(&s);
}

/* Block 0 dropped from h0 on the pier, block 1 from h0 above it and 30 mm to the right: block 1's
 * left bottom corner lands on block 0's top face, block 0's right top corner on block 1's
 * bottom face. */
static void test_two_blocks_pressed(void **state) {
  (void)state;
  stack s;
  stack_make(&s, 2);
  const double h0 = 0.01;
  double q[6] = {0.0, h0, 0.0, 0.03, 2.0 * h0, 0.0}, v[6] = {0};
  trace tr = {0};
  vs_dyn_result res;
  drop(&s, q, v, 1.0, &tr, &res);
  double ke = 0.0;
  for (int i = 0; i < 2; i++)
    ke += 0.5 * s.mass * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1]) +
          0.5 * s.g->blocks[i].inertia * v[3 * i + 2] * v[3 * i + 2];
  const double e_in = s.mass * GRAV * (h0 + 2.0 * h0);
  const double p_pile = 2.0 * s.mass * GRAV / (2.0 * s.kv); /* both blocks on two vertices */
  double qe[12] = {0};
  memcpy(qe, q, sizeof q);
  const double pen = vs_collide_max_penetration(s.cl, qe);
  print_message("two blocks: at %.2f s: kinetic %.3g J, deepest vertex %.4g um (tolerance "
                "2 x %.4g um), largest %.4g um; block 1 at x %.3f mm, gap to block 0 %.4g um; "
                "%ld steps, %ld root events; max |balance| %.3g J (%.3g of the energy in); "
                "friction %.3g J, dashpots %.4g J\n", res.t_end, ke, pen * 1e6, p_pile * 1e6,
                res.max_overlap * 1e6, q[3] * 1e3, (q[4] - q[1]) * 1e6, res.steps,
                res.root_events, tr.max_bal, tr.max_bal / e_in, tr.last.friction,
                tr.last.damped);
  assert_true(ke < 1e-9 * e_in);
  assert_true(pen < 2.0 * p_pile);
  assert_true(pen > 0.5 * p_pile); /* resting on it, not floating */
  /* pressed, not through: block 1 sits on block 0 to the static compressions */
  assert_true(fabs(q[4] - q[1]) < 2.0 * p_pile);
  assert_true(fabs(q[2]) < 1e-3 && fabs(q[5]) < 1e-3);
  assert_true(tr.max_bal < 1e-3 * e_in);
  stack_free(&s);
}

static void test_errors(void **state) {
  (void)state;
  stack s;
  stack_make(&s, 1);
  vs_collide *cl = NULL;
  vs_error err;
  vs_error_clear(&err);
  const int count[3] = {2, 0, 0};
  const double xz[4] = {0.0, 0.0, 1.0, 0.0};
  assert_int_equal(vs_collide_create(s.m, 0.0, NULL, NULL, &cl, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "restitution"));
  assert_int_equal(vs_collide_create(s.m, 0.5, count, xz, &cl, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "body 0"));
  assert_null(cl);
  stack_free(&s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_jacobian),
      cmocka_unit_test(test_drop_on_pier),
      cmocka_unit_test(test_two_blocks_pressed),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
