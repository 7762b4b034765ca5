/* Symbolic links planted at every name a command writes (its outputs, their working files
 * "<name>.part" / ".tmp" / ".snap", the lock files), each in a directory of its own, pointing at
 * a file of the test's outside the output directory: before the command starts, and (through the
 * hook VS_FAULT_LINK) at the moment the file is about to be created, as another process could
 * after the command's checks. Nothing is ever written through a link: the file it points to
 * keeps its bytes, the link stays, and the command names the path it refused (exit 2 when the
 * link was there before it started; a failure naming it, on stderr or for a sweep's run in its
 * table, when the link appeared meanwhile). An HDF5 file's link made meanwhile is not even
 * opened (inotify), nor one that replaces a working file later in the run (VS_FAULT_RELINK: as
 * it is opened again or renamed over its output). */
#define _DEFAULT_SOURCE /* mkdtemp, symlink */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"
/* a cheap case: 21 voussoirs */
#define CASE REFERENCE " --set arch.voussoirs=21"
#define MC_CASE CASE " --set imperfections.kn_cov=0.3 --set imperfections.face_mm=0.002"

/* What the file a link points to holds; it must hold it still after the command. */
static const char PRECIOUS[] = "bytes that no command of voussoir may overwrite\n";

static char g_dir[64];

static int sh(const char *cmd) {
  const int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  static char text[1 << 16];
  const size_t n = fread(text, 1, sizeof text - 1, f);
  text[n] = '\0';
  fclose(f);
  return strdup(text);
}

/* A command and the names it writes, relative to the directory it runs in. */
typedef struct {
  const char *label;       /* for messages */
  const char *args;        /* after the program's name; %s: the test's scratch directory */
  const char *const *pre;  /* links planted before it starts: each refused, exit 2 */
  const char *const *live; /* files it creates: a link put there just before, refused */
} command;

static const char *const run_pre[] = {"r.h5", "r.h5.part", "r.h5.snap", "r.h5.lock", "r.xmf",
                                      "r.xmf.tmp", "r.csv", "r.csv.lock", NULL};
static const char *const run_live[] = {"r.h5.part", "r.h5.snap", "r.xmf.tmp", NULL};

static const char *const sweep_pre[] = {
    "sw/sweep.manifest",    "sw/sweep.journal",      "sw/summary.csv",     "sw/summary.csv.tmp",
    "sw/summary.h5",        "sw/summary.h5.part",    "sw/run_0001.h5",     "sw/run_0001.h5.part",
    "sw/run_0001.h5.snap",  "sw/run_0001.h5.lock",   "sw/run_0001.xmf",    "sw/run_0001.xmf.tmp",
    "sw/run_0001.json",     "sw/run_0001.json.part", NULL};
static const char *const sweep_live[] = {
    "sw/sweep.manifest",   "sw/sweep.journal",    "sw/summary.csv",       "sw/summary.csv.tmp",
    "sw/summary.h5.part",  "sw/run_0001.h5.part", "sw/run_0001.h5.snap",  "sw/run_0001.xmf.tmp",
    "sw/run_0001.json.part", NULL};

#define MC_SUMMARY(d)                                                                            \
  d "/samples.csv", d "/samples.csv.part", d "/statistics.csv", d "/statistics.csv.part",        \
      d "/summary.h5", d "/summary.h5.part"
#define MC_SUMMARY_PARTS(d) d "/samples.csv.part", d "/statistics.csv.part", d "/summary.h5.part"

static const char *const mc_pre[] = {"mc/montecarlo.manifest", "mc/montecarlo.manifest.part",
                                     "mc/montecarlo.journal", MC_SUMMARY("mc"), NULL};
static const char *const mc_live[] = {"mc/montecarlo.manifest.part", "mc/montecarlo.journal",
                                      MC_SUMMARY_PARTS("mc"), NULL};
static const char *const merge_pre[] = {MC_SUMMARY("mg"), NULL};
static const char *const merge_live[] = {MC_SUMMARY_PARTS("mg"), NULL};

static const char *const plot_pre[] = {
    "pics/arch_reference.png", "pics/arch_hinge_A.png", "pics/arch_hinge_B.png",
    "pics/arch_hinge_C.png",   "pics/arch_hinge_D.png", "pics/arch_limit_1.png",
    "pics/arch_end.png",       "pics/curves.png",       "pics/curves.pdf",
    "pics/hinges.svg",         "pics/plots.json",       NULL};
/* the first picture drawn, the last, and the listing (the charts, matplotlib's, are refused
 * when planted before: checked with the arch pictures' names before anything is drawn) */
static const char *const plot_live[] = {"pics/arch_reference.png", "pics/arch_end.png",
                                        "pics/plots.json", NULL};
static const char *const plot_sweep_pre[] = {"pics/domain.png", "pics/sensitivity.pdf",
                                             "pics/plots.json", NULL};
static const char *const plot_sweep_live[] = {NULL};

static const command commands[] = {
    {"run", "run " CASE " --first-limit -q -o r.h5 --csv r.csv", run_pre, run_live},
    {"sweep", "sweep " CASE " --alpha 0 --first-limit -q -o sw", sweep_pre, sweep_live},
    {"montecarlo", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc", mc_pre, mc_live},
    {"merge", "merge %s/s1 %s/s2 -o mg", merge_pre, merge_live},
    {"plot", "plot %s/base.h5 -o pics", plot_pre, plot_live},
    {"plot (sweep)", "plot %s/swbase/summary.h5 -o pics", plot_sweep_pre, plot_sweep_live},
};

/* Run c in a fresh directory with a link at name to a file of the test's: planted before the
 * command (live = 0), or by the hook just before the command creates name (live = 1). 1, with
 * the fault printed, unless the file linked to keeps its bytes, the link stays, and the command
 * refused it (exit 2 when planted before; any failure when made meanwhile) naming it on stderr. */
static int try_link(const command *c, const char *name, int live, int k) {
  char dir[256], target[300], link[600], cmd[3000], args[1024], env[1000] = "";
  snprintf(dir, sizeof dir, "%s/%s%d", g_dir, live ? "live" : "pre", k);
  snprintf(target, sizeof target, "%s/precious", dir);
  snprintf(link, sizeof link, "%s/%s", dir, name);
  snprintf(cmd, sizeof cmd, "mkdir -p %s/sw %s/mc %s/mg %s/pics && printf '%%s' '%s' > %s", dir,
           dir, dir, dir, PRECIOUS, target);
  assert_int_equal(sh(cmd), 0);
  if (live) snprintf(env, sizeof env, "VS_FAULT_LINK='%s=%s'", name, target);
  else assert_int_equal(symlink(target, link), 0);
  snprintf(args, sizeof args, c->args, g_dir, g_dir);
  snprintf(cmd, sizeof cmd, "cd %s && %s timeout -s KILL 120 %s %s > out.txt 2> err.txt", dir,
           env, VS_BINARY, args);
  const int rc = sh(cmd);
  /* where a refusal is said: stderr, or the table of a sweep for a run's files */
  snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
  char *err = slurp(cmd), *after = slurp(target);
  snprintf(cmd, sizeof cmd, "%s/sw/summary.csv", dir);
  char *table = strncmp(name, "sw/run_", 7) == 0 ? slurp(cmd) : NULL;
  const char *base = strrchr(name, '/') != NULL ? strrchr(name, '/') + 1 : name;
  const char *how = live ? "made as it was created" : "planted before";
  struct stat st;
  int bad = 1;
  if (after == NULL || strcmp(after, PRECIOUS) != 0)
    printf("  %s, link at %s %s: the file it points to was overwritten (exit %d)\n", c->label,
           name, how, rc);
  else if (lstat(link, &st) != 0 || !S_ISLNK(st.st_mode))
    printf("  %s, link at %s %s: no longer a link (exit %d)\n", c->label, name, how, rc);
  else if ((live ? rc == 0 : rc != 2) || err == NULL ||
           (strstr(err, base) == NULL && (table == NULL || strstr(table, base) == NULL)))
    printf("  %s, link at %s %s: exit %d, stderr \"%s\": expected %s and a message naming %s\n",
           c->label, name, how, rc, err != NULL ? err : "", live ? "a failure" : "exit 2", base);
  else
    bad = 0;
  free(table);
  free(err);
  free(after);
  return bad;
}

/* A link at each name of every command, planted before (live = 0) or as the file is created;
 * fails after listing those not refused. */
static void try_all(int live) {
  int k = 0, bad = 0;
  for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
    for (const char *const *n = live ? commands[i].live : commands[i].pre; *n != NULL; n++)
      bad += try_link(&commands[i], *n, live, k++);
  if (bad > 0)
    fail_msg("%d of %d links %s not refused (above)", bad, k,
             live ? "made as the file was created" : "planted before");
}

/* A hard link to a file of the test's planted at a lock file's name (a run's FILE.lock, a
 * study's DIR/study.lock): the lock file is written (the owner's pid), so the link is refused
 * (exit 2) and the file keeps its bytes; before, the lock truncated it and wrote a pid there. */
static void test_hard_link_at_lock(void **s) {
  (void)s;
  static const struct {
    const char *name, *args;
  } cases[] = {
      {"r.h5.lock", "run " CASE " --first-limit -q -o r.h5"},
      {"r.csv.lock", "run " CASE " --first-limit -q --no-record --csv r.csv"},
      {"sw/study.lock", "sweep " CASE " --alpha 0 --first-limit -q -o sw"},
      {"mc/study.lock", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char dir[256], target[300], at[600], cmd[3000];
    snprintf(dir, sizeof dir, "%s/hard%zu", g_dir, k);
    snprintf(target, sizeof target, "%s/precious", dir);
    snprintf(at, sizeof at, "%s/%s", dir, cases[k].name);
    snprintf(cmd, sizeof cmd, "mkdir -p %s/sw %s/mc && printf '%%s' '%s' > %s", dir, dir,
             PRECIOUS, target);
    assert_int_equal(sh(cmd), 0);
    assert_int_equal(link(target, at), 0);
    snprintf(cmd, sizeof cmd, "cd %s && timeout -s KILL 120 %s %s > out.txt 2> err.txt", dir,
             VS_BINARY, cases[k].args);
    const int rc = sh(cmd);
    char *after = slurp(target);
    snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
    char *err = slurp(cmd);
    if (after == NULL || strcmp(after, PRECIOUS) != 0)
      fail_msg("%s: a hard link at %s: its target was rewritten (exit %d)", cases[k].args,
               cases[k].name, rc);
    if (rc != 2 || err == NULL || strstr(err, "hard link") == NULL)
      fail_msg("%s: a hard link at %s: exit %d, stderr \"%s\": expected 2 and the link named",
               cases[k].args, cases[k].name, rc, err ? err : "");
    free(after);
    free(err);
  }
}

/* A command run with a link planted by a fault hook at one of its files: in g_dir/NAME (with sw/
 * and mc/ for the studies' outputs) a file of the test's, "precious" (PRECIOUS), watched by
 * inotify; `cd DIR && HOOK=TARGET' timeout -s KILL 120 voussoir ARGS > out.txt 2> err.txt`, HOOK
 * the hook's variable and value up to the link's target (as "VS_FAULT_LINK='r.h5.part=").
 * Returns its exit status; *opened: whether the target was opened, read or written; *err its
 * stderr, *after the target's bytes afterwards (malloc'd, NULL when gone); dir the directory. */
static int watched_run(const char *name, const char *hook, const char *args, int *opened,
                       char **err, char **after, char dir[256]) {
  char target[300], cmd[3000];
  snprintf(dir, 256, "%s/%s", g_dir, name);
  snprintf(target, sizeof target, "%s/precious", dir);
  snprintf(cmd, sizeof cmd, "mkdir -p %s/sw %s/mc && printf '%%s' '%s' > %s", dir, dir,
           PRECIOUS, target);
  assert_int_equal(sh(cmd), 0);
  const int in = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  assert_true(in >= 0);
  assert_true(inotify_add_watch(in, target, IN_OPEN | IN_ACCESS | IN_MODIFY) >= 0);
  snprintf(cmd, sizeof cmd, "cd %s && %s%s' timeout -s KILL 120 %s %s > out.txt 2> err.txt", dir,
           hook, target, VS_BINARY, args);
  const int rc = sh(cmd);
  char ev[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
  *opened = read(in, ev, sizeof ev) > 0;
  close(in);
  snprintf(cmd, sizeof cmd, "%s/err.txt", dir);
  *err = slurp(cmd);
  *after = slurp(target);
  return rc;
}

/* A link made at an HDF5 file's working name just before it is created (the hook, as above),
 * to a file of the test's watched by inotify: the file is not even opened. HDF5's create opens
 * the name read-write to see whether a file is there before its exclusive create, which failed
 * then (so nothing was written) but had opened whatever the link pointed to: a FIFO, a device. */
static void test_hdf5_link_never_opened(void **s) {
  (void)s;
  static const struct {
    const char *name, *args;
  } cases[] = {
      {"r.h5.part", "run " CASE " --first-limit -q -o r.h5"},
      {"sw/summary.h5.part", "sweep " CASE " --alpha 0 --first-limit -q -o sw"},
      {"mc/summary.h5.part", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char dir[256], name[32], hook[64], *err, *after;
    int n;
    snprintf(name, sizeof name, "watched%zu", k);
    snprintf(hook, sizeof hook, "VS_FAULT_LINK='%s=", cases[k].name);
    const int rc = watched_run(name, hook, cases[k].args, &n, &err, &after, dir);
    free(after);
    if (n > 0)
      fail_msg("%s: a link at %s made as it was created: the file it points to was opened "
               "(exit %d, stderr \"%s\")", cases[k].args, cases[k].name, rc, err ? err : "");
    if (rc == 0 || err == NULL || strstr(err, "became a symbolic link") == NULL)
      fail_msg("%s: a link at %s made as it was created: exit %d, stderr \"%s\": expected a "
               "failure naming the link", cases[k].args, cases[k].name, rc, err ? err : "");
    free(err);
  }
}

/* The record's working file FILE.h5.part (and a snapshot's FILE.h5.snap) replaced by a link to
 * a file of the test's watched by inotify during the run, after they were created (the hook
 * VS_FAULT_RELINK, at a point of the run: as a snapshot is about to copy the working file, before
 * the status, whose sidecar reopens the closed working file and which renames it over FILE.h5,
 * before a snapshot is renamed over FILE.h5). Those re-opened them by name and followed a link;
 * the renames moved it over FILE.h5. Now the file it points to is not even opened, the run
 * fails naming the link, and FILE.h5, when there, is a regular file (the last snapshot). */
static void test_part_relinked_during_run(void **s) {
  (void)s;
  static const char *const cases[][2] = {
      {"before-snapshot", "r.h5.part"}, /* the snapshot's copy */
      {"before-status", "r.h5.part"},   /* the sidecar's reopen, the final rename */
      {"before-publish", "r.h5.snap"},  /* a snapshot's rename */
  };
  int bad = 0;
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char dir[256], name[32], hook[64], at[600], *err, *after;
    int n;
    snprintf(name, sizeof name, "relinked%zu", k);
    snprintf(hook, sizeof hook, "VS_FAULT_RELINK='%s:%s=", cases[k][0], cases[k][1]);
    /* --snapshot-share 1: every flush's snapshot taken, so the point is reached in a short run */
    const int rc = watched_run(name, hook,
                               "run " CASE " --first-limit -q --snapshot-share 1 -o r.h5", &n,
                               &err, &after, dir);
    snprintf(at, sizeof at, "%s/r.h5", dir);
    struct stat st;
    if (n > 0) {
      bad++;
      printf("%s at %s: the file a link planted there points to was opened (exit %d, "
             "stderr \"%s\")\n", cases[k][1], cases[k][0], rc, err ? err : "");
    }
    if (after == NULL || strcmp(after, PRECIOUS) != 0) {
      bad++;
      printf("%s at %s: the file a link planted there points to was overwritten\n",
             cases[k][1], cases[k][0]);
    }
    if (lstat(at, &st) == 0 && !S_ISREG(st.st_mode)) {
      bad++;
      printf("%s at %s: r.h5 is no longer a regular file (the link renamed over it)\n",
             cases[k][1], cases[k][0]);
    }
    if (rc == 0 || err == NULL || strstr(err, cases[k][1]) == NULL ||
        strstr(err, "became a symbolic link during the run") == NULL) {
      bad++;
      printf("%s at %s: exit %d, stderr \"%s\": expected a failure naming the link\n",
             cases[k][1], cases[k][0], rc, err ? err : "");
    }
    free(err);
    free(after);
  }
  if (bad > 0) fail_msg("%d faults (above)", bad);
}

/* A finished working file (a CSV's, an HDF5 summary's, a manifest's, a sidecar's ".part" or
 * ".tmp") replaced by a link to a file of the test's watched by inotify just before it is
 * renamed over its output (the hook VS_FAULT_RELINK at "before-replace"): the rename moved the
 * link there, so that the output named the test's file. Now it is refused: the output is never
 * a link, the file pointed to is not opened, and the command names the working file. */
static void test_parts_relinked_before_rename(void **s) {
  (void)s;
  static const char *const cases[][2] = {
      {"r.xmf.tmp", "run " CASE " --first-limit -q -o r.h5"},
      {"sw/summary.csv.tmp", "sweep " CASE " --alpha 0 --first-limit -q -o sw"},
      {"sw/summary.h5.part", "sweep " CASE " --alpha 0 --first-limit -q -o sw"},
      {"sw/run_0001.json.part", "sweep " CASE " --alpha 0 --first-limit -q -o sw"},
      {"mc/montecarlo.manifest.part", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc"},
      {"mc/samples.csv.part", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc"},
      {"mc/summary.h5.part", "montecarlo " MC_CASE " --samples 2 --seed 1 -j 1 -q -o mc"},
  };
  int bad = 0;
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    char dir[256], name[32], hook[96], out[600], *err, *after;
    int n;
    snprintf(name, sizeof name, "renamed%zu", k);
    snprintf(hook, sizeof hook, "VS_FAULT_RELINK='before-replace:%s=", cases[k][0]);
    const int rc = watched_run(name, hook, cases[k][1], &n, &err, &after, dir);
    snprintf(out, sizeof out, "%s/%s", dir, cases[k][0]);
    *strrchr(out, '.') = '\0'; /* the output: the working file's name without ".part"/".tmp" */
    struct stat st;
    if (n > 0 || after == NULL || strcmp(after, PRECIOUS) != 0) {
      bad++;
      printf("%s: the file a link planted there points to was opened or changed (exit %d)\n",
             cases[k][0], rc);
    }
    if (lstat(out, &st) == 0 && !S_ISREG(st.st_mode)) {
      bad++;
      printf("%s: the link was renamed over %s (exit %d)\n", cases[k][0], out, rc);
    }
    if (err == NULL || strstr(err, cases[k][0]) == NULL) {
      bad++;
      printf("%s: exit %d, stderr \"%s\": expected the working file named\n", cases[k][0], rc,
             err ? err : "");
    }
    free(err);
    free(after);
  }
  if (bad > 0) fail_msg("%d faults (above)", bad);
}

static void test_links_planted_before(void **s) {
  (void)s;
  try_all(0);
}

static void test_links_made_meanwhile(void **s) {
  (void)s;
  try_all(1);
}

/* The inputs of merge and plot, made once: two shards, a record, a sweep's summary. */
static int setup(void **s) {
  (void)s;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_links_XXXXXX");
  if (mkdtemp(g_dir) == NULL) return -1;
  char cmd[2048];
  snprintf(cmd, sizeof cmd,
           "cd %s && %s montecarlo " MC_CASE " --samples 2 --seed 1 --shard 1/2 -q -o s1 && "
           "%s montecarlo " MC_CASE " --samples 2 --seed 1 --shard 2/2 -q -o s2 && "
           "%s run " CASE " --first-limit -q -o base.h5 > /dev/null && "
           "%s sweep " CASE " --alpha 0,45 -q -o swbase > /dev/null",
           g_dir, VS_BINARY, VS_BINARY, VS_BINARY, VS_BINARY);
  return sh(cmd) == 0 ? 0 : -1;
}

static int teardown(void **s) {
  (void)s;
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
  return sh(cmd) == 0 ? 0 : -1;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_hard_link_at_lock),
      cmocka_unit_test(test_links_planted_before),
      cmocka_unit_test(test_links_made_meanwhile),
      cmocka_unit_test(test_hdf5_link_never_opened),
      cmocka_unit_test(test_part_relinked_during_run),
      cmocka_unit_test(test_parts_relinked_before_rename),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
