/* Whole-buffer reads and writes on a pipe, retried on EINTR: how a forked worker hands its
 * result (a plain struct) back to the process that forked it (sweep and montecarlo). Private to
 * the executable. */
#ifndef VS_PIPE_IO_H
#define VS_PIPE_IO_H

#include <errno.h>
#include <stddef.h>
#include <unistd.h>

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

#endif
