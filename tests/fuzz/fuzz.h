/* What the fuzz targets (tests/fuzz/fuzz_*.c) share: their own reports, which go to a copy of
 * stderr taken when the target starts (run.sh closes the target's stdout and stderr,
 * -close_fd_mask=3, so that the program's messages for every input stay out of the log), a
 * check that aborts with its line, a scratch directory, and a file read whole. Each target
 * defines _POSIX_C_SOURCE 200809L and FUZZ_NAME before including this. */
#ifndef VS_FUZZ_H
#define VS_FUZZ_H

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

static FILE *fuzz_report;
#define FUZZ_REPORT (fuzz_report != NULL ? fuzz_report : stderr)

#define CHECK(cond)                                                                               \
  do {                                                                                            \
    if (!(cond)) {                                                                                \
      fprintf(FUZZ_REPORT, "%s: check failed: %s (line %d)\n", FUZZ_NAME, #cond, __LINE__);      \
      abort();                                                                                    \
    }                                                                                             \
  } while (0)

/* The copy of stderr for the reports: from LLVMFuzzerInitialize, which runs before libFuzzer
 * closes the target's. */
static inline void fuzz_report_open(void) {
  const int fd = dup(2);
  if (fd >= 0 && (fuzz_report = fdopen(fd, "w")) != NULL) setvbuf(fuzz_report, NULL, _IONBF, 0);
}

/* A new directory $TMPDIR/FUZZ_NAME.XXXXXX (run.sh points TMPDIR at memory) into dir. */
static inline void fuzz_scratch(char *dir, size_t size) {
  const char *tmp = getenv("TMPDIR");
  CHECK((size_t)snprintf(dir, size, "%s/%s.XXXXXX", tmp && *tmp ? tmp : "/tmp", FUZZ_NAME) <
        size);
  CHECK(mkdtemp(dir) != NULL);
}

/* The whole file at path, malloc'd, with a NUL after its *n bytes; NULL if it cannot be opened. */
static inline char *fuzz_slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  size_t cap = 4096;
  char *buf = malloc(cap);
  CHECK(buf != NULL);
  *n = 0;
  for (size_t got; (got = fread(buf + *n, 1, cap - *n - 1, f)) > 0;) {
    *n += got;
    if (*n + 1 == cap) CHECK((buf = realloc(buf, cap *= 2)) != NULL);
  }
  fclose(f);
  buf[*n] = '\0';
  return buf;
}

#endif
