/* Optimised serial N_Vector operations, identical in arithmetic to SUNDIALS' (nvector_ops.h).
 * Each function keeps the special cases and the operation order of the one it replaces: a
 * different order of the same sums would move results by round-off, and the runs' results are
 * meant to stay bit for bit what they were. */
#include "nvector_ops.h"

#include <math.h>
#include <nvector/nvector_serial.h>

typedef sunindextype idx;

static idx len(N_Vector v) { return NV_LENGTH_S(v); }
static double *dat(N_Vector v) { return NV_DATA_S(v); }

/* SUNDIALS' SUNRsqrt: zero for a non-positive argument. */
static double rsqrt0(double x) { return x <= 0.0 ? 0.0 : sqrt(x); }

/* y <- a x + y, with a = 1 and a = -1 as an addition and a subtraction. */
static void axpy(double a, N_Vector x, N_Vector y) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *yd = dat(y);
  if (a == 1.0)
    for (idx i = 0; i < n; i++) yd[i] += xd[i];
  else if (a == -1.0)
    for (idx i = 0; i < n; i++) yd[i] -= xd[i];
  else
    for (idx i = 0; i < n; i++) yd[i] += a * xd[i];
}

/* z <- s (x + t y) for the cases of a linear sum, kind: 0 x + y, 1 x - y, 2 c (x + y),
 * 3 c (x - y), 4 c x + y, 5 c x - y, 6 c x + d y. */
static void lin(int kind, double c, double d, N_Vector x, N_Vector y, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x), *yd = dat(y);
  double *zd = dat(z);
  switch (kind) {
  case 0: for (idx i = 0; i < n; i++) zd[i] = xd[i] + yd[i]; break;
  case 1: for (idx i = 0; i < n; i++) zd[i] = xd[i] - yd[i]; break;
  case 2: for (idx i = 0; i < n; i++) zd[i] = c * (xd[i] + yd[i]); break;
  case 3: for (idx i = 0; i < n; i++) zd[i] = c * (xd[i] - yd[i]); break;
  case 4: for (idx i = 0; i < n; i++) zd[i] = (c * xd[i]) + yd[i]; break;
  case 5: for (idx i = 0; i < n; i++) zd[i] = (c * xd[i]) - yd[i]; break;
  default: for (idx i = 0; i < n; i++) zd[i] = (c * xd[i]) + (d * yd[i]); break;
  }
}

/* z <- a x + b y, dispatched on the coefficients in SUNDIALS' order of cases. */
static void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  if (b == 1.0 && z == y) axpy(a, x, y);
  else if (a == 1.0 && z == x) axpy(b, y, x);
  else if (a == 1.0 && b == 1.0) lin(0, 0.0, 0.0, x, y, z);
  else if (a == 1.0 && b == -1.0) lin(1, 0.0, 0.0, x, y, z);
  else if (a == -1.0 && b == 1.0) lin(1, 0.0, 0.0, y, x, z);
  else if (a == 1.0) lin(4, b, 0.0, y, x, z);
  else if (b == 1.0) lin(4, a, 0.0, x, y, z);
  else if (a == -1.0) lin(5, b, 0.0, y, x, z);
  else if (b == -1.0) lin(5, a, 0.0, x, y, z);
  else if (a == b) lin(2, a, 0.0, x, y, z);
  else if (a == -b) lin(3, a, 0.0, x, y, z);
  else lin(6, a, b, x, y, z);
}

static void vconst(double c, N_Vector z) {
  const idx n = len(z);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = c;
}

static void prod(N_Vector x, N_Vector y, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x), *yd = dat(y);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = xd[i] * yd[i];
}

static void vdiv(N_Vector x, N_Vector y, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x), *yd = dat(y);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = xd[i] / yd[i];
}

/* z <- c x: in place a multiplication even for c = 1; else c = 1 a copy, c = -1 a negation. */
static void scale(double c, N_Vector x, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  if (z == x)
    for (idx i = 0; i < n; i++) zd[i] *= c;
  else if (c == 1.0)
    for (idx i = 0; i < n; i++) zd[i] = xd[i];
  else if (c == -1.0)
    for (idx i = 0; i < n; i++) zd[i] = -xd[i];
  else
    for (idx i = 0; i < n; i++) zd[i] = c * xd[i];
}

static void vabs(N_Vector x, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = fabs(xd[i]);
}

static void inv(N_Vector x, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = 1.0 / xd[i];
}

static void add_const(N_Vector x, double b, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = xd[i] + b;
}

static double dot(N_Vector x, N_Vector y) {
  const idx n = len(x);
  const double *xd = dat(x), *yd = dat(y);
  double sum = 0.0;
  for (idx i = 0; i < n; i++) sum += xd[i] * yd[i];
  return sum;
}

static double max_norm(N_Vector x) {
  const idx n = len(x);
  const double *xd = dat(x);
  double m = 0.0;
  for (idx i = 0; i < n; i++)
    if (fabs(xd[i]) > m) m = fabs(xd[i]);
  return m;
}

/* sum of (x_i w_i)^2 in index order */
static double wsqr_sum(N_Vector x, N_Vector w) {
  const idx n = len(x);
  const double *xd = dat(x), *wd = dat(w);
  double sum = 0.0;
  for (idx i = 0; i < n; i++) {
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

static double wsqr_sum_mask(N_Vector x, N_Vector w, N_Vector id) {
  const idx n = len(x);
  const double *xd = dat(x), *wd = dat(w), *md = dat(id);
  double sum = 0.0;
  for (idx i = 0; i < n; i++)
    if (md[i] > 0.0) {
      const double p = xd[i] * wd[i];
      sum += p * p;
    }
  return sum;
}

static double wrms_norm(N_Vector x, N_Vector w) {
  return rsqrt0(wsqr_sum(x, w) / (double)len(x));
}

static double wrms_norm_mask(N_Vector x, N_Vector w, N_Vector id) {
  return rsqrt0(wsqr_sum_mask(x, w, id) / (double)len(x));
}

static double vmin(N_Vector x) {
  const idx n = len(x);
  const double *xd = dat(x);
  double m = xd[0];
  for (idx i = 1; i < n; i++)
    if (xd[i] < m) m = xd[i];
  return m;
}

static double wl2_norm(N_Vector x, N_Vector w) { return rsqrt0(wsqr_sum(x, w)); }

static double l1_norm(N_Vector x) {
  const idx n = len(x);
  const double *xd = dat(x);
  double sum = 0.0;
  for (idx i = 0; i < n; i++) sum += fabs(xd[i]);
  return sum;
}

static void compare(double c, N_Vector x, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  for (idx i = 0; i < n; i++) zd[i] = fabs(xd[i]) >= c ? 1.0 : 0.0;
}

/* z <- 1 / x where x is not zero (z is left alone there); false if some x is zero */
static sunbooleantype inv_test(N_Vector x, N_Vector z) {
  const idx n = len(x);
  const double *xd = dat(x);
  double *zd = dat(z);
  sunbooleantype ok = SUNTRUE;
  for (idx i = 0; i < n; i++) {
    if (xd[i] == 0.0) ok = SUNFALSE;
    else zd[i] = 1.0 / xd[i];
  }
  return ok;
}

/* m_i <- 1 where x_i violates constraint c_i (|c| 2: strictly of the sign of c, 1: or zero) */
static sunbooleantype constr_mask(N_Vector c, N_Vector x, N_Vector m) {
  const idx n = len(x);
  const double *cd = dat(c), *xd = dat(x);
  double *md = dat(m);
  int violated = 0;
  for (idx i = 0; i < n; i++) {
    md[i] = 0.0;
    if (cd[i] == 0.0) continue;
    if ((fabs(cd[i]) > 1.5 && xd[i] * cd[i] <= 0.0) || (fabs(cd[i]) > 0.5 && xd[i] * cd[i] < 0.0)) {
      md[i] = 1.0;
      violated = 1;
    }
  }
  return violated ? SUNFALSE : SUNTRUE;
}

static double min_quotient(N_Vector num, N_Vector denom) {
  const idx n = len(num);
  const double *nd = dat(num), *dd = dat(denom);
  double m = BIG_REAL;
  int first = 1;
  for (idx i = 0; i < n; i++) {
    if (dd[i] == 0.0) continue;
    const double q = nd[i] / dd[i];
    m = first ? q : (m < q ? m : q); /* SUNMIN, NaN included */
    first = 0;
  }
  return m;
}

void vs_nvector_fast_ops(N_Vector v) {
  if (v == NULL || v->ops == NULL || N_VGetVectorID(v) != SUNDIALS_NVEC_SERIAL) return;
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = linear_sum;
  o->nvconst = vconst;
  o->nvprod = prod;
  o->nvdiv = vdiv;
  o->nvscale = scale;
  o->nvabs = vabs;
  o->nvinv = inv;
  o->nvaddconst = add_const;
  o->nvdotprod = dot;
  o->nvmaxnorm = max_norm;
  o->nvwrmsnorm = wrms_norm;
  o->nvwrmsnormmask = wrms_norm_mask;
  o->nvmin = vmin;
  o->nvwl2norm = wl2_norm;
  o->nvl1norm = l1_norm;
  o->nvcompare = compare;
  o->nvinvtest = inv_test;
  o->nvconstrmask = constr_mask;
  o->nvminquotient = min_quotient;
  o->nvdotprodlocal = dot;
  o->nvmaxnormlocal = max_norm;
  o->nvminlocal = vmin;
  o->nvl1normlocal = l1_norm;
  o->nvinvtestlocal = inv_test;
  o->nvconstrmasklocal = constr_mask;
  o->nvminquotientlocal = min_quotient;
  o->nvwsqrsumlocal = wsqr_sum;
  o->nvwsqrsummasklocal = wsqr_sum_mask;
}
