/* The one option loop of the command line: getopt_long over a command's table (src/cli/cli.h); and
 * the stop signals' handler, installed the same way by every command that handles them. */
#define _GNU_SOURCE /* getopt_long */
#include <signal.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "parse.h"

/* -h or --help before any "--": the command's usage is all that is asked. */
static int wants_help(int argc, char **argv) {
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "--") == 0) return 0;
    if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) return 1;
  }
  return 0;
}

/* The option getopt refused, as the user wrote it: a long one as its word without "=VALUE"
 * (getopt gives its code, >= 256, or 0 when unknown), a short one as -X (it may sit inside a
 * group such as -qx, so its word is not the option). */
static void refused_option(char **argv, char *buf, size_t size) {
  const char *word = argv[optind - 1];
  if (optopt == 0 || optopt >= 256)
    snprintf(buf, size, "%.*s", (int)strcspn(word, "="), word);
  else
    snprintf(buf, size, "-%c", optopt);
}

int cli_parse(const cli_command *cmd, int argc, char **argv, cli_option_fn on_option,
              void *user) {
  if (wants_help(argc, argv)) {
    fputs(cmd->usage, stdout);
    return -1;
  }
  /* "-": operands in place (code 1), so that their order with the options is kept; ":": a
   * missing value is told apart from an unknown option */
  char shortopts[64];
  snprintf(shortopts, sizeof shortopts, "-:%s", cmd->shortopts);
  optind = 0; /* glibc: a full restart of getopt's state */
  opterr = 0;
  int code, rc = 0;
  while (rc == 0 &&
         (code = getopt_long(argc - 1, argv + 1, shortopts, cmd->longopts, NULL)) != -1) {
    char word[128];
    if (code == '?' || code == ':') {
      refused_option(argv + 1, word, sizeof word);
      const char *why = code == ':' ? "needs a value" : optopt >= 256 ? "takes no value" : NULL;
      if (why != NULL) fprintf(stderr, "%s: %s %s\n%s", cmd->name, vs_q(word).s, why, cmd->usage);
      else fprintf(stderr, "%s: unknown option %s\n%s", cmd->name, vs_q(word).s, cmd->usage);
      return VS_EXIT_BAD_INPUT;
    }
    rc = on_option(user, code, optarg);
  }
  for (int i = optind + 1; rc == 0 && i < argc; i++) /* the operands after "--" */
    rc = on_option(user, 1, argv[i]);
  return rc;
}

int cli_int(const char *name, const char *option, const char *text, int lo, int hi, int *out) {
  vs_error err;
  if (vs_parse_option_int(option, text, lo, hi, out, &err) == VS_OK) return 0;
  fprintf(stderr, "%s: %s\n", name, err.msg);
  return VS_EXIT_BAD_INPUT;
}

int cli_double(const char *name, const char *option, const char *text, double lo, double hi,
               double *out) {
  vs_error err;
  if (vs_parse_option_double(option, text, lo, hi, out, &err) == VS_OK) return 0;
  fprintf(stderr, "%s: %s\n", name, err.msg);
  return VS_EXIT_BAD_INPUT;
}

int cli_add_set(const char *name, const char *value, const char **sets, int *nsets) {
  if (*nsets >= VS_CLI_MAX_SETS) {
    fprintf(stderr, "%s: at most %d --set\n", name, VS_CLI_MAX_SETS);
    return VS_EXIT_BAD_INPUT;
  }
  sets[(*nsets)++] = value;
  return 0;
}

int cli_add_key_set(const char *name, const char *option, const char *key, const char *value,
                    char *buf, size_t size, const char **sets, int *nsets) {
  const int n = snprintf(buf, size, "%s=%s", key, value);
  if (n < 0 || (size_t)n >= size) {
    fprintf(stderr, "%s: %s %s: too long (allowed: a number)\n", name, option, vs_q(value).s);
    return VS_EXIT_BAD_INPUT;
  }
  return cli_add_set(name, buf, sets, nsets);
}
