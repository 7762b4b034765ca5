/* The record's /events: one packed row per event of the run, buffered and appended with the
 * rows, rewritten from the run's log when the run is finished. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "record_internal.h"

static const char *event_kind_name(vs_event_kind k) {
  switch (k) {
  case VS_EVENT_JOINT_OPENED: return "joint_opened";
  case VS_EVENT_JOINT_CLOSED: return "joint_closed";
  case VS_EVENT_HINGE_FORMED: return "hinge_formed";
  case VS_EVENT_LIMIT_POINT: return "limit_point";
  case VS_EVENT_SNAP_SETTLED: return "snap_settled";
  case VS_EVENT_COLLAPSE: return "collapse";
  case VS_EVENT_JOINT_SLIPPED: return "joint_slipped";
  case VS_EVENT_PIER_ROCKED: return "pier_rocked";
  case VS_EVENT_COURSE_OPENED: return "course_opened";
  case VS_EVENT_CRACK_INITIATED: return "crack_initiated";
  }
  return "unknown";
}

/* The compound type of event_row: native members (memory) or little-endian ones (file); on a
 * little-endian host the two are equal and a write converts nothing. */
static hid_t event_type(int native) {
  hid_t t = H5Tcreate(H5T_COMPOUND, EV_SIZE);
  hid_t c1 = vs_h5_fixed_str_type(1), vs = vs_h5_fixed_str_type(EV_KIND_LEN);
  herr_t rc = (t >= 0 && c1 >= 0 && vs >= 0) ? 0 : -1;
  hid_t f64 = native ? H5T_NATIVE_DOUBLE : H5T_IEEE_F64LE,
        i32 = native ? H5T_NATIVE_INT32 : H5T_STD_I32LE,
        i8 = native ? H5T_NATIVE_INT8 : H5T_STD_I8LE;
  if (rc >= 0) rc = H5Tinsert(t, "time", EV_TIME, f64);
  if (rc >= 0) rc = H5Tinsert(t, "delta", EV_DELTA, f64);
  if (rc >= 0) rc = H5Tinsert(t, "joint", EV_JOINT, i32);
  if (rc >= 0) rc = H5Tinsert(t, "side", EV_SIDE, c1);
  if (rc >= 0) rc = H5Tinsert(t, "label", EV_LABEL, c1);
  if (rc >= 0) rc = H5Tinsert(t, "phase", EV_PHASE, i8);
  if (rc >= 0) rc = H5Tinsert(t, "order", EV_ORDER, i32);
  if (rc >= 0) rc = H5Tinsert(t, "kind", EV_KIND, vs);
  if (rc >= 0) rc = H5Tinsert(t, "load_factor", EV_LOAD, f64);
  vs_h5_close(c1);
  vs_h5_close(vs);
  if (rc < 0) {
    vs_h5_close(t);
    return H5I_INVALID_HID;
  }
  return t;
}

static const char EVENT_UNITS[] = "s,m,,,,,,,1";

herr_t vs_record_events_create(vs_output *o) {
  o->ev_mtype = event_type(1);
  hid_t ft = event_type(0);
  hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {64};
  hid_t sp = H5Screate_simple(1, dims, maxdims), dcpl = H5Pcreate(H5P_DATASET_CREATE);
  herr_t rc = (ft >= 0 && sp >= 0 && dcpl >= 0) ? 0 : -1;
  if (rc >= 0) rc = H5Pset_chunk(dcpl, 1, chunk);
  if (rc >= 0 && o->opts.deflate > 0) rc = H5Pset_deflate(dcpl, (unsigned)o->opts.deflate);
  if (rc >= 0) o->events = H5Dcreate2(o->file, "events", ft, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  rc = o->events >= 0 ? vs_h5_attr_str(o->events, "unit", EVENT_UNITS) : -1;
  if (rc >= 0)
    rc = vs_h5_attr_str(
        o->events, "description",
        "events in order. unit: one entry per field, comma-separated. kind: "
        "joint_opened/joint_closed (an edge crossed hinges.open_mm; side = the hinge side), "
        "hinge_formed (label A-E, order = order of appearance, delta = interpolated "
        "onset), limit_point, snap_settled, collapse, joint_slipped (the joint began to "
        "slide, or to slide the other way; side = the edge toward which its voussoir slides "
        "relative to the body across it), pier_rocked/course_opened (a pier's base or course "
        "joint opened; side = the edge in contact, I inner, E outer), crack_initiated (a mortared "
        "joint's tensile stress reached f_t at an edge; side = the edge that cracks). joint: 1-based, 0 if none; "
        "phase: 0 quasi-static, 1 dynamic (IDA), 2 the rigid fall after the collapse; "
        "load_factor: on a load path (analysis.type = load, delta the held support "
        "displacement), lambda at the equilibrium where the event was found (a collapse: the "
        "peak's), NaN elsewhere");
  vs_h5_close(dcpl);
  vs_h5_close(sp);
  vs_h5_close(ft);
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
  memcpy(r.b + EV_LOAD, &e->load_factor, 8);
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
  vs_h5_close(ms);
  vs_h5_close(fs);
  return rc;
}

/* Append the buffered events to /events (no flush). */
vs_status vs_record_events_append(vs_output *o) {
  if (o->ev_pending == 0) return VS_OK;
  if (events_write(o, (hsize_t)o->n_events, (hsize_t)o->ev_pending, o->ev_buf) < 0)
    return vs_h5_fail(&o->err, o->path, "cannot append to /events");
  o->n_events += o->ev_pending;
  o->ev_pending = 0;
  return VS_OK;
}

/* Rewrite /events from the run's log: the first three hinges get their labels together, after
 * their events were emitted. */
vs_status vs_record_events_rewrite(vs_output *o, const vs_run *run) {
  const int n = vs_run_event_count(run);
  event_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  if (rows == NULL) return vs_error_set(&o->err, VS_ERR_NOMEM, "output: out of memory");
  for (int i = 0; i < n; i++) rows[i] = event_to_row(vs_run_event_get(run, i));
  herr_t rc = events_write(o, 0, (hsize_t)n, rows);
  free(rows);
  if (rc < 0) return vs_h5_fail(&o->err, o->path, "cannot rewrite /events");
  o->n_events = n;
  return VS_OK;
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
