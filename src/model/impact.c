/* The `impact` damping model: a perfectly plastic impulse where an opened joint edge closes
 * (Housner's restitution for a rocking block), and which edges are armed for it. */
#include "impact.h"

#include <math.h>
#include <stdlib.h>

struct vs_impact {
  const vs_model *m;
  double open; /* m */
  int nj;
  unsigned char *armed; /* 2 per joint: intrados, extrados */
};

double vs_impact_edge_gap(const vs_model *m, int k, int side, const vs_joint_state *st) {
  const vs_joint_law *l = vs_model_joint_law(m, k);
  const double half = 0.5 * vs_model_geometry(m)->joints[k].length;
  return side == 0 ? st->gap_i + l->gap0 - l->gap1 * half : st->gap_e + l->gap0 + l->gap1 * half;
}

/* One body of a joint at its edge point: inverse mass and inertia (0 for a support: immovable
 * for the impulse), the arm rho from its reference point to the edge point (current
 * configuration) and the pointer to its velocities (ux', uz', theta') in ve. */
typedef struct {
  double im, iI, rho[2];
  int i;     /* offset of its (ux, uz, theta) in qe and ve */
  double *v; /* ve + i */
} edge_body;

static void edge_body_at(const vs_model *m, const double *qe, double *ve, int body,
                         const vs_joint_geom *j, double xi, edge_body *e) {
  const vs_geometry *g = vs_model_geometry(m);
  const int i = body >= 0 ? 3 * body : 3 * g->n_blocks + 3 * (body == VS_SUPPORT_LEFT ? 0 : 1);
  double rx = j->px - j->nz * xi, rz = j->pz + j->nx * xi; /* edge point, reference */
  if (body >= 0) {
    rx -= g->blocks[body].cx;
    rz -= g->blocks[body].cz;
    e->im = 1.0 / g->blocks[body].mass;
    e->iI = 1.0 / g->blocks[body].inertia;
  } else { /* a support body's reference point is its joint's centre */
    rx -= j->px;
    rz -= j->pz;
    e->im = e->iI = 0.0;
  }
  const double c = cos(qe[i + 2]), s = sin(qe[i + 2]);
  e->rho[0] = c * rx - s * rz;
  e->rho[1] = s * rx + c * rz;
  e->i = i;
  e->v = ve + i;
}

/* Velocity of the body's material point at the edge. */
static void edge_velocity(const edge_body *e, double u[2]) {
  u[0] = e->v[0] - e->v[2] * e->rho[1];
  u[1] = e->v[1] + e->v[2] * e->rho[0];
}

/* Add the body's mobility at the edge, im I + iI rho_perp rho_perp^T, to W (2x2 row-major). */
static void add_mobility(const edge_body *e, double W[4]) {
  const double px = -e->rho[1], pz = e->rho[0];
  W[0] += e->im + e->iI * px * px;
  W[1] += e->iI * px * pz;
  W[2] += e->iI * px * pz;
  W[3] += e->im + e->iI * pz * pz;
}

static double body_kinetic(const edge_body *e) {
  if (e->im == 0.0) return 0.0;
  return 0.5 * (e->v[0] * e->v[0] + e->v[1] * e->v[1]) / e->im + 0.5 * e->v[2] * e->v[2] / e->iI;
}

/* Impulse P (on body b; -P on a) of a plastic impact with relative edge velocity w and
 * mobility W, within the friction cone |P . s| <= mu P . n; 0 when the edge is not closing. */
static void plastic_impulse(const double W[4], const double w[2], const double n[2],
                            const double s[2], double mu, double P[2]) {
  P[0] = P[1] = 0.0;
  const double wn = w[0] * n[0] + w[1] * n[1];
  const double det = W[0] * W[3] - W[1] * W[2];
  if (!(wn < 0.0) || !(det > 0.0)) return;
  double p[2] = {-(W[3] * w[0] - W[1] * w[1]) / det, -(-W[2] * w[0] + W[0] * w[1]) / det};
  const double pn = p[0] * n[0] + p[1] * n[1], pt = p[0] * s[0] + p[1] * s[1];
  if (pn > 0.0 && fabs(pt) <= mu * pn) {
    P[0] = p[0];
    P[1] = p[1];
    return;
  }
  /* sliding: P = lambda (n + sigma mu s), normal relative velocity zeroed */
  const double sg = pt >= 0.0 ? 1.0 : -1.0;
  const double e[2] = {n[0] + sg * mu * s[0], n[1] + sg * mu * s[1]};
  const double nWe = n[0] * (W[0] * e[0] + W[1] * e[1]) + n[1] * (W[2] * e[0] + W[3] * e[1]);
  const double lam = nWe > 0.0 ? -wn / nWe : 0.0;
  if (lam > 0.0) {
    P[0] = lam * e[0];
    P[1] = lam * e[1];
  }
}

static void push(edge_body *e, double sign, const double P[2]) {
  e->v[0] += sign * e->im * P[0];
  e->v[1] += sign * e->im * P[1];
  e->v[2] += sign * e->iI * (e->rho[0] * P[1] - e->rho[1] * P[0]);
}

double vs_impact_apply(const vs_model *m, const double *qe, double *ve, int k, int side) {
  const vs_joint_geom *j = &vs_model_geometry(m)->joints[k];
  const double xi = (side == 0 ? -0.5 : 0.5) * j->length;
  edge_body A, B;
  edge_body_at(m, qe, ve, j->a, j, xi, &A);
  edge_body_at(m, qe, ve, j->b, j, xi, &B);
  /* the joint frame turns with the mean rotation (joint.h) */
  const double th = 0.5 * (qe[A.i + 2] + qe[B.i + 2]);
  const double c = cos(th), sn = sin(th);
  const double n[2] = {c * j->nx - sn * j->nz, sn * j->nx + c * j->nz};
  const double s[2] = {-n[1], n[0]};
  double ua[2], ub[2], W[4] = {0.0, 0.0, 0.0, 0.0}, P[2];
  edge_velocity(&A, ua);
  edge_velocity(&B, ub);
  const double w[2] = {ub[0] - ua[0], ub[1] - ua[1]};
  add_mobility(&A, W);
  add_mobility(&B, W);
  plastic_impulse(W, w, n, s, vs_model_joint_law(m, k)->mu, P);
  if (P[0] == 0.0 && P[1] == 0.0) return 0.0;
  const double before = body_kinetic(&A) + body_kinetic(&B);
  push(&A, -1.0, P);
  push(&B, 1.0, P);
  return fmax(0.0, before - body_kinetic(&A) - body_kinetic(&B));
}

vs_impact *vs_impact_create(const vs_model *m, double open) {
  vs_impact *imp = calloc(1, sizeof *imp);
  if (imp == NULL) return NULL;
  imp->m = m;
  imp->open = open;
  imp->nj = vs_model_geometry(m)->n_joints;
  imp->armed = calloc((size_t)(2 * imp->nj), 1);
  if (imp->armed == NULL) vs_impact_destroy(&imp);
  return imp;
}

void vs_impact_destroy(vs_impact **imp) {
  if (imp == NULL || *imp == NULL) return;
  free((*imp)->armed);
  free(*imp);
  *imp = NULL;
}

int vs_impact_nroots(const vs_impact *imp) { return 2 * imp->nj; }

void vs_impact_reset(vs_impact *imp, const vs_joint_state *st) {
  for (int i = 0; i < 2 * imp->nj; i++) imp->armed[i] = 0;
  vs_impact_arm(imp, st);
}

void vs_impact_arm(vs_impact *imp, const vs_joint_state *st) {
  for (int i = 0; i < 2 * imp->nj; i++)
    if (vs_impact_edge_gap(imp->m, i / 2, i % 2, &st[i / 2]) > imp->open) imp->armed[i] = 1;
}

void vs_impact_roots(const vs_impact *imp, const vs_joint_state *st, double *g) {
  for (int i = 0; i < 2 * imp->nj; i++)
    g[i] = imp->armed[i] ? vs_impact_edge_gap(imp->m, i / 2, i % 2, &st[i / 2]) : 1.0;
}

double vs_impact_resolve(vs_impact *imp, const double *qe, double *ve, const int *roots,
                         int *count) {
  double lost = 0.0;
  *count = 0;
  for (int i = 0; i < 2 * imp->nj; i++) {
    if (roots[i] >= 0 || !imp->armed[i]) continue;
    imp->armed[i] = 0;
    lost += vs_impact_apply(imp->m, qe, ve, i / 2, i % 2);
    (*count)++;
  }
  return lost;
}
