/* The manifests and journals of sweep and montecarlo (src/study/journal.h). */
#define _DEFAULT_SOURCE /* fileno, ftruncate, O_NOFOLLOW */
#include "journal.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "outpath.h"

char *vs_manifest_case(const vs_case *c, size_t extra) {
  const int nk = vs_case_key_count();
  const size_t cap = 96 * (size_t)nk + extra + 1;
  char *t = malloc(cap);
  if (t == NULL) return NULL;
  size_t used = 0;
  t[0] = '\0';
  for (int i = 0; i < nk; i++) {
    const char *sec, *key;
    double v;
    vs_case_key(c, i, &sec, &key, NULL, NULL, &v);
    used += (size_t)snprintf(t + used, cap - used, "%s.%s=%.17g\n", sec, key, v);
  }
  return t;
}

int vs_manifest_same(const char *path, const char *text) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return -1;
  const size_t n = strlen(text);
  char *buf = malloc(n + 1);
  /* one byte more than the text: a longer manifest is another */
  const size_t got = buf != NULL ? fread(buf, 1, n + 1, f) : 0;
  const int rc = buf == NULL || ferror(f) ? -1 : got == n && memcmp(buf, text, n) == 0;
  free(buf);
  fclose(f);
  return rc;
}

int vs_journal_read(const char *path, const char *head, size_t size,
                    void (*take)(void *user, const void *row), void *user, long *rows) {
  *rows = 0;
  FILE *f = fopen(path, "rb");
  if (f == NULL) return 0;
  const size_t hl = strlen(head);
  char *buf = malloc(hl + 1 > size ? hl + 1 : size);
  const size_t got = buf != NULL ? fread(buf, 1, hl, f) : 0;
  /* a header cut short by a kill while it was written is an empty journal */
  int rc = buf != NULL && memcmp(buf, head, got) == 0 ? 0 : -1;
  if (got < hl) {
    free(buf);
    fclose(f);
    return rc;
  }
  while (rc == 0 && fread(buf, size, 1, f) == 1) {
    take(user, buf);
    (*rows)++;
  }
  free(buf);
  fclose(f);
  return rc;
}

/* The journal being resumed, opened to be cut and appended to: never through a link, nor
 * anything but a regular file (EINVAL). NULL with errno on failure. */
static FILE *reopen(const char *path) {
  const int fd = open(path, O_RDWR | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  struct stat st;
  FILE *f = NULL;
  if (fd >= 0 && fstat(fd, &st) == 0 && !S_ISREG(st.st_mode)) errno = EINVAL;
  else if (fd >= 0) f = fdopen(fd, "r+b");
  if (f == NULL && fd >= 0) {
    const int e = errno;
    close(fd);
    errno = e;
  }
  return f;
}

FILE *vs_journal_open(const char *path, const char *head, size_t size, long rows,
                      vs_error *err) {
  FILE *f = rows > 0 ? reopen(path) : NULL;
  if (f == NULL && (rows <= 0 || errno == ENOENT)) { /* fresh: no row to keep */
    if (vs_outpath_fopen(path, &f, err) != VS_OK) return NULL;
    if (fputs(head, f) >= 0 && fflush(f) == 0) return f;
  } else if (f != NULL) {
    const off_t end = (off_t)strlen(head) + (off_t)rows * (off_t)size;
    if (ftruncate(fileno(f), end) == 0 && fseek(f, 0, SEEK_END) == 0) return f;
  }
  vs_error_set(err, VS_ERR_IO, "%s: cannot write: %s", path,
               f != NULL         ? strerror(errno)
               : errno == EINVAL ? "not a regular file"
               : errno == ELOOP  ? "a symbolic link (not followed)"
                                 : strerror(errno));
  if (f != NULL) fclose(f);
  return NULL;
}

int vs_journal_append(FILE *f, const void *row, size_t size) {
  return fwrite(row, size, 1, f) == 1 && fflush(f) == 0 ? 0 : -1;
}
