/* Private HDF5 helpers of the library and the program (not installed): a quiet error stack, a
 * generic close, the cause of the last error as one line, string types, scalar attributes,
 * small datasets, and whole-dataset reads. Every function returns an HDF5 status (< 0: error)
 * or an identifier (< 0: error) and prints nothing. */
#ifndef VS_H5UTIL_H
#define VS_H5UTIL_H

#include <hdf5.h>
#include <stddef.h>
#include <sys/types.h>

#include "voussoir/status.h"

typedef struct {
  H5E_auto2_t fn;
  void *data;
} vs_h5_quiet;

/* Silence HDF5's error printing (library code must not print) until vs_h5_quiet_end(q). */
vs_h5_quiet vs_h5_quiet_begin(void);
void vs_h5_quiet_end(vs_h5_quiet q);

/* Close id whatever its kind (file, group, type, space, dataset, attribute, property list);
 * id < 0 is ignored. */
void vs_h5_close(hid_t id);

/* Record "output: FILE: what: OS reason" (strerror of the errno a file driver reported, else
 * HDF5's own cause) in err, as one line, and clear HDF5's error stack; returns VS_ERR_IO. */
vs_status vs_h5_fail(vs_error *err, const char *path, const char *what);

/* Create the HDF5 file at path anew (fcpl: its creation properties, or H5P_DEFAULT):
 * vs_outpath_create (a stale regular file removed, anything else refused, the new file made
 * with O_EXCL | O_NOFOLLOW), and HDF5 handed that file by its descriptor's name in /proc, never
 * path, which must still name it after: a link put at path meanwhile is neither followed nor
 * opened, no file is truncated in place. (Without /proc: H5Fcreate at path with H5F_ACC_EXCL,
 * which fails on whatever is put there meanwhile, but whose check first opens the name.) The
 * file, or H5I_INVALID_HID with err set (VS_ERR_INVALID: something other than a regular file
 * there, or put there meanwhile; VS_ERR_IO with the cause). */
hid_t vs_h5_create(const char *path, hid_t fcpl, vs_error *err);

/* The identity (device, inode) of the file HDF5 has open as f (the default sec2 driver), for
 * vs_h5_open_own: 0, or -1. */
int vs_h5_file_id(hid_t f, dev_t *dev, ino_t *ino);

/* Open again, read-only, the HDF5 file this process created at path (dev, ino: from
 * vs_h5_file_id): vs_outpath_open_own (never through a link, only that very file), and HDF5
 * handed the descriptor's name in /proc, never path (without /proc: path, just checked). The
 * file, or H5I_INVALID_HID with err set (VS_ERR_INVALID "PATH: became ... during the run (not
 * opened)"; VS_ERR_IO with the cause). */
hid_t vs_h5_open_own(const char *path, dev_t dev, ino_t ino, vs_error *err);

/* A variable-length UTF-8 string type; a fixed-length string of n bytes, NUL-padded (n = 1
 * holds 'I', 'E' or a hinge label, empty for 0); the caller closes them. */
hid_t vs_h5_vlstr_type(void);
hid_t vs_h5_fixed_str_type(size_t n);

/* Scalar attribute name = value (variable-length UTF-8 string); an existing one is overwritten
 * in place (the object header keeps its size). */
herr_t vs_h5_attr_str(hid_t obj, const char *name, const char *value);
/* Scalar attribute name = value as a fixed-length ASCII string of strlen(value) + 1 bytes,
 * NUL-terminated (the Monte Carlo summary's attributes). */
herr_t vs_h5_attr_cstr(hid_t obj, const char *name, const char *value);
/* Scalar numeric attribute: ftype in the file, mtype and *value in memory. */
herr_t vs_h5_attr_num(hid_t obj, const char *name, hid_t ftype, hid_t mtype, const void *value);
herr_t vs_h5_attr_int(hid_t obj, const char *name, long long v); /* int64 */
herr_t vs_h5_attr_double(hid_t obj, const char *name, double v); /* float64 */

/* A small contiguous dataset (rank 0 for a scalar) with optional unit and columns attributes. */
herr_t vs_h5_dset_write(hid_t loc, const char *name, hid_t ftype, hid_t mtype, int rank,
                        const hsize_t *dims, const void *data, const char *unit,
                        const char *columns);
/* A float64 scalar dataset with its unit. */
herr_t vs_h5_dset_scalar(hid_t loc, const char *name, double v, const char *unit);
/* A group with default properties. */
hid_t vs_h5_group_create(hid_t loc, const char *name);

/* What a reader may allocate for the values file f declares, bytes: VS_H5_READ_EXPANSION times
 * the file's size plus VS_H5_READ_SLACK (0 if its size is unknown). A record holds its values
 * (deflate shrinks them at most 1032-fold, and a float32 is read as a double), whereas a
 * crafted file may declare dimensions far beyond its size (unwritten chunks read as the fill
 * value): a reader checks what a file's dimensions make it allocate against this first. */
#define VS_H5_READ_EXPANSION 2100
#define VS_H5_READ_SLACK ((size_t)16 << 20)
size_t vs_h5_read_budget(hid_t f);
/* 0 when n items of size bytes each fit vs_h5_read_budget(f); otherwise -1 and in msg
 * "PATH declares N WHAT (M MiB in memory): more than a file of B bytes holds (allowed: ...)". */
int vs_h5_check_budget(hid_t f, const char *path, size_t n, const char *what, size_t size,
                       char *msg, size_t msg_size);

/* Read the whole dataset at path (converted to memory type mtype) into out[0..n): 0, or -1 if
 * it is missing, does not hold exactly n values (whatever its rank) or cannot be converted.
 * vs_h5_read_doubles: as double. */
int vs_h5_read(hid_t f, const char *path, hid_t mtype, void *out, size_t n);
int vs_h5_read_doubles(hid_t f, const char *path, double *out, size_t n);
/* The rows of the table at path, a dataset of rank 1 (whose whole read fills that many
 * records): -1 if it is missing, -2 if it is something else (another rank, a scalar, more rows
 * than an int holds), -3 if it declares more than the file holds (vs_h5_read_budget). */
int vs_h5_table_rows(hid_t f, const char *path);
/* The size of the first dimension of the dataset at path: -1 if it is missing, -2 if it is
 * more than an int holds, -3 if the dataset declares more than the file holds
 * (vs_h5_read_budget). */
int vs_h5_rows(hid_t f, const char *path);

#endif
