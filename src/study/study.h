/* The study commands' bodies, given what the command line asked (src/cli/ reads the options):
 * sweep, calibrate, montecarlo and merge. Each returns an exit status (exit_status.h). */
#ifndef VS_STUDY_H
#define VS_STUDY_H

#include "exit_status.h"
#include "sweep_rows.h"

/* sweep (sweep.c). */
typedef struct {
  const char *case_path, *dir; /* dir: default "sweep_out" */
  const char *mode_flag;       /* "--first-limit", "--dynamic" or NULL */
  const char **sets;
  int nsets, nax, jobs, quiet, resume;
  vs_sweep_axis *ax;
} vs_sweep_opts;
/* SIGINT/SIGTERM handled by the sweep from now on (call it before parsing). */
void vs_sweep_catch_signals(void);
int vs_sweep_main(const vs_sweep_opts *o, int *h5_clean);

/* calibrate (calibrate.c). */
typedef struct {
  const char *case_path;
  const char **sets;
  int nsets, dx, quiet; /* dx: the target is dx/L (else dz/L) */
  double target, kn_min, kn_max, tol;
} vs_calibrate_opts;
int vs_calibrate_main(const vs_calibrate_opts *o);

/* montecarlo and merge (montecarlo_cmd.c). */
typedef struct {
  const char *case_path, *dir, *seed;
  const char **sets;
  int nsets, samples, jobs, quiet, shard_k, shard_m, resume;
} vs_mc_opts;
int vs_mc_main(const vs_mc_opts *o);
int vs_merge_main(const char *const *dirs, int ndirs, const char *out);

#endif
