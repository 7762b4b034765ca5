/* The command lines of montecarlo and merge (their work: src/study/montecarlo_cmd.c). */
#define _GNU_SOURCE /* getopt_long */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "parse.h"

static const char *const MC_USAGE =
    "usage: voussoir montecarlo CASE --samples N [--seed S] [--set SECTION.KEY=VALUE]...\n"
    "                           [--max-wall-s S] [-j N] [--shard K/M] [-o DIR] [--resume] [-q]\n"
    "  --samples N   imperfect arches 0..N-1, each with its own draws ([imperfections])\n"
    "  --seed S      generator seed (same as --set imperfections.seed=S)\n"
    "  --max-wall-s S\n"
    "                each sample stops once it has taken S s of wall time (same as --set\n"
    "                run.max_wall_s=S): it is then a failed sample, its cause 'stopped: ...'\n"
    "  -j N          worker processes (default: the cores)\n"
    "  --shard K/M   run only the samples i with i mod M = K-1 (K in 1..M), for a scheduler's\n"
    "                array job; voussoir merge then joins the shards' directories\n"
    "  -o DIR        output directory (default montecarlo_out): samples.csv, statistics.csv,\n"
    "                summary.h5 (its charts: voussoir plot DIR/summary.h5); and the study's\n"
    "                montecarlo.manifest and montecarlo.journal (each sample's result as it ends);\n"
    "                one study at a time in DIR (DIR/study.lock): another there is refused\n"
    "  --resume      continue the study in DIR (same case, --set, --seed, --samples, --shard):\n"
    "                the samples in its journal are not run again (after a kill, a stop, a crash);\n"
    "                a row that is damaged or out of range is named on stderr and run again\n"
    "  -q            no progress line\n"
    "Values: --samples 100 or --samples=100.\n"
    "exit status: 0 done (failed samples are in the table with their cause), 1 every sample\n"
    "failed or the summary could not be written, 2 bad input (nothing written), 130\n"
    "interrupted (SIGINT/SIGTERM: no sample starts after it, those under way finish, or are\n"
    "dropped at a second signal, and the summary of the samples done is written; continue\n"
    "with --resume)\n";

static const char *const MERGE_USAGE =
    "usage: voussoir merge DIR... -o OUT\n"
    "Joins the directories of the shards of one Monte Carlo study (voussoir montecarlo --shard\n"
    "K/M, same case and seed) into one summary in OUT, as one run of every sample would write it:\n"
    "samples.csv, statistics.csv, summary.h5 (its charts: voussoir plot OUT/summary.h5).\n"
    "Each table is checked as a case file is: its header's fields (the case's keys) in their\n"
    "ranges, each once, the same in every shard; every row's fields; a problem is named by file,\n"
    "line and field.\n"
    "exit status: 0 done, 1 the summary could not be written, 2 bad input (a missing, foreign or\n"
    "malformed table, shards of different studies, a sample twice; nothing written)\n";

enum { OPT_SAMPLES = 256, OPT_SEED, OPT_SET, OPT_SHARD, OPT_RESUME, OPT_MAX_WALL };

static const struct option MC_OPTIONS[] = {
    {"samples", required_argument, NULL, OPT_SAMPLES},
    {"seed", required_argument, NULL, OPT_SEED},
    {"set", required_argument, NULL, OPT_SET},
    {"shard", required_argument, NULL, OPT_SHARD},
    {"resume", no_argument, NULL, OPT_RESUME},
    {"max-wall-s", required_argument, NULL, OPT_MAX_WALL},
    {0, 0, 0, 0}};

static const cli_command MONTECARLO = {"voussoir montecarlo", MC_USAGE, "j:o:q", MC_OPTIONS};

/* --shard K/M with 1 <= K <= M <= 1000000. */
static int parse_shard(const char *v, vs_mc_opts *o) {
  char k[32], m[32];
  const char *slash = strchr(v, '/');
  int ok = slash != NULL && (size_t)(slash - v) < sizeof k && strlen(slash + 1) < sizeof m;
  if (ok) {
    snprintf(k, sizeof k, "%.*s", (int)(slash - v), v);
    snprintf(m, sizeof m, "%s", slash + 1);
    long lk = 0, lm = 0;
    ok = vs_parse_long(k, &lk) == VS_NUM_OK && vs_parse_long(m, &lm) == VS_NUM_OK && lm >= 1 &&
         lm <= 1000000 && lk >= 1 && lk <= lm;
    o->shard_k = (int)lk;
    o->shard_m = (int)lm;
  }
  if (ok) return 0;
  fprintf(stderr, "voussoir montecarlo: --shard %s: expected K/M with 1 <= K <= M\n", vs_q(v).s);
  return VS_EXIT_BAD_INPUT;
}

/* The study's options, and the storage of the --set that --max-wall-s stands for. */
typedef struct {
  vs_mc_opts o;
  char max_wall[96];
} mc_args;

static int mc_option(void *user, int code, const char *value) {
  mc_args *a = user;
  vs_mc_opts *o = &a->o;
  const char *name = MONTECARLO.name;
  switch (code) {
  case OPT_SAMPLES: return cli_int(name, "--samples", value, 1, 10000000, &o->samples);
  case OPT_SEED: o->seed = value; return 0;
  case OPT_SET: return cli_add_set(name, value, o->sets, &o->nsets);
  case OPT_MAX_WALL:
    return cli_add_key_set(name, "--max-wall-s", "run.max_wall_s", value, a->max_wall,
                           sizeof a->max_wall, o->sets, &o->nsets);
  case OPT_SHARD: return parse_shard(value, o);
  case OPT_RESUME: o->resume = 1; return 0;
  case 'j': return cli_int(name, "-j", value, 1, 1024, &o->jobs);
  case 'o': o->dir = value; return 0;
  case 'q': o->quiet = 1; return 0;
  default: break; /* 1: the case */
  }
  if (o->case_path == NULL) {
    o->case_path = value;
    return 0;
  }
  fprintf(stderr, "voussoir montecarlo: unexpected argument %s\n%s", vs_q(value).s, MC_USAGE);
  return VS_EXIT_BAD_INPUT;
}

int vs_cli_montecarlo(int argc, char **argv) {
  const char *sets[VS_CLI_MAX_SETS];
  mc_args a = {.o = {.dir = "montecarlo_out", .sets = sets, .samples = -1, .shard_k = 1,
                      .shard_m = 1, .jobs = (int)sysconf(_SC_NPROCESSORS_ONLN)}};
  if (a.o.jobs < 1) a.o.jobs = 1;
  const int rc = cli_parse(&MONTECARLO, argc, argv, mc_option, &a);
  const vs_mc_opts o = a.o;
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (o.case_path == NULL || o.samples < 1) {
    fprintf(stderr, "voussoir montecarlo: needs a CASE and --samples N\n%s", MC_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  return vs_mc_main(&o);
}

/* --- merge --- */

enum { MERGE_MAX_DIRS = 256 };

static const struct option MERGE_OPTIONS[] = {{0, 0, 0, 0}};
static const cli_command MERGE = {"voussoir merge", MERGE_USAGE, "o:", MERGE_OPTIONS};

typedef struct {
  const char *dirs[MERGE_MAX_DIRS], *out;
  int nd;
} merge_args;

static int merge_option(void *user, int code, const char *value) {
  merge_args *a = user;
  if (code == 'o') {
    a->out = value;
    return 0;
  }
  if (a->nd < MERGE_MAX_DIRS) { /* 1: a directory */
    a->dirs[a->nd++] = value;
    return 0;
  }
  fprintf(stderr, "voussoir merge: at most %d directories\n", MERGE_MAX_DIRS);
  return VS_EXIT_BAD_INPUT;
}

int vs_cli_merge(int argc, char **argv) {
  merge_args a = {.nd = 0};
  const int rc = cli_parse(&MERGE, argc, argv, merge_option, &a);
  if (rc != 0) return rc < 0 ? VS_EXIT_OK : rc;
  if (a.nd == 0 || a.out == NULL) {
    fprintf(stderr, "voussoir merge: needs DIR... and -o OUT\n%s", MERGE_USAGE);
    return VS_EXIT_BAD_INPUT;
  }
  return vs_merge_main(a.dirs, a.nd, a.out);
}
