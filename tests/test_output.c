/* Tests of the HDF5 record and its XDMF sidecar (output.h): runs are written and read back with
 * the HDF5 C API, and compared with what is recomputed here from the run and the geometry: the
 * last positions against vs_run_state, delta = rate t, reactions against the arch's weight and
 * against the first joint's forces, hinge flags against the edge openings, outlines against the
 * rigid motion of the arch's sectors, kinetic and gravitational energy from the velocities and
 * positions; units on every floating-point dataset; the events; the summary; the XDMF's tags and
 * the shapes of every dataset it refers to; a run killed by SIGKILL (its file opens and holds
 * the flushed rows, equal to a run recorded in memory); error paths. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, fork, kill */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <hdf5.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include "voussoir/output.h"
#include "voussoir/units.h"
#include "voussoir/version.h"

static char g_dir[64];

static int setup(void **state) {
  (void)state;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_output_XXXXXX");
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

static int teardown(void **state) {
  (void)state;
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
  return system(cmd) == 0 ? 0 : -1;
}

static void path_in(char *buf, size_t size, const char *name) {
  snprintf(buf, size, "%s/%s", g_dir, name);
}

/* ---------------------------------------------------------------------------------------------
 * Writing a run */

typedef struct {
  vs_output *o;
  long samples;
  long interrupt_after; /* call vs_output_interrupt after this many samples (0: never) */
} sink;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  sink *k = user;
  k->samples++;
  int rc = vs_output_sample(k->o, run, s);
  if (k->interrupt_after > 0 && k->samples == k->interrupt_after) vs_output_interrupt(k->o);
  return rc;
}

static int on_event(void *user, const vs_run *run, const vs_run_event *e) {
  sink *k = user;
  return vs_output_event(k->o, run, e);
}

static vs_case small_case(int follow) {
  vs_case c;
  vs_case_defaults(&c);
  c.voussoirs = 11;
  c.follow = follow;
  return c;
}

/* Run c, recording it at path (opts: NULL for the defaults); returns the run (caller destroys),
 * the run status in *st. */
static vs_run *record(const vs_case *c, const char *path, const char *text,
                      const vs_output_opts *opts, long interrupt_after, long *samples,
                      vs_status *st) {
  vs_error err;
  vs_run *run = NULL;
  assert_int_equal(vs_run_create(c, &run, &err), VS_OK);
  sink k = {NULL, 0, interrupt_after};
  if (vs_output_create(path, run, text, opts, &k.o, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_error rerr;
  vs_error_clear(&rerr);
  *st = vs_run_execute(run, on_sample, on_event, &k, &rerr);
  /* after an interruption, the sample that was refused is not a row */
  assert_int_equal(vs_output_rows(k.o),
                   k.samples - (interrupt_after > 0 && k.samples > interrupt_after));
  if (vs_output_finish(k.o, run, *st, &rerr, &err) != VS_OK) fail_msg("%s", err.msg);
  vs_output_destroy(&k.o);
  assert_null(k.o);
  *samples = k.samples;
  return run;
}

/* ---------------------------------------------------------------------------------------------
 * Reading back */

static int rank_of(hid_t f, const char *path, hsize_t dims[3]) {
  dims[0] = dims[1] = dims[2] = 1;
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) fail_msg("dataset %s missing", path);
  hid_t s = H5Dget_space(d);
  int r = H5Sget_simple_extent_ndims(s);
  H5Sget_simple_extent_dims(s, dims, NULL);
  H5Sclose(s);
  H5Dclose(d);
  return r;
}

/* Whole dataset as doubles (malloc'd); *n receives the element count. */
static double *read_all(hid_t f, const char *path, size_t *n) {
  hid_t d = H5Dopen2(f, path, H5P_DEFAULT);
  if (d < 0) fail_msg("dataset %s missing", path);
  hid_t s = H5Dget_space(d);
  hssize_t np = H5Sget_simple_extent_npoints(s);
  double *v = malloc((size_t)(np > 0 ? np : 1) * sizeof *v);
  assert_non_null(v);
  if (np > 0) assert_true(H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  H5Sclose(s);
  H5Dclose(d);
  *n = (size_t)np;
  return v;
}

static double read_scalar(hid_t f, const char *path) {
  size_t n;
  double *v = read_all(f, path, &n);
  assert_int_equal(n, 1);
  double x = v[0];
  free(v);
  return x;
}

/* Attribute name of obj as a string into buf; checks it is a variable-length UTF-8 string. */
static void read_attr_str(hid_t obj, const char *name, char *buf, size_t size) {
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  if (a < 0) fail_msg("attribute %s missing", name);
  hid_t t = H5Aget_type(a);
  assert_int_equal(H5Tget_class(t), H5T_STRING);
  assert_true(H5Tis_variable_str(t) > 0);
  assert_int_equal(H5Tget_cset(t), H5T_CSET_UTF8);
  char *s = NULL;
  hid_t mt = H5Tcopy(t);
  assert_true(H5Aread(a, mt, &s) >= 0);
  snprintf(buf, size, "%s", s != NULL ? s : "");
  hid_t sp = H5Aget_space(a);
  H5Dvlen_reclaim(mt, sp, H5P_DEFAULT, &s);
  H5Sclose(sp);
  H5Tclose(mt);
  H5Tclose(t);
  H5Aclose(a);
}

static long long read_attr_int(hid_t obj, const char *name) {
  long long v = 0;
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT);
  if (a < 0) fail_msg("attribute %s missing", name);
  assert_true(H5Aread(a, H5T_NATIVE_LLONG, &v) >= 0);
  H5Aclose(a);
  return v;
}

/* Every floating-point dataset, and every table with a floating-point field, has a "unit"
 * attribute, a variable-length UTF-8 string; multi-column datasets with "columns" give one unit
 * per column; tables one per field. */
static int has_float(hid_t t) {
  if (H5Tget_class(t) == H5T_FLOAT) return 1;
  if (H5Tget_class(t) != H5T_COMPOUND) return 0;
  for (int i = 0; i < H5Tget_nmembers(t); i++)
    if (H5Tget_member_class(t, (unsigned)i) == H5T_FLOAT) return 1;
  return 0;
}

static int count_fields(const char *s) {
  int n = 1;
  for (; *s; s++) n += *s == ',';
  return n;
}

static herr_t check_unit_cb(hid_t loc, const char *name, const H5O_info_t *info, void *data) {
  int *checked = data;
  if (info->type != H5O_TYPE_DATASET) return 0;
  hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
  hid_t t = H5Dget_type(d);
  if (has_float(t)) {
    if (H5Aexists(d, "unit") <= 0) fail_msg("%s: no unit attribute", name);
    char unit[256];
    read_attr_str(d, "unit", unit, sizeof unit);
    if (H5Tget_class(t) == H5T_COMPOUND) {
      if (count_fields(unit) != H5Tget_nmembers(t)) fail_msg("%s: unit '%s' per field", name, unit);
    } else if (H5Aexists(d, "columns") > 0) {
      char cols[256];
      read_attr_str(d, "columns", cols, sizeof cols);
      hsize_t dims[3];
      int r = rank_of(loc, name, dims);
      if (count_fields(unit) != count_fields(cols) || (hsize_t)count_fields(cols) != dims[r - 1])
        fail_msg("%s: unit '%s', columns '%s', last dimension %llu", name, unit, cols,
                 (unsigned long long)dims[r - 1]);
    } else if (strchr(unit, ',') != NULL) {
      fail_msg("%s: unit '%s' lists columns but there is no columns attribute", name, unit);
    }
    (*checked)++;
  }
  H5Tclose(t);
  H5Dclose(d);
  return 0;
}

/* at_least: floating-point datasets expected */
static void check_units(hid_t f, int at_least) {
  int checked = 0;
  assert_true(H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, check_unit_cb, &checked) >= 0);
  assert_true(checked >= at_least);
}

static const char *const SERIES_GROUPS[] = {
    "delta",          "support_displacement", "phase",       "block_position",
    "block_velocity", "block_speed",          "joint_N",     "joint_T",
    "joint_M",        "joint_contact",        "joint_gap_i", "joint_gap_e",
    "joint_slip",     "joint_slip_plastic",   "joint_hinge", "reactions",
    "energy",         "joint_points"};

/* Every observable has value, step and time with the same number of rows; returns it. */
static hsize_t check_series_rows(hid_t f) {
  hsize_t rows = 0;
  for (size_t i = 0; i < sizeof SERIES_GROUPS / sizeof SERIES_GROUPS[0]; i++) {
    const char *ds[] = {"value", "step", "time"};
    for (int k = 0; k < 3; k++) {
      char path[128];
      hsize_t dims[3];
      snprintf(path, sizeof path, "/observables/%s/%s", SERIES_GROUPS[i], ds[k]);
      rank_of(f, path, dims);
      if (i == 0 && k == 0) rows = dims[0];
      if (dims[0] != rows)
        fail_msg("%s has %llu rows, expected %llu", path, (unsigned long long)dims[0],
                 (unsigned long long)rows);
    }
  }
  return rows;
}

static void check_root(hid_t f, const char *text, const char *status) {
  char buf[1024];
  read_attr_str(f, "program", buf, sizeof buf);
  assert_string_equal(buf, "voussoir");
  read_attr_str(f, "version", buf, sizeof buf);
  assert_string_equal(buf, VS_VERSION);
  read_attr_str(f, "case", buf, sizeof buf);
  assert_string_equal(buf, text);
  read_attr_str(f, "status", buf, sizeof buf);
  assert_string_equal(buf, status);
  read_attr_str(f, "created", buf, sizeof buf);
  int y, mo, d, h, mi, s;
  char z = 0;
  assert_int_equal(sscanf(buf, "%4d-%2d-%2dT%2d:%2d:%2d%c", &y, &mo, &d, &h, &mi, &s, &z), 7);
  assert_int_equal(strlen(buf), 20);
  assert_int_equal(z, 'Z');
  assert_true(y >= 2024 && mo >= 1 && mo <= 12 && d >= 1 && d <= 31);
}

/* ---------------------------------------------------------------------------------------------
 * XDMF: balanced tags; every HDF data item names an existing dataset of the shape it states;
 * hyperslabs inside their datasets; times strictly increasing; the items every row shares
 * defined once, as children of the Domain named by xml:id, and every XInclude naming such
 * items; every grid, its includes resolved, with one topology, one geometry and each of the 14
 * fields once, theta_rad first, every field on every cell, the included ones NaN. */

static const char *attr_in_tag(const char *tag, const char *end, const char *name, char *out,
                               size_t size) {
  char key[64];
  snprintf(key, sizeof key, " %s=\"", name);
  const char *p = strstr(tag, key);
  if (p == NULL || p > end) return NULL;
  p += strlen(key);
  const char *q = strchr(p, '"');
  size_t n = (size_t)(q - p) < size - 1 ? (size_t)(q - p) : size - 1;
  memcpy(out, p, n);
  out[n] = '\0';
  return out;
}

static int parse_dims(const char *s, hsize_t *d, int max) {
  int n = 0;
  char *end;
  for (;;) {
    unsigned long long v = strtoull(s, &end, 10);
    if (end == s || n == max) break;
    d[n++] = v;
    s = end;
  }
  return n;
}

static const char *const XDMF_FIELDS[14] = {
    "theta_rad", "ux_m",  "uz_m",    "speed_m_s", "N_N",
    "T_N",       "M_N_m", "gap_i_m", "gap_e_m",   "hinge_0closed_1intrados_2extrados",
    "Fx_N",      "Fz_N",  "crack_i_m", "crack_e_m"};

typedef struct {
  int grids, hdf_items, slabs; /* time steps; HDF items and slabs in all */
  int nan_refs, nan_inline;    /* NaN items: slabs of /xdmf/nan; inline "nan" items */
  int uniform;                 /* uniform grids: blocks, joints, support_left, support_right */
  int defs, includes;          /* shared items (xml:id); xi:include elements */
  int own, padded;             /* fields the grids carry: their own, included NaN */
  double t_last;
} xdmf_stats;

/* A shared item: an element of the Domain with an xml:id. */
typedef struct {
  char id[16], tag[16], name[64];
  unsigned long long cells; /* Attribute: values; Topology: NumberOfElements */
  int nan;                  /* an Attribute whose values are NaN */
} xdmf_def;

/* The uniform grid being read. */
typedef struct {
  int open, topologies, geometries, nf;
  unsigned long long cells;
  char fields[16][64];
  unsigned long long field_cells[16];
} xdmf_grid;

static char *slurp(const char *path) {
  FILE *fp = fopen(path, "rb");
  if (fp == NULL) fail_msg("cannot open %s", path);
  fseek(fp, 0, SEEK_END);
  long n = ftell(fp);
  fseek(fp, 0, SEEK_SET);
  char *s = malloc((size_t)n + 1);
  assert_non_null(s);
  assert_int_equal(fread(s, 1, (size_t)n, fp), (size_t)n);
  s[n] = '\0';
  fclose(fp);
  return s;
}

/* One HDF data item: "file:/path" (the whole dataset, of the stated dimensions) or an XDMF 3
 * hyperslab "file:/path|start:stride:count:dims" (stated dimensions = count; dims = the
 * dataset's; the slab inside it). Returns 1 for a hyperslab. */
static int check_hdf_item(hid_t f, const char *h5base, const char *text, const hsize_t *stated,
                          int rank) {
  const char *colon = strchr(text, ':');
  assert_non_null(colon);
  if (strncmp(text, h5base, (size_t)(colon - text)) != 0 ||
      strlen(h5base) != (size_t)(colon - text))
    fail_msg("XDMF names file %.*s, not %s", (int)(colon - text), text, h5base);
  char path[256];
  snprintf(path, sizeof path, "%s", colon + 1);
  char *bar = strchr(path, '|');
  if (bar != NULL) *bar = '\0';
  hsize_t real[3];
  const int r = rank_of(f, path, real);
  if (bar == NULL) {
    if (r != rank) fail_msg("XDMF: %s has rank %d, stated %d", path, r, rank);
    for (int i = 0; i < r; i++)
      if (real[i] != stated[i])
        fail_msg("XDMF: %s dimension %d is %llu, stated %llu", path, i, (unsigned long long)real[i],
                 (unsigned long long)stated[i]);
    return 0;
  }
  hsize_t part[4][8];
  char *p = bar + 1;
  for (int k = 0; k < 4; k++) {
    char *next = strchr(p, ':');
    if (k < 3) assert_non_null(next);
    if (next != NULL) *next = '\0';
    if (parse_dims(p, part[k], 8) != r)
      fail_msg("XDMF: %s: slab part %d of rank != %d", path, k, r);
    p = next != NULL ? next + 1 : p;
  }
  if (rank != r) fail_msg("XDMF: %s: stated rank %d, dataset rank %d", path, rank, r);
  for (int i = 0; i < r; i++) {
    if (part[3][i] != real[i])
      fail_msg("XDMF: %s dimension %d is %llu, stated %llu", path, i, (unsigned long long)real[i],
               (unsigned long long)part[3][i]);
    if (part[2][i] != stated[i]) fail_msg("XDMF: %s: count differs from Dimensions", path);
    if (part[1][i] != 1 || part[0][i] + part[2][i] > real[i])
      fail_msg("XDMF: %s: slab outside", path);
  }
  return 1;
}

/* src into dst of size bytes: it must fit. */
static void copy_str(char *dst, size_t size, const char *src) {
  const size_t n = strlen(src);
  if (n >= size) fail_msg("XDMF: %s: longer than %zu", src, size - 1);
  memcpy(dst, src, n + 1);
}

/* The shared items an include names: xpointer="ID" or "xpointer(id('ID ID ...'))". */
static int include_ids(const char *xp, char ids[16][16]) {
  const char *prefix = "xpointer(id('";
  int n = 0;
  if (strncmp(xp, prefix, strlen(prefix)) != 0) {
    copy_str(ids[n++], sizeof ids[0], xp);
    return n;
  }
  const char *p = xp + strlen(prefix), *end = strstr(p, "'))");
  if (end == NULL || end[3] != '\0') fail_msg("XDMF: xpointer %s", xp);
  while (p < end) {
    const size_t len = strcspn(p, " '");
    assert_true(n < 16 && len > 0 && len < sizeof ids[0]);
    memcpy(ids[n], p, len);
    ids[n++][len] = '\0';
    p += len;
    while (*p == ' ') p++;
  }
  return n;
}

static void grid_add_field(xdmf_grid *g, const char *name, unsigned long long cells) {
  assert_true(g->open && g->nf < 16);
  copy_str(g->fields[g->nf], sizeof g->fields[0], name);
  g->field_cells[g->nf++] = cells;
}

/* At a uniform grid's end: one topology and one geometry; every field once, theta_rad first
 * (ParaView shows it on opening); every field on every cell. */
static void grid_close(const xdmf_grid *g) {
  assert_int_equal(g->topologies, 1);
  assert_int_equal(g->geometries, 1);
  assert_int_equal(g->nf, 14);
  assert_string_equal(g->fields[0], "theta_rad");
  for (int i = 0; i < 14; i++) {
    int n = 0;
    for (int k = 0; k < g->nf; k++) n += strcmp(g->fields[k], XDMF_FIELDS[i]) == 0;
    if (n != 1) fail_msg("XDMF: a grid carries %s %d times", XDMF_FIELDS[i], n);
    if (g->field_cells[i] != g->cells)
      fail_msg("XDMF: %s on %llu cells of %llu", g->fields[i], g->field_cells[i], g->cells);
  }
}

static xdmf_stats check_xdmf(const char *xmf_path, hid_t f, const char *h5base) {
  char *s = slurp(xmf_path);
  const char *stack[16];
  size_t stack_len[16];
  int uniform_at[16];
  int depth = 0;
  /* each step: the four, in order, and the ground when the fall landed on it */
  static const char *const NAMES[5] = {"blocks", "joints", "support_left", "support_right",
                                       "ground"};
  const int per_step = H5Lexists(f, "/summary/ground", H5P_DEFAULT) > 0 ? 5 : 4;
  int k = 0;
  xdmf_stats st = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, -INFINITY};
  xdmf_def defs[64];
  int ndefs = 0, def_open = -1, attr_open = 0; /* the definition, and an Attribute, being read */
  unsigned long long attr_cells = 0;
  char attr_name[64] = "";
  xdmf_grid g = {0};
  for (const char *p = strchr(s, '<'); p != NULL; p = strchr(p + 1, '<')) {
    if (strncmp(p, "<?", 2) == 0 || strncmp(p, "<!DOCTYPE", 9) == 0) continue;
    if (strncmp(p, "<!--", 4) == 0) {
      p = strstr(p, "-->");
      assert_non_null(p);
      continue;
    }
    const char *end = strchr(p, '>');
    assert_non_null(end);
    if (p[1] == '/') { /* closing tag */
      assert_true(depth > 0);
      depth--;
      if (strncmp(p + 2, stack[depth], stack_len[depth]) != 0 || p[2 + stack_len[depth]] != '>')
        fail_msg("XDMF: </%.*s> closes <%.*s>", (int)(end - p - 2), p + 2, (int)stack_len[depth],
                 stack[depth]);
      if (uniform_at[depth]) {
        grid_close(&g);
        g.open = 0;
      }
      if (strncmp(p + 2, "Attribute>", 10) == 0) {
        if (def_open >= 0)
          defs[def_open].cells = attr_cells;
        else
          grid_add_field(&g, attr_name, attr_cells);
        attr_open = 0;
      }
      if (def_open >= 0 && depth == 2) def_open = -1;
      continue;
    }
    const size_t nlen = strcspn(p + 1, " />");
    const int self_closing = end[-1] == '/';
    char gtype[32], gname[64], v[128];
    int is_uniform = 0;
    if (strncmp(p + 1, "Grid", 4) == 0 && nlen == 4) {
      if (!attr_in_tag(p, end, "GridType", gtype, sizeof gtype))
        snprintf(gtype, sizeof gtype, "Uniform");
      if (strcmp(gtype, "Uniform") == 0) {
        assert_non_null(attr_in_tag(p, end, "Name", gname, sizeof gname));
        assert_true(k < per_step && !g.open && def_open < 0);
        assert_string_equal(gname, NAMES[k++]);
        st.uniform++;
        memset(&g, 0, sizeof g);
        g.open = is_uniform = 1;
      }
    }
    if (attr_in_tag(p, end, "xml:id", v, sizeof v)) { /* a shared item: a child of the Domain */
      assert_true(depth == 2 && strncmp(stack[1], "Domain", 6) == 0 && ndefs < 64);
      for (int i = 0; i < ndefs; i++)
        if (strcmp(defs[i].id, v) == 0) fail_msg("XDMF: xml:id %s twice", v);
      xdmf_def *d = &defs[ndefs];
      memset(d, 0, sizeof *d);
      copy_str(d->id, sizeof d->id, v);
      snprintf(d->tag, sizeof d->tag, "%.*s", (int)nlen, p + 1);
      if (attr_in_tag(p, end, "Name", v, sizeof v)) copy_str(d->name, sizeof d->name, v);
      if (attr_in_tag(p, end, "NumberOfElements", v, sizeof v)) d->cells = strtoull(v, NULL, 10);
      def_open = ndefs++;
      st.defs++;
    }
    if (strncmp(p + 1, "xi:include", 10) == 0 && nlen == 10) {
      assert_true(self_closing && g.open);
      assert_non_null(attr_in_tag(p, end, "xpointer", v, sizeof v));
      char ids[16][16];
      const int n = include_ids(v, ids);
      for (int i = 0; i < n; i++) {
        const xdmf_def *d = NULL;
        for (int j = 0; j < ndefs; j++)
          if (strcmp(defs[j].id, ids[i]) == 0) d = &defs[j];
        if (d == NULL) fail_msg("XDMF: xml:id %s is not defined before it is included", ids[i]);
        if (strcmp(d->tag, "Topology") == 0) {
          g.topologies++;
          g.cells = d->cells;
        } else if (strcmp(d->tag, "Geometry") == 0) {
          g.geometries++;
        } else {
          assert_string_equal(d->tag, "Attribute");
          if (!d->nan) fail_msg("XDMF: included field %s (%s) is not NaN", d->id, d->name);
          grid_add_field(&g, d->name, d->cells);
          st.padded++;
        }
      }
      st.includes++;
    }
    if (g.open && def_open < 0 && strncmp(p + 1, "Topology", 8) == 0 && nlen == 8) {
      assert_non_null(attr_in_tag(p, end, "NumberOfElements", v, sizeof v));
      g.topologies++;
      g.cells = strtoull(v, NULL, 10);
    }
    if (g.open && strncmp(p + 1, "Geometry", 8) == 0 && nlen == 8) g.geometries++;
    if (strncmp(p + 1, "Attribute", 9) == 0 && nlen == 9) {
      char center[16];
      assert_true(def_open >= 0 || g.open);
      assert_non_null(attr_in_tag(p, end, "Name", attr_name, sizeof attr_name));
      assert_non_null(attr_in_tag(p, end, "Center", center, sizeof center));
      assert_string_equal(center, "Cell");
      if (def_open < 0) st.own++;
      attr_open = 1;
      attr_cells = 0;
    }
    if (strncmp(p + 1, "Time", 4) == 0 && nlen == 4) {
      assert_non_null(attr_in_tag(p, end, "Value", v, sizeof v));
      double t = strtod(v, NULL);
      if (!(t > st.t_last)) fail_msg("XDMF: time %g after %g", t, st.t_last);
      st.t_last = t;
      st.grids++;
      k = 0;
    }
    char fmt[16];
    if (strncmp(p + 1, "DataItem", 8) == 0 && nlen == 8) {
      char dimtxt[128], item[512];
      hsize_t dims[8];
      assert_non_null(attr_in_tag(p, end, "Dimensions", dimtxt, sizeof dimtxt));
      const int rank = parse_dims(dimtxt, dims, 8);
      unsigned long long values = 1;
      for (int i = 0; i < rank; i++) values *= dims[i];
      if (attr_open) attr_cells = values;
      assert_non_null(attr_in_tag(p, end, "Format", fmt, sizeof fmt));
      const char *text = end + 1, *close = strstr(text, "</DataItem>");
      assert_non_null(close);
      size_t len =
          (size_t)(close - text) < sizeof item - 1 ? (size_t)(close - text) : sizeof item - 1;
      memcpy(item, text, len);
      item[len] = '\0';
      int nan = 0;
      if (strcmp(fmt, "HDF") == 0) {
        nan = strstr(item, ":/xdmf/nan|") != NULL;
        st.nan_refs += nan;
        st.slabs += check_hdf_item(f, h5base, item, dims, rank);
        st.hdf_items++;
      } else if (strncmp(item, "nan", 3) == 0) {
        nan = 1;
        st.nan_inline++;
        for (const char *q = item; *q != '\0'; q += strspn(q, " ")) { /* values nan only */
          assert_true(strncmp(q, "nan", 3) == 0);
          q += 3;
          values--;
        }
        assert_true(values == 0);
      }
      if (attr_open && def_open >= 0) defs[def_open].nan = nan;
      if (attr_open && def_open < 0 && nan) fail_msg("XDMF: own field %s is NaN", attr_name);
    }
    if (!self_closing) {
      assert_true(depth < 16);
      stack[depth] = p + 1;
      stack_len[depth] = nlen;
      uniform_at[depth] = is_uniform;
      depth++;
    }
  }
  assert_int_equal(depth, 0);
  assert_int_equal(st.uniform, per_step * st.grids);
  free(s);
  return st;
}

/* ---------------------------------------------------------------------------------------------
 * A quasi-static run to the first limit point */

static void check_joint_states(hid_t f, const vs_run *run, size_t rows) {
  const vs_geometry *g = vs_run_geometry(run);
  const size_t nj = (size_t)g->n_joints;
  size_t n;
  double *N = read_all(f, "/observables/joint_N/value", &n);
  double *T = read_all(f, "/observables/joint_T/value", &n);
  double *gi = read_all(f, "/observables/joint_gap_i/value", &n);
  double *ge = read_all(f, "/observables/joint_gap_e/value", &n);
  double *h = read_all(f, "/observables/joint_hinge/value", &n);
  double *R = read_all(f, "/observables/reactions/value", &n);
  const double W = vs_geometry_weight(g), open = vs_run_case(run)->open_mm * VS_MM;
  int hinges = 0;
  for (size_t r = 0; r < rows; r++) {
    const double *rr = R + 6 * r;
    /* the supports carry the arch's weight: they push it up by W in all */
    assert_true(fabs(rr[1] + rr[4] - W) <= 1e-6 * W);
    /* the left reaction is the force through joint 1 */
    assert_true(fabs(hypot(rr[0], rr[1]) - hypot(N[r * nj], T[r * nj])) <= 1e-9 * W);
    for (size_t k = 0; k < nj; k++) {
      const double a = gi[r * nj + k], b = ge[r * nj + k];
      const int want = fmax(a, b) <= open ? 0 : b > a ? 1 : 2;
      assert_int_equal((int)h[r * nj + k], want);
      hinges += want != 0;
    }
  }
  assert_true(hinges > 0);
  free(N), free(T), free(gi), free(ge), free(h), free(R);
}

/* /geometry/block_points and /geometry/block_centroid against the run's sectors: block b's P
 * points are the intrados arc from phi0 to phi1, then the extrados arc back, P/2 each, evenly
 * spaced in angle (the corners included). */
static void check_reference_outlines(hid_t f, const vs_run *run) {
  const vs_geometry *g = vs_run_geometry(run);
  hsize_t dims[3];
  rank_of(f, "/geometry/block_points", dims);
  const size_t nb = (size_t)g->n_blocks, P = (size_t)dims[0] / nb;
  assert_int_equal(P, 8); /* 2 + 2 corners and 2 x 2 arc points, the default */
  size_t n;
  double *ref = read_all(f, "/geometry/block_points", &n);
  double *cen = read_all(f, "/geometry/block_centroid", &n);
  const double ri = g->radius, re = g->radius + g->thickness;
  for (size_t b = 0; b < nb; b++) {
    const vs_block *blk = &g->blocks[b];
    assert_true(cen[2 * b] == blk->cx && cen[2 * b + 1] == blk->cz);
    for (size_t k = 0; k < P / 2; k++) {
      const double f1 = (double)k / (double)(P / 2 - 1);
      const double pi = blk->phi0 + f1 * (blk->phi1 - blk->phi0);
      const double pe = blk->phi1 - f1 * (blk->phi1 - blk->phi0);
      const double *p = ref + 2 * (b * P + k), *e = ref + 2 * (b * P + P / 2 + k);
      assert_true(fabs(p[0] - ri * sin(pi)) < 1e-12 && fabs(p[1] - ri * cos(pi)) < 1e-12);
      assert_true(fabs(e[0] - re * sin(pe)) < 1e-12 && fabs(e[1] - re * cos(pe)) < 1e-12);
    }
  }
  free(ref), free(cen);
}

/* The rows a sidecar lists (output.h: every k-th row, k = ceil(rows / max_grids), and the last;
 * times strictly increasing) into sel; returns how many. */
static long listed_rows(const double *t, long rows, int max_grids, long *sel) {
  const long k = (rows + max_grids - 1) / max_grids > 1 ? (rows + max_grids - 1) / max_grids : 1;
  long n = 0;
  for (long r = 0; r < rows; r++)
    if ((r % k == 0 || r == rows - 1) && (n == 0 || t[r] > t[sel[n - 1]])) sel[n++] = r;
  return n;
}

typedef struct {
  int frames, states, inline_; /* blocks' geometries from /xdmf/block_points, from
                                  /observables/block_points/value, inline */
} outline_sources;

/* The blocks' geometry of every step of the sidecar xmf_path of record f (h5base: its name)
 * against outlines computed here: /geometry/block_points moved rigidly with the blocks' positions
 * of the step's row (turned by theta about /geometry/block_centroid, which moved by ux, uz), to
 * float32 precision, NaN where the positions are. A geometry from /xdmf/block_points must be the
 * frame of its row (/xdmf/block_points_row). max_grids > 0: the steps must be the rows the
 * listing rule gives (0: rows increasing only: a killed record's datasets may differ in rows). */
static outline_sources check_outlines(const char *xmf_path, hid_t f, const char *h5base,
                                      int max_grids) {
  size_t n, nq, nt;
  double *ref = read_all(f, "/geometry/block_points", &n);
  double *cen = read_all(f, "/geometry/block_centroid", &nq);
  const size_t nb = nq / 2, np = n / 2, P = np / nb;
  double *q = read_all(f, "/observables/block_position/value", &nq);
  double *t = read_all(f, "/observables/delta/time", &nt);
  const long rows = (long)(nq / (3 * nb) < nt ? nq / (3 * nb) : nt);
  long *sel = malloc((size_t)(rows > 0 ? rows : 1) * sizeof *sel);
  double *want = malloc(2 * np * sizeof *want);
  float *got = malloc(2 * np * sizeof *got);
  assert_true(sel != NULL && want != NULL && got != NULL);
  const long listed = max_grids > 0 ? listed_rows(t, rows, max_grids, sel) : -1;
  /* the record's outlines, whole, when it has them */
  double *frames = NULL, *frame_row = NULL, *states = NULL;
  size_t n_frames = 0, n_states = 0;
  if (H5Lexists(f, "/xdmf", H5P_DEFAULT) > 0 &&
      H5Lexists(f, "/xdmf/block_points", H5P_DEFAULT) > 0) {
    frames = read_all(f, "/xdmf/block_points", &n_frames);
    frame_row = read_all(f, "/xdmf/block_points_row", &n);
    assert_int_equal(n_frames, n * 2 * np);
  }
  if (H5Lexists(f, "/observables/block_points", H5P_DEFAULT) > 0)
    states = read_all(f, "/observables/block_points/value", &n_states);
  outline_sources src = {0, 0, 0};
  char *x = slurp(xmf_path);
  long step = 0, last = -1;
  for (const char *p = strstr(x, "<Grid Name=\"row "); p != NULL;
       p = strstr(p + 1, "<Grid Name=\"row "), step++) {
    const long r = strtol(p + strlen("<Grid Name=\"row "), NULL, 10);
    assert_true(r > last && r < rows);
    if (listed >= 0) assert_true(step < listed && r == sel[step]);
    last = r;
    /* the outlines computed here */
    for (size_t b = 0; b < nb; b++) {
      const double *qb = q + (size_t)r * 3 * nb + 3 * b;
      const double c = cos(qb[2]), sn = sin(qb[2]);
      for (size_t k = 0; k < P; k++) {
        const double *rp = ref + 2 * (b * P + k);
        const double dx = rp[0] - cen[2 * b], dz = rp[1] - cen[2 * b + 1];
        want[2 * (b * P + k)] = cen[2 * b] + qb[0] + c * dx - sn * dz;
        want[2 * (b * P + k) + 1] = cen[2 * b + 1] + qb[1] + sn * dx + c * dz;
      }
    }
    /* what the step's blocks show */
    const char *geo = strstr(strstr(p, "<Grid Name=\"blocks\">"), "<Geometry GeometryType=\"XY\">");
    const char *tag = strstr(geo, "<DataItem "), *item = strchr(tag, '>') + 1;
    char fmt[16];
    assert_non_null(attr_in_tag(tag, item, "Format", fmt, sizeof fmt));
    if (strcmp(fmt, "XML") == 0) {
      src.inline_++;
      char *e = (char *)item;
      for (size_t i = 0; i < 2 * np; i++) {
        const char *v = e;
        got[i] = strtof(v, &e);
        assert_true(e != v);
      }
      assert_true(strncmp(e, "</DataItem>", 11) == 0);
    } else {
      char path[64];
      unsigned long long start;
      const size_t hl = strlen(h5base);
      assert_true(strncmp(item, h5base, hl) == 0 && item[hl] == ':');
      assert_int_equal(sscanf(item + hl + 1, "%63[^|]|%llu ", path, &start), 2);
      const double *from;
      if (strcmp(path, "/xdmf/block_points") == 0) {
        src.frames++;
        assert_non_null(frames);
        assert_true(start < n_frames / (2 * np) && frame_row[start] == (double)r);
        from = frames + start * 2 * np;
      } else {
        assert_string_equal(path, "/observables/block_points/value");
        src.states++;
        assert_true(states != NULL && start == (unsigned long long)r);
        from = states + start * 2 * np;
      }
      for (size_t i = 0; i < 2 * np; i++) got[i] = (float)from[i];
    }
    for (size_t i = 0; i < 2 * np; i++)
      if (isnan(want[i]) ? !isnan(got[i]) : !(fabs(got[i] - want[i]) < 1e-6)) /* float32 */
        fail_msg("%s row %ld: point %zu of the blocks is %.9g, computed %.9g", xmf_path, r, i / 2,
                 (double)got[i], want[i]);
  }
  if (listed >= 0) assert_int_equal(step, listed);
  free(x), free(ref), free(cen), free(q), free(t), free(sel), free(want), free(got);
  free(frames), free(frame_row), free(states);
  return src;
}

static void check_events(hid_t f, const vs_run *run) {
  typedef struct {
    double time, delta;
    int joint;
    char kind[17];
  } ev;
  hid_t d = H5Dopen2(f, "/events", H5P_DEFAULT);
  hid_t s = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(s);
  assert_int_equal(n, vs_run_event_count(run));
  hid_t kt = H5Tcopy(H5T_C_S1);
  H5Tset_size(kt, 17); /* NUL-terminated in memory */
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(ev));
  H5Tinsert(mt, "time", HOFFSET(ev, time), H5T_NATIVE_DOUBLE);
  H5Tinsert(mt, "delta", HOFFSET(ev, delta), H5T_NATIVE_DOUBLE);
  H5Tinsert(mt, "joint", HOFFSET(ev, joint), H5T_NATIVE_INT);
  H5Tinsert(mt, "kind", HOFFSET(ev, kind), kt);
  ev *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  assert_non_null(rows);
  if (n > 0) assert_true(H5Dread(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows) >= 0);
  static const char *const kinds[] = {"joint_opened", "joint_closed", "hinge_formed",
                                      "limit_point",  "snap_settled", "collapse",
                                      "joint_slipped"};
  for (int i = 0; i < (int)n; i++) {
    const vs_run_event *e = vs_run_event_get(run, i);
    assert_true(rows[i].time == e->t && rows[i].delta == e->delta);
    assert_int_equal(rows[i].joint, e->joint);
    assert_string_equal(rows[i].kind, kinds[e->kind]);
  }
  free(rows);
  H5Tclose(mt);
  H5Tclose(kt);
  H5Sclose(s);
  H5Dclose(d);
}

static void test_quasistatic_record(void **state) {
  (void)state;
  char path[128], xmf[128];
  path_in(path, sizeof path, "qs.h5");
  path_in(xmf, sizeof xmf, "qs.xmf");
  vs_case c = small_case(0);
  long samples;
  vs_status st;
  const char *text = "[arch]\nvoussoirs = 11 ; coarse\n";
  vs_run *run = record(&c, path, text, NULL, 0, &samples, &st);
  assert_int_equal(st, VS_OK);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  check_root(f, text, "completed");
  check_units(f, 50);
  const hsize_t rows = check_series_rows(f);
  assert_int_equal(rows, samples);
  assert_true(rows > 20);

  /* last row = the run's last state; every row at rest, quasi-static, delta = rate t */
  const vs_model *m = vs_run_model(run);
  const size_t n3 = (size_t)vs_model_size(m);
  size_t n;
  double *q = read_all(f, "/observables/block_position/value", &n);
  double *v = read_all(f, "/observables/block_velocity/value", &n);
  double *t = read_all(f, "/observables/delta/time", &n);
  double *dl = read_all(f, "/observables/delta/value", &n);
  double *ph = read_all(f, "/observables/phase/value", &n);
  double *en = read_all(f, "/observables/energy/value", &n);
  double *step = read_all(f, "/observables/joint_N/step", &n);
  assert_memory_equal(q + (rows - 1) * n3, vs_run_state(run), n3 * sizeof(double));
  const double rate = c.rate_mm_s * VS_MM;
  for (size_t r = 0; r < rows; r++) {
    assert_true(fabs(dl[r] - rate * t[r]) <= 1e-14 * fabs(dl[r]));
    assert_true(r == 0 || dl[r] > dl[r - 1]);
    assert_true(ph[r] == 0.0 && step[r] == (double)r);
    for (size_t i = 0; i < n3; i++) assert_true(v[r * n3 + i] == 0.0);
    assert_true(en[7 * r] == 0.0 && isnan(en[7 * r + 3]) && isnan(en[7 * r + 6]));
    double eg = 0.0; /* gravitational potential from the positions */
    for (int b = 0; b < vs_run_geometry(run)->n_blocks; b++)
      eg += vs_run_geometry(run)->blocks[b].mass * c.gravity_m_s2 * q[r * n3 + 3 * (size_t)b + 1];
    assert_true(fabs(en[7 * r + 1] - eg) <= 1e-12 * fabs(eg) + 1e-15);
  }
  assert_true(dl[0] == 0.0); /* self-weight */
  check_joint_states(f, run, rows);
  check_reference_outlines(f, run);
  check_events(f, run);

  /* summary */
  assert_true(read_scalar(f, "/summary/first_limit/delta") == vs_run_path(run)->delta_limit);
  hsize_t dims[3];
  rank_of(f, "/summary/limit_points", dims);
  assert_int_equal(dims[0], vs_run_limit_count(run));
  rank_of(f, "/summary/hinges", dims);
  assert_int_equal(dims[0], vs_hinges_count(vs_run_hinges(run)));
  hid_t sum = H5Gopen2(f, "/summary", H5P_DEFAULT);
  assert_int_equal(read_attr_int(sum, "rows"), (long long)rows);
  char pattern[64];
  read_attr_str(sum, "pattern_initial", pattern, sizeof pattern);
  assert_string_equal(pattern, vs_run_pattern_initial(run));
  H5Gclose(sum);
  hid_t par = H5Gopen2(f, "/parameters/arch", H5P_DEFAULT);
  assert_int_equal(read_attr_int(par, "voussoirs"), 11);
  H5Gclose(par);

  xdmf_stats xs = check_xdmf(xmf, f, "qs.h5");
  assert_int_equal(xs.grids, (int)rows); /* few rows: all of them, times increasing */
  /* the blocks' outlines: the record's frames, one per listed row, none per state */
  assert_true(H5Lexists(f, "/observables/block_points", H5P_DEFAULT) == 0);
  outline_sources os = check_outlines(xmf, f, "qs.h5", 2000);
  assert_int_equal(os.frames, xs.grids);
  assert_true(os.states == 0 && os.inline_ == 0);
  /* defined once: the topologies of the blocks and the joints (their connectivity), of one
   * segment (inline), and the NaN fields, slabs of /xdmf/nan: 10 on the blocks' cells, 6 on the
   * joints', 11 on one cell (those the supports lack) */
  assert_int_equal(xs.defs, 3 + 27);
  assert_int_equal(xs.nan_refs, 27);
  assert_int_equal(xs.nan_inline, 0);
  /* per step, as slabs of their row: blocks 5 items (points, 4 fields), joints 9 (points, 8
   * fields), left support 4 (points, Fx, Fz, M), right support 6 (and its displacement); each
   * grid includes its topology and the other of the 14 fields as NaN: 10 + 6 + 11 + 9 */
  assert_int_equal(xs.hdf_items, 2 + 27 + xs.grids * 24);
  assert_int_equal(xs.slabs, 27 + xs.grids * 24);
  assert_int_equal(xs.own, xs.grids * 20);
  assert_int_equal(xs.padded, xs.grids * 36);
  assert_int_equal(xs.includes, xs.grids * 4 * 2);
  double *nan = read_all(f, "/xdmf/nan", &n);
  assert_int_equal(n, (size_t)vs_run_geometry(run)->n_joints); /* the largest grid */
  for (size_t i = 0; i < n; i++) assert_true(isnan(nan[i]));
  free(nan);
  free(v), free(t), free(dl), free(ph), free(en), free(step);
  H5Fclose(f);
  /* a record written before /xdmf/nan existed: its sidecar pads inline, as those versions did,
   * and takes the blocks' outlines from the per-state dataset they wrote (made here from the
   * positions and the reference outlines, float32) */
  f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(H5Ldelete(f, "/xdmf", H5P_DEFAULT) >= 0);
  {
    double *ref = read_all(f, "/geometry/block_points", &n);
    const size_t np = n / 2, nb = n3 / 3, P = np / nb;
    float *pts = malloc(rows * 2 * np * sizeof *pts);
    assert_non_null(pts);
    for (size_t r = 0; r < rows; r++)
      for (size_t b = 0; b < nb; b++) {
        const vs_block *blk = &vs_run_geometry(run)->blocks[b];
        const double *qb = q + r * n3 + 3 * b;
        const double co = cos(qb[2]), sn = sin(qb[2]);
        for (size_t k = 0; k < P; k++) {
          const double dx = ref[2 * (b * P + k)] - blk->cx, dz = ref[2 * (b * P + k) + 1] - blk->cz;
          pts[2 * (r * np + b * P + k)] = (float)(blk->cx + qb[0] + co * dx - sn * dz);
          pts[2 * (r * np + b * P + k) + 1] = (float)(blk->cz + qb[1] + sn * dx + co * dz);
        }
      }
    hid_t g = H5Gcreate2(f, "/observables/block_points", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    const hsize_t d3[3] = {rows, np, 2};
    hid_t sp = H5Screate_simple(3, d3, NULL);
    hid_t d = H5Dcreate2(g, "value", H5T_IEEE_F32LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    assert_true(d >= 0 && H5Dwrite(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, pts) >= 0);
    H5Dclose(d), H5Sclose(sp), H5Gclose(g);
    free(pts), free(ref);
  }
  H5Fclose(f);
  vs_error err;
  assert_int_equal(vs_output_write_xdmf(path, 0, &err), VS_OK);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  xdmf_stats old = check_xdmf(xmf, f, "qs.h5");
  assert_int_equal(old.grids, xs.grids);
  assert_int_equal(old.defs, xs.defs);
  assert_int_equal(old.nan_refs, 0);
  assert_int_equal(old.nan_inline, 27);
  assert_int_equal(old.hdf_items, 2 + xs.grids * 24);
  assert_int_equal(old.padded, xs.padded);
  os = check_outlines(xmf, f, "qs.h5", 2000);
  assert_true(os.states == xs.grids && os.frames == 0 && os.inline_ == 0);
  H5Fclose(f);
  free(q);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0); /* nothing left open */
  vs_run_destroy(&run);
}

/* ---------------------------------------------------------------------------------------------
 * A run followed dynamically to the collapse */

static void test_dynamic_record(void **state) {
  (void)state;
  char path[128], xmf[128];
  path_in(path, sizeof path, "dyn.hdf5");
  path_in(xmf, sizeof xmf, "dyn.xmf");
  vs_case c = small_case(1);
  long samples;
  vs_status st;
  vs_output_opts opts;
  vs_output_opts_default(&opts);
  opts.xdmf_max_grids = 40; /* the sidecar lists every k-th row: the record keeps their outlines */
  vs_run *run = record(&c, path, NULL, &opts, 0, &samples, &st);
  assert_int_equal(st, VS_OK);
  assert_true(vs_run_collapse(run)->found);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  check_root(f, "", "completed");
  check_units(f, 50);
  const hsize_t rows = check_series_rows(f);
  assert_int_equal(rows, samples);
  const vs_geometry *g = vs_run_geometry(run);
  const size_t n3 = 3 * (size_t)g->n_blocks;
  size_t n;
  double *ph = read_all(f, "/observables/phase/value", &n);
  double *v = read_all(f, "/observables/block_velocity/value", &n);
  double *sp = read_all(f, "/observables/block_speed/value", &n);
  double *en = read_all(f, "/observables/energy/value", &n);
  double *t = read_all(f, "/observables/reactions/time", &n);
  double *dl = read_all(f, "/observables/delta/value", &n);
  int dyn = 0, qs = 0, switches = 0;
  double ke_max = 0.0;
  for (size_t r = 0; r < rows; r++) {
    assert_true(fabs(dl[r] - c.rate_mm_s * VS_MM * t[r]) <= 1e-14 * fabs(dl[r]));
    assert_true(r == 0 || t[r] >= t[r - 1] * (1.0 - 1e-15));
    switches += r > 0 && ph[r] != ph[r - 1];
    if (ph[r] == 0.0) {
      qs++;
      continue;
    }
    dyn++;
    double ke = 0.0; /* kinetic energy from the velocities, masses and inertias */
    for (int b = 0; b < g->n_blocks; b++) {
      const double *vb = v + r * n3 + 3 * (size_t)b;
      ke += 0.5 * (g->blocks[b].mass * (vb[0] * vb[0] + vb[1] * vb[1]) +
                   g->blocks[b].inertia * vb[2] * vb[2]);
      assert_true(fabs(sp[r * (size_t)g->n_blocks + (size_t)b] - hypot(vb[0], vb[1])) <= 1e-15);
    }
    assert_true(fabs(en[7 * r] - ke) <= 1e-12 * ke + 1e-300);
    assert_true(isfinite(en[7 * r + 6]));
    ke_max = fmax(ke_max, ke);
  }
  assert_true(qs > 10 && dyn > 10 && switches >= 1);
  assert_true(ke_max > 0.0);
  assert_true(fabs(read_scalar(f, "/summary/dynamic/max_kinetic") -
                   vs_run_dynamic_totals(run)->max_kinetic) == 0.0);
  assert_true(read_scalar(f, "/summary/collapse/delta") == vs_run_collapse(run)->delta);
  check_events(f, run);
  /* the first three hinges got their labels after their events: the table was rewritten */
  hid_t d = H5Dopen2(f, "/events", H5P_DEFAULT);
  typedef struct {
    char label;
    int order;
  } lab;
  hid_t c1 = H5Tcopy(H5T_C_S1);
  H5Tset_size(c1, 1);
  H5Tset_strpad(c1, H5T_STR_NULLPAD);
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(lab));
  H5Tinsert(mt, "label", HOFFSET(lab, label), c1);
  H5Tinsert(mt, "order", HOFFSET(lab, order), H5T_NATIVE_INT);
  const int ne = vs_run_event_count(run);
  lab *labs = calloc((size_t)ne, sizeof *labs);
  assert_true(H5Dread(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, labs) >= 0);
  int formed = 0;
  for (int i = 0; i < ne; i++) {
    assert_int_equal(labs[i].label, vs_run_event_get(run, i)->label);
    if (vs_run_event_get(run, i)->kind == VS_EVENT_HINGE_FORMED && labs[i].order <= 3) {
      assert_true(labs[i].label >= 'A' && labs[i].label <= 'C');
      formed++;
    }
  }
  assert_int_equal(formed, 3);
  free(labs);
  H5Tclose(mt), H5Tclose(c1), H5Dclose(d);
  hid_t sum = H5Gopen2(f, "/summary", H5P_DEFAULT);
  char mode[16];
  read_attr_str(sum, "mode", mode, sizeof mode);
  assert_string_equal(mode, vs_run_mode(run) != NULL ? vs_run_mode(run) : "");
  H5Gclose(sum);
  /* the fall to rest: the rest level recorded, the last state's kinetic energy below it */
  assert_true(H5Lexists(f, "/summary/ground", H5P_DEFAULT) > 0);
  const double rest = read_scalar(f, "/summary/ground/rest_level");
  assert_true(rest == vs_run_rest_ke(run) && rest > 0.0);
  assert_int_equal(vs_run_dynamic_totals(run)->fall_at_rest, 1);
  assert_true(en[7 * (rows - 1)] < rest);
  xdmf_stats xs = check_xdmf(xmf, f, "dyn.hdf5");
  assert_true(xs.grids > 20 && xs.grids <= 41 && rows > 200);
  outline_sources os = check_outlines(xmf, f, "dyn.hdf5", 40);
  assert_true(os.frames == xs.grids && os.states == 0 && os.inline_ == 0);
  hsize_t fd[3];
  rank_of(f, "/xdmf/block_points", fd);
  assert_int_equal(fd[0], (hsize_t)xs.grids);
  /* the sidecar rebuilt to list more rows: those without a frame get their outlines inline */
  vs_error err;
  assert_int_equal(vs_output_write_xdmf(path, 0, &err), VS_OK);
  xs = check_xdmf(xmf, f, "dyn.hdf5");
  assert_true(xs.grids > (int)rows / 2 && xs.grids <= (int)rows);
  os = check_outlines(xmf, f, "dyn.hdf5", 2000);
  assert_true(os.frames > 20 && os.inline_ == xs.grids - os.frames && os.states == 0);
  free(ph), free(v), free(sp), free(en), free(t), free(dl);
  H5Fclose(f);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
  vs_run_destroy(&run);
}

/* ---------------------------------------------------------------------------------------------
 * Killed with SIGKILL */

typedef struct {
  int n, cap, n3;
  double *delta, *q;
  int stop_after;
} memrec;

static int mem_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  (void)run;
  memrec *m = user;
  if (m->n == m->cap) return 1;
  m->delta[m->n] = s->delta;
  memcpy(m->q + (size_t)m->n * (size_t)m->n3, s->q, (size_t)m->n3 * sizeof(double));
  m->n++;
  return m->n >= m->stop_after;
}

typedef struct {
  vs_output *o;
  long rows, signal_at, die_at;
  int fd;
  long die_at_event_after; /* > 0: SIGKILL at the first event after this many rows */
} child_sink;

static int child_sample(void *user, const vs_run *run, const vs_run_sample *s) {
  child_sink *k = user;
  int rc = vs_output_sample(k->o, run, s);
  k->rows++;
  if (k->rows == k->signal_at && write(k->fd, "x", 1) != 1) _exit(3);
  if (k->rows == k->die_at) raise(SIGKILL);
  return rc;
}

static int child_event(void *user, const vs_run *run, const vs_run_event *e) {
  child_sink *k = user;
  int rc = vs_output_event(k->o, run, e);
  if (k->die_at_event_after > 0 && k->rows >= k->die_at_event_after) raise(SIGKILL);
  return rc;
}

/* In a child: record case c at path, write a byte to fd after signal_at rows, SIGKILL itself
 * after die_at rows (0: never); at the end wait to be killed. */
static void child_run(const vs_case *c, const char *path, int fd, long signal_at, long die_at) {
  vs_error err;
  vs_run *run = NULL;
  child_sink k = {NULL, 0, signal_at, die_at, fd, 0};
  const char *ev = getenv("VS_TEST_DIE_AT_EVENT_AFTER"); /* set in the child only */
  if (ev != NULL) k.die_at_event_after = atol(ev);
  vs_output_opts o;
  vs_output_opts_default(&o);
  o.snapshot_share = 1.0; /* a snapshot after every flush: what a kill leaves is known */
  if (vs_run_create(c, &run, &err) != VS_OK || vs_output_create(path, run, "", &o, &k.o, &err))
    _exit(2);
  vs_status st = vs_run_execute(run, child_sample, child_event, &k, &err);
  vs_output_finish(k.o, run, st, &err, &err);
  vs_output_destroy(&k.o);
  if (k.rows < signal_at && write(fd, "x", 1) != 1) _exit(3);
  for (;;) pause();
}

/* Rows of the shortest and the longest time series (a kill during a flush may leave some
 * datasets one flush behind the others). */
static void series_rows_range(hid_t f, hsize_t *lo, hsize_t *hi) {
  *lo = (hsize_t)-1;
  *hi = 0;
  for (size_t i = 0; i < sizeof SERIES_GROUPS / sizeof SERIES_GROUPS[0]; i++) {
    char path[128];
    hsize_t dims[3];
    snprintf(path, sizeof path, "/observables/%s/value", SERIES_GROUPS[i]);
    rank_of(f, path, dims);
    if (dims[0] < *lo) *lo = dims[0];
    if (dims[0] > *hi) *hi = dims[0];
  }
}

/* Rows of a killed run's dataset (n rows of width w) against the run recorded in memory: each
 * row is the run's, bit for bit, or entirely NaN (the fill value: rows of a flush cut short by
 * the kill, whose data did not reach the disk), and NaN rows only at the end. Returns the rows
 * that hold data. */
static size_t check_rows(const double *got, const double *want, size_t n, size_t w) {
  size_t good = 0;
  for (size_t r = 0; r < n; r++) {
    if (good == r && memcmp(got + r * w, want + r * w, w * sizeof(double)) == 0) {
      good++;
      continue;
    }
    for (size_t i = 0; i < w; i++)
      if (!isnan(got[r * w + i])) fail_msg("row %zu is neither the run's nor NaN", r);
  }
  return good;
}

/* H5Ovisit: read dataset `name` whole into memory (its native type); count it. */
static herr_t read_one(hid_t loc, const char *name, const H5O_info_t *info, void *op_data) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  hid_t d = H5Dopen2(loc, name, H5P_DEFAULT);
  if (d < 0) fail_msg("dataset %s does not open", name);
  hid_t ft = H5Dget_type(d), t = H5Tget_native_type(ft, H5T_DIR_ASCEND), sp = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(sp);
  void *buf = malloc((size_t)(n > 0 ? n : 1) * H5Tget_size(t));
  assert_non_null(buf);
  if (n > 0 && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf) < 0)
    fail_msg("dataset %s does not read", name);
  if (n > 0) H5Dvlen_reclaim(t, sp, H5P_DEFAULT, buf); /* variable-length strings, if any */
  free(buf);
  H5Sclose(sp), H5Tclose(t), H5Tclose(ft), H5Dclose(d);
  ++*(int *)op_data;
  return 0;
}

/* A killed record's data (check_killed without the sidecar): it opens normally; its status is
 * "running" or "completed"; every series has the same rows, each the run's bit for bit (at
 * least at_least of them while "running"); the units, and every dataset, read whole. */
static void check_killed_data(const char *path, const memrec *ref, long at_least) {
  char status[64];
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT); /* an ordinary open */
  if (f < 0) fail_msg("%s: H5Fopen failed after SIGKILL", path);
  read_attr_str(f, "status", status, sizeof status);
  hsize_t lo, hi;
  series_rows_range(f, &lo, &hi);
  if (strcmp(status, "running") != 0) assert_string_equal(status, "completed"); /* got there */
  assert_true((int)hi <= ref->n);
  size_t nd, nq;
  double *dl = read_all(f, "/observables/delta/value", &nd);
  double *q = read_all(f, "/observables/block_position/value", &nq);
  const size_t good = check_rows(dl, ref->delta, nd, 1);
  const size_t good_q = check_rows(q, ref->q, nq / (size_t)ref->n3, (size_t)ref->n3);
  if (strcmp(status, "running") == 0)
    assert_true((long)good >= at_least && (long)good_q >= at_least);
  /* a snapshot, never the file HDF5 was writing: every series has the same rows, all of them
   * the run's (no row of a flush cut short) */
  assert_true(lo == hi && good == nd && good_q == nd && nq == nd * (size_t)ref->n3);
  print_message("  %s: status %s, %zu rows (datasets of %llu to %llu rows) of %d\n",
                strrchr(path, '/') + 1, status, good, (unsigned long long)lo,
                (unsigned long long)hi, ref->n);
  free(dl), free(q);
  hsize_t dims[3];
  rank_of(f, "/events", dims); /* readable */
  check_units(f, 30);
  int datasets = 0; /* every dataset reads whole */
  assert_true(H5Ovisit2(f, H5_INDEX_NAME, H5_ITER_NATIVE, read_one, &datasets,
                        H5O_INFO_BASIC) >= 0);
  assert_true(datasets > 30);
  H5Fclose(f);
}

/* A killed record (check_killed_data), and its sidecar: written from what survived, with the
 * blocks' outlines inline unless the status vouches for the frames. */
static void check_killed(const char *path, const memrec *ref, long at_least) {
  check_killed_data(path, ref, at_least);
  char status[64];
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  read_attr_str(f, "status", status, sizeof status);
  hsize_t lo, hi;
  series_rows_range(f, &lo, &hi);
  H5Fclose(f);
  /* the sidecar can be written from what survived */
  vs_error err;
  assert_int_equal(vs_output_write_xdmf(path, 0, &err), VS_OK);
  char xmf[160];
  snprintf(xmf, sizeof xmf, "%.*s.xmf", (int)(strlen(path) - 3), path);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  const char *base = strrchr(path, '/') + 1;
  xdmf_stats xs = check_xdmf(xmf, f, base);
  assert_true(xs.grids >= (hi > 0) && xs.grids <= (int)hi); /* none for the layout alone */
  /* the blocks' outlines: inline, from the positions, unless the status vouches for the frames */
  outline_sources os = check_outlines(xmf, f, base, strcmp(status, "running") == 0 ? 0 : 2000);
  if (strcmp(status, "running") == 0)
    assert_true(os.inline_ == xs.grids && os.frames == 0 && os.states == 0);
  else
    assert_true(os.frames == xs.grids && os.inline_ == 0 && os.states == 0);
  H5Fclose(f);
}

/* The case the kill tests run, the reference specimen ending at the collapse (294 rows, long
 * enough to be killed in; every kill is before the collapse, so the fall is not needed), into
 * *c, and its rows run in memory: what a killed record must hold. */
static memrec killed_case(vs_case *c) {
  vs_case_defaults(c);
  c->fall_s = 0.0;
  vs_error err;
  vs_run *run = NULL;
  assert_int_equal(vs_run_create(c, &run, &err), VS_OK);
  memrec ref = {0, 4096, vs_model_size(vs_run_model(run)), NULL, NULL, 1 << 30};
  ref.delta = malloc((size_t)ref.cap * sizeof *ref.delta);
  ref.q = malloc((size_t)ref.cap * (size_t)ref.n3 * sizeof *ref.q);
  assert_true(ref.delta != NULL && ref.q != NULL);
  vs_run_execute(run, mem_sample, NULL, &ref, &err);
  vs_run_destroy(&run);
  assert_true(ref.n > 200);
  return ref;
}

/* Fork a child that records case c at path (child_run: a byte down the pipe at row signal_at,
 * SIGKILL to itself at row die_at; event_after, fault: VS_TEST_DIE_AT_EVENT_AFTER and
 * VS_FAULT_KILL in the child, or NULL). Returns its pid; fds[0] is the pipe's read end. */
static pid_t start_child(const vs_case *c, const char *path, int fds[2], long signal_at,
                         long die_at, const char *event_after, const char *fault) {
  assert_int_equal(pipe(fds), 0);
  fflush(NULL);
  const pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    close(fds[0]);
    if (event_after != NULL) setenv("VS_TEST_DIE_AT_EVENT_AFTER", event_after, 1);
    if (fault != NULL) setenv("VS_FAULT_KILL", fault, 1);
    child_run(c, path, fds[1], signal_at, die_at);
  }
  close(fds[1]);
  return pid;
}

static void test_killed(void **state) {
  (void)state;
  vs_case c;
  memrec ref = killed_case(&c);

  /* The child kills itself at row 137, after it reported row 100 through the pipe (kills at
   * moments spread over a run: test_killed_anywhere). */
  char path[128];
  snprintf(path, sizeof path, "%s/killed.h5", g_dir);
  int fds[2];
  const pid_t pid = start_child(&c, path, fds, 100, 137, NULL, NULL);
  struct pollfd pfd = {fds[0], POLLIN, 0};
  char b;
  if (poll(&pfd, 1, 30000) != 1 || read(fds[0], &b, 1) != 1) {
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
    fail_msg("the child wrote no rows");
  }
  int wst;
  assert_int_equal(waitpid(pid, &wst, 0), pid);
  assert_true(WIFSIGNALED(wst) && WTERMSIG(wst) == SIGKILL);
  close(fds[0]);
  /* rows are flushed at least every 64 rows (and at every event and phase switch) */
  check_killed(path, &ref, 137 - 63);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  char status[64];
  read_attr_str(f, "status", status, sizeof status);
  assert_string_equal(status, "running"); /* killed mid-run: never completed */
  H5Fclose(f);
  free(ref.delta);
  free(ref.q);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

/* Killed at chosen states, each reached deterministically in the child (no timing): right after
 * the 64th row (a write has just filled whole chunks), one row after it, just before and after
 * the second write, late in the dynamic phase, at the first event after row 70 (events are
 * buffered with the rows), inside the second write with half the time series extended
 * (VS_FAULT_KILL "mid-append"), before the status, and in the second snapshot, half copied
 * ("mid-snapshot") or copied but not renamed ("before-publish"). Every file opens normally and
 * holds the run's rows up to its last snapshot, here its last write (at least the rows of the
 * whole writes before the kill), every series as many. */
static void test_killed_at_states(void **state) {
  (void)state;
  vs_case c;
  memrec ref = killed_case(&c);
  const struct {
    long die_at;
    const char *event_after, *fault;
  } at[] = {{64, NULL, NULL}, {65, NULL, NULL},  {127, NULL, NULL},        {129, NULL, NULL},
            {200, NULL, NULL}, {0, "70", NULL}, {0, NULL, "mid-append"},
            {0, NULL, "before-status"}, {0, NULL, "mid-snapshot"}, {0, NULL, "before-publish"}};
  for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
    char path[128];
    snprintf(path, sizeof path, "%s/state%zu.h5", g_dir, i);
    int fds[2];
    const pid_t pid = start_child(&c, path, fds, 1L << 30, at[i].die_at, at[i].event_after,
                                  at[i].fault);
    /* the pipe reads end-of-file once the child is dead; a byte: it finished without the kill */
    struct pollfd pfd = {fds[0], POLLIN, 0};
    char b;
    if (poll(&pfd, 1, 120000) != 1 || read(fds[0], &b, 1) != 0) {
      kill(pid, SIGKILL);
      waitpid(pid, NULL, 0);
      fail_msg("state %zu: the child was not killed there", i);
    }
    int wst;
    assert_int_equal(waitpid(pid, &wst, 0), pid);
    close(fds[0]);
    assert_true(WIFSIGNALED(wst) && WTERMSIG(wst) == SIGKILL);
    /* in the second snapshot's copy, or before its rename: the first, the layout's */
    const int snap = at[i].fault != NULL && strstr(at[i].fault, "snap") != NULL;
    const int pub = at[i].fault != NULL && strstr(at[i].fault, "publish") != NULL;
    check_killed(path, &ref, snap || pub ? 0 : at[i].fault != NULL ? 64 : (at[i].die_at / 64) * 64);
    if (snap || pub) { /* the layout alone, and the working file left beside it */
      hid_t g = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
      hsize_t lo, hi;
      series_rows_range(g, &lo, &hi);
      assert_true(hi == 0);
      H5Fclose(g);
      char part[160];
      snprintf(part, sizeof part, "%s.part", path);
      assert_int_equal(access(part, F_OK), 0);
    }
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    char status[64];
    read_attr_str(f, "status", status, sizeof status);
    assert_string_equal(status, "running");
    H5Fclose(f);
  }
  free(ref.delta);
  free(ref.q);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

/* The CPU time (user and system) of the children waited for so far, us. */
static long children_cpu_us(void) {
  struct rusage ru;
  if (getrusage(RUSAGE_CHILDREN, &ru) != 0) return 0;
  return (long)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1000000L + ru.ru_utime.tv_usec +
         ru.ru_stime.tv_usec;
}

/* In a child: record case c at path with the default options to the end, finish, _exit(0);
 * prof_us > 0: the process dies by SIGPROF (its default action) once it has used that much CPU
 * time, wherever it is then: computing, inside an HDF5 write or flush, copying a snapshot. */
static void child_to_end(const vs_case *c, const char *path, long prof_us) {
  if (prof_us > 0) {
    struct itimerval it = {{0, 0}, {prof_us / 1000000, prof_us % 1000000}};
    if (setitimer(ITIMER_PROF, &it, NULL) != 0) _exit(4);
  }
  vs_error err;
  vs_run *run = NULL;
  vs_output *o = NULL;
  if (vs_run_create(c, &run, &err) != VS_OK || vs_output_create(path, run, "", NULL, &o, &err))
    _exit(2);
  vs_status st = vs_run_execute(run, vs_output_sample, vs_output_event, o, &err);
  st = vs_output_finish(o, run, st, &err, &err);
  vs_output_destroy(&o);
  vs_run_destroy(&run);
  _exit(st == VS_OK ? 0 : 1);
}

/* Killed at moments spread over the whole of a recording run, by its own CPU time (so that a
 * loaded machine moves nothing: no wall-clock race), with the default snapshot policy: at the
 * path there is either nothing yet (before the layout's snapshot) or a record that opens and
 * reads whole, every series with the same rows, each of them the run's (check_killed_data).
 * The kill lands wherever the process is, also inside HDF5's writes and flushes of the working
 * file; runs/kill_stress.sh measures the same over hundreds of wall-clock kills. */
static void test_killed_anywhere(void **state) {
  (void)state;
  vs_case c;
  memrec ref = killed_case(&c);
  char path[128];
  snprintf(path, sizeof path, "%s/anywhere.h5", g_dir);
  /* the whole run's CPU time: the least of three runs to the end (the first can pay for cold
   * caches) */
  long total_us = 0;
  pid_t pid;
  int wst;
  for (int i = 0; i < 3; i++) {
    fflush(NULL);
    pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) child_to_end(&c, path, 0);
    const long before_us = children_cpu_us();
    assert_int_equal(waitpid(pid, &wst, 0), pid);
    assert_true(WIFEXITED(wst) && WEXITSTATUS(wst) == 0);
    const long us = children_cpu_us() - before_us;
    total_us = i == 0 || us < total_us ? us : total_us;
  }
  const int kills = 16;
  int none = 0, whole = 0, ended = 0;
  for (int k = 0; k < kills; k++) {
    char part[160];
    snprintf(part, sizeof part, "%s.part", path);
    unlink(path), unlink(part);
    fflush(NULL);
    pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) child_to_end(&c, path, 1 + total_us * (2 * k + 1) / (2 * kills));
    assert_int_equal(waitpid(pid, &wst, 0), pid);
    if (WIFEXITED(wst)) { /* it ended first: a completed record */
      assert_int_equal(WEXITSTATUS(wst), 0);
      ended++;
      continue;
    }
    assert_true(WIFSIGNALED(wst) && WTERMSIG(wst) == SIGPROF);
    if (access(path, F_OK) != 0) {
      none++;
      continue;
    }
    check_killed_data(path, &ref, 0); /* the sidecar: the tests above */
    whole++;
  }
  print_message("  %d kills over %.3f s of CPU time: %d before the first snapshot, %d records "
                "whole, %d runs ended first\n", kills, 1e-6 * (double)total_us, none, whole, ended);
  assert_true(whole >= kills / 4); /* the kills were in the run, not all before or after it */
  free(ref.delta);
  free(ref.q);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

/* ---------------------------------------------------------------------------------------------
 * Errors and interruption */

static void test_errors(void **state) {
  (void)state;
  vs_case c = small_case(0);
  vs_error err;
  vs_run *run = NULL;
  assert_int_equal(vs_run_create(&c, &run, &err), VS_OK);
  vs_output *o = NULL;
  char path[160];
  snprintf(path, sizeof path, "%s/no/such/dir/x.h5", g_dir);
  /* a path that cannot be written is refused before anything is created (bad input) */
  assert_int_equal(vs_output_create(path, run, NULL, NULL, &o, &err), VS_ERR_INVALID);
  assert_null(o);
  assert_non_null(strstr(err.msg, path));
  vs_output_opts bad;
  vs_output_opts_default(&bad);
  bad.deflate = 10;
  path_in(path, sizeof path, "bad.h5");
  assert_int_equal(vs_output_create(path, run, NULL, &bad, &o, &err), VS_ERR_INVALID);
  assert_non_null(strstr(err.msg, "deflate = 10"));
  assert_int_equal(access(path, F_OK), -1); /* nothing created */
  vs_output_destroy(NULL);
  vs_output_destroy(&o);

  /* finishing twice */
  path_in(path, sizeof path, "twice.h5");
  assert_int_equal(vs_output_create(path, run, NULL, NULL, &o, &err), VS_OK);
  assert_int_equal(vs_output_finish(o, run, VS_OK, NULL, &err), VS_OK);
  assert_int_equal(vs_output_finish(o, run, VS_OK, NULL, &err), VS_ERR_INVALID);
  assert_int_equal(vs_output_error(o)->status, VS_OK);
  vs_output_destroy(&o);

  /* the sidecar of something that is not a record, or of nothing */
  path_in(path, sizeof path, "other.h5");
  hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  H5Fclose(f);
  assert_int_equal(vs_output_write_xdmf(path, 0, &err), VS_ERR_INVALID);
  path_in(path, sizeof path, "missing.h5");
  assert_int_equal(vs_output_write_xdmf(path, 0, &err), VS_ERR_IO);
  assert_non_null(strstr(err.msg, "missing.h5"));
  vs_run_destroy(&run);

  /* interrupted after 5 rows: the run stops, the status says so */
  path_in(path, sizeof path, "int.h5");
  long samples;
  vs_status st;
  run = record(&c, path, NULL, NULL, 5, &samples, &st);
  assert_int_not_equal(st, VS_OK);
  assert_true(samples == 5 || samples == 6); /* a sixth row, or an event, is refused */
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  char status[128];
  read_attr_str(f, "status", status, sizeof status);
  assert_string_equal(status, "failed: interrupted");
  assert_int_equal(check_series_rows(f), 5);
  H5Fclose(f);
  vs_run_destroy(&run);

  /* destroyed without vs_output_finish (after 7 rows, far from a flush): the closed working
   * file, with every row, replaces the snapshot at path, status "running"; nothing left beside
   * it */
  path_in(path, sizeof path, "unfinished.h5");
  assert_int_equal(vs_run_create(&c, &run, &err), VS_OK);
  sink k = {NULL, 0, 7};
  assert_int_equal(vs_output_create(path, run, NULL, NULL, &k.o, &err), VS_OK);
  vs_error rerr0;
  vs_run_execute(run, on_sample, on_event, &k, &rerr0);
  vs_output_destroy(&k.o);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  read_attr_str(f, "status", status, sizeof status);
  assert_string_equal(status, "running");
  assert_int_equal(check_series_rows(f), 7);
  H5Fclose(f);
  char part[200];
  snprintf(part, sizeof part, "%s.part", path);
  assert_int_not_equal(access(part, F_OK), 0);
  snprintf(part, sizeof part, "%s.snap", path);
  assert_int_not_equal(access(part, F_OK), 0);
  vs_run_destroy(&run);

  /* a failed run: its cause is recorded */
  path_in(path, sizeof path, "failed.h5");
  assert_int_equal(vs_run_create(&c, &run, &err), VS_OK);
  assert_int_equal(vs_output_create(path, run, NULL, NULL, &o, &err), VS_OK);
  vs_error rerr;
  vs_error_set(&rerr, VS_ERR_SOLVER, "IDA failed at t = 1 s");
  assert_int_equal(vs_output_finish(o, run, VS_ERR_SOLVER, &rerr, &err), VS_OK);
  vs_output_destroy(&o);
  f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  read_attr_str(f, "status", status, sizeof status);
  assert_string_equal(status, "failed: solver failure: IDA failed at t = 1 s");
  H5Fclose(f);
  vs_run_destroy(&run);
  assert_int_equal(H5Fget_obj_count(H5F_OBJ_ALL, H5F_OBJ_ALL), 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_quasistatic_record),
      cmocka_unit_test(test_dynamic_record),
      cmocka_unit_test(test_killed),
      cmocka_unit_test(test_killed_at_states),
      cmocka_unit_test(test_killed_anywhere),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
