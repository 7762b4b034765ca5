/* For the tests that run the program in a scratch directory (test_quote, test_exit_status,
 * test_merge, test_wall_time): the directory (made by scratch_setup under /tmp, removed whole by
 * scratch_teardown: a cmocka group's setup and teardown), names in it, the program run there
 * with its output captured, files read back. Header-only (static inline): each test is one
 * executable. Define VS_SCRATCH (the directory's name, "quote") and include it after cmocka.h. */
#ifndef VS_TEST_SCRATCH_H
#define VS_TEST_SCRATCH_H

#include <dirent.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef VS_BINARY
#error "VS_BINARY (path of the voussoir executable) must be defined"
#endif
#ifndef VS_SCRATCH
#error "VS_SCRATCH (the scratch directory's name) must be defined"
#endif

static char g_dir[64]; /* the scratch directory: every run's working directory */

/* Make the scratch directory /tmp/vs_test_VS_SCRATCH_XXXXXX; 0 or -1. */
static inline int scratch_setup(void **state) {
  (void)state;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_%s_XXXXXX", VS_SCRATCH);
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

/* argv run in g_dir with stdout and stderr into g_dir/out.txt and err.txt, passed as it is (no
 * shell: any byte reaches the program); the exit status, or -1 when it did not exit. */
static inline int run_argv(char *const argv[]) {
  const pid_t pid = fork();
  if (pid == 0) {
    char out[128], err[128];
    snprintf(out, sizeof out, "%s/out.txt", g_dir);
    snprintf(err, sizeof err, "%s/err.txt", g_dir);
    const int fo = open(out, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fo < 0 || fe < 0 || dup2(fo, 1) < 0 || dup2(fe, 2) < 0 || chdir(g_dir) != 0) _exit(126);
    execv(argv[0], argv);
    _exit(127);
  }
  int st = 0;
  if (pid < 0 || waitpid(pid, &st, 0) != pid) return -1;
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* A shell command; its exit status, or -1. */
static inline int sh(const char *cmd) {
  const int st = system(cmd);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* Remove the scratch directory and all in it (names with any byte: no shell); 0 or -1. */
static inline int scratch_teardown(void **state) {
  (void)state;
  char *rm[] = {"/bin/rm", "-rf", "--", g_dir, NULL};
  return run_argv(rm) == 0 ? 0 : -1;
}

/* g_dir/name, in one of four rotating buffers. */
static inline const char *in_dir(const char *name) {
  static char buf[4][512];
  static int k = 0;
  k = (k + 1) % 4;
  snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
  return buf[k];
}

/* The whole file (at most 1 MiB), NUL-terminated, in a buffer the next call reuses; its length
 * in *n (NULL allowed). Fails the test when it cannot be read. */
static inline char *slurp(const char *path, size_t *n) {
  static char text[1 << 20];
  FILE *f = fopen(path, "rb");
  if (f == NULL) fail_msg("%s: cannot read", path);
  const size_t got = fread(text, 1, sizeof text - 1, f);
  text[got] = '\0';
  fclose(f);
  if (n != NULL) *n = got;
  return text;
}

/* The names in g_dir but the captured outputs, one a line (to compare before and after a run
 * that must write nothing). */
static inline void listing(char *buf, size_t size) {
  buf[0] = '\0';
  DIR *d = opendir(g_dir);
  if (d == NULL) fail_msg("%s: cannot list", g_dir);
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d))
    if (strcmp(e->d_name, "out.txt") != 0 && strcmp(e->d_name, "err.txt") != 0) {
      strncat(buf, e->d_name, size - strlen(buf) - 2);
      strcat(buf, "\n");
    }
  closedir(d);
}

#endif
