/* The blocks file (docs/blocks-file.md): a JSON file of polygons read with libjansson into a
 * geometry (vs_geometry_create_arch for arch.shape = file): blocks and supports, interfaces
 * found where two bodies share a whole edge (vertices within the file's tolerance taken as one),
 * the arch ring that numbers the joints for the hinges, each interface's own law; and a
 * geometry written as such a file (vs_geometry_blocks_json). */
#define _POSIX_C_SOURCE 200809L /* open, fstat */
#include "blocks.h"

#include "outline.h"
#include "quote.h"
#include "voussoir/units.h"

#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define VS_BLOCKS_FORMAT "voussoir-blocks 1"
/* The default tolerance within which two vertices are one point, mm. */
static const double VS_BLOCKS_TOL_MM = 1e-3;

/* One polygon of the file. */
typedef struct {
  char name[64];
  int side;       /* 0: a block; VS_SUPPORT_LEFT or VS_SUPPORT_RIGHT: part of that support */
  int body;       /* its body in the geometry: a block index, or side */
  int n;          /* vertices */
  double *p;      /* n (x, z) pairs, m, counter-clockwise */
  double density; /* kg/m^3 */
  double box[4];  /* min x, max x, min z, max z, m */
} poly;

/* An interface: polygon pa's edge ea is polygon pb's edge eb, run the other way. */
typedef struct {
  int pa, ea, pb, eb;
  double kn, ks_ratio, mu; /* its own law, 0: the run's */
  int joint;               /* its joint (0-based) */
} iface;

typedef struct {
  const char *file;
  const vs_arch_def *a;
  vs_error *err;
  double tol; /* m */
  poly *p;
  int np, nb; /* polygons, of which blocks */
  iface *f;
  int nf, capf;
  int *ring; /* the ring's polygons, nring of them */
  int nring;
} reader;

static vs_status fail(const reader *r, vs_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static vs_status fail(const reader *r, vs_status st, const char *fmt, ...) {
  char msg[sizeof r->err->msg];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  char file[256];
  return vs_error_set(r->err, st, "%s: %s", vs_quote(r->file, file, sizeof file), msg);
}

/* "blocks[3] (\"v3\")" */
static const char *who(const reader *r, int i, char *buf, size_t size) {
  snprintf(buf, size, "blocks[%d] (\"%s\")", i, r->p[i].name);
  return buf;
}

/* ------------------------------------------------------------------------------------------ */
/* Fields                                                                                      */

/* Every key of object o is one of allowed (NULL-terminated). */
static vs_status known_keys(const reader *r, json_t *o, const char *where,
                            const char *const *allowed, const char *list) {
  const char *key;
  json_t *v;
  json_object_foreach(o, key, v) {
    int ok = 0;
    for (int i = 0; allowed[i] != NULL && !ok; i++) ok = strcmp(key, allowed[i]) == 0;
    if (!ok) {
      char k[40];
      snprintf(k, sizeof k, "%.32s%s", key, strlen(key) > 32 ? "..." : "");
      for (char *c = k; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = '?';
      return fail(r, VS_ERR_INVALID, "%s: unknown field \"%s\" (allowed: %s)", where, k, list);
    }
  }
  return VS_OK;
}

/* A number field of o in [lo, hi] (def when absent and has_def). */
static vs_status number(const reader *r, json_t *o, const char *key, const char *where,
                        double lo, double hi, int has_def, double def, double *out) {
  json_t *v = json_object_get(o, key);
  if (v == NULL && has_def) {
    *out = def;
    return VS_OK;
  }
  if (v == NULL || !json_is_number(v) || !(json_number_value(v) >= lo) ||
      !(json_number_value(v) <= hi))
    return fail(r, VS_ERR_INVALID, "%s.%s: %s (allowed: a number in [%g, %g])", where, key,
                v == NULL ? "missing" : json_is_number(v) ? "out of range" : "not a number", lo, hi);
  *out = json_number_value(v);
  return VS_OK;
}

/* A name: printable ASCII of 1 to 63 characters. */
static int good_name(const char *s) {
  const size_t n = strlen(s);
  if (n == 0 || n > 63) return 0;
  for (size_t i = 0; i < n; i++)
    if ((unsigned char)s[i] < 0x20 || (unsigned char)s[i] > 0x7e) return 0;
  return 1;
}

static vs_status read_polygon(reader *r, int i, json_t *b, const char *where) {
  poly *p = &r->p[i];
  json_t *pts = json_object_get(b, "polygon");
  const size_t n = json_is_array(pts) ? json_array_size(pts) : 0;
  if (n < 3 || n > VS_BLOCKS_MAX_VERTICES)
    return fail(r, VS_ERR_INVALID, "%s.polygon: %s (allowed: an array of 3 to %d [x, z] "
                "pairs, mm)", where, pts == NULL ? "missing" : !json_is_array(pts)
                ? "not an array" : "wrong number of vertices", VS_BLOCKS_MAX_VERTICES);
  p->p = malloc(2 * n * sizeof *p->p);
  if (p->p == NULL) return fail(r, VS_ERR_NOMEM, "out of memory");
  p->n = (int)n;
  for (size_t k = 0; k < n; k++) {
    json_t *v = json_array_get(pts, k), *x = json_array_get(v, 0), *z = json_array_get(v, 1);
    if (!json_is_array(v) || json_array_size(v) != 2 || !json_is_number(x) || !json_is_number(z) ||
        !(fabs(json_number_value(x)) <= 1e9) || !(fabs(json_number_value(z)) <= 1e9))
      return fail(r, VS_ERR_INVALID, "%s.polygon[%zu]: not a vertex (allowed: [x, z], two "
                  "numbers within 1e9 mm)", where, k);
    p->p[2 * k] = json_number_value(x) * VS_MM;
    p->p[2 * k + 1] = json_number_value(z) * VS_MM;
  }
  return VS_OK;
}

static vs_status read_block(reader *r, int i, json_t *b) {
  static const char *const keys[] = {"name", "polygon", "support", "density_kg_m3", NULL};
  char where[96];
  snprintf(where, sizeof where, "blocks[%d]", i);
  if (!json_is_object(b))
    return fail(r, VS_ERR_INVALID, "%s: not an object (allowed: {\"name\", \"polygon\", "
                "\"support\", \"density_kg_m3\"})", where);
  vs_status st = known_keys(r, b, where, keys, "name, polygon, support, density_kg_m3");
  poly *p = &r->p[i];
  json_t *name = json_object_get(b, "name"), *sup = json_object_get(b, "support");
  if (st == VS_OK && name != NULL && (!json_is_string(name) || !good_name(json_string_value(name))))
    st = fail(r, VS_ERR_INVALID, "%s.name: not a name (allowed: 1 to 63 printable ASCII "
              "characters)", where);
  if (st != VS_OK) return st;
  if (name != NULL) snprintf(p->name, sizeof p->name, "%s", json_string_value(name));
  else snprintf(p->name, sizeof p->name, "#%d", i);
  for (int j = 0; j < i; j++)
    if (strcmp(r->p[j].name, p->name) == 0)
      return fail(r, VS_ERR_INVALID, "%s.name: \"%s\" is blocks[%d]'s too (allowed: a name of "
                  "its own)", where, p->name, j);
  snprintf(where, sizeof where, "blocks[%d] (\"%s\")", i, p->name);
  if (sup != NULL) {
    const char *s = json_is_string(sup) ? json_string_value(sup) : "";
    if (strcmp(s, "left") == 0) p->side = VS_SUPPORT_LEFT;
    else if (strcmp(s, "right") == 0) p->side = VS_SUPPORT_RIGHT;
    else
      return fail(r, VS_ERR_INVALID, "%s.support: not a support (allowed: \"left\", the fixed "
                  "one, or \"right\", the moved one)", where);
  }
  st = number(r, b, "density_kg_m3", where, 10.0, 1e5, 1, r->a->density, &p->density);
  if (st == VS_OK) st = read_polygon(r, i, b, where);
  return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Polygons                                                                                    */

/* Vertices within the tolerance of an earlier one (in file order) become that one, so that a
 * shared edge is shared exactly. */
static void snap(reader *r) {
  for (int i = 0; i < r->np; i++)
    for (int k = 0; k < r->p[i].n; k++) {
      double *v = r->p[i].p + 2 * k;
      for (int j = 0; j < i; j++) {
        const poly *q = &r->p[j];
        if (v[0] < q->box[0] - r->tol || v[0] > q->box[1] + r->tol || v[1] < q->box[2] - r->tol ||
            v[1] > q->box[3] + r->tol)
          continue;
        for (int m = 0; m < q->n; m++)
          if (hypot(v[0] - q->p[2 * m], v[1] - q->p[2 * m + 1]) <= r->tol) {
            v[0] = q->p[2 * m], v[1] = q->p[2 * m + 1];
            j = i; /* the first one found */
            break;
          }
      }
    }
}

static void set_box(poly *p) {
  p->box[0] = p->box[2] = INFINITY;
  p->box[1] = p->box[3] = -INFINITY;
  for (int k = 0; k < p->n; k++) {
    p->box[0] = fmin(p->box[0], p->p[2 * k]), p->box[1] = fmax(p->box[1], p->p[2 * k]);
    p->box[2] = fmin(p->box[2], p->p[2 * k + 1]), p->box[3] = fmax(p->box[3], p->p[2 * k + 1]);
  }
}

static double cross(const double *o, const double *a, const double *b) {
  return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Segments ab and cd share a point. */
static int segments_meet(const double *a, const double *b, const double *c, const double *d) {
  const double d1 = cross(a, b, c), d2 = cross(a, b, d), d3 = cross(c, d, a), d4 = cross(c, d, b);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return 1;
#define ON(p, q, s) (fmin(p[0], q[0]) <= s[0] && s[0] <= fmax(p[0], q[0]) && \
                     fmin(p[1], q[1]) <= s[1] && s[1] <= fmax(p[1], q[1]))
  return (d1 == 0 && ON(a, b, c)) || (d2 == 0 && ON(a, b, d)) || (d3 == 0 && ON(c, d, a)) ||
         (d4 == 0 && ON(c, d, b));
#undef ON
}

/* Counter-clockwise, every edge longer than the tolerance, no two edges crossing. */
static vs_status check_polygon(const reader *r, int i) {
  poly *p = &r->p[i];
  char w[96];
  double area = 0.0;
  for (int k = 0; k < p->n; k++) {
    const double *a = p->p + 2 * k, *b = p->p + 2 * ((k + 1) % p->n);
    area += 0.5 * (a[0] * b[1] - b[0] * a[1]);
    if (!(hypot(b[0] - a[0], b[1] - a[1]) > r->tol))
      return fail(r, VS_ERR_INVALID, "%s.polygon: vertices %d and %d are within tolerance_mm = "
                  "%g of each other (allowed: edges longer than the tolerance)",
                  who(r, i, w, sizeof w), k, (k + 1) % p->n, r->tol / VS_MM);
  }
  for (int k = 0; k < p->n; k++)
    for (int m = k + 2; m < p->n; m++) {
      if (k == 0 && m == p->n - 1) continue; /* neighbours */
      if (segments_meet(p->p + 2 * k, p->p + 2 * ((k + 1) % p->n), p->p + 2 * m,
                        p->p + 2 * ((m + 1) % p->n)))
        return fail(r, VS_ERR_INVALID, "%s.polygon: edges %d and %d cross (allowed: a simple "
                    "polygon)", who(r, i, w, sizeof w), k, m);
    }
  if (!(fabs(area) > 0.0))
    return fail(r, VS_ERR_INVALID, "%s.polygon: no area (allowed: a polygon enclosing an area)",
                who(r, i, w, sizeof w));
  if (area < 0.0) /* made counter-clockwise */
    for (int k = 0; k < p->n / 2; k++)
      for (int c = 0; c < 2; c++) {
        const double t = p->p[2 * k + c];
        p->p[2 * k + c] = p->p[2 * (p->n - 1 - k) + c];
        p->p[2 * (p->n - 1 - k) + c] = t;
      }
  return VS_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* Interfaces                                                                                  */

static vs_status add_iface(reader *r, int pa, int ea, int pb, int eb) {
  if (r->nf == r->capf) {
    const int cap = r->capf ? 2 * r->capf : 64;
    iface *f = realloc(r->f, (size_t)cap * sizeof *f);
    if (f == NULL) return fail(r, VS_ERR_NOMEM, "out of memory");
    r->f = f, r->capf = cap;
  }
  r->f[r->nf++] = (iface){.pa = pa, .ea = ea, .pb = pb, .eb = eb, .joint = -1};
  return VS_OK;
}

/* Edge e of polygon i against edge f of polygon j: one interface when they are the same edge
 * run both ways; an error when they lie on one line and overlap otherwise. */
static vs_status edge_pair(reader *r, int i, int e, int j, int f) {
  const poly *A = &r->p[i], *B = &r->p[j];
  const double *p0 = A->p + 2 * e, *p1 = A->p + 2 * ((e + 1) % A->n);
  const double *q0 = B->p + 2 * f, *q1 = B->p + 2 * ((f + 1) % B->n);
  if (p0[0] == q1[0] && p0[1] == q1[1] && p1[0] == q0[0] && p1[1] == q0[1])
    return add_iface(r, i, e, j, f);
  const double L = hypot(p1[0] - p0[0], p1[1] - p0[1]);
  const double ux = (p1[0] - p0[0]) / L, uz = (p1[1] - p0[1]) / L;
  const double d0 = ux * (q0[1] - p0[1]) - uz * (q0[0] - p0[0]);
  const double d1 = ux * (q1[1] - p0[1]) - uz * (q1[0] - p0[0]);
  if (!(fabs(d0) <= r->tol && fabs(d1) <= r->tol)) return VS_OK;
  const double t0 = ux * (q0[0] - p0[0]) + uz * (q0[1] - p0[1]);
  const double t1 = ux * (q1[0] - p0[0]) + uz * (q1[1] - p0[1]);
  const double overlap = fmin(L, fmax(t0, t1)) - fmax(0.0, fmin(t0, t1));
  if (!(overlap > r->tol)) return VS_OK;
  char wa[96], wb[96];
  return fail(r, VS_ERR_INVALID, "%s and %s: edges that overlap only partly: %s's edge %d from "
              "(%g, %g) to (%g, %g) mm and %s's edge %d from (%g, %g) to (%g, %g) mm (allowed: "
              "a whole edge of each, its ends within tolerance_mm = %g of the other's: split the "
              "longer edge at the other's ends)", who(r, i, wa, sizeof wa), who(r, j, wb, sizeof wb),
              A->name, e, p0[0] / VS_MM, p0[1] / VS_MM, p1[0] / VS_MM, p1[1] / VS_MM, B->name, f,
              q0[0] / VS_MM, q0[1] / VS_MM, q1[0] / VS_MM, q1[1] / VS_MM, r->tol / VS_MM);
}

static vs_status find_interfaces(reader *r) {
  for (int i = 0; i < r->np; i++)
    for (int j = i + 1; j < r->np; j++) {
      const poly *A = &r->p[i], *B = &r->p[j];
      if (A->body == B->body || (A->side != 0 && B->side != 0)) continue; /* one body; piers */
      if (A->box[0] > B->box[1] + r->tol || B->box[0] > A->box[1] + r->tol ||
          A->box[2] > B->box[3] + r->tol || B->box[2] > A->box[3] + r->tol)
        continue;
      for (int e = 0; e < A->n; e++)
        for (int f = 0; f < B->n; f++) {
          vs_status st = edge_pair(r, i, e, j, f);
          if (st != VS_OK) return st;
        }
    }
  for (int i = 0; i < r->np; i++) {
    if (r->p[i].side != 0) continue;
    int touches = 0;
    for (int k = 0; k < r->nf && !touches; k++) touches = r->f[k].pa == i || r->f[k].pb == i;
    char w[96];
    if (!touches)
      return fail(r, VS_ERR_INVALID, "%s shares no edge with another block or a support "
                  "(allowed: every block shares a whole edge, its ends within tolerance_mm = %g, "
                  "with another body)", who(r, i, w, sizeof w), r->tol / VS_MM);
  }
  return VS_OK;
}

/* The interface between polygons i and j, or -1. */
static int iface_between(const reader *r, int i, int j) {
  for (int k = 0; k < r->nf; k++)
    if ((r->f[k].pa == i && r->f[k].pb == j) || (r->f[k].pa == j && r->f[k].pb == i)) return k;
  return -1;
}

static int polygon_named(const reader *r, const char *name) {
  for (int i = 0; i < r->np; i++)
    if (strcmp(r->p[i].name, name) == 0) return i;
  return -1;
}

/* The name of array element v, as a polygon, or an error naming where. */
static vs_status named(const reader *r, json_t *v, const char *where, int *out) {
  *out = json_is_string(v) ? polygon_named(r, json_string_value(v)) : -1;
  if (*out < 0)
    return fail(r, VS_ERR_INVALID, "%s: not a block's name (allowed: the name of one of "
                "\"blocks\")", where);
  return VS_OK;
}

/* "interfaces": [{"between": [A, B], "kn_N_mm3", "ks_ratio", "friction"}, ...]. */
static vs_status read_laws(reader *r, json_t *list) {
  static const char *const keys[] = {"between", "kn_N_mm3", "ks_ratio", "friction", NULL};
  if (list == NULL) return VS_OK;
  if (!json_is_array(list))
    return fail(r, VS_ERR_INVALID, "interfaces: not an array (allowed: [{\"between\": [A, B], "
                "\"kn_N_mm3\", \"ks_ratio\", \"friction\"}, ...])");
  for (size_t i = 0; i < json_array_size(list); i++) {
    json_t *o = json_array_get(list, i), *bt = json_object_get(o, "between");
    char where[64], w2[80];
    snprintf(where, sizeof where, "interfaces[%zu]", i);
    vs_status st = json_is_object(o) ? known_keys(r, o, where, keys,
                                                  "between, kn_N_mm3, ks_ratio, friction")
                                     : fail(r, VS_ERR_INVALID, "%s: not an object", where);
    if (st == VS_OK && (!json_is_array(bt) || json_array_size(bt) != 2))
      st = fail(r, VS_ERR_INVALID, "%s.between: not two names (allowed: [A, B], two blocks' "
                "names)", where);
    int a = -1, b = -1;
    snprintf(w2, sizeof w2, "%s.between[0]", where);
    if (st == VS_OK) st = named(r, json_array_get(bt, 0), w2, &a);
    snprintf(w2, sizeof w2, "%s.between[1]", where);
    if (st == VS_OK) st = named(r, json_array_get(bt, 1), w2, &b);
    const int k = st == VS_OK ? iface_between(r, a, b) : -1;
    if (st == VS_OK && k < 0)
      st = fail(r, VS_ERR_INVALID, "%s: \"%s\" and \"%s\" share no edge (allowed: two bodies "
                "that touch)", where, r->p[a].name, r->p[b].name);
    double kn = 0.0, ks = 0.0, mu = 0.0;
    if (st == VS_OK) st = number(r, o, "kn_N_mm3", where, 1e-4, 1e4, 1, 0.0, &kn);
    if (st == VS_OK) st = number(r, o, "ks_ratio", where, 1e-9, 100.0, 1, 0.0, &ks);
    if (st == VS_OK) st = number(r, o, "friction", where, 1e-9, 100.0, 1, 0.0, &mu);
    if (st != VS_OK) return st;
    r->f[k].kn = kn * VS_N_MM3, r->f[k].ks_ratio = ks, r->f[k].mu = mu;
  }
  return VS_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* The ring                                                                                    */

/* The chain the blocks make when no ring is given: from the one left support polygon that
 * touches a block, through blocks each touching the next, to a right support polygon, every
 * block on it. */
static vs_status chain(reader *r) {
  int start = -1, ok = 1;
  for (int k = 0; k < r->nf; k++) {
    const iface *f = &r->f[k];
    const int s = r->p[f->pa].side == VS_SUPPORT_LEFT ? f->pa : r->p[f->pb].side == VS_SUPPORT_LEFT ? f->pb : -1;
    if (s < 0) continue;
    if (start >= 0) ok = 0;
    start = s;
  }
  r->nring = 0;
  if (ok && start >= 0) r->ring[r->nring++] = start;
  for (int prev = -1, cur = start; ok && cur >= 0 && r->p[cur].side != VS_SUPPORT_RIGHT;) {
    int next = -1;
    for (int k = 0; k < r->nf && ok; k++) {
      const iface *f = &r->f[k];
      const int o = f->pa == cur ? f->pb : f->pb == cur ? f->pa : -1;
      if (o < 0 || o == prev || r->p[o].side == VS_SUPPORT_LEFT) continue;
      if (next >= 0) ok = 0;
      next = o;
    }
    if (next < 0 || r->nring > r->nb + 1) ok = 0;
    if (ok) r->ring[r->nring++] = next;
    prev = cur, cur = next;
  }
  if (ok && start >= 0 && r->nring == r->nb + 2) return VS_OK;
  return fail(r, VS_ERR_INVALID, "ring: missing, and the blocks do not make one chain from a "
              "left support to a right one (allowed: \"ring\": [the bodies' names from the left "
              "support, through the arch's blocks, to the right support])");
}

static vs_status read_ring(reader *r, json_t *list) {
  if (list == NULL) return chain(r);
  const size_t n = json_is_array(list) ? json_array_size(list) : 0;
  if (n < 3 || n > (size_t)r->np)
    return fail(r, VS_ERR_INVALID, "ring: %s (allowed: the names of at least 3 bodies, from a "
                "left support through blocks to a right support)", json_is_array(list)
                ? "too short or too long" : "not an array");
  for (size_t i = 0; i < n; i++) {
    char where[32];
    snprintf(where, sizeof where, "ring[%zu]", i);
    int p = -1;
    vs_status st = named(r, json_array_get(list, i), where, &p);
    if (st != VS_OK) return st;
    const int want = i == 0 ? VS_SUPPORT_LEFT : i == n - 1 ? VS_SUPPORT_RIGHT : 0;
    if (r->p[p].side != want)
      return fail(r, VS_ERR_INVALID, "%s: \"%s\" is %s (allowed: %s)", where, r->p[p].name,
                  r->p[p].side == 0 ? "a block" : r->p[p].side == VS_SUPPORT_LEFT
                  ? "the left support" : "the right support", want == 0 ? "a block, not a "
                  "support" : want == VS_SUPPORT_LEFT ? "a left support first" : "a right "
                  "support last");
    for (int j = 0; j < r->nring; j++)
      if (r->ring[j] == p)
        return fail(r, VS_ERR_INVALID, "%s: \"%s\" is in the ring twice (allowed: once)", where,
                    r->p[p].name);
    if (i > 0 && iface_between(r, r->ring[r->nring - 1], p) < 0)
      return fail(r, VS_ERR_INVALID, "%s: \"%s\" and \"%s\" share no edge (allowed: each body "
                  "of the ring touching the next)", where, r->p[r->ring[r->nring - 1]].name,
                  r->p[p].name);
    r->ring[r->nring++] = p;
  }
  return VS_OK;
}

/* ------------------------------------------------------------------------------------------ */
/* The geometry                                                                                */

/* Joint k on interface f, from body a (polygon pa, whose edge it is) to the other. */
static void set_joint(const reader *r, vs_geometry *g, int k, const iface *f, int pa) {
  const poly *A = &r->p[pa];
  const int ea = pa == f->pa ? f->ea : f->eb, pb = pa == f->pa ? f->pb : f->pa;
  const double *p0 = A->p + 2 * ea, *p1 = A->p + 2 * ((ea + 1) % A->n);
  const double dx = p1[0] - p0[0], dz = p1[1] - p0[1], L = hypot(dx, dz);
  vs_joint_geom *j = &g->joints[k];
  j->a = A->body;
  j->b = r->p[pb].body;
  j->px = 0.5 * (p0[0] + p1[0]);
  j->pz = 0.5 * (p0[1] + p1[1]);
  j->nx = dz / L; /* a's outward normal: its outline runs counter-clockwise */
  j->nz = -dx / L;
  j->length = L;
  j->depth = r->a->depth;
  j->kn = f->kn, j->ks_ratio = f->ks_ratio, j->mu = f->mu;
}

/* The blocks with their outlines and mass properties, and the supports' polygons. */
static vs_status set_blocks(const reader *r, vs_geometry *g) {
  vs_edge *e = malloc((size_t)VS_BLOCKS_MAX_VERTICES * sizeof *e);
  vs_status st = e != NULL ? VS_OK : fail(r, VS_ERR_NOMEM, "out of memory");
  for (int i = 0; st == VS_OK && i < r->np; i++) {
    const poly *p = &r->p[i];
    for (int k = 0; k < p->n; k++) {
      const double *a = p->p + 2 * k, *b = p->p + 2 * ((k + 1) % p->n);
      e[k] = (vs_edge){.x0 = a[0], .z0 = a[1], .x1 = b[0], .z1 = b[1], .u1 = 1.0, .joint = -1};
    }
    for (int k = 0; k < r->nf; k++) {
      if (r->f[k].pa == i) e[r->f[k].ea].joint = r->f[k].joint;
      if (r->f[k].pb == i) e[r->f[k].eb].joint = r->f[k].joint;
    }
    if (p->side != 0) {
      st = vs_geometry_add_support(g, p->side, p->n, e, r->err);
      continue;
    }
    st = vs_geometry_set_outline(g, p->body, p->n, e, r->err);
    if (st != VS_OK) break;
    vs_section s;
    vs_outline_section(g->edges + g->blocks[p->body].edge0, p->n, &s);
    vs_block *b = &g->blocks[p->body];
    b->area = s.area;
    b->mass = p->density * r->a->depth * s.area;
    b->inertia = p->density * r->a->depth * s.j;
    b->cx = s.cx, b->cz = s.cz;
  }
  free(e);
  return st;
}

/* The width of the ring's blocks: their leftmost vertex to their rightmost, m. */
static double ring_width(const reader *r) {
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < r->nring; i++) {
    const poly *p = &r->p[r->ring[i]];
    if (p->side != 0) continue;
    lo = fmin(lo, p->box[0]);
    hi = fmax(hi, p->box[1]);
  }
  return hi - lo;
}

/* Span, rise and a typical thickness from the ring's joints: their intrados ends. Springings
 * not apart horizontally (a block pushed sideways on its base, a column) would give a span of
 * 0, by which every displacement is divided (dz/L) and the fall's ground is sized: the ring's
 * blocks' width is the span then. */
static void ring_measures(const reader *r, vs_geometry *g) {
  double zmax = -INFINITY, zl = 0.0, xl = 0.0, zr = 0.0, xr = 0.0, t = 0.0;
  for (int k = 0; k < g->ring; k++) {
    const vs_joint_geom *j = &g->joints[k];
    double sx, sz;
    vs_joint_tangent(j, &sx, &sz);
    const double x = j->px - 0.5 * j->length * sx, z = j->pz - 0.5 * j->length * sz;
    if (k == 0) xl = x, zl = z;
    if (k == g->ring - 1) xr = x, zr = z;
    zmax = fmax(zmax, z);
    t += j->length / g->ring;
  }
  g->span = fabs(xr - xl) > r->tol ? fabs(xr - xl) : ring_width(r);
  g->rise = zmax - fmax(zl, zr);
  g->thickness = t;
}

static vs_status build(reader *r, vs_geometry **out) {
  vs_status st = vs_geometry_create(r->nb, r->nf, out, r->err);
  if (st != VS_OK) return st;
  vs_geometry *g = *out;
  int k = 0;
  for (int i = 1; i < r->nring; i++) { /* the ring's joints first, in its order */
    iface *f = &r->f[iface_between(r, r->ring[i - 1], r->ring[i])];
    f->joint = k;
    set_joint(r, g, k++, f, r->ring[i - 1]);
  }
  for (int i = 0; i < r->nf; i++) /* then the others, as found */
    if (r->f[i].joint < 0) {
      r->f[i].joint = k;
      set_joint(r, g, k++, &r->f[i], r->f[i].pa);
    }
  g->ring = r->nring - 1;
  g->gravity = r->a->gravity;
  st = set_blocks(r, g);
  if (st == VS_OK) ring_measures(r, g);
  return st;
}

/* The top level: format, units, tolerance, blocks, interfaces, ring. */
static vs_status read_root(reader *r, json_t *root) {
  static const char *const keys[] = {"format", "units", "tolerance_mm", "blocks", "interfaces",
                                     "ring", NULL};
  if (!json_is_object(root))
    return fail(r, VS_ERR_INVALID, "not an object (allowed: {\"format\": \"%s\", \"blocks\": "
                "[...], ...})", VS_BLOCKS_FORMAT);
  vs_status st = known_keys(r, root, "the file", keys,
                            "format, units, tolerance_mm, blocks, interfaces, ring");
  json_t *fmt = json_object_get(root, "format"), *units = json_object_get(root, "units");
  if (st == VS_OK && (!json_is_string(fmt) || strcmp(json_string_value(fmt), VS_BLOCKS_FORMAT) != 0))
    st = fail(r, VS_ERR_INVALID, "format: %s (allowed: \"%s\")", fmt == NULL ? "missing"
              : "not this format", VS_BLOCKS_FORMAT);
  if (st == VS_OK && units != NULL && (!json_is_string(units) || strcmp(json_string_value(units), "mm") != 0))
    st = fail(r, VS_ERR_INVALID, "units: not mm (allowed: \"mm\")");
  double tol = VS_BLOCKS_TOL_MM;
  if (st == VS_OK) st = number(r, root, "tolerance_mm", "the file", 1e-9, 1e3, 1, tol, &tol);
  r->tol = tol * VS_MM;
  json_t *blocks = json_object_get(root, "blocks");
  const size_t n = json_is_array(blocks) ? json_array_size(blocks) : 0;
  if (st == VS_OK && (n < 3 || n > VS_BLOCKS_MAX))
    st = fail(r, VS_ERR_INVALID, "blocks: %s (allowed: an array of 3 to %d blocks and supports)",
              blocks == NULL ? "missing" : json_is_array(blocks) ? "too few or too many" : "not an array",
              VS_BLOCKS_MAX);
  if (st != VS_OK) return st;
  r->p = calloc(n, sizeof *r->p);
  r->ring = malloc((n + 1) * sizeof *r->ring);
  if (r->p == NULL || r->ring == NULL) return fail(r, VS_ERR_NOMEM, "out of memory");
  r->np = (int)n;
  for (int i = 0; st == VS_OK && i < r->np; i++) st = read_block(r, i, json_array_get(blocks, (size_t)i));
  if (st != VS_OK) return st;
  int left = 0, right = 0;
  for (int i = 0; i < r->np; i++) {
    poly *p = &r->p[i];
    p->body = p->side != 0 ? p->side : r->nb++;
    left += p->side == VS_SUPPORT_LEFT, right += p->side == VS_SUPPORT_RIGHT;
    set_box(p);
  }
  if (r->nb == 0 || left == 0 || right == 0)
    return fail(r, VS_ERR_INVALID, "blocks: %d blocks, %d left and %d right supports (allowed: "
                "at least one block and one of each support)", r->nb, left, right);
  snap(r);
  for (int i = 0; st == VS_OK && i < r->np; i++) {
    st = check_polygon(r, i);
    set_box(&r->p[i]);
  }
  if (st == VS_OK) st = find_interfaces(r);
  if (st == VS_OK) st = read_laws(r, json_object_get(root, "interfaces"));
  if (st == VS_OK) st = read_ring(r, json_object_get(root, "ring"));
  return st;
}

vs_status vs_blocks_parse(const char *name, const char *text, size_t len, const vs_arch_def *a,
                          vs_geometry **out, vs_error *err) {
  *out = NULL;
  reader r = {.file = name, .a = a, .err = err};
  json_error_t je;
  json_t *root = json_loadb(text, len, JSON_REJECT_DUPLICATES, &je);
  vs_status st = VS_OK;
  char qn[256], qt[256];
  if (root == NULL)
    st = vs_error_set(err, VS_ERR_PARSE, "%s:%d:%d: %s (a blocks file is JSON)",
                      vs_quote(name, qn, sizeof qn), je.line, je.column,
                      vs_quote(je.text, qt, sizeof qt));
  if (st == VS_OK) st = read_root(&r, root);
  if (st == VS_OK) st = build(&r, out);
  if (st != VS_OK) vs_geometry_destroy(out);
  json_decref(root);
  for (int i = 0; i < r.np; i++) free(r.p[i].p);
  free(r.p), free(r.f), free(r.ring);
  return st;
}

vs_status vs_blocks_read(const vs_arch_def *a, vs_geometry **out, vs_error *err) {
  *out = NULL;
  const char *path = a->blocks_file;
  if (path[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "arch.shape = file: no arch.blocks_file (allowed: "
                        "the JSON file of blocks)");
  char q[256];
  vs_quote(path, q, sizeof q);
  int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY);
  if (fd < 0)
    return vs_error_set(err, VS_ERR_IO, "arch.blocks_file %s: cannot open: %s", q,
                        strerror(errno));
  struct stat sb;
  vs_status st = VS_OK;
  if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || sb.st_size > VS_BLOCKS_MAX_BYTES)
    st = vs_error_set(err, VS_ERR_IO, "arch.blocks_file %s: not a regular file of at most %d "
                      "bytes", q, VS_BLOCKS_MAX_BYTES);
  char *text = st == VS_OK ? malloc((size_t)sb.st_size + 1) : NULL;
  size_t used = 0;
  if (st == VS_OK && text == NULL) st = vs_error_set(err, VS_ERR_NOMEM, "out of memory");
  while (st == VS_OK && used < (size_t)sb.st_size) {
    const ssize_t n = read(fd, text + used, (size_t)sb.st_size - used);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      st = vs_error_set(err, VS_ERR_IO, "arch.blocks_file %s: cannot read: %s", q,
                        n < 0 ? strerror(errno) : "it shrank");
      break;
    }
    used += (size_t)n;
  }
  close(fd);
  if (st == VS_OK) st = vs_blocks_parse(path, text, used, a, out, err);
  free(text);
  return st;
}

/* ------------------------------------------------------------------------------------------ */
/* Writing                                                                                     */

static json_t *vertex(double x, double z) {
  return json_pack("[f, f]", x / VS_MM, z / VS_MM);
}

/* Block i's outline as a polygon: each segment its start, each curved edge its start and points
 * every 2 degrees of its turn (6 segments at most). */
static json_t *block_polygon(const vs_geometry *g, int i) {
  const vs_block *b = &g->blocks[i];
  json_t *pts = json_array();
  for (int k = 0; pts != NULL && k < b->n_edges; k++) {
    const vs_edge *e = &g->edges[b->edge0 + k];
    const int m = e->curved ? (int)fmin(6.0, fmax(1.0, ceil(vs_edge_turn(e) / (2.0 * VS_DEG) - 1e-9))) : 1;
    for (int j = 0; j < m; j++) {
      double p[2] = {e->x0, e->z0};
      if (j > 0) vs_edge_eval(e, e->u0 + (e->u1 - e->u0) * j / m, p, NULL);
      json_array_append_new(pts, vertex(p[0], p[1]));
    }
  }
  return pts;
}

/* A pier under springing joint k (its face's ends from the block's outline: the face edge of
 * joint k), counter-clockwise: the face, a level top outward, an outer vertical, a base two
 * thicknesses below the face's lower end, an inner vertical. */
static json_t *pier_polygon(const vs_geometry *g, int k, int block) {
  const vs_block *b = &g->blocks[block];
  const vs_joint_geom *j = &g->joints[k];
  double in[2] = {0, 0}, ex[2] = {0, 0}, sx, sz;
  vs_joint_tangent(j, &sx, &sz);
  for (int e = 0; e < b->n_edges; e++) {
    const vs_edge *ed = &g->edges[b->edge0 + e];
    if (ed->joint != k) continue;
    const double t0 = (ed->x0 - j->px) * sx + (ed->z0 - j->pz) * sz;
    const double t1 = (ed->x1 - j->px) * sx + (ed->z1 - j->pz) * sz;
    in[0] = t0 < t1 ? ed->x0 : ed->x1, in[1] = t0 < t1 ? ed->z0 : ed->z1;
    ex[0] = t0 < t1 ? ed->x1 : ed->x0, ex[1] = t0 < t1 ? ed->z1 : ed->z0;
  }
  const double t = g->thickness, out = ex[0] < in[0] ? -1.0 : 1.0;
  const double xo = ex[0] + out * 1.5 * t, zb = fmin(in[1], ex[1]) - 2.0 * t;
  const double v[5][2] = {{in[0], in[1]}, {ex[0], ex[1]}, {xo, ex[1]}, {xo, zb}, {in[0], zb}};
  double area = 0.0;
  for (int i = 0; i < 5; i++)
    area += v[i][0] * v[(i + 1) % 5][1] - v[(i + 1) % 5][0] * v[i][1];
  json_t *pts = json_array();
  for (int i = 0; pts != NULL && i < 5; i++) {
    const int s = area > 0.0 ? i : 4 - i;
    json_array_append_new(pts, vertex(v[s][0], v[s][1]));
  }
  return pts;
}

/* jansson's text of v, one line (15 significant digits: a shared vertex is the same text). */
static char *line(const json_t *v) {
  return json_dumps(v, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(15) |
                           JSON_ENCODE_ANY);
}

/* root's text with each member on its own line and each element of an array member on its own
 * line, for a reader to edit; NULL when out of memory. */
static char *dump(const json_t *root) {
  size_t cap = 4096, used = 0;
  char *out = malloc(cap);
  const char *key;
  json_t *v;
  int first = 1, ok = out != NULL;
#define PUT(s)                                                                                   \
  do {                                                                                           \
    const char *s_ = (s);                                                                        \
    const size_t n_ = s_ != NULL ? strlen(s_) : 0;                                               \
    if (s_ == NULL) ok = 0;                                                                      \
    while (ok && used + n_ + 1 > cap) {                                                          \
      char *b_ = realloc(out, 2 * cap);                                                          \
      if (b_ == NULL) ok = 0;                                                                    \
      else out = b_, cap *= 2;                                                                   \
    }                                                                                            \
    if (ok) memcpy(out + used, s_, n_ + 1), used += n_;                                          \
  } while (0)
  PUT("{");
  json_object_foreach((json_t *)root, key, v) {
    json_t *k = json_string(key);
    char *ks = k != NULL ? line(k) : NULL;
    PUT(first ? "\n " : ",\n ");
    PUT(ks);
    PUT(": ");
    free(ks);
    json_decref(k);
    first = 0;
    if (!json_is_array(v) || strcmp(key, "ring") == 0) {
      char *vs = line(v);
      PUT(vs);
      free(vs);
      continue;
    }
    PUT("[");
    for (size_t i = 0; i < json_array_size(v); i++) {
      char *es = line(json_array_get(v, i));
      PUT(i == 0 ? "\n  " : ",\n  ");
      PUT(es);
      free(es);
    }
    PUT("\n ]");
  }
  PUT("\n}");
#undef PUT
  if (!ok) free(out);
  return ok ? out : NULL;
}

/* Support polygon s as written: "left support 1", "right support 2" (counted per side). */
static void support_name(const vs_geometry *g, int s, char *buf, size_t size) {
  int nth = 0;
  for (int i = 0; i <= s; i++) nth += g->supports[i].body == g->supports[s].body;
  snprintf(buf, size, "%s support %d", g->supports[s].body == VS_SUPPORT_LEFT ? "left" : "right",
           nth);
}

/* The name body (of joint k) is written under: a block's "vN"; a support's polygon that holds
 * joint k's face, or the pier written under a springing face. */
static void body_name(const vs_geometry *g, int k, int body, char *buf, size_t size) {
  if (body >= 0) {
    snprintf(buf, size, "v%d", body + 1);
    return;
  }
  snprintf(buf, size, "%s pier", body == VS_SUPPORT_LEFT ? "left" : "right");
  for (int s = 0; s < g->n_supports; s++)
    for (int e = 0; e < g->supports[s].n_edges; e++)
      if (g->supports[s].body == body && g->edges[g->supports[s].edge0 + e].joint == k) {
        support_name(g, s, buf, size);
        return;
      }
}

static json_t *support_polygon(const vs_geometry *g, int s) {
  const vs_support_outline *o = &g->supports[s];
  json_t *pts = json_array();
  for (int e = 0; pts != NULL && e < o->n_edges; e++)
    json_array_append_new(pts, vertex(g->edges[o->edge0 + e].x0, g->edges[o->edge0 + e].z0));
  return pts;
}

/* Joint k's own law, as an entry of "interfaces" (NULL: it has none). */
static json_t *own_law(const vs_geometry *g, int k) {
  const vs_joint_geom *j = &g->joints[k];
  if (!(j->kn > 0.0 || j->ks_ratio > 0.0 || j->mu > 0.0)) return NULL;
  char a[32], b[32];
  body_name(g, k, j->a, a, sizeof a);
  body_name(g, k, j->b, b, sizeof b);
  json_t *o = json_pack("{s:[s, s]}", "between", a, b);
  if (j->kn > 0.0) json_object_set_new(o, "kn_N_mm3", json_real(j->kn / VS_N_MM3));
  if (j->ks_ratio > 0.0) json_object_set_new(o, "ks_ratio", json_real(j->ks_ratio));
  if (j->mu > 0.0) json_object_set_new(o, "friction", json_real(j->mu));
  return o;
}

/* The ring of an arch on piers (geometry.h: pier_courses > 0): the left foundation, the left
 * pier's courses up, the voussoirs, the right pier's courses down, the right foundation. */
static void ring_on_piers(const vs_geometry *g, json_t *ring) {
  char name[32];
  const int C = g->pier_courses;
  body_name(g, g->pier_joint[0], VS_SUPPORT_LEFT, name, sizeof name);
  json_array_append_new(ring, json_string(name));
  for (int i = 0; i < g->n_blocks; i++) {
    const int b = i < C                       ? g->pier_block[0] + i
                  : i < g->pier_block[0] + C ? i - C
                                             : g->pier_block[1] + (g->n_blocks - 1 - i);
    snprintf(name, sizeof name, "v%d", b + 1);
    json_array_append_new(ring, json_string(name));
  }
  body_name(g, g->pier_joint[1], VS_SUPPORT_RIGHT, name, sizeof name);
  json_array_append_new(ring, json_string(name));
}

vs_status vs_geometry_blocks_json(const vs_geometry *g, char **text, vs_error *err) {
  *text = NULL;
  const int kl = vs_geometry_support_joint(g, 0), kr = vs_geometry_support_joint(g, 1);
  const vs_joint_geom *jl = &g->joints[kl], *jr = &g->joints[kr];
  for (int i = 0; i < g->n_blocks; i++)
    if (g->blocks[i].n_edges < 1)
      return vs_error_set(err, VS_ERR_INVALID, "blocks file: block %d has no outline", i + 1);
  if (jl->a != VS_SUPPORT_LEFT || jl->b < 0 || jr->b != VS_SUPPORT_RIGHT || jr->a < 0)
    return vs_error_set(err, VS_ERR_INVALID, "blocks file: the springing joints are not between "
                        "a block and a support");
  json_t *root = json_object(), *blocks = json_array(), *ring = json_array(), *laws = json_array();
  json_object_set_new(root, "format", json_string(VS_BLOCKS_FORMAT));
  json_object_set_new(root, "units", json_string("mm"));
  json_object_set_new(root, "tolerance_mm", json_real(VS_BLOCKS_TOL_MM));
  for (int s = 0; s < g->n_supports; s++) { /* a blocks file's own supports */
    char name[32];
    support_name(g, s, name, sizeof name);
    json_array_append_new(blocks, json_pack("{s:s, s:s, s:o}", "name", name, "support",
                                            g->supports[s].body == VS_SUPPORT_LEFT ? "left"
                                                                                   : "right",
                                            "polygon", support_polygon(g, s)));
  }
  if (g->n_supports == 0) /* or a pier under each springing face */
    for (int side = 0; side < 2; side++)
      json_array_append_new(blocks, json_pack("{s:s, s:s, s:o}", "name", side ? "right pier"
                                              : "left pier", "support", side ? "right" : "left",
                                              "polygon", side ? pier_polygon(g, kr, jr->a)
                                                              : pier_polygon(g, kl, jl->b)));
  for (int i = 0; i < g->n_blocks; i++) {
    char name[32];
    snprintf(name, sizeof name, "v%d", i + 1);
    const vs_block *b = &g->blocks[i];
    const double rho = b->mass / (b->area * g->joints[0].depth);
    json_array_append_new(blocks, json_pack("{s:s, s:f, s:o}", "name", name, "density_kg_m3",
                                            rho, "polygon", block_polygon(g, i)));
  }
  if (g->pier_courses > 0) ring_on_piers(g, ring);
  for (int k = 0; k <= kr && g->pier_courses == 0; k++) { /* the ring: its joints' bodies */
    char name[32];
    body_name(g, k, k == 0 ? VS_SUPPORT_LEFT : g->joints[k].a, name, sizeof name);
    json_array_append_new(ring, json_string(name));
    if (k == kr) {
      body_name(g, k, VS_SUPPORT_RIGHT, name, sizeof name);
      json_array_append_new(ring, json_string(name));
    }
  }
  for (int k = 0; k < g->n_joints; k++) {
    json_t *o = own_law(g, k);
    if (o != NULL) json_array_append_new(laws, o);
  }
  json_object_set_new(root, "blocks", blocks);
  if (json_array_size(laws) > 0) json_object_set_new(root, "interfaces", laws);
  else json_decref(laws);
  json_object_set_new(root, "ring", ring);
  *text = dump(root);
  json_decref(root);
  if (*text == NULL) return vs_error_set(err, VS_ERR_NOMEM, "blocks file: out of memory");
  return VS_OK;
}
