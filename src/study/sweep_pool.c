/* The sweep's local pool: each case in a worker forked from the loaded process (no program
 * start-up, no exec), its row sent back through a pipe as plain data; stop signals passed on to
 * the workers under way. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "pipe_io.h"
#include "sweep_private.h"

typedef struct {
  pid_t pid; /* 0: free slot */
  int fd;    /* read end of the row's pipe */
  int run;
} worker;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The worker: its own process group (a terminal's ^C reaches the sweep, which passes it on
 * once), killed with the sweep if that is killed outright (vs_worker_tie), the case run here,
 * the row written into the pipe. Never returns. */
static void worker_main(const vs_sweep_job *job, int run, int fd, pid_t parent,
                        volatile sig_atomic_t *stop_count) {
  setpgid(0, 0);
  vs_worker_tie(parent);
  vs_sweep_row row;
  int clean = 1;
  /* the handler inherited from the sweep raises *stop_count: the run stops at its next step */
  vs_sweep_run_case(job, run, stop_count, &row, &clean);
  _exit(vs_write_all(fd, &row, sizeof row) == 0 ? 0 : 3);
}

static int start_worker(const vs_sweep_job *job, int run, worker *w,
                        const volatile sig_atomic_t *stop_count) {
  int fds[2];
  if (pipe(fds) != 0) return -1;
  fflush(NULL); /* nothing buffered is written twice */
  const pid_t parent = getpid();
  pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    close(fds[0]);
    worker_main(job, run, fds[1], parent, (volatile sig_atomic_t *)stop_count);
  }
  close(fds[1]);
  *w = (worker){pid, fds[0], run};
  return 0;
}

/* The row of an ended worker: the one it sent, or (none: it was killed or crashed) a lost row
 * that says why. */
static void finish_worker(worker *w, int status, vs_sweep_row *row) {
  const size_t got = vs_read_full(w->fd, row, sizeof *row);
  close(w->fd);
  if (got != sizeof *row || row->run != w->run || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    memset(row, 0, sizeof *row);
    row->run = w->run;
    row->code = VS_SWEEP_LOST;
    row->left_dx_mm = row->left_dz_mm = row->right_dx_mm = row->right_dz_mm = NAN;
    row->load_factor = NAN;
    snprintf(row->status, sizeof row->status, "failed");
    if (WIFSIGNALED(status))
      snprintf(row->error, sizeof row->error, "worker killed by signal %d", WTERMSIG(status));
    else
      snprintf(row->error, sizeof row->error, "worker exited with status %d and no result",
               WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  }
  w->pid = 0;
}

/* Pass a stop on to every worker under way, once (a second stop: kill them). */
static void forward_stop(const worker *ws, int jobs, int *forwarded,
                         const volatile sig_atomic_t *count, const volatile sig_atomic_t *sig) {
  const int want = *count > 1 ? 2 : *count > 0 ? 1 : 0;
  if (want <= *forwarded) return;
  for (int k = 0; k < jobs; k++)
    if (ws[k].pid > 0) kill(ws[k].pid, want == 2 ? SIGKILL : (int)*sig);
  *forwarded = want;
}

/* Wait for a worker to end, passing stops on meanwhile. Polls rather than blocking in wait(): a
 * signal landing just before a blocking wait would not be passed on until some run ended by
 * itself; 20 ms costs nothing next to a run. */
static pid_t wait_worker(const worker *ws, int jobs, int *forwarded, int *status,
                         const volatile sig_atomic_t *count, const volatile sig_atomic_t *sig) {
  for (;;) {
    forward_stop(ws, jobs, forwarded, count, sig);
    pid_t pid = waitpid(-1, status, WNOHANG);
    if (pid != 0 && !(pid < 0 && errno == EINTR)) return pid;
    nanosleep(&(struct timespec){0, 20000000}, NULL);
  }
}

int vs_sweep_pool_serve(const vs_sweep_server *s, const vs_sweep_job *job, int jobs, int todo,
                        int progress, const volatile sig_atomic_t *stop_count,
                        const volatile sig_atomic_t *stop_signal) {
  worker *ws = calloc((size_t)jobs, sizeof *ws);
  if (ws == NULL) return -1;
  int active = 0, ended = 0, failed = 0, forwarded = 0, rc = 0, more = 1;
  const double t0 = now_s();
  for (;;) {
    while (more && *stop_count == 0 && active < jobs) {
      const int run = s->next(s->user);
      if (run <= 0) {
        more = 0;
        break;
      }
      int k = 0;
      while (ws[k].pid != 0) k++;
      if (start_worker(job, run, &ws[k], stop_count) != 0) {
        rc = -1;
        more = 0;
        break;
      }
      active++;
    }
    if (active == 0) break;
    int status = 0;
    pid_t pid = wait_worker(ws, jobs, &forwarded, &status, stop_count, stop_signal);
    if (pid < 0) break;
    for (int k = 0; k < jobs; k++) {
      if (ws[k].pid != pid) continue;
      vs_sweep_row row;
      finish_worker(&ws[k], status, &row);
      s->take(s->user, &row);
      failed += row.code != VS_SWEEP_OK && row.code != VS_SWEEP_INTERRUPTED;
      active--;
      ended++;
    }
    if (progress)
      fprintf(stderr, "\r  runs %d/%d done, %d running, %d failed, %.1f s   ", ended, todo,
              active, failed, now_s() - t0);
  }
  if (progress) fputs("\r\033[K", stderr);
  free(ws);
  return rc;
}
