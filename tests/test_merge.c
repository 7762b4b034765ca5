/* voussoir merge reads the shards' tables as input it does not trust: tables written here by hand
 * (the format of montecarlo.c's samples.csv) merge when they are sound; a header with a field
 * out of the case's range (voussoirs=0, radius_mm=0), not finite (nan, inf), missing, given
 * twice or unknown, shards whose headers disagree, and rows with a field that is not what its
 * column holds are refused: exit 2, the file, line and field named with what is allowed, and
 * nothing written. An error text with control bytes is merged quoted. Samples that do not fit
 * in memory: exit 1, the file and line named. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define VS_SCRATCH "merge"
#include "scratch.h"

#define MAGIC "# voussoir montecarlo "
#define HEADER MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 voussoirs=55\n"
#define COLUMNS \
  "sample,status,first_limit_mm,delta_u_mm,dz_u_mm,dx_u_mm,mode,pattern,A,B,C,D,E,error," \
  "left_dx_mm,left_dz_mm,right_dx_mm,right_dz_mm,load_factor\n"
/* Rows of two shards (--shard 1/2 and 2/2 of four samples), in the writer's format. */
#define ROWS_1 "0,collapse,60.5,70.25,70.25,0,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n" \
               "2,failed,nan,nan,nan,nan,0,,,,,,,the arch cannot stand,nan,nan,nan,nan,nan\n"
#define ROWS_2 "1,collapse,58,66.5,66.5,0,1,E-I-E-E,8-I,29-E,56-E,1-E,,,0,0,0,70.25,nan\n" \
               "3,max_displacement,nan,nan,nan,nan,0,,,,,,,,nan,nan,nan,nan,nan\n"

/* DIR/samples.csv with text (mkdir DIR first). */
static void shard(const char *dir, const char *text) {
  mkdir(in_dir(dir), 0755);
  char path[300];
  snprintf(path, sizeof path, "%s/samples.csv", in_dir(dir));
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  fputs(text, f);
  assert_int_equal(fclose(f), 0);
}

/* `voussoir merge s1 [s2] -o out` in g_dir; the exit status, stderr in err.txt. */
static int merge(int two) {
  char cmd[512];
  snprintf(cmd, sizeof cmd,
           "cd '%s' && rm -rf out && timeout -s KILL 60 '%s' merge s1 %s -o out >out.txt 2>err.txt",
           g_dir, VS_BINARY, two ? "s2" : "");
  return sh(cmd);
}

/* merge refused: exit 2, every needle in its message, no output directory. */
static void expect_refused(int two, const char *const needles[], const char *what) {
  const int rc = merge(two);
  const char *err = slurp(in_dir("err.txt"), NULL);
  if (rc != 2) fail_msg("%s: exit status %d, expected 2: %s", what, rc, err);
  for (int i = 0; needles[i] != NULL; i++)
    if (strstr(err, needles[i]) == NULL)
      fail_msg("%s: message lacks \"%s\": %s", what, needles[i], err);
  if (access(in_dir("out"), F_OK) == 0) fail_msg("%s: the output directory was written", what);
}

static void test_sound_tables_merge(void **s) {
  (void)s;
  shard("s1", HEADER COLUMNS ROWS_1);
  shard("s2", HEADER COLUMNS ROWS_2);
  const int rc = merge(1);
  if (rc != 0) fail_msg("exit status %d: %s", rc, slurp(in_dir("err.txt"), NULL));
  assert_int_equal(access(in_dir("out/summary.h5"), F_OK), 0);
  const char *out = slurp(in_dir("out/samples.csv"), NULL);
  assert_non_null(strstr(out, "\n3,max_displacement,"));
}

/* Each header as a shard's line 1: refused, naming the file's line 1, the field and (when the
 * value is the problem) what the field allows. */
static void test_bad_headers(void **s) {
  (void)s;
  static const struct {
    const char *header, *needles[5];
  } cases[] = {
      {MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 voussoirs=0\n",
       {"s1/samples.csv:1:", "voussoirs = 0", "allowed: integer in [1, 2000]", NULL}},
      {MAGIC "seed=1 radius_mm=0 embrace_deg=125 max_mm=300 alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "radius_mm = 0", "allowed: [0.001, 1e+06] mm", NULL}},
      {MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=nan alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "max_mm = nan", "not a finite number", "allowed"}},
      {MAGIC "seed=1 radius_mm=300 embrace_deg=inf max_mm=300 alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "embrace_deg = inf", "not a finite number", "allowed"}},
      {MAGIC "seed=1 radius_mm=300 max_mm=300 alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "embrace_deg missing", NULL}},
      {MAGIC "seed=1 radius_mm=300 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 "
             "voussoirs=55\n",
       {"s1/samples.csv:1:", "radius_mm given twice", NULL}},
      {MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 voussoirs=55 kn=3\n",
       {"s1/samples.csv:1:", "'kn'", NULL}},
      {MAGIC "seed=-1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "seed = -1", "allowed", NULL}},
      {MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=400 voussoirs=55\n",
       {"s1/samples.csv:1:", "alpha_deg = 400", "allowed: [-180, 180] deg", NULL}},
      {"# another table\n", {"s1/samples.csv:1:", "not a montecarlo table", NULL}},
      /* each field within its range, the case they make not valid: max_mm below step_mm */
      {MAGIC "seed=1 radius_mm=300 embrace_deg=125 max_mm=0.25 alpha_deg=0 voussoirs=55\n",
       {"s1/samples.csv:1:", "max_mm", "step_mm", NULL}},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char text[1024], what[32];
    snprintf(text, sizeof text, "%s" COLUMNS ROWS_1, cases[i].header);
    snprintf(what, sizeof what, "header %zu", i);
    shard("s1", text);
    expect_refused(0, cases[i].needles, what);
  }
}

/* Two shards whose headers disagree: the field named, with both files. */
static void test_headers_disagree(void **s) {
  (void)s;
  shard("s1", HEADER COLUMNS ROWS_1);
  shard("s2", MAGIC "seed=1 radius_mm=301 embrace_deg=125 max_mm=300 alpha_deg=0 "
              "voussoirs=55\n" COLUMNS ROWS_2);
  const char *needles[] = {"s2/samples.csv:1:", "radius_mm=301", "s1/samples.csv:1", NULL};
  expect_refused(1, needles, "radius");
  shard("s2", MAGIC "seed=2 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 "
              "voussoirs=55\n" COLUMNS ROWS_2);
  const char *seed[] = {"s2/samples.csv:1:", "seed=2", NULL};
  expect_refused(1, seed, "seed");
}

/* A row's field that is not what its column holds: its line and column named. */
static void test_bad_rows(void **s) {
  (void)s;
  static const struct {
    const char *row, *needles[4];
  } cases[] = {
      {"0,collapse,abc,70.25,70.25,0,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n",
       {":3:", "first_limit_mm", NULL}},
      {"0,collapse,60.5,inf,70.25,0,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "delta_u_mm", NULL}},
      {"0,collapse,60.5,nan,nan,nan,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "delta_u_mm", NULL}},
      {"0,bogus,60.5,70.25,70.25,0,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "status", NULL}},
      {"0,collapse,60.5,70.25,70.25,0,7,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "mode", NULL}},
      {"0,collapse,60.5,70.25,70.25,0,1,E-I-E-E,57-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n",
       {":3:", "A = '57-I'", NULL}},
      {"0,collapse,60.5,70.25,70.25,0,1,E-I-E-E,9-X,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "A = '9-X'", NULL}},
      {"0,collapse,60.5,70.25,70.25,0,1,E-I-<b>,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "pattern", NULL}},
      {"-1,collapse,60.5,70.25,70.25,0,1,E-I-E-E,9-I,28-E,56-E,1-E,,,0,0,0,70.25,nan\n", {":3:", "sample", NULL}},
      {"0,collapse,60.5\n", {":3:", "columns", NULL}},
      /* more columns than montecarlo writes: its causes' commas and quotes are written ';'
       * (found by tests/fuzz/fuzz_merge.c) */
      {"0,failed,nan,nan,nan,nan,0,,,,,,,cannot stand, 2 extra,nan,nan,nan,nan\n",
       {":3:", "left_dx_mm", NULL}},
      {"0,failed,nan,nan,nan,nan,0,,,,,,,a \"quoted\" cause,nan,nan,nan,nan,nan\n", {":3:", "error", NULL}},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    char text[1024], what[32];
    snprintf(text, sizeof text, HEADER COLUMNS "%s", cases[i].row);
    snprintf(what, sizeof what, "row %zu", i);
    shard("s1", text);
    expect_refused(0, cases[i].needles, what);
  }
}

/* A FIFO where a table goes (a stand-in in the scratch directory): refused at once, not waited
 * on. */
static void test_table_not_regular(void **s) {
  (void)s;
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s/s1' && mkdir '%s/s1' && mkfifo '%s/s1/samples.csv'", g_dir,
           g_dir, g_dir);
  assert_int_equal(sh(cmd), 0);
  const char *needles[] = {"s1/samples.csv: not a regular file", NULL};
  expect_refused(0, needles, "FIFO");
  snprintf(cmd, sizeof cmd, "rm -rf '%s/s1'", g_dir); /* the next test writes a table there */
  assert_int_equal(sh(cmd), 0);
}

/* An error text with an escape sequence and a bell: merged, quoted. */
static void test_error_text_quoted(void **s) {
  (void)s;
  shard("s1", HEADER COLUMNS "0,failed,nan,nan,nan,nan,0,,,,,,,bad \x1b[2J\x07 luck,nan,nan,nan,nan,nan\n");
  assert_int_equal(merge(0), 0);
  const char *out = slurp(in_dir("out/samples.csv"), NULL);
  for (const char *p = out; *p; p++)
    if ((unsigned char)*p < 0x20 && *p != '\n') fail_msg("control byte 0x%02x in the table", *p);
  assert_non_null(strstr(out, "bad \\x1b[2J\\x07 luck"));
}

/* Shards whose samples do not fit in memory: the merge's growing array cannot grow (the
 * address space limited to 160 MiB, some 60 MiB of it the program's libraries; 300 000 rows
 * take 150 MiB and more): "FILE:LINE: out of memory" with the samples it was holding, exit 1,
 * nothing written. Not under AddressSanitizer, whose shadow memory needs terabytes of address
 * space. */
static void test_out_of_memory(void **s) {
  (void)s;
#if defined(__SANITIZE_ADDRESS__)
  skip();
#endif
  shard("s1", HEADER COLUMNS);
  char path[300];
  snprintf(path, sizeof path, "%s/samples.csv", in_dir("s1"));
  FILE *f = fopen(path, "ab");
  assert_non_null(f);
  for (int i = 0; i < 300000; i++)
    fprintf(f, "%d,failed,nan,nan,nan,nan,0,,,,,,,,nan,nan,nan,nan,nan\n", i);
  assert_int_equal(fclose(f), 0);
  char cmd[512];
  snprintf(cmd, sizeof cmd, "cd '%s' && rm -rf out && ulimit -v 163840 && timeout -s KILL 60 '%s' "
           "merge s1 -o out >out.txt 2>err.txt", g_dir, VS_BINARY);
  const int rc = sh(cmd);
  const char *err = slurp(in_dir("err.txt"), NULL);
  if (rc != 1) fail_msg("exit status %d, expected 1: %s", rc, err);
  if (strstr(err, "s1/samples.csv:") == NULL || strstr(err, ": out of memory holding ") == NULL)
    fail_msg("message: %s", err);
  if (access(in_dir("out"), F_OK) == 0) fail_msg("the output directory was written");
  snprintf(cmd, sizeof cmd, "rm -rf '%s/s1'", g_dir);
  assert_int_equal(sh(cmd), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sound_tables_merge),
      cmocka_unit_test(test_bad_headers),
      cmocka_unit_test(test_headers_disagree),
      cmocka_unit_test(test_bad_rows),
      cmocka_unit_test(test_table_not_regular),
      cmocka_unit_test(test_error_text_quoted),
      cmocka_unit_test(test_out_of_memory),
  };
  return cmocka_run_group_tests(tests, scratch_setup, scratch_teardown);
}
