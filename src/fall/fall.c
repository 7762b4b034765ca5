/* The fall (fall.h): time stepping with impulsive contacts, the impulses by nonsmooth
 * Gauss-Seidel over the contacts (accelerated by NNCG), the energies (fall_state.c: what the
 * record reads at a state). */
#include "voussoir/fall.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fall_internal.h"
#include "wall_clock.h"

void vs_fall_opts_default(vs_fall_opts *o) {
  memset(o, 0, sizeof *o);
  o->step = 1e-3;
  o->slow_step = 2e-3;
  o->slow_speed = 0.5;
  o->rest_time = 0.1;
  o->duration = 5.0;
  o->sample_dt = 0.01;
  o->ground = NAN;
  o->tol = 1e-2;
  o->max_sweeps = VS_FALL_MAX_SWEEPS;
  o->calm = VS_FALL_CALM;
  o->solver = VS_FALL_NNCG;
  o->joints = 1;
}

/* The solvers' names as the case file writes them (fall.solver), in the order of vs_fall_solver. */
static const char *const SOLVER_NAMES[] = {"nncg", "gauss_seidel"};
_Static_assert(sizeof SOLVER_NAMES / sizeof SOLVER_NAMES[0] == VS_FALL_SOLVER_COUNT,
               "a name for every vs_fall_solver");

const char *vs_fall_solver_name(int solver) {
  return solver >= 0 && solver < VS_FALL_SOLVER_COUNT ? SOLVER_NAMES[solver] : "?";
}

static vs_status check_opts(const vs_fall_opts *o, vs_error *err) {
  if (!(o->slow_step >= o->step && o->slow_step <= 0.1) ||
      !(o->slow_speed >= 0.0 && o->slow_speed < INFINITY))
    return vs_error_set(err, VS_ERR_INVALID,
                        "fall: options slow_step = %g s, slow_speed = %g m/s (allowed: step = %g "
                        "<= slow_step <= 0.1, 0 <= slow_speed < inf)", o->slow_step,
                        o->slow_speed, o->step);
  if (!(o->step > 0.0 && o->step <= 0.1) || !(o->rate >= 0.0 && o->rate < INFINITY) ||
      !(o->rest_ke >= 0.0) || !(o->rest_time >= 0.0) || !(o->duration >= 0.0) ||
      !(o->sample_dt > 0.0) || !(o->tol > 0.0 && o->tol <= 1.0) || o->max_sweeps < 1 ||
      !(o->calm >= 0.0 && o->calm < INFINITY) || isinf(o->ground))
    return vs_error_set(err, VS_ERR_INVALID,
                        "fall: options step = %g s, rate = %g m/s, rest_ke = %g J, rest_time = "
                        "%g s, duration = %g s, sample_dt = %g s, tol = %g, max_sweeps = %d, "
                        "calm = %g (allowed: 0 < step <= 0.1, rate >= 0, rest_ke >= 0, "
                        "rest_time >= 0, duration >= 0, sample_dt > 0, 0 < tol <= 1, max_sweeps "
                        ">= 1, 0 <= calm < inf, ground finite or NaN)", o->step, o->rate,
                        o->rest_ke, o->rest_time, o->duration, o->sample_dt, o->tol,
                        o->max_sweeps, o->calm);
  if (o->solver != VS_FALL_NNCG && o->solver != VS_FALL_GAUSS_SEIDEL)
    return vs_error_set(err, VS_ERR_INVALID, "fall: option solver = %d (allowed: %d NNCG, %d "
                        "Gauss-Seidel)", o->solver, VS_FALL_NNCG, VS_FALL_GAUSS_SEIDEL);
  return VS_OK;
}

void vs_fall_destroy(vs_fall **fp) {
  if (fp == NULL || *fp == NULL) return;
  vs_fall *f = *fp;
  vs_fall_geom_free(f);
  vs_fall_chain_free(f);
  free(f->q), free(f->v), free(f->vk), free(f->vs), free(f->w), free(f->c), free(f->pkey);
  free(f->pP), free(f->js);
  free(f->isl_first), free(f->isl_bfirst), free(f->isl_c), free(f->isl_b), free(f->isl_of);
  free(f->qst), free(f->vst), free(f->jlo), free(f->jhi);
  free(f);
  *fp = NULL;
}

vs_status vs_fall_create(vs_model *m, const vs_fall_opts *o, const int *count, const double *xz,
                         vs_fall **out, vs_error *err) {
  *out = NULL;
  vs_status st = check_opts(o, err);
  if (st != VS_OK) return st;
  vs_fall *f = calloc(1, sizeof *f);
  if (f == NULL) return vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory");
  f->m = m;
  f->g = vs_model_geometry(m);
  f->o = *o;
  f->n = f->g->n_blocks;
  f->nb = f->n + 2;
  f->level = NAN;
  const size_t Q = 3 * (size_t)f->nb, nq = (size_t)vs_model_size(m);
  f->q = calloc(Q, sizeof *f->q), f->v = calloc(Q, sizeof *f->v), f->vk = calloc(Q, sizeof *f->vk);
  f->vs = calloc(Q, sizeof *f->vs), f->w = calloc(Q, sizeof *f->w);
  f->js = calloc((size_t)f->g->n_joints + 1, sizeof *f->js);
  f->qst = calloc(nq, sizeof *f->qst), f->vst = calloc(nq, sizeof *f->vst);
  f->jlo = calloc((size_t)f->g->n_joints + 1, sizeof *f->jlo);
  f->jhi = calloc((size_t)f->g->n_joints + 1, sizeof *f->jhi);
  f->isl_first = calloc((size_t)f->nb + 1, sizeof *f->isl_first);
  f->isl_bfirst = calloc((size_t)f->nb + 1, sizeof *f->isl_bfirst);
  f->isl_b = calloc((size_t)f->nb, sizeof *f->isl_b);
  f->isl_of = calloc((size_t)f->nb, sizeof *f->isl_of);
  if (!f->q || !f->v || !f->vk || !f->vs || !f->w || !f->js || !f->qst || !f->vst || !f->jlo ||
      !f->jhi || !f->isl_first || !f->isl_bfirst || !f->isl_b || !f->isl_of)
    st = vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory");
  if (st == VS_OK) st = vs_fall_geom_init(f, count, xz, err);
  if (st == VS_OK && o->joints && f->g->n_joints > 0 && vs_fall_chain_init(f) != 0)
    st = vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory (the joints' system)");

  if (st != VS_OK) {
    vs_fall_destroy(&f);
    return st;
  }
  *out = f;
  return VS_OK;
}

void vs_fall_set_stop(vs_fall *f, const volatile sig_atomic_t *stop) { f->o.stop = stop; }
double vs_fall_level(const vs_fall *f) { return f->level; }

/* --- the impulses --- */

static double dot3(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Contact c's local solve, prepared once a step (W is fixed over the step): W's inverse, and per
 * sliding direction s (0: +, 1: -) the normal impulse per unit of rn on the cone's edge and the
 * ratio of the tangential impulse to it (where friction cannot be balanced, Painleve's case, the
 * normal impulse alone: 1 / W_nn and 0). */
static void prepare(vs_fall_contact *c, double mu) {
  const double *W = c->W, det = W[0] * W[2] - W[1] * W[1];
  c->iW[0] = W[2] / det, c->iW[1] = -W[1] / det, c->iW[2] = W[0] / det;
  c->iWnn = 1.0 / W[0];
  for (int k = 0; k < 2; k++) {
    const double s = k == 0 ? 1.0 : -1.0, den = W[0] + s * mu * W[1];
    c->slide[k][0] = den > 0.0 ? 1.0 / den : 1.0 / W[0];
    c->slide[k][1] = den > 0.0 ? s * mu : 0.0;
  }
}

/* The impulse of contact c that solves its own Signorini-Coulomb problem, the others held:
 * with uf its relative velocity without its impulse, u = uf + W P. Separating if uf_n >= bias;
 * sticking if the impulse that gives u = (bias, 0) is inside the cone; sliding otherwise, on
 * the cone's edge the sticking impulse points past. */
static void local_solve(const vs_fall_contact *c, double mu, const double uf[2], double P[2]) {
  P[0] = P[1] = 0.0;
  if (uf[0] >= c->bias) return;
  const double rn = c->bias - uf[0], rt = -uf[1];
  double pn = c->iW[0] * rn + c->iW[1] * rt, pt = c->iW[1] * rn + c->iW[2] * rt;
  if (!(pn >= 0.0 && fabs(pt) <= mu * pn)) {
    const double *sl = c->slide[pt > 0.0 ? 0 : 1];
    pn = rn * sl[0], pt = sl[1] * pn;
  }
  if (pn > 0.0) P[0] = pn, P[1] = pt;
}

/* One Gauss-Seidel update of contact c (the inner loop of the fall: the relative velocity and
 * the impulse's application written out, the latter with the rows Ka, Kb of the contact). */
static void update(vs_fall *f, vs_fall_contact *c, double mu) {
  double *va = f->v + 3 * c->a, *vb = c->b >= 0 ? f->v + 3 * c->b : NULL;
  double u[2] = {dot3(c->Ja, va), dot3(c->Ja + 3, va)}, uf[2], P[2];
  if (vb != NULL) u[0] += dot3(c->Jb, vb), u[1] += dot3(c->Jb + 3, vb);
  uf[0] = u[0] - (c->W[0] * c->P[0] + c->W[1] * c->P[1]);
  uf[1] = u[1] - (c->W[1] * c->P[0] + c->W[2] * c->P[1]);
  local_solve(c, mu, uf, P);
  const double d0 = P[0] - c->P[0], d1 = P[1] - c->P[1];
  if (d0 == 0.0 && d1 == 0.0) return;
  for (int i = 0; i < 3; i++) va[i] += c->Ka[i] * d0 + c->Ka[3 + i] * d1;
  if (vb != NULL)
    for (int i = 0; i < 3; i++) vb[i] += c->Kb[i] * d0 + c->Kb[3 + i] * d1;
  c->P[0] = P[0], c->P[1] = P[1];
}

/* The last step's impulses, by contact key, for the warm start: an open-addressing hash table
 * (pkey, pP; pcap slots, a power of two, at most half full; VS_FALL_NO_KEY marks a free slot). */
#define VS_FALL_NO_KEY LLONG_MIN

static size_t slot_of(const vs_fall *f, long long key) {
  /* Fibonacci hashing of the key's bits */
  return (size_t)(((unsigned long long)key * 0x9E3779B97F4A7C15ULL) >> 32) & (size_t)(f->pcap - 1);
}

/* The last step's impulse of the contact with this key (0 if it had none), times r: for a step
 * r times as long, the same force. */
static void warm(const vs_fall *f, long long key, double r, double P[2]) {
  P[0] = P[1] = 0.0;
  if (f->npc == 0) return;
  for (size_t i = slot_of(f, key);; i = (i + 1) & (size_t)(f->pcap - 1)) {
    if (f->pkey[i] == VS_FALL_NO_KEY) return;
    if (f->pkey[i] == key) {
      P[0] = r * f->pP[2 * i], P[1] = r * f->pP[2 * i + 1];
      return;
    }
  }
}

/* An empty table with room for n impulses. 0 or -1 (memory). */
static int reserve(vs_fall *f, int n) {
  int cap = f->pcap > 0 ? f->pcap : 64;
  while (cap < 2 * n) cap *= 2;
  if (cap != f->pcap) {
    long long *k = realloc(f->pkey, (size_t)cap * sizeof *k);
    if (k != NULL) f->pkey = k;
    double *p = k != NULL ? realloc(f->pP, 2 * (size_t)cap * sizeof *p) : NULL;
    if (p == NULL) return -1;
    f->pP = p, f->pcap = cap;
  }
  for (int i = 0; i < f->pcap; i++) f->pkey[i] = VS_FALL_NO_KEY;
  f->npc = 0;
  return 0;
}

/* Store impulse P under key (keys are unique within a step). */
static void store(vs_fall *f, long long key, double p0, double p1) {
  size_t i = slot_of(f, key);
  while (f->pkey[i] != VS_FALL_NO_KEY && f->pkey[i] != key) i = (i + 1) & (size_t)(f->pcap - 1);
  f->npc += f->pkey[i] == VS_FALL_NO_KEY;
  f->pkey[i] = key, f->pP[2 * i] = p0, f->pP[2 * i + 1] = p1;
}

/* Keep this step's impulses, by key, for the next step's warm start. 0 or -1 (memory). */
static int keep(vs_fall *f) {
  if (reserve(f, f->nc) != 0) return -1;
  for (int i = 0; i < f->nc; i++) store(f, f->c[i].key, f->c[i].P[0], f->c[i].P[1]);
  return 0;
}

/* --- the state --- */

/* The supports' positions and velocities at time t (driven; a pinned one keeps its rotation). */
static void supports(vs_fall *f, double t) {
  double qs[6], vsu[6];
  vs_model_support_states(f->m, f->o.rate * t, f->o.rate, qs, vsu);
  for (int s = 0; s < 2; s++)
    for (int i = 0; i < 2; i++) {
      f->q[3 * (f->n + s) + i] = qs[3 * s + i];
      f->v[3 * (f->n + s) + i] = vsu[3 * s + i];
    }
  f->v[3 * f->n + 2] = f->v[3 * f->n + 5] = 0.0;
}

static double kinetic(const vs_fall *f) {
  double e = 0.0;
  for (int i = 0; i < 3 * f->n; i++) e += 0.5 * f->v[i] * f->v[i] / f->minv[i];
  return e;
}

typedef struct {
  double normal, tangential, support; /* dissipated at the contacts (J), work of the piers (J) */
  double recovered;      /* work of the overlaps' recovery against gravity (J) */
  double ground, body, joint; /* deepest overlap at the step's start: below the ground, into a
                                 body without a joint, behind a joint's face (m; 0: none) */
  double last;           /* the largest change of a body's velocity in the last sweep, m/s */
  int sweeps, solves, converged, chain, redone;
  int calm;              /* set by the caller: the step is near rest (vs_fall_opts.calm) */
} step_out;

/* Gauss-Seidel's cap on sweeps near rest: max_sweeps, or VS_FALL_CALM_SWEEPS if more. */
static int calm_cap(const vs_fall *f) {
  return f->o.max_sweeps < VS_FALL_CALM_SWEEPS ? VS_FALL_CALM_SWEEPS : f->o.max_sweeps;
}

/* Gauss-Seidel's tolerance in a step of h, as a velocity (m/s): tol g h; near rest a tenth of
 * tol g step (fall.h: VS_FALL_CALM_TOL), the short step's whatever this one's length, so that
 * what it lets a resting contact sink in a second (the tolerance itself) does not grow with the
 * slow step. */
static double sweep_tol(const vs_fall *f, double h, const step_out *so) {
  return f->o.tol * f->g->gravity * (so->calm ? VS_FALL_CALM_TOL * f->o.step : h);
}

/* Overlaps of a vertex with the ground or another body (the scheme's own: a step is a straight
 * line in each body's coordinates) are taken back by this fraction per step, through the
 * positions only (recover); a joint's (its faces' elastic closure at the collapse, where the
 * fall starts) are kept. */
static const double VS_FALL_RECOVER = 0.2;

/* Contact c's normal law for a step of h: where it has a gap, the gap may close within the step
 * but not be passed (u_n >= -gap / h); where the bodies touch or overlap, they stop approaching
 * (u_n >= 0: a perfectly plastic impact). */
static void contact_law(vs_fall_contact *c, double h) {
  c->bias = c->gap > 0.0 ? -c->gap / h : 0.0;
}

/* A bound on how fast any point of body b moves at the velocity (vx, vz, w), m/s: the speed of
 * its reference point, and its rotation's at its outline's reach. Also for velocity changes. */
static double point_speed(const vs_fall *f, int b, double vx, double vz, double w) {
  return sqrt(vx * vx + vz * vz) + fabs(w) * f->rmaxb[b];
}

/* The step's islands: the bodies that contacts join (through moving bodies only: the ground
 * and the piers join nothing), each with its contacts in the order of f->c, so that Gauss-Seidel
 * solves each island on its own, until its own bodies settle: an island at rest takes a sweep
 * or two while another rocks. A body with no contact is an island of its own, with nothing to
 * solve. 0, or -1 when out of memory. */
static int islands(vs_fall *f) {
  int *root = f->isl_of;
  for (int b = 0; b < f->n; b++) root[b] = b;
  for (int i = 0; i < f->nc; i++) {
    int a = f->c[i].a, b = f->c[i].b;
    if (!vs_fall_moving(f, a) || !vs_fall_moving(f, b)) continue;
    while (root[a] != a) a = root[a] = root[root[a]];
    while (root[b] != b) b = root[b] = root[root[b]];
    if (a != b) root[a < b ? b : a] = a < b ? a : b; /* the lower body is the root */
  }
  if (f->nc > f->iccap) {
    int *c = realloc(f->isl_c, (size_t)f->cap * sizeof *c);
    if (c == NULL) return -1;
    f->isl_c = c, f->iccap = f->cap;
  }
  /* every body's root (a body's parent is never above it, so its parent's is final by then),
   * then the islands numbered by their roots (isl_b holds the roots' numbers meanwhile) */
  int *count = f->isl_first, *bcount = f->isl_bfirst, nisl = 0;
  for (int b = 0; b < f->n; b++) root[b] = root[root[b]];
  for (int b = 0; b < f->n; b++)
    if (root[b] == b) f->isl_b[b] = nisl++;
  for (int b = 0; b < f->n; b++) root[b] = f->isl_b[root[b]];
  /* the contacts' and bodies' counts per island, then the slots by prefix sums */
  for (int s = 0; s <= nisl; s++) count[s] = bcount[s] = 0;
  for (int i = 0; i < f->nc; i++) {
    const int b = vs_fall_moving(f, f->c[i].a) ? f->c[i].a : f->c[i].b;
    if (vs_fall_moving(f, b)) count[root[b] + 1]++;
  }
  for (int b = 0; b < f->n; b++) bcount[root[b] + 1]++;
  for (int s = 0; s < nisl; s++) count[s + 1] += count[s], bcount[s + 1] += bcount[s];
  for (int i = 0; i < f->nc; i++) {
    const int b = vs_fall_moving(f, f->c[i].a) ? f->c[i].a : f->c[i].b;
    if (vs_fall_moving(f, b)) f->isl_c[count[root[b]]++] = i;
  }
  for (int b = 0; b < f->n; b++) f->isl_b[bcount[root[b]]++] = b;
  for (int s = nisl; s > 0; s--) count[s] = count[s - 1], bcount[s] = bcount[s - 1];
  count[0] = bcount[0] = 0;
  f->nisl = nisl;
  return 0;
}

/* NNCG's step after a sweep of island s that has not converged (Silcowitz, Niebe and Erleben,
 * "A nonsmooth nonlinear conjugate gradient method for interactive contact force problems", The
 * Visual Computer 26, 2010): the sweep's change of the impulses, r = P - Ps, is the descent
 * direction of a merit function of the contact problem, and the impulses move on along
 * d = r + beta d_prev, beta = |r|^2 / |r_prev|^2 (Fletcher-Reeves; *rr holds |r_prev|^2, 0 at the
 * first sweep), restarting with d = r where beta > 1 (the sweeps stopped closing in). The bodies'
 * velocities move with the impulses; the next sweep projects them back onto the contact laws.
 * Measured: a standing tower's exact impulses in about half the sweeps of Gauss-Seidel alone
 * (test_fall: test_nncg_stack), and falls that come to rest sooner (docs/fall.md, "The rigid
 * fall"). */
static void nncg_step(vs_fall *f, const int *ci, int nci, double *rr) {
  double r2 = 0.0;
  for (int i = 0; i < nci; i++) {
    const vs_fall_contact *c = &f->c[ci[i]];
    const double r0 = c->P[0] - c->Ps[0], r1 = c->P[1] - c->Ps[1];
    r2 += r0 * r0 + r1 * r1;
  }
  const double beta = *rr > 0.0 ? r2 / *rr : 2.0;
  *rr = r2;
  for (int i = 0; i < nci; i++) {
    vs_fall_contact *c = &f->c[ci[i]];
    const double r0 = c->P[0] - c->Ps[0], r1 = c->P[1] - c->Ps[1];
    if (beta > 1.0) { /* a restart: the sweep's own change is the direction */
      c->Pd[0] = r0, c->Pd[1] = r1;
    } else {
      const double a0 = beta * c->Pd[0], a1 = beta * c->Pd[1];
      vs_fall_apply(f, c, a0, a1, f->v);
      c->P[0] += a0, c->P[1] += a1;
      c->Pd[0] = a0 + r0, c->Pd[1] = a1 + r1;
    }
    c->Ps[0] = c->P[0], c->Ps[1] = c->P[1]; /* where the next sweep starts */
  }
}

/* Island s's impulses by Gauss-Seidel over its contacts, sweeps alternating in direction (the
 * first as sweep s0 would), each followed by NNCG's step (vs_fall_opts.solver): until none of
 * the island's bodies' velocities moves by tol in a sweep, or cap sweeps. Where the cap stops
 * them, NNCG's last step is kept (the warm start of the next step carries on from it: without
 * it, more falls of *The fall's cost* were followed to fall_s), its impulses projected onto
 * their contacts' laws (P_n >= 0, |P_t| <= mu P_n) so that every step's are admissible. The
 * sweeps taken, negated if the cap stopped them (*last: then the largest change of a body's
 * velocity in the last sweep, m/s). */
static int solve_island(vs_fall *f, int s, double mu, double tol, int cap, int s0, double *last) {
  const int *ci = f->isl_c + f->isl_first[s], nci = f->isl_first[s + 1] - f->isl_first[s];
  const int *bi = f->isl_b + f->isl_bfirst[s], nbi = f->isl_bfirst[s + 1] - f->isl_bfirst[s];
  const int nncg = f->o.solver == VS_FALL_NNCG;
  double worst = 0.0, rr = 0.0;
  int k = 0, converged = 0;
  if (nncg) /* the first sweep's start (nncg_step sets the next ones') */
    for (int i = 0; i < nci; i++) {
      vs_fall_contact *c = &f->c[ci[i]];
      c->Ps[0] = c->P[0], c->Ps[1] = c->P[1];
    }
  for (; k < cap && !converged; k++) {
    for (int j = 0; j < nbi; j++) memcpy(f->vs + 3 * bi[j], f->v + 3 * bi[j], 3 * sizeof *f->v);
    for (int i = 0; i < nci; i++) update(f, &f->c[ci[((s0 + k) % 2) ? nci - 1 - i : i]], mu);
    /* converged once none of the island's bodies' points move faster or slower by tol after a
     * sweep (the bodies' velocities: a contact's own can keep changing where two contacts share
     * the work, such as a joint's two edges' frictions, with no effect on any body) */
    const int final = k == cap - 1; /* the largest change is kept from this one */
    worst = 0.0;
    for (int j = 0; j < nbi; j++) {
      const double *v = f->v + 3 * bi[j], *w = f->vs + 3 * bi[j];
      const double d = point_speed(f, bi[j], v[0] - w[0], v[1] - w[1], v[2] - w[2]);
      worst = d > worst ? d : worst;
      if (worst > tol && !final) break; /* another sweep: its size is not needed */
    }
    converged = worst <= tol;
    if (nncg && !converged) nncg_step(f, ci, nci, &rr);
  }
  if (nncg && !converged)
    for (int i = 0; i < nci; i++) {
      vs_fall_contact *c = &f->c[ci[i]];
      const double pn = fmax(c->P[0], 0.0), pt = fmax(-mu * pn, fmin(mu * pn, c->P[1]));
      if (pn == c->P[0] && pt == c->P[1]) continue;
      vs_fall_apply(f, c, pn - c->P[0], pt - c->P[1], f->v);
      c->P[0] = pn, c->P[1] = pt;
    }
  *last = worst;
  return converged ? k : -k;
}

/* The step's impulses for the contacts found: from the free velocity, each contact's law and
 * warm start; when every contact is a joint's, the chain's impulses solved at once
 * (fall_chain.c); otherwise, or if that did not settle, island by island (solve_island) until
 * none of the island's bodies' velocities moves by sweep_tol in a sweep, or max_sweeps (near
 * rest at least VS_FALL_CALM_SWEEPS); the step's sweeps are those of the island that took the
 * most. 0, -1 when out of memory, -2 when the joints' system failed. */
static int impulses(vs_fall *f, double h, double mu, step_out *so) {
  if (islands(f) != 0) return -1;
  const double g = f->g->gravity, r = h / f->h; /* the warm start's impulses to this step */
  memcpy(f->v, f->vk, 3 * (size_t)f->nb * sizeof *f->v);
  for (int b = 0; b < f->n; b++) f->v[3 * b + 1] -= g * h; /* the free velocity */
  for (int i = 0; i < f->nc; i++) {
    vs_fall_contact *c = &f->c[i];
    vs_fall_rel_velocity(c, f->vk, c->u0);
    contact_law(c, h);
    prepare(c, mu);
    warm(f, c->key, r, c->P);
    vs_fall_apply(f, c, c->P[0], c->P[1], f->v);
  }
  const double tol = sweep_tol(f, h, so);
  const int cap = so->calm ? calm_cap(f) : f->o.max_sweeps;
  so->converged = f->nc == 0;
  so->last = 0.0;
  int joints = 0;
  for (int i = 0; i < f->nc; i++) joints += f->c[i].joint >= 0;
  if (f->chain && joints > 0 && joints == f->nc) { /* only joints: the chain at once */
    const int rc = vs_fall_chain_solve(f, mu, tol, &so->solves);
    if (rc < 0) return -2;
    so->converged = so->chain = rc == 0;
  }
  if (so->converged) return 0;
  const int s0 = so->sweeps; /* the sweeps' directions go on from a first solve's */
  int most = 0;
  so->converged = 1;
  for (int s = 0; s < f->nisl; s++) {
    if (f->isl_first[s + 1] == f->isl_first[s]) continue; /* a body in free flight */
    double last;
    const int k = solve_island(f, s, mu, tol, cap, s0, &last);
    most = abs(k) > most ? abs(k) : most;
    if (k < 0) so->converged = 0, so->last = fmax(so->last, last);
  }
  so->sweeps += most;
  return 0;
}

/* Did a body's velocity after the impulses carry it further in the step than its velocity at the
 * start, for which its contacts were looked for, by more than gravity moves it in a step (g h^2:
 * a contact missed by less is caught at the next step with no more overlap than that)? */
static int outran(const vs_fall *f, double h) {
  const double gh2 = f->g->gravity * h * h;
  for (int b = 0; b < f->n; b++) {
    const double *v = f->v + 3 * b;
    const double reach = h * point_speed(f, b, v[0], v[1], v[2]) + 1e-9 * f->rmax;
    if (reach > f->reach[b] + gh2) return 1;
  }
  return 0;
}

/* The overlaps' recovery (split impulse): pseudo-velocities w, which move the positions in this
 * step and are then forgotten, so that pushing a vertex out of the ground or another body gives
 * no body a velocity (a recovery through the velocities, as a bias in the contact law, feeds
 * energy into the debris and can keep blocks rocking on the ground for good). Normal
 * pseudo-impulses only, by Gauss-Seidel as the impulses: a vertex inside the ground or another
 * body (no joint) moves out by VS_FALL_RECOVER of its overlap (w_n >= -VS_FALL_RECOVER gap / h),
 * the other contacts that touch do not close further (w_n >= 0). The work this does against
 * gravity enters the energy balance as the contacts' (the dissipated energy, negative). */
static void recover(vs_fall *f, double h, step_out *so) {
  memset(f->w, 0, 3 * (size_t)f->nb * sizeof *f->w);
  /* nothing to do in an island while every overlap is below what the impulses' own tolerance
   * lets a contact sink in a step (sweep_tol h) */
  const double tol = sweep_tol(f, h, so);
  for (int i = 0; i < f->nc; i++) f->c[i].Pw = 0.0;
  for (int s = 0; s < f->nisl; s++) { /* each island on its own (impulses) */
    const int *ci = f->isl_c + f->isl_first[s], nci = f->isl_first[s + 1] - f->isl_first[s];
    int deep = 0;
    for (int i = 0; i < nci; i++) deep += f->c[ci[i]].gap < -tol * h && f->c[ci[i]].joint < 0;
    if (deep == 0) continue;
    for (int k = 0; k < f->o.max_sweeps; k++) {
      double worst = 0.0;
      for (int i = 0; i < nci; i++) {
        vs_fall_contact *c = &f->c[ci[(k % 2) ? nci - 1 - i : i]];
        if (c->gap > 0.0) continue;
        const double target = c->joint < 0 ? -VS_FALL_RECOVER * c->gap / h : 0.0;
        double un = dot3(c->Ja, f->w + 3 * c->a);
        if (c->b >= 0) un += dot3(c->Jb, f->w + 3 * c->b);
        const double p = fmax(0.0, c->Pw + (target - un) * c->iWnn), dp = p - c->Pw;
        if (dp == 0.0) continue;
        for (int j = 0; j < 3; j++) f->w[3 * c->a + j] += c->Ka[j] * dp;
        if (c->b >= 0)
          for (int j = 0; j < 3; j++) f->w[3 * c->b + j] += c->Kb[j] * dp;
        c->Pw = p;
        worst = fabs(dp) * c->W[0] > worst ? fabs(dp) * c->W[0] : worst;
      }
      if (worst <= tol) break;
    }
  }
  for (int b = 0; b < f->n; b++) /* the work against gravity: m g h w_z */
    so->recovered += h * f->g->gravity * f->w[3 * b + 1] / f->minv[3 * b];
}

/* One step of length h from f->t: contacts at the start, impulses, new positions; if the
 * impulses sped a body up beyond what its contacts were found for (an impact that flings a block
 * into another), the contacts are found again for both velocities and the impulses solved again
 * from those found. 0, -1 when out of memory, -2 when the joints' system failed. */
static int step(vs_fall *f, double h, double mu, step_out *so) {
  supports(f, f->t);
  vs_fall_positions(f);
  memcpy(f->vk, f->v, 3 * (size_t)f->nb * sizeof *f->v);
  if (vs_fall_find_contacts(f, h, NULL) != 0) return -1;
  so->ground = so->body = so->joint = 0.0;
  for (int i = 0; i < f->nc; i++) { /* overlaps at the start */
    const vs_fall_contact *c = &f->c[i];
    if (c->b < 0) so->ground = fmax(so->ground, -c->gap);
    else if (c->joint >= 0) so->joint = fmax(so->joint, -c->gap);
    else so->body = fmax(so->body, -c->gap);
  }
  so->sweeps = so->solves = so->chain = so->redone = 0;
  int rc = impulses(f, h, mu, so);
  if (rc == 0 && outran(f, h)) {
    memcpy(f->vs, f->v, 3 * (size_t)f->nb * sizeof *f->v);
    if (keep(f) != 0) return -1; /* this solve's impulses: the warm start of the next */
    f->h = h;
    memcpy(f->v, f->vk, 3 * (size_t)f->nb * sizeof *f->v);
    if (vs_fall_find_contacts(f, h, f->vs) != 0) return -1;
    so->redone = 1;
    rc = impulses(f, h, mu, so);
  }
  if (rc != 0) return rc;
  /* the work of the impulses over the step, with the mean relative velocity */
  so->normal = so->tangential = so->support = 0.0;
  for (int i = 0; i < f->nc; i++) {
    const vs_fall_contact *c = &f->c[i];
    double u[2];
    vs_fall_rel_velocity(c, f->v, u);
    so->normal -= c->P[0] * 0.5 * (c->u0[0] + u[0]);
    so->tangential -= c->P[1] * 0.5 * (c->u0[1] + u[1]);
    for (int s = 0; s < 2; s++) { /* a pier's share: -P . J_s v_s */
      const int b = s == 0 ? c->a : c->b;
      if (b < f->n) continue;
      const double *J = s == 0 ? c->Ja : c->Jb, *vb = f->v + 3 * b;
      so->support -= c->P[0] * dot3(J, vb) + c->P[1] * dot3(J + 3, vb);
    }
  }
  so->recovered = 0.0;
  recover(f, h, so);
  for (int i = 0; i < 3 * f->n; i++) f->q[i] += h * (f->v[i] + f->w[i]);
  f->t += h;
  f->h = h;
  return keep(f);
}

/* The next step's length: slow_step while no point of a block moves faster than slow_speed
 * (point_speed), else step (always where slow_speed is 0). */
static double next_step(const vs_fall *f) {
  if (!(f->o.slow_step > f->o.step && f->o.slow_speed > 0.0)) return f->o.step;
  for (int b = 0; b < f->n; b++) {
    const double *v = f->v + 3 * b;
    if (point_speed(f, b, v[0], v[1], v[2]) > f->o.slow_speed) return f->o.step;
  }
  return f->o.slow_step;
}

/* --- the run --- */

/* The lower springing base: the lowest end of a face that a pier carries, as it sits now. */
static double springing_base(vs_fall *f) {
  double z = INFINITY;
  for (int j = 0; j < f->g->n_joints; j++)
    for (int s = 0; s < 2; s++) {
      const vs_fall_face *fc = &f->faces[j];
      const int b = s == 0 ? fc->a : fc->b;
      if (b < f->n) continue;
      const double (*e)[2] = s == 0 ? fc->ea : fc->eb;
      const double th = f->q[3 * b + 2];
      for (int k = 0; k < 2; k++)
        z = fmin(z, f->ref[2 * b + 1] + f->q[3 * b + 1] + sin(th) * e[k][0] + cos(th) * e[k][1]);
    }
  return z;
}

typedef struct {
  double kinetic, gravity, support, normal, tangential, ref;
} energy_acc;

static void energy_of(vs_fall *f, const energy_acc *a, vs_energy *e) {
  e->kinetic = kinetic(f);
  e->gravity = vs_model_gravity_energy(f->m, f->q);
  e->elastic = 0.0;
  e->support_work = a->support;
  e->damped = a->normal;
  e->friction = a->tangential;
  e->cracking = 0.0;
  e->balance = e->kinetic + e->gravity + e->elastic - e->support_work + e->damped + e->friction -
               a->ref;
}

/* Hand the state after a step, with its energies e, to the caller's sample function. */
static int sample_now(vs_fall *f, vs_dyn_sample_fn sample, void *user, const vs_energy *e) {
  vs_fall_static_state(f);
  return sample(user, f->t, f->o.rate * f->t, f->qst, f->vst, e);
}

/* The joints' forces at the start as the first step's warm start: per joint edge (its key, as
 * face_contacts makes it) the impulse over a step of the edge's share of N, where the joint is
 * in contact at both edges by the lever rule from M (N/2 -+ M/t at the intrados and extrados,
 * none where that is negative), where it is open at one edge all of it at the other; and the
 * joint's friction, P_t = -T h, on its intrados edge (fall_chain.c: one friction per joint).
 * 0, or -1 when out of memory. */
static int warm_from_joints(vs_fall *f, const vs_joint_state *js, double h) {
  const int nj = f->g->n_joints;
  if (reserve(f, 2 * nj) != 0) return -1;
  for (int j = 0; j < nj; j++) {
    const double N = fmax(js[j].N, 0.0), t = f->faces[j].length;
    double Fi = 0.5 * N - js[j].M / t, Fe = 0.5 * N + js[j].M / t;
    if (Fi < 0.0 || js[j].gap_i > 0.0) Fi = 0.0, Fe = N;
    if (Fe < 0.0 || js[j].gap_e > 0.0) Fe = js[j].gap_i > 0.0 ? 0.0 : N, Fi = N - Fe;
    for (int e = 0; e < 2; e++)
      store(f, -(long long)(2 * j + e) - 1, (e == 0 ? Fi : Fe) * h, e == 0 ? -js[j].T * h : 0.0);
  }
  return 0;
}

/* The state at t0 from qe, ve (the joints' forces js0, if any, as the first step's warm start),
 * the supports driven there and the ground's level. VS_ERR_NOMEM when out of memory. */
static vs_status fall_start(vs_fall *f, double t0, const double *qe, const double *ve,
                            const vs_joint_state *js0, vs_fall_result *res, vs_error *err) {
  const size_t Q = 3 * (size_t)f->nb;
  memcpy(f->q, qe, Q * sizeof *qe);
  memcpy(f->v, ve, Q * sizeof *ve);
  f->t = t0;
  f->h = f->o.step; /* warm_from_joints' impulses are over it */
  f->nc = f->npc = 0; /* no warm start from an earlier run (warm: none while npc is 0) */
  if (js0 != NULL && f->o.joints && warm_from_joints(f, js0, f->o.step) != 0)
    return vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory");
  supports(f, t0);
  f->level = isfinite(f->o.ground) ? springing_base(f) + f->o.ground : NAN;
  res->level = f->level;
  return VS_OK;
}

/* The energies at the start into *e, carried on from e0 (NULL: from zero) in acc, whose
 * reference makes the balance start at e0's. */
static void start_energies(vs_fall *f, const vs_energy *e0, vs_fall_result *res, energy_acc *acc,
                           vs_energy *e) {
  /* the energies carry on from e0: the joints' elastic energy is released into the dissipated
   * energy (rigid contacts store none) */
  if (e0 != NULL) {
    res->released = e0->elastic;
    acc->support = e0->support_work;
    acc->normal = e0->damped + res->released;
    acc->tangential = e0->friction;
  }
  energy_of(f, acc, e);
  acc->ref = e->balance - (e0 != NULL ? e0->balance : 0.0);
}

/* The error of a step that failed (step's rc: -2 the joints' system, else out of memory). */
static vs_status step_error(const vs_fall *f, int rc, vs_error *err) {
  return rc == -2 ? vs_error_set(err, VS_ERR_SOLVER, "fall: the joints' system could not be "
                                 "factorised at t = %.6g s (KLU status %d)", f->t,
                                 f->kc.status)
                  : vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory at t = %.6g s", f->t);
}

/* A step's work and dissipation into acc, its solver counts and contacts into the result. */
static void tally_step(const vs_fall *f, const step_out *so, energy_acc *acc,
                       vs_fall_result *res) {
  acc->normal += so->normal - so->recovered, acc->tangential += so->tangential;
  acc->support += so->support;
  res->steps++;
  res->sweeps += so->sweeps;
  res->solves += so->solves;
  res->chain_steps += so->chain;
  res->redone += so->redone;
  res->calm_steps += so->calm;
  res->recovered += so->recovered;
  if (!so->converged) res->residual = fmax(res->residual, so->last);
  res->unconverged += !so->converged;
  res->contacts += f->nc;
  res->max_contacts = f->nc > res->max_contacts ? f->nc : res->max_contacts;
}

/* The energies after a step into *e, the balance's error (against bal0, relative to the
 * largest term so far, *scale) and the step's overlaps into the result. */
static void check_step(vs_fall *f, const step_out *so, const energy_acc *acc, double bal0,
                       double *scale, vs_energy *e, vs_fall_result *res) {
  energy_of(f, acc, e);
  *scale = fmax(*scale, fmax(fmax(fabs(e->kinetic), fabs(e->gravity)),
                             fmax(fabs(e->support_work), fabs(e->damped) + fabs(e->friction))));
  res->balance_error_rel = fmax(res->balance_error_rel, fabs(e->balance - bal0) / *scale);
  res->max_penetration = fmax(res->max_penetration, so->ground);
  res->max_overlap = fmax(res->max_overlap, so->body);
  res->max_joint_overlap = fmax(res->max_joint_overlap, so->joint);
}

/* The last state's overlaps and penetration into the result, the state back into qe, ve, and
 * where the fall ended. */
static void fall_finish(vs_fall *f, double *qe, double *ve, vs_fall_result *res) {
  const size_t Q = 3 * (size_t)f->nb;
  supports(f, f->t);
  vs_fall_positions(f); /* the last state's overlaps (each step measured its start's) */
  double ob, oj;
  vs_fall_overlaps(f, &ob, &oj);
  res->max_overlap = fmax(res->max_overlap, ob);
  res->max_joint_overlap = fmax(res->max_joint_overlap, oj);
  if (isfinite(f->level))
    res->max_penetration = fmax(res->max_penetration, vs_fall_penetration(f));
  memcpy(qe, f->q, Q * sizeof *qe);
  memcpy(ve, f->v, Q * sizeof *ve);
  res->t_end = f->t;
  res->delta_end = f->o.rate * f->t;
}

vs_status vs_fall_run(vs_fall *f, double t0, double *qe, double *ve, const vs_energy *e0,
                      const vs_joint_state *js0, vs_dyn_sample_fn sample, void *user,
                      vs_fall_result *res, vs_error *err) {
  const double w0 = vs_wall_now(), c0 = vs_cpu_now();
  memset(res, 0, sizeof *res);
  res->step = f->o.step;
  res->slow_step = f->o.slow_step;
  res->cap = f->o.max_sweeps, res->calm_cap = calm_cap(f);
  res->solver = f->o.solver;
  vs_status st = fall_start(f, t0, qe, ve, js0, res, err);
  if (st != VS_OK) return st;
  energy_acc acc = {0};
  vs_energy e;
  start_energies(f, e0, res, &acc, &e);
  const double bal0 = e0 != NULL ? e0->balance : 0.0;
  double scale = fmax(fabs(e.kinetic), fabs(e.gravity));
  const double h = f->o.step, mu = vs_model_law(f->m)->mu, t_end = t0 + f->o.duration;
  double t_sample = t0, t_moving = t0;
  const long max_steps = (long)ceil(f->o.duration / h) + 1;
  for (long k = 0; st == VS_OK && k < max_steps && f->t < t_end - 0.5 * h; k++) {
    if ((f->o.stop != NULL && *f->o.stop) || vs_deadline_passed(f->o.deadline)) {
      st = vs_error_set(err, VS_ERR_INTERRUPTED, "interrupted");
      break;
    }
    /* near rest by the last step's kinetic energy */
    step_out so = {.calm = f->o.calm > 0.0 && e.kinetic < f->o.calm * f->o.rest_ke};
    double hk = next_step(f);
    if (f->t + hk > t_end + 0.5 * h) hk = h; /* no step beyond the end */
    res->slow_steps += hk > h;
    const int rc = step(f, hk, mu, &so);
    if (rc != 0) {
      st = step_error(f, rc, err);
      break;
    }
    tally_step(f, &so, &acc, res);
    check_step(f, &so, &acc, bal0, &scale, &e, res);
    if (e.kinetic >= f->o.rest_ke) t_moving = f->t;
    const int at_rest = f->t - t_moving >= f->o.rest_time;
    const int last = at_rest || f->t >= t_end - 0.5 * h;
    if (sample != NULL && (f->t - t_sample >= f->o.sample_dt * (1.0 - 1e-9) || last)) {
      t_sample = f->t;
      if (sample_now(f, sample, user, &e) != 0)
        st = vs_error_set(err, VS_ERR_STOPPED, "stopped by the caller");
    }
    if (at_rest) {
      res->at_rest = 1;
      break;
    }
  }
  fall_finish(f, qe, ve, res);
  res->wall_s = vs_wall_now() - w0;
  res->cpu_s = vs_cpu_now() - c0;
  return st;
}
