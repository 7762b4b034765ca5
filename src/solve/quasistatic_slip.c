/* Slip on the quasi-static path: the joints whose Coulomb limit an increment crosses, the
 * tangent with them on their sliding branch (a joint at the limit that goes on loading slides:
 * its shear follows mu N, no longer its elastic spring), the increment predicted on it, and the
 * limit point at the onset of slip, where the sticking tangent is regular but the sliding one
 * is not: a corner of the path, no fold, which the path ends on as on a limit point. */
#include "quasistatic_internal.h"

#include <math.h>
#include <string.h>

/* A joint's shear as a fraction of its Coulomb limit, |T_trial| / (mu N), from its state with
 * the committed slip (T is the trial force unless the joint slides); 0 when open. */
static double slip_ratio(const vs_model *m, int k, const vs_joint_state *st) {
  if (!(st->N > 0.0)) return 0.0;
  const vs_joint_law *law = vs_model_joint_law(m, k);
  return st->sliding ? 1.0 : fabs(st->T) / (law->mu * st->N);
}

int vs_qs_slip_onsets(vs_qs_solver *s, const double *q0, double d0, const double *q1, double d1,
                      double *frac) {
  const int nj = vs_model_geometry(s->m)->n_joints;
  vs_joint_state *a = s->js, *b = s->js + nj;
  vs_model_joint_states(s->m, q0, d0, a);
  vs_model_joint_states(s->m, q1, d1, b);
  int n = 0;
  double f = 1.0;
  for (int k = 0; k < nj; k++) {
    const int starts = b[k].sliding && b[k].N > 0.0 && !(a[k].sliding && a[k].N > 0.0);
    s->onset[k] = (signed char)(!starts ? 0 : b[k].T > 0.0 ? 1 : -1);
    if (!starts) continue;
    n++;
    const double r0 = slip_ratio(s->m, k, &a[k]);
    const double r1 = fabs(b[k].T) / (vs_model_joint_law(s->m, k)->mu * b[k].N); /* > 1 */
    if (r1 > r0) f = fmin(f, fmax(0.0, (1.0 - r0) / (r1 - r0)));
    else f = 0.0;
  }
  if (frac != NULL) *frac = f;
  return n;
}

/* Put the joints on the branches in branch (vs_model_set_branches) at (q, delta), the committed
 * slips kept in s->slips for branch_off; returns how many were put. */
static int branch_on(vs_qs_solver *s, const double *q, double delta, const signed char *branch) {
  const int nj = vs_model_geometry(s->m)->n_joints;
  memcpy(s->slips, vs_model_slips(s->m), (size_t)nj * sizeof *s->slips);
  return vs_model_set_branches(s->m, q, delta, branch);
}

/* The committed slips back as branch_on found them. */
static void branch_off(vs_qs_solver *s) { vs_model_set_slips(s->m, s->slips); }

/* The path tangent at (q, delta) into tan with the joints on the branches in branch: the tangent
 * stiffness and the support's load dG/ddelta both on them. 0, else -1 (none put, or a solve
 * failed); the committed slips are left as they were. */
static int branch_tangent(vs_qs_solver *s, const double *q, double delta,
                          const signed char *branch, double *tan) {
  int sign = 0;
  int rc = branch_on(s, q, delta, branch) > 0 ? 0 : -1;
  if (rc == 0 && (vs_qs_tangent_factor(s, q, delta, &sign) != 0 ||
                  vs_qs_path_tangent(s, q, delta, tan) != 0))
    rc = -1;
  branch_off(s);
  return rc;
}

int vs_qs_slide_predictor(vs_qs_solver *s, const double *q, double delta, double h,
                          const double *tan, double *qpred) {
  double f = 1.0, *ts = s->fwork;
  for (int i = 0; i < s->n; i++) qpred[i] = q[i] + h * tan[i];
  if (vs_qs_slip_onsets(s, q, delta, qpred, delta + h, &f) == 0 ||
      branch_tangent(s, q, delta, s->onset, ts) != 0)
    return -1;
  /* sticking up to the onset (the fraction f of the increment), sliding beyond */
  for (int i = 0; i < s->n; i++) qpred[i] = q[i] + h * (f * tan[i] + (1.0 - f) * ts[i]);
  return 0;
}

int vs_qs_slip_corner(vs_qs_solver *s, const double *q, double delta, double delta_fail,
                      const double *tan, double *work, vs_limit_evidence *ev) {
  for (int i = 0; i < s->n; i++) work[i] = q[i] + (delta_fail - delta) * tan[i];
  const int n = vs_qs_slip_onsets(s, q, delta, work, delta_fail, NULL);
  if (n == 0) return 0;
  int sign = 0;
  if (branch_on(s, q, delta, s->onset) == 0 || vs_qs_tangent_factor(s, q, delta, &sign) != 0 ||
      vs_spd_test(s->spd, s->Jt) == 1) {
    branch_off(s); /* the sliding branch is stable: no corner */
    return 0;
  }
  ev->det_sign = sign;
  ev->slip_onset = n;
  for (int k = vs_model_geometry(s->m)->n_joints - 1; k >= 0; k--)
    if (s->onset[k]) ev->slip_joint = k;
  return n;
}

/* Passes of vs_qs_loading_tangent at most: sticking one joint may turn back another. */
static const int VS_LOADING_PASSES = 4;

int vs_qs_loading_tangent(vs_qs_solver *s, const double *q, double delta, double h,
                          double *tan) {
  vs_model *const m = s->m;
  const int nj = vs_model_geometry(m)->n_joints;
  vs_joint_state *a = s->js, *b = s->js + nj;
  double *qp = s->fwork;
  signed char *branch = s->onset;
  memset(branch, 0, (size_t)nj);
  vs_model_joint_states(m, q, delta, a);
  int stuck = 0;
  for (int pass = 0; pass < VS_LOADING_PASSES; pass++) {
    for (int i = 0; i < s->n; i++) qp[i] = q[i] + h * tan[i];
    vs_model_joint_states(m, qp, delta + h, b);
    int more = 0;
    for (int k = 0; k < nj; k++)
      if (branch[k] == VS_BRANCH_KEEP && a[k].sliding && a[k].N > 0.0 &&
          (b[k].slip - a[k].slip) * a[k].T < 0.0) { /* its slip turned back: it unloads */
        branch[k] = VS_BRANCH_STICK;
        more++;
      }
    if (more == 0) break;
    stuck += more;
    if (branch_tangent(s, q, delta, branch, qp) != 0) break; /* keep the tangent as it was */
    memcpy(tan, qp, (size_t)s->n * sizeof *tan);
  }
  return stuck;
}
