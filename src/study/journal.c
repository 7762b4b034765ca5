/* The manifests, journals and directory locks of sweep and montecarlo (src/study/journal.h). */
#define _DEFAULT_SOURCE /* fileno, ftruncate, pread, O_NOFOLLOW */
#include "journal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "outpath.h"
#include "voussoir/run.h"

/* A text key's value (a path: at most 32 points of 4 numbers of %.17g and their separators). */
#define VS_MANIFEST_TEXT_MAX 4096

char *vs_manifest_case(const vs_case *c, size_t extra) {
  const int nk = vs_case_key_count();
  /* a number's line at most 96 bytes; a file name's or a list's at most these; a support's
   * path's at most VS_MANIFEST_TEXT_MAX */
  enum { TEXT_MAX = VS_ARCH_PATH_MAX + 32 * VS_ARCH_MAX_POSITIONS };
  const size_t cap = (96 + TEXT_MAX) * (size_t)nk +
                     (size_t)vs_case_text_key_count() * (VS_MANIFEST_TEXT_MAX + 96) + extra + 1;
  char *t = malloc(cap), *text = malloc(TEXT_MAX > VS_MANIFEST_TEXT_MAX ? TEXT_MAX
                                                                         : VS_MANIFEST_TEXT_MAX);
  if (t == NULL || text == NULL) {
    free(t), free(text);
    return NULL;
  }
  size_t used = 0;
  t[0] = '\0';
  for (int i = 0; i < nk; i++) {
    const char *sec, *key;
    double v;
    vs_case_key(c, i, &sec, &key, NULL, NULL, &v);
    if (vs_case_key_text(c, i, text, TEXT_MAX) == 1)
      used += (size_t)snprintf(t + used, cap - used, "%s.%s=%s\n", sec, key, text);
    else
      used += (size_t)snprintf(t + used, cap - used, "%s.%s=%.17g\n", sec, key, v);
  }
  /* a support's path, when there is one (a manifest of a case without stays as it was) */
  for (int i = 0; i < vs_case_text_key_count(); i++) {
    const char *sec, *key;
    vs_case_text_key(c, i, &sec, &key, text, VS_MANIFEST_TEXT_MAX);
    if (text[0] != '\0')
      used += (size_t)snprintf(t + used, cap - used, "%s.%s=%s\n", sec, key, text);
  }
  free(text);
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

uint64_t vs_journal_sum(const void *p, size_t n) {
  const unsigned char *b = p;
  uint64_t h = 0xcbf29ce484222325u; /* FNV-1a 64: offset basis and prime */
  for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 0x100000001b3u;
  return h;
}

static void put_sum(unsigned char *out, uint64_t h) {
  for (int i = 0; i < VS_JOURNAL_SUM; i++) out[i] = (unsigned char)(h >> (8 * i));
}

/* Whether the checksum after the size bytes of a journal row is theirs. */
static int sum_holds(const unsigned char *row, size_t size) {
  unsigned char want[VS_JOURNAL_SUM];
  put_sum(want, vs_journal_sum(row, size));
  return memcmp(want, row + size, VS_JOURNAL_SUM) == 0;
}

/* Up to n bytes at offset off, fewer only at the end of the file: how many, or -1 (errno). */
static ssize_t read_at(int fd, void *buf, size_t n, off_t off) {
  size_t got = 0;
  while (got < n) {
    const ssize_t k = pread(fd, (char *)buf + got, n - got, off + (off_t)got);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) return -1;
    if (k == 0) break;
    got += (size_t)k;
  }
  return (ssize_t)got;
}

static int write_at(int fd, const void *buf, size_t n, off_t off) {
  size_t put = 0;
  while (put < n) {
    const ssize_t k = pwrite(fd, (const char *)buf + put, n - put, off + (off_t)put);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    put += (size_t)k;
  }
  return 0;
}

/* The journal's header: 0 it is head, 1 a kill cut it short (an empty journal), -1 another
 * (or unreadable: VS_JOURNAL_IO). */
static int read_head(int fd, const char *head, char *buf) {
  const size_t hl = strlen(head);
  const ssize_t got = read_at(fd, buf, hl, 0);
  if (got < 0) return VS_JOURNAL_IO;
  if (memcmp(buf, head, (size_t)got) != 0) return -1;
  return (size_t)got < hl ? 1 : 0;
}

/* The rows of an open journal, those refused reported and overwritten by the ones after them. */
static int read_rows(int fd, const char *path, size_t hl, size_t size, const char *who,
                     vs_journal_take_fn take, void *user, unsigned char *buf, long *rows) {
  const size_t stored = size + VS_JOURNAL_SUM;
  long w = 0;
  for (long i = 0;; i++) {
    const ssize_t got = read_at(fd, buf, stored, (off_t)hl + (off_t)i * (off_t)stored);
    if (got < 0) return VS_JOURNAL_IO;
    if ((size_t)got < stored) break; /* the end, or a last row a kill cut short */
    char why[256] = "refused";
    if (!sum_holds(buf, size)) {
      snprintf(why, sizeof why, "its checksum does not match its bytes (a damaged row)");
    } else if (take(user, buf, why, sizeof why)) {
      if (w != i && write_at(fd, buf, stored, (off_t)hl + (off_t)w * (off_t)stored) != 0)
        return VS_JOURNAL_IO;
      *rows = ++w;
      continue;
    }
    fprintf(stderr, "%s: --resume: %s: row %ld: %s: not counted as done, so it runs again\n",
            who, path, i + 1, why);
  }
  return 0;
}

int vs_journal_read(const char *path, const char *head, size_t size, const char *who,
                    vs_journal_take_fn take, void *user, long *rows) {
  *rows = 0;
  const int fd = open(path, O_RDWR | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT ? 0 : VS_JOURNAL_IO;
  const size_t hl = strlen(head), stored = size + VS_JOURNAL_SUM;
  unsigned char *buf = malloc(hl + 1 > stored ? hl + 1 : stored);
  int rc = VS_JOURNAL_IO;
  if (buf != NULL) {
    const int h = read_head(fd, head, (char *)buf); /* cut short (1): no row */
    rc = h == -1 ? VS_JOURNAL_FOREIGN
         : h != 0 ? (h > 0 ? 0 : h)
                  : read_rows(fd, path, hl, size, who, take, user, buf, rows);
  }
  const int e = errno;
  free(buf);
  close(fd);
  errno = e;
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
    const off_t end = (off_t)strlen(head) + (off_t)rows * (off_t)(size + VS_JOURNAL_SUM);
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
  unsigned char sum[VS_JOURNAL_SUM];
  put_sum(sum, vs_journal_sum(row, size));
  /* one flush: the row and its checksum reach the file in one write when they fit the buffer */
  return fwrite(row, size, 1, f) == 1 && fwrite(sum, sizeof sum, 1, f) == 1 && fflush(f) == 0
             ? 0
             : -1;
}

/* --- the rows' fields --- */

/* Whether text is NUL-terminated within its n bytes. */
static int terminated(const char *text, size_t n) { return memchr(text, '\0', n) != NULL; }

/* Whether every character of text is one of allowed. */
static int made_of(const char *text, const char *allowed) {
  return text[strspn(text, allowed)] == '\0';
}

/* A displacement or a time: finite and >= 0; or that, or NaN (none). */
static int size_ok(double v) { return isfinite(v) && v >= 0.0; }
static int none_or_size(double v) { return isnan(v) || size_ok(v); }

/* The fault, into why; 0 (the row's verdict). */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static int refuse(char *why, size_t size, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(why, size, fmt, ap);
  va_end(ap);
  return 0;
}

/* The texts of a sweep row: terminated, then each within what a run writes there. */
static int sweep_texts_ok(const vs_sweep_row *row, char *why, size_t size) {
  static const char *const done[] = {"collapse", "limit_point", "max_displacement"};
  const struct {
    const char *name, *text;
    size_t n;
  } t[] = {{"status", row->status, sizeof row->status},
           {"mode", row->mode, sizeof row->mode},
           {"hinges", row->hinges, sizeof row->hinges},
           {"error", row->error, sizeof row->error},
           {"first_crack_side", row->first_crack_side, sizeof row->first_crack_side}};
  for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
    if (!terminated(t[i].text, t[i].n))
      return refuse(why, size, "%s is not NUL-terminated in its %zu bytes", t[i].name, t[i].n);
  int known = 0;
  for (size_t i = 0; i < sizeof done / sizeof done[0]; i++)
    known |= row->code == VS_SWEEP_OK && strcmp(row->status, done[i]) == 0;
  /* a failed run, or one its wall-time limit stopped (journalled as failed: run.max_wall_s) */
  const int ended = strcmp(row->status, "failed") == 0 || strcmp(row->status, "stopped") == 0;
  if (!known && !(row->code == VS_SWEEP_FAILED && ended))
    return refuse(why, size, "status \"%.32s\" is not a %s run's", row->status,
                  row->code == VS_SWEEP_OK ? "finished" : "failed");
  if (row->mode[0] != '\0' && strcmp(row->mode, "I") != 0 && strcmp(row->mode, "II") != 0 &&
      strcmp(row->mode, "III") != 0)
    return refuse(why, size, "mode is not I, II, III or empty");
  /* labels (A-Z, a-z, then # and ? for none), joints, sides, "D:1-E A:9-10-I", and the end of
   * a list too long for the row, "+12 more" (vs_hinges_list) */
  static const char hinge_chars[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                    "0123456789#?:-+ ";
  if (!made_of(row->hinges, hinge_chars))
    return refuse(why, size, "hinges holds a character no hinge name has");
  if (row->code == VS_SWEEP_OK && row->error[0] != '\0')
    return refuse(why, size, "an error for a run that worked");
  return 1;
}

int vs_sweep_row_check(const vs_sweep_row *row, int total, int nax, char *why, size_t why_size) {
  if (row->run < 1 || row->run > total)
    return refuse(why, why_size, "run %d is not one of this sweep's 1..%d", row->run, total);
  if (row->code != VS_SWEEP_OK && row->code != VS_SWEEP_FAILED)
    return refuse(why, why_size, "code %d is not a finished run's (%d worked, %d failed)",
                  row->code, VS_SWEEP_OK, VS_SWEEP_FAILED);
  if (!sweep_texts_ok(row, why, why_size)) return 0;
  for (int x = 0; x < VS_SWEEP_MAX_AXES; x++)
    if (x < nax ? !isfinite(row->axis[x]) : row->axis[x] != 0.0)
      return refuse(why, why_size, "axis %d's value %g is not %s", x + 1, row->axis[x],
                    x < nax ? "finite" : "0 (no such axis)");
  if (!none_or_size(row->first_limit_mm) || !none_or_size(row->delta_u_mm))
    return refuse(why, why_size, "first_limit_mm %g, delta_u_mm %g: each must be >= 0 or NaN",
                  row->first_limit_mm, row->delta_u_mm);
  const int none = isnan(row->delta_u_mm);
  if ((none ? !isnan(row->dz_pct) || !isnan(row->dx_pct)
            : !isfinite(row->dz_pct) || !isfinite(row->dx_pct)))
    return refuse(why, why_size, "dz %g %%, dx %g %%: must be %s, as delta_u_mm is", row->dz_pct,
                  row->dx_pct, none ? "NaN" : "finite");
  const double tr[4] = {row->left_dx_mm, row->left_dz_mm, row->right_dx_mm, row->right_dz_mm};
  for (int k = 0; k < 4; k++)
    if (none ? !isnan(tr[k]) : !isfinite(tr[k]))
      return refuse(why, why_size, "support travel %g mm: must be %s, as delta_u_mm is", tr[k],
                    none ? "NaN" : "finite");
  if (!none_or_size(row->load_factor))
    return refuse(why, why_size, "load_factor %g is not >= 0 or NaN", row->load_factor);
  const int crack = !isnan(row->first_crack_mm);
  if ((row->mortared != 0 && row->mortared != 1) || (crack && !row->mortared) ||
      !none_or_size(row->first_crack_mm) ||
      (crack ? row->first_crack_joint < 1 || (strcmp(row->first_crack_side, "I") != 0 &&
                                               strcmp(row->first_crack_side, "E") != 0)
             : row->first_crack_joint != 0 || row->first_crack_side[0] != '\0'))
    return refuse(why, why_size, "first crack %g mm, joint %d, side \"%.1s\" (mortared %d): "
                  "a crack of a mortared run (>= 0 mm, a joint, I or E) or none (NaN, 0, \"\")",
                  row->first_crack_mm, row->first_crack_joint, row->first_crack_side,
                  row->mortared);
  if (!none_or_size(row->wall_s))
    return refuse(why, why_size, "wall_s %g is not >= 0 or NaN", row->wall_s);
  if (row->snaps < 0 || row->snaps > VS_RUN_MAX_LIMITS)
    return refuse(why, why_size, "snaps %d is not in 0..%d", row->snaps, VS_RUN_MAX_LIMITS);
  return 1;
}

/* The collapse fields of a montecarlo row: filled for a collapse, none otherwise. */
static int mc_collapse_ok(const vs_mc_sample *r, int joints, char *why, size_t size) {
  const int collapse = r->status == VS_MC_COLLAPSE;
  if (collapse ? !size_ok(r->delta_u_mm) || !isfinite(r->dz_u_mm) || !isfinite(r->dx_u_mm)
               : !isnan(r->delta_u_mm) || !isnan(r->dz_u_mm) || !isnan(r->dx_u_mm))
    return refuse(why, size, "delta_u_mm %g, dz_u_mm %g, dx_u_mm %g: %s", r->delta_u_mm,
                  r->dz_u_mm, r->dx_u_mm,
                  collapse ? "a collapse's are finite (delta_u_mm >= 0)"
                           : "NaN without a collapse");
  if (r->mode < 0 || r->mode > 3 || (!collapse && r->mode != 0))
    return refuse(why, size, "mode %d is not in 0..3 (0 without a collapse)", r->mode);
  for (int l = 0; l < VS_MC_LABELS; l++) {
    const int j = r->hinge_joint[l];
    const char side = r->hinge_side[l];
    if (j < 0 || j > joints || (j > 0) != (side == 'I' || side == 'E') ||
        (j == 0 && side != 0) || (!collapse && j != 0))
      return refuse(why, size, "hinge %c: joint %d, side %d: a joint in 1..%d with side I or E, "
                    "or none (0, 0)%s", 'A' + l, j, side, joints,
                    collapse ? "" : " without a collapse");
  }
  if (!collapse && r->pattern[0] != '\0')
    return refuse(why, size, "a hinge pattern without a collapse");
  return 1;
}

int vs_mc_sample_check(const vs_mc_sample *r, int samples, int shard_k, int shard_m, int joints,
                       char *why, size_t why_size) {
  const int d = r->sample - (shard_k - 1);
  if (r->sample < 0 || r->sample >= samples || d < 0 || d % shard_m != 0)
    return refuse(why, why_size, "sample %d is not one of this study's (0..%d, shard %d/%d)",
                  r->sample, samples - 1, shard_k, shard_m);
  if (r->status < VS_MC_COLLAPSE || r->status > VS_MC_FAILED)
    return refuse(why, why_size, "status %d is not in %d..%d", r->status, VS_MC_COLLAPSE,
                  VS_MC_FAILED);
  if (!terminated(r->pattern, sizeof r->pattern) || !made_of(r->pattern, "IE-"))
    return refuse(why, why_size, "pattern is not NUL-terminated in its %zu bytes, or holds "
                  "other than I, E and '-'", sizeof r->pattern);
  if (!terminated(r->error, sizeof r->error))
    return refuse(why, why_size, "error is not NUL-terminated in its %zu bytes", sizeof r->error);
  if (r->status != VS_MC_FAILED && r->error[0] != '\0')
    return refuse(why, why_size, "an error for a sample that did not fail");
  if (!none_or_size(r->first_limit_mm))
    return refuse(why, why_size, "first_limit_mm %g is not >= 0 or NaN", r->first_limit_mm);
  return mc_collapse_ok(r, joints, why, why_size);
}

/* --- the study's lock --- */

/* Whether process pid still runs (or runs under another user). A zombie does not: it holds no
 * file, and the killed study stays one until its parent waits for it. */
static int alive(long pid) {
  if (kill((pid_t)pid, 0) != 0 && errno != EPERM) return 0;
  char path[64], stat[256] = "";
  snprintf(path, sizeof path, "/proc/%ld/stat", pid);
  FILE *f = fopen(path, "r");
  const size_t n = f != NULL ? fread(stat, 1, sizeof stat - 1, f) : 0;
  if (f != NULL) fclose(f);
  stat[n] = '\0';
  const char *end = strrchr(stat, ')'); /* "pid (comm) S ...": comm may hold anything */
  return end == NULL || end[1] == '\0' || (end[2] != 'Z' && end[2] != 'X');
}

vs_status vs_study_lock(const char *dir, const char *who, vs_outlock **out, vs_error *err) {
  char base[4096];
  const int n = snprintf(base, sizeof base, "%s/%s", dir, VS_STUDY_LOCK);
  if (n < 0 || (size_t)n + sizeof ".lock" > sizeof base)
    return vs_error_set(err, VS_ERR_INVALID, "-o %.64s...: directory name too long", dir);
  const int polls = VS_STUDY_LOCK_WAIT_S * 50; /* every 20 ms */
  for (int i = 0;; i++) {
    vs_error e;
    vs_error_clear(&e);
    const vs_status st = vs_outlock_acquire(base, out, &e);
    if (st == VS_OK) return VS_OK;
    const long pid = vs_outlock_holder(base);
    if (st != VS_ERR_INVALID || pid <= 0) { /* not a lock held by a study: the OS's reason */
      if (err != NULL) *err = e;
      return st;
    }
    if (alive(pid))
      return vs_error_set(err, st, "another study (pid %ld) is under way in -o %s (lock "
                          "%s.lock): one study at a time in a directory", pid, dir, base);
    if (i == polls)
      return vs_error_set(err, st, "the workers of a study that ended (pid %ld) still hold the "
                          "lock %s.lock after %d s (fuser shows them)", pid, base,
                          VS_STUDY_LOCK_WAIT_S);
    if (i == 0)
      fprintf(stderr, "%s: -o %s: waiting for the workers of a study that ended (pid %ld) to "
              "end too\n", who, dir, pid);
    nanosleep(&(struct timespec){0, 20000000}, NULL);
  }
}
