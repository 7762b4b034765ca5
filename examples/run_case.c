/* A case run through libvoussoir's public API: read and validate an INI case, follow it to the
 * collapse, and print the collapse displacement and the hinges of the mechanism.
 *
 *   cc run_case.c $(pkg-config --cflags --libs voussoir) -lm -o run_case
 *   ./run_case CASE.ini [section.key=value]...
 *
 * Exit status: 0 ok, 1 the run failed, 2 bad input (as the voussoir program). */
#include <math.h>
#include <stdio.h>

#include "voussoir/hinges.h"
#include "voussoir/voussoir.h"

/* Count the recorded states; a non-zero return would stop the run. */
static int count_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  (void)run;
  (void)s;
  ++*(long *)user;
  return 0;
}

static void print_result(const vs_run *run, const vs_case *c, long samples) {
  const vs_collapse_record *col = vs_run_collapse(run);
  printf("states %ld, limit points %d, mode %s\n", samples, vs_run_limit_count(run),
         vs_run_mode(run) != NULL ? vs_run_mode(run) : "-");
  if (!col->found) {
    printf("no collapse up to %.3f mm\n", vs_run_delta(run) / VS_MM);
    return;
  }
  printf("collapse delta_u = %.4f mm (dz/L = %.3f %%)\n", col->delta / VS_MM,
         100.0 * col->delta / VS_MM * cos(c->alpha_deg * VS_DEG) / vs_case_span_mm(c));
  for (int i = 0; i < col->n_hinges; ++i) {
    char name[64];
    vs_hinge_name(&col->hinges[i], 0, name, sizeof name);
    printf("  hinge %c  %s  onset at %.3f mm\n", col->hinges[i].label, name,
           col->hinges[i].delta_onset / VS_MM);
  }
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s CASE.ini [section.key=value]...\n", argv[0]);
    return 2;
  }
  vs_case c;
  vs_error err;
  vs_run *run = NULL;
  long samples = 0;
  int rc = 2;
  vs_error_clear(&err);
  vs_case_defaults(&c);
  if (vs_case_read(&c, argv[1], NULL, &err) != VS_OK) goto cleanup;
  for (int i = 2; i < argc; ++i)
    if (vs_case_set(&c, argv[i], &err) != VS_OK) goto cleanup;
  if (vs_case_validate(&c, &err) != VS_OK || vs_run_create(&c, &run, &err) != VS_OK) goto cleanup;
  rc = 1;
  if (vs_run_execute(run, count_sample, NULL, &samples, &err) != VS_OK) goto cleanup;
  print_result(run, &c, samples);
  rc = 0;
cleanup:
  if (rc != 0) fprintf(stderr, "run_case: %s: %s\n", vs_strerror(err.status), err.msg);
  vs_run_destroy(&run);
  return rc;
}
