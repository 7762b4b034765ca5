/* The Monte Carlo's MPI ranks (src/montecarlo_mpi.c): in the program's MPI plugin
 * (libvoussoir-mpi, src/plugin.h), built only with VS_MPI; not part of the installed API. */
#ifndef VS_MONTECARLO_MPI_H
#define VS_MONTECARLO_MPI_H

#include "voussoir/montecarlo.h"

/* The run of the listed samples across the ranks of an MPI job: rank 0 hands them out one at a
 * time and gathers results[i] for samples[i]; *ranks receives the number of ranks. Calls
 * MPI_Init and MPI_Finalize. Returns this process's rank (only rank 0 has the results). */
int vs_mc_run_mpi(const vs_case *c, const int *samples, int n, vs_mc_sample *results, int *ranks);

#endif
