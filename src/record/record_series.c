/* The record's per-state series: the schema in one table (group, dataset, element kind,
 * dimensions, unit, columns, description), the datasets made from it, and the buffered rows
 * appended to them in whole chunks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "record_internal.h"

typedef enum { K_F64, K_F32, K_I8, K_I64 } elem_kind;

/* Symbolic sizes of the dimensions after the row. */
enum { DIM_BLOCKS = -1, DIM_JOINTS = -2, DIM_JOINT_POINTS = -4 };

typedef struct {
  const char *group, *dataset;
  elem_kind kind;
  int rank;   /* including the row dimension */
  int dim[2]; /* sizes of dimensions 1 and 2 (a DIM_ code or a count) */
  const char *unit, *columns, *description;
} series_def;

/* clang-format off */
static const series_def SERIES[S_COUNT] = {
    [S_STEP] = {"delta", "step", K_I64, 1, {0, 0}, NULL, NULL,
                "row index (0-based); shared by every observable (hard links)"},
    [S_TIME] = {"delta", "time", K_F64, 1, {0, 0}, "s", NULL,
                "loading time t = delta / rate; shared by every observable (hard links)"},
    [S_DELTA] = {"delta", "value", K_F64, 1, {0, 0}, "m", NULL,
                 "support displacement delta along the direction alpha"},
    [S_SUPPORT] = {"support_displacement", "value", K_F64, 2, {2, 0}, "m,m", "ux,uz",
                   "displacement of the right support (x right, z up)"},
    [S_PHASE] = {"phase", "value", K_I8, 1, {0, 0}, NULL, NULL,
                 "0 quasi-static equilibrium, 1 dynamic sample (IDA), 2 sample of the rigid fall after "
                 "the collapse (fall.scheme = rigid: joint forces from the contact impulses)"},
    [S_BPOS] = {"block_position", "value", K_F64, 3, {DIM_BLOCKS, 3}, "m,m,rad", "ux,uz,theta",
                "displacement of each block's centroid and its rotation (counter-clockwise)"},
    [S_BVEL] = {"block_velocity", "value", K_F64, 3, {DIM_BLOCKS, 3}, "m/s,m/s,rad/s",
                "vx,vz,omega",
                "velocities (zero on the quasi-static path: at rest)"},
    [S_BSPEED] = {"block_speed", "value", K_F64, 2, {DIM_BLOCKS, 0}, "m/s", NULL,
                  "speed of each block's centroid"},
    [S_N] = {"joint_N", "value", K_F64, 2, {DIM_JOINTS, 0}, "N", NULL,
             "normal force of each joint, compression > 0"},
    [S_T] = {"joint_T", "value", K_F64, 2, {DIM_JOINTS, 0}, "N", NULL,
             "shear force of each joint, along the joint from intrados to extrados"},
    [S_M] = {"joint_M", "value", K_F64, 2, {DIM_JOINTS, 0}, "N m", NULL,
             "moment of the contact stresses about the joint centre (> 0: extrados carries more)"},
    [S_CONTACT] = {"joint_contact", "value", K_F64, 2, {DIM_JOINTS, 0}, "m", NULL,
                   "compressed length of each joint"},
    [S_GAP_I] = {"joint_gap_i", "value", K_F64, 2, {DIM_JOINTS, 0}, "m", NULL,
                 "opening at the intrados edge (> 0 open, < 0 penetration)"},
    [S_GAP_E] = {"joint_gap_e", "value", K_F64, 2, {DIM_JOINTS, 0}, "m", NULL,
                 "opening at the extrados edge (> 0 open, < 0 penetration)"},
    [S_SLIP] = {"joint_slip", "value", K_F64, 2, {DIM_JOINTS, 0}, "m", NULL,
                "total tangential displacement across each joint"},
    [S_SLIP_P] = {"joint_slip_plastic", "value", K_F64, 2, {DIM_JOINTS, 0}, "m", NULL,
                  "plastic (frictional) slip of each joint, committed"},
    [S_HINGE] = {"joint_hinge", "value", K_I8, 2, {DIM_JOINTS, 0}, NULL, NULL,
                 "0 closed, 1 hinge at the intrados (extrados opened), 2 at the extrados"},
    [S_REACT] = {"reactions", "value", K_F64, 2, {6, 0}, "N,N,N m,N,N,N m",
                 "left_Fx,left_Fz,left_M,right_Fx,right_Fz,right_M",
                 "forces the supports exert on the arch (x right, z up; M counter-clockwise about "
                 "the centre of the springing joint): the Lagrange multipliers of the support "
                 "constraints in the dynamic phase, the springing joints' forces at equilibria"},
    [S_ENERGY] = {"energy", "value", K_F64, 2, {7, 0}, "J,J,J,J,J,J,J",
                  "kinetic,gravity,elastic,support_work,damped,friction,balance",
                  "energies; work terms accumulate from the start of each dynamic phase (the rigid "
                  "fall carries on from the phase it follows: the joints' elastic energy there "
                  "goes into damped). Quasi-static rows: kinetic 0, gravity and elastic of the "
                  "state, the others NaN"},
    [S_JPTS] = {"joint_points", "value", K_F32, 3, {DIM_JOINT_POINTS, 2}, "m,m", "x,z",
                "intrados and extrados ends of every joint, moved with its two faces (mean)"},
    [S_SOLVER] = {"solver", "value", K_I64, 2, {3, 0}, NULL,
                  "newton_iterations,ida_steps,ida_newton_iterations",
                  "solver statistics up to this row, cumulative over the run: KINSOL Newton "
                  "iterations of the quasi-static path (equilibrium searches after snaps "
                  "included), IDA steps and IDA Newton iterations of the dynamic phases"},
    [S_SUPPORTS] = {"supports", "value", K_F64, 2, {6, 0}, "m,m,rad,m,m,rad",
                    "left_ux,left_uz,left_theta,right_ux,right_uz,right_theta",
                    "each support's displacement and rotation (x right, z up, theta "
                    "counter-clockwise about the centre of its springing face): its prescribed "
                    "motion (the right one's initial offset included), a pinned one's rotation "
                    "as solved"},
    [S_CRACK] = {"joint_crack", "value", K_F64, 3, {DIM_JOINTS, 2}, "m,m", "intrados,extrados",
                 "length of each joint cracked through from its intrados and from its extrados "
                 "edge (mortar: where the opening has reached 2 G_f / f_t, irreversibly; "
                 "committed at the last converged state; 0 for dry joints)"},
    [S_CRACKING] = {"energy_cracking", "value", K_F64, 1, {0, 0}, "J", NULL,
                    "energy dissipated by the mortar's cracking since the run's start, as "
                    "committed at this row (G_f per unit area cracked through; the term the "
                    "dynamic phases' balance counts from each phase's start); mortared runs only"},
};
/* clang-format on */
static size_t kind_size(elem_kind k) {
  switch (k) {
  case K_F64: return sizeof(double);
  case K_F32: return sizeof(float);
  case K_I8: return sizeof(int8_t);
  case K_I64: return sizeof(int64_t);
  }
  return 0;
}

static hid_t kind_mtype(elem_kind k) {
  switch (k) {
  case K_F64: return H5T_NATIVE_DOUBLE;
  case K_F32: return H5T_NATIVE_FLOAT;
  case K_I8: return H5T_NATIVE_INT8;
  case K_I64: return H5T_NATIVE_INT64;
  }
  return H5I_INVALID_HID;
}

static hid_t kind_ftype(elem_kind k) {
  switch (k) {
  case K_F64: return H5T_IEEE_F64LE;
  case K_F32: return H5T_IEEE_F32LE;
  case K_I8: return H5T_STD_I8LE;
  case K_I64: return H5T_STD_I64LE;
  }
  return H5I_INVALID_HID;
}

static hsize_t dim_size(const vs_output *o, int code) {
  switch (code) {
  case DIM_BLOCKS: return (hsize_t)o->nb;
  case DIM_JOINTS: return (hsize_t)o->nj;
  case DIM_JOINT_POINTS: return 2 * (hsize_t)o->nj;
  default: return (hsize_t)code;
  }
}

/* Dataset creation properties of a time series: chunked by rows (capped in bytes; a divisor of
 * the rows of a write, which then fills whole chunks), shuffle and deflate when asked. */
static hid_t series_dcpl(const vs_output *o, const series *s) {
  hid_t p = H5Pcreate(H5P_DATASET_CREATE);
  if (p < 0) return p;
  size_t row_bytes = s->row_elems * s->esize;
  size_t rows = (size_t)o->opts.chunk_rows;
  if (rows * row_bytes > VS_OUT_CHUNK_BYTES) rows = VS_OUT_CHUNK_BYTES / row_bytes;
  if (rows > o->flush_rows) rows = o->flush_rows;
  while (rows > 1 && o->flush_rows % rows != 0) rows--;
  hsize_t chunk[3] = {rows > 0 ? (hsize_t)rows : 1, s->dims[1], s->dims[2]};
  herr_t rc = H5Pset_chunk(p, s->rank, chunk);
  /* rows that a torn flush exposed without their data read as NaN (or -1), never as zeros */
  const double nan_d = NAN;
  const float nan_f = NAN;
  const int64_t minus1 = -1;
  const int8_t minus1_8 = -1;
  const void *fill = s->mtype == H5T_NATIVE_DOUBLE  ? (const void *)&nan_d
                     : s->mtype == H5T_NATIVE_FLOAT ? (const void *)&nan_f
                     : s->mtype == H5T_NATIVE_INT8  ? (const void *)&minus1_8
                                                    : (const void *)&minus1;
  if (rc >= 0) rc = H5Pset_fill_value(p, s->mtype, fill);
  if (rc >= 0 && o->opts.deflate > 0) rc = H5Pset_shuffle(p);
  if (rc >= 0 && o->opts.deflate > 0) rc = H5Pset_deflate(p, (unsigned)o->opts.deflate);
  if (rc < 0) {
    H5Pclose(p);
    return H5I_INVALID_HID;
  }
  return p;
}

/* Whether the record has series i: all but a dry run's S_CRACKING. */
int vs_record_series_used(const vs_output *o, int i) { return i != S_CRACKING || o->mortar; }

/* Create series i in /observables (its group first, if new) and link the shared step and time
 * into the group; nothing for a series the record has not (vs_record_series_used). */
herr_t vs_record_series_create(vs_output *o, hid_t obs, int i) {
  if (!vs_record_series_used(o, i)) return 0;
  const series_def *def = &SERIES[i];
  series *s = &o->s[i];
  s->rank = def->rank;
  s->dims[0] = 0;
  s->dims[1] = s->rank > 1 ? dim_size(o, def->dim[0]) : 1;
  s->dims[2] = s->rank > 2 ? dim_size(o, def->dim[1]) : 1;
  s->row_elems = (size_t)(s->dims[1] * s->dims[2]);
  s->esize = kind_size(def->kind);
  s->mtype = kind_mtype(def->kind);
  s->buf = malloc(o->flush_rows * s->row_elems * s->esize);
  if (s->buf == NULL) return -1;
  hsize_t maxdims[3] = {H5S_UNLIMITED, s->dims[1], s->dims[2]};
  herr_t rc = -1;
  hid_t g = H5Lexists(obs, def->group, H5P_DEFAULT) > 0 ? H5Gopen2(obs, def->group, H5P_DEFAULT)
                                                        : vs_h5_group_create(obs, def->group);
  hid_t sp = H5Screate_simple(s->rank, s->dims, maxdims), dcpl = series_dcpl(o, s);
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  size_t cache = 2 * VS_OUT_CHUNK_BYTES;
  herr_t cache_rc = dapl >= 0 ? H5Pset_chunk_cache(dapl, 521, cache, 0.75) : -1;
  if (g >= 0 && sp >= 0 && dcpl >= 0 && cache_rc >= 0)
    s->dset = H5Dcreate2(g, def->dataset, kind_ftype(def->kind), sp, H5P_DEFAULT, dcpl, dapl);
  if (s->dset >= 0) {
    rc = 0;
    if (def->unit != NULL) rc = vs_h5_attr_str(s->dset, "unit", def->unit);
    if (rc >= 0 && def->columns != NULL) rc = vs_h5_attr_str(s->dset, "columns", def->columns);
    if (rc >= 0) rc = vs_h5_attr_str(s->dset, "description", def->description);
    if (rc >= 0 && strcmp(def->dataset, "value") == 0 && strcmp(def->group, "delta") != 0) {
      rc = H5Lcreate_hard(o->s[S_STEP].dset, ".", g, "step", H5P_DEFAULT, H5P_DEFAULT);
      if (rc >= 0) rc = H5Lcreate_hard(o->s[S_TIME].dset, ".", g, "time", H5P_DEFAULT, H5P_DEFAULT);
    }
  }
  vs_h5_close(dapl);
  vs_h5_close(dcpl);
  vs_h5_close(sp);
  vs_h5_close(g);
  return rc;
}

/* Flush rows: flush_rows, fewer when rows are wide. */
size_t vs_record_buffer_rows(const vs_output *o) {
  size_t bytes = 0;
  for (int i = 0; i < S_COUNT; i++) {
    if (!vs_record_series_used(o, i)) continue;
    const series_def *d = &SERIES[i];
    size_t e = kind_size(d->kind);
    if (d->rank > 1) e *= (size_t)dim_size(o, d->dim[0]);
    if (d->rank > 2) e *= (size_t)dim_size(o, d->dim[1]);
    bytes += e;
  }
  size_t rows = (size_t)o->opts.flush_rows;
  if (rows * bytes > VS_OUT_BUFFER_BYTES) rows = VS_OUT_BUFFER_BYTES / bytes;
  return rows > 0 ? rows : 1;
}

/* Append the buffered rows of every series, and the buffered events, to the file (no flush). */
vs_status vs_record_write_pending(vs_output *o) {
  vs_status est = vs_record_events_append(o);
  if (est != VS_OK) return est;
  if (o->pending == 0) return VS_OK;
  const hsize_t start0 = (hsize_t)o->rows, n = (hsize_t)o->pending;
  for (int i = 0; i < S_COUNT; i++) {
    if (!vs_record_series_used(o, i)) continue;
    series *s = &o->s[i];
    hsize_t dims[3] = {start0 + n, s->dims[1], s->dims[2]};
    hsize_t start[3] = {start0, 0, 0}, count[3] = {n, s->dims[1], s->dims[2]};
    herr_t rc = H5Dset_extent(s->dset, dims);
    hid_t fs = rc >= 0 ? H5Dget_space(s->dset) : H5I_INVALID_HID;
    hid_t ms = H5Screate_simple(s->rank, count, NULL);
    rc = (fs >= 0 && ms >= 0) ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL)
                              : -1;
    if (rc >= 0) rc = H5Dwrite(s->dset, s->mtype, ms, fs, H5P_DEFAULT, s->buf);
    vs_h5_close(ms);
    vs_h5_close(fs);
    if (i == S_COUNT / 2 && start0 > 0)
      vs_fault_point("mid-append"); /* half a write ahead */
    if (rc < 0) {
      char what[96];
      snprintf(what, sizeof what, "cannot append to /observables/%s/%s", SERIES[i].group,
               SERIES[i].dataset);
      return vs_h5_fail(&o->err, o->path, what);
    }
    s->dims[0] = start0 + n;
  }
  o->rows += o->pending;
  o->pending = 0;
  return VS_OK;
}

vs_status vs_record_flush(vs_output *o) {
  vs_status st = vs_record_write_pending(o);
  if (st == VS_OK && H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0)
    st = vs_h5_fail(&o->err, o->path, "cannot flush");
  if (st == VS_OK) st = vs_record_snapshot(o);
  return st;
}
