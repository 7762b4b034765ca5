/* The plot library's plugin table (libvoussoir-plot): what the program calls through it after
 * loading it with dlopen (src/plugin/plugin.h). */
#ifndef VS_PLOT_PLUGIN_H
#define VS_PLOT_PLUGIN_H

#include "plugin_head.h"
#include "voussoir/limit.h"
#include "voussoir/montecarlo.h"

/* libvoussoir-plot: exported as vs_plot_plugin_table. */
typedef struct {
  vs_plugin_head head;
  /* the plot command's work: the arch pictures of a record into dir (ext "png" or "svg"), or,
   * for a sweep's or a Monte Carlo study's summary.h5, dir checked and created (their charts
   * are matplotlib's, run by src/cli/cli_plot.c); an exit status */
  int (*plot_command)(const char *record, const char *dir, const char *ext);
  vs_status (*mc_write_summary)(const char *dir, const vs_case *base, vs_mc_sample *samples,
                                int n, vs_error *err);
  void (*plot_release)(void);
  /* analysis.type = limit, --plot: the thrust line of the limit analysis la over its arch into
   * path (plot_limit.h) */
  vs_status (*limit_picture)(const char *path, const vs_run_def *d, const vs_limit_analysis *la,
                             vs_error *err);
} vs_plot_plugin;

/* The plot command's work (plot_cmd.c, in the plot library), as in vs_plot_plugin. */
int vs_plot_command(const char *record, const char *dir, const char *ext);

#endif
