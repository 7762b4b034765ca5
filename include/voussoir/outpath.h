/* Output paths made safe to write: a target must be absent or a regular file (never a symbolic
 * link, FIFO, device or directory), must not be one of the run's inputs or another of its
 * outputs, and is written by one process at a time (an exclusive lock on "<target>.lock"). */
#ifndef VOUSSOIR_OUTPATH_H
#define VOUSSOIR_OUTPATH_H

#include "voussoir/status.h"

/* Another file of the run, which an output must not be: its path (NULL: none) and what it is
 * ("the case file"). */
typedef struct {
  const char *path, *role;
} vs_outpath_other;

/* Check that path may be written: its name is printable text (vs_quote_clean: no control
 * character, well-formed UTF-8) and leaves room for the suffix of its working names
 * ("<path>.lock", "<path>.part", "<path>.snap") within NAME_MAX and PATH_MAX; nothing exists
 * there, or a regular file (lstat: a symbolic link is refused whatever it points to), and its
 * directory exists and is writable; and it is not the same file as any others[0..n_others)
 * (same device and inode, or the same name in the same directory, so that files not yet created
 * compare too). Creates nothing. Errors: VS_ERR_INVALID with "PATH: <reason>" in err. */
vs_status vs_outpath_check(const char *path, const vs_outpath_other *others, int n_others,
                           vs_error *err);

/* Check that dir may receive output files: its name is printable text (as for
 * vs_outpath_check), and it is absent (its parent directory must exist) or a directory (not a
 * symbolic link to one). Creates nothing. Errors: VS_ERR_INVALID. */
vs_status vs_outpath_check_dir(const char *dir, vs_error *err);

/* Rename the finished file `from` over path, checked just before: never over anything but a
 * regular file. 0; 1 when path exists and is something else (nothing renamed); -1 when the
 * rename failed (errno says why). from is left in place either way. */
int vs_outpath_replace(const char *from, const char *path);

typedef struct vs_outlock vs_outlock;

/* Take the exclusive lock of the output path: "<path>.lock" is created if needed (0644, holding
 * the owner's pid) and locked with flock(LOCK_EX | LOCK_NB); a lock file that another process
 * replaced or removed meanwhile is retried. Errors: VS_ERR_INVALID "PATH: being written by
 * another process (pid N, lock PATH.lock)" when it is held, or when the lock file is not a
 * regular file; VS_ERR_IO with the OS reason when it cannot be created; VS_ERR_NOMEM. *out
 * receives the lock (NULL on failure). */
vs_status vs_outlock_acquire(const char *path, vs_outlock **out, vs_error *err);

/* Remove the lock file and release the lock; free *l and NULL it. NULL and *l == NULL are
 * allowed. A process that dies holding the lock releases it (the kernel drops the flock); its
 * lock file stays behind and is reused by the next writer. */
void vs_outlock_release(vs_outlock **l);

#endif
