/* The limit analysis' picture (issue 28 item 7; src/plot/plot_limit.c, `voussoir run` with
 * analysis.type = limit and --plot): the thrust line it draws against an independent
 * calculation from the LP's interface forces. At each joint the ends carry N_I, N_E >= 0, so
 * their resultant crosses the joint N_E / (N_I + N_E) of its length from the intrados end; the
 * test places that point itself (the joint's centre and tangent from the geometry) and finds
 * where the line touches an edge. For the reference specimen at its least thickness the line
 * touches at the hinges the picture marks, alternately intrados and extrados, symmetric about
 * the crown, and nowhere else; for the collapse under a point load at quarter span it touches at
 * the mechanism's hinges. The command writes the picture and refuses --plot without limit. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "plot_limit.h"
#include "voussoir/case.h"

#define VS_SCRATCH "limit_draw"
#include "scratch.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static void reference_def(vs_run_def *d, const char *set) {
  vs_case c;
  vs_case_defaults(&c);
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_case_read(&c, REFERENCE, NULL, &err), VS_OK);
  assert_int_equal(vs_case_set(&c, "analysis.type=limit", &err), VS_OK);
  if (set != NULL) {
    char buf[256];
    snprintf(buf, sizeof buf, "%s", set);
    for (char *tok = strtok(buf, " "); tok != NULL; tok = strtok(NULL, " "))
      assert_int_equal(vs_case_set(&c, tok, &err), VS_OK);
  }
  assert_int_equal(vs_case_validate(&c, &err), VS_OK);
  vs_case_to_def(&c, d);
}

/* The drawn thrust line of the picture of la against the forces: returns the touches found
 * independently (side per joint, 0 where none) into touch. */
static void check_line(const vs_run_def *d, const vs_limit_analysis *la, double edge_tol,
                       vs_plot_limit *p, char *touch) {
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_plot_limit_pick(d, la, p, &err), VS_OK);
  const vs_plot_arch_args a = vs_plot_limit_args(p);
  const int nj = p->g->n_joints;
  double *x = calloc((size_t)nj, sizeof *x), *z = calloc((size_t)nj, sizeof *z);
  assert_true(x != NULL && z != NULL);
  assert_int_equal(vs_plot_thrust_points(&a, x, z, &err), VS_OK);
  for (int k = 0; k < nj; k++) {
    const vs_joint_geom *j = &p->g->joints[k];
    const double ni = p->s->force[4 * k], ne = p->s->force[4 * k + 2];
    touch[k] = 0;
    if (!(ni + ne > 0.0)) {
      assert_true(isnan(x[k]));
      continue;
    }
    const double f = ne / (ni + ne);           /* from the intrados, a fraction of t */
    const double sx = -j->nz, sz = j->nx;       /* the tangent, intrados to extrados */
    const double px = j->px + (f - 0.5) * j->length * sx, pz = j->pz + (f - 0.5) * j->length * sz;
    if (!(hypot(x[k] - px, z[k] - pz) <= 1e-9 * j->length))
      fail_msg("joint %d: drawn (%.9g, %.9g), by the forces (%.9g, %.9g)", k + 1, x[k], z[k], px,
               pz);
    touch[k] = f <= edge_tol ? 'I' : f >= 1.0 - edge_tol ? 'E' : 0;
  }
  free(x);
  free(z);
}

/* The drawn hinges are where the line touches, and nothing else touches. */
static void expect_hinges_touch(const vs_plot_limit *p, const char *touch) {
  const int nj = p->g->n_joints;
  int found = 0;
  for (int k = 0; k < nj; k++) {
    char drawn = 0;
    for (int h = 0; h < p->n_hinges; h++)
      if (p->hinges[h].first == k + 1) drawn = p->hinges[h].side;
    if (drawn != touch[k])
      fail_msg("joint %d: hinge drawn '%c', the line by the forces touches '%c'", k + 1,
               drawn ? drawn : '-', touch[k] ? touch[k] : '-');
    found += touch[k] != 0;
  }
  assert_int_equal(found, p->n_hinges);
}

static void test_least_thickness(void **state) {
  (void)state;
  vs_run_def d;
  reference_def(&d, NULL);
  vs_limit_analysis la;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&d, NULL, &la, &err), VS_OK);
  vs_plot_limit p;
  char *touch = calloc(256, 1);
  assert_non_null(touch);
  /* at the bracket's upper end the critical line is within twice its relative width of the
   * edges it touches at the least thickness itself */
  const double tol = 2.0 * (la.thickness_bracket[1] - la.thickness_bracket[0]) /
                     la.thickness_bracket[1];
  check_line(&d, &la, tol, &p, touch);
  assert_true(p.s == &la.thickness);
  assert_true(fabs(p.g->thickness - la.thickness_factor * d.arch.thickness) <= 1e-12);
  expect_hinges_touch(&p, touch);
  const int nj = p.g->n_joints;
  char list[256] = "";
  int n = 0, sides[2] = {0, 0};
  for (int k = 0; k < nj; k++) {
    if (!touch[k]) continue;
    snprintf(list + strlen(list), sizeof list - strlen(list), " %d-%c", k + 1, touch[k]);
    n++;
    sides[touch[k] == 'E']++;
    assert_int_equal(touch[nj - 1 - k], touch[k]); /* symmetric about the crown */
  }
  print_message("least thickness %.5f t: the line touches%s\n", la.thickness_factor, list);
  /* a mechanism: at least four touches, on both edges, the springings' on the extrados */
  assert_true(n >= 4 && sides[0] >= 2 && sides[1] >= 2);
  assert_int_equal(touch[0], 'E');
  free(touch);
  vs_plot_limit_free(&p);
  vs_limit_analysis_free(&la);
}

static void test_collapse(void **state) {
  (void)state;
  vs_run_def d;
  reference_def(&d, "load.kind=point load.x_mm=133.05");
  vs_limit_analysis la;
  vs_error err;
  vs_error_clear(&err);
  assert_int_equal(vs_limit_analyse(&d, NULL, &la, &err), VS_OK);
  vs_plot_limit p;
  char *touch = calloc(256, 1);
  assert_non_null(touch);
  check_line(&d, &la, 1e-6, &p, touch);
  assert_true(p.s == &la.collapse);
  /* every hinge of the mechanism drawn, where the line touches that edge */
  for (int h = 0; h < p.n_hinges; h++) {
    const int k = p.hinges[h].first - 1;
    assert_int_equal(la.collapse.hinge[k], p.hinges[h].side);
    if (touch[k] != p.hinges[h].side)
      fail_msg("mechanism hinge %d-%c: the line does not touch there", k + 1, p.hinges[h].side);
  }
  assert_true(p.n_hinges >= 4);
  free(touch);
  vs_plot_limit_free(&p);
  vs_limit_analysis_free(&la);
}

static void test_cli(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=limit --plot lim.png >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  size_t n = 0;
  const char *png = slurp(in_dir("lim.png"), &n);
  assert_true(n > 1000 && memcmp(png, "\x89PNG", 4) == 0);
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --set analysis.type=limit --set load.kind=point "
           "--set load.x_mm=133.05 --json --plot lim.svg >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  assert_non_null(strstr(slurp(in_dir("lim.svg"), NULL), "<svg"));
  snprintf(cmd, sizeof cmd,
           "cd '%s' && '%s' run '%s' --first-limit --no-record --plot no.png >out.txt 2>err.txt",
           g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 2);
  assert_non_null(strstr(slurp(in_dir("err.txt"), NULL), "--plot"));
  FILE *f = fopen(in_dir("no.png"), "r");
  assert_null(f);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_least_thickness),
      cmocka_unit_test(test_collapse),
      cmocka_unit_test(test_cli),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
