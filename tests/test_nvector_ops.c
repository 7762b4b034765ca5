/* The optimised serial vector operations (nvector_ops.h) against SUNDIALS' own N_V*_Serial
 * functions, bit for bit: every operation on vectors of random values (with zeros, negative
 * values and a NaN-free mix of magnitudes), every special case of a linear sum and a scaling
 * (coefficients 1, -1, equal, opposite, other) with the output aliasing either input, and the
 * reductions. Then cloning: a clone carries the fast operations. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include "nvector_ops.h"

enum { N = 37 }; /* odd: vectorised loops have a remainder */

typedef struct {
  SUNContext ctx;
  N_Vector x, y, z, w, id; /* with the fast operations */
  N_Vector xr, yr, zr;     /* SUNDIALS' own, for the reference results */
} fixture;

static void fill(N_Vector v, unsigned long seed) {
  double *d = N_VGetArrayPointer(v);
  for (int i = 0; i < N; i++) {
    seed = seed * 6364136223846793005ul + 1442695040888963407ul;
    const double u = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
    d[i] = (i % 7 == 3) ? 0.0 : u * pow(10.0, (double)(i % 5) - 2.0);
  }
}

static int setup(void **state) {
  static fixture f;
  memset(&f, 0, sizeof f);
  if (SUNContext_Create(NULL, &f.ctx) != 0) return -1;
  f.x = N_VNew_Serial(N, f.ctx), f.y = N_VNew_Serial(N, f.ctx), f.z = N_VNew_Serial(N, f.ctx);
  f.w = N_VNew_Serial(N, f.ctx), f.id = N_VNew_Serial(N, f.ctx);
  f.xr = N_VNew_Serial(N, f.ctx), f.yr = N_VNew_Serial(N, f.ctx), f.zr = N_VNew_Serial(N, f.ctx);
  vs_nvector_fast_ops(f.x), vs_nvector_fast_ops(f.y), vs_nvector_fast_ops(f.z);
  vs_nvector_fast_ops(f.w), vs_nvector_fast_ops(f.id);
  fill(f.w, 7);
  double *id = N_VGetArrayPointer(f.id);
  for (int i = 0; i < N; i++) id[i] = (i % 3 == 0) ? 0.0 : 1.0;
  *state = &f;
  return 0;
}

static int teardown(void **state) {
  fixture *f = *state;
  N_Vector *v[] = {&f->x, &f->y, &f->z, &f->w, &f->id, &f->xr, &f->yr, &f->zr};
  for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) N_VDestroy(*v[i]);
  SUNContext_Free(&f->ctx);
  return 0;
}

/* x, y (fast) and xr, yr (reference) the same random values; z, zr too. */
static void reset(fixture *f, unsigned long seed) {
  fill(f->x, seed), fill(f->xr, seed);
  fill(f->y, seed + 1), fill(f->yr, seed + 1);
  fill(f->z, seed + 2), fill(f->zr, seed + 2);
}

static void same_bits(N_Vector a, N_Vector b) {
  assert_memory_equal(N_VGetArrayPointer(a), N_VGetArrayPointer(b), N * sizeof(double));
}

static void same_double(double a, double b) { assert_memory_equal(&a, &b, sizeof a); }

static void test_linear_sum(void **state) {
  fixture *f = *state;
  const double c[] = {1.0, -1.0, 0.0, 0.37, -2.5};
  for (size_t i = 0; i < 5; i++)
    for (size_t j = 0; j < 7; j++) /* b: each of c, then a and -a */
      for (int alias = 0; alias < 3; alias++) { /* z apart, z = x, z = y */
        const double a = c[i], b = j < 5 ? c[j] : j == 5 ? a : -a;
        reset(f, 11 + 7 * i + j);
        N_Vector z = alias == 1 ? f->x : alias == 2 ? f->y : f->z;
        N_Vector zr = alias == 1 ? f->xr : alias == 2 ? f->yr : f->zr;
        N_VLinearSum(a, f->x, b, f->y, z);
        N_VLinearSum_Serial(a, f->xr, b, f->yr, zr);
        same_bits(z, zr);
      }
}

static void test_elementwise(void **state) {
  fixture *f = *state;
  const double c[] = {1.0, -1.0, 0.0, 3.25};
  for (int alias = 0; alias < 2; alias++)
    for (size_t i = 0; i < 4; i++) {
      reset(f, 101 + i);
      N_VScale(c[i], f->x, alias ? f->x : f->z);
      N_VScale_Serial(c[i], f->xr, alias ? f->xr : f->zr);
      same_bits(alias ? f->x : f->z, alias ? f->xr : f->zr);
    }
  reset(f, 201);
  N_VConst(0.7, f->z), N_VConst_Serial(0.7, f->zr), same_bits(f->z, f->zr);
  N_VProd(f->x, f->y, f->z), N_VProd_Serial(f->xr, f->yr, f->zr), same_bits(f->z, f->zr);
  reset(f, 202);
  double *yd = N_VGetArrayPointer(f->y), *yrd = N_VGetArrayPointer(f->yr);
  for (int i = 0; i < N; i++) yd[i] = yrd[i] = yd[i] == 0.0 ? 0.5 : yd[i];
  N_VDiv(f->x, f->y, f->z), N_VDiv_Serial(f->xr, f->yr, f->zr), same_bits(f->z, f->zr);
  N_VAbs(f->x, f->z), N_VAbs_Serial(f->xr, f->zr), same_bits(f->z, f->zr);
  N_VAddConst(f->x, -0.3, f->z), N_VAddConst_Serial(f->xr, -0.3, f->zr), same_bits(f->z, f->zr);
  N_VCompare(0.01, f->x, f->z), N_VCompare_Serial(0.01, f->xr, f->zr), same_bits(f->z, f->zr);
  N_VInv(f->y, f->z), N_VInv_Serial(f->yr, f->zr), same_bits(f->z, f->zr);
  reset(f, 203); /* x has zeros: the test fails, and z is left alone there */
  assert_int_equal(N_VInvTest(f->x, f->z), N_VInvTest_Serial(f->xr, f->zr));
  same_bits(f->z, f->zr);
  double *cd = N_VGetArrayPointer(f->y), *crd = N_VGetArrayPointer(f->yr);
  for (int i = 0; i < N; i++) cd[i] = crd[i] = (double)(i % 5) - 2.0; /* -2 .. 2 */
  assert_int_equal(N_VConstrMask(f->y, f->x, f->z), N_VConstrMask_Serial(f->yr, f->xr, f->zr));
  same_bits(f->z, f->zr);
}

static void test_reductions(void **state) {
  fixture *f = *state;
  reset(f, 301);
  same_double(N_VDotProd(f->x, f->y), N_VDotProd_Serial(f->xr, f->yr));
  same_double(N_VMaxNorm(f->x), N_VMaxNorm_Serial(f->xr));
  same_double(N_VWrmsNorm(f->x, f->w), N_VWrmsNorm_Serial(f->xr, f->w));
  same_double(N_VWrmsNormMask(f->x, f->w, f->id), N_VWrmsNormMask_Serial(f->xr, f->w, f->id));
  same_double(N_VMin(f->x), N_VMin_Serial(f->xr));
  same_double(N_VWL2Norm(f->x, f->w), N_VWL2Norm_Serial(f->xr, f->w));
  same_double(N_VL1Norm(f->x), N_VL1Norm_Serial(f->xr));
  same_double(N_VMinQuotient(f->x, f->y), N_VMinQuotient_Serial(f->xr, f->yr));
  same_double(N_VWSqrSumLocal(f->x, f->w), N_VWSqrSumLocal_Serial(f->xr, f->w));
  same_double(N_VWSqrSumMaskLocal(f->x, f->w, f->id),
              N_VWSqrSumMaskLocal_Serial(f->xr, f->w, f->id));
  N_VConst(0.0, f->y), N_VConst(0.0, f->yr); /* no quotient at all */
  same_double(N_VMinQuotient(f->x, f->y), N_VMinQuotient_Serial(f->xr, f->yr));
  /* the fused operation's generic fall-back runs on these */
  reset(f, 302);
  double cc[3] = {1.0, -0.5, 2.0};
  N_Vector X[3] = {f->x, f->y, f->w}, Xr[3] = {f->xr, f->yr, f->w};
  N_VLinearCombination(3, cc, X, f->z);
  N_VScale_Serial(cc[0], Xr[0], f->zr);
  for (int i = 1; i < 3; i++) N_VLinearSum_Serial(cc[i], Xr[i], 1.0, f->zr, f->zr);
  same_bits(f->z, f->zr);
}

static void test_clone(void **state) {
  fixture *f = *state;
  N_Vector c = N_VClone(f->x), r = N_VNew_Serial(N, f->ctx);
  assert_non_null(c);
  assert_ptr_equal(c->ops->nvlinearsum, f->x->ops->nvlinearsum);
  assert_ptr_not_equal(c->ops->nvlinearsum, r->ops->nvlinearsum);
  vs_nvector_fast_ops(NULL); /* accepted, nothing done */
  N_VDestroy(c);
  N_VDestroy(r);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_linear_sum), cmocka_unit_test(test_elementwise),
      cmocka_unit_test(test_reductions), cmocka_unit_test(test_clone)};
  return cmocka_run_group_tests(tests, setup, teardown);
}
