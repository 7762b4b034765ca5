/* The command line of plot (its work: src/plot/plot_cmd.c, in the plot plugin). */
#define _GNU_SOURCE /* getopt_long */
#include <stdio.h>

#include "cli.h"
#include "plugin.h"

static const char *const PLOT_USAGE =
    "usage: voussoir plot RUN.h5|SWEEP/summary.h5 [-o DIR] [--svg]\n"
    "Draws the recorded run at true scale: the reference state, each hinge's onset, each limit\n"
    "point and settled snap-through, the collapse and the end of the record (open joints shaded,\n"
    "hinges marked on their side with labels A-E, the support displacement annotated), and the\n"
    "support reaction and hinge joints against the support displacement. Files arch_*.png (or\n"
    ".svg) and curves.png go to DIR (default: RUN_plots next to the record).\n"
    "Given a sweep's summary.h5, draws domain.png: the support displacement at collapse, dx/L\n"
    "against dz/L, one line per k_n through the directions alpha, each point marked by its mode\n"
    "(I, II, III); and sensitivity.png: delta_u/L against alpha, one line per k_n (against k_n\n"
    "when the sweep varies only k_n).\n"
    "plots.json in DIR says what each picture shows: its title, the hinges labelled in each arch\n"
    "picture (label, side, joints), the points of a sweep's pictures.\n"
    "exit status: 0 done, 1 a picture could not be written, 2 bad input (not a record, an output\n"
    "that is not a regular file)\n";

enum { OPT_SVG = 256 };

static const struct option PLOT_OPTIONS[] = {{"svg", no_argument, NULL, OPT_SVG}, {0, 0, 0, 0}};
static const cli_command PLOT = {"voussoir plot", PLOT_USAGE, "o:", PLOT_OPTIONS};

typedef struct {
  const char *run, *dir, *ext;
} plot_args;

static int plot_option(void *user, int code, const char *value) {
  plot_args *a = user;
  if (code == 'o') a->dir = value;
  else if (code == OPT_SVG) a->ext = "svg";
  else if (a->run == NULL) a->run = value; /* 1: the record */
  else {
    fprintf(stderr, "voussoir plot: unexpected argument %s\n%s", vs_q(value).s, PLOT_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  return 0;
}

int vs_cli_plot(int argc, char **argv) {
  plot_args a = {NULL, NULL, "png"};
  const int rc = cli_parse(&PLOT, argc, argv, plot_option, &a);
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (a.run == NULL) {
    fprintf(stderr, "voussoir plot: needs a RUN.h5 record\n%s", PLOT_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir plot") != 0) return VS_EXIT_FAILED;
  return vs_plugin_plot()->plot_command(a.run, a.dir, a.ext);
}
