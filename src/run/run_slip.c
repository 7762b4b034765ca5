/* Slip in a run (run_internal.h): the events of joints that begin to slide (on the path, at a
 * limit point at the onset of slip, in the motion up to the collapse criterion), the slips of
 * the collapse's mechanism, and its name: rotational, sliding or mixed. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "run_internal.h"

int vs_run_slips_create(vs_run *r) {
  const size_t nj = (size_t)r->g->n_joints;
  r->slip_dir = calloc(nj, sizeof *r->slip_dir);
  r->slip_anchor = calloc(nj, sizeof *r->slip_anchor);
  r->slip_from = calloc(nj, sizeof *r->slip_from);
  r->slip_onset = calloc(nj, sizeof *r->slip_onset);
  r->mech_slips = calloc(nj, sizeof *r->mech_slips);
  r->pier_side = calloc(nj, sizeof *r->pier_side);
  r->crack_margin = calloc(2 * nj, sizeof *r->crack_margin);
  r->cracked = calloc(nj, sizeof *r->cracked);
  r->crack_delta = NAN;
  return r->slip_dir && r->slip_anchor && r->slip_from && r->slip_onset && r->mech_slips &&
                 r->pier_side && r->crack_margin && r->cracked
             ? 0
             : -1;
}

void vs_run_slips_free(vs_run *r) {
  free(r->slip_dir);
  free(r->slip_anchor);
  free(r->slip_from);
  free(r->slip_onset);
  free(r->mech_slips);
  free(r->pier_side);
  free(r->crack_margin);
  free(r->cracked);
}

/* The edge toward which joint k's voussoir slides relative to the body across the joint, when
 * body b slides relative to body a along s (sense +1) or against it (-1): at the right
 * springing the voussoir is body a. At a pier's joint, the edge toward which the course above
 * slides (I: the inner face, E: the outer): on the right pier it is body a. */
static char slip_side(const vs_run *r, int k, int sense) {
  int pier = 0;
  const int voussoir_is_a =
      r->g->joints[k].b < 0 || (vs_geometry_pier_joint(r->g, k, &pier, NULL) > 0 && pier == 1);
  return (sense > 0) != voussoir_is_a ? 'E' : 'I';
}

/* A slip event of joint k in the sense sense, unless its last one was in that sense. */
static int slip_event(vs_run *r, int k, int sense, double t, double delta) {
  if (r->slip_dir[k] == sense) return 0;
  r->slip_dir[k] = (signed char)sense;
  return vs_run_log_event(r, VS_EVENT_JOINT_SLIPPED, t, delta, k + 1, slip_side(r, k, sense), 0,
                          0);
}

int vs_run_slips_at_equilibrium(vs_run *r, double delta, const vs_joint_state *js) {
  const int nj = r->g->n_joints;
  const double *slips = vs_model_slips(r->m);
  int sliding = 0;
  for (int k = 0; k < nj; k++) {
    r->slip_anchor[k] = slips[k];
    if (!(js[k].sliding && js[k].N > 0.0)) continue;
    sliding++;
    /* the force resists the slip: T > 0 while b slides along s relative to a */
    if (slip_event(r, k, js[k].T > 0.0 ? 1 : -1, delta / r->dopts.rate, delta) != 0) return -1;
  }
  if (sliding == 0) vs_run_slips_mark(r); /* all stick: a sliding mechanism starts after this */
  return 0;
}

int vs_run_slips_in_motion(vs_run *r, double t, double delta) {
  const double *slips = vs_model_slips(r->m);
  for (int k = 0; k < r->g->n_joints; k++) {
    const double moved = slips[k] - r->slip_anchor[k];
    if (!(fabs(moved) > r->hopts.open)) continue;
    r->slip_anchor[k] = slips[k];
    if (slip_event(r, k, moved > 0.0 ? 1 : -1, t, delta) != 0) return -1;
  }
  return 0;
}

void vs_run_slips_mark(vs_run *r) {
  memcpy(r->slip_from, vs_model_slips(r->m), (size_t)r->g->n_joints * sizeof *r->slip_from);
}

void vs_run_slips_onset(vs_run *r) {
  memcpy(r->slip_onset, vs_model_slips(r->m), (size_t)r->g->n_joints * sizeof *r->slip_onset);
}

void vs_run_slips_mechanism(vs_run *r, const vs_joint_state *sliding_now) {
  vs_collapse_record *c = &r->collapse;
  c->n_slips = 0;
  for (int k = 0; k < r->g->n_joints; k++) {
    const double moved = r->slip_onset[k] - r->slip_from[k];
    const int in = sliding_now != NULL
                       ? sliding_now[k].sliding && sliding_now[k].N > 0.0 && moved != 0.0
                       : fabs(moved) > r->hopts.open;
    if (in)
      r->mech_slips[c->n_slips++] =
          (vs_slip){.joint = k + 1, .side = slip_side(r, k, moved > 0.0 ? 1 : -1),
                    .slip = fabs(moved)};
  }
  c->slips = r->mech_slips;
  c->mechanism = c->n_slips == 0 ? "rotational" : c->n_hinges > 0 ? "mixed" : "sliding";
}
