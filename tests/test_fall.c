/* The fall's nonsmooth contact dynamics (fall.h) against independent references:
 *  - free flight is exact: a block released above the ground lands at t = sqrt(2 h0 / g) (to a
 *    step), and the perfectly plastic landing takes m g h0, all of the energy, into the
 *    dissipated energy; it then lies on the ground without sinking or moving;
 *  - a block sliding on the ground stops after v0^2 / (2 mu g), in v0 / (mu g), its kinetic energy
 *    all dissipated by friction, closer to both as the step is refined; with the slow step
 *    (twice as long below 0.5 m/s) it takes as many short steps as that rule gives, stops as
 *    near, and the warm start, scaled to the longer step, needs no more sweeps;
 *  - a block rocking on a corner: at the impact on its other corner it keeps
 *    (1 - (3/2) sin^2 a)^2 of its kinetic energy (Housner: angular momentum conserved about the
 *    new corner, a = atan(B / H)), within 2 %, for H/B = 6 and 2;
 *  - a block rolling over a pier's corner on their joint, folding onto the pier's top, and a
 *    block's corner flying at the pier's corner: no corner goes deeper into the other body than
 *    3 g h^2 (outlines written out here);
 *  - bodies that do not touch do not act on each other: a tower on the ground creeps the same,
 *    bit for bit, with or without a block landing beside it (with either solver);
 *  - both solvers give a standing tower's exact impulses (every block still after a step from no
 *    warm start), NNCG in fewer sweeps, and keep it at rest;
 *  - the reference arch at its self-weight equilibrium, its joints turned into rigid contacts
 *    whose impulses start from the elastic joints' forces there (as the fall starts from those at
 *    the collapse), stands: the supports carry its weight and it does not move;
 *  - bad options are refused with the field and its range.
 * SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/fall.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"

static const double GRAV = 9.81;
static const double PI = 3.14159265358979323846;

/* One free rectangular block B x H (depth 0.1 m, 2000 kg/m^3) and a dummy joint that never
 * touches (a gap of 1 m); the fall's outline its four corners, no joint contacts. */
typedef struct {
  vs_geometry *g;
  vs_model *m;
  vs_fall *f;
  double B, H, mass, inertia;
} block;

/* The block tests' fall options: steps of step, all of them (the closed forms' steps), no joint
 * contacts, the ground, Gauss-Seidel to 1e-6 (up to 1000 sweeps), at rest below 1e-12 J for
 * 0.05 s, at most 3 s. */
static void block_opts(vs_fall_opts *o, double step) {
  vs_fall_opts_default(o);
  o->step = o->slow_step = step;
  o->joints = 0;
  o->ground = 0.0; /* offset from the lower springing's base: set below */
  o->rest_ke = 1e-12;
  o->rest_time = 0.05;
  o->duration = 3.0;
  o->sample_dt = step;
  o->tol = 1e-6;
  o->max_sweeps = 1000;
}

/* The block's fall with options o (its outline B x H on z = 0), replacing any it had. */
static void block_fall(block *bk, const vs_fall_opts *o) {
  vs_error err;
  vs_error_clear(&err);
  vs_fall_destroy(&bk->f);
  const double B = bk->B, H = bk->H;
  const int count[3] = {4, 0, 0};
  const double xz[8] = {-0.5 * B, 0.0, 0.5 * B, 0.0, 0.5 * B, H, -0.5 * B, H};
  /* the ground at z = 0: the springing base is the dummy joint's intrados end, at z = 0 */
  assert_int_equal(vs_fall_create(bk->m, o, count, xz, &bk->f, &err), VS_OK);
}

static void block_make(block *bk, double B, double H, double mu, double step) {
  vs_error err;
  vs_error_clear(&err);
  bk->f = NULL;
  assert_int_equal(vs_geometry_create(1, 1, &bk->g, &err), VS_OK);
  vs_block *blk = &bk->g->blocks[0];
  blk->area = B * H;
  blk->mass = 2000.0 * 0.1 * B * H;
  blk->inertia = blk->mass * (B * B + H * H) / 12.0;
  blk->cz = 0.5 * H;
  bk->g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .px = -0.5 * B - 1.0,
                                     .pz = 0.5 * H, .nx = 1.0, .nz = 0.0, .length = H,
                                     .depth = 0.1};
  bk->g->gravity = GRAV;
  vs_joint_law law = {.kn = 1e9, .ks = 0.5e9, .mu = mu, .gap0 = 1.0};
  assert_int_equal(vs_model_create(bk->g, &law, 0.0, &bk->m, &err), VS_OK);
  bk->B = B, bk->H = H, bk->mass = blk->mass, bk->inertia = blk->inertia;
  vs_fall_opts o;
  block_opts(&o, step);
  block_fall(bk, &o);
}

static void block_free(block *bk) {
  vs_fall_destroy(&bk->f);
  vs_model_destroy(&bk->m);
  vs_geometry_destroy(&bk->g);
}

/* Samples of one block's state. */
typedef struct {
  int n;
  double t[20000], x[20000], z[20000], th[20000], vx[20000], vz[20000], w[20000];
  vs_energy e[20000];
} trace;

static int on_sample(void *user, double t, double delta, const double *q, const double *v,
                     const vs_energy *e) {
  (void)delta;
  trace *tr = user;
  if (tr->n < 20000) {
    const int i = tr->n++;
    tr->t[i] = t, tr->x[i] = q[0], tr->z[i] = q[1], tr->th[i] = q[2];
    tr->vx[i] = v[0], tr->vz[i] = v[1], tr->w[i] = v[2], tr->e[i] = *e;
  }
  return 0;
}

/* Run fall f of one block from (q, v) (the block's three, the piers' zero) into tr. */
static void fall_from(vs_fall *f, const double q3[3], const double v3[3], trace *tr,
                      vs_fall_result *res) {
  double qe[9] = {0}, ve[9] = {0};
  memcpy(qe, q3, 3 * sizeof *qe);
  memcpy(ve, v3, 3 * sizeof *ve);
  vs_error err;
  vs_error_clear(&err);
  tr->n = 0;
  vs_status st = vs_fall_run(f, 0.0, qe, ve, NULL, NULL, on_sample, tr, res, &err);
  if (st != VS_OK) fail_msg("fall: %s", err.msg);
}

/* Run the block lying on the ground, at rest, for the given time (s) whatever its kinetic
 * energy. */
static void fall_block_for(block *bk, double duration, trace *tr, vs_fall_result *res) {
  vs_fall_opts o;
  block_opts(&o, 1e-3);
  o.rest_ke = 0.0; /* never at rest: the steps asked for */
  o.duration = duration;
  block_fall(bk, &o);
  fall_from(bk->f, (double[3]){0.0, 0.0, 0.0}, (double[3]){0}, tr, res);
}

/* ------------------------------------------------------------------------------------------- */

static void test_drop(void **state) {
  (void)state;
  const double h = 1e-3, h0 = 0.05;
  block bk;
  block_make(&bk, 0.2, 0.1, 0.7, h);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(bk.f, (double[3]){0.0, h0, 0.0}, (double[3]){0}, tr, &res);
  assert_int_equal(vs_fall_level(bk.f) == 0.0, 1);
  /* free flight exact: z = h0 - g t^2 / 2 at every sample before the landing */
  const double t_land = sqrt(2.0 * h0 / GRAV);
  int i = 0, bad = 0;
  for (; i < tr->n && tr->t[i] < t_land - 2 * h; i++) {
    const double exact = h0 - 0.5 * GRAV * tr->t[i] * tr->t[i];
    /* positions advance with the end-of-step velocity: z lags the parabola by g h t / 2 */
    if (fabs(tr->z[i] - exact) > 0.5 * GRAV * h * tr->t[i] + 1e-12) bad++;
  }
  assert_int_equal(bad, 0);
  /* landed within two steps of the closed form, then at rest on the ground */
  int k = 0;
  while (k < tr->n && tr->z[k] > 1e-9) k++;
  print_message("drop: landed at %.5f s (closed form %.5f s, step %.0e s); at rest %d at %.3f s; "
                "lowest %.3g m, final %.3g m; dissipated %.6f J of m g h0 = %.6f J; balance %.2g\n",
                tr->t[k], t_land, h, res.at_rest, res.t_end, -res.max_penetration, tr->z[tr->n - 1],
                tr->e[tr->n - 1].damped, bk.mass * GRAV * h0, res.balance_error_rel);
  assert_true(k < tr->n && fabs(tr->t[k] - t_land) <= 2 * h);
  assert_int_equal(res.at_rest, 1);
  assert_true(res.max_penetration < 1e-9); /* it never sinks into the ground */
  double zmax = 0.0, xmax = 0.0;
  for (int j = k; j < tr->n; j++) zmax = fmax(zmax, fabs(tr->z[j])), xmax = fmax(xmax, fabs(tr->x[j]));
  print_message("drop: after landing |z| <= %.3g m, |x| <= %.3g m\n", zmax, xmax);
  assert_true(zmax < 1e-9 && xmax < 1e-9);
  /* the plastic landing takes the whole energy, within the free flight's O(h) */
  const double mgh = bk.mass * GRAV * h0;
  assert_true(fabs(tr->e[tr->n - 1].damped - mgh) < 0.02 * mgh);
  assert_true(res.balance_error_rel < 0.02);
  free(tr);
  block_free(&bk);
}

/* A block lying on the ground: each step's contacts are the last step's and so is their problem,
 * so the last step's impulses, the warm start, solve it and one sweep confirms it; a step that
 * started from no impulses needs as many sweeps as the first one took. */
static void test_warm_start(void **state) {
  (void)state;
  const double h = 1e-3;
  block bk;
  block_make(&bk, 0.2, 0.1, 0.7, h);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result one, many;
  fall_block_for(&bk, h, tr, &one);
  fall_block_for(&bk, 100 * h, tr, &many);
  print_message("warm start: the first step %ld sweeps, %ld steps %ld sweeps\n", one.sweeps,
                many.steps, many.sweeps);
  assert_int_equal(one.steps, 1);
  assert_true(one.sweeps > 2); /* the first step's two contacts need several sweeps */
  assert_int_equal(many.steps, 100);
  assert_true(many.sweeps - one.sweeps <= 2 * (many.steps - 1));
  free(tr);
  block_free(&bk);
}

/* A block that starts 1 mm inside the ground (a vertex overlap, as impacts leave them) is moved out
 * through its positions: the overlap shrinks by the recovery's fraction every step, the block is
 * never launched (no speed beyond the g h a step of gravity gives and its contact takes back) and
 * never lifts off, and the work done against gravity is booked as the contacts' (the energy balance
 * holds). A recovery through the velocities would leave it at d / h * fraction = 0.2 m/s. */
static void test_overlap_recovery(void **state) {
  (void)state;
  const double h = 1e-3, d = 1e-3;
  block bk;
  block_make(&bk, 0.2, 0.1, 0.7, h);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(bk.f, (double[3]){0.0, -d, 0.0}, (double[3]){0}, tr, &res);
  double vmax = 0.0, zmax = -INFINITY;
  int slow = 0; /* samples where the overlap shrank by less than a fifth a step (test_drop's
                   solver tolerance) */
  for (int i = 0; i < tr->n; i++) {
    vmax = fmax(vmax, hypot(tr->vx[i], tr->vz[i]) + fabs(tr->w[i]) * 0.5 * hypot(bk.B, bk.H));
    zmax = fmax(zmax, tr->z[i]);
    const double steps = round(tr->t[i] / h);
    /* slack: what the contact's Gauss-Seidel tolerance (1e-6 g h) lets it sink in the steps */
    if (-tr->z[i] > d * pow(0.8, steps) + steps * 1e-6 * GRAV * h * h) slow++;
  }
  const double mgd = bk.mass * GRAV * d;
  print_message("recovery: overlap %.3g m after %.0f steps (%.3g at a fifth a step); speed <= "
                "%.3g m/s (g h = %.3g); highest z %.3g m; at rest %d; work against gravity in "
                "the contacts %.6g J (m g d = %.6g J); balance %.2g\n",
                -tr->z[tr->n - 1], round(tr->t[tr->n - 1] / h),
                d * pow(0.8, round(tr->t[tr->n - 1] / h)), vmax, GRAV * h, zmax, res.at_rest,
                -tr->e[tr->n - 1].damped, mgd, res.balance_error_rel);
  assert_int_equal(slow, 0);
  assert_true(vmax <= GRAV * h * (1.0 + 1e-9));
  assert_true(zmax <= 0.0);
  assert_int_equal(res.at_rest, 1);
  assert_true(fabs(-tr->e[tr->n - 1].damped - mgd) < 1e-3 * mgd);
  assert_true(res.balance_error_rel < 1e-3);
  free(tr);
  block_free(&bk);
}

/* Stopping distance and time of a block sliding at v0 on the ground, with the step h. */
static void slide(double h, double *dist, double *time, double *friction, double *ke0) {
  const double v0 = 1.0, mu = 0.5;
  block bk;
  block_make(&bk, 0.2, 0.1, mu, h);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(bk.f, (double[3]){0.0, 0.0, 0.0}, (double[3]){v0, 0.0, 0.0}, tr, &res);
  int k = 0;
  while (k < tr->n && tr->vx[k] > 1e-8) k++; /* stopped: sticking, to the solver's tolerance */
  assert_true(k < tr->n);
  *dist = tr->x[tr->n - 1];
  *time = tr->t[k];
  *friction = tr->e[tr->n - 1].friction;
  *ke0 = 0.5 * bk.mass * v0 * v0;
  for (int j = 0; j < tr->n; j++) /* it slides flat: no rocking, no sinking */
    assert_true(fabs(tr->th[j]) < 1e-9 && fabs(tr->z[j]) < 1e-9);
  free(tr);
  block_free(&bk);
}

static void test_slide(void **state) {
  (void)state;
  const double v0 = 1.0, mu = 0.5;
  const double d_exact = v0 * v0 / (2 * mu * GRAV), t_exact = v0 / (mu * GRAV);
  double d[2], t[2], fr[2], ke0;
  slide(1e-3, &d[0], &t[0], &fr[0], &ke0);
  slide(2.5e-4, &d[1], &t[1], &fr[1], &ke0);
  print_message("slide: distance %.6f / %.6f m (closed form %.6f), time %.5f / %.5f s (%.5f), "
                "friction dissipated %.6f / %.6f J of %.6f J, steps 1e-3 / 2.5e-4 s\n", d[0],
                d[1], d_exact, t[0], t[1], t_exact, fr[0], fr[1], ke0);
  assert_true(fabs(t[0] - t_exact) <= 1e-3 && fabs(t[1] - t_exact) <= 2.5e-4);
  assert_true(fabs(d[0] - d_exact) < 0.01 * d_exact);
  assert_true(fabs(d[1] - d_exact) < fabs(d[0] - d_exact) || fabs(d[1] - d_exact) < 1e-9);
  for (int i = 0; i < 2; i++) assert_true(fabs(fr[i] - ke0) < 0.01 * ke0);
}

/* The slow step (vs_fall_opts.slow_step): a block sliding at v0 = 1 m/s on the ground (mu 0.5)
 * takes steps of 1 ms while faster than 0.5 m/s, then of 2 ms. Friction slows it by mu g h a
 * step, so the fast steps are those k = 0, 1, ... with v0 - mu g h k > 0.5 m/s: 102. It still
 * stops within a slow step of v0 / (mu g), within 1 % of v0^2 / (2 mu g), with its kinetic
 * energy dissipated by friction. At the switch the contact's impulses double with the step,
 * and the warm start, scaled by the steps' ratio, still solves the step in one sweep (Gauss-Seidel
 * to 1e-6 g h): the sweeps beyond one a step (the first step's, the stop's) are those of the
 * same slide in steps of 1 ms throughout, to within 2 (unscaled: 15 more). */
static void test_slow_step(void **state) {
  (void)state;
  const double v0 = 1.0, mu = 0.5, h = 1e-3, vs = 0.5;
  block bk;
  block_make(&bk, 0.2, 0.1, mu, h);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result fixed, res;
  fall_from(bk.f, (double[3]){0.0, 0.0, 0.0}, (double[3]){v0, 0.0, 0.0}, tr, &fixed);
  vs_fall_opts o;
  block_opts(&o, h);
  o.slow_step = 2.0 * h;
  o.slow_speed = vs;
  block_fall(&bk, &o);
  fall_from(bk.f, (double[3]){0.0, 0.0, 0.0}, (double[3]){v0, 0.0, 0.0}, tr, &res);
  const long fast = (long)ceil((v0 - vs) / (mu * GRAV * h));
  int k = 0;
  while (k < tr->n && tr->vx[k] > 1e-8) k++;
  assert_true(k < tr->n);
  const double d_exact = v0 * v0 / (2 * mu * GRAV), t_exact = v0 / (mu * GRAV);
  const double ke0 = 0.5 * bk.mass * v0 * v0, fr = tr->e[tr->n - 1].friction;
  print_message("slow step: %ld steps, %ld of 2 ms (%ld of 1 ms, expected %ld); stopped at "
                "%.5f s (%.5f), after %.6f m (%.6f); friction %.6f J of %.6f J; sweeps beyond "
                "one a step %ld (all of 1 ms: %ld)\n", res.steps, res.slow_steps,
                res.steps - res.slow_steps, fast, tr->t[k], t_exact, tr->x[tr->n - 1], d_exact,
                fr, ke0, res.sweeps - res.steps, fixed.sweeps - fixed.steps);
  assert_int_equal(res.steps - res.slow_steps, fast);
  assert_true(fabs(tr->t[k] - t_exact) <= 2.0 * h);
  assert_true(fabs(tr->x[tr->n - 1] - d_exact) < 0.01 * d_exact);
  assert_true(fabs(fr - ke0) < 0.01 * ke0);
  assert_int_equal(fixed.slow_steps, 0);
  assert_true(res.sweeps - res.steps <= fixed.sweeps - fixed.steps + 2);
  free(tr);
  block_free(&bk);
}

/* A block B x H standing on its right corner, tilted clockwise by theta0 (its left corner up):
 * released, it falls back and strikes with its left corner, then rocks on about that one. Its
 * angular velocity (counter-clockwise, > 0) just before and just after that impact. */
static void rock(double HB, double *ratio, double *housner) {
  const double B = 0.05, H = HB * B, h = 2e-5;
  block bk;
  block_make(&bk, B, H, 5.0, h); /* friction high enough that the corners stick */
  const double a = atan(B / H), R = 0.5 * hypot(B, H), th0 = 0.5 * a;
  /* turned by -th0 about the right corner (B/2, 0): the centroid's displacement */
  const double cx = 0.5 * B - R * sin(a - th0), cz = R * cos(a - th0) - 0.5 * H;
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(bk.f, (double[3]){cx, cz, -th0}, (double[3]){0}, tr, &res);
  /* the impact: the first sample with the block level (its left corner down) */
  int k = 0;
  while (k < tr->n && tr->th[k] < -1e-12) k++;
  assert_true(k > 0 && k + 5 < tr->n);
  const double wm = tr->w[k - 1], wp = tr->w[k + 3]; /* the impulses act over two steps */
  *ratio = wp / wm;
  *housner = 1.0 - 1.5 * sin(a) * sin(a);
  free(tr);
  block_free(&bk);
}

static void test_rocking_housner(void **state) {
  (void)state;
  const double slender[2] = {6.0, 2.0};
  for (int s = 0; s < 2; s++) {
    double r, hz;
    rock(slender[s], &r, &hz);
    print_message("rocking H/B = %g: w+/w- = %.5f, Housner %.5f (energy kept %.5f against "
                  "%.5f)\n", slender[s], r, hz, r * r, hz * hz);
    assert_true(fabs(r * r - hz * hz) < 0.02 * hz * hz);
  }
}

/* A pier (the left support, immovable: the square [-L, 0] x [-L, 0], its top-right corner at the
 * origin) and one block W x L (its reference the rectangle [0, W] x [-L, 0], against the pier's
 * right face) with the joint of that face between them (its extrados end at the origin) and a
 * dummy one to the right support 10 m away; outlines their four corners, the right support's
 * none; no ground. joints: the joint contacts on or off. */
typedef struct {
  vs_geometry *g;
  vs_model *m;
  vs_fall *f;
  double W, L;
} pier_block;

static void pier_block_make(pier_block *pb, double W, double L, double mu, int joints,
                            double step, double duration) {
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(1, 2, &pb->g, &err), VS_OK);
  vs_block *blk = &pb->g->blocks[0];
  blk->area = W * L;
  blk->mass = 2000.0 * 0.1 * W * L;
  blk->inertia = blk->mass * (W * W + L * L) / 12.0;
  blk->cx = 0.5 * W, blk->cz = -0.5 * L;
  pb->g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .px = 0.0, .pz = -0.5 * L,
                                     .nx = 1.0, .nz = 0.0, .length = L, .depth = 0.1};
  pb->g->joints[1] = (vs_joint_geom){.a = 0, .b = VS_SUPPORT_RIGHT, .px = 10.0, .pz = -0.5 * L,
                                     .nx = 1.0, .nz = 0.0, .length = L, .depth = 0.1};
  pb->g->gravity = GRAV;
  vs_joint_law law = {.kn = 1e9, .ks = 0.5e9, .mu = mu, .gap0 = 1.0};
  assert_int_equal(vs_model_create(pb->g, &law, 0.0, &pb->m, &err), VS_OK);
  vs_fall_opts o;
  vs_fall_opts_default(&o);
  o.step = step;
  o.joints = joints;
  o.ground = NAN;
  o.rest_ke = 0.0; /* followed for the whole duration */
  o.duration = duration;
  o.sample_dt = step;
  const int count[3] = {4, 4, 0};
  const double xz[16] = {0.0, -L, W, -L, W, 0.0, 0.0, 0.0, -L, -L, 0.0, -L, 0.0, 0.0, -L, 0.0};
  assert_int_equal(vs_fall_create(pb->m, &o, count, xz, &pb->f, &err), VS_OK);
  pb->W = W, pb->L = L;
}

static void pier_block_free(pier_block *pb) {
  vs_fall_destroy(&pb->f);
  vs_model_destroy(&pb->m);
  vs_geometry_destroy(&pb->g);
}

/* How deep (m; 0: not) the point (x, z) is inside the rectangle [x0, x1] x [z0, z1]. */
static double depth_in(double x, double z, double x0, double x1, double z0, double z1) {
  return fmax(0.0, fmin(fmin(x - x0, x1 - x), fmin(z - z0, z1 - z)));
}

/* The deepest corner of the block inside the pier or of the pier inside the block over the
 * samples, from the outlines written out here (m). */
static double pier_block_overlap(const pier_block *pb, const trace *tr) {
  const double W = pb->W, L = pb->L, cx = 0.5 * W, cz = -0.5 * L;
  const double bx[4] = {0.0, W, W, 0.0}, bz[4] = {-L, -L, 0.0, 0.0};
  const double ax[4] = {-L, 0.0, 0.0, -L}, az[4] = {-L, -L, 0.0, 0.0};
  double worst = 0.0;
  for (int i = 0; i < tr->n; i++) {
    const double c = cos(tr->th[i]), s = sin(tr->th[i]);
    const double ox = cx + tr->x[i], oz = cz + tr->z[i]; /* the centroid */
    for (int v = 0; v < 4; v++) {
      /* the block's corner in the world, in the pier */
      const double rx = bx[v] - cx, rz = bz[v] - cz;
      worst = fmax(worst, depth_in(ox + c * rx - s * rz, oz + s * rx + c * rz, -L, 0.0, -L, 0.0));
      /* the pier's corner in the block's reference frame, in the block */
      const double px = ax[v] - ox, pz = az[v] - oz;
      worst = fmax(worst, depth_in(cx + c * px + s * pz, cz - s * px + c * pz, 0.0, W, -L, 0.0));
    }
  }
  return worst;
}

/* A joint folding: the block, slid up its joint by d (the pier's corner on its face, d below
 * the face's extrados end) and turned about that corner by 35 degrees, rolls over the corner
 * (started just fast enough to pass over it, friction high enough that the corner sticks) and
 * falls onto the pier's top, its face folding 90 degrees onto it. The pier's corner is the
 * joint's contact at that edge; the block's corner there must be met on the pier's top (an edge
 * other than the joint's face) and stop there: the block comes to lie on the pier, no corner
 * deeper inside the other body than 3 g h^2 (what gravity and the turn's curvature move a vertex
 * beyond its contact's linear law in a step, (g + w^2 r) h^2, about 1.5 g h^2 here).
 * Before this release that corner was left to the joint's contact and went through the pier's
 * top until a corner away from the joint struck: turned 125.5 degrees, 34 mm inside, of which
 * the fall's own measure saw 2 um. */
static void test_fold_over_corner(void **state) {
  (void)state;
  const double h = 1e-3, W = 0.06, L = 0.1, d = 0.08, th0 = 35.0 * PI / 180.0;
  pier_block pb;
  pier_block_make(&pb, W, L, 5.0, 1, h, 1.0);
  /* the centroid about the pier's corner (the origin), after the slide: r0; turned: r */
  const double r0x = 0.5 * W, r0z = d - 0.5 * L;
  const double rx = cos(th0) * r0x - sin(th0) * r0z, rz = sin(th0) * r0x + cos(th0) * r0z;
  /* the speed that lifts the centroid over the corner (its height there |r0|), with 10 % more */
  const double ip = pb.g->blocks[0].inertia / pb.g->blocks[0].mass + r0x * r0x + r0z * r0z;
  const double w0 = 1.1 * sqrt(2.0 * GRAV * (hypot(r0x, r0z) - rz) / ip);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(pb.f, (double[3]){rx - 0.5 * W, rz + 0.5 * L, th0},
                  (double[3]){-w0 * rz, w0 * rx, w0}, tr, &res);
  const double worst = pier_block_overlap(&pb, tr), tol = 3.0 * GRAV * h * h;
  print_message("fold over a corner: turned %.1f degrees at the end (90: lying on the pier), "
                "deepest corner inside the other body %.3g m (tolerance 3 g h^2 = %.3g m; the "
                "fall's own measure %.3g m)\n", tr->th[tr->n - 1] * 180.0 / PI, worst, tol,
                res.max_overlap);
  assert_true(worst <= tol);
  assert_true(fabs(tr->th[tr->n - 1] - 0.5 * PI) < 0.05);
  free(tr);
  pier_block_free(&pb);
}

/* A corner against a corner: the block (no joint contacts) flies at 1.0, 1.2 m/s towards the
 * pier's top-right corner, its own bottom-left corner 0.3, 0.4 mm up and to the right of it:
 * each corner in the other's corner region, a step (1.0, 1.2 mm) from being inside. They must
 * meet before either is inside: no corner deeper than 3 g h^2 in the other body. Before this
 * release neither was a contact until inside (0.7 mm deep at the next step). */
static void test_corner_corner(void **state) {
  (void)state;
  const double h = 1e-3, W = 0.06, L = 0.1;
  pier_block pb;
  pier_block_make(&pb, W, L, 0.7, 0, h, 0.05);
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_fall_result res;
  fall_from(pb.f, (double[3]){3e-4, L + 4e-4, 0.0}, (double[3]){-1.0, -1.2, 0.0}, tr, &res);
  const double worst = pier_block_overlap(&pb, tr), tol = 3.0 * GRAV * h * h;
  print_message("corner against corner: deepest corner inside the other body %.3g m "
                "(tolerance 3 g h^2 = %.3g m; the fall's own measure %.3g m)\n", worst, tol,
                res.max_overlap);
  assert_true(worst <= tol);
  free(tr);
  pier_block_free(&pb);
}

/* A tower of n blocks B x H (no joints: block on block through the narrow phase), each set
 * off sideways by +-off from the one below, placed touching, at rest, on the ground; calm as
 * vs_fall_opts.calm, the rest level that of the run (100 times the kinetic energy at 0.04
 * mm/s). With drop >= 0, one more block B x H, 1 m to the right of the tower, its base drop (m)
 * above the ground. With timed, the fall runs its whole duration in 1-ms steps (never at rest,
 * no slow step). tol, max_sweeps (0: the defaults') and solver as vs_fall_opts'. */
typedef struct {
  int n;
  double B, H, off, calm, drop;
  int timed;
  double duration; /* s */
  double tol;
  int max_sweeps, solver;
} tower_spec;

/* The tower of eight blocks 0.1 x 0.05 m, set off by 5 mm, followed for 2 s (the defaults'
 * solver and tolerances, no block dropped). */
static tower_spec tower8(void) {
  return (tower_spec){.n = 8, .B = 0.1, .H = 0.05, .off = 0.005, .calm = VS_FALL_CALM,
                      .drop = -1.0, .duration = 2.0, .solver = VS_FALL_NNCG};
}

/* Tower ts's fall. Returns the largest displacement of a tower block (m) after it; the tower's
 * final positions (3 n) into qt and velocities into vt (unless NULL), the result into *res. */
static double tower(const tower_spec *ts, double *qt, double *vt, vs_fall_result *res) {
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  const int n = ts->n, nb = n + (ts->drop >= 0.0);
  const double B = ts->B, H = ts->H;
  assert_int_equal(vs_geometry_create(nb, 1, &g, &err), VS_OK);
  double M = 0.0;
  int count[32 + 2] = {0};
  double xz[8 * 32];
  assert_true(nb <= 32);
  for (int i = 0; i < nb; i++) {
    vs_block *b = &g->blocks[i];
    b->area = B * H;
    b->mass = 2000.0 * 0.1 * B * H;
    b->inertia = b->mass * (B * B + H * H) / 12.0;
    b->cx = i == n ? 1.0 : i % 2 ? ts->off : -ts->off;
    const double z0 = i == n ? ts->drop : i * H;
    b->cz = z0 + 0.5 * H;
    M += b->mass;
    count[i] = 4;
    const double x0 = b->cx - 0.5 * B, x1 = b->cx + 0.5 * B, z1 = z0 + H;
    const double v[8] = {x0, z0, x1, z0, x1, z1, x0, z1};
    memcpy(xz + 8 * i, v, sizeof v);
  }
  /* the dummy joint, far to the left, only sets the springing base (z = 0) */
  g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .px = -0.5 * B - 1.0,
                                 .pz = 0.5 * H, .nx = 1.0, .nz = 0.0, .length = H, .depth = 0.1};
  g->gravity = GRAV;
  vs_joint_law law = {.kn = 1e9, .ks = 0.5e9, .mu = 0.7, .gap0 = 1.0};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  vs_fall_opts o;
  vs_fall_opts_default(&o);
  o.joints = 0;
  o.ground = 0.0;
  o.rest_ke = ts->timed ? 0.0 : 100.0 * 0.5 * M * 4e-5 * 4e-5;
  o.rest_time = 0.1;
  o.duration = ts->duration;
  o.calm = ts->calm;
  o.solver = ts->solver;
  if (ts->tol > 0.0) o.tol = ts->tol;
  if (ts->max_sweeps > 0) o.max_sweeps = ts->max_sweeps;
  if (ts->timed) o.slow_step = o.step;
  vs_fall *f = NULL;
  assert_int_equal(vs_fall_create(m, &o, count, xz, &f, &err), VS_OK);
  double qe[3 * 32 + 6] = {0}, ve[3 * 32 + 6] = {0};
  assert_int_equal(vs_fall_run(f, 0.0, qe, ve, NULL, NULL, NULL, NULL, res, &err), VS_OK);
  double worst = 0.0;
  for (int i = 0; i < 3 * n; i++) worst = fmax(worst, fabs(qe[i]) * (i % 3 == 2 ? H : 1.0));
  if (qt != NULL) memcpy(qt, qe, 3 * (size_t)n * sizeof *qt);
  if (vt != NULL) memcpy(vt, ve, 3 * (size_t)n * sizeof *vt);
  vs_fall_destroy(&f);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
  return worst;
}

/* A tower of eight blocks set in equilibrium on the ground stays there: at rest after the rest
 * window, every block within 0.01 mm of where it stood. Without the tighter tolerance near rest
 * (calm 0) Gauss-Seidel's tolerance lets the blocks sink by up to tol g h^2 a step, the
 * recovery lifts them back, and the tower creeps and never comes to rest. */
static void test_tower_rests(void **state) {
  (void)state;
  vs_fall_result res, res0;
  tower_spec ts = tower8();
  const double moved = tower(&ts, NULL, NULL, &res);
  ts.calm = 0.0;
  const double moved0 = tower(&ts, NULL, NULL, &res0);
  print_message("tower of 8: at rest %d after %.3f s, moved %.3g m, recovery's work %.3g J, "
                "%ld steps near rest; without the calm tolerance: at rest %d after %.3f s, moved "
                "%.3g m, recovery's work %.3g J\n", res.at_rest, res.t_end, moved, res.recovered,
                res.calm_steps, res0.at_rest, res0.t_end, moved0, res0.recovered);
  assert_int_equal(res.at_rest, 1);
  assert_true(res.t_end < 0.1 + 0.01);
  assert_true(moved < 1e-5);
  assert_int_equal(res.calm_steps, res.steps);
}

/* Bodies that touch nothing of each other's cannot act on each other: the tower of eight, on
 * the ground, creeps the same, bit for bit, whether or not a block dropped 0.2 m lands on the
 * ground 1 m away, rocks and settles meanwhile. Gauss-Seidel solves each island of bodies on its
 * own, to its own tolerance (with one sweep count for all, the tower was swept for as long as
 * the block's impact took, and crept differently). The step's length and regime are the whole
 * debris': the same here (1-ms steps, no calm regime). */
static void test_islands_independent(void **state) {
  (void)state;
  vs_fall_result alone, with;
  double qa[3 * 8], qw[3 * 8];
  for (int solver = VS_FALL_NNCG; solver <= VS_FALL_GAUSS_SEIDEL; solver++) {
    tower_spec ts = tower8();
    ts.calm = 0.0, ts.timed = 1, ts.solver = solver;
    tower(&ts, qa, NULL, &alone);
    ts.drop = 0.2;
    tower(&ts, qw, NULL, &with);
    double diff = 0.0;
    for (int i = 0; i < 3 * 8; i++) diff = fmax(diff, fabs(qa[i] - qw[i]));
    print_message("tower of 8 for 2 s, %s: %ld sweeps alone, %ld with the block dropped beside "
                  "it; largest difference of a coordinate %.3g\n", vs_fall_solver_name(solver),
                  alone.sweeps, with.sweeps, diff);
    assert_int_equal(alone.steps, with.steps);
    assert_memory_equal(qa, qw, sizeof qa);
    assert_true(with.sweeps > alone.sweeps); /* the block's impact took sweeps of its own */
  }
}

/* Both solvers on a contact problem with an exact solution: the tower of eight standing on the
 * ground at rest, one 1-ms step from no warm start. The exact impulses hold every block still
 * (each contact carries what stands on it over the step), so every velocity after the step is
 * zero, against the free velocity g h. Solved to 1e-6 g h a sweep, each leaves every point of
 * every block slower than 1e-4 g h; NNCG in fewer sweeps. Then the tower standing for its rest
 * window: each brings it to rest where it stood, NNCG in fewer sweeps and fewer capped steps. */
static void test_nncg_stack(void **state) {
  (void)state;
  const double gh = GRAV * 1e-3;
  long step_sweeps[2], rest_sweeps[2], capped[2];
  for (int sv = 0; sv < 2; sv++) {
    const int solver = sv == 0 ? VS_FALL_NNCG : VS_FALL_GAUSS_SEIDEL;
    tower_spec ts = tower8();
    ts.solver = solver, ts.calm = 0.0, ts.timed = 1, ts.duration = 1e-3;
    ts.tol = 1e-6, ts.max_sweeps = 10000;
    vs_fall_result res;
    double v[3 * 8];
    tower(&ts, NULL, v, &res);
    double fastest = 0.0;
    for (int i = 0; i < 8; i++) /* a block's points: within 0.056 m of its centre */
      fastest = fmax(fastest, hypot(v[3 * i], v[3 * i + 1]) + fabs(v[3 * i + 2]) * 0.056);
    assert_int_equal(res.steps, 1);
    assert_int_equal(res.unconverged, 0);
    step_sweeps[sv] = res.sweeps;
    ts = tower8();
    ts.solver = solver;
    vs_fall_result rest;
    const double moved = tower(&ts, NULL, NULL, &rest);
    rest_sweeps[sv] = rest.sweeps, capped[sv] = rest.unconverged;
    print_message("tower of 8, %s: one step from cold in %ld sweeps, fastest point then %.3g g h; "
                  "standing: at rest %d after %.3f s, moved %.3g m, %ld sweeps, %ld steps capped\n",
                  vs_fall_solver_name(solver), res.sweeps, fastest / gh, rest.at_rest,
                  rest.t_end, moved, rest.sweeps, rest.unconverged);
    assert_true(fastest < 1e-4 * gh);
    assert_int_equal(rest.at_rest, 1);
    assert_true(moved < 1e-5);
  }
  assert_true(step_sweeps[0] < step_sweeps[1]);
  assert_true(rest_sweeps[0] < rest_sweeps[1]);
  assert_true(capped[0] < capped[1]);
}

/* The reference arch at its self-weight equilibrium (the elastic joints' solution), its joints
 * then rigid contacts whose impulses start from that equilibrium's joint forces (as the fall
 * starts from the forces at the collapse): it stands, its weight carried by the supports. At
 * rest its steps are all slow ones (2 ms): the supports carry the weight only if the reactions
 * are the impulses over the step's own length (the warm start's scaling: test_slow_step). */
static void test_arch_stands(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  vs_joint_law law = {.kn = 3e9, .ks = 1.5e9, .mu = 0.7};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  vs_path_opts po;
  vs_test_path_opts(&c, &po);
  const int ne = vs_model_ext_size(m), n = 3 * g->n_blocks;
  double *qe = calloc((size_t)ne, sizeof *qe), *ve = calloc((size_t)ne, sizeof *ve);
  vs_joint_state *js = calloc((size_t)g->n_joints, sizeof *js);
  assert_true(qe && ve && js);
  long iters = 0;
  assert_int_equal(vs_equilibrium_solve(m, &po, 0.0, qe, &iters, &err), VS_OK);
  vs_model_joint_states(m, qe, 0.0, js);
  double q0[3 * 55];
  memcpy(q0, qe, (size_t)n * sizeof *qe);
  vs_fall_opts o;
  vs_fall_opts_default(&o);
  o.duration = 0.05;
  o.rest_ke = 0.0;
  vs_fall *f = NULL;
  assert_int_equal(vs_fall_create(m, &o, NULL, NULL, &f, &err), VS_OK);
  vs_fall_result res;
  assert_int_equal(vs_fall_run(f, 0.0, qe, ve, NULL, js, NULL, NULL, &res, &err), VS_OK);
  double worst = 0.0, r[6];
  for (int i = 0; i < n; i++)
    worst = fmax(worst, fabs(qe[i] - q0[i]) * (i % 3 == 2 ? g->thickness : 1.0));
  vs_fall_reactions(f, r);
  const double fz = r[1] + r[4], W = vs_geometry_weight(g);
  print_message("arch stands: after %.3f s largest displacement %.3g m (rotations x t); "
                "supports carry Fz %.6f N of the weight %.6f N; %ld steps, %.1f sweeps a step, %ld "
                "stopped at the cap (last change up to %.3g m/s), %d contacts\n", res.t_end, worst,
                fz, W, res.steps, (double)res.sweeps / (double)res.steps, res.unconverged,
                res.residual, res.max_contacts);
  assert_true(worst < 1e-5); /* a hundredth of a millimetre: the joints' elastic closure */
  assert_true(fabs(fz - W) < 1e-3 * W);
  assert_int_equal(res.slow_steps, res.steps);
  assert_true(res.cpu_s >= 0.0 && res.cpu_s <= res.wall_s + 0.01);
  free(qe), free(ve), free(js);
  vs_fall_destroy(&f);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

static void test_options(void **state) {
  (void)state;
  block bk;
  block_make(&bk, 0.2, 0.1, 0.5, 1e-3);
  vs_fall_opts o;
  vs_fall_opts_default(&o);
  vs_error err;
  vs_error_clear(&err);
  vs_fall *f = NULL;
  o.step = 0.0;
  assert_int_equal(vs_fall_create(bk.m, &o, NULL, NULL, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "0 < step <= 0.1"));
  assert_null(f);
  vs_fall_opts_default(&o);
  o.tol = 2.0;
  assert_int_equal(vs_fall_create(bk.m, &o, NULL, NULL, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "0 < tol <= 1"));
  vs_fall_opts_default(&o);
  o.slow_step = 0.5 * o.step;
  assert_int_equal(vs_fall_create(bk.m, &o, NULL, NULL, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "step = 0.001 <= slow_step <= 0.1"));
  vs_fall_opts_default(&o);
  o.slow_speed = -1.0;
  assert_int_equal(vs_fall_create(bk.m, &o, NULL, NULL, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "0 <= slow_speed < inf"));
  vs_fall_opts_default(&o);
  o.calm = -1.0;
  assert_int_equal(vs_fall_create(bk.m, &o, NULL, NULL, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "0 <= calm < inf"));
  vs_fall_opts_default(&o);
  const int count[3] = {2, 0, 0};
  const double xz[4] = {0, 0, 1, 1};
  assert_int_equal(vs_fall_create(bk.m, &o, count, xz, &f, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "3 to 16 vertices"));
  block_free(&bk);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_drop),
      cmocka_unit_test(test_warm_start),
      cmocka_unit_test(test_overlap_recovery),
      cmocka_unit_test(test_slide),
      cmocka_unit_test(test_slow_step),
      cmocka_unit_test(test_rocking_housner),
      cmocka_unit_test(test_fold_over_corner),
      cmocka_unit_test(test_corner_corner),
      cmocka_unit_test(test_tower_rests),
      cmocka_unit_test(test_islands_independent),
      cmocka_unit_test(test_nncg_stack),
      cmocka_unit_test(test_arch_stands),
      cmocka_unit_test(test_options),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
