/* The supports' motion (support.h): the right support's direction and its components, and each
 * support's motion in the loading parameter delta, from its straight motion or its path. */
#include "voussoir/support.h"

#include <math.h>
#include <string.h>

vs_support_dir vs_support_direction(double alpha_rad) {
  return (vs_support_dir){.dx = sin(alpha_rad), .dz = cos(alpha_rad)};
}

void vs_support_displacement(vs_support_dir d, double delta, double u[2]) {
  u[0] = delta * d.dx;
  u[1] = -delta * d.dz;
}

void vs_support_motion_line(vs_support_motion *mo, const double slope[3]) {
  memset(mo, 0, sizeof *mo);
  mo->n = 1;
  memcpy(mo->slope[0], slope, 3 * sizeof(double));
}

double vs_support_loading_rate(const vs_support_def *s) {
  return s->rate > 0.0 ? s->rate : s->left_rate > 0.0 ? s->left_rate : 0.0;
}

/* The model's (ux, uz, theta) of a path's point i: outward is +x on the right, -x on the left;
 * down is -z; an outward lean turns the right support clockwise, the left counter-clockwise. */
static void path_point(const vs_support_path_def *p, int i, int right, double u[3]) {
  u[0] = right ? p->dx[i] : -p->dx[i];
  u[1] = -p->dz[i];
  u[2] = right ? -p->rot[i] : p->rot[i];
}

/* Check path p of the support named side ("left", "right"). */
static vs_status path_check(const vs_support_path_def *p, const char *side, vs_error *err) {
  if (p->n < 0 || p->n > VS_SUPPORT_PATH_MAX)
    return vs_error_set(err, VS_ERR_INVALID, "support.%s_path: %d points (allowed: 0 .. %d)", side,
                        p->n, VS_SUPPORT_PATH_MAX);
  for (int i = 0; i < p->n; i++) {
    if (!isfinite(p->t[i]) || !isfinite(p->dx[i]) || !isfinite(p->dz[i]) || !isfinite(p->rot[i]))
      return vs_error_set(err, VS_ERR_INVALID,
                          "support.%s_path: point %d: not a finite number (allowed: finite times, "
                          "displacements and rotations)",
                          side, i + 1);
    const double before = i > 0 ? p->t[i - 1] : 0.0;
    if (i > 0 ? !(p->t[i] > before) : !(p->t[i] >= 0.0))
      return vs_error_set(err, VS_ERR_INVALID,
                          "support.%s_path: point %d: t = %g s (allowed: times increasing from 0)",
                          side, i + 1, p->t[i]);
    if (p->t[i] == 0.0 && (p->dx[i] != 0.0 || p->dz[i] != 0.0 || p->rot[i] != 0.0))
      return vs_error_set(err, VS_ERR_INVALID,
                          "support.%s_path: point %d at t = 0 is away from the origin (allowed: at "
                          "t = 0 the support stands in place: 0 mm, 0 mm, 0 deg)",
                          side, i + 1);
  }
  return VS_OK;
}

/* mo from path p (checked) at loading rate v: the origin, then every point after t = 0; the
 * last segment goes on along the one before it (a path of one point: from the origin). */
static void motion_of_path(const vs_support_path_def *p, int right, double v,
                           vs_support_motion *mo) {
  memset(mo, 0, sizeof *mo);
  double d_prev = 0.0, u_prev[3] = {0.0, 0.0, 0.0};
  int n = 1; /* segment 0 starts at the origin */
  for (int i = 0; i < p->n; i++) {
    if (p->t[i] == 0.0) continue;
    const double d = v * p->t[i];
    double u[3];
    path_point(p, i, right, u);
    for (int c = 0; c < 3; c++) mo->slope[n - 1][c] = (u[c] - u_prev[c]) / (d - d_prev);
    mo->d[n] = d;
    memcpy(mo->u[n], u, sizeof u);
    memcpy(mo->slope[n], mo->slope[n - 1], sizeof u);
    memcpy(u_prev, u, sizeof u);
    d_prev = d;
    n++;
  }
  mo->n = n;
}

vs_status vs_support_motion_from_def(const vs_support_def *s, int right, vs_support_motion *mo,
                                     vs_error *err) {
  const char *side = right ? "right" : "left";
  const double rate = right ? s->rate : s->left_rate;
  if (!(rate >= 0.0) || !isfinite(rate))
    return vs_error_set(err, VS_ERR_INVALID, "support.%s = %g mm/s (allowed: >= 0)",
                        right ? "rate_mm_s" : "left_rate_mm_s", rate * 1e3);
  const double v = vs_support_loading_rate(s);
  if (!(v > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "support.rate_mm_s = 0 and support.left_rate_mm_s = 0: no loading rate "
                        "(allowed: at least one > 0; delta = that rate x time)");
  const vs_support_path_def *p = right ? &s->right_path : &s->left_path;
  vs_status st = path_check(p, side, err);
  if (st != VS_OK) return st;
  if (p->n > 0) {
    motion_of_path(p, right, v, mo);
  } else {
    const double alpha = right ? s->alpha : s->left_alpha, r = rate / v;
    const double slope[3] = {(right ? r : -r) * sin(alpha), r * -cos(alpha), 0.0};
    const double none[3] = {0.0, 0.0, 0.0}; /* a support at rest: no -0 */
    vs_support_motion_line(mo, rate > 0.0 ? slope : none);
  }
  const vs_support_kind kind = right ? s->right_kind : s->left_kind;
  if (kind == VS_SUPPORT_PINNED && vs_support_motion_rotates(mo))
    return vs_error_set(err, VS_ERR_INVALID,
                        "support.%s_path turns the %s support, which is pinned (allowed: a "
                        "rotation only on a fixed support; a pinned one's rotation is free)",
                        side, side);
  return VS_OK;
}

void vs_support_motion_at(const vs_support_motion *mo, double delta, double u[3], double du[3]) {
  int i = mo->n - 1;
  while (i > 0 && mo->d[i] > delta) i--;
  for (int c = 0; c < 3; c++) {
    /* segment 0 starts at the origin: delta slope, as the straight motion always was */
    if (u != NULL)
      u[c] = i == 0 ? delta * mo->slope[0][c] : mo->u[i][c] + (delta - mo->d[i]) * mo->slope[i][c];
    if (du != NULL) du[c] = mo->slope[i][c];
  }
}

double vs_support_motion_next(const vs_support_motion *mo, double delta, double tol) {
  for (int i = 1; i < mo->n; i++)
    if (mo->d[i] > delta + tol) return mo->d[i];
  return INFINITY;
}

int vs_support_motion_rotates(const vs_support_motion *mo) {
  for (int i = 0; i < mo->n; i++)
    if (mo->slope[i][2] != 0.0) return 1;
  return 0;
}
