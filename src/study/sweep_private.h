/* Inside the sweep command: one case of a sweep run in this process (its result is a row of
 * sweep_rows.h), and the local pool of forked workers (the MPI farm is sweep_mpi.h). */
#ifndef VOUSSOIR_SWEEP_PRIVATE_H
#define VOUSSOIR_SWEEP_PRIVATE_H

#include <signal.h>

#include "sweep_mpi.h"
#include "sweep_rows.h"
#include "voussoir/case.h"

/* What every case of a sweep shares. */
typedef struct {
  const char *case_path;      /* the case file, as named on the command line */
  const char *case_text;      /* its text, for the records' "case" attribute */
  const char *dir;            /* output directory */
  const vs_case *base;        /* the case after --set (not yet validated) */
  const vs_sweep_axis *ax;
  int nax;
  const char *mode_set;       /* "dynamic.full=1", "dynamic.follow=0" or NULL */
} vs_sweep_job;

/* The axes' value indices of run `run` (1-based): the last axis varies fastest. */
void vs_sweep_pick(const vs_sweep_job *job, int run, int *pick);

/* Run case `run` (1-based) in this process: DIR/run_NNNN.h5 (the record, with its XDMF
 * sidecar) and DIR/run_NNNN.json.part (the JSON of `voussoir run --json`; the caller renames it
 * to .json once it has taken the row), and the row. stop (borrowed) stops the run once non-zero
 * (the record is then closed as interrupted). *h5_clean becomes 0 when a record could not be
 * written (see vs_output_process_end). Never fails as a function: a failure is in the row. */
void vs_sweep_run_case(const vs_sweep_job *job, int run, const volatile sig_atomic_t *stop,
                       vs_sweep_row *row, int *h5_clean);

/* The local pool (src/study/sweep_pool.c): the runs next() gives, each in a worker forked from this
 * process (in its own process group, so that a terminal's ^C reaches the sweep only), `jobs` at
 * a time; every row goes to take() as its worker ends. A stop (*stop_count > 0) starts no new
 * run and is passed on to the workers under way (the signal *stop_signal; a second stop:
 * SIGKILL). todo: the number of runs next() will give, for the progress line on stderr (when
 * progress is non-zero). Returns 0, or -1 when a worker cannot be started (errno). */
int vs_sweep_pool_serve(const vs_sweep_server *s, const vs_sweep_job *job, int jobs, int todo,
                        int progress, const volatile sig_atomic_t *stop_count,
                        const volatile sig_atomic_t *stop_signal);


#endif
