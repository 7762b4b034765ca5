/* Ground contact (contact.h) against independent references:
 *  - its forces are the gradient of its stored energy while the vertices stick, and its analytic
 *    Jacobians dF/dq and dF/dv match central differences, sticking and sliding;
 *  - a block dropped flat on the ground rebounds with the coefficient of restitution it was given
 *    (the vertical impact of a linear spring-dashpot of damping ratio zeta: e = exp(-zeta pi /
 *    sqrt(1 - zeta^2)), so the first rebound rises to e^2 h0), and comes to rest on the ground
 *    with the static penetration m g / (2 k_v) under each of its two bottom vertices;
 *  - a block dropped tilted and sliding rocks, slides, stops and comes to rest lying flat, the
 *    energy balance (kinetic + gravity + elastic + dissipated by the dashpots and by friction)
 *    held throughout;
 *  - the reference run (the default case: the specimen, k_n 3 N/mm^3, settlement) lands, with
 *    the rigid fall (fall.h) and, on an arch of 21 voussoirs, with this penalty contact: at its
 *    last recorded state no block vertex (computed here from the block's sector and its rigid
 *    motion) is below the ground by more than the stated tolerance (rigid: g h^2, what one step
 *    of gravity moves a vertex; penalty: the whole arch's weight on one vertex, W / k_v); the
 *    kinetic energy is below the rest level; the fall's energy balance holds to 1 % of the
 *    largest energy term; no vertex of a block is inside another block it shares no joint with
 *    or inside a pier (outlines written out here from the geometry) by more than the same
 *    tolerance.
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

#include <sundials/sundials_context.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "contact.h"
#include "voussoir/dynamic.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/run.h"

static const double PI = 3.14159265358979323846;
static const double GRAV = 9.81;

static double urand(unsigned *s, double lo, double hi) {
  *s = *s * 1103515245u + 12345u;
  return lo + (hi - lo) * (double)((*s >> 8) & 0xffffff) / (double)0xffffff;
}

/* ------------------------------- 1. forces and Jacobian ------------------------------- */

static void test_jacobian(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = 7;
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  vs_contact *ct = NULL;
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  vs_joint_law law = {.kn = 3e9, .ks = 1.5e9, .mu = 0.7};
  assert_int_equal(vs_model_create(g, &law, 0.0, &m, &err), VS_OK);
  assert_int_equal(vs_contact_create(m, 0.5, 0, NULL, NULL, &ct, &err), VS_OK);
  assert_int_equal(vs_contact_count(ct), 7 * 5 - 4); /* 4 corners + extrados mid, less the springings' */
  const int ne = vs_model_ext_size(m), n = 3 * g->n_blocks;
  double *q = calloc((size_t)ne, sizeof *q), *v = calloc((size_t)ne, sizeof *v);
  double *Fp = calloc((size_t)ne, sizeof *Fp), *Fm = calloc((size_t)ne, sizeof *Fm);
  assert_true(q && v && Fp && Fm);
  unsigned seed = 7;
  for (int i = 0; i < n; i++) { /* a fallen arch: blocks sunk by 0..1 mm, turned, moving */
    q[i] = (i % 3 == 2) ? urand(&seed, -0.3, 0.3) : urand(&seed, -1e-3, 1e-3);
    v[i] = urand(&seed, -0.1, 0.1);
  }
  /* the ground 5 mm below the crown's extrados: most vertices deep below it, a few above */
  vs_contact_arm(ct, g->radius + g->thickness - 5e-3, q);
  int touching = 0;
  for (int k = 0; k < vs_contact_count(ct); k++) {
    double x, z;
    vs_contact_vertex(ct, q, k, &x, &z);
    touching += z < vs_contact_level(ct);
  }
  print_message("contact jacobian: %d of %d vertices below the ground\n", touching,
                vs_contact_count(ct));
  assert_true(touching >= 4);
  SUNContext ctx;
  assert_int_equal(SUNContext_Create(NULL, &ctx), 0);
  SUNMatrix K = SUNSparseMatrix(ne, ne, vs_model_ext_nnz(m), CSC_MAT, ctx);
  SUNMatrix C = SUNSparseMatrix(ne, ne, vs_model_ext_nnz(m), CSC_MAT, ctx);
  for (int pass = 0; pass < 2; pass++) { /* 0: sticking at the anchors; 1: moved, sliding */
    if (pass == 1)
      for (int i = 0; i < n; i += 3) q[i] += 2e-3; /* beyond mu N / k_t where p < 1.4 mm */
    vs_model_ext_jacobian(m, q, K); /* the pattern */
    double *v0 = calloc((size_t)ne, sizeof *v0);
    assert_non_null(v0);
    memset(SUNSparseMatrix_Data(K), 0, (size_t)SUNSparseMatrix_NNZ(K) * sizeof(double));
    SUNMatCopy(K, C);
    vs_contact_jacobian(ct, q, v0, K, NULL); /* at v = 0: the dashpots' dependence on q is */
    vs_contact_jacobian(ct, q, v, NULL, C);  /* left out of K (as the joints') */
    free(v0);
    const sunindextype *kp = SUNSparseMatrix_IndexPointers(K), *ki = SUNSparseMatrix_IndexValues(K);
    const double *kx = SUNSparseMatrix_Data(K), *cx = SUNSparseMatrix_Data(C);
    int bad = 0, checked = 0;
    double *zv = calloc((size_t)ne, sizeof *zv);
    assert_non_null(zv);
    for (int j = 0; j < n; j++) {
      const double L = g->thickness, hq = (j % 3 == 2) ? 1e-7 / L : 1e-7; /* rotations: / L */
      for (int w = 0; w < 2; w++) { /* w 0: dF/dq, 1: dF/dv */
        double *x = w ? v : q;
        const double x0 = x[j], h = w ? 1e3 * hq : hq; /* F is linear in v: no truncation */
        memset(Fp, 0, (size_t)ne * sizeof *Fp);
        memset(Fm, 0, (size_t)ne * sizeof *Fm);
        x[j] = x0 + h;
        vs_contact_forces(ct, q, w ? v : zv, Fp, NULL, NULL);
        x[j] = x0 - h;
        vs_contact_forces(ct, q, w ? v : zv, Fm, NULL, NULL);
        x[j] = x0;
        for (int i = 0; i < n; i++) {
          double an = 0.0;
          for (sunindextype p = kp[j]; p < kp[j + 1]; p++)
            if (ki[p] == i) an = w ? cx[p] : kx[p];
          const double fd = (Fp[i] - Fm[i]) / (2 * h);
          /* scales: moments over L, rotations times L; the 1e7 N/m of k_n b t */
          const double s = ((i % 3 == 2) ? 1.0 / L : 1.0) * ((j % 3 == 2) ? L : 1.0);
          const double tol = w ? 1e-6 * fabs(fd * s) + 1e-3 : 1e-5 * fabs(fd * s) + 1e-8 * 1e7;
          checked++;
          if (!(fabs(an - fd) * s <= tol) && bad++ < 10)
            print_message("pass %d %s[%d][%d]: analytic %.10g, differences %.10g\n", pass,
                          w ? "C" : "K", i, j, an, fd);
        }
      }
    }
    free(zv);
    print_message("contact jacobian pass %d: %d entries checked, %d off\n", pass, checked, bad);
    assert_int_equal(bad, 0);
    if (pass == 0) { /* sticking: F (at v = 0) is the gradient of the stored energy */
      double *z0 = calloc((size_t)ne, sizeof *z0), *F = calloc((size_t)ne, sizeof *F);
      assert_true(z0 && F);
      vs_contact_forces(ct, q, z0, F, NULL, NULL);
      for (int j = 0; j < n; j++) {
        const double h = (j % 3 == 2) ? 1e-7 / g->thickness : 1e-7, x0 = q[j];
        q[j] = x0 + h;
        const double ep = vs_contact_energy(ct, q);
        q[j] = x0 - h;
        const double em = vs_contact_energy(ct, q);
        q[j] = x0;
        assert_true(fabs((ep - em) / (2 * h) - F[j]) <= 1e-6 * fabs(F[j]) + 1e-6);
      }
      free(z0);
      free(F);
    }
  }
  SUNMatDestroy(K);
  SUNMatDestroy(C);
  SUNContext_Free(&ctx);
  free(q), free(v), free(Fp), free(Fm);
  vs_contact_destroy(&ct);
  assert_null(ct);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* ------------------------------- 2. a block dropped ------------------------------- */

/* A rectangular block B wide, H high, depth b, centred on x = 0 with its bottom at z = 0 in the
 * reference configuration. Its one joint (a vertical face to the left support) is given an
 * as-built gap of 1 m: it never closes, so the block is free but for the ground. */
typedef struct {
  vs_geometry *g;
  vs_model *m;
  vs_contact *ct;
  double B, H, b, mass, kv, e;
} block;

static void block_make(block *bk, double e) {
  const double B = 0.2, H = 0.1, b = 0.1, rho = 2000.0, kn = 1e10;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(1, 1, &bk->g, &err), VS_OK);
  vs_block *blk = &bk->g->blocks[0];
  blk->area = B * H;
  blk->mass = rho * b * B * H;
  blk->inertia = blk->mass * (B * B + H * H) / 12.0;
  blk->cz = 0.5 * H;
  vs_joint_geom *j = &bk->g->joints[0];
  *j = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .px = -0.5 * B, .pz = 0.5 * H, .nx = 1.0,
                       .nz = 0.0, .length = H, .depth = b};
  bk->g->gravity = GRAV;
  vs_joint_law law = {.kn = kn, .ks = 0.5 * kn, .mu = 0.7, .gap0 = 1.0};
  assert_int_equal(vs_model_create(bk->g, &law, 0.0, &bk->m, &err), VS_OK);
  const int vb[4] = {0, 0, 0, 0};
  const double xz[8] = {-0.5 * B, 0.0, 0.5 * B, 0.0, 0.5 * B, H, -0.5 * B, H};
  assert_int_equal(vs_contact_create(bk->m, e, 4, vb, xz, &bk->ct, &err), VS_OK);
  bk->B = B, bk->H = H, bk->b = b, bk->mass = blk->mass, bk->e = e;
  bk->kv = 0.5 * kn * b * H; /* k_n b t / 2, t the joint's length */
}

static void block_free(block *bk) {
  vs_contact_destroy(&bk->ct);
  vs_model_destroy(&bk->m);
  vs_geometry_destroy(&bk->g);
}

typedef struct {
  double t[200000], z[200000], vz[200000];
  int n;
  double max_bal, scale;
  vs_energy last;
} trace;

static int on_sample(void *user, double t, double delta, const double *q, const double *v,
                     const vs_energy *e) {
  (void)delta;
  trace *tr = user;
  if (tr->n < 200000) {
    tr->t[tr->n] = t;
    tr->vz[tr->n] = v[1];
    tr->z[tr->n++] = q[1];
  }
  tr->max_bal = fmax(tr->max_bal, fabs(e->balance));
  tr->last = *e;
  return 0;
}

static void drop(block *bk, double q[3], double v[3], double t_end, double sample_dt, trace *tr,
                 vs_dyn_result *res) {
  vs_dyn_opts o;
  memset(&o, 0, sizeof o);
  o.rate = 1e-3; /* only clocks delta = rate t: nothing touches the right support */
  o.rtol = 1e-7;
  o.atol_q = 1e-9;
  o.open = 1e-5;
  o.rest_ke = 1e-12; /* J: the departure root, a level KE crosses (KE itself only touches 0) */
  o.rest_time = INFINITY;
  o.collapse_ke = 1e30;
  o.max_delta = o.rate * t_end;
  o.sample_dt = sample_dt;
  vs_error err;
  vs_error_clear(&err);
  vs_dynamic *d = NULL;
  assert_int_equal(vs_dynamic_create(bk->m, &o, &d, &err), VS_OK);
  assert_int_equal(vs_dynamic_set_contact(d, bk->ct, 0.0, &err), VS_OK);
  double qe[9] = {q[0], q[1], q[2]};
  vs_contact_arm(bk->ct, 0.0, qe);
  vs_status st = vs_dynamic_run(d, 0.0, q, v, on_sample, NULL, tr, res, &err);
  if (st != VS_OK) fail_msg("vs_dynamic_run: %s: %s", vs_strerror(st), err.msg);
  vs_dynamic_destroy(&d);
}

/* The rebound speed of the flat landing, integrated here by RK4 from the law of contact.h: two
 * vertices, m z'' = 2 k_v p + 2 c_v s(p) p' - m g with p = -z, s = min(1, p / p_f), from z = 0 at
 * -v_in until z = 0 again. Without gravity it would be e v_in exactly (Kelvin-Voigt); gravity
 * acting through the contact takes about g T (T = pi / omega_d) off it. */
static double rebound_speed(const block *bk, double v_in) {
  const double m = bk->mass, k = 2.0 * bk->kv, pf = m * GRAV / bk->kv;
  const double le = log(bk->e), zeta = -le / sqrt(PI * PI + le * le);
  const double c = 2.0 * 2.0 * zeta * sqrt(0.5 * bk->kv * m); /* two vertices' dashpots */
  double z = 0.0, v = -v_in;
  const double dt = 1e-3 * PI / sqrt(k / m);
#define ACC(z_, v_) ((k * (-(z_)) + c * fmin(1.0, -(z_) / pf) * (-(v_))) / m - GRAV)
  for (int i = 0; i < 100000 && (i == 0 || z < 0.0); i++) {
    const double a1 = ACC(z, v), z2 = z + 0.5 * dt * v, v2 = v + 0.5 * dt * a1;
    const double a2 = ACC(z2, v2), z3 = z + 0.5 * dt * v2, v3 = v + 0.5 * dt * a2;
    const double a3 = ACC(z3, v3), z4 = z + dt * v3, v4 = v + dt * a3, a4 = ACC(z4, v4);
    z += dt * (v + 2 * v2 + 2 * v3 + v4) / 6.0;
    v += dt * (a1 + 2 * a2 + 2 * a3 + a4) / 6.0;
  }
#undef ACC
  return v; /* at z = 0 within a step's travel (1e-3 of the contact) */
}

/* Dropped flat from h0: free fall, an impact of two vertices together (one spring 2 k_v with one
 * dashpot 2 c_v: damping ratio zeta), a rebound to e^2 h0, fewer and smaller bounces, rest. */
static void test_drop_flat(void **state) {
  (void)state;
  block bk;
  block_make(&bk, 0.5);
  const double h0 = 0.01;
  double q[3] = {0.0, h0, 0.0}, v[3] = {0.0, 0.0, 0.0};
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_dyn_result res;
  drop(&bk, q, v, 0.6, 2e-5, tr, &res);
  /* the first rebound's apex: the highest sample after the first touch-down */
  int i = 0;
  while (i < tr->n && tr->z[i] > 0.0) i++;
  while (i < tr->n && tr->z[i] <= 0.0) i++;
  double apex = 0.0;
  for (; i < tr->n && tr->z[i] > 0.0; i++) /* ballistic: the apex from any point of the flight */
    apex = fmax(apex, tr->z[i] + tr->vz[i] * tr->vz[i] / (2.0 * GRAV));
  const double e_meas = sqrt(apex / h0);
  print_message("drop flat: rebound to %.4g mm: restitution %.4f (given %.4f); %ld steps, "
                "%ld root events; max |balance| %.3g J = %.3g m g h0\n", apex * 1e3, e_meas,
                bk.e, res.steps, res.root_events, tr->max_bal, tr->max_bal / (bk.mass * GRAV * h0));
  const double v_in = sqrt(2.0 * GRAV * h0), v_out = rebound_speed(&bk, v_in);
  const double e_ref = v_out / v_in;
  print_message("drop flat: reference (RK4 of the law, gravity included) %.4f\n", e_ref);
  assert_true(fabs(e_meas - e_ref) <= 0.005 * e_ref);
  assert_true(fabs(e_ref - bk.e) <= 0.1 * bk.e); /* gravity's share, g T / (e v_in) ~ 3 % */
  assert_true(res.root_events >= 4); /* two vertices down and up, at least once */
  /* at rest: still, lying flat with the static penetration m g / (2 k_v) per vertex */
  const double ke = 0.5 * bk.mass * (v[0] * v[0] + v[1] * v[1]);
  const double p_static = bk.mass * GRAV / (2.0 * bk.kv);
  double qe[9] = {q[0], q[1], q[2]};
  const double pen = vs_contact_max_penetration(bk.ct, qe, NULL);
  print_message("drop flat: at %.2f s: kinetic %.3g J, penetration %.4g um (static %.4g um), "
                "largest %.4g um\n", res.t_end, ke, pen * 1e6, p_static * 1e6,
                res.max_penetration * 1e6);
  assert_true(ke < 1e-9 * bk.mass * GRAV * h0);
  assert_true(fabs(pen - p_static) <= 1e-3 * p_static);
  assert_true(fabs(q[2]) < 1e-9);
  /* the energy: balance at the integrator's tolerance; the dashpots took the drop's energy */
  assert_true(tr->max_bal < 1e-3 * bk.mass * GRAV * h0);
  assert_true(fabs(tr->last.damped - bk.mass * GRAV * h0) < 1e-3 * bk.mass * GRAV * h0);
  free(tr);
  block_free(&bk);
}

/* Dropped tilted by 0.2 rad and moving sideways at 0.3 m/s: it lands on a corner, slides and
 * rocks, and must come to rest lying flat (theta a multiple of pi/2 with the long side down:
 * 0), penetration below the stated tolerance (twice the static one), energy balance held with
 * friction and the dashpots' losses. */
static void test_drop_tilted(void **state) {
  (void)state;
  block bk;
  block_make(&bk, 0.5);
  const double h0 = 0.02;
  double q[3] = {0.0, h0 + 0.5 * bk.B * sin(0.2), 0.2}, v[3] = {0.3, 0.0, 0.0};
  trace *tr = calloc(1, sizeof *tr);
  assert_non_null(tr);
  vs_dyn_result res;
  drop(&bk, q, v, 2.0, 1e-3, tr, &res);
  const double scale = bk.mass * GRAV * h0 + 0.5 * bk.mass * 0.09;
  const double ke = 0.5 * bk.mass * (v[0] * v[0] + v[1] * v[1]) +
                    0.5 * bk.g->blocks[0].inertia * v[2] * v[2];
  double qe[9] = {q[0], q[1], q[2]};
  const double pen = vs_contact_max_penetration(bk.ct, qe, NULL);
  const double p_static = bk.mass * GRAV / (2.0 * bk.kv);
  print_message("drop tilted: at %.2f s: x %.3f mm, theta %.3g rad, kinetic %.3g J, "
                "penetration %.4g um (static %.4g); friction %.4g J, dashpots %.4g J, "
                "max |balance| %.3g J (%.3g of the energy in)\n", res.t_end, q[0] * 1e3, q[2], ke,
                pen * 1e6, p_static * 1e6, tr->last.friction, tr->last.damped, tr->max_bal,
                tr->max_bal / scale);
  assert_true(ke < 1e-9 * scale);
  assert_true(fabs(q[2]) < 1e-6);
  assert_true(pen < 2.0 * p_static);
  assert_true(tr->last.friction > 0.01 * scale); /* it slid */
  assert_true(tr->max_bal < 1e-3 * scale);
  free(tr);
  block_free(&bk);
}

/* ------------------------------- 3. the reference run lands ------------------------------- */

/* A body's outline at the last state, written out here from the geometry (not collide.c's):
 * a voussoir's four corners and its extrados mid-point, a pier's springing face and the
 * vertical drops from its ends by the span; moved rigidly by (ux, uz, theta) about (cx, cz). */
typedef struct {
  int n;
  double x[5], z[5];
} outline;

static void outline_move(outline *o, double cx, double cz, const double *u) {
  for (int k = 0; k < o->n; k++) {
    const double X = o->x[k] - cx, Z = o->z[k] - cz;
    o->x[k] = cx + u[0] + cos(u[2]) * X - sin(u[2]) * Z;
    o->z[k] = cz + u[1] + sin(u[2]) * X + cos(u[2]) * Z;
  }
}

static void voussoir_outline(const vs_geometry *g, int i, const double *q, outline *o) {
  const vs_block *b = &g->blocks[i];
  const double ph[5] = {b->phi0, b->phi1, b->phi1, 0.5 * (b->phi0 + b->phi1), b->phi0};
  const double r[5] = {0, 0, 1, 1, 1};
  o->n = 5;
  for (int k = 0; k < 5; k++) {
    o->x[k] = (g->radius + r[k] * g->thickness) * sin(ph[k]);
    o->z[k] = (g->radius + r[k] * g->thickness) * cos(ph[k]);
  }
  outline_move(o, b->cx, b->cz, q + 3 * i);
}

static void pier_outline(const vs_geometry *g, int right, const double u[3], outline *o) {
  const vs_joint_geom *j = &g->joints[right ? g->n_joints - 1 : 0];
  const double sx = -j->nz, sz = j->nx, h = 0.5 * j->length;
  o->n = 4;
  o->x[0] = o->x[3] = j->px - h * sx, o->z[0] = j->pz - h * sz;
  o->x[1] = o->x[2] = j->px + h * sx, o->z[1] = j->pz + h * sz;
  o->z[2] = o->z[3] = fmin(o->z[0], o->z[1]) - g->span;
  outline_move(o, j->px, j->pz, u);
}

/* How deep (m) the point is inside the convex outline (<= 0: outside): the least distance
 * behind its edges' lines, either orientation. */
static double depth_in(const outline *o, double x, double z) {
  double area = 0.0, d = INFINITY;
  for (int k = 0; k < o->n; k++) {
    const int l = (k + 1) % o->n;
    area += o->x[k] * o->z[l] - o->x[l] * o->z[k];
  }
  for (int k = 0; k < o->n; k++) {
    const int l = (k + 1) % o->n;
    const double tx = o->x[l] - o->x[k], tz = o->z[l] - o->z[k], len = hypot(tx, tz);
    const double behind = (area > 0 ? -1.0 : 1.0) * (tz * (x - o->x[k]) - tx * (z - o->z[k])) / len;
    d = fmin(d, behind);
  }
  return d;
}

/* The deepest vertex of a block inside another block that shares no joint with it, or inside a
 * pier it is not joined to (the springers stand on theirs), at the blocks' state q and the
 * supports' displacements us (6). */
static double deepest_overlap(const vs_geometry *g, const double *q, const double *us) {
  const int n = g->n_blocks;
  outline *o = calloc((size_t)n + 2, sizeof *o);
  assert_non_null(o);
  for (int i = 0; i < n; i++) voussoir_outline(g, i, q, &o[i]);
  pier_outline(g, 0, us, &o[n]);
  pier_outline(g, 1, us + 3, &o[n + 1]);
  double worst = 0.0;
  for (int a = 0; a < n + 2; a++)
    for (int b = 0; b < n + 2; b++) {
      const int joined = (a < n && b < n && abs(a - b) <= 1) || (a == 0 && b == n) ||
                         (a == n && b == 0) || (a == n - 1 && b == n + 1) ||
                         (a == n + 1 && b == n - 1) || (a >= n && b >= n);
      if (joined) continue;
      for (int k = 0; k < o[a].n; k++) worst = fmax(worst, depth_in(&o[b], o[a].x[k], o[a].z[k]));
    }
  free(o);
  return worst;
}

typedef struct {
  double ke, delta;
  vs_phase phase;
  long fall_steps;
} last_sample;

static int on_run_sample(void *user, const vs_run *run, const vs_run_sample *smp) {
  (void)run;
  last_sample *ls = user;
  ls->phase = smp->phase;
  ls->ke = smp->energy != NULL ? smp->energy->kinetic : 0.0;
  ls->delta = smp->delta;
  ls->fall_steps = smp->fall_steps;
  return 0;
}

/* The reference specimen (voussoirs of them; settlement) run to rest with the fall's scheme;
 * checks of its last state against tol, m: the deepest block vertex below the ground and inside
 * another block or a pier. */
static void lands(vs_fall_scheme scheme, int voussoirs, double tol, const char *why) {
  vs_case c;
  vs_case_defaults(&c);
  c.scheme = scheme;
  c.voussoirs = voussoirs;
  vs_error err;
  vs_error_clear(&err);
  vs_run *run = NULL;
  assert_int_equal(vs_run_create(&c, &run, &err), VS_OK);
  last_sample ls = {0};
  vs_status st = vs_run_execute(run, on_run_sample, NULL, &ls, &err);
  if (st != VS_OK) fail_msg("run: %s: %s", vs_strerror(st), err.msg);
  const vs_geometry *g = vs_run_geometry(run);
  const vs_dyn_result *d = vs_run_dynamic_totals(run);
  const double level = vs_run_ground(run);
  const char *name = scheme == VS_FALL_RIGID ? "rigid" : "penalty";
  assert_true(vs_run_collapse(run)->found);
  assert_true(isfinite(level));
  /* the ground: the lower springing base, the right one moved down by delta at the collapse */
  const double beta = 0.5 * g->embrace, base = g->radius * cos(beta);
  print_message("%s fall, %d voussoirs: ground at %.3f mm (left springing base %.3f mm), fall %s, "
                "%.3f s wall of %.3f s, balance in the fall %.3g\n", name, voussoirs, level * 1e3,
                base * 1e3, d->fall_at_rest ? "at rest" : "not at rest", d->fall_wall_s,
                vs_run_wall_s(run), d->balance_error_fall);
  assert_true(level < base - 0.05 * g->span); /* the settled right springing, 16 % of L down */
  /* every vertex of every block at the last state, from its sector and its rigid motion */
  const double *q = vs_run_state(run);
  double worst = -INFINITY;
  for (int i = 0; i < g->n_blocks; i++) {
    const vs_block *b = &g->blocks[i];
    const double phi[3] = {b->phi0, 0.5 * (b->phi0 + b->phi1), b->phi1};
    for (int a = 0; a < 3; a++)
      for (int r = 0; r < 2; r++) {
        if ((a == 1 && r == 0) || (i == 0 && a == 0) || (i == g->n_blocks - 1 && a == 2))
          continue; /* the concave intrados arc; the faces on the supports (on the piers) */
        const double rad = g->radius + r * g->thickness;
        const double X = rad * sin(phi[a]) - b->cx, Z = rad * cos(phi[a]) - b->cz;
        const double z = b->cz + q[3 * i + 1] + sin(q[3 * i + 2]) * X + cos(q[3 * i + 2]) * Z;
        worst = fmax(worst, level - z);
      }
  }
  const double mass = vs_geometry_weight(g) / g->gravity, rate = c.rate_mm_s * 1e-3;
  const double collapse_ke = c.collapse_ke * vs_geometry_weight(g) * c.thickness_mm * 1e-3 +
                             0.5 * mass * rate * rate;
  const double rest_ke = fmin(c.rest_factor * 0.5 * mass * rate * rate, 0.01 * collapse_ke);
  assert_true(fabs(vs_run_rest_ke(run) - rest_ke) <= 1e-12 * rest_ke);
  print_message("%s fall: last state: deepest vertex %.3g um below the ground (tolerance %s = "
                "%.3g um; %.3g um during the fall), kinetic %.3g J (rest level %.3g J)\n", name,
                worst * 1e6, why, tol * 1e6, d->max_penetration * 1e6, ls.ke, rest_ke);
  /* no vertex inside another block or a pier by more than the same tolerance */
  double us[6] = {0}, u[2];
  vs_model_support_displacement(vs_run_model(run), d->delta_end, u);
  us[3] = u[0], us[4] = u[1];
  const double overlap = deepest_overlap(g, q, us);
  print_message("%s fall: last state: deepest vertex %.3g um inside another block or a pier "
                "(tolerance %.3g um; %.3g um during the fall)\n", name, overlap * 1e6, tol * 1e6,
                d->max_overlap * 1e6);
  assert_true(overlap < tol);
  assert_true(ls.phase == (scheme == VS_FALL_RIGID ? VS_PHASE_FALL : VS_PHASE_DYNAMIC));
  /* the samples' step counter: the last sample is the fall's last step (none in the penalty
   * scheme, whose steps are IDA's) */
  const vs_fall_result *fr = vs_run_fall(run);
  assert_int_equal(ls.fall_steps, fr != NULL ? fr->steps : 0);
  assert_true(worst < tol);
  assert_true(ls.ke < rest_ke);
  assert_int_equal(d->fall_at_rest, 1);
  assert_true(d->balance_error_fall < 0.01);
  vs_run_destroy(&run);
}

/* The reference run lands with the default, rigid scheme: a vertex at rest sits no deeper than
 * one step of gravity moves it (g h^2; the scheme takes the rest back); and with the penalty
 * scheme on an arch of 21 voussoirs (its fall costs seconds), within the whole arch's weight on
 * one vertex of the ground's spring, W / k_v. */
static void test_reference_lands(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  const double h = 1e-3 * c.step_ms;
  lands(VS_FALL_RIGID, c.voussoirs, c.gravity_m_s2 * h * h, "g h^2");
  vs_geometry *g = NULL;
  vs_error err;
  c.voussoirs = 21;
  assert_int_equal(vs_test_arch(&c, &g, &err), VS_OK);
  const double kv = 0.5 * c.kn_N_mm3 * 1e9 * g->joints[0].depth * g->joints[0].length;
  const double W = vs_geometry_weight(g);
  vs_geometry_destroy(&g);
  lands(VS_FALL_PENALTY, 21, W / kv, "W / k_v");
}

static void test_errors(void **state) {
  (void)state;
  block bk;
  block_make(&bk, 0.5);
  vs_contact *ct = NULL;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_contact_create(bk.m, 0.0, 0, NULL, NULL, &ct, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "restitution"));
  assert_int_equal(vs_contact_create(bk.m, 1.5, 0, NULL, NULL, &ct, &err), VS_ERR_INVALID);
  const int vb = 3;
  const double xz[2] = {0.0, 0.0};
  assert_int_equal(vs_contact_create(bk.m, 0.5, 1, &vb, xz, &ct, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "block 3"));
  assert_null(ct);
  vs_contact_destroy(&ct);
  block_free(&bk);
  (void)PI;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_jacobian),
      cmocka_unit_test(test_drop_flat),
      cmocka_unit_test(test_drop_tilted),
      cmocka_unit_test(test_reference_lands),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
