/* Monte Carlo over imperfect arches: sample i of a case is the case with [imperfections]
 * sample = i (its own draws, imperfections.h), run to the collapse. The samples' results, their
 * statistics, the empirical fragility curve with a confidence band, the hinge locations and the
 * convergence of the statistics with the number of samples; an HDF5 summary and PNG figures.
 * A sample's result depends only on (case, seed, sample), so the summary is the same whatever
 * the number of processes that computed it. */
#ifndef VOUSSOIR_MONTECARLO_H
#define VOUSSOIR_MONTECARLO_H

#include "voussoir/api.h"

#include "voussoir/case.h"
#include "voussoir/status.h"

enum { VS_MC_COLLAPSE = 0, VS_MC_NO_COLLAPSE = 1, VS_MC_FAILED = 2 };
#define VS_MC_LABELS 5 /* hinge labels A..E */

/* One sample's result: plain data (it travels through pipes and MPI as bytes). */
typedef struct {
  int sample;           /* sample number */
  int status;           /* VS_MC_COLLAPSE, VS_MC_NO_COLLAPSE (none within support.max_mm) or
                           VS_MC_FAILED */
  double first_limit_mm;   /* first limit point (NaN if none) */
  double delta_u_mm;       /* collapse displacement (NaN unless a collapse) */
  double dz_u_mm, dx_u_mm; /* its components, down and outward */
  int mode;                /* 1..3 for modes I..III, 0 unclassified */
  int hinge_joint[VS_MC_LABELS]; /* hinges at collapse by label A..E: middle joint, 0 if none */
  char hinge_side[VS_MC_LABELS]; /* 'I', 'E' or 0 */
  char pattern[16];        /* sides at collapse, left to right ("E-I-E-E"); of more than 8
                              hinges the first 7 and a '-' (vs_hinges_side_pattern) */
  char error[400];         /* the cause of a failure, "" otherwise */
  double load_factor;      /* analysis.type = load: the load factor at collapse (0: the arch
                              failed before the hold), the status then VS_MC_NO_COLLAPSE (the
                              support did not bring it down); NaN otherwise */
  int mortared;            /* the case has mortar (joints.tensile_MPa or cohesion_MPa > 0) */
  double first_crack_mm;   /* its first crack (the run's JSON first_crack): the support */
  int first_crack_joint;   /* displacement (mm), the joint (1-based) and the edge that cracks, */
  char first_crack_side;   /* 'I' or 'E'; NaN, 0, 0 when none (and for a dry case) */
} vs_mc_sample;

/* Run sample `sample` of case base (validated): base with imperfections.sample = sample and
 * dynamic.fall_s = 0 (the collapse displacement and the mechanism are read before the fall).
 * Never fails as a function: a failed run gives status VS_MC_FAILED with its cause. */
VS_API void vs_mc_run_sample(const vs_case *base, int sample, vs_mc_sample *out);

/* Each support's own travel at delta_mm (the right support's travel, mm) as case c moves them
 * (without an imperfect arch's offset): t = left dx, dz, right dx, dz, mm, outward and downward
 * positive, as the JSON's collapse.left and collapse.right and samples.csv's last four columns.
 * NaN when delta_mm is, or the case defines no motion. */
VS_API void vs_mc_travel(const vs_case *c, double delta_mm, double t[4]);

/* The columns of samples.csv (line 2; `voussoir merge` reads them back, and the first 14 of a
 * table of 0.3.0 and before): then each support's own travel at the collapse (mm, outward and
 * downward positive, as the JSON's collapse.left and collapse.right) and the load factor at
 * collapse (analysis.type = load; NaN otherwise). */
#define VS_MC_TABLE_COLUMNS \
  "sample,status,first_limit_mm,delta_u_mm,dz_u_mm,dx_u_mm,mode,pattern,A,B,C,D,E,error," \
  "left_dx_mm,left_dz_mm,right_dx_mm,right_dz_mm,load_factor"
/* A mortared study's samples.csv (a sample's case has mortar) has these columns after them:
 * the first crack's support displacement (mm, nan none), joint (0 none) and edge (I, E, empty). */
#define VS_MC_CRACK_COLUMNS ",first_crack_mm,first_crack_joint,first_crack_side"

/* The files vs_mc_write_summary writes into its directory (for an initialiser list). Its charts
 * (fragility, convergence, hinge histogram) are matplotlib's: `voussoir plot DIR/summary.h5`,
 * or voussoir.figures in Python. */
#define VS_MC_OUTPUTS "samples.csv", "statistics.csv", "summary.h5"

/* Write the summary of n samples (sorted here by sample number) into directory dir (created if
 * missing): VS_MC_OUTPUTS, each written as "<name>.part" and renamed into place (only over a
 * regular file), so that none is ever half-written. span_mm normalises (L). Errors: VS_ERR_IO,
 * VS_ERR_NOMEM, VS_ERR_INVALID (a target became something other than a regular file). In
 * libvoussoir-plot (with HDF5); the rest of this header is in libvoussoir. */
VS_API vs_status vs_mc_write_summary(const char *dir, const vs_case *base, vs_mc_sample *samples,
                                     int n, vs_error *err);

#endif
