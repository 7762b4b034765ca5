/* Private HDF5 helpers shared by the record's writer, its sidecar and the commands that read
 * records (see h5util.h). */
#define _POSIX_C_SOURCE 200809L /* fchmod, lstat */
#include "h5util.h"

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "outpath.h"

/* HDF5 prints its error stack to stderr by default; library code must not print. */
vs_h5_quiet vs_h5_quiet_begin(void) {
  vs_h5_quiet q = {NULL, NULL};
  H5Eget_auto2(H5E_DEFAULT, &q.fn, &q.data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  return q;
}

void vs_h5_quiet_end(vs_h5_quiet q) { H5Eset_auto2(H5E_DEFAULT, q.fn, q.data); }

void vs_h5_close(hid_t id) {
  if (id < 0) return;
  switch (H5Iget_type(id)) {
  case H5I_FILE: H5Fclose(id); break;
  case H5I_GROUP: H5Gclose(id); break;
  case H5I_DATATYPE: H5Tclose(id); break;
  case H5I_DATASPACE: H5Sclose(id); break;
  case H5I_DATASET: H5Dclose(id); break;
  case H5I_ATTR: H5Aclose(id); break;
  case H5I_GENPROP_LST: H5Pclose(id); break;
  default: break;
  }
}

typedef struct {
  char api[64], cause[256];
  int os_errno; /* the errno a file driver reported ("errno = 28, ..."), or 0 */
} h5_cause;

static herr_t walk_cb(unsigned n, const H5E_error2_t *e, void *data) {
  h5_cause *c = data;
  if (n == 0 && e->func_name != NULL) snprintf(c->api, sizeof c->api, "%s", e->func_name);
  if (e->desc == NULL || e->desc[0] == '\0') return 0;
  /* the first line only: a driver's message lists buffers and offsets after it */
  snprintf(c->cause, sizeof c->cause, "%.*s", (int)strcspn(e->desc, "\n,"), e->desc);
  const char *en = strstr(e->desc, "errno = ");
  if (en != NULL && c->os_errno == 0) c->os_errno = atoi(en + 8);
  return 0;
}

/* Record "output: FILE: what: OS reason" (strerror of the errno a file driver reported, else
 * HDF5's own cause) in err, as one line, and clear HDF5's error stack. */
vs_status vs_h5_fail(vs_error *err, const char *path, const char *what) {
  h5_cause c = {"", "", 0};
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk_cb, &c);
  H5Eclear2(H5E_DEFAULT);
  if (c.os_errno > 0)
    return vs_error_set(err, VS_ERR_IO, "output: %s: %s: %s", path, what, strerror(c.os_errno));
  return vs_error_set(err, VS_ERR_IO, "output: %s: %s%s%s%s%s", path, what, c.cause[0] ? ": " : "",
                      c.cause, c.api[0] ? " in " : "", c.api);
}

/* HDF5 opens files by name, and its exclusive create first opens the name read-write to see
 * whether a file is there (HDF5 1.10): that open follows a link put at path after the checks,
 * opening what it points to (a FIFO, a device), though the create then fails. So the file is
 * created here (vs_outpath_create: O_EXCL | O_NOFOLLOW) and HDF5 is handed it by its
 * descriptor's name in /proc, which is that file whatever is at path by then; and it must still
 * be at path once HDF5 has it. Where /proc is not mounted, HDF5's exclusive create at path. */
static hid_t create_by_fd(const char *path, hid_t fcpl, vs_error *err) {
  int fd = -1;
  if (vs_outpath_create(path, &fd, err) != VS_OK) return H5I_INVALID_HID;
  char byfd[64];
  snprintf(byfd, sizeof byfd, "/proc/self/fd/%d", fd);
  struct stat own, now;
  if (fstat(fd, &own) != 0 || access(byfd, F_OK) != 0) { /* no /proc */
    close(fd);
    unlink(path);
    if (vs_outpath_clear(path, err) != VS_OK) return H5I_INVALID_HID;
    return H5Fcreate(path, H5F_ACC_EXCL, fcpl, H5P_DEFAULT);
  }
  /* HDF5 opens it read-write: so must its owner be allowed to (a umask may forbid it) */
  const mode_t mode = own.st_mode & 07777;
  if ((mode & 0600) != 0600) fchmod(fd, mode | 0600);
  hid_t f = H5Fcreate(byfd, H5F_ACC_TRUNC, fcpl, H5P_DEFAULT);
  if ((mode & 0600) != 0600) fchmod(fd, mode);
  const int ours = lstat(path, &now) == 0 && now.st_dev == own.st_dev && now.st_ino == own.st_ino;
  if (f < 0) {
    vs_h5_fail(err, path, "cannot create the file");
    if (ours) unlink(path);
  } else if (!ours) {
    H5Fclose(f); /* written to the file created, which is no longer at path */
    f = H5I_INVALID_HID;
    if (vs_outpath_intruded(path, err) == VS_OK)
      vs_error_set(err, VS_ERR_INVALID, "%s: replaced by another file as it was created (not "
                   "written over)", path);
  }
  close(fd);
  return f;
}

hid_t vs_h5_create(const char *path, hid_t fcpl, vs_error *err) {
  const vs_h5_quiet q = vs_h5_quiet_begin();
  vs_error_clear(err);
  const hid_t f = create_by_fd(path, fcpl, err);
  /* something put there meanwhile is named as such; otherwise HDF5's cause */
  if (f < 0 && err->status == VS_OK && vs_outpath_intruded(path, err) == VS_OK)
    vs_h5_fail(err, path, "cannot create the file");
  H5Eclear2(H5E_DEFAULT);
  vs_h5_quiet_end(q);
  return f;
}

int vs_h5_file_id(hid_t f, dev_t *dev, ino_t *ino) {
  void *handle = NULL;
  struct stat st;
  if (H5Fget_vfd_handle(f, H5P_DEFAULT, &handle) < 0 || handle == NULL) return -1;
  if (fstat(*(const int *)handle, &st) != 0) return -1; /* the sec2 driver's: a descriptor */
  *dev = st.st_dev;
  *ino = st.st_ino;
  return 0;
}

hid_t vs_h5_open_own(const char *path, dev_t dev, ino_t ino, vs_error *err) {
  const vs_h5_quiet q = vs_h5_quiet_begin();
  int fd = -1;
  hid_t f = H5I_INVALID_HID;
  if (vs_outpath_open_own(path, dev, ino, &fd, err) == VS_OK) {
    char byfd[64];
    snprintf(byfd, sizeof byfd, "/proc/self/fd/%d", fd);
    /* without /proc: by name, just checked (the window that remains is HDF5's open) */
    f = H5Fopen(access(byfd, F_OK) == 0 ? byfd : path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) vs_h5_fail(err, path, "cannot reopen");
    close(fd);
  }
  H5Eclear2(H5E_DEFAULT);
  vs_h5_quiet_end(q);
  return f;
}

hid_t vs_h5_vlstr_type(void) {
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  if (H5Tset_size(t, H5T_VARIABLE) < 0 || H5Tset_cset(t, H5T_CSET_UTF8) < 0) {
    H5Tclose(t);
    return H5I_INVALID_HID;
  }
  return t;
}

/* A fixed-length string of n bytes, NUL-padded: n = 1 holds 'I', 'E' or a hinge label (empty
 * for 0). */
hid_t vs_h5_fixed_str_type(size_t n) {
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  if (H5Tset_size(t, n) < 0 || H5Tset_strpad(t, H5T_STR_NULLPAD) < 0) {
    H5Tclose(t);
    return H5I_INVALID_HID;
  }
  return t;
}

/* Scalar attribute name = value (variable-length UTF-8 string); an existing one is overwritten
 * in place (the object header keeps its size). */
herr_t vs_h5_attr_str(hid_t obj, const char *name, const char *value) {
  herr_t rc = -1;
  hid_t t = vs_h5_vlstr_type(), s = H5Screate(H5S_SCALAR), a = H5I_INVALID_HID;
  if (t >= 0 && s >= 0)
    a = H5Aexists(obj, name) > 0 ? H5Aopen(obj, name, H5P_DEFAULT)
                                 : H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) rc = H5Awrite(a, t, &value);
  vs_h5_close(a);
  vs_h5_close(s);
  vs_h5_close(t);
  return rc;
}

herr_t vs_h5_attr_cstr(hid_t obj, const char *name, const char *value) {
  hid_t t = H5Tcopy(H5T_C_S1), s = H5Screate(H5S_SCALAR), a = H5I_INVALID_HID;
  herr_t rc = -1;
  if (t >= 0 && H5Tset_size(t, strlen(value) + 1) >= 0 && s >= 0)
    a = H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) rc = H5Awrite(a, t, value);
  vs_h5_close(a);
  vs_h5_close(s);
  vs_h5_close(t);
  return rc;
}

/* Scalar numeric attribute: ftype in the file, mtype and *value in memory. */
herr_t vs_h5_attr_num(hid_t obj, const char *name, hid_t ftype, hid_t mtype, const void *value) {
  herr_t rc = -1;
  hid_t s = H5Screate(H5S_SCALAR), a = H5I_INVALID_HID;
  if (s >= 0) a = H5Acreate2(obj, name, ftype, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) rc = H5Awrite(a, mtype, value);
  vs_h5_close(a);
  vs_h5_close(s);
  return rc;
}

herr_t vs_h5_attr_int(hid_t obj, const char *name, long long v) {
  return vs_h5_attr_num(obj, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &v);
}

herr_t vs_h5_attr_double(hid_t obj, const char *name, double v) {
  return vs_h5_attr_num(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
}

/* A small contiguous dataset (rank 0 for a scalar) with optional unit and columns attributes. */
herr_t vs_h5_dset_write(hid_t loc, const char *name, hid_t ftype, hid_t mtype, int rank,
                        const hsize_t *dims, const void *data, const char *unit,
                        const char *columns) {
  herr_t rc = -1;
  hid_t s = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, NULL);
  hid_t d = s >= 0 ? H5Dcreate2(loc, name, ftype, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                   : H5I_INVALID_HID;
  if (d >= 0) {
    hssize_t n = H5Sget_simple_extent_npoints(s);
    rc = (n > 0 && data != NULL) ? H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
    if (rc >= 0 && unit != NULL) rc = vs_h5_attr_str(d, "unit", unit);
    if (rc >= 0 && columns != NULL) rc = vs_h5_attr_str(d, "columns", columns);
  }
  vs_h5_close(d);
  vs_h5_close(s);
  return rc;
}

herr_t vs_h5_dset_scalar(hid_t loc, const char *name, double v, const char *unit) {
  return vs_h5_dset_write(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, NULL, &v, unit, NULL);
}

hid_t vs_h5_group_create(hid_t loc, const char *name) {
  return H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
}

size_t vs_h5_read_budget(hid_t f) {
  hsize_t size = 0;
  if (H5Fget_filesize(f, &size) < 0) return 0;
  if (size > (SIZE_MAX - VS_H5_READ_SLACK) / VS_H5_READ_EXPANSION) return SIZE_MAX;
  return (size_t)size * VS_H5_READ_EXPANSION + VS_H5_READ_SLACK;
}

static int fits_budget(hid_t f, size_t n, size_t size) {
  return size == 0 || n <= vs_h5_read_budget(f) / size;
}

int vs_h5_check_budget(hid_t f, const char *path, size_t n, const char *what, size_t size,
                       char *msg, size_t msg_size) {
  if (fits_budget(f, n, size)) return 0;
  hsize_t fsize = 0;
  H5Fget_filesize(f, &fsize);
  const double mib = (double)n * (double)size / 1048576.0;
  snprintf(msg, msg_size, "%s declares %zu %s (%.0f MiB in memory): more than a file of %llu "
           "bytes holds (allowed: at most %d x its size + %zu MiB)", path, n, what, mib,
           (unsigned long long)fsize, VS_H5_READ_EXPANSION, VS_H5_READ_SLACK >> 20);
  return -1;
}

/* Whether dataset d's whole extent, as stored, fits the budget of file f. */
static int within_budget(hid_t f, hid_t d, hid_t sp) {
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  const hid_t t = H5Dget_type(d);
  const size_t size = t >= 0 ? H5Tget_size(t) : 0;
  if (t >= 0) H5Tclose(t);
  return np >= 0 && size > 0 && fits_budget(f, (size_t)np, size);
}

int vs_h5_read(hid_t f, const char *path, hid_t mtype, void *out, size_t n) {
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  int rc = (np == (hssize_t)n && H5Dread(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) >= 0)
               ? 0
               : -1;
  H5Sclose(sp);
  H5Dclose(d);
  return rc;
}

int vs_h5_read_doubles(hid_t f, const char *path, double *out, size_t n) {
  return vs_h5_read(f, path, H5T_NATIVE_DOUBLE, out, n);
}

int vs_h5_table_rows(hid_t f, const char *path) {
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) return -2;
  hid_t sp = H5Dget_space(d);
  hsize_t rows = 0;
  const int ok = H5Sget_simple_extent_type(sp) == H5S_SIMPLE &&
                 H5Sget_simple_extent_ndims(sp) == 1 &&
                 H5Sget_simple_extent_dims(sp, &rows, NULL) == 1 && rows <= INT_MAX;
  const int fits = ok && within_budget(f, d, sp);
  H5Sclose(sp);
  H5Dclose(d);
  return !ok ? -2 : !fits ? -3 : (int)rows;
}

int vs_h5_rows(hid_t f, const char *path) {
  if (H5Lexists(f, path, H5P_DEFAULT) <= 0) return -1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) return -1;
  hid_t sp = H5Dget_space(d);
  hsize_t dims[H5S_MAX_RANK] = {0}; /* it writes as many as the dataset has: any rank */
  int nd = H5Sget_simple_extent_dims(sp, dims, NULL);
  const int fits = nd >= 1 && within_budget(f, d, sp);
  H5Sclose(sp);
  H5Dclose(d);
  return nd < 1 ? -1 : dims[0] > INT_MAX ? -2 : !fits ? -3 : (int)dims[0];
}
