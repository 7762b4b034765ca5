/* The command line of plot: the arch pictures in C (src/plot/plot_cmd.c, in the plot plugin),
 * then the charts with matplotlib (python3 -m voussoir.figures, python/voussoir/figures), one
 * plotting stack for charts. */
#define _GNU_SOURCE /* getopt_long; environ */
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli.h"
#include "outpath.h"
#include "plugin.h"

extern char **environ;

/* The arch pictures were drawn (or there are none: a study) but not the charts: no python3, or
 * it lacks matplotlib, h5py, numpy or the voussoir package. */
enum { VS_EXIT_NO_CHARTS = 3 };

static const char *const PLOT_USAGE =
    "usage: voussoir plot RUN.h5|SWEEP/summary.h5|MC/summary.h5 [-o DIR] [--svg]\n"
    "Draws a recorded run's arch at true scale (cairo): the reference state, each hinge's onset,\n"
    "each limit point and settled snap-through, the collapse and the end of the record (open\n"
    "joints shaded, hinges marked on their side with labels A-E, the support displacement\n"
    "annotated), files arch_*.png (or .svg with --svg); plots.json says what each shows (its\n"
    "title, the hinges labelled: label, side, joints). Then the charts, with matplotlib\n"
    "(the Python module voussoir.figures), each as .png, .pdf and .svg, a journal column wide,\n"
    "editable: of a run, curves (the supports' forces against the support displacement),\n"
    "hinges (the hinges and open joints against it) and, for a load run, load_deflection; of a\n"
    "sweep's summary.h5, domain (dx/L against dz/L, one line per k_n, each point marked by its\n"
    "mode I, II, III) and sensitivity (delta_u/L against alpha, or k_n); of a Monte Carlo\n"
    "study's summary.h5, fragility (with its 95 % band), convergence and hinge_histogram.\n"
    "DIR: default RUN_plots next to the file. The charts' Python: $VOUSSOIR_PYTHON (default\n"
    "python3 on PATH) with the voussoir package this program ships (the build tree's python/,\n"
    "or PREFIX/share/voussoir/python) ahead of PYTHONPATH.\n"
    "exit status: 0 done, 1 a picture could not be written, 2 bad input (not a record nor a\n"
    "study's summary, an output that is not a regular file), 3 the arch pictures drawn but no\n"
    "charts: python3, matplotlib, h5py, numpy or the voussoir package missing (said on stderr)\n";

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

/* The voussoir package this program ships, in dir (PATH_MAX): beside the program in a build
 * tree (BUILD/python), or PREFIX/share/voussoir/python for an installed one. 1 found, 0 not. */
static int package_dir(char *dir) {
  char exe[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return 0;
  exe[n] = '\0';
  char *slash = strrchr(exe, '/');
  if (slash == NULL) return 0;
  *slash = '\0';
  static const char *const WHERE[] = {"/python", "/../share/voussoir/python"};
  static const char PROBE[] = "/voussoir/figures/__init__.py";
  const size_t ne = strlen(exe);
  for (size_t i = 0; i < sizeof WHERE / sizeof *WHERE; i++) {
    const size_t nw = strlen(WHERE[i]);
    if (ne + nw + sizeof PROBE > PATH_MAX) continue;
    char probe[PATH_MAX];
    struct stat st;
    memcpy(dir, exe, ne);
    memcpy(dir + ne, WHERE[i], nw + 1);
    memcpy(probe, dir, ne + nw);
    memcpy(probe + ne + nw, PROBE, sizeof PROBE);
    if (stat(probe, &st) == 0 && S_ISREG(st.st_mode)) return 1;
  }
  return 0;
}

/* Imports the charts' entry point, or says what is missing (exit 3); then runs it. */
static const char *const BOOT =
    "import sys\n"
    "try:\n"
    "    from voussoir.figures import main\n"
    "except ImportError as e:\n"
    "    sys.stderr.write('voussoir plot: no charts: %s cannot import voussoir.figures (%s); "
    "Debian: apt-get install python3-matplotlib python3-h5py python3-numpy python3-cffi; "
    "docs/python.md\\n' % (sys.executable, e))\n"
    "    sys.exit(3)\n"
    "sys.exit(main(sys.argv[1:]))\n";

/* The environment of the charts' Python: environ with PYTHONPATH led by pkg (NULL: as it is),
 * MPLBACKEND=Agg unless set. Returns a NULL-terminated array (free it and its first `owned`
 * strings), or NULL when out of memory. */
static char **chart_env(const char *pkg, int *owned) {
  size_t n = 0;
  while (environ[n] != NULL) n++;
  char **env = calloc(n + 3, sizeof *env);
  if (env == NULL) return NULL;
  const char *pp = getenv("PYTHONPATH");
  size_t k = 0;
  *owned = 0;
  if (pkg != NULL) {
    const size_t len = strlen(pkg) + (pp != NULL ? strlen(pp) + 1 : 0) + sizeof "PYTHONPATH=";
    env[k] = malloc(len);
    if (env[k] == NULL) {
      free(env);
      return NULL;
    }
    snprintf(env[k++], len, "PYTHONPATH=%s%s%s", pkg, pp != NULL && *pp ? ":" : "",
             pp != NULL ? pp : "");
    *owned = 1;
  }
  if (getenv("MPLBACKEND") == NULL) env[k++] = "MPLBACKEND=Agg";
  for (size_t i = 0; i < n; i++)
    if (pkg == NULL || strncmp(environ[i], "PYTHONPATH=", 11) != 0) env[k++] = environ[i];
  env[k] = NULL;
  return env;
}

/* python3 -m voussoir.figures FILE -o DIR: the exit status (0, 1, or VS_EXIT_NO_CHARTS with
 * the reason printed). */
static int run_charts(const char *file, const char *dir) {
  const char *py = getenv("VOUSSOIR_PYTHON");
  if (py == NULL || *py == '\0') py = "python3";
  char pkg[PATH_MAX];
  const int found = package_dir(pkg);
  int owned;
  char **env = chart_env(found ? pkg : NULL, &owned);
  if (env == NULL) {
    fputs("voussoir plot: out of memory\n", stderr);
    return VS_EXIT_FAILED;
  }
  char *argv[] = {(char *)py, "-c", (char *)BOOT, (char *)file, "-o", (char *)dir, NULL};
  fflush(stdout);
  pid_t pid;
  const int rc = posix_spawnp(&pid, py, NULL, NULL, argv, env);
  if (owned) free(env[0]);
  free(env);
  if (rc != 0) {
    fprintf(stderr, "voussoir plot: no charts: cannot run %s: %s (set VOUSSOIR_PYTHON to a "
            "python3 with matplotlib, h5py and numpy; docs/python.md)\n", vs_q(py).s,
            strerror(rc));
    return VS_EXIT_NO_CHARTS;
  }
  int status;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      fprintf(stderr, "voussoir plot: %s: %s\n", py, strerror(errno));
      return VS_EXIT_FAILED;
    }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return VS_EXIT_OK;
  if (WIFEXITED(status) && WEXITSTATUS(status) == VS_EXIT_NO_CHARTS) return VS_EXIT_NO_CHARTS;
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) return VS_EXIT_INTERRUPTED;
  fprintf(stderr, "voussoir plot: the charts (%s -m voussoir.figures) failed\n", py);
  return VS_EXIT_FAILED;
}

int vs_cli_plot(int argc, char **argv) {
  plot_args a = {NULL, NULL, "png"};
  const int rc = cli_parse(&PLOT, argc, argv, plot_option, &a);
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (a.run == NULL) {
    fprintf(stderr, "voussoir plot: needs a RUN.h5 record\n%s", PLOT_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  char defdir[VS_OUTPATH_DIR_MAX + 1];
  if (a.dir == NULL) { /* RUN without its extension, and "_plots" */
    const char *dot = strrchr(a.run, '.'), *slash = strrchr(a.run, '/');
    const size_t n = dot != NULL && (slash == NULL || dot > slash) ? (size_t)(dot - a.run)
                                                                   : strlen(a.run);
    if (n + sizeof "_plots" > sizeof defdir) {
      fprintf(stderr, "voussoir plot: %s: name too long for the default -o %.*s..._plots (at "
              "most %d bytes): give -o DIR\n", vs_q(a.run).s, 32, a.run,
              (int)VS_OUTPATH_DIR_MAX);
      return VS_EXIT_BAD_INPUT;
    }
    snprintf(defdir, sizeof defdir, "%.*s_plots", (int)n, a.run);
    a.dir = defdir;
  }
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir plot") != 0) return VS_EXIT_FAILED;
  const int arch = vs_plugin_plot()->plot_command(a.run, a.dir, a.ext);
  if (arch == VS_EXIT_BAD_INPUT) return arch;
  const int charts = run_charts(a.run, a.dir);
  return arch != VS_EXIT_OK ? arch : charts;
}
