/* The wall-time limit (run.max_wall_s, --max-wall-s): a run that passes it stops at its next
 * step in whichever phase it is (the quasi-static path, IDA, the rigid fall), with
 * VS_ERR_WALL_TIME and "stopped: wall-time limit S s reached"; an accepted but pathological case
 * (a fall of 1e6 s in steps of 1 us) given --max-wall-s 1, or the key, ends within seconds with
 * the exit status of an interrupted run (130), its record closed and marked stopped, its
 * summary and JSON saying so; the runs of a sweep and the samples of a Monte Carlo study stop
 * the same way and count as failed. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, clock_gettime, nanosleep */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define VS_SCRATCH "wall"
#include "record_status.h"
#include "scratch.h"
#include "voussoir/case.h"
#include "voussoir/run.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"
/* A fall that never ends: 1e6 s in steps of 1 us (both within the keys' ranges). */
#define ENDLESS_FALL "[fall]\nstep_ms = 0.001\n[dynamic]\nfall_s = 1e6\n"

static void expect_in(const char *text, const char *needle, const char *what) {
  if (strstr(text, needle) == NULL) fail_msg("%s lacks \"%s\": %.2000s", what, needle, text);
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------------------------------------------------------------------------------------
 * Every phase: the run's first sample of the phase waits until the limit has passed (what the
 * test needs to happen is that much wall time going by; the limit started before the run's first
 * step, so waiting the limit's length from any later moment passes it), then the phase's next
 * step must stop the run, in that phase. The limit is a few times the time the same run took to
 * reach the phase just before (measured here: sanitizers and load slow it down many times). */

typedef struct {
  vs_phase target;
  double limit;     /* s: the case's max_wall_s; 0: only measure the time to the phase */
  double t0;        /* when the run started */
  double reached;   /* s after t0: the phase's first sample (NAN: none) */
  int waited;       /* the wait is over ... */
  double waited_at; /* ... since then */
  int later;        /* a sample of a later phase came after it */
  int gave_up;      /* the run went on GIVE_UP_S after the wait: stopped by the callback */
} phase_probe;

/* Beyond this after the wait, the run has not stopped: the callback stops it itself (the
 * endless fall would otherwise run for ever), and the test fails. */
static const double GIVE_UP_S = 30.0;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *smp) {
  (void)run;
  phase_probe *p = user;
  if (p->waited && smp->phase > p->target) p->later = 1;
  if (isnan(p->reached) && smp->phase == p->target) {
    p->reached = now_s() - p->t0;
    if (p->limit <= 0.0) return 1; /* measured: stop here */
    const double until = now_s() + p->limit;
    while (now_s() < until) nanosleep(&(struct timespec){0, 10000000}, NULL);
    p->waited = 1;
    p->waited_at = now_s();
  }
  p->gave_up = p->waited && now_s() - p->waited_at > GIVE_UP_S;
  return p->gave_up;
}

/* The reference case with an endless fall (1e6 s in steps of 10 us, so that its first sample,
 * 0.01 s of fall, comes 500 steps after the collapse) and the limit; for the IDA phase the
 * whole loading dynamic (dynamic.full = 1): after a limit point of the quasi-static path the
 * motion's rest probes are quasi-static solves, which would stop the run themselves. Run until
 * the callback or the limit stops it; *st and err its end, the probe what it saw. */
static vs_run *run_to_phase(phase_probe *p, vs_status *st, vs_error *err) {
  vs_case c;
  vs_run *run = NULL;
  vs_error_clear(err);
  vs_case_defaults(&c);
  assert_int_equal(vs_case_read(&c, REFERENCE, NULL, err), VS_OK);
  assert_int_equal(vs_case_set(&c, "fall.step_ms=0.01", err), VS_OK);
  assert_int_equal(vs_case_set(&c, "dynamic.fall_s=1e6", err), VS_OK);
  if (p->target == VS_PHASE_DYNAMIC) assert_int_equal(vs_case_set(&c, "dynamic.full=1", err), 0);
  c.max_wall_s = p->limit;
  assert_int_equal(vs_case_validate(&c, err), VS_OK);
  assert_int_equal(vs_run_create(&c, &run, err), VS_OK);
  p->reached = NAN;
  p->t0 = now_s();
  *st = vs_run_execute(run, on_sample, NULL, p, err);
  return run;
}

static void test_each_phase(void **s) {
  (void)s;
  const vs_phase phases[] = {VS_PHASE_QUASISTATIC, VS_PHASE_DYNAMIC, VS_PHASE_FALL};
  for (int i = 0; i < 3; i++) {
    vs_error err;
    vs_status st;
    phase_probe m = {.target = phases[i]}; /* no limit: how long to the phase */
    vs_run *run = run_to_phase(&m, &st, &err);
    vs_run_destroy(&run);
    if (isnan(m.reached)) fail_msg("phase %d: never reached (%s)", (int)phases[i], err.msg);
    phase_probe p = {.target = phases[i], .limit = 0.5 + 3.0 * m.reached};
    run = run_to_phase(&p, &st, &err);
    const double took = now_s() - p.t0;
    /* what ran: no IDA step before the motion, no fall before the fall */
    const int ida = vs_run_dynamic_totals(run)->steps > 0, fell = vs_run_fall(run) != NULL;
    vs_run_destroy(&run);
    char want[96];
    snprintf(want, sizeof want, "stopped: wall-time limit %g s reached", p.limit);
    if (p.gave_up)
      fail_msg("phase %d: still running %g s past the limit", (int)phases[i], GIVE_UP_S);
    if (!p.waited)
      fail_msg("phase %d: no sample of the phase within %g s (reached in %g s before)",
               (int)phases[i], p.limit, m.reached);
    if (st != VS_ERR_WALL_TIME || strcmp(err.msg, want) != 0)
      fail_msg("phase %d: status %s (%s), expected \"%s\"", (int)phases[i], vs_strerror(st),
               err.msg, want);
    if (p.later || (phases[i] == VS_PHASE_QUASISTATIC && ida) ||
        (phases[i] != VS_PHASE_FALL && fell))
      fail_msg("phase %d: the run went on to a later phase (IDA steps %d, fall %d)",
               (int)phases[i], ida, fell);
    if (took > p.limit + GIVE_UP_S) fail_msg("phase %d: stopped after %.1f s", (int)phases[i], took);
  }
}

/* ---------------------------------------------------------------------------------------------
 * The program */

static void write_case(const char *name, const char *text) {
  FILE *f = fopen(in_dir(name), "w");
  assert_non_null(f);
  fputs(text, f);
  assert_int_equal(fclose(f), 0);
}

/* `voussoir ARGS` in g_dir (killed after 60 s should it not stop), stdout and stderr into
 * out.txt, err.txt; the exit status and, in *took, the wall time it took. */
static int voussoir(const char *args, double *took) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd '%s' && timeout -s KILL 60 '%s' %s >out.txt 2>err.txt", g_dir,
           VS_BINARY, args);
  const double t0 = now_s();
  const int rc = sh(cmd);
  if (took != NULL) *took = now_s() - t0;
  return rc;
}

/* The pathological case with --max-wall-s 1: stopped within seconds (30 s allowed under load),
 * exit 130, the record closed and marked stopped (it reads: HDF5 opens it and its sidecar is
 * there), the summary and stderr saying so. */
static void test_option_stops_endless_fall(void **s) {
  (void)s;
  write_case("endless.ini", ENDLESS_FALL);
  double took = 0.0;
  const int rc = voussoir("run endless.ini -q --max-wall-s 1 -o rec.h5", &took);
  const char *err = slurp(in_dir("err.txt"), NULL);
  if (rc != 130) fail_msg("exit status %d (expected 130) after %.1f s: %s", rc, took, err);
  if (took > 30.0) fail_msg("took %.1f s", took);
  expect_in(err, "voussoir: stopped: wall-time limit 1 s reached", "stderr");
  expect_in(slurp(in_dir("out.txt"), NULL), "\nstopped: wall-time limit 1 s reached at delta",
            "summary");
  char status[256];
  vs_test_record_status(in_dir("rec.h5"), status, sizeof status);
  assert_string_equal(status, "stopped: wall-time limit 1 s reached");
  assert_int_equal(access(in_dir("rec.xmf"), F_OK), 0);
}

/* The same limit as the case's key [run] max_wall_s, with the JSON summary. */
static void test_key_stops_endless_fall(void **s) {
  (void)s;
  write_case("endless_key.ini", ENDLESS_FALL "[run]\nmax_wall_s = 1\n");
  double took = 0.0;
  const int rc = voussoir("run endless_key.ini -q --json -o rec_key.h5", &took);
  if (rc != 130) fail_msg("exit status %d (expected 130) after %.1f s", rc, took);
  if (took > 30.0) fail_msg("took %.1f s", took);
  const char *out = slurp(in_dir("out.txt"), NULL);
  expect_in(out, "\"status\":\"stopped\",\"error\":\"stopped: wall-time limit 1 s reached\"",
            "JSON");
  char status[256];
  vs_test_record_status(in_dir("rec_key.h5"), status, sizeof status);
  assert_string_equal(status, "stopped: wall-time limit 1 s reached");
}

/* The option and the key refuse what is not a number of seconds in [0, 1e6]. */
static void test_limit_checked(void **s) {
  (void)s;
  assert_int_equal(voussoir("run " REFERENCE " -q --no-record --max-wall-s -1", NULL), 2);
  expect_in(slurp(in_dir("err.txt"), NULL),
            "run.max_wall_s = -1: out of range (allowed: [0, 1e+06] s)", "stderr");
  assert_int_equal(voussoir("run " REFERENCE " -q --no-record --set run.max_wall_s=nan", NULL), 2);
  expect_in(slurp(in_dir("err.txt"), NULL), "not a finite number", "stderr");
  assert_int_equal(voussoir("sweep " REFERENCE " --alpha 0 -q -o sw0 --max-wall-s 2e6", NULL), 2);
  assert_int_equal(access(in_dir("sw0"), F_OK), -1);
}

/* Each run of a sweep and each sample of a Monte Carlo study stops at its own limit (1 us: at
 * their first step): rows "stopped", counted as failed (exit 1), said on stderr. */
static void test_studies_stop_each_run(void **s) {
  (void)s;
  assert_int_equal(voussoir("sweep " REFERENCE " --alpha 0,10 --max-wall-s 1e-6 -q -j 2 -o sw",
                            NULL), 1);
  expect_in(slurp(in_dir("err.txt"), NULL),
            "every run failed (2 of 2); run 1: stopped: wall-time limit 1e-06 s reached",
            "sweep's stderr");
  const char *table = slurp(in_dir("sw/summary.csv"), NULL);
  expect_in(table, "\n1,0,stopped,", "summary.csv");
  expect_in(table, "\n2,10,stopped,", "summary.csv");
  assert_int_equal(voussoir("montecarlo " REFERENCE " --samples 2 --max-wall-s 1e-6 -q -j 2 -o mc",
                            NULL), 1);
  expect_in(slurp(in_dir("err.txt"), NULL),
            "every sample failed; sample 0: stopped: wall-time limit 1e-06 s reached",
            "montecarlo's stderr");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_each_phase),
      cmocka_unit_test(test_option_stops_endless_fall),
      cmocka_unit_test(test_key_stops_endless_fall),
      cmocka_unit_test(test_limit_checked),
      cmocka_unit_test(test_studies_stop_each_run),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
