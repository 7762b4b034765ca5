/* A sweep's summary table as plain data (no pointers: a row travels through a pipe from a forked
 * worker, or as bytes between MPI ranks): its axes and one row per case, the inputs and the
 * results. Written as DIR/summary.h5 here, in the record library (sweep_summary.c), and as
 * summary.csv by the sweep command (src/study/). */
#ifndef VS_SWEEP_ROWS_H
#define VS_SWEEP_ROWS_H

#include "voussoir/status.h"

enum { VS_SWEEP_MAX_AXES = 8 };

/* An axis of a sweep: the key it sets and its values (case units). */
typedef struct {
  char key[96]; /* section.key */
  double *v;
  int n;
} vs_sweep_axis;

/* How a case ended, in vs_sweep_row.code: run (VS_SWEEP_OK), failed with its cause, stopped by
 * the stop flag, lost: its worker ended without a result (killed, crashed; set by the pool), or
 * not started: its record could not be created (locked by another process, not a regular
 * file, no space, no memory), so that nothing of the case ran; the cause in error. Only OK and
 * FAILED are journalled: the others are run again by --resume. */
enum { VS_SWEEP_OK = 0, VS_SWEEP_FAILED = 1, VS_SWEEP_LOST = 2, VS_SWEEP_NOT_STARTED = 3,
       VS_SWEEP_INTERRUPTED = 130 };

/* One row of the summary: a case's inputs and results. Plain data, no pointers. */
typedef struct {
  int run;                            /* 1-based run number */
  int code;                           /* VS_SWEEP_OK, _FAILED (cause in error), ... (above) */
  double axis[VS_SWEEP_MAX_AXES];     /* the axes' values (case units) */
  char status[32];                    /* collapse, limit_point, max_displacement, failed, ... */
  char mode[8];                       /* I, II, III or "" */
  char hinges[512];                   /* hinges at collapse: "D:1-E A:9-10-I ..." */
  char error[512];                    /* the cause of a failure, "" otherwise */
  double first_limit_mm, delta_u_mm;  /* NaN when absent */
  double dz_pct, dx_pct;              /* delta_u's components, % of the intrados span (the
                                         supports' relative displacement when both move) */
  double wall_s;                      /* the run's wall time */
  int snaps;                          /* limit points the path snapped through */
  double left_dx_mm, left_dz_mm;      /* each support's own travel at the collapse (outward, */
  double right_dx_mm, right_dz_mm;    /* downward positive; as the JSON's collapse.left/right) */
  double load_factor;                 /* analysis.type = load: the load factor at collapse (0:
                                         the arch failed before the hold); NaN otherwise */
  int mortared;                       /* the case has mortar (joints.tensile_MPa or cohesion_MPa
                                         > 0): its table has the first crack's columns */
  double first_crack_mm;              /* the first crack (the JSON's first_crack): the support */
  int first_crack_joint;              /* displacement (mm), the joint (1-based) and the edge */
  char first_crack_side[2];           /* that cracks, "I" or "E"; NaN, 0, "" when none */
} vs_sweep_row;

/* The summary table of a sweep as DIR/summary.h5 (sweep_summary.c, in the record library).
 * Errors: VS_ERR_INVALID (something other than a regular file in the way), VS_ERR_IO,
 * VS_ERR_NOMEM, the path in err. */
vs_status vs_sweep_summary_h5(const char *dir, const vs_sweep_axis *ax, int nax,
                              const vs_sweep_row *rows, int n, vs_error *err);

#endif
