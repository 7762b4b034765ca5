/* Statics of the model (model.h, quasistatic.h) against independent arguments: global
 * equilibrium of the support reactions, mirror symmetry of the symmetric arch, the horizontal
 * thrust inside the [H_min, H_max] range of a thrust-line analysis written here, and a block on
 * an incline that holds below the friction angle and slides above it. SI units. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/joint.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"

static double deg(double d) { return d * acos(-1.0) / 180; }

/* ------------------------ the arch under self-weight (the model) ------------------------ */

typedef struct {
  vs_case c;
  vs_geometry *g;
  vs_model *m;
  double *q;
  int n;
} arch_run;

/* Build the arch of case c (its support kinds too), solve self-weight equilibrium from q = 0 at
 * delta = 0. */
static void arch_solve(arch_run *r) {
  vs_error err;
  vs_error_clear(&err);
  vs_status s = vs_test_arch(&r->c, &r->g, &err);
  if (s != VS_OK) fail_msg("geometry: %s: %s", vs_strerror(s), err.msg);
  vs_joint_law law = {.kn = r->c.kn_N_mm3 * 1e9, .ks = r->c.ks_ratio * r->c.kn_N_mm3 * 1e9, .mu = r->c.friction};
  s = vs_model_create(r->g, &law, deg(r->c.alpha_deg), &r->m, &err);
  if (s != VS_OK) fail_msg("model: %s: %s", vs_strerror(s), err.msg);
  s = vs_model_set_support_kinds(r->m, (vs_support_kind)r->c.left_kind,
                                 (vs_support_kind)r->c.right_kind, &err);
  if (s != VS_OK) fail_msg("support kinds: %s: %s", vs_strerror(s), err.msg);
  r->n = vs_model_size(r->m);
  assert_int_equal(r->n, 3 * r->c.voussoirs + r->c.left_kind + r->c.right_kind);
  r->q = calloc((size_t)r->n, sizeof(double));
  assert_non_null(r->q);
  vs_path_opts o;
  vs_test_path_opts(&r->c, &o);
  long iters = 0;
  s = vs_equilibrium_solve(r->m, &o, 0.0, r->q, &iters, &err);
  if (s != VS_OK) fail_msg("self-weight equilibrium: %s: %s", vs_strerror(s), err.msg);
}

static void arch_free(arch_run *r) {
  free(r->q);
  vs_model_destroy(&r->m);
  assert_null(r->m);
  vs_geometry_destroy(&r->g);
}

/* Closed-form weight of the arch: rho b g (E/2)(Re^2 - Ri^2). */
static double arch_weight(const vs_case *c) {
  double Ri = c->radius_mm * 1e-3, Re = Ri + c->thickness_mm * 1e-3;
  return c->density_kg_m3 * c->depth_mm * 1e-3 * c->gravity_m_s2 * 0.5 * deg(c->embrace_deg) *
         (Re * Re - Ri * Ri);
}

static arch_run reference_run(double kn) {
  arch_run r = {0};
  vs_case_defaults(&r.c);
  r.c.kn_N_mm3 = kn;
  arch_solve(&r);
  return r;
}

/* The supports carry the whole weight, downwards, half each by symmetry; the horizontal
 * reactions are equal and opposite and push the supports outwards. */
static void test_reactions(void **state) {
  (void)state;
  const double kns[] = {3.0, 48.0};
  for (int k = 0; k < 2; k++) {
    arch_run r = reference_run(kns[k]);
    double W = arch_weight(&r.c), left[2], right[2];
    vs_model_reactions(r.m, r.q, 0.0, left, right);
    CHECK(left[1] + right[1], -W, 1e-8, 0);
    CHECK(left[1], -0.5 * W, 1e-7, 0);
    CHECK(right[1], -0.5 * W, 1e-7, 0);
    CHECK(left[0], -right[0], 0, 1e-8 * W);
    assert_true(right[0] > 0 && left[0] < 0);
    CHECK(vs_geometry_weight(r.g), W, 1e-12, 0);
    arch_free(&r);
  }
}

/* Mirror x -> -x maps block i to n-1-i: ux and theta change sign, uz does not. */
static void test_symmetry(void **state) {
  (void)state;
  const double kns[] = {3.0, 48.0};
  for (int k = 0; k < 2; k++) {
    arch_run r = reference_run(kns[k]);
    int nb = r.n / 3;
    double U = 0, TH = 0;
    for (int i = 0; i < nb; i++) {
      U = fmax(U, fmax(fabs(r.q[3 * i]), fabs(r.q[3 * i + 1])));
      TH = fmax(TH, fabs(r.q[3 * i + 2]));
    }
    assert_true(U > 0 && TH > 0); /* the arch did deform */
    for (int i = 0; i < nb; i++) {
      int j = nb - 1 - i;
      CHECK(r.q[3 * i], -r.q[3 * j], 0, 1e-6 * U);
      CHECK(r.q[3 * i + 1], r.q[3 * j + 1], 0, 1e-6 * U);
      CHECK(r.q[3 * i + 2], -r.q[3 * j + 2], 0, 1e-6 * TH);
    }
    /* The crown block (odd count) neither moves sideways nor turns. */
    CHECK(r.q[3 * (nb / 2)], 0, 0, 1e-6 * U);
    CHECK(r.q[3 * (nb / 2) + 2], 0, 0, 1e-6 * TH);
    arch_free(&r);
  }
}

/* ------------------------ independent thrust-line analysis ------------------------------
 * Symmetric arch, circle centre at the origin, phi from the crown (x = r sin phi,
 * z = r cos phi). By symmetry the force across the vertical plane x = 0 is horizontal, H, at
 * height z0. Free body: the material between x = 0 and the radial section at phi > 0 (right
 * half); weight V (down) at x = S / V (S its first moment about x = 0). The rest of the arch
 * pushes on it at the section with (-H, +V), at radius r. Moments about the origin
 * (x F_z - z F_x): crown force (H, 0) at (0, z0): -H z0; weight: -S; section force at
 * r (sin phi, cos phi): r (V sin phi + H cos phi). Their sum is zero, so
 *   r = (H z0 + S) / (H cos phi + V sin phi).
 * (Check: H -> inf gives r cos phi = z0, a horizontal line.) Feasibility R <= r <= R + t at
 * every section is, with y = H z0, R D - S <= y <= (R + t) D - S, D = H cos phi + V sin phi:
 * linear in (H, y), so the feasible set is a convex polygon and
 *   g(H) = min_k [(R + t) D_k - S_k] - max_k [R D_k - S_k]
 * is concave; H_min and H_max are its zeros on either side of its maximum.
 * For the annular sector 0 <= phi' <= phi: V = rho b g phi (Re^2 - Ri^2) / 2,
 * S = rho b g (Re^3 - Ri^3)(1 - cos phi) / 3. */
typedef struct {
  int n;
  double R, t;
  double *cphi, *sphi, *V, *S;
} thrust_problem;

static void thrust_init(thrust_problem *p, double Ri, double t, double wgt, const double *phi,
                        int n) {
  double Re = Ri + t;
  p->n = n;
  p->R = Ri;
  p->t = t;
  p->cphi = malloc(4 * (size_t)n * sizeof(double));
  assert_non_null(p->cphi);
  p->sphi = p->cphi + n;
  p->V = p->sphi + n;
  p->S = p->V + n;
  for (int k = 0; k < n; k++) {
    p->cphi[k] = cos(phi[k]);
    p->sphi[k] = sin(phi[k]);
    p->V[k] = wgt * phi[k] * (Re * Re - Ri * Ri) / 2;
    p->S[k] = wgt * (Re * Re * Re - Ri * Ri * Ri) * (1 - cos(phi[k])) / 3;
  }
}

static void thrust_free(thrust_problem *p) { free(p->cphi); }

static double thrust_g(const thrust_problem *p, double H) {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  for (int k = 0; k < p->n; k++) {
    double D = H * p->cphi[k] + p->V[k] * p->sphi[k];
    lo = fmax(lo, p->R * D - p->S[k]);
    hi = fmin(hi, (p->R + p->t) * D - p->S[k]);
  }
  return hi - lo;
}

/* H_min, H_max in (0, Hhi); returns 0 when no thrust line fits. */
static int thrust_bounds(const thrust_problem *p, double Hhi, double *Hmin, double *Hmax) {
  const double gr = 0.5 * (sqrt(5.0) - 1);
  double a = 0, b = Hhi, c = b - gr * (b - a), d = a + gr * (b - a);
  double gc = thrust_g(p, c), gd = thrust_g(p, d);
  for (int it = 0; it < 200 && b - a > 1e-15 * Hhi; it++) {
    if (gc < gd) {
      a = c;
      c = d;
      gc = gd;
      d = a + gr * (b - a);
      gd = thrust_g(p, d);
    } else {
      b = d;
      d = c;
      gd = gc;
      c = b - gr * (b - a);
      gc = thrust_g(p, c);
    }
  }
  double Hs = 0.5 * (a + b);
  if (thrust_g(p, Hs) < 0) return 0;
  assert_true(thrust_g(p, 0) < 0 && thrust_g(p, Hhi) < 0);
  double lo = 0, hi = Hs;
  for (int it = 0; it < 200 && hi - lo > 1e-14 * Hs; it++) {
    double m = 0.5 * (lo + hi);
    if (thrust_g(p, m) >= 0) hi = m;
    else lo = m;
  }
  *Hmin = hi;
  lo = Hs;
  hi = Hhi;
  for (int it = 0; it < 200 && hi - lo > 1e-14 * Hs; it++) {
    double m = 0.5 * (lo + hi);
    if (thrust_g(p, m) >= 0) lo = m;
    else hi = m;
  }
  *Hmax = lo;
  return 1;
}

/* Semicircle of centre-line radius 1 and thickness t, radial sections densely spaced (the
 * continuous arch, crown section included). */
static int semicircle_bounds(double t, double *Hmin, double *Hmax) {
  enum { K = 2000 };
  double *phi = malloc((K + 1) * sizeof(double));
  assert_non_null(phi);
  for (int k = 0; k <= K; k++) phi[k] = 0.5 * acos(-1.0) * k / K;
  thrust_problem p;
  thrust_init(&p, 1 - 0.5 * t, t, 1.0, phi, K + 1);
  int ok = thrust_bounds(&p, 100.0, Hmin, Hmax);
  thrust_free(&p);
  free(phi);
  return ok;
}

/* Sanity of the analysis itself: the least thickness of a semicircular arch with radial joints
 * under self-weight is t / R_centre = 0.1075 (Milankovitch), where H_min meets H_max. */
static void test_thrust_line_semicircle(void **state) {
  (void)state;
  double lo = 0.09, hi = 0.13, a, b;
  assert_int_equal(semicircle_bounds(lo, &a, &b), 0);
  assert_int_equal(semicircle_bounds(hi, &a, &b), 1);
  for (int it = 0; it < 30; it++) {
    double m = 0.5 * (lo + hi);
    if (semicircle_bounds(m, &a, &b)) hi = m;
    else lo = m;
  }
  assert_true(hi > 0.1065 && hi < 0.1085);
  assert_int_equal(semicircle_bounds(hi * (1 + 1e-6), &a, &b), 1);
  CHECK(b, a, 1e-3, 0);
  /* Thicker: a clear range. */
  assert_int_equal(semicircle_bounds(0.12, &a, &b), 1);
  assert_true(b > 1.05 * a);
}

/* [H_min, H_max] of the discrete arch of case c: the radial joints of the right half (for an
 * odd voussoir count the plane x = 0 cuts the crown voussoir, which is rigid, so it is not a
 * section; for an even count it is joint n/2 + 1). */
static void arch_thrust_bounds(const vs_case *c, double *Hmin, double *Hmax) {
  int n = c->voussoirs;
  double E = deg(c->embrace_deg), dphi = E / n;
  int ns = n / 2 + 1;
  double *phi = malloc((size_t)ns * sizeof(double));
  assert_non_null(phi);
  for (int k = 0; k < ns; k++) phi[k] = (n % 2 ? 0.5 * dphi : 0.0) + k * dphi;
  CHECK(phi[ns - 1], 0.5 * E, 1e-14, 0);
  thrust_problem p;
  thrust_init(&p, c->radius_mm * 1e-3, c->thickness_mm * 1e-3,
              c->density_kg_m3 * c->depth_mm * 1e-3 * c->gravity_m_s2, phi, ns);
  int ok = thrust_bounds(&p, 100 * arch_weight(c), Hmin, Hmax);
  thrust_free(&p);
  free(phi);
  assert_int_equal(ok, 1);
}

/* The model's thrust under self-weight must be statically admissible for the undeformed arch
 * (to the order of the deformation: 1 %). */
static void test_thrust_in_range(void **state) {
  (void)state;
  const double kns[] = {3.0, 48.0};
  double Hmin, Hmax;
  vs_case c;
  vs_case_defaults(&c);
  arch_thrust_bounds(&c, &Hmin, &Hmax);
  assert_true(Hmax > Hmin && Hmin > 0);
  for (int k = 0; k < 2; k++) {
    arch_run r = reference_run(kns[k]);
    double left[2], right[2];
    vs_model_reactions(r.m, r.q, 0.0, left, right);
    double H = right[0];
    if (!(H >= 0.99 * Hmin && H <= 1.01 * Hmax))
      fail_msg("kn = %g N/mm^3: thrust H = %.6g N outside [%.6g, %.6g] N", kns[k], H, Hmin,
               Hmax);
    arch_free(&r);
  }
}

/* ---------------------------------- block on an incline ---------------------------------
 * A rectangular block (base w along the plane, height h, depth b) rests on the fixed support
 * over a plane inclined at beta, rising to the right (the block tends to slide down to the
 * left); normal from the support into the block n = (-sin beta, cos beta); centroid at h/2
 * along n above the joint centre (origin); the resultant's eccentricity (h/2) tan beta stays
 * below w/6, so the joint stays fully closed.
 * Equilibrium of the block (gravity (0, -m g), joint force on b = N n - T s with s = n turned
 * +90 degrees, frame turned by the mean rotation theta/2 of the joint):
 *   N = m g cos(beta + theta/2), T = m g sin(beta + theta/2) -> T/N = tan(beta + theta/2),
 * possible only while tan(beta + theta/2) <= mu. */
typedef struct {
  vs_geometry *g;
  vs_model *m;
  double q[3];
  double mass;
  vs_status status;
  vs_joint_state st;
  char msg[sizeof(((vs_error *)0)->msg)]; /* why, when there is no equilibrium */
} incline_run;

static void incline_solve(double tanb, incline_run *r) {
  const double wd = 0.1, hh = 0.04, b = 0.1, rho = 2000, beta = atan(tanb);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_geometry_create(1, 1, &r->g, &err), VS_OK);
  vs_geometry *g = r->g;
  double nx = -sin(beta), nz = cos(beta);
  r->mass = rho * wd * hh * b;
  g->blocks[0] = (vs_block){.mass = r->mass,
                            .inertia = r->mass * (wd * wd + hh * hh) / 12,
                            .cx = 0.5 * hh * nx,
                            .cz = 0.5 * hh * nz,
                            .area = wd * hh,
                            .phi0 = 0,
                            .phi1 = 0};
  g->joints[0] = (vs_joint_geom){.a = VS_SUPPORT_LEFT, .b = 0, .px = 0, .pz = 0, .nx = nx,
                                 .nz = nz, .length = wd, .depth = b};
  g->gravity = 9.81;
  g->span = wd;
  g->rise = 0;
  g->radius = 0;
  g->thickness = wd;
  g->embrace = 0;
  vs_joint_law law = {.kn = 3e9, .ks = 1.5e9, .mu = 0.7};
  assert_int_equal(vs_model_create(g, &law, 0.0, &r->m, &err), VS_OK);
  assert_int_equal(vs_model_size(r->m), 3);
  vs_case c;
  vs_case_defaults(&c);
  vs_path_opts o;
  vs_test_path_opts(&c, &o);
  r->q[0] = r->q[1] = r->q[2] = 0;
  long iters = 0;
  r->status = vs_equilibrium_solve(r->m, &o, 0.0, r->q, &iters, &err);
  if (r->status == VS_OK) vs_model_joint_states(r->m, r->q, 0.0, &r->st);
  else assert_true(err.msg[0] != '\0');
  snprintf(r->msg, sizeof r->msg, "%s", err.msg);
}

static void incline_free(incline_run *r) {
  vs_model_destroy(&r->m);
  vs_geometry_destroy(&r->g);
}

static void test_incline_holds(void **state) {
  (void)state;
  const double tans[] = {0.0, 0.3, 0.6};
  for (int k = 0; k < 3; k++) {
    incline_run r = {0};
    incline_solve(tans[k], &r);
    if (r.status != VS_OK) fail_msg("tan beta = %g: no equilibrium (%s)", tans[k],
                                    vs_strerror(r.status));
    double mg = r.mass * 9.81, be = atan(tans[k]) + 0.5 * r.q[2];
    CHECK(r.st.N, mg * cos(be), 1e-8, 0);
    CHECK(r.st.T, mg * sin(be), 1e-8, 1e-10 * mg);
    CHECK(r.st.T / r.st.N, tan(be), 1e-8, 1e-10);
    CHECK(r.st.T / r.st.N, tans[k], 1e-4, 1e-10); /* theta is tiny */
    CHECK(r.st.N, mg * cos(atan(tans[k])), 1e-4, 0);
    assert_int_equal(r.st.sliding, 0);
    incline_free(&r);
  }
}

static void test_incline_slides(void **state) {
  (void)state;
  incline_run r = {0};
  incline_solve(0.8, &r);
  if (!(r.status == VS_ERR_NO_EQUILIBRIUM || r.status == VS_ERR_SOLVER))
    fail_msg("tan beta = 0.8 > mu = 0.7: expected no equilibrium, got %s (T/N = %g)",
             vs_strerror(r.status), r.status == VS_OK ? r.st.T / r.st.N : 0.0);
  /* the cause stated: the line search cut short by voussoir (VS_MAX_LINESEARCH), not KINSOL's
   * "system function failed", the residual function's -1 by which the cut is made */
  if (strstr(r.msg, "the line search found no lower residual in 5 trial steps") == NULL ||
      strstr(r.msg, "system function") != NULL)
    fail_msg("the failure's cause misstated: %s", r.msg);
  incline_free(&r);
}

/* ------------------------------- pinned supports ------------------------------- */

/* At an equilibrium with pinned supports: the supports' reactions carry no moment about the
 * pivots (the rotation's equation dE/dtheta_s, the moment conjugate to the springer's rotation)
 * and balance the weight; returns the largest |moment| / (W t). Independently, from the joint's
 * own contact stresses: the line of thrust passes through the pivot, i.e. the eccentricity M/N
 * of the springing joint's normal force about its centre is a small fraction of t (zero but for
 * the second-order terms of the joint's mean-rotation frame: slip and penetration times
 * rotations), and the joint closes almost uniformly (its edges' gaps agree). *ecc gets the
 * largest |M/N| / t. */
static double pinned_check(const vs_model *m, const double *q, double delta, double W,
                           double *ecc) {
  const vs_geometry *g = vs_model_geometry(m);
  const double t = g->joints[0].length;
  vs_joint_state *st = malloc((size_t)g->n_joints * sizeof *st);
  assert_non_null(st);
  vs_model_joint_states(m, q, delta, st);
  double worst = 0.0;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    const int sup = j->a < 0 ? j->a : j->b < 0 ? j->b : 0;
    if (sup == 0 || vs_model_support_kind(m, sup == VS_SUPPORT_RIGHT) != VS_SUPPORT_PINNED)
      continue;
    assert_true(st[k].N > 0.0);
    *ecc = fmax(*ecc, fabs(st[k].M / st[k].N) / t);
    CHECK(st[k].gap_i, st[k].gap_e, 0, 1e-3 * fabs(st[k].a));
  }
  free(st);
  double r[6];
  vs_model_support_reactions(m, q, delta, r);
  for (int s = 0; s < 2; s++)
    if (vs_model_support_kind(m, s) == VS_SUPPORT_PINNED) worst = fmax(worst, fabs(r[3 * s + 2]) / (W * t));
  CHECK(r[1] + r[4], W, 1e-8, 0); /* the supports carry the weight */
  CHECK(r[0], -r[3], 0, 1e-8 * W);
  return worst;
}

typedef struct {
  double W, worst, ecc;
  int count;
} pin_path;

static int on_pinned_step(void *user, double delta, const double *q, const vs_model *m) {
  pin_path *p = user;
  p->worst = fmax(p->worst, pinned_check(m, q, delta, p->W, &p->ecc));
  p->count++;
  return 0;
}

/* Both springers pinned, the arch symmetric: the self-weight equilibrium is mirror symmetric
 * (the springers turn by opposite angles, both outwards-down), and on the whole path of the
 * settling right support to its first limit point the springing joints' moments about the
 * pivots vanish (to the Newton tolerance, far below round-off of W t) at every equilibrium. */
static void test_pinned_supports(void **state) {
  (void)state;
  arch_run r = {0};
  vs_case_defaults(&r.c);
  r.c.left_kind = r.c.right_kind = VS_SUPPORT_PINNED;
  arch_solve(&r);
  const int nb = r.c.voussoirs, kl = vs_model_support_dof(r.m, 0), kr = vs_model_support_dof(r.m, 1);
  assert_true(kl == 3 * nb && kr == 3 * nb + 1);
  const double W = arch_weight(&r.c), TH = fabs(r.q[kl]);
  assert_true(TH > 1e-6); /* the springers did turn */
  CHECK(r.q[kl], -r.q[kr], 0, 1e-6 * TH);
  double U = 0.0;
  for (int i = 0; i < 3 * nb; i++) U = fmax(U, fabs(r.q[i]));
  for (int i = 0; i < nb; i++) {
    const int j = nb - 1 - i;
    CHECK(r.q[3 * i], -r.q[3 * j], 0, 1e-6 * U);
    CHECK(r.q[3 * i + 1], r.q[3 * j + 1], 0, 1e-6 * U);
  }
  double ecc = 0.0;
  assert_true(pinned_check(r.m, r.q, 0.0, W, &ecc) < 1e-9);
  print_message("pinned: springing eccentricity under self-weight %.3g t\n", ecc);
  assert_true(ecc < 1e-4);
  vs_path_opts o;
  vs_test_path_opts(&r.c, &o);
  pin_path p = {.W = W};
  vs_path_result res;
  vs_error err;
  vs_error_clear(&err);
  for (int i = 0; i < r.n; i++) r.q[i] = 0.0;
  vs_status s = vs_path_run(r.m, &o, 0.0, r.q, on_pinned_step, &p, &res, &err);
  if (s != VS_OK) fail_msg("path: %s: %s", vs_strerror(s), err.msg);
  assert_int_equal(res.end, VS_PATH_LIMIT_POINT);
  print_message("pinned: %d equilibria to the limit point at %.4f mm, largest springing moment "
                "%.3g W t, eccentricity %.3g t\n", p.count, res.delta_limit * 1e3, p.worst, p.ecc);
  assert_true(p.count > 10);
  assert_true(p.worst < 1e-9);
  assert_true(p.ecc < 1e-4);
  arch_free(&r);
}

/* First limit point of the reference arch for alpha = 90 (spreading) with one springer pinned,
 * and the springer's rotation there. */
static double spreading_limit(vs_support_kind left, vs_support_kind right, double *theta) {
  arch_run r = {0};
  vs_case_defaults(&r.c);
  r.c.alpha_deg = 90.0;
  r.c.left_kind = (int)left;
  r.c.right_kind = (int)right;
  arch_solve(&r);
  vs_path_opts o;
  vs_test_path_opts(&r.c, &o);
  vs_path_result res;
  vs_error err;
  vs_error_clear(&err);
  for (int i = 0; i < r.n; i++) r.q[i] = 0.0;
  vs_status s = vs_path_run(r.m, &o, 0.0, r.q, NULL, NULL, &res, &err);
  if (s != VS_OK) fail_msg("path: %s: %s", vs_strerror(s), err.msg);
  assert_int_equal(res.end, VS_PATH_LIMIT_POINT);
  *theta = r.q[vs_model_support_dof(r.m, right == VS_SUPPORT_PINNED)];
  arch_free(&r);
  return res.delta_limit;
}

/* Mirror symmetry: moving the right support outwards by delta is, up to a rigid translation
 * (which changes nothing: the joint law is objective and gravity acts vertically), the mirror
 * image of moving the left one outwards. So the arch with its left springer pinned and the one
 * with its right springer pinned must reach their first limit points at the same delta (within
 * the two brackets, limit_tol each) with opposite springer rotations. */
static void test_pinned_mirror(void **state) {
  (void)state;
  double thl = 0.0, thr = 0.0;
  const double dl = spreading_limit(VS_SUPPORT_PINNED, VS_SUPPORT_FIXED, &thl);
  const double dr = spreading_limit(VS_SUPPORT_FIXED, VS_SUPPORT_PINNED, &thr);
  vs_case c;
  vs_case_defaults(&c);
  print_message("spreading: first limit point %.5f mm (left pinned, springer %.4g rad), %.5f mm "
                "(right pinned, %.4g rad)\n", dl * 1e3, thl, dr * 1e3, thr);
  assert_true(dl > 1e-3);
  CHECK(dl, dr, 0, 2.0 * c.limit_tol_mm * 1e-3);
  assert_true(fabs(thl) > 1e-4);
  CHECK(thl, -thr, 1e-3, 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reactions),
      cmocka_unit_test(test_symmetry),
      cmocka_unit_test(test_pinned_supports),
      cmocka_unit_test(test_pinned_mirror),
      cmocka_unit_test(test_thrust_line_semicircle),
      cmocka_unit_test(test_thrust_in_range),
      cmocka_unit_test(test_incline_holds),
      cmocka_unit_test(test_incline_slides),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
