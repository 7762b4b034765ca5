/* The supports' motion. The right support moves by delta along alpha, measured from the vertical
 * (0 = settlement down, 90 = outward spreading; x right, z up): the one place where alpha becomes
 * components (the model's support displacement, the pictures, and the settlement dz and
 * spreading dx every report, record, sweep and calibration gives). Both supports may also move
 * each on its own (def.h, vs_support_def): their motions as functions of the loading parameter
 * delta, which the model follows (vs_support_motion). */
#ifndef VOUSSOIR_SUPPORT_H
#define VOUSSOIR_SUPPORT_H

#include "voussoir/api.h"
#include "voussoir/def.h"
#include "voussoir/status.h"

typedef struct {
  double dx; /* sin alpha: the outward (x) share of delta, the spreading */
  double dz; /* cos alpha: the downward share of delta, the settlement */
} vs_support_dir;

/* The direction alpha_rad (rad). */
VS_API vs_support_dir vs_support_direction(double alpha_rad);

/* The right support's displacement for delta (m) along d: u = (delta dx, -delta dz), m. */
VS_API void vs_support_displacement(vs_support_dir d, double delta, double u[2]);

/* --- both supports: each one's motion in the loading parameter delta --- */

/* A support's motion as delta (m) grows: piecewise linear. On segment i, from delta = d[i]
 * (d[0] = 0, increasing) on, the support's reference point (the centre of its springing face)
 * has moved by u[i] + (delta - d[i]) slope[i] = (ux, uz, theta) (m, m, rad; x right, z up, theta
 * counter-clockwise about that point); the last segment goes on for ever. */
#define VS_SUPPORT_SEGMENTS_MAX (VS_SUPPORT_PATH_MAX + 1)
typedef struct {
  int n; /* segments, 1 .. VS_SUPPORT_SEGMENTS_MAX */
  double d[VS_SUPPORT_SEGMENTS_MAX];
  double u[VS_SUPPORT_SEGMENTS_MAX][3];
  double slope[VS_SUPPORT_SEGMENTS_MAX][3];
} vs_support_motion;

/* A motion along a straight line from the origin: (ux, uz, theta) = delta slope (slope zero:
 * the support stays in place). */
VS_API void vs_support_motion_line(vs_support_motion *mo, const double slope[3]);

/* The loading rate of s (m/s): s->rate, or s->left_rate when s->rate is 0; delta = that rate
 * times the loading time t. 0 when both are 0 (vs_support_motion_from_def refuses it). */
VS_API double vs_support_loading_rate(const vs_support_def *s);

/* The motion of the left (right = 0) or the right support (1) that s defines, in delta: its
 * path (times scaled by the loading rate) when it has one, else its straight motion along its
 * direction (the left one mirrored) at its rate over the loading rate. VS_ERR_INVALID, naming
 * the case key, on a negative or non-finite rate, no loading rate, a path with too many points,
 * times not increasing, a first point at t = 0 away from the origin, a non-finite value, or a
 * rotation on a pinned support. */
VS_API vs_status vs_support_motion_from_def(const vs_support_def *s, int right,
                                            vs_support_motion *mo, vs_error *err);

/* The support's (ux, uz, theta) at delta into u and their rates d/d(delta) into du (either may be
 * NULL): on the segment that holds delta (at a breakpoint, the one that starts there; before
 * d[0], the first). */
VS_API void vs_support_motion_at(const vs_support_motion *mo, double delta, double u[3],
                                 double du[3]);

/* The first breakpoint d[i] > delta + tol, INFINITY when there is none. */
VS_API double vs_support_motion_next(const vs_support_motion *mo, double delta, double tol);

/* Whether the motion ever rotates the support (a slope of theta not zero). */
VS_API int vs_support_motion_rotates(const vs_support_motion *mo);

#endif
