/* Inside the sweep command (not installed): one case of a sweep run in this process, its result
 * as plain data (it travels through a pipe from a forked worker, or as bytes between MPI ranks),
 * and the MPI farm that hands the cases out from rank 0. */
#ifndef VOUSSOIR_SWEEP_PRIVATE_H
#define VOUSSOIR_SWEEP_PRIVATE_H

#include <signal.h>

#include "voussoir/case.h"

enum { VS_SWEEP_MAX_AXES = 8 };

/* An axis of a sweep: the key it sets and its values (case units). */
typedef struct {
  char key[96]; /* section.key */
  double *v;
  int n;
} vs_sweep_axis;

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
  double dz_pct, dx_pct;              /* delta_u's components, % of the intrados span */
  double wall_s;                      /* the run's wall time */
  int snaps;                          /* limit points the path snapped through */
} vs_sweep_row;

/* The axes' value indices of run `run` (1-based): the last axis varies fastest. */
void vs_sweep_pick(const vs_sweep_job *job, int run, int *pick);

/* Run case `run` (1-based) in this process: DIR/run_NNNN.h5 (the record, with its XDMF
 * sidecar) and DIR/run_NNNN.json.part (the JSON of `voussoir run --json`; the caller renames it
 * to .json once it has taken the row), and the row. stop (borrowed) stops the run once non-zero
 * (the record is then closed as interrupted). *h5_clean becomes 0 when a record could not be
 * written (see vs_output_process_end). Never fails as a function: a failure is in the row. */
void vs_sweep_run_case(const vs_sweep_job *job, int run, const volatile sig_atomic_t *stop,
                       vs_sweep_row *row, int *h5_clean);
typedef void (*vs_sweep_case_fn)(const vs_sweep_job *job, int run,
                                 const volatile sig_atomic_t *stop, vs_sweep_row *row,
                                 int *h5_clean);

/* MPI (src/sweep_mpi.c, in the MPI plugin, libvoussoir-mpi: src/plugin.h). vs_sweep_mpi_begin
 * calls MPI_Init and returns this process's rank (*size: the number of ranks). On rank 0,
 * vs_sweep_mpi_serve hands out the runs next() gives (until it returns 0) to the other ranks one
 * at a time, and passes every row that comes back to take(); it returns once every other rank
 * has been told to stop. next() also sees the stop flag: after a stop it should return 0. On the
 * other ranks, vs_sweep_mpi_work runs what rank 0 hands out with run_case (the program's
 * vs_sweep_run_case) until told to stop. vs_sweep_mpi_end finalises. */
typedef struct {
  int (*next)(void *user);                           /* the next run (1-based), or 0: no more */
  void (*take)(void *user, const vs_sweep_row *row); /* a case's row, as it comes */
  void *user;
} vs_sweep_server;

/* The local pool (src/sweep_pool.c): the runs next() gives, each in a worker forked from this
 * process (in its own process group, so that a terminal's ^C reaches the sweep only), `jobs` at
 * a time; every row goes to take() as its worker ends. A stop (*stop_count > 0) starts no new
 * run and is passed on to the workers under way (the signal *stop_signal; a second stop:
 * SIGKILL). todo: the number of runs next() will give, for the progress line on stderr (when
 * progress is non-zero). Returns 0, or -1 when a worker cannot be started (errno). */
int vs_sweep_pool_serve(const vs_sweep_server *s, const vs_sweep_job *job, int jobs, int todo,
                        int progress, const volatile sig_atomic_t *stop_count,
                        const volatile sig_atomic_t *stop_signal);

int vs_sweep_mpi_begin(int *size);
void vs_sweep_mpi_serve(const vs_sweep_server *s, int size);
void vs_sweep_mpi_work(const vs_sweep_job *job, vs_sweep_case_fn run_case,
                       const volatile sig_atomic_t *stop, int *h5_clean);
void vs_sweep_mpi_end(void);

#endif
