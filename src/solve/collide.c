/* Contact between bodies that share no joint (see collide.h for the law): outlines, broad
 * phase on bounding boxes, narrow phase vertex against edge, forces and their analytic Jacobian
 * over the two bodies, root functions, stored energy and the friction anchors. */
#include "collide.h"

#include "outline.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
  int k, b, e; /* vertex k inside body b's outline, behind its edge e */
} hit;

struct vs_collide {
  const vs_model *m;
  int nb, nv;          /* bodies (blocks, then the two supports), vertices */
  int *first, *count;  /* per body: its vertices first .. first + count - 1, counter-clockwise */
  int *body;           /* per vertex: its body */
  double *rx, *rz;     /* per vertex: from its body's reference point, reference configuration */
  double *mass;        /* per body (supports: INFINITY) */
  double *ref;         /* per body: reference point (x, z) */
  unsigned char *adj;  /* nb x nb: 1 where two bodies share a joint */
  double kv, kt, mu, zeta, margin;
  int *ab, *ae;        /* per vertex: the body and edge of its anchor (-1: none) */
  double *sa;          /* ... and the anchor's coordinate along that edge, m */
  double *px, *pz;     /* work: the vertices' positions at the last state */
  double *n0x, *n0z;   /* per edge (numbered as its first vertex): outward unit normal in the
                          reference configuration */
  double *at;          /* the state (3 nb) the work below was computed for */
  int at_valid, hits_valid;
  double *nx, *nz, *no; /* work: per edge (numbered as its first vertex) outward unit normal,
                           and n . (its first vertex) */
  double *box;         /* work: per body min x, max x, min z, max z */
  hit *hits;           /* work: nv * nb */
  unsigned char *seen; /* work: nv */
  int *order;          /* work: the bodies by their boxes' left ends (kept from call to call) */
  int *cand, ncand;    /* work: candidate pairs (a, b), a before b in order */
  int nh;
  int armed;
};

/* One vertex against one edge: penetration, tangential coordinate, their gradients over
 * x = (u_a, theta_a, u_b, theta_b) (a: the vertex's body, b: the edge's) and forces. */
typedef struct {
  double p, s, gp[6], gs[6];
  double n[2], t[2], W[2], R[2]; /* normal, tangent, vertex - b's point, vertex - a's point */
  double N, Ne, Nd, T, cv, fade, pdot, sdot;
  int sliding;
} pair_eval;

/* The vertices, boxes and edge normals at qe (kept: nothing is redone for the same qe, which
 * IDA's residual, energy and root evaluations share). */
static void positions(vs_collide *c, const double *qe) {
  const size_t nq = 3 * (size_t)c->nb * sizeof *qe;
  if (c->at_valid && memcmp(c->at, qe, nq) == 0) return;
  memcpy(c->at, qe, nq);
  c->at_valid = 1;
  c->hits_valid = 0;
  for (int b = 0; b < c->nb; b++) {
    const double *q = qe + 3 * b, cs = cos(q[2]), sn = sin(q[2]);
    double *bx = c->box + 4 * b;
    bx[0] = bx[2] = INFINITY;
    bx[1] = bx[3] = -INFINITY;
    for (int k = c->first[b]; k < c->first[b] + c->count[b]; k++) {
      c->px[k] = c->ref[2 * b] + q[0] + cs * c->rx[k] - sn * c->rz[k];
      c->pz[k] = c->ref[2 * b + 1] + q[1] + sn * c->rx[k] + cs * c->rz[k];
      bx[0] = fmin(bx[0], c->px[k]), bx[1] = fmax(bx[1], c->px[k]);
      bx[2] = fmin(bx[2], c->pz[k]), bx[3] = fmax(bx[3], c->pz[k]);
    }
    for (int i = c->first[b]; i < c->first[b] + c->count[b]; i++) { /* the normals turned */
      c->nx[i] = cs * c->n0x[i] - sn * c->n0z[i];
      c->nz[i] = sn * c->n0x[i] + cs * c->n0z[i];
      c->no[i] = c->nx[i] * c->px[i] + c->nz[i] * c->pz[i];
    }
  }
}

/* The candidate pairs for boxes widened by w, by sweep and prune along x: the bodies sorted
 * by their boxes' left ends (insertion sort from the last order: nearly sorted already), each
 * tested against those whose left end is within its right end. */
static int candidates(const vs_collide *c, int a, int b, double w);

static void sweep(vs_collide *c, double w) {
  int *o = c->order;
  for (int i = 1; i < c->nb; i++)
    for (int j = i; j > 0 && c->box[4 * o[j - 1]] > c->box[4 * o[j]]; j--) {
      const int t = o[j];
      o[j] = o[j - 1], o[j - 1] = t;
    }
  c->ncand = 0;
  for (int i = 0; i < c->nb; i++)
    for (int j = i + 1; j < c->nb && c->box[4 * o[j]] <= c->box[4 * o[i] + 1] + w; j++)
      if (candidates(c, o[i], o[j], w)) {
        c->cand[2 * c->ncand] = o[i];
        c->cand[2 * c->ncand++ + 1] = o[j];
      }
}

/* Bodies a and b are a candidate pair: no joint between them and their boxes, widened by w,
 * overlap. */
static int candidates(const vs_collide *c, int a, int b, double w) {
  if (a == b || c->adj[a * c->nb + b] || c->count[a] == 0 || c->count[b] == 0) return 0;
  const double *A = c->box + 4 * a, *B = c->box + 4 * b;
  return A[0] <= B[1] + w && B[0] <= A[1] + w && A[2] <= B[3] + w && B[2] <= A[3] + w;
}

/* Signed distance of (x, z) from body b's outline (largest over the edges), and that edge. */
static double signed_distance(const vs_collide *c, int b, double x, double z, int *edge) {
  double best = -INFINITY;
  const int f = c->first[b], nc = c->count[b];
  for (int e = 0; e < nc; e++) {
    const double d = c->nx[f + e] * x + c->nz[f + e] * z - c->no[f + e];
    if (d > best) best = d, *edge = e;
  }
  return best;
}

/* The narrow phase at the positions of the last positions(): every vertex inside another
 * body's outline. */
static void find_hits(vs_collide *c) {
  if (c->hits_valid) return;
  c->hits_valid = 1;
  c->nh = 0;
  sweep(c, 0.0);
  for (int p = 0; p < 2 * c->ncand; p++) {
    const int a = c->cand[p], b = c->cand[p ^ 1]; /* both ways */
    for (int k = c->first[a]; k < c->first[a] + c->count[a]; k++) {
      int e = -1;
      if (!(signed_distance(c, b, c->px[k], c->pz[k], &e) < 0.0)) continue;
      const int f = c->first[b] + c->ae[k]; /* its anchor's edge while still behind it */
      if (c->ab[k] == b && c->nx[f] * c->px[k] + c->nz[f] * c->pz[k] - c->no[f] < 0.0)
        e = c->ae[k];
      c->hits[c->nh++] = (hit){.k = k, .b = b, .e = e};
    }
  }
}

static void gradients(pair_eval *o) {
  const double *n = o->n, *t = o->t, *W = o->W, *R = o->R;
  const double dW[2][6] = {{1, 0, -R[1], -1, 0, 0}, {0, 1, R[0], 0, -1, 0}};
  for (int i = 0; i < 6; i++) {
    o->gp[i] = -(n[0] * dW[0][i] + n[1] * dW[1][i]);
    o->gs[i] = t[0] * dW[0][i] + t[1] * dW[1][i];
  }
  o->gp[5] = -(-n[1] * W[0] + n[0] * W[1]); /* -n_perp . W, n_perp = (-n_z, n_x) */
  o->gs[5] = -t[1] * W[0] + t[0] * W[1];    /* t_perp . W */
}

static void eval_hit(const vs_collide *c, const double *qe, const double *ve, const hit *h,
                     pair_eval *o) {
  const int k = h->k, a = c->body[k], b = h->b, f = c->first[b];
  const int i = f + h->e, j = f + (h->e + 1) % c->count[b];
  const double tx = c->px[j] - c->px[i], tz = c->pz[j] - c->pz[i], len = hypot(tx, tz);
  o->t[0] = tx / len, o->t[1] = tz / len;
  o->n[0] = o->t[1], o->n[1] = -o->t[0];
  o->W[0] = c->px[k] - (c->ref[2 * b] + qe[3 * b]);
  o->W[1] = c->pz[k] - (c->ref[2 * b + 1] + qe[3 * b + 1]);
  o->R[0] = c->px[k] - (c->ref[2 * a] + qe[3 * a]);
  o->R[1] = c->pz[k] - (c->ref[2 * a + 1] + qe[3 * a + 1]);
  const double dx = c->px[k] - c->px[i], dz = c->pz[k] - c->pz[i];
  o->p = -(o->n[0] * dx + o->n[1] * dz);
  o->s = o->t[0] * dx + o->t[1] * dz;
  gradients(o);
  const double ma = c->mass[a], mb = c->mass[b];
  const double mr = isinf(mb) ? ma : isinf(ma) ? mb : ma * mb / (ma + mb);
  o->cv = 2.0 * c->zeta * sqrt(0.5 * c->kv * mr);
  o->fade = fmin(1.0, o->p * c->kv / (mr * vs_model_geometry(c->m)->gravity));
  o->pdot = o->sdot = 0.0;
  if (ve != NULL)
    for (int d = 0; d < 3; d++) {
      o->pdot += o->gp[d] * ve[3 * a + d] + o->gp[3 + d] * ve[3 * b + d];
      o->sdot += o->gs[d] * ve[3 * a + d] + o->gs[3 + d] * ve[3 * b + d];
    }
  o->Ne = c->kv * o->p;
  o->Nd = o->cv * o->fade * o->pdot;
  o->N = o->Ne + o->Nd;
  const int anchored = c->ab[k] == b && c->ae[k] == h->e;
  const double trial = anchored ? c->kt * (o->s - c->sa[k]) : 0.0, cap = c->mu * o->Ne;
  o->sliding = 0;
  o->T = trial;
  if (fabs(trial) > cap) {
    o->sliding = trial > 0.0 ? 1 : -1;
    o->T = o->sliding * cap;
  }
}

static void outline_box(vs_collide *c, const double *qe) {
  positions(c, qe);
  find_hits(c);
}

void vs_collide_forces(vs_collide *c, const double *qe, const double *ve, double *F,
                       double *damped, double *friction) {
  if (!c->armed) return;
  outline_box(c, qe);
  for (int h = 0; h < c->nh; h++) {
    pair_eval o;
    eval_hit(c, qe, ve, &c->hits[h], &o);
    const int a = c->body[c->hits[h].k], b = c->hits[h].b;
    if (F != NULL)
      for (int d = 0; d < 3; d++) {
        F[3 * a + d] += o.N * o.gp[d] + o.T * o.gs[d];
        F[3 * b + d] += o.N * o.gp[3 + d] + o.T * o.gs[3 + d];
      }
    if (damped != NULL) *damped += o.Nd * o.pdot;
    if (friction != NULL && o.sliding != 0)
      *friction += o.T * (o.sdot - o.sliding * c->mu * c->kv * o.pdot / c->kt);
  }
}

/* The second derivatives of p (hp) and s (hs) over x, symmetric. */
static void hessians(const pair_eval *o, double hp[6][6], double hs[6][6]) {
  memset(hp, 0, 36 * sizeof hp[0][0]);
  memset(hs, 0, 36 * sizeof hs[0][0]);
  const double *n = o->n, *t = o->t, *W = o->W, *R = o->R;
  const double np[2] = {-n[1], n[0]}, tp[2] = {-t[1], t[0]}, Rp[2] = {-R[1], R[0]};
  hp[2][2] = n[0] * R[0] + n[1] * R[1];
  hs[2][2] = -(t[0] * R[0] + t[1] * R[1]);
  hp[2][5] = hp[5][2] = -(np[0] * Rp[0] + np[1] * Rp[1]);
  hs[2][5] = hs[5][2] = tp[0] * Rp[0] + tp[1] * Rp[1];
  hp[5][5] = n[0] * W[0] + n[1] * W[1];
  hs[5][5] = -(t[0] * W[0] + t[1] * W[1]);
  for (int d = 0; d < 2; d++) {
    hp[5][d] = hp[d][5] = -np[d];
    hp[5][3 + d] = hp[3 + d][5] = np[d];
    hs[5][d] = hs[d][5] = tp[d];
    hs[5][3 + d] = hs[3 + d][5] = -tp[d];
  }
}

void vs_collide_jacobian(vs_collide *c, const double *qe, const double *ve, double *K,
                         double *C) {
  if (!c->armed || (K == NULL && C == NULL)) return;
  const int ne = vs_model_ext_size(c->m);
  outline_box(c, qe);
  for (int h = 0; h < c->nh; h++) {
    pair_eval o;
    eval_hit(c, qe, ve, &c->hits[h], &o);
    const int a = c->body[c->hits[h].k], b = c->hits[h].b;
    const int anchored = c->ab[c->hits[h].k] == b && c->ae[c->hits[h].k] == c->hits[h].e;
    double hp[6][6], hs[6][6], dT[6];
    hessians(&o, hp, hs);
    for (int j = 0; j < 6; j++)
      dT[j] = o.sliding ? o.sliding * c->mu * c->kv * o.gp[j] : anchored ? c->kt * o.gs[j] : 0.0;
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        const int r = 3 * (i < 3 ? a : b) + i % 3, col = 3 * (j < 3 ? a : b) + j % 3;
        const size_t e = (size_t)col * (size_t)ne + (size_t)r;
        if (K != NULL)
          K[e] += c->kv * o.gp[i] * o.gp[j] + o.gs[i] * dT[j] + o.N * hp[i][j] + o.T * hs[i][j];
        if (C != NULL) C[e] += o.cv * o.fade * o.gp[i] * o.gp[j];
      }
  }
}

void vs_collide_pairs(vs_collide *c, const double *qe, unsigned char *pair) {
  positions(c, qe);
  sweep(c, c->margin);
  memset(pair, 0, (size_t)c->nb * (size_t)c->nb);
  for (int p = 0; p < c->ncand; p++) {
    const int a = c->cand[2 * p], b = c->cand[2 * p + 1];
    pair[a * c->nb + b] = pair[b * c->nb + a] = 1;
  }
}

void vs_collide_roots(vs_collide *c, const double *qe, double *g) {
  positions(c, qe);
  for (int k = 0; k < c->nv; k++) g[k] = c->margin;
  sweep(c, 0.0);
  for (int p = 0; p < 2 * c->ncand; p++) {
    const int a = c->cand[p], b = c->cand[p ^ 1]; /* both ways */
    for (int k = c->first[a]; k < c->first[a] + c->count[a]; k++) {
      int e = -1;
      g[k] = fmin(g[k], signed_distance(c, b, c->px[k], c->pz[k], &e));
    }
  }
}

double vs_collide_energy(vs_collide *c, const double *qe) {
  if (!c->armed) return 0.0;
  outline_box(c, qe);
  double e = 0.0;
  for (int h = 0; h < c->nh; h++) {
    pair_eval o;
    eval_hit(c, qe, NULL, &c->hits[h], &o);
    e += 0.5 * c->kv * o.p * o.p + 0.5 * o.T * o.T / c->kt;
  }
  return e;
}

void vs_collide_commit(vs_collide *c, const double *qe) {
  if (!c->armed) return;
  outline_box(c, qe);
  memset(c->seen, 0, (size_t)c->nv);
  for (int h = 0; h < c->nh; h++) { /* a vertex still behind its anchor's edge keeps it */
    const hit *ht = &c->hits[h];
    if (c->ab[ht->k] != ht->b || c->ae[ht->k] != ht->e) continue;
    pair_eval o;
    eval_hit(c, qe, NULL, ht, &o);
    if (o.sliding) c->sa[ht->k] = o.s - o.T / c->kt;
    c->seen[ht->k] = 1;
  }
  for (int h = 0; h < c->nh; h++) { /* a vertex in contact elsewhere: a new, unstretched one */
    const hit *ht = &c->hits[h];
    if (c->seen[ht->k]) continue;
    pair_eval o;
    eval_hit(c, qe, NULL, ht, &o);
    c->ab[ht->k] = ht->b, c->ae[ht->k] = ht->e, c->sa[ht->k] = o.s;
    c->seen[ht->k] = 1;
  }
  for (int k = 0; k < c->nv; k++)
    if (!c->seen[k]) c->ab[k] = c->ae[k] = -1;
  c->hits_valid = 0; /* the edges chosen follow the anchors */
}

double vs_collide_max_penetration(vs_collide *c, const double *qe) {
  positions(c, qe);
  find_hits(c);
  double worst = 0.0;
  for (int h = 0; h < c->nh; h++) {
    int e = -1;
    const hit *ht = &c->hits[h];
    worst = fmax(worst, -signed_distance(c, ht->b, c->px[ht->k], c->pz[ht->k], &e));
  }
  return worst;
}

void vs_collide_arm(vs_collide *c, const double *qe) {
  c->armed = 1;
  for (int k = 0; k < c->nv; k++) c->ab[k] = c->ae[k] = -1;
  c->hits_valid = 0;
  vs_collide_commit(c, qe);
}
void vs_collide_disarm(vs_collide *c) { c->armed = 0; }
int vs_collide_armed(const vs_collide *c) { return c->armed; }
int vs_collide_bodies(const vs_collide *c) { return c->nb; }
int vs_collide_count(const vs_collide *c) { return c->nv; }

void vs_collide_destroy(vs_collide **c) {
  if (c == NULL || *c == NULL) return;
  vs_collide *p = *c;
  free(p->first), free(p->count), free(p->body), free(p->rx), free(p->rz), free(p->mass);
  free(p->ref), free(p->adj), free(p->ab), free(p->ae), free(p->sa), free(p->px), free(p->pz);
  free(p->box), free(p->hits), free(p->seen), free(p->nx), free(p->nz), free(p->no);
  free(p->order), free(p->cand), free(p->n0x), free(p->n0z), free(p->at);
  free(p);
  *c = NULL;
}

/* The convex hull of support body's polygons (a blocks file's) into xz (NULL: only counted):
 * its number of vertices, 0 when it has none, -1 when they enclose no area or have too many. */
static int support_hull(const vs_geometry *g, int body, double *xz) {
  double pts[2 * VS_HULL_MAX], hull[2 * (VS_HULL_MAX + 1)];
  int n = 0;
  for (int s = 0; s < g->n_supports; s++) {
    if (g->supports[s].body != body) continue;
    for (int e = 0; e < g->supports[s].n_edges; e++) {
      if (n == VS_HULL_MAX) return -1;
      const vs_edge *ed = &g->edges[g->supports[s].edge0 + e];
      pts[2 * n] = ed->x0, pts[2 * n + 1] = ed->z0;
      n++;
    }
  }
  if (n == 0) return 0;
  const int m = vs_convex_hull(pts, n, hull);
  if (m == 0) return -1;
  if (xz != NULL) memcpy(xz, hull, (size_t)(2 * m) * sizeof *xz);
  return m;
}

int vs_collide_arch_outlines(const vs_geometry *g, int *count, double *xz) {
  int n = 0;
  for (int i = 0; i < g->n_blocks; i++) {
    const int nh = vs_block_hull(g, i, xz != NULL ? xz + 2 * n : NULL, NULL);
    if (nh < 0) return -1;
    if (count != NULL) count[i] = nh;
    n += nh;
  }
  for (int s = 0; s < 2; s++) {
    const int m = support_hull(g, s == 0 ? VS_SUPPORT_LEFT : VS_SUPPORT_RIGHT,
                               xz != NULL ? xz + 2 * n : NULL);
    if (m < 0) return -1;
    if (m > 0) {
      if (count != NULL) count[g->n_blocks + s] = m;
      n += m;
      continue;
    }
    const vs_joint_geom *j = &g->joints[vs_geometry_springing(g, s)];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double ix = j->px - 0.5 * j->length * sx, iz = j->pz - 0.5 * j->length * sz;
    const double ex = j->px + 0.5 * j->length * sx, ez = j->pz + 0.5 * j->length * sz;
    const double low = fmin(iz, ez) - g->span;
    const double v[8] = {ix, iz, ex, ez, ex, low, ix, low};
    if (xz != NULL) memcpy(xz + 2 * n, v, sizeof v);
    if (count != NULL) count[g->n_blocks + s] = 4;
    n += 4;
  }
  return n;
}

void vs_collide_reference_points(const vs_geometry *g, double *ref) {
  for (int i = 0; i < g->n_blocks; i++)
    ref[2 * i] = g->blocks[i].cx, ref[2 * i + 1] = g->blocks[i].cz;
  for (int k = 0; k < g->n_joints; k++)
    for (int e = 0; e < 2; e++) {
      const vs_joint_geom *j = &g->joints[k];
      const int s = e == 0 ? j->a : j->b;
      if (s < 0) ref[2 * vs_collide_body(g, s)] = j->px, ref[2 * vs_collide_body(g, s) + 1] = j->pz;
    }
}

/* Bodies' reference points, masses, adjacency. */
static void bodies(vs_collide *c, const vs_geometry *g) {
  vs_collide_reference_points(g, c->ref);
  for (int i = 0; i < g->n_blocks; i++) c->mass[i] = g->blocks[i].mass;
  for (int s = 0; s < 2; s++) c->mass[g->n_blocks + s] = INFINITY;
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    const int a = vs_collide_body(g, j->a), b = vs_collide_body(g, j->b);
    c->adj[a * c->nb + b] = c->adj[b * c->nb + a] = 1;
  }
}

vs_status vs_collide_outlines(int nb, const int *count, const double *xz, const double *ref,
                              int max_vertices, const char *who, const vs_collide_outline *o,
                              vs_error *err) {
  int k = 0;
  for (int b = 0; b < nb; b++) {
    const int nc = count[b];
    double area = 0.0;
    for (int v = 0; v < nc; v++) {
      const double *p = xz + 2 * (k + v), *q = xz + 2 * (k + (v + 1) % nc);
      if (!isfinite(p[0]) || !isfinite(p[1]))
        return vs_error_set(err, VS_ERR_INVALID, "%s: body %d vertex %d not finite", who, b, v);
      area += p[0] * q[1] - q[0] * p[1];
    }
    if (nc != 0 && (nc < 3 || nc > max_vertices || !(fabs(area) > 0.0)))
      return vs_error_set(err, VS_ERR_INVALID, "%s: body %d outline of %d vertices and area %g "
                          "m^2 (allowed: 0, or 3 to %d vertices enclosing an area)", who, b, nc,
                          0.5 * area, max_vertices);
    o->first[b] = k, o->count[b] = nc;
    for (int v = 0; v < nc; v++) {
      const int src = k + (area > 0.0 ? v : nc - 1 - v);
      o->body[k + v] = b;
      o->rx[k + v] = xz[2 * src] - ref[2 * b];
      o->rz[k + v] = xz[2 * src + 1] - ref[2 * b + 1];
    }
    for (int v = 0; v < nc; v++) {
      const int i = k + v, j = k + (v + 1) % nc;
      const double tx = o->rx[j] - o->rx[i], tz = o->rz[j] - o->rz[i], len = hypot(tx, tz);
      if (!(len > 0.0))
        return vs_error_set(err, VS_ERR_INVALID, "%s: body %d vertices %d and %d coincide "
                            "(allowed: distinct)", who, b, v, (v + 1) % nc);
      o->n0x[i] = tz / len, o->n0z[i] = -tx / len; /* outward: counter-clockwise */
    }
    k += nc;
  }
  return VS_OK;
}

static vs_collide *alloc_collide(int nb, int nv) {
  vs_collide *c = calloc(1, sizeof *c);
  if (c == NULL) return NULL;
  const size_t B = (size_t)nb, V = (size_t)nv;
  c->nb = nb, c->nv = nv;
  c->first = calloc(B, sizeof *c->first), c->count = calloc(B, sizeof *c->count);
  c->body = calloc(V, sizeof *c->body), c->rx = calloc(V, sizeof *c->rx);
  c->rz = calloc(V, sizeof *c->rz), c->mass = calloc(B, sizeof *c->mass);
  c->ref = calloc(2 * B, sizeof *c->ref), c->adj = calloc(B * B, 1);
  c->ab = calloc(V, sizeof *c->ab), c->ae = calloc(V, sizeof *c->ae);
  c->sa = calloc(V, sizeof *c->sa), c->px = calloc(V, sizeof *c->px);
  c->pz = calloc(V, sizeof *c->pz), c->box = calloc(4 * B, sizeof *c->box);
  c->hits = calloc(V * B, sizeof *c->hits), c->seen = calloc(V, 1);
  c->nx = calloc(V, sizeof *c->nx), c->nz = calloc(V, sizeof *c->nz);
  c->no = calloc(V, sizeof *c->no);
  c->order = calloc(B, sizeof *c->order), c->cand = calloc(B * B, sizeof *c->cand);
  c->n0x = calloc(V, sizeof *c->n0x), c->n0z = calloc(V, sizeof *c->n0z);
  c->at = calloc(3 * B, sizeof *c->at);
  for (int b = 0; c->order != NULL && b < nb; b++) c->order[b] = b;
  if (!c->first || !c->count || !c->body || !c->rx || !c->rz || !c->mass || !c->ref || !c->adj ||
      !c->ab || !c->ae || !c->sa || !c->px || !c->pz || !c->box || !c->hits || !c->seen ||
      !c->nx || !c->nz || !c->no || !c->order || !c->cand ||
      !c->n0x || !c->n0z || !c->at)
    vs_collide_destroy(&c);
  return c;
}

vs_status vs_collide_create(const vs_model *m, double restitution, const int *count,
                            const double *xz, vs_collide **out, vs_error *err) {
  *out = NULL;
  if (!(restitution > 0.0 && restitution <= 1.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "collide: restitution = %g (allowed: 0 < e <= 1)", restitution);
  const vs_geometry *g = vs_model_geometry(m);
  const int nb = g->n_blocks + 2;
  int *own = count == NULL ? calloc((size_t)nb, sizeof *own) : NULL;
  const int nv = count == NULL ? vs_collide_arch_outlines(g, own, NULL) : 0;
  if (nv < 0) {
    free(own);
    return vs_error_set(err, VS_ERR_INVALID, "collide: a block's outline cannot be made convex "
                        "(allowed: at most %d corners)", VS_HULL_MAX);
  }
  double *oxz = count == NULL ? malloc((size_t)(2 * nv + 1) * sizeof *oxz) : NULL;
  int total = 0;
  if (count != NULL)
    for (int b = 0; b < nb; b++) total += count[b] > 0 ? count[b] : 0;
  vs_collide *c = alloc_collide(nb, count == NULL ? nv : total);
  if (c == NULL || (count == NULL && (own == NULL || oxz == NULL))) {
    free(own), free(oxz);
    vs_collide_destroy(&c);
    return vs_error_set(err, VS_ERR_NOMEM, "collide: out of memory");
  }
  if (count == NULL) vs_collide_arch_outlines(g, own, oxz);
  c->m = m;
  bodies(c, g);
  const vs_collide_outline ol = {c->first, c->count, c->body, c->rx, c->rz, c->n0x, c->n0z};
  vs_status st = vs_collide_outlines(c->nb, count != NULL ? count : own, count != NULL ? xz : oxz,
                                     c->ref, INT_MAX, "collide", &ol, err);
  free(own), free(oxz);
  if (st != VS_OK) {
    vs_collide_destroy(&c);
    return st;
  }
  const vs_joint_law *law = vs_model_law(m);
  c->kv = 0.5 * law->kn * g->joints[0].depth * g->joints[0].length;
  c->kt = c->kv * law->ks / law->kn;
  c->mu = law->mu;
  c->margin = g->joints[0].length;
  const double pi = 3.14159265358979323846, le = log(restitution);
  c->zeta = -le / sqrt(pi * pi + le * le);
  *out = c;
  return VS_OK;
}
