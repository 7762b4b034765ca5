/* The record plugin's table (libvoussoir-record; record_plugin.h): the one symbol the program
 * looks up in it. */
#include "record_plugin.h"
#include "voussoir/version.h"

extern VS_PLUGIN_TABLE const vs_record_plugin vs_record_plugin_table;
VS_PLUGIN_TABLE const vs_record_plugin vs_record_plugin_table = {
    {VS_PLUGIN_ABI, VS_VERSION},
    vs_output_opts_default,
    vs_output_create,
    vs_output_sample,
    vs_output_event,
    vs_output_interrupt,
    vs_output_finish,
    vs_output_error,
    vs_output_rows,
    vs_output_xdmf_path,
    vs_output_xdmf_written,
    vs_output_xdmf_path_for,
    vs_output_destroy,
    vs_output_process_init,
    vs_output_process_end,
    vs_sweep_summary_h5,
};
