/* Ground contact of the blocks' vertices during the fall (see contact.h for the law): forces,
 * their analytic Jacobian on the blocks' own 3x3 diagonal blocks, the root functions of a vertex
 * crossing the ground, the stored energy and the friction anchors' return mapping. */
#include "contact.h"

#include "outline.h"

#include <math.h>
#include <stdlib.h>
#include <sunmatrix/sunmatrix_sparse.h>

typedef struct {
  int block;
  double rx, rz; /* from the block's centroid in the reference configuration, m */
  double kv, kt; /* normal and tangential stiffness, N/m */
  double cv;     /* dashpot, N s/m */
  double pf;     /* penetration over which the dashpot fades in, m */
  double xa;     /* friction anchor: x where the tangential spring is unstretched, m */
} vertex;

struct vs_contact {
  const vs_model *m;
  int nv;
  vertex *v;
  double mu;
  int armed;
  double level;
};

/* Everything one vertex's evaluation gives: gz = dz/dq, gx = dx/dq over the block's (ux, uz,
 * theta), penetration, forces and the regime. */
typedef struct {
  double x, z, Rx, Rz, gz[3], gx[3];
  double p, Ne, Nd, T, s; /* s: the dashpot's fade factor */
  int sliding;           /* -1, +1: sliding (T = sliding mu Ne), 0: sticking */
} vertex_eval;

/* cos and sin of a block's rotation, computed once for its consecutive vertices */
typedef struct {
  int block;
  double theta, cs, sn;
} rot_cache;

static void eval_vertex_r(const vs_contact *c, const vertex *vx, const double *qe,
                          const double *ve, rot_cache *rc, vertex_eval *o) {
  const vs_block *b = &vs_model_geometry(c->m)->blocks[vx->block];
  const double *q = qe + 3 * vx->block;
  if (rc->block != vx->block || rc->theta != q[2]) {
    rc->block = vx->block;
    rc->theta = q[2];
    rc->cs = cos(q[2]);
    rc->sn = sin(q[2]);
  }
  const double cs = rc->cs, sn = rc->sn;
  o->Rx = cs * vx->rx - sn * vx->rz;
  o->Rz = sn * vx->rx + cs * vx->rz;
  o->x = b->cx + q[0] + o->Rx;
  o->z = b->cz + q[1] + o->Rz;
  o->gz[0] = 0.0, o->gz[1] = 1.0, o->gz[2] = o->Rx;
  o->gx[0] = 1.0, o->gx[1] = 0.0, o->gx[2] = -o->Rz;
  /* summed from the block's displacement last: near touch-down p is then resolved to the
   * round-off of q[1], not of the vertex's height (IDA's root search needs p to change) */
  o->p = -(q[1] + ((b->cz - c->level) + o->Rz));
  o->Ne = o->Nd = o->T = o->s = 0.0;
  o->sliding = 0;
  if (!c->armed || !(o->p > 0.0)) return;
  o->Ne = vx->kv * o->p;
  o->s = fmin(1.0, o->p / vx->pf);
  if (ve != NULL) {
    const double *v = ve + 3 * vx->block;
    const double pdot = -(v[1] + o->Rx * v[2]);
    o->Nd = vx->cv * o->s * pdot;
  }
  const double trial = vx->kt * (o->x - vx->xa), cap = c->mu * o->Ne;
  if (fabs(trial) > cap) {
    o->sliding = trial > 0.0 ? 1 : -1;
    o->T = o->sliding * cap;
  } else {
    o->T = trial;
  }
}

static void eval_vertex(const vs_contact *c, const vertex *vx, const double *qe, const double *ve,
                        vertex_eval *o) {
  rot_cache rc = {.block = -1};
  eval_vertex_r(c, vx, qe, ve, &rc, o);
}

static vs_status add_vertex(vs_contact *c, int k, int block, double x, double z, vs_error *err) {
  const vs_geometry *g = vs_model_geometry(c->m);
  const vs_joint_law *law = vs_model_law(c->m);
  if (block < 0 || block >= g->n_blocks || !isfinite(x) || !isfinite(z))
    return vs_error_set(err, VS_ERR_INVALID, "contact: vertex %d on block %d at (%g, %g) m "
                        "(allowed: a block 0..%d, finite coordinates)", k, block, x, z,
                        g->n_blocks - 1);
  const vs_block *b = &g->blocks[block];
  vertex *vx = &c->v[k];
  vx->block = block;
  vx->rx = x - b->cx;
  vx->rz = z - b->cz;
  vx->kv = 0.5 * law->kn * g->joints[0].depth * g->joints[0].length;
  vx->kt = vx->kv * law->ks / law->kn;
  vx->pf = b->mass * g->gravity / vx->kv;
  vx->cv = 0.0; /* set by the caller from the restitution */
  vx->xa = x;
  return VS_OK;
}

/* The end of face edge ei (0: its start, 1: its end) in the hull (edge_of as vs_block_hull's),
 * or -1 when it is not a vertex there. */
static int face_end(const vs_block *b, const int *edge_of, int nh, int ei, int end) {
  const int want = end == 0 ? ei : b->edge0 + (ei - b->edge0 + 1) % b->n_edges;
  for (int v = 0; v < nh; v++)
    if (edge_of[v] == want) return v;
  return -1;
}

/* Append hull vertex v of block i (unless seen, or on a support's face). */
static void take(int i, const double *hx, int v, unsigned char *seen, int *block, double *xz,
                 int *n) {
  if (v < 0 || seen[v]) return;
  seen[v] = 1;
  if (block != NULL) {
    block[*n] = i;
    xz[2 * *n] = hx[2 * v];
    xz[2 * *n + 1] = hx[2 * v + 1];
  }
  (*n)++;
}

/* Face edge ei's two ends, intrados first (along its joint's tangent). */
static void take_face(const vs_geometry *g, int i, const double *hx, const int *eo, int nh, int ei,
                      unsigned char *seen, int *block, double *xz, int *n) {
  const vs_block *b = &g->blocks[i];
  const vs_joint_geom *j = &g->joints[g->edges[ei].joint];
  int v[2] = {face_end(b, eo, nh, ei, 0), face_end(b, eo, nh, ei, 1)};
  double sx, sz, eta[2] = {0.0, 0.0};
  vs_joint_tangent(j, &sx, &sz);
  for (int k = 0; k < 2; k++)
    if (v[k] >= 0) eta[k] = (hx[2 * v[k]] - j->px) * sx + (hx[2 * v[k] + 1] - j->pz) * sz;
  if (eta[1] < eta[0]) {
    const int t = v[0];
    v[0] = v[1], v[1] = t;
  }
  if (j->a < 0 || j->b < 0) { /* on a springing face: they sit on the pier */
    for (int k = 0; k < 2; k++)
      if (v[k] >= 0) seen[v[k]] = 1;
    return;
  }
  for (int k = 0; k < 2; k++) take(i, hx, v[k], seen, block, xz, n);
}

/* The blocks' vertices: per block the corners and bulges of its convex outline (outline.h;
 * for an arch voussoir its four corners and its extrados arc's mid-point), less the corners on
 * a springing face. Per block, along the arch: the ends of its face on its lowest-numbered joint
 * (intrados, extrados), the vertices on no face (going back round the outline from there), the
 * ends of its other faces by joint (intrados, extrados). -1 when an outline cannot be made
 * convex. */
static int arch_vertices(const vs_geometry *g, int *block, double *xz) {
  int n = 0;
  for (int i = 0; i < g->n_blocks; i++) {
    const vs_block *b = &g->blocks[i];
    double hx[2 * VS_HULL_MAX];
    int eo[VS_HULL_MAX], lo = -1;
    unsigned char seen[VS_HULL_MAX] = {0}, face[VS_HULL_MAX] = {0};
    const int nh = vs_block_hull(g, i, hx, eo);
    if (nh < 0) return -1;
    for (int k = 0; k < b->n_edges; k++) {
      const int ei = b->edge0 + k, jn = g->edges[ei].joint;
      if (jn < 0) continue;
      if (lo < 0 || jn < g->edges[lo].joint) lo = ei;
      for (int e = 0; e < 2; e++) {
        const int v = face_end(b, eo, nh, ei, e);
        if (v >= 0) face[v] = 1;
      }
    }
    int start = 0;
    if (lo >= 0) {
      take_face(g, i, hx, eo, nh, lo, seen, block, xz, &n);
      const int v = face_end(b, eo, nh, lo, 0);
      start = v >= 0 ? v : 0;
    }
    for (int k = 1; k <= nh; k++) { /* back round the outline from the first face */
      const int v = (start - k + nh) % nh;
      if (!face[v]) take(i, hx, v, seen, block, xz, &n);
    }
    for (int done = lo; done >= 0;) { /* the other faces, by joint */
      int next = -1;
      for (int k = 0; k < b->n_edges; k++) {
        const int ei = b->edge0 + k, jn = g->edges[ei].joint;
        if (jn > g->edges[done].joint && (next < 0 || jn < g->edges[next].joint)) next = ei;
      }
      if (next >= 0) take_face(g, i, hx, eo, nh, next, seen, block, xz, &n);
      done = next;
    }
  }
  return n;
}

static vs_status fill_vertices(vs_contact *c, int nv, const int *block, const double *xz,
                               vs_error *err) {
  for (int k = 0; k < nv; k++) {
    vs_status st = add_vertex(c, k, block[k], xz[2 * k], xz[2 * k + 1], err);
    if (st != VS_OK) return st;
  }
  return VS_OK;
}

vs_status vs_contact_create(const vs_model *m, double restitution, int nv, const int *block,
                            const double *xz, vs_contact **out, vs_error *err) {
  *out = NULL;
  if (!(restitution > 0.0 && restitution <= 1.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "contact: restitution = %g (allowed: 0 < e <= 1)", restitution);
  const vs_geometry *g = vs_model_geometry(m);
  const int own = nv == 0;
  if (own) nv = arch_vertices(g, NULL, NULL);
  if (nv < 0)
    return vs_error_set(err, VS_ERR_INVALID, "contact: a block's outline cannot be made convex");
  if (nv < 1) return vs_error_set(err, VS_ERR_INVALID, "contact: no vertices (allowed: >= 1)");
  vs_contact *c = calloc(1, sizeof *c);
  int *ob = own ? malloc((size_t)nv * sizeof *ob) : NULL;
  double *oxz = own ? malloc((size_t)(2 * nv) * sizeof *oxz) : NULL;
  if (c != NULL) c->v = calloc((size_t)nv, sizeof *c->v);
  if (c == NULL || c->v == NULL || (own && (ob == NULL || oxz == NULL))) {
    free(ob);
    free(oxz);
    vs_contact_destroy(&c);
    return vs_error_set(err, VS_ERR_NOMEM, "contact: out of memory");
  }
  if (own) arch_vertices(g, ob, oxz);
  c->m = m;
  c->nv = nv;
  c->mu = vs_model_law(m)->mu;
  vs_status st = fill_vertices(c, nv, own ? ob : block, own ? oxz : xz, err);
  free(ob);
  free(oxz);
  if (st != VS_OK) {
    vs_contact_destroy(&c);
    return st;
  }
  /* calibrated on a block landing flat on a face: two vertices, each carrying half its mass */
  const double pi = 3.14159265358979323846, le = log(restitution);
  const double zeta = -le / sqrt(pi * pi + le * le);
  for (int k = 0; k < nv; k++)
    c->v[k].cv = 2.0 * zeta * sqrt(0.5 * c->v[k].kv * g->blocks[c->v[k].block].mass);
  *out = c;
  return VS_OK;
}

void vs_contact_destroy(vs_contact **c) {
  if (c == NULL || *c == NULL) return;
  free((*c)->v);
  free(*c);
  *c = NULL;
}

void vs_contact_arm(vs_contact *c, double level, const double *qe) {
  c->armed = 1;
  c->level = level;
  vs_contact_commit(c, qe);
}

void vs_contact_disarm(vs_contact *c) { c->armed = 0; }
int vs_contact_armed(const vs_contact *c) { return c->armed; }
double vs_contact_level(const vs_contact *c) { return c->level; }
int vs_contact_count(const vs_contact *c) { return c->nv; }

double vs_contact_springing_base(const vs_model *m, const double *qe) {
  const vs_geometry *g = vs_model_geometry(m);
  /* the supports' faces: the springings, or with piers the piers' bases */
  const vs_joint_geom *jg[2] = {&g->joints[vs_geometry_support_joint(g, 0)],
                                &g->joints[vs_geometry_support_joint(g, 1)]};
  double low = INFINITY;
  for (int s = 0; s < 2; s++) {
    const double *qs = qe + 3 * g->n_blocks + 3 * s;
    double sx, sz;
    vs_joint_tangent(jg[s], &sx, &sz);
    const double rx = -0.5 * jg[s]->length * sx, rz = -0.5 * jg[s]->length * sz;
    low = fmin(low, jg[s]->pz + qs[1] + sin(qs[2]) * rx + cos(qs[2]) * rz);
  }
  return low;
}

void vs_contact_vertex(const vs_contact *c, const double *qe, int k, double *x, double *z) {
  vertex_eval o;
  eval_vertex(c, &c->v[k], qe, NULL, &o);
  *x = o.x;
  *z = o.z;
}

void vs_contact_roots(const vs_contact *c, const double *qe, double *g) {
  rot_cache rc = {.block = -1};
  for (int k = 0; k < c->nv; k++) {
    vertex_eval o;
    eval_vertex_r(c, &c->v[k], qe, NULL, &rc, &o);
    g[k] = -o.p;
  }
}

void vs_contact_forces(const vs_contact *c, const double *qe, const double *ve, double *F,
                       double *damped, double *friction) {
  if (!c->armed) return;
  rot_cache rc = {.block = -1};
  for (int k = 0; k < c->nv; k++) {
    const vertex *vx = &c->v[k];
    vertex_eval o;
    eval_vertex_r(c, vx, qe, ve, &rc, &o);
    if (!(o.p > 0.0)) continue;
    if (F != NULL)
      for (int i = 0; i < 3; i++) F[3 * vx->block + i] += -(o.Ne + o.Nd) * o.gz[i] + o.T * o.gx[i];
    const double *v = ve + 3 * vx->block;
    const double pdot = -(v[1] + o.Rx * v[2]), xdot = v[0] - o.Rz * v[2];
    if (damped != NULL) *damped += o.Nd * pdot;
    if (friction != NULL && o.sliding != 0)
      *friction += o.T * (xdot - o.sliding * c->mu * vx->kv * pdot / vx->kt);
  }
}

/* Index of entry (row, col) in the pattern of A (-1 if absent). */
static sunindextype entry(SUNMatrix A, sunindextype row, sunindextype col) {
  const sunindextype *ap = SUNSparseMatrix_IndexPointers(A), *ai = SUNSparseMatrix_IndexValues(A);
  for (sunindextype p = ap[col]; p < ap[col + 1]; p++)
    if (ai[p] == row) return p;
  return -1;
}

void vs_contact_jacobian(const vs_contact *c, const double *qe, const double *ve, SUNMatrix K,
                         SUNMatrix C) {
  if (!c->armed || (K == NULL && C == NULL)) return;
  rot_cache rc = {.block = -1};
  for (int k = 0; k < c->nv; k++) {
    const vertex *vx = &c->v[k];
    vertex_eval o;
    eval_vertex_r(c, vx, qe, ve, &rc, &o);
    if (!(o.p > 0.0)) continue;
    double dT[3]; /* dT/dq */
    for (int j = 0; j < 3; j++)
      dT[j] = o.sliding ? -o.sliding * c->mu * vx->kv * o.gz[j] : vx->kt * o.gx[j];
    const sunindextype b0 = 3 * vx->block;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double kij = vx->kv * o.gz[i] * o.gz[j] + o.gx[i] * dT[j];
        if (i == 2 && j == 2) kij += o.Ne * o.Rz - o.T * o.Rx; /* the lever arms turning */
        const sunindextype e = entry(K != NULL ? K : C, b0 + i, b0 + j);
        if (e < 0) continue;
        if (K != NULL) SUNSparseMatrix_Data(K)[e] += kij;
        if (C != NULL) SUNSparseMatrix_Data(C)[e] += vx->cv * o.s * o.gz[i] * o.gz[j];
      }
  }
}

double vs_contact_energy(const vs_contact *c, const double *qe) {
  double e = 0.0;
  if (!c->armed) return 0.0;
  rot_cache rc = {.block = -1};
  for (int k = 0; k < c->nv; k++) {
    vertex_eval o;
    eval_vertex_r(c, &c->v[k], qe, NULL, &rc, &o);
    if (o.p > 0.0) e += 0.5 * c->v[k].kv * o.p * o.p + 0.5 * o.T * o.T / c->v[k].kt;
  }
  return e;
}

void vs_contact_commit(vs_contact *c, const double *qe) {
  for (int k = 0; k < c->nv; k++) {
    vertex *vx = &c->v[k];
    vertex_eval o;
    eval_vertex(c, vx, qe, NULL, &o);
    if (!(o.p > 0.0)) vx->xa = o.x; /* off the ground: the anchor follows */
    else if (o.sliding) vx->xa = o.x - o.T / vx->kt;
  }
}

double vs_contact_max_penetration(const vs_contact *c, const double *qe, int *which) {
  double worst = -INFINITY;
  int kw = -1;
  const double level = c->level;
  for (int k = 0; k < c->nv; k++) {
    double x, z;
    vs_contact_vertex(c, qe, k, &x, &z);
    if (level - z > worst) {
      worst = level - z;
      kw = k;
    }
  }
  if (which != NULL) *which = kw;
  return worst;
}
