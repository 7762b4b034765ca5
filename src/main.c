/* voussoir command line: create -> configure -> run -> report -> destroy. */
#define _POSIX_C_SOURCE 200809L /* readlink, isatty */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "voussoir/case.h"
#include "voussoir/montecarlo.h"
#include "voussoir/output.h"
#include "voussoir/report.h"
#include "voussoir/run.h"
#include "voussoir/sweep.h"

int vs_cmd_plot(int argc, char **argv); /* plot_cmd.c */
#include "voussoir/units.h"
#include "voussoir/version.h"

enum { EXIT_RUN_FAILED = 1, EXIT_BAD_INPUT = 2, EXIT_INTERRUPTED = 130 };

/* Set by SIGINT/SIGTERM; the run stops at its next recorded state and the outputs are closed
 * with the status "failed: interrupted". */
static volatile sig_atomic_t g_interrupted = 0;

static void on_signal(int sig) {
  (void)sig;
  g_interrupted = 1;
}

static void catch_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

static const char *USAGE =
    "usage: voussoir run CASE [options]\n"
    "       voussoir sweep CASE --alpha LIST --kn LIST [...]   (voussoir sweep --help)\n"
    "       voussoir calibrate CASE --target-dz-pct X [...]  (voussoir calibrate --help)\n"
    "       voussoir montecarlo CASE --samples N [...]  (voussoir montecarlo --help)\n"
    "       voussoir plot RUN.h5 [-o DIR] [--svg]            (voussoir plot --help)\n"
    "       voussoir --help | --version\n"
    "\n"
    "Simulates a masonry arch of rigid voussoirs on dry, no-tension, frictional, elastic joints\n"
    "while its right support moves along a direction alpha (from the vertical). Follows the\n"
    "quasi-static equilibrium path (KINSOL) from self-weight; at every limit point integrates the\n"
    "motion (IDA) until it settles on another branch (a snap-through) or collapses, and reports\n"
    "the collapse displacement, the limit points and the hinges (joint, side, onset, label).\n"
    "\n"
    "options for run:\n"
    "  --alpha DEG            support direction from the vertical, deg (0 = settlement,\n"
    "                         90 = outward spreading); same as --set support.alpha_deg=DEG\n"
    "  --kn N_MM3             joint normal stiffness, N/mm^3; same as --set joints.kn_N_mm3=N_MM3\n"
    "  --set SECTION.KEY=VAL  override any case key (repeatable; see README for all keys)\n"
    "  --dynamic              integrate the whole loading dynamically from rest at the support\n"
    "                         rate (no quasi-static phase); same as --set dynamic.full=1\n"
    "  --first-limit          stop at the first limit point (no dynamics); --set dynamic.follow=0\n"
    "  --json                 print one JSON object on stdout instead of the summary\n"
    "  -o FILE.h5             the HDF5 record of the run (default: the case's name with .h5, in\n"
    "                         the current directory) and its XDMF sidecar FILE.xmf (ParaView)\n"
    "  --no-record            no HDF5 record\n"
    "  --csv FILE             also write the history as CSV (one row per equilibrium or dynamic\n"
    "                         sample: phase, time, support displacement, reactions, hinges)\n"
    "  -q                     no progress line\n"
    "  -h, --help             this help\n"
    "  --version              program version\n"
    "\n"
    "CASE is an INI file (runs/reference.ini is the reference specimen). Units: mm, N/mm^3, deg.\n"
    "exit status: 0 ok, 1 the run failed (solver; the cause is printed), 2 bad input,\n"
    "130 interrupted (SIGINT/SIGTERM: the record is closed with status 'failed: interrupted').\n";

typedef struct {
  FILE *csv;
  vs_output *record; /* the HDF5 record, or NULL */
  int progress;
  long rows;
} cli_sink;

static int on_sample(void *user, const vs_run *run, const vs_run_sample *smp) {
  cli_sink *s = user;
  if (g_interrupted) {
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
            smp->phase == VS_PHASE_DYNAMIC ? "dynamic" : "quasistatic", smp->t, smp->delta / VS_MM,
            -u[1] / VS_MM, u[0] / VS_MM, rc[0], rc[1], rc[2], rc[3], rc[4], rc[5],
            smp->q[3 * crown + 1] / VS_MM,
            smp->energy != NULL ? smp->energy->kinetic : 0.0, vs_hinges_open_count(h), hinges);
    fflush(s->csv);
    s->rows++;
  }
  if (s->progress) {
    fprintf(stderr, "\r  %s  t = %10.2f s  delta = %9.4f mm   hinges open %d   ",
            smp->phase == VS_PHASE_DYNAMIC ? "dynamic     " : "quasi-static", smp->t,
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

static int cmd_run(int argc, char **argv) {
  const char *case_path = NULL, *out_path = NULL, *csv_path = NULL;
  int json = 0, quiet = 0, record = 1, rc = EXIT_BAD_INPUT;
  char *case_text = NULL, default_path[1024];
  vs_case c;
  vs_error err;
  vs_run *run = NULL;
  cli_sink sink = {0};
  vs_error_clear(&err);
  vs_case_defaults(&c);
  /* the case file first, then the overrides in the order given */
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    if (a[0] != '-' || strcmp(a, "-") == 0) {
      if (case_path != NULL) {
        fprintf(stderr, "voussoir: more than one case file (%s, %s)\n", case_path, a);
        return EXIT_BAD_INPUT;
      }
      case_path = a;
    } else if (strcmp(a, "--alpha") == 0 || strcmp(a, "--kn") == 0 || strcmp(a, "--set") == 0 ||
               strcmp(a, "-o") == 0 || strcmp(a, "--csv") == 0) {
      if (++i >= argc) {
        fprintf(stderr, "voussoir: %s needs a value\n%s", a, USAGE);
        return EXIT_BAD_INPUT;
      }
      if (strcmp(a, "-o") == 0) out_path = argv[i];
      if (strcmp(a, "--csv") == 0) csv_path = argv[i];
    } else if (strcmp(a, "--no-record") == 0) {
      record = 0;
    } else if (strcmp(a, "--dynamic") == 0 || strcmp(a, "--first-limit") == 0) {
      /* applied with the overrides below */
    } else if (strcmp(a, "--json") == 0) {
      json = 1;
    } else if (strcmp(a, "-q") == 0) {
      quiet = 1;
    } else {
      fprintf(stderr, "voussoir: unknown option %s\n%s", a, USAGE);
      return EXIT_BAD_INPUT;
    }
  }
  if (case_path == NULL) {
    fprintf(stderr, "voussoir: run needs a CASE file\n%s", USAGE);
    return EXIT_BAD_INPUT;
  }
  if (vs_case_read(&c, case_path, &case_text, &err) != VS_OK) goto input_error;
  for (int i = 2; i < argc; i++) {
    char buf[512];
    const char *a = argv[i];
    if (strcmp(a, "--alpha") == 0) snprintf(buf, sizeof buf, "support.alpha_deg=%s", argv[++i]);
    else if (strcmp(a, "--kn") == 0) snprintf(buf, sizeof buf, "joints.kn_N_mm3=%s", argv[++i]);
    else if (strcmp(a, "--set") == 0) snprintf(buf, sizeof buf, "%s", argv[++i]);
    else if (strcmp(a, "--dynamic") == 0) snprintf(buf, sizeof buf, "dynamic.full=1");
    else if (strcmp(a, "--first-limit") == 0) snprintf(buf, sizeof buf, "dynamic.follow=0");
    else {
      if (strcmp(a, "-o") == 0 || strcmp(a, "--csv") == 0) i++;
      continue;
    }
    if (vs_case_set(&c, buf, &err) != VS_OK) goto input_error;
  }
  if (vs_case_validate(&c, &err) != VS_OK) goto input_error;

  /* everything is valid: only now create outputs */
  if (vs_run_create(&c, &run, &err) != VS_OK) goto input_error;
  if (record) {
    if (out_path == NULL) {
      default_record_path(case_path, default_path, sizeof default_path);
      out_path = default_path;
    }
    if (vs_output_create(out_path, run, case_text, NULL, &sink.record, &err) != VS_OK) {
      fprintf(stderr, "voussoir: -o %s: %s\n", out_path, err.msg);
      rc = EXIT_RUN_FAILED;
      goto cleanup;
    }
  }
  if (csv_path != NULL) {
    sink.csv = fopen(csv_path, "w");
    if (sink.csv == NULL) {
      fprintf(stderr, "voussoir: --csv %s: cannot create: %s\n", csv_path, strerror(errno));
      rc = EXIT_RUN_FAILED;
      goto cleanup;
    }
    fputs("phase,time_s,delta_mm,dz_mm,dx_mm,left_Fx_N,left_Fz_N,left_M_Nm,right_Fx_N,right_Fz_N,right_M_Nm,"
          "crown_uz_mm,kinetic_J,open_hinges,hinges\n",
          sink.csv);
  }
  sink.progress = !quiet && isatty(STDERR_FILENO);
  catch_signals();
  vs_status st = vs_run_execute(run, on_sample, on_event, &sink, &err);
  if (sink.progress) fputs("\r\033[K", stderr);
  if (st != VS_OK && g_interrupted) vs_error_set(&err, st, "interrupted");
  if (st != VS_OK && sink.record != NULL && vs_output_error(sink.record)->status != VS_OK)
    err = *vs_output_error(sink.record); /* the run stopped because the record failed */
  if (sink.record != NULL) {
    vs_error oerr;
    vs_error_clear(&oerr);
    if (vs_output_finish(sink.record, run, st, &err, &oerr) != VS_OK) {
      fprintf(stderr, "voussoir: -o %s: %s\n", out_path, oerr.msg);
      if (st == VS_OK) st = oerr.status;
    }
  }
  if (json) vs_report_json(stdout, run, st, &err, case_path);
  else vs_report_text(stdout, run, st, &err, case_path);
  if (!json && sink.record != NULL)
    printf("record   %s (%ld states; ParaView: %s; pictures: voussoir plot %s)\n", out_path,
           vs_output_rows(sink.record), vs_output_xdmf_path(sink.record), out_path);
  if (st != VS_OK) fprintf(stderr, "voussoir: run failed: %s\n", err.msg);
  rc = (st == VS_OK) ? EXIT_SUCCESS : g_interrupted ? EXIT_INTERRUPTED : EXIT_RUN_FAILED;
  goto cleanup;

input_error:
  fprintf(stderr, "voussoir: %s\n", err.msg);
  rc = EXIT_BAD_INPUT;
cleanup:
  if (sink.csv != NULL && fclose(sink.csv) != 0) {
    fprintf(stderr, "voussoir: --csv %s: write failed: %s\n", csv_path, strerror(errno));
    rc = EXIT_RUN_FAILED;
  }
  vs_output_destroy(&sink.record);
  vs_run_destroy(&run);
  free(case_text);
  return rc;
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fputs(USAGE, stderr);
    return EXIT_BAD_INPUT;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
    fputs(USAGE, stdout);
    return EXIT_SUCCESS;
  }
  if (strcmp(argv[1], "--version") == 0) {
    printf("voussoir %s\n", VS_VERSION);
    return EXIT_SUCCESS;
  }
  if (strcmp(argv[1], "sweep") == 0) {
    char self[4096];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) return vs_cmd_sweep(argc, argv, argv[0]);
    self[n] = '\0';
    return vs_cmd_sweep(argc, argv, self);
  }
  if (strcmp(argv[1], "calibrate") == 0) return vs_cmd_calibrate(argc, argv);
  if (strcmp(argv[1], "montecarlo") == 0) return vs_cmd_montecarlo(argc, argv);
  if (strcmp(argv[1], "merge") == 0) return vs_cmd_merge(argc, argv);
  if (strcmp(argv[1], "plot") == 0) return vs_cmd_plot(argc, argv);
  if (strcmp(argv[1], "run") == 0) {
    for (int i = 2; i < argc; i++)
      if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
        fputs(USAGE, stdout);
        return EXIT_SUCCESS;
      }
    return cmd_run(argc, argv);
  }
  fprintf(stderr, "voussoir: unknown command '%s'\n%s", argv[1], USAGE);
  return EXIT_BAD_INPUT;
}
