/* The model's dynamics (model.h): masses and kinetic energy, and one pass over the joints for
 * their elastic, damping (joint dashpots or Rayleigh's) and friction terms with the Jacobians
 * dG/dq and dfd/dv; over the static unknowns or the extended state with driven supports. */
#include "model_internal.h"

#include <string.h>

void vs_model_mass(const vs_model *m, double *mdiag) {
  for (int i = 0; i < m->g->n_blocks; i++) {
    mdiag[3 * i] = mdiag[3 * i + 1] = m->g->blocks[i].mass;
    mdiag[3 * i + 2] = m->g->blocks[i].inertia;
  }
}

double vs_model_kinetic_energy(const vs_model *m, const double *v) {
  double e = 0.0;
  for (int i = 0; i < m->g->n_blocks; i++) {
    const vs_block *b = &m->g->blocks[i];
    e += 0.5 * (b->mass * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1]) +
                b->inertia * v[3 * i + 2] * v[3 * i + 2]);
  }
  return e;
}

/* Rayleigh's mass-proportional part alpha M v on the blocks (body columns 0..n_blocks-1 of p):
 * it acts on absolute velocities, so it also slows a rigid-body motion (a falling block tends to
 * g / alpha). */
static void mass_damping(const vs_model *m, const vs_pattern *p, const double *v, double *fd,
                         double *diss, double *data) {
  for (int i = 0; i < m->g->n_blocks; i++) {
    const vs_block *b = &m->g->blocks[i];
    const double mi[3] = {b->mass, b->mass, b->inertia};
    for (int c = 0; c < 3; c++) {
      const int r = 3 * i + c;
      if (fd != NULL) fd[r] += m->alpha_m * mi[c] * v[r];
      *diss += m->alpha_m * mi[c] * v[r] * v[r];
      if (data == NULL) continue;
      const sunindextype stride = p->colptr[3 * i + 1] - p->colptr[3 * i];
      data[vs_model_csc_pos(p, i, i) + c * stride + c] += m->alpha_m * mi[c];
    }
  }
}

/* What one pass over the joints yields (motion_core); NULL pointers are not computed. */
typedef struct {
  double *G;        /* elastic forces minus gravity (as vs_model_residual), p->n entries */
  double *fd;       /* damping forces, p->n entries */
  SUNMatrix K, C;   /* dG/dq and dfd/dv over p */
  int want_damping; /* the damping terms (fd, C, diss, sup) */
  int want_friction;
  double diss, sup, fric; /* out: dissipated power, damping power the support takes (W, < 0
                             when it supplies), friction power */
} motion_out;

/* Add joint k's damping force f (at body velocities va, vb) to fd over p and its work on the
 * prescribed support components to *sup. */
static void add_damping(const vs_model *m, const vs_pattern *p, int k, const double f[6],
                        const double va[3], const double vb[3], double *fd, double *sup) {
  const vs_joint_geom *j = &m->g->joints[k];
  const int body[2] = {j->a, j->b};
  const int *d = p->jdof + 6 * k;
  for (int s = 0; s < 2; s++) {
    const double *vv = s == 0 ? va : vb;
    for (int c = 0; c < 3; c++) {
      /* the support's prescribed components work on the arch; a free one is the arch's */
      if (!body_is_block(body[s]) && d[3 * s + c] < 0) *sup -= f[3 * s + c] * vv[c];
      if (d[3 * s + c] >= 0 && fd != NULL) fd[d[3 * s + c]] += f[3 * s + c];
    }
  }
}

/* The joints' elastic, damping and friction terms over the bodies of p at block states (q, v)
 * and support states (qs, vs), from one evaluation of every joint (v NULL: no rates). */
static void motion_core(const vs_model *m, const vs_pattern *p, const double *q, const double *v,
                        const double qs[6], const double vs[6], motion_out *o) {
  const vs_geometry *g = m->g;
  double *kdata = NULL, *cdata = NULL;
  if (o->G != NULL) {
    memset(o->G, 0, (size_t)p->n * sizeof *o->G);
    for (int i = 0; i < g->n_blocks; i++)
      o->G[3 * i + 1] = m->gscale * g->blocks[i].mass * g->gravity; /* minus the load -m g */
  }
  if (o->fd != NULL) memset(o->fd, 0, (size_t)p->n * sizeof *o->fd);
  if (o->K != NULL) kdata = vs_model_csc_reset(p, o->K);
  if (o->C != NULL) cdata = vs_model_csc_reset(p, o->C);
  o->diss = o->sup = o->fric = 0.0;
  const int damp = m->damped && v != NULL && o->want_damping;
  vs_model_half_angles(m, q, qs);
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double f[6], Kk[36], fdk[6], Ck[36];
    vs_joint_law tmp;
    const double *va = v != NULL ? body_ptr(v, vs, j->a) : NULL;
    const double *vb = v != NULL ? body_ptr(v, vs, j->b) : NULL;
    const vs_joint_bodies bd = {body_ptr(q, qs, j->a), body_ptr(q, qs, j->b), body_rot(m, j->a),
                                body_rot(m, j->b), va, vb, m->ra + 2 * k, m->rb + 2 * k};
    /* HOOK (damping): Rayleigh's stiffness part, else the joint dashpots */
    const vs_joint_dashpot dp = {m->cn[k], m->cs[k], m->beta_k};
    vs_joint_motion jm = {o->G != NULL ? f : NULL, o->K != NULL ? Kk : NULL, damp ? fdk : NULL,
                          damp && o->C != NULL ? Ck : NULL, o->want_friction && v != NULL, 0.0,
                          0.0};
    vs_joint_eval_motion(j, law_at(m, k, &tmp), &bd, m->slip_p[k], damp ? &dp : NULL, &jm);
    const int *d = p->jdof + 6 * k;
    if (o->G != NULL && p->full[k]) /* (the joints of the dynamic phase's extended state) */
      for (int e = 0; e < 6; e++) o->G[d[e]] += f[e];
    else if (o->G != NULL)
      for (int e = 0; e < 6; e++)
        if (d[e] >= 0) o->G[d[e]] += f[e];
    if (o->K != NULL) scatter_joint(p, k, Kk, kdata);
    if (damp) {
      o->diss += jm.power;
      if (p->full[k] && o->fd != NULL) /* no prescribed component: nothing the support works */
        for (int e = 0; e < 6; e++) o->fd[d[e]] += fdk[e];
      else
        add_damping(m, p, k, fdk, va, vb, o->fd, &o->sup);
      if (o->C != NULL) scatter_joint(p, k, Ck, cdata);
    }
    o->fric += jm.friction;
  }
  vs_model_loads_add(m, p, q, o->G, kdata); /* external forces, as in the statics */
  if (m->alpha_m > 0.0 && v != NULL && o->want_damping) /* HOOK (damping) */
    mass_damping(m, p, v, o->fd, &o->diss, cdata);
}

/* Damping forces over the bodies of p at block states (q, v) and support states (qs, vs). */
static void damping_core(const vs_model *m, const vs_pattern *p, const double *q, const double *v,
                         const double qs[6], const double vs[6], double *fd, double *dissipated,
                         double *support_power, SUNMatrix C) {
  motion_out o = {.fd = fd, .C = C, .want_damping = 1};
  motion_core(m, p, q, v, qs, vs, &o);
  /* the support does the work -f . u_dot on the arch through the damper: the dissipated power
   * splits into what the blocks lose (fd . v) and what the support supplies */
  if (dissipated != NULL) *dissipated = o.diss;
  if (support_power != NULL) *support_power = -o.sup;
}

void vs_model_damping(const vs_model *m, const double *q, const double *v, double delta,
                      double ddelta_dt, double *fd, double *dissipated, double *support_power,
                      SUNMatrix C) {
  double qs[6], vs[6];
  sup_pos_q(m, q, delta, qs);
  sup_vel_q(m, v, delta, ddelta_dt, vs);
  damping_core(m, &m->pat, q, v, qs, vs, fd, dissipated, support_power, C);
}

/* The friction power of the joints over the bodies of p (motion_core's). */
static double friction_core(const vs_model *m, const vs_pattern *p, const double *q,
                            const double *v, const double qs[6], const double vs[6]) {
  motion_out o = {.want_friction = 1};
  motion_core(m, p, q, v, qs, vs, &o);
  return o.fric;
}

double vs_model_friction_power(const vs_model *m, const double *q, const double *v, double delta,
                               double ddelta_dt) {
  double qs[6], vs[6];
  sup_pos_q(m, q, delta, qs);
  sup_vel_q(m, v, delta, ddelta_dt, vs);
  return friction_core(m, &m->pat, q, v, qs, vs);
}

/* --- driven supports: the extended state qe = (blocks, left support, right support) --- */

void vs_model_ext_mass(const vs_model *m, double *mdiag) {
  const vs_geometry *g = m->g;
  vs_model_mass(m, mdiag);
  double mass = 0.0, inertia = 0.0;
  for (int i = 0; i < g->n_blocks; i++) {
    mass += g->blocks[i].mass / g->n_blocks;
    inertia += g->blocks[i].inertia / g->n_blocks;
  }
  const int nq = 3 * g->n_blocks;
  for (int s = 0; s < 2; s++) {
    mdiag[nq + 3 * s] = mdiag[nq + 3 * s + 1] = mass;
    mdiag[nq + 3 * s + 2] = inertia;
  }
}

void vs_model_ext_damping(const vs_model *m, const double *qe, const double *ve, double *fd,
                          double *dissipated, SUNMatrix C) {
  damping_core(m, &m->pate, qe, ve, qe + 3 * m->g->n_blocks, ve + 3 * m->g->n_blocks, fd,
               dissipated, NULL, C);
}

void vs_model_ext_motion(const vs_model *m, const double *qe, const double *ve, double *F,
                         double *dissipated, double *friction, SUNMatrix K, SUNMatrix C) {
  const int n = m->pate.n;
  motion_out o = {.G = F, .fd = F != NULL ? m->fdw : NULL, .K = K, .C = C,
                  .want_damping = F != NULL || C != NULL || dissipated != NULL,
                  .want_friction = friction != NULL};
  motion_core(m, &m->pate, qe, ve, qe + 3 * m->g->n_blocks,
              ve != NULL ? ve + 3 * m->g->n_blocks : NULL, &o);
  if (F != NULL)
    for (int i = 0; i < n; i++) F[i] += m->fdw[i];
  if (dissipated != NULL) *dissipated = o.diss;
  if (friction != NULL) *friction = o.fric;
}

void vs_model_ext_support_forces(const vs_model *m, const double *qe, const double *ve,
                                 double out[6]) {
  const vs_geometry *g = m->g;
  const int n = 3 * g->n_blocks;
  const double *qs = qe + n, *vs = ve + n;
  double fd[6] = {0};
  memset(out, 0, 6 * sizeof *out);
  for (int k = 0; k < g->n_joints; k++) { /* as motion_core, on the joints at a support */
    const vs_joint_geom *j = &g->joints[k];
    if (body_is_block(j->a) && body_is_block(j->b)) continue;
    double qa[3], qb[3], va[3], vb[3], ha[2], hb[2], f[6], fdk[6];
    vs_joint_law tmp;
    body_q(qe, qs, j->a, qa);
    body_q(qe, qs, j->b, qb);
    body_q(ve, vs, j->a, va);
    body_q(ve, vs, j->b, vb);
    vs_joint_half_angle(qa[2], ha);
    vs_joint_half_angle(qb[2], hb);
    const vs_joint_bodies bd = {qa, qb, ha, hb, va, vb, m->ra + 2 * k, m->rb + 2 * k};
    const vs_joint_dashpot dp = {m->cn[k], m->cs[k], m->beta_k};
    vs_joint_motion jm = {f, NULL, m->damped ? fdk : NULL, NULL, 0, 0.0, 0.0};
    vs_joint_eval_motion(j, law_at(m, k, &tmp), &bd, m->slip_p[k], m->damped ? &dp : NULL, &jm);
    const int *d = m->pate.jdof + 6 * k;
    for (int e = 0; e < 6; e++) {
      if (d[e] < n) continue; /* a block's component */
      out[d[e] - n] += f[e];
      if (m->damped) fd[d[e] - n] += fdk[e];
    }
  }
  for (int i = 0; i < 6; i++) out[i] += fd[i];
}

double vs_model_ext_friction_power(const vs_model *m, const double *qe, const double *ve) {
  return friction_core(m, &m->pate, qe, ve, qe + 3 * m->g->n_blocks, ve + 3 * m->g->n_blocks);
}

