/* The limit analysis' picture (plot_limit.c): private to the plot library and its tests. */
#ifndef VS_PLOT_LIMIT_H
#define VS_PLOT_LIMIT_H

#include "voussoir/def.h"
#include "voussoir/limit.h"
#include "voussoir/plot.h"

/* What the picture draws: solution s (the collapse when a live load found one, else the
 * least-thickness solution, else the least thrust) on geometry g (the arch at thickness x
 * factor, at rest: q zeros), the joints' resultants N (N) and moments M (N m, about each joint's
 * centre, > 0 toward the extrados), the hinges (the mechanism's, or the thrust line's touches)
 * and a title. */
typedef struct {
  const vs_limit_solution *s;
  double factor;
  vs_geometry *g;
  double *N, *M, *q;
  vs_hinge *hinges;
  int n_hinges;
  char title[200];
} vs_plot_limit;

/* Fill p from the analysis la of definition d; free it with vs_plot_limit_free. VS_ERR_INVALID
 * when no solution is optimal, the geometry's errors, VS_ERR_NOMEM. */
vs_status vs_plot_limit_pick(const vs_run_def *d, const vs_limit_analysis *la, vs_plot_limit *p,
                             vs_error *err);
void vs_plot_limit_free(vs_plot_limit *p);
/* The arch picture's arguments for p (borrowing its arrays). */
vs_plot_arch_args vs_plot_limit_args(const vs_plot_limit *p);
/* The picture of la into path (PNG, or SVG by its extension): the arch, the thrust line, the
 * hinges, and for the collapse the live load. Errors as vs_plot_arch_draw and the above. */
vs_status vs_plot_limit_picture(const char *path, const vs_run_def *d,
                                const vs_limit_analysis *la, vs_error *err);

#endif
