/* The model (model.h): creation, with the block adjacency (the CSC patterns of
 * model_pattern.c) built once; its settings (support kinds, the joints' laws, the misfit of an
 * imperfect arch, damping, the gravity factor) and what it tells of itself. The assembly is in
 * model_residual.c, model_states.c and model_dynamics.c (model_internal.h). */
#include "model_internal.h"
#include "voussoir/support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

vs_status vs_model_create(const vs_geometry *g, const vs_joint_law *law, double alpha_rad,
                          vs_model **out, vs_error *err) {
  *out = NULL;
  if (!(law->kn > 0.0) || !(law->ks > 0.0) || !(law->mu > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "model: joint law kn = %g, ks = %g N/m^3, mu = %g (allowed: all > 0)",
                        law->kn, law->ks, law->mu);
  vs_model *m = calloc(1, sizeof *m);
  if (m == NULL) return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  m->g = g;
  m->law = *law;
  const vs_support_dir sd = vs_support_direction(alpha_rad); /* support.h: delta (dx, -dz) */
  const double fixed[3] = {0.0, 0.0, 0.0}, line[3] = {sd.dx, -sd.dz, 0.0};
  vs_support_motion_line(&m->mo[0], fixed);
  vs_support_motion_line(&m->mo[1], line);
  m->gscale = 1.0;
  m->mscale = 1.0;
  m->n = 3 * g->n_blocks;
  size_t nj = (size_t)g->n_joints;
  m->ra = calloc(2 * nj, sizeof(double));
  m->rb = calloc(2 * nj, sizeof(double));
  m->slip_p = calloc(nj, sizeof(double));
  m->cn = calloc(nj, sizeof(double));
  m->cs = calloc(nj, sizeof(double));
  m->laws = malloc(nj * sizeof *m->laws);
  m->rot = malloc(2 * ((size_t)g->n_blocks + 2) * sizeof *m->rot);
  m->rot_of = malloc(((size_t)g->n_blocks + 2) * sizeof *m->rot_of);
  m->memo = calloc(1, sizeof *m->memo);
  if (m->memo != NULL) {
    m->memo->q = malloc(3 * ((size_t)g->n_blocks + 1) * sizeof *m->memo->q);
    m->memo->pt = malloc((nj > 0 ? nj : 1) * sizeof *m->memo->pt);
  }
  m->fdw = malloc(3 * ((size_t)g->n_blocks + 2) * sizeof *m->fdw);
  if (m->ra == NULL || m->rb == NULL || m->slip_p == NULL || m->cn == NULL || m->cs == NULL ||
      m->laws == NULL || m->rot == NULL || m->fdw == NULL || m->rot_of == NULL ||
      m->memo == NULL || m->memo->q == NULL || m->memo->pt == NULL) {
    vs_model_destroy(&m);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
  for (int i = 0; i < g->n_blocks + 2; i++) m->rot_of[i] = NAN; /* no half angle yet */
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    m->laws[k] = *law;
    if (body_is_block(j->a)) {
      m->ra[2 * k] = j->px - g->blocks[j->a].cx;
      m->ra[2 * k + 1] = j->pz - g->blocks[j->a].cz;
    }
    if (body_is_block(j->b)) {
      m->rb[2 * k] = j->px - g->blocks[j->b].cx;
      m->rb[2 * k + 1] = j->pz - g->blocks[j->b].cz;
    }
  }
  vs_status st = vs_model_build_patterns(m, err);
  if (st != VS_OK) {
    vs_model_destroy(&m);
    return st;
  }
  *out = m;
  return VS_OK;
}

void vs_model_destroy(vs_model **m) {
  if (m == NULL || *m == NULL) return;
  vs_model *p = *m;
  free(p->ra);
  free(p->rb);
  free(p->slip_p);
  free(p->loads);
  free(p->dead);
  free(p->cn);
  free(p->cs);
  free(p->laws);
  free(p->rot);
  free(p->rot_of);
  if (p->memo != NULL) {
    free(p->memo->q);
    free(p->memo->pt);
    free(p->memo);
  }
  free(p->fdw);
  vs_model_pattern_free(&p->pat);
  vs_model_pattern_free(&p->pate);
  free(p);
  *m = NULL;
}

vs_status vs_model_set_support_kinds(vs_model *m, vs_support_kind left, vs_support_kind right,
                                     vs_error *err) {
  const vs_support_kind k[2] = {left, right};
  for (int s = 0; s < 2; s++)
    if (k[s] != VS_SUPPORT_FIXED && k[s] != VS_SUPPORT_PINNED)
      return vs_error_set(err, VS_ERR_INVALID, "model: %s support kind %d (allowed: fixed, pinned)",
                          s == 0 ? "left" : "right", (int)k[s]);
  m->pinned[0] = left == VS_SUPPORT_PINNED;
  m->pinned[1] = right == VS_SUPPORT_PINNED;
  return vs_model_build_patterns(m, err);
}

vs_support_kind vs_model_support_kind(const vs_model *m, int right) {
  return m->pinned[right ? 1 : 0] ? VS_SUPPORT_PINNED : VS_SUPPORT_FIXED;
}

int vs_model_support_dof(const vs_model *m, int right) {
  return m->pat.dof[3 * (m->g->n_blocks + (right ? 1 : 0)) + 2];
}

void vs_model_band_order(const vs_model *m, int *perm) {
  const int left = vs_model_support_dof(m, 0), right = vs_model_support_dof(m, 1);
  int k = 0;
  if (left >= 0) perm[k++] = left;
  for (int i = 0; i < m->n; i++)
    if (i != left && i != right) perm[k++] = i;
  if (right >= 0) perm[k++] = right;
}

int vs_model_size(const vs_model *m) { return m->n; }
int vs_model_nnz(const vs_model *m) { return m->pat.nnz; }
const vs_geometry *vs_model_geometry(const vs_model *m) { return m->g; }
const vs_joint_law *vs_model_law(const vs_model *m) { return &m->law; }
const double *vs_model_slips(const vs_model *m) { return m->slip_p; }
double vs_model_cracking_energy(const vs_model *m) { return m->cracking; }

void vs_model_support_displacement(const vs_model *m, double delta, double u[2]) {
  double qs[6];
  vs_model_support_position(m, NULL, delta, qs);
  u[0] = qs[3];
  u[1] = qs[4];
}

vs_status vs_model_set_support_motion(vs_model *m, int right, const vs_support_motion *mo,
                                      vs_error *err) {
  if (mo->n < 1 || mo->n > VS_SUPPORT_SEGMENTS_MAX || mo->d[0] != 0.0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "model: %s support motion of %d segments from %g m (allowed: 1 .. %d, "
                        "from 0)",
                        right ? "right" : "left", mo->n, mo->d[0], VS_SUPPORT_SEGMENTS_MAX);
  for (int i = 1; i < mo->n; i++)
    if (!(mo->d[i] > mo->d[i - 1]))
      return vs_error_set(err, VS_ERR_INVALID,
                          "model: %s support motion: segment %d starts at %g m, not after %g m "
                          "(allowed: increasing)",
                          right ? "right" : "left", i + 1, mo->d[i], mo->d[i - 1]);
  m->mo[right ? 1 : 0] = *mo;
  memo_drop(m);
  return VS_OK;
}

const vs_support_motion *vs_model_support_motion(const vs_model *m, int right) {
  return &m->mo[right ? 1 : 0];
}

void vs_model_support_position(const vs_model *m, const double *q, double delta, double u[6]) {
  sup_state_q(m, q, delta, u);
  u[3] += m->mscale * m->offset[0]; /* always added (sup_pos_q: only when there is one): a
                                       settlement's -0 is written 0, as it always was */
  u[4] += m->mscale * m->offset[1];
}

double vs_model_support_next_kink(const vs_model *m, double delta, double tol) {
  return fmin(vs_support_motion_next(&m->mo[0], delta, tol),
              vs_support_motion_next(&m->mo[1], delta, tol));
}

vs_status vs_model_set_joint_law(vs_model *m, int k, const vs_joint_law *law, vs_error *err) {
  if (k < 0 || k >= m->g->n_joints)
    return vs_error_set(err, VS_ERR_INVALID, "model: joint %d (allowed: 1..%d)", k + 1,
                        m->g->n_joints);
  if (!(law->kn > 0.0) || !(law->ks > 0.0) || !(law->mu > 0.0) || !isfinite(law->gap0) ||
      !isfinite(law->gap1))
    return vs_error_set(err, VS_ERR_INVALID,
                        "model: joint %d law kn = %g, ks = %g N/m^3, mu = %g, gap %g m, %g "
                        "(allowed: kn, ks, mu > 0, gaps finite)",
                        k + 1, law->kn, law->ks, law->mu, law->gap0, law->gap1);
  if (law->env_n < 0 || law->env_n > VS_JOINT_ENV_MAX || law->env_n == 1)
    return vs_error_set(err, VS_ERR_INVALID,
                        "model: joint %d law env_n = %d (allowed: 0, undamaged, or 2..%d "
                        "vertices of its damage envelope)",
                        k + 1, law->env_n, VS_JOINT_ENV_MAX);
  m->laws[k] = *law;
  memo_drop(m);
  vs_model_set_damping(m, m->zeta); /* the damping coefficients follow the joint's stiffness */
  return VS_OK;
}

const vs_joint_law *vs_model_joint_law(const vs_model *m, int k) { return &m->laws[k]; }

void vs_model_set_support_offset(vs_model *m, const double offset[2]) {
  m->offset[0] = offset[0];
  m->offset[1] = offset[1];
}

int vs_model_has_misfit(const vs_model *m) {
  if (m->offset[0] != 0.0 || m->offset[1] != 0.0) return 1;
  for (int k = 0; k < m->g->n_joints; k++)
    if (m->laws[k].gap0 != 0.0 || m->laws[k].gap1 != 0.0) return 1;
  return 0;
}

void vs_model_set_misfit_scale(vs_model *m, double s) {
  m->mscale = s;
  memo_drop(m); /* the joints' initial gaps scale with it */
}

void vs_model_set_damping(vs_model *m, double zeta) {
  const vs_geometry *g = m->g;
  m->zeta = zeta;
  m->alpha_m = m->beta_k = 0.0;
  m->damped = zeta > 0.0;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    const double A = j->depth * j->length;
    double ma = body_is_block(j->a) ? g->blocks[j->a].mass : INFINITY;
    double mb = body_is_block(j->b) ? g->blocks[j->b].mass : INFINITY;
    const double mr = isinf(ma) ? mb : isinf(mb) ? ma : ma * mb / (ma + mb);
    m->cn[k] = 2.0 * zeta * sqrt(m->laws[k].kn * A * mr) / A;
    m->cs[k] = 2.0 * zeta * sqrt(m->laws[k].ks * A * mr) / A;
  }
}

double vs_model_damping_ratio(const vs_model *m) { return m->zeta; }

void vs_model_set_rayleigh(vs_model *m, double alpha, double beta) {
  m->zeta = 0.0;
  m->alpha_m = alpha;
  m->beta_k = beta;
  m->damped = beta > 0.0;
}

void vs_model_set_gravity_scale(vs_model *m, double lambda) { m->gscale = lambda; }
double vs_model_gravity_scale(const vs_model *m) { return m->gscale; }

/* --- driven supports: the extended state qe = (blocks, left support, right support) --- */

int vs_model_ext_size(const vs_model *m) { return m->pate.n; }
int vs_model_ext_nnz(const vs_model *m) { return m->pate.nnz; }

void vs_model_support_states(const vs_model *m, double delta, double rate, double qs[6],
                             double vs[6]) {
  sup_pos_q(m, NULL, delta, qs);
  sup_vel_q(m, NULL, delta, rate, vs);
}

