/* The calibrate command: the k_n that reproduces a measured collapse displacement, found by a
 * log-spaced scan and bracketed false position on log k_n, each evaluation a run in this
 * process. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "voussoir/parse.h"
#include "voussoir/run.h"
#include "voussoir/support.h"
#include "voussoir/sweep.h"
#include "voussoir/units.h"

enum { EXIT_FAIL = 1, EXIT_USAGE = 2, MAX_SETS = 64 };

static const char *CAL_USAGE =
    "usage: voussoir calibrate CASE (--target-dz-pct X | --target-dx-pct X) [--kn-min N_MM3]\n"
    "                          [--kn-max N_MM3] [--tol-pct X] [--set SECTION.KEY=VALUE]... [-q]\n"
    "Finds the joint stiffness k_n (N/mm^3) whose collapse displacement component dz/L (or\n"
    "dx/L), in %, equals the target: a log-spaced scan of [kn-min, kn-max] (default 0.1, 100)\n"
    "brackets the first crossing, then bracketed false position (Illinois) on log k_n refines it\n"
    "to tol-pct (default 0.01 % of L). Reports the bracket, every iteration and the sensitivity\n"
    "d(delta_u/L)/d(log10 k_n) at the answer; says so when no k_n in the range reaches the target.\n";

static int parse_common(int argc, char **argv, int i, char **sets, int *nsets) {
  if (strcmp(argv[i], "--set") == 0 && i + 1 < argc && *nsets < MAX_SETS) {
    sets[(*nsets)++] = argv[i + 1];
    return 2;
  }
  return 0;
}

/* The case file with the --set overrides applied (in order), not yet validated. */
static vs_status load_case(const char *case_path, char **sets, int nsets, vs_case *c,
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
} cal_ctx;

/* Collapse displacement component (% of L) at k_n; NaN if the run has no collapse. */
static double cal_eval(cal_ctx *c, double kn) {
  vs_case k = c->base;
  k.kn_N_mm3 = kn;
  k.fall_s = 0.0; /* delta_u is read before the fall, which costs the most */
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  double out = NAN;
  c->runs++;
  if (vs_run_create(&k, &r, &err) == VS_OK && vs_run_execute(r, NULL, NULL, NULL, &err) == VS_OK &&
      vs_run_collapse(r)->found) {
    const double d = vs_run_collapse(r)->delta / VS_MM;
    const vs_support_dir sd = vs_support_case_direction(&k);
    out = 100.0 * d * (c->dx ? sd.dx : sd.dz) / vs_case_span_mm(&k);
  }
  vs_run_destroy(&r);
  if (!c->quiet) fprintf(stderr, "  k_n = %-12.6g  collapse %s/L = %.4f %%\n", kn, c->dx ? "dx" : "dz", out);
  return out;
}

/* One numeric option of calibrate, in [lo, hi] (the k_n bounds are the case's range of
 * joints.kn_N_mm3); prints the error. */
static int cal_number(const char *option, const char *text, double lo, double hi, double *out) {
  vs_error err;
  if (vs_parse_option_double(option, text, lo, hi, out, &err) == VS_OK) return 0;
  fprintf(stderr, "voussoir calibrate: %s\n", err.msg);
  return -1;
}

int vs_cmd_calibrate(int argc, char **argv) {
  const char *case_path = NULL;
  char *sets[MAX_SETS];
  int nsets = 0, have_target = 0;
  double target = NAN, kmin = 0.1, kmax = 100.0, tol = 0.01;
  cal_ctx c = {0};
  vs_error err;
  vs_error_clear(&err);
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int used = parse_common(argc, argv, i, sets, &nsets);
    if (used) {
      i += used - 1;
    } else if ((strcmp(a, "--target-dz-pct") == 0 || strcmp(a, "--target-dx-pct") == 0) && i + 1 < argc) {
      c.dx = strcmp(a, "--target-dx-pct") == 0;
      if (cal_number(a, argv[++i], 1e-9, 1e4, &target) != 0) return EXIT_USAGE;
      have_target = 1;
    } else if (strcmp(a, "--kn-min") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-4, 1e4, &kmin) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "--kn-max") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-4, 1e4, &kmax) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "--tol-pct") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-12, 100.0, &tol) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "-q") == 0) {
      c.quiet = 1;
    } else if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(CAL_USAGE, stdout);
      return 0;
    } else if (a[0] != '-' && case_path == NULL) {
      case_path = a;
    } else {
      fprintf(stderr, "voussoir calibrate: unexpected argument %s\n%s", a, CAL_USAGE);
      return EXIT_USAGE;
    }
  }
  if (case_path == NULL || !have_target || !(target > 0.0) || !isfinite(target)) {
    fprintf(stderr, "voussoir calibrate: needs a CASE and a target > 0 %%\n%s", CAL_USAGE);
    return EXIT_USAGE;
  }
  if (!(kmax > kmin)) {
    fprintf(stderr, "voussoir calibrate: --kn-min %g, --kn-max %g (allowed: "
                    "1e-4 <= kn-min < kn-max <= 10000 N/mm^3)\n", kmin, kmax);
    return EXIT_USAGE;
  }
  if (load_case(case_path, sets, nsets, &c.base, &err) != VS_OK) goto bad;
  c.base.follow = 1;
  c.base.full = 0;
  if (vs_case_validate(&c.base, &err) != VS_OK) goto bad;
  if (c.dx && fabs(sin(c.base.alpha_deg * VS_DEG)) < 1e-12) {
    fprintf(stderr, "voussoir calibrate: --target-dx-pct with alpha = 0: dx is always 0\n");
    return EXIT_USAGE;
  }
  /* scan: log-spaced k_n, the first bracket of the target */
  enum { SCAN = 9 };
  double kn[SCAN], f[SCAN];
  int lo = -1;
  for (int i = 0; i < SCAN; i++) {
    kn[i] = kmin * pow(kmax / kmin, (double)i / (SCAN - 1));
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
    printf("no k_n in [%g, %g] N/mm^3 gives a collapse %s/L of %g %%: the scan gives %.4f..%.4f %%\n",
           kmin, kmax, c.dx ? "dx" : "dz", target, fmin_, fmax_);
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
    printf("calibration failed: no collapse within support.max_mm near k_n = %.6g\n", pow(10.0, x));
    return EXIT_FAIL;
  }
  const double k = pow(10.0, x), h = 0.01; /* central difference over +-0.01 in log10 k_n */
  const double fp = cal_eval(&c, pow(10.0, x + h)), fm = cal_eval(&c, pow(10.0, x - h));
  printf("k_n = %.6g N/mm^3 gives collapse %s/L = %.4f %% (target %g %%, tolerance %g %%)\n", k,
         c.dx ? "dx" : "dz", fx + target, target, tol);
  printf("sensitivity d(%s/L)/d(log10 k_n) = %.4g %% per decade; %d runs\n", c.dx ? "dx" : "dz",
         (fp - fm) / (2.0 * h), c.runs);
  return fabs(fx) <= tol ? 0 : EXIT_FAIL;
bad:
  fprintf(stderr, "voussoir calibrate: %s\n", err.msg);
  return EXIT_USAGE;
}
