/* The record's snapshots (record_internal.h): HDF5 writes the working file "<path>.part" in
 * place, and a kill inside one of its flushes can tear it (HDF5 1.10 has no crash-consistent
 * flush: 1 record in 247 kept an object that did not read). So the file at path is never the one
 * HDF5 writes: after a flush, the working file, consistent on disk, is copied to "<path>.snap"
 * and that copy renamed over path. A rename is atomic, so a kill at any moment leaves at path
 * either the last snapshot whole or none yet (before the layout's). At the end the closed
 * working file itself is renamed over path. */
#define _GNU_SOURCE /* copy_file_range */
#include <errno.h>
#include <fcntl.h>
#include <hdf5.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "record_internal.h"
#include "outpath.h"
#include "wall_clock.h"

vs_status vs_record_publish(vs_output *o, const char *from, dev_t dev, ino_t ino) {
  struct stat st;
  if (lstat(from, &st) != 0)
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: %s: %s", o->path, from, strerror(errno));
  if (!S_ISREG(st.st_mode) || st.st_dev != dev || st.st_ino != ino)
    return vs_error_set(&o->err, VS_ERR_INVALID,
                        "output: %s: %s: became %s during the run (not renamed over %s)", o->path,
                        from, S_ISLNK(st.st_mode)  ? "a symbolic link"
                              : S_ISREG(st.st_mode) ? "another file"
                                                    : "something other than a regular file",
                        o->path);
  if (!o->replaced && !o->stranded) { /* the record there goes: its sidecar first */
    vs_outpath_discard(o->xmf_path);
    o->replaced = 1;
  }
  const int rc = o->stranded ? 1 : vs_outpath_replace(from, o->path);
  if (rc == 2)
    return vs_error_set(&o->err, VS_ERR_INVALID,
                        "output: %s: %s: became something other than a regular file during the "
                        "run (not renamed over %s)", o->path, from, o->path);
  if (rc > 0) {
    o->stranded = 1;
    return VS_ERR_INVALID;
  }
  if (rc < 0)
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: cannot rename to %s: %s", from, o->path,
                        strerror(errno));
  return VS_OK;
}

vs_status vs_record_stranded_error(const vs_output *o, vs_error *err) {
  return vs_error_set(err, VS_ERR_INVALID,
                      "%s: became something other than a regular file during the run; not "
                      "replaced: the record is in %s", o->path, o->part);
}

/* Copy n bytes of fd `in` to `out` from their offsets: in the kernel where the file system can
 * (a reflink on some, no pass through user space on any), else by reads and writes. 0, or -1
 * with errno. */
static int copy_bytes(int in, int out, off_t n) {
  off_t done = 0;
  int kernel = 1; /* 0 once the kernel's copy is refused: not on this file system */
  char buf[1 << 16];
  while (done < n) {
    ssize_t k = -1;
    if (kernel) {
      k = copy_file_range(in, NULL, out, NULL, (size_t)(n - done), 0);
      if (k < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP)) {
        kernel = 0; /* nothing copied by this call: the plain way from here */
        continue;
      }
    } else {
      k = read(in, buf, (size_t)(n - done) < sizeof buf ? (size_t)(n - done) : sizeof buf);
      for (ssize_t w = 0; k > 0 && w < k;) {
        const ssize_t r = write(out, buf + w, (size_t)(k - w));
        if (r < 0) return -1;
        w += r;
      }
    }
    if (k < 0) return -1;
    if (k == 0) break; /* the file ended early: copy what there is */
    done += k;
  }
  return 0;
}

/* Copy the working file to the snapshot's name and rename that over path. */
static vs_status take(vs_output *o, off_t *size) {
  /* by name, but only the file created there: never a link put there during the run */
  if (o->snapshots > 0) vs_fault_point("before-snapshot"); /* after the layout's */
  int in;
  vs_error why;
  if (vs_outpath_open_own(o->part, o->part_dev, o->part_ino, &in, &why) != VS_OK)
    return vs_error_set(&o->err, why.status, "output: %s: cannot read the working file: %s",
                        o->path, why.msg);
  struct stat st;
  if (fstat(in, &st) != 0) {
    const int e = errno;
    close(in);
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: cannot read the working file %s: %s",
                        o->path, o->part, strerror(e));
  }
  *size = st.st_size;
  int out;
  if (vs_outpath_create(o->snap, &out, &o->err) != VS_OK) {
    close(in);
    return o->err.status;
  }
  struct stat made; /* the snapshot's own identity: only that file is renamed over path */
  int rc = fstat(out, &made);
  if (rc == 0) rc = copy_bytes(in, out, st.st_size / 2);
  /* the crash tests' points, in a snapshot after the layout's (there is one at path) */
  if (rc == 0 && o->snapshots > 0) vs_fault_point("mid-snapshot"); /* half copied */
  if (rc == 0) rc = copy_bytes(in, out, st.st_size - st.st_size / 2);
  int e = errno;
  if (close(out) != 0 && rc == 0) rc = -1, e = errno;
  close(in);
  if (rc != 0) {
    unlink(o->snap);
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: cannot write its snapshot %s: %s",
                        o->path, o->snap, strerror(e));
  }
  if (o->snapshots > 0) vs_fault_point("before-publish");
  const vs_status s = vs_record_publish(o, o->snap, made.st_dev, made.st_ino);
  if (s != VS_OK) unlink(o->snap);
  return o->stranded ? VS_OK : s; /* stranded: the run goes on, into the working file */
}

vs_status vs_record_snapshot(vs_output *o) {
  if (o->err.status != VS_OK) return o->err.status;
  if (o->stranded) return VS_OK;
  const double now = vs_wall_now();
  if (o->opts.snapshot_share < 1.0 && o->snapshots > 0) {
    /* the next copy's cost, from the last's, grows with the file */
    struct stat st;
    const double size = lstat(o->part, &st) == 0 ? (double)st.st_size : o->snap_size;
    const double next = o->snap_size > 0.0 ? o->snap_last * size / o->snap_size : o->snap_last;
    if (o->snap_spent + next > o->opts.snapshot_share * (now - o->t_open)) return VS_OK;
  }
  off_t size = 0;
  const vs_status s = take(o, &size);
  if (s != VS_OK) return s;
  o->snap_last = vs_wall_now() - now;
  o->snap_spent += o->snap_last;
  o->snap_size = (double)size;
  o->snapshots++;
  return VS_OK;
}
