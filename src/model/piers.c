/* The piers under an arch's springings (piers.h; docs/model.md, "Piers"): per springing a stack
 * of equal courses from the ground up to the springing's intrados point, its inner face flush
 * with that point, its top course a skewback cut along the springing joint, on a foundation. */
#include "piers.h"

#include "outline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The most vertices of a pier's course (the top one has five) or its foundation slab (six). */
enum { PIER_VERTS = 6 };

/* A course's outline: n vertices counter-clockwise, edge k from vertex k to k + 1 on joint
 * jt[k] (-1: none). */
typedef struct {
  int n;
  double x[PIER_VERTS], z[PIER_VERTS];
  int jt[PIER_VERTS];
} course_poly;

/* The polygon mirrored about x = xm: the vertices reversed, so that it stays counter-clockwise. */
static void mirror(course_poly *c, double xm) {
  course_poly m = {.n = c->n};
  for (int k = 0; k < c->n; k++) {
    m.x[k] = 2.0 * xm - c->x[c->n - 1 - k];
    m.z[k] = c->z[c->n - 1 - k];
    m.jt[k] = c->jt[(2 * c->n - 2 - k) % c->n];
  }
  *c = m;
}

/* One pier's geometry: the springing's intrados point (xi, zi), the face's extrados end
 * (xe, ze), outward sign s (-1 left, +1 right). */
typedef struct {
  double xi, zi, xe, ze, s, w, h;
  int courses;
} pier_shape;

/* Course c of pier ps, whose joints are base + 0 .. base + courses - 1 (the one under course c
 * is base + c) and whose top course carries springing joint js. Built for the left pier (s = -1)
 * and mirrored for the right one. */
static void course_of(const pier_shape *ps, int c, int base, int js, course_poly *out) {
  const double xi = ps->xi, xo = xi - ps->w, dz = ps->h / ps->courses;
  const double z0 = ps->zi - ps->h + c * dz, z1 = ps->zi - ps->h + (c + 1) * dz;
  const double xe = ps->s < 0 ? ps->xe : 2.0 * xi - ps->xe; /* in the left pier's frame */
  const int below = base + c, above = c + 1 < ps->courses ? base + c + 1 : -1;
  if (above >= 0) {
    *out = (course_poly){.n = 4, .x = {xo, xi, xi, xo}, .z = {z0, z0, z1, z1},
                         .jt = {below, -1, above, -1}};
  } else {
    *out = (course_poly){.n = 5, .x = {xo, xi, xi, xe, xo}, .z = {z0, z0, ps->zi, ps->ze, ps->ze},
                         .jt = {below, -1, js, -1, -1}};
  }
  if (ps->s > 0) mirror(out, xi);
}

/* The foundation slab under pier ps: a quarter of its width beyond either face, half its width
 * deep; its top carries the base joint jb. */
static void slab_of(const pier_shape *ps, int jb, course_poly *out) {
  const double f0 = fmin(ps->xi, ps->xi + ps->s * ps->w), f1 = fmax(ps->xi, ps->xi + ps->s * ps->w);
  const double m = 0.25 * ps->w, zg = ps->zi - ps->h, zb = zg - 0.5 * ps->w;
  *out = (course_poly){.n = 6, .x = {f0 - m, f1 + m, f1 + m, f1, f0, f0 - m},
                       .z = {zb, zb, zg, zg, zg, zg}, .jt = {-1, -1, -1, jb, -1, -1}};
}

static void poly_edges(const course_poly *c, vs_edge *e) {
  for (int k = 0; k < c->n; k++) {
    const int l = (k + 1) % c->n;
    e[k] = (vs_edge){.x0 = c->x[k], .z0 = c->z[k], .x1 = c->x[l], .z1 = c->z[l], .u1 = 1.0,
                     .joint = c->jt[k]};
  }
}

/* The springing's intrados point and the face's extrados end of joint j. */
static void face_ends(const vs_joint_geom *j, pier_shape *ps) {
  double sx, sz;
  vs_joint_tangent(j, &sx, &sz);
  ps->xi = j->px - 0.5 * j->length * sx, ps->zi = j->pz - 0.5 * j->length * sz;
  ps->xe = j->px + 0.5 * j->length * sx, ps->ze = j->pz + 0.5 * j->length * sz;
}

/* Check that pier ps can stand under its springing face: the face runs outward and up (or
 * level) from the intrados point and ends inside the pier's width. */
static vs_status check_shape(const pier_shape *ps, vs_error *err) {
  const double reach = ps->s * (ps->xe - ps->xi), tol = 1e-9 * (ps->w + ps->h);
  const char *side = ps->s < 0 ? "left" : "right";
  if (reach < -tol || ps->ze < ps->zi - tol)
    return vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %g: the %s springing face runs "
                        "%s from its intrados point (allowed: piers under a face that runs "
                        "outward and up, or level)", ps->h * 1e3, side,
                        reach < -tol ? "inward" : "down");
  if (!(ps->w > reach + tol))
    return vs_error_set(err, VS_ERR_INVALID, "piers.width_mm = %g: narrower than the %s "
                        "springing face's horizontal extent (allowed: > %.6g mm)",
                        ps->w * 1e3, side, reach * 1e3);
  return VS_OK;
}

static vs_status check_def(const vs_piers_def *p, vs_error *err) {
  if (!(p->height > 0.0) || !isfinite(p->height))
    return vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %g (allowed: 0, no piers, or > 0)",
                        p->height * 1e3);
  if (!(p->width > 0.0) || !isfinite(p->width))
    return vs_error_set(err, VS_ERR_INVALID, "piers.width_mm = %g (allowed: > 0)", p->width * 1e3);
  if (p->courses < 1 || p->courses > VS_PIERS_MAX_COURSES)
    return vs_error_set(err, VS_ERR_INVALID, "piers.courses = %d (allowed: 1 .. %d)", p->courses,
                        VS_PIERS_MAX_COURSES);
  if (!(p->density >= 0.0) || !isfinite(p->density) || !(p->base_friction >= 0.0) ||
      !isfinite(p->base_friction))
    return vs_error_set(err, VS_ERR_INVALID, "piers.density_kg_m3 = %g, piers.base_friction = %g "
                        "(allowed: 0, the arch's and the joints', or > 0)", p->density,
                        p->base_friction);
  return VS_OK;
}

/* Grow g's blocks and joints to nb and nj (the new ones zero). */
static vs_status grow(vs_geometry *g, int nb, int nj, vs_error *err) {
  vs_block *b = realloc(g->blocks, (size_t)nb * sizeof *b);
  if (b != NULL) g->blocks = b;
  vs_joint_geom *j = b != NULL ? realloc(g->joints, (size_t)nj * sizeof *j) : NULL;
  if (j == NULL) return vs_error_set(err, VS_ERR_NOMEM, "geometry: out of memory");
  g->joints = j;
  memset(g->blocks + g->n_blocks, 0, (size_t)(nb - g->n_blocks) * sizeof *b);
  memset(g->joints + g->n_joints, 0, (size_t)(nj - g->n_joints) * sizeof *j);
  g->n_blocks = nb;
  g->n_joints = nj;
  return VS_OK;
}

/* Pier p (0 left, 1 right) of shape ps: its blocks, joints and foundation slab. */
static vs_status build_pier(vs_geometry *g, int p, const pier_shape *ps, double rho_b,
                            double mu_base, double depth, int js, vs_error *err) {
  const int C = ps->courses, b0 = g->pier_block[p], j0 = g->pier_joint[p];
  const int support = p == 0 ? VS_SUPPORT_LEFT : VS_SUPPORT_RIGHT;
  vs_edge e[6];
  course_poly cp;
  vs_status st = VS_OK;
  for (int c = 0; c < C && st == VS_OK; c++) {
    /* the joint under course c: left pier from below (normal up), right from above (normal
     * down), so that eta runs from the inner face outward on both, as a mirror image */
    vs_joint_geom *j = &g->joints[j0 + c];
    const int lower = c == 0 ? support : b0 + c - 1, upper = b0 + c;
    j->a = p == 0 ? lower : upper;
    j->b = p == 0 ? upper : lower;
    j->px = ps->xi + 0.5 * ps->s * ps->w;
    j->pz = ps->zi - ps->h + c * ps->h / C;
    j->nx = 0.0;
    j->nz = p == 0 ? 1.0 : -1.0;
    j->length = ps->w;
    j->depth = depth;
    if (c == 0) j->mu = mu_base;
    course_of(ps, c, j0, js, &cp);
    poly_edges(&cp, e);
    st = vs_geometry_set_outline(g, b0 + c, cp.n, e, err);
    if (st != VS_OK) break;
    vs_section sec;
    vs_outline_section(g->edges + g->blocks[b0 + c].edge0, cp.n, &sec);
    vs_block *b = &g->blocks[b0 + c];
    b->area = sec.area;
    b->mass = rho_b * sec.area;
    b->inertia = rho_b * sec.j;
    b->cx = sec.cx, b->cz = sec.cz;
  }
  if (st != VS_OK) return st;
  slab_of(ps, j0, &cp);
  poly_edges(&cp, e);
  return vs_geometry_add_support(g, support, cp.n, e, err);
}

vs_status vs_piers_add(vs_geometry **gp, const vs_piers_def *p, double density, double depth,
                       vs_error *err) {
  if (p->height == 0.0) return VS_OK;
  vs_geometry *g = *gp;
  vs_status st = check_def(p, err);
  const int ring = g->ring > 0 ? g->ring : g->n_joints, js[2] = {0, ring - 1};
  if (st == VS_OK &&
      (g->joints[js[0]].a != VS_SUPPORT_LEFT || g->joints[js[1]].b != VS_SUPPORT_RIGHT ||
       g->n_supports > 0 || ring != g->n_joints))
    st = vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %g: the arch does not stand on "
                      "two springings (allowed: 0 with arch.shape = file, whose blocks draw "
                      "their own piers)", p->height * 1e3);
  pier_shape ps[2];
  for (int s = 0; s < 2 && st == VS_OK; s++) {
    ps[s] = (pier_shape){.s = s ? 1.0 : -1.0, .w = p->width, .h = p->height,
                         .courses = p->courses};
    face_ends(&g->joints[js[s]], &ps[s]);
    st = check_shape(&ps[s], err);
  }
  const int C = p->courses, nb = g->n_blocks;
  if (st == VS_OK) {
    g->ring = ring;
    g->pier_courses = C;
    g->pier_block[0] = nb, g->pier_block[1] = nb + C;
    g->pier_joint[0] = ring, g->pier_joint[1] = ring + C;
    st = grow(g, nb + 2 * C, ring + 2 * C, err);
  }
  if (st == VS_OK) {
    g->joints[js[0]].a = g->pier_block[0] + C - 1; /* the springings on the top courses */
    g->joints[js[1]].b = g->pier_block[1] + C - 1;
  }
  const double rho_b = (p->density > 0.0 ? p->density : density) * depth;
  for (int s = 0; s < 2 && st == VS_OK; s++)
    st = build_pier(g, s, &ps[s], rho_b, p->base_friction, depth, js[s], err);
  if (st != VS_OK) vs_geometry_destroy(gp);
  return st;
}
