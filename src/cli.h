/* The command line of the voussoir program (private to it): every command's options are read by
 * one getopt_long loop (cli_parse, src/cli_opts.c), so that `--alpha 30` and `--alpha=30` mean
 * the same everywhere, every command answers -h/--help with its own usage, and an unknown
 * option, a missing value or an extra operand is refused the same way (exit status 2, the
 * culprit named). One file per command or group of commands: cli_run.c (run), cli_sweep.c
 * (sweep, calibrate), cli_montecarlo.c (montecarlo, merge), cli_plot.c (plot); cli_main.c
 * dispatches. The commands' bodies stay where they were (sweep.c, calibrate.c,
 * montecarlo_cmd.c, plot_cmd.c) and receive the parsed options. */
#ifndef VS_CLI_H
#define VS_CLI_H

#include <getopt.h>
#include <signal.h>

#include "sweep_private.h"
#include "voussoir/case.h"
#include "voussoir/status.h"

/* Exit statuses of every command. */
enum { VS_EXIT_OK = 0, VS_EXIT_FAILED = 1, VS_EXIT_BAD_INPUT = 2, VS_EXIT_INTERRUPTED = 130 };

/* Most --set overrides one command line may carry. */
enum { VS_CLI_MAX_SETS = 64 };

/* What cli_parse needs to know about a command. Its options are given twice, as getopt_long
 * wants them: the short ones (e.g. "o:qj:") and the long ones (terminated by a zero entry); an
 * option's code is its short letter or a value >= 256 for a long-only option. */
typedef struct {
  const char *name;  /* in messages: "voussoir" (run) or "voussoir sweep" */
  const char *usage; /* printed by -h/--help (stdout) and after a usage error (stderr) */
  const char *shortopts;
  const struct option *longopts;
} cli_command;

/* Called for every option in the order given (code, its value or NULL) and with code 1 for
 * every operand (a word that is not an option, "-" included). Returns 0 to go on, or an exit
 * status (after printing why). */
typedef int (*cli_option_fn)(void *user, int code, const char *value);

/* Read argv[2..argc-1] (argv[1] is the command). When -h or --help is among them (before a
 * "--"), prints the usage on stdout and returns -1 without calling on_option: the caller
 * returns VS_EXIT_OK. Otherwise returns 0 when every option was taken, or an exit status: an
 * unknown option, an option without its value, or on_option's refusal. */
int cli_parse(const cli_command *cmd, int argc, char **argv, cli_option_fn on_option,
              void *user);

/* The value of an integer or real option in [lo, hi] (vs_parse_option_*), or VS_EXIT_BAD_INPUT
 * after printing "NAME: OPTION TEXT: reason (allowed: ...)". */
int cli_int(const char *name, const char *option, const char *text, int lo, int hi, int *out);
int cli_double(const char *name, const char *option, const char *text, double lo, double hi,
               double *out);

/* A word of the command line or a path, quoted for a message (vs_quote: no control character or
 * escape sequence reaches the terminal), by value: cli_q(path).s lives until the end of the
 * printf that uses it. */
typedef struct {
  char s[1024];
} cli_quoted;
static inline cli_quoted cli_q(const char *s) {
  cli_quoted q;
  vs_quote(s, q.s, sizeof q.s);
  return q;
}

/* Keep one more --set value; VS_EXIT_BAD_INPUT beyond VS_CLI_MAX_SETS. */
int cli_add_set(const char *name, const char *value, const char **sets, int *nsets);

/* An option that stands for a --set (--max-wall-s S: run.max_wall_s=S): "KEY=VALUE" built in
 * buf (size bytes, living as long as sets) and kept as cli_add_set keeps it (checked with the
 * other --set, where the case is read); VS_EXIT_BAD_INPUT when it does not fit. */
int cli_add_key_set(const char *name, const char *option, const char *key, const char *value,
                    char *buf, size_t size, const char **sets, int *nsets);

/* The usage of run (src/cli_run.c), which the program's own --help ends with. */
extern const char VS_CLI_RUN_USAGE[];

/* Install fn for SIGINT and SIGTERM (no SA_RESTART: a blocking wait returns with EINTR), the
 * stop signals every command handles its own way (src/cli_opts.c). */
void cli_on_stop_signals(void (*fn)(int));

/* The stop flag set by SIGINT/SIGTERM during `run` (src/cli_main.c). */
const volatile sig_atomic_t *cli_stop_flag(void);

/* The commands (argv as given to main). *h5_clean becomes 0 when a record this process wrote
 * failed (see vs_output_process_end). */
int vs_cli_run(int argc, char **argv, int *h5_clean);
int vs_cli_sweep(int argc, char **argv, int *h5_clean);
int vs_cli_calibrate(int argc, char **argv);
int vs_cli_montecarlo(int argc, char **argv);
int vs_cli_merge(int argc, char **argv);
int vs_cli_plot(int argc, char **argv);

/* --- the commands' bodies, given what the command line asked --- */

/* sweep (src/sweep.c). */
typedef struct {
  const char *case_path, *dir; /* dir: default "sweep_out" */
  const char *mode_flag;       /* "--first-limit", "--dynamic" or NULL */
  const char **sets;
  int nsets, nax, jobs, quiet, resume;
  vs_sweep_axis *ax;
} vs_sweep_opts;
/* SIGINT/SIGTERM handled by the sweep from now on (call it before parsing). */
void vs_sweep_catch_signals(void);
int vs_sweep_main(const vs_sweep_opts *o, int *h5_clean);

/* calibrate (src/calibrate.c). */
typedef struct {
  const char *case_path;
  const char **sets;
  int nsets, dx, quiet; /* dx: the target is dx/L (else dz/L) */
  double target, kn_min, kn_max, tol;
} vs_calibrate_opts;
int vs_calibrate_main(const vs_calibrate_opts *o);

/* montecarlo and merge (src/montecarlo_cmd.c). */
typedef struct {
  const char *case_path, *dir, *seed;
  const char **sets;
  int nsets, samples, jobs, quiet, shard_k, shard_m, resume;
} vs_mc_opts;
int vs_mc_main(const vs_mc_opts *o);
int vs_merge_main(const char *const *dirs, int ndirs, const char *out);

#endif
