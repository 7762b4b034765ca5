/* Tests of both supports moving (support.h, docs/model.md "Both supports move") against
 * independent truth: the mirror image (the left support moved as the right one was: the same
 * collapse displacement, the hinges at joints k <-> n + 2 - k with the same sides, the blocks'
 * states mirrored); a rigid translation (both supports moved alike move the arch bodily, nothing
 * else); both supports spreading by d/2 equal one spreading by d (the relative displacement is
 * what the arch feels); symmetric spreading forms a symmetric mechanism; a path that settles
 * then spreads reaches the state of the straight motion to the same support position (the
 * joints are elastic and do not slide here: the equilibrium depends on the supports' position
 * only); a springer turned to the rotation a pinned one takes carries no moment about its
 * pivot; the case keys' errors. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/run.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

static void set(vs_case *c, const char *a) {
  vs_error err;
  if (vs_case_set(c, a, &err) != VS_OK) fail_msg("%s: %s", a, err.msg);
}

/* What a run gives the tests. */
typedef struct {
  int n;                     /* voussoirs */
  double delta;              /* the collapse's (follow) or the first limit point's, m */
  double last_delta;         /* where the run ended, m */
  int n_hinges;              /* at the collapse */
  vs_hinge hinges[16];
  double q[3 * 64];          /* the final state */
  double react[6];           /* the supports' forces on the arch at the end */
} outcome;

static outcome run_case(const vs_case *c) {
  vs_case v = *c;
  vs_error err;
  if (vs_case_validate(&v, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_run *r = NULL;
  if (vs_run_create(&v, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  outcome o = {.n = v.voussoirs};
  const vs_collapse_record *col = vs_run_collapse(r);
  o.delta = v.follow ? (col->found ? col->delta : NAN) : vs_run_path(r)->delta_limit;
  o.last_delta = vs_run_delta(r);
  if (col->found) {
    o.n_hinges = col->n_hinges < 16 ? col->n_hinges : 16;
    memcpy(o.hinges, col->hinges, (size_t)o.n_hinges * sizeof *o.hinges);
  }
  const int nq = vs_model_size(vs_run_model(r));
  assert_true(nq <= 3 * 64);
  memcpy(o.q, vs_run_state(r), (size_t)nq * sizeof *o.q);
  vs_model_support_reactions(vs_run_model(r), o.q, o.last_delta, o.react);
  vs_run_destroy(&r);
  return o;
}

/* Is there a hinge on side `side` over joints [first, last] in o, or, with slack > 0, one
 * whose joints reach within slack joints of that range? */
static int has_hinge(const outcome *o, int first, int last, char side, int slack) {
  for (int i = 0; i < o->n_hinges; i++) {
    const vs_hinge *h = &o->hinges[i];
    if (h->side != side) continue;
    if (slack == 0 ? h->first == first && h->last == last
                   : h->first <= last + slack && h->last >= first - slack)
      return 1;
  }
  return 0;
}

/* Every hinge of a at the mirrored joints of b (k <-> n + 2 - k; within slack joints), the same
 * side, and as many. */
static void assert_hinges_mirrored(const outcome *a, const outcome *b, int slack) {
  assert_true(a->n_hinges >= 4);
  assert_int_equal(a->n_hinges, b->n_hinges);
  const int m = a->n + 2;
  for (int i = 0; i < a->n_hinges; i++) {
    const vs_hinge *h = &a->hinges[i];
    if (!has_hinge(b, m - h->last, m - h->first, h->side, slack))
      fail_msg("hinge %d-%d-%c has no mirror image %d-%d-%c (within %d joints)", h->first,
               h->last, h->side, m - h->last, m - h->first, h->side, slack);
  }
}

/* The reference specimen, quick: stiff joints, follow to the collapse. */
static void reference(vs_case *c, double kn) {
  vs_case_defaults(c);
  c->kn_N_mm3 = kn;
}

/* The left support moved as the right one was, mirrored: the same collapse displacement (delta
 * is the moving support's travel in both), hinges mirrored with the same sides, and at the first
 * limit point the blocks' states mirrored (x -> -x, theta -> -theta, block i <-> n - 1 - i). */
static void test_mirror(void **state) {
  (void)state;
  const double alphas[] = {0.0, 30.0, 90.0};
  for (size_t a = 0; a < sizeof alphas / sizeof alphas[0]; a++) {
    vs_case right, left;
    reference(&right, 3.0);
    right.alpha_deg = alphas[a];
    left = right;
    left.rate_mm_s = 0.0;
    left.left_rate_mm_s = right.rate_mm_s;
    left.left_alpha_deg = alphas[a];
    const outcome r = run_case(&right), l = run_case(&left);
    if (!(fabs(l.delta - r.delta) <= 1e-3 * r.delta))
      fail_msg("alpha %g: collapse at %.9g mm (left moved), %.9g mm (right)", alphas[a],
               l.delta / VS_MM, r.delta / VS_MM);
    assert_hinges_mirrored(&r, &l, 0);
    assert_hinges_mirrored(&l, &r, 0);
    right.follow = left.follow = 0;
    const outcome rf = run_case(&right), lf = run_case(&left);
    assert_true(fabs(lf.delta - rf.delta) <= 1e-6 * rf.delta + 1e-8);
    const int n = rf.n;
    for (int i = 0; i < n; i++) {
      const double *p = rf.q + 3 * i, *q = lf.q + 3 * (n - 1 - i);
      if (!(fabs(p[0] + q[0]) < 1e-3 * VS_MM && fabs(p[1] - q[1]) < 1e-3 * VS_MM &&
            fabs(p[2] + q[2]) < 1e-5))
        fail_msg("alpha %g: block %d (%g, %g, %g) is not the mirror of block %d (%g, %g, %g)",
                 alphas[a], i + 1, p[0], p[1], p[2], n - i, q[0], q[1], q[2]);
    }
  }
}

/* Both supports moved alike (down, at the same rate) translate the arch bodily: no limit point
 * up to 40 mm, every block displaced by the supports' displacement from its self-weight state,
 * unturned; and the reactions those of self-weight. */
static void test_rigid_translation(void **state) {
  (void)state;
  vs_case c, still;
  reference(&c, 3.0);
  c.follow = 0;
  c.max_mm = 40.0;
  c.alpha_deg = 30.0;
  c.left_alpha_deg = -30.0; /* mirrored: the left one's -30 is the right one's direction */
  c.left_rate_mm_s = c.rate_mm_s;
  still = c;
  still.max_mm = 1.0; /* the self-weight state: barely moved by 1 mm of rigid translation */
  const outcome o = run_case(&c), s = run_case(&still);
  assert_true(fabs(o.last_delta - 40.0 * VS_MM) < 1e-9);
  const double ux = 40.0 * VS_MM * sin(30.0 * VS_DEG), uz = -40.0 * VS_MM * cos(30.0 * VS_DEG);
  const double sx = 1.0 * VS_MM * sin(30.0 * VS_DEG), sz = -1.0 * VS_MM * cos(30.0 * VS_DEG);
  for (int i = 0; i < o.n; i++) {
    const double *p = o.q + 3 * i, *q = s.q + 3 * i;
    if (!(fabs((p[0] - ux) - (q[0] - sx)) < 1e-9 && fabs((p[1] - uz) - (q[1] - sz)) < 1e-9 &&
          fabs(p[2] - q[2]) < 1e-9))
      fail_msg("block %d: (%g, %g, %g) m is not its self-weight state (%g, %g, %g) moved bodily",
               i + 1, p[0] - ux, p[1] - uz, p[2], q[0] - sx, q[1] - sz, q[2]);
  }
  for (int k = 0; k < 6; k++) assert_true(fabs(o.react[k] - s.react[k]) < 1e-6);
}

/* Both supports spreading by d/2 outward collapse at the relative displacement at which one
 * spreading by d does, with the same hinges, sides and joints (to a joint: the snap-throughs
 * before the collapse settle where the dynamics' round-off lets them, which a rigid translation
 * of every position changes); at the first limit point the blocks are those of the one-sided
 * run moved bodily by -d/2 in x. */
static void test_half_each(void **state) {
  (void)state;
  vs_case one, both;
  reference(&one, 48.0);
  one.alpha_deg = 90.0;
  both = one;
  both.rate_mm_s = 0.5 * one.rate_mm_s; /* delta: the right one's travel, d/2 */
  both.left_rate_mm_s = both.rate_mm_s;
  both.left_alpha_deg = 90.0;
  const outcome o = run_case(&one), b = run_case(&both);
  if (!(fabs(2.0 * b.delta - o.delta) <= 1e-3 * o.delta))
    fail_msg("collapse at a relative displacement of %.9g mm (both moved), %.9g mm (one)",
             2.0 * b.delta / VS_MM, o.delta / VS_MM);
  assert_int_equal(o.n_hinges, b.n_hinges);
  for (int i = 0; i < o.n_hinges; i++)
    if (!has_hinge(&b, o.hinges[i].first, o.hinges[i].last, o.hinges[i].side, 1))
      fail_msg("hinge %d-%d-%c of the one-sided run is not in the two-sided one",
               o.hinges[i].first, o.hinges[i].last, o.hinges[i].side);
  one.follow = both.follow = 0;
  one.limit_tol_mm = both.limit_tol_mm = 1e-6; /* the limit points bracketed to 1e-6 mm */
  const outcome of = run_case(&one), bf = run_case(&both);
  if (!(fabs(2.0 * bf.delta - of.delta) <= 5e-6 * VS_MM))
    fail_msg("first limit point at a relative displacement of %.9g mm (both moved), %.9g mm (one)",
             2.0 * bf.delta / VS_MM, of.delta / VS_MM);
  const double shift = -0.5 * of.delta; /* the left support's travel, to the left */
  for (int i = 0; i < of.n; i++) {
    const double *p = of.q + 3 * i, *q = bf.q + 3 * i;
    /* at limit points that agree to the bisection's tolerance */
    if (!(fabs(p[0] + shift - q[0]) < 2e-3 * VS_MM && fabs(p[1] - q[1]) < 2e-3 * VS_MM &&
          fabs(p[2] - q[2]) < 1e-4))
      fail_msg("block %d: (%g, %g, %g) m, the one-sided run's moved by %g m: (%g, %g, %g)", i + 1,
               q[0], q[1], q[2], shift, p[0] + shift, p[1], p[2]);
  }
}

/* Both supports spreading alike: the mechanism at the collapse is its own mirror image, to a
 * joint (55 voussoirs: the crown is a voussoir, its two joints 28 and 29 mirror each other), of
 * five hinges: E-I-E-I-E, the symmetric five-hinge mode. */
static void test_symmetric_spreading(void **state) {
  (void)state;
  vs_case c;
  reference(&c, 48.0);
  c.alpha_deg = 90.0;
  c.left_alpha_deg = 90.0;
  c.left_rate_mm_s = c.rate_mm_s;
  const outcome o = run_case(&c);
  assert_true(isfinite(o.delta));
  assert_hinges_mirrored(&o, &o, 1);
  assert_int_equal(o.n_hinges, 5);
  char sides[17] = "";
  int joint = 0;
  for (int k = 0; k < o.n_hinges; k++) { /* left to right */
    int best = -1;
    for (int i = 0; i < o.n_hinges; i++)
      if (o.hinges[i].first > joint && (best < 0 || o.hinges[i].first < o.hinges[best].first))
        best = i;
    sides[k] = o.hinges[best].side;
    joint = o.hinges[best].first;
  }
  assert_string_equal(sides, "EIEIE");
}

/* A path that settles the right support by 5 mm, then spreads it by 5 mm, against the straight
 * motions to the same positions: settlement alone to 5 mm (at the path's corner), and the
 * straight line at 45 deg to (5, 5) mm (at its end). The joints are elastic and do not slide
 * (|T| < mu N throughout), so an equilibrium depends only on where the supports are. */
static void test_path_settle_then_spread(void **state) {
  (void)state;
  vs_case path;
  reference(&path, 3.0);
  path.follow = 0;
  set(&path, "support.right_path = 0:0:0, 125:0:5, 250:5:5"); /* 0.04 mm/s: delta 5, 10 mm */
  vs_case corner = path, end = path;
  path.max_mm = 10.0;
  corner.max_mm = 5.0;
  set(&corner, "support.right_path=none");
  corner.alpha_deg = 0.0;
  set(&end, "support.right_path=none");
  end.alpha_deg = 45.0;
  end.max_mm = 5.0 * sqrt(2.0);
  vs_case to_corner = path;
  to_corner.max_mm = 5.0;
  const outcome p = run_case(&path), pc = run_case(&to_corner), c = run_case(&corner),
                e = run_case(&end);
  assert_true(fabs(p.last_delta - 10.0 * VS_MM) < 1e-12 && fabs(pc.last_delta - 5.0 * VS_MM) < 1e-12);
  assert_true(fabs(e.last_delta - end.max_mm * VS_MM) < 1e-12);
  for (int i = 0; i < 3 * p.n; i++) {
    const double tol = i % 3 == 2 ? 1e-8 : 1e-9;
    if (!(fabs(pc.q[i] - c.q[i]) < tol))
      fail_msg("at the corner, q[%d] = %.12g, settlement alone: %.12g", i, pc.q[i], c.q[i]);
    if (!(fabs(p.q[i] - e.q[i]) < tol))
      fail_msg("at the end, q[%d] = %.12g, the straight line: %.12g", i, p.q[i], e.q[i]);
  }
  /* and the path did not stop at its corner: the spreading moved the arch */
  assert_true(fabs(p.q[3 * (p.n - 1)] - pc.q[3 * (p.n - 1)]) > 1e-3);
}

/* A springer turned to the rotation that a pinned springer takes freely under self-weight
 * carries no moment about its pivot (the springer's moment balance, the pinned one's defining
 * equation), and the arch is in the pinned arch's state; not turned (clamped) or turned twice as
 * far it carries one, of opposite signs. A wrong sign convention or pivot would leave a moment.
 * Two voussoirs, so that the springer's rotation matters to the whole arch. The right support
 * moves down by 1e-6 mm in both runs (the path needs a loading rate). */
static void test_rotation_moment_balance(void **state) {
  (void)state;
  vs_case pinned;
  reference(&pinned, 3.0);
  pinned.voussoirs = 2;
  pinned.follow = 0;
  pinned.right_kind = VS_SUPPORT_PINNED;
  pinned.max_mm = 1e-6;
  pinned.step_mm = pinned.step_max_mm = 5e-7;
  pinned.limit_tol_mm = 1e-7;
  const outcome free = run_case(&pinned);
  const double theta = free.q[3 * 2]; /* the pinned support's rotation, after the blocks' */
  const double scale = 0.5 * 31.5 * 0.024; /* half the weight x t, N m */
  assert_true(fabs(theta) > 1e-6);          /* it does turn */
  assert_true(fabs(free.react[5]) < 1e-8 * scale);
  vs_case fixed = pinned;
  fixed.right_kind = VS_SUPPORT_FIXED;
  const double t_end = fixed.max_mm / fixed.rate_mm_s; /* s */
  double M[3];
  for (int k = 0; k < 3; k++) { /* turned by 0, 1, 2 times theta */
    /* outward (clockwise on the right) positive: the right springer's theta is -rot */
    char a[160];
    snprintf(a, sizeof a, "support.right_path = 0:0:0, %.17g:0:%.17g:%.17g", t_end, fixed.max_mm,
             -k * theta / VS_DEG);
    set(&fixed, a);
    const outcome o = run_case(&fixed);
    M[k] = o.react[5];
    if (k == 1)
      for (int i = 0; i < 6; i++)
        if (!(fabs(o.q[i] - free.q[i]) < 1e-10))
          fail_msg("q[%d] = %.12g, the pinned arch's %.12g", i, o.q[i], free.q[i]);
  }
  if (!(fabs(M[1]) < 1e-6 * scale)) fail_msg("moment about the pivot %g N m (pinned: 0)", M[1]);
  assert_true(fabs(M[0]) > 1e-3 * scale && fabs(M[2]) > 1e-3 * scale && M[0] * M[2] < 0.0);
}

/* The path and rate keys: accepted forms, and each refusal names the key and the allowed. */
static void test_keys(void **state) {
  (void)state;
  vs_case c;
  vs_error err;
  vs_case_defaults(&c);
  assert_int_equal(vs_case_set(&c, "support.right_path = 0:0:0, 250:0:10 ,500:10:10:1.5", &err),
                   VS_OK);
  assert_int_equal(c.right_path.n, 3);
  assert_true(c.right_path.t_s[2] == 500.0 && c.right_path.dx_mm[2] == 10.0 &&
              c.right_path.rot_deg[2] == 1.5 && c.right_path.rot_deg[1] == 0.0);
  char text[256];
  assert_int_equal(vs_case_text_key(&c, 1, NULL, NULL, text, sizeof text), 0);
  assert_string_equal(text, "0:0:0, 250:0:10, 500:10:10:1.5");
  const char *bad[][2] = {
      {"support.right_path=0:0", "point 1: 2 numbers"},
      {"support.right_path=1:2:3, 1:2:3", "point 2: t = 1 s not after 1 s"},
      {"support.left_path=0:1:0", "point 1: at t = 0 away from the origin"},
      {"support.left_path=5:1:0:91", "point 1: out of range"},
      {"support.left_path=5:1:x", "point 1: not a number"},
      {"support.left_path=5:1:2:3:4", "point 1: more than 4 numbers"},
      {"support.left_path=-1:0:0", "point 1: out of range"},
      {"support.left_rate_mm_s=-1", "out of range (allowed: 0 or [1e-06, 1e+06] mm/s)"},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    vs_case k = c;
    vs_error_clear(&err);
    assert_int_equal(vs_case_set(&k, bad[i][0], &err), VS_ERR_INVALID);
    if (strstr(err.msg, bad[i][1]) == NULL || strstr(err.msg, "(allowed: ") == NULL)
      fail_msg("%s: %s", bad[i][0], err.msg);
    assert_memory_equal(&k, &c, sizeof k); /* unchanged */
  }
  char many[2048] = "support.right_path=";
  for (int i = 1; i <= 33; i++)
    snprintf(many + strlen(many), sizeof many - strlen(many), "%s%d:0:%d", i > 1 ? "," : "", i, i);
  assert_int_equal(vs_case_set(&c, many, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "more than 32 points"));
  /* no loading rate; a pinned support turned */
  vs_case k;
  vs_case_defaults(&k);
  set(&k, "support.rate_mm_s=0");
  assert_int_equal(vs_case_validate(&k, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "support.rate_mm_s = 0 and support.left_rate_mm_s = 0"));
  vs_case_defaults(&k);
  set(&k, "support.left_kind=pinned");
  set(&k, "support.left_path=10:0:0:1");
  assert_int_equal(vs_case_validate(&k, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "support.left_path: point 1 turns the support by 1 deg"));
  /* the same from the definition (a library user's) */
  vs_run_def d;
  vs_case_to_def(&k, &d);
  vs_run *r = NULL;
  assert_int_equal(vs_run_create_def(&d, &r, &err), VS_ERR_INVALID);
  assert_null(r);
  assert_non_null(strstr(err.msg, "support.left_path turns the left support, which is pinned"));
}

/* A support's motion in delta: the straight motion is delta times its direction bit for bit;
 * a path's corners, its extrapolation beyond the last point, and the next corner. */
static void test_motion(void **state) {
  (void)state;
  vs_run_def d;
  vs_run_def_default(&d);
  d.support.alpha = 0.3;
  vs_support_motion mo;
  vs_error err;
  assert_int_equal(vs_support_motion_from_def(&d.support, 1, &mo, &err), VS_OK);
  double u[3], du[3];
  vs_support_motion_at(&mo, 0.0123, u, du);
  assert_true(u[0] == 0.0123 * sin(0.3) && u[1] == 0.0123 * -cos(0.3) && u[2] == 0.0);
  assert_true(isinf(vs_support_motion_next(&mo, 0.0, 0.0)));
  d.support.right_path = (vs_support_path_def){
      .n = 2, .t = {100.0, 200.0}, .dx = {0.0, 0.004}, .dz = {0.004, 0.004}, .rot = {0.0, 0.01}};
  assert_int_equal(vs_support_motion_from_def(&d.support, 1, &mo, &err), VS_OK);
  const double v = d.support.rate; /* delta = v t */
  vs_support_motion_at(&mo, v * 50.0, u, du);
  assert_true(fabs(u[0]) < 1e-18 && fabs(u[1] + 0.002) < 1e-15 && fabs(du[1] + 0.004 / (v * 100.0)) < 1e-9);
  vs_support_motion_at(&mo, v * 250.0, u, du); /* beyond: the last segment goes on */
  assert_true(fabs(u[0] - 0.006) < 1e-15 && fabs(u[1] + 0.004) < 1e-15 &&
              fabs(u[2] + 0.015) < 1e-15); /* right: outward turn is clockwise */
  assert_true(fabs(vs_support_motion_next(&mo, 0.0, 0.0) - v * 100.0) < 1e-18);
  assert_true(fabs(vs_support_motion_next(&mo, v * 100.0, 1e-9) - v * 200.0) < 1e-18);
  /* the left support mirrored: outward is -x, and an outward turn counter-clockwise */
  d.support.left_path = d.support.right_path;
  assert_int_equal(vs_support_motion_from_def(&d.support, 0, &mo, &err), VS_OK);
  vs_support_motion_at(&mo, v * 200.0, u, NULL);
  assert_true(fabs(u[0] + 0.004) < 1e-15 && fabs(u[1] + 0.004) < 1e-15 && fabs(u[2] - 0.01) < 1e-15);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_motion),
      cmocka_unit_test(test_keys),
      cmocka_unit_test(test_mirror),
      cmocka_unit_test(test_rigid_translation),
      cmocka_unit_test(test_half_each),
      cmocka_unit_test(test_symmetric_spreading),
      cmocka_unit_test(test_path_settle_then_spread),
      cmocka_unit_test(test_rotation_moment_balance),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
