/* Output safety, signals and crash consistency, tried as a hostile user would, with stand-ins in
 * a scratch directory (a FIFO, a copy of the case, symbolic links, a small tmpfs; never a real
 * device): refused targets exit 2 with one line and leave everything as it was; a second writer
 * of the same output is refused; a stop flag stops the solvers inside their callbacks; a run
 * killed at the final write never reads "completed" without its /events and /summary; a record
 * whose path became something else during the run is not renamed over it and stays whole in
 * its working file; a full disk gives one line with the OS reason and no false claim. */
#define _DEFAULT_SOURCE /* mkdtemp, mount */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <hdf5.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "record_status.h"
#include "voussoir/case.h"
#include "voussoir/output.h"
#include "voussoir/run.h"

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

static char g_dir[64];
static pid_t g_child = 0; /* a long run under way, killed by teardown if a test failed */

static int sh(const char *cmd) {
  int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

static const char *in_dir(const char *name) {
  static char buf[8][256];
  static int k = 0;
  k = (k + 1) % 8;
  snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
  return buf[k];
}

/* The whole file (a sidecar is megabytes), NUL-terminated; NULL when it cannot be read. */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  long n = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
  char *s = n >= 0 && fseek(f, 0, SEEK_SET) == 0 ? malloc((size_t)n + 1) : NULL;
  if (s != NULL && fread(s, 1, (size_t)n, f) != (size_t)n) {
    free(s);
    s = NULL;
  }
  if (s != NULL) s[n] = '\0';
  fclose(f);
  return s;
}

static int count_lines(const char *s) {
  int n = 0;
  for (; *s; s++) n += *s == '\n';
  return n;
}

/* Run `PREFIX voussoir run CASE -q ARGS` in g_dir; stderr into err.txt, stdout into out.txt. */
static int run_cli_with(const char *prefix, const char *case_path, const char *args) {
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "cd %s && %s %s run %s -q %s > out.txt 2> err.txt", g_dir, prefix,
           VS_BINARY, case_path, args);
  return sh(cmd);
}

static int run_cli(const char *case_path, const char *args) {
  return run_cli_with("", case_path, args);
}

/* Rows of a dataset read back whole (-1 when it does not read). */
static long read_rows(hid_t f, const char *name) {
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t ft = H5Dget_type(d), t = H5Tget_native_type(ft, H5T_DIR_ASCEND), sp = H5Dget_space(d);
  H5Tclose(ft);
  hsize_t dims[3] = {0, 0, 0};
  const int rank = H5Sget_simple_extent_dims(sp, dims, NULL);
  size_t bytes = H5Tget_size(t);
  for (int i = 0; i < rank; i++) bytes *= (size_t)dims[i];
  void *buf = malloc(bytes > 0 ? bytes : 1);
  const herr_t rc = H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  if (rc >= 0) H5Dvlen_reclaim(t, sp, H5P_DEFAULT, buf); /* the strings of the hinge table */
  free(buf);
  H5Sclose(sp);
  H5Tclose(t);
  H5Dclose(d);
  return rc < 0 ? -1 : (rank > 0 ? (long)dims[0] : 1);
}

/* ---------------------------------------------------------------------------------------------
 * Output targets */

/* FIFO, directory, symbolic links, the case file itself (other spellings, a hard link), an
 * output named twice: exit 2, one line naming the option and the path, nothing changed. */
static void test_refused_targets(void **s) {
  (void)s;
  char cmd[1024];
  snprintf(cmd, sizeof cmd,
           "cd %s && cp %s case.ini && mkfifo fifo y.xmf && mkdir dir && ln -s case.ini link && "
           "ln -s dir dlink && ln -s nowhere dangling && ln case.ini hard.ini",
           g_dir, REFERENCE);
  assert_int_equal(sh(cmd), 0);
  char *before = slurp(in_dir("case.ini"));
  assert_non_null(before);
  const struct {
    const char *args, *option, *culprit;
  } cases[] = {
      {"-o fifo", "-o", "fifo"},
      {"-o dir", "-o", "dir"},
      {"-o dir/", "-o", "dir/"},
      {"-o link", "-o", "link"},
      {"-o dlink", "-o", "dlink"},
      {"-o dangling", "-o", "dangling"},
      {"-o case.ini", "-o", "case.ini"},
      {"-o ./case.ini", "-o", "./case.ini"},
      {"-o hard.ini", "-o", "hard.ini"},
      {"-o nodir/x.h5", "-o", "nodir/x.h5"},
      {"-o x.h5 --csv fifo", "--csv", "fifo"},
      {"-o x.h5 --csv case.ini", "--csv", "case.ini"},
      {"-o x.h5 --csv link", "--csv", "link"},
      {"-o x.h5 --csv x.xmf", "--csv", "x.xmf"},
      {"-o x.h5 --csv x.h5", "-o", "x.h5"},
      {"-o y.h5", "-o", "y.xmf"}, /* the record's sidecar */
      {"-o x.h5 --snapshot-share 0", "--snapshot-share", "0"},
      {"-o x.h5 --snapshot-share 1.5", "--snapshot-share", "1.5"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    const int rc = run_cli("case.ini", cases[i].args);
    if (rc != 2) fail_msg("run %s: exit %d, expected 2", cases[i].args, rc);
    char *err = slurp(in_dir("err.txt"));
    assert_non_null(err);
    char want[128];
    snprintf(want, sizeof want, "voussoir: %s %s: ", cases[i].option, cases[i].culprit);
    if (strncmp(err, want, strlen(want)) != 0 || count_lines(err) != 1)
      fail_msg("run %s: stderr \"%s\", expected one line starting \"%s\"", cases[i].args, err,
               want);
    free(err);
  }
  /* everything as it was: the case's bytes, the FIFO, the links; no file created */
  char *after = slurp(in_dir("case.ini"));
  assert_string_equal(before, after);
  free(before);
  free(after);
  struct stat st;
  assert_int_equal(lstat(in_dir("fifo"), &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  assert_int_equal(lstat(in_dir("y.xmf"), &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  assert_int_equal(lstat(in_dir("link"), &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  assert_int_equal(lstat(in_dir("dangling"), &st), 0);
  assert_true(S_ISLNK(st.st_mode));
  const char *absent[] = {"x.h5", "x.xmf", "y.h5", "x.h5.part", "x.h5.lock", "fifo.part", "fifo.lock",
                          "case.ini.part", "case.ini.lock", "nowhere"};
  for (size_t i = 0; i < sizeof absent / sizeof absent[0]; i++)
    if (access(in_dir(absent[i]), F_OK) == 0) fail_msg("%s was created", absent[i]);
}

/* A --csv path that cannot be created: exit 2 before the record exists (it was left "running"
 * with 0 rows, exit 1). */
static void test_bad_csv_no_record(void **s) {
  (void)s;
  assert_int_equal(run_cli(REFERENCE, "-o rec.h5 --csv nodir/h.csv"), 2);
  char *err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "--csv nodir/h.csv: "));
  assert_int_equal(count_lines(err), 1);
  free(err);
  assert_int_not_equal(access(in_dir("rec.h5"), F_OK), 0);
  assert_int_not_equal(access(in_dir("rec.h5.part"), F_OK), 0);
}

/* Start a long run (880 voussoirs) writing -o NAME and --csv NAME.csv in g_dir; returns once it
 * has recorded a first equilibrium (a data row in its CSV): an observable state, no sleep. */
static pid_t start_long_run(const char *name) {
  char h5[256], csv[256];
  snprintf(h5, sizeof h5, "%s/%s", g_dir, name);
  snprintf(csv, sizeof csv, "%s/%s.csv", g_dir, name);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    if (freopen("/dev/null", "w", stdout) == NULL || freopen("/dev/null", "w", stderr) == NULL)
      _exit(126);
    execl(VS_BINARY, VS_BINARY, "run", REFERENCE, "-q", "--set", "arch.voussoirs=880", "-o", h5,
          "--csv", csv, (char *)NULL);
    _exit(127);
  }
  g_child = pid;
  for (int i = 0;; i++) {
    char *text = slurp(csv);
    const int rows = text != NULL ? count_lines(text) : 0;
    free(text);
    if (rows >= 2) break;
    int st;
    if (waitpid(pid, &st, WNOHANG) == pid) fail_msg("the long run ended before its first row");
    if (i > 600 * 100) fail_msg("no first row after 600 s");
    struct timespec ts = {0, 10 * 1000 * 1000};
    nanosleep(&ts, NULL); /* polling interval only: the condition is the row */
  }
  return pid;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Two runs with the same -o (or --csv): the second is refused, the first's record is kept; then
 * SIGTERM stops the first promptly (exit 130, status "failed: interrupted"). */
static void test_second_writer_refused(void **s) {
  (void)s;
  pid_t pid = start_long_run("busy.h5");
  assert_int_equal(run_cli(REFERENCE, "-o busy.h5"), 2);
  char *err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir: -o busy.h5: being written by another process"));
  assert_int_equal(count_lines(err), 1);
  free(err);
  assert_int_equal(run_cli(REFERENCE, "-o other.h5 --csv busy.h5.csv"), 2);
  err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir: --csv busy.h5.csv: being written by another process"));
  free(err);
  assert_int_not_equal(access(in_dir("other.h5"), F_OK), 0);
  const double t0 = now_s();
  kill(pid, SIGTERM);
  int st = 0;
  assert_int_equal(waitpid(pid, &st, 0), pid);
  g_child = 0;
  const double dt = now_s() - t0;
  assert_true(WIFEXITED(st));
  assert_int_equal(WEXITSTATUS(st), 130);
  printf("  stopped %.3f s after SIGTERM\n", dt);
  assert_true(dt < 10.0); /* within a second on an idle machine; bounded loosely under load */
  char status[256];
  vs_test_record_status(in_dir("busy.h5"), status, sizeof status);
  assert_string_equal(status, "failed: interrupted");
  assert_int_not_equal(access(in_dir("busy.h5.lock"), F_OK), 0); /* removed at exit */
  /* the lock is free again */
  assert_int_equal(run_cli(REFERENCE, "--first-limit -o busy.h5"), 0);
}

/* ---------------------------------------------------------------------------------------------
 * Solver loops */

/* A density of 1e-300 kg/m^3 made the residual NaN and KINSOL's line search looped for ever.
 * The case range now refuses it (exit 2, naming the key); and should a non-finite residual
 * reach the solver through the library (which does not re-validate), the run ends with that
 * cause instead of looping. */
static void test_nonfinite_residual_ends(void **s) {
  (void)s;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd %s && timeout -s KILL 60 %s run %s -q --no-record --set "
           "arch.density_kg_m3=1e-300 > out.txt 2> err.txt", g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 2);
  char *err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "density_kg_m3"));
  free(err);

  vs_case c;
  vs_error e;
  vs_run *run = NULL;
  vs_error_clear(&e);
  vs_case_defaults(&c);
  assert_int_equal(vs_case_read(&c, REFERENCE, NULL, &e), VS_OK);
  c.density_kg_m3 = 1e-300; /* past the validation, straight to the solver */
  assert_int_equal(vs_run_create(&c, &run, &e), VS_OK);
  assert_int_not_equal(vs_run_execute(run, NULL, NULL, NULL, &e), VS_OK);
  assert_non_null(strstr(e.msg, "not finite"));
  vs_run_destroy(&run);
}

typedef struct {
  volatile sig_atomic_t stop;
  int raise_at_phase; /* raise the flag at the first sample of this phase (-1: never) */
  int raise_after;    /* ... after this many samples of it */
  long samples, of_phase, after_raise;
} stopper;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *smp) {
  (void)run;
  stopper *sp = user;
  sp->samples++;
  if (sp->stop) sp->after_raise++;
  if ((int)smp->phase == sp->raise_at_phase && sp->of_phase++ == sp->raise_after) sp->stop = 1;
  return 0; /* the callback never asks to stop: the flag alone must */
}

/* The stop flag reaches the solvers: raised before the run (KINSOL's first residual), at an
 * equilibrium of the quasi-static path, at a sample of the dynamic phase (IDA's residual): the
 * run returns VS_ERR_INTERRUPTED and records nothing after it. */
static void test_stop_flag_in_solvers(void **s) {
  (void)s;
  const struct {
    int phase, after;
  } when[] = {{-2, 0}, {VS_PHASE_QUASISTATIC, 2}, {VS_PHASE_DYNAMIC, 0}};
  for (size_t k = 0; k < sizeof when / sizeof when[0]; k++) {
    vs_case c;
    vs_error err;
    vs_error_clear(&err);
    vs_case_defaults(&c);
    assert_int_equal(vs_case_read(&c, REFERENCE, NULL, &err), VS_OK);
    vs_run *run = NULL;
    assert_int_equal(vs_run_create(&c, &run, &err), VS_OK);
    stopper sp = {.stop = when[k].phase == -2, .raise_at_phase = when[k].phase,
                  .raise_after = when[k].after};
    vs_run_set_stop(run, &sp.stop);
    const vs_status st = vs_run_execute(run, on_sample, NULL, &sp, &err);
    if (st != VS_ERR_INTERRUPTED)
      fail_msg("case %zu: status %s (%s), expected interrupted", k, vs_strerror(st), err.msg);
    assert_int_equal(sp.after_raise, 0);
    if (when[k].phase == -2) assert_int_equal(sp.samples, 0);
    else assert_true(sp.samples > when[k].after);
    vs_run_destroy(&run);
  }
}

/* ---------------------------------------------------------------------------------------------
 * Crash consistency */

/* Killed (SIGKILL) at the final write, before the status (everything else flushed and, with a
 * snapshot after every flush, in the record) and after it (the working file closed and renamed
 * over the record): a record whose status reads "completed" has readable /events and /summary;
 * one killed before reads "running". */
static void test_killed_at_final_write(void **s) {
  (void)s;
  const char *points[] = {"before-status", "after-status"};
  for (int i = 0; i < 2; i++) {
    char cmd[1024], status[256];
    snprintf(cmd, sizeof cmd, /* the shell's "Killed" goes to /dev/null too */
             "cd %s && exec 2> /dev/null && VS_FAULT_KILL=%s %s run %s -q --set dynamic.fall_s=0 "
             "--snapshot-share 1 -o k%d.h5 > /dev/null", /* the fall (most of a run) does not matter here */
             g_dir, points[i], VS_BINARY, REFERENCE, i);
    assert_int_equal(sh(cmd), 128 + SIGKILL); /* the hook fired */
    char path[256];
    snprintf(path, sizeof path, "%s/k%d.h5", g_dir, i);
    vs_test_record_status(path, status, sizeof status);
    assert_string_equal(status, i == 0 ? "running" : "completed");
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    assert_true(read_rows(f, "/events") > 3);
    assert_true(read_rows(f, "/summary/hinges") >= 4); /* the collapse's four hinges at least */
    assert_true(read_rows(f, "/summary/limit_points") >= 1);
    assert_true(read_rows(f, "/summary/delta_final") == 1);
    H5Fclose(f);
  }
}

/* A record never sits beside a sidecar that is not its own. A run of another arch (21
 * voussoirs) leaves sc.h5 and sc.xmf; a run of the reference arch (55) over them is killed
 * (SIGKILL) before its status (its record at sc.h5, "running") and after it (the record in place,
 * "completed"), and the sidecar at sc.xmf, if any, must be the one rebuilt from the record at
 * sc.h5, byte for byte. Then the same run not killed: its sidecar is there, and its record's. */
static void test_sidecar_is_its_records(void **s) {
  (void)s;
  const char *points[] = {"before-status", "after-status", NULL};
  for (int i = 0; i < 3; i++) {
    char cmd[1024], h5[256], xmf[256];
    snprintf(h5, sizeof h5, "%s/sc%d.h5", g_dir, i);
    snprintf(xmf, sizeof xmf, "%s/sc%d.xmf", g_dir, i);
    snprintf(cmd, sizeof cmd, "cd %s && %s run %s -q --set arch.voussoirs=21 --first-limit -o %s "
             "> /dev/null", g_dir, VS_BINARY, REFERENCE, h5);
    assert_int_equal(sh(cmd), 0);
    char *first = slurp(xmf);
    assert_non_null(first);
    snprintf(cmd, sizeof cmd, /* the shell's "Killed" goes to /dev/null too */
             "cd %s && exec 2> /dev/null && %s%s %s run %s -q --set dynamic.fall_s=0 "
             "--snapshot-share 1 -o %s > /dev/null", g_dir,
             points[i] != NULL ? "VS_FAULT_KILL=" : "", points[i] != NULL ? points[i] : "",
             VS_BINARY, REFERENCE, h5);
    assert_int_equal(sh(cmd), points[i] != NULL ? 128 + SIGKILL : 0);
    char status[256];
    vs_test_record_status(h5, status, sizeof status);
    assert_string_equal(status, i == 0 ? "running" : "completed");
    char *side = slurp(xmf);
    if (side != NULL || points[i] == NULL) {
      vs_error err;
      if (vs_output_write_xdmf(h5, 0, &err) != VS_OK) fail_msg("%s", err.msg); /* over sc.xmf */
      char *own = slurp(xmf);
      if (side == NULL || own == NULL || strcmp(side, own) != 0)
        fail_msg("%s: sc%d.xmf is %s, not the sidecar of the record at sc%d.h5",
                 points[i] != NULL ? points[i] : "not killed", i,
                 side == NULL ? "missing" : strcmp(side, first) == 0 ? "the first run's" : "other",
                 i);
      free(own);
    }
    free(side);
    free(first);
  }
}

/* `plot -o DIR`: a regular file as DIR, or a FIFO where a picture would go, is refused (exit 2)
 * before anything is drawn, and left as it was. Uses the completed record of the test above. */
static void test_plot_dir_refused(void **s) {
  (void)s;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd %s && touch plainfile && mkdir pics && mkfifo pics/arch_end.png && "
           "%s plot k1.h5 -o plainfile > out.txt 2> err.txt", g_dir, VS_BINARY);
  assert_int_equal(sh(cmd), 2);
  char *err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir plot: -o plainfile: exists and is a regular file"));
  free(err);
  snprintf(cmd, sizeof cmd, "cd %s && %s plot k1.h5 -o pics > out.txt 2> err.txt", g_dir,
           VS_BINARY);
  assert_int_equal(sh(cmd), 2);
  err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir plot: -o pics/arch_end.png: exists and is a FIFO"));
  free(err);
  struct stat st;
  assert_int_equal(lstat(in_dir("pics/arch_end.png"), &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  assert_int_not_equal(access(in_dir("pics/arch_reference.png"), F_OK), 0); /* nothing drawn */
}

/* Something else put at the record's path, or its sidecar's, during the run (a FIFO, made by
 * the hook VS_FAULT_FIFO where the record is first put in place, as another process could after
 * the checks at the start): nothing is renamed over it; the run goes on and ends with exit 1 and
 * one line saying where the record is (the working file, whole: the run's status, its events and
 * summary), or that the sidecar was not written (the record in place, whole). */
static void test_target_replaced_during_run(void **s) {
  (void)s;
  const char *names[] = {"t.h5", "u.xmf"};
  for (int i = 0; i < 2; i++) {
    char prefix[64];
    snprintf(prefix, sizeof prefix, "VS_FAULT_FIFO=%s", names[i]);
    const int rc = run_cli_with(prefix, REFERENCE, i == 0 ? "-o t.h5 --set dynamic.fall_s=0"
                                                          : "-o u.h5 --set dynamic.fall_s=0");
    char *err = slurp(in_dir("err.txt"));
    assert_non_null(err);
    const char *want = i == 0 ? "voussoir: run failed: t.h5: became something other than a "
                                "regular file during the run; not replaced: the record is in "
                                "t.h5.part\n"
                              : "voussoir: run failed: output: u.xmf: became something other "
                                "than a regular file; not replaced\n";
    if (rc != 1 || strcmp(err, want) != 0)
      fail_msg("%s: exit %d, stderr \"%s\"; expected 1, \"%s\"", names[i], rc, err, want);
    free(err);
    struct stat st;
    assert_int_equal(lstat(in_dir(names[i]), &st), 0);
    assert_true(S_ISFIFO(st.st_mode)); /* left as it was */
    const char *record = in_dir(i == 0 ? "t.h5.part" : "u.h5");
    char status[256];
    vs_test_record_status(record, status, sizeof status);
    assert_string_equal(status, "completed");
    hid_t f = H5Fopen(record, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    assert_true(read_rows(f, "/events") > 3);
    assert_true(read_rows(f, "/summary/hinges") >= 4);
    H5Fclose(f);
  }
  const char *absent[] = {"t.xmf", "t.h5.snap", "t.h5.lock", "u.h5.part", "u.h5.lock"};
  for (size_t i = 0; i < sizeof absent / sizeof absent[0]; i++)
    if (access(in_dir(absent[i]), F_OK) == 0) fail_msg("%s was left", absent[i]);
}

/* `sweep -o DIR`: a regular file as DIR, or a FIFO as its summary.csv or summary.h5: exit 2, no
 * run started. */
static void test_sweep_dir_refused(void **s) {
  (void)s;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cd %s && mkdir sw && mkfifo sw/summary.csv && timeout -s KILL 60 "
           "%s sweep %s --alpha 0 --kn 3 -q -o sw > out.txt 2> err.txt", g_dir, VS_BINARY,
           REFERENCE);
  assert_int_equal(sh(cmd), 2);
  char *err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir sweep: -o sw/summary.csv: exists and is a FIFO"));
  free(err);
  struct stat st;
  assert_int_equal(lstat(in_dir("sw/summary.csv"), &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  assert_int_not_equal(access(in_dir("sw/run_0000.h5"), F_OK), 0);
  snprintf(cmd, sizeof cmd, "cd %s && touch swfile && %s sweep %s --alpha 0 --kn 3 -q -o swfile "
           "> out.txt 2> err.txt", g_dir, VS_BINARY, REFERENCE);
  assert_int_equal(sh(cmd), 2);
  /* a FIFO as its summary.h5, the table written at the end */
  snprintf(cmd, sizeof cmd, "cd %s && mkdir sw2 && mkfifo sw2/summary.h5 && timeout -s KILL 60 "
           "%s sweep %s --alpha 0 --kn 3 -q -o sw2 > out.txt 2> err.txt", g_dir, VS_BINARY,
           REFERENCE);
  assert_int_equal(sh(cmd), 2);
  err = slurp(in_dir("err.txt"));
  assert_non_null(strstr(err, "voussoir sweep: -o sw2/summary.h5: exists and is a FIFO"));
  free(err);
  assert_int_equal(lstat(in_dir("sw2/summary.h5"), &st), 0);
  assert_true(S_ISFIFO(st.st_mode));
  assert_int_not_equal(access(in_dir("sw2/run_0000.h5"), F_OK), 0);
}

/* ---------------------------------------------------------------------------------------------
 * Full disk */

/* The failure of a full disk as the user sees it: exit 1 (not a crash), exactly one line on
 * stderr naming the record and the OS reason, no "record ..." claim on stdout, and no .part or
 * .lock left. */
static void check_full(const char *prefix, const char *dir, const char *reason) {
  char args[512];
  snprintf(args, sizeof args, "-o %s/x.h5 --csv %s/x.csv", dir, dir);
  assert_int_equal(run_cli_with(prefix, REFERENCE, args), 1);
  char *err = slurp(in_dir("err.txt")), *out = slurp(in_dir("out.txt"));
  char want[300];
  snprintf(want, sizeof want, "%s/x.h5", dir);
  if (count_lines(err) != 1 || strstr(err, want) == NULL || strstr(err, reason) == NULL ||
      strstr(err, "HDF5") != NULL)
    fail_msg("stderr \"%s\": expected one line naming %s and \"%s\"", err, want, reason);
  assert_null(strstr(out, "record "));
  assert_null(strstr(out, ".xmf"));
  free(err);
  free(out);
  char p[300];
  snprintf(p, sizeof p, "%s/x.h5.part", dir);
  assert_int_not_equal(access(p, F_OK), 0);
  snprintf(p, sizeof p, "%s/x.h5.lock", dir);
  assert_int_not_equal(access(p, F_OK), 0);
}

static void test_full_disk(void **s) {
  (void)s;
  /* fails creating, at the layout, during the run (at 200k the CSV fills the disk first since
   * the record gained /observables/joint_crack) */
  const char *sizes[] = {"8k", "48k", "250k"};
  char dir[256];
  snprintf(dir, sizeof dir, "%s/small", g_dir);
  assert_int_equal(mkdir(dir, 0755), 0);
  for (int i = 0; i < 3; i++) {
    char opts[32];
    snprintf(opts, sizeof opts, "size=%s", sizes[i]);
    if (mount("tmpfs", dir, "tmpfs", 0, opts) != 0) {
      printf("  skipped: cannot mount a small tmpfs (%s): needs root\n", strerror(errno));
      skip();
    }
    check_full("", dir, "No space left on device");
    umount(dir);
  }
}

/* The same through a file size limit (no privilege needed): SIGXFSZ is ignored, EFBIG reported. */
static void test_file_size_limit(void **s) {
  (void)s;
  char sub[256];
  snprintf(sub, sizeof sub, "%s/lim", g_dir);
  assert_int_equal(mkdir(sub, 0755), 0);
  check_full("ulimit -f 300 &&", sub, "File too large");
  /* its JSON: the run failed for the record's reason (the record's callback stopped the run,
   * but that is the record's failure, not a run stopped by its caller) */
  char args[512];
  snprintf(args, sizeof args, "-o %s/j.h5 --json", sub);
  assert_int_equal(run_cli_with("ulimit -f 300 &&", REFERENCE, args), 1);
  char *out = slurp(in_dir("out.txt"));
  if (strstr(out, "\"status\":\"failed\",\"error\":\"output: ") == NULL ||
      strstr(out, "File too large\"") == NULL)
    fail_msg("the JSON of a run whose record failed: %.300s", out);
  free(out);
}

static int setup(void **s) {
  (void)s;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_safety_XXXXXX");
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

static int teardown(void **s) {
  (void)s;
  if (g_child > 0) {
    kill(g_child, SIGKILL);
    waitpid(g_child, NULL, 0);
  }
  char cmd[256];
  snprintf(cmd, sizeof cmd, "umount '%s/small' 2>/dev/null; rm -rf '%s'", g_dir, g_dir);
  return sh(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_refused_targets),
      cmocka_unit_test(test_bad_csv_no_record),
      cmocka_unit_test(test_second_writer_refused),
      cmocka_unit_test(test_nonfinite_residual_ends),
      cmocka_unit_test(test_stop_flag_in_solvers),
      cmocka_unit_test(test_killed_at_final_write),
      cmocka_unit_test(test_sidecar_is_its_records),
      cmocka_unit_test(test_plot_dir_refused),
      cmocka_unit_test(test_target_replaced_during_run),
      cmocka_unit_test(test_sweep_dir_refused),
      cmocka_unit_test(test_full_disk),
      cmocka_unit_test(test_file_size_limit),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
