/* The HDF5 record of a run (an H5MD-like layout: /parameters, /geometry, /observables/<name>/
 * {step,time,value}, /events, /summary) and its XDMF sidecar for ParaView. Rows and events are
 * buffered and written in blocks, each followed by a flush, and the file never reuses freed space, so that a
 * killed run leaves what its last flush wrote (see file_create for what was measured). */
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

#include "voussoir/damping.h"
#include "voussoir/outpath.h"
#include "voussoir/units.h"
#include "voussoir/version.h"

/* Suffix of the file while its layout is being written. */
#define VS_OUT_PART ".part"

/* Layout version, in the root attribute "layout". */
#define VS_OUTPUT_LAYOUT "voussoir-h5 1"

/* Buffered rows stay under this many bytes (wide rows: fewer rows per flush). */
static const size_t VS_OUT_BUFFER_BYTES = (size_t)16 << 20;
/* A chunk stays under this many bytes (wide rows: fewer rows per chunk). */
static const size_t VS_OUT_CHUNK_BYTES = (size_t)1 << 20;

/* ------------------------------------------------------------------------------------------ */
/* HDF5 plumbing: quiet error stack, generic close, cause of the last error                     */

typedef struct {
  H5E_auto2_t fn;
  void *data;
} h5_quiet;

/* HDF5 prints its error stack to stderr by default; library code must not print. */
static h5_quiet quiet_begin(void) {
  h5_quiet q = {NULL, NULL};
  H5Eget_auto2(H5E_DEFAULT, &q.fn, &q.data);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  return q;
}

static void quiet_end(h5_quiet q) { H5Eset_auto2(H5E_DEFAULT, q.fn, q.data); }

static void h5_close(hid_t id) {
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
static vs_status h5_fail(vs_error *err, const char *path, const char *what) {
  h5_cause c = {"", "", 0};
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, walk_cb, &c);
  H5Eclear2(H5E_DEFAULT);
  if (c.os_errno > 0)
    return vs_error_set(err, VS_ERR_IO, "output: %s: %s: %s", path, what, strerror(c.os_errno));
  return vs_error_set(err, VS_ERR_IO, "output: %s: %s%s%s%s%s", path, what, c.cause[0] ? ": " : "",
                      c.cause, c.api[0] ? " in " : "", c.api);
}

/* Fault injection for the crash tests: when the environment variable VS_FAULT_KILL names this
 * point, the process kills itself there with SIGKILL (see vs_output_finish for the points;
 * "mid-append": in a write of rows after the first, once half the time series have theirs). */
static void fault_point(const char *name) {
  const char *v = getenv("VS_FAULT_KILL");
  if (v != NULL && strcmp(v, name) == 0) raise(SIGKILL);
}

static hid_t vlstr_type(void) {
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
static hid_t fixed_str_type(size_t n) {
  hid_t t = H5Tcopy(H5T_C_S1);
  if (t < 0) return t;
  if (H5Tset_size(t, n) < 0 || H5Tset_strpad(t, H5T_STR_NULLPAD) < 0) {
    H5Tclose(t);
    return H5I_INVALID_HID;
  }
  return t;
}

static hid_t char_type(void) { return fixed_str_type(1); }

/* Scalar attribute name = value (variable-length UTF-8 string); an existing one is overwritten
 * in place (the object header keeps its size). */
static herr_t attr_str(hid_t obj, const char *name, const char *value) {
  herr_t rc = -1;
  hid_t t = vlstr_type(), s = H5Screate(H5S_SCALAR), a = H5I_INVALID_HID;
  if (t >= 0 && s >= 0)
    a = H5Aexists(obj, name) > 0 ? H5Aopen(obj, name, H5P_DEFAULT)
                                 : H5Acreate2(obj, name, t, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) rc = H5Awrite(a, t, &value);
  h5_close(a);
  h5_close(s);
  h5_close(t);
  return rc;
}

/* Scalar numeric attribute: ftype in the file, mtype and *value in memory. */
static herr_t attr_num(hid_t obj, const char *name, hid_t ftype, hid_t mtype, const void *value) {
  herr_t rc = -1;
  hid_t s = H5Screate(H5S_SCALAR), a = H5I_INVALID_HID;
  if (s >= 0) a = H5Acreate2(obj, name, ftype, s, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) rc = H5Awrite(a, mtype, value);
  h5_close(a);
  h5_close(s);
  return rc;
}

static herr_t attr_int(hid_t obj, const char *name, long long v) {
  return attr_num(obj, name, H5T_STD_I64LE, H5T_NATIVE_LLONG, &v);
}

static herr_t attr_double(hid_t obj, const char *name, double v) {
  return attr_num(obj, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, &v);
}

/* A small contiguous dataset (rank 0 for a scalar) with optional unit and columns attributes. */
static herr_t dset_write(hid_t loc, const char *name, hid_t ftype, hid_t mtype, int rank,
                         const hsize_t *dims, const void *data, const char *unit,
                         const char *columns) {
  herr_t rc = -1;
  hid_t s = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, NULL);
  hid_t d = s >= 0 ? H5Dcreate2(loc, name, ftype, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                   : H5I_INVALID_HID;
  if (d >= 0) {
    hssize_t n = H5Sget_simple_extent_npoints(s);
    rc = (n > 0 && data != NULL) ? H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : 0;
    if (rc >= 0 && unit != NULL) rc = attr_str(d, "unit", unit);
    if (rc >= 0 && columns != NULL) rc = attr_str(d, "columns", columns);
  }
  h5_close(d);
  h5_close(s);
  return rc;
}

static herr_t dset_scalar(hid_t loc, const char *name, double v, const char *unit) {
  return dset_write(loc, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 0, NULL, &v, unit, NULL);
}

static hid_t group_create(hid_t loc, const char *name) {
  return H5Gcreate2(loc, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
}

/* "2024-05-01T12:00:00Z" */
static void iso8601_utc(char *buf, size_t size) {
  time_t now = time(NULL);
  struct tm tmv;
  if (gmtime_r(&now, &tmv) == NULL || strftime(buf, size, "%Y-%m-%dT%H:%M:%SZ", &tmv) == 0)
    snprintf(buf, size, "unknown");
}

/* ------------------------------------------------------------------------------------------ */
/* Time series                                                                                  */

typedef enum { K_F64, K_F32, K_I8, K_I64 } elem_kind;

/* Symbolic sizes of the dimensions after the row. */
enum { DIM_BLOCKS = -1, DIM_JOINTS = -2, DIM_BLOCK_POINTS = -3, DIM_JOINT_POINTS = -4 };

typedef struct {
  const char *group, *dataset;
  elem_kind kind;
  int rank;   /* including the row dimension */
  int dim[2]; /* sizes of dimensions 1 and 2 (a DIM_ code or a count) */
  const char *unit, *columns, *description;
} series_def;

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
  S_BPTS,
  S_JPTS,
  S_SOLVER,
  S_COUNT
};

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
                 "0 quasi-static equilibrium, 1 dynamic sample"},
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
                  "energies; work terms accumulate from the start of each dynamic phase. "
                  "Quasi-static rows: kinetic 0, gravity and elastic of the state, the others NaN"},
    [S_BPTS] = {"block_points", "value", K_F32, 3, {DIM_BLOCK_POINTS, 2}, "m,m", "x,z",
                "outline of every block, moved (float32, for display): block i owns points i*P .. "
                "i*P+P-1 of /geometry/block_points"},
    [S_JPTS] = {"joint_points", "value", K_F32, 3, {DIM_JOINT_POINTS, 2}, "m,m", "x,z",
                "intrados and extrados ends of every joint, moved with its two faces (mean)"},
    [S_SOLVER] = {"solver", "value", K_I64, 2, {3, 0}, NULL,
                  "newton_iterations,ida_steps,ida_newton_iterations",
                  "solver statistics up to this row, cumulative over the run: KINSOL Newton "
                  "iterations of the quasi-static path (equilibrium searches after snaps "
                  "included), IDA steps and IDA Newton iterations of the dynamic phases"},
};
/* clang-format on */

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
enum { EV_TIME = 0, EV_DELTA = 8, EV_JOINT = 16, EV_SIDE = 20, EV_LABEL = 21, EV_PHASE = 22,
       EV_ORDER = 23, EV_KIND = 27, EV_KIND_LEN = 16, EV_SIZE = 43 };
typedef struct {
  unsigned char b[EV_SIZE];
} event_row;

struct vs_output {
  hid_t file;
  char *path, *xmf_path;
  vs_output_opts opts;
  int nb, nj, np;     /* blocks, joints, outline points per block */
  size_t flush_rows;  /* rows buffered before a write */
  double *bref;       /* reference outlines, nb * np * 2 */
  double *jref;       /* reference joint ends (intrados, extrados), nj * 2 * 2 */
  vs_joint_state *js; /* workspace, nj */
  series s[S_COUNT];
  long rows;              /* written to the file */
  long pending;           /* buffered */
  int last_phase;         /* of the last row, -1 before any */
  hid_t events, ev_mtype; /* /events and its (packed, file = memory) type */
  long n_events;          /* written to the file */
  event_row *ev_buf;      /* events waiting for the next write */
  long ev_pending, ev_cap;
  int interrupted, finished, xmf_written;
  vs_outlock *lock; /* the exclusive lock on path, held until destroy */
  vs_error err; /* first write error (sticky) */
};

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
  case DIM_BLOCK_POINTS: return (hsize_t)o->nb * (hsize_t)o->np;
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

/* Create series i in /observables (its group first, if new) and link the shared step and time
 * into the group. */
static herr_t series_create(vs_output *o, hid_t obs, int i) {
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
                                                        : group_create(obs, def->group);
  hid_t sp = H5Screate_simple(s->rank, s->dims, maxdims), dcpl = series_dcpl(o, s);
  hid_t dapl = H5Pcreate(H5P_DATASET_ACCESS);
  size_t cache = 2 * VS_OUT_CHUNK_BYTES;
  herr_t cache_rc = dapl >= 0 ? H5Pset_chunk_cache(dapl, 521, cache, 0.75) : -1;
  if (g >= 0 && sp >= 0 && dcpl >= 0 && cache_rc >= 0)
    s->dset = H5Dcreate2(g, def->dataset, kind_ftype(def->kind), sp, H5P_DEFAULT, dcpl, dapl);
  if (s->dset >= 0) {
    rc = 0;
    if (def->unit != NULL) rc = attr_str(s->dset, "unit", def->unit);
    if (rc >= 0 && def->columns != NULL) rc = attr_str(s->dset, "columns", def->columns);
    if (rc >= 0) rc = attr_str(s->dset, "description", def->description);
    if (rc >= 0 && strcmp(def->dataset, "value") == 0 && strcmp(def->group, "delta") != 0) {
      rc = H5Lcreate_hard(o->s[S_STEP].dset, ".", g, "step", H5P_DEFAULT, H5P_DEFAULT);
      if (rc >= 0) rc = H5Lcreate_hard(o->s[S_TIME].dset, ".", g, "time", H5P_DEFAULT, H5P_DEFAULT);
    }
  }
  h5_close(dapl);
  h5_close(dcpl);
  h5_close(sp);
  h5_close(g);
  return rc;
}

static void *row_ptr(vs_output *o, int i) {
  series *s = &o->s[i];
  return s->buf + (size_t)o->pending * s->row_elems * s->esize;
}

static herr_t events_write(vs_output *o, hsize_t first, hsize_t n, const event_row *rows);

/* Append the buffered events to /events (no flush). */
static vs_status write_events(vs_output *o) {
  if (o->ev_pending == 0) return VS_OK;
  if (events_write(o, (hsize_t)o->n_events, (hsize_t)o->ev_pending, o->ev_buf) < 0)
    return h5_fail(&o->err, o->path, "cannot append to /events");
  o->n_events += o->ev_pending;
  o->ev_pending = 0;
  return VS_OK;
}

/* Append the buffered rows of every series, and the buffered events, to the file (no flush). */
static vs_status write_pending(vs_output *o) {
  vs_status est = write_events(o);
  if (est != VS_OK) return est;
  if (o->pending == 0) return VS_OK;
  const hsize_t start0 = (hsize_t)o->rows, n = (hsize_t)o->pending;
  for (int i = 0; i < S_COUNT; i++) {
    series *s = &o->s[i];
    hsize_t dims[3] = {start0 + n, s->dims[1], s->dims[2]};
    hsize_t start[3] = {start0, 0, 0}, count[3] = {n, s->dims[1], s->dims[2]};
    herr_t rc = H5Dset_extent(s->dset, dims);
    hid_t fs = rc >= 0 ? H5Dget_space(s->dset) : H5I_INVALID_HID;
    hid_t ms = H5Screate_simple(s->rank, count, NULL);
    rc = (fs >= 0 && ms >= 0) ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL)
                              : -1;
    if (rc >= 0) rc = H5Dwrite(s->dset, s->mtype, ms, fs, H5P_DEFAULT, s->buf);
    h5_close(ms);
    h5_close(fs);
    if (i == S_COUNT / 2 && start0 > 0) fault_point("mid-append"); /* half a write ahead */
    if (rc < 0) {
      char what[96];
      snprintf(what, sizeof what, "cannot append to /observables/%s/%s", SERIES[i].group,
               SERIES[i].dataset);
      return h5_fail(&o->err, o->path, what);
    }
    s->dims[0] = start0 + n;
  }
  o->rows += o->pending;
  o->pending = 0;
  return VS_OK;
}

static vs_status flush_file(vs_output *o) {
  vs_status st = write_pending(o);
  if (st == VS_OK && H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0)
    st = h5_fail(&o->err, o->path, "cannot flush");
  return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Geometry: outlines of the voussoirs and the joint segments                                   */

/* Reference outline of arch block b: the intrados arc from phi0 to phi1, then the extrados arc
 * back (counter-clockwise in the x-z plane), arc_points inside each arc. */
static void block_outline(const vs_geometry *g, int b, int arc_points, double *pts) {
  const vs_block *blk = &g->blocks[b];
  const int per_arc = arc_points + 2;
  const double ri = g->radius, re = g->radius + g->thickness;
  for (int k = 0; k < per_arc; k++) {
    double f = (double)k / (double)(per_arc - 1);
    double phi_i = blk->phi0 + f * (blk->phi1 - blk->phi0),
           phi_e = blk->phi1 - f * (blk->phi1 - blk->phi0);
    pts[2 * k] = ri * sin(phi_i);
    pts[2 * k + 1] = ri * cos(phi_i);
    pts[2 * (per_arc + k)] = re * sin(phi_e);
    pts[2 * (per_arc + k) + 1] = re * cos(phi_e);
  }
}

/* Point (X, Z) of body `body` in the reference configuration, moved to the state q with the right
 * support displaced by usup. */
static void body_move(const vs_geometry *g, const double *q, const double usup[2], int body,
                      double X, double Z, double out[2]) {
  if (body == VS_SUPPORT_LEFT) {
    out[0] = X;
    out[1] = Z;
  } else if (body == VS_SUPPORT_RIGHT) {
    out[0] = X + usup[0];
    out[1] = Z + usup[1];
  } else {
    const vs_block *b = &g->blocks[body];
    const double c = cos(q[3 * body + 2]), s = sin(q[3 * body + 2]);
    const double dx = X - b->cx, dz = Z - b->cz;
    out[0] = b->cx + q[3 * body] + c * dx - s * dz;
    out[1] = b->cz + q[3 * body + 1] + s * dx + c * dz;
  }
}

static vs_status geometry_init(vs_output *o, const vs_geometry *g) {
  o->nb = g->n_blocks;
  o->nj = g->n_joints;
  o->np = 2 * (o->opts.arc_points + 2);
  o->bref = malloc((size_t)o->nb * (size_t)o->np * 2 * sizeof *o->bref);
  o->jref = malloc((size_t)o->nj * 4 * sizeof *o->jref);
  o->js = malloc((size_t)o->nj * sizeof *o->js);
  if (o->bref == NULL || o->jref == NULL || o->js == NULL) return VS_ERR_NOMEM;
  for (int b = 0; b < o->nb; b++)
    block_outline(g, b, o->opts.arc_points, o->bref + (size_t)b * (size_t)o->np * 2);
  for (int k = 0; k < o->nj; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double h = 0.5 * j->length;
    o->jref[4 * k] = j->px - h * sx;
    o->jref[4 * k + 1] = j->pz - h * sz;
    o->jref[4 * k + 2] = j->px + h * sx;
    o->jref[4 * k + 3] = j->pz + h * sz;
  }
  return VS_OK;
}

static herr_t write_geometry(const vs_output *o, const vs_geometry *g) {
  hid_t grp = group_create(o->file, "geometry");
  if (grp < 0) return -1;
  const size_t nb = (size_t)o->nb, nj = (size_t)o->nj, np = (size_t)o->np;
  double *buf = malloc((nb > nj ? nb : nj) * 2 * sizeof *buf);
  int32_t *conn = malloc((nb * np > nj * 2 ? nb * np : nj * 2) * sizeof *conn);
  herr_t rc = (buf != NULL && conn != NULL) ? 0 : -1;
  hsize_t d2[2];
#define GEO_COLUMN(n_, expr, name, unit)                                                     \
  do {                                                                                       \
    for (size_t i = 0; i < (n_); i++) buf[i] = (expr);                                       \
    d2[0] = (hsize_t)(n_);                                                                   \
    if (rc >= 0)                                                                             \
      rc = dset_write(grp, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, d2, buf, unit, NULL); \
  } while (0)
#define GEO_PAIR(n_, e0, e1, name, unit, cols)                                               \
  do {                                                                                       \
    for (size_t i = 0; i < (n_); i++) buf[2 * i] = (e0), buf[2 * i + 1] = (e1);              \
    d2[0] = (hsize_t)(n_), d2[1] = 2;                                                        \
    if (rc >= 0)                                                                             \
      rc = dset_write(grp, name, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d2, buf, unit, cols); \
  } while (0)
  if (rc >= 0) {
    GEO_COLUMN(nb, g->blocks[i].mass, "block_mass", "kg");
    GEO_COLUMN(nb, g->blocks[i].inertia, "block_inertia", "kg m^2");
    GEO_COLUMN(nb, g->blocks[i].area, "block_area", "m^2");
    GEO_PAIR(nb, g->blocks[i].cx, g->blocks[i].cz, "block_centroid", "m,m", "x,z");
    GEO_PAIR(nb, g->blocks[i].phi0, g->blocks[i].phi1, "block_phi", "rad,rad", "phi0,phi1");
    GEO_PAIR(nj, g->joints[i].px, g->joints[i].pz, "joint_centre", "m,m", "x,z");
    GEO_PAIR(nj, g->joints[i].nx, g->joints[i].nz, "joint_normal", "1,1", "nx,nz");
    GEO_COLUMN(nj, g->joints[i].length, "joint_length", "m");
    GEO_COLUMN(nj, g->joints[i].depth, "joint_depth", "m");
  }
#undef GEO_COLUMN
#undef GEO_PAIR
  if (rc >= 0) {
    for (size_t i = 0; i < nj; i++) conn[2 * i] = g->joints[i].a, conn[2 * i + 1] = g->joints[i].b;
    d2[0] = nj, d2[1] = 2;
    rc = dset_write(grp, "joint_bodies", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn, NULL, "a,b");
  }
  hsize_t d3[3] = {nb * np, 2, 0};
  if (rc >= 0)
    rc = dset_write(grp, "block_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d3, o->bref, "m,m",
                    "x,z");
  for (size_t i = 0; rc >= 0 && i < nb * np; i++) conn[i] = (int32_t)i;
  d2[0] = nb, d2[1] = np;
  if (rc >= 0)
    rc = dset_write(grp, "block_connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn, NULL,
                    NULL);
  d3[0] = 2 * nj;
  if (rc >= 0)
    rc = dset_write(grp, "joint_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d3, o->jref, "m,m",
                    "x,z");
  for (size_t i = 0; rc >= 0 && i < 2 * nj; i++) conn[i] = (int32_t)i;
  d2[0] = nj, d2[1] = 2;
  if (rc >= 0)
    rc = dset_write(grp, "joint_connectivity", H5T_STD_I32LE, H5T_NATIVE_INT32, 2, d2, conn, NULL,
                    "intrados,extrados");
  if (rc >= 0) rc = dset_scalar(grp, "radius", g->radius, "m");
  if (rc >= 0) rc = dset_scalar(grp, "thickness", g->thickness, "m");
  if (rc >= 0) rc = dset_scalar(grp, "embrace", g->embrace, "rad");
  if (rc >= 0) rc = dset_scalar(grp, "span", g->span, "m");
  if (rc >= 0) rc = dset_scalar(grp, "rise", g->rise, "m");
  if (rc >= 0) rc = dset_scalar(grp, "gravity", g->gravity, "m/s^2");
  if (rc >= 0) rc = attr_int(grp, "n_blocks", o->nb);
  if (rc >= 0) rc = attr_int(grp, "n_joints", o->nj);
  if (rc >= 0) rc = attr_int(grp, "points_per_block", o->np);
  if (rc >= 0)
    rc = attr_str(grp, "description",
                  "reference configuration; x right, z up, circle centre at the origin. Block i's "
                  "outline is block_points[i*P:(i+1)*P] (P = points_per_block): intrados arc from "
                  "phi0 to phi1, then extrados arc back. Joint k (1-based in reports) is row k-1; "
                  "joint_bodies: block index, -1 left support, -2 right support");
  free(buf);
  free(conn);
  h5_close(grp);
  return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Parameters: the case's values under the case's keys and units                               */

static herr_t write_parameters(hid_t file, const vs_case *c) {
  hid_t grp = group_create(file, "parameters");
  herr_t rc = grp >= 0 ? attr_str(grp, "description",
                                  "the case's values as attributes of /parameters/<section>, "
                                  "named after the case keys, in the case's units (mm, N/mm^3, "
                                  "deg, kg/m^3, s)")
                       : -1;
  hid_t sec = H5I_INVALID_HID;
  const char *open_name = "";
  for (int i = 0; rc >= 0 && i < vs_case_key_count(); i++) {
    const char *section = NULL, *key = NULL;
    int is_int = 0;
    double value = 0.0;
    vs_case_key(c, i, &section, &key, NULL, &is_int, &value);
    if (strcmp(open_name, section) != 0) {
      h5_close(sec);
      sec = group_create(grp, section);
      open_name = section;
      if (sec < 0) rc = -1;
    }
    if (rc >= 0) rc = is_int ? attr_int(sec, key, (int)value) : attr_double(sec, key, value);
  }
  h5_close(sec);
  h5_close(grp);
  return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Events                                                                                       */

static const char *event_kind_name(vs_event_kind k) {
  switch (k) {
  case VS_EVENT_JOINT_OPENED: return "joint_opened";
  case VS_EVENT_JOINT_CLOSED: return "joint_closed";
  case VS_EVENT_HINGE_FORMED: return "hinge_formed";
  case VS_EVENT_LIMIT_POINT: return "limit_point";
  case VS_EVENT_SNAP_SETTLED: return "snap_settled";
  case VS_EVENT_COLLAPSE: return "collapse";
  }
  return "unknown";
}

/* The compound type of event_row: native members (memory) or little-endian ones (file); on a
 * little-endian host the two are equal and a write converts nothing. */
static hid_t event_type(int native) {
  hid_t t = H5Tcreate(H5T_COMPOUND, EV_SIZE);
  hid_t c1 = char_type(), vs = fixed_str_type(EV_KIND_LEN);
  herr_t rc = (t >= 0 && c1 >= 0 && vs >= 0) ? 0 : -1;
  hid_t f64 = native ? H5T_NATIVE_DOUBLE : H5T_IEEE_F64LE,
        i32 = native ? H5T_NATIVE_INT32 : H5T_STD_I32LE, i8 = native ? H5T_NATIVE_INT8 : H5T_STD_I8LE;
  if (rc >= 0) rc = H5Tinsert(t, "time", EV_TIME, f64);
  if (rc >= 0) rc = H5Tinsert(t, "delta", EV_DELTA, f64);
  if (rc >= 0) rc = H5Tinsert(t, "joint", EV_JOINT, i32);
  if (rc >= 0) rc = H5Tinsert(t, "side", EV_SIDE, c1);
  if (rc >= 0) rc = H5Tinsert(t, "label", EV_LABEL, c1);
  if (rc >= 0) rc = H5Tinsert(t, "phase", EV_PHASE, i8);
  if (rc >= 0) rc = H5Tinsert(t, "order", EV_ORDER, i32);
  if (rc >= 0) rc = H5Tinsert(t, "kind", EV_KIND, vs);
  h5_close(c1);
  h5_close(vs);
  if (rc < 0) {
    h5_close(t);
    return H5I_INVALID_HID;
  }
  return t;
}

static const char EVENT_UNITS[] = "s,m,,,,,,";

static herr_t events_create(vs_output *o) {
  o->ev_mtype = event_type(1);
  hid_t ft = event_type(0);
  hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {64};
  hid_t sp = H5Screate_simple(1, dims, maxdims), dcpl = H5Pcreate(H5P_DATASET_CREATE);
  herr_t rc = (ft >= 0 && sp >= 0 && dcpl >= 0) ? 0 : -1;
  if (rc >= 0) rc = H5Pset_chunk(dcpl, 1, chunk);
  if (rc >= 0 && o->opts.deflate > 0) rc = H5Pset_deflate(dcpl, (unsigned)o->opts.deflate);
  if (rc >= 0) o->events = H5Dcreate2(o->file, "events", ft, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  rc = o->events >= 0 ? attr_str(o->events, "unit", EVENT_UNITS) : -1;
  if (rc >= 0)
    rc = attr_str(
        o->events, "description",
        "events in order. unit: one entry per field, comma-separated. kind: "
        "joint_opened/joint_closed (an edge crossed hinges.open_mm; side = the hinge side), "
        "hinge_formed (label A-E, order = order of appearance, delta = interpolated "
        "onset), limit_point, snap_settled, collapse. joint: 1-based, 0 if none; "
        "phase: 0 quasi-static, 1 dynamic");
  h5_close(dcpl);
  h5_close(sp);
  h5_close(ft);
  return rc;
}

/* The fields in the host's order, at the packed offsets (the memory type's). */
static event_row event_to_row(const vs_run_event *e) {
  event_row r;
  memset(&r, 0, sizeof r);
  const int32_t joint = e->joint, order = e->order;
  const int8_t phase = (int8_t)e->phase;
  memcpy(r.b + EV_TIME, &e->t, 8);
  memcpy(r.b + EV_DELTA, &e->delta, 8);
  memcpy(r.b + EV_JOINT, &joint, 4);
  r.b[EV_SIDE] = (unsigned char)e->side;
  r.b[EV_LABEL] = (unsigned char)e->label;
  memcpy(r.b + EV_PHASE, &phase, 1);
  memcpy(r.b + EV_ORDER, &order, 4);
  const char *k = event_kind_name(e->kind);
  const size_t n = strlen(k);
  memcpy(r.b + EV_KIND, k, n < EV_KIND_LEN ? n : EV_KIND_LEN);
  return r;
}

/* Write rows [first, first + n) of /events (extending it). */
static herr_t events_write(vs_output *o, hsize_t first, hsize_t n, const event_row *rows) {
  hsize_t dims[1] = {first + n}, start[1] = {first}, count[1] = {n};
  herr_t rc = H5Dset_extent(o->events, dims);
  if (n == 0 || rc < 0) return rc;
  hid_t fs = H5Dget_space(o->events), ms = H5Screate_simple(1, count, NULL);
  rc =
      (fs >= 0 && ms >= 0) ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) : -1;
  if (rc >= 0) rc = H5Dwrite(o->events, o->ev_mtype, ms, fs, H5P_DEFAULT, rows);
  h5_close(ms);
  h5_close(fs);
  return rc;
}

/* ------------------------------------------------------------------------------------------ */
/* Create / destroy                                                                             */

void vs_output_opts_default(vs_output_opts *o) {
  o->arc_points = 2;
  o->flush_rows = 64;
  o->chunk_rows = 64;
  o->deflate = 0;
  o->xdmf_max_grids = 2000;
}

static vs_status check_opts(const vs_output_opts *o, vs_error *err) {
  if (o->arc_points < 0 || o->arc_points > 64 || o->flush_rows < 1 || o->chunk_rows < 1 ||
      o->deflate < 0 || o->deflate > 9 || o->xdmf_max_grids < 2)
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: options arc_points = %d, flush_rows = %d, chunk_rows = %d, "
                        "deflate = %d, xdmf_max_grids = %d (allowed: arc_points in [0, 64], "
                        "flush_rows >= 1, chunk_rows >= 1, deflate in [0, 9], xdmf_max_grids >= 2)",
                        o->arc_points, o->flush_rows, o->chunk_rows, o->deflate, o->xdmf_max_grids);
  return VS_OK;
}

static char *xmf_path_of(const char *path) {
  const char *exts[] = {".h5", ".hdf5", ".hdf"};
  size_t n = strlen(path), keep = n;
  for (size_t i = 0; i < sizeof exts / sizeof exts[0]; i++) {
    size_t e = strlen(exts[i]);
    if (n > e && strcmp(path + n - e, exts[i]) == 0) keep = n - e;
  }
  char *x = malloc(keep + 5);
  if (x == NULL) return NULL;
  memcpy(x, path, keep);
  memcpy(x + keep, ".xmf", 5);
  return x;
}

static char *dup_str(const char *s) {
  size_t n = strlen(s) + 1;
  char *d = malloc(n);
  if (d != NULL) memcpy(d, s, n);
  return d;
}

/* Flush rows: flush_rows, fewer when rows are wide. */
static size_t buffer_rows(const vs_output *o) {
  size_t bytes = 0;
  for (int i = 0; i < S_COUNT; i++) {
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

/* Crash safety. HDF5 1.10 has no crash consistency: a flush rewrites metadata in place. What a
 * kill -9 at a random moment of a run (runs/reference.ini, about 30 flushes) leaves was measured:
 *  - HDF5's default file-space strategy reuses freed space: a partial chunk rewritten at a flush
 *    may land where the last flushed index still points. 22 killed files in 25 (a prototype
 *    writing like this one) had chunks that failed to inflate or held other data. Hence
 *    H5F_FSPACE_STRATEGY_NONE: freed space is never reused;
 *  - between flushes nothing is written (rows wait in memory), so a kill there leaves the state
 *    of the last flush intact. A kill inside a flush can tear it. Of 140 killed files (deflate 4)
 *    138 were intact; 1 had some datasets a flush ahead of the others, the extra rows reading as
 *    NaN (-1 for integers: the fill values, never plausible numbers); in 1 the last chunk of
 *    /observables/.../step lay past the recorded end of file (that dataset fails to read). Without
 *    deflate flushes are shorter: 471 of 476 intact, 2 one flush behind in some datasets, 2 with
 *    NaN rows, 1 with a group index past the end of file;
 *  - the file is built as PATH.part and renamed once its layout is complete; vs_output_finish only
 *    adds to /summary, created empty at the start, and rewrites root attributes in place (a kill
 *    while the root group gained /summary once left a file whose root could not be opened).
 * SWMR writing (H5Fstart_swmr_write, latest format) was measured too and rejected: a killed file
 * keeps an "open for writing" mark so that an ordinary open fails (h5py needs swmr=True, or
 * h5clear -s); 4 files in 194, killed while /summary was written, opened in no mode at all; and
 * one made an SWMR reader retry a torn index block for minutes. In 1.10 an SWMR writer cannot
 * create objects or attributes either (/summary and the final status would need a reopen).
 * Without deflate a chunk keeps its size, so a flush rewrites a partial chunk in place, and rows
 * are written at chunk boundaries (every flush_rows-th row), so most writes fill whole chunks. */
static vs_status file_create(vs_output *o, const char *path) {
  hid_t fcpl = H5Pcreate(H5P_FILE_CREATE);
  if (fcpl >= 0 && H5Pset_file_space_strategy(fcpl, H5F_FSPACE_STRATEGY_NONE, 0, 1) >= 0)
    o->file = H5Fcreate(path, H5F_ACC_EXCL, fcpl, H5P_DEFAULT);
  /* the cause is read before closing fcpl (any API call clears the error stack) */
  vs_status st = o->file < 0 ? h5_fail(&o->err, path, "cannot create the file") : VS_OK;
  h5_close(fcpl);
  return st;
}

static herr_t write_root(vs_output *o, const char *case_text) {
  char now[32];
  iso8601_utc(now, sizeof now);
  herr_t rc = attr_str(o->file, "program", "voussoir");
  if (rc >= 0) rc = attr_str(o->file, "version", VS_VERSION);
  if (rc >= 0) rc = attr_str(o->file, "layout", VS_OUTPUT_LAYOUT);
  if (rc >= 0) rc = attr_str(o->file, "created", now);
  if (rc >= 0) rc = attr_str(o->file, "case", case_text != NULL ? case_text : "");
  if (rc >= 0) rc = attr_str(o->file, "status", "running");
  if (rc >= 0) rc = attr_str(o->file, "finished", "");
  if (rc >= 0) rc = attr_str(o->file, "units", "SI (m, N, kg, s, rad); see each dataset's unit");
  return rc;
}

/* /imperfections: the values drawn for this run ([imperfections]; nominal when none), SI. */
static herr_t write_imperfections(hid_t file, const vs_imperfections *p) {
  hid_t grp = group_create(file, "imperfections");
  if (grp < 0) return -1;
  const hsize_t nj = (hsize_t)p->n_joints, nb = (hsize_t)p->n_blocks;
  double *buf = malloc((size_t)(nj > nb ? nj : nb) * sizeof *buf);
  herr_t rc = buf != NULL ? attr_str(grp, "description",
                                     "drawn by the counter-based generator keyed by (seed, "
                                     "sample); see /parameters/imperfections")
                          : -1;
  if (rc >= 0)
    rc = dset_write(grp, "kn_factor", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj, p->kn_factor, "1",
                    NULL);
  for (hsize_t k = 0; rc >= 0 && k < nj; k++) buf[k] = p->face_gap_mm[k] * VS_MM;
  if (rc >= 0)
    rc = dset_write(grp, "face_gap", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nj, buf, "m", NULL);
  for (hsize_t i = 0; rc >= 0 && i < nb; i++) buf[i] = p->angle_deg[i] * VS_DEG;
  if (rc >= 0)
    rc = dset_write(grp, "voussoir_angle", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nb, buf, "rad",
                    NULL);
  for (hsize_t i = 0; rc >= 0 && i < nb; i++) buf[i] = p->thickness_mm[i] * VS_MM;
  if (rc >= 0)
    rc = dset_write(grp, "voussoir_thickness", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &nb, buf, "m",
                    NULL);
  const hsize_t two = 2;
  const double off[2] = {p->support_mm[0] * VS_MM, p->support_mm[1] * VS_MM};
  if (rc >= 0)
    rc = dset_write(grp, "support_offset", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &two, off, "m, m",
                    "outward, downward");
  free(buf);
  h5_close(grp);
  return rc;
}

static vs_status create_layout(vs_output *o, const vs_run *run, const char *case_text) {
  if (write_root(o, case_text) < 0)
    return h5_fail(&o->err, o->path, "cannot write root attributes");
  if (write_parameters(o->file, vs_run_case(run)) < 0)
    return h5_fail(&o->err, o->path, "cannot write /parameters");
  if (write_geometry(o, vs_run_geometry(run)) < 0)
    return h5_fail(&o->err, o->path, "cannot write /geometry");
  if (write_imperfections(o->file, vs_run_imperfections(run)) < 0)
    return h5_fail(&o->err, o->path, "cannot write /imperfections");
  /* /summary is filled by vs_output_finish: created now, so that finishing never touches the
   * root group's header */
  hid_t obs = group_create(o->file, "summary");
  h5_close(obs);
  obs = obs >= 0 ? group_create(o->file, "observables") : H5I_INVALID_HID;
  herr_t rc = obs >= 0 ? 0 : -1;
  for (int i = 0; rc >= 0 && i < S_COUNT; i++) rc = series_create(o, obs, i);
  h5_close(obs);
  if (rc < 0) return h5_fail(&o->err, o->path, "cannot create /observables");
  if (events_create(o) < 0) return h5_fail(&o->err, o->path, "cannot create /events");
  return flush_file(o);
}

/* A "<path>.part" left by a killed run is ours to remove (we hold the lock on path); anything
 * there that is not a regular file is not. */
static vs_status remove_stale_part(vs_output *o, const char *part) {
  struct stat st;
  if (lstat(part, &st) != 0) return VS_OK;
  if (!S_ISREG(st.st_mode))
    return vs_error_set(&o->err, VS_ERR_INVALID, "%s: exists and is not a regular file", part);
  if (unlink(part) != 0)
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: cannot remove the stale file: %s", part,
                        strerror(errno));
  return VS_OK;
}

/* Rename part over path, checked again just before: never over anything but a regular file. */
static vs_status replace_target(vs_output *o, const char *part) {
  struct stat st;
  if (lstat(o->path, &st) == 0 && !S_ISREG(st.st_mode))
    return vs_error_set(&o->err, VS_ERR_INVALID,
                        "%s: became something other than a regular file; not replaced",
                        o->path);
  if (rename(part, o->path) != 0)
    return vs_error_set(&o->err, VS_ERR_IO, "output: %s: cannot rename to %s: %s", part, o->path,
                        strerror(errno));
  return VS_OK;
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
  vs_error_clear(&o->err);
  o->path = dup_str(path);
  o->xmf_path = xmf_path_of(path);
  if (o->path == NULL || o->xmf_path == NULL || geometry_init(o, vs_run_geometry(run)) != VS_OK) {
    vs_output_destroy(&o);
    return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  }
  o->flush_rows = buffer_rows(o);
  /* the target and its sidecar are absent or regular files, and no other process writes them */
  const vs_outpath_other sidecar[1] = {{o->xmf_path, "its XDMF sidecar"}};
  st = vs_outpath_check(path, sidecar, 1, err);
  if (st == VS_OK) st = vs_outpath_check(o->xmf_path, NULL, 0, err);
  if (st == VS_OK) st = vs_outlock_acquire(path, &o->lock, err);
  if (st != VS_OK) {
    vs_output_destroy(&o);
    return st;
  }
  /* built under a temporary name: a file at path always has its whole layout */
  char *part = malloc(strlen(path) + sizeof VS_OUT_PART);
  if (part == NULL) {
    vs_output_destroy(&o);
    return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  }
  snprintf(part, strlen(path) + sizeof VS_OUT_PART, "%s%s", path, VS_OUT_PART);
  h5_quiet q = quiet_begin();
  st = remove_stale_part(o, part);
  const int made = st == VS_OK; /* a part file from here on is ours */
  if (st == VS_OK) {
    st = file_create(o, part);
    if (st == VS_OK) st = create_layout(o, run, case_text);
  }
  if (st == VS_OK) st = replace_target(o, part);
  quiet_end(q);
  if (st != VS_OK) {
    if (err != NULL) *err = o->err;
    o->pending = 0;
    o->err.status = VS_ERR_IO; /* destroy must not flush */
    vs_output_destroy(&o);
    if (made) remove(part);
    free(part);
    return st;
  }
  free(part);
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
  h5_quiet q = quiet_begin();
  if (o->file >= 0 && o->err.status == VS_OK) flush_file(o);
  if (o->err.status != VS_OK) abandon_file(o);
  for (int i = 0; i < S_COUNT; i++) {
    h5_close(o->s[i].dset);
    free(o->s[i].buf);
  }
  h5_close(o->events);
  h5_close(o->ev_mtype);
  free(o->ev_buf);
  h5_close(o->file);
  H5Eclear2(H5E_DEFAULT);
  quiet_end(q);
  vs_outlock_release(&o->lock);
  free(o->path);
  free(o->xmf_path);
  free(o->bref);
  free(o->jref);
  free(o->js);
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
char *vs_output_xdmf_path_for(const char *h5_path) { return xmf_path_of(h5_path); }

void vs_output_interrupt(vs_output *o) {
  if (o != NULL) o->interrupted = 1;
}

/* ------------------------------------------------------------------------------------------ */
/* Rows                                                                                         */

static void fill_blocks(vs_output *o, const vs_run *run, const vs_run_sample *s,
                        const double usup[2]) {
  const vs_geometry *g = vs_run_geometry(run);
  const size_t n3 = 3 * (size_t)o->nb;
  double *bv = row_ptr(o, S_BVEL), *sp = row_ptr(o, S_BSPEED);
  memcpy(row_ptr(o, S_BPOS), s->q, n3 * sizeof(double));
  if (s->v != NULL)
    memcpy(bv, s->v, n3 * sizeof(double));
  else
    memset(bv, 0, n3 * sizeof(double));
  for (int b = 0; b < o->nb; b++) sp[b] = hypot(bv[3 * b], bv[3 * b + 1]);
  float *pts = row_ptr(o, S_BPTS);
  const size_t np = (size_t)o->np;
  for (int b = 0; b < o->nb; b++)
    for (size_t k = 0; k < np; k++) {
      const double *ref = o->bref + 2 * ((size_t)b * np + k);
      double p[2];
      body_move(g, s->q, usup, b, ref[0], ref[1], p);
      pts[2 * ((size_t)b * np + k)] = (float)p[0];
      pts[2 * ((size_t)b * np + k) + 1] = (float)p[1];
    }
}

static void fill_joints(vs_output *o, const vs_run *run, const vs_run_sample *s,
                        const double usup[2]) {
  const vs_geometry *g = vs_run_geometry(run);
  const vs_hinge_opts *ho = vs_run_hinge_opts(run);
  double *N = row_ptr(o, S_N), *T = row_ptr(o, S_T), *M = row_ptr(o, S_M);
  double *c = row_ptr(o, S_CONTACT), *gi = row_ptr(o, S_GAP_I), *ge = row_ptr(o, S_GAP_E);
  double *sl = row_ptr(o, S_SLIP), *sp = row_ptr(o, S_SLIP_P);
  int8_t *h = row_ptr(o, S_HINGE);
  float *pts = row_ptr(o, S_JPTS);
  for (int k = 0; k < o->nj; k++) {
    const vs_joint_state *st = &s->joints[k]; /* the run's evaluation at this state */
    N[k] = st->N, T[k] = st->T, M[k] = st->M, c[k] = st->contact;
    gi[k] = st->gap_i, ge[k] = st->gap_e, sl[k] = st->slip, sp[k] = st->slip_p;
    const char side = vs_hinges_joint_side(ho, st);
    h[k] = (int8_t)(side == 'I' ? 1 : side == 'E' ? 2 : 0);
    const vs_joint_geom *j = &g->joints[k];
    for (int e = 0; e < 2; e++) {
      double pa[2], pb[2];
      body_move(g, s->q, usup, j->a, o->jref[4 * k + 2 * e], o->jref[4 * k + 2 * e + 1], pa);
      body_move(g, s->q, usup, j->b, o->jref[4 * k + 2 * e], o->jref[4 * k + 2 * e + 1], pb);
      pts[4 * k + 2 * e] = (float)(0.5 * (pa[0] + pb[0]));
      pts[4 * k + 2 * e + 1] = (float)(0.5 * (pa[1] + pb[1]));
    }
  }
}

static void fill_row(vs_output *o, const vs_run *run, const vs_run_sample *s) {
  const vs_model *m = vs_run_model(run);
  double usup[2];
  vs_model_support_displacement(m, s->delta, usup);
  *(int64_t *)row_ptr(o, S_STEP) = (int64_t)(o->rows + o->pending);
  *(double *)row_ptr(o, S_TIME) = s->t;
  *(double *)row_ptr(o, S_DELTA) = s->delta;
  memcpy(row_ptr(o, S_SUPPORT), usup, sizeof usup);
  *(int8_t *)row_ptr(o, S_PHASE) = (int8_t)s->phase;
  fill_blocks(o, run, s, usup);
  fill_joints(o, run, s, usup);
  double *r = row_ptr(o, S_REACT);
  memcpy(r, s->reactions, 6 * sizeof *r); /* the run's, at this state */
  int64_t *sv = row_ptr(o, S_SOLVER);
  sv[0] = (int64_t)s->newton_iterations;
  sv[1] = (int64_t)s->ida_steps;
  sv[2] = (int64_t)s->ida_newton_iterations;
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
  h5_quiet q = quiet_begin();
  vs_status st = VS_OK;
  if (o->last_phase >= 0 && (int)s->phase != o->last_phase) st = flush_file(o);
  if (st == VS_OK) {
    fill_row(o, run, s);
    o->pending++;
    o->last_phase = (int)s->phase;
    /* at every flush_rows-th row of the file: the writes fill whole chunks */
    if ((size_t)(o->rows + o->pending) % o->flush_rows == 0) st = flush_file(o);
  }
  quiet_end(q);
  return st == VS_OK ? 0 : 1;
}

int vs_output_event(void *user, const vs_run *run, const vs_run_event *e) {
  (void)run;
  vs_output *o = user;
  if (o->err.status != VS_OK || o->interrupted || o->finished) return 1;
  /* buffered: written with the rows at the next flush */
  if (o->ev_pending == o->ev_cap) {
    long cap = o->ev_cap ? 2 * o->ev_cap : 64;
    event_row *b = realloc(o->ev_buf, (size_t)cap * sizeof *b);
    if (b == NULL) {
      vs_error_set(&o->err, VS_ERR_NOMEM, "output: out of memory");
      return 1;
    }
    o->ev_buf = b;
    o->ev_cap = cap;
  }
  o->ev_buf[o->ev_pending++] = event_to_row(e);
  return 0;
}

/* ------------------------------------------------------------------------------------------ */
/* Summary                                                                                      */

typedef struct {
  char label, side;
  const char *name, *name_onset;
  int32_t first, last, onset_first, onset_last;
  double delta_onset, time_onset;
  int32_t order;
  int8_t open;
  double delta_closed;
  int8_t during_fall;
} hinge_row;

static const char HINGE_UNITS[] = ",,,,,,,,m,s,,,m,";

static hid_t hinge_mtype(void) {
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(hinge_row)), c1 = char_type(), vs = vlstr_type();
  herr_t rc = (t >= 0 && c1 >= 0 && vs >= 0) ? 0 : -1;
#define INS(field, type) \
  if (rc >= 0) rc = H5Tinsert(t, #field, HOFFSET(hinge_row, field), type)
  INS(label, c1);
  INS(side, c1);
  INS(name, vs);
  INS(name_onset, vs);
  INS(first, H5T_NATIVE_INT32);
  INS(last, H5T_NATIVE_INT32);
  INS(onset_first, H5T_NATIVE_INT32);
  INS(onset_last, H5T_NATIVE_INT32);
  INS(delta_onset, H5T_NATIVE_DOUBLE);
  INS(time_onset, H5T_NATIVE_DOUBLE);
  INS(order, H5T_NATIVE_INT32);
  INS(open, H5T_NATIVE_INT8);
  INS(delta_closed, H5T_NATIVE_DOUBLE);
  INS(during_fall, H5T_NATIVE_INT8);
#undef INS
  h5_close(c1);
  h5_close(vs);
  if (rc < 0) h5_close(t);
  return rc < 0 ? H5I_INVALID_HID : t;
}

/* A compound table: memory type mt, packed in the file, with unit and description. */
static herr_t table_write(hid_t loc, const char *name, hid_t mt, size_t n, const void *rows,
                          const char *unit, const char *description) {
  hid_t ft = H5Tcopy(mt);
  hsize_t dims[1] = {n};
  herr_t rc = ft >= 0 ? H5Tpack(ft) : -1;
  hid_t sp = H5Screate_simple(1, dims, NULL);
  hid_t d = (rc >= 0 && sp >= 0)
                ? H5Dcreate2(loc, name, ft, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                : H5I_INVALID_HID;
  rc = d >= 0 ? 0 : -1;
  if (rc >= 0 && n > 0) rc = H5Dwrite(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows);
  if (rc >= 0) rc = attr_str(d, "unit", unit);
  if (rc >= 0) rc = attr_str(d, "description", description);
  h5_close(d);
  h5_close(sp);
  h5_close(ft);
  return rc;
}

/* Hinge table name of hinges h[0..n); during_fall from index fall_from on. */
static herr_t hinge_table(hid_t loc, const char *name, const vs_hinge *h, int n, int fall_from,
                          double rate, const char *description) {
  typedef char name_buf[96];
  hinge_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  name_buf *names = calloc((size_t)(n > 0 ? n : 1), 2 * sizeof *names);
  hid_t mt = hinge_mtype();
  herr_t rc = (rows != NULL && names != NULL && mt >= 0) ? 0 : -1;
  for (int i = 0; rc >= 0 && i < n; i++) {
    vs_hinge_name(&h[i], 0, names[2 * i], sizeof names[0]);
    vs_hinge_name(&h[i], 1, names[2 * i + 1], sizeof names[0]);
    rows[i] = (hinge_row){.label = h[i].label,
                          .side = h[i].side,
                          .name = names[2 * i],
                          .name_onset = names[2 * i + 1],
                          .first = h[i].first,
                          .last = h[i].last,
                          .onset_first = h[i].onset_first,
                          .onset_last = h[i].onset_last,
                          .delta_onset = h[i].delta_onset,
                          .time_onset = h[i].delta_onset / rate,
                          .order = h[i].order,
                          .open = (int8_t)h[i].open,
                          .delta_closed = h[i].delta_closed,
                          .during_fall = (int8_t)(i >= fall_from)};
  }
  if (rc >= 0) rc = table_write(loc, name, mt, (size_t)n, rows, HINGE_UNITS, description);
  h5_close(mt);
  free(rows);
  free(names);
  return rc;
}

typedef struct {
  double delta;
  const char *kind;
  double delta_settled;
  const char *hinges_before, *hinges_after;
} limit_row;

static herr_t limits_table(hid_t loc, const vs_run *run) {
  const int n = vs_run_limit_count(run);
  limit_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(limit_row)), vs = vlstr_type();
  herr_t rc = (rows != NULL && mt >= 0 && vs >= 0) ? 0 : -1;
  if (rc >= 0) rc = H5Tinsert(mt, "delta", HOFFSET(limit_row, delta), H5T_NATIVE_DOUBLE);
  if (rc >= 0) rc = H5Tinsert(mt, "kind", HOFFSET(limit_row, kind), vs);
  if (rc >= 0)
    rc = H5Tinsert(mt, "delta_settled", HOFFSET(limit_row, delta_settled), H5T_NATIVE_DOUBLE);
  if (rc >= 0) rc = H5Tinsert(mt, "hinges_before", HOFFSET(limit_row, hinges_before), vs);
  if (rc >= 0) rc = H5Tinsert(mt, "hinges_after", HOFFSET(limit_row, hinges_after), vs);
  for (int i = 0; rc >= 0 && i < n; i++) {
    const vs_limit_record *l = vs_run_limit(run, i);
    rows[i] = (limit_row){.delta = l->delta,
                          .delta_settled = l->delta_settled,
                          .kind = l->collapse                  ? "collapse"
                                  : isfinite(l->delta_settled) ? "snap"
                                                               : "unfollowed",
                          .hinges_before = l->hinges_before,
                          .hinges_after = l->hinges_after};
  }
  if (rc >= 0)
    rc = table_write(loc, "limit_points", mt, (size_t)n, rows, "m,,m,,",
                     "limit points of the quasi-static path in order; kind: snap (the motion "
                     "settled at delta_settled), collapse, unfollowed (dynamic.follow = 0)");
  h5_close(vs);
  h5_close(mt);
  free(rows);
  return rc;
}

static herr_t summary_collapse(hid_t sum, const vs_run *run) {
  const vs_collapse_record *c = vs_run_collapse(run);
  const vs_case *cs = vs_run_case(run);
  const double L = vs_run_geometry(run)->span, alpha = cs->alpha_deg * VS_DEG;
  const double rate = cs->rate_mm_s * VS_MM;
  hid_t g = group_create(sum, "collapse");
  herr_t rc = g >= 0 ? attr_int(g, "found", c->found) : -1;
  if (rc >= 0) rc = attr_str(g, "pattern", vs_run_pattern_collapse(run));
  if (rc >= 0) rc = dset_scalar(g, "delta", c->found ? c->delta : NAN, "m");
  if (rc >= 0) rc = dset_scalar(g, "dz_over_L", c->found ? c->delta * cos(alpha) / L : NAN, "1");
  if (rc >= 0) rc = dset_scalar(g, "dx_over_L", c->found ? c->delta * sin(alpha) / L : NAN, "1");
  if (rc >= 0) rc = dset_scalar(g, "time", c->found ? c->t : NAN, "s");
  if (rc >= 0) rc = dset_scalar(g, "delta_detected", c->found ? c->delta_detected : NAN, "m");
  if (rc >= 0) rc = dset_scalar(g, "time_detected", c->found ? c->t_criterion : NAN, "s");
  if (rc >= 0) rc = dset_scalar(g, "time_onset", c->found ? c->t_onset : NAN, "s");
  if (rc >= 0) rc = dset_scalar(g, "delta_onset", c->found ? c->t_onset * rate : NAN, "m");
  if (rc >= 0)
    rc = hinge_table(g, "hinges", c->hinges, c->found ? c->n_hinges : 0, 1 << 30, rate,
                     "hinges open at the collapse's onset, left to right");
  if (rc >= 0)
    rc = attr_str(g, "description",
                  "collapse: delta (delta_u) is the support displacement at which the arch "
                  "departs from its last stable equilibrium: the collapsing limit point, or "
                  "with --dynamic the kinetic energy's last rise through the rest level (an "
                  "IDA root); delta_detected when the kinetic energy passed the collapse "
                  "threshold; time_onset when the final motion began (NaN if the arch was never "
                  "at rest); NaN everywhere when found = 0");
  h5_close(g);
  return rc;
}

static herr_t summary_first_limit(hid_t sum, const vs_run *run) {
  const vs_path_result *p = vs_run_path(run);
  const int found = p->end == VS_PATH_LIMIT_POINT && vs_run_limit_count(run) > 0;
  hid_t g = group_create(sum, "first_limit");
  herr_t rc = g >= 0 ? attr_int(g, "found", found) : -1;
  if (rc >= 0) rc = attr_int(g, "det_sign", found ? p->evidence.det_sign : 0);
  if (rc >= 0) rc = dset_scalar(g, "delta", found ? p->delta_limit : NAN, "m");
  if (rc >= 0) rc = dset_scalar(g, "delta_fail", found ? p->delta_fail : NAN, "m");
  if (rc >= 0) rc = dset_scalar(g, "lambda_start", found ? p->evidence.lambda_start : NAN, "N/m");
  if (rc >= 0) rc = dset_scalar(g, "lambda_last", found ? p->evidence.lambda_last : NAN, "N/m");
  if (rc >= 0)
    rc = dset_scalar(g, "delta_extrapolated", found ? p->evidence.delta_extrap : NAN, "m");
  h5_close(g);
  return rc;
}

static herr_t summary_totals(hid_t sum, const vs_run *run) {
  const vs_path_result *p = vs_run_path_totals(run);
  const vs_dyn_result *d = vs_run_dynamic_totals(run);
  hid_t g = group_create(sum, "quasistatic");
  herr_t rc = g >= 0 ? attr_int(g, "steps", p->steps) : -1;
  if (rc >= 0) rc = attr_int(g, "rejected", p->rejected);
  if (rc >= 0) rc = attr_int(g, "newton_iterations", p->newton_iterations);
  if (rc >= 0) rc = attr_int(g, "jacobian_evals", p->jacobian_evals);
  if (rc >= 0) rc = attr_int(g, "floor_limited", p->floor_limited);
  if (rc >= 0) rc = dset_scalar(g, "max_residual", p->max_residual, "1");
  h5_close(g);
  g = rc >= 0 ? group_create(sum, "dynamic") : H5I_INVALID_HID;
  rc = g >= 0 ? attr_int(g, "steps", d->steps) : -1;
  if (rc >= 0) rc = attr_int(g, "newton_iterations", d->newton_iterations);
  if (rc >= 0) rc = attr_int(g, "root_events", d->root_events);
  if (rc >= 0) rc = attr_int(g, "jacobian_evals", d->jac_evals);
  if (rc >= 0) rc = dset_scalar(g, "max_kinetic", d->max_kinetic, "J");
  if (rc >= 0) rc = dset_scalar(g, "balance_error_rel", d->balance_error_rel, "1");
  if (rc >= 0)
    rc = attr_str(g, "description",
                  "totals of all dynamic phases; balance_error_rel: the worst |energy balance| "
                  "relative to the largest energy term");
  h5_close(g);
  return rc;
}

/* /summary/damping: the model and the natural frequencies under self-weight with the damping
 * ratio the model gives each mode. */
static herr_t summary_damping(hid_t sum, const vs_run *run) {
  const vs_case *c = vs_run_case(run);
  const vs_modal *md = vs_run_modal(run);
  double alpha, beta, col[3][VS_MODAL_MAX];
  vs_run_rayleigh(run, &alpha, &beta);
  hid_t g = group_create(sum, "damping");
  herr_t rc = g >= 0 ? attr_str(g, "model", vs_damping_model_name((vs_damping_model)c->damping_model)) : -1;
  if (rc >= 0) rc = attr_double(g, "ratio", c->damping);
  if (rc >= 0) rc = dset_scalar(g, "rayleigh_alpha", alpha, "1/s");
  if (rc >= 0) rc = dset_scalar(g, "rayleigh_beta", beta, "s");
  if (rc >= 0) rc = attr_int(g, "impacts", vs_run_dynamic_totals(run)->impacts);
  for (int i = 0; i < md->n_modes; i++) {
    col[0][i] = md->freq_hz[i];
    col[1][i] = md->omega[i];
    col[2][i] = md->zeta[i];
  }
  const hsize_t dims[1] = {(hsize_t)md->n_modes};
  if (rc >= 0) rc = dset_write(g, "freq", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[0], "Hz", NULL);
  if (rc >= 0) rc = dset_write(g, "omega", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[1], "rad/s", NULL);
  if (rc >= 0) rc = dset_write(g, "damping_ratio", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[2], "1", NULL);
  if (rc >= 0)
    rc = attr_str(g, "description",
                  "the lowest natural modes about the self-weight equilibrium (tangent stiffness, "
                  "block masses) and the damping ratio phi^T C phi / (2 omega) the damping model "
                  "gives each; empty when not computed (more than 5000 voussoirs)");
  h5_close(g);
  return rc;
}

/* /summary/ground, when the fall landed on the ground (contact.h): its level, a segment of it
 * for the pictures and the sidecar (two span widths, centred on the arch), the penetrations and
 * whether the debris came to rest, and the fall's cost. */
static herr_t summary_ground(hid_t sum, const vs_run *run) {
  const double z = vs_run_ground(run), L = vs_run_geometry(run)->span;
  if (!isfinite(z)) return 0;
  const vs_dyn_result *d = vs_run_dynamic_totals(run);
  const double pts[4] = {-L, z, L, z};
  const hsize_t dims[2] = {2, 2};
  hid_t g = group_create(sum, "ground");
  herr_t rc = g >= 0 ? dset_scalar(g, "level", z, "m") : -1;
  if (rc >= 0)
    rc = dset_write(g, "points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dims, pts, "m,m", "x,z");
  if (rc >= 0) rc = dset_scalar(g, "penetration_final", vs_run_penetration(run), "m");
  if (rc >= 0) rc = dset_scalar(g, "penetration_max", d->max_penetration, "m");
  if (rc >= 0) rc = dset_scalar(g, "fall_wall_time", d->fall_wall_s, "s");
  if (rc >= 0) rc = attr_int(g, "at_rest", d->fall_at_rest);
  if (rc >= 0)
    rc = attr_str(g, "description",
                  "the ground the collapsed arch fell onto (z up, the geometry's frame): level; "
                  "points, a segment of it; penetration_final, the deepest block vertex below it "
                  "at the last state (< 0: none touches), penetration_max over the fall; at_rest "
                  "= 1 if the fall ended with the debris at rest; fall_wall_time, its cost");
  h5_close(g);
  return rc;
}

static vs_status write_summary(vs_output *o, const vs_run *run) {
  hid_t sum = H5Gopen2(o->file, "summary", H5P_DEFAULT);
  const char *mode = vs_run_mode(run);
  char open[512];
  vs_run_open_hinges(run, open, sizeof open);
  herr_t rc = sum >= 0 ? attr_str(sum, "mode", mode != NULL ? mode : "") : -1;
  if (rc >= 0) rc = attr_str(sum, "pattern_initial", vs_run_pattern_initial(run));
  if (rc >= 0) rc = attr_str(sum, "pattern_collapse", vs_run_pattern_collapse(run));
  if (rc >= 0) rc = attr_str(sum, "open_hinges", open);
  if (rc >= 0) rc = attr_int(sum, "rows", o->rows);
  if (rc >= 0) rc = attr_int(sum, "events", o->n_events);
  if (rc >= 0) rc = dset_scalar(sum, "delta_final", vs_run_delta(run), "m");
  if (rc >= 0) rc = dset_scalar(sum, "time_final", vs_run_time(run), "s");
  if (rc >= 0) rc = dset_scalar(sum, "wall_time", vs_run_wall_s(run), "s");
  if (rc >= 0) rc = limits_table(sum, run);
  if (rc >= 0) rc = summary_first_limit(sum, run);
  if (rc >= 0) rc = summary_collapse(sum, run);
  if (rc >= 0) rc = summary_totals(sum, run);
  if (rc >= 0) rc = summary_damping(sum, run);
  if (rc >= 0) rc = summary_ground(sum, run);
  const vs_hinges *h = vs_run_hinges(run);
  const int n = vs_hinges_count(h);
  vs_hinge *all = calloc((size_t)(n > 0 ? n : 1), sizeof *all);
  if (all == NULL) rc = -1;
  for (int i = 0; rc >= 0 && i < n; i++) all[i] = *vs_run_hinge(run, i);
  if (rc >= 0)
    rc = hinge_table(sum, "hinges", all, n, vs_run_hinge_count(run),
                     vs_run_case(run)->rate_mm_s * VS_MM,
                     "hinges in order of appearance. label A-E; side: the edge that stays in "
                     "contact (I intrados, E extrados); name: joints (e.g. 44-45-46-I, "
                     "after a collapse those at its onset, not at the end of the fall; "
                     "a hinge spread over consecutive joints), name_onset: joints when it formed; "
                     "during_fall = 1: opened as the arch fell after the collapse's onset");
  free(all);
  h5_close(sum);
  return rc < 0 ? h5_fail(&o->err, o->path, "cannot write /summary") : VS_OK;
}

/* Rewrite /events from the run's log: the first three hinges get their labels together, after
 * their events were emitted. */
static vs_status rewrite_events(vs_output *o, const vs_run *run) {
  const int n = vs_run_event_count(run);
  event_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  if (rows == NULL) return vs_error_set(&o->err, VS_ERR_NOMEM, "output: out of memory");
  for (int i = 0; i < n; i++) rows[i] = event_to_row(vs_run_event_get(run, i));
  herr_t rc = events_write(o, 0, (hsize_t)n, rows);
  free(rows);
  if (rc < 0) return h5_fail(&o->err, o->path, "cannot rewrite /events");
  o->n_events = n;
  return VS_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* XDMF sidecar                                                                                 */

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
  X_COUNT
};

static const char *const XDMF_PATHS[X_COUNT] = {
    "/observables/block_points/value", "/geometry/block_connectivity",
    "/observables/joint_points/value", "/geometry/joint_connectivity",
    "/observables/delta/time",         "/observables/block_position/value",
    "/observables/block_speed/value",  "/observables/joint_N/value",
    "/observables/joint_T/value",      "/observables/joint_M/value",
    "/observables/joint_gap_i/value",  "/observables/joint_gap_e/value",
    "/observables/joint_hinge/value",  "/observables/reactions/value",
    "/observables/support_displacement/value"};
static const int XDMF_RANKS[X_COUNT] = {3, 2, 3, 2, 1, 3, 2, 2, 2, 2, 2, 2, 2, 2, 2};

/* Every cell field any grid carries. ParaView's default XDMF reader (Xdmf3ReaderS, what File >
 * Open picks) flattens a step's grids into pieces of one data set, and its geometry filter then
 * appends the pieces keeping only the fields that all of them carry: a field on the blocks alone
 * is dropped and colouring by it leaves the arch grey. So every grid carries every field, NaN
 * where the field is not its own (ParaView draws NaN in its NaN colour and leaves it out of
 * ranges); Xdmf3ReaderT keeps the grids as named blocks and reads the same file. */
static const char *const XDMF_FIELDS[] = {"theta_rad", "ux_m",    "uz_m",    "speed_m_s",
                                          "N_N",       "T_N",     "M_N_m",   "gap_i_m",
                                          "gap_e_m",   "hinge_0closed_1intrados_2extrados",
                                          "Fx_N",      "Fz_N"};
enum { XDMF_N_FIELDS = (int)(sizeof XDMF_FIELDS / sizeof XDMF_FIELDS[0]) };

typedef struct {
  FILE *f;
  const char *h5name; /* XML-escaped name of the HDF5 file, relative to the sidecar */
  xdmf_ds ds[X_COUNT];
  unsigned carried; /* bit i: the open grid carries XDMF_FIELDS[i] */
  int ground; /* the record has /summary/ground/points */
} xdmf_ctx;

static void xml_escape(const char *s, char *out, size_t size) {
  size_t used = 0;
  for (; *s != '\0' && used + 7 < size; s++) {
    const char *rep = *s == '&'   ? "&amp;"
                      : *s == '<' ? "&lt;"
                      : *s == '>' ? "&gt;"
                      : *s == '"' ? "&quot;"
                                  : NULL;
    if (rep != NULL) {
      memcpy(out + used, rep, strlen(rep));
      used += strlen(rep);
    } else {
      out[used++] = *s;
    }
  }
  out[used] = '\0';
}

static void xdmf_dims(FILE *f, int rank, const hsize_t *d) {
  for (int i = 0; i < rank; i++) fprintf(f, "%s%llu", i ? " " : "", (unsigned long long)d[i]);
}

/* The block [start, start + count) of dataset `which`, in XDMF 3's own hyperslab syntax:
 * "file:/path|start:stride:count:dataset dimensions". ParaView's default XDMF reader
 * (Xdmf3ReaderS/T) reads it; it crashes on an ItemType="HyperSlab" item used as a geometry (it
 * asks the array's type before reading the slab), and the legacy "XDMF Reader" reads only that
 * older form, so there is no syntax both accept. */
static void xdmf_block(const xdmf_ctx *x, int which, const hsize_t *start, const hsize_t *count,
                       const char *type, int prec, const char *ind) {
  const xdmf_ds *d = &x->ds[which];
  const hsize_t stride[3] = {1, 1, 1};
  fprintf(x->f, "%s<DataItem Dimensions=\"", ind);
  xdmf_dims(x->f, d->rank, count);
  fprintf(x->f, "\" NumberType=\"%s\" Precision=\"%d\" Format=\"HDF\">%s:%s|", type, prec,
          x->h5name, d->path);
  xdmf_dims(x->f, d->rank, start);
  fputc(':', x->f);
  xdmf_dims(x->f, d->rank, stride);
  fputc(':', x->f);
  xdmf_dims(x->f, d->rank, count);
  fputc(':', x->f);
  xdmf_dims(x->f, d->rank, d->dims);
  fputs("</DataItem>\n", x->f);
}

/* Row r of dataset `which`, columns [col, col + ncol) of its last dimension (ncol 0: all). */
static void xdmf_slab(const xdmf_ctx *x, int which, hsize_t r, hsize_t col, hsize_t ncol,
                      const char *type, int prec, const char *ind) {
  const xdmf_ds *d = &x->ds[which];
  hsize_t start[3] = {r, 0, 0}, count[3] = {1, d->dims[1], d->dims[2]};
  if (ncol > 0) start[d->rank - 1] = col, count[d->rank - 1] = ncol;
  xdmf_block(x, which, start, count, type, prec, ind);
}

/* A cell field (one of XDMF_FIELDS); its name carries its unit (ParaView shows names only). */
static void xdmf_attribute(xdmf_ctx *x, const char *name, int which, hsize_t r, hsize_t col,
                           hsize_t ncol, const char *type, int prec) {
  const char *ind = "          ";
  for (int i = 0; i < XDMF_N_FIELDS; i++)
    if (strcmp(name, XDMF_FIELDS[i]) == 0) x->carried |= 1u << i;
  fprintf(x->f, "        <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n", name);
  xdmf_slab(x, which, r, col, ncol, type, prec, ind);
  fputs("        </Attribute>\n", x->f);
}

static void xdmf_grid_open(xdmf_ctx *x, const char *name) {
  x->carried = 0;
  fprintf(x->f, "      <Grid Name=\"%s\" GridType=\"Uniform\">\n", name);
}

/* Field XDMF_FIELDS[i] as NaN on all n_cells cells of the open grid, inline. */
static void xdmf_nan_field(xdmf_ctx *x, int i, hsize_t n_cells) {
  x->carried |= 1u << i;
  fprintf(x->f,
          "        <Attribute Name=\"%s\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
          "          <DataItem Dimensions=\"%llu\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"XML\">",
          XDMF_FIELDS[i], (unsigned long long)n_cells);
  for (hsize_t c = 0; c < n_cells; c++) fputs(c ? " nan" : "nan", x->f);
  fputs("</DataItem>\n        </Attribute>\n", x->f);
}

/* A grid that is not the blocks starts with theta_rad (NaN): ParaView shows the first field of
 * a grid on opening, and the blocks' rotation is the one worth seeing first. */
static void xdmf_theta_first(xdmf_ctx *x, hsize_t n_cells) { xdmf_nan_field(x, 0, n_cells); }

/* End a grid of n_cells cells: the fields of XDMF_FIELDS it does not carry, NaN. */
static void xdmf_grid_close(xdmf_ctx *x, hsize_t n_cells) {
  for (int i = 0; i < XDMF_N_FIELDS; i++)
    if (!(x->carried & (1u << i))) xdmf_nan_field(x, i, n_cells);
  fputs("      </Grid>\n", x->f);
}

/* The blocks at row r: one polygon each, moved. */
static void xdmf_blocks(xdmf_ctx *x, hsize_t r) {
  const xdmf_ds *bc = &x->ds[X_BCONN];
  xdmf_grid_open(x, "blocks");
  fprintf(x->f,
          "        <Topology TopologyType=\"Polygon\" NodesPerElement=\"%llu\" "
          "NumberOfElements=\"%llu\">\n"
          "          <DataItem Dimensions=\"%llu %llu\" NumberType=\"Int\" Precision=\"4\" "
          "Format=\"HDF\">%s:%s</DataItem>\n"
          "        </Topology>\n        <Geometry GeometryType=\"XY\">\n",
          (unsigned long long)bc->dims[1], (unsigned long long)bc->dims[0],
          (unsigned long long)bc->dims[0], (unsigned long long)bc->dims[1], x->h5name, bc->path);
  xdmf_slab(x, X_BPTS, r, 0, 0, "Float", 4, "          ");
  fputs("        </Geometry>\n", x->f);
  xdmf_attribute(x, "theta_rad", X_BPOS, r, 2, 1, "Float", 8);
  xdmf_attribute(x, "ux_m", X_BPOS, r, 0, 1, "Float", 8);
  xdmf_attribute(x, "uz_m", X_BPOS, r, 1, 1, "Float", 8);
  xdmf_attribute(x, "speed_m_s", X_BSPEED, r, 0, 0, "Float", 8);
  xdmf_grid_close(x, bc->dims[0]);
}

/* The joints at row r: one segment each, intrados to extrados. */
static void xdmf_joints(xdmf_ctx *x, hsize_t r) {
  const xdmf_ds *jc = &x->ds[X_JCONN];
  xdmf_grid_open(x, "joints");
  fprintf(x->f,
          "        <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
          "NumberOfElements=\"%llu\">\n"
          "          <DataItem Dimensions=\"%llu 2\" NumberType=\"Int\" Precision=\"4\" "
          "Format=\"HDF\">%s:%s</DataItem>\n"
          "        </Topology>\n        <Geometry GeometryType=\"XY\">\n",
          (unsigned long long)jc->dims[0], (unsigned long long)jc->dims[0], x->h5name, jc->path);
  xdmf_slab(x, X_JPTS, r, 0, 0, "Float", 4, "          ");
  fputs("        </Geometry>\n", x->f);
  xdmf_theta_first(x, jc->dims[0]);
  xdmf_attribute(x, "N_N", X_N, r, 0, 0, "Float", 8);
  xdmf_attribute(x, "T_N", X_T, r, 0, 0, "Float", 8);
  xdmf_attribute(x, "M_N_m", X_M, r, 0, 0, "Float", 8);
  xdmf_attribute(x, "gap_i_m", X_GAPI, r, 0, 0, "Float", 8);
  xdmf_attribute(x, "gap_e_m", X_GAPE, r, 0, 0, "Float", 8);
  /* read as a double (HDF5 converts), the type the other grids' NaN has */
  xdmf_attribute(x, "hinge_0closed_1intrados_2extrados", X_HINGE, r, 0, 0, "Float", 8);
  xdmf_grid_close(x, jc->dims[0]);
}

/* A support at row r: the springing face it carries (joint 1 on the left, n+1 on the right),
 * with the force it exerts on the arch and, for the moved right support, its displacement. */
static void xdmf_support(xdmf_ctx *x, int right, hsize_t r) {
  const char *ind = "          ";
  const hsize_t nj = x->ds[X_JCONN].dims[0];
  const hsize_t start[3] = {r, right ? 2 * nj - 2 : 0, 0}, count[3] = {1, 2, 2};
  xdmf_grid_open(x, right ? "support_right" : "support_left");
  fputs("        <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
        "NumberOfElements=\"1\">\n"
        "          <DataItem Dimensions=\"1 2\" NumberType=\"Int\" Precision=\"4\" "
        "Format=\"XML\">0 1</DataItem>\n"
        "        </Topology>\n        <Geometry GeometryType=\"XY\">\n",
        x->f);
  xdmf_block(x, X_JPTS, start, count, "Float", 4, ind);
  fputs("        </Geometry>\n", x->f);
  xdmf_theta_first(x, 1);
  xdmf_attribute(x, "Fx_N", X_REACT, r, right ? 3 : 0, 1, "Float", 8);
  xdmf_attribute(x, "Fz_N", X_REACT, r, right ? 4 : 1, 1, "Float", 8);
  xdmf_attribute(x, "M_N_m", X_REACT, r, right ? 5 : 2, 1, "Float", 8);
  if (right) {
    xdmf_attribute(x, "ux_m", X_SUPPORT, r, 0, 1, "Float", 8);
    xdmf_attribute(x, "uz_m", X_SUPPORT, r, 1, 1, "Float", 8);
  }
  xdmf_grid_close(x, 1);
}

/* The ground (a fixed segment), when the fall landed on it; every field NaN (XDMF_FIELDS). */
static void xdmf_ground(xdmf_ctx *x) {
  xdmf_grid_open(x, "ground");
  fprintf(x->f,
          "        <Topology TopologyType=\"Polyline\" NodesPerElement=\"2\" "
          "NumberOfElements=\"1\">\n"
          "          <DataItem Dimensions=\"1 2\" NumberType=\"Int\" Precision=\"4\" "
          "Format=\"XML\">0 1</DataItem>\n"
          "        </Topology>\n        <Geometry GeometryType=\"XY\">\n"
          "          <DataItem Dimensions=\"2 2\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">%s:/summary/ground/points</DataItem>\n"
          "        </Geometry>\n",
          x->h5name);
  xdmf_theta_first(x, 1);
  xdmf_grid_close(x, 1);
}

/* One time step: the row's objects as named grids of a spatial collection. */
static void xdmf_step(xdmf_ctx *x, hsize_t r, double t) {
  fprintf(x->f,
          "    <Grid Name=\"row %llu\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
          "      <Time Value=\"%.17g\"/>\n",
          (unsigned long long)r, t);
  xdmf_blocks(x, r);
  xdmf_joints(x, r);
  xdmf_support(x, 0, r);
  xdmf_support(x, 1, r);
  if (x->ground) xdmf_ground(x);
  fputs("    </Grid>\n", x->f);
}

/* Shapes of the datasets the XDMF refers to; the number of rows they all hold; -1 if the file
 * is not a consistent voussoir record. */
static long xdmf_shapes(hid_t file, xdmf_ctx *x) {
  long rows = -1;
  for (int i = 0; i < X_COUNT; i++) {
    xdmf_ds *d = &x->ds[i];
    d->path = XDMF_PATHS[i];
    d->rank = XDMF_RANKS[i];
    d->dims[1] = d->dims[2] = 1;
    hid_t ds = H5Dopen2(file, d->path, H5P_DEFAULT);
    hid_t sp = ds >= 0 ? H5Dget_space(ds) : H5I_INVALID_HID;
    int rank = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
    if (rank == d->rank) H5Sget_simple_extent_dims(sp, d->dims, NULL);
    h5_close(sp);
    h5_close(ds);
    if (rank != d->rank) return -1;
    if (i != X_BCONN && i != X_JCONN && (rows < 0 || (long)d->dims[0] < rows))
      rows = (long)d->dims[0];
  }
  const hsize_t nb = x->ds[X_BCONN].dims[0], P = x->ds[X_BCONN].dims[1];
  const hsize_t nj = x->ds[X_JCONN].dims[0];
  if (x->ds[X_BPTS].dims[1] != nb * P || x->ds[X_BPTS].dims[2] != 2 ||
      x->ds[X_JCONN].dims[1] != 2 || x->ds[X_JPTS].dims[1] != 2 * nj ||
      x->ds[X_JPTS].dims[2] != 2 || x->ds[X_BPOS].dims[1] != nb || x->ds[X_BPOS].dims[2] != 3 ||
      x->ds[X_BSPEED].dims[1] != nb)
    return -1;
  for (int i = X_N; i <= X_HINGE; i++)
    if (x->ds[i].dims[1] != nj) return -1;
  if (nj < 2 || x->ds[X_REACT].dims[1] != 6 || x->ds[X_SUPPORT].dims[1] != 2) return -1;
  return rows;
}

static vs_status xdmf_write(hid_t file, const char *h5_path, const char *xmf_path, int max_grids,
                            vs_error *err) {
  xdmf_ctx x;
  const long rows = xdmf_shapes(file, &x);
  if (rows < 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "output: %s: not a voussoir record (datasets for "
                        "the XDMF missing or of inconsistent shapes)",
                        h5_path);
  double *t = malloc((size_t)(rows > 0 ? rows : 1) * sizeof *t);
  if (t == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  hid_t td = H5Dopen2(file, x.ds[X_TIME].path, H5P_DEFAULT);
  hid_t fs = td >= 0 ? H5Dget_space(td) : H5I_INVALID_HID;
  hsize_t start[1] = {0}, count[1] = {(hsize_t)rows};
  hid_t ms = H5Screate_simple(1, count, NULL);
  herr_t rc =
      (fs >= 0 && ms >= 0) ? H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) : -1;
  if (rc >= 0 && rows > 0) rc = H5Dread(td, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, t);
  h5_close(ms);
  h5_close(fs);
  h5_close(td);
  if (rc < 0) {
    free(t);
    return h5_fail(err, h5_path, "cannot read /observables/delta/time");
  }
  const char *base = strrchr(h5_path, '/');
  char name[1024], tmp[4096];
  xml_escape(base != NULL ? base + 1 : h5_path, name, sizeof name);
  x.h5name = name;
  x.ground = H5Lexists(file, "/summary", H5P_DEFAULT) > 0 &&
             H5Lexists(file, "/summary/ground", H5P_DEFAULT) > 0 &&
             H5Lexists(file, "/summary/ground/points", H5P_DEFAULT) > 0;
  snprintf(tmp, sizeof tmp, "%s.tmp", xmf_path);
  /* never written through, nor renamed over, anything but a regular file */
  struct stat sb;
  const char *odd = lstat(tmp, &sb) == 0 && !S_ISREG(sb.st_mode)        ? tmp
                    : lstat(xmf_path, &sb) == 0 && !S_ISREG(sb.st_mode) ? xmf_path
                                                                        : NULL;
  if (odd != NULL) {
    free(t);
    return vs_error_set(err, VS_ERR_INVALID, "output: %s: exists and is not a regular file", odd);
  }
  x.f = fopen(tmp, "w");
  if (x.f == NULL) {
    free(t);
    return vs_error_set(err, VS_ERR_IO, "output: %s: cannot write: %s", tmp, strerror(errno));
  }
  const long stride =
      (rows + max_grids - 1) / max_grids > 1 ? (rows + max_grids - 1) / max_grids : 1;
  fprintf(x.f,
          "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
          "<!-- voussoir: %s, %ld rows, every %ld-th shown (and the last), times strictly "
          "increasing (the loading time delta / rate, s).\n"
          "     ParaView: either XDMF 3 reader colours by any field: every grid carries every "
          "field, NaN where it is not the grid's own (the default Xdmf3ReaderS keeps only the "
          "fields all grids carry); Xdmf3ReaderT also keeps the grids as named blocks.\n"
          "     blocks (polygons): theta_rad rotation, ux_m uz_m centroid displacement, speed_m_s;\n"
          "     joints (segments, intrados to extrados): N_N normal force (compression > 0), T_N "
          "shear force, M_N_m moment about the joint centre, gap_i_m gap_e_m edge openings, "
          "hinge code 0 closed, 1 intrados, 2 extrados;\n"
          "     support_left, support_right (the springing faces): Fx_N Fz_N force of the support "
          "on the arch (x right, z up), M_N_m its moment (counter-clockwise, about the springing "
          "joint's centre), ux_m uz_m displacement of the moved support;\n"
          "     ground (a segment, when the fall landed on it): the plane the debris rests on.\n"
          "     The HDF5 file is named relative to this file. -->\n"
          "<Xdmf Version=\"3.0\">\n  <Domain>\n"
          "    <Grid Name=\"voussoir\" GridType=\"Collection\" CollectionType=\"Temporal\">\n",
          name, rows, stride);
  double t_last = -INFINITY;
  for (long r = 0; r < rows; r++) {
    if (r % stride != 0 && r != rows - 1) continue;
    if (!(t[r] > t_last)) continue;
    xdmf_step(&x, (hsize_t)r, t[r]);
    t_last = t[r];
  }
  fputs("    </Grid>\n  </Domain>\n</Xdmf>\n", x.f);
  free(t);
  const int bad = ferror(x.f);
  errno = 0;
  if (fflush(x.f) != 0 || bad) {
    const int e = errno;
    fclose(x.f);
    remove(tmp);
    return vs_error_set(err, VS_ERR_IO, "output: %s: cannot write: %s", xmf_path,
                        e != 0 ? strerror(e) : "write error");
  }
  if (fclose(x.f) != 0 || rename(tmp, xmf_path) != 0) {
    const int e = errno;
    remove(tmp);
    return vs_error_set(err, VS_ERR_IO, "output: %s: cannot write: %s", xmf_path, strerror(e));
  }
  return VS_OK;
}

vs_status vs_output_write_xdmf(const char *h5_path, int max_grids, vs_error *err) {
  vs_output_opts def;
  vs_output_opts_default(&def);
  if (max_grids <= 0) max_grids = def.xdmf_max_grids;
  if (max_grids < 2)
    return vs_error_set(err, VS_ERR_INVALID, "output: xdmf max_grids = %d (allowed: >= 2)",
                        max_grids);
  char *xmf = xmf_path_of(h5_path);
  if (xmf == NULL) return vs_error_set(err, VS_ERR_NOMEM, "output: out of memory");
  h5_quiet q = quiet_begin();
  hid_t f = H5Fopen(h5_path, H5F_ACC_RDONLY, H5P_DEFAULT);
  vs_status st = f < 0 ? h5_fail(err, h5_path, "cannot open") : VS_OK;
  if (st == VS_OK) st = xdmf_write(f, h5_path, xmf, max_grids, err);
  h5_close(f);
  H5Eclear2(H5E_DEFAULT);
  quiet_end(q);
  free(xmf);
  return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Finish                                                                                       */

static void status_text(const vs_output *o, vs_status run_status, const vs_error *run_err,
                        char *buf, size_t size) {
  if (o->interrupted)
    snprintf(buf, size, "failed: interrupted");
  else if (o->err.status != VS_OK)
    snprintf(buf, size, "failed: %s", o->err.msg);
  else if (run_status != VS_OK)
    snprintf(buf, size, "failed: %s%s%s", vs_strerror(run_status),
             run_err != NULL && run_err->msg[0] ? ": " : "", run_err != NULL ? run_err->msg : "");
  else
    snprintf(buf, size, "completed");
}

vs_status vs_output_finish(vs_output *o, const vs_run *run, vs_status run_status,
                           const vs_error *run_err, vs_error *err) {
  if (o->finished) return vs_error_set(err, VS_ERR_INVALID, "output: %s: finished twice", o->path);
  o->finished = 1;
  h5_quiet q = quiet_begin();
  vs_status st = o->err.status == VS_OK ? write_pending(o) : o->err.status;
  if (st == VS_OK) st = rewrite_events(o, run);
  if (st == VS_OK) st = write_summary(o, run);
  /* what the status vouches for is on disk before the status is written */
  if (st == VS_OK && H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0)
    st = h5_fail(&o->err, o->path, "cannot flush /events and /summary");
  if (st == VS_OK) fault_point("before-status");
  /* the status is recorded when the run failed but the file is sound (see abandon_file) */
  char status[sizeof o->err.msg + 64], now[32];
  status_text(o, run_status, run_err, status, sizeof status);
  iso8601_utc(now, sizeof now);
  if (o->err.status == VS_OK && o->file >= 0 &&
      (attr_str(o->file, "status", status) < 0 || attr_str(o->file, "finished", now) < 0 ||
       H5Fflush(o->file, H5F_SCOPE_LOCAL) < 0))
    st = h5_fail(&o->err, o->path, "cannot write the status");
  if (st == VS_OK) fault_point("after-status");
  if (o->err.status != VS_OK) abandon_file(o);
  /* the sidecar is written from what the closed file holds */
  for (int i = 0; i < S_COUNT; i++) {
    h5_close(o->s[i].dset);
    o->s[i].dset = H5I_INVALID_HID;
  }
  h5_close(o->events);
  o->events = H5I_INVALID_HID;
  if (o->file >= 0 && H5Fclose(o->file) < 0 && st == VS_OK)
    st = h5_fail(&o->err, o->path, "cannot close");
  o->file = H5I_INVALID_HID;
  if (st == VS_OK) {
    hid_t f = H5Fopen(o->path, H5F_ACC_RDONLY, H5P_DEFAULT);
    st = f < 0 ? h5_fail(&o->err, o->path, "cannot reopen")
               : xdmf_write(f, o->path, o->xmf_path, o->opts.xdmf_max_grids, &o->err);
    h5_close(f);
    o->xmf_written = st == VS_OK;
  }
  H5Eclear2(H5E_DEFAULT);
  quiet_end(q);
  if (st != VS_OK && err != NULL) *err = o->err;
  return st;
}
