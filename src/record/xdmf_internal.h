/* Private to the sidecar's sources (xdmf*.c): the state of a sidecar being written, the
 * datasets it refers to, where the blocks' outlines come from, and the functions the files
 * share. xdmf.h is what the record's writer uses. Not installed. */
#ifndef VS_XDMF_INTERNAL_H
#define VS_XDMF_INTERNAL_H

#include <hdf5.h>
#include <stdio.h>

#include "voussoir/status.h"

/* The datasets the sidecar refers to (their paths: XDMF_PATHS, xdmf_record.c). */
typedef struct {
  const char *path; /* in the HDF5 file */
  int rank;
  hsize_t dims[3];
} xdmf_ds;

enum {
  X_BPTS,
  X_BCONN,
  X_JPTS,
  X_JCONN,
  X_TIME,
  X_BPOS,
  X_BSPEED,
  X_N,
  X_T,
  X_M,
  X_GAPI,
  X_GAPE,
  X_HINGE,
  X_REACT,
  X_SUPPORT,
  X_CRACK,
  X_COUNT
};

/* The grids of a row, in this order (the ground only when the fall landed on it, the load only
 * for a live load: /summary/load/forces). */
enum { G_BLOCKS, G_JOINTS, G_LEFT, G_RIGHT, G_GROUND, G_LOAD, G_COUNT };

/* Where the blocks' moved outlines of a listed row come from: a record written by this version
 * holds them for the rows its sidecar lists (/xdmf/block_points, its row numbers in
 * /xdmf/block_points_row, written at the finish, before /summary and the status); one written
 * by an earlier version holds them for every row (/observables/block_points/value). Rows that
 * have neither (a killed run's record, whose status is still "running", or a sidecar listing
 * other rows) get theirs computed from /observables/block_position and /geometry, inline. */
enum { BP_STATES, BP_FRAMES, BP_INLINE };
#define XDMF_BPTS_STATES "/observables/block_points/value"
#define XDMF_BPTS_FRAMES "/xdmf/block_points"
#define XDMF_BPTS_ROWS "/xdmf/block_points_row"

typedef struct {
  FILE *f;
  char buf[1 << 15]; /* what is written goes through here: see out_mem */
  size_t used;
  const char *h5name; /* XML-escaped name of the HDF5 file, relative to the sidecar */
  xdmf_ds ds[X_COUNT];
  int ground;              /* the record has /summary/ground/points */
  int n_loads;             /* rows of /summary/load/forces (0: none) */
  double *loads;           /* those rows: block, fx, fz, px, pz */
  long n_curve;            /* rows of /summary/load/curve: a load run's path, the record's last
                              n_curve rows (0: none, or not a load run) ... */
  double *curve_lambda;    /* ... and the load factor of each */
  long rows;               /* the record's rows */
  hid_t load_pos;          /* with a live load: /observables/block_position/value, open ... */
  double *load_q, *load_cen; /* ... a row of it (nb x 3) and /geometry/block_centroid */
  double load_arrow;       /* an arrow's length per N (xdmf_load_shared), m/N */
  double joint_len;        /* /geometry/joint_length's first (0: not read) */
  hsize_t sup_joint[2];    /* the joints on the left and the right support: the springings, or
                              with piers their bases (the first of /geometry/joint_bodies with
                              body -1, -2; vs_xdmf_support_joints) */
  hsize_t nan_n;           /* values in /xdmf/nan (0: the record has none) */
  char pads[G_COUNT][160]; /* each grid's include of its NaN fields */
  int bp_source;           /* BP_STATES, BP_FRAMES or BP_INLINE */
  long *geo;     /* per listed row: its frame of /xdmf/block_points, or -1 - its inline frame */
  long listed;   /* rows listed so far */
  /* the inline frames: need[i] is the row of inline frame i; inl holds the outlines of frames
   * inl_at .. inl_at + XDMF_INLINE_BLOCK - 1 (nb * P * 2 values each), computed from pos (the
   * record's /observables/block_position/value), ref and cen (its /geometry/block_points and
   * block_centroid) as the rows are written; failed: one could not be read */
  long *need, n_inl, inl_at;
  float *inl;
  hid_t pos;
  double *ref, *cen;
  int failed;
} xdmf_ctx;

/* Inline frames computed at a time: the memory they take stays small whatever the rows. */
#define XDMF_INLINE_BLOCK 64

/* NaN values the grids' padding refers to (written with the record's layout). */
#define XDMF_NAN "/xdmf/nan"

/* xdmf_record.c: the record read, the sidecar's file */
/* Shapes of the datasets the XDMF refers to; the number of rows they all hold; -1 if the file
 * is not a consistent voussoir record. */
long vs_xdmf_shapes(hid_t file, xdmf_ctx *x);
/* The rows the sidecar lists into *sel (n of them) and where their outlines come from: reads
 * the times and, for rows without a frame in the record, the blocks' positions. */
vs_status vs_xdmf_listing(hid_t file, xdmf_ctx *x, long rows, int max_grids,
                          const char *h5_path, double **t, long **sel, long *n,
                          vs_error *err);
/* Whether the record has the ground the fall landed on: /summary/ground/points, 2 x 2 (the
 * sidecar refers to it as such). */
int vs_xdmf_has_ground(hid_t file);
/* The live load of a load run, /summary/load/forces, into x->loads (malloc'd) and x->n_loads;
 * none (0) when the record has no such table or it cannot be read; then its path's load factors
 * (/summary/load/curve's first column: x->curve_lambda, x->n_curve) and what moves the load
 * with its blocks (x->load_pos, load_q, load_cen; the load is not drawn when they cannot be
 * read). Before vs_xdmf_listing (which times a load run's rows by their number). */
void vs_xdmf_loads(hid_t file, xdmf_ctx *x);
/* Row r's block positions into x->load_q (nb x 3); 0, or -1 when it cannot be read. */
int vs_xdmf_load_row(xdmf_ctx *x, hsize_t r);
/* /geometry/joint_length's first value (the springing's: the arch's thickness), 0 when it
 * cannot be read. */
double vs_xdmf_joint_length(hid_t file);

/* x->sup_joint from the record's /geometry/joint_bodies (unreadable: the first joint and the
 * last, every record's springings before piers). */
void vs_xdmf_support_joints(hid_t file, xdmf_ctx *x);

/* The number of values of a rank-1 /xdmf/nan, or 0 if the record has none. */
hsize_t vs_xdmf_nan_count(hid_t file);
/* Create "<xmf_path>.tmp" (its name into tmp) anew for writing (vs_outpath_fopen): never
 * written through, nor renamed over, anything but a regular file. */
vs_status vs_xdmf_open_tmp(const char *xmf_path, char *tmp, size_t size, FILE **f,
                           vs_error *err);
/* Close f, the sidecar written at tmp; on a write error remove tmp. */
vs_status vs_xdmf_close_tmp(FILE *f, const char *tmp, const char *xmf_path, vs_error *err);

/* xdmf_rows.c */
/* The k of vs_xdmf_rows: ceil(rows / max_grids), at least 1. */
long vs_xdmf_stride(long rows, int max_grids);

#endif
