/* The sweep command's work (its command line is read by src/cli/cli_sweep.c): many runs of one case.
 * A sweep runs every combination of its axes, each case in a worker forked from this process (or
 * on the ranks of an MPI job), and gathers the rows the cases return into a summary table (CSV;
 * HDF5 by src/record/sweep_summary.c in the record plugin) and a journal for --resume. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "stop.h"
#include "study.h"
#include "journal.h"
#include "plugin.h"
#include "sweep_private.h"
#include "outpath.h"
#include "parse.h"
#include "voussoir/run.h"
#include "list.h"
#include "voussoir/units.h"
#include "quote.h"

enum { EXIT_FAIL = VS_EXIT_FAILED, EXIT_USAGE = VS_EXIT_BAD_INPUT,
       EXIT_STOPPED = VS_EXIT_INTERRUPTED, MAX_AXES = VS_SWEEP_MAX_AXES };

typedef vs_sweep_axis axis;

/* --- sweep --- */

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The signal that asked the sweep to stop (0: none) and how many arrived: the first is passed
 * on to the runs under way, a second kills them. Static because a handler can reach nothing
 * else; a forked worker inherits the handler, and its run watches its own copy of the count. */
static volatile sig_atomic_t g_stop_signal = 0, g_stop_count = 0;

/* One line of the table (the error's double quotes as single quotes, its first line only). */
static void write_csv_row(FILE *csv, const vs_sweep_row *row, int nax, int mortar) {
  char error[sizeof row->error];
  snprintf(error, sizeof error, "%s", row->error);
  error[strcspn(error, "\n")] = '\0';
  for (char *p = error; *p; p++)
    if (*p == '"') *p = '\'';
  fprintf(csv, "%d", row->run);
  for (int x = 0; x < nax; x++) fprintf(csv, ",%.10g", row->axis[x]);
  fprintf(csv, ",%s,%.10g,%.10g,%.10g,%.10g,\"%s\",%s,%d,%.4g,\"%s\",%.10g,%.10g,%.10g,%.10g,%.10g",
          row->status, row->first_limit_mm, row->delta_u_mm, row->dz_pct, row->dx_pct,
          row->hinges, row->mode, row->snaps, row->wall_s, error, row->left_dx_mm,
          row->left_dz_mm, row->right_dx_mm, row->right_dz_mm, row->load_factor);
  if (mortar) /* a mortared study's: the first crack */
    fprintf(csv, ",%.10g,%d,%s", row->first_crack_mm, row->first_crack_joint,
            row->first_crack_side);
  fputc('\n', csv);
}

static void write_csv_header(FILE *csv, const axis *ax, int nax, int mortar) {
  fputs("run", csv);
  for (int x = 0; x < nax; x++) fprintf(csv, ",%s", ax[x].key);
  fputs(",status,first_limit_mm,delta_u_mm,dz_over_L_pct,dx_over_L_pct,hinges_at_collapse,mode,"
        "snaps,wall_s,error,left_dx_mm,left_dz_mm,right_dx_mm,right_dz_mm,load_factor",
        csv);
  if (mortar) fputs(",first_crack_mm,first_crack_joint,first_crack_side", csv);
  fputc('\n', csv);
}

/* Whether a case of the study has mortar (joints.tensile_MPa or cohesion_MPa > 0): the base's,
 * or a value of an axis over either key. Its tables then have the first crack's columns. */
static int study_mortared(const vs_case *base, const axis *ax, int nax) {
  static const char *const keys[2] = {"joints.tensile_MPa", "joints.cohesion_MPa"};
  const double own[2] = {base->tensile_MPa, base->cohesion_MPa};
  for (int i = 0; i < 2; i++) {
    int swept = 0, any = 0;
    for (int x = 0; x < nax; x++) {
      if (strcmp(ax[x].key, keys[i]) != 0) continue;
      swept = 1;
      for (int v = 0; v < ax[x].n; v++) any |= ax[x].v[v] > 0.0;
    }
    if (swept ? any : own[i] > 0.0) return 1;
  }
  return 0;
}

static int cmp_sweep_rows(const void *x, const void *y) {
  return ((const vs_sweep_row *)x)->run - ((const vs_sweep_row *)y)->run;
}

/* The whole table in run order, replacing the one written in completion order, atomically. 0,
 * or -1 after printing why. */
static int rewrite_table(const char *path, const axis *ax, int nax, const vs_sweep_row *rows,
                         int n, int mortar) {
  char tmp[1200];
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  FILE *f;
  vs_error err;
  if (vs_outpath_fopen(tmp, &f, &err) != VS_OK) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return -1;
  }
  write_csv_header(f, ax, nax, mortar);
  for (int i = 0; i < n; i++) write_csv_row(f, &rows[i], nax, mortar);
  /* renamed never over anything but a regular file */
  const vs_status st =
      fclose(f) == 0 ? vs_outpath_publish(tmp, path, &err)
                     : vs_error_set(&err, VS_ERR_IO, "%s: cannot write: %s", tmp, strerror(errno));
  if (st == VS_OK) return 0;
  fprintf(stderr, "voussoir sweep: %s\n", err.msg);
  remove(tmp);
  return -1;
}

/* The case file with the --set overrides applied (in order), not yet validated; *text (when
 * not NULL) receives the file's text (malloc'd). The runs do not follow the fall: the domain is
 * read before it, and the fall (to rest on the ground) costs the most; a --set of the sweep's
 * own, applied after, still follows it. */
static vs_status load_case_text(const char *case_path, const char *const *sets, int nsets, vs_case *c,
                                char **text, vs_error *err) {
  vs_case_defaults(c);
  vs_status st = vs_case_read(c, case_path, text, err);
  if (st == VS_OK) st = vs_case_set(c, "dynamic.fall_s=0", err);
  for (int s = 0; st == VS_OK && s < nsets; s++) st = vs_case_set(c, sets[s], err);
  return st;
}

static vs_status load_case(const char *case_path, const char *const *sets, int nsets, vs_case *c,
                           vs_error *err) {
  return load_case_text(case_path, sets, nsets, c, NULL, err);
}

/* The shapes that read an [arch] key of the geometry (docs/case-file.md): an axis over a key its
 * case's shape does not read would run the same arch again and again. Keys not listed are read
 * by every shape (a blocks file's: depth, density, gravity; span_mm, the span L). */
static const struct {
  const char *key, *shapes;
  unsigned mask; /* 1 << vs_arch_shape */
} SHAPE_KEYS[] = {
    {"radius_mm", "circular", 1u << VS_SHAPE_CIRCULAR},
    {"embrace_deg", "circular", 1u << VS_SHAPE_CIRCULAR},
    {"eccentricity", "pointed", 1u << VS_SHAPE_POINTED},
    {"haunch_deg", "basket", 1u << VS_SHAPE_BASKET},
    {"rise_mm", "every shape but pointed and file",
     ~((1u << VS_SHAPE_POINTED) | (1u << VS_SHAPE_FILE))},
    {"thickness_mm", "every shape but file", ~(1u << VS_SHAPE_FILE)},
    {"thickness_springing_mm", "every shape but file", ~(1u << VS_SHAPE_FILE)},
    {"voussoirs", "every shape but file", ~(1u << VS_SHAPE_FILE)},
    {"keystone_mm", "every shape but file", ~(1u << VS_SHAPE_FILE)},
};

/* Whether case c's shape reads the axis key ("section.key"); if not, why, in err. */
static int axis_read(const vs_case *c, const char *key, vs_error *err) {
  static const char *const names[] = {"circular", "pointed", "elliptical", "basket",
                                      "parabolic", "catenary", "file"};
  _Static_assert(sizeof names / sizeof names[0] == VS_SHAPE_COUNT, "a name for every shape");
  if (strncmp(key, "arch.", 5) != 0 || c->shape < 0 || c->shape >= VS_SHAPE_COUNT) return 1;
  for (size_t i = 0; i < sizeof SHAPE_KEYS / sizeof SHAPE_KEYS[0]; i++)
    if (strcmp(key + 5, SHAPE_KEYS[i].key) == 0 && !(SHAPE_KEYS[i].mask & (1u << c->shape))) {
      vs_error_set(err, VS_ERR_INVALID, "--vary %s: arch.shape = %s does not read it, every run "
                   "would be the same arch (allowed: %s with %s)", key, names[c->shape], key,
                   SHAPE_KEYS[i].shapes);
      return 0;
    }
  /* a circle from radius and embrace: only when span and rise do not give it */
  if (c->shape == VS_SHAPE_CIRCULAR && c->span_mm > 0.0 &&
      (strcmp(key, "arch.radius_mm") == 0 || strcmp(key, "arch.embrace_deg") == 0)) {
    vs_error_set(err, VS_ERR_INVALID, "--vary %s: arch.span_mm and arch.rise_mm give the circle "
                 "(allowed: %s with span_mm = rise_mm = 0)", key, key);
    return 0;
  }
  return 1;
}

/* Validate the case with the fixed overrides and every value of every axis. */
static int validate_all(const char *case_path, const char *const *sets, int nsets, const axis *ax, int nax) {
  vs_case c;
  vs_error err;
  vs_error_clear(&err);
  if (load_case(case_path, sets, nsets, &c, &err) != VS_OK) goto bad;
  for (int x = 0; x < nax; x++)
    for (int k = 0; k < ax[x].n; k++) {
      vs_case t = c;
      char buf[160];
      snprintf(buf, sizeof buf, "%.95s=%.17g", ax[x].key, ax[x].v[k]);
      if (vs_case_set(&t, buf, &err) != VS_OK || vs_case_validate(&t, &err) != VS_OK ||
          vs_case_check_path(&t, "sweep", &err) != VS_OK || !axis_read(&t, ax[x].key, &err))
        goto bad;
    }
  return 0;
bad:
  fprintf(stderr, "voussoir sweep: %s\n", err.msg);
  return -1;
}

static void on_stop_signal(int sig) {
  g_stop_signal = sig;
  g_stop_count++;
}

void vs_sweep_catch_signals(void) { vs_on_stop_signals(on_stop_signal); }

/* What the sweep is, as text: the case after --set, every axis with its values, the mode. A
 * --resume must find the same in DIR/sweep.manifest, so that it completes the same sweep. */
static char *manifest_text(const vs_case *c, const axis *ax, int nax, const char *mode_flag) {
  size_t extra = 64;
  for (int x = 0; x < nax; x++) extra += 128 + 26 * (size_t)ax[x].n;
  char *t = vs_manifest_case(c, extra);
  if (t == NULL) return NULL;
  size_t used = strlen(t);
  const size_t cap = used + extra + 1;
  for (int x = 0; x < nax; x++) {
    used += (size_t)snprintf(t + used, cap - used, "axis %s:", ax[x].key);
    for (int k = 0; k < ax[x].n; k++)
      used += (size_t)snprintf(t + used, cap - used, " %.17g", ax[x].v[k]);
    used += (size_t)snprintf(t + used, cap - used, "\n");
  }
  snprintf(t + used, cap - used, "mode %s\n", mode_flag ? mode_flag : "default");
  return t;
}

/* --- the journal: DIR/sweep.journal, the rows of the complete runs as they end (journal.h) --- */

/* Its first line names this layout (the row's size with its checksum): a journal of another
 * build, or of the layout before the checksums (journal 1), is refused by --resume. */
static void journal_header(char *buf, size_t size) {
  snprintf(buf, size, "voussoir sweep journal 2 row %zu bytes\n",
           sizeof(vs_sweep_row) + VS_JOURNAL_SUM);
}

static void journal_path(const char *dir, char *path, size_t size) {
  snprintf(path, size, "%s/sweep.journal", dir);
}

/* Fresh sweep: write the manifest and forget the results of any earlier sweep in DIR (its
 * journal and run_NNNN.json). Resume: require the same manifest. 0, or -1 after printing why. */
static int prepare_dir(const char *dir, const char *manifest, int total, int resume) {
  char path[1100];
  snprintf(path, sizeof path, "%s/sweep.manifest", dir);
  if (resume) {
    const int same = vs_manifest_same(path, manifest);
    if (same != 1)
      fprintf(stderr, "voussoir sweep: --resume: %s %s\n", path,
              same < 0 ? "is missing: no sweep to resume in this directory"
                       : "differs: that sweep had another case, lists, --set or mode");
    return same == 1 ? 0 : -1;
  }
  for (int r = 1; r <= total; r++) {
    char json[1100];
    snprintf(json, sizeof json, "%s/run_%04d.json", dir, r);
    remove(json);
  }
  FILE *f;
  vs_error err;
  if (vs_outpath_fopen(path, &f, &err) != VS_OK) { /* the earlier sweep's manifest replaced */
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return -1;
  }
  int ok = fputs(manifest, f) >= 0;
  if (fclose(f) != 0) ok = 0;
  if (!ok) fprintf(stderr, "voussoir sweep: %s: cannot write: %s\n", path, strerror(errno));
  return ok ? 0 : -1;
}

/* The product of the axes' lengths, or -1 beyond VS_SWEEP_MAX_RUNS (checked before multiplying,
 * so it cannot overflow). */
static int sweep_size(const axis *ax, int nax) {
  long total = 1;
  for (int x = 0; x < nax; x++) {
    if (ax[x].n > VS_SWEEP_MAX_RUNS / total) return -1;
    total *= ax[x].n;
  }
  return (int)total;
}

typedef vs_sweep_opts sweep_opts;

/* A sweep under way: which runs are done, their rows, the table and the journal. */
typedef struct {
  const sweep_opts *o;
  vs_sweep_job job;
  int total, n, failed, not_started, next, todo;
  int mortar;         /* a case of the study has mortar: the tables' first crack columns */
  char *state;        /* per run: 0 to run, 1 handed out, 2 done (its row kept) */
  vs_sweep_row *rows; /* the rows kept, in the order they came */
  FILE *csv, *journal;
  vs_outlock *lock;   /* DIR's (journal.h), from before anything in DIR is written to the end */
} sweep_state;

/* A row kept: in the table too once it is open (the journal's rows are read before). */
static void keep_row(sweep_state *s, const vs_sweep_row *row) {
  s->rows[s->n++] = *row;
  s->state[row->run - 1] = 2;
  s->failed += row->code != VS_SWEEP_OK;
  if (s->csv == NULL) return;
  write_csv_row(s->csv, row, s->o->nax, s->mortar);
  fflush(s->csv);
}

/* The next run to hand out (1-based), or 0: none left, or the sweep was asked to stop. */
static int next_run(void *user) {
  sweep_state *s = user;
  while (g_stop_count == 0 && s->next < s->total) {
    const int r = s->next++;
    if (s->state[r] != 0) continue;
    s->state[r] = 1;
    return r + 1;
  }
  return 0;
}

/* A run's row as it comes back: a complete run (worked, or failed with its cause) is kept and
 * journalled, and its JSON renamed into place; a worker lost on its own, or a run that could not
 * start (its record refused: locked, not a regular file, not creatable), is a failed row that
 * is not journalled (run again by --resume); an interrupted run stays handed out (marked at
 * the end). */
static void take_row(void *user, const vs_sweep_row *in) {
  sweep_state *s = user;
  if (in->run < 1 || in->run > s->total || s->state[in->run - 1] != 1) return;
  vs_sweep_row row = *in;
  int pick[MAX_AXES];
  vs_sweep_pick(&s->job, row.run, pick);
  for (int x = 0; x < s->o->nax; x++) row.axis[x] = s->o->ax[x].v[pick[x]];
  char part[1100], json[1100];
  snprintf(part, sizeof part, "%s/run_%04d.json.part", s->o->dir, row.run);
  snprintf(json, sizeof json, "%s/run_%04d.json", s->o->dir, row.run);
  struct stat st; /* the worker's JSON: a regular file, never a link put in its place */
  const int written = lstat(part, &st) == 0 && S_ISREG(st.st_mode);
  if (row.code == VS_SWEEP_OK || row.code == VS_SWEEP_FAILED) {
    errno = 0;
    const int moved = written ? vs_outpath_replace(part, json) : 0;
    if (moved != 0) {
      fprintf(stderr, "voussoir sweep: %s: not renamed to %s (%s)\n", part, json,
              moved > 0 || errno == 0 ? "not a regular file" : strerror(errno));
      remove(part);
    }
    if (vs_journal_append(s->journal, &row, sizeof row) != 0)
      fprintf(stderr, "voussoir sweep: sweep.journal: cannot write: %s\n", strerror(errno));
    keep_row(s, &row);
    return;
  }
  if (written) remove(part);
  if (row.code == VS_SWEEP_NOT_STARTED) {
    fprintf(stderr, "voussoir sweep: run %d could not start: %s (not journalled: --resume runs "
            "it)\n", row.run, row.error);
    s->not_started++;
  }
  if ((row.code == VS_SWEEP_LOST && g_stop_count == 0) || row.code == VS_SWEEP_NOT_STARTED)
    keep_row(s, &row);
}

/* A row from the journal of the sweep being resumed (a complete run's): taken when every field
 * is sound, its axes' values are its run's, and it is the first for its run. */
static int resumed_row(void *user, const void *r, char *why, size_t size) {
  sweep_state *s = user;
  const vs_sweep_row *row = r;
  if (!vs_sweep_row_check(row, s->total, s->o->nax, why, size)) return 0;
  int pick[MAX_AXES];
  vs_sweep_pick(&s->job, row->run, pick);
  for (int x = 0; x < s->o->nax; x++)
    if (row->axis[x] != s->o->ax[x].v[pick[x]]) {
      snprintf(why, size, "run %d: %s = %.17g is not the run's %.17g", row->run, s->o->ax[x].key,
               row->axis[x], s->o->ax[x].v[pick[x]]);
      return 0;
    }
  if (s->state[row->run - 1] != 0) {
    snprintf(why, size, "a second row for run %d", row->run);
    return 0;
  }
  keep_row(s, row);
  return 1;
}

/* Whether name is one a run of a sweep writes: run_NNNN followed by ".h5", ".xmf", ".json",
 * with or without the suffix of its working file, snapshot or lock. */
static int run_file(const char *name, void *user) {
  (void)user;
  static const char *const ends[] = {".h5",  ".h5.part", ".h5.snap", ".h5.lock", ".xmf",
                                     ".xmf.tmp", ".json", ".json.part"};
  if (strncmp(name, "run_", 4) != 0) return 0;
  const char *p = name + 4;
  while (*p >= '0' && *p <= '9') p++;
  if (p == name + 4) return 0;
  for (size_t i = 0; i < sizeof ends / sizeof ends[0]; i++)
    if (strcmp(p, ends[i]) == 0) return 1;
  return 0;
}

/* DIR and every file the sweep writes there are fit to be written (absent or regular files):
 * checked before DIR or anything in it is created or removed. 0, or -1 with err set. */
static int check_dir(const char *dir, vs_error *err) {
  static const char *const names[] = {"summary.csv",   "summary.csv.tmp", "summary.h5",
                                      "summary.h5.part", "sweep.journal",  "sweep.manifest",
                                      VS_STUDY_LOCK ".lock"};
  if (vs_outpath_check_dir(dir, err) != VS_OK) return -1;
  if (access(dir, F_OK) != 0) return 0; /* created afresh */
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    char path[1100];
    snprintf(path, sizeof path, "%s/%s", dir, names[i]);
    if (vs_outpath_check(path, NULL, 0, err) != VS_OK) return -1;
  }
  return vs_outpath_check_entries(dir, run_file, NULL, err) == VS_OK ? 0 : -1;
}

/* The rows of the journal of the sweep being resumed (jpath), those found sound kept, the
 * others removed from it; *rows: how many it keeps. 0, or an exit status after printing why. */
static int resume_journal(sweep_state *s, const char *jpath, const char *head, long *rows) {
  const int rc = vs_journal_read(jpath, head, sizeof(vs_sweep_row), "voussoir sweep",
                                 resumed_row, s, rows);
  if (rc == VS_JOURNAL_FOREIGN)
    fprintf(stderr, "voussoir sweep: --resume: %s was not written by this build of voussoir "
            "(it expects \"%.*s\"); run the sweep afresh\n", jpath, (int)strlen(head) - 1, head);
  else if (rc != 0)
    fprintf(stderr, "voussoir sweep: --resume: %s: cannot read or rewrite: %s\n", jpath,
            strerror(errno));
  else if (!s->o->quiet) /* progress: -q silences it, as montecarlo's */
    fprintf(stderr, "voussoir sweep: resuming: %d of %d runs already complete\n", s->n, s->total);
  return rc == 0 ? 0 : EXIT_USAGE;
}

/* Check and create DIR and lock it, its manifest, the table (header written) and the journal.
 * 0, or an exit status after printing why. */
static int sweep_open(sweep_state *s, const char *manifest) {
  const sweep_opts *o = s->o;
  char path[1100], jpath[1100];
  snprintf(path, sizeof path, "%s/summary.csv", o->dir);
  journal_path(o->dir, jpath, sizeof jpath);
  vs_error err;
  vs_error_clear(&err);
  if (check_dir(o->dir, &err) != 0) {
    fprintf(stderr, "voussoir sweep: -o %s\n", err.msg);
    return EXIT_USAGE;
  }
  if (mkdir(o->dir, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir sweep: -o %s: cannot create: %s\n", o->dir, strerror(errno));
    return EXIT_USAGE;
  }
  if (vs_study_lock(o->dir, "voussoir sweep", &s->lock, &err) != VS_OK) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return EXIT_USAGE;
  }
  if (prepare_dir(o->dir, manifest, s->total, o->resume) != 0) return EXIT_USAGE;
  s->rows = calloc((size_t)s->total, sizeof *s->rows);
  s->state = calloc((size_t)s->total, 1);
  if (s->rows == NULL || s->state == NULL) {
    fprintf(stderr, "voussoir sweep: out of memory\n");
    return EXIT_FAIL;
  }
  char head[96];
  journal_header(head, sizeof head);
  long rows = -1; /* fresh */
  /* the journal's rows first (a journal refused leaves the table as it was), then it is appended
   * to, after the rows kept */
  int rc = o->resume ? resume_journal(s, jpath, head, &rows) : 0;
  if (rc != 0) return rc;
  if (vs_outpath_fopen(path, &s->csv, &err) != VS_OK) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return EXIT_USAGE;
  }
  write_csv_header(s->csv, o->ax, o->nax, s->mortar);
  for (int i = 0; i < s->n; i++) write_csv_row(s->csv, &s->rows[i], o->nax, s->mortar);
  fflush(s->csv);
  s->journal = vs_journal_open(jpath, head, sizeof(vs_sweep_row), rows, &err);
  if (s->journal == NULL) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    return EXIT_USAGE;
  }
  s->todo = s->total - s->n;
  return 0;
}

/* Failed runs said on stderr (stdout's last line counts them, but -q or a redirected stdout
 * would leave an exit status 1 unexplained): how many, and the first one's cause (its row in the
 * table, in run order; the cause may come from the journal: quoted). */
static void report_failures(const sweep_state *s, const char *table) {
  for (int i = 0; s->failed > 0 && i < s->n; i++) {
    const vs_sweep_row *r = &s->rows[i];
    if (r->code == VS_SWEEP_OK) continue;
    if (s->failed == s->total)
      fprintf(stderr, "voussoir sweep: every run failed (%d of %d); run %d: %s\n", s->failed,
              s->total, r->run, vs_q(r->error).s);
    else
      fprintf(stderr, "voussoir sweep: %d of %d runs failed (their causes: %s); the first, run %d: "
              "%s\n", s->failed, s->total, table, r->run, vs_q(r->error).s);
    return;
  }
}

/* Rows for the runs that did not finish, the table in run order, summary.h5, the last line. */
static int sweep_close(sweep_state *s, double wall, int processes) {
  const sweep_opts *o = s->o;
  const int skipped = s->total - s->todo;
  int unfinished = 0;
  for (int r = 0; r < s->total; r++) /* interrupted or never started: marked as such */
    if (s->state[r] != 2) {
      vs_sweep_row row;
      memset(&row, 0, sizeof row);
      row.run = r + 1;
      int pick[MAX_AXES];
      vs_sweep_pick(&s->job, row.run, pick);
      for (int x = 0; x < o->nax; x++) row.axis[x] = o->ax[x].v[pick[x]];
      snprintf(row.status, sizeof row.status, "%s", s->state[r] == 1 ? "interrupted" : "not_run");
      snprintf(row.error, sizeof row.error, "%s", s->state[r] == 1
                                                      ? "interrupted (rerun with --resume)"
                                                      : "not started: the sweep was interrupted");
      row.first_limit_mm = row.delta_u_mm = row.dz_pct = row.dx_pct = row.wall_s = NAN;
      row.left_dx_mm = row.left_dz_mm = row.right_dx_mm = row.right_dz_mm = NAN;
      row.load_factor = NAN;
      s->rows[s->n++] = row;
      unfinished++;
    }
  qsort(s->rows, (size_t)s->n, sizeof *s->rows, cmp_sweep_rows);
  char path[1100];
  snprintf(path, sizeof path, "%s/summary.csv", o->dir);
  /* a table not written is a failed sweep, though its runs are in the journal */
  int tables_ok = rewrite_table(path, o->ax, o->nax, s->rows, s->n, s->mortar) == 0;
  vs_error err;
  if (vs_sweep_summary_h5(o->dir, o->ax, o->nax, s->rows, s->n, &err) != VS_OK) {
    fprintf(stderr, "voussoir sweep: %s\n", err.msg);
    tables_ok = 0;
  }
  if (unfinished > 0) {
    printf("interrupted: %d of %d runs complete (%d failed), %d unfinished; table: %s; "
           "continue with --resume\n", s->total - unfinished, s->total, s->failed, unfinished,
           path);
    return EXIT_STOPPED;
  }
  char not_started[96] = "";
  if (s->not_started > 0)
    snprintf(not_started, sizeof not_started, ", %d of them could not start: run them with "
             "--resume", s->not_started);
  printf("%d runs (%d failed%s%s) in %.1f s on %d processes; ", s->total, s->failed, not_started,
         skipped ? ", some from before --resume" : "", wall, processes);
  if (tables_ok) printf("table: %s (and summary.h5)\n", path);
  else printf("the tables were not written (above); --resume writes them\n");
  report_failures(s, path);
  return s->failed || !tables_ok ? EXIT_FAIL : 0;
}

static void sweep_free(sweep_state *s) {
  if (s->csv != NULL) fclose(s->csv);
  if (s->journal != NULL) fclose(s->journal);
  vs_outlock_release(&s->lock);
  free(s->rows);
  free(s->state);
}

/* The runs on this machine: forked workers, -j at a time. */
static int serve_local(sweep_state *s, int *h5_clean) {
  (void)h5_clean; /* the workers' records are closed in the workers */
  const vs_sweep_server srv = {next_run, take_row, s};
  const int progress = !s->o->quiet && isatty(STDERR_FILENO);
  if (vs_sweep_pool_serve(&srv, &s->job, s->o->jobs, s->todo, progress, &g_stop_count,
                          &g_stop_signal) != 0)
    fprintf(stderr, "voussoir sweep: cannot start a worker: %s\n", strerror(errno));
  return s->o->jobs;
}

#ifdef VS_HAVE_MPI
/* The MPI farm's view of vs_sweep_run_case: its job is opaque there. */
static void run_case_any(const void *job, int run, const volatile sig_atomic_t *stop,
                         vs_sweep_row *row, int *h5_clean) {
  vs_sweep_run_case(job, run, stop, row, h5_clean);
}
#endif

#ifdef VS_HAVE_MPI
/* The runs across the ranks of an MPI job: rank 0 hands them out (one rank: it runs them
 * itself). Returns the number of ranks on rank 0, 0 on the others (which have finished). */
static int serve_mpi(sweep_state *s, const char *manifest, int *rc, int *h5_clean) {
  int size = 1;
  const int rank = vs_sweep_mpi_begin(&size);
  if (rank != 0) {
    vs_sweep_mpi_work(&s->job, run_case_any, &g_stop_count, h5_clean);
  } else if ((*rc = sweep_open(s, manifest)) != 0) {
    const vs_sweep_server none = {next_run, take_row, s};
    s->total = 0; /* nothing to hand out: the other ranks are told to stop */
    vs_sweep_mpi_serve(&none, size);
  } else if (size == 1) {
    for (int r = next_run(s); r > 0; r = next_run(s)) {
      vs_sweep_row row;
      vs_sweep_run_case(&s->job, r, &g_stop_count, &row, h5_clean);
      take_row(s, &row);
    }
  } else {
    const vs_sweep_server srv = {next_run, take_row, s};
    vs_sweep_mpi_serve(&srv, size);
  }
  vs_sweep_mpi_end();
  return rank == 0 ? (size > 1 ? size - 1 : 1) : 0;
}
#endif

static int sweep_run(const sweep_opts *o, const vs_case *base, const char *case_text,
                     const char *manifest, int *h5_clean) {
  sweep_state s = {.o = o, .total = sweep_size(o->ax, o->nax)}; /* checked by vs_cmd_sweep */
  s.job = (vs_sweep_job){o->case_path, case_text, o->dir, base, o->ax, o->nax,
                         o->mode_flag == NULL                        ? NULL
                         : strcmp(o->mode_flag, "--dynamic") == 0 ? "dynamic.full=1"
                                                                   : "dynamic.follow=0"};
  s.mortar = study_mortared(base, o->ax, o->nax);
  const double t0 = now_s();
  int rc = 0, processes;
#ifdef VS_HAVE_MPI
  if (vs_plugin_mpi_launched()) {
    if (vs_plugin_load(VS_PLUGIN_MPI, "voussoir sweep") != 0) {
      sweep_free(&s);
      return EXIT_FAIL;
    }
    processes = serve_mpi(&s, manifest, &rc, h5_clean);
    if (processes == 0 || rc != 0) { /* a worker rank, or rank 0 could not start */
      sweep_free(&s);
      return rc;
    }
  } else
#endif
  {
    if ((rc = sweep_open(&s, manifest)) != 0) {
      sweep_free(&s);
      return rc;
    }
    processes = serve_local(&s, h5_clean);
  }
  rc = sweep_close(&s, now_s() - t0, processes);
  sweep_free(&s);
  return rc;
}

int vs_sweep_main(const vs_sweep_opts *o, int *h5_clean) {
  int rc = -1;
  if (sweep_size(o->ax, o->nax) < 0) {
    fprintf(stderr, "voussoir sweep: more than %d runs (the product of the lists' lengths); "
                    "split the study\n", VS_SWEEP_MAX_RUNS);
    rc = EXIT_USAGE;
  }
  if (rc < 0 && validate_all(o->case_path, o->sets, o->nsets, o->ax, o->nax) != 0) rc = EXIT_USAGE;
  /* every run writes a record: the record plugin, before anything is written or forked */
  if (rc < 0 && vs_plugin_load(VS_PLUGIN_RECORD, "voussoir sweep") != 0) rc = EXIT_FAIL;
  if (rc < 0) {
    vs_case c;
    vs_error err;
    vs_error_clear(&err);
    char *manifest = NULL, *case_text = NULL;
    if (load_case_text(o->case_path, o->sets, o->nsets, &c, &case_text, &err) == VS_OK)
      manifest = manifest_text(&c, o->ax, o->nax, o->mode_flag);
    rc = manifest == NULL ? EXIT_FAIL : sweep_run(o, &c, case_text, manifest, h5_clean);
    free(manifest);
    free(case_text);
  }
  return rc;
}
