/* Output paths made safe to write: a target must be absent or a regular file (never a symbolic
 * link, FIFO, device or directory), must not be one of the run's inputs or another of its
 * outputs, and is written by one process at a time (an exclusive lock on "<target>.lock").
 * Every file the program writes is created here, anew (vs_outpath_create, HDF5's too; without
 * /proc, vs_outpath_clear before HDF5's exclusive create): never opened through a link, nor truncated in place (the one
 * exception, a run's --csv kept until the run starts: vs_outpath_open_existing). */
#ifndef VOUSSOIR_OUTPATH_H
#define VOUSSOIR_OUTPATH_H

#include <stdio.h>
#include <sys/types.h>

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

/* As vs_outpath_check, for a working name made from an output's ("<path>.tmp", "<path>.part"):
 * it gets no suffix of its own, so it need only fit NAME_MAX itself. */
vs_status vs_outpath_check_working(const char *path, vs_error *err);

/* The longest output directory (-o of sweep, montecarlo, merge, plot), bytes: the paths of the
 * files a command writes there ("DIR/run_NNNN.json.part", "DIR/montecarlo.manifest.part") fit
 * its buffers, so that none is ever cut short. */
enum { VS_OUTPATH_DIR_MAX = 1000 };

/* Check that dir may receive output files: its name is printable text (as for
 * vs_outpath_check) of at most VS_OUTPATH_DIR_MAX bytes, and it is absent (its parent directory
 * must exist) or a directory (not a symbolic link to one). Creates nothing. Errors:
 * VS_ERR_INVALID. */
vs_status vs_outpath_check_dir(const char *dir, vs_error *err);

/* Check that every entry of directory dir whose name ours(name, user) claims is a regular file:
 * one pass over the directory, for the names a command writes there that are too many to check
 * one by one (a sweep's run_NNNN.*). An absent or unreadable dir passes (its files are checked
 * as they are created). Errors: VS_ERR_INVALID with "DIR/NAME: <reason>" in err. */
vs_status vs_outpath_check_entries(const char *dir, int (*ours)(const char *name, void *user),
                                   void *user, vs_error *err);

/* Make way for a file about to be created at path: nothing there, or a regular file (a working
 * file a killed process left behind, or the output being replaced), which is removed, never
 * truncated (a hard link to it keeps its bytes). Anything else (a symbolic link, FIFO, device,
 * directory) is left as it is, and refused. For a creator that cannot take a descriptor
 * (HDF5 where /proc is not mounted: H5Fcreate with H5F_ACC_EXCL, which then fails on whatever
 * is put there meanwhile); everything else uses vs_outpath_create. Errors: VS_ERR_INVALID "PATH: exists and is ...";
 * VS_ERR_IO when the stale file cannot be removed. */
vs_status vs_outpath_clear(const char *path, vs_error *err);

/* Create path as a new file (0644) for writing: vs_outpath_clear, then
 * open(O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC), so that nothing put at path
 * between the checks and the creation (a link, a FIFO) is ever opened, let alone written
 * through. *fd receives the descriptor, -1 on failure. Errors: those of vs_outpath_clear;
 * VS_ERR_INVALID "PATH: became ... as it was created" when something was put there meanwhile;
 * VS_ERR_IO with the OS reason. */
vs_status vs_outpath_create(const char *path, int *fd, vs_error *err);

/* After an exclusive create of path failed: VS_ERR_INVALID "PATH: became ... as it was created"
 * when something other than a regular file is there now (put there meanwhile), else VS_OK (the
 * caller reports its own cause). */
vs_status vs_outpath_intruded(const char *path, vs_error *err);

/* Open path for writing without truncating it, for a writer that keeps the old file until its
 * run starts (voussoir run --csv): created as vs_outpath_create does when nothing is there
 * (*created = 1), else opened without following a link, and kept only if it is a regular file.
 * *fd receives the descriptor, -1 on failure. Errors: VS_ERR_INVALID "PATH: exists and is ...";
 * VS_ERR_IO with the OS reason. */
vs_status vs_outpath_open_existing(const char *path, int *fd, int *created, vs_error *err);

/* Open again, read-only, a file this process created at path (dev, ino: its identity, from
 * the descriptor it was created with), by name: never through a link, and only when path still
 * names that very file (checked before the open and on the descriptor after), so that nothing
 * put there during the run (a link, another file, a device) is opened. *fd receives the
 * descriptor, -1 on failure. Errors: VS_ERR_INVALID "PATH: became ... during the run (not
 * opened)"; VS_ERR_IO with the OS reason (e.g. removed). */
vs_status vs_outpath_open_own(const char *path, dev_t dev, ino_t ino, int *fd, vs_error *err);

/* vs_outpath_create as a stdio stream, "wb"; *f is NULL on failure. Errors: as
 * vs_outpath_create, and VS_ERR_NOMEM. */
vs_status vs_outpath_fopen(const char *path, FILE **f, vs_error *err);

/* Rename the finished file `from` over path, checked just before: never over anything but a
 * regular file, and never anything but a regular file (a link put at `from` during the run is
 * not moved to path). 0; 1 when path exists and is something else, 2 when `from` is something
 * else (nothing renamed); -1 when the rename failed (errno says why). from is left in place
 * either way. */
int vs_outpath_replace(const char *from, const char *path);

/* Remove the working file path after a failure, when it is a regular file: never a link or
 * anything else put there (whose presence may be why the file could not be created). */
void vs_outpath_discard(const char *path);

/* vs_outpath_replace with its outcome as an error: VS_ERR_INVALID "PATH: became something
 * other than a regular file; not replaced" (or "FROM: became ... during the run; not renamed
 * over PATH"), VS_ERR_IO "FROM: cannot rename to PATH: reason".
 * from is left in place on failure (the caller removes it). */
vs_status vs_outpath_publish(const char *from, const char *path, vs_error *err);

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

/* The pid recorded in path's lock file ("<path>.lock", as vs_outlock_acquire writes it) by its
 * latest owner, who may hold it still or may have ended (the file outlives a killed owner): 0
 * when there is none, or the file is not a regular file or holds no pid. */
long vs_outlock_holder(const char *path);

#endif
