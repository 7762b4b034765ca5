/* One run: case -> geometry -> model -> quasi-static path; at each limit point the dynamic phase
 * (IDA) until the motion settles (a snap-through: the path resumes) or collapses. Hinges are
 * updated at every equilibrium and dynamic sample; events and limit points are recorded
 * (run_sample.c: the solvers' callbacks that do it). */
#include "voussoir/run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"
#include "voussoir/damping.h"
#include "voussoir/imperfections.h"
#include "voussoir/support.h"
#include "voussoir/units.h"
#include "wall_clock.h"

/* Rest is at most this fraction of the collapse threshold (fast loading would otherwise put the
 * rest threshold above it). */
static const double VS_REST_OF_COLLAPSE = 0.01;

/* The speed at which the supports deform the arch (m/s), for the energy levels of rest and
 * collapse: the right support's rate when it moves alone (as always), else the largest relative
 * speed of the two supports along their motions, so that moving both supports, or the whole
 * arch bodily, changes neither level (the arch feels only the relative motion). */
static double deform_speed(const vs_support_def *s) {
  const double v = vs_support_loading_rate(s);
  if (s->left_rate == 0.0 && s->left_path.n == 0 && s->right_path.n == 0) return v;
  vs_support_motion mo[2];
  if (vs_support_motion_from_def(s, 0, &mo[0], NULL) != VS_OK ||
      vs_support_motion_from_def(s, 1, &mo[1], NULL) != VS_OK)
    return v; /* refused when the model is set up */
  double k = 0.0;
  for (int side = 0; side < 2; side++)
    for (int i = 0; i < mo[side].n; i++) { /* at every corner of either */
      double l[3], r[3];
      vs_support_motion_at(&mo[0], mo[side].d[i], NULL, l);
      vs_support_motion_at(&mo[1], mo[side].d[i], NULL, r);
      k = fmax(k, hypot(r[0] - l[0], r[1] - l[1]));
    }
  return k > 0.0 ? k * v : v;
}

static void dyn_opts_from_def(const vs_run_def *d, const vs_geometry *g, vs_dyn_opts *o) {
  double mass = 0.0;
  for (int i = 0; i < g->n_blocks; i++) mass += g->blocks[i].mass;
  o->rate = vs_support_loading_rate(&d->support); /* delta = rate t */
  const double w = deform_speed(&d->support);
  o->rtol = d->dynamic.rtol;
  o->atol_q = d->dynamic.atol_q;
  o->open = d->hinges.open;
  /* the collapse threshold rides on the kinetic energy of the arch moving bodily at the
   * support's rate, which fast loading reaches without any collapse; rest stays well below it */
  o->collapse_ke = d->dynamic.collapse_ke * vs_geometry_weight(g) * g->thickness +
                   0.5 * mass * w * w;
  o->rest_ke = fmin(d->dynamic.rest_factor * 0.5 * mass * w * w,
                    VS_REST_OF_COLLAPSE * o->collapse_ke);
  o->rest_time = d->dynamic.rest_time;
  o->fall_time = d->dynamic.fall_time;
  o->max_delta = d->support.max_delta;
  o->sample_dt = d->dynamic.sample_dt;
  o->settle = 1;
  o->impact = d->dynamic.damping_model == VS_DAMPING_IMPACT;
}

/* The rest window in the fall: the shorter of rest_s and this (s), a hundred periods of the
 * arch's lowest mode and long enough for debris that is still rocking to show it (as the
 * penalty scheme's fall in dynamic_run.c). */
static const double VS_RUN_FALL_REST = 0.1;

static vs_status fall_create(vs_run *r, vs_error *err) {
  const vs_fall_def *f = &r->def.fall;
  vs_fall_opts fo;
  vs_fall_opts_default(&fo);
  fo.step = f->step;
  fo.slow_step = f->slow_step;
  fo.slow_speed = f->slow_speed;
  fo.max_sweeps = f->max_sweeps;
  fo.solver = f->solver;
  fo.rate = r->dopts.rate;
  fo.rest_ke = r->dopts.rest_ke;
  fo.rest_time = fmin(r->def.dynamic.rest_time, VS_RUN_FALL_REST);
  fo.duration = r->def.dynamic.fall_time;
  fo.sample_dt = r->def.dynamic.sample_dt;
  fo.ground = f->ground;
  fo.deadline = &r->deadline;
  return vs_fall_create(r->m, &fo, NULL, NULL, &r->fall, err);
}

/* The arch and the imperfections drawn on it: for a blocks file, the blocks first (they say how
 * many blocks and joints the draws cover), else the draws first (they shape the arch). */
static vs_status arch_and_imperfections(vs_run *r, vs_error *err) {
  const vs_run_def *d = &r->def;
  if (d->arch.shape != VS_SHAPE_FILE) {
    vs_status st = vs_imperfections_draw(&d->imperfections, &d->arch, &r->imp, err);
    if (st == VS_OK) st = vs_imperfections_arch(&d->imperfections, &d->arch, r->imp, &r->g, err);
    return st;
  }
  vs_status st = vs_imperfections_arch(&d->imperfections, &d->arch, NULL, &r->g, err);
  if (st == VS_OK)
    st = vs_imperfections_draw_counts(&d->imperfections, &d->arch, r->g->n_blocks,
                                      r->g->n_joints, &r->imp, err);
  return st;
}

/* A blocks file's interfaces with a law of their own; a pinned support must have one joint (it
 * turns about that joint's centre). */
static vs_status own_laws(vs_run *r, vs_error *err) {
  const vs_geometry *g = r->g;
  const vs_joints_def *jd = &r->def.joints;
  int on[2] = {0, 0};
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    for (int s = 0; s < 2; s++) on[s] += j->a == (s ? VS_SUPPORT_RIGHT : VS_SUPPORT_LEFT) ||
                                         j->b == (s ? VS_SUPPORT_RIGHT : VS_SUPPORT_LEFT);
    if (!(j->kn > 0.0 || j->ks_ratio > 0.0 || j->mu > 0.0)) continue;
    vs_joint_law law = *vs_model_joint_law(r->m, k);
    law.kn = j->kn > 0.0 ? j->kn : jd->kn;
    law.ks = (j->ks_ratio > 0.0 ? j->ks_ratio : jd->ks / jd->kn) * law.kn;
    law.mu = j->mu > 0.0 ? j->mu : jd->mu;
    vs_status st = vs_model_set_joint_law(r->m, k, &law, err);
    if (st != VS_OK) return st;
  }
  const vs_support_kind kind[2] = {r->def.support.left_kind, r->def.support.right_kind};
  for (int s = 0; s < 2; s++)
    if (kind[s] == VS_SUPPORT_PINNED && on[s] != 1)
      return vs_error_set(err, VS_ERR_INVALID, "support.%s_kind = pinned: the %s support has %d "
                          "joints (allowed: fixed, or pinned with one joint: it turns about its "
                          "centre)", s ? "right" : "left", s ? "right" : "left", on[s]);
  return VS_OK;
}

vs_status vs_run_create(const vs_case *c, vs_run **out, vs_error *err) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  vs_status st = vs_run_create_def(&d, out, err);
  if (st == VS_OK) {
    (*out)->c = *c;
    (*out)->have_case = 1;
  }
  return st;
}

/* What a run computes: the support's path, or the live load's after a held support
 * displacement (analysis.type = load); the limit analysis is vs_limit_analyse's, refused here
 * by name. */
static vs_status check_analysis(const vs_run_def *d, vs_error *err) {
  if (d->analysis.type == VS_ANALYSIS_LIMIT && !(d->analysis.hold > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.type = limit: a limit analysis of the initial configuration has "
                        "no path to run (voussoir run prints it; the library's vs_limit_analyse "
                        "computes it; with analysis.hold_mm > 0 the run follows the support's "
                        "path to the hold and analyses the arch there)");
  if (d->analysis.type == VS_ANALYSIS_LIMIT) {
    if (d->dynamic.full)
      return vs_error_set(err, VS_ERR_INVALID,
                          "analysis.type = limit with dynamic.full = 1: the path to the hold is "
                          "quasi-static (allowed: dynamic.full = 0)");
    return VS_OK;
  }
  if (d->analysis.type == VS_ANALYSIS_LOAD) {
    if (d->load.kind == VS_LOAD_NONE)
      return vs_error_set(err, VS_ERR_INVALID,
                          "analysis.type = load needs a live load (load.kind = none; allowed: "
                          "point, line, patch, tilt)");
    if (d->dynamic.full)
      return vs_error_set(err, VS_ERR_INVALID,
                          "analysis.type = load with dynamic.full = 1: the load path is "
                          "quasi-static (allowed: dynamic.full = 0)");
    return VS_OK;
  }
  if (d->analysis.hold != 0.0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.hold_mm = %g: a held support displacement needs analysis.type "
                        "= load or limit",
                        d->analysis.hold / VS_MM);
  if (d->load.kind != VS_LOAD_NONE)
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.kind = %s: the support's path carries no live load (allowed with "
                        "analysis.type = support: none; a live load: analysis.type = load or "
                        "limit)",
                        vs_load_kind_name(d->load.kind));
  return VS_OK;
}

/* Mortar (vs_joints_def ft, c, gf, gc; SI): each finite and >= 0, and a softening that ends
 * beyond the peak's opening (gf > ft^2 / (2 kn), gc > c^2 / (2 ks): no snap-back within a
 * joint), as the case's validation has it for a def built by the library's caller. */
static vs_status check_mortar(const vs_run_def *d, vs_error *err) {
  const vs_joints_def *j = &d->joints;
  static const char *names[4] = {"tensile_MPa", "cohesion_MPa", "gf_N_mm", "gc_N_mm"};
  const double v[4] = {j->ft / VS_MPA, j->c / VS_MPA, j->gf / VS_N_MM, j->gc / VS_N_MM};
  for (int i = 0; i < 4; i++)
    if (!(v[i] >= 0.0 && v[i] <= (i < 2 ? 100.0 : 1000.0)))
      return vs_error_set(err, VS_ERR_INVALID, "joints.%s = %g (allowed: 0 .. %g)", names[i],
                          v[i], i < 2 ? 100.0 : 1000.0);
  if (j->ft > 0.0 && !(j->gf > j->ft * j->ft / (2.0 * j->kn)))
    return vs_error_set(err, VS_ERR_INVALID, "joints.gf_N_mm = %g: with joints.tensile_MPa = %g "
                        "must be > tensile_MPa^2 / (2 kn_N_mm3) = %g (allowed: the softening ends "
                        "beyond the peak's opening)", v[2], v[0],
                        j->ft * j->ft / (2.0 * j->kn) / VS_N_MM);
  if (j->c > 0.0 && !(j->gc > j->c * j->c / (2.0 * j->ks)))
    return vs_error_set(err, VS_ERR_INVALID, "joints.gc_N_mm = %g: with joints.cohesion_MPa = %g "
                        "must be > cohesion_MPa^2 / (2 ks_ratio kn_N_mm3) = %g (allowed: the "
                        "cohesion softens more slowly than the joint unloads)", v[3], v[1],
                        j->c * j->c / (2.0 * j->ks) / VS_N_MM);
  return VS_OK;
}

vs_status vs_run_create_def(const vs_run_def *def, vs_run **out, vs_error *err) {
  *out = NULL;
  vs_status st0 = check_mortar(def, err);
  if (st0 == VS_OK) st0 = check_analysis(def, err);
  if (st0 != VS_OK) return st0;
  vs_run *r = calloc(1, sizeof *r);
  if (r == NULL) return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  r->def = *def;
  const vs_run_def *d = &r->def;
  for (int i = 0; i < 6; i++) r->react[i] = r->react_eq[i] = NAN;
  r->load_now = NAN;
  vs_status st = arch_and_imperfections(r, err);
  if (st == VS_OK) {
    vs_joint_law law = {.kn = d->joints.kn, .ks = d->joints.ks, .mu = d->joints.mu,
                        .ft = d->joints.ft, .c = d->joints.c, .gf = d->joints.gf, .gc = d->joints.gc};
    st = vs_model_create(r->g, &law, d->support.alpha, &r->m, err);
    if (st == VS_OK)
      st = vs_model_set_support_kinds(r->m, d->support.left_kind, d->support.right_kind, err);
    for (int s = 0; s < 2 && st == VS_OK; s++) { /* each support's own motion in delta */
      vs_support_motion mo;
      st = vs_support_motion_from_def(&d->support, s, &mo, err);
      if (st == VS_OK) st = vs_model_set_support_motion(r->m, s, &mo, err);
    }
    if (st == VS_OK) st = own_laws(r, err);
    if (st == VS_OK) st = vs_run_load_setup(r, err);
  }
  if (st == VS_OK) st = vs_imperfections_apply(&d->imperfections, r->imp, r->m, err);
  if (st == VS_OK && d->dynamic.damping_model == VS_DAMPING_RAYLEIGH &&
      3 * d->arch.voussoirs > VS_MODAL_MAX_DOF)
    st = vs_error_set(err, VS_ERR_INVALID,
                      "dynamic.damping_model = rayleigh needs the natural frequencies: arch.voussoirs "
                      "= %d (allowed with rayleigh: <= %d)",
                      d->arch.voussoirs, VS_MODAL_MAX_DOF / 3);
  if (st == VS_OK) { /* rayleigh is set at the self-weight equilibrium (damping_setup) */
    if (d->dynamic.damping_model == VS_DAMPING_RAYLEIGH) vs_model_set_damping(r->m, 0.0);
    else
      vs_damping_apply(r->m, d->dynamic.damping_model, d->dynamic.damping, 0.0, 0.0, NULL, NULL,
                       NULL);
    r->hopts.open = d->hinges.open;
    r->hopts.migrate = d->hinges.migrate;
    /* with piers, the arch's hinges are the ring's (its joints first); the piers' joints
     * have their own events (run_sample.c: track_piers) */
    st = vs_hinges_create(r->g->pier_courses > 0 ? r->g->ring : r->g->n_joints, &r->hopts,
                          &r->h, err);
  }
  if (st == VS_OK) {
    r->q = calloc((size_t)vs_model_size(r->m), sizeof *r->q);
    r->v = calloc((size_t)vs_model_size(r->m), sizeof *r->v);
    r->q_rest = calloc((size_t)vs_model_size(r->m), sizeof *r->q_rest);
    r->js = calloc(2 * (size_t)r->g->n_joints, sizeof *r->js); /* and the hinges' view */
    int mech_nomem = 0;
    if (d->joints.ft > 0.0 || d->joints.c > 0.0) { /* a mortared arch's mechanism */
      const size_t nj = (size_t)r->g->n_joints;
      r->mech_w = calloc(nj, sizeof *r->mech_w);
      r->mech = calloc(nj, sizeof *r->mech);
      r->pattern_m = calloc(2 * nj + 1, 1);
      r->mech_hinge = calloc(nj, sizeof *r->mech_hinge);
      mech_nomem = r->mech_w == NULL || r->mech == NULL || r->pattern_m == NULL ||
                   r->mech_hinge == NULL;
    }
    if (mech_nomem || r->q == NULL || r->v == NULL || r->q_rest == NULL || r->js == NULL ||
        vs_run_slips_create(r) != 0)
      st = vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  }
  if (st == VS_OK) {
    vs_path_opts_from_def(d, &r->popts);
    dyn_opts_from_def(d, r->g, &r->dopts);
    r->popts.deadline = r->dopts.deadline = &r->deadline; /* the wall-time limit's */
    if (d->analysis.type != VS_ANALYSIS_SUPPORT) /* the support's path, its motions too, ends held */
      r->popts.max_delta = r->dopts.max_delta = d->analysis.hold;
    double mass = 0.0;
    for (int i = 0; i < r->g->n_blocks; i++) mass += r->g->blocks[i].mass;
    const double w = deform_speed(&d->support);
    r->ke_move = 0.5 * mass * w * w;
    const vs_dynamic_def *dy = &d->dynamic;
    const int rigid = d->fall.scheme == VS_FALL_RIGID && dy->fall_time > 0.0 && (dy->follow || dy->full);
    if (rigid) { /* IDA stops at the collapse criterion, the rigid fall goes on from there */
      r->dopts.fall_time = 0.0;
      st = fall_create(r, err);
    }
    if (st == VS_OK && (dy->follow || dy->full))
      st = vs_dynamic_create(r->m, &r->dopts, &r->dyn, err);
    if (st == VS_OK && r->dyn != NULL && dy->fall_time > 0.0 && !rigid) { /* armed at the collapse */
      const double e = d->fall.restitution;
      st = vs_contact_create(r->m, e, 0, NULL, NULL, &r->ground, err);
      if (st == VS_OK) st = vs_dynamic_set_contact(r->dyn, r->ground, d->fall.ground, err);
      if (st == VS_OK) st = vs_collide_create(r->m, e, NULL, NULL, &r->bodies, err);
      if (st == VS_OK) st = vs_dynamic_set_collide(r->dyn, r->bodies, err);
    }
  }
  if (st == VS_OK) st = vs_path_solver_create(r->m, &r->popts, &r->ps, err);
  if (st != VS_OK) {
    vs_run_destroy(&r);
    return st;
  }
  r->collapse.delta = r->collapse.t = r->collapse.t_criterion = r->collapse.t_onset = NAN;
  r->mech_t = NAN;
  r->dtot.fall_failed_t = NAN;
  r->pending_snap = -1;
  *out = r;
  return VS_OK;
}

void vs_run_set_stop(vs_run *r, const volatile sig_atomic_t *stop) {
  r->popts.stop = stop;
  r->dopts.stop = stop;
  if (r->dyn != NULL) vs_dynamic_set_stop(r->dyn, stop);
  if (r->fall != NULL) vs_fall_set_stop(r->fall, stop);
}

void vs_run_destroy(vs_run **r) {
  if (r == NULL || *r == NULL) return;
  vs_run *p = *r;
  free(p->q);
  free(p->v);
  free(p->q_rest);
  free(p->js);
  free(p->limits);
  free(p->events);
  free(p->onset);
  free(p->onset_all);
  free(p->pattern_u);
  free(p->mech_w);
  free(p->mech);
  free(p->pattern_m);
  free(p->mech_hinge);
  vs_run_slips_free(p);
  vs_run_load_free(p);
  vs_modal_free(&p->modal);
  vs_dynamic_destroy(&p->dyn);
  vs_path_solver_destroy(&p->ps);
  vs_contact_destroy(&p->ground);
  vs_collide_destroy(&p->bodies);
  vs_fall_destroy(&p->fall);
  vs_hinges_destroy(&p->h);
  vs_model_destroy(&p->m);
  vs_geometry_destroy(&p->g);
  vs_imperfections_destroy(&p->imp);
  free(p);
  *r = NULL;
}


/* The rigid fall from the state at the collapse criterion (d: the IDA phase that ended there):
 * the supports' states as driven, a pinned one's rotation held; the energies carried on. */
static vs_status fall_phase(vs_run *r, const vs_dyn_result *d, vs_error *err) {
  const int n = 3 * r->g->n_blocks, ne = vs_model_ext_size(r->m);
  double *qe = calloc((size_t)ne, sizeof *qe), *ve = calloc((size_t)ne, sizeof *ve);
  if (qe == NULL || ve == NULL) {
    free(qe), free(ve);
    return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  }
  memcpy(qe, r->q, (size_t)n * sizeof *qe);
  memcpy(ve, r->v, (size_t)n * sizeof *ve);
  vs_model_support_states(r->m, r->delta, r->dopts.rate, qe + n, ve + n);
  for (int s = 0; s < 2; s++) {
    const int k = vs_model_support_dof(r->m, s);
    if (k >= 0) qe[n + 3 * s + 2] = r->q[k];
  }
  r->phase = VS_PHASE_FALL;
  vs_status st = vs_fall_run(r->fall, r->t, qe, ve, &d->e_end, vs_dynamic_joint_states(r->dyn),
                             vs_run_on_fall_sample, r, &r->fres, err);
  r->fall_done = 1;
  memcpy(r->q, qe, (size_t)n * sizeof *qe);
  memcpy(r->v, ve, (size_t)n * sizeof *ve);
  r->t = r->fres.t_end;
  r->delta = r->fres.delta_end;
  r->dtot.fall_at_rest = r->fres.at_rest;
  r->dtot.max_penetration = r->fres.max_penetration;
  r->dtot.max_overlap = r->fres.max_overlap;
  r->dtot.fall_wall_s = r->fres.wall_s;
  r->dtot.balance_error_fall = r->fres.balance_error_rel;
  free(qe), free(ve);
  return st;
}

static void add_path_totals(vs_run *r, const vs_path_result *p) {
  if (!r->have_first) {
    r->first = *p;
    r->have_first = 1;
  }
  r->totals.steps += p->steps;
  r->totals.rejected += p->rejected;
  r->totals.located += p->located;
  r->totals.newton_iterations += p->newton_iterations;
  r->totals.jacobian_evals += p->jacobian_evals;
  r->totals.floor_limited += p->floor_limited;
  r->totals.max_residual = fmax(r->totals.max_residual, p->max_residual);
  r->totals.end = p->end;
  r->totals.delta_limit = p->delta_limit;
  r->totals.delta_fail = p->delta_fail;
  r->totals.evidence = p->evidence;
}

static void add_dyn_totals(vs_run *r, const vs_dyn_result *d) {
  r->dtot.steps += d->steps;
  r->dtot.newton_iterations += d->newton_iterations;
  r->dtot.root_events += d->root_events;
  r->dtot.impacts += d->impacts;
  r->dtot.jac_evals += d->jac_evals;
  r->dtot.max_kinetic = fmax(r->dtot.max_kinetic, d->max_kinetic);
  r->dtot.balance_error_rel = fmax(r->dtot.balance_error_rel, d->balance_error_rel);
  r->dtot.balance_error_fall = fmax(r->dtot.balance_error_fall, d->balance_error_fall);
  r->dtot.max_drift = fmax(r->dtot.max_drift, d->max_drift);
  r->dtot.max_penetration = fmax(r->dtot.max_penetration, d->max_penetration);
  r->dtot.max_overlap = fmax(r->dtot.max_overlap, d->max_overlap);
  r->dtot.fall_wall_s += d->fall_wall_s;
  r->dtot.fall_at_rest = d->fall_at_rest;
  r->dtot.fall_failed_t = d->fall_failed_t;
  memcpy(r->dtot.fall_failure, d->fall_failure, sizeof d->fall_failure);
  r->dtot.dae_differential = d->dae_differential;
  r->dtot.dae_algebraic = d->dae_algebraic;
  r->dtot.dae_index = d->dae_index;
  r->dtot.end = d->end;
  r->dtot.t_end = d->t_end;
  r->dtot.delta_end = d->delta_end;
}


/* A snap ended by its ringing (d) at the equilibrium qe found from its last state r->q: the
 * vibration energy it left, kinetic + potential above qe, into the tallies. */
static void ring_settled(vs_run *r, const vs_dyn_result *d, const double *qe) {
  const double v = d->e_end.kinetic + vs_model_energy(r->m, r->q, r->delta) -
                   vs_model_energy(r->m, qe, r->delta);
  r->dtot.ring_settles++;
  r->dtot.ring_energy += v;
}

/* The motion from a limit point (or from rest at the start, full-dynamic): integrate; whenever
 * the arch is at rest, look for a stable equilibrium there and resume the quasi-static path from
 * it. Returns through *resume_at the delta to resume from (NaN: the run is over). */
static vs_status dynamic_phase(vs_run *r, double *resume_at, vs_error *err) {
  const int n = vs_model_size(r->m);
  double *qs = r->q_rest;
  *resume_at = NAN;
  r->phase = VS_PHASE_DYNAMIC;
  vs_status st = VS_OK;
  for (int restart = 0;; restart++) {
    if (restart >= VS_RUN_MAX_RESTARTS) {
      st = vs_error_set(err, VS_ERR_SOLVER,
                        "the motion came to rest %d times (the limit) with no equilibrium there, "
                        "up to %.6g mm",
                        VS_RUN_MAX_RESTARTS, r->delta / VS_MM);
      break;
    }
    vs_dyn_result d;
    memset(&d, 0, sizeof d);
    r->live_dyn = &d;
    st = vs_dynamic_run(r->dyn, r->t, r->q, r->v, vs_run_on_dyn_sample, vs_run_on_dyn_event, r,
                        &d, err);
    r->live_dyn = NULL;
    add_dyn_totals(r, &d);
    r->t = d.t_end;
    r->delta = d.delta_end;
    if (st != VS_OK) break;
    if (d.end == VS_DYN_COLLAPSED) {
      if (vs_run_record_collapse(r, &d) != 0) {
        st = vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
        break;
      }
      if (r->n_limits > 0) r->limits[r->n_limits - 1].collapse = 1;
      st = vs_run_log_event(r, VS_EVENT_COLLAPSE, d.t_collapse, d.t_collapse * r->dopts.rate, 0,
                            0, 0, 0)
               ? vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller")
               : VS_OK;
      if (st == VS_OK && r->fall != NULL) st = fall_phase(r, &d, err);
      break;
    }
    if (d.end == VS_DYN_MAX_DELTA) break;
    /* at rest: is there a stable equilibrium here, beyond the limit point? */
    memcpy(qs, r->q, (size_t)n * sizeof *qs);
    vs_path_opts probe = r->popts;
    probe.max_delta = r->delta; /* only the start: solve and check stability */
    vs_path_result pr;
    vs_error perr;
    vs_error_clear(&perr);
    const vs_status ps = vs_path_run_with(r->ps, &probe, r->delta, qs, NULL, NULL, &pr, &perr);
    if (ps == VS_OK) {
      if (d.ringing) ring_settled(r, &d, qs);
      *resume_at = r->delta;
      break;
    }
    if (ps == VS_ERR_INTERRUPTED) {
      st = vs_error_set(err, ps, "interrupted");
      break;
    }
  }
  return st;
}

/* A limit point at the onset of slip (p): the joints committed on their sliding branch there
 * slip from it (their events). Non-zero when an event stopped the run. */
static int limit_slips(vs_run *r, const vs_path_result *p) {
  if (p->evidence.slip_onset == 0) return 0;
  vs_model_joint_states(r->m, r->q, r->delta, r->js);
  return vs_run_slips_at_equilibrium(r, r->delta, r->js);
}

/* The path p ended on a sliding mechanism that the support drives: that is the collapse, at
 * the force the support can no longer raise; no motion follows (the support drags the
 * mechanism at its own rate). */
static vs_status sliding_collapse(vs_run *r, const vs_path_result *p, vs_error *err) {
  r->delta = p->delta_fail;
  r->t = r->delta / r->dopts.rate;
  if (vs_run_record_sliding(r, p) != 0) return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  if (vs_run_log_event(r, VS_EVENT_COLLAPSE, r->t, r->delta, 0, 0, 0, 0) != 0)
    return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
  return VS_OK;
}

/* A solver stopped as after the stop flag (VS_ERR_INTERRUPTED) when the stop flag was not
 * raised: its deadline, the wall-time limit, passed. Said so (a raised flag wins). */
static vs_status wall_time_stop(const vs_run *r, vs_status st, vs_error *err) {
  const int flagged = r->popts.stop != NULL && *r->popts.stop;
  if (st != VS_ERR_INTERRUPTED || flagged || !vs_deadline_passed(&r->deadline)) return st;
  return vs_error_set(err, VS_ERR_WALL_TIME, "stopped: wall-time limit %g s reached",
                      r->def.max_wall_s);
}

/* A solver stopped by the run's callbacks (VS_ERR_STOPPED) that stopped because they ran out
 * of memory, not because the caller asked to: said so. */
static vs_status nomem_stop(const vs_run *r, vs_status st, vs_error *err) {
  if (st != VS_ERR_STOPPED || !r->nomem) return st;
  return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
}

/* The support's path: the quasi-static path from self-weight, and at each limit point (with
 * dynamic.follow) the motion, resuming the path where the arch comes to rest, until the collapse
 * or popts.max_delta. */
static vs_status support_phases(vs_run *r, vs_error *err) {
  vs_status st = VS_OK;
  double delta0 = 0.0;
  for (;;) {
    vs_path_result p;
    r->phase = VS_PHASE_QUASISTATIC;
    r->pending_snap = (delta0 > 0.0 && r->n_limits > 0) ? r->n_limits - 1 : -1;
    memset(&p, 0, sizeof p);
    r->live_path = &p;
    st = vs_path_run_with(r->ps, &r->popts, delta0, r->q, vs_run_on_equilibrium, r, &p, err);
    if (st == VS_ERR_NO_EQUILIBRIUM && delta0 > 0.0 && p.steps == 0) {
      /* Newton from the state at rest missed the equilibrium the probe found from it, with the
       * slips the probe committed there (a joint sliding along a nearly free mode can throw
       * its steps onto the reverse branch): the path resumes from that equilibrium itself */
      add_path_totals(r, &p);
      memcpy(r->q, r->q_rest, (size_t)vs_model_size(r->m) * sizeof *r->q);
      memset(&p, 0, sizeof p);
      st = vs_path_run_with(r->ps, &r->popts, delta0, r->q, vs_run_on_equilibrium, r, &p, err);
    }
    r->live_path = NULL;
    if (r->modal_st != VS_OK) st = vs_error_set(err, r->modal_st, "%s", r->modal_err.msg);
    add_path_totals(r, &p);
    if (st == VS_OK && p.end == VS_PATH_SLIDING) {
      st = sliding_collapse(r, &p, err);
      break;
    }
    if (st != VS_OK || p.end != VS_PATH_LIMIT_POINT) break;
    if (r->n_limits >= VS_RUN_MAX_LIMITS) {
      st = vs_error_set(err, VS_ERR_SOLVER, "%d limit points (the limit) up to %.6g mm",
                        VS_RUN_MAX_LIMITS, p.delta_limit / VS_MM);
      break;
    }
    r->delta = p.delta_limit;
    r->t = r->delta / r->dopts.rate;
    vs_model_support_reactions(r->m, r->q, r->delta, r->react_eq);
    if (limit_slips(r, &p) != 0 || vs_run_add_limit(r, p.delta_limit) != 0) {
      st = vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
      break;
    }
    if (!r->def.dynamic.follow) break;
    memset(r->v, 0, (size_t)vs_model_size(r->m) * sizeof *r->v);
    st = dynamic_phase(r, &delta0, err);
    if (st != VS_OK || isnan(delta0)) break;
  }
  return st;
}

/* analysis.type = load: the support's path (its snap-throughs followed as always) to
 * analysis.hold (0: self-weight alone), held there at an equilibrium, then the live load to
 * collapse (run_load.c). A collapse before the hold, or an arch still moving there (or a limit
 * point not followed, dynamic.follow = 0): it carries no load (load_factor 0). */
static vs_status load_phases(vs_run *r, vs_error *err) {
  vs_run_load_result *l = &r->load;
  const int limit = r->def.analysis.type == VS_ANALYSIS_LIMIT;
  l->done = !limit;
  l->hold = r->def.analysis.hold;
  l->first_peak = NAN;
  vs_status st = support_phases(r, err);
  if (st != VS_OK) return st;
  if (!r->collapse.found && r->totals.end == VS_PATH_LIMIT_POINT && r->def.dynamic.follow &&
      r->dtot.end == VS_DYN_MAX_DELTA) {
    /* the support reached the hold while the arch was still moving (a snap-through under way):
     * held there, the arch settles; its equilibrium is taken as the stable one that Newton
     * finds from the moving state (as the motion's rest probe does) */
    const int n = vs_model_size(r->m);
    memcpy(r->q_rest, r->q, (size_t)n * sizeof *r->q);
    vs_path_opts probe = r->popts;
    probe.max_delta = r->delta;
    vs_path_result pr;
    vs_error perr;
    vs_error_clear(&perr);
    const vs_status ps = vs_path_run_with(r->ps, &probe, r->delta, r->q_rest, NULL, NULL, &pr, &perr);
    if (ps == VS_ERR_INTERRUPTED) return vs_error_set(err, ps, "interrupted");
    if (ps == VS_OK) {
      memcpy(r->q, r->q_rest, (size_t)n * sizeof *r->q);
      r->totals.end = VS_PATH_MAX_DISPLACEMENT;
      l->settled = 1;
      if (vs_run_on_equilibrium(r, r->delta, r->q, r->m) != 0)
        return vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
    }
  }
  if (r->collapse.found || r->totals.end != VS_PATH_MAX_DISPLACEMENT) {
    l->held_limit = 1;
    /* collapsed: it carries nothing; still moving with no equilibrium found: unknown */
    l->load_factor = r->collapse.found ? 0.0 : NAN;
    snprintf(l->cause, sizeof l->cause,
             "the arch %s at %.6g mm, before the hold (%.6g mm)",
             r->collapse.found         ? "collapsed"
             : r->def.dynamic.follow ? "was still moving"
                                     : "met a limit point (not followed: dynamic.follow = 0)",
             (r->collapse.found ? r->collapse.delta : r->delta) / VS_MM, l->hold / VS_MM);
    return VS_OK;
  }
  vs_run_limit_at_hold(r); /* beside the load path's result; analysis.type = limit: the result */
  if (limit)
    return r->held_la_st == VS_OK ? VS_OK
                                  : vs_error_set(err, r->held_la_st, "%s", r->held_la_err.msg);
  return vs_run_load_path(r, err);
}

vs_status vs_run_execute(vs_run *r, vs_run_sample_fn sample, vs_run_event_fn event, void *user,
                         vs_error *err) {
  r->sample_fn = sample;
  r->event_fn = event;
  r->user = user;
  const double t0 = vs_wall_now();
  r->deadline = r->def.max_wall_s > 0.0 ? vs_monotonic_s() + r->def.max_wall_s : 0.0;
  vs_status st = VS_OK;
  double delta0 = 0.0;
  if (r->def.analysis.type == VS_ANALYSIS_LOAD || r->def.analysis.type == VS_ANALYSIS_LIMIT) {
    st = load_phases(r, err);
  } else if (r->def.dynamic.full) {
    /* self-weight by KINSOL, then the whole loading dynamically from rest */
    vs_path_opts sw = r->popts;
    sw.max_delta = 0.0;
    vs_path_result p;
    memset(&p, 0, sizeof p);
    r->live_path = &p;
    st = vs_path_run_with(r->ps, &sw, 0.0, r->q, vs_run_on_equilibrium, r, &p, err);
    r->live_path = NULL;
    if (r->modal_st != VS_OK) st = vs_error_set(err, r->modal_st, "%s", r->modal_err.msg);
    add_path_totals(r, &p);
    for (int i = 0; i < 6; i++) r->react_eq[i] = NAN; /* no limit point to depart from */
    if (st == VS_OK) {
      r->dopts.settle = 0;
      vs_dynamic_destroy(&r->dyn);
      st = vs_dynamic_create(r->m, &r->dopts, &r->dyn, err);
    }
    if (st == VS_OK) st = dynamic_phase(r, &delta0, err);
  } else {
    st = support_phases(r, err);
  }
  if (!r->collapse.found) vs_run_name_first(r, vs_hinges_count(r->h));
  vs_run_classify(r);
  r->wall_s = vs_wall_now() - t0;
  return wall_time_stop(r, nomem_stop(r, st, err), err);
}

const vs_case *vs_run_case(const vs_run *r) { return r->have_case ? &r->c : NULL; }
const vs_run_def *vs_run_def_of(const vs_run *r) { return &r->def; }
const vs_geometry *vs_run_geometry(const vs_run *r) { return r->g; }
const vs_imperfections *vs_run_imperfections(const vs_run *r) { return r->imp; }
const vs_model *vs_run_model(const vs_run *r) { return r->m; }
const vs_hinges *vs_run_hinges(const vs_run *r) { return r->h; }
const vs_hinge_opts *vs_run_hinge_opts(const vs_run *r) { return &r->hopts; }
const vs_path_result *vs_run_path(const vs_run *r) { return &r->first; }
const vs_path_result *vs_run_path_totals(const vs_run *r) { return &r->totals; }
int vs_run_limit_count(const vs_run *r) { return r->n_limits; }
const vs_limit_record *vs_run_limit(const vs_run *r, int i) {
  return (i >= 0 && i < r->n_limits) ? &r->limits[i] : NULL;
}
const vs_collapse_record *vs_run_collapse(const vs_run *r) { return &r->collapse; }
const vs_dyn_result *vs_run_dynamic_totals(const vs_run *r) { return &r->dtot; }
int vs_run_event_count(const vs_run *r) { return r->n_events; }
const vs_run_event *vs_run_event_get(const vs_run *r, int i) {
  return (i >= 0 && i < r->n_events) ? &r->events[i] : NULL;
}
const char *vs_run_mode(const vs_run *r) { return r->mode; }
const vs_hinge *vs_run_hinge(const vs_run *r, int i) {
  if (r->collapse.found && i < r->hinges_at_onset) return &r->onset_all[i];
  return vs_hinges_get(r->h, i);
}

int vs_run_hinge_count(const vs_run *r) {
  return r->collapse.found ? r->hinges_at_onset : vs_hinges_count(r->h);
}
const char *vs_run_pattern_initial(const vs_run *r) { return r->pattern0; }
int vs_run_mechanism_count(const vs_run *r) { return r->collapse.found ? r->n_mech : 0; }
const vs_active_hinge *vs_run_mechanism_hinge(const vs_run *r, int i) {
  return (i >= 0 && i < vs_run_mechanism_count(r)) ? &r->mech[i] : NULL;
}
const char *vs_run_pattern_mechanism(const vs_run *r) {
  return vs_run_mechanism_count(r) > 0 ? r->pattern_m : "";
}
double vs_run_mechanism_time(const vs_run *r) {
  return vs_run_mechanism_count(r) > 0 ? r->mech_t : NAN;
}
int vs_run_mode_from_mechanism(const vs_run *r) { return r->mode_from_mech; }
const vs_run_event *vs_run_first_crack(const vs_run *r) {
  const vs_run_event *f = NULL; /* events are logged as each state is tracked, several a state */
  for (int i = 0; i < r->n_events; i++) {
    const vs_run_event *e = &r->events[i];
    if (e->kind == VS_EVENT_CRACK_INITIATED && (f == NULL || e->delta < f->delta)) f = e;
  }
  return f;
}

int vs_run_joint_cracks(const vs_run *r, double *out) {
  for (int k = 0; k < r->g->n_joints && out != NULL; k++) {
    const vs_joint_law *law = vs_model_joint_law(r->m, k);
    out[2 * k] = law->crack[0];
    out[2 * k + 1] = law->crack[1];
  }
  return r->g->n_joints;
}
const char *vs_run_pattern_collapse(const vs_run *r) {
  return r->collapse.found && r->pattern_u != NULL ? r->pattern_u : "";
}
const double *vs_run_state(const vs_run *r) { return r->q; }
double vs_run_delta(const vs_run *r) { return r->delta; }
double vs_run_time(const vs_run *r) { return r->t; }
const double *vs_run_reactions(const vs_run *r) { return r->react; }
double vs_run_wall_s(const vs_run *r) { return r->wall_s; }
double vs_run_ground(const vs_run *r) {
  if (r->fall != NULL) return r->fall_done ? r->fres.level : NAN;
  return (r->ground != NULL && vs_contact_armed(r->ground)) ? vs_contact_level(r->ground) : NAN;
}
double vs_run_rest_ke(const vs_run *r) { return r->dopts.rest_ke; }
double vs_run_penetration(const vs_run *r) {
  if (r->fall != NULL) return r->fall_done ? vs_fall_penetration(r->fall) : NAN;
  return isfinite(vs_run_ground(r)) ? vs_contact_max_penetration(r->ground, r->q, NULL) : NAN;
}
const vs_fall_result *vs_run_fall(const vs_run *r) { return r->fall_done ? &r->fres : NULL; }
const vs_modal *vs_run_modal(const vs_run *r) { return &r->modal; }
void vs_run_rayleigh(const vs_run *r, double *alpha, double *beta) {
  *alpha = r->ray_alpha;
  *beta = r->ray_beta;
}
