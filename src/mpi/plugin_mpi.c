/* The MPI plugin's table (libvoussoir-mpi; mpi_plugin.h): the one symbol the program looks up in
 * it. */
#include "mpi_plugin.h"
#include "voussoir/version.h"

extern VS_PLUGIN_TABLE const vs_mpi_plugin vs_mpi_plugin_table;
VS_PLUGIN_TABLE const vs_mpi_plugin vs_mpi_plugin_table = {
    {VS_PLUGIN_ABI, VS_VERSION},
    vs_mc_run_mpi,
    vs_sweep_mpi_begin,
    vs_sweep_mpi_serve,
    vs_sweep_mpi_work,
    vs_sweep_mpi_end,
};
