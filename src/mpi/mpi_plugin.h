/* The MPI library's plugin table (libvoussoir-mpi): what the program calls through it after
 * loading it with dlopen under mpirun (src/plugin/plugin.h). */
#ifndef VS_MPI_PLUGIN_H
#define VS_MPI_PLUGIN_H

#include "montecarlo_mpi.h"
#include "plugin_head.h"
#include "sweep_mpi.h"

/* libvoussoir-mpi: exported as vs_mpi_plugin_table (montecarlo_mpi.h, sweep_mpi.h). */
typedef struct {
  vs_plugin_head head;
  int (*mc_run)(const vs_case *c, const vs_mc_server *s, int *opened, int *ranks);
  int (*sweep_begin)(int *size);
  void (*sweep_serve)(const vs_sweep_server *s, int size);
  void (*sweep_work)(const void *job, vs_sweep_case_fn run_case,
                     const volatile sig_atomic_t *stop, int *h5_clean);
  void (*sweep_end)(void);
} vs_mpi_plugin;

#endif
