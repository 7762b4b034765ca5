/* Runs in threads of one process (as the Python package's sweep runs them): each gives, bit for
 * bit, what it gives alone: its collapse and the natural frequencies computed at its first
 * equilibrium. The library keeps no state between runs; ARPACK keeps the state of its reverse
 * communication in Fortran SAVE variables, which src/model/modal.c takes in turns (without
 * that, two threads crashed in dsaupd or mixed their Lanczos vectors). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "voussoir/case.h"
#include "voussoir/run.h"

enum { N_THREADS = 3, ROUNDS = 2 };

typedef struct {
  vs_case c;
  vs_status st;
  double delta_u;
  vs_modal modal;
  char msg[512];
} job;

/* One run of j->c to its collapse: its status, delta_u and modes (the copy of the struct: the
 * mode shapes are not compared). */
static void *run_job(void *arg) {
  job *j = arg;
  vs_error err;
  vs_run *r = NULL;
  vs_error_clear(&err);
  j->st = vs_run_create(&j->c, &r, &err);
  if (j->st == VS_OK) j->st = vs_run_execute(r, NULL, NULL, NULL, &err);
  if (j->st == VS_OK) {
    j->delta_u = vs_run_collapse(r)->delta;
    j->modal = *vs_run_modal(r);
    j->modal.phi = NULL;
  }
  snprintf(j->msg, sizeof j->msg, "%s", err.msg);
  vs_run_destroy(&r);
  return NULL;
}

static void test_threads_equal_alone(void **state) {
  (void)state;
  job alone;
  vs_error err;
  memset(&alone, 0, sizeof alone);
  vs_case_defaults(&alone.c);
  /* 200 voussoirs (600 unknowns): ARPACK's iterations take long enough for threads to meet */
  assert_int_equal(vs_case_set(&alone.c, "arch.voussoirs=200", &err), VS_OK);
  assert_int_equal(vs_case_set(&alone.c, "dynamic.fall_s=0", &err), VS_OK);
  assert_int_equal(vs_case_validate(&alone.c, &err), VS_OK);
  run_job(&alone);
  if (alone.st != VS_OK) fail_msg("alone: %s", alone.msg);
  assert_true(alone.modal.n_modes > 0);
  for (int round = 0; round < ROUNDS; round++) {
    job jobs[N_THREADS];
    pthread_t th[N_THREADS];
    for (int k = 0; k < N_THREADS; k++) {
      memset(&jobs[k], 0, sizeof jobs[k]);
      jobs[k].c = alone.c;
      assert_int_equal(pthread_create(&th[k], NULL, run_job, &jobs[k]), 0);
    }
    for (int k = 0; k < N_THREADS; k++) assert_int_equal(pthread_join(th[k], NULL), 0);
    for (int k = 0; k < N_THREADS; k++) {
      if (jobs[k].st != VS_OK) fail_msg("round %d, thread %d: %s", round, k, jobs[k].msg);
      if (jobs[k].delta_u != alone.delta_u)
        fail_msg("round %d, thread %d: delta_u %.17g, alone %.17g", round, k, jobs[k].delta_u,
                 alone.delta_u);
      assert_int_equal(jobs[k].modal.n_modes, alone.modal.n_modes);
      for (int m = 0; m < alone.modal.n_modes; m++)
        if (jobs[k].modal.omega[m] != alone.modal.omega[m])
          fail_msg("round %d, thread %d: mode %d at %.17g rad/s, alone %.17g", round, k, m,
                   jobs[k].modal.omega[m], alone.modal.omega[m]);
    }
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_threads_equal_alone)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
