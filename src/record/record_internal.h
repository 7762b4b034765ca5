/* Private to the record's sources (record*.c): the writer's state, the per-state series of the
 * schema (record_series.c holds the table), the packed /events row, and the functions the
 * record's files share. Not installed. */
#ifndef VS_RECORD_INTERNAL_H
#define VS_RECORD_INTERNAL_H

#include <hdf5.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "fault.h"
#include "h5util.h"
#include "outpath.h"
#include "voussoir/output.h"
#include "wall_clock.h"

/* Buffered rows stay under this many bytes (wide rows: fewer rows per flush). */
#define VS_OUT_BUFFER_BYTES ((size_t)16 << 20)
/* A chunk stays under this many bytes (wide rows: fewer rows per chunk). */
#define VS_OUT_CHUNK_BYTES ((size_t)1 << 20)

/* The per-state series, in the order of the schema table (record_series.c). */
enum {
  S_STEP,
  S_TIME,
  S_DELTA,
  S_SUPPORT,
  S_PHASE,
  S_BPOS,
  S_BVEL,
  S_BSPEED,
  S_N,
  S_T,
  S_M,
  S_CONTACT,
  S_GAP_I,
  S_GAP_E,
  S_SLIP,
  S_SLIP_P,
  S_HINGE,
  S_REACT,
  S_ENERGY,
  S_JPTS,
  S_SOLVER,
  S_SUPPORTS, /* both supports (docs/model.md, "Both supports move") */
  S_CRACK,    /* mortar: each joint's cracked-through lengths */
  S_CRACKING, /* mortar only (a dry run's record has none): the energy cracking dissipated */
  S_COUNT
};

typedef struct {
  hid_t dset;
  int rank;
  hsize_t dims[3];  /* dims[0] = rows written to the file */
  size_t row_elems; /* elements per row */
  size_t esize;     /* bytes per element */
  hid_t mtype;
  unsigned char *buf; /* pending rows */
} series;

/* One row of /events as stored: packed, little-endian (the file's compound type, also used as
 * the memory type, so a write converts nothing): time f64 at 0, delta f64 at 8, joint i32 at 16,
 * side char at 20, label char at 21, phase i8 at 22, order i32 at 23, kind char[16] at 27
 * (NUL-padded). */
enum {
  EV_TIME = 0,
  EV_DELTA = 8,
  EV_JOINT = 16,
  EV_SIDE = 20,
  EV_LABEL = 21,
  EV_PHASE = 22,
  EV_ORDER = 23,
  EV_KIND = 27,
  EV_KIND_LEN = 16,
  EV_LOAD = 43,
  EV_SIZE = 51
};
typedef struct {
  unsigned char b[EV_SIZE];
} event_row;

struct vs_output {
  hid_t file;
  char *path, *xmf_path;
  char *part, *snap;  /* the working file HDF5 writes, path.part; a snapshot's copy, path.snap */
  vs_output_opts opts;
  int nb, nj, np;     /* blocks, joints, outline points per block */
  int mortar;         /* a mortared run (joints.tensile_MPa or cohesion_MPa > 0): S_CRACKING */
  size_t flush_rows;  /* rows buffered before a write */
  double *bref;       /* reference outlines, nb * np * 2 (/xdmf/block_points moves them) */
  double *jref;       /* reference joint ends (intrados, extrados), nj * 2 * 2 */
  double *rot;        /* per block: cos, sin of its rotation at the row being filled */
  series s[S_COUNT];
  long rows;              /* written to the file */
  long pending;           /* buffered */
  int last_phase;         /* of the last row, -1 before any */
  hid_t events, ev_mtype; /* /events and its (packed, file = memory) type */
  long n_events;          /* written to the file */
  event_row *ev_buf;      /* events waiting for the next write */
  long ev_pending, ev_cap;
  int interrupted, finished, xmf_written;
  int working;      /* 1 while path.part is ours: created, not yet renamed over path */
  dev_t part_dev;   /* path.part's identity once created: a reopen by name checks it is the */
  ino_t part_ino;   /* same file, never a link or another put there (vs_outpath_open_own) */
  int stranded;     /* 1 once path became something other than a regular file during the run:
                       nothing is renamed over it again, and the record stays whole in path.part
                       (record_snapshot.c) */
  int replaced;     /* 1 once something was renamed over path: the sidecar beside the record
                       that was there (not this run's) was removed just before */
  vs_outlock *lock; /* the exclusive lock on path, held until destroy */
  double t_open;    /* wall clock at the start, s */
  double snap_spent, snap_last, snap_size; /* the snapshots' wall time, the last's, its bytes */
  long snapshots;
  vs_error err;     /* first write error (sticky) */
};

/* Whether the record has series i (record_series.c). */
int vs_record_series_used(const vs_output *o, int i);

/* Where row `pending` of series i is buffered. */
static inline void *row_ptr(vs_output *o, int i) {
  series *s = &o->s[i];
  return s->buf + (size_t)o->pending * s->row_elems * s->esize;
}

/* record_snapshot.c: the file at path is a snapshot of the working file (see there) */
/* Rename `from` (the file this run created there: dev, ino) over o->path, checked just before:
 * never over anything but a regular file, and never anything but that file (a link or another
 * file put at `from` during the run is refused: VS_ERR_INVALID in o->err). The first time, the
 * sidecar at o->xmf_path (a regular file: another record's) is removed first.
 * VS_OK; VS_ERR_INVALID when path has become something else (o->stranded set, o->err left
 * alone: the working file is sound) or was already; VS_ERR_IO (in o->err) when the rename
 * failed. */
vs_status vs_record_publish(vs_output *o, const char *from, dev_t dev, ino_t ino);
/* The error of a stranded record (o->stranded) into err: path not replaced, the record in
 * path.part. */
vs_status vs_record_stranded_error(const vs_output *o, vs_error *err);
/* After a flush: copy the working file and rename the copy over path if it is the first (the
 * layout's), or when the snapshots' wall time, with this one's (estimated from the last's and the
 * file's growth), stays within opts.snapshot_share of the time since the start (always when it
 * is 1). VS_OK, or VS_ERR_IO with the cause in o->err (the copy removed, path left as it was).
 * Once path has become something other than a regular file (o->stranded) there are no more
 * snapshots, and the run goes on writing path.part. */
vs_status vs_record_snapshot(vs_output *o);

/* record_series.c: the schema table and the buffered rows */
/* Rows buffered before a write: opts.flush_rows, fewer when rows are wide. */
size_t vs_record_buffer_rows(const vs_output *o);
/* Create series i in /observables (its group first, if new) and link the shared step and time
 * into the group; allocates its row buffer. */
herr_t vs_record_series_create(vs_output *o, hid_t obs, int i);
/* Append the buffered rows of every series, and the buffered events, to the file (no flush). */
vs_status vs_record_write_pending(vs_output *o);
/* vs_record_write_pending, then flush the file. */
vs_status vs_record_flush(vs_output *o);

/* record_layout.c: what does not change during a run */
/* o's block outlines and joint ends in the reference configuration (nb, nj, np, bref, jref). */
vs_status vs_record_geometry_init(vs_output *o, const vs_geometry *g);
/* Root attributes, /parameters, /geometry, /imperfections, the empty /summary, the series and
 * /events, flushed; errors recorded on o. */
vs_status vs_record_layout_write(vs_output *o, const vs_run *run, const char *case_text);

/* record_events.c: /events */
herr_t vs_record_events_create(vs_output *o);
/* Append the buffered events to /events (no flush). */
vs_status vs_record_events_append(vs_output *o);
/* Rewrite /events from the run's log: the first three hinges get their labels together, after
 * their events were emitted. */
vs_status vs_record_events_rewrite(vs_output *o, const vs_run *run);

/* record_summary.c: /summary, filled when the run is finished */
vs_status vs_record_summary_write(vs_output *o, const vs_run *run);

#endif
