/* libFuzzer target for the readers of a run's record: `voussoir plot` (vs_plot_command:
 * src/plot_cmd.c, plot_record.c; a sweep's summary.h5 only recognised, its charts being
 * matplotlib's) and the XDMF sidecar
 * (vs_output_write_xdmf: src/xdmf_record.c, xdmf.c). Run it with tests/fuzz/run.sh [SECONDS]
 * record.
 *
 * What is fuzzed: not HDF5's own parser of the file's bytes. HDF5 is not hardened against a
 * hostile file (crafted files overflow buffers in its own decoders: CVE-2019-8396, HDFGroup/hdf5
 * issue 2209; CVE-2025-2915, issue 5380; many alike), and a harness that flipped bits in an .h5
 * file would spend its time there, not in this project's code. Instead,
 * each input describes a record that the HDF5 library writes (so the file is well formed) and
 * that differs from a nominal one by a list of edits: a dataset or attribute missing, or a group
 * in its place, another rank, other dimensions (0, one more, one fewer, any up to 255), another
 * type (float, integers, strings fixed or variable, a compound), NaN, infinities or any other
 * value at any place, rows of /summary/hinges whose joints, sides and labels are anything,
 * members of a compound missing or of another type, a status that is not "completed". So the
 * project's own reading logic meets every shape, type and value a record can hold. An empty
 * input is the nominal record (a 5-voussoir arch, 4 rows); an input starting with a byte whose
 * remainder by 4 is 3 is a sweep's summary table instead. A record whose extents claim more
 * than 65536 values per dataset is not made (exhausting memory by claiming a huge extent is
 * not what this target looks for).
 *
 * Checks besides crashes and sanitizer reports:
 *  - vs_plot_command ends with 0, 1 or 2; the plots.json it writes is JSON (RFC 8259 grammar;
 *    bytes >= 0x80 are taken as they are);
 *  - vs_output_write_xdmf succeeds or says why; a sidecar it writes is well-formed markup
 *    (tags nested and closed, attributes quoted, no raw '<' or '&'), its times strictly
 *    increase, and every slab it names, "FILE:/path|start:stride:count:dims", lies within the
 *    dataset of that path, whose dimensions are those it states.
 * Seams: the pictures are not rasterised (vs_plot_emit is wrapped: ld --wrap), everything before
 * that (the arguments' checks, the frame) is the real code; vs_output_opts_default (record.c,
 * the writer) and the model's functions that imperfections.c calls (vs_imperfections_apply,
 * which the readers do not use) are stubs. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <hdf5.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FUZZ_NAME "fuzz_record"
#include "fuzz.h"

#include "plot_cmd.h"
#include "plot_draw.h"
#include "plugin.h"
#include "voussoir/case.h"
#include "voussoir/model.h"
#include "voussoir/output.h"
#include "voussoir/plot.h"

/* --- seams --- */

vs_status __wrap_vs_plot_emit(const char *path, vs_plot_format fmt, int w, int h,
                              vs_plot_draw_fn draw, const void *data, vs_error *err) {
  (void)fmt, (void)draw, (void)data, (void)err;
  CHECK(path != NULL && w > 0 && h > 0);
  return VS_OK;
}

void vs_output_opts_default(vs_output_opts *o) {
  memset(o, 0, sizeof *o);
  o->xdmf_max_grids = 2000;
}

/* The model, which imperfections.c also applies the draws to (not what the readers do). */
const vs_geometry *vs_model_geometry(const vs_model *m) {
  (void)m;
  abort();
}
const vs_joint_law *vs_model_joint_law(const vs_model *m, int k) {
  (void)m, (void)k;
  abort();
}
vs_status vs_model_set_joint_law(vs_model *m, int k, const vs_joint_law *law, vs_error *err) {
  (void)m, (void)k, (void)law, (void)err;
  abort();
}
void vs_model_set_support_offset(vs_model *m, const double offset[2]) {
  (void)m, (void)offset;
  abort();
}

/* --- the input, read as a stream (0 once it is used up) --- */

typedef struct {
  const uint8_t *p;
  size_t n;
} input;

static unsigned in_u8(input *in) {
  if (in->n == 0) return 0;
  in->n--;
  return *in->p++;
}

static uint32_t in_u32(input *in) {
  uint32_t v = 0;
  for (int i = 0; i < 4; i++) v |= (uint32_t)in_u8(in) << (8 * i);
  return v;
}

static double in_f64(input *in) {
  uint64_t b = 0;
  for (int i = 0; i < 8; i++) b |= (uint64_t)in_u8(in) << (8 * i);
  double d;
  memcpy(&d, &b, sizeof d);
  return d;
}

/* A value worth trying: special ones, small integers, or any 64 bits. */
static double in_value(input *in) {
  static const double special[] = {0.0, -0.0, 1.0, -1.0, 0.5, 2.0, 1e-3, 1e300, -1e300, 1e-310};
  const unsigned k = in_u8(in);
  if (k < 10) return special[k];
  if (k < 12) return k == 10 ? NAN : -NAN;
  if (k < 14) return k == 12 ? INFINITY : -INFINITY;
  if (k < 128) return (double)k - 70.0; /* small integers, negative ones too */
  return in_f64(in);
}

/* --- the record described: datasets with their shapes, types and values --- */

/* The types a value is written as: T_VLSTR is UTF-8, as the record's writer makes them (HDF5
 * does not convert between the character sets: T_VLASCII does not read as T_VLSTR). */
enum { T_F64, T_F32, T_I8, T_I32, T_I64, T_U8, T_STR, T_VLSTR, T_VLASCII, T_CMPD, T_COUNT };
enum { MAX_VALUES = 1 << 16, MAX_DIM = 255 };

typedef struct {
  const char *path;
  int type, rank, absent, group, null_space;
  hsize_t dims[6];
  double *v; /* values as doubles (converted when written); count(dims) of them */
  size_t n;
} dset;

/* The nominal record's dimensions. */
typedef struct {
  int nb, nj, rows, np; /* blocks, joints, rows, points per block outline */
} shape;

/* The datasets the readers read, with their nominal type, shape ('R' rows, 'B' blocks, 'J'
 * joints, 'P' outline points, 'Q' all blocks' points, 'K' 2 joints, a digit: that many) and
 * values (see nominal). */
static const struct {
  const char *path;
  int type;
  const char *dims;
  char values;
} DSETS[] = {
    {"/observables/delta/value", T_F64, "R", 'd'},
    {"/observables/delta/time", T_F64, "R", 't'},
    {"/observables/block_position/value", T_F64, "RB3", '0'},
    {"/observables/block_speed/value", T_F64, "RB", '0'},
    {"/observables/joint_points/value", T_F32, "RK2", '0'},
    {"/observables/joint_N/value", T_F64, "RJ", '0'},
    {"/observables/joint_T/value", T_F64, "RJ", '0'},
    {"/observables/joint_M/value", T_F64, "RJ", '0'},
    {"/observables/joint_gap_i/value", T_F64, "RJ", '0'},
    {"/observables/joint_gap_e/value", T_F64, "RJ", '0'},
    {"/observables/joint_hinge/value", T_I8, "RJ", 'h'},
    {"/observables/reactions/value", T_F64, "R6", '0'},
    {"/observables/support_displacement/value", T_F64, "R2", '0'},
    {"/observables/block_points/value", T_F32, "RQ2", '0'}, /* an earlier layout's: absent */
    {"/geometry/block_connectivity", T_I32, "BP", 'i'},
    {"/geometry/block_points", T_F64, "Q2", '0'},
    {"/geometry/block_centroid", T_F64, "B2", '0'},
    {"/geometry/joint_connectivity", T_I32, "J2", 'i'},
    {"/imperfections/voussoir_angle", T_F64, "B", 'a'},
    {"/imperfections/voussoir_thickness", T_F64, "B", 'w'},
    {"/summary/collapse/delta", T_F64, "", 'c'},
    {"/summary/ground/level", T_F64, "", '0'},
    {"/summary/ground/points", T_F64, "22", '0'},
    {"/xdmf/block_points", T_F32, "RQ2", '0'},
    {"/xdmf/block_points_row", T_I64, "R", 'r'},
    {"/xdmf/nan", T_F64, "J", 'n'},
};
enum { N_DSETS = sizeof DSETS / sizeof DSETS[0], D_OLD_POINTS = 13 };

static hsize_t dim_of(char c, const shape *s) {
  switch (c) {
  case 'R': return (hsize_t)s->rows;
  case 'B': return (hsize_t)s->nb;
  case 'J': return (hsize_t)s->nj;
  case 'P': return (hsize_t)s->np;
  case 'Q': return (hsize_t)s->nb * (hsize_t)s->np;
  case 'K': return 2 * (hsize_t)s->nj;
  default: return (hsize_t)(c - '0');
  }
}

static size_t count_of(const dset *d) {
  if (d->null_space) return 0;
  size_t n = 1;
  for (int k = 0; k < d->rank; k++) n *= (size_t)d->dims[k];
  return n;
}

/* The nominal value of element i, in row `row`, of a dataset whose values are of kind `values`
 * (DSETS), for an arch of 125 degrees: the support displacement (m) and the time (s) growing with
 * the row, element numbers, the voussoirs' angle (rad) and thickness (m), the collapse's
 * displacement, hinges (A at joint 1 on the intrados from row 1, B at the last joint on the
 * extrados from row 2), row numbers, NaN, or 0. */
static double nominal(char values, size_t i, size_t row, const shape *s) {
  const size_t j = i % (size_t)s->nj;
  switch (values) {
  case 'd': return 1e-3 * (double)row;
  case 't': return 25.0 * (double)row;
  case 'i': return (double)i;
  case 'a': return s->nb > 0 ? 125.0 * 0.017453292519943295 / s->nb : 0.0;
  case 'w': return 0.024;
  case 'c': return 2e-3;
  case 'h': return j == 0 && row >= 1 ? 1.0 : j == (size_t)s->nj - 1 && row >= 2 ? 2.0 : 0.0;
  case 'r': return (double)row;
  case 'n': return NAN;
  default: return 0.0;
  }
}

static int dset_alloc(dset *d) {
  free(d->v);
  d->n = count_of(d);
  d->v = calloc(d->n > 0 ? d->n : 1, sizeof *d->v);
  return d->v != NULL ? 0 : -1;
}

/* --- compound tables: /summary/hinges, /summary/limit_points, a sweep's /summary --- */

enum { MAX_ROWS = 12 };
enum { H_LABEL, H_SIDE, H_FIRST, H_LAST, H_ONSET_FIRST, H_ONSET_LAST, H_ORDER, H_OPEN, H_FALL,
       H_DELTA, H_FIELDS };
static const char *const H_NAMES[H_FIELDS] = {"label", "side", "first", "last", "onset_first",
                                              "onset_last", "order", "open", "during_fall",
                                              "delta_onset"};
enum { L_DELTA, L_SETTLED, L_FIELDS };
static const char *const L_NAMES[L_FIELDS] = {"delta", "delta_settled"};
enum { S_KN, S_ALPHA, S_DZ, S_DX, S_STATUS, S_MODE, S_FIELDS };
static const char *const S_NAMES[S_FIELDS] = {"joints.kn_N_mm3", "support.alpha_deg",
                                              "dz_over_L_pct", "dx_over_L_pct", "status", "mode"};

/* A compound table: rows x fields values (doubles; chars and strings by code), each field with
 * its type (T_COUNT: left out), and the dataset's rank (1, or 2 with a second dimension). */
typedef struct {
  int absent, rows, nf, rank, dim2;
  int type[H_FIELDS];
  double v[MAX_ROWS][H_FIELDS];
} table;

/* The strings a string field may hold, by code (value % 8). */
static const char *const STRINGS[8] = {"collapse", "I", "II", "III", "", "max_displacement",
                                       "failed: x", "A\"\\\x01\x7f\xff"};

typedef struct {
  int sweep;       /* a sweep's summary table rather than a run's record */
  shape s;
  dset d[N_DSETS];
  table hinges, limits, summary;
  int status;      /* the root attribute: 0 "completed", 1 "running", 2 absent, 3 an integer,
                      4 a fixed-length string "completed" */
  int no_params;   /* /parameters: 0 a group, 1 absent, 2 a dataset */
  int nk;          /* the case's keys */
  double *key;     /* their values */
  int *key_type;   /* T_F64, T_I64, T_STR or T_COUNT (absent) */
  int max_grids;
} record;

static void record_free(record *r) {
  for (int i = 0; i < N_DSETS; i++) free(r->d[i].v);
  free(r->key);
  free(r->key_type);
}

static int record_nominal(record *r, input *in) {
  memset(r, 0, sizeof *r);
  const unsigned kind = in_u8(in), nb = in_u8(in), rows = in_u8(in), np = in_u8(in);
  r->sweep = kind % 4 == 3;
  r->s.nb = nb == 0 ? 5 : (int)(nb % 16);
  r->s.nj = r->s.nb + 1;
  r->s.rows = rows == 0 ? 4 : (int)(rows % 40);
  r->s.np = np == 0 ? 8 : (int)(np % 12);
  r->max_grids = (int)(kind / 4) % 8 + 2;
  for (int i = 0; i < N_DSETS; i++) {
    dset *d = &r->d[i];
    d->path = DSETS[i].path;
    d->type = DSETS[i].type;
    d->rank = (int)strlen(DSETS[i].dims);
    d->absent = i == D_OLD_POINTS;
    for (int k = 0; k < d->rank; k++) d->dims[k] = dim_of(DSETS[i].dims[k], &r->s);
    if (dset_alloc(d) != 0) return -1;
    const size_t width = d->rank > 0 && d->dims[0] > 0 ? d->n / (size_t)d->dims[0] : 1;
    for (size_t e = 0; e < d->n; e++)
      d->v[e] = nominal(DSETS[i].values, e, width > 0 ? e / width : 0, &r->s);
  }
  /* hinges A at the left springing (intrados) and B at the right (extrados) */
  table *h = &r->hinges;
  h->rows = 2, h->nf = H_FIELDS, h->rank = 1;
  const double hv[2][H_FIELDS] = {{'A', 'I', 1, 1, 1, 1, 1, 1, 0, 1e-3},
                                  {'B', 'E', r->s.nj, r->s.nj, r->s.nj, r->s.nj, 2, 1, 0, 2e-3}};
  for (int f = 0; f < H_FIELDS; f++) {
    h->type[f] = f <= H_SIDE ? T_STR : f == H_DELTA ? T_F64 : f >= H_OPEN ? T_I8 : T_I32;
    h->v[0][f] = hv[0][f], h->v[1][f] = hv[1][f];
  }
  table *l = &r->limits;
  l->rows = 1, l->nf = L_FIELDS, l->rank = 1;
  l->type[L_DELTA] = l->type[L_SETTLED] = T_F64;
  l->v[0][L_DELTA] = 1.5e-3, l->v[0][L_SETTLED] = NAN;
  table *t = &r->summary; /* three directions of one k_n, two collapses */
  t->rows = 3, t->nf = S_FIELDS, t->rank = 1;
  const double sv[3][S_FIELDS] = {
      {NAN, 0, 20, 0, 0, 1}, {NAN, 30, 15, 8, 0, 2}, {NAN, 60, NAN, NAN, 5, 4}};
  for (int f = 0; f < S_FIELDS; f++) {
    t->type[f] = f >= S_STATUS ? T_VLSTR : T_F64;
    for (int i = 0; i < 3; i++) t->v[i][f] = sv[i][f];
  }
  r->nk = vs_case_key_count();
  r->key = calloc((size_t)r->nk, sizeof *r->key);
  r->key_type = calloc((size_t)r->nk, sizeof *r->key_type);
  if (r->key == NULL || r->key_type == NULL) return -1;
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = r->s.nb;
  for (int k = 0; k < r->nk; k++) {
    int is_int;
    vs_case_key(&c, k, NULL, NULL, NULL, &is_int, &r->key[k]);
    r->key_type[k] = is_int ? T_I64 : T_F64;
  }
  return 0;
}

/* --- the edits --- */

static void edit_dset(dset *d, input *in) {
  const unsigned op = in_u8(in) % 9;
  switch (op) {
  case 0: d->absent = !d->absent; return;
  case 1: d->group = 1; return;
  case 2: d->null_space = 1; return;
  case 3: { /* another rank (0 to 6), its dimensions small */
    d->rank = (int)(in_u8(in) % 7);
    for (int k = 0; k < d->rank; k++) d->dims[k] = in_u8(in) % 8;
    break;
  }
  case 4: { /* one dimension: 0, one more, one fewer or anything up to MAX_DIM */
    if (d->rank == 0) return;
    const int k = (int)(in_u8(in) % (unsigned)d->rank);
    const unsigned how = in_u8(in);
    d->dims[k] = how == 0 ? 0 : how == 1 ? d->dims[k] + 1 : how == 2 && d->dims[k] > 0
                                                            ? d->dims[k] - 1
                                                            : how % (MAX_DIM + 1);
    break;
  }
  case 5: d->type = (int)(in_u8(in) % T_COUNT); return;
  case 6: { /* one value */
    if (d->n == 0) return;
    const size_t i = (size_t)in_u32(in) % d->n;
    d->v[i] = in_value(in);
    return;
  }
  case 7: { /* every value */
    const double v = in_value(in);
    for (size_t i = 0; i < d->n; i++) d->v[i] = v;
    return;
  }
  default: { /* a run of values from a start, each its own */
    if (d->n == 0) return;
    size_t i = (size_t)in_u32(in) % d->n;
    for (unsigned m = in_u8(in) % 16; m > 0 && i < d->n; m--) d->v[i++] = in_value(in);
    return;
  }
  }
  size_t n = 1; /* a new shape: values kept where they fit, the rest 0 */
  for (int k = 0; k < d->rank; k++) n *= (size_t)d->dims[k];
  if (n > MAX_VALUES) {
    d->rank = 1, d->dims[0] = 1; /* too big for this target: see the header */
  }
  double *old = d->v;
  const size_t old_n = d->n;
  d->v = NULL;
  if (dset_alloc(d) != 0) abort();
  memcpy(d->v, old, (old_n < d->n ? old_n : d->n) * sizeof *old);
  free(old);
}

static void edit_table(table *t, input *in) {
  const unsigned op = in_u8(in) % 6;
  switch (op) {
  case 0: t->absent = !t->absent; break;
  case 1: t->rows = (int)(in_u8(in) % (MAX_ROWS + 1)); break;
  case 2: t->type[in_u8(in) % (unsigned)t->nf] = (int)(in_u8(in) % (T_COUNT + 1)); break;
  case 3: t->rank = 2, t->dim2 = (int)(in_u8(in) % 4); break;
  case 4: { /* a field's value: an integer (a joint, a character) or any */
    const int row = (int)(in_u8(in) % MAX_ROWS), f = (int)(in_u8(in) % (unsigned)t->nf);
    t->v[row][f] = in_u8(in) % 2 ? (double)(int32_t)in_u32(in) : in_value(in);
    break;
  }
  default: { /* a field's value, small */
    const int row = (int)(in_u8(in) % MAX_ROWS), f = (int)(in_u8(in) % (unsigned)t->nf);
    t->v[row][f] = (double)in_u8(in) - 16.0;
    break;
  }
  }
}

static void edit(record *r, input *in) {
  const unsigned which = in_u8(in) % (N_DSETS + 6);
  if (which < N_DSETS) edit_dset(&r->d[which], in);
  else if (which == N_DSETS) edit_table(&r->hinges, in);
  else if (which == N_DSETS + 1) edit_table(&r->limits, in);
  else if (which == N_DSETS + 2) edit_table(&r->summary, in);
  else if (which == N_DSETS + 3) r->status = (int)(in_u8(in) % 5);
  else if (which == N_DSETS + 4) r->no_params = (int)(in_u8(in) % 3);
  else { /* a key of /parameters: absent, another type, another value */
    const int k = (int)(in_u8(in) % (unsigned)r->nk);
    const unsigned how = in_u8(in) % 4;
    if (how == 0) r->key_type[k] = T_COUNT;
    else if (how == 1) r->key_type[k] = (int)(in_u8(in) % T_COUNT);
    else r->key[k] = in_value(in);
  }
}

/* --- writing it with HDF5 --- */

static hid_t file_type(int type) {
  switch (type) {
  case T_F64: return H5Tcopy(H5T_IEEE_F64LE);
  case T_F32: return H5Tcopy(H5T_IEEE_F32LE);
  case T_I8: return H5Tcopy(H5T_STD_I8LE);
  case T_I32: return H5Tcopy(H5T_STD_I32LE);
  case T_I64: return H5Tcopy(H5T_STD_I64LE);
  case T_U8: return H5Tcopy(H5T_STD_U8LE);
  case T_STR: { /* fixed length, NUL-padded: may hold no terminator */
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, 1);
    H5Tset_strpad(t, H5T_STR_NULLPAD);
    return t;
  }
  case T_VLSTR:
  case T_VLASCII: {
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, H5T_VARIABLE);
    H5Tset_cset(t, type == T_VLSTR ? H5T_CSET_UTF8 : H5T_CSET_ASCII);
    return t;
  }
  default: { /* a compound of one double */
    hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(double));
    H5Tinsert(t, "x", 0, H5T_NATIVE_DOUBLE);
    return t;
  }
  }
}

/* A character from a value: its integer part modulo 256 (0 for NaN, infinities). */
static unsigned char byte_of(double v) {
  return isfinite(v) ? (unsigned char)(int)fmod(fabs(v), 256.0) : 0;
}

/* Write n values v as type `type` into dataset or attribute id (write_fn: H5Dwrite/H5Awrite). */
static void write_values(hid_t id, int is_attr, int type, const double *v, size_t n) {
  if (n == 0) return;
  hid_t mt;
  void *buf;
  if (type == T_STR) {
    char *c = malloc(n);
    for (size_t i = 0; c != NULL && i < n; i++) c[i] = (char)byte_of(v[i]);
    buf = c, mt = file_type(T_STR);
  } else if (type == T_VLSTR || type == T_VLASCII) {
    const char **s = malloc(n * sizeof *s);
    for (size_t i = 0; s != NULL && i < n; i++)
      s[i] = STRINGS[isfinite(v[i]) ? (unsigned)fabs(fmod(v[i], 8.0)) : 7];
    buf = (void *)s, mt = file_type(type);
  } else {
    buf = (void *)v, mt = type == T_CMPD ? file_type(T_CMPD) : H5Tcopy(H5T_NATIVE_DOUBLE);
  }
  if (buf != NULL) {
    if (is_attr) H5Awrite(id, mt, buf);
    else H5Dwrite(id, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  }
  if (buf != (void *)v) free(buf);
  H5Tclose(mt);
}

/* The groups above path (each created if missing); path's last component is left. */
static void make_parents(hid_t f, const char *path) {
  char buf[256];
  snprintf(buf, sizeof buf, "%s", path);
  for (char *p = strchr(buf + 1, '/'); p != NULL; p = strchr(p + 1, '/')) {
    *p = '\0';
    if (H5Lexists(f, buf, H5P_DEFAULT) <= 0) {
      hid_t g = H5Gcreate2(f, buf, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
      if (g >= 0) H5Gclose(g);
    }
    *p = '/';
  }
}

static void write_dset(hid_t f, const dset *d) {
  if (d->absent) return;
  make_parents(f, d->path);
  if (H5Lexists(f, d->path, H5P_DEFAULT) > 0) return; /* a group of that name already */
  if (d->group) {
    hid_t g = H5Gcreate2(f, d->path, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g >= 0) H5Gclose(g);
    return;
  }
  hid_t sp = d->null_space ? H5Screate(H5S_NULL)
             : d->rank == 0 ? H5Screate(H5S_SCALAR)
                            : H5Screate_simple(d->rank, d->dims, NULL);
  hid_t t = file_type(d->type);
  hid_t ds = H5Dcreate2(f, d->path, t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds >= 0) {
    write_values(ds, 0, d->type, d->v, d->n);
    H5Dclose(ds);
  }
  H5Tclose(t);
  H5Sclose(sp);
}

/* A compound table at path: its fields named names, of the table's types. */
static void write_table(hid_t f, const char *path, const table *t, const char *const *names) {
  if (t->absent) return;
  make_parents(f, path);
  size_t off[H_FIELDS], size = 0;
  hid_t ft[H_FIELDS];
  for (int k = 0; k < t->nf; k++) { /* file and memory layout alike: fields one after another */
    ft[k] = t->type[k] < T_COUNT ? file_type(t->type[k]) : H5I_INVALID_HID;
    off[k] = size;
    if (ft[k] >= 0) size += H5Tget_size(ft[k]);
  }
  hid_t ct = H5Tcreate(H5T_COMPOUND, size > 0 ? size : 1);
  for (int k = 0; k < t->nf; k++)
    if (ft[k] >= 0) H5Tinsert(ct, names[k], off[k], ft[k]);
  const hsize_t dims[2] = {(hsize_t)t->rows, (hsize_t)t->dim2};
  hid_t sp = H5Screate_simple(t->rank, dims, NULL);
  const size_t n = (size_t)t->rows * (t->rank == 2 ? (size_t)t->dim2 : 1);
  unsigned char *buf = calloc(n > 0 ? n : 1, size > 0 ? size : 1);
  for (size_t i = 0; buf != NULL && i < n; i++)
    for (int k = 0; k < t->nf; k++) {
      if (ft[k] < 0) continue;
      const double v = t->v[i % (size_t)(t->rows > 0 ? t->rows : 1)][k];
      unsigned char *at = buf + i * size + off[k];
      if (t->type[k] == T_STR) {
        *at = byte_of(v);
      } else if (t->type[k] == T_VLSTR || t->type[k] == T_VLASCII) {
        const char *s = STRINGS[isfinite(v) ? (unsigned)fabs(fmod(v, 8.0)) : 7];
        memcpy(at, &s, sizeof s);
      } else {
        hid_t src = H5Tcopy(H5T_NATIVE_DOUBLE); /* v converted to the field's type */
        unsigned char tmp[16] = {0};
        memcpy(tmp, &v, sizeof v);
        H5Tconvert(src, ft[k], 1, tmp, NULL, H5P_DEFAULT);
        memcpy(at, tmp, H5Tget_size(ft[k]));
        H5Tclose(src);
      }
    }
  hid_t ds = H5Dcreate2(f, path, ct, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (ds >= 0 && buf != NULL && n > 0) H5Dwrite(ds, ct, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf);
  if (ds >= 0) H5Dclose(ds);
  free(buf);
  H5Sclose(sp);
  H5Tclose(ct);
  for (int k = 0; k < t->nf; k++)
    if (ft[k] >= 0) H5Tclose(ft[k]);
}

static void write_attr(hid_t loc, const char *name, int type, double v) {
  hid_t t = file_type(type), sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    write_values(a, 1, type, &v, 1);
    H5Aclose(a);
  }
  H5Sclose(sp);
  H5Tclose(t);
}

static void write_parameters(hid_t f, const record *r) {
  if (r->no_params == 1) return;
  if (r->no_params == 2) {
    dset d = {.path = "/parameters", .type = T_F64, .rank = 0, .v = (double[]){1.0}, .n = 1};
    write_dset(f, &d);
    return;
  }
  hid_t p = H5Gcreate2(f, "/parameters", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  vs_case names; /* for the keys' names */
  vs_case_defaults(&names);
  for (int k = 0; p >= 0 && k < r->nk; k++) {
    const char *sec, *key;
    vs_case_key(&names, k, &sec, &key, NULL, NULL, NULL);
    if (r->key_type[k] == T_COUNT) continue;
    char path[96];
    snprintf(path, sizeof path, "/parameters/%s", sec);
    hid_t g = H5Lexists(f, path, H5P_DEFAULT) > 0
                  ? H5Gopen2(f, path, H5P_DEFAULT)
                  : H5Gcreate2(f, path, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g < 0) continue;
    write_attr(g, key, r->key_type[k], r->key[k]);
    H5Gclose(g);
  }
  if (p >= 0) H5Gclose(p);
}

static void write_status(hid_t f, int status) {
  if (status == 2) return;
  if (status == 3) {
    write_attr(f, "status", T_I64, 1.0);
    return;
  }
  const char *v = status == 1 ? "running" : "completed";
  hid_t t = H5Tcopy(H5T_C_S1), sp = H5Screate(H5S_SCALAR);
  H5Tset_size(t, status == 4 ? strlen(v) : H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  hid_t a = H5Acreate2(f, "status", t, sp, H5P_DEFAULT, H5P_DEFAULT);
  if (a >= 0) {
    H5Awrite(a, t, status == 4 ? (const void *)v : (const void *)&v);
    H5Aclose(a);
  }
  H5Sclose(sp);
  H5Tclose(t);
}

static void write_record(const record *r, const char *path) {
  hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  CHECK(f >= 0);
  if (r->sweep) {
    write_table(f, "/summary", &r->summary, S_NAMES);
  } else {
    write_status(f, r->status);
    write_parameters(f, r);
    for (int i = 0; i < N_DSETS; i++) write_dset(f, &r->d[i]);
    write_table(f, "/summary/hinges", &r->hinges, H_NAMES);
    write_table(f, "/summary/limit_points", &r->limits, L_NAMES);
  }
  CHECK(H5Fclose(f) >= 0);
}

/* --- plots.json: JSON by RFC 8259's grammar (bytes >= 0x80 taken as they are) --- */

typedef struct {
  const char *p, *end;
  int depth;
} json;

static void js_ws(json *j) {
  while (j->p < j->end && (*j->p == ' ' || *j->p == '\t' || *j->p == '\n' || *j->p == '\r'))
    j->p++;
}

static int js_peek(const json *j, char c) { return j->p < j->end && *j->p == c; }

static int js_digits(json *j) {
  const char *s = j->p;
  while (j->p < j->end && *j->p >= '0' && *j->p <= '9') j->p++;
  return j->p > s;
}

static int js_number(json *j) {
  if (js_peek(j, '-')) j->p++;
  if (js_peek(j, '0')) j->p++;
  else if (!(j->p < j->end && *j->p >= '1' && *j->p <= '9') || !js_digits(j)) return 0;
  if (js_peek(j, '.') && (j->p++, !js_digits(j))) return 0;
  if (js_peek(j, 'e') || js_peek(j, 'E')) {
    j->p++;
    if (js_peek(j, '+') || js_peek(j, '-')) j->p++;
    if (!js_digits(j)) return 0;
  }
  return 1;
}

static int js_string(json *j) {
  if (!js_peek(j, '"')) return 0;
  for (j->p++; j->p < j->end;) {
    const unsigned char c = (unsigned char)*j->p++;
    if (c == '"') return 1;
    if (c < 0x20) return 0;
    if (c != '\\') continue;
    if (j->p >= j->end) return 0;
    const char e = *j->p++;
    if (e == 'u') {
      for (int k = 0; k < 4; k++, j->p++)
        if (j->p >= j->end || strchr("0123456789abcdefABCDEF", *j->p) == NULL || *j->p == '\0')
          return 0;
    } else if (e == '\0' || strchr("\"\\/bfnrt", e) == NULL) {
      return 0;
    }
  }
  return 0;
}

static int js_value(json *j);

/* The members or elements of an object (close '}') or array (close ']') after its opening. */
static int js_list(json *j, char close) {
  js_ws(j);
  if (js_peek(j, close)) return j->p++, 1;
  for (;;) {
    js_ws(j);
    if (close == '}') {
      if (!js_string(j)) return 0;
      js_ws(j);
      if (!js_peek(j, ':')) return 0;
      j->p++;
    }
    if (!js_value(j)) return 0;
    js_ws(j);
    if (js_peek(j, close)) return j->p++, 1;
    if (!js_peek(j, ',')) return 0;
    j->p++;
  }
}

static int js_value(json *j) {
  js_ws(j);
  if (j->p >= j->end || ++j->depth > 64) return 0;
  int ok;
  const char c = *j->p;
  if (c == '{' || c == '[') {
    j->p++;
    ok = js_list(j, c == '{' ? '}' : ']');
  } else if (c == '"') {
    ok = js_string(j);
  } else if (c == 't' || c == 'f' || c == 'n') {
    const char *w = c == 't' ? "true" : c == 'f' ? "false" : "null";
    const size_t n = strlen(w);
    ok = (size_t)(j->end - j->p) >= n && memcmp(j->p, w, n) == 0;
    j->p += ok ? n : 0;
  } else {
    ok = js_number(j);
  }
  j->depth--;
  return ok;
}

static int is_json(const char *text, size_t n) {
  json j = {text, text + n, 0};
  if (!js_value(&j)) return 0;
  js_ws(&j);
  return j.p == j.end;
}

/* --- the sidecar: well-formed markup whose HDF5 references lie within the record --- */

typedef struct {
  const char *p, *end;
  hid_t file;          /* the record, to check the references against */
  double t_last;       /* the last Time Value */
  char dims[64], format[16]; /* the open DataItem's Dimensions and Format */
  int in_item;
} xml;

/* Text without '<' and with '&' only as one of XML's five entities. */
static int xml_text_ok(const char *s, const char *end) {
  static const char *const ent[] = {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"};
  for (; s < end; s++) {
    if (*s == '<' || (unsigned char)*s < 0x09) return 0;
    if (*s != '&') continue;
    int known = 0;
    for (int k = 0; k < 5 && !known; k++)
      known = (size_t)(end - s) >= strlen(ent[k]) && memcmp(s, ent[k], strlen(ent[k])) == 0;
    if (!known) return 0;
  }
  return 1;
}

/* Up to 4 numbers separated by blanks; their count, or -1. */
static int numbers(const char *s, size_t n, unsigned long long *v) {
  char buf[128];
  if (n >= sizeof buf) return -1;
  memcpy(buf, s, n);
  buf[n] = '\0';
  int k = 0;
  for (char *p = buf, *e; *p != '\0'; p = e) {
    while (*p == ' ') p++;
    if (*p == '\0') break;
    if (k == 4 || *p < '0' || *p > '9') return -1;
    v[k++] = strtoull(p, &e, 10);
    if (*e != ' ' && *e != '\0') return -1;
  }
  return k;
}

/* A DataItem's HDF reference "FILE:/path" or "FILE:/path|start:stride:count:dims" (text of
 * n bytes): the dataset exists, and a slab lies within it and states its dimensions. */
static int reference_ok(const xml *x, const char *text, size_t n) {
  const char *colon = memchr(text, ':', n), *bar = memchr(text, '|', n);
  if (colon == NULL) return 0;
  char path[256];
  const size_t pl = (size_t)((bar != NULL ? bar : text + n) - (colon + 1));
  if (pl == 0 || pl >= sizeof path) return 0;
  memcpy(path, colon + 1, pl);
  path[pl] = '\0';
  hid_t d = H5Lexists(x->file, path, H5P_DEFAULT) > 0 ? H5Dopen2(x->file, path, H5P_DEFAULT)
                                                        : H5I_INVALID_HID;
  if (d < 0) return 0;
  hid_t sp = H5Dget_space(d);
  hsize_t dims[8] = {0};
  const int rank = H5Sget_simple_extent_ndims(sp);
  if (rank > 0 && rank <= 4) H5Sget_simple_extent_dims(sp, dims, NULL);
  H5Sclose(sp);
  H5Dclose(d);
  if (rank < 1 || rank > 4) return 0;
  unsigned long long item[4], part[4][4];
  const int ni = numbers(x->dims, strlen(x->dims), item);
  if (bar == NULL) { /* the whole dataset: the item's dimensions are its own */
    for (int k = 0; k < ni; k++)
      if (ni != rank || item[k] != dims[k]) return 0;
    return ni == rank;
  }
  const char *p = bar + 1;
  for (int f = 0; f < 4; f++) { /* start, stride, count, dims */
    const char *e = f < 3 ? memchr(p, ':', (size_t)(text + n - p)) : text + n;
    if (e == NULL || numbers(p, (size_t)(e - p), part[f]) != rank) return 0;
    p = e + 1;
  }
  unsigned long long cells = 1, want = 1;
  for (int k = 0; k < rank; k++) {
    if (part[3][k] != dims[k] || part[1][k] < 1) return 0;
    if (part[2][k] > 0 && part[0][k] + (part[2][k] - 1) * part[1][k] >= dims[k]) return 0;
    cells *= part[2][k];
  }
  for (int k = 0; k < ni; k++) want *= item[k];
  return ni > 0 && want == cells; /* the item holds what the slab selects */
}

/* The value of attribute name in the tag text [s, e), into out; 0 if absent. */
static int attr_of(const char *s, const char *e, const char *name, char *out, size_t size) {
  const size_t n = strlen(name);
  for (const char *p = s; p + n + 2 < e; p++)
    if (p[-1] == ' ' && memcmp(p, name, n) == 0 && p[n] == '=' && p[n + 1] == '"') {
      const char *v = p + n + 2, *q = memchr(v, '"', (size_t)(e - v));
      if (q == NULL || (size_t)(q - v) >= size) return 0;
      memcpy(out, v, (size_t)(q - v));
      out[q - v] = '\0';
      return 1;
    }
  return 0;
}

/* One tag [s, e) (between '<' and '>'): its attributes quoted and their values text. */
static int tag_ok(xml *x, const char *s, const char *e, int *closing, int *empty,
                  char *name, size_t size) {
  *closing = *s == '/';
  *empty = e > s && e[-1] == '/';
  const char *n = s + *closing, *ne = n;
  while (ne < e && *ne != ' ' && *ne != '/' && *ne != '\n') ne++;
  if (ne == n || (size_t)(ne - n) >= size) return 0;
  memcpy(name, n, (size_t)(ne - n));
  name[ne - n] = '\0';
  for (const char *p = ne; p < e - *empty;) { /* name="value" pairs */
    while (p < e && (*p == ' ' || *p == '\n')) p++;
    if (p >= e - *empty) break;
    const char *eq = memchr(p, '=', (size_t)(e - p));
    if (eq == NULL || eq + 1 >= e || eq[1] != '"') return 0;
    const char *q = memchr(eq + 2, '"', (size_t)(e - eq - 2));
    if (q == NULL || !xml_text_ok(eq + 2, q)) return 0;
    p = q + 1;
  }
  if (strcmp(name, "Time") == 0) {
    char v[64];
    if (!attr_of(s, e, "Value", v, sizeof v)) return 0;
    const double t = strtod(v, NULL);
    if (!(t > x->t_last) || !isfinite(t)) return 0;
    x->t_last = t;
  }
  if (strcmp(name, "DataItem") == 0 && !*closing) {
    x->in_item = 1;
    x->dims[0] = x->format[0] = '\0';
    attr_of(s, e, "Dimensions", x->dims, sizeof x->dims);
    attr_of(s, e, "Format", x->format, sizeof x->format);
  }
  return 1;
}

/* The sidecar's text: elements nested and closed, one root, references within the record. */
static const char *xmf_problem(xml *x) {
  char stack[64][32];
  int depth = 0, roots = 0;
  const char *p = x->p;
  while (p < x->end) {
    const char *lt = memchr(p, '<', (size_t)(x->end - p));
    const char *text_end = lt != NULL ? lt : x->end;
    if (!xml_text_ok(p, text_end)) return "text with a raw '<' or '&'";
    if (x->in_item && depth > 0 && text_end > p && strcmp(x->format, "HDF") == 0 &&
        !reference_ok(x, p, (size_t)(text_end - p)))
      return "an HDF reference outside the record or of other dimensions";
    if (lt == NULL) break;
    if (strncmp(lt, "<?", 2) == 0 || strncmp(lt, "<!DOCTYPE", 9) == 0) {
      const char *gt = memchr(lt, '>', (size_t)(x->end - lt));
      if (gt == NULL) return "an unclosed declaration";
      p = gt + 1;
      continue;
    }
    if (strncmp(lt, "<!--", 4) == 0) {
      const char *c = lt + 4, *close = NULL;
      for (; c + 2 < x->end && close == NULL; c++)
        if (c[0] == '-' && c[1] == '-') close = c;
      if (close == NULL || close[2] != '>') return "a comment holding \"--\" or unclosed";
      p = close + 3;
      continue;
    }
    const char *gt = memchr(lt, '>', (size_t)(x->end - lt));
    if (gt == NULL) return "an unclosed tag";
    char name[32];
    int closing, empty;
    if (!tag_ok(x, lt + 1, gt, &closing, &empty, name, sizeof name))
      return "a tag with an unquoted attribute, a bad value or a time not above the last";
    if (closing) {
      if (depth == 0 || strcmp(stack[depth - 1], name) != 0) return "a tag closed out of order";
      depth--;
      x->in_item = 0;
    } else if (!empty) {
      if (depth == 0 && ++roots > 1) return "more than one root element";
      if (depth == 64) return "nested too deep";
      snprintf(stack[depth++], sizeof stack[0], "%s", name);
    }
    p = gt + 1;
  }
  return depth == 0 && roots == 1 ? NULL : "an element left open, or no root";
}

/* --- the scratch directory and the run --- */

static char g_root[4096], g_h5[4200], g_xmf[4200], g_plots[4200];

static void remove_plots(void) {
  DIR *d = opendir(g_plots);
  if (d == NULL) return;
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d)) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char f[4200 + 256];
    snprintf(f, sizeof f, "%s/%s", g_plots, e->d_name);
    unlink(f);
  }
  closedir(d);
  rmdir(g_plots);
}

static void remove_root(void) {
  remove_plots();
  unlink(g_h5);
  unlink(g_xmf);
  rmdir(g_root);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  fuzz_report_open();
  fuzz_scratch(g_root, sizeof g_root);
  snprintf(g_h5, sizeof g_h5, "%s/run.h5", g_root);
  snprintf(g_xmf, sizeof g_xmf, "%s/run.xmf", g_root);
  snprintf(g_plots, sizeof g_plots, "%s/plots", g_root);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* the edits make HDF5 refuse things: not shown */
  /* HDF5 keeps what it frees for its next file (its metadata cache alone is some 0.5 MB,
   * mapped afresh and zeroed at every open otherwise: most of this target's time) */
  H5set_free_list_limits(-1, -1, -1, -1, -1, -1);
  atexit(remove_root);
  return 0;
}

static void check_plot(void) {
  remove_plots();
  const int rc = vs_plot_command(g_h5, g_plots, "png");
  CHECK(rc >= 0 && rc <= 2);
  char path[4300];
  snprintf(path, sizeof path, "%s/plots.json", g_plots);
  size_t n;
  char *text = fuzz_slurp(path, &n);
  if (text != NULL && !is_json(text, n)) {
    fprintf(FUZZ_REPORT, "fuzz_record: plots.json is not JSON:\n%s\n", text);
    abort();
  }
  free(text);
}

static void check_xdmf(int max_grids) {
  unlink(g_xmf);
  vs_error err;
  vs_error_clear(&err);
  const vs_status st = vs_output_write_xdmf(g_h5, max_grids, &err);
  CHECK(st == VS_OK || (err.status == st && err.msg[0] != '\0'));
  size_t n;
  char *text = fuzz_slurp(g_xmf, &n);
  CHECK((st == VS_OK) == (text != NULL));
  if (text == NULL) return;
  xml x = {text, text + n, H5Fopen(g_h5, H5F_ACC_RDONLY, H5P_DEFAULT), -INFINITY, "", "", 0};
  CHECK(x.file >= 0);
  const char *why = xmf_problem(&x);
  H5Fclose(x.file);
  if (why != NULL) {
    fprintf(FUZZ_REPORT, "fuzz_record: the sidecar is not right: %s\n", why);
    abort();
  }
  free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  input in = {data, size};
  record r;
  CHECK(record_nominal(&r, &in) == 0);
  while (in.n > 0) edit(&r, &in);
  write_record(&r, g_h5);
  check_plot();
  if (!r.sweep) check_xdmf(r.max_grids);
  record_free(&r);
  return 0;
}
