/* The run's callbacks from its solvers (run_internal.h): at each equilibrium, dynamic sample and
 * joint event the hinges are tracked, the events logged and the sample handed on to the caller;
 * the mechanism of the collapse is taken early in its motion and classified. */
#include "voussoir/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mechanism.h"
#include "run_internal.h"
#include "voussoir/damping.h"

/* --- records --- */

void vs_run_open_hinges(const vs_run *r, char *buf, size_t size) {
  vs_hinges_list(vs_hinges_get(r->h, 0), vs_hinges_count(r->h), 1, buf, size);
}

int vs_run_add_limit(vs_run *r, double delta) {
  if (r->n_limits == r->cap_limits) {
    int cap = r->cap_limits ? 2 * r->cap_limits : 8;
    vs_limit_record *l = realloc(r->limits, (size_t)cap * sizeof *l);
    if (l == NULL) return vs_run_out_of_memory(r);
    r->limits = l;
    r->cap_limits = cap;
  }
  vs_limit_record *l = &r->limits[r->n_limits++];
  memset(l, 0, sizeof *l);
  l->delta = delta;
  l->delta_settled = NAN;
  vs_run_open_hinges(r, l->hinges_before, sizeof l->hinges_before);
  vs_run_slips_mark(r); /* the departure of what follows */
  return vs_run_log_event(r, VS_EVENT_LIMIT_POINT, delta / r->dopts.rate, delta, 0, 0, 0, 0);
}

/* The hinge events logged before their hinges were named take the names. */
static void relabel_events(vs_run *r) {
  for (int e = 0; e < r->n_events; e++)
    if (r->events[e].kind == VS_EVENT_HINGE_FORMED && r->events[e].order <= 3 &&
        r->events[e].order <= vs_hinges_count(r->h))
      r->events[e].label = vs_hinges_get(r->h, r->events[e].order - 1)->label;
}

/* Fewer than three hinges formed before the collapse's onset (or the end): name those n A, B
 * from left to right and later ones in order, so that no hinge of the record stays '?'. */
void vs_run_name_first(vs_run *r, int n) {
  if (n >= 3) return;
  vs_hinges_name_first(r->h, n);
  for (int e = 0; e < r->n_events; e++)
    if (r->events[e].kind == VS_EVENT_HINGE_FORMED && r->events[e].order <= vs_hinges_count(r->h))
      r->events[e].label = vs_hinges_get(r->h, r->events[e].order - 1)->label;
}

/* The piers' joints in r->js: each one that opens (from closed) logs that its pier rocks (a
 * base) or that a course joint opened, with the side that stays in contact. */
static int track_piers(vs_run *r, double delta) {
  const vs_geometry *g = r->g;
  for (int k = g->ring; k < g->n_joints && g->pier_courses > 0; k++) {
    const int kind = vs_geometry_pier_joint(g, k, NULL, NULL);
    const char side = kind > 0 ? vs_hinges_joint_side(&r->hopts, &r->js[k]) : 0;
    const char was = r->pier_side[k];
    r->pier_side[k] = side;
    if (side == 0 || side == was) continue;
    if (vs_run_log_event(r, kind == 1 ? VS_EVENT_PIER_ROCKED : VS_EVENT_COURSE_OPENED,
                         delta / r->dopts.rate, delta, k + 1, side, 0, 0) != 0)
      return -1;
  }
  return 0;
}

/* Crack initiation (VS_EVENT_CRACK_INITIATED): an edge of a mortared joint whose opening
 * (the law's, less its initial gap) passes f_t / k_n, where the tensile stress reaches f_t.
 * Logged once per edge, at the support displacement interpolated linearly in the opening
 * between the last state tracked and this one (r->js at delta). */
static int track_cracks(vs_run *r, double delta) {
  const vs_geometry *g = r->g;
  const double before = r->crack_delta;
  r->crack_delta = delta;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_law *l = vs_model_joint_law(r->m, k);
    if (!(l->ft > 0.0)) continue;
    const double h = 0.5 * g->joints[k].length, d0 = l->ft / l->kn;
    const double a = r->js[k].a - l->gap0, w = r->js[k].w - l->gap1;
    for (int e = 0; e < 2; e++) {
      const double margin = d0 + (a + (e ? h : -h) * w); /* d0 - opening */
      const double was = r->crack_margin[2 * k + e];
      r->crack_margin[2 * k + e] = margin;
      if ((r->cracked[k] >> e) & 1 || margin > 0.0) continue;
      r->cracked[k] |= (unsigned char)(1 << e);
      double at = delta;
      if (isfinite(before) && was > 0.0) at = before + (delta - before) * was / (was - margin);
      if (vs_run_log_event(r, VS_EVENT_CRACK_INITIATED, at / r->dopts.rate, at, k + 1,
                           e ? 'E' : 'I', 0, 0) != 0)
        return -1;
    }
  }
  return 0;
}

/* The joints' states as the hinge tracker sees them: a mortared joint's edge can be open only
 * once its mortar has cracked there (the opening past f_t / k_n, or cracked through); before
 * that its opening is the mortar's elastic stretch, not a hinge, and it is seen closed. (A
 * cracked edge is then a hinge past hinges.open_mm, as a dry one.) Dry joints as they are
 * (r->js itself for a dry arch). */
static const vs_joint_state *hinge_view(vs_run *r) {
  const vs_joints_def *jd = &r->def.joints;
  if (!(jd->ft > 0.0)) return r->js;
  const int nj = r->g->n_joints;
  vs_joint_state *v = r->js + nj;
  memcpy(v, r->js, (size_t)nj * sizeof *v);
  for (int k = 0; k < nj; k++) {
    const vs_joint_law *l = vs_model_joint_law(r->m, k);
    if (!(l->ft > 0.0)) continue;
    const double d0 = l->ft / l->kn;
    if (l->crack[0] <= 0.0 && v[k].gap_i < d0) v[k].gap_i = fmin(v[k].gap_i, 0.0);
    if (l->crack[1] <= 0.0 && v[k].gap_e < d0) v[k].gap_e = fmin(v[k].gap_e, 0.0);
  }
  return v;
}

/* Update the hinges at (delta, q); log the hinges that formed. */
/* js: the joints' states at (delta, q) if the caller has them (NULL: evaluated here). */
static int track_hinges(vs_run *r, double delta, const double *q, const vs_joint_state *js) {
  const int before = vs_hinges_count(r->h);
  if (js != NULL) memcpy(r->js, js, (size_t)r->g->n_joints * sizeof *js);
  else vs_model_joint_states(r->m, q, delta, r->js);
  if (vs_hinges_update(r->h, delta, hinge_view(r)) < 0) return vs_run_out_of_memory(r);
  for (int i = before; i < vs_hinges_count(r->h); i++) {
    const vs_hinge *hg = vs_hinges_get(r->h, i);
    /* at its interpolated onset: delta = rate t holds for every event */
    if (vs_run_log_event(r, VS_EVENT_HINGE_FORMED, hg->delta_onset / r->dopts.rate,
                         hg->delta_onset, hg->first, hg->side, hg->label, hg->order) != 0)
      return -1;
  }
  /* the first three get their labels together: fix up the events logged before */
  if (before < 3 && vs_hinges_count(r->h) >= 3) relabel_events(r);
  if (track_cracks(r, delta) != 0) return -1;
  return track_piers(r, delta);
}

/* --- callbacks from the solvers --- */

/* Cumulative solver statistics: the finished segments and phases plus the one under way. */
static void fill_counters(const vs_run *r, vs_run_sample *s) {
  s->newton_iterations = r->totals.newton_iterations +
                         (r->live_path != NULL ? r->live_path->newton_iterations : 0);
  s->ida_steps = r->dtot.steps + (r->live_dyn != NULL ? r->live_dyn->steps : 0);
  s->fall_steps = r->fres.steps; /* the fall counts into r->fres as it goes */
  s->ida_newton_iterations =
      r->dtot.newton_iterations + (r->live_dyn != NULL ? r->live_dyn->newton_iterations : 0);
}

/* The ringing window (vs_dyn_opts's ring_window) of an arch with mortar: dynamic.ring_periods
 * periods of its lowest natural frequency under self-weight (r->modal), once the modes are
 * known; none when every joint is dry (imperfections.debonded may have taken all the mortar). */
static void ring_window(vs_run *r) {
  if (r->dyn == NULL || r->modal.n_modes < 1) return;
  int bonded = 0;
  for (int k = 0; k < r->g->n_joints && !bonded; k++) {
    const vs_joint_law *law = vs_model_joint_law(r->m, k);
    bonded = law->ft > 0.0 || law->c > 0.0;
  }
  if (bonded)
    vs_dynamic_set_ring_window(r->dyn, r->def.dynamic.ring_periods / r->modal.freq_hz[0]);
}

/* HOOK (damping): at the self-weight equilibrium, the natural frequencies; Rayleigh damping is
 * fitted to the two lowest; the ratio every mode gets from the model's damping. Returns non-zero
 * (with r->modal_st, r->modal_err) when the damping cannot be set. */
static int damping_setup(vs_run *r, double delta, const double *q) {
  r->modal_done = 1;
  vs_error_clear(&r->modal_err);
  if (3 * r->def.arch.voussoirs > VS_MODAL_MAX_DOF) return 0; /* not computed (not rayleigh: checked) */
  r->modal_st = vs_modal_compute(r->m, q, delta, VS_MODAL_MAX, &r->modal, &r->modal_err);
  const int rayleigh = r->def.dynamic.damping_model == VS_DAMPING_RAYLEIGH;
  if (r->modal_st != VS_OK && !rayleigh) { /* the modes are only reported: none, then */
    r->modal_st = VS_OK;
    return 0;
  }
  if (r->modal_st != VS_OK) return 1;
  ring_window(r);
  if (rayleigh && r->modal.n_modes >= 2) {
    r->modal_st = vs_damping_apply(r->m, VS_DAMPING_RAYLEIGH, r->def.dynamic.damping, r->modal.omega[0],
                                   r->modal.omega[1], &r->ray_alpha, &r->ray_beta, &r->modal_err);
    if (r->modal_st == VS_OK)
      r->modal_st = vs_modal_damping_ratios(r->m, q, delta, &r->modal, &r->modal_err);
  }
  return r->modal_st != VS_OK;
}

int vs_run_on_equilibrium(void *user, double delta, const double *q, const vs_model *m) {
  (void)m;
  vs_run *r = user;
  if (!r->modal_done && damping_setup(r, delta, q) != 0) return 1;
  r->delta = delta;
  r->t = delta / r->dopts.rate;
  r->phase = VS_PHASE_QUASISTATIC;
  if (!r->frozen) { /* a motion that comes to rest was not the collapse: no mechanism of it */
    r->n_mech = 0;
    r->mech_t = NAN;
  }
  if (track_hinges(r, delta, q, NULL) != 0) return 1;
  if (vs_run_slips_at_equilibrium(r, delta, r->js) != 0) return 1;
  if (r->pending_snap >= 0) { /* the first equilibrium after a snap-through */
    vs_limit_record *l = &r->limits[r->pending_snap];
    r->pending_snap = -1;
    l->delta_settled = delta;
    vs_run_open_hinges(r, l->hinges_after, sizeof l->hinges_after);
    if (vs_run_log_event(r, VS_EVENT_SNAP_SETTLED, r->t, delta, 0, 0, 0, 0) != 0) return 1;
  }
  vs_model_support_reactions(r->m, q, delta, r->react);
  memcpy(r->react_eq, r->react, sizeof r->react);
  /* the joints' states of track_hinges, at this equilibrium */
  vs_run_sample s = {.phase = VS_PHASE_QUASISTATIC, .t = r->t, .delta = delta, .q = q,
                     .reactions = r->react, .joints = r->js,
                     .gravity = vs_model_gravity_energy(r->m, q)};
  for (int k = 0; k < r->g->n_joints; k++) s.elastic += r->js[k].energy;
  fill_counters(r, &s);
  return r->sample_fn != NULL ? r->sample_fn(r->user, r, &s) : 0;
}

/* The mechanism of a collapse is read early in its motion, once the kinetic energy beyond that of
 * the arch moving bodily at the support's rate has passed this fraction of the collapse threshold
 * (blocks have then moved by hundredths of a millimetre): later, the falling arch opens joints
 * everywhere. */
static const double VS_ONSET_FRACTION = 0.01;

/* Every hinge formed so far, and the open ones, as they are now: nothing is left out, however
 * many (a long deformable arch can open many). 0, or -1 when out of memory. */
static int snapshot_onset(vs_run *r) {
  const int n = vs_hinges_count(r->h);
  if (n > r->cap_onset) {
    vs_hinge *o = realloc(r->onset, (size_t)n * sizeof *o);
    if (o != NULL) r->onset = o;
    vs_hinge *a = o != NULL ? realloc(r->onset_all, (size_t)n * sizeof *a) : NULL;
    if (a == NULL) return vs_run_out_of_memory(r);
    r->onset_all = a;
    r->cap_onset = n;
  }
  r->n_onset = 0;
  r->hinges_at_onset = n;
  vs_run_slips_onset(r);
  for (int i = 0; i < n; i++) {
    r->onset_all[i] = *vs_hinges_get(r->h, i);
    if (r->onset_all[i].open) r->onset[r->n_onset++] = r->onset_all[i];
  }
  return 0;
}

/* The mechanism is taken at the collapse criterion (the first three hinges, the onset snapshot):
 * the hinges of the fall after it never change the reported mode or hinges. 0, or -1 when out
 * of memory. */
static int freeze_mechanism(vs_run *r) {
  if (!r->onset_taken && snapshot_onset(r) != 0) return -1;
  r->onset_taken = 1;
  r->frozen = 1;
  return 0;
}

/* A mortared arch's mechanism at this sample of the motion (v its velocities): the hinges
 * it turns about (mechanism.h), kept until the collapse freezes them. The joints' states are
 * the hinge tracker's view of them (track_hinges has just set it). */
static void track_mechanism(vs_run *r, double t, double delta, const double *v) {
  if (r->mech == NULL) return; /* a dry arch */
  const int n = r->g->pier_courses > 0 ? r->g->ring : r->g->n_joints; /* the tracker's */
  vs_mechanism_joint_rates(r->m, v, delta, r->dopts.rate, r->mech_w);
  r->n_mech = vs_mechanism_active(n, r->mech_w, hinge_view(r), &r->hopts, r->mech);
  r->mech_t = t;
  for (int i = 0; i < r->n_mech; i++) { /* the tracked hinge it is: open there, of its side,
                                           within hinges.migrate joints; the nearest */
    const vs_active_hinge *a = &r->mech[i];
    int best = r->hopts.migrate + 1;
    r->mech_hinge[i] = -1;
    for (int k = 0; k < vs_hinges_count(r->h); k++) {
      const vs_hinge *hg = vs_hinges_get(r->h, k);
      if (hg->side != a->side || !hg->open) continue;
      const int d = a->last < hg->first ? hg->first - a->last
                    : hg->last < a->first ? a->first - hg->last : 0;
      if (d < best) {
        best = d;
        r->mech_hinge[i] = k;
      }
    }
  }
}

int vs_run_on_dyn_sample(void *user, double t, double delta, const double *q, const double *v,
                         const vs_energy *e) {
  vs_run *r = user;
  r->delta = delta;
  r->t = t;
  r->phase = VS_PHASE_DYNAMIC;
  /* the joints' states the integrator evaluated at this state (its commit and energies) */
  const vs_joint_state *js = vs_dynamic_joint_states(r->dyn);
  if (!r->frozen && track_hinges(r, delta, q, js) != 0) return 1;
  if (!r->frozen) track_mechanism(r, t, delta, v);
  if (!r->frozen && vs_run_slips_in_motion(r, t, delta) != 0) return 1;
  const int falling = r->live_dyn != NULL && isfinite(r->live_dyn->t_collapse);
  if (falling) { /* the onset is the collapse's: debris at rest and moving again is not one */
  } else if (e->kinetic < r->dopts.rest_ke) {
    r->onset_taken = 0;
    vs_run_slips_mark(r); /* at rest: a motion that collapses departs from here */
  } else if (!r->onset_taken &&
             e->kinetic >= r->ke_move + VS_ONSET_FRACTION * (r->dopts.collapse_ke - r->ke_move)) {
    if (snapshot_onset(r) != 0) return 1;
    r->onset_taken = 1;
  }
  /* the sample at the collapse criterion: nothing after it counts */
  if (!r->frozen && r->live_dyn != NULL && !isnan(r->live_dyn->t_collapse) &&
      freeze_mechanism(r) != 0)
    return 1;
  vs_dynamic_reactions(r->dyn, r->react);
  vs_run_sample s = {.phase = VS_PHASE_DYNAMIC, .t = t, .delta = delta, .q = q, .v = v,
                     .energy = e, .reactions = r->react, .joints = js,
                     .elastic = e->elastic, .gravity = e->gravity};
  fill_counters(r, &s);
  return r->sample_fn != NULL ? r->sample_fn(r->user, r, &s) : 0;
}

int vs_run_on_dyn_event(void *user, const vs_dyn_event *ev, const double *q) {
  vs_run *r = user;
  if (!r->frozen && track_hinges(r, ev->delta, q, vs_dynamic_joint_states(r->dyn)) != 0) return 1;
  char label = 0;
  for (int i = 0; i < vs_hinges_count(r->h); i++) {
    const vs_hinge *hg = vs_hinges_get(r->h, i);
    if (hg->side == ev->side && ev->joint >= hg->first - r->hopts.migrate &&
        ev->joint <= hg->last + r->hopts.migrate && (hg->open || !ev->opened))
      label = hg->label;
  }
  return vs_run_log_event(r, ev->opened ? VS_EVENT_JOINT_OPENED : VS_EVENT_JOINT_CLOSED, ev->t,
                          ev->delta, ev->joint, ev->side, label, 0);
}

int vs_run_on_fall_sample(void *user, double t, double delta, const double *q, const double *v,
                          const vs_energy *e) {
  vs_run *r = user;
  r->delta = delta;
  r->t = t;
  r->phase = VS_PHASE_FALL;
  vs_fall_reactions(r->fall, r->react);
  vs_run_sample s = {.phase = VS_PHASE_FALL, .t = t, .delta = delta, .q = q, .v = v,
                     .energy = e, .reactions = r->react, .joints = vs_fall_joint_states(r->fall),
                     .elastic = e->elastic, .gravity = e->gravity};
  fill_counters(r, &s);
  return r->sample_fn != NULL ? r->sample_fn(r->user, r, &s) : 0;
}

/* --- the mechanism of the collapse --- */

static int cmp_hinge_first(const void *x, const void *y) {
  const vs_hinge *a = x, *b = y;
  return (a->first > b->first) - (a->first < b->first);
}

/* The collapse's hinges, from the snapshot taken at its criterion (freeze_mechanism): named,
 * left to right, with room for their side pattern. 0, or -1 when out of memory. */
static int collapse_hinges(vs_run *r) {
  vs_collapse_record *c = &r->collapse;
  char *pu = realloc(r->pattern_u, 2 * (size_t)r->n_onset + 1);
  if (pu == NULL) return vs_run_out_of_memory(r);
  r->pattern_u = pu;
  vs_run_name_first(r, r->hinges_at_onset); /* the snapshot's hinges take the names too */
  for (int i = 0; i < r->hinges_at_onset; i++) r->onset_all[i].label = vs_hinges_get(r->h, i)->label;
  for (int i = 0; i < r->n_onset; i++) r->onset[i].label = vs_hinges_get(r->h, r->onset[i].order - 1)->label;
  if (r->n_onset > 1) /* (a sliding mechanism may have none: no qsort of a NULL array) */
    qsort(r->onset, (size_t)r->n_onset, sizeof r->onset[0], cmp_hinge_first);
  c->n_hinges = r->n_onset;
  c->hinges = r->onset;
  memcpy(c->reactions_limit, r->react_eq, sizeof r->react_eq);
  return 0;
}

int vs_run_record_collapse(vs_run *r, const vs_dyn_result *d) {
  vs_collapse_record *c = &r->collapse;
  c->found = 1;
  c->t_criterion = d->t_collapse;
  c->delta_detected = d->t_collapse * r->dopts.rate;
  c->t_onset = (d->onset_found && d->t_motion <= d->t_collapse) ? d->t_motion : NAN;
  /* the departure: the limit point the motion started from, or (--dynamic) its located onset */
  c->delta = (!r->def.dynamic.full && r->n_limits > 0) ? r->limits[r->n_limits - 1].delta
                                             : c->t_onset * r->dopts.rate;
  c->t = c->delta / r->dopts.rate;
  /* (frozen at the collapse criterion's sample) */
  if (!r->frozen && freeze_mechanism(r) != 0) return -1;
  if (collapse_hinges(r) != 0) return -1;
  vs_run_slips_mechanism(r, NULL);
  return 0;
}

int vs_run_record_sliding(vs_run *r, const vs_path_result *p) {
  vs_collapse_record *c = &r->collapse;
  c->found = 1;
  c->delta = p->delta_limit; /* where the joints of the mechanism were all sliding */
  c->t = c->delta / r->dopts.rate;
  c->delta_detected = p->delta_fail; /* where the force on the support was seen stationary */
  c->t_criterion = c->delta_detected / r->dopts.rate;
  c->t_onset = NAN;
  r->onset_taken = 0; /* the hinges open at the end of the path */
  r->n_mech = 0;      /* no motion: no mechanism read from one */
  if (freeze_mechanism(r) != 0 || collapse_hinges(r) != 0) return -1;
  vs_model_joint_states(r->m, r->q, r->delta, r->js);
  vs_run_slips_mechanism(r, r->js);
  return 0;
}

/* A mortared arch's mechanism hinges take the labels of the tracked hinges they are (matched
 * where they were read: track_mechanism), their sides the pattern; the mode is read from them
 * when the hinges open at the collapse's onset fit none (docs/mortar.md, "The mode of a
 * mortared arch"). */
static void classify_mechanism(vs_run *r) {
  r->mode_from_mech = 0;
  if (r->mech == NULL) return;
  if (!r->collapse.found) r->n_mech = 0; /* a collapse in motion reads it (a sliding one not) */
  for (int i = 0; i < r->n_mech; i++)
    r->mech[i].label = r->mech_hinge[i] >= 0 ? vs_hinges_get(r->h, r->mech_hinge[i])->label : 0;
  size_t used = 0; /* 2 n_joints + 1 bytes hold any */
  for (int i = 0; i < r->n_mech; i++) {
    if (i > 0) r->pattern_m[used++] = '-';
    r->pattern_m[used++] = r->mech[i].side;
  }
  r->pattern_m[used] = '\0';
  if (r->mode == NULL && r->n_mech > 0 && r->pattern0[0] != '\0') {
    r->mode = vs_hinges_mode(r->pattern0, r->pattern_m);
    r->mode_from_mech = r->mode != NULL;
  }
}

/* Modes (docs/model.md, "Vocabulary") from the first three hinges (A, B, C, left to right) and
 * the hinges at the collapse. */
void vs_run_classify(vs_run *r) {
  r->mode = NULL;
  vs_hinges_pattern_first(r->h, r->pattern0, sizeof r->pattern0);
  if (r->collapse.found && r->pattern_u != NULL) /* it holds them all (vs_run_record_collapse) */
    vs_hinges_side_pattern(r->collapse.hinges, r->collapse.n_hinges, r->pattern_u,
                           2 * (size_t)r->collapse.n_hinges + 1);
  if (r->collapse.found && r->pattern0[0] != '\0')
    r->mode = vs_hinges_mode(r->pattern0, r->pattern_u);
  classify_mechanism(r);
}
