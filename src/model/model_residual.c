/* The model's static system (model.h): the residual G of the equilibrium, its analytic CSC
 * Jacobian and dG/d(delta), assembled from one evaluation of the joint law per joint (the memo
 * passes the residual's evaluation to a Jacobian at the same state), over the static unknowns or
 * the extended state; and the residual's scale. */
#include "model_internal.h"

#include <math.h>
#include <string.h>

/* Residual over the unknowns of pattern p (G has p->n entries); the joints' points are kept
 * (struct vs_model_memo) for a Jacobian at the same state. */
static void residual_core(const vs_model *m, const vs_pattern *p, const double *q,
                          const double qs[6], double *G) {
  const vs_geometry *g = m->g;
  memset(G, 0, (size_t)p->n * sizeof *G);
  for (int i = 0; i < g->n_blocks; i++)
    G[3 * i + 1] = m->gscale * g->blocks[i].mass * g->gravity; /* minus the load -m g */
  if (!vs_model_memo_hit(m, q, qs)) {
    vs_model_half_angles(m, q, qs);
    vs_model_memo_fill(m, q, qs);
  }
  for (int k = 0; k < g->n_joints; k++) {
    double f[6];
    memo_out(m, k, NULL, f, NULL);
    const int *d = p->jdof + 6 * k;
    for (int e = 0; e < 6; e++)
      if (d[e] >= 0) G[d[e]] += f[e];
  }
  vs_model_loads_add(m, p, q, G, NULL);
}

void vs_model_residual(const vs_model *m, const double *q, double delta, double *G) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  residual_core(m, &m->pat, q, qs, G);
}

/* Jacobian over the unknowns of pattern p, from the memo when it holds this state. */
static void jacobian_core(const vs_model *m, const vs_pattern *p, const double *q,
                          const double qs[6], SUNMatrix J) {
  double *data = vs_model_csc_reset(p, J);
  const vs_geometry *g = m->g;
  const int hit = vs_model_memo_hit(m, q, qs);
  if (!hit) vs_model_half_angles(m, q, qs);
  for (int k = 0; k < g->n_joints; k++) {
    double K[36];
    if (hit) memo_out(m, k, NULL, NULL, K);
    else vs_model_eval_joint(m, q, qs, k, 1, NULL, NULL, K);
    scatter_joint(p, k, K, data);
  }
  vs_model_loads_add(m, p, q, NULL, data);
}

int vs_model_jacobian(const vs_model *m, const double *q, double delta, SUNMatrix J) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  jacobian_core(m, &m->pat, q, qs, J);
  return 0;
}

/* dG/d(delta) = sum over the supports of dG/dqs dqs/d(delta): each joint at a moving support
 * adds its stiffness against that support's coordinates times their rates (a pinned support's
 * rotation is an unknown, not loaded). A support at rest adds nothing. */
void vs_model_dG_ddelta(const vs_model *m, const double *q, double delta, double *out) {
  const vs_geometry *g = m->g;
  double qs[6], rate[6];
  sup_pos_q(m, q, delta, qs);
  int moving[2];
  for (int s = 0; s < 2; s++) {
    vs_support_motion_at(&m->mo[s], delta, NULL, rate + 3 * s);
    if (m->pinned[s]) rate[3 * s + 2] = 0.0;
    moving[s] = rate[3 * s] != 0.0 || rate[3 * s + 1] != 0.0 || rate[3 * s + 2] != 0.0;
  }
  memset(out, 0, (size_t)m->n * sizeof *out);
  for (int k = 0; k < g->n_joints; k++) {
    const int body[2] = {g->joints[k].a, g->joints[k].b};
    const int ss = !body_is_block(body[1]) ? 1 : !body_is_block(body[0]) ? 0 : -1;
    if (ss < 0) continue;
    const int sup = body[ss] == VS_SUPPORT_LEFT ? 0 : 1;
    if (!moving[sup]) continue;
    const double *r = rate + 3 * sup;
    double K[36];
    int d[6];
    vs_model_eval_joint(m, q, qs, k, 0, NULL, NULL, K);
    vs_model_joint_dofs(m, &m->pat, k, d);
    for (int e = 0; e < 6; e++) {
      if (d[e] < 0) continue;
      const double *row = K + 6 * e + 3 * ss;
      double x = row[0] * r[0] + row[1] * r[1];
      if (r[2] != 0.0) x += row[2] * r[2];
      out[d[e]] += x;
    }
  }
}

void vs_model_residual_scale(const vs_model *m, double *scale) {
  const vs_geometry *g = m->g;
  for (int i = 0; i < g->n_blocks; i++) {
    double len = 0.0;
    for (int k = 0; k < g->n_joints; k++)
      if (g->joints[k].a == i || g->joints[k].b == i) len = fmax(len, g->joints[k].length);
    if (!(len > 0.0)) len = sqrt(g->blocks[i].area);
    const double w = g->blocks[i].mass * g->gravity;
    scale[3 * i] = w;
    scale[3 * i + 1] = w;
    scale[3 * i + 2] = w * len;
  }
  /* a pinned support's rotation: the moment of its neighbouring block's weight over the joint */
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    const int sup = body_is_block(j->a) ? j->b : j->a, blk = body_is_block(j->a) ? j->a : j->b;
    if (body_is_block(sup) || !body_is_block(blk)) continue;
    const int d = m->pat.dof[3 * body_slot(m, sup) + 2];
    if (d >= 0) scale[d] = g->blocks[blk].mass * g->gravity * j->length;
  }
}

/* --- the extended state qe = (blocks, left support, right support) --- */

void vs_model_ext_residual(const vs_model *m, const double *qe, double *Ge) {
  residual_core(m, &m->pate, qe, qe + 3 * m->g->n_blocks, Ge);
}

void vs_model_ext_jacobian(const vs_model *m, const double *qe, SUNMatrix J) {
  jacobian_core(m, &m->pate, qe, qe + 3 * m->g->n_blocks, J);
}

