/* What the tests of the study commands (test_sweep.c, test_montecarlo.c) share: the program
 * started as a process of this one, the processes it forks, a file's bytes, and the journal's
 * checksum computed here again. Included after cmocka.h; VS_BINARY names the program. */
#ifndef VS_TEST_STUDY_PROCS_H
#define VS_TEST_STUDY_PROCS_H

#include <dirent.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* Start "voussoir ARGS..." with stdout and stderr to files; returns its pid. */
static inline pid_t spawn(char *const argv[], const char *out, const char *err) {
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    if (freopen(out, "w", stdout) == NULL || freopen(err, "w", stderr) == NULL) _exit(127);
    execv(VS_BINARY, argv);
    _exit(127);
  }
  return pid;
}

static inline int exit_code(pid_t pid) {
  int st = 0;
  assert_int_equal(waitpid(pid, &st, 0), pid);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* How an orphaned worker of a killed study may end (wait status st): killed with it (its
 * parent-death signal, SIGKILL), or, when the study died before the worker had set that signal
 * up (a worker stopped just after fork, as a loaded machine may leave it), ended at once by the
 * check that follows (exit status 130), before it ran anything. */
static inline int died_with_study(int st) {
  return (WIFSIGNALED(st) && WTERMSIG(st) == SIGKILL) || (WIFEXITED(st) && WEXITSTATUS(st) == 130);
}

/* The pids of the children of process parent (from /proc), at most max; how many. */
static inline int children_of(pid_t parent, pid_t *out, int max) {
  DIR *d = opendir("/proc");
  assert_non_null(d);
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL && n < max) {
    if (e->d_name[0] < '1' || e->d_name[0] > '9') continue;
    char path[300], buf[512] = "";
    snprintf(path, sizeof path, "/proc/%s/stat", e->d_name);
    FILE *f = fopen(path, "r");
    if (f == NULL) continue;
    const size_t k = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[k] = '\0';
    const char *end = strrchr(buf, ')'); /* "pid (comm) state ppid ..." */
    long ppid = 0;
    if (end != NULL && sscanf(end + 1, " %*c %ld", &ppid) == 1 && ppid == (long)parent)
      out[n++] = (pid_t)atol(e->d_name);
  }
  closedir(d);
  return n;
}

/* Wait until ready(arg) while process pid runs (at most 600 s); polls every 10 ms. */
static inline void wait_until(int (*ready)(const void *arg), const void *arg, pid_t pid,
                              const char *what) {
  for (int i = 0; !ready(arg); i++) {
    if (i > 60000) fail_msg("not %s after 600 s", what);
    if (waitpid(pid, NULL, WNOHANG) == pid) fail_msg("process %d ended before %s", (int)pid, what);
    nanosleep(&(struct timespec){0, 10000000}, NULL);
  }
}

/* A whole file (NUL-terminated after its n bytes); *n: its size. */
static inline unsigned char *load_file(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) fail_msg("%s: missing", path);
  assert_int_equal(fseek(f, 0, SEEK_END), 0);
  const long size = ftell(f);
  rewind(f);
  unsigned char *b = malloc((size_t)size + 1);
  assert_non_null(b);
  assert_int_equal(fread(b, 1, (size_t)size, f), (size_t)size);
  fclose(f);
  b[size] = '\0';
  *n = (size_t)size;
  return b;
}

/* FNV-1a 64 of n bytes, the journal's documented checksum (src/journal.h), written here again
 * so that the tests do not take the program's word for it. */
static inline uint64_t fnv1a64(const unsigned char *p, size_t n) {
  uint64_t h = 0xcbf29ce484222325u;
  for (size_t i = 0; i < n; i++) h = (h ^ p[i]) * 0x100000001b3u;
  return h;
}

/* Whether the 8 bytes after the n bytes at row are their checksum (little endian). */
static inline int sum_holds(const unsigned char *row, size_t n) {
  const uint64_t h = fnv1a64(row, n);
  for (int b = 0; b < 8; b++)
    if (row[n + (size_t)b] != (unsigned char)(h >> (8 * b))) return 0;
  return 1;
}

/* Make the 8 bytes after the n bytes at row their checksum again. */
static inline void set_sum(unsigned char *row, size_t n) {
  const uint64_t h = fnv1a64(row, n);
  for (int b = 0; b < 8; b++) row[n + (size_t)b] = (unsigned char)(h >> (8 * b));
}

#endif
