/* voussoir: the program's entry point. Picks the command; HDF5 and cairo are not loaded here
 * (src/plugin/plugin.c loads them for the commands that need them). */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "plugin.h"
#include "stop.h"
#include "voussoir/version.h"

static const char *USAGE =
    "usage: voussoir run CASE [options]                        (voussoir run --help)\n"
    "       voussoir sweep CASE --alpha LIST --kn LIST [...]   (voussoir sweep --help)\n"
    "       voussoir calibrate CASE --target-dz-pct X [...]    (voussoir calibrate --help)\n"
    "       voussoir montecarlo CASE --samples N [...]         (voussoir montecarlo --help)\n"
    "       voussoir merge DIR... -o OUT                       (voussoir merge --help)\n"
    "       voussoir plot RUN.h5 [-o DIR] [--svg]              (voussoir plot --help)\n"
    "       voussoir blocks CASE [-o FILE]                     (voussoir blocks --help)\n"
    "       voussoir --help | --version\n"
    "\n"
    "Simulates a masonry arch of rigid voussoirs on dry, no-tension, frictional, elastic joints\n"
    "while its right support moves along a direction alpha (from the vertical). Follows the\n"
    "quasi-static equilibrium path (KINSOL) from self-weight; at every limit point integrates the\n"
    "motion (IDA) until it settles on another branch (a snap-through) or collapses, and reports\n"
    "the collapse displacement, the limit points and the hinges (joint, side, onset, label).\n"
    "Options take their value as the next word or after '=': --alpha 30, --alpha=30.\n"
    "\n";

static int dispatch(int argc, char **argv, int *h5_clean) {
  if (argc < 2) {
    fprintf(stderr, "%s%s", USAGE, VS_CLI_RUN_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  const char *cmd = argv[1];
  if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
    printf("%s%s", USAGE, VS_CLI_RUN_USAGE);
    return VS_EXIT_OK;
  }
  if (strcmp(cmd, "--version") == 0) {
    printf("voussoir %s\n", VS_VERSION);
    return VS_EXIT_OK;
  }
  if (strcmp(cmd, "run") == 0) return vs_cli_run(argc, argv, h5_clean);
  if (strcmp(cmd, "sweep") == 0) return vs_cli_sweep(argc, argv, h5_clean);
  if (strcmp(cmd, "calibrate") == 0) return vs_cli_calibrate(argc, argv);
  if (strcmp(cmd, "montecarlo") == 0) return vs_cli_montecarlo(argc, argv);
  if (strcmp(cmd, "merge") == 0) return vs_cli_merge(argc, argv);
  if (strcmp(cmd, "plot") == 0) return vs_cli_plot(argc, argv);
  if (strcmp(cmd, "blocks") == 0) return vs_cli_blocks(argc, argv);
  fprintf(stderr, "voussoir: unknown command '%s'\n%s", vs_q(cmd).s, USAGE);
  return VS_EXIT_BAD_INPUT;
}

#ifdef __SANITIZE_ADDRESS__
/* AddressSanitizer's defaults for this program (ASAN_OPTIONS in the environment adds to them and
 * wins). GCC 12's LeakSanitizer, tracking the dynamic thread-local storage of dlopen'ed objects
 * through __tls_get_addr, misreads glibc 2.36's TLS vector for some layouts of the loaded
 * objects and crashes in its exit scan ("Tracer caught signal 11", `voussoir plot` of a sweep's
 * summary once CHOLMOD and libgomp were no longer loaded at start). Without that tracking it
 * does not scan the plugins' dynamic TLS: memory only a plugin's thread-local variable points
 * to would be reported as leaked, never hidden (the sanitizer suite reports none). Exported:
 * the shared sanitizer run-time looks it up, and the program's symbols are hidden. */
__attribute__((visibility("default"))) const char *__asan_default_options(void);
__attribute__((visibility("default"))) const char *__asan_default_options(void) {
  return "intercept_tls_get_addr=0";
}
#endif

int main(int argc, char **argv) {
  vs_stop_catch(); /* first: a signal at any moment of a run ends it cleanly */
  if (argc < 2 || strcmp(argv[1], "run") != 0) vs_stop_release();
  signal(SIGXFSZ, SIG_IGN); /* a file size limit: the write fails with EFBIG, reported */
  int h5_clean = 1;
  const int rc = dispatch(argc, argv, &h5_clean);
  vs_plugin_end(h5_clean); /* HDF5 shut down when it was loaded */
  return rc;
}
