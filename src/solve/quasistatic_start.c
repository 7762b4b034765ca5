/* The quasi-static path's starting equilibrium: self-weight with the supports in place (by
 * continuation in the gravity factor when Newton fails from the reference configuration), an
 * imperfect arch's misfit by continuation in its factor, or the state a snap-through settled in;
 * accepted when stable. */
#include "quasistatic_internal.h"

#include <kinsol/kinsol.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "voussoir/units.h"

/* Self-weight continuation: largest and smallest increments of the gravity factor. */
static const double VS_RAMP_STEP = 0.25;
static const double VS_RAMP_MIN = 1e-4;
static const long VS_RAMP_MAXITER = 200;
static const long VS_MISFIT_MAXITER = 25; /* Newton iterations per step of the misfit ramp */

/* The misfit of an imperfect arch (vs_model_set_misfit_scale) by continuation in its factor,
 * from the self-weight equilibrium on nominal faces: increments halve when Newton fails or the
 * state is not stable. Returns 0 when the factor 1 is reached (q holds the equilibrium), else -1
 * with *reached the largest factor that had an equilibrium. */
static int misfit_ramp(vs_qs_solver *s, double *q, double *reached) {
  const size_t bytes = (size_t)s->n * sizeof(double);
  double *qt = malloc(bytes), *qp = malloc(bytes), lam = 0.0, lam_prev = 0.0, h = VS_RAMP_STEP;
  int ok = -1;
  if (qt == NULL || qp == NULL) goto done;
  memcpy(qp, q, bytes);
  /* many joints touch on small wedges: Newton is slow far from the solution, so the factor
   * advances by short steps from a secant predictor rather than by long Newton solves */
  KINSetNumMaxIters(s->kin, VS_MISFIT_MAXITER);
  for (;;) {
    const double next = fmin(1.0, lam + h);
    const double r = lam > lam_prev ? (next - lam) / (lam - lam_prev) : 0.0;
    for (int i = 0; i < s->n; i++) qt[i] = q[i] + r * (q[i] - qp[i]);
    vs_model_set_misfit_scale(s->m, next);
    if (vs_qs_solve(s, 0.0, qt, NULL) == 0 && vs_qs_stable_state(s, qt, 0.0)) {
      memcpy(qp, q, bytes);
      memcpy(q, qt, bytes);
      lam_prev = lam;
      lam = next;
      if (lam >= 1.0) {
        ok = 0;
        break;
      }
      h = fmin(2.0 * h, VS_RAMP_STEP);
    } else if (s->interrupted || s->nonfinite || (h *= 0.5) < VS_RAMP_MIN) {
      break;
    }
  }
done:
  KINSetNumMaxIters(s->kin, s->o->newton_maxiter);
  vs_model_set_misfit_scale(s->m, ok == 0 ? 1.0 : lam);
  *reached = lam;
  free(qt);
  free(qp);
  return ok;
}

/* Self-weight by continuation in the gravity factor lambda: the reference configuration is the
 * exact equilibrium at lambda = 0; lambda grows by increments that halve when Newton fails (tangent
 * predictor dq/dlambda = -K^-1 dG/dlambda). Returns 0 when lambda = 1 is reached (q holds the
 * equilibrium), else -1 with *lambda_max the largest factor that had an equilibrium and *slides
 * the joints that the last step's predictor took past their Coulomb limit (flagged in
 * s->onset): the weight would make them slide. */
static int gravity_ramp(vs_qs_solver *s, double *q, double *lambda_max, int *slides) {
  vs_model *m = s->m;
  const size_t bytes = (size_t)s->n * sizeof(double);
  double *qt = malloc(bytes), lam = 0.0, h = VS_RAMP_STEP;
  N_Vector b = s->w1, x = s->w2; /* vs_qs_solve and vs_qs_stable_state do not use them */
  int ok = -1;
  *slides = 0;
  if (qt == NULL) goto done;
  memset(q, 0, bytes);
  /* the contact pattern is found at any load level alike (the no-tension law is homogeneous):
   * the ramp's solves may take many iterations */
  KINSetNumMaxIters(s->kin, VS_RAMP_MAXITER);
  for (;;) {
    const double next = fmin(1.0, lam + h);
    /* predictor: dG/dlambda is the weight on the vertical equations */
    vs_model_set_gravity_scale(m, lam);
    int sign = 0;
    int have_tangent = vs_qs_tangent_factor(s, q, 0.0, &sign) == 0;
    if (have_tangent) {
      double *pb = N_VGetArrayPointer(b);
      vs_model_residual_scale(m, pb); /* weights on 3i, 3i+1 */
      for (int i = 0; i < s->n; i++) pb[i] = (i < s->nb3 && i % 3 == 1) ? -pb[i] : 0.0;
      have_tangent = vs_qs_tangent_solve(s, x, b) == 0;
    }
    for (int i = 0; i < s->n; i++)
      qt[i] = q[i] + (have_tangent ? (next - lam) * N_VGetArrayPointer(x)[i] : 0.0);
    vs_model_set_gravity_scale(m, next);
    if (vs_qs_solve(s, 0.0, qt, NULL) == 0 && vs_qs_stable_state(s, qt, 0.0)) {
      memcpy(q, qt, bytes);
      lam = next;
      if (lam >= 1.0) {
        ok = 0;
        break;
      }
      h = fmin(2.0 * h, VS_RAMP_STEP);
    } else if ((h *= 0.5) < VS_RAMP_MIN || s->interrupted || s->nonfinite) {
      *slides = vs_qs_slip_onsets(s, q, 0.0, qt, 0.0, NULL);
      break;
    }
  }
done:
  KINSetNumMaxIters(s->kin, s->o->newton_maxiter);
  vs_model_set_gravity_scale(m, 1.0);
  *lambda_max = lam;
  free(qt);
  return ok;
}

/* The joints flagged in s->onset, 1-based, into buf: "1, 56" (a long list ends with "..."). */
static void onset_names(const vs_qs_solver *s, char *buf, size_t size) {
  const int nj = vs_model_geometry(s->m)->n_joints;
  size_t len = 0;
  buf[0] = '\0';
  for (int k = 0; k < nj && len + 1 < size; k++) {
    if (s->onset[k] == 0) continue;
    const int w = snprintf(buf + len, size - len, "%s%d", len ? ", " : "", k + 1);
    if (w < 0 || (size_t)w >= size - len) {
      snprintf(buf + (size > 4 ? size - 4 : 0), size > 4 ? 4 : size, "...");
      return;
    }
    len += (size_t)w;
  }
}

/* No equilibrium to start from at delta0 (flag: the last solve's; lambda_max: how far the
 * self-weight's continuation went; slides: the joints its last step would have made slide):
 * the error that says so. */
static vs_status start_failed(const vs_qs_solver *s, double delta0, int flag, double lambda_max,
                              int slides, vs_error *err) {
  const vs_status st = vs_qs_fatal(s, delta0, err);
  if (st != VS_OK) return st;
  if (delta0 == 0.0 && slides > 0) {
    char joints[64];
    onset_names(s, joints, sizeof joints);
    return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                        "the arch cannot stand without sliding: its weight takes the shear at "
                        "joint%s %s past the Coulomb limit |T| = mu N, and growing the weight "
                        "from zero no equilibrium was found beyond %.4g of it (increments down "
                        "to %.1e)",
                        slides > 1 ? "s" : "", joints, lambda_max, VS_RAMP_MIN);
  }
  if (delta0 == 0.0)
    return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                        "the arch cannot stand: no equilibrium under self-weight (growing the "
                        "weight from zero, equilibrium was followed up to %.4g of it and none "
                        "was found beyond, with increments down to %.1e)",
                        lambda_max, VS_RAMP_MIN);
  return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM, "no equilibrium at %.6g mm to resume from (%s)",
                      delta0 / VS_MM, vs_qs_kin_cause(flag));
}

vs_status vs_qs_start(vs_qs_solver *s, double delta0, double *q, vs_path_result *res,
                      vs_error *err) {
  const int misfit = delta0 == 0.0 && vs_model_has_misfit(s->m);
  if (misfit) vs_model_set_misfit_scale(s->m, 0.0);
  int flag = vs_qs_solve(s, delta0, q, NULL), slides = 0;
  double lambda_max = 1.0, misfit_max = 1.0;
  if (flag != 0 && delta0 == 0.0 && vs_qs_fatal(s, delta0, NULL) == VS_OK &&
      gravity_ramp(s, q, &lambda_max, &slides) == 0)
    flag = 0;
  if (flag == 0 && misfit && misfit_ramp(s, q, &misfit_max) != 0) {
    vs_status st = vs_qs_fatal(s, delta0, err); /* an interrupt or a non-finite residual says so */
    if (st == VS_OK)
      st = vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                        "the imperfect arch cannot stand: no equilibrium under self-weight with "
                        "its misfit (face gaps, support offset) beyond %.4g of it, with "
                        "increments down to %.1e",
                        misfit_max, VS_RAMP_MIN);
    return st;
  }
  res->newton_iterations = s->iters;
  if (flag != 0) {
    res->evidence.slip_onset = slides;
    for (int k = vs_model_geometry(s->m)->n_joints - 1; k >= 0 && slides > 0; k--)
      if (s->onset[k] != 0) res->evidence.slip_joint = k;
    return start_failed(s, delta0, flag, lambda_max, slides, err);
  }
  if (!vs_qs_stable_state(s, q, delta0))
    return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                        "the equilibrium at %.6g mm is unstable (tangent not positive definite)",
                        delta0 / VS_MM);
  return VS_OK;
}
