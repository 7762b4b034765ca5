/* Output paths: what may be written (regular files only, never an input), and the lock file
 * that keeps two processes from writing the same output. */
#define _DEFAULT_SOURCE /* flock, O_NOFOLLOW */
#include "outpath.h"
#include "fault.h"
#include "quote.h"

#include <dirent.h>
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
 * through with ENAMETOOLONG: refused here, before anything is created. is_file: 0 a directory,
 * 1 an output (room for its working names' suffix), 2 a working name itself (no more suffix). */
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
  if (is_file == 2 && base > (size_t)name_max)
    return vs_error_set(err, VS_ERR_INVALID, "%s: file name too long: %zu bytes (at most %ld)",
                        path, base, name_max);
  if (is_file == 2) return VS_OK;
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

/* The refusal of something other than a regular file at an output's path. */
static vs_status not_regular(const char *path, mode_t m, vs_error *err) {
  return vs_error_set(err, VS_ERR_INVALID,
                      "%s: exists and is %s (an output must be a regular file or absent)", path,
                      kind_of(m));
}

static vs_status check_file(const char *path, int kind, const vs_outpath_other *others,
                            int n_others, vs_error *err) {
  struct stat st;
  if (path == NULL || path[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "empty output path");
  if (path[strlen(path) - 1] == '/')
    return vs_error_set(err, VS_ERR_INVALID, "%s: names a directory, not a file", path);
  vs_status s = check_name(path, kind, err);
  if (s != VS_OK) return s;
  if (lstat(path, &st) == 0) {
    if (!S_ISREG(st.st_mode)) return not_regular(path, st.st_mode, err);
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

vs_status vs_outpath_check(const char *path, const vs_outpath_other *others, int n_others,
                           vs_error *err) {
  return check_file(path, 1, others, n_others, err);
}

vs_status vs_outpath_check_working(const char *path, vs_error *err) {
  return check_file(path, 2, NULL, 0, err);
}

vs_status vs_outpath_check_dir(const char *dir, vs_error *err) {
  struct stat st;
  if (dir == NULL || dir[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "empty output directory");
  if (strlen(dir) > VS_OUTPATH_DIR_MAX)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%.64s...: directory name too long: %zu bytes (at most %d, so that the "
                        "paths of the files written there fit)",
                        dir, strlen(dir), (int)VS_OUTPATH_DIR_MAX);
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

vs_status vs_outpath_check_entries(const char *dir, int (*ours)(const char *name, void *user),
                                   void *user, vs_error *err) {
  DIR *d = opendir(dir);
  if (d == NULL) return VS_OK;
  vs_status s = VS_OK;
  for (struct dirent *e = readdir(d); e != NULL && s == VS_OK; e = readdir(d)) {
    struct stat st;
    if (ours(e->d_name, user) && fstatat(dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) == 0 &&
        !S_ISREG(st.st_mode)) {
      char path[4096];
      snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
      s = not_regular(path, st.st_mode, err);
    }
  }
  closedir(d);
  return s;
}

/* Fault injection for the link tests: where the environment variable VS_FAULT_LINK is
 * "PATH=TARGET" and path is PATH, a symbolic link to TARGET is made there once the way is clear,
 * as another process could between a writer's checks and its creating the file. */
static void fault_link(const char *path) {
  const char *v = getenv("VS_FAULT_LINK");
  const char *eq = v != NULL ? strchr(v, '=') : NULL;
  if (eq != NULL && strlen(path) == (size_t)(eq - v) && strncmp(v, path, (size_t)(eq - v)) == 0)
    (void)symlink(eq + 1, path);
}

vs_status vs_outpath_clear(const char *path, vs_error *err) {
  struct stat st;
  if (lstat(path, &st) == 0) {
    if (!S_ISREG(st.st_mode)) return not_regular(path, st.st_mode, err);
    if (unlink(path) != 0 && errno != ENOENT)
      return vs_error_set(err, VS_ERR_IO, "%s: cannot remove the file there: %s", path,
                          strerror(errno));
  }
  fault_link(path);
  return VS_OK;
}

vs_status vs_outpath_intruded(const char *path, vs_error *err) {
  struct stat st;
  if (lstat(path, &st) != 0 || S_ISREG(st.st_mode)) return VS_OK;
  return vs_error_set(err, VS_ERR_INVALID,
                      "%s: became %s as it was created (nothing written through it)", path,
                      kind_of(st.st_mode));
}

vs_status vs_outpath_create(const char *path, int *fd, vs_error *err) {
  *fd = -1;
  vs_status s = vs_outpath_clear(path, err);
  if (s != VS_OK) return s;
  *fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (*fd >= 0) return VS_OK;
  const int e = errno;
  if (e == EEXIST && (s = vs_outpath_intruded(path, err)) != VS_OK) return s;
  if (e == EEXIST)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: created by another process meanwhile (not written over)", path);
  return vs_error_set(err, VS_ERR_IO, "%s: cannot create: %s", path, strerror(e));
}

vs_status vs_outpath_open_own(const char *path, dev_t dev, ino_t ino, int *fd, vs_error *err) {
  struct stat st;
  *fd = -1;
  /* looked at before it is opened: nothing put there (a device) is opened at all */
  if (lstat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_dev == dev && st.st_ino == ino) {
    *fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (*fd >= 0 && fstat(*fd, &st) == 0 && st.st_dev == dev && st.st_ino == ino) return VS_OK;
  }
  const int e = errno;
  if (*fd >= 0) close(*fd);
  *fd = -1;
  if (lstat(path, &st) != 0)
    return vs_error_set(err, VS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (!S_ISREG(st.st_mode) || st.st_dev != dev || st.st_ino != ino)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: became %s during the run (not opened)",
                        path, S_ISREG(st.st_mode) ? "another file" : kind_of(st.st_mode));
  return vs_error_set(err, VS_ERR_IO, "%s: cannot open: %s", path, strerror(e));
}

vs_status vs_outpath_open_existing(const char *path, int *fd, int *created, vs_error *err) {
  *created = 0;
  *fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (*fd >= 0) {
    *created = 1;
    return VS_OK;
  }
  if (errno == EEXIST) *fd = open(path, O_WRONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  struct stat st;
  if (*fd >= 0 && fstat(*fd, &st) == 0 && S_ISREG(st.st_mode)) return VS_OK;
  const int e = errno;
  if (*fd >= 0) close(*fd);
  *fd = -1;
  if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode)) return not_regular(path, st.st_mode, err);
  return vs_error_set(err, VS_ERR_IO, "%s: cannot create: %s", path, strerror(e));
}

vs_status vs_outpath_fopen(const char *path, FILE **f, vs_error *err) {
  int fd;
  *f = NULL;
  vs_status s = vs_outpath_create(path, &fd, err);
  if (s != VS_OK) return s;
  *f = fdopen(fd, "wb");
  if (*f != NULL) return VS_OK;
  s = vs_error_set(err, VS_ERR_NOMEM, "%s: cannot create: %s", path, strerror(errno));
  close(fd);
  unlink(path);
  return s;
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
  vs_fault_point_at("before-replace", from);
  struct stat st;
  if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode)) return 1;
  /* the working file too: a link put in its place during the run is not moved over path */
  if (lstat(from, &st) == 0 && !S_ISREG(st.st_mode)) return 2;
  return rename(from, path) == 0 ? 0 : -1;
}

void vs_outpath_discard(const char *path) {
  struct stat st;
  if (lstat(path, &st) == 0 && S_ISREG(st.st_mode)) unlink(path);
}

vs_status vs_outpath_publish(const char *from, const char *path, vs_error *err) {
  const int rc = vs_outpath_replace(from, path);
  if (rc == 2)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: became something other than a regular file during the run; not "
                        "renamed over %s", from, path);
  if (rc > 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "%s: became something other than a regular file; not replaced", path);
  if (rc < 0)
    return vs_error_set(err, VS_ERR_IO, "%s: cannot rename to %s: %s", from, path,
                        strerror(errno));
  return VS_OK;
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
  /* the pid is written into the lock file: a hard link there to another file would have that
   * file rewritten (a lock file of ours has one name) */
  if (st.st_nlink != 1) {
    close(f);
    vs_error_set(err, VS_ERR_INVALID,
                 "%s: its lock file %s has %ld names (a hard link to another file?): not "
                 "written",
                 target, lp, (long)st.st_nlink);
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

long vs_outlock_holder(const char *path) {
  char lp[4096], pid[32] = "";
  const int n = snprintf(lp, sizeof lp, "%s.lock", path);
  if (n < 0 || (size_t)n >= sizeof lp) return 0;
  const int f = open(lp, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (f < 0) return 0;
  struct stat st;
  const ssize_t got = fstat(f, &st) == 0 && S_ISREG(st.st_mode) ? pread(f, pid, sizeof pid - 1, 0)
                                                                 : 0;
  close(f);
  pid[got > 0 ? got : 0] = '\0';
  char *end = NULL;
  const long v = strtol(pid, &end, 10);
  return end != pid && *end == '\n' && v > 0 ? v : 0;
}
