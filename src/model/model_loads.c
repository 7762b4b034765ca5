/* External forces on the blocks (model.h, "external loads"): a list of dead forces, each fixed
 * in size and direction and applied at a material point of its block, scaled by the load factor
 * lambda. The live load of a load path (issue 28) is one; a fill's dead load can be another.
 * They enter the residual as generalised forces (Fx, Fz, moment about the moving centroid), the
 * Jacobian through the moment's dependence on the block's rotation, the potential energy as
 * -lambda f . u of each force's point. */
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Check and copy n forces into *dst (freed first), *nd their count. */
static vs_status copy_forces(const vs_model *m, const char *what, const vs_model_force *f, int n,
                             vs_model_force **dst, int *nd, vs_error *err) {
  if (n < 0 || (n > 0 && f == NULL))
    return vs_error_set(err, VS_ERR_INVALID, "model: %d %s (allowed: >= 0, given)", n, what);
  for (int i = 0; i < n; i++) {
    if (f[i].block < 0 || f[i].block >= m->g->n_blocks)
      return vs_error_set(err, VS_ERR_INVALID, "model: %s %d on block %d (allowed: 0..%d)", what,
                          i, f[i].block, m->g->n_blocks - 1);
    if (!(isfinite(f[i].fx) && isfinite(f[i].fz) && isfinite(f[i].px) && isfinite(f[i].pz)))
      return vs_error_set(err, VS_ERR_INVALID, "model: %s %d is not finite", what, i);
  }
  vs_model_force *copy = NULL;
  if (n > 0) {
    copy = malloc((size_t)n * sizeof *copy);
    if (copy == NULL) return vs_error_set(err, VS_ERR_NOMEM, "model: out of memory");
    memcpy(copy, f, (size_t)n * sizeof *copy);
  }
  free(*dst);
  *dst = copy;
  *nd = n;
  return VS_OK;
}

vs_status vs_model_set_loads(vs_model *m, const vs_model_force *f, int n, vs_error *err) {
  return copy_forces(m, "loads", f, n, &m->loads, &m->n_loads, err);
}

vs_status vs_model_set_dead_loads(vs_model *m, const vs_model_force *f, int n, vs_error *err) {
  return copy_forces(m, "dead loads", f, n, &m->dead, &m->n_dead, err);
}

int vs_model_load_count(const vs_model *m) { return m->n_loads; }
void vs_model_set_load_factor(vs_model *m, double lambda) { m->lscale = lambda; }
double vs_model_load_factor(const vs_model *m) { return m->lscale; }

/* Force i's arm from its block's centroid at the block's rotation in q: R(theta) (p - c). */
static void load_arm(const vs_model *m, const vs_model_force *f, const double *q, double r[2]) {
  const vs_block *b = &m->g->blocks[f->block];
  const double th = q[3 * f->block + 2], c = cos(th), s = sin(th);
  const double x = f->px - b->cx, z = f->pz - b->cz;
  r[0] = c * x - s * z;
  r[1] = s * x + c * z;
}

void vs_model_load_vector(const vs_model *m, const double *q, double *out) {
  memset(out, 0, (size_t)m->n * sizeof *out);
  for (int i = 0; i < m->n_loads; i++) {
    const vs_model_force *f = &m->loads[i];
    double r[2];
    load_arm(m, f, q, r);
    double *o = out + 3 * f->block;
    o[0] += f->fx;
    o[1] += f->fz;
    o[2] += r[0] * f->fz - r[1] * f->fx;
  }
}

double vs_model_load_size(const vs_model *m) {
  double size = 0.0;
  for (int i = 0; i < m->n_loads; i++) size += hypot(m->loads[i].fx, m->loads[i].fz);
  return size;
}

/* Forces f[0..n) times lam over pattern p (blocks are slots 0..n_blocks-1): G -= lam f(q);
 * K(theta, theta) += lam (f . r) (d/dtheta of the moment r x f is -f . r). */
static void add_forces(const vs_model *m, const vs_pattern *p, const vs_model_force *fs, int n,
                       double lam, const double *q, double *G, double *kdata) {
  for (int i = 0; i < n; i++) {
    const vs_model_force *f = &fs[i];
    double r[2];
    load_arm(m, f, q, r);
    const int *d = p->dof + 3 * f->block;
    if (G != NULL) {
      G[d[0]] -= lam * f->fx;
      G[d[1]] -= lam * f->fz;
      G[d[2]] -= lam * (r[0] * f->fz - r[1] * f->fx);
    }
    if (kdata != NULL) kdata[vs_model_csc_pos(p, d[2], d[2])] += lam * (f->fx * r[0] + f->fz * r[1]);
  }
}

/* The loads' part of the residual and Jacobian: the dead loads, and the live ones times the
 * load factor. */
void vs_model_loads_add(const vs_model *m, const vs_pattern *p, const double *q, double *G,
                        double *kdata) {
  if (m->n_dead > 0) add_forces(m, p, m->dead, m->n_dead, 1.0, q, G, kdata);
  if (m->n_loads > 0 && m->lscale != 0.0)
    add_forces(m, p, m->loads, m->n_loads, m->lscale, q, G, kdata);
}

/* The work of forces f[0..n) on their points' displacements at q (J). */
static double forces_work(const vs_model *m, const vs_model_force *fs, int n, const double *q) {
  double work = 0.0;
  for (int i = 0; i < n; i++) {
    const vs_model_force *f = &fs[i];
    const vs_block *b = &m->g->blocks[f->block];
    double r[2];
    load_arm(m, f, q, r);
    const double ux = q[3 * f->block] + r[0] - (f->px - b->cx);
    const double uz = q[3 * f->block + 1] + r[1] - (f->pz - b->cz);
    work += f->fx * ux + f->fz * uz;
  }
  return work;
}

double vs_model_load_energy(const vs_model *m, const double *q) {
  double e = 0.0;
  if (m->n_dead > 0) e -= forces_work(m, m->dead, m->n_dead, q);
  if (m->n_loads > 0 && m->lscale != 0.0) e -= m->lscale * forces_work(m, m->loads, m->n_loads, q);
  return e;
}

double vs_model_load_displacement(const vs_model *m, const double *q) {
  const double size = vs_model_load_size(m);
  return size > 0.0 ? forces_work(m, m->loads, m->n_loads, q) / size : 0.0;
}
