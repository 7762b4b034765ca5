/* The record of a run: an HDF5 file laid out in the spirit of H5MD (the case's parameters, the
 * reference geometry, one group per time-dependent quantity, an event table and a summary) and
 * an XDMF sidecar with which ParaView plays the motion. SI units; every floating-point dataset
 * carries a "unit" attribute. HDF5 writes "<path>.part"; the file at path is a whole copy of it
 * taken after a flush and renamed into place (vs_output_opts.snapshot_share), and at the end the
 * closed file itself: a run killed at any moment (even by SIGKILL) leaves at path nothing (before
 * the first snapshot) or a file that HDF5 opens normally and reads whole, every time series up
 * to the same row. */
#ifndef VOUSSOIR_OUTPUT_H
#define VOUSSOIR_OUTPUT_H

#include "voussoir/api.h"

#include "voussoir/run.h"
#include "voussoir/status.h"

typedef struct vs_output vs_output;

typedef struct {
  int arc_points;     /* points inside each arc (intrados, extrados) of a voussoir's outline, in
                         [0, 64]; default 2: polygons of 2 + 2 corners + 2 x 2 arc points */
  int flush_rows;     /* rows are written and the file flushed at every flush_rows-th row of
                         the file, >= 1, default 64 (and at every phase switch); events are
                         buffered and written with the rows */
  int chunk_rows;     /* rows per chunk of the time series, >= 1, default 64; lowered to a
                         divisor of flush_rows (writes then fill whole chunks) and capped at
                         about 1 MiB for wide rows */
  int deflate;        /* deflate level with shuffle, 1 to 9, or 0 (default): no compression
                         (measured on runs/reference.ini: level 4 makes the record 3.4 MB
                         instead of 5.1 MB and its writes longer; `run --compress` sets 4) */
  int xdmf_max_grids; /* the XDMF lists at most this many rows (>= 2, default 2000): every k-th
                         row with k = ceil(rows / xdmf_max_grids), and always the last one; the
                         record keeps the blocks' moved outlines of those rows only */
  double snapshot_share; /* the file at path is a snapshot: HDF5 writes "<path>.part", which is
                         copied and the copy renamed over path after a flush, as long as the
                         copies take at most this share of the wall time since the start, in
                         (0, 1], default 0.1; 1: after every flush. Always after the layout; at
                         the end the working file itself is renamed */
} vs_output_opts;

/* Fill o with the defaults above. */
VS_API void vs_output_opts_default(vs_output_opts *o);

/* Create the HDF5 file at path (replaced if it exists; written as "<path>.part", copied to
 * "<path>.snap" and renamed over path after the layout and some flushes, renamed itself at the
 * end; a killed run's .part and .snap are removed). path and its sidecar must be absent or
 * regular files (vs_outpath_check), path's file name one the sidecar can refer to (printable
 * UTF-8 text with no ':' or '|' and no leading blank: ParaView's XDMF reader splits and trims
 * there), and path is locked for this writer until vs_output_destroy (vs_outlock_acquire):
 * otherwise VS_ERR_INVALID and nothing is created. For run (borrowed: its geometry and model are read now and at every sample), with
 * opts (NULL: defaults) copied. Writes the root attributes (program "voussoir", version, layout,
 * created: ISO 8601 UTC, case: case_text or "" when NULL, status "running", finished ""),
 * /parameters (the case's values, as attributes named after the case keys, in the case's
 * units), /geometry (the reference configuration), an empty /summary, the empty time series and
 * event table, and flushes. The XDMF sidecar's path is path with its extension (".h5", ".hdf5",
 * ".hdf") replaced by ".xmf" (or ".xmf" appended); it is written by vs_output_finish. *out
 * receives the writer (NULL on failure). Errors: VS_ERR_IO with the HDF5 cause (path is left as it
 * was), VS_ERR_INVALID for bad options, VS_ERR_NOMEM. */
VS_API vs_status vs_output_create(const char *path, const vs_run *run, const char *case_text,
                                  const vs_output_opts *opts, vs_output **out, vs_error *err);

/* A vs_run_sample_fn: user is the vs_output. Appends one row to every time series (buffered;
 * written with the buffered events and flushed at every flush_rows-th row and whenever the
 * phase changes). Returns 0, or 1
 * when the file cannot be written (the run then stops; vs_output_error has the cause) or after
 * vs_output_interrupt. */
VS_API int vs_output_sample(void *user, const vs_run *run, const vs_run_sample *s);

/* A vs_run_event_fn: user is the vs_output. Buffers the event for /events (written with the next
 * rows; all events are written again by vs_output_finish). Returns as vs_output_sample. */
VS_API int vs_output_event(void *user, const vs_run *run, const vs_run_event *e);

/* Mark the run as interrupted (e.g. after SIGINT; call it from normal code, not from a signal
 * handler): the next sample or event callback returns 1 so that the run stops, and
 * vs_output_finish records status "failed: interrupted". NULL is ignored. */
VS_API void vs_output_interrupt(vs_output *o);

/* Close the record of run: write the buffered rows, then the blocks' outlines moved to the rows
 * the sidecar lists (/xdmf/block_points, and the rows in /xdmf/block_points_row: computed from
 * /observables/block_position and /geometry), rewrite /events from the run's log (hinge
 * labels are assigned after the first three hinge events were emitted), write /summary (limit
 * points, first limit point, collapse, hinges, mode, totals, energy balance) and flush; only
 * then (so that a "completed" on disk vouches for them) set the root attributes status ("completed" when run_status is VS_OK, else "failed: <cause>" with run_err's
 * message when given, "failed: <cause>" of a write error, "failed: interrupted" after
 * vs_output_interrupt, "stopped: wall-time limit S s reached" (run_err's message) when
 * run_status is VS_ERR_WALL_TIME, "stopped by the caller" (run_err's message) when it is
 * VS_ERR_STOPPED: the record holds the run up to its stop) and finished (ISO
 * 8601 UTC), close the file and write the XDMF sidecar. Call
 * it at most once, after vs_run_execute (a second call fails with VS_ERR_INVALID). Returns VS_OK or
 * VS_ERR_IO (err, and vs_output_error, have the cause). For the crash tests only: when the
 * environment variable VS_FAULT_KILL is "before-status" (everything flushed but the status) or
 * "after-status" (the file closed and renamed over path, the sidecar not yet written), or, in a
 * snapshot after the layout's, "mid-snapshot" (half of the copy written) or "before-publish"
 * (the copy written, not renamed), the process kills itself with SIGKILL at that point. */
VS_API vs_status vs_output_finish(vs_output *o, const vs_run *run, vs_status run_status,
                                  const vs_error *run_err, vs_error *err);

/* The first write error of o (status VS_OK if none); never NULL for a non-NULL o. */
VS_API const vs_error *vs_output_error(const vs_output *o);

/* Rows written so far (flushed or buffered). */
VS_API long vs_output_rows(const vs_output *o);

/* Path of the XDMF sidecar: an XDMF 3 temporal collection with one spatial collection per listed
 * row (Time = the loading time, s; rows whose time does not increase, or is NaN, are skipped),
 * holding two
 * grids in the x-z plane (GeometryType XY: x, z): "blocks", one polygon per voussoir (cell
 * attributes theta, rad, and speed, m/s) and "joints", one segment per joint from intrados to
 * extrados (N, N; gap_i, gap_e, m; hinge 0/1/2). Rows are XDMF 3 hyperslabs of the time series
 * ("file:/path|start:stride:count:dims"): ParaView's default reader for .xmf (Xdmf3ReaderS/T)
 * plays it; its legacy "XDMF Reader" does not read this form. */
VS_API const char *vs_output_xdmf_path(const vs_output *o);

/* 1 once vs_output_finish has written the XDMF sidecar, else 0. */
VS_API int vs_output_xdmf_written(const vs_output *o);

/* The sidecar's path for a record at h5_path (see vs_output_xdmf_path), malloc'd (the caller
 * frees it), or NULL when out of memory. */
VS_API char *vs_output_xdmf_path_for(const char *h5_path);

/* Close every HDF5 object and the file (flushing it), free o and NULL *o; NULL and *o == NULL
 * are allowed. Without vs_output_finish the buffered rows are written but the status stays
 * "running" and there is no XDMF. */
VS_API void vs_output_destroy(vs_output **o);

/* For a program: call vs_output_process_init before anything else uses HDF5 and
 * vs_output_process_end before it exits, with clean = 0 if a record failed to be created or
 * written (vs_output_create returned VS_ERR_IO, or vs_output_error is set). HDF5 1.10 cannot
 * close a file after a failed write (a full disk) and would crash, or loop, in its exit handler;
 * such a file is abandoned (it keeps what its last good flush wrote, status "running"), the exit
 * handler is not installed, and process_end shuts HDF5 down only when it is clean and no file
 * is left open. */
VS_API void vs_output_process_init(void);
VS_API void vs_output_process_end(int clean);

/* Write the XDMF sidecar of an existing record (e.g. of a run that was killed) next to it, from
 * the datasets it holds (opened read-only); max_grids as in vs_output_opts (<= 0: the default).
 * The blocks' outlines of a listed row are the record's /xdmf/block_points frame of that row when
 * its status is not "running" (written before the status), an earlier version's
 * /observables/block_points/value, or else computed from the positions and written into the
 * sidecar (Format="XML"). Errors: VS_ERR_IO
 * (cannot open or read the file, or write the sidecar), VS_ERR_INVALID (not a voussoir
 * record). */
VS_API vs_status vs_output_write_xdmf(const char *h5_path, int max_grids, vs_error *err);

#endif
