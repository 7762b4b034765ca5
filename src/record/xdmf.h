/* Private: the XDMF sidecar of a record, from the HDF5 file that holds it (xdmf.c, the record
 * read in xdmf_record.c), and what the record's writer shares with it (xdmf_rows.c): the rows the
 * sidecar lists and the blocks' outlines moved to them (the record keeps those frames only, in
 * /xdmf/block_points). The sidecar's sources share xdmf_internal.h. */
#ifndef VS_XDMF_H
#define VS_XDMF_H

#include <hdf5.h>

#include "voussoir/status.h"

/* The suffix of the sidecar's working file, "<xmf_path>.tmp". */
#define VS_XDMF_TMP ".tmp"

/* Write the sidecar xmf_path (through "<xmf_path>.tmp", renamed) of the record h5_path opened
 * as file, listing at most max_grids rows (see vs_output_opts). Errors: VS_ERR_INVALID (not a
 * voussoir record, or xmf_path is not a regular file), VS_ERR_IO, VS_ERR_NOMEM. */
vs_status vs_xdmf_write(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                        vs_error *err);

/* vs_xdmf_write in two halves, for a writer that puts the record in place between them (so that
 * no sidecar is ever beside a record that is not its own, record.c): the sidecar written whole
 * and closed as "<xmf_path>.tmp" (its name into tmp, size bytes; removed on failure), and that
 * file renamed over xmf_path (only over a regular file; removed on failure). file may be the
 * record's working file: h5_path is the name the sidecar gives the record. */
vs_status vs_xdmf_write_tmp(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                            char *tmp, size_t size, vs_error *err);
vs_status vs_xdmf_publish(const char *tmp, const char *xmf_path, vs_error *err);

/* Can the sidecar refer to the record at h5_path by its file name? XML escapes &, <, >, " and
 * ', but cannot hold a control character nor bytes that are not UTF-8 (nor U+FFFE, U+FFFF),
 * and ParaView's XDMF reader splits its reference "FILE:/DATASET|SLAB" at the first ':' and at
 * every '|' and trims blanks: such a name is refused with VS_ERR_INVALID (the record's writer
 * checks it before anything is written; vs_xdmf_write again). */
vs_status vs_xdmf_name_check(const char *h5_path, vs_error *err);

/* The rows a sidecar lists, of rows [0, rows) with times t: every k-th row, k = ceil(rows /
 * max_grids), and the last, each only if its time is finite and above the previous listed one
 * (ParaView wants times, strictly increasing). Into sel (room for max_grids + 1 rows; NULL: only counted),
 * increasing; returns how many. */
long vs_xdmf_rows(const double *t, long rows, int max_grids, long *sel);

/* Point (X, Z) of a block in the reference configuration (centroid cx, cz) moved to a state in
 * which the block's centroid moved by (ux, uz) and the block turned by the angle whose cosine
 * and sine are c, s: the one formula of the record's moved points (the joints' ends at every
 * row, the outlines of the frames the sidecar lists). */
static inline void vs_xdmf_move(double cx, double cz, double ux, double uz, double c, double s,
                                double X, double Z, double out[2]) {
  const double dx = X - cx, dz = Z - cz;
  out[0] = cx + ux + c * dx - s * dz;
  out[1] = cz + uz + s * dx + c * dz;
}

/* The outlines of nb blocks of np points each (ref: the reference points, nb * np * 2 values, as
 * /geometry/block_points; centroid: nb * 2, as /geometry/block_centroid) moved to rows sel[0..n)
 * (increasing) of pos, the record's open /observables/block_position/value (rows x nb x 3: ux,
 * uz, theta), into out (n * nb * np * 2 float32, frame after frame). Reads the rows in blocks of
 * at most 64 consecutive rows. Returns 0, or -1 (a read failed, or out of memory). */
int vs_xdmf_outlines(hid_t pos, const long *sel, long n, int nb, int np, const double *ref,
                     const double *centroid, float *out);

#endif
