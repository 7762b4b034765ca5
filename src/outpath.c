/* Output paths: what may be written (regular files only, never an input), and the lock file
 * that keeps two processes from writing the same output. */
#define _DEFAULT_SOURCE /* flock, O_NOFOLLOW */
#include "voussoir/outpath.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* A file's identity: the directory it is named in and its name there, and, when it exists, its
 * own device and inode. */
typedef struct {
  dev_t pdev, dev;
  ino_t pino, ino;
  int parent_ok, exists;
  char base[256];
} file_id;

/* The directory part of path ("." when there is none) into buf. */
static void dir_of(const char *path, char *buf, size_t size) {
  const char *slash = strrchr(path, '/');
  if (slash == NULL) snprintf(buf, size, ".");
  else if (slash == path) snprintf(buf, size, "/");
  else snprintf(buf, size, "%.*s", (int)(slash - path), path);
}

static void identify(const char *path, file_id *id) {
  memset(id, 0, sizeof *id);
  char dir[4096];
  struct stat st;
  dir_of(path, dir, sizeof dir);
  const char *slash = strrchr(path, '/');
  snprintf(id->base, sizeof id->base, "%s", slash != NULL ? slash + 1 : path);
  if (stat(dir, &st) == 0) {
    id->parent_ok = 1;
    id->pdev = st.st_dev;
    id->pino = st.st_ino;
  }
  if (stat(path, &st) == 0) {
    id->exists = 1;
    id->dev = st.st_dev;
    id->ino = st.st_ino;
  }
}

static int same_file(const file_id *a, const file_id *b) {
  if (a->exists && b->exists && a->dev == b->dev && a->ino == b->ino) return 1;
  return a->parent_ok && b->parent_ok && a->pdev == b->pdev && a->pino == b->pino &&
         strcmp(a->base, b->base) == 0;
}

static const char *kind_of(mode_t m) {
  if (S_ISLNK(m)) return "a symbolic link";
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

/* The longest suffix of a working name made from an output's: "<path>.lock" (vs_outlock_acquire),
 * "<path>.part" and "<path>.snap" (the record's working file and snapshot); ".tmp" is shorter. */
enum { SUFFIX_MAX = sizeof ".lock" - 1 };

/* An output's name is shown in messages and tables and written into its XDMF sidecar: it must
 * be printable text (vs_quote_clean: no control character, no escape sequence, well-formed
 * UTF-8), so that nothing that prints it can act on a terminal. A file's name (not a
 * directory's) must also leave room for its working names' suffix within the file system's
 * limits (NAME_MAX of its directory, PATH_MAX), so that "<name>.lock" cannot fail half-way
 * through with ENAMETOOLONG: refused here, before anything is created. */
static vs_status check_name(const char *path, int is_file, vs_error *err) {
  size_t bad = 0;
  if (!vs_quote_clean(path, &bad))
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: byte %zu of the name (0x%02x) is a control character or not UTF-8 "
                        "text (an output's name must be printable text)",
                        path, bad + 1, (unsigned)(unsigned char)path[bad]);
  if (!is_file) return VS_OK;
  char dir[4096];
  dir_of(path, dir, sizeof dir);
  long name_max = pathconf(dir, _PC_NAME_MAX);
  if (name_max <= 0) name_max = NAME_MAX;
  const char *slash = strrchr(path, '/');
  const size_t base = strlen(slash != NULL ? slash + 1 : path);
  if (base + SUFFIX_MAX > (size_t)name_max)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: file name too long: %zu bytes (at most %ld, so that its lock file "
                        "and working copy, NAME.lock and NAME.part, fit the file system's limit "
                        "of %ld bytes)",
                        path, base, name_max - (long)SUFFIX_MAX, name_max);
  if (strlen(path) + SUFFIX_MAX >= PATH_MAX)
    return vs_error_set(err, VS_ERR_INVALID, "%s: path too long: %zu bytes (at most %ld)", path,
                        strlen(path), (long)(PATH_MAX - 1 - SUFFIX_MAX));
  return VS_OK;
}

/* The directory that will hold path must exist, be a directory and be writable. */
static vs_status check_parent(const char *path, vs_error *err) {
  char dir[4096];
  struct stat st;
  dir_of(path, dir, sizeof dir);
  if (stat(dir, &st) != 0)
    return vs_error_set(err, VS_ERR_INVALID, "%s: directory %s: %s", path, dir, strerror(errno));
  if (!S_ISDIR(st.st_mode))
    return vs_error_set(err, VS_ERR_INVALID, "%s: %s is not a directory", path, dir);
  if (access(dir, W_OK | X_OK) != 0)
    return vs_error_set(err, VS_ERR_INVALID, "%s: directory %s: %s", path, dir, strerror(errno));
  return VS_OK;
}

vs_status vs_outpath_check(const char *path, const vs_outpath_other *others, int n_others,
                           vs_error *err) {
  struct stat st;
  if (path == NULL || path[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "empty output path");
  if (path[strlen(path) - 1] == '/')
    return vs_error_set(err, VS_ERR_INVALID, "%s: names a directory, not a file", path);
  vs_status s = check_name(path, 1, err);
  if (s != VS_OK) return s;
  if (lstat(path, &st) == 0) {
    if (!S_ISREG(st.st_mode))
      return vs_error_set(err, VS_ERR_INVALID,
                          "%s: exists and is %s (an output must be a regular file or absent)",
                          path, kind_of(st.st_mode));
  } else if (errno != ENOENT) {
    return vs_error_set(err, VS_ERR_INVALID, "%s: %s", path, strerror(errno));
  }
  s = check_parent(path, err);
  if (s != VS_OK) return s;
  file_id me, other;
  identify(path, &me);
  for (int i = 0; i < n_others; i++) {
    if (others[i].path == NULL) continue;
    identify(others[i].path, &other);
    if (same_file(&me, &other))
      return vs_error_set(err, VS_ERR_INVALID, "%s: is the same file as %s %s", path,
                          others[i].role, others[i].path);
  }
  return VS_OK;
}

vs_status vs_outpath_check_dir(const char *dir, vs_error *err) {
  struct stat st;
  if (dir == NULL || dir[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "empty output directory");
  const vs_status s = check_name(dir, 0, err);
  if (s != VS_OK) return s;
  if (lstat(dir, &st) == 0) {
    if (!S_ISDIR(st.st_mode))
      return vs_error_set(err, VS_ERR_INVALID,
                          "%s: exists and is %s (an output directory must be a directory or "
                          "absent)",
                          dir, S_ISREG(st.st_mode) ? "a regular file" : kind_of(st.st_mode));
    if (access(dir, W_OK | X_OK) != 0)
      return vs_error_set(err, VS_ERR_INVALID, "%s: %s", dir, strerror(errno));
    return VS_OK;
  }
  if (errno != ENOENT) return vs_error_set(err, VS_ERR_INVALID, "%s: %s", dir, strerror(errno));
  return check_parent(dir, err);
}

/* Fault injection for the race tests: where the environment variable VS_FAULT_FIFO names this
 * path and nothing is there, a FIFO is made there just before the check, as another process
 * could between the run's checks at its start and the rename (it never removes anything). */
static void fault_fifo(const char *path) {
  const char *v = getenv("VS_FAULT_FIFO");
  struct stat st;
  if (v != NULL && strcmp(v, path) == 0 && lstat(path, &st) != 0 && errno == ENOENT)
    (void)mkfifo(path, 0600);
}

int vs_outpath_replace(const char *from, const char *path) {
  fault_fifo(path);
  struct stat st;
  if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode)) return 1;
  return rename(from, path) == 0 ? 0 : -1;
}

/* ------------------------------------------------------------------------------------------ */
/* Lock                                                                                         */

struct vs_outlock {
  int fd;
  char *path; /* the lock file */
};

/* Open and lock the lock file once; 1: locked (*fd set), 0: retry (the file was replaced or
 * removed under us), < 0: failed (err set). */
static int lock_once(const char *target, const char *lp, int *fd, vs_error *err) {
  struct stat st, st2;
  if (lstat(lp, &st) == 0 && !S_ISREG(st.st_mode)) {
    vs_error_set(err, VS_ERR_INVALID, "%s: its lock file %s is %s", target, lp,
                 kind_of(st.st_mode));
    return -1;
  }
  int f = open(lp, O_RDWR | O_CREAT | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC, 0644);
  if (f < 0) {
    vs_error_set(err, VS_ERR_IO, "%s: cannot create the lock file %s: %s", target, lp,
                 strerror(errno));
    return -1;
  }
  if (fstat(f, &st) != 0 || !S_ISREG(st.st_mode)) {
    close(f);
    vs_error_set(err, VS_ERR_INVALID, "%s: its lock file %s is not a regular file", target, lp);
    return -1;
  }
  if (flock(f, LOCK_EX | LOCK_NB) != 0) {
    char pid[32] = "";
    const ssize_t n = pread(f, pid, sizeof pid - 1, 0);
    pid[n > 0 ? n : 0] = '\0';
    pid[strcspn(pid, "\n")] = '\0';
    close(f);
    vs_error_set(err, VS_ERR_INVALID, "%s: being written by another process (pid %s, lock %s)",
                 target, pid[0] ? pid : "unknown", lp);
    return -1;
  }
  /* the holder removes its lock file when it is done: ours must still be the one at lp */
  if (stat(lp, &st2) != 0 || st2.st_dev != st.st_dev || st2.st_ino != st.st_ino) {
    close(f);
    return 0;
  }
  char pid[32];
  const int n = snprintf(pid, sizeof pid, "%ld\n", (long)getpid());
  if (ftruncate(f, 0) != 0 || pwrite(f, pid, (size_t)n, 0) != n) { /* only informative */
  }
  *fd = f;
  return 1;
}

/* Attempts at a lock file that keeps being replaced (each replacement means another process
 * finished with it in between). */
enum { VS_OUTLOCK_ATTEMPTS = 100 };

vs_status vs_outlock_acquire(const char *path, vs_outlock **out, vs_error *err) {
  *out = NULL;
  vs_outlock *l = calloc(1, sizeof *l);
  const size_t n = strlen(path) + sizeof ".lock";
  if (l == NULL || (l->path = malloc(n)) == NULL) {
    free(l);
    return vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory", path);
  }
  snprintf(l->path, n, "%s.lock", path);
  vs_error e;
  vs_error_set(&e, VS_ERR_INVALID, "%s: its lock file %s keeps being replaced", path, l->path);
  for (int i = 0; i < VS_OUTLOCK_ATTEMPTS; i++) {
    const int r = lock_once(path, l->path, &l->fd, &e);
    if (r == 0) continue;
    if (r < 0) break;
    *out = l;
    return VS_OK;
  }
  free(l->path);
  free(l);
  if (err != NULL) *err = e;
  return e.status;
}

void vs_outlock_release(vs_outlock **lp) {
  if (lp == NULL || *lp == NULL) return;
  vs_outlock *l = *lp;
  unlink(l->path); /* while still locked: a waiting process then sees it replaced and retries */
  close(l->fd);
  free(l->path);
  free(l);
  *lp = NULL;
}
