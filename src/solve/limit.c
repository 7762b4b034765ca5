/* The limit-analysis LP of a rigid block assembly (limit.h), solved by COIN-OR CLP through its C
 * interface: assembly of the equilibrium and friction rows, one solve per goal, and what a
 * solution says (the forces, the thrust line, its touches, the dual's mechanism). */
#include "voussoir/limit.h"

#include <Clp_C_Interface.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "limit_internal.h"
#include "wall_clock.h"

/* Columns: 4 per joint (N_I, T_I, N_E, T_E), then lambda. Rows: 3 per block (equilibrium: x, z,
 * moment about its centroid), 4 per joint (T - mu N <= 0 and -T - mu N <= 0 at each end), one
 * per pinned support joint (N_I = N_E). Forces are scaled by the assembly's weight, moments by
 * weight x mean joint length, so that the coefficients are of order one (CLP's tolerances are
 * absolute). */
enum { COLS_PER_JOINT = 4, ROWS_PER_BLOCK = 3, FRICTION_ROWS = 4 };

/* CLP's infinity (COIN_DBL_MAX of its C++ headers, which C cannot include) */
#define VS_CLP_INF DBL_MAX

/* An end that carries less than this fraction of the scale carries nothing. */
static const double VS_LIMIT_ZERO = 1e-9;
/* A solution that violates a row or a bound by more than this (a fraction of the weight; CLP's
 * own primal tolerance is 1e-7 on its scaled problem) is not taken. */
static const double VS_LIMIT_FEASIBLE = 1e-9;
/* A joint's |V| at least mu N (1 - this): at the friction limit (an active row of the LP is
 * exact to round-off, an inactive one is not that close unless by coincidence). */
static const double VS_LIMIT_FRICTION_REL = 1e-7;

struct vs_limit {
  const vs_geometry *g;
  vs_limit_opts o;
  int nb, nj, ncol, nrow;
  double wref, lref;   /* N, m */
  int n_live;
  vs_limit_force *live; /* a copy */
  CoinBigIndex *start;  /* the matrix, column-major */
  int *index;
  double *value;
  double *collb, *colub, *rowlb, *rowub, *obj;
  unsigned char *basis; /* CLP's status of each column and row after the last solve ... */
  int warm;             /* ... and whether the next solve starts from it */
};

void vs_limit_opts_default(vs_limit_opts *o) {
  *o = (vs_limit_opts){.mu = 0.7,
                       .left_kind = VS_SUPPORT_FIXED,
                       .right_kind = VS_SUPPORT_FIXED,
                       .touch = 1e-6,
                       .hinge = 1e-6,
                       .thickness_tol = 1e-5,
                       .thickness_max = 16.0};
}

/* ---------------------------------------------------------------------------------------------
 * Assembly */

/* The ends of joint j: intrados (e = 0) and extrados (e = 1). */
static void joint_end(const vs_joint_geom *j, int e, double *x, double *z) {
  double sx, sz;
  vs_joint_tangent(j, &sx, &sz);
  const double h = (e ? 0.5 : -0.5) * j->length;
  *x = j->px + h * sx;
  *z = j->pz + h * sz;
}

/* Is body `body` (a block index, or a support) a support of the kind pinned? */
static int pinned_support(const vs_limit *l, int body) {
  return (body == VS_SUPPORT_LEFT && l->o.left_kind == VS_SUPPORT_PINNED) ||
         (body == VS_SUPPORT_RIGHT && l->o.right_kind == VS_SUPPORT_PINNED);
}

static int is_pinned_joint(const vs_limit *l, int j) {
  return pinned_support(l, l->g->joints[j].a) || pinned_support(l, l->g->joints[j].b);
}

/* The scaled generalised force (x, z rows; moment row) on block i of a force (fx, fz) at (px, pz). */
static void block_load(const vs_limit *l, int i, double fx, double fz, double px, double pz,
                       double out[3]) {
  const vs_block *b = &l->g->blocks[i];
  out[0] = fx / l->wref;
  out[1] = fz / l->wref;
  out[2] = ((px - b->cx) * fz - (pz - b->cz) * fx) / (l->wref * l->lref);
}

/* Append the entries of one contact column: a unit force (fx, fz) of body a on body b at
 * (px, pz) (its reaction on a), and the friction rows' coefficients. */
static void put_contact(vs_limit *l, int *nz, const vs_joint_geom *j, double fx, double fz,
                        double px, double pz, int row0, const double fr[2]) {
  const int bodies[2] = {j->a, j->b};
  for (int s = 0; s < 2; s++) {
    if (bodies[s] < 0) continue; /* a support */
    double gf[3];
    const double sign = s == 0 ? -l->wref : l->wref; /* the column's unit is wref */
    block_load(l, bodies[s], sign * fx, sign * fz, px, pz, gf);
    for (int r = 0; r < 3; r++) {
      l->index[*nz] = ROWS_PER_BLOCK * bodies[s] + r;
      l->value[(*nz)++] = gf[r];
    }
  }
  for (int r = 0; r < 2; r++) {
    l->index[*nz] = row0 + r;
    l->value[(*nz)++] = fr[r];
  }
}

/* Joint j's friction: its own (a blocks file's interface, a pier's base), else the options'. */
static double joint_mu(const vs_limit *l, const vs_joint_geom *j) {
  return j->mu > 0.0 ? j->mu : l->o.mu;
}

static void assemble(vs_limit *l) {
  const vs_geometry *g = l->g;
  int nz = 0, col = 0, pin = ROWS_PER_BLOCK * l->nb + FRICTION_ROWS * l->nj;
  for (int k = 0; k < l->nj; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const int pinned = is_pinned_joint(l, k);
    for (int e = 0; e < 2; e++) {
      double px, pz;
      joint_end(j, e, &px, &pz);
      const int row0 = ROWS_PER_BLOCK * l->nb + FRICTION_ROWS * k + 2 * e;
      const double mu = joint_mu(l, j), frn[2] = {-mu, -mu}, frt[2] = {1.0, -1.0};
      l->start[col++] = nz; /* N: >= 0 */
      put_contact(l, &nz, j, j->nx, j->nz, px, pz, row0, frn);
      if (pinned) { /* N_I - N_E = 0: the resultant at the pivot */
        l->index[nz] = pin;
        l->value[nz++] = e ? -1.0 : 1.0;
      }
      l->start[col++] = nz; /* T: free */
      put_contact(l, &nz, j, sx, sz, px, pz, row0, frt);
    }
    if (pinned) pin++;
  }
  l->start[col] = nz; /* lambda: the live load's resultants */
  for (int f = 0; f < l->n_live; f++) {
    const vs_limit_force *lf = &l->live[f];
    double gf[3];
    block_load(l, lf->block, lf->fx, lf->fz, lf->px, lf->pz, gf);
    for (int r = 0; r < 3; r++) { /* summed over the forces on one block, in place */
      const int row = ROWS_PER_BLOCK * lf->block + r;
      int at = l->start[col];
      while (at < nz && l->index[at] != row) at++;
      if (at == nz) {
        l->index[nz] = row;
        l->value[nz++] = 0.0;
      }
      l->value[at] += gf[r];
    }
  }
  l->start[col + 1] = nz;
  /* bounds: N >= 0, T free, lambda >= 0 (set per goal); rows: equilibrium = -dead load */
  for (int c = 0; c < l->ncol; c++) {
    l->collb[c] = (c < l->ncol - 1 && c % 2 == 1) ? -VS_CLP_INF : 0.0;
    l->colub[c] = VS_CLP_INF;
  }
  for (int r = 0; r < l->nrow; r++) {
    l->rowlb[r] = r < ROWS_PER_BLOCK * l->nb ? 0.0 : -VS_CLP_INF;
    l->rowub[r] = 0.0;
  }
  for (int r = ROWS_PER_BLOCK * l->nb + FRICTION_ROWS * l->nj; r < l->nrow; r++) l->rowlb[r] = 0.0;
  for (int i = 0; i < l->nb; i++) { /* the weight, (0, -W) at the centroid: -dead = +W / wref */
    const double w = g->blocks[i].mass * g->gravity / l->wref;
    l->rowlb[ROWS_PER_BLOCK * i + 1] = l->rowub[ROWS_PER_BLOCK * i + 1] = w;
  }
}

static vs_status check_live(const vs_geometry *g, const vs_limit_force *live, int n_live,
                            vs_error *err) {
  if (n_live < 0 || (n_live > 0 && live == NULL))
    return vs_error_set(err, VS_ERR_INVALID, "limit: %d live forces (allowed: >= 0, given)",
                        n_live);
  for (int f = 0; f < n_live; f++) {
    const vs_limit_force *lf = &live[f];
    if (lf->block < 0 || lf->block >= g->n_blocks)
      return vs_error_set(err, VS_ERR_INVALID, "limit: live force %d on block %d (allowed: 0..%d)",
                          f, lf->block, g->n_blocks - 1);
    if (!(isfinite(lf->fx) && isfinite(lf->fz) && isfinite(lf->px) && isfinite(lf->pz)))
      return vs_error_set(err, VS_ERR_INVALID, "limit: live force %d is not finite", f);
  }
  return VS_OK;
}

vs_status vs_limit_create(const vs_geometry *g, const vs_limit_opts *o, const vs_limit_force *live,
                          int n_live, vs_limit **out, vs_error *err) {
  *out = NULL;
  vs_status st = check_live(g, live, n_live, err);
  if (st != VS_OK) return st;
  vs_limit *l = calloc(1, sizeof *l);
  if (l == NULL) return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  l->g = g;
  if (o != NULL) l->o = *o;
  else vs_limit_opts_default(&l->o);
  if (!(l->o.mu > 0.0 && isfinite(l->o.mu))) {
    free(l);
    return vs_error_set(err, VS_ERR_INVALID, "limit: mu = %g (allowed: > 0)", l->o.mu);
  }
  l->nb = g->n_blocks;
  l->nj = g->n_joints;
  int npin = 0;
  for (int k = 0; k < l->nj; k++) npin += is_pinned_joint(l, k);
  l->ncol = COLS_PER_JOINT * l->nj + 1;
  l->nrow = ROWS_PER_BLOCK * l->nb + FRICTION_ROWS * l->nj + npin;
  l->wref = vs_geometry_weight(g);
  double len = 0.0;
  for (int k = 0; k < l->nj; k++) len += g->joints[k].length;
  l->lref = len / l->nj;
  /* a column: two blocks' three rows, two friction rows, a pinned row */
  const size_t nnz = (size_t)COLS_PER_JOINT * (size_t)l->nj * 9 + 3 * (size_t)n_live + 3;
  l->n_live = n_live;
  l->live = malloc((size_t)(n_live > 0 ? n_live : 1) * sizeof *l->live);
  l->start = malloc((size_t)(l->ncol + 1) * sizeof *l->start);
  l->index = malloc(nnz * sizeof *l->index);
  l->value = malloc(nnz * sizeof *l->value);
  l->collb = malloc((size_t)l->ncol * sizeof *l->collb);
  l->colub = malloc((size_t)l->ncol * sizeof *l->colub);
  l->obj = malloc((size_t)l->ncol * sizeof *l->obj);
  l->rowlb = malloc((size_t)l->nrow * sizeof *l->rowlb);
  l->rowub = malloc((size_t)l->nrow * sizeof *l->rowub);
  l->basis = calloc((size_t)(l->ncol + l->nrow), 1);
  if (!l->live || !l->start || !l->index || !l->value || !l->collb || !l->colub || !l->obj ||
      !l->rowlb || !l->rowub || !l->basis) {
    vs_limit_destroy(&l);
    return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  }
  if (!(l->wref > 0.0 && l->lref > 0.0)) {
    vs_limit_destroy(&l);
    return vs_error_set(err, VS_ERR_INVALID, "limit: the assembly has no weight or no joint length");
  }
  if (n_live > 0) memcpy(l->live, live, (size_t)n_live * sizeof *live);
  assemble(l);
  *out = l;
  return VS_OK;
}

vs_status vs_limit_add_dead(vs_limit *l, const vs_limit_force *dead, int n, vs_error *err) {
  vs_status st = check_live(l->g, dead, n, err);
  if (st != VS_OK) return st;
  for (int f = 0; f < n; f++) { /* equilibrium = -dead load, as the weight's */
    double gf[3];
    block_load(l, dead[f].block, dead[f].fx, dead[f].fz, dead[f].px, dead[f].pz, gf);
    for (int r = 0; r < 3; r++) {
      const int row = ROWS_PER_BLOCK * dead[f].block + r;
      l->rowlb[row] -= gf[r];
      l->rowub[row] -= gf[r];
    }
  }
  return VS_OK;
}

void vs_limit_destroy(vs_limit **lp) {
  if (lp == NULL || *lp == NULL) return;
  vs_limit *l = *lp;
  free(l->live);
  free(l->start);
  free(l->index);
  free(l->value);
  free(l->collb);
  free(l->colub);
  free(l->obj);
  free(l->rowlb);
  free(l->rowub);
  free(l->basis);
  free(l);
  *lp = NULL;
}

/* ---------------------------------------------------------------------------------------------
 * One solve */

void vs_limit_solution_free(vs_limit_solution *s) {
  if (s == NULL) return;
  free(s->force);
  free(s->eta);
  free(s->px);
  free(s->pz);
  free(s->touch);
  free(s->hinge);
  free(s->open);
  free(s->slip);
  free(s->friction);
  s->force = s->eta = s->px = s->pz = s->open = s->slip = NULL;
  s->touch = s->hinge = s->friction = NULL;
}

static vs_status solution_alloc(int nj, int mechanism, vs_limit_solution *s, vs_error *err) {
  vs_limit_solution_free(s);
  const size_t n = (size_t)nj;
  s->n_joints = nj;
  s->force = calloc(4 * n, sizeof *s->force);
  s->eta = calloc(n, sizeof *s->eta);
  s->px = calloc(n, sizeof *s->px);
  s->pz = calloc(n, sizeof *s->pz);
  s->touch = calloc(n, 1);
  s->friction = calloc(n, 1);
  if (mechanism) {
    s->hinge = calloc(n, 1);
    s->open = calloc(2 * n, sizeof *s->open);
    s->slip = calloc(n, sizeof *s->slip);
  }
  if (!s->force || !s->eta || !s->px || !s->pz || !s->touch || !s->friction ||
      (mechanism && (!s->hinge || !s->open || !s->slip))) {
    vs_limit_solution_free(s);
    return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  }
  return VS_OK;
}

/* The coefficients of H, the horizontal force of the left support on the assembly, per
 * column (scaled: H = wref x obj . x). */
static void thrust_objective(const vs_limit *l, double *obj) {
  memset(obj, 0, (size_t)l->ncol * sizeof *obj);
  for (int k = 0; k < l->nj; k++) {
    const vs_joint_geom *j = &l->g->joints[k];
    const double sign = j->a == VS_SUPPORT_LEFT ? 1.0 : j->b == VS_SUPPORT_LEFT ? -1.0 : 0.0;
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    for (int e = 0; e < 2; e++) {
      obj[COLS_PER_JOINT * k + 2 * e] = sign * j->nx;
      obj[COLS_PER_JOINT * k + 2 * e + 1] = sign * sx;
    }
  }
}

/* The forces, the thrust line and its touches, the joints at the friction limit. */
static void read_forces(const vs_limit *l, const double *x, const double *hobj,
                        vs_limit_solution *s) {
  s->thrust = 0.0;
  for (int c = 0; c < l->ncol - 1; c++) s->thrust += l->wref * hobj[c] * x[c];
  s->n_touch = s->n_friction = 0;
  const double zero = VS_LIMIT_ZERO * l->wref;
  for (int k = 0; k < l->nj; k++) {
    const vs_joint_geom *j = &l->g->joints[k];
    double *f = &s->force[COLS_PER_JOINT * k];
    for (int c = 0; c < COLS_PER_JOINT; c++) f[c] = l->wref * x[COLS_PER_JOINT * k + c];
    /* the joint's resultant: how its shear is split between the ends does not matter (any
     * split of |V| <= mu N in proportion to the ends' N satisfies both ends' rows) */
    const double ni = fmax(f[0], 0.0), ne = fmax(f[2], 0.0), ntot = ni + ne, v = f[1] + f[3];
    s->friction[k] = ntot > zero && fabs(v) >= joint_mu(l, j) * ntot * (1.0 - VS_LIMIT_FRICTION_REL);
    s->n_friction += s->friction[k];
    double ix, iz, sx, sz;
    joint_end(j, 0, &ix, &iz);
    vs_joint_tangent(j, &sx, &sz);
    if (!(ntot > zero)) {
      s->eta[k] = s->px[k] = s->pz[k] = NAN;
      s->touch[k] = 'O';
      continue;
    }
    s->eta[k] = ne / ntot;
    s->px[k] = ix + s->eta[k] * j->length * sx;
    s->pz[k] = iz + s->eta[k] * j->length * sz;
    s->touch[k] = s->eta[k] <= l->o.touch ? 'I' : s->eta[k] >= 1.0 - l->o.touch ? 'E' : 0;
    s->n_touch += s->touch[k] != 0;
  }
}

/* Velocity at (px, pz) of body `body` in the mechanism u (3 per block: vx, vz, omega). */
static void body_velocity(const vs_limit *l, const double *u, int body, double px, double pz,
                          double v[2]) {
  v[0] = v[1] = 0.0;
  if (body < 0) return; /* a support does not move */
  const vs_block *b = &l->g->blocks[body];
  const double *ub = &u[ROWS_PER_BLOCK * body];
  v[0] = ub[0] - ub[2] * (pz - b->cz);
  v[1] = ub[1] + ub[2] * (px - b->cx);
}

/* The mechanism from the equilibrium rows' duals (the blocks' virtual velocities), oriented so
 * that the live load does positive work: each joint's opening at its ends and its sliding (as
 * fractions of the largest rate, 0 below the tolerance), and the hinges they make. */
static vs_status read_mechanism(const vs_limit *l, const double *dual, vs_limit_solution *s,
                                vs_error *err) {
  double power = 0.0, *vel = malloc((size_t)(ROWS_PER_BLOCK * l->nb) * sizeof *vel);
  if (vel == NULL) return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  for (int i = 0; i < l->nb; i++) { /* the moment row is scaled by lref */
    vel[3 * i] = dual[3 * i];
    vel[3 * i + 1] = dual[3 * i + 1];
    vel[3 * i + 2] = dual[3 * i + 2] / l->lref;
  }
  for (int f = 0; f < l->n_live; f++) {
    const vs_limit_force *lf = &l->live[f];
    double v[2];
    body_velocity(l, vel, lf->block, lf->px, lf->pz, v);
    power += lf->fx * v[0] + lf->fz * v[1];
  }
  const double orient = power < 0.0 ? -1.0 : 1.0;
  double top = 0.0;
  for (int k = 0; k < l->nj; k++) {
    const vs_joint_geom *j = &l->g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    for (int e = 0; e < 2; e++) {
      double px, pz, va[2], vb[2];
      joint_end(j, e, &px, &pz);
      body_velocity(l, vel, j->a, px, pz, va);
      body_velocity(l, vel, j->b, px, pz, vb);
      const double rx = orient * (vb[0] - va[0]), rz = orient * (vb[1] - va[1]);
      s->open[2 * k + e] = rx * j->nx + rz * j->nz;
      if (e == 0) s->slip[k] = rx * sx + rz * sz; /* the same at every point of the joint */
    }
    top = fmax(top, fmax(fmax(fabs(s->open[2 * k]), fabs(s->open[2 * k + 1])), fabs(s->slip[k])));
  }
  free(vel);
  s->n_hinges = s->n_sliding = 0;
  for (int k = 0; k < l->nj; k++) {
    double *r[3] = {&s->open[2 * k], &s->open[2 * k + 1], &s->slip[k]};
    for (int c = 0; c < 3; c++) {
      *r[c] = top > 0.0 ? *r[c] / top : 0.0;
      if (fabs(*r[c]) <= l->o.hinge) *r[c] = 0.0;
    }
    const int oi = s->open[2 * k] > 0.0, oe = s->open[2 * k + 1] > 0.0, sl = s->slip[k] != 0.0;
    s->hinge[k] = oi && oe ? 'O' : oe ? 'I' : oi ? 'E' : sl ? 'S' : 0;
    s->n_hinges += oi || oe;
    s->n_sliding += sl;
  }
  return VS_OK;
}

/* Bounds and objective of goal: lambda free above 0 for the load factor, fixed at 0 otherwise. */
static void set_goal(vs_limit *l, vs_limit_goal goal, double *hobj) {
  thrust_objective(l, hobj);
  const int lam = l->ncol - 1;
  if (goal == VS_LIMIT_LOAD_FACTOR) {
    memset(l->obj, 0, (size_t)l->ncol * sizeof *l->obj);
    l->obj[lam] = 1.0;
    l->colub[lam] = VS_CLP_INF;
  } else {
    memcpy(l->obj, hobj, (size_t)l->ncol * sizeof *l->obj);
    l->colub[lam] = 0.0;
  }
}

/* The largest violation of a row's or a column's bounds by CLP's solution (scaled units: a
 * fraction of the assembly's weight, or of weight x mean joint length). */
static double violation(const vs_limit *l, Clp_Simplex *m) {
  const double *ra = Clp_getRowActivity(m), *x = Clp_getColSolution(m);
  double v = 0.0;
  for (int r = 0; r < l->nrow; r++) v = fmax(v, fmax(l->rowlb[r] - ra[r], ra[r] - l->rowub[r]));
  for (int c = 0; c < l->ncol; c++) v = fmax(v, fmax(l->collb[c] - x[c], x[c] - l->colub[c]));
  return v;
}

/* Near a critical thickness CLP's scaled problem can be optimal where the problem itself is not
 * (its optimum violates a row by up to 1e-5 of the weight), or look infeasible: the unscaled
 * problem decides, by the primal simplex from an optimum that violates a row, by the dual
 * simplex again from an infeasible end. */
static void recheck(const vs_limit *l, Clp_Simplex *m) {
  const int status = Clp_status(m);
  if (status == 0 && violation(l, m) <= VS_LIMIT_FEASIBLE) return;
  if (status != 0 && status != 1) return;
  Clp_scaling(m, 0);
  if (status == 0) Clp_primal(m, 0);
  else Clp_dual(m, 0);
}

static vs_status read_solution(vs_limit *l, Clp_Simplex *m, vs_limit_goal goal, const double *hobj,
                               vs_limit_solution *s, vs_error *err) {
  const int status = Clp_status(m);
  s->iterations = Clp_numberIterations(m);
  if (status == 1 || status == 2) {
    s->outcome = status == 1 ? VS_LIMIT_INFEASIBLE : VS_LIMIT_UNBOUNDED;
    return VS_OK;
  }
  if (status != 0)
    return vs_error_set(err, VS_ERR_SOLVER, "limit: CLP stopped with status %d (%s)", status,
                        status == 3 ? "iteration limit" : "numerical trouble");
  const double v = violation(l, m);
  if (v > VS_LIMIT_FEASIBLE)
    return vs_error_set(err, VS_ERR_SOLVER,
                        "limit: CLP's optimum violates the equilibrium or the bounds by %.3g of "
                        "the weight (allowed: %g)", v, VS_LIMIT_FEASIBLE);
  s->outcome = VS_LIMIT_OPTIMAL;
  const double *x = Clp_getColSolution(m);
  read_forces(l, x, hobj, s);
  s->value = goal == VS_LIMIT_LOAD_FACTOR ? x[l->ncol - 1] : s->thrust;
  return goal == VS_LIMIT_LOAD_FACTOR ? read_mechanism(l, Clp_getRowPrice(m), s, err) : VS_OK;
}

vs_status vs_limit_solve(vs_limit *l, vs_limit_goal goal, vs_limit_solution *s, vs_error *err) {
  if (goal < 0 || goal >= VS_LIMIT_GOAL_COUNT)
    return vs_error_set(err, VS_ERR_INVALID, "limit: goal %d (allowed: 0..%d)", (int)goal,
                        VS_LIMIT_GOAL_COUNT - 1);
  if (goal == VS_LIMIT_LOAD_FACTOR && l->n_live == 0)
    return vs_error_set(err, VS_ERR_INVALID, "limit: the load factor needs a live load");
  const double t0 = vs_cpu_now();
  vs_status st = solution_alloc(l->nj, goal == VS_LIMIT_LOAD_FACTOR, s, err);
  if (st != VS_OK) return st;
  s->goal = goal;
  s->outcome = VS_LIMIT_INFEASIBLE;
  s->value = s->thrust = NAN;
  double *hobj = malloc((size_t)l->ncol * sizeof *hobj);
  Clp_Simplex *m = hobj != NULL ? Clp_newModel() : NULL;
  if (m == NULL) {
    free(hobj);
    return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  }
  set_goal(l, goal, hobj);
  Clp_setLogLevel(m, 0);
  Clp_loadProblem(m, l->ncol, l->nrow, l->start, l->index, l->value, l->collb, l->colub, l->obj,
                  l->rowlb, l->rowub);
  Clp_setOptimizationDirection(m, goal == VS_LIMIT_THRUST_MIN ? 1.0 : -1.0);
  if (l->warm) { /* from the basis of a like LP (the same rows and columns) */
    Clp_copyinStatus(m, l->basis);
    Clp_dual(m, 0);
  } else {
    Clp_initialDualSolve(m);
  }
  recheck(l, m);
  if (Clp_statusExists(m)) memcpy(l->basis, Clp_statusArray(m), vs_limit_basis_size(l));
  st = read_solution(l, m, goal, hobj, s, err);
  Clp_deleteModel(m);
  free(hobj);
  s->cpu_s = vs_cpu_now() - t0;
  return st;
}

/* ---------------------------------------------------------------------------------------------
 * Lists */

void vs_limit_list(const vs_limit_solution *s, char which, char *buf, size_t size) {
  if (size == 0) return;
  buf[0] = '\0';
  if (s == NULL || s->touch == NULL) return;
  size_t used = 0;
  int left = 0;
  for (int k = 0; k < s->n_joints; k++) {
    char side = 0;
    switch (which) {
    case 'h': side = s->hinge != NULL && s->hinge[k] != 'S' ? s->hinge[k] : 0; break;
    case 'x': side = s->slip != NULL && s->slip[k] != 0.0 ? 'S' : 0; break;
    case 't': side = s->touch[k] == 'I' || s->touch[k] == 'E' ? s->touch[k] : 0; break;
    case 'f': side = s->friction[k] ? 'F' : 0; break;
    default: break;
    }
    if (side == 0) continue;
    char item[32];
    if (side == 'I' || side == 'E') snprintf(item, sizeof item, "%s%d-%c", used ? " " : "", k + 1, side);
    else if (side == 'O') snprintf(item, sizeof item, "%s%d-open", used ? " " : "", k + 1);
    else snprintf(item, sizeof item, "%s%d", used ? " " : "", k + 1);
    /* room for the item and a " +K more" after it */
    if (left == 0 && used + strlen(item) + 16 < size) {
      memcpy(buf + used, item, strlen(item) + 1);
      used += strlen(item);
    } else {
      left++;
    }
  }
  if (left > 0) snprintf(buf + used, size - used, "%s+%d more", used ? " " : "", left);
}

/* ---------------------------------------------------------------------------------------------
 * Warm starts (limit_internal.h) */

size_t vs_limit_basis_size(const vs_limit *l) { return (size_t)(l->ncol + l->nrow); }

void vs_limit_basis_save(const vs_limit *l, unsigned char *to) {
  memcpy(to, l->basis, vs_limit_basis_size(l));
}

void vs_limit_basis_start(vs_limit *l, const unsigned char *from) {
  memcpy(l->basis, from, vs_limit_basis_size(l));
  l->warm = 1;
}
