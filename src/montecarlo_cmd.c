/* The montecarlo and merge commands' work (their command lines are read by
 * src/cli_montecarlo.c): samples handed out to a pool of forked workers (one process per sample,
 * its result sent back through a pipe), --shard K/M for batch schedulers, and merge of shard
 * directories into one summary. */
#define _POSIX_C_SOURCE 200809L /* fork, pipe, clock_gettime */
#include "voussoir/montecarlo.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "montecarlo_mpi.h"
#include "pipe_io.h"
#include "plugin.h"
#include "voussoir/outpath.h"
#include "voussoir/parse.h"
#include "voussoir/plot.h"

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

/* For the crash tests only: the environment variable VS_FAULT_STOP_AFTER = K makes the pool
 * raise SIGINT at itself once K samples are done (a stop at a state reached without timing). */
static long fault_stop_after(void) {
  const char *v = getenv("VS_FAULT_STOP_AFTER");
  long k = 0;
  return v != NULL && vs_parse_long(v, &k) == VS_NUM_OK && k > 0 ? k : 0;
}

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct {
  pid_t pid;
  int fd, slot; /* read end of the result pipe; index into the results */
} worker;

/* Fork a worker for sample `sample`: it runs it and writes the result into a pipe. */
static int start_worker(const vs_case *c, int sample, worker *w) {
  int fds[2];
  if (pipe(fds) != 0) return -1;
  fflush(NULL);
  pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    close(fds[0]);
    vs_mc_sample r;
    vs_mc_run_sample(c, sample, &r);
    _exit(vs_write_all(fds[1], &r, sizeof r) == 0 ? 0 : 3);
  }
  close(fds[1]);
  w->pid = pid;
  w->fd = fds[0];
  return 0;
}

/* Collect a finished worker's result (or record why there is none). */
static void finish_worker(worker *w, int status, int sample, vs_mc_sample *out) {
  const size_t got = vs_read_full(w->fd, out, sizeof *out);
  close(w->fd);
  if (got != sizeof *out || out->sample != sample) {
    memset(out, 0, sizeof *out);
    out->sample = sample;
    out->status = VS_MC_FAILED;
    out->first_limit_mm = out->delta_u_mm = out->dz_u_mm = out->dx_u_mm = NAN;
    if (WIFSIGNALED(status))
      snprintf(out->error, sizeof out->error, "worker killed by signal %d", WTERMSIG(status));
    else
      snprintf(out->error, sizeof out->error, "worker exited with status %d and no result",
               WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  }
  w->pid = 0;
}

/* Run the listed samples on `jobs` processes; results[i] for samples[i], done[i] set once it is
 * there. After a stop (g_stops) no sample starts; after a second the workers under way are
 * killed and their samples left undone. 0 when every sample ran or a stop ended the pool, -1
 * when a worker could not be started. */
static int run_pool(const vs_case *c, const int *samples, int n, int jobs, int quiet,
                    vs_mc_sample *results, char *done_at) {
  worker *ws = calloc((size_t)jobs, sizeof *ws);
  if (ws == NULL) return -1;
  int next = 0, done = 0, active = 0, failed = 0, killed = 0;
  const long stop_after = fault_stop_after();
  const double t0 = now_s();
  const int progress = !quiet && isatty(STDERR_FILENO);
  while (done < n) {
    if (g_stops > 1 && !killed) { /* a second stop: the samples under way are dropped */
      for (int k = 0; k < jobs; k++)
        if (ws[k].pid != 0) kill(ws[k].pid, SIGKILL);
      killed = 1;
    }
    while (active < jobs && next < n && g_stops == 0) {
      int k = 0;
      while (ws[k].pid != 0) k++;
      if (start_worker(c, samples[next], &ws[k]) != 0) break;
      ws[k].slot = next++;
      active++;
    }
    if (active == 0) break;
    int status = 0;
    pid_t pid = wait(&status);
    if (pid < 0 && errno == EINTR) continue;
    if (pid < 0) break;
    for (int k = 0; k < jobs; k++) {
      if (ws[k].pid != pid) continue;
      const int slot = ws[k].slot;
      active--;
      if (killed) { /* stopped by us: not a sample's failure */
        close(ws[k].fd);
        ws[k].pid = 0;
        continue;
      }
      finish_worker(&ws[k], status, samples[slot], &results[slot]);
      done_at[slot] = 1;
      failed += results[slot].status == VS_MC_FAILED;
      done++;
      if (stop_after > 0 && done == stop_after) raise(SIGINT);
    }
    if (progress)
      fprintf(stderr, "\r  samples %d/%d done, %d running, %d failed, %.1f s   ", done, n, active,
              failed, now_s() - t0);
  }
  if (progress) fputs("\r\033[K", stderr);
  free(ws);
  return done == n || g_stops > 0 ? 0 : -1;
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
  if (st == VS_OK) return 0;
  fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
  return -1;
}

/* Check that dir may receive the summary's files (VS_MC_OUTPUTS): dir absent or a directory,
 * each file there absent or a regular file and none of the others (the case file, an input
 * shard's table). 0, or EXIT_USAGE after printing why ("voussoir CMD: -o PATH: reason"). */
static int check_outputs(const char *cmd, const char *dir, const vs_outpath_other *others,
                         int n_others) {
  static const char *const names[] = {VS_MC_OUTPUTS};
  vs_error err;
  vs_error_clear(&err);
  int bad = vs_outpath_check_dir(dir, &err) != VS_OK;
  for (size_t i = 0; !bad && access(dir, F_OK) == 0 && i < sizeof names / sizeof names[0]; i++) {
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    bad = vs_outpath_check(path, others, n_others, &err) != VS_OK;
  }
  if (bad) fprintf(stderr, "voussoir %s: -o %s\n", cmd, err.msg);
  return bad ? EXIT_USAGE : 0;
}

static void print_result(const char *dir, const vs_mc_sample *r, int n, double wall, int jobs) {
  int collapses = 0, failed = 0;
  for (int i = 0; i < n; i++) {
    collapses += r[i].status == VS_MC_COLLAPSE;
    failed += r[i].status == VS_MC_FAILED;
  }
  printf("%d samples (%d collapses, %d failed) in %.1f s on %d processes (or MPI ranks); summary: %s/summary.h5, "
         "statistics: %s/statistics.csv\n",
         n, collapses, failed, wall, jobs, dir, dir);
}

int vs_mc_main(const vs_mc_opts *o) {
  vs_mc_opts a = *o; /* a.jobs becomes the number of MPI ranks under MPI */
  vs_case c;
  if (load_case(&a, &c) != 0) return EXIT_USAGE;
  /* the summary is HDF5 and pictures: the plot plugin, before anything is written */
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir montecarlo") != 0) return EXIT_FAIL;
  int n = 0;
  for (int i = a.shard_k - 1; i < a.samples; i += a.shard_m) n++;
  int *samples = malloc((size_t)(n > 0 ? n : 1) * sizeof *samples);
  vs_mc_sample *res = calloc((size_t)(n > 0 ? n : 1), sizeof *res);
  char *done_at = calloc((size_t)(n > 0 ? n : 1), 1);
  int rc = EXIT_FAIL;
  if (samples == NULL || res == NULL || done_at == NULL) {
    fprintf(stderr, "voussoir montecarlo: out of memory\n");
    goto done;
  }
  for (int i = a.shard_k - 1, k = 0; i < a.samples; i += a.shard_m) samples[k++] = i;
  const vs_outpath_other case_file[1] = {{a.case_path, "the case file"}};
  if ((rc = check_outputs("montecarlo", a.dir, case_file, 1)) != 0) goto done;
  rc = EXIT_FAIL;
  if (mkdir(a.dir, 0755) != 0 && errno != EEXIST) { /* before hours of work, not after */
    fprintf(stderr, "voussoir montecarlo: -o %s: cannot create: %s\n", a.dir, strerror(errno));
    goto done;
  }
  const double t0 = now_s();
#ifdef VS_HAVE_MPI
  if (vs_plugin_mpi_launched()) {
    if (vs_plugin_load(VS_PLUGIN_MPI, "voussoir montecarlo") != 0) goto done;
    if (vs_mc_run_mpi(&c, samples, n, res, &a.jobs) != 0) { /* a worker rank: rank 0 reports */
      rc = 0;
      goto done;
    }
  } else
#endif
  {
    cli_on_stop_signals(on_stop); /* no SA_RESTART: wait() returns at once with EINTR */
    if (run_pool(&c, samples, n, a.jobs, a.quiet, res, done_at) != 0) {
      fprintf(stderr, "voussoir montecarlo: cannot start the workers: %s\n", strerror(errno));
      goto done;
    }
    /* stopped: the summary of the samples done (in sample order, as every summary) */
    int k = 0;
    for (int i = 0; i < n; i++)
      if (done_at[i]) res[k++] = res[i];
    if (k < n) {
      const int total = n;
      n = k;
      fprintf(stderr, "voussoir montecarlo: interrupted: %d of %d samples done, their summary "
              "in %s\n", n, total, a.dir);
    }
  }
  vs_error err;
  vs_error_clear(&err);
  if (vs_mc_write_summary(a.dir, &c, res, n, &err) != VS_OK) {
    fprintf(stderr, "voussoir montecarlo: %s\n", err.msg);
    goto done;
  }
  print_result(a.dir, res, n, now_s() - t0, a.jobs);
  rc = g_stops > 0 ? EXIT_INTERRUPTED : 0;
  int failed = 0;
  for (int i = 0; i < n; i++) failed += res[i].status == VS_MC_FAILED;
  if (n > 0 && failed == n) { /* no statistics at all: say why (the first cause) */
    fprintf(stderr, "voussoir montecarlo: every sample failed; sample %d: %s\n", res[0].sample,
            res[0].error);
    rc = EXIT_FAIL;
  }
done:
  free(samples);
  free(res);
  free(done_at);
  vs_plot_release();
  return rc;
}

/* --- merge --- */

/* Split line in place at commas into at most max fields; returns the count. */
static int split_csv(char *line, char **f, int max) {
  int n = 0;
  f[n++] = line;
  for (char *p = line; *p && n < max; p++)
    if (*p == ',') {
      *p = '\0';
      f[n++] = p + 1;
    }
  return n;
}

static int parse_row(char *line, vs_mc_sample *x) {
  char *f[14];
  line[strcspn(line, "\r\n")] = '\0';
  if (split_csv(line, f, 14) != 14) return -1;
  memset(x, 0, sizeof *x);
  long smp = -1, mode = 0;
  if (vs_parse_long(f[0], &smp) != VS_NUM_OK || smp < 0 || smp > INT_MAX ||
      vs_parse_long(f[6], &mode) != VS_NUM_OK || mode < 0 || mode > 3)
    return -1;
  x->sample = (int)smp;
  x->mode = (int)mode;
  x->status = strcmp(f[1], "collapse") == 0           ? VS_MC_COLLAPSE
              : strcmp(f[1], "max_displacement") == 0 ? VS_MC_NO_COLLAPSE
                                                      : VS_MC_FAILED;
  /* the table is ours: "nan" marks a missing value, which the strict parser refuses */
  x->first_limit_mm = strtod(f[2], NULL);
  x->delta_u_mm = strtod(f[3], NULL);
  x->dz_u_mm = strtod(f[4], NULL);
  x->dx_u_mm = strtod(f[5], NULL);
  snprintf(x->pattern, sizeof x->pattern, "%s", f[7]);
  for (int l = 0; l < VS_MC_LABELS; l++) {
    char side = 0;
    int j = 0;
    if (f[8 + l][0] != '\0' && sscanf(f[8 + l], "%d-%c", &j, &side) == 2) {
      x->hinge_joint[l] = j;
      x->hinge_side[l] = side;
    }
  }
  snprintf(x->error, sizeof x->error, "%s", f[13]);
  return 0;
}

/* Append the samples of DIR/samples.csv to *all; the header line must equal *header (set by the
 * first directory). */
static int read_shard(const char *dir, char *header, size_t hsize, vs_mc_sample **all, int *n,
                      int *cap) {
  char path[1200], line[1024];
  snprintf(path, sizeof path, "%s/samples.csv", dir);
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    fprintf(stderr, "voussoir merge: %s: cannot open: %s\n", path, strerror(errno));
    return -1;
  }
  int rc = 0;
  if (fgets(line, sizeof line, f) == NULL || strncmp(line, "# voussoir montecarlo ", 22) != 0) {
    fprintf(stderr, "voussoir merge: %s: not a montecarlo table\n", path);
    rc = -1;
  } else if (header[0] == '\0') {
    snprintf(header, hsize, "%s", line);
  } else if (strcmp(header, line) != 0) {
    fprintf(stderr, "voussoir merge: %s: another case or seed than the first directory\n", path);
    rc = -1;
  }
  if (rc == 0 && fgets(line, sizeof line, f) == NULL) rc = -1; /* column names */
  while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
    if (*n == *cap) {
      const int nc = *cap ? 2 * *cap : 256;
      vs_mc_sample *b = realloc(*all, (size_t)nc * sizeof *b);
      if (b == NULL) {
        rc = -1;
        break;
      }
      *all = b;
      *cap = nc;
    }
    if (parse_row(line, &(*all)[*n]) != 0) {
      fprintf(stderr, "voussoir merge: %s: malformed row %d\n", path, *n + 1);
      rc = -1;
    } else {
      (*n)++;
    }
  }
  fclose(f);
  return rc;
}

static int header_case(const char *header, vs_case *c) {
  vs_case_defaults(c);
  return sscanf(header,
                "# voussoir montecarlo seed=%d radius_mm=%lf embrace_deg=%lf max_mm=%lf "
                "alpha_deg=%lf voussoirs=%d",
                &c->seed, &c->radius_mm, &c->embrace_deg, &c->max_mm, &c->alpha_deg,
                &c->voussoirs) == 6
             ? 0
             : -1;
}

static int cmp_sample_no(const void *x, const void *y) {
  const int a = ((const vs_mc_sample *)x)->sample, b = ((const vs_mc_sample *)y)->sample;
  return (a > b) - (a < b);
}

int vs_merge_main(const char *const *dirs, int nd, const char *out) {
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir merge") != 0) return EXIT_FAIL;
  char header[1024] = "";
  vs_mc_sample *all = NULL;
  int n = 0, cap = 0, rc = EXIT_USAGE;
  /* the shards' tables are inputs: never replaced by the merged one */
  char (*tables)[1100] = malloc((size_t)(nd > 0 ? nd : 1) * sizeof *tables);
  vs_outpath_other *others = malloc((size_t)(nd > 0 ? nd : 1) * sizeof *others);
  if (tables == NULL || others == NULL) {
    fprintf(stderr, "voussoir merge: out of memory\n");
    rc = EXIT_FAIL;
    goto done;
  }
  for (int d = 0; d < nd; d++) {
    snprintf(tables[d], sizeof tables[d], "%s/samples.csv", dirs[d]);
    others[d] = (vs_outpath_other){tables[d], "an input shard's table"};
  }
  if (check_outputs("merge", out, others, nd) != 0) goto done;
  for (int d = 0; d < nd; d++)
    if (read_shard(dirs[d], header, sizeof header, &all, &n, &cap) != 0) goto done;
  qsort(all, (size_t)n, sizeof *all, cmp_sample_no);
  for (int i = 1; i < n; i++)
    if (all[i].sample == all[i - 1].sample) {
      fprintf(stderr, "voussoir merge: sample %d appears twice\n", all[i].sample);
      goto done;
    }
  vs_case c;
  vs_error err;
  vs_error_clear(&err);
  if (n == 0 || header_case(header, &c) != 0) {
    fprintf(stderr, "voussoir merge: no samples, or an unreadable table header\n");
    goto done;
  }
  rc = EXIT_FAIL;
  if (vs_mc_write_summary(out, &c, all, n, &err) != VS_OK) {
    fprintf(stderr, "voussoir merge: %s\n", err.msg);
    goto done;
  }
  printf("%d samples from %d directories; summary: %s/summary.h5\n", n, nd, out);
  rc = 0;
done:
  free(all);
  free(tables);
  free(others);
  vs_plot_release();
  return rc;
}
