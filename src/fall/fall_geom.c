/* The fall's geometry (fall.h): the bodies' outlines and joint faces, and the contact points at
 * a state, each with its rows and Delassus block: joint faces end against face, vertices
 * against the ground, and (broad phase on bounding boxes, narrow phase vertex against the
 * nearest edge or corner) vertices against the outlines of other bodies. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fall_internal.h"
#include "collide.h"

/* A face end counts as on its face while its projection is within this fraction of the joint's
 * length beyond the face's end at its own edge (a sliding joint keeps its contact until the end
 * passes; past the far end the faces have slid a whole length apart). */
static const double VS_FALL_FACE_SLACK = 0.02;
/* ... and while it is no deeper behind it than this fraction of the joint's length: deeper, the
 * bodies have come apart and met elsewhere (a vertex behind a face's line may be beyond the body,
 * or past its other side), and the vertex meets the other body's outline as any vertex would. */
static const double VS_FALL_FACE_DEPTH = 0.1;
/* A joint's faces are one contact surface at an edge (its two corners there one contact point,
 * neither met by the narrow phase) while they have turned from each other by less than this
 * share of the turn at which a corner could first reach the other body's outline beyond its
 * face: pi minus the larger outline angle at the two corners, at least a right angle (89 and 90
 * degrees between voussoirs, 62.5 at a pier's intrados end on the reference arch). Beyond it the
 * joint has folded there: the corner that is not the contact's would enter the other body
 * through another edge unseen, and a corner past the face's end is no longer in front of or
 * behind the body, so both corners meet the other body's outline as any vertex does (and an
 * overlap there is moved out). */
static const double VS_FALL_FOLD = 0.5;
static const double VS_PI = 3.14159265358979323846;

/* Reference points (collide.h's), inverse masses (the piers: 0, driven). */
static void bodies(vs_fall *f) {
  const vs_geometry *g = f->g;
  vs_collide_reference_points(g, f->ref);
  for (int i = 0; i < f->n; i++) {
    f->minv[3 * i] = f->minv[3 * i + 1] = 1.0 / g->blocks[i].mass;
    f->minv[3 * i + 2] = 1.0 / g->blocks[i].inertia;
  }
}

/* Vertices from count and xz (vs_collide_outlines: counter-clockwise, with their edges'
 * normals; at most 16 to a body, the contacts' keys' room), and each body's reach. */
static vs_status outlines(vs_fall *f, const int *count, const double *xz, vs_error *err) {
  const vs_collide_outline ol = {f->first, f->count, f->body, f->rx, f->rz, f->n0x, f->n0z};
  const vs_status st = vs_collide_outlines(f->nb, count, xz, f->ref, 16, "fall", &ol, err);
  for (int k = 0; st == VS_OK && k < f->nv; k++) {
    const int b = f->body[k];
    f->rmaxb[b] = fmax(f->rmaxb[b], hypot(f->rx[k], f->rz[k]));
    f->rmax = fmax(f->rmax, f->rmaxb[b]);
  }
  return st;
}

/* The outline's interior angle at vertex v (rad; the outlines are convex). */
static double corner_angle(const vs_fall *f, int v) {
  const int b = f->body[v], i = v - f->first[b], nb = f->count[b];
  const int p = f->first[b] + (i + nb - 1) % nb, q = f->first[b] + (i + 1) % nb;
  const double ax = f->rx[p] - f->rx[v], az = f->rz[p] - f->rz[v];
  const double bx = f->rx[q] - f->rx[v], bz = f->rz[q] - f->rz[v];
  return atan2(fabs(ax * bz - az * bx), ax * bx + az * bz);
}

/* The joints' faces on their two bodies, which vertices are face ends, and each body's joints. */
static void faces(vs_fall *f) {
  const vs_geometry *g = f->g;
  for (int k = 0; k < f->nv; k++) f->face_of[k] = -1;
  for (int jn = 0; jn < g->n_joints; jn++) {
    f->adj_first[vs_collide_body(g, g->joints[jn].a) + 1]++;
    f->adj_first[vs_collide_body(g, g->joints[jn].b) + 1]++;
  }
  for (int b = 0; b < f->nb; b++) f->adj_first[b + 1] += f->adj_first[b];
  for (int jn = 0; jn < g->n_joints; jn++)
    for (int s = 0; s < 2; s++) {
      const int a = vs_collide_body(g, s == 0 ? g->joints[jn].a : g->joints[jn].b);
      const int b = vs_collide_body(g, s == 0 ? g->joints[jn].b : g->joints[jn].a);
      int i = f->adj_first[a];
      while (f->adj_body[i] >= 0) i++;
      f->adj_body[i] = b, f->adj_joint[i] = jn;
    }
  for (int jn = 0; jn < g->n_joints; jn++) {
    const vs_joint_geom *j = &g->joints[jn];
    vs_fall_face *fc = &f->faces[jn];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    fc->a = vs_collide_body(g, j->a), fc->b = vs_collide_body(g, j->b);
    fc->na[0] = j->nx, fc->na[1] = j->nz;
    fc->length = j->length;
    fc->vend[0][0] = fc->vend[0][1] = fc->vend[1][0] = fc->vend[1][1] = -1;
    for (int e = 0; e < 2; e++) {
      const double h = (e == 0 ? -0.5 : 0.5) * j->length;
      const double x = j->px + h * sx, z = j->pz + h * sz;
      fc->ea[e][0] = x - f->ref[2 * fc->a], fc->ea[e][1] = z - f->ref[2 * fc->a + 1];
      fc->eb[e][0] = x - f->ref[2 * fc->b], fc->eb[e][1] = z - f->ref[2 * fc->b + 1];
      double angle = 0.5 * VS_PI; /* the larger outline angle at the two corners, at least a
                                     right angle (also where a face end is no vertex) */
      for (int s = 0; s < 2; s++) {
        const int bd = s == 0 ? fc->a : fc->b;
        const double *r = s == 0 ? fc->ea[e] : fc->eb[e];
        for (int v = f->first[bd]; v < f->first[bd] + f->count[bd]; v++)
          if (hypot(f->rx[v] - r[0], f->rz[v] - r[1]) < 1e-6 * j->length) {
            f->face_of[v] = jn, fc->vend[s][e] = v;
            angle = fmax(angle, corner_angle(f, v));
          }
      }
      fc->fold_cos[e] = cos(VS_FALL_FOLD * (VS_PI - angle));
    }
  }
}

vs_status vs_fall_geom_init(vs_fall *f, const int *count, const double *xz, vs_error *err) {
  const vs_geometry *g = f->g;
  int *own = NULL;
  double *oxz = NULL;
  if (count == NULL) {
    own = calloc((size_t)f->nb, sizeof *own);
    const int nv = vs_collide_arch_outlines(g, own, NULL);
    if (nv < 0) {
      free(own);
      return vs_error_set(err, VS_ERR_INVALID, "fall: a block's outline cannot be made convex");
    }
    oxz = malloc((size_t)(2 * nv + 1) * sizeof *oxz);
    if (own == NULL || oxz == NULL) {
      free(own), free(oxz);
      return vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory");
    }
    vs_collide_arch_outlines(g, own, oxz);
    count = own, xz = oxz;
  }
  f->nv = 0;
  for (int b = 0; b < f->nb; b++) f->nv += count[b] > 0 ? count[b] : 0;
  const size_t B = (size_t)f->nb, V = (size_t)f->nv + 1;
  f->first = calloc(B, sizeof *f->first), f->count = calloc(B, sizeof *f->count);
  f->body = calloc(V, sizeof *f->body), f->face_of = calloc(V, sizeof *f->face_of);
  f->onface = calloc(V, 1);
  f->rx = calloc(V, sizeof *f->rx), f->rz = calloc(V, sizeof *f->rz);
  f->n0x = calloc(V, sizeof *f->n0x), f->n0z = calloc(V, sizeof *f->n0z);
  f->ref = calloc(2 * B, sizeof *f->ref), f->minv = calloc(3 * B, sizeof *f->minv);
  f->faces = calloc((size_t)g->n_joints + 1, sizeof *f->faces);
  f->px = calloc(V, sizeof *f->px), f->pz = calloc(V, sizeof *f->pz);
  f->nx = calloc(V, sizeof *f->nx), f->nz = calloc(V, sizeof *f->nz);
  f->no = calloc(V, sizeof *f->no), f->box = calloc(4 * B, sizeof *f->box);
  f->rot = calloc(2 * B, sizeof *f->rot);
  f->order = calloc(B, sizeof *f->order);
  f->rmaxb = calloc(B, sizeof *f->rmaxb), f->reach = calloc(B, sizeof *f->reach);
  const size_t J = 2 * (size_t)g->n_joints + 1;
  f->adj_first = calloc(B + 1, sizeof *f->adj_first);
  f->adj_body = malloc(J * sizeof *f->adj_body), f->adj_joint = malloc(J * sizeof *f->adj_joint);
  for (size_t i = 0; f->adj_body != NULL && i < J; i++) f->adj_body[i] = -1;
  vs_status st = VS_OK;
  if (!f->first || !f->count || !f->body || !f->face_of || !f->onface || !f->rx || !f->rz ||
      !f->n0x || !f->n0z || !f->ref || !f->minv || !f->faces || !f->px || !f->pz || !f->nx ||
      !f->nz || !f->no || !f->box || !f->rot || !f->order || !f->rmaxb || !f->reach ||
      !f->adj_first || !f->adj_body || !f->adj_joint)
    st = vs_error_set(err, VS_ERR_NOMEM, "fall: out of memory");
  if (st == VS_OK) {
    for (int b = 0; b < f->nb; b++) f->order[b] = b;
    bodies(f);
    st = outlines(f, count, xz, err);
  }
  if (st == VS_OK) faces(f);
  free(own), free(oxz);
  return st;
}

void vs_fall_geom_free(vs_fall *f) {
  free(f->first), free(f->count), free(f->body), free(f->face_of), free(f->onface), free(f->rx);
  free(f->rz);
  free(f->n0x), free(f->n0z), free(f->ref), free(f->minv), free(f->faces), free(f->px);
  free(f->pz), free(f->nx), free(f->nz), free(f->no), free(f->box), free(f->order);
  free(f->cand), free(f->rmaxb), free(f->reach), free(f->adj_first), free(f->adj_body);
  free(f->adj_joint), free(f->rot);
}

/* Body b's pose at f->q as vs_fall_positions last saw it: position of its reference point and
 * rotation's cosine and sine (those computed there: the sines and cosines of a step are taken
 * once). */
static void pose(const vs_fall *f, int b, double *x, double *z, double *cs, double *sn) {
  const double *q = f->q + 3 * b;
  *x = f->ref[2 * b] + q[0], *z = f->ref[2 * b + 1] + q[1];
  *cs = f->rot[2 * b], *sn = f->rot[2 * b + 1];
}

void vs_fall_positions(vs_fall *f) {
  for (int b = 0; b < f->nb; b++) {
    f->rot[2 * b] = cos(f->q[3 * b + 2]), f->rot[2 * b + 1] = sin(f->q[3 * b + 2]);
    double x, z, cs, sn;
    pose(f, b, &x, &z, &cs, &sn);
    double *bx = f->box + 4 * b;
    bx[0] = bx[2] = INFINITY;
    bx[1] = bx[3] = -INFINITY;
    for (int k = f->first[b]; k < f->first[b] + f->count[b]; k++) {
      f->px[k] = x + cs * f->rx[k] - sn * f->rz[k];
      f->pz[k] = z + sn * f->rx[k] + cs * f->rz[k];
      if (f->px[k] < bx[0]) bx[0] = f->px[k];
      if (f->px[k] > bx[1]) bx[1] = f->px[k];
      if (f->pz[k] < bx[2]) bx[2] = f->pz[k];
      if (f->pz[k] > bx[3]) bx[3] = f->pz[k];
      f->nx[k] = cs * f->n0x[k] - sn * f->n0z[k];
      f->nz[k] = sn * f->n0x[k] + cs * f->n0z[k];
      f->no[k] = f->nx[k] * f->px[k] + f->nz[k] * f->pz[k];
    }
  }
}

/* Append a contact at point (px, pz) with normal n from b to a and gap; its rows, M^-1 J^T and
 * Delassus block. 0, or -1 when out of memory. */
static int add(vs_fall *f, long long key, int a, int b, int joint, double px, double pz,
               double nx, double nz, double gap) {
  if (f->nc == f->cap) {
    const int cap = f->cap ? 2 * f->cap : 256;
    vs_fall_contact *c = realloc(f->c, (size_t)cap * sizeof *c);
    if (c == NULL) return -1;
    f->c = c, f->cap = cap;
  }
  vs_fall_contact *c = &f->c[f->nc++];
  *c = (vs_fall_contact){.key = key, .a = a, .b = b, .joint = joint, .px = px, .pz = pz,
                         .n = {nx, nz}, .t = {-nz, nx}, .gap = gap};
  double W[3] = {0.0, 0.0, 0.0};
  for (int s = 0; s < 2; s++) {
    const int bd = s == 0 ? a : b;
    double *J = s == 0 ? c->Ja : c->Jb;
    if (bd < 0) continue; /* the ground: no row */
    const double sign = s == 0 ? 1.0 : -1.0;
    const double rx = px - (f->ref[2 * bd] + f->q[3 * bd]);
    const double rz = pz - (f->ref[2 * bd + 1] + f->q[3 * bd + 1]);
    for (int r = 0; r < 2; r++) {
      const double *d = r == 0 ? c->n : c->t;
      J[3 * r] = sign * d[0], J[3 * r + 1] = sign * d[1];
      J[3 * r + 2] = sign * (rx * d[1] - rz * d[0]);
    }
    const double *mi = f->minv + 3 * bd;
    double *K = s == 0 ? c->Ka : c->Kb; /* M^-1 J^T */
    for (int i = 0; i < 6; i++) K[i] = J[i] * mi[i % 3];
    for (int i = 0; i < 3; i++) {
      W[0] += K[i] * J[i];
      W[1] += K[i] * J[3 + i];
      W[2] += K[3 + i] * J[3 + i];
    }
  }
  memcpy(c->W, W, sizeof W);
  if (!(W[0] > 0.0)) f->nc--; /* two driven bodies: nothing to solve */
  return 0;
}

/* Face end e (0 intrados, 1 extrados) of body va against body eb's face of joint jn: the end's
 * position, its gap in front of that face and its coordinate along it from the face's middle,
 * and the face's outward normal (-n on b, n on a). */
typedef struct {
  double px, pz, gap, along, nx, nz;
} face_end;

static face_end end_on_face(const vs_fall *f, const vs_fall_face *fc, int s, int e) {
  const int va = s == 0 ? fc->a : fc->b, eb = s == 0 ? fc->b : fc->a;
  double xa, za, ca, sa, xb, zb, cb, sb;
  pose(f, va, &xa, &za, &ca, &sa);
  pose(f, eb, &xb, &zb, &cb, &sb);
  const double (*ev)[2] = s == 0 ? fc->ea : fc->eb, (*ee)[2] = s == 0 ? fc->eb : fc->ea;
  const double sg = s == 0 ? -1.0 : 1.0;
  face_end o;
  o.nx = sg * (cb * fc->na[0] - sb * fc->na[1]);
  o.nz = sg * (sb * fc->na[0] + cb * fc->na[1]);
  const double mx = xb + cb * 0.5 * (ee[0][0] + ee[1][0]) - sb * 0.5 * (ee[0][1] + ee[1][1]);
  const double mz = zb + sb * 0.5 * (ee[0][0] + ee[1][0]) + cb * 0.5 * (ee[0][1] + ee[1][1]);
  o.px = xa + ca * ev[e][0] - sa * ev[e][1];
  o.pz = za + sa * ev[e][0] + ca * ev[e][1];
  o.gap = o.nx * (o.px - mx) + o.nz * (o.pz - mz);
  o.along = -o.nz * (o.px - mx) + o.nx * (o.pz - mz);
  return o;
}

/* The largest signed distance of (x, z) from the lines of body b's outline's edges (m; < 0:
 * inside, as deep as it is behind the edge it is least deep behind; -inf: no outline). */
static double least_deep(const vs_fall *f, int b, double x, double z) {
  double best = -INFINITY;
  for (int i = f->first[b]; i < f->first[b] + f->count[b]; i++)
    best = fmax(best, f->nx[i] * x + f->nz[i] * z - f->no[i]);
  return best;
}

/* Joint jn's two edges, each one contact point: of the two corners there (a's face end against
 * b's face, b's against a's), the one on the other's face nearer to or deeper behind it (where
 * the faces have slid apart, the corner that bounds their common part). Two points carry any
 * distribution of the joint's normal force and moment between its edges; more would only be
 * redundant. Both corners at an edge with a contact are left out of the narrow phase; an edge
 * where the joint has folded (VS_FALL_FOLD) has none. */
static int face_contacts(vs_fall *f, int jn, double margin) {
  const vs_fall_face *fc = &f->faces[jn];
  if (!vs_fall_moving(f, fc->a) && !vs_fall_moving(f, fc->b)) return 0;
  const double reach = (0.5 + VS_FALL_FACE_SLACK) * fc->length;
  const double turn = cos(f->q[3 * fc->a + 2] - f->q[3 * fc->b + 2]);
  for (int e = 0; e < 2; e++) {
    if (turn < fc->fold_cos[e]) continue; /* folded: its corners are the narrow phase's */
    /* of the two corners at this edge (a's on b's face, b's on a's), the one on the other's
     * face that is nearer to or deeper behind it */
    int s = -1;
    face_end o = {0};
    for (int t = 0; t < 2; t++) {
      const face_end ot = end_on_face(f, fc, t, e);
      /* from the face's middle towards the corner's own end (the other face's end there) */
      const double own = (e == 0 ? -1.0 : 1.0) * (t == 0 ? -1.0 : 1.0) * ot.along;
      if (own < -0.5 * fc->length || own > reach || ot.gap < -VS_FALL_FACE_DEPTH * fc->length)
        continue;
      /* behind the face on its far half: on it only where the face is the other outline's edge
       * it is least deep behind (one that came round the face's far end is outside the other
       * body, or inside it behind another edge: the face's line is not its surface there) */
      if (own < 0.0 && ot.gap < 0.0 &&
          least_deep(f, t == 0 ? fc->b : fc->a, ot.px, ot.pz) > ot.gap + 1e-9 * fc->length)
        continue;
      if (s < 0 || ot.gap < o.gap) s = t, o = ot;
    }
    if (s < 0 || o.gap > margin) continue;
    for (int t = 0; t < 2; t++) /* both bodies' corners at this edge: the face contact's */
      if (fc->vend[t][e] >= 0) f->onface[fc->vend[t][e]] = 1;
    const long long key = -(long long)(2 * jn + e) - 1;
    if (add(f, key, s == 0 ? fc->a : fc->b, s == 0 ? fc->b : fc->a, jn, o.px, o.pz, o.nx, o.nz,
            o.gap) != 0)
      return -1;
  }
  return 0;
}

/* Is vertex k met by the narrow phase against the body it shares joint jn with (-1: none)? Not
 * while that joint's face contact holds it (face_contacts marks it on its face). */
static int met_by_narrow_phase(const vs_fall *f, int k, int jn) {
  return jn < 0 || f->face_of[k] != jn || !f->onface[k];
}

/* Do bodies a and b share a joint (its index), or not (-1)? */
static int shared_joint(const vs_fall *f, int a, int b) {
  for (int i = f->adj_first[a]; i < f->adj_first[a + 1]; i++)
    if (f->adj_body[i] == b) return f->adj_joint[i];
  return -1;
}

/* Vertex k (of body a) against body b's outline (convex). Outside, within margin, on the
 * feature of the outline nearest to it: an edge it is in front of (that edge's normal, its
 * distance from the edge's line) or a corner whose region it is in (the normal from the corner
 * to it, their distance), so that a vertex coming at a corner is met before it is inside.
 * Inside, on the edge it is least deep behind. */
static int vertex_edge(vs_fall *f, int k, int b, double margin) {
  const int fb = f->first[b], nb = f->count[b];
  double best = -INFINITY;
  int e = -1;
  for (int i = 0; i < nb; i++) {
    const double d = f->nx[fb + i] * f->px[k] + f->nz[fb + i] * f->pz[k] - f->no[fb + i];
    if (d > best) best = d, e = i;
  }
  if (best > margin) return 0; /* its distance from the outline is at least best */
  double gap = best, nx = f->nx[fb + e], nz = f->nz[fb + e];
  int feature = e; /* the key's: edges 0 .. 15, corners 16 .. 31 */
  if (best > 0.0) { /* outside: the nearest edge or corner (one nearer than a round-off length
                       gives no direction: the edge's normal then) */
    const double tiny = 1e-9 * f->rmax;
    double near = INFINITY;
    for (int i = 0; i < nb; i++) {
      const int i0 = fb + i, i1 = fb + (i + 1) % nb;
      const double tx = f->px[i1] - f->px[i0], tz = f->pz[i1] - f->pz[i0];
      const double rx = f->px[k] - f->px[i0], rz = f->pz[k] - f->pz[i0];
      const double s = rx * tx + rz * tz, tt = tx * tx + tz * tz;
      if (s <= 0.0) { /* behind corner i0 along edge i: its region if nearest */
        const double d = hypot(rx, rz);
        if (d < near && d > tiny) near = d, nx = rx / d, nz = rz / d, feature = 16 + i;
      } else if (s < tt) { /* abreast of edge i */
        const double d = f->nx[i0] * f->px[k] + f->nz[i0] * f->pz[k] - f->no[i0];
        if (d >= 0.0 && d < near) near = d, nx = f->nx[i0], nz = f->nz[i0], feature = i;
      }
    }
    if (near < INFINITY) gap = near;
    if (gap > margin) return 0;
  }
  const long long key = ((long long)k * (f->nb + 2) + (b + 1)) * 32 + feature;
  return add(f, key, f->body[k], b, -1, f->px[k], f->pz[k], nx, nz, gap);
}

static int add_pair(vs_fall *f, int a, int b) {
  if (f->ncand == f->candcap) {
    const int cap = f->candcap ? 2 * f->candcap : 4 * f->nb;
    int *c = realloc(f->cand, 2 * (size_t)cap * sizeof *c);
    if (c == NULL) return -1;
    f->cand = c, f->candcap = cap;
  }
  f->cand[2 * f->ncand] = a;
  f->cand[2 * f->ncand++ + 1] = b;
  return 0;
}

/* The candidate pairs of bodies (at least one of them moving) whose boxes, each widened by its
 * reach (NULL: none), overlap: sort and sweep along x (insertion sort from the last order). 0,
 * or -1 when out of memory. */
static int sweep(vs_fall *f, const double *reach) {
  int *o = f->order;
#define LEFT(b) (f->box[4 * (b)] - (reach != NULL ? reach[b] : 0.0))
  for (int i = 1; i < f->nb; i++)
    for (int j = i; j > 0 && LEFT(o[j - 1]) > LEFT(o[j]); j--) {
      const int t = o[j];
      o[j] = o[j - 1], o[j - 1] = t;
    }
  f->ncand = 0;
  for (int i = 0; i < f->nb; i++) {
    const int a = o[i];
    if (f->count[a] == 0) continue;
    const double ra = reach != NULL ? reach[a] : 0.0;
    for (int j = i + 1; j < f->nb && LEFT(o[j]) <= f->box[4 * a + 1] + ra; j++) {
      const int b = o[j];
      const double *A = f->box + 4 * a, *B = f->box + 4 * b;
      const double w = ra + (reach != NULL ? reach[b] : 0.0);
      if (f->count[b] == 0 || (!vs_fall_moving(f, a) && !vs_fall_moving(f, b))) continue;
      if (A[2] <= B[3] + w && B[2] <= A[3] + w && add_pair(f, a, b) != 0) return -1;
    }
  }
#undef LEFT
  return 0;
}

int vs_fall_find_contacts(vs_fall *f, double h, const double *v2) {
  /* how far each body's points can move in the step: its speed, turned at its outline's reach,
   * and gravity's share */
  const double g = f->g->gravity;
  for (int b = 0; b < f->nb; b++) {
    double speed = 0.0;
    for (int s = 0; s < (v2 != NULL ? 2 : 1); s++) {
      const double *v = (s == 0 ? f->v : v2) + 3 * b;
      speed = fmax(speed, hypot(v[0], v[1]) + fabs(v[2]) * f->rmaxb[b]);
    }
    f->reach[b] = h * speed + (b < f->n ? g * h * h : 0.0) + 1e-9 * f->rmax;
  }
  f->nc = 0;
  memset(f->onface, 0, (size_t)f->nv);
  if (f->o.joints)
    for (int jn = 0; jn < f->g->n_joints; jn++)
      if (face_contacts(f, jn, f->reach[f->faces[jn].a] + f->reach[f->faces[jn].b]) != 0)
        return -1;
  if (isfinite(f->level))
    for (int b = 0; b < f->n; b++)
      for (int k = f->first[b]; k < f->first[b] + f->count[b]; k++) {
        const double gap = f->pz[k] - f->level;
        const long long key = ((long long)k * (f->nb + 2)) * 32 + 31;
        if (gap <= f->reach[b] && add(f, key, b, -1, -1, f->px[k], f->pz[k], 0.0, 1.0, gap) != 0)
          return -1;
      }
  if (sweep(f, f->reach) != 0) return -1;
  for (int p = 0; p < f->ncand; p++)
    for (int s = 0; s < 2; s++) {
      const int a = f->cand[2 * p + s], b = f->cand[2 * p + 1 - s];
      if (!vs_fall_moving(f, a) && !vs_fall_moving(f, b)) continue;
      const int jn = f->o.joints ? shared_joint(f, a, b) : -1;
      const double margin = f->reach[a] + f->reach[b], *B = f->box + 4 * b;
      for (int k = f->first[a]; k < f->first[a] + f->count[a]; k++) {
        /* farther than margin from b's box, so from its outline: no contact */
        if (f->px[k] < B[0] - margin || f->px[k] > B[1] + margin || f->pz[k] < B[2] - margin ||
            f->pz[k] > B[3] + margin)
          continue;
        if (met_by_narrow_phase(f, k, jn) && vertex_edge(f, k, b, margin) != 0) return -1;
      }
    }
  return 0;
}

void vs_fall_overlaps(vs_fall *f, double *bodies_out, double *joints_out) {
  double worst = 0.0, worst_j = 0.0;
  const int nc = f->nc;
  memset(f->onface, 0, (size_t)f->nv);
  if (f->o.joints) { /* the face ends behind their faces: the contacts of a zero margin */
    for (int jn = 0; jn < f->g->n_joints; jn++) face_contacts(f, jn, 0.0);
    for (int i = nc; i < f->nc; i++) worst_j = fmax(worst_j, -f->c[i].gap);
  }
  f->nc = nc;
  if (sweep(f, NULL) != 0) f->ncand = 0; /* out of memory: bodies not measured */
  for (int p = 0; p < f->ncand; p++)
    for (int s = 0; s < 2; s++) {
      const int a = f->cand[2 * p + s], b = f->cand[2 * p + 1 - s];
      const int jn = f->o.joints ? shared_joint(f, a, b) : -1;
      for (int k = f->first[a]; k < f->first[a] + f->count[a]; k++) {
        if (!met_by_narrow_phase(f, k, jn)) continue; /* its face contact's */
        worst = fmax(worst, -least_deep(f, b, f->px[k], f->pz[k]));
      }
    }
  *bodies_out = worst;
  *joints_out = worst_j;
}
