/* The command line of the voussoir program (private to it): every command's options are read by
 * one getopt_long loop (cli_parse, src/cli/cli_opts.c), so that `--alpha 30` and `--alpha=30` mean
 * the same everywhere, every command answers -h/--help with its own usage, and an unknown
 * option, a missing value or an extra operand is refused the same way (exit status 2, the
 * culprit named). One file per command or group of commands: cli_run.c (run), cli_sweep.c
 * (sweep, calibrate), cli_montecarlo.c (montecarlo, merge), cli_plot.c (plot), cli_blocks.c
 * (blocks); cli_main.c
 * dispatches. The commands' bodies stay where they were (sweep.c, calibrate.c,
 * montecarlo_cmd.c, plot_cmd.c) and receive the parsed options. */
#ifndef VS_CLI_H
#define VS_CLI_H

#include <getopt.h>
#include <signal.h>

#include "exit_status.h"
#include "quote.h"
#include "study.h"
#include "voussoir/case.h"
#include "voussoir/status.h"

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

/* Keep one more --set value; VS_EXIT_BAD_INPUT beyond VS_CLI_MAX_SETS. */
int cli_add_set(const char *name, const char *value, const char **sets, int *nsets);

/* An option that stands for a --set (--max-wall-s S: run.max_wall_s=S): "KEY=VALUE" built in
 * buf (size bytes, living as long as sets) and kept as cli_add_set keeps it (checked with the
 * other --set, where the case is read); VS_EXIT_BAD_INPUT when it does not fit. */
int cli_add_key_set(const char *name, const char *option, const char *key, const char *value,
                    char *buf, size_t size, const char **sets, int *nsets);

/* The usage of run (src/cli/cli_run.c), which the program's own --help ends with. */
extern const char VS_CLI_RUN_USAGE[];


/* The commands (argv as given to main). *h5_clean becomes 0 when a record this process wrote
 * failed (see vs_output_process_end). */
int vs_cli_run(int argc, char **argv, int *h5_clean);
int vs_cli_sweep(int argc, char **argv, int *h5_clean);
int vs_cli_calibrate(int argc, char **argv);
int vs_cli_montecarlo(int argc, char **argv);
int vs_cli_merge(int argc, char **argv);
int vs_cli_plot(int argc, char **argv);
int vs_cli_blocks(int argc, char **argv);

#endif
