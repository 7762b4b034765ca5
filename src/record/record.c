/* The HDF5 record of a run (an H5MD-like layout: /parameters, /geometry, /observables/<name>/
 * {step,time,value}, /events, /summary) and its XDMF sidecar for ParaView: the writer's life
 * (create, rows, finish, destroy). Rows and events are buffered and written in blocks, each
 * followed by a flush, to the working file path.part; path itself is only ever a whole copy of
 * it taken after a flush and renamed into place (record_snapshot.c), or at the end the closed
 * file, so that a run killed at any moment leaves a record that reads whole (see file_create
 * for what was measured). The layout is written by record_layout.c, the series by
 * record_series.c, /events by record_events.c, /summary by record_summary.c, the sidecar by
 * xdmf.c. */
#define _POSIX_C_SOURCE 200809L /* gmtime_r */
#include "voussoir/output.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "record_internal.h"
#include "wall_clock.h"
#include "xdmf.h"

/* Suffixes of the working file HDF5 writes and of a snapshot's copy (record_snapshot.c). */
#define VS_OUT_PART ".part"
#define VS_OUT_SNAP ".snap"

/* ------------------------------------------------------------------------------------------ */
/* Create / destroy                                                                             */

void vs_output_opts_default(vs_output_opts *o) {
  o->arc_points = 2;
  o->flush_rows = 64;
  o->chunk_rows = 64;
  o->deflate = 0;
  o->xdmf_max_grids = 2000;
  o->snapshot_share = 0.1;
}

static vs_status check_opts(const vs_output_opts *o, vs_error *err) {
  if (o->arc_points < 0 || o->arc_points > 64 || o->flush_rows < 1 || o->chunk_rows < 1 ||
      o->deflate < 0 || o->deflate > 9 || o->xdmf_max_grids < 2 ||
      !(o->snapshot_share > 0.0 && o->snapshot_share <= 1.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: options arc_points = %d, flush_rows = %d, chunk_rows = %d, "
                        "deflate = %d, xdmf_max_grids = %d, snapshot_share = %g (allowed: "
                        "arc_points in [0, 64], flush_rows >= 1, chunk_rows >= 1, deflate in "
                        "[0, 9], xdmf_max_grids >= 2, 0 < snapshot_share <= 1)",
                        o->arc_points, o->flush_rows, o->chunk_rows, o->deflate, o->xdmf_max_grids,
                        o->snapshot_share);
  return VS_OK;
}

static char *dup_str(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d != NULL) memcpy(d, s, n);
  return d;
}

/* path with suffix appended (malloc'd; NULL when out of memory). */
static char *suffixed(const char *path, const char *suffix) {
  const size_t n = strlen(path) + strlen(suffix) + 1;
  char *d = malloc(n);
  if (d != NULL) snprintf(d, n, "%s%s", path, suffix);
  return d;
}

/* Before anything is written: the target, its sidecar and the sidecar's working file (written
 * at the end) are absent or regular files, the target is not its own sidecar, and no other
 * process writes them (the lock taken). The working and snapshot files are checked as they are
 * made, also before the run. */
static vs_status check_targets(vs_output *o, vs_error *err) {
  const vs_outpath_other sidecar[1] = {{o->xmf_path, "its XDMF sidecar"}};
  char *xmf_tmp = suffixed(o->xmf_path, VS_XDMF_TMP);
  vs_status st = xmf_tmp == NULL ? vs_error_set(err, VS_ERR_NOMEM, "output: out of memory")
                                 : vs_outpath_check(o->path, sidecar, 1, err);
  if (st == VS_OK) st = vs_outpath_check(o->xmf_path, NULL, 0, err);
  if (st == VS_OK) st = vs_outpath_check_working(xmf_tmp, err);
  if (st == VS_OK) st = vs_xdmf_name_check(o->path, err); /* the sidecar must name the record */
  if (st == VS_OK) st = vs_outlock_acquire(o->path, &o->lock, err);
  free(xmf_tmp);
  return st;
}

/* Crash safety. HDF5 1.10 has no crash consistency: a flush rewrites metadata in place. What a
 * kill -9 at a random moment of a run (runs/reference.ini, about 30 flushes) left in the file
 * HDF5 writes was measured, when that file was the record itself (hence the snapshots: the
 * record is now a copy of it taken after a flush, and none of 1130 killed records tore):
 *  - HDF5's default file-space strategy reuses freed space: a partial chunk rewritten at a flush
 *    may land where the last flushed index still points. 22 killed files in 25 (a prototype
 *    writing like this one) had chunks that failed to inflate or held other data. Hence
 *    H5F_FSPACE_STRATEGY_NONE: freed space is never reused;
 *  - between flushes nothing is written (rows wait in memory), so a kill there leaves the state
 *    of the last flush intact. A kill inside a flush can tear it (1 record in 247 did). Of 140 killed files (deflate 4)
 *    138 were intact; 1 had some datasets a flush ahead of the others, the extra rows reading as
 *    NaN (-1 for integers: the fill values, never plausible numbers); in 1 the last chunk of
 *    /observables/.../step lay past the recorded end of file (that dataset fails to read). Without
 *    deflate flushes are shorter: 471 of 476 intact, 2 one flush behind in some datasets, 2 with
 *    NaN rows, 1 with a group index past the end of file;
 *  - the first snapshot is taken once the layout is complete; vs_output_finish only
 *    adds to /xdmf and /summary, created at the start, and rewrites root attributes in place (a
 *    kill while the root group gained /summary once left a file whose root could not be opened).
 *    What it adds (the outlines' frames in /xdmf, then /summary) is flushed before the status,
 *    which vouches for it; a reader of a "running" file must not trust it.
 * SWMR writing (H5Fstart_swmr_write, latest format) was measured too and rejected: a killed file
 * keeps an "open for writing" mark so that an ordinary open fails (h5py needs swmr=True, or
 * h5clear -s); 4 files in 194, killed while /summary was written, opened in no mode at all; and
 * one made an SWMR reader retry a torn index block for minutes. In 1.10 an SWMR writer cannot
 * create objects or attributes either (/summary and the final status would need a reopen).
 * Without deflate a chunk keeps its size, so a flush rewrites a partial chunk in place, and rows
 * are written at chunk boundaries (every flush_rows-th row), so most writes fill whole chunks. */
static vs_status file_create(vs_output *o, const char *path) {
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  vs_status st = VS_OK;
  if (fcpl < 0 || H5Pset_file_space_strategy(fcpl, H5F_FSPACE_STRATEGY_NONE, 0, 1) < 0)
    st = vs_h5_fail(&o->err, path, "cannot create the file");
  /* the cause is read before closing fcpl (any API call clears the error stack) */
  else if ((o->file = vs_h5_create(path, fcpl, &o->err)) < 0)
    st = o->err.status;
  vs_h5_close(fcpl);
  return st;
}

vs_status vs_output_create(const char *path, const vs_run *run, const char *case_text,
                           const vs_output_opts *opts, vs_output **out, vs_error *err) {
  *out = NULL;
  vs_output_opts def;
  vs_output_opts_default(&def);
  if (opts == NULL) opts = &def;
  vs_status st = check_opts(opts, err);
  if (st != VS_OK) return st;
  vs_output *o = calloc(1, sizeof *o);
  if (o == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  o->file = o->events = o->ev_mtype = H5I_INVALID_HID;
  for (int i = 0; i < S_COUNT; i++) o->s[i].dset = H5I_INVALID_HID;
  o->opts = *opts;
  o->last_phase = -1;
  const vs_joints_def *jd = &vs_run_def_of(run)->joints;
  o->mortar = jd->ft > 0.0 || jd->c > 0.0;
  vs_error_clear(&o->err);
  o->path = dup_str(path);
  o->xmf_path = vs_output_xdmf_path_for(path);
  if (o->path == NULL || o->xmf_path == NULL ||
      vs_record_geometry_init(o, vs_run_geometry(run)) != VS_OK) {
    vs_output_destroy(&o);
    return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  }
  o->flush_rows = vs_record_buffer_rows(o);
  st = check_targets(o, err);
  if (st != VS_OK) {
    vs_output_destroy(&o);
    return st;
  }
  /* HDF5 writes path.part; path is its snapshot (record_snapshot.c), the first once the layout
   * is written: a file at path always has its whole layout */
  o->part = suffixed(path, VS_OUT_PART);
  o->snap = suffixed(path, VS_OUT_SNAP);
  if (o->part == NULL || o->snap == NULL) {
    vs_output_destroy(&o);
    return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  }
  o->t_open = vs_wall_now();
  vs_h5_quiet q = vs_h5_quiet_begin();
  st = vs_outpath_clear(o->snap, &o->err); /* a kill's leftover removed; created at each snapshot */
  if (st == VS_OK) {
    st = file_create(o, o->part);
    if (st == VS_OK && vs_h5_file_id(o->file, &o->part_dev, &o->part_ino) != 0)
      st = vs_h5_fail(&o->err, o->part, "cannot read the identity of the file created");
    /* a part file from here on is ours, even half created (a full disk); not one refused */
    o->working = st != VS_ERR_INVALID;
    /* its last flush takes the first snapshot (always taken: vs_record_snapshot) */
    if (st == VS_OK) st = vs_record_layout_write(o, run, case_text);
  }
  vs_h5_quiet_end(q);
  if (st != VS_OK) {
    if (err != NULL) *err = o->err;
    o->pending = 0;
    o->err.status = VS_ERR_IO; /* destroy must not flush, and removes the part file */
    vs_output_destroy(&o);
    return st;
  }
  *out = o;
  return VS_OK;
}

/* After a failed write or flush HDF5 1.10.8 cannot close the file: every later flush fails
 * ("slist already enabled?") and a failed close leaves a half-torn file object on which the
 * library crashes at exit. Such a file is abandoned: its identifiers are left open (the process
 * releases them when it ends; see vs_output_process_end), and the file on disk keeps what the
 * last good flush wrote (status "running"). */
static void abandon_file(vs_output *o) {
  for (int i = 0; i < S_COUNT; i++) o->s[i].dset = H5I_INVALID_HID;
  o->events = H5I_INVALID_HID;
  o->file = H5I_INVALID_HID;
}

void vs_output_destroy(vs_output **op) {
  if (op == NULL || *op == NULL) return;
  vs_output *o = *op;
  vs_h5_quiet q = vs_h5_quiet_begin();
  /* the buffered rows (no snapshot: the closed file is renamed into place below) */
  if (o->file >= 0 && o->err.status == VS_OK) vs_record_write_pending(o);
  if (o->err.status != VS_OK) abandon_file(o);
  for (int i = 0; i < S_COUNT; i++) {
    vs_h5_close(o->s[i].dset);
    free(o->s[i].buf);
  }
  vs_h5_close(o->events);
  vs_h5_close(o->ev_mtype);
  free(o->ev_buf);
  const int closed = o->file >= 0 && H5Fclose(o->file) >= 0;
  o->file = H5I_INVALID_HID;
  H5Eclear2(H5E_DEFAULT);
  vs_h5_quiet_end(q);
  /* not finished: the closed working file, whole, replaces the snapshot; after a write error it
   * is removed, and path keeps the last snapshot; where path is no longer ours it stays */
  if (o->working &&
      !(closed && o->err.status == VS_OK &&
        vs_record_publish(o, o->part, o->part_dev, o->part_ino) == VS_OK) &&
      !(closed && o->stranded))
    unlink(o->part);
  vs_outlock_release(&o->lock);
  free(o->part);
  free(o->snap);
  free(o->path);
  free(o->xmf_path);
  free(o->bref);
  free(o->jref);
  free(o->rot);
  free(o);
  *op = NULL;
}

void vs_output_process_init(void) { H5dont_atexit(); }

void vs_output_process_end(int clean) {
  if (clean && H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_FILE) == 0) H5close();
}

const vs_error *vs_output_error(const vs_output *o) { return &o->err; }
long vs_output_rows(const vs_output *o) { return o->rows + o->pending; }
const char *vs_output_xdmf_path(const vs_output *o) { return o->xmf_path; }
int vs_output_xdmf_written(const vs_output *o) { return o->xmf_written; }

void vs_output_interrupt(vs_output *o) {
  if (o != NULL) o->interrupted = 1;
}

/* ------------------------------------------------------------------------------------------ */
/* Finish                                                                                       */

static void status_text(const vs_output *o, vs_status run_status, const vs_error *run_err,
                        char *buf, size_t size) {
  if (o->interrupted)
    snprintf(buf, size, "failed: interrupted");
  else if (o->err.status != VS_OK)
    snprintf(buf, size, "failed: %s", o->err.msg);
  else if (run_status == VS_ERR_WALL_TIME || run_status == VS_ERR_STOPPED) /* "stopped..." */
    snprintf(buf, size, "%s", run_err != NULL && run_err->msg[0] ? run_err->msg
                                                                  : vs_strerror(run_status));
  else if (run_status != VS_OK)
    snprintf(buf, size, "failed: %s%s%s", vs_strerror(run_status),
             run_err != NULL && run_err->msg[0] ? ": " : "", run_err != NULL ? run_err->msg : "");
  else
    snprintf(buf, size, "completed");
}

/* Dataset `name` of /xdmf with its attributes (unit and columns when not NULL), chunked by
 * chunk[0] rows; unwritten rows read as the fill value (NaN, -1), as in the time series;
 * shuffled and deflated when asked. */
static hid_t frames_dataset(const vs_output *o, hid_t grp, const char *name, int rank,
                            const hsize_t *dims, const hsize_t *chunk, hid_t ftype, hid_t mtype,
                            const void *fill, const char *unit, const char *columns,
                            const char *description) {
  hid_t p = H5Pcreate(H5P_DATASET_CREATE);
  herr_t rc = p >= 0 ? H5Pset_fill_value(p, mtype, fill) : -1;
  if (rc >= 0 && dims[0] > 0) rc = H5Pset_chunk(p, rank, chunk);
  if (rc >= 0 && dims[0] > 0 && o->opts.deflate > 0) rc = H5Pset_shuffle(p);
  if (rc >= 0 && dims[0] > 0 && o->opts.deflate > 0)
    rc = H5Pset_deflate(p, (unsigned)o->opts.deflate);
  hid_t sp = rc >= 0 ? H5Screate_simple(rank, dims, NULL) : H5I_INVALID_HID;
  hid_t d = sp >= 0 ? H5Dcreate2(grp, name, ftype, sp, H5P_DEFAULT, p, H5P_DEFAULT)
                    : H5I_INVALID_HID;
  rc = d >= 0 ? 0 : -1;
  if (rc >= 0 && unit != NULL) rc = vs_h5_attr_str(d, "unit", unit);
  if (rc >= 0 && columns != NULL) rc = vs_h5_attr_str(d, "columns", columns);
  if (rc >= 0) rc = vs_h5_attr_str(d, "description", description);
  vs_h5_close(sp);
  vs_h5_close(p);
  if (rc < 0) {
    vs_h5_close(d);
    return H5I_INVALID_HID;
  }
  return d;
}

/* Rows [start, start + count[0]) of dataset d from buf. */
static herr_t write_rows(hid_t d, hid_t mtype, int rank, hsize_t start0, const hsize_t *count,
                         const void *buf) {
  const hsize_t start[3] = {start0, 0, 0};
  hid_t fs = H5Dget_space(d), ms = H5Screate_simple(rank, count, NULL);
  herr_t rc = fs >= 0 && ms >= 0 ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL)
                                 : -1;
  if (rc >= 0) rc = H5Dwrite(d, mtype, ms, fs, H5P_DEFAULT, buf);
  vs_h5_close(ms);
  vs_h5_close(fs);
  return rc;
}

/* The n listed rows sel's outlines into /xdmf/block_points, computed a chunk of frames at a
 * time (at most about 1 MiB of them in memory), and the rows into /xdmf/block_points_row. */
static herr_t write_frames(const vs_output *o, hid_t grp, const double *cen, const long *sel,
                           long n) {
  const hsize_t pts = (hsize_t)o->nb * (hsize_t)o->np, frame_bytes = 2 * pts * sizeof(float);
  /* chunks of at most about 1 MiB, as even as can be: the last one, stored whole, wastes little */
  const hsize_t most = VS_OUT_CHUNK_BYTES / frame_bytes > 0 ? VS_OUT_CHUNK_BYTES / frame_bytes : 1;
  const hsize_t nf = n > 0 ? (hsize_t)n : 1, chunks = (nf + most - 1) / most;
  const hsize_t c = (nf + chunks - 1) / chunks;
  const hsize_t dims[3] = {(hsize_t)n, pts, 2}, chunk[3] = {c, pts, 2};
  const float nan_f = NAN;
  const int64_t minus1 = -1;
  float *buf = malloc((size_t)c * (size_t)frame_bytes);
  int64_t *row = malloc((size_t)(n > 0 ? n : 1) * sizeof *row);
  hid_t d = buf != NULL && row != NULL
                ? frames_dataset(o, grp, "block_points", 3, dims, chunk, H5T_IEEE_F32LE,
                                 H5T_NATIVE_FLOAT, &nan_f, "m,m", "x,z",
                                 "outline of every block moved to the rows the XDMF sidecar "
                                 "lists (float32, for display): frame i shows row "
                                 "block_points_row[i] of /observables; block b owns points "
                                 "b*P .. b*P+P-1, those of /geometry/block_points moved rigidly "
                                 "by /observables/block_position (centroid + (ux, uz) + rotation "
                                 "by theta about /geometry/block_centroid)")
                : H5I_INVALID_HID;
  herr_t rc = d >= 0 ? 0 : -1;
  for (long i = 0; rc >= 0 && i < n; i += (long)c) {
    const long m = n - i < (long)c ? n - i : (long)c;
    const hsize_t count[3] = {(hsize_t)m, pts, 2};
    rc = vs_xdmf_outlines(o->s[S_BPOS].dset, sel + i, m, o->nb, o->np, o->bref, cen, buf);
    if (rc >= 0) rc = write_rows(d, H5T_NATIVE_FLOAT, 3, (hsize_t)i, count, buf);
  }
  vs_h5_close(d);
  for (long i = 0; rc >= 0 && i < n; i++) row[i] = (int64_t)sel[i];
  const hsize_t rchunk[1] = {(hsize_t)(n > 0 ? n : 1)};
  d = rc >= 0 ? frames_dataset(o, grp, "block_points_row", 1, dims, rchunk, H5T_STD_I64LE,
                               H5T_NATIVE_INT64, &minus1, NULL, NULL,
                               "the row of /observables each frame of block_points shows")
              : H5I_INVALID_HID;
  rc = d >= 0 ? 0 : -1;
  if (rc >= 0 && n > 0) rc = write_rows(d, H5T_NATIVE_INT64, 1, 0, dims, row);
  vs_h5_close(d);
  free(buf);
  free(row);
  return rc;
}

/* /xdmf/block_points and /xdmf/block_points_row: the blocks' outlines moved to the rows the
 * sidecar lists (vs_xdmf_rows), and those rows. Kept for every row they were 30 % of a record's
 * bytes, and the sidecar is their only reader; they follow from /geometry/block_points and
 * /observables/block_position (read back here: as cheap as keeping every row's positions in
 * memory, 0.2 ms of the 5 these frames cost for 1400 rows), by the formula the joints' ends are
 * moved with. Written once every row is, before /summary and the status: a record that is not
 * "running" has them. */
static vs_status write_outlines(vs_output *o, const vs_run *run) {
  const vs_geometry *g = vs_run_geometry(run);
  const size_t nb = (size_t)o->nb;
  const long rows = o->rows;
  double *t = malloc((size_t)(rows > 0 ? rows : 1) * sizeof *t);
  double *cen = malloc(2 * (nb > 0 ? nb : 1) * sizeof *cen);
  long n = 0, *sel = NULL;
  herr_t rc = t != NULL && cen != NULL ? 0 : -1;
  if (rc >= 0 && rows > 0)
    rc = H5Dread(o->s[S_TIME].dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, t);
  if (rc >= 0) {
    n = vs_xdmf_rows(t, rows, o->opts.xdmf_max_grids, NULL);
    sel = malloc((size_t)(n > 0 ? n : 1) * sizeof *sel);
    rc = sel != NULL ? 0 : -1;
  }
  if (rc >= 0) {
    vs_xdmf_rows(t, rows, o->opts.xdmf_max_grids, sel);
    for (size_t b = 0; b < nb; b++) cen[2 * b] = g->blocks[b].cx, cen[2 * b + 1] = g->blocks[b].cz;
  }
  hid_t grp = rc >= 0 ? H5Gopen2(o->file, "xdmf", H5P_DEFAULT) : H5I_INVALID_HID;
  rc = grp >= 0 ? write_frames(o, grp, cen, sel, n) : -1;
  vs_h5_close(grp);
  free(t);
  free(cen);
  free(sel);
  return rc >= 0 ? VS_OK : vs_h5_fail(&o->err, o->path, "cannot write /xdmf/block_points");
}

/* The sidecar of the closed working file, naming the record path, written whole at tmp (the
 * name "<xmf_path>.tmp" into tmp, size bytes) and not yet put in place. */
static vs_status sidecar_tmp(const vs_output *o, char *tmp, size_t size, vs_error *err) {
  /* by name, but only the file created there: never a link put there during the run */
  vs_error why;
  const hid_t f = vs_h5_open_own(o->part, o->part_dev, o->part_ino, &why);
  const vs_status st =
      f < 0 ? vs_error_set(err, why.status, "output: %s: cannot reopen the working file: %s",
                           o->path, why.msg)
            : vs_xdmf_write_tmp(f, o->path, o->xmf_path, o->opts.xdmf_max_grids, tmp, size, err);
  vs_h5_close(f);
  return st;
}

vs_status vs_output_finish(vs_output *o, const vs_run *run, vs_status run_status,
                           const vs_error *run_err, vs_error *err) {
  if (o->finished) return vs_error_set(err, VS_ERR_INVALID, "output: %s: finished twice", o->path);
  o->finished = 1;
  vs_h5_quiet q = vs_h5_quiet_begin();
  vs_status st = o->err.status == VS_OK ? vs_record_write_pending(o) : o->err.status;
  if (st == VS_OK) st = write_outlines(o, run);
  if (st == VS_OK) st = vs_record_events_rewrite(o, run);
  if (st == VS_OK) st = vs_record_summary_write(o, run);
  /* what the status vouches for is on disk before the status is written */
  if (st == VS_OK && H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0)
    st = vs_h5_fail(&o->err, o->path, "cannot flush /events and /summary");
  if (st == VS_OK) st = vs_record_snapshot(o);
  if (st == VS_OK) vs_fault_point("before-status");
  /* the status is recorded when the run failed but the file is sound (see abandon_file) */
  char status[sizeof o->err.msg + 64], now[32];
  status_text(o, run_status, run_err, status, sizeof status);
  vs_iso8601_utc(now, sizeof now);
  if (o->err.status == VS_OK && o->file >= 0 &&
      (vs_h5_attr_str(o->file, "status", status) < 0 ||
       vs_h5_attr_str(o->file, "finished", now) < 0 || H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0))
    st = vs_h5_fail(&o->err, o->path, "cannot write the status");
  if (o->err.status != VS_OK) abandon_file(o);
  /* the sidecar is written from what the closed file holds */
  for (int i = 0; i < S_COUNT; i++) {
    vs_h5_close(o->s[i].dset);
    o->s[i].dset = H5I_INVALID_HID;
  }
  vs_h5_close(o->events);
  o->events = H5I_INVALID_HID;
  if (o->file >= 0 && H5Fclose(o->file) < 0 && st == VS_OK)
    st = vs_h5_fail(&o->err, o->path, "cannot close");
  o->file = H5I_INVALID_HID;
  /* the sidecar is written from the closed working file before that file is put in place, and
   * put in place after it: a record at path is never beside a sidecar that is not its own (the
   * previous record's went with the first snapshot); a kill between the two renames leaves the
   * record without a sidecar (vs_output_write_xdmf rebuilds it) */
  char tmp[4096];
  vs_error side; /* the sidecar's outcome */
  vs_error_set(&side, VS_ERR_INTERNAL, "output: %s: no record, no sidecar", o->path);
  if (o->working && st == VS_OK) side.status = sidecar_tmp(o, tmp, sizeof tmp, &side);
  /* the closed working file replaces the snapshot (after a write error: removed, path keeps
   * the last snapshot; where path is no longer ours, the working file stays, whole) */
  if (o->working && st == VS_OK && vs_record_publish(o, o->part, o->part_dev, o->part_ino) != VS_OK)
    st = o->stranded ? vs_record_stranded_error(o, &o->err) : o->err.status;
  if (o->working && st != VS_OK && !o->stranded) unlink(o->part);
  o->working = 0;
  if (st == VS_OK) vs_fault_point("after-status");
  if (side.status == VS_OK && st != VS_OK) remove(tmp); /* no record in place: no sidecar */
  if (st == VS_OK && side.status != VS_OK) st = (o->err = side).status; /* the record in place */
  if (st == VS_OK) st = vs_xdmf_publish(tmp, o->xmf_path, &o->err);
  o->xmf_written = st == VS_OK;
  H5Eclear2(H5E_DEFAULT);
  vs_h5_quiet_end(q);
  if (st != VS_OK && err != NULL) *err = o->err;
  return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Rows                                                                                         */

/* Point (X, Z) of body `body` of joint j in the reference configuration, moved to the state q
 * with the supports at usup (left ux, uz, theta, then right; a support turns about its pivot,
 * the centre of its springing joint j); rot: every block's cos and sin of its rotation in q. */
static void body_move(const vs_geometry *g, const double *q, const double *rot,
                      const double usup[6], const vs_joint_geom *j, int body, double X, double Z,
                      double out[2]) {
  if (body < 0) { /* a support */
    const double *u = usup + (body == VS_SUPPORT_LEFT ? 0 : 3);
    if (u[2] == 0.0) { /* most supports never turn: their points only translate */
      out[0] = X + u[0];
      out[1] = Z + u[1];
    } else {
      vs_xdmf_move(j->px, j->pz, u[0], u[1], cos(u[2]), sin(u[2]), X, Z, out);
    }
  } else {
    const vs_block *b = &g->blocks[body];
    vs_xdmf_move(b->cx, b->cz, q[3 * body], q[3 * body + 1], rot[2 * body], rot[2 * body + 1], X,
                 Z, out);
  }
}

/* The blocks' series; their moved outlines are not kept for every row (see write_outlines). */
static void fill_blocks(vs_output *o, const vs_run_sample *s) {
  const size_t n3 = 3 * (size_t)o->nb;
  double *bv = row_ptr(o, S_BVEL), *sp = row_ptr(o, S_BSPEED);
  memcpy(row_ptr(o, S_BPOS), s->q, n3 * sizeof(double));
  if (s->v != NULL)
    memcpy(bv, s->v, n3 * sizeof(double));
  else
    memset(bv, 0, n3 * sizeof(double));
  for (int b = 0; b < o->nb; b++) sp[b] = hypot(bv[3 * b], bv[3 * b + 1]);
}

static void fill_joints(vs_output *o, const vs_run *run, const vs_run_sample *s,
                        const double usup[6]) {
  const vs_geometry *g = vs_run_geometry(run);
  const vs_hinge_opts *ho = vs_run_hinge_opts(run);
  double *N = row_ptr(o, S_N), *T = row_ptr(o, S_T), *M = row_ptr(o, S_M);
  double *c = row_ptr(o, S_CONTACT), *gi = row_ptr(o, S_GAP_I), *ge = row_ptr(o, S_GAP_E);
  double *sl = row_ptr(o, S_SLIP), *sp = row_ptr(o, S_SLIP_P), *cr = row_ptr(o, S_CRACK);
  int8_t *h = row_ptr(o, S_HINGE);
  float *pts = row_ptr(o, S_JPTS);
  vs_run_joint_cracks(run, cr); /* as committed, per joint from the intrados and extrados */
  for (int k = 0; k < o->nj; k++) {
    const vs_joint_state *st = &s->joints[k]; /* the run's evaluation at this state */
    N[k] = st->N, T[k] = st->T, M[k] = st->M, c[k] = st->contact;
    gi[k] = st->gap_i, ge[k] = st->gap_e, sl[k] = st->slip, sp[k] = st->slip_p;
    const char side = vs_hinges_joint_side(ho, st);
    h[k] = (int8_t)(side == 'I' ? 1 : side == 'E' ? 2 : 0);
    const vs_joint_geom *j = &g->joints[k];
    for (int e = 0; e < 2; e++) {
      double pa[2], pb[2];
      body_move(g, s->q, o->rot, usup, j, j->a, o->jref[4 * k + 2 * e],
                o->jref[4 * k + 2 * e + 1], pa);
      body_move(g, s->q, o->rot, usup, j, j->b, o->jref[4 * k + 2 * e],
                o->jref[4 * k + 2 * e + 1], pb);
      pts[4 * k + 2 * e] = (float)(0.5 * (pa[0] + pb[0]));
      pts[4 * k + 2 * e + 1] = (float)(0.5 * (pa[1] + pb[1]));
    }
  }
}

static void fill_row(vs_output *o, const vs_run *run, const vs_run_sample *s) {
  const vs_model *m = vs_run_model(run);
  double usup[6]; /* both supports' (ux, uz, theta) */
  vs_model_support_position(m, s->q, s->delta, usup);
  *(int64_t *)row_ptr(o, S_STEP) = (int64_t)(o->rows + o->pending);
  *(double *)row_ptr(o, S_TIME) = s->t;
  *(double *)row_ptr(o, S_DELTA) = s->delta;
  memcpy(row_ptr(o, S_SUPPORT), usup + 3, 2 * sizeof *usup);
  memcpy(row_ptr(o, S_SUPPORTS), usup, sizeof usup);
  *(int8_t *)row_ptr(o, S_PHASE) = (int8_t)s->phase;
  /* one cos and sin per block and row (the joints' ends use them) */
  for (int b = 0; b < o->nb; b++) {
    o->rot[2 * b] = cos(s->q[3 * b + 2]);
    o->rot[2 * b + 1] = sin(s->q[3 * b + 2]);
  }
  fill_blocks(o, s);
  fill_joints(o, run, s, usup);
  double *r = row_ptr(o, S_REACT);
  memcpy(r, s->reactions, 6 * sizeof *r); /* the run's, at this state */
  int64_t *sv = row_ptr(o, S_SOLVER);
  sv[0] = (int64_t)s->newton_iterations;
  sv[1] = (int64_t)s->ida_steps;
  sv[2] = (int64_t)s->ida_newton_iterations;
  if (o->mortar) *(double *)row_ptr(o, S_CRACKING) = vs_model_cracking_energy(vs_run_model(run));
  double *e = row_ptr(o, S_ENERGY);
  if (s->energy != NULL) {
    const vs_energy *en = s->energy;
    const double v[7] = {en->kinetic, en->gravity,  en->elastic, en->support_work,
                         en->damped,  en->friction, en->balance};
    memcpy(e, v, sizeof v);
  } else {
    e[0] = 0.0;
    e[1] = s->gravity;
    e[2] = s->elastic;
    e[3] = e[4] = e[5] = e[6] = NAN;
  }
}

int vs_output_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  vs_output *o = user;
  if (o->err.status != VS_OK || o->interrupted || o->finished) return 1;
  vs_h5_quiet q = vs_h5_quiet_begin();
  vs_status st = VS_OK;
  if (o->last_phase >= 0 && (int)s->phase != o->last_phase) st = vs_record_flush(o);
  if (st == VS_OK) {
    fill_row(o, run, s);
    o->pending++;
    o->last_phase = (int)s->phase;
    /* at every flush_rows-th row of the file: the writes fill whole chunks */
    if ((size_t)(o->rows + o->pending) % o->flush_rows == 0) st = vs_record_flush(o);
  }
  vs_h5_quiet_end(q);
  return st == VS_OK ? 0 : 1;
}

