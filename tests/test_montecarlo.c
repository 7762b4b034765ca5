/* Tests of voussoir montecarlo and merge through the CLI: the same seed gives identical summaries
 * on 1 and 2 processes and from two shards merged; another seed other results; bad input exits
 * with 2 and writes nothing. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef VS_BINARY
#error "VS_BINARY (path of the voussoir executable) must be defined"
#endif

#include "study_procs.h"
#include "voussoir/montecarlo.h"

static char g_dir[] = "/tmp/vs_mc_XXXXXX";

static int setup(void **state) {
  (void)state;
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

static int teardown(void **state) {
  (void)state;
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
  return system(cmd) == 0 ? 0 : -1;
}

/* The imperfect reference arch, small amplitudes, a cheap case: 21 voussoirs. */
#define CASE VS_SOURCE_DIR "/runs/reference.ini --set arch.voussoirs=21 " \
  "--set imperfections.kn_cov=0.3 --set imperfections.face_mm=0.002 --set imperfections.angle_cov=0.02"

static int run(const char *args) {
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "'%s' %s >/dev/null 2>'%s/err.txt'", VS_BINARY, args, g_dir);
  int w = system(cmd);
  return WIFEXITED(w) ? WEXITSTATUS(w) : -1;
}

static char *slurp(const char *dir, const char *name) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s/%s", g_dir, dir, name);
  FILE *f = fopen(path, "rb");
  if (f == NULL) fail_msg("%s: missing", path);
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  rewind(f);
  char *s = malloc((size_t)n + 1);
  assert_non_null(s);
  assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
  s[n] = '\0';
  fclose(f);
  return s;
}

static void same_file(const char *a, const char *b, const char *name) {
  char *x = slurp(a, name), *y = slurp(b, name);
  if (strcmp(x, y) != 0) fail_msg("%s differs between %s and %s", name, a, b);
  free(x);
  free(y);
}

static void test_same_summary_any_process_count(void **state) {
  (void)state;
  char args[1024];
  snprintf(args, sizeof args, "montecarlo %s --samples 6 --seed 11 -j 1 -q -o %s/j1", CASE, g_dir);
  assert_int_equal(run(args), 0);
  snprintf(args, sizeof args, "montecarlo %s --samples 6 --seed 11 -j 2 -q -o %s/j2", CASE, g_dir);
  assert_int_equal(run(args), 0);
  same_file("j1", "j2", "samples.csv");
  same_file("j1", "j2", "statistics.csv");
  /* two shards, merged */
  snprintf(args, sizeof args, "montecarlo %s --samples 6 --seed 11 --shard 1/2 -q -o %s/s1", CASE,
           g_dir);
  assert_int_equal(run(args), 0);
  snprintf(args, sizeof args, "montecarlo %s --samples 6 --seed 11 --shard 2/2 -q -o %s/s2", CASE,
           g_dir);
  assert_int_equal(run(args), 0);
  snprintf(args, sizeof args, "merge %s/s2 %s/s1 -o %s/merged", g_dir, g_dir, g_dir);
  assert_int_equal(run(args), 0);
  same_file("j1", "merged", "samples.csv");
  same_file("j1", "merged", "statistics.csv");
  /* a shard twice is refused; so is a merge into a shard's own directory (its table is an
   * input), which stays as it was */
  snprintf(args, sizeof args, "merge %s/s1 %s/s1 -o %s/twice", g_dir, g_dir, g_dir);
  assert_int_equal(run(args), 2);
  char *s1 = slurp("s1", "samples.csv");
  snprintf(args, sizeof args, "merge %s/s2 %s/s1 -o %s/s1", g_dir, g_dir, g_dir);
  assert_int_equal(run(args), 2);
  char *s1_after = slurp("s1", "samples.csv");
  assert_string_equal(s1, s1_after);
  free(s1), free(s1_after);
  /* every file renamed into place: no working file left */
  const char *names[] = {"samples.csv", "statistics.csv", "summary.h5"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    struct stat sp;
    snprintf(args, sizeof args, "%s/merged/%s", g_dir, names[i]);
    assert_int_equal(stat(args, &sp), 0);
    snprintf(args, sizeof args, "%s/merged/%s.part", g_dir, names[i]);
    assert_int_not_equal(stat(args, &sp), 0);
  }
  /* the draws differ between samples: not every sample collapses at the same displacement */
  char *t = slurp("j1", "samples.csv");
  double first = NAN;
  int differ = 0, rows = 0;
  for (char *line = strchr(t, '\n') + 1; (line = strchr(line, '\n')) != NULL && line[1];) {
    line++;
    double d;
    if (sscanf(line, "%*d,collapse,%*[^,],%lf", &d) == 1) {
      rows++;
      if (isnan(first)) first = d;
      differ += d != first;
    }
  }
  free(t);
  assert_int_equal(rows, 6);
  assert_true(differ > 0);
  struct stat sb;
  snprintf(args, sizeof args, "%s/j1/summary.h5", g_dir);
  assert_int_equal(stat(args, &sb), 0);
  snprintf(args, sizeof args, "%s/j1/fragility.png", g_dir); /* the charts: voussoir plot's */
  assert_int_not_equal(stat(args, &sb), 0);
}

/* A value of statistics.csv ("name,value,unit" rows); NaN when absent. */
static double stat_of(const char *text, const char *name) {
  char key[96];
  snprintf(key, sizeof key, "\n%s,", name);
  const char *p = strstr(text, key);
  return p != NULL ? strtod(p + strlen(key), NULL) : NAN;
}

static int cmp_d(const void *x, const void *y) {
  const double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* analysis.type = load: statistics.csv has the load factor's mean, CoV and 5 % quantile, here
 * recomputed from samples.csv's load_factor column (the sample CoV, n - 1; the type-7 quantile:
 * x[floor(h)] + frac(h) (x[floor(h) + 1] - x[floor(h)]), h = 0.05 (n - 1)); a support run's has
 * none of them. */
static void test_load_statistics(void **state) {
  (void)state;
  char args[1400];
  snprintf(args, sizeof args,
           "montecarlo %s --set analysis.type=load --set load.kind=point --set load.x_mm=133.05 "
           "--samples 7 --seed 5 -j 2 -q -o %s/lf", CASE, g_dir);
  assert_int_equal(run(args), 0);
  char *csv = slurp("lf", "samples.csv"), *st = slurp("lf", "statistics.csv");
  double x[16];
  int n = 0;
  for (char *line = strchr(csv, '\n'); line != NULL && n < 16; line = strchr(line + 1, '\n')) {
    if (line[1] == '\0' || line[1] == '#' || strncmp(line + 1, "sample", 6) == 0) continue;
    const char *last = line + 1;
    for (const char *c = line + 1; *c != '\0' && *c != '\n'; c++)
      if (*c == ',') last = c + 1;
    x[n++] = strtod(last, NULL);
  }
  assert_int_equal(n, 7);
  double mean = 0.0, ss = 0.0;
  for (int i = 0; i < n; i++) mean += x[i] / n;
  for (int i = 0; i < n; i++) ss += (x[i] - mean) * (x[i] - mean);
  const double cov = sqrt(ss / (n - 1)) / mean;
  qsort(x, (size_t)n, sizeof *x, cmp_d);
  const double h = 0.05 * (n - 1);
  const int i0 = (int)h;
  const double q05 = x[i0] + (h - i0) * (x[i0 + 1] - x[i0]);
  assert_true(mean > 1.0);
  assert_int_equal((int)stat_of(st, "load_factor_samples"), 7);
  assert_true(fabs(stat_of(st, "mean_load_factor") - mean) < 1e-6);
  assert_true(fabs(stat_of(st, "cov_load_factor") - cov) < 1e-6);
  assert_true(fabs(stat_of(st, "q05_load_factor") - q05) < 1e-6);
  free(csv);
  free(st);
  /* two shards merged: the same statistics (merge reads the samples' load factors) */
  for (int k = 1; k <= 2; k++) {
    snprintf(args, sizeof args,
             "montecarlo %s --set analysis.type=load --set load.kind=point --set load.x_mm=133.05 "
             "--samples 7 --seed 5 --shard %d/2 -q -o %s/lf%d", CASE, k, g_dir, k);
    assert_int_equal(run(args), 0);
  }
  snprintf(args, sizeof args, "merge %s/lf1 %s/lf2 -o %s/lfm", g_dir, g_dir, g_dir);
  assert_int_equal(run(args), 0);
  same_file("lf", "lfm", "statistics.csv");
  st = slurp("j1", "statistics.csv"); /* a support run's */
  assert_true(isnan(stat_of(st, "mean_load_factor")));
  free(st);
}

static void test_bad_input(void **state) {
  (void)state;
  char args[1024], path[512];
  struct stat sb;
  snprintf(args, sizeof args, "montecarlo %s --samples 0 -q -o %s/bad1", CASE, g_dir);
  assert_int_equal(run(args), 2);
  snprintf(args, sizeof args,
           "montecarlo %s --samples 3 --set imperfections.kn_cov=-1 -q -o %s/bad2", CASE, g_dir);
  assert_int_equal(run(args), 2);
  snprintf(args, sizeof args, "montecarlo %s --samples 3 --seed x -q -o %s/bad3", CASE, g_dir);
  assert_int_equal(run(args), 2);
  snprintf(args, sizeof args, "montecarlo %s --samples 3 --shard 3/2 -q -o %s/bad4", CASE, g_dir);
  assert_int_equal(run(args), 2);
  for (int i = 1; i <= 4; i++) {
    snprintf(path, sizeof path, "%s/bad%d", g_dir, i);
    assert_int_not_equal(stat(path, &sb), 0);
  }
  /* an output that is not a regular file (a FIFO where statistics.csv goes): refused before any
   * sample runs (opening it would block), left as it was */
  snprintf(path, sizeof path, "%s/fifo", g_dir);
  assert_int_equal(mkdir(path, 0755), 0);
  snprintf(path, sizeof path, "%s/fifo/statistics.csv", g_dir);
  assert_int_equal(mkfifo(path, 0644), 0);
  snprintf(args, sizeof args, "montecarlo %s --samples 3 -q -o %s/fifo", CASE, g_dir);
  assert_int_equal(run(args), 2);
  char *err = slurp(".", "err.txt");
  if (strstr(err, "voussoir montecarlo: -o ") == NULL || strstr(err, "statistics.csv") == NULL ||
      strstr(err, "FIFO") == NULL)
    fail_msg("stderr \"%s\": expected the FIFO named", err);
  free(err);
  assert_int_equal(lstat(path, &sb), 0);
  assert_true(S_ISFIFO(sb.st_mode));
  snprintf(path, sizeof path, "%s/fifo/samples.csv", g_dir);
  assert_int_not_equal(stat(path, &sb), 0); /* nothing written */
  /* so is a FIFO where the study's journal goes */
  snprintf(path, sizeof path, "%s/fifo/statistics.csv", g_dir);
  assert_int_equal(remove(path), 0);
  snprintf(path, sizeof path, "%s/fifo/montecarlo.journal", g_dir);
  assert_int_equal(mkfifo(path, 0644), 0);
  assert_int_equal(run(args), 2);
  err = slurp(".", "err.txt");
  if (strstr(err, "montecarlo.journal") == NULL || strstr(err, "FIFO") == NULL)
    fail_msg("stderr \"%s\": expected the FIFO named", err);
  free(err);
  snprintf(path, sizeof path, "%s/fifo/montecarlo.manifest", g_dir);
  assert_int_not_equal(stat(path, &sb), 0); /* nothing written */
}

/* DIR/samples.csv: a shard's table with the given rows after its two header lines (the case's
 * and the column names, as the README documents them). */
static void write_table(const char *dir, const char *columns, const char *rows) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", g_dir, dir);
  assert_int_equal(mkdir(path, 0755), 0);
  snprintf(path, sizeof path, "%s/%s/samples.csv", g_dir, dir);
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fprintf(f, "# voussoir montecarlo seed=1 radius_mm=300 embrace_deg=125 max_mm=300 alpha_deg=0 "
             "voussoirs=21\n%s%s",
          columns, rows);
  assert_int_equal(fclose(f), 0);
}

/* merge reads a shard's table column by column: a row that montecarlo could not have written
 * (found by tests/fuzz/fuzz_merge.c) is refused, exit 2, naming its line and column, and
 * nothing is written; so is a table without its column names (its first row was skipped as if
 * it were them) or without rows (a sanitizer report: qsort of a NULL array). */
static void test_merge_bad_rows(void **state) {
  (void)state;
  static const char COLUMNS[] =
      "sample,status,first_limit_mm,delta_u_mm,dz_u_mm,dx_u_mm,mode,pattern,A,B,C,D,E,error\n";
  static const char GOOD[] = "0,collapse,85.9,85.9,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n";
  static const char TWO[] = "0,collapse,85.9,85.9,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n"
                            "1,collapse,87.1,87.1,87.1,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n";
  /* a row of 1023 bytes and no newline, then a good row: one line, whose cause holds the second
   * row's commas (fgets into 1024 bytes would have read them as two rows) */
  char long_rows[2048];
  int k = snprintf(long_rows, sizeof long_rows, "%s1,failed,nan,nan,nan,nan,0,,,,,,,", GOOD);
  memset(long_rows + k, 'x', 1023 - (size_t)k + strlen(GOOD));
  snprintf(long_rows + strlen(GOOD) + 1023, sizeof long_rows - strlen(GOOD) - 1023, "%s",
           "2,collapse,85.9,85.9,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n");
  struct {
    const char *rows, *said;
  } bad[] = {
      {"0,collapsed,85.9,85.9,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n", ":3: status"},
      {"0,collapse,85.9,85.9mm,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n", ":3: delta_u_mm"},
      {"0,collapse,85.9,1e999,85.9,0,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n", ":3: delta_u_mm"},
      {"0,collapse,85.9,nan,nan,nan,1,E-I-E-E,4-I,12-E,22-E,1-E,,\n", ":3: delta_u_mm"},
      {"0,collapse,85.9,85.9,85.9,0,1,E-I-E-E,-3-I,12-E,22-E,1-E,,\n", ":3: A = "},
      {"0,collapse,85.9,85.9,85.9,0,1,E-I-E-E,4-X,12-E,22-E,1-E,,\n", ":3: A = "},
      {"0,collapse,85.9,85.9,85.9,0,1,E-I-E-E-I-E-I-E-I-E,4-I,12-E,22-E,1-E,,\n",
       ":3: pattern"},
      {"0,failed,nan,nan,nan,nan,0,,,,,,,cause, with a comma\n", ":3: error"},
      {NULL, ":4: error"}, /* long: below */
  };
  bad[sizeof bad / sizeof bad[0] - 1].rows = long_rows;
  char dir[32], args[1024], path[512];
  struct stat sb;
  write_table("rows_good", COLUMNS, GOOD); /* the control: the same table with a good row */
  snprintf(args, sizeof args, "merge %s/rows_good -o %s/rows_good_out", g_dir, g_dir);
  assert_int_equal(run(args), 0);
  const size_t nb = sizeof bad / sizeof bad[0];
  for (size_t i = 0; i < nb + 2; i++) { /* the bad rows, then no column names, then no rows */
    snprintf(dir, sizeof dir, "rows%zu", i);
    const int no_columns = i == nb, no_rows = i == nb + 1;
    write_table(dir, no_columns ? "" : COLUMNS,
                no_rows ? "" : no_columns ? TWO : bad[i].rows);
    snprintf(args, sizeof args, "merge %s/%s -o %s/%s_out", g_dir, dir, g_dir, dir);
    const int rc = run(args);
    char *err = slurp(".", "err.txt");
    const char *said = no_rows ? "no samples" : no_columns ? ":2: not the columns"
                                                           : bad[i].said;
    if (rc != 2 || strstr(err, said) == NULL)
      fail_msg("table %zu: exit %d, stderr \"%s\": expected 2 and \"%s\"", i, rc, err, said);
    free(err);
    snprintf(path, sizeof path, "%s/%s_out", g_dir, dir);
    assert_int_not_equal(stat(path, &sb), 0); /* nothing written */
  }
}

/* Stopped (SIGINT, raised by the pool itself once 3 samples are done: VS_FAULT_STOP_AFTER, no
 * timing): exit 130, no sample started after the stop, those under way finished, and the
 * summary of the samples done written, each row the sample's own (the same as in the run of
 * samples 0-5 above: a sample's draws depend on its number alone). */
static void test_interrupted(void **state) {
  (void)state;
  char args[1024];
  snprintf(args, sizeof args, "montecarlo %s --samples 40 --seed 11 -j 2 -q -o %s/int", CASE,
           g_dir);
  assert_int_equal(setenv("VS_FAULT_STOP_AFTER", "3", 1), 0);
  const int rc = run(args);
  assert_int_equal(unsetenv("VS_FAULT_STOP_AFTER"), 0);
  assert_int_equal(rc, 130);
  char *err = slurp(".", "err.txt");
  int k = -1, total = -1;
  const char *at = strstr(err, "interrupted: ");
  if (at == NULL || sscanf(at, "interrupted: %d of %d samples done", &k, &total) != 2)
    fail_msg("stderr \"%s\": expected \"interrupted: K of 40 samples done\"", err);
  free(err);
  /* the third sample done stops the pool; at most the other worker's sample was under way */
  assert_true(k >= 3 && k <= 4 && total == 40);
  char *t = slurp("int", "samples.csv"), *ref = slurp("j1", "samples.csv");
  int rows = 0;
  for (char *line = strchr(strchr(t, '\n') + 1, '\n') + 1; *line; rows++) {
    char *end = strchr(line, '\n');
    assert_non_null(end);
    *end = '\0';
    int sample = -1;
    assert_int_equal(sscanf(line, "%d,", &sample), 1);
    assert_true(sample >= 0 && sample < 6); /* among the first: dispatched in order */
    char want[64];
    snprintf(want, sizeof want, "\n%d,", sample);
    const char *r = strstr(ref, want);
    assert_non_null(r);
    if (strncmp(r + 1, line, strlen(line)) != 0 || r[1 + strlen(line)] != '\n')
      fail_msg("sample %d: \"%s\" differs from the uninterrupted run's row", sample, line);
    line = end + 1;
  }
  assert_int_equal(rows, k);
  free(t), free(ref);
  char *st = slurp("int", "statistics.csv");
  char want[32];
  snprintf(want, sizeof want, "samples,%d,", k);
  assert_non_null(strstr(st, want));
  free(st);
}

/* The size of dir/name in bytes (-1: missing). */
static long file_size(const char *dir, const char *name) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s/%s", g_dir, dir, name);
  struct stat sb;
  return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

/* Run "voussoir montecarlo CASE --samples 6 EXTRA" into g_dir/DIR: its exit status must be rc
 * and its standard error must say text (NULL: not checked). */
static void resume_run(const char *extra, const char *dir, int rc, const char *text) {
  char args[1024];
  snprintf(args, sizeof args, "montecarlo %s --samples 6 %s -o %s/%s", CASE, extra, g_dir, dir);
  assert_int_equal(run(args), rc);
  if (text == NULL) return;
  char *err = slurp(".", "err.txt");
  if (strstr(err, text) == NULL) fail_msg("stderr \"%s\": expected \"%s\"", err, text);
  free(err);
}

/* Killed (SIGKILL, raised by the study itself once 2 samples are journalled:
 * VS_FAULT_KILL_AFTER, no timing), with the journal's last row then torn as a kill in the middle
 * of its write would leave it: --resume keeps the whole row, runs the other 5 samples, and writes
 * the uninterrupted run's summary; a second --resume runs none. A --resume of another study, in
 * a directory without one, or from a journal of another layout is refused with exit 2; one whose
 * header was cut short is empty. */
static void test_resume(void **state) {
  (void)state;
  char args[1024];
  snprintf(args, sizeof args, "montecarlo %s --samples 6 --seed 11 -j 2 -q -o %s/res", CASE, g_dir);
  assert_int_equal(setenv("VS_FAULT_KILL_AFTER", "2", 1), 0);
  const int rc = run(args); /* not resume_run: the shell may report the kill either way */
  assert_int_equal(unsetenv("VS_FAULT_KILL_AFTER"), 0);
  assert_true(rc == 128 + SIGKILL || rc == -1); /* killed (as the shell reports it, or not) */
  assert_int_equal(file_size("res", "samples.csv"), -1); /* no summary yet */
  char *j = slurp("res", "montecarlo.journal");
  size_t row = 0;
  if (sscanf(j, "voussoir montecarlo journal 2 row %zu bytes", &row) != 1)
    fail_msg("journal header \"%.60s\"", j);
  const long head = (long)(strchr(j, '\n') + 1 - j);
  free(j);
  assert_int_equal(file_size("res", "montecarlo.journal"), head + 2 * (long)row);
  char path[512];
  snprintf(path, sizeof path, "%s/res/montecarlo.journal", g_dir);
  assert_int_equal(truncate(path, head + 2 * (long)row - 10), 0); /* the second row torn */
  for (int k = 0; k < 2; k++) {
    char want[64];
    snprintf(want, sizeof want, "resuming: %d of 6 samples already done", k == 0 ? 1 : 6);
    resume_run("--seed 11 -j 2 --resume", "res", 0, want);
    same_file("j1", "res", "samples.csv");
    same_file("j1", "res", "statistics.csv");
    assert_int_equal(file_size("res", "montecarlo.journal"), head + 6 * (long)row);
  }
  /* refused: another study, no study, another layout; the directory left as it was */
  resume_run("--seed 12 -q --resume", "res", 2, "montecarlo.manifest differs");
  resume_run("--seed 11 -q --resume", "nores", 2, NULL);
  assert_int_equal(file_size("nores", "."), -1);
  FILE *f = fopen(path, "r+b");
  assert_non_null(f);
  assert_int_equal(fputs("voussoir montecarlo journal 0", f) >= 0, 1);
  assert_int_equal(fclose(f), 0);
  resume_run("--seed 11 -q --resume", "res", 2, "was not written by this build");
  same_file("j1", "res", "samples.csv");
  /* a header cut short (a kill while it was written) is an empty journal: every sample runs */
  assert_int_equal(truncate(path, 10), 0);
  resume_run("--seed 11 -j 2 --resume", "res", 0, "resuming: 0 of 6 samples already done");
  same_file("j1", "res", "samples.csv");
  assert_int_equal(file_size("res", "montecarlo.journal"), head + 6 * (long)row);
}

/* --- the journal's rows: checksummed, every field checked before a sample counts as done --- */

/* g_dir/DIR/montecarlo.journal; *n its size, *head its header's length, *rows its rows (each a
 * vs_mc_sample and its checksum, checked). */
static unsigned char *load_journal(const char *dir, size_t *n, size_t *head, int *rows) {
  char *j = slurp(dir, "montecarlo.journal");
  *n = (size_t)file_size(dir, "montecarlo.journal");
  size_t stored = 0;
  if (sscanf(j, "voussoir montecarlo journal 2 row %zu bytes", &stored) != 1)
    fail_msg("journal header \"%.60s\"", j);
  assert_int_equal(stored, sizeof(vs_mc_sample) + 8);
  *head = (size_t)(strchr(j, '\n') + 1 - j);
  assert_int_equal((*n - *head) % stored, 0);
  *rows = (int)((*n - *head) / stored);
  const unsigned char *b = (const unsigned char *)j + *head;
  for (int i = 0; i < *rows; i++)
    assert_true(sum_holds(b + (size_t)i * stored, sizeof(vs_mc_sample)));
  return (unsigned char *)j;
}

/* A damage done to sample 1's journal row (sample 0's at hand), whether its checksum is then
 * made right again, and what stderr must say of it. */
typedef struct {
  void (*damage)(vs_mc_sample *r, const vs_mc_sample *first);
  int resum;
  const char *says;
} mc_damage;

static void dmg_pattern(vs_mc_sample *r, const vs_mc_sample *f) {
  (void)f;
  memset(r->pattern, 'E', sizeof r->pattern);
}
static void dmg_error(vs_mc_sample *r, const vs_mc_sample *f) { /* and the padding after it */
  (void)f;
  r->status = VS_MC_FAILED;
  memset(r->error, 'x', sizeof *r - offsetof(vs_mc_sample, error));
}
static void dmg_flip(vs_mc_sample *r, const vs_mc_sample *f) {
  (void)f;
  ((unsigned char *)&r->delta_u_mm)[2] ^= 0x04;
}
static void dmg_sample(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->sample = 99; }
static void dmg_status(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->status = 5; }
static void dmg_mode(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->mode = 7; }
static void dmg_joint(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->hinge_joint[0] = 999; }
static void dmg_side(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->hinge_side[1] = 'X'; }
static void dmg_inf(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->delta_u_mm = INFINITY; }
static void dmg_nan(vs_mc_sample *r, const vs_mc_sample *f) { (void)f; r->dz_u_mm = NAN; }
static void dmg_cause(vs_mc_sample *r, const vs_mc_sample *f) {
  (void)f;
  snprintf(r->error, sizeof r->error, "no memory");
}
static void dmg_twice(vs_mc_sample *r, const vs_mc_sample *f) { *r = *f; }

/* A study of 6 samples, then, for each damage, a copy of its directory with sample 1's journal
 * row damaged and --resume there: the row is named once on stderr with what is wrong, sample 1
 * (and it alone) runs again, its row is appended after the others' (the damaged one is gone),
 * and the summary is the uninterrupted study's (j1, samples 0-5). */
static void test_journal_rows(void **state) {
  (void)state;
  static const mc_damage damages[] = {
      {dmg_pattern, 1, "pattern is not NUL-terminated"},
      {dmg_error, 1, "error is not NUL-terminated"},
      {dmg_flip, 0, "checksum does not match"},
      {dmg_sample, 1, "sample 99 is not one of this study's (0..5, shard 1/1)"},
      {dmg_status, 1, "status 5"},
      {dmg_mode, 1, "mode 7"},
      {dmg_joint, 1, "hinge A: joint 999"},
      {dmg_side, 1, "hinge B:"},
      {dmg_inf, 1, "delta_u_mm inf"},
      {dmg_nan, 1, "dz_u_mm nan"},
      {dmg_cause, 1, "an error for a sample that did not fail"},
      {dmg_twice, 1, "a second row for sample 0"},
  };
  resume_run("--seed 11 -j 1 -q", "jr", 0, NULL);
  for (size_t k = 0; k < sizeof damages / sizeof damages[0]; k++) {
    const mc_damage *d = &damages[k];
    char dir[32], cmd[1024];
    snprintf(dir, sizeof dir, "jr%zu", k);
    snprintf(cmd, sizeof cmd, "rm -rf %s/%s && cp -a %s/jr %s/%s", g_dir, dir, g_dir, g_dir, dir);
    assert_int_equal(system(cmd), 0);
    size_t n = 0, head = 0;
    int rows = 0;
    unsigned char *j = load_journal(dir, &n, &head, &rows);
    const size_t stored = sizeof(vs_mc_sample) + 8;
    assert_int_equal(rows, 6);
    vs_mc_sample first, r;
    memcpy(&first, j + head, sizeof first);
    memcpy(&r, j + head + stored, sizeof r);
    assert_int_equal(first.sample, 0); /* -j 1: the rows in sample order */
    assert_int_equal(r.sample, 1);
    d->damage(&r, &first);
    memcpy(j + head + stored, &r, sizeof r);
    if (d->resum) set_sum(j + head + stored, sizeof r);
    char path[512];
    snprintf(path, sizeof path, "%s/%s/montecarlo.journal", g_dir, dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(j, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
    free(j);
    resume_run("--seed 11 -j 1 --resume", dir, 0, "resuming: 5 of 6 samples already done");
    char *e = slurp(".", "err.txt");
    const char *at = strstr(e, "montecarlo.journal: row 2: ");
    if (at == NULL || strstr(at + 1, "montecarlo.journal: row") != NULL ||
        strstr(at, d->says) == NULL)
      fail_msg("damage %zu: stderr \"%s\": expected row 2 named once with \"%s\"", k, e, d->says);
    free(e);
    j = load_journal(dir, &n, &head, &rows); /* the others kept, sample 1 run again and appended */
    assert_int_equal(rows, 6);
    static const int order[] = {0, 2, 3, 4, 5, 1};
    for (int i = 0; i < 6; i++) {
      memcpy(&r, j + head + (size_t)i * stored, sizeof r);
      assert_int_equal(r.sample, order[i]);
    }
    free(j);
    same_file("j1", dir, "samples.csv");
    same_file("j1", dir, "statistics.csv");
  }
}

/* --- a killed study's workers, and one study at a time in a directory --- */

/* CASE as arguments, for spawn(). */
#define CASE_ARGV VS_SOURCE_DIR "/runs/reference.ini", "--set", "arch.voussoirs=21", "--set", \
  "imperfections.kn_cov=0.3", "--set", "imperfections.face_mm=0.002", "--set",                  \
  "imperfections.angle_cov=0.02"

/* A study under way in g_dir/dir (process pid): ready once its journal holds `rows` rows and,
 * with worker, it has a worker (forked, not yet ended) that holds its sample (VS_FAULT_HOLD: the
 * file held exists, so that the worker is past setting up its parent-death signal). */
typedef struct {
  const char *dir;
  int rows, worker;
  pid_t pid;
  const char *held;
} study_state;

static int study_reached(const void *arg) {
  const study_state *s = arg;
  char head[96];
  const int hl = snprintf(head, sizeof head, "voussoir montecarlo journal 2 row %zu bytes\n",
                          sizeof(vs_mc_sample) + 8);
  pid_t w[4];
  const long size = hl + s->rows * (long)(sizeof(vs_mc_sample) + 8);
  return file_size(s->dir, "montecarlo.journal") >= size &&
         (!s->worker || (children_of(s->pid, w, 4) == 1 &&
                         (s->held == NULL || access(s->held, F_OK) == 0)));
}

/* SIGKILL to a study while sample 1 is under way (held: VS_FAULT_HOLD, sample 0 journalled),
 * then --resume at once. The worker is stopped (SIGSTOP) before the kill, as slow to react to
 * its parent's death as a loaded machine may make it: it must die with the study all the same
 * (montecarlo's workers had no parent-death signal and ran on with their samples after the
 * study was gone). This process is the killed study's subreaper: the orphaned worker becomes
 * its child, and it sees how it ended. The resume gives the uninterrupted study's summary. */
static void test_kill_resume(void **state) {
  (void)state;
  char dir[256], out[256], err[256];
  snprintf(dir, sizeof dir, "%s/kill", g_dir);
  snprintf(out, sizeof out, "%s/kill.out", g_dir);
  snprintf(err, sizeof err, "%s/kill.err", g_dir);
  char *argv[] = {VS_BINARY, "montecarlo", CASE_ARGV, "--samples", "6", "--seed", "11", "-j", "1",
                  "-q", "-o", dir, NULL};
  char *resume[] = {VS_BINARY, "montecarlo", CASE_ARGV, "--samples", "6", "--seed", "11", "-j",
                    "1", "-o", dir, "--resume", NULL};
  assert_int_equal(prctl(PR_SET_CHILD_SUBREAPER, 1), 0);
  char held[256];
  snprintf(held, sizeof held, "%s/kill.held", g_dir);
  assert_int_equal(setenv("VS_FAULT_HOLD", "1", 1), 0);
  assert_int_equal(setenv("VS_FAULT_HELD", held, 1), 0);
  const pid_t pid = spawn(argv, out, err);
  assert_int_equal(unsetenv("VS_FAULT_HOLD"), 0);
  assert_int_equal(unsetenv("VS_FAULT_HELD"), 0);
  const study_state reached = {"kill", 1, 1, pid, held};
  wait_until(study_reached, &reached, pid, "sample 0 journalled and sample 1 under way");
  pid_t worker[4];
  assert_int_equal(children_of(pid, worker, 4), 1);
  assert_int_equal(kill(worker[0], SIGSTOP), 0);
  assert_int_equal(kill(pid, SIGKILL), 0);
  int st = 0;
  assert_int_equal(waitpid(pid, &st, 0), pid);
  const int rc = exit_code(spawn(resume, out, err));
  kill(worker[0], SIGCONT); /* if it still lives, let it end as it would */
  pid_t p;
  while ((p = waitpid(-1, &st, 0)) > 0) /* the orphaned worker, now ours */
    if (p != worker[0] || !died_with_study(st))
      fail_msg("orphan %d ended %s %d, not killed with the study", (int)p,
               WIFSIGNALED(st) ? "by signal" : "with status",
               WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
  assert_int_equal(prctl(PR_SET_CHILD_SUBREAPER, 0), 0);
  assert_int_equal(rc, 0);
  char *e = slurp(".", "kill.err");
  assert_non_null(strstr(e, "resuming: 1 of 6 samples already done"));
  free(e);
  same_file("j1", "kill", "samples.csv");
  same_file("j1", "kill", "statistics.csv");
}

/* One study at a time in a directory: a montecarlo held with sample 1 under way (VS_FAULT_HOLD,
 * let go by a file: VS_FAULT_RELEASE) holds the directory's lock; a second montecarlo there,
 * fresh or --resume, and a sweep there are refused with exit 2 and the first's pid, before they
 * write anything (a second montecarlo used to empty the first's journal): the first's manifest
 * and journal are as they were, and once let go it finishes with the uninterrupted study's
 * summary. */
static void test_study_lock(void **state) {
  (void)state;
  char dir[256], out[256], err[256], release[256];
  snprintf(dir, sizeof dir, "%s/lock", g_dir);
  snprintf(out, sizeof out, "%s/lock.out", g_dir);
  snprintf(err, sizeof err, "%s/lock.err", g_dir);
  snprintf(release, sizeof release, "%s/lock.release", g_dir);
  char *argv[] = {VS_BINARY, "montecarlo", CASE_ARGV, "--samples", "6", "--seed", "11", "-j", "1",
                  "-q", "-o", dir, NULL};
  assert_int_equal(setenv("VS_FAULT_HOLD", "1", 1), 0);
  assert_int_equal(setenv("VS_FAULT_RELEASE", release, 1), 0);
  const pid_t first = spawn(argv, out, err);
  assert_int_equal(unsetenv("VS_FAULT_HOLD"), 0);
  assert_int_equal(unsetenv("VS_FAULT_RELEASE"), 0);
  const study_state reached = {"lock", 1, 0, first, NULL};
  wait_until(study_reached, &reached, first, "sample 0 journalled");
  char *manifest = slurp("lock", "montecarlo.manifest");
  char *journal = slurp("lock", "montecarlo.journal");
  const long jsize = file_size("lock", "montecarlo.journal");
  char *resume[] = {VS_BINARY, "montecarlo", CASE_ARGV, "--samples", "6", "--seed", "11", "-q",
                    "-o", dir, "--resume", NULL};
  char *sweep[] = {VS_BINARY, "sweep", VS_SOURCE_DIR "/runs/reference.ini", "--alpha", "0", "-q",
                   "-o", dir, NULL};
  char shard[256];
  snprintf(shard, sizeof shard, "%s/j1", g_dir);
  char *merge[] = {VS_BINARY, "merge", shard, "-o", dir, NULL};
  char **others[] = {argv, resume, sweep, merge};
  char pid[32], err2[256];
  snprintf(pid, sizeof pid, "pid %d", (int)first);
  snprintf(err2, sizeof err2, "%s/lock2.err", g_dir);
  for (int k = 0; k < 4; k++) {
    const int rc = exit_code(spawn(others[k], out, err2));
    char *e = slurp(".", "lock2.err");
    if (rc != 2 || strstr(e, pid) == NULL || strstr(e, "another study") == NULL)
      fail_msg("%s in the directory of a study under way: exit %d, stderr \"%s\" (expected 2 "
               "and %s)", others[k][1], rc, e, pid);
    free(e);
  }
  char *m2 = slurp("lock", "montecarlo.manifest"), *j2 = slurp("lock", "montecarlo.journal");
  assert_string_equal(m2, manifest);
  assert_int_equal(file_size("lock", "montecarlo.journal"), jsize);
  assert_memory_equal(j2, journal, (size_t)jsize);
  free(manifest), free(journal), free(m2), free(j2);
  FILE *f = fopen(release, "w"); /* let the first go on */
  assert_non_null(f);
  fclose(f);
  assert_int_equal(exit_code(first), 0);
  same_file("j1", "lock", "samples.csv");
  same_file("j1", "lock", "statistics.csv");
  assert_int_equal(file_size("lock", "study.lock"), -1); /* released: removed */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_merge_bad_rows),
      cmocka_unit_test(test_same_summary_any_process_count),
      cmocka_unit_test(test_load_statistics), /* after the first, whose j1 it reads */
      cmocka_unit_test(test_interrupted), /* after the run of samples 0-5, which it reads */
      cmocka_unit_test(test_resume),      /* so does this one */
      cmocka_unit_test(test_journal_rows), /* and this one */
      cmocka_unit_test(test_kill_resume),  /* and this one */
      cmocka_unit_test(test_study_lock),   /* and this one */
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
