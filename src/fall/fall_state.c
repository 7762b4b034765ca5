/* The fall's state as the record reads it (fall.h): the model's coordinates of the bodies, the
 * joints' forces and states from the step's contact impulses, the piers' reactions, the deepest
 * vertex below the ground. */
#include "voussoir/fall.h"

#include <math.h>
#include <string.h>

#include "fall_internal.h"

void vs_fall_static_state(vs_fall *f) {
  memcpy(f->qst, f->q, 3 * (size_t)f->n * sizeof *f->qst);
  memcpy(f->vst, f->v, 3 * (size_t)f->n * sizeof *f->vst);
  for (int s = 0; s < 2; s++) {
    const int k = vs_model_support_dof(f->m, s);
    if (k >= 0) f->qst[k] = f->q[3 * (f->n + s) + 2], f->vst[k] = 0.0;
  }
}

/* Mean force of contact c over the last step on body b (N), at its point. */
static void force_on(const vs_fall *f, const vs_fall_contact *c, int b, double F[2]) {
  const double sg = (b == c->a ? 1.0 : -1.0) / f->h;
  F[0] = sg * (c->P[0] * c->n[0] + c->P[1] * c->t[0]);
  F[1] = sg * (c->P[0] * c->n[1] + c->P[1] * c->t[1]);
}

const vs_joint_state *vs_fall_joint_states(vs_fall *f) {
  const int nj = f->g->n_joints;
  vs_model_ext_joint_states(f->m, f->q, f->js);
  double *lo = f->jlo, *hi = f->jhi;
  for (int j = 0; j < nj; j++) {
    f->js[j].N = f->js[j].T = f->js[j].M = f->js[j].energy = f->js[j].contact = 0.0;
    lo[j] = INFINITY, hi[j] = -INFINITY;
  }
  for (int i = 0; i < f->nc; i++) {
    const vs_fall_contact *c = &f->c[i];
    if (c->joint < 0 || !(c->P[0] > 0.0)) continue;
    const vs_fall_face *fc = &f->faces[c->joint];
    const double th = 0.5 * (f->q[3 * fc->a + 2] + f->q[3 * fc->b + 2]);
    const double cs = cos(th), sn = sin(th);
    const double nx = cs * fc->na[0] - sn * fc->na[1], nz = sn * fc->na[0] + cs * fc->na[1];
    const double sx = -nz, sz = nx; /* from intrados to extrados */
    double cx = 0.0, cz = 0.0; /* the joint's centre, mean of its two faces' */
    for (int s = 0; s < 2; s++) {
      const int b = s == 0 ? fc->a : fc->b;
      const double (*e)[2] = s == 0 ? fc->ea : fc->eb;
      const double qb = f->q[3 * b + 2], cb = cos(qb), sb = sin(qb);
      const double mx = 0.5 * (e[0][0] + e[1][0]), mz = 0.5 * (e[0][1] + e[1][1]);
      cx += 0.5 * (f->ref[2 * b] + f->q[3 * b] + cb * mx - sb * mz);
      cz += 0.5 * (f->ref[2 * b + 1] + f->q[3 * b + 1] + sb * mx + cb * mz);
    }
    double F[2];
    force_on(f, c, fc->b, F); /* on b: compression pushes it along n, away from a */
    const double N = F[0] * nx + F[1] * nz, eta = (c->px - cx) * sx + (c->pz - cz) * sz;
    vs_joint_state *js = &f->js[c->joint];
    js->N += N;
    js->T -= F[0] * sx + F[1] * sz;
    js->M += N * eta;
    lo[c->joint] = fmin(lo[c->joint], eta), hi[c->joint] = fmax(hi[c->joint], eta);
  }
  for (int j = 0; j < nj; j++)
    if (hi[j] >= lo[j]) f->js[j].contact = fmin(hi[j] - lo[j], f->faces[j].length);
  return f->js;
}

void vs_fall_reactions(const vs_fall *f, double out[6]) {
  memset(out, 0, 6 * sizeof *out);
  for (int i = 0; i < f->nc; i++) {
    const vs_fall_contact *c = &f->c[i];
    for (int s = 0; s < 2; s++) {
      const int sup = s == 0 ? c->a : c->b, other = s == 0 ? c->b : c->a;
      if (sup < f->n || other < 0) continue;
      double F[2];
      force_on(f, c, other, F); /* the pier's force on the block */
      const double rx = c->px - (f->ref[2 * sup] + f->q[3 * sup]);
      const double rz = c->pz - (f->ref[2 * sup + 1] + f->q[3 * sup + 1]);
      double *o = out + 3 * (sup - f->n);
      o[0] += F[0], o[1] += F[1], o[2] += rx * F[1] - rz * F[0];
    }
  }
}

double vs_fall_penetration(vs_fall *f) {
  if (!isfinite(f->level)) return NAN;
  vs_fall_positions(f);
  double worst = -INFINITY;
  for (int k = 0; k < f->nv; k++)
    if (f->body[k] < f->n) worst = fmax(worst, f->level - f->pz[k]);
  return worst;
}
