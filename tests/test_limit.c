/* The limit analysis (limit.h) against hand calculations written here, none of them an LP:
 *  - a block and a two-block column under tilt overturn at lambda = b / H (width over height,
 *    rigid blocks on a no-tension base), or slide at lambda = mu when mu is the smaller, which
 *    the solution then calls an upper bound;
 *  - a block overhanging the one below it tips about that block's edge under a point load at its
 *    tip: lambda P (B - b) = W (b - B / 2);
 *  - a three-block arch and the reference specimen under a point load, and the specimen under
 *    tilt: the kinematic theorem by hand, every four-hinge mechanism (instantaneous centres,
 *    the hinges opening the right way, virtual work) and its least load factor;
 *  - the reference specimen's least and greatest thrust under self-weight: the symmetric thrust
 *    line by statics (the horizontal thrust H and its moment at the crown, every joint of a half
 *    arch holding it with N >= 0 at both ends and |V| <= mu N, the polygon of (H, moment) by its
 *    vertices), the arch computed here from R, t, the embrace and the density;
 *  - its least thickness: the same statics, bisected here; a semicircle's against Milankovitch's
 *    t / r = 0.1075;
 *  - consistency: the elastic self-weight state's thrust lies between the least and the greatest,
 *    the mechanism has four hinges that all open, a pinned springing carries its thrust at its
 *    centre; and the command line (analysis.type = limit, its errors). */
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

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/limit.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"

#define VS_SCRATCH "limit"
#include "scratch.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static const double PI = 3.14159265358979323846;

/* |a - b| <= tol, saying the values when not */
#define near(a, b, tol)                                                                        \
  do {                                                                                         \
    const double a_ = (a), b_ = (b);                                                           \
    if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.17g, %s = %.17g", #a, a_, #b, b_);         \
  } while (0)

/* ---------------------------------------------------------------------------------------------
 * Columns: blocks of width b stacked on the base (the left support), x in [x0, x0 + b] */

static vs_geometry *column(int n, const double *width, const double *height, const double *mass) {
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(n, n, &g, &err), VS_OK);
  double z = 0.0;
  for (int i = 0; i < n; i++) {
    /* the joint under block i: its face is the narrower of the two blocks' (all from x = 0) */
    const double face = i == 0 ? width[0] : fmin(width[i - 1], width[i]);
    g->joints[i] = (vs_joint_geom){.a = i == 0 ? VS_SUPPORT_LEFT : i - 1, .b = i,
                                   .px = 0.5 * face, .pz = z, .nx = 0.0, .nz = 1.0,
                                   .length = face, .depth = 1.0};
    g->blocks[i] = (vs_block){.mass = mass[i], .inertia = 1.0, .cx = 0.5 * width[i],
                              .cz = z + 0.5 * height[i], .area = width[i] * height[i]};
    z += height[i];
  }
  g->gravity = 9.81;
  return g;
}

static vs_limit_opts opts_mu(double mu) {
  vs_limit_opts o;
  vs_limit_opts_default(&o);
  o.mu = mu;
  return o;
}

/* The load factor of geometry g under the forces f[0..nf-1] into s; its outcome. */
static vs_limit_outcome try_load(const vs_geometry *g, double mu, const vs_limit_force *f, int nf,
                                 vs_limit_solution *s) {
  vs_error err;
  vs_error_clear(&err);
  const vs_limit_opts o = opts_mu(mu);
  vs_limit *l = NULL;
  assert_int_equal(vs_limit_create(g, &o, f, nf, &l, &err), VS_OK);
  assert_int_equal(vs_limit_solve(l, VS_LIMIT_LOAD_FACTOR, s, &err), VS_OK);
  vs_limit_destroy(&l);
  return s->outcome;
}

/* ... which must be optimal */
static void solve_load(const vs_geometry *g, double mu, const vs_limit_force *f, int nf,
                       vs_limit_solution *s) {
  assert_int_equal(try_load(g, mu, f, nf, s), VS_LIMIT_OPTIMAL);
}

static void tilt_of(const vs_geometry *g, vs_limit_force **f, int *n) {
  vs_error err;
  vs_error_clear(&err);
  const vs_load_def tilt = {.kind = VS_LOAD_TILT};
  assert_int_equal(vs_limit_live_load(g, &tilt, NULL, f, n, &err), VS_OK);
  assert_int_equal(*n, g->n_blocks);
}

/* One block, then two, of width b and height h each, tilted: overturning about the base's
 * downhill edge when lambda W (H / 2) = W (b / 2), lambda = b / H with H the column's height
 * (the joint between the blocks holds: it would need b / h). mu = 2 > b / H: no sliding. */
static void test_column_tilt_overturns(void **state) {
  (void)state;
  const double b = 0.2, h = 0.3, w[2] = {b, b}, hh[2] = {h, h}, m[2] = {1.0, 1.0};
  for (int n = 1; n <= 2; n++) {
    vs_geometry *g = column(n, w, hh, m);
    vs_limit_force *f = NULL;
    int nf = 0;
    tilt_of(g, &f, &nf);
    vs_limit_solution s = {0};
    solve_load(g, 2.0, f, nf, &s);
    near(s.value, b / (n * h), 1e-9);
    /* the base pivots on its +x edge (the intrados end, since the tangent is -x) and opens at
     * the other; the joint between the blocks stays closed; nothing at the friction limit */
    assert_int_equal(s.hinge[0], 'I');
    if (n == 2) assert_int_equal(s.hinge[1], 0);
    assert_int_equal(s.n_hinges, 1);
    assert_int_equal(s.n_sliding, 0);
    assert_int_equal(s.n_friction, 0);
    print_message("column of %d: lambda = %.12f (b/H = %.12f), exact\n", n, s.value, b / (n * h));
    vs_limit_solution_free(&s);
    free(f);
    vs_geometry_destroy(&g);
  }
}

/* mu = 0.2 < b / H = 1/3: each joint slides when lambda W_above = mu W_above, lambda = mu; the
 * mechanism slides and the solution is at the friction limit (an upper bound). */
static void test_column_tilt_slides(void **state) {
  (void)state;
  const double w[2] = {0.2, 0.2}, hh[2] = {0.3, 0.3}, m[2] = {1.0, 3.0};
  vs_geometry *g = column(2, w, hh, m);
  vs_limit_force *f = NULL;
  int nf = 0;
  tilt_of(g, &f, &nf);
  vs_limit_solution s = {0};
  solve_load(g, 0.2, f, nf, &s);
  near(s.value, 0.2, 1e-9);
  assert_true(s.n_sliding >= 1);
  assert_true(s.n_friction >= 1);
  char buf[64];
  vs_limit_list(&s, 'f', buf, sizeof buf);
  assert_true(buf[0] != '\0');
  vs_limit_solution_free(&s);
  free(f);
  vs_geometry_destroy(&g);
}

/* A block of width B = 0.5 m on one of width b = 0.3 m (both from x = 0), a point load P at the
 * upper block's far tip: it tips about the lower block's edge x = b when lambda P (B - b) =
 * W1 (b - B/2) (its weight W1 at B/2); the base would need W0 b/2 more. */
static void test_overhang_point(void **state) {
  (void)state;
  const double B = 0.5, b = 0.3, w[2] = {b, B}, hh[2] = {0.4, 0.2}, m[2] = {1.0, 2.0};
  vs_geometry *g = column(2, w, hh, m);
  const double W1 = m[1] * g->gravity, P = 1.0;
  const vs_limit_force tip = {1, 0.0, -P, B, 0.6};
  vs_limit_solution s = {0};
  solve_load(g, 0.7, &tip, 1, &s);
  const double hand = W1 * (b - 0.5 * B) / (P * (B - b));
  near(s.value, hand, 1e-9 * hand);
  assert_int_equal(s.hinge[1], 'I'); /* the +x end of the upper joint */
  assert_int_equal(s.hinge[0], 0);
  assert_int_equal(s.n_friction, 0);
  print_message("overhang: lambda = %.12f, by hand %.12f\n", s.value, hand);
  vs_limit_solution_free(&s);
  vs_geometry_destroy(&g);
}

/* ---------------------------------------------------------------------------------------------
 * The kinematic theorem by hand: four-hinge mechanisms of an arch of n blocks, joints 0..n */

typedef struct {
  int n;
  double *sw, *sx, *sz;    /* prefix sums over blocks 0..i-1 of W, W cx, W cz */
  const vs_geometry *g;
} kin_arch;

typedef struct {
  double lambda;
  int joint[4], side[4]; /* the best mechanism's hinges: side 0 intrados, 1 extrados */
  long admissible;       /* mechanisms that open the right way and that the load drives */
} kin_result;

static void end_of(const vs_joint_geom *j, int e, double p[2]) {
  const double h = (e ? 0.5 : -0.5) * j->length;
  p[0] = j->px - h * j->nz; /* the tangent is the normal turned +90 degrees: (-nz, nx) */
  p[1] = j->pz + h * j->nx;
}

/* The velocity at p of the body made of blocks [lo, hi) turning at w about o (its centre), or
 * (body 2) moving with the velocity vb at b and turning at w. */
static void vel_about(double w, const double o[2], const double p[2], const double vo[2],
                      double v[2]) {
  v[0] = vo[0] - w * (p[1] - o[1]);
  v[1] = vo[1] + w * (p[0] - o[0]);
}

/* sum over blocks [lo, hi) of the weights' power for a body whose velocity field is v(p) =
 * vo + w k x (p - o): -W v_z(c) summed = -(vo_z S_W + w (S_x - o_x S_W)) */
static double dead_power(const kin_arch *k, int lo, int hi, double w, const double o[2],
                         const double vo[2]) {
  const double SW = k->sw[hi] - k->sw[lo], SX = k->sx[hi] - k->sx[lo];
  return -(vo[1] * SW + w * (SX - o[0] * SW));
}

/* The load factor of one mechanism (hinges at joints j[0] < .. < j[3], sides sd), or NAN when
 * it is not admissible (a hinge that would close, a load that does no positive work). */
static double mechanism(const kin_arch *k, const int *j, const int *sd, const vs_limit_force *f,
                        int nf) {
  const vs_geometry *g = k->g;
  double P[4][2], Q[4][2];
  for (int h = 0; h < 4; h++) {
    end_of(&g->joints[j[h]], sd[h], P[h]);
    end_of(&g->joints[j[h]], !sd[h], Q[h]);
  }
  const double *A = P[0], *B = P[1], *C = P[2], *D = P[3], zero[2] = {0.0, 0.0};
  const double w1 = 1.0;
  double vB[2];
  vel_about(w1, A, B, zero, vB);
  /* w2 k x (C - B) - w3 k x (C - D) = -vB, k x r = (-r_z, r_x) */
  const double a11 = -(C[1] - B[1]), a12 = (C[1] - D[1]), a21 = (C[0] - B[0]), a22 = -(C[0] - D[0]);
  const double det = a11 * a22 - a12 * a21;
  if (fabs(det) < 1e-12 * g->joints[0].length * g->joints[0].length) return NAN;
  const double w2 = (-vB[0] * a22 + vB[1] * a12) / det, w3 = (-a11 * vB[1] + a21 * vB[0]) / det;
  const double rel[4] = {w1, w2 - w1, w3 - w2, -w3};
  int sign = 0;
  for (int h = 0; h < 4; h++) { /* the far end must open: rel k x (Q - P) . n > 0 */
    const vs_joint_geom *jj = &g->joints[j[h]];
    const double dx = Q[h][0] - P[h][0], dz = Q[h][1] - P[h][1];
    const double open = rel[h] * (-dz * jj->nx + dx * jj->nz);
    const int s = open > 1e-12 * jj->length ? 1 : open < -1e-12 * jj->length ? -1 : 0;
    if (s == 0 || (sign != 0 && s != sign)) return NAN;
    sign = s;
  }
  /* (the orientation: sign -1 means the reversed motion is the admissible one) */
  const double wb[3] = {sign * w1, sign * w2, sign * w3};
  double vb2[2] = {sign * vB[0], sign * vB[1]};
  const double *centre[3] = {A, B, D};
  const double *vo[3] = {zero, vb2, zero};
  const int lo[3] = {j[0], j[1], j[2]}, hi[3] = {j[1], j[2], j[3]};
  double pd = 0.0, pl = 0.0;
  for (int b = 0; b < 3; b++) pd += dead_power(k, lo[b], hi[b], wb[b], centre[b], vo[b]);
  for (int i = 0; i < nf; i++) {
    int b = -1;
    for (int c = 0; c < 3; c++)
      if (f[i].block >= lo[c] && f[i].block < hi[c]) b = c;
    if (b < 0) continue; /* on a block that does not move */
    const double p[2] = {f[i].px, f[i].pz};
    double v[2];
    vel_about(wb[b], centre[b], p, vo[b], v);
    pl += f[i].fx * v[0] + f[i].fz * v[1];
  }
  if (!(pl > 0.0)) return NAN;
  return -pd / pl;
}

/* The least load factor over every four-hinge mechanism of arch g (joints 0..n: joint k between
 * blocks k-1 and k, joint 0 and n on the supports). */
static kin_result kinematic(const vs_geometry *g, const vs_limit_force *f, int nf) {
  kin_arch k = {.n = g->n_blocks, .g = g};
  k.sw = calloc((size_t)k.n + 1, sizeof *k.sw);
  k.sx = calloc((size_t)k.n + 1, sizeof *k.sx);
  k.sz = calloc((size_t)k.n + 1, sizeof *k.sz);
  assert_true(k.sw && k.sx && k.sz);
  for (int i = 0; i < k.n; i++) {
    const double W = g->blocks[i].mass * g->gravity;
    k.sw[i + 1] = k.sw[i] + W;
    k.sx[i + 1] = k.sx[i] + W * g->blocks[i].cx;
    k.sz[i + 1] = k.sz[i] + W * g->blocks[i].cz;
  }
  kin_result r = {.lambda = INFINITY};
  int j[4], sd[4];
  for (j[0] = 0; j[0] <= k.n; j[0]++)
    for (j[1] = j[0] + 1; j[1] <= k.n; j[1]++)
      for (j[2] = j[1] + 1; j[2] <= k.n; j[2]++)
        for (j[3] = j[2] + 1; j[3] <= k.n; j[3]++)
          for (int s = 0; s < 16; s++) {
            for (int h = 0; h < 4; h++) sd[h] = (s >> h) & 1;
            const double lam = mechanism(&k, j, sd, f, nf);
            if (!isfinite(lam)) continue;
            r.admissible++;
            if (lam < r.lambda) {
              r.lambda = lam;
              memcpy(r.joint, j, sizeof j);
              memcpy(r.side, sd, sizeof sd);
            }
          }
  free(k.sw), free(k.sx), free(k.sz);
  return r;
}

/* The LP's hinges are the hand mechanism's. */
static void same_hinges(const vs_limit_solution *s, const kin_result *r) {
  assert_int_equal(s->n_hinges, 4);
  for (int h = 0; h < 4; h++)
    if (s->hinge[r->joint[h]] != (r->side[h] ? 'E' : 'I'))
      fail_msg("hinge %d: joint %d-%c by hand, the LP has '%c'", h, r->joint[h] + 1,
               r->side[h] ? 'E' : 'I', s->hinge[r->joint[h]] ? s->hinge[r->joint[h]] : '0');
  /* every opening rate is >= 0: the mechanism is admissible */
  for (int k = 0; k < 2 * s->n_joints; k++) assert_true(s->open[k] >= 0.0);
}

/* The block under x (absolute) on the extrados of the circular arch of case c, by the circle:
 * angle asin(x / (R + t)) from the crown, voussoirs of equal angles. */
static int block_under(const vs_case *c, double x_abs) {
  const double re = (c->radius_mm + c->thickness_mm) * 1e-3, beta = 0.5 * c->embrace_deg * PI / 180.0;
  const double phi = asin(x_abs / re);
  return (int)floor((phi + beta) / (2.0 * beta / c->voussoirs));
}

/* A point load on arch c at x (from the left springing's intrados point), placed by hand. */
static vs_limit_force point_load(const vs_case *c, double x_mm, double P) {
  const double beta = 0.5 * c->embrace_deg * PI / 180.0;
  const double xa = -c->radius_mm * 1e-3 * sin(beta) + x_mm * 1e-3;
  const double re = (c->radius_mm + c->thickness_mm) * 1e-3;
  return (vs_limit_force){block_under(c, xa), 0.0, -P, xa, sqrt(re * re - xa * xa)};
}

/* Three voussoirs, R = 1 m, t = 0.25 m, embrace 150 deg; point loads at several places. Over
 * the keystone no four-hinge mechanism lets the load do work (the thick keystone wedges between
 * its neighbours): the LP finds no bound either. */
static void test_three_block_arch(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.radius_mm = 1000.0, c.thickness_mm = 250.0, c.embrace_deg = 150.0, c.voussoirs = 3;
  c.density_kg_m3 = 2000.0, c.depth_mm = 1000.0;
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  const double span = vs_case_span_mm(&c);
  const double at[] = {0.1, 0.25, 0.4, 0.5, 0.7, 0.85};
  int bounded = 0, unbounded = 0;
  for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
    const vs_limit_force f = point_load(&c, at[i] * span, 1000.0);
    const kin_result hand = kinematic(g, &f, 1);
    vs_limit_solution s = {0};
    const vs_limit_outcome out = try_load(g, 10.0, &f, 1, &s);
    if (!isfinite(hand.lambda)) {
      print_message("three blocks, load at %.2f L on voussoir %d: no mechanism by hand, the LP "
                    "%s\n", at[i], f.block + 1, out == VS_LIMIT_UNBOUNDED ? "unbounded" : "bounded");
      assert_int_equal(out, VS_LIMIT_UNBOUNDED);
      unbounded++;
      vs_limit_solution_free(&s);
      continue;
    }
    assert_int_equal(out, VS_LIMIT_OPTIMAL);
    bounded++;
    print_message("three blocks, load at %.2f L on voussoir %d: lambda %.10f, by hand %.10f "
                  "(%ld admissible mechanisms)\n",
                  at[i], f.block + 1, s.value, hand.lambda, hand.admissible);
    near(s.value, hand.lambda, 1e-7 * hand.lambda);
    same_hinges(&s, &hand);
    assert_int_equal(s.n_friction, 0);
    vs_limit_solution_free(&s);
  }
  assert_true(bounded >= 4 && unbounded >= 1);
  vs_geometry_destroy(&g);
}

/* The reference specimen's case (the defaults) and its arch. */
static vs_geometry *reference_arch(vs_case *c) {
  vs_case_defaults(c);
  vs_geometry *g = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_test_arch(c, &g, &err), VS_OK);
  return g;
}

/* The reference specimen: a point load at quarter span, and tilt. */
static double g_quarter_lambda = NAN; /* by hand, for the command line's test */

static void test_reference_by_hand(void **state) {
  (void)state;
  vs_case c;
  vs_geometry *g = reference_arch(&c);
  const vs_limit_force f = point_load(&c, 0.25 * vs_case_span_mm(&c), 1.0);
  const kin_result hand = kinematic(g, &f, 1);
  vs_limit_solution s = {0};
  solve_load(g, c.friction, &f, 1, &s);
  print_message("reference, 1 N at L/4 on voussoir %d: lambda %.10f, by hand %.10f (%ld "
                "mechanisms); hinges by hand %d-%c %d-%c %d-%c %d-%c\n",
                f.block + 1, s.value, hand.lambda, hand.admissible, hand.joint[0] + 1,
                hand.side[0] ? 'E' : 'I', hand.joint[1] + 1, hand.side[1] ? 'E' : 'I',
                hand.joint[2] + 1, hand.side[2] ? 'E' : 'I', hand.joint[3] + 1,
                hand.side[3] ? 'E' : 'I');
  near(s.value, hand.lambda, 1e-7 * hand.lambda);
  same_hinges(&s, &hand);
  assert_int_equal(s.n_friction, 0); /* no sliding at mu = 0.7: the bound is exact */
  g_quarter_lambda = hand.lambda;
  vs_limit_solution_free(&s);

  vs_limit_force *t = NULL;
  int nt = 0;
  tilt_of(g, &t, &nt);
  const kin_result tilt = kinematic(g, t, nt);
  solve_load(g, c.friction, t, nt, &s);
  print_message("reference, tilt: lambda %.10f, by hand %.10f\n", s.value, tilt.lambda);
  near(s.value, tilt.lambda, 1e-7 * tilt.lambda);
  same_hinges(&s, &tilt);
  vs_limit_solution_free(&s);
  free(t);
  vs_geometry_destroy(&g);
}

/* ---------------------------------------------------------------------------------------------
 * The symmetric thrust line by statics: H at the crown, its moment m = z0 H about the circle's
 * centre; a half-plane a H + b m/t + c >= 0 per condition */

typedef struct {
  double a, b, c;
} halfplane;

/* Annular sector ri..re over [p0, p1] (angles from the crown): weight and centroid, by hand. */
static void sector(double ri, double re, double p0, double p1, double wpa, double *W, double *cx) {
  const double h = 0.5 * (p1 - p0), mid = 0.5 * (p0 + p1);
  const double rc = (2.0 / 3.0) * (re * re * re - ri * ri * ri) / (re * re - ri * ri) * sin(h) / h;
  *W = wpa * h * (re * re - ri * ri);
  *cx = rc * sin(mid);
}

/* The conditions of the right half of the circular arch of case c with its thickness times f
 * (intrados radius kept), n odd (the crown is a voussoir's middle); returns how many. */
static int half_arch(const vs_case *c, double f, halfplane *hp) {
  const double ri = c->radius_mm * 1e-3, t = f * c->thickness_mm * 1e-3, re = ri + t;
  const double beta = 0.5 * c->embrace_deg * PI / 180.0, dphi = 2.0 * beta / c->voussoirs;
  const double wpa = c->density_kg_m3 * c->depth_mm * 1e-3 * c->gravity_m_s2; /* N per m^2 */
  const double mu = c->friction;
  assert_true(c->voussoirs % 2 == 1);
  double W, cx;
  sector(ri, re, 0.0, 0.5 * dphi, wpa, &W, &cx); /* the right half of the crown voussoir */
  double Wt = W, Mx = W * cx;
  int n = 0;
  for (int k = (c->voussoirs + 1) / 2; k <= c->voussoirs; k++) { /* joint k (0-based) */
    const double phi = -beta + k * dphi;
    const double nx = cos(phi), nz = -sin(phi), sx = sin(phi), sz = cos(phi);
    const double Ix = ri * sx, Iz = ri * sz;
    /* F = (H, -Wt) through the joint; N_E t = I x F + m + Mx, N = F.n, V = F.s */
    const halfplane ne = {-Iz / t, 1.0, (-Ix * Wt + Mx) / t};    /* N_E >= 0 (x t / t) */
    const halfplane nn = {nx, 0.0, -Wt * nz};                   /* N */
    const halfplane vv = {sx, 0.0, -Wt * sz};                   /* V */
    hp[n++] = ne;
    hp[n++] = (halfplane){nn.a - ne.a, nn.b - ne.b, nn.c - ne.c}; /* N_I = N - N_E >= 0 */
    hp[n++] = (halfplane){mu * nn.a - vv.a, -vv.b, mu * nn.c - vv.c};
    hp[n++] = (halfplane){mu * nn.a + vv.a, vv.b, mu * nn.c + vv.c};
    if (k < c->voussoirs) { /* the next voussoir joins the free body */
      sector(ri, re, phi, phi + dphi, wpa, &W, &cx);
      Wt += W, Mx += W * cx;
    }
  }
  return n;
}

/* The least and greatest H over the polygon (its vertices: every pair of boundary lines);
 * 0 when it is empty. */
static int thrust_range(const halfplane *hp, int n, double scale, double *hmin, double *hmax) {
  *hmin = INFINITY, *hmax = -INFINITY;
  for (int p = 0; p < n; p++)
    for (int q = p + 1; q < n; q++) {
      const double det = hp[p].a * hp[q].b - hp[p].b * hp[q].a;
      if (fabs(det) < 1e-14) continue;
      const double H = (-hp[p].c * hp[q].b + hp[q].c * hp[p].b) / det;
      const double m = (-hp[p].a * hp[q].c + hp[q].a * hp[p].c) / det;
      int ok = 1;
      for (int r = 0; r < n && ok; r++) ok = hp[r].a * H + hp[r].b * m + hp[r].c >= -1e-11 * scale;
      if (!ok) continue;
      *hmin = fmin(*hmin, H), *hmax = fmax(*hmax, H);
    }
  return isfinite(*hmin);
}

/* The limit analysis of case c (its definition in *d). */
static void analyse(const vs_case *c, vs_run_def *d, vs_limit_analysis *a) {
  vs_error err;
  vs_error_clear(&err);
  vs_case_to_def(c, d);
  assert_int_equal(vs_limit_analyse(d, NULL, a, &err), VS_OK);
}

static void test_reference_thrust(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  halfplane hp[4 * 60];
  const int n = half_arch(&c, 1.0, hp);
  double hmin, hmax;
  assert_true(thrust_range(hp, n, 31.5, &hmin, &hmax));

  vs_run_def d;
  vs_limit_analysis a;
  analyse(&c, &d, &a);
  print_message("reference: least thrust %.10f N (by hand %.10f), greatest %.10f N (by hand "
                "%.10f)\n", a.thrust_min.value, hmin, a.thrust_max.value, hmax);
  near(a.thrust_min.value, hmin, 1e-6 * hmin);
  near(a.thrust_max.value, hmax, 1e-6 * hmax);
  assert_false(a.have_load);
  /* each thrust line touches: the least at the crown's extrados and the haunches' intrados, the
   * greatest at the crown's intrados and the springings' extrados */
  assert_true(a.thrust_min.n_touch >= 3 && a.thrust_max.n_touch >= 3);
  assert_true(a.thrust_max.touch[0] == 'E' && a.thrust_max.touch[55] == 'E');

  /* the elastic self-weight state (k_n 3 and 48 N/mm^3) is one admissible state: its thrust
   * lies between */
  const double kns[2] = {3.0, 48.0};
  vs_error err;
  vs_error_clear(&err);
  for (int i = 0; i < 2; i++) {
    c.kn_N_mm3 = kns[i];
    vs_geometry *g = NULL;
    vs_model *m = NULL;
    assert_int_equal(vs_test_model(&c, &g, &m, &err), VS_OK);
    vs_path_opts po;
    vs_test_path_opts(&c, &po);
    double *q = calloc((size_t)vs_model_size(m), sizeof *q), rc[6];
    long it = 0;
    assert_non_null(q);
    assert_int_equal(vs_equilibrium_solve(m, &po, 0.0, q, &it, &err), VS_OK);
    vs_model_support_reactions(m, q, 0.0, rc);
    print_message("  elastic k_n = %g: thrust %.6f N\n", kns[i], rc[0]);
    assert_true(rc[0] > a.thrust_min.value && rc[0] < a.thrust_max.value);
    free(q);
    vs_model_destroy(&m);
    vs_geometry_destroy(&g);
  }
  vs_limit_analysis_free(&a);
}

/* The least thickness: bisection here on the same statics (the polygon not empty). */
static void test_reference_thickness(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  halfplane hp[4 * 60];
  double lo = 0.05, hi = 1.0, h0, h1;
  for (int it = 0; it < 60 && hi - lo > 1e-10; it++) {
    const double mid = 0.5 * (lo + hi);
    const int n = half_arch(&c, mid, hp);
    if (thrust_range(hp, n, 31.5 * mid, &h0, &h1)) hi = mid;
    else lo = mid;
  }
  vs_run_def d;
  vs_limit_analysis a;
  analyse(&c, &d, &a);
  print_message("reference: thickness factor %.8f [%.8f, %.8f] (by hand %.10f): t_min = %.4f mm, "
                "geometric factor %.4f; %d LPs\n",
                a.thickness_factor, a.thickness_bracket[0], a.thickness_bracket[1], hi,
                hi * c.thickness_mm, 1.0 / hi, a.thickness_solves);
  assert_true(a.thickness_bracket[0] <= hi + 1e-7 && hi <= a.thickness_bracket[1] + 1e-7);
  assert_true(a.thickness_bracket[1] - a.thickness_bracket[0] <= 1e-5);
  /* at the least thickness the thrust line touches at five places or more (both sides of the
   * crown voussoir, the haunches, the springings) */
  assert_true(a.thickness.n_touch >= 5);
  vs_limit_analysis_free(&a);
  /* each LP on its own, from a cold start: a little thinner than the hand's least thickness no
   * goal finds admissible forces, a little thicker both do (CLP's scaled problem alone called
   * arches up to 7e-5 too thin optimal, with forces that violate equilibrium by 1e-5 of the
   * weight) */
  const double rel[] = {-1e-4, -9e-5, -8e-5, -7e-5, -6e-5, -5e-5, -4e-5, -3e-5, -2e-5, -1e-5,
                        1e-5,  2e-5,  5e-5,  1e-4};
  vs_error err;
  vs_error_clear(&err);
  for (size_t i = 0; i < sizeof rel / sizeof rel[0]; i++) {
    vs_arch_def arch = d.arch;
    arch.thickness *= hi * (1.0 + rel[i]);
    vs_geometry *g = NULL;
    vs_limit *l = NULL;
    vs_limit_solution s = {0};
    assert_int_equal(vs_geometry_create_arch(&arch, &g, &err), VS_OK);
    assert_int_equal(vs_limit_create(g, NULL, NULL, 0, &l, &err), VS_OK);
    for (int goal = VS_LIMIT_THRUST_MIN; goal <= VS_LIMIT_THRUST_MAX; goal++) {
      assert_int_equal(vs_limit_solve(l, (vs_limit_goal)goal, &s, &err), VS_OK);
      if (s.outcome != (rel[i] < 0.0 ? VS_LIMIT_INFEASIBLE : VS_LIMIT_OPTIMAL))
        fail_msg("thickness %.6f of the least (by hand), goal %d: outcome %d", 1.0 + rel[i], goal,
                 s.outcome);
    }
    vs_limit_solution_free(&s);
    vs_limit_destroy(&l);
    vs_geometry_destroy(&g);
  }
}

/* A semicircular arch's least thickness: Milankovitch's t / r = 0.1075 (r the centre line's
 * radius; Heyman's approximation gives 0.106), the haunch hinges at 54.5 deg from the crown, for
 * a continuous arch; 199 voussoirs come within 0.5 % and one joint of it. */
static void test_semicircle_milankovitch(void **state) {
  (void)state;
  vs_run_def d;
  vs_run_def_default(&d);
  d.arch.embrace = PI;
  d.arch.voussoirs = 199;
  vs_limit_analysis a;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&d, NULL, &a, &err), VS_OK);
  const double t = a.thickness_factor * d.arch.thickness, ratio = t / (d.arch.radius + 0.5 * t);
  int haunch = -1;
  for (int k = 0; k < a.thickness.n_joints / 2; k++)
    if (a.thickness.touch[k] == 'I') haunch = k;
  assert_true(haunch > 0);
  const double angle = 90.0 - haunch * 180.0 / 199.0; /* joint k (0-based) from the crown, deg */
  print_message("semicircle, 199 voussoirs: t/r = %.5f (Milankovitch 0.1075), haunch hinge at "
                "joint %d, %.2f deg from the crown (54.5)\n", ratio, haunch + 1, angle);
  near(ratio, 0.1075, 0.0005);
  near(angle, 54.5, 180.0 / 199.0);
  vs_limit_analysis_free(&a);
}

/* A pinned springing carries its thrust at its centre (eta = 1/2); the LP still solves. */
static void test_pinned(void **state) {
  (void)state;
  vs_run_def d;
  vs_run_def_default(&d);
  d.support.left_kind = d.support.right_kind = VS_SUPPORT_PINNED;
  vs_limit_analysis a;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&d, NULL, &a, &err), VS_OK);
  const vs_limit_solution *s[2] = {&a.thrust_min, &a.thrust_max};
  for (int i = 0; i < 2; i++) {
    assert_int_equal(s[i]->outcome, VS_LIMIT_OPTIMAL);
    near(s[i]->eta[0], 0.5, 1e-9);
    near(s[i]->eta[55], 0.5, 1e-9);
  }
  vs_limit_analysis_free(&a);
}

/* ---------------------------------------------------------------------------------------------
 * The live load's placement and its errors */

static void test_live_load(void **state) {
  (void)state;
  vs_case c;
  vs_geometry *g = reference_arch(&c);
  vs_error err;
  vs_error_clear(&err);
  const double beta = 0.5 * c.embrace_deg * PI / 180.0, x0 = -0.3 * sin(beta);
  /* a point: on the voussoir the circle puts under it */
  const double xs[] = {1.0, 100.0, 266.1, 400.0, 531.0};
  for (size_t i = 0; i < sizeof xs / sizeof xs[0]; i++) {
    const vs_load_def ld = {.kind = VS_LOAD_POINT, .value = 7.0, .x = xs[i] * 1e-3};
    vs_limit_force *f = NULL;
    int n = 0;
    assert_int_equal(vs_limit_live_load(g, &ld, NULL, &f, &n, &err), VS_OK);
    assert_int_equal(n, 1);
    assert_int_equal(f[0].block, block_under(&c, x0 + xs[i] * 1e-3));
    near(f[0].px, x0 + xs[i] * 1e-3, 1e-15);
    assert_true(f[0].fx == 0.0 && f[0].fz == -7.0);
    free(f);
  }
  /* a patch: the shares add to the load, each in proportion to its block's width under it */
  const vs_load_def patch = {.kind = VS_LOAD_PATCH, .value = 10.0, .x = 0.2, .width = 0.05};
  vs_limit_force *f = NULL;
  int n = 0;
  assert_int_equal(vs_limit_live_load(g, &patch, NULL, &f, &n, &err), VS_OK);
  assert_true(n >= 2);
  double sum = 0.0, moment = 0.0;
  for (int i = 0; i < n; i++) sum += f[i].fz, moment += f[i].fz * f[i].px;
  near(sum, -10.0, 1e-12);
  near(moment / sum, x0 + 0.2, 1e-12); /* a uniform load's resultant at its middle */
  free(f);
  /* errors, naming the key */
  const vs_load_def off = {.kind = VS_LOAD_POINT, .value = 1.0, .x = 0.6};
  assert_int_equal(vs_limit_live_load(g, &off, NULL, &f, &n, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "load.x_mm = 600: not over the arch's extrados (allowed: ["));
  assert_null(f);
  const vs_load_def thin = {.kind = VS_LOAD_PATCH, .value = 1.0, .x = 0.2, .width = 0.0};
  assert_int_equal(vs_limit_live_load(g, &thin, NULL, &f, &n, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "load.width_mm = 0"));
  const vs_load_def wide = {.kind = VS_LOAD_PATCH, .value = 1.0, .x = 0.2, .width = 0.5};
  assert_int_equal(vs_limit_live_load(g, &wide, NULL, &f, &n, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "the patch reaches beyond"));
  /* the load factor without a live load, a force on no block */
  vs_limit *l = NULL;
  vs_limit_solution s = {0};
  assert_int_equal(vs_limit_create(g, NULL, NULL, 0, &l, &err), VS_OK);
  assert_int_equal(vs_limit_solve(l, VS_LIMIT_LOAD_FACTOR, &s, &err), VS_ERR_INVALID);
  vs_limit_destroy(&l);
  const vs_limit_force bad = {55, 0.0, -1.0, 0.0, 0.0};
  assert_int_equal(vs_limit_create(g, NULL, &bad, 1, &l, &err), VS_ERR_INVALID);
  assert_null(l);
  vs_limit_solution_free(&s);
  vs_geometry_destroy(&g);
}

/* ---------------------------------------------------------------------------------------------
 * The command line */

static int vsrun(const char *extra) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' run '%s' -q %s >out.txt 2>err.txt", g_dir, VS_BINARY,
           REFERENCE, extra);
  return sh(cmd);
}

static double json_number(const char *text, const char *key) {
  const char *p = strstr(text, key);
  if (p == NULL) fail_msg("no %s in %s", key, text);
  return strtod(p + strlen(key), NULL);
}

static void test_cli(void **state) {
  (void)state;
  char before[4096], after[4096];
  listing(before, sizeof before);
  vs_case c;
  vs_case_defaults(&c);
  char quarter[128];
  snprintf(quarter, sizeof quarter, "--set analysis.type=limit --json --set load.kind=point "
           "--set load.x_mm=%.17g", 0.25 * vs_case_span_mm(&c));
  assert_int_equal(vsrun(quarter), 0);
  const char *out = slurp(in_dir("out.txt"), NULL);
  assert_non_null(strstr(out, "\"analysis\":\"limit\""));
  assert_non_null(strstr(out, "\"load_factor_exact\":true"));
  const double lam = json_number(out, "\"load_factor\":");
  const double tmin = json_number(out, "\"thrust_min_N\":"), tmax = json_number(out, "\"thrust_max_N\":");
  const double tf = json_number(out, "\"thickness_factor\":");
  assert_true(tmin > 0.0 && tmin < tmax && tf > 0.0 && tf < 1.0);
  if (isfinite(g_quarter_lambda)) near(lam, g_quarter_lambda, 1e-6 * g_quarter_lambda);
  char cmd[512];
  snprintf(cmd, sizeof cmd, "python3 -c 'import json,sys; json.load(open(sys.argv[1]))' '%s'",
           in_dir("out.txt"));
  assert_int_equal(sh(cmd), 0); /* valid JSON */
  listing(after, sizeof after);
  assert_string_equal(before, after); /* no record */

  /* the summary */
  assert_int_equal(vsrun("--set analysis.type=limit --set load.kind=tilt"), 0);
  out = slurp(in_dir("out.txt"), NULL);
  assert_non_null(strstr(out, "load factor  lambda = "));
  assert_non_null(strstr(out, "geometric factor of safety"));

  /* bad input: exit 2, a message naming the key, nothing written */
  const struct {
    const char *args, *msg;
  } bad[] = {
      {"--set analysis.type=load", "voussoir: analysis.type = load needs a live load"},
      {"--set load.kind=point --set load.x_mm=100", "load.kind = point: the support's path carries no live load"},
      {"--set analysis.hold_mm=5", "analysis.hold_mm = 5: a held support displacement needs analysis.type = load"},
      {"--set analysis.type=limit --set load.kind=point --set load.x_mm=900", "load.x_mm = 900: not over the arch's extrados"},
      {"--set analysis.type=limit --set load.kind=patch --set load.x_mm=100", "load.width_mm = 0: a patch load needs a width"},
      {"--set analysis.type=limit -o x.h5", "-o: analysis.type = limit writes no record"},
      {"--set analysis.type=limit --csv x.csv", "--csv: analysis.type = limit writes no record"},
      {"--set analysis.type=sideways", "analysis.type = sideways: unknown name (allowed: one of support, load, limit)"},
      {"--set load.value_N=0", "load.value_N = 0: out of range"},
  };
  /* the study commands follow the support's path only */
  const struct {
    const char *cmd, *name;
  } studies[] = {{"sweep '" REFERENCE "' --alpha 0 -q -o sw", "sweep"},
                 {"montecarlo '" REFERENCE "' --samples 2 -q -o mc", "montecarlo"},
                 {"calibrate '" REFERENCE "' --target-dz-pct 16 -q", "calibrate"}};
  for (size_t i = 0; i < sizeof studies / sizeof studies[0]; i++) {
    listing(before, sizeof before);
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s --set analysis.type=limit >out.txt 2>err.txt",
             g_dir, VS_BINARY, studies[i].cmd);
    assert_int_equal(sh(cmd), 2);
    char want[160];
    snprintf(want, sizeof want, "analysis.type = limit: %s follows the support's path",
             studies[i].name);
    assert_non_null(strstr(slurp(in_dir("err.txt"), NULL), want));
    listing(after, sizeof after);
    assert_string_equal(before, after);
  }
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    listing(before, sizeof before);
    assert_int_equal(vsrun(bad[i].args), 2);
    const char *e = slurp(in_dir("err.txt"), NULL);
    if (strstr(e, bad[i].msg) == NULL) fail_msg("%s: stderr %s", bad[i].args, e);
    assert_string_equal(slurp(in_dir("out.txt"), NULL), "");
    listing(after, sizeof after);
    assert_string_equal(before, after);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_column_tilt_overturns),
      cmocka_unit_test(test_column_tilt_slides),
      cmocka_unit_test(test_overhang_point),
      cmocka_unit_test(test_three_block_arch),
      cmocka_unit_test(test_reference_by_hand),
      cmocka_unit_test(test_reference_thrust),
      cmocka_unit_test(test_reference_thickness),
      cmocka_unit_test(test_semicircle_milankovitch),
      cmocka_unit_test(test_pinned),
      cmocka_unit_test(test_live_load),
      cmocka_unit_test(test_cli),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
