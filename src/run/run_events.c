/* The run's event log (run_internal.h): every event in order, handed to the caller's event
 * function as it is logged. */
#include <stdlib.h>

#include "run_internal.h"

int vs_run_out_of_memory(vs_run *r) {
  r->nomem = 1;
  return -1;
}

int vs_run_log_event(vs_run *r, vs_event_kind kind, double t, double delta, int joint, char side,
                     char label, int order) {
  if (r->n_events == r->cap_events) {
    int cap = r->cap_events ? 2 * r->cap_events : 64;
    vs_run_event *e = realloc(r->events, (size_t)cap * sizeof *e);
    if (e == NULL) return vs_run_out_of_memory(r);
    r->events = e;
    r->cap_events = cap;
  }
  vs_run_event *e = &r->events[r->n_events++];
  *e = (vs_run_event){.kind = kind, .phase = r->phase, .t = t, .delta = delta, .joint = joint,
                      .side = side, .label = label, .order = order, .load_factor = r->load_now};
  return r->event_fn != NULL ? r->event_fn(r->user, r, e) : 0;
}

