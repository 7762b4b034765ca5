/* The joints' impulses of a fall step solved together (fall.h), for steps whose contacts are all
 * joint faces: the arch, or parts of it, in the air. Its voussoirs are then a chain, along which
 * Gauss-Seidel passes a force one joint per sweep (a standing arch sagged by 0.3 mm in 50 ms at
 * 30 sweeps a step). Each joint has three unknowns: its two edges' normal impulses and one
 * friction (the face is one line: two frictions, one per edge, would be a pair that W cannot
 * tell apart), bounded by mu times the joint's normal impulse. Every edge is pressed (its normal
 * velocity the contact's bias) or open (no impulse), every joint sticks (no sliding) or slides
 * (its friction mu times its normal impulse, against the sliding); for given statuses the
 * impulses solve one sparse system, W + eps I on the unknowns solved for with a sliding joint's
 * friction column folded into its normal ones, factorised by KLU (the pattern, each joint's
 * three unknowns coupled with the joints that share a moving body, analysed once). The statuses
 * are then corrected and the system solved again until they settle (new_statuses); the step
 * starts from the last step's impulses, so one or two solves usually do. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <klu.h>

#include "fall_internal.h"

/* With both supports fixed and the joints closed the chain is statically indeterminate and W
 * singular: among the impulses that hold it, the solve picks those nearest the ones the step
 * started from (the last step's, at first the elastic joints' forces at the collapse): the
 * system is W + eps I, its right-hand side plus eps times those impulses (a proximal term), eps
 * this multiple of W's largest diagonal entry. */
static const double VS_CHAIN_EPS = 1e-6;


void vs_fall_chain_free(vs_fall *f) {
  if (!f->chain) return;
  klu_free_numeric(&f->Num, &f->kc);
  klu_free_symbolic(&f->Sym, &f->kc);
  free(f->Ap), free(f->Ai), free(f->Ax), free(f->rhs), free(f->sval), free(f->sdiag);
  free(f->sc), free(f->sst), free(f->ssign), free(f->sp0), free(f->vrest), free(f->mask);
  f->chain = 0;
}

/* The joints that share a moving body with joint j, itself included, ascending, into out;
 * returns how many (the arch's: its neighbours). */
static int neighbours(const vs_fall *f, int j, int *out) {
  int n = 0;
  out[n++] = j;
  for (int s = 0; s < 2; s++) {
    const int b = s == 0 ? f->faces[j].a : f->faces[j].b;
    if (!vs_fall_moving(f, b)) continue;
    for (int i = f->adj_first[b]; i < f->adj_first[b + 1]; i++) {
      int k = f->adj_joint[i], seen = 0;
      for (int q = 0; q < n; q++) seen |= out[q] == k;
      if (!seen) out[n++] = k;
    }
  }
  for (int i = 1; i < n; i++)
    for (int q = i; q > 0 && out[q - 1] > out[q]; q--) {
      const int t = out[q];
      out[q] = out[q - 1], out[q - 1] = t;
    }
  return n;
}

/* The pattern (CSC, both triangles): joint j's three unknowns with its own and with every joint
 * it shares a moving body with, the same rows in the same order in each of its three columns
 * (so that a sliding joint's friction column folds into its normal ones entry by entry). 0, or
 * -1 when out of memory. */
static int pattern(vs_fall *f) {
  const int nj = f->g->n_joints;
  int maxdeg = 1;
  for (int b = 0; b < f->nb; b++) maxdeg += f->adj_first[b + 1] - f->adj_first[b];
  int *nb = malloc((size_t)(maxdeg + 1) * sizeof *nb);
  f->Ap = malloc((3 * (size_t)nj + 1) * sizeof *f->Ap);
  if (nb == NULL || f->Ap == NULL) {
    free(nb);
    return -1;
  }
  for (int pass = 0; pass < 2; pass++) {
    size_t p = 0;
    for (int j = 0; j < nj; j++) {
      const int nn = neighbours(f, j, nb);
      for (int c = 0; c < 3; c++) {
        if (pass) f->Ap[3 * j + c] = (int)p;
        for (int i = 0; i < nn; i++)
          for (int r = 0; r < 3; r++, p++)
            if (pass) f->Ai[p] = 3 * nb[i] + r;
      }
    }
    if (pass) {
      f->Ap[3 * nj] = (int)p;
    } else {
      f->Ai = malloc((p + 1) * sizeof *f->Ai);
      f->Ax = calloc(p + 1, sizeof *f->Ax);
      f->sval = calloc(p + 1, sizeof *f->sval);
      if (f->Ai == NULL || f->Ax == NULL || f->sval == NULL) {
        free(nb);
        return -1;
      }
    }
  }
  free(nb);
  return 0;
}

int vs_fall_chain_init(vs_fall *f) {
  const int nj = f->g->n_joints;
  const size_t U = 3 * (size_t)nj, S = 2 * (size_t)nj;
  f->chain = 1;
  klu_defaults(&f->kc);
  f->sc = malloc(S * sizeof *f->sc), f->sst = calloc(S, sizeof *f->sst);
  f->ssign = calloc((size_t)nj, sizeof *f->ssign), f->sp0 = calloc(2 * S, sizeof *f->sp0);
  f->vrest = calloc(3 * (size_t)f->nb, sizeof *f->vrest), f->rhs = calloc(U + 1, sizeof *f->rhs);
  f->mask = calloc(U, 1), f->sdiag = calloc(U, sizeof *f->sdiag);
  if (!f->sc || !f->sst || !f->ssign || !f->sp0 || !f->vrest || !f->rhs || !f->mask ||
      !f->sdiag || pattern(f) != 0)
    return -1;
  f->Sym = klu_analyze(3 * nj, f->Ap, f->Ai, &f->kc);
  return f->Sym != NULL ? 0 : -1;
}

/* Row r (0 normal, 1 tangential) of contact ci times M^-1 times row q of contact cj, over the
 * moving bodies they share. */
static double w_entry(const vs_fall *f, const vs_fall_contact *ci, int r, const vs_fall_contact *cj,
                      int q) {
  double w = 0.0;
  for (int s = 0; s < 2; s++) {
    const int b = s == 0 ? ci->a : ci->b;
    if (!vs_fall_moving(f, b)) continue;
    const double *Ji = (s == 0 ? ci->Ja : ci->Jb) + 3 * r;
    for (int t = 0; t < 2; t++) {
      if ((t == 0 ? cj->a : cj->b) != b) continue;
      const double *Jj = (t == 0 ? cj->Ja : cj->Jb) + 3 * q, *mi = f->minv + 3 * b;
      w += Ji[0] * mi[0] * Jj[0] + Ji[1] * mi[1] * Jj[1] + Ji[2] * mi[2] * Jj[2];
    }
  }
  return w;
}

/* Joint j's friction: carried by its intrados edge's contact, or the extrados one's when alone
 * (both edges' tangential rows are the same, the edges being on one line); -1: neither. */
static int tslot(const vs_fall *f, int j) {
  return f->sc[2 * j] >= 0 ? 2 * j : f->sc[2 * j + 1] >= 0 ? 2 * j + 1 : -1;
}

/* The contact behind unknown u (its normal row for an edge, the joint's friction row), or NULL. */
static const vs_fall_contact *unknown_contact(const vs_fall *f, int u) {
  const int j = u / 3, k = u % 3 < 2 ? 2 * j + u % 3 : tslot(f, j);
  return k >= 0 && f->sc[k] >= 0 ? &f->c[f->sc[k]] : NULL;
}

/* W's values in the pattern into f->sval, its diagonal plus eps into f->sdiag (1 where W has
 * none: an absent edge). */
static void assemble(vs_fall *f) {
  const int nu = 3 * f->g->n_joints;
  double wmax = 0.0;
  for (int u = 0; u < nu; u++) {
    const vs_fall_contact *cu = unknown_contact(f, u);
    f->sdiag[u] = 0.0;
    for (int p = f->Ap[u]; p < f->Ap[u + 1]; p++) {
      const int r = f->Ai[p];
      const vs_fall_contact *cr = unknown_contact(f, r);
      f->sval[p] = (cu == NULL || cr == NULL) ? 0.0 : w_entry(f, cr, r % 3 == 2, cu, u % 3 == 2);
      if (r == u) f->sdiag[u] = f->sval[p];
    }
    wmax = fmax(wmax, f->sdiag[u]);
  }
  f->seps = VS_CHAIN_EPS * wmax;
  for (int u = 0; u < nu; u++) f->sdiag[u] = f->sdiag[u] > 0.0 ? f->sdiag[u] + f->seps : 1.0;
}

/* The system for the current statuses: W + eps I on the unknowns solved for, identity on the
 * held ones (open edges; the friction of a joint that carries nothing or slides), and a sliding
 * joint's friction column, s mu times, added into its normal columns (its friction is s mu
 * times their sum). */
static void system_values(vs_fall *f, double mu) {
  const int nj = f->g->n_joints;
  for (int u = 0; u < 3 * nj; u++)
    for (int p = f->Ap[u]; p < f->Ap[u + 1]; p++) {
      const int r = f->Ai[p];
      f->Ax[p] = r == u ? (f->mask[u] ? 1.0 : f->sdiag[u])
                        : (f->mask[u] || f->mask[r]) ? 0.0 : f->sval[p];
    }
  for (int j = 0; j < nj; j++) {
    if (f->ssign[j] == 0 || !(f->sst[2 * j] || f->sst[2 * j + 1])) continue;
    const int t = 3 * j + 2, len = f->Ap[t + 1] - f->Ap[t];
    const double smu = f->ssign[j] * mu;
    for (int e = 0; e < 2; e++) {
      const int n = 3 * j + e;
      if (f->mask[n]) continue;
      for (int i = 0; i < len; i++) {
        const int r = f->Ai[f->Ap[t] + i];
        if (f->mask[r]) continue;
        f->Ax[f->Ap[n] + i] += smu * (r == t ? f->sdiag[t] : f->sval[f->Ap[t] + i]);
      }
    }
  }
}

/* Solve for the current statuses: pressed edges' normal impulses for their normal velocities
 * bias, a sticking joint's friction for no sliding, a sliding joint's s mu times its normal
 * impulse, open edges' nothing. The impulses into the contacts and f->v = vrest + theirs. 0, or
 * -1 when KLU failed. */
static int solve_statuses(vs_fall *f, double mu) {
  const int nj = f->g->n_joints;
  for (int j = 0; j < nj; j++) {
    const int pressed = tslot(f, j) >= 0 && (f->sst[2 * j] || f->sst[2 * j + 1]);
    f->mask[3 * j] = f->sc[2 * j] < 0 || !f->sst[2 * j];
    f->mask[3 * j + 1] = f->sc[2 * j + 1] < 0 || !f->sst[2 * j + 1];
    f->mask[3 * j + 2] = !pressed || f->ssign[j] != 0;
  }
  for (int u = 0; u < 3 * nj; u++) {
    f->rhs[u] = 0.0;
    if (f->mask[u]) continue;
    const vs_fall_contact *c = unknown_contact(f, u);
    double v[2];
    vs_fall_rel_velocity(c, f->vrest, v);
    /* the proximal term: eps times the impulse the step started from */
    const int j = u / 3, k = u % 3 < 2 ? 2 * j + u % 3 : tslot(f, j);
    const double p0 = f->sp0[2 * k + (u % 3 == 2)];
    f->rhs[u] = (u % 3 < 2 ? c->bias - v[0] : -v[1]) + f->seps * p0;
  }
  system_values(f, mu);
  /* refactorise on the last pivots (half the work); afresh when that fails or its pivots have
   * become poor (reciprocal pivot growth below 1e-8) */
  int ok = f->Num != NULL && klu_refactor(f->Ap, f->Ai, f->Ax, f->Sym, f->Num, &f->kc) &&
           klu_rgrowth(f->Ap, f->Ai, f->Ax, f->Sym, f->Num, &f->kc) && f->kc.rgrowth > 1e-8;
  if (!ok) {
    klu_free_numeric(&f->Num, &f->kc);
    f->Num = klu_factor(f->Ap, f->Ai, f->Ax, f->Sym, &f->kc);
  }
  if (f->Num == NULL || !klu_solve(f->Sym, f->Num, 3 * nj, 1, f->rhs, &f->kc)) return -1;
  const double *x = f->rhs;
  memcpy(f->v, f->vrest, 3 * (size_t)f->nb * sizeof *f->v);
  for (int j = 0; j < nj; j++) {
    const int ts = tslot(f, j);
    const double pn = (f->mask[3 * j] ? 0.0 : x[3 * j]) + (f->mask[3 * j + 1] ? 0.0 : x[3 * j + 1]);
    for (int e = 0; e < 2; e++) {
      const int k = 2 * j + e;
      if (f->sc[k] < 0) continue;
      vs_fall_contact *c = &f->c[f->sc[k]];
      c->P[0] = f->sst[k] ? x[3 * j + e] : 0.0;
      c->P[1] = k != ts ? 0.0 : !f->mask[3 * j + 2] ? x[3 * j + 2]
                : (f->sst[2 * j] || f->sst[2 * j + 1]) ? f->ssign[j] * mu * pn : 0.0;
      vs_fall_apply(f, c, c->P[0], c->P[1], f->v);
    }
  }
  return 0;
}

/* The statuses the last solve calls for; returns how many changed. Every open edge that
 * approaches is pressed at once (contacts that close must act); of the other corrections (a
 * pressed edge pulling, a sticking joint's friction beyond its cone, a sliding one moving along
 * its friction) only the largest, measured as a velocity, is made: making them all at once
 * overshoots (a whole run of edges opens where one hinge forms) and cycles. */
static int new_statuses(vs_fall *f, double mu, double tolv) {
  int changed = 0, which = -1, kind = 0;
  double worst = tolv;
  for (int j = 0; j < f->g->n_joints; j++) {
    const int ts = tslot(f, j);
    if (ts < 0) continue;
    double pn = 0.0;
    for (int e = 0; e < 2; e++) {
      const int k = 2 * j + e;
      if (f->sc[k] < 0) continue;
      const vs_fall_contact *c = &f->c[f->sc[k]];
      double u[2];
      vs_fall_rel_velocity(c, f->v, u);
      if (f->sst[k] && -c->P[0] * f->sdiag[3 * j + e] > worst)
        worst = -c->P[0] * f->sdiag[3 * j + e], which = k, kind = 0;
      else if (!f->sst[k] && u[0] < c->bias - tolv) f->sst[k] = 1, changed++;
      pn += fmax(c->P[0], 0.0);
    }
    const vs_fall_contact *c = &f->c[f->sc[ts]];
    double u[2];
    vs_fall_rel_velocity(c, f->v, u);
    const double over = (fabs(c->P[1]) - mu * pn) * f->sdiag[3 * j + 2];
    if (f->ssign[j] == 0 && over > worst) worst = over, which = j, kind = 1;
    else if (f->ssign[j] != 0 && u[1] * f->ssign[j] > worst)
      worst = u[1] * f->ssign[j], which = j, kind = 2;
  }
  if (which >= 0 && kind == 0) f->sst[which] = 0;
  if (which >= 0 && kind == 1) f->ssign[which] = f->c[f->sc[tslot(f, which)]].P[1] > 0.0 ? 1 : -1;
  if (which >= 0 && kind == 2) f->ssign[which] = 0;
  return changed + (which >= 0);
}

int vs_fall_chain_solve(vs_fall *f, double mu, double tolv, int *solves) {
  const int nj = f->g->n_joints;
  for (int k = 0; k < 2 * nj; k++) f->sc[k] = -1;
  memcpy(f->vrest, f->v, 3 * (size_t)f->nb * sizeof *f->v);
  for (int i = 0; i < f->nc; i++) { /* the edges, their impulses out of the velocities */
    const vs_fall_contact *c = &f->c[i];
    if (c->joint < 0) continue;
    const int k = 2 * c->joint + (int)((-c->key - 1) % 2); /* its edge: face_contacts' key */
    f->sc[k] = i;
    f->sp0[2 * k] = c->P[0], f->sp0[2 * k + 1] = c->P[1];
    vs_fall_apply(f, c, -c->P[0], -c->P[1], f->vrest);
  }
  /* statuses from the impulses held: an edge is pressed if it carries or approaches; a joint
   * slides if its friction is on its cone's edge */
  int any = 0;
  for (int j = 0; j < nj; j++) {
    double T = 0.0, pn = 0.0;
    for (int e = 0; e < 2; e++) {
      const int k = 2 * j + e;
      f->sst[k] = 0;
      if (f->sc[k] < 0) continue;
      const vs_fall_contact *c = &f->c[f->sc[k]];
      double u[2];
      vs_fall_rel_velocity(c, f->v, u);
      /* an edge with a gap starts open even if it approaches: as a rigid chain holds it, its
       * closing would be an inconsistent demand (the solve then presses it if it must) */
      f->sst[k] = c->P[0] > 0.0 || (c->gap <= 0.0 && u[0] < c->bias - tolv);
      pn += fmax(c->P[0], 0.0);
      T += c->P[1];
      any |= f->sst[k];
    }
    f->ssign[j] = pn > 0.0 && fabs(T) >= mu * pn ? (T > 0.0 ? 1 : -1) : 0;
  }
  if (!any) return 0;
  assemble(f);
  for (int it = 0; it < VS_FALL_CHAIN_SOLVES; it++) {
    if (solve_statuses(f, mu) != 0) return -1;
    ++*solves;
    if (new_statuses(f, mu, tolv) == 0) return 0;
  }
  /* not settled: back to the impulses it started from, for the sweeps that follow */
  memcpy(f->v, f->vrest, 3 * (size_t)f->nb * sizeof *f->v);
  for (int k = 0; k < 2 * nj; k++) {
    if (f->sc[k] < 0) continue;
    vs_fall_contact *c = &f->c[f->sc[k]];
    c->P[0] = f->sp0[2 * k], c->P[1] = f->sp0[2 * k + 1];
    vs_fall_apply(f, c, c->P[0], c->P[1], f->v);
  }
  return 1;
}
