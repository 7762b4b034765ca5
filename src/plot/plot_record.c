/* `voussoir plot`: reading a run's record (the case from /parameters, the arch it simulated,
 * the time series the pictures show, /summary's hinges and limit points) and choosing which
 * recorded hinges each picture labels. */
#define _POSIX_C_SOURCE 200809L
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "h5util.h"
#include "plot_cmd.h"
#include "voussoir/imperfections.h"
#include "voussoir/model.h"
#include "voussoir/units.h"

/* The case key section.name's index in the table, or -1. */
static int key_index(const vs_case *c, const char *section, const char *name) {
  const char *s = NULL, *k = NULL;
  for (int i = 0; vs_case_key(c, i, &s, &k, NULL, NULL, NULL) == 0; i++)
    if (strcmp(s, section) == 0 && strcmp(k, name) == 0) return i;
  return -1;
}

/* Attribute a's value as a case file writes it into buf: a string as it is, a named choice's
 * number as its name, a number in full. 0, or -1 when it is none of these. */
static int attr_value(hid_t a, int key, char *buf, size_t size) {
  hid_t t = H5Aget_type(a);
  const int is_str = t >= 0 && H5Tget_class(t) == H5T_STRING;
  if (t >= 0) H5Tclose(t);
  if (is_str) { /* written as a variable-length string (vs_h5_attr_str) */
    hid_t m = vs_h5_vlstr_type();
    char *v = NULL;
    const int ok = m >= 0 && H5Aread(a, m, &v) >= 0 && v != NULL;
    if (ok) snprintf(buf, size, "%s", v);
    if (v != NULL) H5free_memory(v);
    vs_h5_close(m);
    return ok ? 0 : -1;
  }
  double v = NAN;
  if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0 || !isfinite(v)) return -1;
  const int small = v >= 0.0 && v <= 1000.0 && v == floor(v); /* a named choice's number */
  const char *name = small ? vs_case_key_name_of(key, (int)v) : NULL;
  if (name != NULL) snprintf(buf, size, "%s", name);
  else snprintf(buf, size, "%.17g", v);
  return 0;
}

/* The case from /parameters: every attribute of every section group, applied as a --set. */
static herr_t on_attr(hid_t loc, const char *name, const H5A_info_t *info, void *data) {
  (void)info;
  vs_plotrec *r = data;
  char section[64] = "", value[VS_ARCH_PATH_MAX], buf[VS_ARCH_PATH_MAX + 160];
  ssize_t n = H5Iget_name(loc, section, sizeof section);
  if (n <= 0) return 0;
  const char *sec = strrchr(section, '/');
  sec = sec ? sec + 1 : section;
  const int key = key_index(&r->c, sec, name);
  hid_t a = key >= 0 ? H5Aopen(loc, name, H5P_DEFAULT) : H5I_INVALID_HID;
  const int ok = a >= 0 && attr_value(a, key, value, sizeof value) == 0;
  if (a >= 0) H5Aclose(a);
  if (!ok) return 0;
  snprintf(buf, sizeof buf, "%s.%s=%s", sec, name, value);
  vs_error err;
  vs_case_set(&r->c, buf, &err); /* keys the case does not know are ignored */
  return 0;
}

static herr_t on_section(hid_t g, const char *name, const H5L_info_t *info, void *data) {
  (void)info;
  hid_t s = H5Gopen2(g, name, H5P_DEFAULT);
  if (s < 0) return 0;
  hsize_t idx = 0;
  H5Aiterate2(s, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, on_attr, data);
  H5Gclose(s);
  return 0;
}

void vs_plotrec_free(vs_plotrec *r) {
  vs_geometry_destroy(&r->g);
  free(r->thick);
  free(r->loads);
  free(r->delta);
  free(r->pos);
  free(r->sup);
  free(r->gap_i);
  free(r->gap_e);
  free(r->jN);
  free(r->jM);
  free(r->react);
  free(r->hinge);
  free(r->h);
  free(r->limits);
  free(r->settled);
  if (r->file >= 0) H5Fclose(r->file);
}

/* Whether a recorded hinge lies within the arch's nj joints, on a side, as the writer makes
 * them: what the pictures' labels and the pairing of hinges with open joints (hinge_dist's sums
 * of joint numbers) rely on. */
static int hinge_within(const rec_hinge *h, int nj) {
  return (h->side == 'I' || h->side == 'E') && h->first >= 1 && h->first <= h->last &&
         h->last <= nj && h->onset_first >= 1 && h->onset_first <= h->onset_last &&
         h->onset_last <= nj;
}

/* /summary/hinges (none when missing): 0, or -1 when it is not a table of hinges within the
 * arch (-3: of more rows than the file holds, vs_h5_table_rows). read_limits: the same. */
static int read_hinges(vs_plotrec *r) {
  const char *path = "/summary/hinges";
  const int n = vs_h5_table_rows(r->file, path); /* a whole read fills n records */
  if (n == -1 || n == 0) return 0;
  if (n < 0) return n;
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(rec_hinge)), c1 = H5Tcopy(H5T_C_S1);
  H5Tset_size(c1, 1);
  H5Tset_strpad(c1, H5T_STR_NULLPAD); /* one character, no terminator */
  H5Tinsert(t, "label", HOFFSET(rec_hinge, label), c1);
  H5Tinsert(t, "side", HOFFSET(rec_hinge, side), c1);
  H5Tinsert(t, "first", HOFFSET(rec_hinge, first), H5T_NATIVE_INT);
  H5Tinsert(t, "last", HOFFSET(rec_hinge, last), H5T_NATIVE_INT);
  H5Tinsert(t, "onset_first", HOFFSET(rec_hinge, onset_first), H5T_NATIVE_INT);
  H5Tinsert(t, "onset_last", HOFFSET(rec_hinge, onset_last), H5T_NATIVE_INT);
  H5Tinsert(t, "order", HOFFSET(rec_hinge, order), H5T_NATIVE_INT);
  H5Tinsert(t, "during_fall", HOFFSET(rec_hinge, during_fall), H5T_NATIVE_INT);
  H5Tinsert(t, "open", HOFFSET(rec_hinge, open), H5T_NATIVE_INT);
  H5Tinsert(t, "delta_onset", HOFFSET(rec_hinge, delta_onset), H5T_NATIVE_DOUBLE);
  r->h = calloc((size_t)n, sizeof *r->h);
  hid_t d = H5Dopen2(r->file, path, H5P_DEFAULT);
  int ok = r->h != NULL && d >= 0 && H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, r->h) >= 0;
  for (int i = 0; ok && i < n; i++) ok = hinge_within(&r->h[i], r->nj);
  if (d >= 0) H5Dclose(d);
  H5Tclose(c1);
  H5Tclose(t);
  r->nh = ok ? n : 0;
  return ok ? 0 : -1;
}

static int read_limits(vs_plotrec *r) {
  const char *path = "/summary/limit_points";
  const int n = vs_h5_table_rows(r->file, path);
  if (n == -1 || n == 0) return 0;
  if (n < 0) return n;
  typedef struct {
    double delta, settled;
  } lim;
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(lim));
  H5Tinsert(t, "delta", HOFFSET(lim, delta), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "delta_settled", HOFFSET(lim, settled), H5T_NATIVE_DOUBLE);
  lim *l = calloc((size_t)n, sizeof *l);
  r->limits = calloc((size_t)n, sizeof(double));
  r->settled = calloc((size_t)n, sizeof(double));
  hid_t d = H5Dopen2(r->file, path, H5P_DEFAULT);
  int ok = l && r->limits && r->settled && d >= 0 &&
           H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, l) >= 0;
  for (int i = 0; ok && i < n; i++) {
    r->limits[i] = l[i].delta;
    r->settled[i] = l[i].settled;
  }
  if (d >= 0) H5Dclose(d);
  H5Tclose(t);
  free(l);
  r->nl = ok ? n : 0;
  return ok ? 0 : -1;
}

/* The arch the run simulated: the voussoirs' angles and thicknesses of /imperfections (written
 * when the case scatters them), else those the case's seed draws. */
static vs_status record_geometry(vs_plotrec *r, vs_error *err) {
  vs_imperfections *imp = NULL;
  vs_run_def d;
  vs_case_to_def(&r->c, &d);
  vs_status st = vs_imperfections_draw(&d.imperfections, &d.arch, &imp, err);
  const size_t nb = st == VS_OK ? (size_t)imp->n_blocks : 0;
  double *buf = st == VS_OK ? malloc((nb > 0 ? nb : 1) * sizeof *buf) : NULL;
  if (buf != NULL && vs_h5_read_doubles(r->file, "/imperfections/voussoir_angle", buf, nb) == 0)
    memcpy(imp->angle, buf, nb * sizeof *buf);
  if (buf != NULL && vs_h5_read_doubles(r->file, "/imperfections/voussoir_thickness", buf, nb) == 0)
    memcpy(imp->thickness, buf, nb * sizeof *buf);
  free(buf);
  if (st == VS_OK) st = vs_imperfections_arch(&d.imperfections, &d.arch, imp, &r->g, err);
  if (st == VS_OK && r->c.thickness_cov > 0.0) {
    r->thick = malloc((size_t)imp->n_blocks * sizeof *r->thick);
    if (r->thick == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "out of memory");
    for (int i = 0; r->thick != NULL && i < imp->n_blocks; i++) r->thick[i] = imp->thickness[i];
  }
  vs_imperfections_destroy(&imp);
  return st;
}

/* The live load of a load run (analysis.type = load; /parameters holds its [load] keys) on the
 * record's arch, as the run applied it, and its note for the pictures. */
static vs_status record_loads(vs_plotrec *r, vs_error *err) {
  r->load_note[0] = '\0';
  if (r->c.type != VS_ANALYSIS_LOAD || r->c.kind == VS_LOAD_NONE) return VS_OK;
  vs_run_def d;
  vs_case_to_def(&r->c, &d);
  vs_status st = vs_limit_live_load(r->g, &d.load, &d.fill, &r->loads, &r->n_loads, err);
  if (st != VS_OK) return st;
  if (d.load.kind == VS_LOAD_TILT)
    snprintf(r->load_note, sizeof r->load_note,
             "live load: tilt, lambda x each voussoir's weight horizontally toward the right "
             "support; support held at %.2f mm", r->c.hold_mm);
  else if (d.load.kind == VS_LOAD_PATCH)
    snprintf(r->load_note, sizeof r->load_note,
             "live load: lambda x patch of %g N over %g mm at x = %g mm (arrows); support held "
             "at %.2f mm", r->c.value_N, r->c.width_mm, r->c.x_mm, r->c.hold_mm);
  else
    snprintf(r->load_note, sizeof r->load_note,
             "live load: lambda x %s load of %g N at x = %g mm (arrow); support held at %.2f mm",
             vs_load_kind_name(d.load.kind), r->c.value_N, r->c.x_mm, r->c.hold_mm);
  return VS_OK;
}

int vs_plotrec_open(const char *path, vs_plotrec *r) {
  memset(r, 0, sizeof *r);
  r->file = -1;
  r->collapse = NAN;
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* errors are reported here, not printed by HDF5 */
  r->file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (r->file < 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: cannot open as HDF5", path);
    return -1;
  }
  vs_case_defaults(&r->c);
  if (H5Lexists(r->file, "/parameters", H5P_DEFAULT) <= 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: not a voussoir record (no /parameters)", path);
    return -1;
  }
  hid_t pg = H5Gopen2(r->file, "/parameters", H5P_DEFAULT);
  hsize_t idx = 0;
  H5Literate(pg, H5_INDEX_NAME, H5_ITER_NATIVE, &idx, on_section, r);
  H5Gclose(pg);
  vs_error err;
  if (record_geometry(r, &err) != VS_OK) {
    snprintf(r->msg, sizeof r->msg, "%.200s: %.300s", path, err.msg);
    return -1;
  }
  if (record_loads(r, &err) != VS_OK) {
    snprintf(r->msg, sizeof r->msg, "%.200s: %.300s", path, err.msg);
    return -1;
  }
  r->nb = r->g->n_blocks;
  r->nj = r->g->n_joints;
  r->rows = vs_h5_rows(r->file, "/observables/delta/value");
  /* what the states take in memory, checked against the file before it is allocated */
  const size_t row_bytes = (1 + 3 * (size_t)r->nb + 4 * (size_t)r->nj + 12) * sizeof(double) +
                           (size_t)r->nj;
  char big[300] = "/observables/delta/value declares more values than the file holds";
  if (r->rows < -1 || (r->rows > 0 && vs_h5_check_budget(r->file, "/observables/delta/value",
                                                         (size_t)r->rows, "states", row_bytes,
                                                         big, sizeof big) != 0)) {
    snprintf(r->msg, sizeof r->msg, "%.200s: %s", path, big);
    return -1;
  }
  if (r->rows <= 0) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record holds no state", path);
    return -1;
  }
  const size_t n = (size_t)r->rows;
  r->delta = malloc(n * sizeof(double));
  r->pos = malloc(n * 3 * (size_t)r->nb * sizeof(double));
  r->gap_i = malloc(n * (size_t)r->nj * sizeof(double));
  r->gap_e = malloc(n * (size_t)r->nj * sizeof(double));
  r->react = malloc(n * 6 * sizeof(double));
  r->jN = malloc(n * (size_t)r->nj * sizeof(double));
  r->jM = malloc(n * (size_t)r->nj * sizeof(double));
  r->hinge = malloc(n * (size_t)r->nj);
  if (!r->delta || !r->pos || !r->gap_i || !r->gap_e || !r->react || !r->hinge || !r->jN ||
      !r->jM) {
    snprintf(r->msg, sizeof r->msg, "out of memory");
    return -1;
  }
  const int bad =
      vs_h5_read_doubles(r->file, "/observables/delta/value", r->delta, n) ||
      vs_h5_read_doubles(r->file, "/observables/block_position/value", r->pos,
                         n * 3 * (size_t)r->nb) ||
      vs_h5_read_doubles(r->file, "/observables/joint_gap_i/value", r->gap_i, n * (size_t)r->nj) ||
      vs_h5_read_doubles(r->file, "/observables/joint_gap_e/value", r->gap_e, n * (size_t)r->nj) ||
      vs_h5_read_doubles(r->file, "/observables/reactions/value", r->react, n * 6) ||
      vs_h5_read_doubles(r->file, "/observables/joint_N/value", r->jN, n * (size_t)r->nj) ||
      vs_h5_read_doubles(r->file, "/observables/joint_M/value", r->jM, n * (size_t)r->nj) ||
      vs_h5_read(r->file, "/observables/joint_hinge/value", H5T_NATIVE_SCHAR, r->hinge,
                 n * (size_t)r->nj);
  if (bad) {
    snprintf(r->msg, sizeof r->msg, "%.400s: the record's time series are incomplete", path);
    return -1;
  }
  /* both supports, in a record that has them (not before they could both move) */
  if (H5Lexists(r->file, "/observables/supports", H5P_DEFAULT) > 0) {
    r->sup = malloc(n * 6 * sizeof(double));
    if (r->sup == NULL ||
        vs_h5_read_doubles(r->file, "/observables/supports/value", r->sup, n * 6)) {
      snprintf(r->msg, sizeof r->msg, "%.400s: the record's time series are incomplete", path);
      return -1;
    }
  }
  int tables = read_hinges(r);
  if (tables == 0) tables = read_limits(r);
  if (tables == -3) {
    snprintf(r->msg, sizeof r->msg, "%.300s: /summary/hinges or /summary/limit_points declares "
             "more rows than the file holds (allowed: at most %d x its size + %zu MiB)", path,
             VS_H5_READ_EXPANSION, VS_H5_READ_SLACK >> 20);
    return -1;
  }
  if (tables != 0) {
    snprintf(r->msg, sizeof r->msg,
             "%.300s: /summary/hinges or /summary/limit_points is not a table of rank 1 of the "
             "record's layout (hinges within joints 1..%d, on side I or E)",
             path, r->nj);
    return -1;
  }
  vs_h5_read_doubles(r->file, "/summary/collapse/delta", &r->collapse, 1);
  r->ground = NAN;
  if (H5Lexists(r->file, "/summary/ground", H5P_DEFAULT) > 0 &&
      H5Lexists(r->file, "/summary/ground/level", H5P_DEFAULT) > 0 &&
      vs_h5_read_doubles(r->file, "/summary/ground/level", &r->ground, 1) != 0)
    r->ground = NAN;
  return 0;
}

/* First row at or after delta (the last row if none). */
int vs_plotrec_row_at(const vs_plotrec *r, double delta) {
  for (int i = 0; i < r->rows; i++)
    if (r->delta[i] >= delta - 1e-12) return i;
  return r->rows - 1;
}

static vs_hinge hinge_of(const rec_hinge *rh, int first, int last) {
  return (vs_hinge){.label = rh->label, .side = rh->side, .first = first, .last = last, .open = 1};
}

/* Distance in joints from a group [a, b] to the nearer of a recorded hinge's onset and collapse
 * positions. */
static int hinge_dist(const rec_hinge *rh, int a, int b) {
  const int m = (a + b) / 2, c = (rh->first + rh->last) / 2,
            c0 = (rh->onset_first + rh->onset_last) / 2;
  return abs(c - m) < abs(c0 - m) ? abs(c - m) : abs(c0 - m);
}

/* The groups of consecutive joints of row hj open on one side, [ga[g], gb[g]] (1-based), all of
 * them but the forming hinge's (PIC_ONSET, focus); their number. */
static int open_groups(const vs_plotrec *r, const signed char *hj, pic_kind kind, int focus,
                       int *ga, int *gb) {
  int ng = 0;
  for (int k = 0; k < r->nj;) {
    int e = k;
    while (hj[k] != 0 && e + 1 < r->nj && hj[e + 1] == hj[k]) e++;
    if (hj[k] != 0) {
      const char side = hj[k] == 1 ? 'I' : 'E';
      const int on_focus = kind == PIC_ONSET && side == r->h[focus].side &&
                           e + 1 >= r->h[focus].onset_first && k + 1 <= r->h[focus].onset_last;
      if (!on_focus) ga[ng] = k + 1, gb[ng++] = e + 1;
    }
    k = e + 1;
  }
  return ng;
}

/* The labelled hinges of a picture of the state at support displacement delta whose open joints
 * are those of row `row`, every label one of /summary/hinges and none twice: PIC_COLLAPSE takes
 * them from the vs_plotrec; otherwise each group of consecutive open joints on one side is paired
 * with the nearest same-side recorded hinge formed by delta (within 6 joints of where it formed
 * or of where it was at the collapse), nearest pairs first; groups left unpaired are not labelled.
 * Hinges of the fall are not named (the end of a fall to rest opens dozens: they are in
 * /summary/hinges and /events); their open joints are shaded. Every group and every recorded
 * hinge is considered, however many. */
int vs_plotrec_hinges_at(const vs_plotrec *r, int row, double delta, pic_kind kind, int focus,
                         vs_hinge *out) {
  int n = 0;
  if (kind == PIC_COLLAPSE) {
    for (int i = 0; i < r->nh; i++)
      if (!r->h[i].during_fall && r->h[i].open)
        out[n++] = hinge_of(&r->h[i], r->h[i].first, r->h[i].last);
    return n;
  }
  if (kind == PIC_ONSET)
    out[n++] = hinge_of(&r->h[focus], r->h[focus].onset_first, r->h[focus].onset_last);
  const signed char *hj = r->hinge + (size_t)row * (size_t)r->nj;
  int *ga = malloc(2 * (size_t)r->nj * sizeof *ga);
  unsigned char *used_g = calloc((size_t)r->nj + (size_t)r->nh, 1), *used_h = used_g + r->nj;
  if (ga == NULL || used_g == NULL) {
    free(ga);
    free(used_g);
    return -1;
  }
  int *gb = ga + r->nj;
  const int ng = open_groups(r, hj, kind, focus, ga, gb);
  for (;;) { /* nearest pair first */
    int bi = -1, bg = -1, bd = 7;
    for (int g = 0; g < ng; g++)
      for (int i = 0; i < r->nh; i++) {
        const rec_hinge *rh = &r->h[i];
        const char side = hj[ga[g] - 1] == 1 ? 'I' : 'E';
        if (used_g[g] || used_h[i] || i == focus || rh->side != side ||
            rh->delta_onset > delta + 1e-9 || rh->during_fall)
          continue;
        const int d = hinge_dist(rh, ga[g], gb[g]);
        if (d < bd) bd = d, bi = i, bg = g;
      }
    if (bi < 0) break;
    used_h[bi] = used_g[bg] = 1;
    out[n++] = hinge_of(&r->h[bi], ga[bg], gb[bg]);
  }
  free(ga);
  free(used_g);
  return n;
}

state vs_plotrec_state(const vs_plotrec *r, int row) {
  const size_t o = (size_t)row * (size_t)r->nj;
  return (state){r->pos + (size_t)row * 3 * (size_t)r->nb, r->gap_i + o, r->gap_e + o,
                 r->jN + o, r->jM + o, r->delta[row], row, PIC_ROW, -1,
                 r->sup != NULL ? r->sup + (size_t)row * 6 : NULL};
}
