/* The model: equilibrium residual of the rigid blocks and its analytic CSC Jacobian, both
 * assembled from one joint-law evaluation per joint. The block adjacency (and so the CSC
 * pattern and the scatter map of every joint's 6x6 stiffness) is built once at creation. */
#include "voussoir/model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sunmatrix/sunmatrix_sparse.h>

struct vs_model {
  const vs_geometry *g;
  vs_joint_law law;
  vs_joint_law *laws; /* per joint: the law (the nominal one unless an imperfection changed it) */
  double dir[2];   /* unit direction of the right support's motion */
  double offset[2]; /* initial offset of the right support, m, applied with the gravity factor */
  int n;           /* unknowns, 3 per block */
  double *ra, *rb; /* per joint: reference point of body a/b -> joint centre, m */
  double *slip_p;  /* per joint: committed plastic slip, m */
  double zeta;     /* damping ratio */
  double gscale;   /* gravity load factor (1: the arch's own weight) */
  double mscale;   /* misfit factor: fraction of the face gaps and support offset applied */
  double *cn, *cs; /* per joint: damping coefficients, N s/m^3 */
  sunindextype *colptr, *rowind;
  int nnz;
  int *blk_start;  /* CSC: per block column, offset of its first row-block in adj[] */
  int *adj;        /* per block column, the sorted blocks coupled to it */
};

static int body_is_block(int body) { return body >= 0; }

/* The (ux, uz, theta) of a body -- or its velocities, given v and the support's speed: a block's
 * from the state vector, the right support's its scalar motion along dir, the left support's 0. */
static void body_q(const vs_model *m, const double *q, double delta, int body, double out[3]) {
  if (body_is_block(body)) {
    memcpy(out, q + 3 * body, 3 * sizeof(double));
  } else if (body == VS_SUPPORT_RIGHT) {
    out[0] = delta * m->dir[0];
    out[1] = delta * m->dir[1];
    out[2] = 0.0;
  } else {
    out[0] = out[1] = out[2] = 0.0;
  }
}

/* body_q for positions: the right support also carries its initial offset. */
static void body_pos(const vs_model *m, const double *q, double delta, int body, double out[3]) {
  body_q(m, q, delta, body, out);
  if (body == VS_SUPPORT_RIGHT && (m->offset[0] != 0.0 || m->offset[1] != 0.0)) {
    out[0] += m->mscale * m->offset[0];
    out[1] += m->mscale * m->offset[1];
  }
}

static int cmp_int(const void *x, const void *y) {
  int a = *(const int *)x, b = *(const int *)y;
  return (a > b) - (a < b);
}

/* Block adjacency (each block with itself and its joint neighbours) -> CSC pattern. */
static vs_status build_pattern(vs_model *m, vs_error *err) {
  const vs_geometry *g = m->g;
  const int nb = g->n_blocks;
  int *deg = calloc((size_t)nb + 1, sizeof *deg);
  if (deg == NULL) return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  for (int i = 0; i < nb; i++) deg[i] = 1;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    if (body_is_block(j->a) && body_is_block(j->b) && j->a != j->b) {
      deg[j->a]++;
      deg[j->b]++;
    }
  }
  m->blk_start = malloc(((size_t)nb + 1) * sizeof *m->blk_start);
  int total = 0;
  for (int i = 0; i < nb; i++) total += deg[i];
  m->adj = malloc((size_t)total * sizeof *m->adj);
  if (m->blk_start == NULL || m->adj == NULL) {
    free(deg);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
  m->blk_start[0] = 0;
  for (int i = 0; i < nb; i++) m->blk_start[i + 1] = m->blk_start[i] + deg[i];
  for (int i = 0; i < nb; i++) {
    m->adj[m->blk_start[i]] = i;
    deg[i] = 1; /* reuse as fill counter */
  }
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    if (body_is_block(j->a) && body_is_block(j->b) && j->a != j->b) {
      m->adj[m->blk_start[j->a] + deg[j->a]++] = j->b;
      m->adj[m->blk_start[j->b] + deg[j->b]++] = j->a;
    }
  }
  free(deg);
  /* sort and remove duplicates (two joints between the same blocks) */
  int w = 0;
  for (int i = 0; i < nb; i++) {
    int s = m->blk_start[i], e = m->blk_start[i + 1];
    qsort(m->adj + s, (size_t)(e - s), sizeof(int), cmp_int);
    m->blk_start[i] = w;
    for (int p = s; p < e; p++)
      if (p == s || m->adj[p] != m->adj[p - 1]) m->adj[w++] = m->adj[p];
  }
  m->blk_start[nb] = w;
  m->nnz = 9 * w;
  m->colptr = malloc(((size_t)m->n + 1) * sizeof *m->colptr);
  m->rowind = malloc((size_t)m->nnz * sizeof *m->rowind);
  if (m->colptr == NULL || m->rowind == NULL)
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  sunindextype p = 0;
  for (int bj = 0; bj < nb; bj++) {
    for (int cj = 0; cj < 3; cj++) {
      m->colptr[3 * bj + cj] = p;
      for (int q = m->blk_start[bj]; q < m->blk_start[bj + 1]; q++)
        for (int ci = 0; ci < 3; ci++) m->rowind[p++] = 3 * m->adj[q] + ci;
    }
  }
  m->colptr[m->n] = p;
  return VS_OK;
}

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
  m->dir[0] = sin(alpha_rad);
  m->dir[1] = -cos(alpha_rad);
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
  if (m->ra == NULL || m->rb == NULL || m->slip_p == NULL || m->cn == NULL || m->cs == NULL ||
      m->laws == NULL) {
    vs_model_destroy(&m);
    return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
  }
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
  vs_status st = build_pattern(m, err);
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
  free(p->cn);
  free(p->cs);
  free(p->laws);
  free(p->colptr);
  free(p->rowind);
  free(p->blk_start);
  free(p->adj);
  free(p);
  *m = NULL;
}

int vs_model_size(const vs_model *m) { return m->n; }
int vs_model_nnz(const vs_model *m) { return m->nnz; }
const vs_geometry *vs_model_geometry(const vs_model *m) { return m->g; }
const vs_joint_law *vs_model_law(const vs_model *m) { return &m->law; }
const double *vs_model_slips(const vs_model *m) { return m->slip_p; }

void vs_model_support_displacement(const vs_model *m, double delta, double u[2]) {
  u[0] = delta * m->dir[0] + m->mscale * m->offset[0];
  u[1] = delta * m->dir[1] + m->mscale * m->offset[1];
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
  m->laws[k] = *law;
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

void vs_model_set_misfit_scale(vs_model *m, double s) { m->mscale = s; }

/* The law of joint k at the current misfit factor (vs_model_set_misfit_scale). */
static const vs_joint_law *law_at(const vs_model *m, int k, vs_joint_law *tmp) {
  const vs_joint_law *l = &m->laws[k];
  if (m->mscale == 1.0 || (l->gap0 == 0.0 && l->gap1 == 0.0)) return l;
  *tmp = *l;
  tmp->gap0 *= m->mscale;
  tmp->gap1 *= m->mscale;
  return tmp;
}

static void eval_joint(const vs_model *m, const double *q, double delta, int k, vs_joint_state *st,
                       double f[6], double K[36]) {
  const vs_joint_geom *j = &m->g->joints[k];
  double qa[3], qb[3];
  vs_joint_law tmp;
  body_pos(m, q, delta, j->a, qa);
  body_pos(m, q, delta, j->b, qb);
  vs_joint_eval(j, law_at(m, k, &tmp), qa, qb, m->ra + 2 * k, m->rb + 2 * k, m->slip_p[k], st, f, K);
}

void vs_model_residual(const vs_model *m, const double *q, double delta, double *G) {
  const vs_geometry *g = m->g;
  for (int i = 0; i < g->n_blocks; i++) {
    G[3 * i] = 0.0;
    G[3 * i + 1] = m->gscale * g->blocks[i].mass * g->gravity; /* minus the load -m g */
    G[3 * i + 2] = 0.0;
  }
  for (int k = 0; k < g->n_joints; k++) {
    double f[6];
    eval_joint(m, q, delta, k, NULL, f, NULL);
    const int body[2] = {g->joints[k].a, g->joints[k].b};
    for (int s = 0; s < 2; s++)
      if (body_is_block(body[s]))
        for (int c = 0; c < 3; c++) G[3 * body[s] + c] += f[3 * s + c];
  }
}

/* Position in the CSC data of entry (row block bi, column block bj), component (0, 0). */
static sunindextype csc_pos(const vs_model *m, int bi, int bj) {
  int lo = m->blk_start[bj], hi = m->blk_start[bj + 1] - 1;
  while (lo < hi) { /* adjacency lists are sorted */
    int mid = (lo + hi) / 2;
    if (m->adj[mid] < bi) lo = mid + 1;
    else hi = mid;
  }
  return m->colptr[3 * bj] + 3 * (lo - m->blk_start[bj]);
}

/* Write the CSC pattern into A, zero its values and return them. */
static double *csc_reset(const vs_model *m, SUNMatrix A) {
  memcpy(SUNSparseMatrix_IndexPointers(A), m->colptr, ((size_t)m->n + 1) * sizeof(sunindextype));
  memcpy(SUNSparseMatrix_IndexValues(A), m->rowind, (size_t)m->nnz * sizeof(sunindextype));
  double *data = SUNSparseMatrix_Data(A);
  memset(data, 0, (size_t)m->nnz * sizeof *data);
  return data;
}

/* Add a joint's 6x6 matrix (row-major, rows and columns (body a, body b)) into the CSC values. */
static void scatter_joint(const vs_model *m, const int body[2], const double Kj[36], double *data) {
  for (int si = 0; si < 2; si++) {
    if (!body_is_block(body[si])) continue;
    for (int sj = 0; sj < 2; sj++) {
      if (!body_is_block(body[sj])) continue;
      const sunindextype p0 = csc_pos(m, body[si], body[sj]);
      const sunindextype stride = m->colptr[3 * body[sj] + 1] - m->colptr[3 * body[sj]];
      for (int cj = 0; cj < 3; cj++)
        for (int ci = 0; ci < 3; ci++) data[p0 + cj * stride + ci] += Kj[(3 * si + ci) * 6 + 3 * sj + cj];
    }
  }
}

int vs_model_jacobian(const vs_model *m, const double *q, double delta, SUNMatrix J) {
  double *data = csc_reset(m, J);
  const vs_geometry *g = m->g;
  for (int k = 0; k < g->n_joints; k++) {
    double K[36];
    eval_joint(m, q, delta, k, NULL, NULL, K);
    const int body[2] = {g->joints[k].a, g->joints[k].b};
    scatter_joint(m, body, K, data);
  }
  return 0;
}

void vs_model_dG_ddelta(const vs_model *m, const double *q, double delta, double *out) {
  const vs_geometry *g = m->g;
  memset(out, 0, (size_t)m->n * sizeof *out);
  for (int k = 0; k < g->n_joints; k++) {
    const int body[2] = {g->joints[k].a, g->joints[k].b};
    int ss = (body[1] == VS_SUPPORT_RIGHT) ? 1 : (body[0] == VS_SUPPORT_RIGHT) ? 0 : -1;
    if (ss < 0) continue;
    double K[36];
    eval_joint(m, q, delta, k, NULL, NULL, K);
    for (int si = 0; si < 2; si++) {
      if (!body_is_block(body[si])) continue;
      for (int ci = 0; ci < 3; ci++) {
        const double *row = K + (3 * si + ci) * 6 + 3 * ss;
        out[3 * body[si] + ci] += row[0] * m->dir[0] + row[1] * m->dir[1];
      }
    }
  }
}

void vs_model_joint_states(const vs_model *m, const double *q, double delta, vs_joint_state *st) {
  for (int k = 0; k < m->g->n_joints; k++) eval_joint(m, q, delta, k, &st[k], NULL, NULL);
}

int vs_model_commit(vs_model *m, const double *q, double delta) {
  int slid = 0;
  for (int k = 0; k < m->g->n_joints; k++) {
    vs_joint_state st;
    eval_joint(m, q, delta, k, &st, NULL, NULL);
    if (st.sliding && st.N > 0.0) slid++;
    m->slip_p[k] = st.slip_p;
  }
  return slid;
}

void vs_model_reactions(const vs_model *m, const double *q, double delta, double left[2],
                        double right[2]) {
  left[0] = left[1] = right[0] = right[1] = 0.0;
  for (int k = 0; k < m->g->n_joints; k++) {
    const vs_joint_geom *j = &m->g->joints[k];
    if (body_is_block(j->a) && body_is_block(j->b)) continue; /* not at a support */
    double f[6];
    eval_joint(m, q, delta, k, NULL, f, NULL);
    /* f on a support's translation is dE/du_support; the arch pushes it with -f */
    const int body[2] = {j->a, j->b};
    for (int s = 0; s < 2; s++) {
      double *r = (body[s] == VS_SUPPORT_LEFT) ? left : (body[s] == VS_SUPPORT_RIGHT) ? right : NULL;
      if (r == NULL) continue;
      r[0] -= f[3 * s];
      r[1] -= f[3 * s + 1];
    }
  }
}

double vs_model_energy(const vs_model *m, const double *q, double delta) {
  const vs_geometry *g = m->g;
  double e = 0.0;
  for (int i = 0; i < g->n_blocks; i++) e += m->gscale * g->blocks[i].mass * g->gravity * q[3 * i + 1];
  for (int k = 0; k < g->n_joints; k++) {
    vs_joint_state st;
    eval_joint(m, q, delta, k, &st, NULL, NULL);
    e += st.energy;
  }
  return e;
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
}

/* --- dynamics --- */

void vs_model_set_damping(vs_model *m, double zeta) {
  const vs_geometry *g = m->g;
  m->zeta = zeta;
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

void vs_model_set_gravity_scale(vs_model *m, double lambda) { m->gscale = lambda; }
double vs_model_gravity_scale(const vs_model *m) { return m->gscale; }

void vs_model_damping(const vs_model *m, const double *q, const double *v, double delta,
                      double ddelta_dt, double *fd, double *dissipated, double *support_power,
                      SUNMatrix C) {
  const vs_geometry *g = m->g;
  double *data = NULL;
  if (fd != NULL) memset(fd, 0, (size_t)m->n * sizeof *fd);
  if (C != NULL) data = csc_reset(m, C);
  double diss = 0.0, sup = 0.0;
  if (m->zeta > 0.0) {
    for (int k = 0; k < g->n_joints; k++) {
      const vs_joint_geom *j = &g->joints[k];
      double qa[3], qb[3], va[3], vb[3], f[6], Ck[36], p;
      vs_joint_law tmp;
      body_pos(m, q, delta, j->a, qa);
      body_pos(m, q, delta, j->b, qb);
      body_q(m, v, ddelta_dt, j->a, va);
      body_q(m, v, ddelta_dt, j->b, vb);
      vs_joint_damping(j, law_at(m, k, &tmp), m->cn[k], m->cs[k], qa, qb, va, vb, m->ra + 2 * k, m->rb + 2 * k,
                       f, C != NULL ? Ck : NULL, &p);
      diss += p;
      const int body[2] = {j->a, j->b};
      for (int s = 0; s < 2; s++) {
        if (body[s] == VS_SUPPORT_RIGHT)
          sup -= f[3 * s] * ddelta_dt * m->dir[0] + f[3 * s + 1] * ddelta_dt * m->dir[1];
        if (!body_is_block(body[s])) continue;
        if (fd != NULL)
          for (int c = 0; c < 3; c++) fd[3 * body[s] + c] += f[3 * s + c];
      }
      if (C != NULL) scatter_joint(m, body, Ck, data);
    }
  }
  /* the support does the work -f . u_dot on the arch through the damper: the dissipated power
   * splits into what the blocks lose (fd . v) and what the support supplies */
  if (dissipated != NULL) *dissipated = diss;
  if (support_power != NULL) *support_power = -sup;
}

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

double vs_model_friction_power(const vs_model *m, const double *q, const double *v, double delta,
                               double ddelta_dt) {
  double p = 0.0;
  for (int k = 0; k < m->g->n_joints; k++) {
    const vs_joint_geom *j = &m->g->joints[k];
    double qa[3], qb[3], va[3], vb[3];
    vs_joint_law tmp;
    body_pos(m, q, delta, j->a, qa);
    body_pos(m, q, delta, j->b, qb);
    body_q(m, v, ddelta_dt, j->a, va);
    body_q(m, v, ddelta_dt, j->b, vb);
    p += vs_joint_friction_power(j, law_at(m, k, &tmp), qa, qb, va, vb, m->ra + 2 * k, m->rb + 2 * k,
                                 m->slip_p[k]);
  }
  return p;
}

double vs_model_support_force(const vs_model *m, const double *q, double delta) {
  double left[2], right[2];
  vs_model_reactions(m, q, delta, left, right);
  /* dE/du_support = f = -(force of the arch on the support) */
  return -(right[0] * m->dir[0] + right[1] * m->dir[1]);
}

void vs_model_energies(const vs_model *m, const double *q, double delta, double *elastic,
                       double *gravity) {
  const vs_geometry *g = m->g;
  double eg = 0.0, ee = 0.0;
  for (int i = 0; i < g->n_blocks; i++) eg += m->gscale * g->blocks[i].mass * g->gravity * q[3 * i + 1];
  for (int k = 0; k < g->n_joints; k++) {
    vs_joint_state st;
    eval_joint(m, q, delta, k, &st, NULL, NULL);
    ee += st.energy;
  }
  *elastic = ee;
  *gravity = eg;
}
