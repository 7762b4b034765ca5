/* The thrust line of the pictures (vs_plot_thrust_points) against closed forms: one loaded joint
 * puts its centre of pressure at e = M/N from the joint centre along the radius, in the
 * reference configuration and after a rigid rotation of the whole arch; under self-weight the
 * symmetric arch gives a mirror-symmetric line that stays inside every joint (a resultant of
 * compressive contact stresses acts within the compressed face). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/joint.h"
#include "voussoir/model.h"
#include "voussoir/plot.h"
#include "voussoir/quasistatic.h"

/* |a - b| <= tol, saying the values when not */
#define near(a, b, tol)                                                                        \
  do {                                                                                         \
    const double a_ = (a), b_ = (b);                                                           \
    if (!(fabs(a_ - b_) <= (tol))) fail_msg("%s = %.17g, %s = %.17g", #a, a_, #b, b_);         \
  } while (0)

typedef struct {
  vs_case c;
  vs_geometry *g;
  int nb, nj;
  double *q, *N, *M, *x, *z;
} fixture;

static int setup(void **state) {
  fixture *f = calloc(1, sizeof *f);
  assert_non_null(f);
  vs_case_defaults(&f->c);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_test_arch(&f->c, &f->g, &err), VS_OK);
  f->nb = f->g->n_blocks, f->nj = f->g->n_joints;
  f->q = calloc((size_t)(3 * f->nb + 2), sizeof *f->q);
  f->N = calloc((size_t)f->nj, sizeof *f->N);
  f->M = calloc((size_t)f->nj, sizeof *f->M);
  f->x = calloc((size_t)f->nj, sizeof *f->x);
  f->z = calloc((size_t)f->nj, sizeof *f->z);
  assert_true(f->q && f->N && f->M && f->x && f->z);
  *state = f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  vs_geometry_destroy(&f->g);
  free(f->q), free(f->N), free(f->M), free(f->x), free(f->z);
  free(f);
  return 0;
}

/* The thrust line's points of f's arch in state f->q with joint forces f->N, f->M into f->x,
 * f->z (vs_plot_thrust_points of that picture). */
static vs_status thrust_points(fixture *f, vs_error *err) {
  const vs_plot_arch_args a = {.g = f->g, .q = f->q, .joint_N = f->N, .joint_M = f->M};
  return vs_plot_thrust_points(&a, f->x, f->z, err);
}

/* Joint k (1-based) lies on the radial plane at the angle its right-hand block starts at (the
 * last joint: where the last block ends), measured from the crown. */
static double joint_angle(const fixture *f, int k) {
  return k <= f->nb ? f->g->blocks[k - 1].phi0 : f->g->blocks[f->nb - 1].phi1;
}

/* One compressed joint, N = 100 N, M = 0.3 N m: e = 3 mm outward along the radius; the others
 * carry nothing and break the line (NaN). Then every block turned by theta about the arch's
 * centre: the point turns with them. */
static void test_single_joint(void **state) {
  fixture *f = *state;
  const int k = 20;
  const double N = 100.0, M = 0.3, e = M / N;
  f->N[k - 1] = N, f->M[k - 1] = M;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(thrust_points(f, &err), VS_OK);
  const double phi = joint_angle(f, k), rho = f->c.radius_mm * 1e-3 + 0.5 * f->c.thickness_mm * 1e-3 + e;
  near(f->x[k - 1], rho * sin(phi), 1e-12);
  near(f->z[k - 1], rho * cos(phi), 1e-12);
  for (int j = 0; j < f->nj; j++)
    if (j != k - 1) assert_true(isnan(f->x[j]) && isnan(f->z[j]));
  /* a joint in tension (N < 0) is no point of the line */
  f->N[k - 1] = -N;
  assert_int_equal(thrust_points(f, &err), VS_OK);
  assert_true(isnan(f->x[k - 1]));
  f->N[k - 1] = N;

  const double th = 0.2, c = cos(th), s = sin(th);
  for (int b = 0; b < f->nb; b++) { /* u = R(theta) c - c */
    const double cx = f->g->blocks[b].cx, cz = f->g->blocks[b].cz;
    f->q[3 * b] = c * cx - s * cz - cx;
    f->q[3 * b + 1] = s * cx + c * cz - cz;
    f->q[3 * b + 2] = th;
  }
  assert_int_equal(thrust_points(f, &err), VS_OK);
  const double x0 = rho * sin(phi), z0 = rho * cos(phi);
  near(f->x[k - 1], c * x0 - s * z0, 1e-12);
  near(f->z[k - 1], s * x0 + c * z0, 1e-12);
}

/* Self-weight equilibrium of the symmetric arch on fixed supports: the line is the mirror image
 * of itself (joint k and joint n+2-k), and every centre of pressure is inside its joint. */
static void test_symmetric_self_weight(void **state) {
  fixture *f = *state;
  vs_error err;
  vs_error_clear(&err);
  vs_joint_law law = {.kn = f->c.kn_N_mm3 * 1e9, .ks = f->c.ks_ratio * f->c.kn_N_mm3 * 1e9, .mu = f->c.friction};
  vs_model *m = NULL;
  assert_int_equal(vs_model_create(f->g, &law, 0.0, &m, &err), VS_OK);
  vs_path_opts o;
  vs_test_path_opts(&f->c, &o);
  long iters = 0;
  for (int i = 0; i < 3 * f->nb; i++) f->q[i] = 0.0;
  assert_int_equal(vs_equilibrium_solve(m, &o, 0.0, f->q, &iters, &err), VS_OK);
  vs_joint_state *st = calloc((size_t)f->nj, sizeof *st);
  assert_non_null(st);
  vs_model_joint_states(m, f->q, 0.0, st);
  for (int k = 0; k < f->nj; k++) f->N[k] = st[k].N, f->M[k] = st[k].M;
  assert_int_equal(thrust_points(f, &err), VS_OK);
  const double t = f->c.thickness_mm * 1e-3, R = f->c.radius_mm * 1e-3;
  for (int k = 0; k < f->nj; k++) {
    const int mk = f->nj - 1 - k;
    assert_true(f->N[k] > 0.0); /* every joint compressed under self-weight */
    near(f->x[k], -f->x[mk], 1e-9);
    near(f->z[k], f->z[mk], 1e-9);
    const double r = hypot(f->x[k], f->z[k]); /* blocks barely move: radial position */
    assert_true(r > R - 1e-6 && r < R + t + 1e-6);
  }
  /* not trivially on the centre line: the line moves through the section */
  double lo = INFINITY, hi = -INFINITY;
  for (int k = 0; k < f->nj; k++) {
    const double e = f->M[k] / f->N[k];
    lo = fmin(lo, e), hi = fmax(hi, e);
  }
  assert_true(hi - lo > 0.1 * t);
  free(st);
  vs_model_destroy(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_single_joint, setup, teardown),
      cmocka_unit_test_setup_teardown(test_symmetric_self_weight, setup, teardown),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
