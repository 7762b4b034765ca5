/* The calibrate command's work (its command line is read by src/cli/cli_sweep.c): the k_n that
 * reproduces a measured collapse displacement, found by a log-spaced scan and bracketed false
 * position on log k_n, each evaluation a run in this process. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "collapse_at.h"
#include "study.h"
#include "voussoir/run.h"
#include "voussoir/support.h"
#include "list.h"
#include "voussoir/units.h"

enum { EXIT_FAIL = VS_EXIT_FAILED, EXIT_USAGE = VS_EXIT_BAD_INPUT };

/* The case file with the --set overrides applied (in order), not yet validated. */
static vs_status load_case(const char *case_path, const char *const *sets, int nsets, vs_case *c,
                           vs_error *err) {
  vs_case_defaults(c);
  vs_status st = vs_case_read(c, case_path, NULL, err);
  for (int s = 0; st == VS_OK && s < nsets; s++) st = vs_case_set(c, sets[s], err);
  return st;
}

typedef struct {
  vs_case base;
  int dx;        /* 1: the dx component, 0: dz */
  int quiet;
  int runs;
  int failed;          /* runs that failed (not a run without a collapse) */
  double failed_kn;    /* the first failed run's k_n, */
  char failed_msg[sizeof ((vs_error *)0)->msg]; /* and its cause */
} cal_ctx;

/* Collapse displacement component (% of L) at k_n; NaN if the run has no collapse or fails
 * (the first failure's k_n and cause are kept for the report). */
static double cal_eval(cal_ctx *c, double kn) {
  vs_case k = c->base;
  k.kn_N_mm3 = kn;
  k.fall_s = 0.0; /* delta_u is read before the fall, which costs the most */
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  double out = NAN;
  c->runs++;
  const int ok =
      vs_run_create(&k, &r, &err) == VS_OK && vs_run_execute(r, NULL, NULL, NULL, &err) == VS_OK;
  if (ok && vs_run_collapse(r)->found) {
    double dz, dx; /* as the run's JSON gives them (a blocks file's own span) */
    vs_study_components_pct(r, vs_run_collapse(r)->delta, &dz, &dx);
    out = c->dx ? dx : dz;
  }
  vs_run_destroy(&r);
  if (!ok && c->failed++ == 0) {
    c->failed_kn = kn;
    snprintf(c->failed_msg, sizeof c->failed_msg, "%s", err.msg);
  }
  if (!c->quiet) {
    fprintf(stderr, "  k_n = %-12.6g  collapse %s/L = %.4f %%", kn, c->dx ? "dx" : "dz", out);
    if (!ok) fprintf(stderr, "  (run failed: %s)", err.msg);
    else if (isnan(out)) fprintf(stderr, "  (no collapse within support.max_mm)");
    fputc('\n', stderr);
  }
  return out;
}

/* Why some k_n gave no value: the failed runs, the first one's k_n and cause (nothing if none). */
static void print_failures(const cal_ctx *c) {
  if (c->failed > 0)
    printf("%d of the %d runs failed, the first at k_n = %g N/mm^3: %s\n", c->failed, c->runs,
           c->failed_kn, c->failed_msg);
}

int vs_calibrate_main(const vs_calibrate_opts *o) {
  const double target = o->target, kmin = o->kn_min, kmax = o->kn_max, tol = o->tol;
  cal_ctx c = {.dx = o->dx, .quiet = o->quiet};
  vs_error err;
  vs_error_clear(&err);
  if (load_case(o->case_path, o->sets, o->nsets, &c.base, &err) != VS_OK) goto bad;
  c.base.follow = 1;
  c.base.full = 0;
  if (vs_case_validate(&c.base, &err) != VS_OK ||
      vs_case_check_path(&c.base, "calibrate", &err) != VS_OK)
    goto bad;
  const int right_alone = c.base.left_rate_mm_s == 0.0 && c.base.left_path.n == 0 &&
                          c.base.right_path.n == 0; /* else dx is the supports' spreading */
  if (c.dx && right_alone && fabs(sin(c.base.alpha_deg * VS_DEG)) < 1e-12) {
    fprintf(stderr, "voussoir calibrate: --target-dx-pct with alpha = 0: dx is always 0\n");
    return EXIT_USAGE;
  }
  /* scan: log-spaced k_n, the first bracket of the target */
  enum { SCAN = 9 };
  double kn[SCAN], f[SCAN];
  int lo = -1;
  for (int i = 0; i < SCAN; i++) {
    kn[i] = fmin(kmax, kmin * pow(kmax / kmin, (double)i / (SCAN - 1))); /* kmax: not above it */
    f[i] = cal_eval(&c, kn[i]) - target;
    if (i > 0 && isfinite(f[i]) && isfinite(f[i - 1]) && (f[i - 1] <= 0.0) != (f[i] <= 0.0)) {
      lo = i - 1;
      break;
    }
  }
  if (lo < 0) {
    double fmin_ = INFINITY, fmax_ = -INFINITY;
    for (int i = 0; i < SCAN; i++)
      if (isfinite(f[i])) {
        fmin_ = fmin(fmin_, f[i] + target);
        fmax_ = fmax(fmax_, f[i] + target);
      }
    if (fmin_ <= fmax_)
      printf("no k_n in [%g, %g] N/mm^3 gives a collapse %s/L of %g %%: the scan gives %.4f..%.4f %%\n",
             kmin, kmax, c.dx ? "dx" : "dz", target, fmin_, fmax_);
    else
      printf("no k_n in [%g, %g] N/mm^3 gives a collapse %s/L of %g %%: no run of the scan gives a "
             "collapse\n", kmin, kmax, c.dx ? "dx" : "dz", target);
    print_failures(&c);
    return EXIT_FAIL;
  }
  /* Illinois false position on log k_n within the bracket */
  double xa = log10(kn[lo]), xb = log10(kn[lo + 1]), fa = f[lo], fb = f[lo + 1], x = xa, fx = fa;
  printf("bracket: k_n in [%.6g, %.6g] N/mm^3 (%s/L %.4f .. %.4f %%)\n", kn[lo], kn[lo + 1],
         c.dx ? "dx" : "dz", fa + target, fb + target);
  int side = 0, it = 0;
  for (; it < 40; it++) {
    x = (xa * fb - xb * fa) / (fb - fa);
    fx = cal_eval(&c, pow(10.0, x)) - target;
    if (!isfinite(fx)) { /* no collapse there: bisect instead */
      x = 0.5 * (xa + xb);
      fx = cal_eval(&c, pow(10.0, x)) - target;
      if (!isfinite(fx)) break;
    }
    printf("  iteration %2d: k_n = %.6g N/mm^3, %s/L = %.4f %%\n", it + 1, pow(10.0, x),
           c.dx ? "dx" : "dz", fx + target);
    if (fabs(fx) <= tol || xb - xa < 1e-5) break;
    if ((fx <= 0.0) == (fa <= 0.0)) {
      xa = x;
      fa = fx;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      xb = x;
      fb = fx;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
  }
  if (!isfinite(fx)) {
    printf("calibration failed: no collapse value near k_n = %.6g N/mm^3\n", pow(10.0, x));
    print_failures(&c);
    return EXIT_FAIL;
  }
  /* central difference over +-0.01 in log10 k_n, one-sided at an end of [kn-min, kn-max] (beyond
   * it k_n may leave joints.kn_N_mm3's range) */
  const double k = pow(10.0, x), xp = fmin(x + 0.01, log10(kmax)), xm = fmax(x - 0.01, log10(kmin));
  const double fp = cal_eval(&c, pow(10.0, xp)), fm = cal_eval(&c, pow(10.0, xm));
  printf("k_n = %.6g N/mm^3 gives collapse %s/L = %.4f %% (target %g %%, tolerance %g %%)\n", k,
         c.dx ? "dx" : "dz", fx + target, target, tol);
  printf("sensitivity d(%s/L)/d(log10 k_n) = %.4g %% per decade; %d runs\n", c.dx ? "dx" : "dz",
         (fp - fm) / (xp - xm), c.runs);
  if (!isfinite(fp - fm)) print_failures(&c);
  return fabs(fx) <= tol ? 0 : EXIT_FAIL;
bad:
  fprintf(stderr, "voussoir calibrate: %s\n", err.msg);
  return EXIT_USAGE;
}
