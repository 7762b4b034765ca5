/* The sweep and calibrate commands: many runs of one case. A sweep runs every combination of its
 * axes as an independent process of this program on all cores and collects their JSON into a
 * summary table; calibrate finds the k_n that reproduces a measured collapse displacement. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

#include <hdf5.h>

#include "voussoir/outpath.h"
#include "voussoir/parse.h"
#include "voussoir/run.h"
#include "voussoir/sweep.h"
#include "voussoir/units.h"

enum { EXIT_FAIL = 1, EXIT_USAGE = 2, MAX_AXES = 8, MAX_SETS = 64 };

static const char *SWEEP_USAGE =
    "usage: voussoir sweep CASE [--alpha LIST] [--kn LIST] [--vary SECTION.KEY=LIST]...\n"
    "                      [--set SECTION.KEY=VALUE]... [--first-limit | --dynamic]\n"
    "                      [-j N] [-o DIR] [--resume] [-q]\n"
    "Runs the case for every combination of the lists, as independent processes (-j, default:\n"
    "the number of cores), and writes DIR/run_NNNN.h5 (the record) and .json per run and\n"
    "DIR/summary.csv. A run that\n"
    "fails is reported in the table with its cause; the others go on.\n"
    "LIST: comma-separated numbers and inclusive ranges first:last:step, e.g. 0:45:5,60,75,90.\n"
    "--alpha and --kn are the axes support.alpha_deg and joints.kn_N_mm3; --vary sweeps any key.\n"
    "-o DIR: default sweep_out. At most 100000 runs.\n"
    "SIGINT/SIGTERM: the runs under way are interrupted (the signal is passed on), the summary\n"
    "lists what finished and marks the rest 'interrupted' or 'not_run'; exit status 130.\n"
    "--resume: continue the sweep in DIR (same case, lists, --set and mode): a run whose\n"
    "DIR/run_NNNN.json exists is complete and is not run again (that file appears only when\n"
    "the run has ended).\n"
    "Exit status 0 when every run worked, 1 if any failed, 2 bad input, 130 interrupted.\n";

static const char *CAL_USAGE =
    "usage: voussoir calibrate CASE (--target-dz-pct X | --target-dx-pct X) [--kn-min N_MM3]\n"
    "                          [--kn-max N_MM3] [--tol-pct X] [--set SECTION.KEY=VALUE]... [-q]\n"
    "Finds the joint stiffness k_n (N/mm^3) whose collapse displacement component dz/L (or\n"
    "dx/L), in %, equals the target: a log-spaced scan of [kn-min, kn-max] (default 0.1, 100)\n"
    "brackets the first crossing, then bracketed false position (Illinois) on log k_n refines it\n"
    "to tol-pct (default 0.01 % of L). Reports the bracket, every iteration and the sensitivity\n"
    "d(delta_u/L)/d(log10 k_n) at the answer; says so when no k_n in the range reaches the target.\n";

typedef struct {
  char key[96];  /* section.key */
  double *v;
  int n;
} axis;

/* --- a tiny reader of the fields of voussoir's own JSON --- */

static const char *after(const char *s, const char *anchor) {
  const char *p = s ? strstr(s, anchor) : NULL;
  return p ? p + strlen(anchor) : NULL;
}

static double num_after(const char *s, const char *anchor) {
  const char *p = after(s, anchor);
  if (p == NULL || strncmp(p, "null", 4) == 0) return NAN;
  return strtod(p, NULL);
}

/* The string value after anchor (which ends with the opening quote), unescaped naively. */
static void str_after(const char *s, const char *anchor, char *out, size_t size) {
  const char *p = after(s, anchor);
  size_t k = 0;
  out[0] = '\0';
  if (p == NULL) return;
  for (; *p && *p != '"' && k + 1 < size; p++) {
    if (*p == '\\' && p[1]) p++;
    out[k++] = *p;
  }
  out[k] = '\0';
}

/* "D:1-E A:9-10-I ..." from the collapse object's hinges. */
static void collapse_hinges(const char *json, char *out, size_t size) {
  out[0] = '\0';
  const char *c = after(json, "\"collapse\":{");
  const char *h = c ? after(c, "\"hinges\":[") : NULL;
  size_t used = 0;
  while (h && *h == '{') {
    char label[8], side[8], joints[128] = "";
    str_after(h, "\"label\":\"", label, sizeof label);
    str_after(h, "\"side\":\"", side, sizeof side);
    const char *j = after(h, "\"joints\":[");
    size_t k = 0;
    for (; j && *j && *j != ']' && k + 1 < sizeof joints; j++) joints[k++] = (*j == ',') ? '-' : *j;
    joints[k] = '\0';
    int w = snprintf(out + used, size - used, "%s%s:%s-%s", used ? " " : "", label, joints, side);
    if (w < 0 || (size_t)w >= size - used) break;
    used += (size_t)w;
    h = strchr(h, '}');
    if (h == NULL) break;
    h += (h[1] == ',') ? 2 : 1;
  }
}

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  size_t cap = 4096, n = 0;
  char *buf = malloc(cap);
  for (size_t r; buf != NULL && (r = fread(buf + n, 1, cap - n - 1, f)) > 0;) {
    n += r;
    if (cap - n < 2) {
      char *nb = realloc(buf, cap *= 2);
      if (nb == NULL) {
        free(buf);
        buf = NULL;
      } else {
        buf = nb;
      }
    }
  }
  fclose(f);
  if (buf) buf[n] = '\0';
  return buf;
}

/* --- sweep --- */

/* One row of the summary, as parsed from a run's JSON. */
typedef struct {
  int run;
  double axis[MAX_AXES];
  char status[32], mode[8], hinges[512], error[512];
  double first_limit, delta_u, dz, dx, wall;
  int snaps;
} sweep_row;

typedef struct {
  pid_t pid;
  int index;
} child;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The signal that asked the sweep to stop (0: none) and how many arrived: the first is passed
 * on to the runs under way, a second kills them. Static because a handler can reach nothing
 * else; only vs_cmd_sweep reads them. */
static volatile sig_atomic_t g_stop_signal = 0, g_stop_count = 0;

/* Start run `index` (values[a] of every axis) as a child writing DIR/run_NNNN.json/.err. */
static pid_t start_run(const char *self, const char *case_path, const char *dir, int index,
                       const axis *ax, int nax, const int *pick, char **sets, int nsets,
                       const char *mode_flag) {
  char *args[2 * (MAX_AXES + MAX_SETS) + 16];
  char vals[MAX_AXES][160], json[1100], errp[1100], h5[1100];
  int a = 0;
  args[a++] = (char *)self;
  args[a++] = "run";
  args[a++] = (char *)case_path;
  /* the domain is read before the fall, which (to rest on the ground) costs the most; a --set
   * of the sweep's own, after it, still follows it */
  args[a++] = "--set";
  args[a++] = "dynamic.fall_s=0";
  for (int s = 0; s < nsets; s++) {
    args[a++] = "--set";
    args[a++] = sets[s];
  }
  for (int x = 0; x < nax; x++) {
    snprintf(vals[x], sizeof vals[x], "%.95s=%.17g", ax[x].key, ax[x].v[pick[x]]);
    args[a++] = "--set";
    args[a++] = vals[x];
  }
  if (mode_flag != NULL) args[a++] = (char *)mode_flag;
  snprintf(h5, sizeof h5, "%s/run_%04d.h5", dir, index);
  args[a++] = "-o";
  args[a++] = h5;
  args[a++] = "--json";
  args[a++] = "-q";
  args[a] = NULL;
  snprintf(json, sizeof json, "%s/run_%04d.json.part", dir, index);
  snprintf(errp, sizeof errp, "%s/run_%04d.err", dir, index);
  const pid_t parent = getpid();
  pid_t pid = fork();
  if (pid != 0) return pid; /* parent (or -1) */
  /* Own process group: a terminal's ^C reaches the parent only, which passes it on once. */
  setpgid(0, 0);
#ifdef __linux__
  prctl(PR_SET_PDEATHSIG, SIGTERM); /* the parent killed outright: the run stops too */
#endif
  if (getppid() != parent) _exit(130); /* it died before prctl */
  /* Until exec, a signal passed on to this run must not be lost in the parent's handler. */
  signal(SIGINT, SIG_DFL);
  signal(SIGTERM, SIG_DFL);
  if (g_stop_count > 0) _exit(130);
  int fo = open(json, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  int fe = open(errp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fo < 0 || fe < 0 || dup2(fo, STDOUT_FILENO) < 0 || dup2(fe, STDERR_FILENO) < 0) _exit(127);
  execv(self, args);
  _exit(127);
}

/* One row of the summary: from DIR/run_NNNN.json, or (unfinished: "interrupted" or "not_run")
 * with that status and no results. */
static void write_row(FILE *csv, sweep_row *row, int index, const axis *ax, int nax,
                      const int *pick, const char *dir, int exit_status, const char *unfinished) {
  char path[1024], status[32] = "failed", error[512] = "", mode[8] = "", hinges[512] = "";
  snprintf(path, sizeof path, "%s/run_%04d.json", dir, index);
  char *json = unfinished == NULL ? slurp(path) : NULL;
  fprintf(csv, "%d", index);
  for (int x = 0; x < nax; x++) fprintf(csv, ",%.10g", ax[x].v[pick[x]]);
  if (unfinished != NULL) {
    snprintf(status, sizeof status, "%s", unfinished);
    snprintf(error, sizeof error, "%s", strcmp(unfinished, "not_run") == 0
                                            ? "not started: the sweep was interrupted"
                                            : "interrupted (rerun with --resume)");
  } else if (json != NULL && strstr(json, "\"program\":\"voussoir\"") != NULL) {
    str_after(json, "\"status\":\"", status, sizeof status);
    str_after(json, "\"error\":\"", error, sizeof error);
    str_after(json, "\"mode\":\"", mode, sizeof mode);
    collapse_hinges(json, hinges, sizeof hinges);
  } else {
    snprintf(path, sizeof path, "%s/run_%04d.err", dir, index);
    char *e = slurp(path);
    snprintf(error, sizeof error, "exit status %d: %s", exit_status, e ? e : "");
    free(e);
    char *nl = strchr(error, '\n');
    if (nl) *nl = '\0';
  }
  int snaps = 0;
  for (const char *p = json; p && (p = strstr(p, "\"kind\":\"snap\"")) != NULL; p++) snaps++;
  for (char *p = error; *p; p++)
    if (*p == '"') *p = '\'';
  row->run = index;
  for (int x = 0; x < nax; x++) row->axis[x] = ax[x].v[pick[x]];
  snprintf(row->status, sizeof row->status, "%s", status);
  snprintf(row->mode, sizeof row->mode, "%s", mode);
  snprintf(row->hinges, sizeof row->hinges, "%s", hinges);
  snprintf(row->error, sizeof row->error, "%s", error);
  row->first_limit = num_after(json, "\"first_limit\":{\"delta_mm\":");
  row->delta_u = num_after(json, "\"collapse\":{\"delta_mm\":");
  row->dz = num_after(after(json, "\"collapse\":{"), "\"dz_over_L_pct\":");
  row->dx = num_after(after(json, "\"collapse\":{"), "\"dx_over_L_pct\":");
  row->wall = num_after(json, "\"wall_s\":");
  row->snaps = snaps;
  fprintf(csv, ",%s,%.10g,%.10g,%.10g,%.10g,\"%s\",%s,%d,%.4g,\"%s\"\n", status, row->first_limit,
          row->delta_u, row->dz, row->dx, hinges, mode, snaps, row->wall, error);
  fflush(csv);
  free(json);
}

static int cmp_sweep_rows(const void *x, const void *y) {
  return ((const sweep_row *)x)->run - ((const sweep_row *)y)->run;
}

/* The summary as an HDF5 compound table DIR/summary.h5 (/summary), units in an attribute. */
static int write_summary_h5(const char *dir, const axis *ax, int nax, sweep_row *rows, int n) {
  char path[1100];
  snprintf(path, sizeof path, "%s/summary.h5", dir);
  qsort(rows, (size_t)n, sizeof *rows, cmp_sweep_rows);
  typedef struct {
    int run;
    double axis[MAX_AXES];
    const char *status, *mode, *hinges, *error;
    double first_limit, delta_u, dz, dx, wall;
    int snaps;
  } mem;
  mem *m = calloc((size_t)(n > 0 ? n : 1), sizeof *m);
  if (m == NULL) return -1;
  for (int i = 0; i < n; i++) {
    m[i].run = rows[i].run;
    memcpy(m[i].axis, rows[i].axis, sizeof m[i].axis);
    m[i].status = rows[i].status;
    m[i].mode = rows[i].mode;
    m[i].hinges = rows[i].hinges;
    m[i].error = rows[i].error;
    m[i].first_limit = rows[i].first_limit;
    m[i].delta_u = rows[i].delta_u;
    m[i].dz = rows[i].dz;
    m[i].dx = rows[i].dx;
    m[i].wall = rows[i].wall;
    m[i].snaps = rows[i].snaps;
  }
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t str = H5Tcopy(H5T_C_S1);
  H5Tset_size(str, H5T_VARIABLE);
  H5Tset_cset(str, H5T_CSET_UTF8);
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(mem));
  H5Tinsert(t, "run", HOFFSET(mem, run), H5T_NATIVE_INT);
  char units[1024] = "run: -";
  size_t used = strlen(units);
  for (int x = 0; x < nax; x++) {
    H5Tinsert(t, ax[x].key, HOFFSET(mem, axis) + (size_t)x * sizeof(double), H5T_NATIVE_DOUBLE);
    used += (size_t)snprintf(units + used, sizeof units - used, "; %s: case units", ax[x].key);
  }
  H5Tinsert(t, "status", HOFFSET(mem, status), str);
  H5Tinsert(t, "first_limit_mm", HOFFSET(mem, first_limit), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "delta_u_mm", HOFFSET(mem, delta_u), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dz_over_L_pct", HOFFSET(mem, dz), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "dx_over_L_pct", HOFFSET(mem, dx), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "hinges_at_collapse", HOFFSET(mem, hinges), str);
  H5Tinsert(t, "mode", HOFFSET(mem, mode), str);
  H5Tinsert(t, "snaps", HOFFSET(mem, snaps), H5T_NATIVE_INT);
  H5Tinsert(t, "wall_s", HOFFSET(mem, wall), H5T_NATIVE_DOUBLE);
  H5Tinsert(t, "error", HOFFSET(mem, error), str);
  snprintf(units + used, sizeof units - used,
           "; status, hinges_at_collapse, mode, error: text; first_limit_mm, delta_u_mm: mm; "
           "dz_over_L_pct, dx_over_L_pct: %% of the intrados span; snaps: count; wall_s: s");
  hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  hsize_t dims[1] = {(hsize_t)n};
  hid_t sp = H5Screate_simple(1, dims, NULL);
  hid_t d = f >= 0 ? H5Dcreate2(f, "summary", t, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT) : -1;
  int ok = d >= 0 && H5Dwrite(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, m) >= 0;
  if (ok) {
    hid_t as = H5Screate(H5S_SCALAR), a = H5Acreate2(d, "unit", str, as, H5P_DEFAULT, H5P_DEFAULT);
    const char *u = units;
    ok = a >= 0 && H5Awrite(a, str, &u) >= 0;
    if (a >= 0) H5Aclose(a);
    H5Sclose(as);
  }
  if (d >= 0) H5Dclose(d);
  H5Sclose(sp);
  if (f >= 0) H5Fclose(f);
  H5Tclose(t);
  H5Tclose(str);
  free(m);
  return ok ? 0 : -1;
}

static int cmp_rows(const void *x, const void *y) {
  return (int)(strtol(*(char *const *)x, NULL, 10) - strtol(*(char *const *)y, NULL, 10));
}

/* Rewrite the table (written in completion order) in run order, atomically. */
static void sort_table(const char *path) {
  char *text = slurp(path), tmp[1200];
  if (text == NULL) return;
  char *header = text, *body = strchr(text, '\n');
  int n = 0, cap = 64;
  char **rows = malloc((size_t)cap * sizeof *rows);
  if (body == NULL || rows == NULL) {
    free(text);
    free(rows);
    return;
  }
  *body++ = '\0';
  for (char *line = strtok(body, "\n"); line; line = strtok(NULL, "\n")) {
    if (n == cap) {
      char **nr = realloc(rows, (size_t)(cap *= 2) * sizeof *rows);
      if (nr == NULL) break;
      rows = nr;
    }
    rows[n++] = line;
  }
  qsort(rows, (size_t)n, sizeof *rows, cmp_rows);
  snprintf(tmp, sizeof tmp, "%s.tmp", path);
  FILE *f = fopen(tmp, "w");
  if (f != NULL) {
    fprintf(f, "%s\n", header);
    for (int i = 0; i < n; i++) fprintf(f, "%s\n", rows[i]);
    if (fclose(f) == 0) rename(tmp, path);
  }
  free(rows);
  free(text);
}

static int parse_common(int argc, char **argv, int i, char **sets, int *nsets) {
  if (strcmp(argv[i], "--set") == 0 && i + 1 < argc && *nsets < MAX_SETS) {
    sets[(*nsets)++] = argv[i + 1];
    return 2;
  }
  return 0;
}

/* The case file with the --set overrides applied (in order), not yet validated. */
static vs_status load_case(const char *case_path, char **sets, int nsets, vs_case *c,
                           vs_error *err) {
  vs_case_defaults(c);
  vs_status st = vs_case_read(c, case_path, NULL, err);
  for (int s = 0; st == VS_OK && s < nsets; s++) st = vs_case_set(c, sets[s], err);
  return st;
}

/* Validate the case with the fixed overrides and every value of every axis. */
static int validate_all(const char *case_path, char **sets, int nsets, const axis *ax, int nax) {
  vs_case c;
  vs_error err;
  vs_error_clear(&err);
  if (load_case(case_path, sets, nsets, &c, &err) != VS_OK) goto bad;
  for (int x = 0; x < nax; x++)
    for (int k = 0; k < ax[x].n; k++) {
      vs_case t = c;
      char buf[160];
      snprintf(buf, sizeof buf, "%.95s=%.17g", ax[x].key, ax[x].v[k]);
      if (vs_case_set(&t, buf, &err) != VS_OK || vs_case_validate(&t, &err) != VS_OK) goto bad;
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

static void catch_stop_signals(void) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
}

/* A run's JSON as written by a run that ended: one object, complete. */
static int json_complete(const char *json) {
  size_t n = json ? strlen(json) : 0;
  return n > 2 && strstr(json, "\"program\":\"voussoir\"") != NULL && json[n - 1] == '\n' &&
         json[n - 2] == '}';
}

/* What the sweep is, as text: the case after --set, every axis with its values, the mode. A
 * --resume must find the same in DIR/sweep.manifest, so that it completes the same sweep. */
static char *manifest_text(const vs_case *c, const axis *ax, int nax, const char *mode_flag) {
  size_t cap = 4096, used = 0;
  for (int x = 0; x < nax; x++) cap += 128 + 26 * (size_t)ax[x].n;
  char *t = malloc(cap);
  if (t == NULL) return NULL;
  t[0] = '\0';
  for (int i = 0; i < vs_case_key_count(); i++) {
    const char *sec, *key;
    double v;
    vs_case_key(c, i, &sec, &key, NULL, NULL, &v);
    used += (size_t)snprintf(t + used, cap - used, "%s.%s=%.17g\n", sec, key, v);
  }
  for (int x = 0; x < nax; x++) {
    used += (size_t)snprintf(t + used, cap - used, "axis %s:", ax[x].key);
    for (int k = 0; k < ax[x].n; k++)
      used += (size_t)snprintf(t + used, cap - used, " %.17g", ax[x].v[k]);
    used += (size_t)snprintf(t + used, cap - used, "\n");
  }
  snprintf(t + used, cap - used, "mode %s\n", mode_flag ? mode_flag : "default");
  return t;
}

/* Fresh sweep: write the manifest and forget the results of any earlier sweep in DIR (their
 * run_NNNN.json would otherwise count as complete for a later --resume). Resume: require the
 * same manifest. Returns 0, or -1 after printing why. */
static int prepare_dir(const char *dir, const char *manifest, int total, int resume) {
  char path[1100];
  snprintf(path, sizeof path, "%s/sweep.manifest", dir);
  if (resume) {
    char *old = slurp(path);
    int same = old != NULL && strcmp(old, manifest) == 0;
    if (!same)
      fprintf(stderr, "voussoir sweep: --resume: %s %s\n", path,
              old == NULL ? "is missing: no sweep to resume in this directory"
                          : "differs: that sweep had another case, lists, --set or mode");
    free(old);
    return same ? 0 : -1;
  }
  remove(path);
  for (int r = 1; r <= total; r++) {
    char json[1100];
    snprintf(json, sizeof json, "%s/run_%04d.json", dir, r);
    remove(json);
  }
  FILE *f = fopen(path, "w");
  int ok = f != NULL && fputs(manifest, f) >= 0;
  if (f != NULL && fclose(f) != 0) ok = 0;
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

typedef struct {
  const char *self, *case_path, *dir, *mode_flag;
  char **sets;
  int nsets, nax, jobs, quiet, resume;
  axis *ax;
} sweep_opts;

static int parse_sweep_args(int argc, char **argv, sweep_opts *o, char **sets) {
  vs_error err;
  vs_error_clear(&err);
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int used = parse_common(argc, argv, i, sets, &o->nsets);
    if (used) {
      i += used - 1;
    } else if ((strcmp(a, "--alpha") == 0 || strcmp(a, "--kn") == 0 || strcmp(a, "--vary") == 0) &&
               i + 1 < argc) {
      if (o->nax == MAX_AXES) {
        fprintf(stderr, "voussoir sweep: at most %d axes\n", MAX_AXES);
        return EXIT_USAGE;
      }
      axis *x = &o->ax[o->nax];
      const char *list = argv[++i];
      if (strcmp(a, "--vary") == 0) {
        const char *eq = strchr(list, '=');
        if (eq == NULL || (size_t)(eq - list) >= sizeof x->key) {
          fprintf(stderr, "voussoir sweep: --vary %.64s: expected SECTION.KEY=LIST (KEY shorter "
                          "than %d characters)\n", list, (int)sizeof x->key);
          return EXIT_USAGE;
        }
        snprintf(x->key, sizeof x->key, "%.*s", (int)(eq - list), list);
        list = eq + 1;
      } else {
        snprintf(x->key, sizeof x->key, "%s",
                 strcmp(a, "--alpha") == 0 ? "support.alpha_deg" : "joints.kn_N_mm3");
      }
      if (vs_parse_list(a, list, &x->v, &x->n, &err) != VS_OK) {
        fprintf(stderr, "voussoir sweep: %s\n", err.msg);
        return EXIT_USAGE;
      }
      o->nax++;
    } else if (strcmp(a, "-j") == 0 && i + 1 < argc) {
      if (vs_parse_option_int("-j", argv[++i], 1, 1024, &o->jobs, &err) != VS_OK) {
        fprintf(stderr, "voussoir sweep: %s\n", err.msg);
        return EXIT_USAGE;
      }
    } else if (strcmp(a, "-o") == 0 && i + 1 < argc) {
      o->dir = argv[++i];
    } else if (strcmp(a, "-q") == 0) {
      o->quiet = 1;
    } else if (strcmp(a, "--resume") == 0) {
      o->resume = 1;
    } else if (strcmp(a, "--first-limit") == 0 || strcmp(a, "--dynamic") == 0) {
      o->mode_flag = a;
    } else if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(SWEEP_USAGE, stdout);
      return 0;
    } else if (a[0] != '-' && o->case_path == NULL) {
      o->case_path = a;
    } else {
      fprintf(stderr, "voussoir sweep: unexpected argument %s\n%s", a, SWEEP_USAGE);
      return EXIT_USAGE;
    }
  }
  if (strlen(o->dir) > 1000) {
    fprintf(stderr, "voussoir sweep: -o %.64s...: directory name too long (at most 1000 "
                    "characters)\n", o->dir);
    return EXIT_USAGE;
  }
  if (o->case_path == NULL || o->nax == 0) {
    fprintf(stderr, "voussoir sweep: needs a CASE and at least one list\n%s", SWEEP_USAGE);
    return EXIT_USAGE;
  }
  return -1; /* go on */
}

/* Pass the stop signal on to every run under way (a second signal: kill them). */
static void forward_signal(const child *running, int jobs, int *forwarded) {
  if (g_stop_count == 0 || *forwarded >= (g_stop_count > 1 ? 2 : 1)) return;
  const int sig = g_stop_count > 1 ? SIGKILL : g_stop_signal;
  for (int k = 0; k < jobs; k++)
    if (running[k].pid > 0) kill(running[k].pid, sig);
  *forwarded = g_stop_count > 1 ? 2 : 1;
}

/* Run every run not yet complete, -j at a time; rows are written in completion order. Returns
 * the number of rows written; *failed counts the failed runs; state[r]: 0 to run, 1 running,
 * 2 done (its row written). */
static int run_all(const sweep_opts *o, int total, int (*picks)[MAX_AXES], char *state,
                   sweep_row *rows, FILE *csv, int *failed) {
  child *running = calloc((size_t)o->jobs, sizeof *running);
  if (running == NULL) return -1;
  int n = 0, active = 0, next = 0, forwarded = 0, todo = 0;
  for (int r = 0; r < total; r++) todo += state[r] == 0;
  const double t0 = now_s();
  const int progress = !o->quiet && isatty(STDERR_FILENO);
  for (int ended = 0; ended < todo;) {
    while (g_stop_count == 0 && active < o->jobs && next < total) {
      if (state[next] != 0) {
        next++;
        continue;
      }
      pid_t pid = start_run(o->self, o->case_path, o->dir, next + 1, o->ax, o->nax, picks[next],
                            o->sets, o->nsets, o->mode_flag);
      if (pid < 0) {
        fprintf(stderr, "voussoir sweep: fork failed: %s\n", strerror(errno));
        break;
      }
      for (int k = 0; k < o->jobs; k++)
        if (running[k].pid == 0) {
          running[k] = (child){pid, next};
          break;
        }
      state[next++] = 1;
      active++;
    }
    if (active == 0) break;
    /* Poll rather than block in wait(): a signal landing just before a blocking wait would not
     * be passed on until some run ended by itself. 20 ms costs nothing next to a run. */
    int status = 0;
    pid_t pid;
    while ((pid = waitpid(-1, &status, WNOHANG)) == 0) {
      forward_signal(running, o->jobs, &forwarded);
      nanosleep(&(struct timespec){0, 20000000}, NULL);
    }
    if (pid < 0 && errno == EINTR) continue;
    if (pid < 0) break;
    for (int k = 0; k < o->jobs; k++) {
      if (running[k].pid != pid) continue;
      const int r = running[k].index, code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      char part[1100], json[1100];
      snprintf(part, sizeof part, "%s/run_%04d.json.part", o->dir, r + 1);
      snprintf(json, sizeof json, "%s/run_%04d.json", o->dir, r + 1);
      char *text = slurp(part);
      /* ended (0 ok, 1 failed with its cause) and said so: from now on the run is complete */
      const int complete = (code == 0 || code == 1) && json_complete(text);
      free(text);
      if (complete && rename(part, json) != 0) {
        fprintf(stderr, "voussoir sweep: %s: cannot rename: %s\n", part, strerror(errno));
      }
      if (!complete) remove(part);
      if (complete || g_stop_count == 0) { /* a run that crashed on its own is a failed row */
        write_row(csv, &rows[n++], r + 1, o->ax, o->nax, picks[r], o->dir, code, NULL);
        *failed += code != 0;
        state[r] = 2;
      } /* else interrupted: state stays 1, written as such at the end */
      running[k].pid = 0;
      active--;
      ended++;
    }
    if (progress)
      fprintf(stderr, "\r  runs %d/%d done, %d running, %d failed, %.1f s   ", ended, todo, active,
              *failed, now_s() - t0);
  }
  if (progress) fputs("\r\033[K", stderr);
  free(running);
  return n;
}

/* Rows of the runs already complete in DIR (--resume); marks them done. */
static int resumed_rows(const sweep_opts *o, int total, int (*picks)[MAX_AXES], char *state,
                        sweep_row *rows, FILE *csv, int *failed) {
  int n = 0;
  for (int r = 0; r < total; r++) {
    char path[1100];
    snprintf(path, sizeof path, "%s/run_%04d.json", o->dir, r + 1);
    char *json = slurp(path);
    if (json_complete(json)) {
      const int code = strstr(json, "\"status\":\"failed\"") != NULL;
      write_row(csv, &rows[n++], r + 1, o->ax, o->nax, picks[r], o->dir, code, NULL);
      *failed += code;
      state[r] = 2;
    }
    free(json);
  }
  return n;
}

static int sweep_run(const sweep_opts *o, const char *manifest) {
  const int total = sweep_size(o->ax, o->nax); /* checked by vs_cmd_sweep */
  char path[1100];
  snprintf(path, sizeof path, "%s/summary.csv", o->dir);
  vs_error err;
  vs_error_clear(&err);
  if (vs_outpath_check_dir(o->dir, &err) != VS_OK ||
      (access(o->dir, F_OK) == 0 && vs_outpath_check(path, NULL, 0, &err) != VS_OK)) {
    fprintf(stderr, "voussoir sweep: -o %s\n", err.msg);
    return EXIT_USAGE;
  }
  if (mkdir(o->dir, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir sweep: -o %s: cannot create: %s\n", o->dir, strerror(errno));
    return EXIT_USAGE;
  }
  if (prepare_dir(o->dir, manifest, total, o->resume) != 0) return EXIT_USAGE;
  FILE *csv = fopen(path, "w");
  if (csv == NULL) {
    fprintf(stderr, "voussoir sweep: %s: cannot create: %s\n", path, strerror(errno));
    return EXIT_USAGE;
  }
  fputs("run", csv);
  for (int x = 0; x < o->nax; x++) fprintf(csv, ",%s", o->ax[x].key);
  fputs(",status,first_limit_mm,delta_u_mm,dz_over_L_pct,dx_over_L_pct,hinges_at_collapse,mode,"
        "snaps,wall_s,error\n",
        csv);
  int (*picks)[MAX_AXES] = calloc((size_t)total, sizeof *picks);
  sweep_row *rows = calloc((size_t)total, sizeof *rows);
  char *state = calloc((size_t)total, 1);
  if (picks == NULL || rows == NULL || state == NULL) {
    fprintf(stderr, "voussoir sweep: out of memory\n");
    fclose(csv);
    free(picks);
    free(rows);
    free(state);
    return EXIT_FAIL;
  }
  for (int r = 0; r < total; r++)
    for (int x = o->nax - 1, rem = r; x >= 0; x--) {
      picks[r][x] = rem % o->ax[x].n;
      rem /= o->ax[x].n;
    }
  const double t0 = now_s();
  int failed = 0, n = 0, skipped = 0;
  if (o->resume) {
    n = skipped = resumed_rows(o, total, picks, state, rows, csv, &failed);
    fprintf(stderr, "voussoir sweep: resuming: %d of %d runs already complete\n", skipped, total);
  }
  int ran = run_all(o, total, picks, state, rows + n, csv, &failed);
  n += ran > 0 ? ran : 0;
  int unfinished = 0;
  for (int r = 0; r < total; r++) /* interrupted or never started: marked as such */
    if (state[r] != 2) {
      write_row(csv, &rows[n++], r + 1, o->ax, o->nax, picks[r], o->dir, 0,
                state[r] == 1 ? "interrupted" : "not_run");
      unfinished++;
    }
  fclose(csv);
  sort_table(path);
  if (write_summary_h5(o->dir, o->ax, o->nax, rows, n) != 0)
    fprintf(stderr, "voussoir sweep: %s/summary.h5: cannot write\n", o->dir);
  free(picks);
  free(rows);
  free(state);
  if (unfinished > 0) {
    printf("interrupted: %d of %d runs complete (%d failed), %d unfinished; table: %s; "
           "continue with --resume\n", total - unfinished, total, failed, unfinished, path);
    return 130;
  }
  printf("%d runs (%d failed%s) in %.1f s on %d processes; table: %s (and summary.h5)\n", total,
         failed, skipped ? ", some from before --resume" : "", now_s() - t0, o->jobs, path);
  return failed ? EXIT_FAIL : 0;
}

int vs_cmd_sweep(int argc, char **argv, const char *self) {
  char *sets[MAX_SETS];
  axis ax[MAX_AXES];
  memset(ax, 0, sizeof ax);
  sweep_opts o = {.self = self, .dir = "sweep_out", .sets = sets, .ax = ax,
                  .jobs = (int)sysconf(_SC_NPROCESSORS_ONLN)};
  if (o.jobs < 1) o.jobs = 1;
  if (o.jobs > 1024) o.jobs = 1024;
  catch_stop_signals(); /* first, so that no signal is lost while the sweep sets up */
  int rc = parse_sweep_args(argc, argv, &o, sets);
  if (rc < 0 && sweep_size(ax, o.nax) < 0) {
    fprintf(stderr, "voussoir sweep: more than %d runs (the product of the lists' lengths); "
                    "split the study\n", VS_SWEEP_MAX_RUNS);
    rc = EXIT_USAGE;
  }
  if (rc < 0 && validate_all(o.case_path, sets, o.nsets, ax, o.nax) != 0) rc = EXIT_USAGE;
  if (rc < 0) {
    vs_case c;
    vs_error err;
    vs_error_clear(&err);
    char *manifest = NULL;
    if (load_case(o.case_path, sets, o.nsets, &c, &err) == VS_OK)
      manifest = manifest_text(&c, ax, o.nax, o.mode_flag);
    rc = manifest == NULL ? EXIT_FAIL : sweep_run(&o, manifest);
    free(manifest);
  }
  for (int x = 0; x < o.nax; x++) free(ax[x].v);
  return rc;
}

/* --- calibrate --- */

typedef struct {
  vs_case base;
  int dx;        /* 1: the dx component, 0: dz */
  int quiet;
  int runs;
} cal_ctx;

/* Collapse displacement component (% of L) at k_n; NaN if the run has no collapse. */
static double cal_eval(cal_ctx *c, double kn) {
  vs_case k = c->base;
  k.kn_N_mm3 = kn;
  k.fall_s = 0.0; /* delta_u is read before the fall, which costs the most */
  vs_run *r = NULL;
  vs_error err;
  vs_error_clear(&err);
  double out = NAN;
  c->runs++;
  if (vs_run_create(&k, &r, &err) == VS_OK && vs_run_execute(r, NULL, NULL, NULL, &err) == VS_OK &&
      vs_run_collapse(r)->found) {
    const double d = vs_run_collapse(r)->delta / VS_MM, a = k.alpha_deg * VS_DEG;
    out = 100.0 * d * (c->dx ? sin(a) : cos(a)) / vs_case_span_mm(&k);
  }
  vs_run_destroy(&r);
  if (!c->quiet) fprintf(stderr, "  k_n = %-12.6g  collapse %s/L = %.4f %%\n", kn, c->dx ? "dx" : "dz", out);
  return out;
}

/* One numeric option of calibrate, in [lo, hi] (the k_n bounds are the case's range of
 * joints.kn_N_mm3); prints the error. */
static int cal_number(const char *option, const char *text, double lo, double hi, double *out) {
  vs_error err;
  if (vs_parse_option_double(option, text, lo, hi, out, &err) == VS_OK) return 0;
  fprintf(stderr, "voussoir calibrate: %s\n", err.msg);
  return -1;
}

int vs_cmd_calibrate(int argc, char **argv) {
  const char *case_path = NULL;
  char *sets[MAX_SETS];
  int nsets = 0, have_target = 0;
  double target = NAN, kmin = 0.1, kmax = 100.0, tol = 0.01;
  cal_ctx c = {0};
  vs_error err;
  vs_error_clear(&err);
  for (int i = 2; i < argc; i++) {
    const char *a = argv[i];
    int used = parse_common(argc, argv, i, sets, &nsets);
    if (used) {
      i += used - 1;
    } else if ((strcmp(a, "--target-dz-pct") == 0 || strcmp(a, "--target-dx-pct") == 0) && i + 1 < argc) {
      c.dx = strcmp(a, "--target-dx-pct") == 0;
      if (cal_number(a, argv[++i], 1e-9, 1e4, &target) != 0) return EXIT_USAGE;
      have_target = 1;
    } else if (strcmp(a, "--kn-min") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-4, 1e4, &kmin) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "--kn-max") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-4, 1e4, &kmax) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "--tol-pct") == 0 && i + 1 < argc) {
      if (cal_number(a, argv[++i], 1e-12, 100.0, &tol) != 0) return EXIT_USAGE;
    } else if (strcmp(a, "-q") == 0) {
      c.quiet = 1;
    } else if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
      fputs(CAL_USAGE, stdout);
      return 0;
    } else if (a[0] != '-' && case_path == NULL) {
      case_path = a;
    } else {
      fprintf(stderr, "voussoir calibrate: unexpected argument %s\n%s", a, CAL_USAGE);
      return EXIT_USAGE;
    }
  }
  if (case_path == NULL || !have_target || !(target > 0.0) || !isfinite(target)) {
    fprintf(stderr, "voussoir calibrate: needs a CASE and a target > 0 %%\n%s", CAL_USAGE);
    return EXIT_USAGE;
  }
  if (!(kmax > kmin)) {
    fprintf(stderr, "voussoir calibrate: --kn-min %g, --kn-max %g (allowed: "
                    "1e-4 <= kn-min < kn-max <= 10000 N/mm^3)\n", kmin, kmax);
    return EXIT_USAGE;
  }
  if (load_case(case_path, sets, nsets, &c.base, &err) != VS_OK) goto bad;
  c.base.follow = 1;
  c.base.full = 0;
  if (vs_case_validate(&c.base, &err) != VS_OK) goto bad;
  if (c.dx && fabs(sin(c.base.alpha_deg * VS_DEG)) < 1e-12) {
    fprintf(stderr, "voussoir calibrate: --target-dx-pct with alpha = 0: dx is always 0\n");
    return EXIT_USAGE;
  }
  /* scan: log-spaced k_n, the first bracket of the target */
  enum { SCAN = 9 };
  double kn[SCAN], f[SCAN];
  int lo = -1;
  for (int i = 0; i < SCAN; i++) {
    kn[i] = kmin * pow(kmax / kmin, (double)i / (SCAN - 1));
    f[i] = cal_eval(&c, kn[i]) - target;
    if (i > 0 && isfinite(f[i]) && isfinite(f[i - 1]) && (f[i - 1] <= 0.0) != (f[i] <= 0.0)) {
      lo = i - 1;
      break;
    }
  }
  if (lo < 0) {
    double fmin_ = INFINITY, fmax_ = -INFINITY;
    for (int i = 0; i < SCAN; i++)
      if (isfinite(f[i])) {
        fmin_ = fmin(fmin_, f[i] + target);
        fmax_ = fmax(fmax_, f[i] + target);
      }
    printf("no k_n in [%g, %g] N/mm^3 gives a collapse %s/L of %g %%: the scan gives %.4f..%.4f %%\n",
           kmin, kmax, c.dx ? "dx" : "dz", target, fmin_, fmax_);
    return EXIT_FAIL;
  }
  /* Illinois false position on log k_n within the bracket */
  double xa = log10(kn[lo]), xb = log10(kn[lo + 1]), fa = f[lo], fb = f[lo + 1], x = xa, fx = fa;
  printf("bracket: k_n in [%.6g, %.6g] N/mm^3 (%s/L %.4f .. %.4f %%)\n", kn[lo], kn[lo + 1],
         c.dx ? "dx" : "dz", fa + target, fb + target);
  int side = 0, it = 0;
  for (; it < 40; it++) {
    x = (xa * fb - xb * fa) / (fb - fa);
    fx = cal_eval(&c, pow(10.0, x)) - target;
    if (!isfinite(fx)) { /* no collapse there: bisect instead */
      x = 0.5 * (xa + xb);
      fx = cal_eval(&c, pow(10.0, x)) - target;
      if (!isfinite(fx)) break;
    }
    printf("  iteration %2d: k_n = %.6g N/mm^3, %s/L = %.4f %%\n", it + 1, pow(10.0, x),
           c.dx ? "dx" : "dz", fx + target);
    if (fabs(fx) <= tol || xb - xa < 1e-5) break;
    if ((fx <= 0.0) == (fa <= 0.0)) {
      xa = x;
      fa = fx;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      xb = x;
      fb = fx;
      if (side == 1) fa *= 0.5;
      side = 1;
    }
  }
  if (!isfinite(fx)) {
    printf("calibration failed: no collapse within support.max_mm near k_n = %.6g\n", pow(10.0, x));
    return EXIT_FAIL;
  }
  const double k = pow(10.0, x), h = 0.01; /* central difference over +-0.01 in log10 k_n */
  const double fp = cal_eval(&c, pow(10.0, x + h)), fm = cal_eval(&c, pow(10.0, x - h));
  printf("k_n = %.6g N/mm^3 gives collapse %s/L = %.4f %% (target %g %%, tolerance %g %%)\n", k,
         c.dx ? "dx" : "dz", fx + target, target, tol);
  printf("sensitivity d(%s/L)/d(log10 k_n) = %.4g %% per decade; %d runs\n", c.dx ? "dx" : "dz",
         (fp - fm) / (2.0 * h), c.runs);
  return fabs(fx) <= tol ? 0 : EXIT_FAIL;
bad:
  fprintf(stderr, "voussoir calibrate: %s\n", err.msg);
  return EXIT_USAGE;
}
