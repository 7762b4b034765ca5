/* The sweep's MPI farm (sweep_mpi.c, in the MPI library libvoussoir-mpi): rank 0 hands the runs
 * out, the other ranks run them. The job is the sweep command's, opaque here. */
#ifndef VS_SWEEP_MPI_H
#define VS_SWEEP_MPI_H

#include <signal.h>

#include "sweep_rows.h"

/* Run case `run` (1-based) of job in this process into row (the sweep command's
 * vs_sweep_run_case); *h5_clean becomes 0 when a record could not be written. */
typedef void (*vs_sweep_case_fn)(const void *job, int run, const volatile sig_atomic_t *stop,
                                 vs_sweep_row *row, int *h5_clean);

/* vs_sweep_mpi_begin calls MPI_Init and returns this process's rank (*size: the number of
 * ranks). On rank 0, vs_sweep_mpi_serve hands out the runs next() gives (until it returns 0) to the other ranks one
 * at a time, and passes every row that comes back to take(); it returns once every other rank
 * has been told to stop. next() also sees the stop flag: after a stop it should return 0. On the
 * other ranks, vs_sweep_mpi_work runs what rank 0 hands out with run_case (the program's
 * vs_sweep_run_case) until told to stop. vs_sweep_mpi_end finalises. */
typedef struct {
  int (*next)(void *user);                           /* the next run (1-based), or 0: no more */
  void (*take)(void *user, const vs_sweep_row *row); /* a case's row, as it comes */
  void *user;
} vs_sweep_server;

int vs_sweep_mpi_begin(int *size);
void vs_sweep_mpi_serve(const vs_sweep_server *s, int size);
void vs_sweep_mpi_work(const void *job, vs_sweep_case_fn run_case,
                       const volatile sig_atomic_t *stop, int *h5_clean);
void vs_sweep_mpi_end(void);

#endif
