/* Tests of the blocks files (arch.shape = file; src/model/blocks.c, docs/blocks-file.md):
 * - two rectangles on two piers: the blocks' area, centroid and inertia against a rectangle's
 *   closed forms at each block's own density, the interfaces found on the shared edges and
 *   numbered by the ring, each interface's own law in the model, the supports as the model's;
 * - under self-weight a symmetric lintel on two piers gives each pier half the weight and no
 *   horizontal force (statics);
 * - the reference arch written as a blocks file (vs_geometry_blocks_json, the `blocks` command)
 *   and run from it collapses as the arch it came from (its polygons facet the curves: to 1e-3),
 *   with the same hinges;
 * - springings on one vertical (a pushed block, a column): the span is the blocks' width; the
 *   column's path ends with its cause stated (a converged state off the branch);
 * - bad files refused, naming the field or the blocks and what is allowed, and the program's
 *   exit status 2 with nothing written; outputs of `blocks` that are not regular files refused. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, mkfifo, symlink */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define VS_SCRATCH "blocks"
#include "check.h"
#include "scratch.h"
#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/run.h"
#include "voussoir/units.h"

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "wb");
  if (f == NULL) fail_msg("%s: cannot write", path);
  fputs(text, f);
  fclose(f);
}

/* The reference case with arch.shape = file on the blocks file text (written in the scratch
 * directory as name). */
static vs_case file_case(const char *name, const char *text) {
  vs_case c;
  vs_case_defaults(&c);
  write_file(in_dir(name), text);
  c.shape = VS_SHAPE_FILE;
  snprintf(c.blocks_file, sizeof c.blocks_file, "%s", in_dir(name));
  return c;
}

static vs_status geometry_of(const vs_case *c, vs_geometry **g, vs_error *err) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  vs_error_clear(err);
  return vs_geometry_create_arch(&d.arch, g, err);
}

/* Two blocks 40 x 20 mm side by side on a left pier (under both) and against a right pier
 * (beside the second); the block on the left of density 2000, the other the case's. */
static const char *TWO =
    "{\"format\": \"voussoir-blocks 1\", \"units\": \"mm\",\n"
    " \"blocks\": [\n"
    "  {\"name\": \"L\", \"support\": \"left\", \"polygon\": [[0,0],[100,0],[100,10],[90,10],"
    "[50,10],[10,10],[0,10]]},\n"
    "  {\"name\": \"a\", \"density_kg_m3\": 2000, \"polygon\": [[10,10],[50,10],[50,30],[10,30]]},\n"
    "  {\"name\": \"b\", \"polygon\": [[90,30],[50,30],[50,10],[90,10]]},\n"
    "  {\"name\": \"R\", \"support\": \"right\", \"polygon\": [[90,10],[120,10],[120,30],[90,30]]}\n"
    " ],\n"
    " \"interfaces\": [{\"between\": [\"b\", \"a\"], \"friction\": 0.4, \"kn_N_mm3\": 10}],\n"
    " \"ring\": [\"L\", \"a\", \"b\", \"R\"]}\n";

static void test_two_blocks(void **state) {
  (void)state;
  const vs_case c = file_case("two.json", TWO);
  vs_geometry *g = NULL;
  vs_error err;
  if (geometry_of(&c, &g, &err) != VS_OK) fail_msg("%s", err.msg);
  assert_int_equal(g->n_blocks, 2);
  assert_int_equal(g->ring, 3); /* L-a, a-b, b-R; then L-b */
  assert_int_equal(g->n_joints, 4);
  const double w = 0.04, h = 0.02, b = c.depth_mm * VS_MM, A = w * h;
  const double rho[2] = {2000.0, c.density_kg_m3}, cx[2] = {0.03, 0.07};
  for (int i = 0; i < 2; i++) {
    CHECK(g->blocks[i].area, A, 1e-13, 0);
    CHECK(g->blocks[i].cx, cx[i], 0, 1e-15);
    CHECK(g->blocks[i].cz, 0.02, 0, 1e-15);
    CHECK(g->blocks[i].mass, rho[i] * b * A, 1e-13, 0);
    CHECK(g->blocks[i].inertia, rho[i] * b * A * (w * w + h * h) / 12.0, 1e-11, 0);
  }
  /* the ring's joints: left pier / a (a's bottom), a / b (their shared side), b / right pier */
  const int ja[4] = {VS_SUPPORT_LEFT, 0, 1, VS_SUPPORT_LEFT};
  const int jb[4] = {0, 1, VS_SUPPORT_RIGHT, 1};
  const double px[4] = {0.03, 0.05, 0.09, 0.07}, pz[4] = {0.01, 0.02, 0.02, 0.01};
  const double nx[4] = {0, 1, 1, 0}, nz[4] = {1, 0, 0, 1}, len[4] = {0.04, 0.02, 0.02, 0.04};
  for (int k = 0; k < 4; k++) {
    const vs_joint_geom *j = &g->joints[k];
    assert_int_equal(j->a, ja[k]);
    assert_int_equal(j->b, jb[k]);
    CHECK(j->px, px[k], 0, 1e-15);
    CHECK(j->pz, pz[k], 0, 1e-15);
    CHECK(j->nx, nx[k], 0, 1e-15);
    CHECK(j->nz, nz[k], 0, 1e-15);
    CHECK(j->length, len[k], 1e-14, 0);
  }
  assert_int_equal(g->n_supports, 2);
  vs_geometry_destroy(&g);
  /* the run's model: the interface a-b at its own k_n and friction, k_s at the case's ratio */
  vs_run *r = NULL;
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_joint_law *l = vs_model_joint_law(vs_run_model(r), 1);
  CHECK(l->kn, 10.0 * VS_N_MM3, 1e-15, 0);
  CHECK(l->ks, 0.5 * 10.0 * VS_N_MM3, 1e-15, 0);
  CHECK(l->mu, 0.4, 1e-15, 0);
  l = vs_model_joint_law(vs_run_model(r), 0);
  CHECK(l->kn, c.kn_N_mm3 * VS_N_MM3, 1e-15, 0);
  CHECK(l->mu, c.friction, 1e-15, 0);
  vs_run_destroy(&r);
}

/* The reactions of the first equilibrium (self-weight, delta = 0) into user (6 doubles). */
static int first_reactions(void *user, const vs_run *run, const vs_run_sample *smp) {
  (void)run;
  double *R = user;
  if (smp->delta == 0.0 && isnan(R[0])) memcpy(R, smp->reactions, 6 * sizeof *R);
  return 0;
}

/* A lintel 200 x 20 mm on two piers, 30 mm of it on each: under its own weight each pier
 * carries half of it, with no horizontal force (the program's reactions at the first
 * equilibrium, to its Newton tolerance). */
static void test_lintel_statics(void **state) {
  (void)state;
  const char *text =
      "{\"format\": \"voussoir-blocks 1\",\n"
      " \"blocks\": [\n"
      "  {\"name\": \"left\", \"support\": \"left\", \"polygon\": [[-30,-50],[0,-50],[0,0],[-30,0]]},\n"
      "  {\"name\": \"lintel\", \"polygon\": [[-30,0],[0,0],[140,0],[170,0],[170,20],[-30,20]]},\n"
      "  {\"name\": \"right\", \"support\": \"right\", \"polygon\": [[140,-50],[170,-50],[170,0],"
      "[140,0]]}]}\n";
  vs_case c = file_case("lintel.json", text);
  c.kn_N_mm3 = 48.0;
  c.max_mm = 1e-3, c.step_mm = c.step_max_mm = 5e-4, c.limit_tol_mm = 1e-6;
  c.fall_s = 0.0;
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  assert_int_equal(vs_run_geometry(r)->ring, 2); /* the chain left / lintel / right, found */
  double R[6] = {NAN, NAN, NAN, NAN, NAN, NAN};
  assert_int_equal(vs_run_execute(r, first_reactions, NULL, R, &err), VS_OK);
  const double W = vs_geometry_weight(vs_run_geometry(r));
  CHECK(W, c.density_kg_m3 * c.depth_mm * VS_MM * 0.2 * 0.02 * c.gravity_m_s2, 1e-12, 0);
  /* on the arch: left Fx, Fz, M; right Fx, Fz, M */
  CHECK(R[1], 0.5 * W, 1e-6, 0);
  CHECK(R[4], 0.5 * W, 1e-6, 0);
  CHECK(R[0], 0.0, 0, 1e-6 * W);
  CHECK(R[3], 0.0, 0, 1e-6 * W);
  vs_run_destroy(&r);
}

/* The collapse of case c (k_n 48, settlement): delta_u and the hinges' names at the collapse. */
static double collapse_of(const vs_case *c, char *hinges, size_t size) {
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_run_create(c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) != VS_OK) fail_msg("%s", err.msg);
  const vs_collapse_record *col = vs_run_collapse(r);
  hinges[0] = '\0';
  for (int i = 0; i < col->n_hinges; i++) {
    char name[64];
    vs_hinge_name(&col->hinges[i], 0, name, sizeof name);
    strncat(hinges, name, size - strlen(hinges) - 2);
    strcat(hinges, " ");
  }
  const double d = col->delta;
  vs_run_destroy(&r);
  return d;
}

static void test_reference_as_a_file(void **state) {
  (void)state;
  char case_path[600];
  snprintf(case_path, sizeof case_path, "%s/runs/reference.ini", VS_SOURCE_DIR);
  char *argv[] = {VS_BINARY, "blocks", case_path, "-o", "ref.json", NULL};
  assert_int_equal(run_argv(argv), 0);
  vs_case ref, file;
  vs_case_defaults(&ref);
  ref.kn_N_mm3 = 48.0;
  ref.fall_s = 0.0;
  file = ref;
  file.shape = VS_SHAPE_FILE;
  snprintf(file.blocks_file, sizeof file.blocks_file, "%s", in_dir("ref.json"));
  char h_ref[256], h_file[256];
  const double d_ref = collapse_of(&ref, h_ref, sizeof h_ref);
  const double d_file = collapse_of(&file, h_file, sizeof h_file);
  print_message("collapse: the arch %.4f mm (%s), its blocks file %.4f mm (%s)\n", d_ref / VS_MM,
                h_ref, d_file / VS_MM, h_file);
  CHECK(d_file, d_ref, 1e-3, 0);
  assert_string_equal(h_file, h_ref);
  /* and the file names its blocks, supports and ring as the command says */
  const char *t = slurp(in_dir("ref.json"), NULL);
  assert_non_null(strstr(t, "\"format\": \"voussoir-blocks 1\""));
  assert_non_null(strstr(t, "{\"name\":\"left pier\",\"support\":\"left\""));
  assert_non_null(strstr(t, "\"ring\": [\"left pier\",\"v1\",\"v2\","));
}

/* Springings not apart horizontally: a block pushed sideways on its base (the intrados ends of
 * its joints both at its bottom right corner) and a column of two blocks on a base (all three
 * joints level, their intrados ends on one vertical): no intrados span, so the span is the
 * width of the ring's blocks (it divides the displacements, dz/L, and sizes the fall's ground). */
static void test_span_of_springings_on_a_vertical(void **state) {
  (void)state;
  static const char *const files[2] = {
      "{\"format\": \"voussoir-blocks 1\", \"blocks\": ["
      "{\"name\": \"L\", \"support\": \"left\", \"polygon\": [[0,-50],[100,-50],[100,0],[0,0]]},"
      "{\"name\": \"a\", \"polygon\": [[0,0],[100,0],[100,50],[0,50]]},"
      "{\"name\": \"R\", \"support\": \"right\", \"polygon\": [[100,0],[150,0],[150,50],"
      "[100,50]]}], \"ring\": [\"L\", \"a\", \"R\"]}",
      "{\"format\": \"voussoir-blocks 1\", \"blocks\": ["
      "{\"name\": \"L\", \"support\": \"left\", \"polygon\": [[-20,0],[60,0],[60,10],[40,10],"
      "[0,10],[-20,10]]},"
      "{\"name\": \"a\", \"polygon\": [[0,10],[40,10],[40,20],[0,20]]},"
      "{\"name\": \"b\", \"polygon\": [[0,20],[40,20],[40,30],[0,30]]},"
      "{\"name\": \"R\", \"support\": \"right\", \"polygon\": [[0,30],[40,30],[40,40],[0,40]]}]}"};
  const double width[2] = {0.1, 0.04};
  for (int i = 0; i < 2; i++) {
    const vs_case c = file_case("vertical.json", files[i]);
    vs_geometry *g = NULL;
    vs_error err;
    if (geometry_of(&c, &g, &err) != VS_OK) fail_msg("%s", err.msg);
    CHECK(g->span, width[i], 0, 1e-15);
    vs_geometry_destroy(&g);
  }
  /* A block between a base and a top support moved down along their axis: no path tangent (it
   * only presses on them), so the first increment's converged state leaves the predictor, which
   * did not move; the run's error says so (it said "Newton failed", which it had not). */
  vs_case c = file_case("column.json",
      "{\"format\": \"voussoir-blocks 1\", \"blocks\": ["
      "{\"name\": \"L\", \"support\": \"left\", \"polygon\": [[-100,0],[0,0],[0,100],[-100,100]]},"
      "{\"name\": \"a\", \"polygon\": [[-100,100],[0,100],[0,200],[-100,200]]},"
      "{\"name\": \"R\", \"support\": \"right\", \"polygon\": [[-100,200],[0,200],[0,300],"
      "[-100,300]]}]}");
  c.fall_s = 0.0;
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  if (vs_run_create(&c, &r, &err) != VS_OK) fail_msg("%s", err.msg);
  if (vs_run_execute(r, NULL, NULL, NULL, &err) == VS_OK) {
    print_message("the column's run ended without an error: nothing to check\n");
  } else if (strstr(err.msg, "Newton failed") != NULL ||
             strstr(err.msg, "Newton converged at") == NULL ||
             strstr(err.msg, "off the followed branch") == NULL) {
    fail_msg("the column's run: its cause misstated: %s", err.msg);
  }
  vs_run_destroy(&r);
}

/* A file refused: the status and the message's words. */
static void refused(const char *text, vs_status want, const char *needle) {
  const vs_case c = file_case("bad.json", text);
  vs_geometry *g = NULL;
  vs_error err;
  assert_int_equal(geometry_of(&c, &g, &err), want);
  assert_null(g);
  if (strstr(err.msg, needle) == NULL) fail_msg("expected \"%s\" in \"%s\"", needle, err.msg);
}

#define HEAD "{\"format\": \"voussoir-blocks 1\", \"blocks\": ["
#define PIERS                                                                                    \
  "{\"name\": \"L\", \"support\": \"left\", \"polygon\": [[-10,0],[0,0],[0,10],[-10,10]]},"      \
  "{\"name\": \"R\", \"support\": \"right\", \"polygon\": [[40,0],[50,0],[50,10],[40,10]]}"

static void test_refused(void **state) {
  (void)state;
  refused("{\"format\": ", VS_ERR_PARSE, "bad.json:1:");
  refused("[1, 2]", VS_ERR_INVALID, "not an object");
  refused("{\"format\": \"voussoir-blocks 2\", \"blocks\": []}", VS_ERR_INVALID,
          "format: not this format (allowed: \"voussoir-blocks 1\")");
  refused(HEAD PIERS "], \"colour\": 1}", VS_ERR_INVALID,
          "the file: unknown field \"colour\" (allowed: format, units, tolerance_mm, blocks, "
          "interfaces, ring)");
  refused(HEAD PIERS "], \"units\": \"m\"}", VS_ERR_INVALID, "units: not mm (allowed: \"mm\")");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0]]}]}", VS_ERR_INVALID,
          "blocks[2] (\"a\").polygon: wrong number of vertices (allowed: an array of 3 to 256");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,\"x\"]]}]}", VS_ERR_INVALID,
          "blocks[2] (\"a\").polygon[2]: not a vertex (allowed: [x, z]");
  refused(HEAD PIERS ",{\"name\": \"L\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]}]}",
          VS_ERR_INVALID, "blocks[2].name: \"L\" is blocks[0]'s too");
  refused(HEAD PIERS ",{\"name\": \"a\", \"support\": \"middle\", \"polygon\": [[0,0],[40,0],"
          "[40,10],[0,10]]}]}", VS_ERR_INVALID, "blocks[2] (\"a\").support: not a support");
  refused(HEAD PIERS ",{\"name\": \"a\", \"density_kg_m3\": 5, \"polygon\": [[0,0],[40,0],"
          "[40,10],[0,10]]}]}", VS_ERR_INVALID, "blocks[2] (\"a\").density_kg_m3: out of range "
          "(allowed: a number in [10, 100000])");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,10],[40,0],[0,10]]}]}",
          VS_ERR_INVALID, "blocks[2] (\"a\").polygon: edges 0 and 2 cross");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]},"
          "{\"name\": \"z\", \"polygon\": [[200,0],[210,0],[210,10]]}]}", VS_ERR_INVALID,
          "blocks[3] (\"z\") shares no edge with another block or a support");
  /* the left pier's side is 0..10, the block's 0..6: on one line, overlapping only partly */
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,6],[0,6]]}]}",
          VS_ERR_INVALID, "blocks[0] (\"L\") and blocks[2] (\"a\"): edges that overlap only partly");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]}],"
          " \"ring\": [\"R\", \"a\", \"L\"]}", VS_ERR_INVALID,
          "ring[0]: \"R\" is the right support (allowed: a left support first)");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]}],"
          " \"ring\": [\"L\", \"q\", \"R\"]}", VS_ERR_INVALID, "ring[1]: not a block's name");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]}],"
          " \"interfaces\": [{\"between\": [\"L\", \"R\"], \"friction\": 0.3}]}", VS_ERR_INVALID,
          "interfaces[0]: \"L\" and \"R\" share no edge");
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[40,0],[40,10],[0,10]]}],"
          " \"interfaces\": [{\"between\": [\"L\", \"a\"], \"friction\": -1}]}", VS_ERR_INVALID,
          "interfaces[0].friction: out of range");
  /* two blocks side by side on the piers: no chain, so a ring is needed */
  refused(HEAD PIERS ",{\"name\": \"a\", \"polygon\": [[0,0],[20,0],[20,10],[0,10]]},"
          "{\"name\": \"b\", \"polygon\": [[20,0],[40,0],[40,10],[20,10]]},"
          "{\"name\": \"c\", \"polygon\": [[0,10],[20,10],[20,20],[0,20]]}]}", VS_ERR_INVALID,
          "ring: missing, and the blocks do not make one chain");
  /* a FIFO is refused without blocking */
  vs_case c;
  vs_case_defaults(&c);
  c.shape = VS_SHAPE_FILE;
  snprintf(c.blocks_file, sizeof c.blocks_file, "%s", in_dir("fifo.json"));
  assert_int_equal(mkfifo(c.blocks_file, 0600), 0);
  vs_geometry *g = NULL;
  vs_error err;
  alarm(30);
  assert_int_equal(geometry_of(&c, &g, &err), VS_ERR_IO);
  alarm(0);
  assert_non_null(strstr(err.msg, "not a regular file"));
}

/* The program: a bad blocks file is bad input (exit status 2), and nothing is written. */
static void test_program_refuses(void **state) {
  (void)state;
  write_file(in_dir("bad.json"), HEAD PIERS ",{\"name\": \"L2\", \"support\": \"left\", "
                                 "\"polygon\": [[-10,-10],[0,-10],[0,0],[-10,0]]}]}");
  write_file(in_dir("bad.ini"), "[arch]\nshape = file\nblocks_file = bad.json\n");
  char before[4096], after[4096];
  listing(before, sizeof before);
  char *run[] = {VS_BINARY, "run", "bad.ini", "-o", "bad.h5", "-q", NULL};
  assert_int_equal(run_argv(run), 2);
  assert_non_null(strstr(slurp(in_dir("err.txt"), NULL), "blocks: 0 blocks, 2 left and 1 right "
                                                         "supports (allowed: at least one block"));
  listing(after, sizeof after);
  assert_string_equal(before, after);
  /* blocks -o: never the case file, nor written through a link */
  char case_path[600];
  snprintf(case_path, sizeof case_path, "%s/runs/reference.ini", VS_SOURCE_DIR);
  write_file(in_dir("target.txt"), "keep");
  assert_int_equal(symlink(in_dir("target.txt"), in_dir("link.json")), 0);
  char *link[] = {VS_BINARY, "blocks", case_path, "-o", "link.json", NULL};
  assert_int_equal(run_argv(link), 2);
  assert_string_equal(slurp(in_dir("target.txt"), NULL), "keep");
  char *self[] = {VS_BINARY, "blocks", "bad.ini", "-o", "bad.ini", NULL};
  assert_int_equal(run_argv(self), 2);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_two_blocks),
      cmocka_unit_test(test_lintel_statics),
      cmocka_unit_test(test_span_of_springings_on_a_vertical),
      cmocka_unit_test(test_refused),
      cmocka_unit_test(test_program_refuses),
      cmocka_unit_test(test_reference_as_a_file),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
