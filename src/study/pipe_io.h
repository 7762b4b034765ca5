/* Whole-buffer reads and writes on a pipe, retried on EINTR: how a forked worker hands its
 * result (a plain struct) back to the process that forked it (sweep and montecarlo); and the
 * worker's tie to that process. Private to the executable. */
#ifndef VS_PIPE_IO_H
#define VS_PIPE_IO_H

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stddef.h>
#include <stdlib.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

/* Write all n bytes of buf to fd: 0, or -1 on an error or a closed pipe. */
static inline int vs_write_all(int fd, const void *buf, size_t n) {
  const char *p = buf;
  while (n > 0) {
    ssize_t k = write(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    p += k;
    n -= (size_t)k;
  }
  return 0;
}

/* Read up to n bytes from fd into buf, until n or end of file or an error: the bytes read. */
static inline size_t vs_read_full(int fd, void *buf, size_t n) {
  char *p = buf;
  size_t got = 0;
  while (got < n) {
    ssize_t k = read(fd, p + got, n - got);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) break;
    got += (size_t)k;
  }
  return got;
}

/* First thing in a forked worker: it ends with the study that forked it (pid parent), at once.
 * SIGKILL, not SIGTERM: the worker inherits the study's SIGTERM handler, under which its run
 * would go on to the end of its step and close its record, while it holds the study's directory
 * lock and its run's lock, so that a --resume started right after the kill found them taken.
 * A parent that died before the prctl: the worker ends here. */
static inline void vs_worker_tie(pid_t parent) {
#ifdef __linux__
  prctl(PR_SET_PDEATHSIG, SIGKILL);
#endif
  if (getppid() != parent) _exit(130);
}

/* Fault injection for the tests: with the environment variable VS_FAULT_HOLD = N, the worker of
 * run (or sample) N waits, its case begun, until its stop flag is raised or the file that
 * VS_FAULT_RELEASE names exists, so that a test finds the study with that case under way however
 * fast the machine runs it (it waits for an observable state, then signals, kills, or releases
 * it: no race). Polls (10 ms): neither can be waited on otherwise. At most 600 s, so that a test
 * that fails before releasing it leaves no process waiting for ever. The file VS_FAULT_HELD
 * names, if any, is created once it holds: the worker is then past vs_worker_tie. */
static inline void vs_fault_hold(int id, const volatile sig_atomic_t *stop) {
  const char *v = getenv("VS_FAULT_HOLD"), *release = getenv("VS_FAULT_RELEASE");
  const char *held = getenv("VS_FAULT_HELD");
  if (v == NULL || stop == NULL || atoi(v) != id) return;
  if (held != NULL) {
    const int fd = open(held, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) close(fd);
  }
  for (int i = 0; i < 60000 && !*stop && !(release != NULL && access(release, F_OK) == 0); i++)
    nanosleep(&(struct timespec){0, 10000000}, NULL);
}

#endif
