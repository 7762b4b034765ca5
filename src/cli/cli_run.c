/* The run command: create -> configure -> run -> report -> destroy; the history to a CSV and,
 * through the record plugin (src/plugin/plugin.h), to an HDF5 record. */
#define _GNU_SOURCE /* getopt_long; isatty, ftruncate */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "stop.h"
#include "plugin.h"
#include "voussoir/case.h"
#include "outpath.h"
#include "voussoir/output.h"
#include "voussoir/report.h"
#include "voussoir/run.h"
#include "voussoir/units.h"

enum { EXIT_RUN_FAILED = VS_EXIT_FAILED, EXIT_BAD_INPUT = VS_EXIT_BAD_INPUT,
       EXIT_INTERRUPTED = VS_EXIT_INTERRUPTED };

const char VS_CLI_RUN_USAGE[] =
    "usage: voussoir run CASE [options]\n"
    "options for run (a value follows its option as the next word or after '=': --alpha 30,\n"
    "--alpha=30):\n"
    "  --alpha DEG            support direction from the vertical, deg (0 = settlement,\n"
    "                         90 = outward spreading); same as --set support.alpha_deg=DEG\n"
    "  --kn N_MM3             joint normal stiffness, N/mm^3; same as --set joints.kn_N_mm3=N_MM3\n"
    "  --set SECTION.KEY=VAL  override any case key (repeatable; every key: man voussoir, docs/case-file.md)\n"
    "  --dynamic              integrate the whole loading dynamically from rest at the support\n"
    "                         rate (no quasi-static phase); same as --set dynamic.full=1\n"
    "  --first-limit          stop at the first limit point (no dynamics); --set dynamic.follow=0\n"
    "  --max-wall-s S         stop the run once it has taken S seconds of wall time (checked at\n"
    "                         every step of every phase); its record, summary and JSON say\n"
    "                         'stopped: wall-time limit S s reached'; 0: no limit (default);\n"
    "                         same as --set run.max_wall_s=S\n"
    "  --json                 print one JSON object on stdout instead of the summary\n"
    "                         (--set analysis.type=limit: the limit analysis alone, no path and\n"
    "                         no record: load factor, least and greatest thrust, thickness)\n"
    "  -o FILE.h5             the HDF5 record of the run (default: the case's name with .h5, in\n"
    "                         the current directory) and its XDMF sidecar FILE.xmf (ParaView);\n"
    "                         its name: printable UTF-8 without ':' or '|' (the sidecar names\n"
    "                         it), at most 249 bytes as NAME.h5 (NAME.xmf and a working\n"
    "                         suffix such as .lock must fit in 255)\n"
    "  --no-record            no HDF5 record (without --csv either, the run stops at the\n"
    "                         collapse: the fall after it is integrated only to be recorded)\n"
    "  --compress             deflate the HDF5 record (level 4 with shuffle; for archives:\n"
    "                         about a fifth smaller, slower to write; default: uncompressed)\n"
    "  --snapshot-share S     the record at FILE.h5 is a whole copy of the file HDF5 writes\n"
    "                         (FILE.h5.part), renamed into place after a flush, so that a run\n"
    "                         killed at any moment leaves a readable record: copies take at\n"
    "                         most this share of the wall time, in [1e-6, 1] (default 0.1;\n"
    "                         1: after every flush, which loses no more than 64 rows)\n"
    "  --plot FILE            analysis.type=limit only: its picture, PNG (SVG for FILE.svg):\n"
    "                         the thrust line over the arch, with the mechanism's hinges (a\n"
    "                         live load's collapse), else at the least thickness, its touches\n"
    "  --csv FILE             also write the history as CSV (one row per equilibrium or dynamic\n"
    "                         sample: phase, time, support displacement, reactions, hinges)\n"
    "  -q                     no progress line\n"
    "  -h, --help             this help\n"
    "  --version              program version (voussoir --version)\n"
    "The overrides (--alpha, --kn, --set, --dynamic, --first-limit, --max-wall-s) apply in the\n"
    "order given.\n"
    "CASE is an INI file (runs/reference.ini is the reference specimen). Units: mm, N/mm^3, deg.\n"
    "exit status: 0 ok, 1 the run failed (solver, full disk; the cause is printed), 2 bad input\n"
    "(also an output that is not a regular file, is the case file, or another run is writing,\n"
    "or whose name is not printable or too long),\n"
    "130 interrupted (SIGINT/SIGTERM: the record is closed with status 'failed: interrupted'),\n"
    "or stopped by the wall-time limit (--max-wall-s, run.max_wall_s: the record is closed with\n"
    "status 'stopped: wall-time limit S s reached').\n";

typedef struct {
  FILE *csv;
  vs_output *record; /* the HDF5 record, or NULL */
  int progress;
  long rows;
} cli_sink;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *smp) {
  cli_sink *s = user;
  if (*vs_stop_flag()) {
    vs_output_interrupt(s->record);
    return 1;
  }
  if (s->record != NULL && vs_output_sample(s->record, run, smp) != 0) return 1;
  const vs_hinges *h = vs_run_hinges(run);
  if (s->csv != NULL) {
    const vs_model *m = vs_run_model(run);
    const vs_case *c = vs_run_case(run);
    double rc[6], u[2];
    if (smp->reactions != NULL) memcpy(rc, smp->reactions, sizeof rc);
    else vs_model_support_reactions(m, smp->q, smp->delta, rc);
    vs_model_support_displacement(m, smp->delta, u);
    const int crown = c->voussoirs / 2;
    char hinges[256];
    vs_run_open_hinges(run, hinges, sizeof hinges);
    fprintf(s->csv,
            "%s,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.10g,%.6g,%d,\"%s\"\n",
            smp->phase == VS_PHASE_FALL ? "fall" : smp->phase == VS_PHASE_DYNAMIC ? "dynamic"
                                                                   : "quasistatic",
            smp->t, smp->delta / VS_MM,
            -u[1] / VS_MM, u[0] / VS_MM, rc[0], rc[1], rc[2], rc[3], rc[4], rc[5],
            smp->q[3 * crown + 1] / VS_MM,
            smp->energy != NULL ? smp->energy->kinetic : 0.0, vs_hinges_open_count(h), hinges);
    fflush(s->csv);
    s->rows++;
  }
  if (s->progress) {
    fprintf(stderr, "\r  %s  t = %10.2f s  delta = %9.4f mm   hinges open %d   ",
            smp->phase == VS_PHASE_FALL      ? "fall        "
            : smp->phase == VS_PHASE_DYNAMIC ? "dynamic     "
                                             : "quasi-static",
            smp->t,
            smp->delta / VS_MM, vs_hinges_open_count(h));
    fflush(stderr);
  }
  return 0;
}

static int on_event(void *user, const vs_run *run, const vs_run_event *e) {
  cli_sink *s = user;
  return s->record != NULL ? vs_output_event(s->record, run, e) : 0;
}

/* Default record name: the case's file name with its extension replaced by ".h5", in the
 * current directory. */
static void default_record_path(const char *case_path, char *buf, size_t size) {
  const char *base = strrchr(case_path, '/');
  base = base ? base + 1 : case_path;
  const char *dot = strrchr(base, '.');
  const int n = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
  snprintf(buf, size, "%.*s.h5", n, base);
}

typedef struct {
  const char *key, *value; /* key NULL: value is a --set assignment */
  const char *option;      /* the option that stands for key=value ("--kn") */
} run_override;

/* Apply "KEY=VALUE" (key not NULL: --alpha, --kn) or the assignment VALUE (--set), whatever
 * its length: the whole text reaches the parser, so nothing is cut and trailing junk is seen. */
static vs_status set_option(vs_case *c, const run_override *o, vs_error *err) {
  if (o->key == NULL) return vs_case_set(c, o->value, err);
  /* the option the user typed starts the message ("--kn: joints.kn_N_mm3 = -3: ..."), not the
   * --set it stands for */
  char section[32];
  const size_t dot = strcspn(o->key, ".");
  snprintf(section, sizeof section, "%.*s", (int)dot, o->key);
  return vs_case_assign(c, section, o->key + dot + 1, o->value, o->option, err);
}

/* One override of the case, in command-line order: "KEY=VALUE" (key not NULL: --alpha, --kn)
 * or the assignment VALUE (--set, --dynamic, --first-limit). */
typedef struct {
  const char *case_path, *out_path, *csv_path; /* out_path NULL: no record */
  const char *plot_path; /* --plot: the limit analysis' picture */
  int json, quiet, record, compress;
  double snapshot_share; /* 0: the default */
  run_override *overrides; /* argc entries at most */
  int n_overrides;
  char default_path[1024];
} run_args;

enum { OPT_ALPHA = 256, OPT_KN, OPT_SET, OPT_DYNAMIC, OPT_FIRST_LIMIT, OPT_JSON, OPT_NO_RECORD,
       OPT_COMPRESS, OPT_CSV, OPT_SNAPSHOT_SHARE, OPT_MAX_WALL, OPT_PLOT };

static const struct option RUN_OPTIONS[] = {
    {"alpha", required_argument, NULL, OPT_ALPHA},
    {"kn", required_argument, NULL, OPT_KN},
    {"set", required_argument, NULL, OPT_SET},
    {"dynamic", no_argument, NULL, OPT_DYNAMIC},
    {"first-limit", no_argument, NULL, OPT_FIRST_LIMIT},
    {"json", no_argument, NULL, OPT_JSON},
    {"no-record", no_argument, NULL, OPT_NO_RECORD},
    {"compress", no_argument, NULL, OPT_COMPRESS},
    {"csv", required_argument, NULL, OPT_CSV},
    {"plot", required_argument, NULL, OPT_PLOT},
    {"snapshot-share", required_argument, NULL, OPT_SNAPSHOT_SHARE},
    {"max-wall-s", required_argument, NULL, OPT_MAX_WALL},
    {0, 0, 0, 0}};

static int run_option(void *user, int code, const char *value) {
  run_args *a = user;
  run_override *o = &a->overrides[a->n_overrides];
  switch (code) {
  case OPT_ALPHA: *o = (run_override){"support.alpha_deg", value, "--alpha"}; break;
  case OPT_KN: *o = (run_override){"joints.kn_N_mm3", value, "--kn"}; break;
  case OPT_MAX_WALL: *o = (run_override){"run.max_wall_s", value, "--max-wall-s"}; break;
  case OPT_SET: *o = (run_override){NULL, value, NULL}; break;
  case OPT_DYNAMIC: *o = (run_override){NULL, "dynamic.full=1", NULL}; break;
  case OPT_FIRST_LIMIT: *o = (run_override){NULL, "dynamic.follow=0", NULL}; break;
  case OPT_JSON: a->json = 1; return 0;
  case OPT_NO_RECORD: a->record = 0; return 0;
  case OPT_COMPRESS: a->compress = 1; return 0;
  case OPT_CSV: a->csv_path = value; return 0;
  case OPT_PLOT: a->plot_path = value; return 0;
  case OPT_SNAPSHOT_SHARE:
    return cli_double("voussoir", "--snapshot-share", value, 1e-6, 1.0, &a->snapshot_share);
  case 'o': a->out_path = value; return 0;
  case 'q': a->quiet = 1; return 0;
  default: /* 1: the case */
    if (a->case_path != NULL) {
      fprintf(stderr, "voussoir: more than one case file (%s, %s)\n", vs_q(a->case_path).s,
              vs_q(value).s);
      return EXIT_BAD_INPUT;
    }
    a->case_path = value;
    return 0;
  }
  a->n_overrides++;
  return 0;
}

static const cli_command RUN = {"voussoir", VS_CLI_RUN_USAGE, "o:q", RUN_OPTIONS};

/* The command line of `run` (the overrides are applied later, in order): 0, -1 after --help,
 * or an exit status. a->overrides (malloc'd) is freed by the caller. */
static int parse_run_args(int argc, char **argv, run_args *a) {
  memset(a, 0, sizeof *a);
  a->record = 1;
  a->overrides = malloc((size_t)argc * sizeof *a->overrides);
  if (a->overrides == NULL) {
    fputs("voussoir: out of memory\n", stderr);
    return EXIT_RUN_FAILED;
  }
  const int rc = cli_parse(&RUN, argc, argv, run_option, a);
  if (rc != 0) return rc;
  if (a->case_path == NULL) {
    fprintf(stderr, "voussoir: run needs a CASE file\n%s", VS_CLI_RUN_USAGE);
    return EXIT_BAD_INPUT;
  }
  if (!a->record) a->out_path = NULL;
  else if (a->out_path == NULL) {
    default_record_path(a->case_path, a->default_path, sizeof a->default_path);
    a->out_path = a->default_path;
  }
  return 0;
}

/* The overrides of the command line, in the order given. */
static vs_status apply_overrides(const run_args *a, vs_case *c, vs_error *err) {
  for (int i = 0; i < a->n_overrides; i++) {
    vs_status st = set_option(c, &a->overrides[i], err);
    if (st != VS_OK) return st;
  }
  return VS_OK;
}

/* Every output path checked before anything is created: a regular file or absent, not the case
 * file, not another output (the record's XDMF sidecar included). 0 or EXIT_BAD_INPUT. */
static int check_outputs(const run_args *a) {
  vs_error err;
  vs_error_clear(&err);
  char *xmf = a->out_path != NULL ? vs_output_xdmf_path_for(a->out_path) : NULL;
  const vs_outpath_other cs = {a->case_path, "the case file"}, csv = {a->csv_path, "the --csv file"},
                         rec = {a->out_path, "the record"}, side = {xmf, "the record's XDMF sidecar"};
  const vs_outpath_other for_rec[] = {cs, csv, side}, for_side[] = {cs}, for_csv[] = {cs, rec, side};
  int rc = 0;
  if (a->out_path != NULL && (vs_outpath_check(a->out_path, for_rec, 3, &err) != VS_OK ||
                              vs_outpath_check(xmf, for_side, 1, &err) != VS_OK)) {
    fprintf(stderr, "voussoir: -o %s\n", err.msg);
    rc = EXIT_BAD_INPUT;
  }
  if (rc == 0 && a->csv_path != NULL && vs_outpath_check(a->csv_path, for_csv, 3, &err) != VS_OK) {
    fprintf(stderr, "voussoir: --csv %s\n", err.msg);
    rc = EXIT_BAD_INPUT;
  }
  free(xmf);
  return rc;
}

/* Lock and open the CSV without truncating it yet (*created: it did not exist). 0 or
 * EXIT_BAD_INPUT (with the reason printed). */
static int csv_open(const char *path, vs_outlock **lock, FILE **out, int *created) {
  vs_error err;
  *out = NULL;
  *created = 0;
  if (vs_outlock_acquire(path, lock, &err) != VS_OK) {
    fprintf(stderr, "voussoir: --csv %s\n", err.msg);
    return EXIT_BAD_INPUT;
  }
  int fd;
  if (vs_outpath_open_existing(path, &fd, created, &err) != VS_OK) {
    fprintf(stderr, "voussoir: --csv %s\n", err.msg);
  } else if ((*out = fdopen(fd, "w")) == NULL) {
    fprintf(stderr, "voussoir: --csv %s: cannot create: %s\n", path, strerror(errno));
  }
  if (*out == NULL) {
    if (fd >= 0) close(fd);
    if (*created) unlink(path);
    vs_outlock_release(lock);
    return EXIT_BAD_INPUT;
  }
  return 0;
}

static int csv_start(FILE *csv) {
  if (fflush(csv) != 0 || ftruncate(fileno(csv), 0) != 0) return -1;
  fputs("phase,time_s,delta_mm,dz_mm,dx_mm,left_Fx_N,left_Fz_N,left_M_Nm,right_Fx_N,right_Fz_N,right_M_Nm,"
        "crown_uz_mm,kinetic_J,open_hinges,hinges\n",
        csv);
  return fflush(csv);
}

/* The outputs, in this order: CSV (locked, not yet truncated), record, then the CSV's header.
 * 0 or an exit status (nothing left behind). */
static int open_outputs(const run_args *a, const vs_run *run, const char *case_text,
                        cli_sink *sink, vs_outlock **csv_lock) {
  int created = 0, rc = 0;
  if (a->csv_path != NULL && (rc = csv_open(a->csv_path, csv_lock, &sink->csv, &created)) != 0)
    return rc;
  vs_error err;
  vs_error_clear(&err);
  vs_output_opts oo = {0};
  if (a->out_path != NULL) vs_output_opts_default(&oo); /* the record plugin is loaded */
  if (a->compress) oo.deflate = 4; /* for archives: about 10 % smaller, slower to write */
  if (a->snapshot_share > 0.0) oo.snapshot_share = a->snapshot_share;
  if (a->out_path != NULL &&
      vs_output_create(a->out_path, run, case_text, &oo, &sink->record, &err) != VS_OK) {
    /* a refused path ("PATH: reason") is bad input; the writer's own errors name the path */
    fprintf(stderr, "voussoir: %s%s\n", err.status == VS_ERR_INVALID ? "-o " : "", err.msg);
    rc = err.status == VS_ERR_INVALID ? EXIT_BAD_INPUT : EXIT_RUN_FAILED;
  } else if (sink->csv != NULL && csv_start(sink->csv) != 0) {
    fprintf(stderr, "voussoir: --csv %s: write failed: %s\n", a->csv_path, strerror(errno));
    rc = EXIT_RUN_FAILED;
  }
  if (rc != 0 && sink->csv != NULL) {
    fclose(sink->csv);
    sink->csv = NULL;
    if (created) unlink(a->csv_path);
    vs_outlock_release(csv_lock);
  }
  return rc;
}

/* Close the record after the run (status st, cause err). When the record fails after a good
 * run, its error becomes the run's (*err); after a failed run it is printed unless it is the
 * run's own cause. Returns the run's status, or the record's error after a good run. */
static vs_status finish_record(cli_sink *sink, const vs_run *run, vs_status st, vs_error *err) {
  if (sink->record == NULL) return st;
  vs_error oerr;
  vs_error_clear(&oerr);
  if (vs_output_finish(sink->record, run, st, err, &oerr) == VS_OK) return st;
  if (st == VS_OK) {
    *err = oerr;
    return oerr.status;
  }
  if (strcmp(oerr.msg, err->msg) != 0) fprintf(stderr, "voussoir: %s\n", oerr.msg);
  return st;
}

static void print_record_line(const run_args *a, const cli_sink *sink) {
  const vs_output *o = sink->record;
  if (a->json || o == NULL || vs_output_error(o)->status != VS_OK) return; /* nothing to vouch */
  printf("record   %s (%ld states", a->out_path, vs_output_rows(o));
  if (vs_output_xdmf_written(o)) printf("; ParaView: %s", vs_output_xdmf_path(o));
  printf("; pictures: voussoir plot %s)\n", a->out_path);
}

/* analysis.hold_mm > 0: the support's path to the hold (no record), then the limit analysis of
 * the arch held there, into *held (owned by *run). VS_ERR_NO_EQUILIBRIUM when the arch did not
 * stand still at the hold. */
static vs_status limit_held(const vs_case *c, vs_run **run, const vs_limit_analysis **held,
                            vs_error *err) {
  vs_status st = vs_run_create(c, run, err);
  if (st != VS_OK) return st;
  vs_run_set_stop(*run, vs_stop_flag());
  st = vs_run_execute(*run, NULL, NULL, NULL, err);
  if (st != VS_OK) return st;
  vs_status lst = VS_OK;
  *held = vs_run_limit_held(*run, &lst, NULL);
  if (*held == NULL)
    return vs_error_set(err, VS_ERR_NO_EQUILIBRIUM, "%s", vs_run_load(*run)->cause);
  return lst;
}

/* analysis.type = limit: the limit analysis (limit.h) of the initial configuration, or with
 * analysis.hold_mm > 0 of the arch held there; no record: an explicit -o or --csv is refused.
 * An exit status. */
static int run_limit(const run_args *a, const vs_case *c) {
  if ((a->out_path != NULL && a->out_path != a->default_path) || a->csv_path != NULL) {
    fprintf(stderr, "voussoir: %s: analysis.type = limit writes no record or history (allowed "
                    "with it: --json, -q, the overrides)\n", a->csv_path != NULL ? "--csv" : "-o");
    return EXIT_BAD_INPUT;
  }
  if (a->plot_path != NULL && c->hold_mm > 0.0) {
    fprintf(stderr, "voussoir: --plot: the limit analysis of a held configuration "
                    "(analysis.hold_mm = %g) is not drawn yet (allowed: analysis.hold_mm = 0)\n",
            c->hold_mm);
    return EXIT_BAD_INPUT;
  }
  if (a->plot_path != NULL) {
    vs_error perr;
    vs_error_clear(&perr);
    const vs_outpath_other cs = {a->case_path, "the case file"};
    if (vs_outpath_check(a->plot_path, &cs, 1, &perr) != VS_OK) {
      fprintf(stderr, "voussoir: --plot %s\n", perr.msg);
      return EXIT_BAD_INPUT;
    }
  }
  vs_run_def d;
  vs_case_to_def(c, &d);
  vs_limit_analysis la = {0};
  const vs_limit_analysis *held = NULL;
  vs_run *run = NULL;
  vs_error err;
  vs_error_clear(&err);
  const vs_status st = c->hold_mm > 0.0 ? limit_held(c, &run, &held, &err)
                                        : vs_limit_analyse(&d, NULL, &la, &err);
  if (st == VS_ERR_INVALID) { /* the load does not fit the arch: bad input, nothing printed */
    fprintf(stderr, "voussoir: %s\n", err.msg);
    vs_run_destroy(&run);
    return EXIT_BAD_INPUT;
  }
  if (st == VS_ERR_INTERRUPTED) {
    vs_run_destroy(&run);
    return EXIT_INTERRUPTED;
  }
  const vs_limit_analysis *an = held != NULL ? held : &la;
  if (a->json) vs_report_limit_json(stdout, c, an, st, &err, a->case_path);
  else vs_report_limit_text(stdout, c, an, st, &err, a->case_path);
  if (st != VS_OK) fprintf(stderr, "voussoir: limit analysis failed: %s\n", err.msg);
  int rc = st == VS_OK ? EXIT_SUCCESS : EXIT_RUN_FAILED;
  if (st == VS_OK && a->plot_path != NULL) {
    vs_error perr;
    vs_error_clear(&perr);
    if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir") != 0) rc = EXIT_RUN_FAILED;
    else if (vs_plugin_plot()->limit_picture(a->plot_path, &d, &la, &perr) != VS_OK) {
      fprintf(stderr, "voussoir: --plot %s\n", perr.msg);
      rc = perr.status == VS_ERR_INVALID ? EXIT_BAD_INPUT : EXIT_RUN_FAILED;
    } else if (!a->json) {
      printf("picture      %s\n", a->plot_path);
    }
    if (vs_plugin_plot() != NULL) vs_plugin_plot()->plot_release(); /* cairo's, fontconfig's */
  }
  vs_limit_analysis_free(&la);
  vs_run_destroy(&run);
  return rc;
}

/* *h5_clean becomes 0 when the record failed to be written (see vs_output_process_end). */
int vs_cli_run(int argc, char **argv, int *h5_clean) {
  run_args a;
  int rc = parse_run_args(argc, argv, &a);
  if (rc == 0 && a.out_path != NULL) /* a record: the record plugin, before anything is written */
    rc = vs_plugin_load(VS_PLUGIN_RECORD, "voussoir");
  if (rc != 0) {
    free(a.overrides);
    return rc < 0 ? EXIT_SUCCESS : rc;
  }
  char *case_text = NULL;
  vs_case c;
  vs_error err;
  vs_run *run = NULL;
  vs_outlock *csv_lock = NULL;
  cli_sink sink = {0};
  vs_error_clear(&err);
  vs_case_defaults(&c);
  if (vs_case_read(&c, a.case_path, &case_text, &err) != VS_OK ||
      apply_overrides(&a, &c, &err) != VS_OK || vs_case_validate(&c, &err) != VS_OK)
    goto input_error;
  if (c.type == VS_ANALYSIS_LIMIT) {
    rc = run_limit(&a, &c);
    goto cleanup;
  }
  if (a.plot_path != NULL) {
    fprintf(stderr, "voussoir: --plot: only with analysis.type = limit (a record's pictures: "
                    "voussoir plot FILE.h5)\n");
    rc = EXIT_BAD_INPUT;
    goto cleanup;
  }
  if ((rc = check_outputs(&a)) != 0) goto cleanup;
  if (a.out_path == NULL && a.csv_path == NULL)
    c.fall_s = 0.0; /* nothing records the fall: the run ends at the collapse */
  if (vs_run_create(&c, &run, &err) != VS_OK) goto input_error;
  vs_run_set_stop(run, vs_stop_flag());
  /* everything is valid: only now create outputs */
  if (*vs_stop_flag() || (rc = open_outputs(&a, run, case_text, &sink, &csv_lock)) != 0) {
    *h5_clean = rc != EXIT_RUN_FAILED;
    if (rc == 0) fputs("voussoir: interrupted before the run started\n", stderr);
    rc = rc != 0 ? rc : EXIT_INTERRUPTED;
    goto cleanup;
  }
  sink.progress = !a.quiet && isatty(STDERR_FILENO);
  vs_status st = vs_run_execute(run, on_sample, on_event, &sink, &err);
  if (sink.progress) fputs("\r\033[K", stderr);
  if (st != VS_OK && *vs_stop_flag()) {
    st = vs_error_set(&err, VS_ERR_INTERRUPTED, "interrupted");
    vs_output_interrupt(sink.record);
  }
  if (st != VS_OK && sink.record != NULL && vs_output_error(sink.record)->status != VS_OK) {
    err = *vs_output_error(sink.record); /* the run stopped because the record failed: */
    st = err.status;                     /* that is the run's status, not VS_ERR_STOPPED */
  }
  st = finish_record(&sink, run, st, &err);
  if (a.json) vs_report_json(stdout, run, st, &err, a.case_path);
  else vs_report_text(stdout, run, st, &err, a.case_path);
  print_record_line(&a, &sink);
  if (st == VS_ERR_WALL_TIME) fprintf(stderr, "voussoir: %s\n", err.msg); /* stopped: ... */
  else if (st != VS_OK) fprintf(stderr, "voussoir: run failed: %s\n", err.msg);
  /* a run stopped by its wall-time limit ends as an interrupted one: it did not finish */
  rc = (st == VS_OK)                                           ? EXIT_SUCCESS
       : st == VS_ERR_INTERRUPTED || st == VS_ERR_WALL_TIME ? EXIT_INTERRUPTED
                                                              : EXIT_RUN_FAILED;
  goto cleanup;

input_error:
  fprintf(stderr, "voussoir: %s\n", err.msg);
  rc = EXIT_BAD_INPUT;
cleanup:
  if (sink.csv != NULL && fclose(sink.csv) != 0) {
    fprintf(stderr, "voussoir: --csv %s: write failed: %s\n", a.csv_path, strerror(errno));
    rc = EXIT_RUN_FAILED;
  }
  vs_outlock_release(&csv_lock);
  if (sink.record != NULL && vs_output_error(sink.record)->status != VS_OK) *h5_clean = 0;
  vs_output_destroy(&sink.record);
  vs_run_destroy(&run);
  free(case_text);
  free(a.overrides);
  return rc;
}

