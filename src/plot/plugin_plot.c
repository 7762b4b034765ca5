/* The plot plugin's table (libvoussoir-plot; plot_plugin.h): the one symbol the program looks
 * up in it. */
#include "plot_limit.h"
#include "plot_plugin.h"
#include "voussoir/plot.h"
#include "voussoir/version.h"

extern VS_PLUGIN_TABLE const vs_plot_plugin vs_plot_plugin_table;
VS_PLUGIN_TABLE const vs_plot_plugin vs_plot_plugin_table = {
    {VS_PLUGIN_ABI, VS_VERSION},
    vs_plot_command,
    vs_mc_write_summary,
    vs_plot_release,
    vs_plot_limit_picture,
};
