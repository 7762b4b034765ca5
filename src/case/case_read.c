/* The case file reader (case.h: vs_case_read, vs_case_parse): the file read whole (a regular
 * file of bounded size), its lines handed to inih one at a time and normalised, each key = value
 * checked by the one assignment of case.c (case_internal.h). */
#define _POSIX_C_SOURCE 200809L /* open, fstat */
#include "voussoir/case.h"

#include <ini.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "case_internal.h"

/* ---------------------------------------------------------------------------------------------
 * The file reader. inih gets the text one line per call from next_line, so our line count is
 * exactly inih's and every message can name its line, whatever INI_HANDLER_LINENO the installed
 * libinih was built with. next_line also normalises each line so that inih's build options do not
 * change the meaning of a case file: leading blanks go (no multi-line continuations), ';' and '#'
 * comments go (at the start of a line, or after a blank), a UTF-8 byte-order mark goes. */

typedef struct {
  vs_case value;          /* working copy, committed only if the whole file is accepted */
  const char *path;
  const char *pos, *end;  /* unread text */
  int lineno;             /* line last handed to inih */
  int error_line;         /* line of the first error found by next_line or on_pair, 0 = none */
  vs_status status;
  vs_error *err;
} reader_ctx;

static const char *comment_start(const char *start, const char *stop) {
  for (const char *p = start; p < stop; p++)
    if ((*p == ';' || *p == '#') && (p == start || vs_case_is_blank(p[-1]))) return p;
  return stop;
}

static char *reader_fail(reader_ctx *x, vs_status status) {
  x->error_line = x->lineno;
  x->status = status;
  return NULL;
}

static char *next_line(char *buf, int size, void *stream) {
  reader_ctx *x = stream;
  if (x->error_line > 0 || x->pos >= x->end) return NULL;
  const char *start = x->pos, *stop = start;
  while (stop < x->end && *stop != '\n' && *stop != '\r') stop++;
  /* a line ends at LF, CR LF or a lone CR (old Mac files), so CR-only files read line by line */
  x->pos = stop;
  if (x->pos < x->end && *x->pos == '\r') x->pos++;
  if (x->pos < x->end && *x->pos == '\n') x->pos++;
  x->lineno++;

  if (memchr(start, '\0', (size_t)(stop - start)) != NULL) {
    vs_error_set(x->err, VS_ERR_PARSE, "%s:%d: NUL character (a case file is plain text)", x->path,
                 x->lineno);
    return reader_fail(x, VS_ERR_PARSE);
  }
  if (x->lineno == 1 && stop - start >= 3 && memcmp(start, "\xEF\xBB\xBF", 3) == 0) start += 3;
  while (start < stop && vs_case_is_blank(*start)) start++;
  stop = comment_start(start, stop);
  while (stop > start && vs_case_is_blank(stop[-1])) stop--;

  size_t len = (size_t)(stop - start);
  if (size < 1 || len >= (size_t)size) {
    vs_error_set(x->err, VS_ERR_PARSE,
                 "%s:%d: line too long (at most %d characters, not counting indentation and "
                 "comments)",
                 x->path, x->lineno, size > 0 ? size - 1 : 0);
    return reader_fail(x, VS_ERR_PARSE);
  }
  memcpy(buf, start, len);
  buf[len] = '\0';

  /* inih does not tell the handler about a section until it holds a key; check "[name]" here so
   * an unknown (even empty) section is reported on its own line. "[name" is left to inih. */
  const char *close = buf[0] == '[' ? strchr(buf, ']') : NULL;
  if (close != NULL && !vs_case_section_known(buf + 1, (size_t)(close - buf - 1))) {
    char list[256];
    vs_case_echo b;
    vs_case_list_sections(list, sizeof list);
    buf[close - buf] = '\0';
    vs_error_set(x->err, VS_ERR_PARSE, "%s:%d: [%s]: unknown section (allowed sections: %s)",
                 x->path, x->lineno, vs_case_clip(buf + 1, &b), list);
    return reader_fail(x, VS_ERR_PARSE);
  }
  if (close != NULL && close[1] != '\0') { /* inih would drop "radius_mm=3" in "[arch] radius_mm=3" */
    vs_case_echo b;
    while (vs_case_is_blank(*++close)) {}
    vs_error_set(x->err, VS_ERR_PARSE,
                 "%s:%d: '%s' after the section header (put each key = value on its own line)",
                 x->path, x->lineno, vs_case_clip(close, &b));
    return reader_fail(x, VS_ERR_PARSE);
  }
  return buf;
}

/* A relative blocks file names a file beside the case file: prefixed with the case's folder. */
static vs_status relative_to_case(reader_ctx *x, const char *where) {
  char *file = x->value.blocks_file;
  const char *slash = strrchr(x->path, '/');
  if (file[0] == '\0' || file[0] == '/' || slash == NULL) return VS_OK;
  const size_t dir = (size_t)(slash - x->path) + 1, len = strlen(file);
  if (dir + len >= sizeof x->value.blocks_file) {
    vs_case_echo b;
    return vs_error_set(x->err, VS_ERR_INVALID, "%s: arch.blocks_file = %s: too long beside the "
                        "case file (allowed: a file name of at most %d bytes with its folder)",
                        where, vs_case_clip(file, &b), VS_ARCH_PATH_MAX - 1);
  }
  memmove(file + dir, file, len + 1);
  memcpy(file, x->path, dir);
  return VS_OK;
}

static int on_pair_at_line(reader_ctx *x, const char *section, const char *name,
                           const char *value) {
  if (x->error_line > 0) return 0;
  if (name == NULL) return 1; /* start-of-section call, when inih is built to make one */
  char where[sizeof x->err->msg];
  snprintf(where, sizeof where, "%s:%d", x->path, x->lineno);
  vs_status st;
  if (name[0] == '\0') /* "= 3": inih accepts it, we do not */
    st = vs_error_set(x->err, VS_ERR_PARSE, "%s: malformed line (expected key = value or [section])",
                      where);
  else if (value == NULL) /* only when inih is built to allow keys without values */
    st = vs_error_set(x->err, VS_ERR_PARSE, "%s: %s.%s: no value (expected key = value)", where,
                      section, name);
  else
    st = vs_case_assign(&x->value, section, name, value, where, x->err);
  if (st == VS_OK && strcmp(section, "arch") == 0 && strcmp(name, "blocks_file") == 0)
    st = relative_to_case(x, where);
  if (st == VS_OK) return 1;
  x->error_line = x->lineno;
  x->status = st;
  return 0;
}

#if INI_HANDLER_LINENO
static int on_pair(void *user, const char *section, const char *name, const char *value,
                   int lineno) {
  (void)lineno; /* same as our own count */
  return on_pair_at_line(user, section, name, value);
}
#else
static int on_pair(void *user, const char *section, const char *name, const char *value) {
  return on_pair_at_line(user, section, name, value);
}
#endif

/* Refuse what is not a regular file of at most VS_CASE_MAX_BYTES: a FIFO would block, a device
 * such as /dev/zero would grow memory without bound. The file is opened without blocking (a FIFO
 * with no writer) and checked on the open descriptor, so a swap after the check does not matter. */
static vs_status open_case(const char *path, int *fd_out, size_t *size, vs_error *err) {
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) return vs_error_set(err, VS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat sb;
  vs_status st = VS_OK;
  if (fstat(fd, &sb) != 0)
    st = vs_error_set(err, VS_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
  else if (!S_ISREG(sb.st_mode))
    st = vs_error_set(err, VS_ERR_IO, "%s: not a regular file (a case must be a plain file, not a "
                                      "%s)", path, S_ISDIR(sb.st_mode) ? "directory"
                                      : S_ISFIFO(sb.st_mode) ? "pipe" : "device or socket");
  else if (sb.st_size > VS_CASE_MAX_BYTES)
    st = vs_error_set(err, VS_ERR_IO, "%s: %lld bytes: too large (a case file is at most %d bytes)",
                      path, (long long)sb.st_size, VS_CASE_MAX_BYTES);
  if (st != VS_OK) {
    close(fd);
    return st;
  }
  *fd_out = fd;
  *size = (size_t)sb.st_size;
  return VS_OK;
}

/* Read the whole file into a NUL-terminated malloc'd buffer; a file that grows past the limit
 * while it is read is refused too. */
static vs_status read_text(const char *path, char **text, size_t *len, vs_error *err) {
  int fd = -1;
  size_t size = 0;
  vs_status st = open_case(path, &fd, &size, err);
  if (st != VS_OK) return st;
  char *buf = malloc((size_t)VS_CASE_MAX_BYTES + 2);
  size_t used = 0;
  while (buf != NULL && used <= (size_t)VS_CASE_MAX_BYTES) {
    ssize_t n = read(fd, buf + used, (size_t)VS_CASE_MAX_BYTES + 1 - used);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      st = vs_error_set(err, VS_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
      break;
    }
    if (n == 0) break;
    used += (size_t)n;
  }
  close(fd);
  if (buf == NULL) return vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory reading the file", path);
  if (st == VS_OK && used > (size_t)VS_CASE_MAX_BYTES)
    st = vs_error_set(err, VS_ERR_IO, "%s: too large (a case file is at most %d bytes)", path,
                      VS_CASE_MAX_BYTES);
  if (st != VS_OK) {
    free(buf);
    return st;
  }
  buf[used] = '\0';
  *text = buf;
  *len = used;
  return VS_OK;
}

vs_status vs_case_parse(vs_case *c, const char *name, const char *text, size_t len,
                        vs_error *err) {
  if (c == NULL || name == NULL || text == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "vs_case_parse: %s is NULL",
                        c == NULL ? "case" : name == NULL ? "name" : "text");
  if (len > (size_t)VS_CASE_MAX_BYTES)
    return vs_error_set(err, VS_ERR_IO, "%s: too large (a case file is at most %d bytes)", name,
                        VS_CASE_MAX_BYTES);
  reader_ctx x = {.value = *c, .path = name, .pos = text, .end = text + len, .status = VS_OK,
                  .err = err};
  int ret = ini_parse_stream(next_line, &x, on_pair, &x);
  vs_status st = VS_OK;
  /* inih returns the first line it could not parse; ours may be earlier or later. */
  if (ret > 0 && (x.error_line == 0 || ret < x.error_line))
    st = vs_error_set(err, VS_ERR_PARSE, "%s:%d: malformed line (expected key = value or [section])",
                      name, ret);
  else if (x.error_line > 0)
    st = x.status;
  else if (ret < 0)
    st = vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory while parsing", name);
  if (st == VS_OK) *c = x.value;
  return st;
}

/* A blocks file the case file names by a relative name (beside the case file, whose own name
 * may be relative): made absolute from the working directory, so that a record's copy of the
 * case still finds it from elsewhere. */
static vs_status absolute(vs_case *c, const char *path, vs_error *err) {
  char cwd[VS_ARCH_PATH_MAX];
  if (c->blocks_file[0] == '/' || c->blocks_file[0] == '\0') return VS_OK;
  const size_t len = strlen(c->blocks_file);
  if (getcwd(cwd, sizeof cwd) == NULL || strlen(cwd) + 1 + len >= sizeof c->blocks_file) {
    vs_case_echo b;
    return vs_error_set(err, VS_ERR_INVALID, "%s: arch.blocks_file = %s: too long with the "
                        "working directory before it (allowed: a file name of at most %d bytes)",
                        path, vs_case_clip(c->blocks_file, &b), VS_ARCH_PATH_MAX - 1);
  }
  const size_t dir = strlen(cwd);
  memmove(c->blocks_file + dir + 1, c->blocks_file, len + 1);
  memcpy(c->blocks_file, cwd, dir);
  c->blocks_file[dir] = '/';
  return VS_OK;
}

vs_status vs_case_read(vs_case *c, const char *path, char **text_out, vs_error *err) {
  if (text_out != NULL) *text_out = NULL;
  if (c == NULL || path == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "vs_case_read: %s is NULL", c == NULL ? "case" : "path");
  char *text = NULL;
  size_t len = 0;
  vs_status st = read_text(path, &text, &len, err);
  vs_case v = *c;
  if (st == VS_OK) st = vs_case_parse(&v, path, text, len, err);
  if (st == VS_OK && strcmp(v.blocks_file, c->blocks_file) != 0) st = absolute(&v, path, err);
  if (st == VS_OK) *c = v;
  if (st != VS_OK) {
    free(text);
    return st;
  }
  if (text_out != NULL)
    *text_out = text;
  else
    free(text);
  return VS_OK;
}
