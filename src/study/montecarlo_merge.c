/* The merge command's work (its command line is read by src/cli/cli_montecarlo.c): the shards'
 * tables (voussoir montecarlo --shard K/M) joined into one summary. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "study.h"
#include "journal.h"
#include "montecarlo_cmd.h"
#include "plugin.h"
#include "voussoir/montecarlo.h"
#include "parse.h"
#include "voussoir/plot.h"
#include "quote.h"

enum { EXIT_FAIL = VS_EXIT_FAILED, EXIT_USAGE = VS_EXIT_BAD_INPUT };

/* A shard's table, as montecarlo.c writes it: line 1 "# voussoir montecarlo" and the case keys
 * its summary needs as NAME=VALUE (HEADER), line 2 the column names (VS_MC_TABLE_COLUMNS), then
 * one row per sample. Nothing in it is trusted: every field is checked as the case file's line
 * would be, and a problem is reported as "FILE:LINE: field = value: reason (allowed: ...)".
 * The fields marked optional came later (the span of any shape, both supports' motion): a table
 * written before them lacks them, and its summary is that of the circular arch and the right
 * support alone, as then. L_mm, the span the ratios are of, becomes the case's arch.span_mm
 * (the case here only writes the summary). */
#define TABLE_MAGIC "# voussoir montecarlo "
static const struct {
  const char *field, *section, *key; /* key: the case key section.key (NULL: field) */
  int optional;
} HEADER[] = {{"seed", "imperfections", NULL, 0},  {"radius_mm", "arch", NULL, 0},
              {"embrace_deg", "arch", NULL, 0},    {"max_mm", "support", NULL, 0},
              {"alpha_deg", "support", NULL, 0},   {"voussoirs", "arch", NULL, 0},
              {"L_mm", "arch", "span_mm", 1},      {"rate_mm_s", "support", NULL, 1},
              {"left_alpha_deg", "support", NULL, 1}, {"left_rate_mm_s", "support", NULL, 1},
              {"left_path", "support", NULL, 1},   {"right_path", "support", NULL, 1}};
enum { N_HEADER = sizeof HEADER / sizeof HEADER[0], N_OLD_COLUMNS = 8 + VS_MC_LABELS + 1,
       N_COLUMNS = N_OLD_COLUMNS + 5, N_CRACK_COLUMNS = N_COLUMNS + 3, H_SPAN = 6 };
#define HEADER_LIST                                                                              \
  "seed, radius_mm, embrace_deg, max_mm, alpha_deg, voussoirs; optional: L_mm, rate_mm_s, "     \
  "left_alpha_deg, left_rate_mm_s, left_path, right_path"
/* The columns of a table of 0.3.0 and before (no supports' travel, no load_factor): still read,
 * the travel from the header's motion, load_factor NaN. */
#define OLD_COLUMNS "sample,status,first_limit_mm,delta_u_mm,dz_u_mm,dx_u_mm,mode,pattern,A,B,C,D,E,error"

/* The first shard's header, which every other shard's must equal. */
typedef struct {
  char path[1100];
  vs_case c;
  int have;
} shard_head;

static const char *header_key(int i) { return HEADER[i].key ? HEADER[i].key : HEADER[i].field; }

/* The value of header field i in c (the case key it names), into text (a path's text, or the
 * number's); NAN for a text key. */
static double header_value(const vs_case *c, int i, char *text, size_t size) {
  const char *sec = NULL, *key = NULL;
  double v = NAN;
  text[0] = '\0';
  for (int k = 0; vs_case_key(c, k, &sec, &key, NULL, NULL, &v) == 0; k++)
    if (strcmp(sec, HEADER[i].section) == 0 && strcmp(key, header_key(i)) == 0) {
      snprintf(text, size, "%.17g", v);
      return v;
    }
  for (int k = 0; vs_case_text_key(c, k, &sec, &key, text, size) == 0; k++)
    if (strcmp(sec, HEADER[i].section) == 0 && strcmp(key, header_key(i)) == 0) return NAN;
  text[0] = '\0';
  return NAN;
}

/* Line 1 of path (line, its newline gone) into c over the defaults: every field of HEADER
 * exactly once (an optional one at most once), each value parsed and range-checked by the
 * case's own assignment, and the case they make validated as a case file is. */
static vs_status parse_header(const char *where, char *line, vs_case *c, vs_error *err) {
  vs_case_defaults(c);
  if (strncmp(line, TABLE_MAGIC, strlen(TABLE_MAGIC)) != 0)
    return vs_error_set(err, VS_ERR_PARSE, "%s: not a montecarlo table (line 1 must start with "
                        "\"%s\")", where, TABLE_MAGIC);
  int seen[N_HEADER] = {0};
  char *save = NULL, *span = NULL;
  for (char *tok = strtok_r(line + strlen(TABLE_MAGIC), " ", &save); tok != NULL;
       tok = strtok_r(NULL, " ", &save)) {
    char *eq = strchr(tok, '=');
    int i = 0;
    if (eq != NULL) *eq = '\0';
    while (eq != NULL && i < N_HEADER && strcmp(HEADER[i].field, tok) != 0) i++;
    if (eq == NULL || i == N_HEADER)
      return vs_error_set(err, VS_ERR_PARSE, "%s: header field '%.64s': unknown (expected "
                          "NAME=VALUE for each of %s)", where, tok, HEADER_LIST);
    if (seen[i]++)
      return vs_error_set(err, VS_ERR_PARSE, "%s: header field %s given twice", where, tok);
    if (i == H_SPAN) { /* assigned below, once the case is validated */
      span = eq + 1;
      continue;
    }
    const vs_status st = vs_case_assign(c, HEADER[i].section, tok, eq + 1, where, err);
    if (st != VS_OK) return st;
  }
  for (int i = 0; i < N_HEADER; i++)
    if (!seen[i] && !HEADER[i].optional)
      return vs_error_set(err, VS_ERR_PARSE, "%s: header field %s missing (expected NAME=VALUE "
                          "for each of %s)", where, HEADER[i].field, HEADER_LIST);
  /* and the relations between keys, as for a case file (support.max_mm > solver.step_mm) */
  vs_error why;
  if (vs_case_validate(c, &why) != VS_OK)
    return vs_error_set(err, VS_ERR_INVALID, "%s: %s", where, why.msg);
  double L = 0.0;
  if (span != NULL && (vs_parse_double(span, &L) != VS_NUM_OK || !isfinite(L) || L <= 0.0))
    return vs_error_set(err, VS_ERR_PARSE, "%s: header field L_mm = '%.64s': not a span (allowed: "
                        "a finite number > 0, mm)", where, span);
  /* the span the summary's ratios are of (none: the circle's, as before); the case stays one
   * that validates, a circle of that span (its rise, any the span allows, is not used) */
  if (L > 0.0) {
    c->span_mm = L;
    c->rise_mm = 0.5 * L;
    if (vs_case_validate(c, &why) != VS_OK)
      return vs_error_set(err, VS_ERR_INVALID, "%s: header field L_mm: %s", where, why.msg);
  }
  return VS_OK;
}

/* The shards of one study share its case and seed: c (of where) equal to the first's. */
static vs_status same_header(const char *where, const vs_case *c, const shard_head *first,
                             vs_error *err) {
  for (int i = 0; i < N_HEADER; i++) {
    char ta[1024], tb[1024];
    const double a = header_value(c, i, ta, sizeof ta), b = header_value(&first->c, i, tb, sizeof tb);
    if (a != b && strcmp(ta, tb) != 0)
      return vs_error_set(err, VS_ERR_INVALID, "%s: %s=%s, but %s:1 has %s=%s (the shards "
                          "of one study share its case and seed)", where, HEADER[i].field, ta,
                          first->path, HEADER[i].field, tb);
  }
  return VS_OK;
}

/* A number of the table: a decimal (parse.h) or "nan" (none). */
static int table_number(const char *s, double *out) {
  if (strcmp(s, "nan") == 0) {
    *out = NAN;
    return 0;
  }
  return vs_parse_double(s, out) == VS_NUM_OK ? 0 : -1;
}

/* A hinge column: empty, or JOINT-SIDE with 1 <= JOINT <= n_joints and SIDE I or E. */
static int table_hinge(const char *s, int n_joints, int *joint, char *side) {
  *joint = 0;
  *side = 0;
  if (*s == '\0') return 0;
  const char *dash = strchr(s, '-');
  char num[16];
  long j = 0;
  if (dash == NULL || dash == s || (size_t)(dash - s) >= sizeof num) return -1;
  snprintf(num, sizeof num, "%.*s", (int)(dash - s), s);
  if (vs_parse_long(num, &j) != VS_NUM_OK || j < 1 || j > n_joints) return -1;
  if ((dash[1] != 'I' && dash[1] != 'E') || dash[2] != '\0') return -1;
  *joint = (int)j;
  *side = dash[1];
  return 0;
}

/* Split line in place at commas into n fields, the last taking the rest; the count found. */
static int split_csv(char *line, char **f, int n) {
  int k = 0;
  f[k++] = line;
  for (char *p = line; *p && k < n; p++)
    if (*p == ',') {
      *p = '\0';
      f[k++] = p + 1;
    }
  return k;
}

/* One row (where: "FILE:LINE") into x, every field checked; the error text is kept quoted. */
static vs_status parse_row(const char *where, char *line, int n_joints, int ncol,
                           vs_mc_sample *x, vs_error *err) {
  static const char *const COL[N_CRACK_COLUMNS] = {
      "sample", "status", "first_limit_mm", "delta_u_mm", "dz_u_mm", "dx_u_mm", "mode",
      "pattern", "A", "B", "C", "D", "E", "error", "left_dx_mm", "left_dz_mm", "right_dx_mm",
      "right_dz_mm", "load_factor", "first_crack_mm", "first_crack_joint", "first_crack_side"};
  char *f[N_CRACK_COLUMNS];
  memset(x, 0, sizeof *x);
  if (split_csv(line, f, ncol) != ncol)
    return vs_error_set(err, VS_ERR_PARSE, "%s: %d columns expected (%s)", where, ncol,
                        ncol == N_CRACK_COLUMNS ? VS_MC_TABLE_COLUMNS VS_MC_CRACK_COLUMNS
                        : ncol == N_COLUMNS     ? VS_MC_TABLE_COLUMNS
                                                : OLD_COLUMNS);
  long smp = -1, mode = -1;
  double num[4];
  int bad = -1; /* the column refused, and why */
  const char *why = NULL;
  if (vs_parse_long(f[0], &smp) != VS_NUM_OK || smp < 0 || smp > INT_MAX)
    bad = 0, why = "an integer in [0, 2147483647]";
  x->status = strcmp(f[1], "collapse") == 0           ? VS_MC_COLLAPSE
              : strcmp(f[1], "max_displacement") == 0 ? VS_MC_NO_COLLAPSE
              : strcmp(f[1], "failed") == 0           ? VS_MC_FAILED
                                                      : -1;
  if (bad < 0 && x->status < 0) bad = 1, why = "collapse, max_displacement or failed";
  for (int i = 0; bad < 0 && i < 4; i++)
    if (table_number(f[2 + i], &num[i]) != 0) bad = 2 + i, why = "a finite number, or nan";
  if (bad < 0 && (vs_parse_long(f[6], &mode) != VS_NUM_OK || mode < 0 || mode > 3))
    bad = 6, why = "an integer in [0, 3]";
  if (bad < 0 && (strlen(f[7]) >= sizeof x->pattern || strspn(f[7], "IE-") != strlen(f[7])))
    bad = 7, why = "sides I, E joined by '-', at most 15 characters";
  for (int l = 0; bad < 0 && l < VS_MC_LABELS; l++)
    if (table_hinge(f[8 + l], n_joints, &x->hinge_joint[l], &x->hinge_side[l]) != 0)
      bad = 8 + l, why = "empty, or JOINT-I or JOINT-E with JOINT a joint of the arch";
  if (bad < 0 && x->status == VS_MC_COLLAPSE && !isfinite(num[1]))
    bad = 3, why = "a collapse's displacement, a finite number";
  /* the writer turns a comma or a quote of the cause into ';': a table with one has more
   * columns than montecarlo writes */
  if (bad < 0 && strpbrk(f[13], ",\"") != NULL)
    bad = 13, why = "a cause without a comma or a quote (montecarlo writes them as ';')";
  /* the supports' travel: checked, then written again from the header's motion */
  for (int k = N_OLD_COLUMNS; bad < 0 && k < ncol && k < N_OLD_COLUMNS + 4; k++) {
    double t;
    if (table_number(f[k], &t) != 0 || (x->status == VS_MC_COLLAPSE) != !isnan(t))
      bad = k, why = "a finite number for a collapse, nan otherwise";
  }
  double lf = NAN;
  if (bad < 0 && ncol >= N_COLUMNS && (table_number(f[N_COLUMNS - 1], &lf) != 0 || lf < 0.0))
    bad = N_COLUMNS - 1, why = "a finite number >= 0, or nan (a comma in a cause shifts it here: "
                              "montecarlo writes a cause's commas as ';')";
  /* a mortared study's first crack: none (nan, 0, empty) or a crack (>= 0 mm, a joint, I or E) */
  double fc = NAN;
  long fj = 0;
  const int crack = ncol == N_CRACK_COLUMNS;
  const char *fs = crack ? f[N_COLUMNS + 2] : "";
  if (bad < 0 && crack && (table_number(f[N_COLUMNS], &fc) != 0 || fc < 0.0))
    bad = N_COLUMNS, why = "a finite number >= 0, or nan";
  if (bad < 0 && crack &&
      (vs_parse_long(f[N_COLUMNS + 1], &fj) != VS_NUM_OK || fj < 0 || fj > n_joints ||
       (fj == 0) != isnan(fc)))
    bad = N_COLUMNS + 1, why = "a joint of the arch with a crack's displacement, 0 without";
  if (bad < 0 && crack && (fj == 0 ? *fs != '\0' : strcmp(fs, "I") != 0 && strcmp(fs, "E") != 0))
    bad = N_COLUMNS + 2, why = "I or E with a crack's joint, empty without";
  if (bad >= 0)
    return vs_error_set(err, VS_ERR_PARSE, "%s: %s = '%.64s': not %s", where, COL[bad], f[bad],
                        why);
  x->mortared = crack;
  x->first_crack_mm = fc;
  x->first_crack_joint = (int)fj;
  x->first_crack_side = *fs;
  x->sample = (int)smp;
  x->mode = (int)mode;
  x->first_limit_mm = num[0];
  x->delta_u_mm = num[1];
  x->dz_u_mm = num[2];
  x->dx_u_mm = num[3];
  x->load_factor = lf;
  snprintf(x->pattern, sizeof x->pattern, "%s", f[7]);
  vs_quote(f[13], x->error, sizeof x->error); /* shown and written again: no control byte */
  return VS_OK;
}

/* The next line of f into buf (its newline gone): 1, 0 at the end, -1 when it does not fit. */
static int next_line(FILE *f, char *buf, int size) {
  if (fgets(buf, size, f) == NULL) return 0;
  const size_t n = strlen(buf);
  if (n > 0 && buf[n - 1] == '\n') buf[n - 1] = '\0';
  else if (!feof(f)) return -1;
  buf[strcspn(buf, "\r")] = '\0';
  return 1;
}

/* DIR/samples.csv opened for reading into *f (its path in path): only a regular file (a FIFO
 * would block the merge, a device feed it without end), opened without blocking and checked on
 * the open descriptor; a path that does not fit is refused, not cut. */
static vs_status open_table(const char *dir, char *path, size_t size, FILE **f, vs_error *err) {
  const int n = snprintf(path, size, "%s/samples.csv", dir);
  if (n < 0 || (size_t)n >= size)
    return vs_error_set(err, VS_ERR_INVALID, "%s: directory name too long (at most %zu bytes)",
                        dir, size - sizeof "/samples.csv");
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  struct stat sb;
  if (fd < 0) return vs_error_set(err, VS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode) || (*f = fdopen(fd, "r")) == NULL) {
    close(fd);
    return vs_error_set(err, VS_ERR_INVALID, "%s: not a regular file", path);
  }
  return VS_OK;
}

/* Append *all with the samples of DIR/samples.csv, its header checked (and, past the first
 * shard, equal to the first's). VS_OK or the first problem in err. */
static vs_status read_shard(const char *dir, shard_head *first, vs_mc_sample **all, int *n,
                            int *cap, vs_error *err) {
  char path[1100], where[1200], line[2048];
  FILE *f = NULL;
  if (open_table(dir, path, sizeof path, &f, err) != VS_OK) return err->status;
  vs_case c;
  vs_status st = VS_OK;
  int lineno = 1, got = next_line(f, line, sizeof line);
  snprintf(where, sizeof where, "%s:%d", path, lineno);
  if (got <= 0) st = vs_error_set(err, VS_ERR_PARSE, "%s: not a montecarlo table (%s)", where,
                                  got == 0 ? "empty" : "line 1 too long");
  if (st == VS_OK) st = parse_header(where, line, &c, err);
  if (st == VS_OK && first->have) st = same_header(where, &c, first, err);
  if (st == VS_OK && !first->have) {
    snprintf(first->path, sizeof first->path, "%s", path);
    first->c = c;
    first->have = 1;
  }
  int ncol = 0;
  if (st == VS_OK && next_line(f, line, sizeof line) == 1)
    ncol = strcmp(line, VS_MC_TABLE_COLUMNS) == 0                       ? N_COLUMNS
           : strcmp(line, VS_MC_TABLE_COLUMNS VS_MC_CRACK_COLUMNS) == 0 ? N_CRACK_COLUMNS
           : strcmp(line, OLD_COLUMNS) == 0                             ? N_OLD_COLUMNS
                                                                        : 0;
  if (st == VS_OK && ncol == 0)
    st = vs_error_set(err, VS_ERR_PARSE, "%s:2: not the columns of a montecarlo table (%s)", path,
                      VS_MC_TABLE_COLUMNS);
  lineno = 2;
  while (st == VS_OK && (got = next_line(f, line, sizeof line)) != 0) {
    snprintf(where, sizeof where, "%s:%d", path, ++lineno);
    if (got < 0) {
      st = vs_error_set(err, VS_ERR_PARSE, "%s: line too long (at most %d bytes)", where,
                        (int)sizeof line - 2);
      break;
    }
    if (*n == *cap) {
      const int nc = *cap == 0 ? 256 : *cap <= INT_MAX / 2 ? 2 * *cap : INT_MAX;
      vs_mc_sample *b = *n < INT_MAX ? realloc(*all, (size_t)nc * sizeof *b) : NULL;
      if (b == NULL) {
        st = vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory holding %d samples (%zu MiB; "
                          "%d more would not fit)", where, *n,
                          (size_t)*n * sizeof *b >> 20, nc - *n);
        break;
      }
      *all = b;
      *cap = nc;
    }
    st = parse_row(where, line, c.voussoirs + 1, ncol, &(*all)[*n], err);
    if (st == VS_OK) (*n)++;
  }
  fclose(f);
  return st;
}

static int cmp_sample_no(const void *x, const void *y) {
  const int a = ((const vs_mc_sample *)x)->sample, b = ((const vs_mc_sample *)y)->sample;
  return (a > b) - (a < b);
}

int vs_merge_main(const char *const *dirs, int nd, const char *out) {
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir merge") != 0) return EXIT_FAIL;
  shard_head first = {.have = 0};
  vs_mc_sample *all = NULL;
  int n = 0, cap = 0, rc = EXIT_USAGE;
  vs_outlock *lock = NULL;
  /* the shards' tables are inputs: never replaced by the merged one */
  char (*tables)[1100] = malloc((size_t)(nd > 0 ? nd : 1) * sizeof *tables);
  vs_outpath_other *others = malloc((size_t)(nd > 0 ? nd : 1) * sizeof *others);
  if (tables == NULL || others == NULL) {
    fprintf(stderr, "voussoir merge: out of memory\n");
    rc = EXIT_FAIL;
    goto done;
  }
  for (int d = 0; d < nd; d++) {
    snprintf(tables[d], sizeof tables[d], "%s/samples.csv", dirs[d]);
    others[d] = (vs_outpath_other){tables[d], "an input shard's table"};
  }
  if (vs_mc_check_outputs("merge", out, others, nd, 0) != 0) goto done;
  vs_error err;
  vs_error_clear(&err);
  for (int d = 0; d < nd; d++)
    if (read_shard(dirs[d], &first, &all, &n, &cap, &err) != VS_OK) {
      fprintf(stderr, "voussoir merge: %s\n", err.msg);
      if (err.status == VS_ERR_NOMEM) rc = EXIT_FAIL;
      goto done;
    }
  if (n == 0) { /* (and no qsort of a NULL array) */
    fprintf(stderr, "voussoir merge: no samples in the shards' tables\n");
    goto done;
  }
  qsort(all, (size_t)n, sizeof *all, cmp_sample_no);
  for (int i = 1; i < n; i++)
    if (all[i].sample == all[i - 1].sample) {
      fprintf(stderr, "voussoir merge: sample %d appears twice\n", all[i].sample);
      goto done;
    }
  /* DIR is a study's: locked as sweep and montecarlo lock theirs, so that a merge into the
   * directory of a study under way (or of another merge) is refused */
  if (mkdir(out, 0755) != 0 && errno != EEXIST) {
    fprintf(stderr, "voussoir merge: -o %s: cannot create: %s\n", out, strerror(errno));
    goto done;
  }
  if (vs_study_lock(out, "voussoir merge", &lock, &err) != VS_OK) {
    fprintf(stderr, "voussoir merge: %s\n", err.msg);
    goto done;
  }
  rc = EXIT_FAIL;
  if (vs_mc_write_summary(out, &first.c, all, n, &err) != VS_OK) {
    fprintf(stderr, "voussoir merge: %s\n", err.msg);
    goto done;
  }
  printf("%d samples from %d directories; summary: %s/summary.h5\n", n, nd, out);
  rc = 0;
done:
  vs_outlock_release(&lock);
  free(all);
  free(tables);
  free(others);
  vs_plot_release();
  return rc;
}
