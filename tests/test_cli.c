/* Tests of the voussoir command line, run as a program: help and version, exit status 2 with a
 * message naming the culprit (and no output file) on bad input, the JSON summary (keys, one
 * object on one line, numbers consistent with the support direction) and the -o CSV history
 * (one row per equilibrium; self-weight reactions against the arch weight computed here). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, mkfifo */

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef VS_BINARY
#error "VS_BINARY (path of the voussoir executable) must be defined"
#endif
#ifndef VS_SOURCE_DIR
#error "VS_SOURCE_DIR must be defined"
#endif

#define REFERENCE VS_SOURCE_DIR "/runs/reference.ini"

/* ---------------------------------------------------------------------------------------------
 * Running the program */

static char g_dir[64]; /* scratch directory of this test run */

static int setup(void **state) {
  (void)state;
  snprintf(g_dir, sizeof g_dir, "/tmp/vs_test_cli_XXXXXX");
  return mkdtemp(g_dir) == NULL ? -1 : 0;
}

static int teardown(void **state) {
  (void)state;
  DIR *d = opendir(g_dir);
  if (d == NULL) return -1;
  struct dirent *e;
  char path[512];
  while ((e = readdir(d)) != NULL) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    snprintf(path, sizeof path, "%s/%s", g_dir, e->d_name);
    remove(path);
  }
  closedir(d);
  return rmdir(g_dir);
}

typedef struct {
  char p[256];
} path_t;

/* g_dir/name, by value */
static path_t scratch(const char *name) {
  path_t r;
  snprintf(r.p, sizeof r.p, "%s/%s", g_dir, name);
  return r;
}

static int exists(const char *path) { return access(path, F_OK) == 0; }

/* Whole file as a string (caller frees); NULL if it cannot be read. */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) return NULL;
  size_t cap = 4096, n = 0;
  char *s = malloc(cap);
  size_t got;
  while (s != NULL && (got = fread(s + n, 1, cap - n - 1, f)) > 0) {
    n += got;
    if (cap - n - 1 == 0) {
      char *t = realloc(s, 2 * cap);
      if (t == NULL) free(s);
      s = t;
      cap *= 2;
    }
  }
  fclose(f);
  if (s != NULL) s[n] = '\0';
  return s;
}

typedef struct {
  int status; /* exit status, or -1 when it did not exit normally */
  char *out, *err;
} result;

/* Run "VS_BINARY args" with stdout and stderr captured in the scratch directory. */
static result run(const char *args) {
  char cmd[2048];
  const path_t po = scratch("stdout"), pe = scratch("stderr");
  const char *o = po.p, *e = pe.p;
  snprintf(cmd, sizeof cmd, "'%s' %s >'%s' 2>'%s'", VS_BINARY, args, o, e);
  int w = system(cmd);
  result r = {-1, NULL, NULL};
  if (w != -1 && WIFEXITED(w)) r.status = WEXITSTATUS(w);
  r.out = slurp(o);
  r.err = slurp(e);
  assert_non_null(r.out);
  assert_non_null(r.err);
  return r;
}

static void drop(result *r) {
  free(r->out);
  free(r->err);
}

static void expect_in(const char *text, const char *needle, const char *what) {
  if (strstr(text, needle) == NULL) fail_msg("%s lacks \"%s\":\n%s", what, needle, text);
}

static void expect_close(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want) + 1e-12))
    fail_msg("%s = %.12g, expected %.12g (relative tolerance %g)", what, got, want, rel);
}

/* ---------------------------------------------------------------------------------------------
 * A minimal JSON scanner: enough to check structure and pick values, no library. */

/* End of the JSON value starting at p (one past it), or NULL if malformed. Strings, objects and
 * arrays are matched (brackets of the right kind, escapes inside strings); scalars run to the
 * next ',', '}' or ']'. */
static const char *value_end(const char *p) {
  if (*p == '"') {
    for (p++; *p && *p != '"'; p++)
      if (*p == '\\' && *++p == '\0') return NULL;
    return *p == '"' ? p + 1 : NULL;
  }
  if (*p == '{' || *p == '[') {
    char stack[256];
    int depth = 0;
    while (*p) {
      if (*p == '"') {
        p = value_end(p);
        if (p == NULL) return NULL;
        continue;
      }
      if (*p == '{' || *p == '[') {
        if (depth == (int)sizeof stack) return NULL;
        stack[depth++] = (*p == '{') ? '}' : ']';
      } else if (*p == '}' || *p == ']') {
        if (depth == 0 || stack[depth - 1] != *p) return NULL;
        if (--depth == 0) return p + 1;
      }
      p++;
    }
    return NULL;
  }
  while (*p && *p != ',' && *p != '}' && *p != ']' && *p != '\n') p++;
  return p;
}

typedef struct {
  const char *b, *e; /* [b, e) */
} span;

/* The value of "key": directly inside the object s (not in nested ones). b == NULL if absent. */
static span member(span s, const char *key) {
  span none = {NULL, NULL};
  if (s.b == NULL || *s.b != '{') return none;
  const size_t kl = strlen(key);
  const char *p = s.b + 1;
  while (p < s.e && *p == '"') {
    const char *k = p, *ke = value_end(p);
    if (ke == NULL || ke >= s.e || *ke != ':') return none;
    const char *v = ke + 1, *ve = value_end(v);
    if (ve == NULL || ve > s.e) return none;
    if ((size_t)(ke - k) == kl + 2 && strncmp(k + 1, key, kl) == 0) return (span){v, ve};
    p = (*ve == ',') ? ve + 1 : ve;
  }
  return none;
}

static span need(span s, const char *key) {
  span v = member(s, key);
  if (v.b == NULL) fail_msg("JSON lacks the key \"%s\" in %.200s", key, s.b ? s.b : "(null)");
  return v;
}

static double number(span s, const char *key) {
  span v = need(s, key);
  char *end;
  double x = strtod(v.b, &end);
  if (end != v.e) fail_msg("\"%s\" is not a number: %.40s", key, v.b);
  return x;
}

/* stdout must be exactly one JSON object on one line; return it. */
static span one_object(const char *out) {
  const size_t n = strlen(out);
  if (n < 3 || out[0] != '{' || out[n - 1] != '\n' || strchr(out, '\n') != out + n - 1)
    fail_msg("stdout is not one object on one line:\n%s", out);
  const char *e = value_end(out);
  if (e == NULL) fail_msg("unbalanced braces, brackets or quotes in:\n%s", out);
  if (e != out + n - 1) fail_msg("text after the object: %s", e);
  return (span){out, e};
}

/* ---------------------------------------------------------------------------------------------
 * Help and version */

static void test_help(void **state) {
  (void)state;
  const char *opts[] = {"--alpha", "--kn", "--set", "--json", "-o", "-q", "--version", "--help"};
  const char *how[] = {"--help", "-h", "run --help"};
  for (size_t h = 0; h < sizeof how / sizeof how[0]; h++) {
    result r = run(how[h]);
    assert_int_equal(r.status, 0);
    for (size_t i = 0; i < sizeof opts / sizeof opts[0]; i++) expect_in(r.out, opts[i], how[h]);
    expect_in(r.out, "usage:", how[h]);
    drop(&r);
  }
}

/* Every command answers -h and --help with its own usage (exit 0, stdout), and refuses an unknown
 * option or an option without its value the same way (exit 2, the option named, nothing on
 * stdout), whatever its other arguments. */
static void test_command_help(void **state) {
  (void)state;
  const char *cmds[] = {"sweep", "calibrate", "montecarlo", "merge", "plot"};
  const char *own[] = {"--vary", "--target-dz-pct", "--shard", "DIR... -o OUT", "--svg"};
  const char *valued[] = {"--alpha", "--kn-min", "--samples", "-o", "-o"}; /* needs a value */
  for (size_t c = 0; c < sizeof cmds / sizeof cmds[0]; c++) {
    char args[256], want[64];
    snprintf(want, sizeof want, "usage: voussoir %s", cmds[c]);
    for (int h = 0; h < 2; h++) {
      snprintf(args, sizeof args, "%s x.ini %s", cmds[c], h ? "-h" : "--help");
      result r = run(args);
      assert_int_equal(r.status, 0);
      expect_in(r.out, want, args);
      expect_in(r.out, own[c], args);
      drop(&r);
    }
    snprintf(args, sizeof args, "%s x.ini --frob=2", cmds[c]);
    result r = run(args);
    assert_int_equal(r.status, 2);
    expect_in(r.err, "unknown option --frob", args);
    assert_string_equal(r.out, "");
    drop(&r);
    snprintf(args, sizeof args, "%s x.ini %s", cmds[c], valued[c]);
    r = run(args);
    assert_int_equal(r.status, 2);
    snprintf(want, sizeof want, "%s needs a value", valued[c]);
    expect_in(r.err, want, args);
    drop(&r);
  }
}

static void test_version(void **state) {
  (void)state;
  result r = run("--version");
  assert_int_equal(r.status, 0);
  if (strncmp(r.out, "voussoir ", 9) != 0) fail_msg("--version printed \"%s\"", r.out);
  assert_true(strlen(r.out) > 10);
  drop(&r);
}

/* ---------------------------------------------------------------------------------------------
 * Bad input: status 2, the culprit named on stderr, nothing on stdout, no output file */

static void expect_bad_input(const char *args, const char *needle) {
  const path_t pcsv = scratch("bad.csv");
  const char *csv = pcsv.p;
  char full[2048];
  if (snprintf(full, sizeof full, "%s -o '%s'", args, csv) >= (int)sizeof full) fail_msg("args too long");
  remove(csv);
  result r = run(full);
  if (r.status != 2) fail_msg("\"%s\": exit status %d, expected 2", full, r.status);
  expect_in(r.err, needle, full);
  if (r.out[0] != '\0') fail_msg("\"%s\" printed on stdout:\n%s", full, r.out);
  if (exists(csv)) fail_msg("\"%s\" created %s", full, csv);
  drop(&r);
}

static void test_bad_input(void **state) {
  (void)state;
  const path_t pbad = scratch("bad.ini");
  const char *bad = pbad.p;
  FILE *f = fopen(bad, "w");
  assert_non_null(f);
  fputs("[arch]\nradius_mm = 300\n[joints]\nkn_N_mm3 = -3\n", f);
  assert_int_equal(fclose(f), 0);
  char args[512];

  expect_bad_input("frobnicate", "frobnicate");            /* unknown command */
  expect_bad_input("run '" REFERENCE "' --frob", "--frob"); /* unknown option */
  expect_bad_input("run -q", "CASE");                      /* missing case */
  snprintf(args, sizeof args, "run '%s' -q", bad);         /* a case with a bad value */
  expect_bad_input(args, "kn_N_mm3");
  expect_bad_input(args, "bad.ini:4");
  expect_bad_input("run '" REFERENCE "' --set joints.bogus=1 -q", "bogus"); /* unknown key */
  expect_bad_input("run '" REFERENCE "' --set nosuch.kn_N_mm3=1 -q", "nosuch");
  expect_bad_input("run '" REFERENCE "' --alpha abc -q", "alpha_deg");
  expect_bad_input("run '" REFERENCE "' --kn -1 -q", "kn_N_mm3");
  expect_bad_input("run '" REFERENCE "' --set support.right_kind=hinged -q",
                   "support.right_kind = hinged: unknown name (allowed: one of fixed, pinned)");
  expect_bad_input("run '" REFERENCE "' --set support.left_kind=1 -q", "support.left_kind");
  snprintf(args, sizeof args, "run '%s' -q", scratch("missing.ini").p); /* no such file */
  expect_bad_input(args, "missing.ini");

  /* the same refusals with the value after '=' */
  expect_bad_input("run '" REFERENCE "' --alpha=abc -q", "alpha_deg");
  expect_bad_input("run '" REFERENCE "' --kn=-1 -q", "kn_N_mm3");
  expect_bad_input("run '" REFERENCE "' --frob=1 -q", "unknown option --frob");
  expect_bad_input("run '" REFERENCE "' --json=1 -q", "--json takes no value");
  expect_bad_input("run '" REFERENCE "' -qx", "unknown option -x");
  expect_bad_input("run '" REFERENCE "' '" REFERENCE "' -q", "more than one case file");

  /* an option without its value (last, so that it cannot take the -o that follows) */
  result v = run("run '" REFERENCE "' -q --alpha");
  assert_int_equal(v.status, 2);
  expect_in(v.err, "--alpha needs a value", "--alpha without a value");
  drop(&v);
  v = run("run '" REFERENCE "' -q -o");
  assert_int_equal(v.status, 2);
  expect_in(v.err, "-o needs a value", "-o without a value");
  drop(&v);

  /* an output file that cannot be created is reported, naming it */
  const path_t pnowhere = scratch("no/such/dir.csv");
  const char *nowhere = pnowhere.p;
  snprintf(args, sizeof args, "run '%s' -q --json -o '%s'", REFERENCE, nowhere);
  result r = run(args);
  assert_true(r.status != 0);
  expect_in(r.err, nowhere, args);
  drop(&r);
}

/* ---------------------------------------------------------------------------------------------
 * The JSON summary and the CSV history */

static const double DEG = 3.14159265358979323846 / 180.0;

/* Span used to normalise: L = 2 R sin(embrace / 2), mm (R = 300 mm, embrace 125 deg). */
static double span_mm(void) { return 2.0 * 300.0 * sin(62.5 * DEG); }

/* Arch weight, N: rho b g (embrace/2) ((R + t)^2 - R^2), SI. */
static double weight_N(void) {
  const double rho = 1640.0, b = 0.12, g = 9.81, R = 0.3, t = 0.024, phi = 125.0 * DEG;
  return rho * b * g * (phi / 2.0) * ((R + t) * (R + t) - R * R);
}

/* Run the reference case with extra arguments; check the JSON keys and the first limit point
 * against the support direction; return steps. *json receives stdout (caller frees). */
static long check_json_run(const char *extra, double alpha_deg, double kn, char **json) {
  char args[1024];
  /* what is checked is fixed at the collapse: the fall to rest (most of a run) is left out */
  snprintf(args, sizeof args, "run '%s' --json -q --set dynamic.fall_s=0 %s", REFERENCE, extra);
  result r = run(args);
  if (r.status != 0) fail_msg("\"%s\": exit status %d\n%s", args, r.status, r.err);
  span o = one_object(r.out);

  expect_close(number(o, "alpha_deg"), alpha_deg, 0.0, "alpha_deg");
  expect_close(number(o, "kn_N_mm3"), kn, 0.0, "kn_N_mm3");
  expect_close(number(o, "span_mm"), span_mm(), 1e-12, "span_mm");

  span fl = need(o, "first_limit");
  if (*fl.b != '{') fail_msg("\"%s\": no first limit point: %.60s", args, fl.b);
  const double d = number(fl, "delta_mm"), L = span_mm(), a = alpha_deg * DEG;
  assert_true(d > 0.0);
  expect_close(number(fl, "dz_over_L_pct"), 100.0 * d * cos(a) / L, 1e-8, "dz_over_L_pct");
  expect_close(number(fl, "dx_over_L_pct"), 100.0 * d * sin(a) / L, 1e-8, "dx_over_L_pct");

  span hs = need(o, "hinges");
  assert_true(*hs.b == '[');
  enum { MAXH = 64 };
  char label[MAXH];
  int order[MAXH], onset[MAXH], n = 0;
  for (const char *p = hs.b + 1; *p == '{'; n++) {
    const char *e = value_end(p);
    assert_non_null(e);
    assert_true(n < MAXH);
    span h = {p, e};
    span lab = need(h, "label"), side = need(h, "side"), j = need(h, "joints");
    span j0 = need(h, "joints_onset");
    (void)number(h, "delta_onset_mm");
    if (lab.e - lab.b != 3 || !strchr("ABCDEFGHIJKLMNOPQRSTUVWXYZ?", lab.b[1]))
      fail_msg("bad label %.10s", lab.b);
    if (side.e - side.b != 3 || (side.b[1] != 'I' && side.b[1] != 'E'))
      fail_msg("bad side %.10s", side.b);
    if (*j.b != '[' || j.e - j.b < 3) fail_msg("bad joints %.20s", j.b);
    if (*j0.b != '[' || j0.e - j0.b < 3) fail_msg("bad joints_onset %.20s", j0.b);
    label[n] = lab.b[1];
    order[n] = (int)number(h, "order");
    onset[n] = atoi(j0.b + 1);
    p = (*e == ',') ? e + 1 : e;
  }
  assert_true(hs.e[-1] == ']');
  /* docs/model.md#vocabulary labels: '?' until three exist; then the first three A, B, C from left
   * to right (by the joint where each formed), the 4th D, the 5th E in order of appearance */
  for (int i = 0; i < n; i++) {
    char want = '?';
    if (n >= 3 && order[i] > 3) want = (char)('A' + order[i] - 1);
    if (n >= 3 && order[i] <= 3) {
      want = 'A';
      for (int k = 0; k < n; k++) want = (char)(want + (order[k] <= 3 && onset[k] < onset[i]));
    }
    if (label[i] != want)
      fail_msg("\"%s\": hinge of order %d (onset joint %d) labelled %c, expected %c", args,
               order[i], onset[i], label[i], want);
  }
  assert_true(n >= 1);

  span st = need(o, "stats");
  const double steps = number(st, "steps") + number(st, "located_equilibria");
  assert_true(number(st, "newton_iterations") >= steps);
  assert_true(number(st, "wall_s") >= 0.0);
  assert_true(steps >= 2.0);
  *json = r.out;
  free(r.err);
  return (long)steps;
}

/* Numeric field col of a CSV line. */
static double field(const char *line, int col) {
  for (int c = 0; c < col; c++) {
    line = strchr(line, ',');
    assert_non_null(line);
    line++;
  }
  return strtod(line, NULL);
}

static int column(const char *header, const char *name) {
  int c = 0;
  const size_t n = strlen(name);
  for (const char *p = header;; c++) {
    if (strncmp(p, name, n) == 0 && (p[n] == ',' || p[n] == '\n' || p[n] == '\0')) return c;
    p = strchr(p, ',');
    if (p == NULL || p > strchr(header, '\n')) fail_msg("CSV header lacks %s: %s", name, header);
    p++;
  }
}

static void test_reference_json_csv(void **state) {
  (void)state;
  const path_t pcsv = scratch("path.csv");
  const char *csv = pcsv.p;
  char extra[512], *json = NULL;
  snprintf(extra, sizeof extra, "--csv '%s' --no-record", csv);
  const long steps = check_json_run(extra, 0.0, 3.0, &json);
  span fl = need(one_object(json), "first_limit");
  expect_close(number(fl, "dx_over_L_pct"), 0.0, 0.0, "dx_over_L_pct at alpha 0");
  free(json);

  char *text = slurp(csv);
  assert_non_null(text);
  if (strncmp(text, "phase,time_s,delta_mm", 21) != 0) fail_msg("CSV header: %.80s", text);
  const int cd = column(text, "delta_mm"), cl = column(text, "left_Fz_N"),
            cr = column(text, "right_Fz_N"), ct = column(text, "time_s");
  long qs_rows = 0;
  int ncol = 1;
  for (const char *p = text; *p != '\n'; p++) ncol += *p == ',';
  long rows = 0;
  double last = -INFINITY;
  for (char *line = strchr(text, '\n') + 1; *line; rows++) {
    char *nl = strchr(line, '\n');
    assert_non_null(nl);
    int commas = 0, quoted = 0;
    for (const char *p = line; p < nl; p++) {
      if (*p == '"') quoted = !quoted;
      commas += (*p == ',' && !quoted);
    }
    if (commas + 1 != ncol) fail_msg("CSV row %ld has %d fields, header %d", rows + 1, commas + 1, ncol);
    const double d = field(line, cd);
    if (!(d >= last)) fail_msg("CSV row %ld: delta %g after %g", rows + 1, d, last);
    qs_rows += strncmp(line, "quasistatic,", 12) == 0;
    if (strncmp(line, "quasistatic,", 12) != 0 && strncmp(line, "dynamic,", 8) != 0)
      fail_msg("CSV row %ld: phase %.12s", rows + 1, line);
    /* loading time is support displacement over the rate, 0.04 mm/s in the reference case */
    expect_close(field(line, ct), d / 0.04, 1e-9, "time_s = delta_mm / rate");
    if (rows == 0) {
      assert_true(d == 0.0);
      /* self-weight only: the supports carry the whole arch (forces they exert on it) */
      expect_close(field(line, cl) + field(line, cr), weight_N(), 1e-6, "left + right Fz at 0");
    }
    last = d;
    line = nl + 1;
  }
  assert_int_equal(qs_rows, steps);
  assert_true(rows > qs_rows); /* the run goes on dynamically past the limit points */
  free(text);
}

/* The run to collapse: the collapse object, the limit points and their kinds, the mode and the
 * energy balance, with relations that hold independently of the numbers: time = delta / rate,
 * the collapse after (or at) the last limit point, which is the one marked "collapse". */
static void test_collapse_json(void **state) {
  (void)state;
  char *json = NULL;
  check_json_run("", 0.0, 3.0, &json);
  span o = one_object(json);
  span col = need(o, "collapse");
  if (*col.b != '{') fail_msg("collapse is %.10s", col.b);
  const double du = number(col, "delta_mm"), L = span_mm();
  assert_true(du > 0.0);
  expect_close(number(col, "dz_over_L_pct"), 100.0 * du / L, 1e-8, "collapse dz_over_L_pct");
  expect_close(number(col, "dx_over_L_pct"), 0.0, 0.0, "collapse dx_over_L_pct");
  expect_close(number(col, "time_s"), du / 0.04, 1e-8, "collapse time_s = delta / rate");
  /* the departure precedes the detection; the dynamic phase was a DAE of index 2 with the
   * supports' 6 reactions and 6 velocity-constraint multipliers as algebraic unknowns */
  assert_true(number(col, "delta_detected_mm") > du);
  span dae = need(need(o, "stats"), "dae");
  expect_close(number(dae, "index"), 2.0, 0.0, "stats.dae.index");
  expect_close(number(dae, "algebraic"), 12.0, 0.0, "stats.dae.algebraic");
  assert_true(number(dae, "differential") > 12.0);
  span ch = need(col, "hinges");
  assert_true(*ch.b == '[');
  int nh = 0;
  for (const char *p = ch.b + 1; *p == '{';) {
    const char *e = value_end(p);
    span h = {p, e};
    (void)need(h, "label");
    (void)need(h, "joints");
    (void)need(h, "side");
    expect_close(number(h, "time_onset_s"), number(h, "delta_onset_mm") / 0.04, 1e-8,
                 "hinge time_onset_s = delta / rate");
    nh++;
    p = (*e == ',') ? e + 1 : e;
  }
  if (nh < 4) fail_msg("%d hinges at collapse: a mechanism needs at least four", nh);
  span lp = need(o, "limit_points");
  assert_true(*lp.b == '[');
  double last_delta = -1.0;
  int n = 0, last_is_collapse = 0;
  for (const char *p = lp.b + 1; *p == '{';) {
    const char *e = value_end(p);
    span l = {p, e};
    last_delta = number(l, "delta_mm");
    span kind = need(l, "kind");
    last_is_collapse = strncmp(kind.b, "\"collapse\"", 10) == 0;
    if (!last_is_collapse && strncmp(kind.b, "\"snap\"", 6) != 0) fail_msg("kind %.12s", kind.b);
    n++;
    p = (*e == ',') ? e + 1 : e;
  }
  assert_true(n >= 1);
  assert_true(last_is_collapse);
  assert_true(du >= last_delta);
  span mode = need(o, "mode");
  assert_true(*mode.b == '"' || strncmp(mode.b, "null", 4) == 0);
  const double bal = number(need(o, "energy"), "balance_error_rel");
  assert_true(bal >= 0.0 && bal < 1e-3);
  free(json);
}

static void test_alpha_kn_override(void **state) {
  (void)state;
  char *json = NULL;
  /* the case says alpha = 0, k_n = 3: the options win */
  check_json_run("--alpha 30", 30.0, 3.0, &json);
  span fl = need(one_object(json), "first_limit");
  assert_true(number(fl, "dx_over_L_pct") > 0.0);
  free(json);
  check_json_run("--kn 10", 0.0, 10.0, &json);
  free(json);
  check_json_run("--set support.alpha_deg=15 --alpha 30 --kn 10", 30.0, 10.0, &json);
  free(json);
  /* a value after '=' is the same value: the same first limit point, to the last digit */
  char *spaced = NULL, *joined = NULL;
  check_json_run("--first-limit --alpha 30 --kn 10 --set support.rate_mm_s=0.04", 30.0, 10.0,
                 &spaced);
  check_json_run("--first-limit --alpha=30 --kn=10 --set=support.rate_mm_s=0.04", 30.0, 10.0,
                 &joined);
  const span a = need(need(one_object(spaced), "first_limit"), "delta_mm");
  const span b = need(need(one_object(joined), "first_limit"), "delta_mm");
  if (a.e - a.b != b.e - b.b || strncmp(a.b, b.b, (size_t)(a.e - a.b)) != 0)
    fail_msg("first limit %.*s mm with --alpha 30, %.*s mm with --alpha=30", (int)(a.e - a.b), a.b,
             (int)(b.e - b.b), b.b);
  free(spaced);
  free(joined);
}

/* Input that used to be accepted silently (exit 0, part of it ignored) or to reach the JSON as
 * inf, now refused at the command line: exit 2, the culprit named, nothing on stdout or disk. */
static void test_strict_input(void **state) {
  (void)state;
  char args[1536], value[700] = "0.";
  memset(value + 2, '0', 600); /* past the old 512-byte buffer */
  strcpy(value + 602, "1x");
  snprintf(args, sizeof args, "run '%s' -q --set support.alpha_deg=%s", REFERENCE, value);
  expect_bad_input(args, "unexpected characters after the number");
  snprintf(args, sizeof args, "run '%s' -q --alpha %s", REFERENCE, value);
  expect_bad_input(args, "unexpected characters after the number");
  snprintf(args, sizeof args, "run '%s' -q --kn 3%s", REFERENCE, value + 1);
  expect_bad_input(args, "joints.kn_N_mm3");
  expect_bad_input("run '" REFERENCE "' -q --alpha 0x10", "hexadecimal");
  /* radius 1e308: "span_mm":inf in the JSON before; refused with the allowed range now */
  expect_bad_input("run '" REFERENCE "' -q --json --set arch.radius_mm=1e308",
                   "arch.radius_mm = 1e308: out of range (allowed: [0.001, 1e+06] mm)");

  /* a key on the section line */
  const path_t pk = scratch("keyline.ini");
  FILE *f = fopen(pk.p, "w");
  assert_non_null(f);
  fputs("[arch] radius_mm = 250\n", f);
  assert_int_equal(fclose(f), 0);
  snprintf(args, sizeof args, "run '%s' -q", pk.p);
  expect_bad_input(args, "after the section header");

  /* a FIFO as the case (a stand-in for a device): refused at once, not read */
  const path_t pf = scratch("fifo.ini");
  assert_int_equal(mkfifo(pf.p, 0600), 0);
  snprintf(args, sizeof args, "timeout 60 '%s' run '%s' -q", VS_BINARY, pf.p);
  int w = system(args); /* through timeout: a reader that blocks fails instead of hanging */
  assert_true(WIFEXITED(w) && WEXITSTATUS(w) == 2);
  snprintf(args, sizeof args, "run '%s' -q", pf.p);
  expect_bad_input(args, "not a regular file");
  remove(pf.p);

  /* a case file over the limit (a 100 MB comment was copied into the record before) */
  const path_t pb = scratch("big.ini");
  f = fopen(pb.p, "w");
  assert_non_null(f);
  fputs("[arch]\n", f);
  for (int i = 0; i < (1 << 20) / 64 + 1; i++) fprintf(f, ";%062d\n", i);
  assert_int_equal(fclose(f), 0);
  snprintf(args, sizeof args, "run '%s' -q", pb.p);
  expect_bad_input(args, "too large (a case file is at most 1048576 bytes)");
  remove(pb.p);
}

/* Mortar keys out of range: refused by name (exit 2, nothing written); the softening's bounds
 * G_f > f_t^2 / (2 k_n) and G_c > c^2 / (2 k_s) named likewise. */
static void test_mortar_refused(void **state) {
  (void)state;
  expect_bad_input("run '" REFERENCE "' -q --set joints.cohesion_MPa=0.2",
                   "joints.gc_N_mm = 0: with joints.cohesion_MPa = 0.2 must be >");
  expect_bad_input("run '" REFERENCE "' -q --set joints.tensile_MPa=1",
                   "joints.gf_N_mm = 0: with joints.tensile_MPa = 1 must be >");
  expect_bad_input("run '" REFERENCE "' -q --set joints.tensile_MPa=-1",
                   "joints.tensile_MPa = -1: out of range (allowed: [0, 100] MPa)");
  expect_bad_input("run '" REFERENCE "' -q --set joints.gf_N_mm=1001",
                   "joints.gf_N_mm = 1001: out of range (allowed: [0, 1000] N/mm)");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_mortar_refused),
      cmocka_unit_test(test_help),
      cmocka_unit_test(test_version),
      cmocka_unit_test(test_command_help),
      cmocka_unit_test(test_bad_input),
      cmocka_unit_test(test_reference_json_csv),
      cmocka_unit_test(test_alpha_kn_override),
      cmocka_unit_test(test_collapse_json),
      cmocka_unit_test(test_strict_input),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
