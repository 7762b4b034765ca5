/* Reports of a run for people (a readable summary) and for programs (one JSON object), in the
 * units engineers use: mm, %, N, deg. */
#ifndef VOUSSOIR_REPORT_H
#define VOUSSOIR_REPORT_H

#include "voussoir/api.h"

#include <stdio.h>

#include "voussoir/limit.h"
#include "voussoir/run.h"

/* Human summary of run r to out. status/err: how vs_run_execute ended (err may be NULL). */
VS_API void vs_report_text(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                           const char *case_path);

/* One JSON object (and a newline) to out. Stable keys: alpha_deg, kn_N_mm3, span_mm,
 * first_limit {delta_mm, dz_over_L_pct, dx_over_L_pct, ...} (null when there is none), hinges
 * [{label, joints, joints_onset, side, delta_onset_mm, open}], stats {steps, newton_iterations,
 * wall_s, ...}, status (collapse, limit_point, max_displacement, failed, or stopped: the
 * wall-time limit, run.max_wall_s, or the caller's sample or event function ended the run),
 * error (the cause, or for a stopped run "stopped: wall-time limit S s reached" or "stopped by
 * the caller"; null otherwise). A number that is not finite (no
 * collapse time, a quantity the run did not reach) is written as null: the output is always
 * valid JSON. */
VS_API void vs_report_json(FILE *out, const vs_run *r, vs_status status, const vs_error *err,
                           const char *case_path);

/* The limit analysis a of case c (analysis.type = limit; limit.h: vs_limit_analyse), status/err
 * how it ended: a readable summary, or one JSON object (and a newline) whose stable keys are
 * program, version, case, analysis ("limit"), status (ok, failed), error, span_mm, friction,
 * supports, load {kind, value_N, x_mm, width_mm, voussoir}, and limit {load_factor (null without
 * a live load or when unbounded), collapse_load_N, load_factor_exact (no interface at the
 * friction limit), thickness_factor, min_thickness_mm, geometric_safety_factor, thrust_min_N,
 * thrust_max_N, and per solution (collapse, thrust_min, thrust_max, thickness) its outcome,
 * touches, at_friction_limit, mechanism and sliding (collapse), thrust_line_eta} (null when
 * the analysis failed). docs/run.md shows one. */
VS_API void vs_report_limit_text(FILE *out, const vs_case *c, const vs_limit_analysis *a,
                                 vs_status status, const vs_error *err, const char *case_path);
VS_API void vs_report_limit_json(FILE *out, const vs_case *c, const vs_limit_analysis *a,
                                 vs_status status, const vs_error *err, const char *case_path);

/* Write s as a JSON string literal (quoted; quotes, backslashes, control characters and DEL
 * escaped; a byte that is not part of well-formed UTF-8 written as U+FFFD, so that the output
 * is valid JSON whatever s holds). */
VS_API void vs_json_string(FILE *out, const char *s);

#endif
