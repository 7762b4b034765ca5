/* Hinge onsets located on the quasi-static path: between two accepted equilibria, the support
 * displacements at which joint edges open or close, bracketed to limit_tol by re-solving the
 * equilibrium (secant predictions of the crossing from the edges' gaps, bisection after a miss). */
#include "quasistatic_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Which joint edges are open (gap > open) at (q, delta): 2 flags per joint, and each edge's
 * gap minus the opening (gap, m; may be NULL). */
static void edge_flags(const vs_qs_solver *s, const double *q, double delta, vs_joint_state *js,
                       unsigned char *fl, double *gap) {
  const int nj = vs_model_geometry(s->m)->n_joints;
  vs_model_joint_states(s->m, q, delta, js);
  for (int k = 0; k < nj; k++) {
    fl[2 * k] = js[k].gap_i > s->o->open;
    fl[2 * k + 1] = js[k].gap_e > s->o->open;
    if (gap == NULL) continue;
    gap[2 * k] = js[k].gap_i - s->o->open;
    gap[2 * k + 1] = js[k].gap_e - s->o->open;
  }
}

/* The first crossing of an edge in (a, b) predicted from the gaps there (linear in delta), for
 * the edges whose flags differ; b if none crosses between. */
static double predict_crossing(int ne, const unsigned char *fa, const unsigned char *fb,
                               const double *ga, const double *gb, double a, double b) {
  double x = b;
  for (int e = 0; e < ne; e++)
    if (fa[e] != fb[e] && ga[e] != gb[e]) {
      const double f = ga[e] / (ga[e] - gb[e]);
      if (f > 0.0 && f < 1.0) x = fmin(x, a + f * (b - a));
    }
  return x;
}

/* Workspace of a location: joint states, flags and gaps at both ends and at a trial point. */
typedef struct {
  vs_joint_state *js;
  unsigned char *fa, *fb, *fm;
  double *ga, *gb, *gm;
  double *qa, *qb, *qm;
} locate_ws;

/* Shrink the bracket (a, b) -- edges fa at a, other ones at b -- around the first crossing to
 * limit_tol. Each trial solves the equilibrium at a point x from the interpolated states and
 * moves a or b there as bisection would; x is the crossing predicted from the gaps at the two
 * ends (a secant step) offset by half the tolerance, below it and then above it, so that a
 * smooth gap is bracketed in two solves; after a prediction that missed, one bisection step.
 * Returns 0, or 1 if a solve failed. */
static int bracket_crossing(vs_qs_solver *s, int n, int ne, locate_ws *w, double *a, double *b) {
  const double tol = s->o->limit_tol;
  int bisect = 0, side = 0;
  while (*b - *a > tol) {
    double x = 0.5 * (*a + *b);
    if (!bisect) {
      const double c = predict_crossing(ne, w->fa, w->fb, w->ga, w->gb, *a, *b);
      x = side == 0 ? c - 0.5 * tol : c + 0.5 * tol; /* below the crossing first, then above */
      x = fmin(fmax(x, *a + 0.25 * tol), *b - 0.25 * tol);
    }
    const double f = (x - *a) / (*b - *a);
    for (int i = 0; i < n; i++) w->qm[i] = w->qa[i] + f * (w->qb[i] - w->qa[i]);
    long it = 0;
    if (vs_qs_solve(s, x, w->qm, &it) != 0) return 1;
    edge_flags(s, w->qm, x, w->js, w->fm, w->gm);
    const int below = memcmp(w->fm, w->fa, (size_t)ne) == 0;
    double *q = below ? w->qa : w->qb, *g = below ? w->ga : w->gb;
    unsigned char *fl = below ? w->fa : w->fb;
    if (below) *a = x;
    else *b = x;
    memcpy(q, w->qm, (size_t)n * sizeof *q);
    memcpy(g, w->gm, (size_t)ne * sizeof *g);
    memcpy(fl, w->fm, (size_t)ne);
    /* a prediction that missed the crossing by more than half the tolerance (the gap is not
     * linear in delta there): bisect once before the next one */
    const int miss = !bisect && (side == 0) != below;
    bisect = miss;
    side = !miss && below; /* just below the crossing: close the bracket from above */
  }
  return 0;
}

/* Hinge onsets located on the path: between the accepted equilibria (qa, a) and (qb, b), find
 * (bracket_crossing: re-solving equilibria from the linear interpolation of the two bracketing
 * states, with the slips committed at a) the first delta at which any edge changes between open
 * and closed, to limit_tol; pass the equilibria on both sides of it to step_fn; then the next one
 * after it, until the edges are those at b. The onsets the hinge tracker interpolates between
 * consecutive equilibria are then within limit_tol of the crossing, and the joints it sees open
 * are those of the crossing, whatever the increment. Returns non-zero if step_fn asked to stop.
 * A location whose Newton fails ends it (the tracker then interpolates over what is left). */
int vs_qs_locate_edges(vs_qs_solver *s, const double *qa0, double a0, const double *qb0,
                       double b0, vs_path_step_fn step_fn, void *user, double *work,
                       long *located) {
  const int n = s->n, nj = vs_model_geometry(s->m)->n_joints, ne = 2 * nj;
  locate_ws w = {.js = malloc((size_t)nj * sizeof *w.js), .fa = malloc((size_t)(4 * ne)),
                 .ga = malloc(4 * (size_t)ne * sizeof(double)), .qa = work, .qb = work + n,
                 .qm = work + 2 * n};
  if (w.js == NULL || w.fa == NULL || w.ga == NULL) {
    free(w.js);
    free(w.fa);
    free(w.ga);
    return 0;
  }
  unsigned char *fb0 = w.fa + 3 * ne;
  double *gb0 = w.ga + 3 * ne;
  w.fb = w.fa + ne, w.fm = w.fa + 2 * ne;
  w.gb = w.ga + ne, w.gm = w.ga + 2 * ne;
  memcpy(w.qa, qa0, (size_t)n * sizeof *w.qa);
  double a = a0;
  edge_flags(s, w.qa, a, w.js, w.fa, w.ga);
  edge_flags(s, qb0, b0, w.js, fb0, gb0);
  int stop = 0;
  for (int found = 0; !stop && found < ne && memcmp(w.fa, fb0, (size_t)ne) != 0; found++) {
    double b = b0;
    memcpy(w.qb, qb0, (size_t)n * sizeof *w.qb);
    memcpy(w.fb, fb0, (size_t)ne);
    memcpy(w.gb, gb0, (size_t)ne * sizeof *w.gb);
    if (bracket_crossing(s, n, ne, &w, &a, &b) != 0 || b >= b0)
      break; /* a failed solve, or the crossing is at the end of the increment */
    stop = step_fn(user, a, w.qa, s->m) != 0 || step_fn(user, b, w.qb, s->m) != 0;
    *located += 2;
    a = b;
    memcpy(w.qa, w.qb, (size_t)n * sizeof *w.qa);
    memcpy(w.fa, w.fb, (size_t)ne);
    memcpy(w.ga, w.gb, (size_t)ne * sizeof *w.ga);
  }
  free(w.js);
  free(w.fa);
  free(w.ga);
  return stop;
}

