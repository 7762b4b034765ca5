/* Stopped by the caller (VS_ERR_STOPPED, "stopped by the caller"): a callback that returns
 * non-zero stops the solver under way there, with its own status, not VS_ERR_INTERNAL: the
 * quasi-static path's step function at its third equilibrium (vs_path_run), a run's sample
 * function at the third sample of each phase (the path's equilibria, IDA's samples, the rigid
 * fall's), and its event function at the first hinge. Nothing is called after the stop; the
 * report says the run stopped, and a record closed with that status says so too. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, open_memstream */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "record_status.h"
#include "test_support.h"
#include "voussoir/case.h"
#include "voussoir/model.h"
#include "voussoir/output.h"
#include "voussoir/quasistatic.h"
#include "voussoir/report.h"
#include "voussoir/run.h"

/* The status and message of a stop, and that it is not an internal error. */
static void expect_stopped(vs_status st, const vs_error *err, const char *what) {
  if (st != VS_ERR_STOPPED || err->status != VS_ERR_STOPPED ||
      strcmp(err->msg, "stopped by the caller") != 0)
    fail_msg("%s: status %d (%s), message \"%s\"; expected VS_ERR_STOPPED", what, (int)st,
             vs_strerror(st), err->msg);
  assert_string_equal(vs_strerror(VS_ERR_STOPPED), "stopped by the caller");
}

/* ---------------------------------------------------------------------------------------------
 * The quasi-static path */

typedef struct {
  int calls, stop_at;
} counter;

static int stop_at_count(void *user, double delta, const double *q, const vs_model *m) {
  (void)delta, (void)q, (void)m;
  counter *c = user;
  return ++c->calls == c->stop_at;
}

static void test_path_stopped_at_third_equilibrium(void **state) {
  (void)state;
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  vs_geometry *g = NULL;
  vs_model *m = NULL;
  assert_int_equal(vs_test_model(&c, &g, &m, &err), VS_OK);
  vs_path_opts o;
  vs_test_path_opts(&c, &o);
  double *q = calloc((size_t)vs_model_size(m), sizeof *q);
  assert_non_null(q);
  counter k = {.stop_at = 3};
  vs_path_result res;
  const vs_status st = vs_path_run(m, &o, 0.0, q, stop_at_count, &k, &res, &err);
  expect_stopped(st, &err, "vs_path_run");
  assert_int_equal(k.calls, 3); /* not called again after it said stop */
  assert_true(res.delta_limit > 0.0); /* the path did go on from self-weight before the stop */
  free(q);
  vs_model_destroy(&m);
  vs_geometry_destroy(&g);
}

/* ---------------------------------------------------------------------------------------------
 * A run */

typedef struct {
  vs_phase phase;     /* stop at the third sample of this phase ... */
  int stop_event;     /* ... or (1) at the first hinge's event */
  int seen;           /* samples of the phase seen */
  int after;          /* samples or events after the stop */
  int stopped;
  vs_output *record;  /* NULL: none; else each sample goes to it first */
} stopper;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  stopper *p = user;
  if (p->stopped) return ++p->after, 1;
  if (p->record != NULL && vs_output_sample(p->record, run, s) != 0) return 1;
  if (!p->stop_event && s->phase == p->phase && ++p->seen == 3) p->stopped = 1;
  return p->stopped;
}

static int on_event(void *user, const vs_run *run, const vs_run_event *e) {
  stopper *p = user;
  if (p->stopped) return ++p->after, 1;
  if (p->record != NULL && vs_output_event(p->record, run, e) != 0) return 1;
  if (p->stop_event && e->kind == VS_EVENT_HINGE_FORMED) p->stopped = 1;
  return p->stopped;
}

/* The reference case run with p's callbacks: its status (and err), the run in *out. */
static vs_status run_reference(stopper *p, vs_run **out, vs_error *err) {
  vs_case c;
  vs_case_defaults(&c);
  vs_error_clear(err);
  assert_int_equal(vs_run_create(&c, out, err), VS_OK);
  return vs_run_execute(*out, on_sample, on_event, p, err);
}

/* The JSON report of a run that ended with st, err. */
static char *json_of(const vs_run *r, vs_status st, const vs_error *err) {
  char *buf = NULL;
  size_t n = 0;
  FILE *f = open_memstream(&buf, &n);
  assert_non_null(f);
  vs_report_json(f, r, st, err, "reference.ini");
  assert_int_equal(fclose(f), 0);
  return buf;
}

static void test_run_stopped_in_each_phase(void **state) {
  (void)state;
  const vs_phase phases[] = {VS_PHASE_QUASISTATIC, VS_PHASE_DYNAMIC, VS_PHASE_FALL};
  for (int i = 0; i < 3; i++) {
    stopper p = {.phase = phases[i]};
    vs_run *r = NULL;
    vs_error err;
    const vs_status st = run_reference(&p, &r, &err);
    if (!p.stopped) fail_msg("phase %d: no third sample (%s)", (int)phases[i], err.msg);
    expect_stopped(st, &err, "vs_run_execute");
    assert_int_equal(p.after, 0);
    /* where it stopped: no IDA step before the motion, no fall before the fall */
    const int ida = vs_run_dynamic_totals(r)->steps > 0, fell = vs_run_fall(r) != NULL &&
                                                                vs_run_fall(r)->steps > 0;
    assert_int_equal(ida, phases[i] != VS_PHASE_QUASISTATIC);
    assert_int_equal(fell, phases[i] == VS_PHASE_FALL);
    char *json = json_of(r, st, &err);
    if (strstr(json, "\"status\":\"stopped\",\"error\":\"stopped by the caller\"") == NULL)
      fail_msg("phase %d: the report says %.300s", (int)phases[i], json);
    free(json);
    vs_run_destroy(&r);
  }
}

static void test_run_stopped_by_event(void **state) {
  (void)state;
  stopper p = {.stop_event = 1};
  vs_run *r = NULL;
  vs_error err;
  const vs_status st = run_reference(&p, &r, &err);
  assert_true(p.stopped);
  expect_stopped(st, &err, "vs_run_execute, an event");
  assert_int_equal(p.after, 0);
  /* at the first hinges, on the path: before any limit point or motion */
  assert_true(vs_hinges_count(vs_run_hinges(r)) >= 1);
  assert_int_equal(vs_run_limit_count(r), 0);
  assert_int_equal(vs_run_dynamic_totals(r)->steps, 0);
  vs_run_destroy(&r);
}

/* ---------------------------------------------------------------------------------------------
 * The record */

static void test_record_of_a_stopped_run(void **state) {
  (void)state;
  char dir[] = "/tmp/vs_stop_XXXXXX", path[64], xmf[64];
  assert_non_null(mkdtemp(dir));
  snprintf(path, sizeof path, "%s/stopped.h5", dir);
  snprintf(xmf, sizeof xmf, "%s/stopped.xmf", dir);
  vs_case c;
  vs_case_defaults(&c);
  vs_error err, oerr;
  vs_error_clear(&err);
  vs_error_clear(&oerr);
  vs_run *r = NULL;
  assert_int_equal(vs_run_create(&c, &r, &err), VS_OK);
  vs_output_opts oo;
  vs_output_opts_default(&oo);
  stopper p = {.phase = VS_PHASE_DYNAMIC};
  assert_int_equal(vs_output_create(path, r, NULL, &oo, &p.record, &err), VS_OK);
  const vs_status st = vs_run_execute(r, on_sample, on_event, &p, &err);
  expect_stopped(st, &err, "a recorded run");
  assert_int_equal(vs_output_finish(p.record, r, st, &err, &oerr), VS_OK);
  vs_output_destroy(&p.record);
  char status[256];
  vs_test_record_status(path, status, sizeof status);
  assert_string_equal(status, "stopped by the caller");
  vs_run_destroy(&r);
  assert_int_equal(unlink(path), 0);
  unlink(xmf);
  assert_int_equal(rmdir(dir), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_path_stopped_at_third_equilibrium),
      cmocka_unit_test(test_run_stopped_in_each_phase),
      cmocka_unit_test(test_run_stopped_by_event),
      cmocka_unit_test(test_record_of_a_stopped_run),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
