/* The limit analysis of a run's definition (limit.h): the live load placed on the arch, the load
 * factor, the least and greatest thrust under self-weight, and the thickness factor at which the
 * arch just stands (bisection on arch.thickness, the arch rebuilt for every trial). */
#include "voussoir/limit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/imperfections.h"
#include "limit_internal.h"
#include "voussoir/units.h"
#include "wall_clock.h"

/* ---------------------------------------------------------------------------------------------
 * The live load */

/* Each block's extrados as seen from above: the horizontal extent of its joints' extrados ends
 * (xa < xb) and their heights. */
typedef struct {
  double xa, za, xb, zb;
} extent;

static void extrados_extents(const vs_geometry *g, extent *ex) {
  for (int i = 0; i < g->n_blocks; i++) ex[i] = (extent){INFINITY, 0.0, -INFINITY, 0.0};
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double x = j->px + 0.5 * j->length * sx, z = j->pz + 0.5 * j->length * sz;
    const int bodies[2] = {j->a, j->b};
    for (int s = 0; s < 2; s++) {
      if (bodies[s] < 0) continue;
      extent *e = &ex[bodies[s]];
      if (x < e->xa) e->xa = x, e->za = z;
      if (x > e->xb) e->xb = x, e->zb = z;
    }
  }
}

/* The extrados' height at x over block extent e (on the chord: a vertical load's line of action
 * does not depend on it). */
static double extrados_z(const extent *e, double x) {
  const double w = e->xb - e->xa;
  return w > 0.0 ? e->za + (x - e->xa) / w * (e->zb - e->za) : e->za;
}

/* x of the left springing's intrados point: the intrados end of the left support's joint. */
static vs_status springing_x(const vs_geometry *g, double *x0, vs_error *err) {
  for (int k = 0; k < g->n_joints; k++) {
    const vs_joint_geom *j = &g->joints[k];
    if (j->a != VS_SUPPORT_LEFT && j->b != VS_SUPPORT_LEFT) continue;
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    *x0 = j->px - 0.5 * j->length * sx;
    return VS_OK;
  }
  return vs_error_set(err, VS_ERR_INVALID,
                      "load: the assembly has no left support, from which load.x_mm is measured");
}

static void span_of(const extent *ex, int n, double *lo, double *hi) {
  *lo = INFINITY, *hi = -INFINITY;
  for (int i = 0; i < n; i++) *lo = fmin(*lo, ex[i].xa), *hi = fmax(*hi, ex[i].xb);
}

/* point and line: value down on the block under x. */
static vs_status place_point(const vs_geometry *g, const extent *ex, double x0, const vs_load_def *ld,
                             vs_limit_force *f, vs_error *err) {
  const double x = x0 + ld->x;
  for (int i = 0; i < g->n_blocks; i++)
    if (ex[i].xa <= x && x <= ex[i].xb) {
      *f = (vs_limit_force){i, 0.0, -ld->value, x, extrados_z(&ex[i], x)};
      return VS_OK;
    }
  double lo, hi;
  span_of(ex, g->n_blocks, &lo, &hi);
  return vs_error_set(err, VS_ERR_INVALID,
                      "load.x_mm = %g: not over the arch's extrados (allowed: [%g, %g] mm from "
                      "the left springing's intrados point)",
                      ld->x / VS_MM, (lo - x0) / VS_MM, (hi - x0) / VS_MM);
}

/* patch: value spread uniformly over [x - width/2, x + width/2]; each block's share at the middle
 * of its part (the resultant of a uniform load). *n forces written. */
static vs_status place_patch(const vs_geometry *g, const extent *ex, double x0, const vs_load_def *ld,
                             vs_limit_force *f, int *n, vs_error *err) {
  if (!(ld->width > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.width_mm = %g: a patch load needs a width (allowed: > 0 mm)",
                        ld->width / VS_MM);
  const double a = x0 + ld->x - 0.5 * ld->width, b = a + ld->width;
  double lo, hi;
  span_of(ex, g->n_blocks, &lo, &hi);
  if (a < lo || b > hi)
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.x_mm = %g, load.width_mm = %g: the patch reaches beyond the arch's "
                        "extrados (allowed: within [%g, %g] mm from the left springing's intrados "
                        "point)",
                        ld->x / VS_MM, ld->width / VS_MM, (lo - x0) / VS_MM, (hi - x0) / VS_MM);
  *n = 0;
  for (int i = 0; i < g->n_blocks; i++) {
    const double ca = fmax(a, ex[i].xa), cb = fmin(b, ex[i].xb);
    if (!(cb > ca)) continue;
    const double xm = 0.5 * (ca + cb);
    f[(*n)++] = (vs_limit_force){i, 0.0, -ld->value * (cb - ca) / ld->width, xm,
                                 extrados_z(&ex[i], xm)};
  }
  return VS_OK;
}

/* The height of the fill's surface over geometry g: level above the highest extrados chord end. */
static double fill_surface(const vs_geometry *g, const extent *ex, double level) {
  double top = -INFINITY;
  for (int i = 0; i < g->n_blocks; i++) top = fmax(top, fmax(ex[i].za, ex[i].zb));
  return top + level;
}

vs_status vs_limit_fill_load(const vs_geometry *g, const vs_fill_def *fd, vs_limit_force **out,
                             int *n, vs_error *err) {
  *out = NULL;
  *n = 0;
  if (!(isfinite(fd->unit_weight) && fd->unit_weight >= 0.0 && isfinite(fd->level) &&
        fd->level >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "fill.unit_weight_kN_m3 = %g, fill.level_mm = %g (allowed: >= 0, finite)",
                        fd->unit_weight / 1e3, fd->level / VS_MM);
  if (!(isfinite(fd->k_horizontal) && fd->k_horizontal >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "fill.k_horizontal = %g (allowed: >= 0, finite)",
                        fd->k_horizontal);
  if (fd->unit_weight == 0.0 || g->n_blocks == 0) return VS_OK;
  vs_limit_force *f = malloc(2 * (size_t)g->n_blocks * sizeof *f);
  extent *ex = malloc((size_t)g->n_blocks * sizeof *ex);
  if (f == NULL || ex == NULL) {
    free(f), free(ex);
    return vs_error_set(err, VS_ERR_NOMEM, "fill: out of memory");
  }
  extrados_extents(g, ex);
  const double surface = fill_surface(g, ex, fd->level), depth = g->joints[0].depth;
  for (int i = 0; i < g->n_blocks; i++) {
    const double w = ex[i].xb - ex[i].xa, ha = surface - ex[i].za, hb = surface - ex[i].zb;
    const double area = 0.5 * w * (ha + hb); /* the trapezoid over the chord */
    if (!(w > 0.0 && area > 0.0)) continue;
    const double xc = ex[i].xa + w * (ha + 2.0 * hb) / (3.0 * (ha + hb));
    f[(*n)++] = (vs_limit_force){i, 0.0, -fd->unit_weight * depth * area, xc,
                                 extrados_z(&ex[i], xc)};
  }
  /* the horizontal pressure k gamma h on the chord's vertical projection, inward: where the
   * chord rises to the right (the left haunch) toward +x, where it falls toward -x; its
   * resultant k gamma depth (zb - za)(ha + hb) / 2 at the pressure trapezoid's centroid height,
   * on the chord */
  for (int i = 0; i < g->n_blocks && fd->k_horizontal > 0.0; i++) {
    const double dz = ex[i].zb - ex[i].za, ha = surface - ex[i].za, hb = surface - ex[i].zb;
    if (!(ex[i].xb > ex[i].xa && fabs(dz) > 1e-12 * (ex[i].xb - ex[i].xa) && ha + hb > 0.0))
      continue;
    const double zc = ex[i].za + dz * (ha + 2.0 * hb) / (3.0 * (ha + hb));
    const double xc = ex[i].xa + (zc - ex[i].za) / dz * (ex[i].xb - ex[i].xa);
    f[(*n)++] = (vs_limit_force){
        i, fd->k_horizontal * fd->unit_weight * depth * dz * 0.5 * (ha + hb), 0.0, xc, zc};
  }
  free(ex);
  *out = f;
  return VS_OK;
}

/* A point, line or patch load spread through the fill: uniform over [x - w/2, x + w/2] on the
 * extrados, w = width + 2 h tan(spread), h the fill's depth over the extrados at x (surface at
 * fd->level above the crown's extrados); the part of w beyond the arch's extrados goes into the
 * ground beside it. *n forces written. */
static vs_status place_spread(const vs_geometry *g, const extent *ex, double x0,
                              const vs_load_def *ld, const vs_fill_def *fd, vs_limit_force *f,
                              int *n, vs_error *err) {
  if (ld->kind == VS_LOAD_PATCH && !(ld->width > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.width_mm = %g: a patch load needs a width (allowed: > 0 mm)",
                        ld->width / VS_MM);
  const double x = x0 + ld->x;
  int at = -1;
  for (int i = 0; i < g->n_blocks && at < 0; i++)
    if (ex[i].xa <= x && x <= ex[i].xb) at = i;
  double lo, hi;
  span_of(ex, g->n_blocks, &lo, &hi);
  if (at < 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.x_mm = %g: not over the arch's extrados (allowed: [%g, %g] mm from "
                        "the left springing's intrados point)",
                        ld->x / VS_MM, (lo - x0) / VS_MM, (hi - x0) / VS_MM);
  const double h = fmax(0.0, fill_surface(g, ex, fd->level) - extrados_z(&ex[at], x));
  const double w = (ld->kind == VS_LOAD_PATCH ? ld->width : 0.0) + 2.0 * h * tan(ld->spread);
  if (!(w > 0.0)) { /* no depth: the load as given */
    *n = 1;
    return ld->kind == VS_LOAD_PATCH ? place_patch(g, ex, x0, ld, f, n, err)
                                     : place_point(g, ex, x0, ld, f, err);
  }
  const double a = x - 0.5 * w, b = x + 0.5 * w;
  *n = 0;
  for (int i = 0; i < g->n_blocks; i++) {
    const double ca = fmax(a, ex[i].xa), cb = fmin(b, ex[i].xb);
    if (!(cb > ca)) continue;
    const double xm = 0.5 * (ca + cb);
    f[(*n)++] = (vs_limit_force){i, 0.0, -ld->value * (cb - ca) / w, xm, extrados_z(&ex[i], xm)};
  }
  return VS_OK;
}

vs_status vs_limit_live_load(const vs_geometry *g, const vs_load_def *ld, const vs_fill_def *fd,
                             vs_limit_force **out, int *n, vs_error *err) {
  *out = NULL;
  *n = 0;
  if (ld->kind == VS_LOAD_NONE) return VS_OK;
  if (ld->kind < 0 || ld->kind >= VS_LOAD_KIND_COUNT)
    return vs_error_set(err, VS_ERR_INVALID, "load.kind = %d (allowed: 0..%d)", (int)ld->kind,
                        VS_LOAD_KIND_COUNT - 1);
  if (ld->kind != VS_LOAD_TILT && !(ld->value > 0.0 && isfinite(ld->value)))
    return vs_error_set(err, VS_ERR_INVALID, "load.value_N = %g (allowed: > 0 N)", ld->value);
  if (!(ld->spread >= 0.0 && ld->spread <= 80.0 * VS_DEG))
    return vs_error_set(err, VS_ERR_INVALID, "load.spread_deg = %g (allowed: [0, 80] deg)",
                        ld->spread / VS_DEG);
  const vs_fill_def none = {0};
  if (fd == NULL) fd = &none;
  if (ld->spread > 0.0 && !(isfinite(fd->level) && fd->level >= 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "fill.level_mm = %g (allowed: >= 0, finite)",
                        fd->level / VS_MM);
  vs_limit_force *f = malloc((size_t)g->n_blocks * sizeof *f);
  extent *ex = malloc((size_t)g->n_blocks * sizeof *ex);
  vs_status st = VS_OK;
  if (f == NULL || ex == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "load: out of memory");
  double x0 = 0.0;
  if (st == VS_OK && ld->kind != VS_LOAD_TILT) {
    extrados_extents(g, ex);
    st = springing_x(g, &x0, err);
  }
  const int spread = ld->kind != VS_LOAD_TILT && ld->spread > 0.0;
  if (st == VS_OK && spread) st = place_spread(g, ex, x0, ld, fd, f, n, err);
  else if (st == VS_OK) switch (ld->kind) {
    case VS_LOAD_POINT:
    case VS_LOAD_LINE: /* a knife-edge across the barrel: in the plane, a point load */
      st = place_point(g, ex, x0, ld, f, err);
      *n = 1;
      break;
    case VS_LOAD_PATCH: st = place_patch(g, ex, x0, ld, f, n, err); break;
    default: /* tilt: lambda x the weight, horizontal, at the centroid */
      for (int i = 0; i < g->n_blocks; i++) {
        const vs_block *b = &g->blocks[i];
        f[i] = (vs_limit_force){i, b->mass * g->gravity, 0.0, b->cx, b->cz};
      }
      *n = g->n_blocks;
      break;
    }
  free(ex);
  if (st != VS_OK) {
    free(f);
    *n = 0;
    return st;
  }
  *out = f;
  return VS_OK;
}

/* ---------------------------------------------------------------------------------------------
 * A deformed configuration (vs_limit_analyse_moved) */

/* Every body's rigid motion: block i by q[3i..3i+2] (its displacement and rotation) about ref's
 * centroid i; a support (s 0 left, 1 right) by qs[3s..3s+2] about the centre, in ref, of the
 * joint it carries (as the model's kinematics: a support's face turns about its joint's centre). */
typedef struct {
  const vs_geometry *ref;
  const double *q, *qs;
  double *seg; /* per joint, the part of its face in contact: [eta0, eta1], fractions from the
                  intrados end (malloc'd; [0, 1] where closed) */
} pose;

/* Point (x, z) of body `body` (through joint k when a support) at p's motion. */
static void pose_point(const pose *p, int body, int k, double x, double z, double *ox,
                       double *oz) {
  double c0x, c0z;
  const double *u;
  if (body >= 0) {
    c0x = p->ref->blocks[body].cx, c0z = p->ref->blocks[body].cz;
    u = p->q + 3 * body;
  } else {
    c0x = p->ref->joints[k].px, c0z = p->ref->joints[k].pz;
    u = p->qs + (body == VS_SUPPORT_RIGHT ? 3 : 0);
  }
  const double c = cos(u[2]), s = sin(u[2]), dx = x - c0x, dz = z - c0z;
  *ox = c0x + u[0] + c * dx - s * dz;
  *oz = c0z + u[1] + s * dx + c * dz;
}

static double pose_angle(const pose *p, int body) {
  return body >= 0 ? p->q[3 * body + 2] : p->qs[body == VS_SUPPORT_RIGHT ? 5 : 2];
}

/* g (ref's blocks and joints, of any thickness) moved: each block with its motion; each joint's
 * centre the mean of where its two bodies carry it, its normal turned by their mean rotation
 * (the model's joint frame), its length kept. */
static void move_geometry(const pose *p, vs_geometry *g) {
  for (int i = 0; i < g->n_blocks; i++) {
    vs_block *b = &g->blocks[i];
    pose_point(p, i, -1, b->cx, b->cz, &b->cx, &b->cz);
  }
  for (int k = 0; k < g->n_joints; k++) {
    vs_joint_geom *j = &g->joints[k];
    double ax, az, bx, bz;
    pose_point(p, j->a, k, j->px, j->pz, &ax, &az);
    pose_point(p, j->b, k, j->px, j->pz, &bx, &bz);
    const double th = 0.5 * (pose_angle(p, j->a) + pose_angle(p, j->b));
    const double c = cos(th), s = sin(th), nx = j->nx, nz = j->nz;
    j->px = 0.5 * (ax + bx), j->pz = 0.5 * (az + bz);
    j->nx = c * nx - s * nz, j->nz = s * nx + c * nz;
  }
}

/* Each joint of g (moved) cut to the part of its face in contact, p->seg (a pinned support's
 * joint kept whole: it carries its resultant at its centre). */
static void cut_joints(const pose *p, vs_limit_opts o, vs_geometry *g) {
  for (int k = 0; k < g->n_joints; k++) {
    vs_joint_geom *j = &g->joints[k];
    const double e0 = p->seg[2 * k], e1 = p->seg[2 * k + 1];
    const int pinned = (j->a == VS_SUPPORT_LEFT || j->b == VS_SUPPORT_LEFT)
                           ? o.left_kind == VS_SUPPORT_PINNED
                           : (j->a == VS_SUPPORT_RIGHT || j->b == VS_SUPPORT_RIGHT) &&
                                 o.right_kind == VS_SUPPORT_PINNED;
    if (pinned || (e0 <= 0.0 && e1 >= 1.0)) continue;
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double shift = (0.5 * (e0 + e1) - 0.5) * j->length;
    j->px += shift * sx, j->pz += shift * sz;
    j->length *= e1 - e0;
  }
}

/* The part of each joint's face in contact, from its openings at the ends gap[2k] (intrados),
 * gap[2k + 1] (extrados), m (affine along it): where the opening is at most `open` (the hinges'
 * threshold, hinges.open_mm), at least VS_LIMIT_CONTACT_MIN of the face at the less open end
 * (a joint open all along keeps that much there). */
static const double VS_LIMIT_CONTACT_MIN = 1e-6;
static void contact_segments(const double *gap, int nj, double open, double *seg) {
  for (int k = 0; k < nj; k++) {
    const double gi = gap[2 * k], ge = gap[2 * k + 1];
    double e0 = 0.0, e1 = 1.0;
    if (gi > open && ge > open) { /* open all along: a sliver at the less open end */
      e0 = gi <= ge ? 0.0 : 1.0 - VS_LIMIT_CONTACT_MIN;
      e1 = e0 + VS_LIMIT_CONTACT_MIN;
    } else if (ge > open) { /* open at the extrados: in contact from the intrados */
      e1 = fmax((open - gi) / (ge - gi), VS_LIMIT_CONTACT_MIN);
    } else if (gi > open) {
      e0 = fmin(1.0 - (open - ge) / (gi - ge), 1.0 - VS_LIMIT_CONTACT_MIN);
    }
    seg[2 * k] = e0, seg[2 * k + 1] = e1;
  }
}

/* A solution on the cut joints as one on the whole faces: eta from the intrados end of the face,
 * the touches where that is within opts.touch of an edge of the face. */
static void uncut_solution(const pose *p, double touch, vs_limit_solution *s) {
  if (s->eta == NULL) return;
  s->n_touch = 0;
  for (int k = 0; k < s->n_joints; k++) {
    const double e0 = p->seg[2 * k], e1 = p->seg[2 * k + 1];
    if (isfinite(s->eta[k])) s->eta[k] = e0 + s->eta[k] * (e1 - e0);
    if (s->touch[k] == 'O') continue;
    s->touch[k] = 0;
    if (s->eta[k] <= touch) s->touch[k] = 'I';
    else if (s->eta[k] >= 1.0 - touch) s->touch[k] = 'E';
    s->n_touch += s->touch[k] != 0;
  }
}

/* Forces fixed to their blocks (a live load, the fill): each point moved with its block, its
 * direction kept (the model's loads: vs_model_set_loads). */
static void move_forces(const pose *p, vs_limit_force *f, int n) {
  for (int i = 0; i < n; i++) pose_point(p, f[i].block, -1, f[i].px, f[i].pz, &f[i].px, &f[i].pz);
}

/* g may take p's motions: the same blocks and joints between the same bodies as p->ref. */
static vs_status pose_fits(const pose *p, const vs_geometry *g, vs_error *err) {
  int same = g->n_blocks == p->ref->n_blocks && g->n_joints == p->ref->n_joints;
  for (int k = 0; same && k < g->n_joints; k++)
    same = g->joints[k].a == p->ref->joints[k].a && g->joints[k].b == p->ref->joints[k].b;
  return same ? VS_OK
              : vs_error_set(err, VS_ERR_INVALID,
                             "limit: the deformed configuration's geometry (%d blocks, %d joints) "
                             "is not the definition's arch (%d blocks, %d joints)",
                             p->ref->n_blocks, p->ref->n_joints, g->n_blocks, g->n_joints);
}

/* ---------------------------------------------------------------------------------------------
 * The analysis */

/* The arch of d with its thickness scaled by factor, its imperfections drawn for that arch. */
static vs_status arch_scaled(const vs_run_def *d, double factor, vs_geometry **g, vs_error *err) {
  vs_arch_def a = d->arch;
  a.thickness *= factor;
  vs_imperfections *imp = NULL;
  vs_status st = vs_imperfections_draw(&d->imperfections, &a, &imp, err);
  if (st == VS_OK) st = vs_imperfections_arch(&d->imperfections, &a, imp, g, err);
  vs_imperfections_destroy(&imp);
  return st;
}

/* The LP of geometry g (moved by p in place, when given) with d's fill as dead load and live[0 ..
 * n_live) as its live load (moved with their blocks), both placed on g as built. */
static vs_status lp_of(const vs_run_def *d, vs_geometry *g, const pose *p, vs_limit_force *live,
                       int n_live, const vs_limit_opts *o, vs_limit **l, vs_error *err) {
  vs_limit_force *fill = NULL;
  int n_fill = 0;
  vs_status st = vs_limit_fill_load(g, &d->fill, &fill, &n_fill, err);
  if (st == VS_OK && p != NULL) st = pose_fits(p, g, err);
  if (st == VS_OK && p != NULL) {
    move_forces(p, fill, n_fill);
    move_forces(p, live, n_live);
    move_geometry(p, g);
    cut_joints(p, *o, g);
  }
  if (st == VS_OK) st = vs_limit_create(g, o, live, n_live, l, err);
  if (st == VS_OK && n_fill > 0) st = vs_limit_add_dead(*l, fill, n_fill, err);
  free(fill);
  return st;
}

/* The trials of the bisection: the options, and the basis of the last trial's LP, from which
 * the next starts (malloc'd at the first trial; every trial's LP has the same rows, columns). */
typedef struct {
  const vs_run_def *d;
  const vs_limit_opts *o;
  const pose *pose; /* a deformed configuration's motions, or NULL */
  unsigned char *basis;
  int unbuildable; /* a thicker ring's springing face no longer fits its piers' width */
  int inexact;     /* trials taken as not standing: CLP's optimum not accurate enough */
} trials;

/* One trial of stands: from the last trial's basis (warm) or from scratch. */
static vs_status stands_once(trials *t, double factor, int warm, int *ok, vs_limit_solution *s,
                             vs_error *err) {
  vs_geometry *g = NULL;
  vs_limit *l = NULL;
  vs_status st = arch_scaled(t->d, factor, &g, err);
  if (st == VS_ERR_INVALID && factor > 1.0 && t->d->arch.piers.height > 0.0) {
    /* thickened beyond what its piers carry (docs/model.md, "Piers"): the search ends there */
    t->unbuildable = 1;
    *ok = 0;
    vs_error_clear(err);
    return VS_OK;
  }
  if (st == VS_OK) st = lp_of(t->d, g, t->pose, NULL, 0, t->o, &l, err);
  if (st == VS_OK && warm && t->basis != NULL) vs_limit_basis_start(l, t->basis);
  if (st == VS_OK) st = vs_limit_solve(l, VS_LIMIT_THRUST_MIN, s, err);
  if (st == VS_OK && t->basis == NULL && (t->basis = malloc(vs_limit_basis_size(l))) == NULL)
    st = vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  if (st == VS_OK) vs_limit_basis_save(l, t->basis);
  *ok = st == VS_OK && s->outcome != VS_LIMIT_INFEASIBLE;
  vs_limit_destroy(&l);
  vs_geometry_destroy(&g);
  return st;
}

/* Does the arch of t->d with thickness x factor stand under its weight? *s: its least thrust.
 * A warm start that CLP leaves inaccurate (near the critical thickness of a deformed arch, whose
 * hinges' faces are cut short) is solved again from scratch; a trial whose optimum still violates
 * equilibrium by more than the LP's tolerance (VS_LIMIT_FEASIBLE of the weight) has no admissible
 * thrust line that the solve can show: it does not stand. */
static vs_status stands(trials *t, double factor, int *ok, vs_limit_solution *s, vs_error *err) {
  vs_status st = stands_once(t, factor, 1, ok, s, err);
  if (st == VS_ERR_SOLVER && t->basis != NULL) {
    vs_error_clear(err);
    st = stands_once(t, factor, 0, ok, s, err);
  }
  if (st == VS_ERR_SOLVER && t->pose != NULL && strstr(err->msg, "violates") != NULL) {
    vs_error_clear(err);
    *ok = 0;
    t->inexact++;
    return VS_OK;
  }
  return st;
}

static void swap_solutions(vs_limit_solution *a, vs_limit_solution *b) {
  const vs_limit_solution t = *a;
  *a = *b;
  *b = t;
}

/* The touches of s within tol of an edge (a fraction of the joint's length): at the upper end
 * of the bracket the critical thrust line's edges are that much farther out. */
static void widen_touches(vs_limit_solution *s, double tol) {
  if (s->touch == NULL) return;
  s->n_touch = 0;
  for (int k = 0; k < s->n_joints; k++) {
    if (s->touch[k] == 'O') continue;
    if (s->eta[k] <= tol) s->touch[k] = 'I';
    else if (s->eta[k] >= 1.0 - tol) s->touch[k] = 'E';
    s->n_touch += s->touch[k] != 0;
  }
}

/* The least thickness factor at which the arch stands: bracketed from [0, 1] when the arch
 * stands (at_one), else from 1 upward by doubling, then bisected to thickness_tol; every trial
 * starts from the last one's basis, the first from basis (the self-weight LP's; freed here). */
static vs_status thickness_factor(const vs_run_def *d, const vs_limit_opts *o, const pose *p,
                                  int at_one, unsigned char *basis, vs_limit_analysis *a,
                                  vs_error *err) {
  vs_limit_solution trial = {0};
  trials t = {d, o, p, basis, 0, 0}; /* the trials own it from here */
  double lo = 0.0, hi = 1.0;
  int ok = at_one;
  vs_status st = VS_OK;
  if (at_one) st = stands(&t, hi, &ok, &a->thickness, err), a->thickness_solves++;
  while (st == VS_OK && !ok && hi < o->thickness_max && !t.unbuildable) {
    lo = hi;
    hi = fmin(2.0 * hi, o->thickness_max);
    st = stands(&t, hi, &ok, &a->thickness, err);
    a->thickness_solves += !t.unbuildable;
  }
  if (st == VS_OK && !ok) { /* not even at thickness_max (or the thickest its piers carry) */
    free(t.basis);
    a->thickness_bracket[0] = t.unbuildable ? lo : hi;
    a->thickness_bracket[1] = NAN;
    vs_limit_solution_free(&a->thickness);
    a->thickness.outcome = VS_LIMIT_INFEASIBLE;
    return VS_OK;
  }
  while (st == VS_OK && hi - lo > o->thickness_tol) {
    const double mid = 0.5 * (lo + hi);
    st = stands(&t, mid, &ok, &trial, err);
    a->thickness_solves++;
    if (st != VS_OK) break;
    if (ok) {
      hi = mid;
      swap_solutions(&trial, &a->thickness);
    } else {
      lo = mid;
    }
  }
  vs_limit_solution_free(&trial);
  free(t.basis);
  a->thickness_bracket[0] = lo;
  a->thickness_bracket[1] = hi;
  a->thickness_factor = st == VS_OK ? hi : NAN;
  if (st == VS_OK) widen_touches(&a->thickness, 2.0 * (hi - lo) / hi);
  return st;
}

void vs_limit_analysis_free(vs_limit_analysis *a) {
  if (a == NULL) return;
  vs_limit_solution_free(&a->collapse);
  vs_limit_solution_free(&a->thrust_min);
  vs_limit_solution_free(&a->thrust_max);
  vs_limit_solution_free(&a->thickness);
}

/* The load factor (with a live load) and the thrusts, on the arch as defined; *basis (malloc'd,
 * or NULL) the least thrust's, from which the others and the thickness's trials start. */
static vs_status solve_arch(const vs_run_def *d, const vs_limit_opts *o, const pose *p,
                            vs_limit_analysis *a, unsigned char **basis, vs_error *err) {
  vs_geometry *g = NULL;
  vs_limit *l = NULL;
  vs_limit_force *live = NULL;
  int n_live = 0;
  vs_status st = arch_scaled(d, 1.0, &g, err);
  if (st == VS_OK) st = vs_limit_live_load(g, &d->load, &d->fill, &live, &n_live, err);
  if (st == VS_OK) st = lp_of(d, g, p, live, n_live, o, &l, err);
  a->have_load = n_live > 0;
  /* the least thrust from scratch, the other two from its basis (the same rows and columns) */
  if (st == VS_OK) st = vs_limit_solve(l, VS_LIMIT_THRUST_MIN, &a->thrust_min, err);
  if (st == VS_OK && (*basis = malloc(vs_limit_basis_size(l))) == NULL)
    st = vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  if (st == VS_OK) vs_limit_basis_save(l, *basis);
  if (st == VS_OK) vs_limit_basis_start(l, *basis);
  if (st == VS_OK) st = vs_limit_solve(l, VS_LIMIT_THRUST_MAX, &a->thrust_max, err);
  if (st == VS_OK) vs_limit_basis_start(l, *basis);
  if (st == VS_OK && a->have_load) st = vs_limit_solve(l, VS_LIMIT_LOAD_FACTOR, &a->collapse, err);
  if (st == VS_OK && (d->load.kind == VS_LOAD_POINT || d->load.kind == VS_LOAD_LINE) &&
      n_live == 1) /* not spread through the fill over several */
    a->load_block = live[0].block;
  free(live);
  vs_limit_destroy(&l);
  vs_geometry_destroy(&g);
  return st;
}

/* The analysis of d's arch, moved by p (NULL: as built). */
static vs_status analyse(const vs_run_def *d, const vs_limit_opts *o, const pose *p,
                         vs_limit_analysis *a, vs_error *err) {
  memset(a, 0, sizeof *a);
  a->load_block = -1;
  a->thickness_factor = a->thickness_bracket[0] = a->thickness_bracket[1] = NAN;
  vs_limit_opts opts;
  if (o != NULL) {
    opts = *o;
  } else {
    vs_limit_opts_default(&opts);
    opts.mu = d->joints.mu;
    opts.left_kind = d->support.left_kind;
    opts.right_kind = d->support.right_kind;
  }
  const double t0 = vs_cpu_now();
  unsigned char *basis = NULL;
  vs_status st = solve_arch(d, &opts, p, a, &basis, err);
  if (st == VS_OK)
    st = thickness_factor(d, &opts, p, a->thrust_min.outcome != VS_LIMIT_INFEASIBLE, basis, a,
                          err);
  else
    free(basis);
  if (st == VS_OK && p != NULL) {
    vs_limit_solution *sols[3] = {&a->collapse, &a->thrust_min, &a->thrust_max};
    for (int i = 0; i < 3; i++) uncut_solution(p, opts.touch, sols[i]);
    uncut_solution(p, /* the critical line's edges, as widen_touches */
                   isfinite(a->thickness_factor)
                       ? 2.0 * (a->thickness_bracket[1] - a->thickness_bracket[0]) /
                             a->thickness_bracket[1]
                       : opts.touch,
                   &a->thickness);
  }
  a->cpu_s = vs_cpu_now() - t0;
  if (st != VS_OK) vs_limit_analysis_free(a);
  return st;
}

vs_status vs_limit_analyse(const vs_run_def *d, const vs_limit_opts *o, vs_limit_analysis *a,
                           vs_error *err) {
  return analyse(d, o, NULL, a, err);
}

vs_status vs_limit_analyse_moved(const vs_run_def *d, const vs_geometry *ref, const double *q,
                                 const double qs[6], const double *gap, const vs_limit_opts *o,
                                 vs_limit_analysis *a, vs_error *err) {
  if (ref == NULL || q == NULL || qs == NULL) {
    memset(a, 0, sizeof *a);
    return vs_error_set(err, VS_ERR_INVALID,
                        "limit: a deformed configuration needs its reference geometry and the "
                        "blocks' and supports' motions (given NULL)");
  }
  for (int i = 0; gap != NULL && i < 2 * ref->n_joints; i++)
    if (!isfinite(gap[i])) {
      memset(a, 0, sizeof *a);
      return vs_error_set(err, VS_ERR_INVALID, "limit: joint %d's opening is not finite",
                          i / 2 + 1);
    }
  for (int i = 0; i < 3 * ref->n_blocks; i++)
    if (!isfinite(q[i])) {
      memset(a, 0, sizeof *a);
      return vs_error_set(err, VS_ERR_INVALID, "limit: block %d's motion is not finite",
                          i / 3 + 1);
    }
  pose p = {ref, q, qs, calloc(2 * (size_t)(ref->n_joints > 0 ? ref->n_joints : 1), sizeof(double))};
  if (p.seg == NULL) {
    memset(a, 0, sizeof *a);
    return vs_error_set(err, VS_ERR_NOMEM, "limit: out of memory");
  }
  for (int k = 0; k < ref->n_joints; k++) p.seg[2 * k + 1] = 1.0;
  if (gap != NULL) contact_segments(gap, ref->n_joints, d->hinges.open, p.seg);
  const vs_status st = analyse(d, o, &p, a, err);
  free(p.seg);
  return st;
}
