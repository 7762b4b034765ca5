/* The Monte Carlo's MPI ranks (src/mpi/montecarlo_mpi.c): in the program's MPI plugin
 * (libvoussoir-mpi, src/plugin/plugin.h), built only with VS_MPI; not part of the installed API. */
#ifndef VS_MONTECARLO_MPI_H
#define VS_MONTECARLO_MPI_H

#include "voussoir/montecarlo.h"

/* What rank 0 serves: open(user) once MPI is up (0, or an exit status: then nothing is handed
 * out), next(user) the next sample to hand out (-1: none left), take(user, r) each result. */
typedef struct {
  int (*open)(void *user);
  int (*next)(void *user);
  void (*take)(void *user, const vs_mc_sample *r);
  void *user;
} vs_mc_server;

/* The study's samples across the ranks of an MPI job: rank 0 opens the study and hands the
 * samples out one at a time, taking their results (one rank: it runs them itself); *opened
 * receives open's status on rank 0, *ranks the number of ranks. Calls MPI_Init and
 * MPI_Finalize. Returns this process's rank. */
int vs_mc_run_mpi(const vs_case *c, const vs_mc_server *s, int *opened, int *ranks);

#endif
