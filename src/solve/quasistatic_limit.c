/* The limit point of the quasi-static path: approached by increments bounded ahead of the fold
 * that the tangent's smallest eigenvalue predicts, bracketed when an increment at limit_tol still
 * fails, and confirmed on the tangent (its smallest eigenvalue extrapolated to zero). */
#include "quasistatic_internal.h"
#include "stability.h"

#include <math.h>
#include <stdlib.h>

#include "voussoir/units.h"

/* Inverse iteration on the tangent: relative change of the eigenvalue estimate that stops it,
 * and the iteration cap. */
static const double VS_EIG_RTOL = 1e-10;
static const int VS_EIG_MAXIT = 200;
/* Near a fold the smallest eigenvalue of the tangent vanishes like (delta_L - delta)^1/2, so
 * lambda^2 is linear in delta and its extrapolation from the last two equilibria predicts
 * delta_L; an increment goes at most this fraction of the way there, so that the fold is
 * approached by converging steps rather than by failing ones. */
static const double VS_FOLD_APPROACH = 0.5;
/* Two successive fold predictions agree when they differ by less than this fraction of the
 * distance to the fold. */
static const double VS_FOLD_AGREE = 0.5;

/* Confirm a bracketed limit point at delta_lo (last equilibrium q_lo): near a fold the smallest
 * eigenvalue of the tangent vanishes like sqrt(delta_L - delta), so lambda^2 is linear in delta.
 * Take a second equilibrium a little behind (delta_b, solved from the interpolation between the
 * previous accepted state and q_lo: Newton from q_lo itself is useless there, its tangent is
 * nearly singular), extrapolate lambda^2 to zero and require the zero to fall in the bracket
 * (within its width plus the bisection tolerance). */
static vs_status confirm_limit(vs_qs_solver *s, const double *q_prev, double delta_prev,
                               const double *q_lo, double delta_lo, double delta_fail,
                               vs_path_result *res, vs_error *err) {
  const double width = delta_fail - delta_lo;
  const double delta_b = fmax(delta_lo - 10.0 * fmax(width, s->o->limit_tol), delta_prev);
  vs_limit_evidence *ev = &res->evidence;
  int sign = 0;
  if (vs_qs_tangent_factor(s, q_lo, delta_lo, &sign) != 0)
    return vs_error_set(err, VS_ERR_SOLVER, "the tangent at %.6g mm could not be factored",
                        delta_lo / VS_MM);
  ev->det_sign = sign;
  double *vec = calloc((size_t)s->n, sizeof *vec);
  if (vec == NULL) return vs_error_set(err, VS_ERR_NOMEM, "out of memory");
  const double lam_lo = vs_qs_tangent_min_eig(s, vec, VS_EIG_RTOL, VS_EIG_MAXIT);
  ev->lambda_last = lam_lo;
  double *qb = malloc((size_t)s->n * sizeof *qb);
  if (qb == NULL) {
    free(vec);
    return vs_error_set(err, VS_ERR_NOMEM, "out of memory");
  }
  const double f = (delta_lo > delta_prev) ? (delta_b - delta_prev) / (delta_lo - delta_prev) : 0.0;
  for (int i = 0; i < s->n; i++) qb[i] = q_prev[i] + f * (q_lo[i] - q_prev[i]);
  int flag = (delta_b > delta_prev) ? vs_qs_solve(s, delta_b, qb, NULL) : 0;
  double lam_b = NAN;
  int sign_b = 0;
  if (flag == 0 && vs_qs_tangent_factor(s, qb, delta_b, &sign_b) == 0)
    lam_b = vs_qs_tangent_min_eig(s, vec, VS_EIG_RTOL, VS_EIG_MAXIT);
  free(qb);
  free(vec);
  if (flag != 0 || !isfinite(lam_b))
    return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                        "no equilibrium accepted beyond %.6g mm, and the path could not be "
                        "re-solved at %.6g mm to examine the tangent (%s)",
                        delta_lo / VS_MM, delta_b / VS_MM,
                        flag != 0 ? s->fail_cause : "its tangent's eigenvalue not found");
  const double l2b = lam_b * lam_b, l2 = lam_lo * lam_lo;
  ev->delta_extrap = (l2b > l2) ? delta_lo + (delta_lo - delta_b) * l2 / (l2b - l2) : INFINITY;
  const double slack = width + s->o->limit_tol;
  if (sign > 0 && ev->delta_extrap <= delta_fail + slack) return VS_OK;
  return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM,
                      "no equilibrium accepted beyond %.6g mm (%s) but the tangent stiffness "
                      "there is not vanishing (smallest eigenvalue %.4g N/m, extrapolated to zero "
                      "at %.6g mm, det sign %+d): not a limit point",
                      delta_lo / VS_MM, s->fail_cause[0] ? s->fail_cause : "no convergence", lam_lo,
                      ev->delta_extrap / VS_MM, sign);
}

/* Fold predictor: lambda^2 extrapolated from the last two equilibria, trusted once two
 * successive predictions agree (lambda^2 linear in delta, as near a fold; a hinge forming also
 * lowers lambda, but not along a line). */
void vs_qs_fold_limit(vs_qs_path *w) {
  const double delta = w->delta, delta_prev = w->delta_prev, lam = w->lam, lam_prev = w->lam_prev;
  w->fold = (isfinite(lam_prev) && lam < lam_prev && delta > delta_prev)
                ? delta + lam * lam * (delta - delta_prev) / (lam_prev * lam_prev - lam * lam)
                : INFINITY;
  if (isfinite(w->fold) && isfinite(w->fold_prev) &&
      fabs(w->fold - w->fold_prev) <= VS_FOLD_AGREE * (w->fold - delta))
    w->h = fmin(w->h, fmax(VS_FOLD_APPROACH * (w->fold - delta), w->o->limit_tol));
}

/* A limit point of a mortared arch at the softening of a joint: the tangent's smallest
 * eigenvalue then falls by an amount that grows as the softening zone enters the joint (its
 * length grows like the opening over the gap slope), not like the square root of a smooth fold,
 * so that confirm_limit's extrapolation says nothing. The bracket holds the limit when the
 * tangent at the failed increment's predictor (the path's tangent from the last equilibrium), or
 * at twice or four times it, is no longer positive definite while the last equilibrium's is. Only for a model with mortar: a
 * dry arch's limit points are folds or slip corners. */
/* The predictors tested: at 1, 2, ... up to this many times the failed increment (within
 * confirm_limit's slack of a bracket width and the bisection tolerance, the increment being at
 * most the tolerance there). */
enum { VS_CRACK_CORNER_REACH = 4 };

static int crack_corner(vs_qs_path *w) {
  vs_qs_solver *const s = w->s;
  const vs_joint_law *law = vs_model_law(s->m);
  if (!(law->ft > 0.0 || law->c > 0.0)) return 0;
  for (int f = 1; f <= VS_CRACK_CORNER_REACH; f *= 2) {
    for (int i = 0; i < s->n; i++) w->qtry[i] = w->q[i] + f * w->h * w->tan[i];
    int sign = 0;
    if (vs_qs_tangent_factor(s, w->qtry, w->delta + f * w->h, &sign) != 0) return 0;
    if (vs_spd_test(s->spd, s->Jt) == 0) {
      w->res->evidence.delta_extrap = w->delta + f * w->h;
      return 1;
    }
  }
  return 0;
}

vs_status vs_qs_limit_end(vs_qs_path *w, vs_error *err) {
  vs_qs_solver *const s = w->s;
  vs_path_result *const res = w->res;
  res->delta_limit = w->delta;
  res->delta_fail = w->delta + w->h;
  /* the onset of slip first: a corner, where the sticking tangent says nothing */
  if (vs_qs_slip_corner(s, w->q, w->delta, w->delta + w->h, w->tan, w->qtry, &res->evidence) > 0) {
    for (int i = 0; i < s->n; i++) w->qtry[i] = 0.0; /* a fixed start for the eigenvector */
    res->evidence.lambda_last = vs_qs_tangent_min_eig(s, w->qtry, VS_EIG_RTOL, VS_EIG_MAXIT);
    res->evidence.delta_extrap = NAN;
    res->end = VS_PATH_LIMIT_POINT;
    return VS_OK;
  }
  vs_status st = confirm_limit(s, w->qprev, w->delta_prev, w->q, w->delta, w->delta + w->h, res,
                               err);
  if (st == VS_ERR_NO_EQUILIBRIUM && !s->interrupted && !s->nonfinite && crack_corner(w)) {
    vs_error_clear(err);
    st = VS_OK;
  }
  if (s->interrupted || s->nonfinite) st = vs_qs_fatal(s, w->delta + w->h, err);
  if (st == VS_OK) res->end = VS_PATH_LIMIT_POINT;
  return st;
}
