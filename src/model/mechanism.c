/* The hinges a motion turns about, from the relative rotation rates of the joints' bodies. */
#include "mechanism.h"

#include <math.h>
#include <string.h>

/* The rotation rate (rad/s) of support right (0 left, 1 right): its pinned rotation's velocity,
 * or the rate of its prescribed rotation (a forward difference of its motion, which is linear
 * in delta between kinks). */
static double support_rate(const vs_model *m, int right, const double *v, double delta,
                           double ddelta) {
  const int dof = vs_model_support_dof(m, right);
  if (dof >= 0) return v[dof];
  if (ddelta == 0.0) return 0.0;
  const double h = 1e-9 + 1e-9 * fabs(delta);
  double u0[6], u1[6];
  vs_model_support_position(m, NULL, delta, u0);
  vs_model_support_position(m, NULL, delta + h, u1);
  const int i = right ? 5 : 2;
  return (u1[i] - u0[i]) / h * ddelta;
}

static double body_rate(int body, const double *v, const double sup[2]) {
  if (body == VS_SUPPORT_LEFT) return sup[0];
  if (body == VS_SUPPORT_RIGHT) return sup[1];
  return v[3 * body + 2];
}

void vs_mechanism_joint_rates(const vs_model *m, const double *v, double delta, double ddelta,
                              double *w) {
  const vs_geometry *g = vs_model_geometry(m);
  const double sup[2] = {support_rate(m, 0, v, delta, ddelta), support_rate(m, 1, v, delta, ddelta)};
  for (int k = 0; k < g->n_joints; k++)
    w[k] = body_rate(g->joints[k].b, v, sup) - body_rate(g->joints[k].a, v, sup);
}

int vs_mechanism_active(int n, const double *w, const vs_joint_state *st,
                        const vs_hinge_opts *opts, vs_active_hinge *out) {
  double wmax = 0.0;
  for (int k = 0; k < n; k++) wmax = fmax(wmax, fabs(w[k]));
  if (!(wmax > 0.0)) return 0;
  /* the groups: runs of turning joints of one sense */
  int ng = 0;
  double gmax = 0.0;
  for (int k = 0; k < n;) {
    if (!(fabs(w[k]) >= VS_MECH_JOINT_SHARE * wmax)) {
      k++;
      continue;
    }
    const int sense = w[k] > 0.0;
    int e = k;
    double rate = w[k];
    while (e + 1 < n && fabs(w[e + 1]) >= VS_MECH_JOINT_SHARE * wmax && (w[e + 1] > 0.0) == sense)
      rate += w[++e];
    vs_active_hinge *a = &out[ng++];
    memset(a, 0, sizeof *a);
    a->first = k + 1;
    a->last = e + 1;
    a->rate = rate;
    double peak = 0.0;
    for (int j = k; j <= e; j++) peak = fmax(peak, fabs(w[j]));
    a->share = peak / wmax; /* (until the hinges are kept) */
    double best = -1.0; /* the most turning open joint gives the side */
    for (int j = k; j <= e; j++) {
      const char s = vs_hinges_joint_side(opts, &st[j]);
      if (s != 0 && fabs(w[j]) > best) {
        best = fabs(w[j]);
        a->side = s;
      }
    }
    a->open = a->side != 0;
    if (!a->open) a->side = rate > 0.0 ? 'E' : 'I';
    gmax = fmax(gmax, fabs(rate));
    k = e + 1;
  }
  /* the hinges: groups of a sizeable rate, same-side neighbours merged */
  int na = 0;
  for (int i = 0; i < ng; i++) {
    const vs_active_hinge g = out[i];
    if (g.open ? !(fabs(g.rate) >= VS_MECH_OPEN_SHARE * gmax)
               : !(g.share >= VS_MECH_CLOSED_SHARE))
      continue;
    vs_active_hinge *p = na > 0 ? &out[na - 1] : NULL;
    if (p != NULL && p->side == g.side && g.first - p->last <= opts->migrate) {
      p->last = g.last;
      p->rate += g.rate;
      p->open |= g.open;
      continue;
    }
    out[na++] = g;
  }
  double hmax = 0.0;
  for (int i = 0; i < na; i++) hmax = fmax(hmax, fabs(out[i].rate));
  for (int i = 0; i < na; i++) {
    vs_active_hinge *a = &out[i];
    a->share = hmax > 0.0 ? fabs(a->rate) / hmax : 0.0;
    /* turning against its opening: an 'I' hinge (extrados open) turning as an 'E' one */
    a->closing = a->open && ((a->side == 'I') == (a->rate > 0.0));
  }
  return na;
}
