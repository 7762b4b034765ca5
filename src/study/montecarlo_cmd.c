/* The montecarlo command's work (its command line is read by src/cli/cli_montecarlo.c): samples
 * handed out to a pool of forked workers (one process per sample, its result sent back through
 * a pipe) or to MPI ranks, --shard K/M for batch schedulers, the study's journal for --resume.
 * merge: src/study/montecarlo_merge.c. */
#define _POSIX_C_SOURCE 200809L /* fork, pipe, clock_gettime */
#include "voussoir/montecarlo.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "stop.h"
#include "study.h"
#include "journal.h"
#include "montecarlo_cmd.h"
#include "montecarlo_mpi.h"
#include "pipe_io.h"
#include "plugin.h"
#include "outpath.h"
#include "parse.h"
#include "voussoir/geometry.h"
#include "voussoir/plot.h"
#include "quote.h"

/* The size of the paths of the study's files in its directory; run_study's status on an MPI
 * worker rank (not an exit status). */
enum { MC_JPATH = 1200, MC_WORKER_RANK = -1 };

enum { EXIT_FAIL = VS_EXIT_FAILED, EXIT_USAGE = VS_EXIT_BAD_INPUT,
       EXIT_INTERRUPTED = VS_EXIT_INTERRUPTED };

/* SIGINT/SIGTERM during the pool: no sample is started after the first (those under way end and
 * count), the workers are killed after the second; the summary of the samples done is written
 * and the exit status is 130. A signal handler can only reach a global. */
static volatile sig_atomic_t g_stops = 0;

static void on_stop(int sig) {
  (void)sig;
  g_stops++;
}

/* --- a study under way: this shard's samples, their results, the journal --- */

/* What a --resume must find the same in DIR/montecarlo.manifest: the case after --set and
 * --seed (every key), the sample count and the shard. */
static const char MANIFEST[] = "montecarlo.manifest", JOURNAL[] = "montecarlo.journal";

typedef struct {
  const vs_mc_opts *o;
  const vs_case *c;
  int n;              /* this shard's samples: shard_k - 1, shard_k - 1 + shard_m, ... */
  vs_mc_sample *res;  /* per slot (sample (slot) = shard_k - 1 + slot shard_m) */
  char *done;         /* per slot: its result is in res */
  int next;           /* the next slot to consider handing out */
  int ndone, resumed, taken; /* results held, of which from the journal; taken in this run */
  FILE *journal;
  vs_outlock *lock; /* DIR's (journal.h), from before anything in DIR is written to the end */
} mc_study;

static int sample_of(const mc_study *s, int slot) {
  return s->o->shard_k - 1 + slot * s->o->shard_m;
}

/* The slot of sample `sample`, or -1 when it is not one of this shard's. */
static int slot_of(const mc_study *s, int sample) {
  const int d = sample - (s->o->shard_k - 1);
  return d >= 0 && d % s->o->shard_m == 0 && d / s->o->shard_m < s->n ? d / s->o->shard_m : -1;
}

/* The journal's first line: its kind and the layout of its rows, their size with the checksum
 * (a journal of another build, or of the layout before the checksums, journal 1, is refused). */
static void journal_head(char *buf, size_t size) {
  snprintf(buf, size, "voussoir montecarlo journal 2 row %zu bytes\n",
           sizeof(vs_mc_sample) + VS_JOURNAL_SUM);
}

static char *manifest_text(const mc_study *s) {
  enum { EXTRA = 64 };
  char *t = vs_manifest_case(s->c, EXTRA);
  if (t != NULL)
    snprintf(t + strlen(t), EXTRA + 1, "samples %d\nshard %d/%d\n", s->o->samples,
             s->o->shard_k, s->o->shard_m);
  return t;
}

/* A result kept (from a worker, or from the journal). */
static void keep(mc_study *s, const vs_mc_sample *r) {
  const int slot = slot_of(s, r->sample);
  if (slot < 0) return;
  s->ndone += !s->done[slot];
  s->res[slot] = *r;
  s->done[slot] = 1;
}

/* A row of the journal being resumed: kept when every field is sound (one of this shard's
 * samples, on this arch) and it is the first for its sample. */
static int resumed(void *user, const void *row, char *why, size_t size) {
  mc_study *s = user;
  const vs_mc_sample *r = row;
  if (!vs_mc_sample_check(r, s->o->samples, s->o->shard_k, s->o->shard_m, s->c->voussoirs + 1,
                          why, size))
    return 0;
  if (s->done[slot_of(s, r->sample)]) {
    snprintf(why, size, "a second row for sample %d", r->sample);
    return 0;
  }
  keep(s, r);
  return 1;
}

/* --resume: the manifest at mpath must say want; the sound rows of the journal at path are kept
 * (*rows: how many). 0, or an exit status after printing why. */
static int resume_study(mc_study *s, const char *mpath, const char *want, const char *path,
                        const char *head, long *rows) {
  const int same = vs_manifest_same(mpath, want);
  if (same != 1) {
    fprintf(stderr, "voussoir montecarlo: --resume: %s %s\n", mpath,
            same < 0 ? "is missing: no study to resume in this directory"
                     : "differs: that study had another case, --set, --seed, --samples or "
                       "--shard");
    return EXIT_USAGE;
  }
  const int rc = vs_journal_read(path, head, sizeof(vs_mc_sample), "voussoir montecarlo",
                                 resumed, s, rows);
  if (rc == VS_JOURNAL_FOREIGN)
    fprintf(stderr, "voussoir montecarlo: --resume: %s was not written by this build of "
            "voussoir (it expects \"%.*s\"); run the study afresh\n", path,
            (int)strlen(head) - 1, head);
  else if (rc != 0)
    fprintf(stderr, "voussoir montecarlo: --resume: %s: cannot read or rewrite: %s\n", path,
            strerror(errno));
  s->resumed = s->ndone;
  if (rc == 0 && !s->o->quiet)
    fprintf(stderr, "voussoir montecarlo: resuming: %d of %d samples already done\n", s->ndone,
            s->n);
  return rc == 0 ? 0 : EXIT_USAGE;
}

/* The directory locked; fresh: the manifest written (renamed into place) and an empty journal.
 * --resume: the manifest must be the same, the journal's sound results are kept and it is
 * appended to after them. 0, or an exit status after printing why. */
static int study_open(mc_study *s) {
  const char *dir = s->o->dir;
  char *want = manifest_text(s), path[MC_JPATH], head[96];
  if (want == NULL) {
    fprintf(stderr, "voussoir montecarlo: out of memory\n");
    return EXIT_FAIL;
  }
  journal_head(head, sizeof head);
  snprintf(path, sizeof path, "%s/%s", dir, JOURNAL);
  long rows = -1;
  int rc = 0;
  char mpath[MC_JPATH];
  snprintf(mpath, sizeof mpath, "%s/%s", dir, MANIFEST);
  vs_error err;
  vs_error_clear(&err);
  if (vs_study_lock(dir, "voussoir montecarlo", &s->lock, &err) != VS_OK) {
    fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
    rc = EXIT_USAGE;
  } else if (s->o->resume) {
    rc = resume_study(s, mpath, want, path, head, &rows);
  } else {
    char part[MC_JPATH + 8];
    snprintf(part, sizeof part, "%s.part", mpath);
    FILE *f;
    vs_status st = vs_outpath_fopen(part, &f, &err);
    if (st == VS_OK) {
      const int ok = fputs(want, f) >= 0;
      st = fclose(f) == 0 && ok ? vs_outpath_publish(part, mpath, &err)
                                : vs_error_set(&err, VS_ERR_IO, "%s: cannot write: %s", part,
                                               strerror(errno));
      if (st != VS_OK) vs_outpath_discard(part);
    }
    if (st != VS_OK) {
      fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
      rc = st == VS_ERR_INVALID ? EXIT_USAGE : EXIT_FAIL;
    }
  }
  free(want);
  if (rc == 0 &&
      (s->journal = vs_journal_open(path, head, sizeof(vs_mc_sample), rows, &err)) == NULL) {
    fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
    rc = err.status == VS_ERR_INVALID ? EXIT_USAGE : EXIT_FAIL;
  }
  return rc;
}

/* For the crash tests only: VS_FAULT_STOP_AFTER = K makes the study raise SIGINT at itself once
 * K samples are taken in this run, VS_FAULT_KILL_AFTER = K SIGKILL once K are journalled (stops
 * at states reached without timing). */
static long fault_after(const char *name) {
  const char *v = getenv(name);
  long k = 0;
  return v != NULL && vs_parse_long(v, &k) == VS_NUM_OK && k > 0 ? k : 0;
}

/* A sample's result as it comes back: kept and, when the sample ran to its own end (a result,
 * even a failed run's; not a worker lost), journalled. */
static void take(mc_study *s, const vs_mc_sample *r, int ran) {
  const int slot = slot_of(s, r->sample);
  if (slot < 0 || s->done[slot]) return;
  keep(s, r);
  s->taken++;
  if (ran && vs_journal_append(s->journal, r, sizeof *r) != 0)
    fprintf(stderr, "voussoir montecarlo: %s: cannot write: %s\n", JOURNAL, strerror(errno));
  if (ran && s->taken == fault_after("VS_FAULT_KILL_AFTER")) raise(SIGKILL);
  if (s->taken == fault_after("VS_FAULT_STOP_AFTER")) raise(SIGINT);
}

/* The next sample to run, or -1: none left, or the study was asked to stop. */
static int next_sample(mc_study *s) {
  while (g_stops == 0 && s->next < s->n) {
    const int slot = s->next++;
    if (!s->done[slot]) return sample_of(s, slot);
  }
  return -1;
}

static void study_close(mc_study *s) {
  if (s->journal != NULL) fclose(s->journal);
  vs_outlock_release(&s->lock);
  free(s->res);
  free(s->done);
}

/* --- the local pool: one forked worker per sample --- */

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
  pid_t pid;
  int fd, sample; /* read end of the result pipe; the sample it runs */
} worker;

/* Fork a worker for sample `sample`: it runs it and writes the result into a pipe; killed with
 * the study if that is killed outright (vs_worker_tie). */
static int start_worker(const vs_case *c, int sample, worker *w) {
  int fds[2];
  if (pipe(fds) != 0) return -1;
  fflush(NULL);
  const pid_t parent = getpid();
  pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    vs_worker_tie(parent);
    close(fds[0]);
    vs_fault_hold(sample, &g_stops); /* tests only */
    vs_mc_sample r;
    vs_mc_run_sample(c, sample, &r);
    _exit(vs_write_all(fds[1], &r, sizeof r) == 0 ? 0 : 3);
  }
  close(fds[1]);
  w->pid = pid;
  w->fd = fds[0];
  w->sample = sample;
  return 0;
}

/* Collect a finished worker's result (or record why there is none). 1 when the worker sent its
 * sample's result, 0 when it was lost. */
static int finish_worker(worker *w, int status, vs_mc_sample *out) {
  const size_t got = vs_read_full(w->fd, out, sizeof *out);
  close(w->fd);
  w->pid = 0;
  if (got == sizeof *out && out->sample == w->sample) return 1;
  memset(out, 0, sizeof *out);
  out->sample = w->sample;
  out->status = VS_MC_FAILED;
  out->first_limit_mm = out->delta_u_mm = out->dz_u_mm = out->dx_u_mm = NAN;
  if (WIFSIGNALED(status))
    snprintf(out->error, sizeof out->error, "worker killed by signal %d", WTERMSIG(status));
  else
    snprintf(out->error, sizeof out->error, "worker exited with status %d and no result",
             WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  return 0;
}

/* Run the study's samples still to do on `jobs` processes. After a stop (g_stops) no sample
 * starts; after a second the workers under way are killed and their samples left undone. 0 when
 * every sample ran or a stop ended the pool, -1 when a worker could not be started. */
static int run_pool(mc_study *s, int jobs) {
  worker *ws = calloc((size_t)jobs, sizeof *ws);
  if (ws == NULL) return -1;
  int active = 0, failed = 0, killed = 0, more = 1;
  const int todo = s->n - s->ndone;
  const double t0 = now_s();
  const int progress = !s->o->quiet && isatty(STDERR_FILENO);
  while (s->ndone < s->n) {
    if (g_stops > 1 && !killed) { /* a second stop: the samples under way are dropped */
      for (int k = 0; k < jobs; k++)
        if (ws[k].pid != 0) kill(ws[k].pid, SIGKILL);
      killed = 1;
    }
    while (active < jobs && more) {
      const int sample = next_sample(s);
      if (sample < 0) {
        more = 0;
        break;
      }
      int k = 0;
      while (ws[k].pid != 0) k++;
      if (start_worker(s->c, sample, &ws[k]) != 0) {
        s->next--; /* not started */
        more = 0;
        break;
      }
      active++;
    }
    if (active == 0) break;
    int status = 0;
    pid_t pid = wait(&status);
    if (pid < 0 && errno == EINTR) continue;
    if (pid < 0) break;
    for (int k = 0; k < jobs; k++) {
      if (ws[k].pid != pid) continue;
      active--;
      if (killed) { /* stopped by us: not a sample's failure */
        close(ws[k].fd);
        ws[k].pid = 0;
        continue;
      }
      vs_mc_sample r;
      const int ran = finish_worker(&ws[k], status, &r);
      failed += r.status == VS_MC_FAILED;
      take(s, &r, ran);
    }
    if (progress)
      fprintf(stderr, "\r  samples %d/%d done, %d running, %d failed, %.1f s   ",
              s->ndone - s->resumed, todo, active, failed, now_s() - t0);
  }
  if (progress) fputs("\r\033[K", stderr);
  free(ws);
  return s->ndone == s->n || g_stops > 0 ? 0 : -1;
}

#ifdef VS_HAVE_MPI
static int mpi_open(void *user) { return study_open(user); }
static int mpi_next(void *user) { return next_sample(user); }
static void mpi_take(void *user, const vs_mc_sample *r) { take(user, r, 1); }
#endif

/* A blocks file's arch ring as arch.voussoirs (which the file's blocks do not read): the
 * hinges' joints the samples are checked against, the hinge histogram's joints, and the table's
 * header, which `voussoir merge` reads back. The file's errors, as a run gives them. */
static vs_status file_voussoirs(vs_case *c, vs_error *err) {
  vs_run_def *d = malloc(sizeof *d);
  if (d == NULL) return vs_error_set(err, VS_ERR_NOMEM, "out of memory");
  vs_geometry *g = NULL;
  vs_case_to_def(c, d);
  vs_status st = vs_geometry_create_arch(&d->arch, &g, err);
  if (st == VS_OK) c->voussoirs = (g->ring > 0 ? g->ring : g->n_joints) - 1;
  vs_geometry_destroy(&g);
  free(d);
  return st;
}

/* The case with the overrides and the seed applied, validated. */
static int load_case(const vs_mc_opts *a, vs_case *c) {
  vs_error err;
  vs_error_clear(&err);
  vs_case_defaults(c);
  vs_status st = vs_case_read(c, a->case_path, NULL, &err);
  for (int s = 0; st == VS_OK && s < a->nsets; s++) st = vs_case_set(c, a->sets[s], &err);
  if (st == VS_OK && a->seed != NULL) {
    char buf[96];
    snprintf(buf, sizeof buf, "imperfections.seed=%.60s", a->seed);
    st = vs_case_set(c, buf, &err);
  }
  if (st == VS_OK) st = vs_case_validate(c, &err);
  if (st == VS_OK) st = vs_case_check_path(c, "montecarlo", &err);
  if (st == VS_OK && c->shape == VS_SHAPE_FILE) st = file_voussoirs(c, &err);
  if (st == VS_OK) return 0;
  fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
  return -1;
}

int vs_mc_check_outputs(const char *cmd, const char *dir, const vs_outpath_other *others,
                        int n_others, int state) {
  /* each written through "<name>.part" but the journal and the study lock */
  static const char *const names[] = {VS_MC_OUTPUTS, MANIFEST, JOURNAL, VS_STUDY_LOCK ".lock"};
  const size_t count = sizeof names / sizeof names[0] - (state ? 0 : 3);
  vs_error err;
  vs_error_clear(&err);
  int bad = vs_outpath_check_dir(dir, &err) != VS_OK;
  for (size_t i = 0; !bad && access(dir, F_OK) == 0 && i < 2 * count; i++) {
    char path[MC_JPATH];
    const char *part = i % 2 == 0 || names[i / 2] == JOURNAL ? "" : ".part";
    snprintf(path, sizeof path, "%s/%s%s", dir, names[i / 2], part);
    bad = vs_outpath_check(path, others, n_others, &err) != VS_OK;
  }
  if (bad) fprintf(stderr, "voussoir %s: -o %s\n", cmd, err.msg);
  return bad ? EXIT_USAGE : 0;
}

static void print_result(const mc_study *s, const vs_mc_sample *r, int n, double wall, int jobs) {
  int collapses = 0, failed = 0;
  for (int i = 0; i < n; i++) {
    collapses += r[i].status == VS_MC_COLLAPSE;
    failed += r[i].status == VS_MC_FAILED;
  }
  char from[64] = "";
  if (s->resumed > 0) snprintf(from, sizeof from, ", %d of them from the journal", s->resumed);
  printf("%d samples (%d collapses, %d failed%s) in %.1f s on %d processes (or MPI ranks); "
         "summary: %s/summary.h5, statistics: %s/statistics.csv\n",
         n, collapses, failed, from, wall, jobs, s->o->dir, s->o->dir);
}

/* The samples' runs, locally or across MPI ranks. 0 on the process that writes the summary,
 * MC_WORKER_RANK on an MPI worker rank (done), or an exit status after printing why. */
static int run_study(mc_study *s, vs_mc_opts *a) {
#ifdef VS_HAVE_MPI
  if (vs_plugin_mpi_launched()) {
    if (vs_plugin_load(VS_PLUGIN_MPI, "voussoir montecarlo") != 0) return EXIT_FAIL;
    int opened = 0;
    const vs_mc_server srv = {mpi_open, mpi_next, mpi_take, s};
    if (vs_mc_run_mpi(s->c, &srv, &opened, &a->jobs) != 0) return MC_WORKER_RANK;
    return opened;
  }
#endif
  int rc = study_open(s);
  if (rc != 0) return rc;
  vs_on_stop_signals(on_stop); /* no SA_RESTART: wait() returns at once with EINTR */
  if (run_pool(s, a->jobs) != 0) {
    fprintf(stderr, "voussoir montecarlo: cannot start the workers: %s\n", strerror(errno));
    return EXIT_FAIL;
  }
  return 0;
}

int vs_mc_main(const vs_mc_opts *o) {
  vs_mc_opts a = *o; /* a.jobs becomes the number of MPI ranks under MPI */
  vs_case c;
  if (load_case(&a, &c) != 0) return EXIT_USAGE;
  /* the summary is HDF5 and pictures: the plot plugin, before anything is written */
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir montecarlo") != 0) return EXIT_FAIL;
  mc_study s = {.o = &a, .c = &c};
  for (int i = a.shard_k - 1; i < a.samples; i += a.shard_m) s.n++;
  s.res = calloc((size_t)(s.n > 0 ? s.n : 1), sizeof *s.res);
  s.done = calloc((size_t)(s.n > 0 ? s.n : 1), 1);
  int rc = EXIT_FAIL;
  if (s.res == NULL || s.done == NULL) {
    fprintf(stderr, "voussoir montecarlo: out of memory\n");
    goto done;
  }
  const vs_outpath_other case_file[1] = {{a.case_path, "the case file"}};
  if ((rc = vs_mc_check_outputs("montecarlo", a.dir, case_file, 1, 1)) != 0) goto done;
  if (a.resume && access(a.dir, F_OK) != 0) {
    fprintf(stderr, "voussoir montecarlo: --resume: -o %s: no such directory: no study to resume "
            "there\n", a.dir);
    rc = EXIT_USAGE;
    goto done;
  }
  rc = EXIT_FAIL;
  if (mkdir(a.dir, 0755) != 0 && errno != EEXIST) { /* before hours of work, not after */
    fprintf(stderr, "voussoir montecarlo: -o %s: cannot create: %s\n", a.dir, strerror(errno));
    goto done;
  }
  const double t0 = now_s();
  rc = run_study(&s, &a);
  if (rc != 0) {
    if (rc == MC_WORKER_RANK) rc = 0; /* rank 0 reports */
    goto done;
  }
  rc = EXIT_FAIL;
  /* the summary of the samples done, in sample order (a stop may leave some undone) */
  int n = 0;
  for (int i = 0; i < s.n; i++)
    if (s.done[i]) s.res[n++] = s.res[i];
  if (n < s.n)
    fprintf(stderr, "voussoir montecarlo: interrupted: %d of %d samples done, their summary "
            "in %s (continue with --resume)\n", n, s.n, a.dir);
  vs_error err;
  vs_error_clear(&err);
  if (vs_mc_write_summary(a.dir, &c, s.res, n, &err) != VS_OK) {
    fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
    goto done;
  }
  print_result(&s, s.res, n, now_s() - t0, a.jobs);
  rc = n < s.n ? EXIT_INTERRUPTED : 0;
  int failed = 0;
  for (int i = 0; i < n; i++) failed += s.res[i].status == VS_MC_FAILED;
  if (n > 0 && failed == n) { /* no statistics at all: say why (the first cause) */
    fprintf(stderr, "voussoir montecarlo: every sample failed; sample %d: %s\n", s.res[0].sample,
            vs_q(s.res[0].error).s); /* it may come from the journal */
    rc = EXIT_FAIL;
  }
done:
  study_close(&s);
  vs_plot_release();
  return rc;
}
