/* The command lines of sweep and calibrate (their work: src/study/sweep.c, src/study/calibrate.c). */
#define _GNU_SOURCE /* getopt_long */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "list.h"
#include "outpath.h"

/* --- sweep --- */

static const char *const SWEEP_USAGE =
    "usage: voussoir sweep CASE [--alpha LIST] [--kn LIST] [--vary SECTION.KEY=LIST]...\n"
    "                      [--set SECTION.KEY=VALUE]... [--first-limit | --dynamic]\n"
    "                      [--max-wall-s S] [-j N] [-o DIR] [--resume] [-q]\n"
    "       mpirun -np N voussoir sweep ...   (rank 0 hands the runs out to the other ranks)\n"
    "Runs the case for every combination of the lists, each in a worker process forked from\n"
    "this one (-j at a time, default: the number of cores), and writes DIR/run_NNNN.h5 (the\n"
    "record) and .json per run, DIR/summary.csv and DIR/summary.h5. A run that fails is\n"
    "reported in the table with its cause; the others go on.\n"
    "LIST: comma-separated numbers and inclusive ranges first:last:step, e.g. 0:45:5,60,75,90.\n"
    "--alpha and --kn are the axes support.alpha_deg and joints.kn_N_mm3; --vary sweeps any key.\n"
    "-o DIR: default sweep_out. At most 100000 runs. Values: --alpha 0:90:5 or --alpha=0:90:5.\n"
    "--max-wall-s S: each run stops once it has taken S s of wall time (--set run.max_wall_s=S);\n"
    "its row says 'stopped' and it counts as failed.\n"
    "SIGINT/SIGTERM: the runs under way are interrupted (the signal is passed on), the summary\n"
    "lists what finished and marks the rest 'interrupted' or 'not_run'; exit status 130.\n"
    "--resume: continue the sweep in DIR (same case, lists, --set and mode): a run whose row is\n"
    "in DIR/sweep.journal (written as each run ends) is complete and is not run again; a row\n"
    "that is damaged or out of range is named on stderr and its run runs again. A run that could\n"
    "not start (its record locked or refused) is listed 'not_started' and is left to --resume.\n"
    "One study at a time in DIR (DIR/study.lock): another sweep or montecarlo there is refused.\n"
    "Exit status 0 when every run worked, 1 if any failed, 2 bad input, 130 interrupted.\n";

enum { OPT_ALPHA = 256, OPT_KN, OPT_VARY, OPT_SET, OPT_FIRST_LIMIT, OPT_DYNAMIC, OPT_RESUME,
       OPT_MAX_WALL };

static const struct option SWEEP_OPTIONS[] = {
    {"alpha", required_argument, NULL, OPT_ALPHA},
    {"kn", required_argument, NULL, OPT_KN},
    {"vary", required_argument, NULL, OPT_VARY},
    {"set", required_argument, NULL, OPT_SET},
    {"first-limit", no_argument, NULL, OPT_FIRST_LIMIT},
    {"dynamic", no_argument, NULL, OPT_DYNAMIC},
    {"resume", no_argument, NULL, OPT_RESUME},
    {"max-wall-s", required_argument, NULL, OPT_MAX_WALL},
    {0, 0, 0, 0}};

static const cli_command SWEEP = {"voussoir sweep", SWEEP_USAGE, "j:o:q", SWEEP_OPTIONS};

/* One axis: --alpha LIST, --kn LIST or --vary SECTION.KEY=LIST. */
static int add_axis(vs_sweep_opts *o, int code, const char *value) {
  if (o->nax == VS_SWEEP_MAX_AXES) {
    fprintf(stderr, "voussoir sweep: at most %d axes\n", VS_SWEEP_MAX_AXES);
    return VS_EXIT_BAD_INPUT;
  }
  vs_sweep_axis *x = &o->ax[o->nax];
  const char *list = value;
  const char *what = code == OPT_ALPHA ? "--alpha" : code == OPT_KN ? "--kn" : "--vary";
  if (code == OPT_VARY) {
    const char *eq = strchr(list, '=');
    if (eq == NULL || (size_t)(eq - list) >= sizeof x->key) {
      char q[68];
      fprintf(stderr, "voussoir sweep: --vary %s: expected SECTION.KEY=LIST (KEY shorter "
                      "than %d characters)\n", vs_quote(list, q, sizeof q), (int)sizeof x->key);
      return VS_EXIT_BAD_INPUT;
    }
    snprintf(x->key, sizeof x->key, "%.*s", (int)(eq - list), list);
    list = eq + 1;
  } else {
    snprintf(x->key, sizeof x->key, "%s",
             code == OPT_ALPHA ? "support.alpha_deg" : "joints.kn_N_mm3");
  }
  vs_error err;
  if (vs_parse_list(what, list, &x->v, &x->n, &err) != VS_OK) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return VS_EXIT_BAD_INPUT;
  }
  o->nax++;
  return 0;
}

/* The sweep's options, and the storage of the --set that --max-wall-s stands for. */
typedef struct {
  vs_sweep_opts o;
  char max_wall[96];
} sweep_args;

static int sweep_option(void *user, int code, const char *value) {
  sweep_args *a = user;
  vs_sweep_opts *o = &a->o;
  switch (code) {
  case OPT_ALPHA: case OPT_KN: case OPT_VARY: return add_axis(o, code, value);
  case OPT_SET: return cli_add_set(SWEEP.name, value, o->sets, &o->nsets);
  case OPT_MAX_WALL:
    return cli_add_key_set(SWEEP.name, "--max-wall-s", "run.max_wall_s", value, a->max_wall,
                           sizeof a->max_wall, o->sets, &o->nsets);
  case OPT_FIRST_LIMIT: o->mode_flag = "--first-limit"; return 0;
  case OPT_DYNAMIC: o->mode_flag = "--dynamic"; return 0;
  case OPT_RESUME: o->resume = 1; return 0;
  case 'j': return cli_int(SWEEP.name, "-j", value, 1, 1024, &o->jobs);
  case 'o': o->dir = value; return 0;
  case 'q': o->quiet = 1; return 0;
  default: break; /* 1: the case */
  }
  if (o->case_path == NULL) {
    o->case_path = value;
    return 0;
  }
  fprintf(stderr, "voussoir sweep: unexpected argument %s\n%s", vs_q(value).s, SWEEP_USAGE);
  return VS_EXIT_BAD_INPUT;
}

int vs_cli_sweep(int argc, char **argv, int *h5_clean) {
  const char *sets[VS_CLI_MAX_SETS];
  vs_sweep_axis ax[VS_SWEEP_MAX_AXES];
  memset(ax, 0, sizeof ax);
  sweep_args a = {.o = {.dir = "sweep_out", .sets = sets, .ax = ax,
                        .jobs = (int)sysconf(_SC_NPROCESSORS_ONLN)}};
  if (a.o.jobs < 1) a.o.jobs = 1;
  if (a.o.jobs > 1024) a.o.jobs = 1024;
  vs_sweep_catch_signals(); /* first, so that no signal is lost while the sweep sets up */
  int rc = cli_parse(&SWEEP, argc, argv, sweep_option, &a);
  vs_sweep_opts o = a.o; /* its --set may point into a: a outlives the sweep */
  if (rc == 0 && strlen(o.dir) > VS_OUTPATH_DIR_MAX) {
    char q[68];
    fprintf(stderr, "voussoir sweep: -o %s: directory name too long (at most %d bytes)\n",
            vs_quote(o.dir, q, sizeof q), (int)VS_OUTPATH_DIR_MAX);
    rc = VS_EXIT_BAD_INPUT;
  }
  if (rc == 0 && (o.case_path == NULL || o.nax == 0)) {
    fprintf(stderr, "voussoir sweep: needs a CASE and at least one list\n%s", SWEEP_USAGE);
    rc = VS_EXIT_BAD_INPUT;
  }
  if (rc == 0) rc = vs_sweep_main(&o, h5_clean);
  for (int x = 0; x < o.nax; x++) free(ax[x].v);
  return rc < 0 ? VS_EXIT_OK : rc;
}

/* --- calibrate --- */

static const char *const CAL_USAGE =
    "usage: voussoir calibrate CASE (--target-dz-pct X | --target-dx-pct X) [--kn-min N_MM3]\n"
    "                          [--kn-max N_MM3] [--tol-pct X] [--set SECTION.KEY=VALUE]... [-q]\n"
    "Finds the joint stiffness k_n (N/mm^3) whose collapse displacement component dz/L (or\n"
    "dx/L), in %, equals the target: a log-spaced scan of [kn-min, kn-max] (default 0.1, 100;\n"
    "within joints.kn_N_mm3's range) brackets the first crossing, then bracketed false position\n"
    "(Illinois) on log k_n refines it to tol-pct (default 0.01 % of L). Reports the bracket,\n"
    "every iteration and the sensitivity d(delta_u/L)/d(log10 k_n) at the answer; says so when\n"
    "no k_n in the range reaches the target, and why when runs failed.\n"
    "Values: --target-dz-pct 16 or --target-dz-pct=16.\n";

enum { OPT_TARGET_DZ = 256, OPT_TARGET_DX, OPT_KN_MIN, OPT_KN_MAX, OPT_TOL, OPT_CAL_SET };

static const struct option CAL_OPTIONS[] = {
    {"target-dz-pct", required_argument, NULL, OPT_TARGET_DZ},
    {"target-dx-pct", required_argument, NULL, OPT_TARGET_DX},
    {"kn-min", required_argument, NULL, OPT_KN_MIN},
    {"kn-max", required_argument, NULL, OPT_KN_MAX},
    {"tol-pct", required_argument, NULL, OPT_TOL},
    {"set", required_argument, NULL, OPT_CAL_SET},
    {0, 0, 0, 0}};

static const cli_command CALIBRATE = {"voussoir calibrate", CAL_USAGE, "q", CAL_OPTIONS};

typedef struct {
  vs_calibrate_opts o;
  int have_target;
} cal_args;

/* joints.kn_N_mm3's range as closed bounds (an open end: the nearest double inside). */
static int kn_range(double *lo, double *hi) {
  int lo_in = 1, hi_in = 1;
  if (vs_case_key_range("joints", "kn_N_mm3", lo, &lo_in, hi, &hi_in) != 0) return -1;
  if (!lo_in) *lo = nextafter(*lo, INFINITY);
  if (!hi_in) *hi = nextafter(*hi, -INFINITY);
  return 0;
}

static int cal_option(void *user, int code, const char *value) {
  cal_args *a = user;
  const char *name = CALIBRATE.name;
  switch (code) {
  case OPT_TARGET_DZ: case OPT_TARGET_DX:
    a->o.dx = code == OPT_TARGET_DX;
    a->have_target = 1;
    return cli_double(name, a->o.dx ? "--target-dx-pct" : "--target-dz-pct", value, 1e-9, 1e4,
                      &a->o.target);
  case OPT_KN_MIN: case OPT_KN_MAX: { /* within joints.kn_N_mm3's range, from the key table */
    double lo = 0.0, hi = 0.0;
    if (kn_range(&lo, &hi) != 0) {
      fprintf(stderr, "%s: no key joints.kn_N_mm3 in the case's table\n", name);
      return VS_EXIT_FAILED;
    }
    return code == OPT_KN_MIN ? cli_double(name, "--kn-min", value, lo, hi, &a->o.kn_min)
                              : cli_double(name, "--kn-max", value, lo, hi, &a->o.kn_max);
  }
  case OPT_TOL: return cli_double(name, "--tol-pct", value, 1e-12, 100.0, &a->o.tol);
  case OPT_CAL_SET: return cli_add_set(name, value, a->o.sets, &a->o.nsets);
  case 'q': a->o.quiet = 1; return 0;
  default: break; /* 1: the case */
  }
  if (a->o.case_path == NULL) {
    a->o.case_path = value;
    return 0;
  }
  fprintf(stderr, "voussoir calibrate: unexpected argument %s\n%s", vs_q(value).s, CAL_USAGE);
  return VS_EXIT_BAD_INPUT;
}

int vs_cli_calibrate(int argc, char **argv) {
  const char *sets[VS_CLI_MAX_SETS];
  cal_args a = {.o = {.sets = sets, .target = NAN, .kn_min = 0.1, .kn_max = 100.0, .tol = 0.01}};
  const int rc = cli_parse(&CALIBRATE, argc, argv, cal_option, &a);
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (a.o.case_path == NULL || !a.have_target || !(a.o.target > 0.0) || !isfinite(a.o.target)) {
    fprintf(stderr, "voussoir calibrate: needs a CASE and a target > 0 %%\n%s", CAL_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  if (!(a.o.kn_max > a.o.kn_min)) {
    double lo = 0.0, hi = 0.0;
    kn_range(&lo, &hi);
    fprintf(stderr, "voussoir calibrate: --kn-min %g, --kn-max %g (allowed: "
                    "%g <= kn-min < kn-max <= %g N/mm^3, joints.kn_N_mm3's range)\n", a.o.kn_min,
            a.o.kn_max, lo, hi);
    return VS_EXIT_BAD_INPUT;
  }
  return vs_calibrate_main(&a.o);
}
