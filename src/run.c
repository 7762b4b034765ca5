/* One run: case -> geometry -> model -> quasi-static path, hinges updated at each equilibrium. */
#include "voussoir/run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "voussoir/units.h"

struct vs_run {
  vs_case c;
  vs_geometry *g;
  vs_model *m;
  vs_hinges *h;
  vs_hinge_opts hopts;
  vs_path_opts popts;
  vs_path_result path;
  double *q;
  vs_joint_state *js;
  double delta, wall_s;
  vs_run_step_fn fn;
  void *user;
};

vs_status vs_run_create(const vs_case *c, vs_run **out, vs_error *err) {
  *out = NULL;
  vs_run *r = calloc(1, sizeof *r);
  if (r == NULL) return vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  r->c = *c;
  vs_status st = vs_geometry_create_arch(c, &r->g, err);
  if (st == VS_OK) {
    vs_joint_law law = {.kn = c->kn_N_mm3 * VS_N_MM3,
                        .ks = c->ks_ratio * c->kn_N_mm3 * VS_N_MM3,
                        .mu = c->friction};
    st = vs_model_create(r->g, &law, c->alpha_deg * VS_DEG, &r->m, err);
  }
  if (st == VS_OK) {
    r->hopts.open = c->open_mm * VS_MM;
    r->hopts.migrate = c->migrate_joints;
    st = vs_hinges_create(r->g->n_joints, &r->hopts, &r->h, err);
  }
  if (st == VS_OK) {
    r->q = calloc((size_t)vs_model_size(r->m), sizeof *r->q);
    r->js = calloc((size_t)r->g->n_joints, sizeof *r->js);
    if (r->q == NULL || r->js == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "run: out of memory");
  }
  if (st != VS_OK) {
    vs_run_destroy(&r);
    return st;
  }
  vs_path_opts_from_case(c, &r->popts);
  *out = r;
  return VS_OK;
}

void vs_run_destroy(vs_run **r) {
  if (r == NULL || *r == NULL) return;
  vs_run *p = *r;
  free(p->q);
  free(p->js);
  vs_hinges_destroy(&p->h);
  vs_model_destroy(&p->m);
  vs_geometry_destroy(&p->g);
  free(p);
  *r = NULL;
}

static int on_step(void *user, double delta, const double *q, const vs_model *m) {
  vs_run *r = user;
  vs_model_joint_states(m, q, delta, r->js);
  vs_hinges_update(r->h, delta, r->js);
  r->delta = delta;
  return r->fn != NULL ? r->fn(r->user, r, delta, q) : 0;
}

static double now_s(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

vs_status vs_run_execute(vs_run *r, vs_run_step_fn fn, void *user, vs_error *err) {
  r->fn = fn;
  r->user = user;
  const double t0 = now_s();
  vs_status st = vs_path_run(r->m, &r->popts, r->q, on_step, r, &r->path, err);
  r->wall_s = now_s() - t0;
  return st;
}

const vs_case *vs_run_case(const vs_run *r) { return &r->c; }
const vs_geometry *vs_run_geometry(const vs_run *r) { return r->g; }
const vs_model *vs_run_model(const vs_run *r) { return r->m; }
const vs_hinges *vs_run_hinges(const vs_run *r) { return r->h; }
const vs_path_result *vs_run_path(const vs_run *r) { return &r->path; }
const vs_hinge_opts *vs_run_hinge_opts(const vs_run *r) { return &r->hopts; }
const double *vs_run_state(const vs_run *r) { return r->q; }
double vs_run_delta(const vs_run *r) { return r->delta; }
double vs_run_wall_s(const vs_run *r) { return r->wall_s; }
