/* The merge command's work (its command line is read by src/cli_montecarlo.c): the shards'
 * tables (voussoir montecarlo --shard K/M) joined into one summary. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "montecarlo_cmd.h"
#include "plugin.h"
#include "voussoir/montecarlo.h"
#include "voussoir/parse.h"
#include "voussoir/plot.h"

enum { EXIT_FAIL = VS_EXIT_FAILED, EXIT_USAGE = VS_EXIT_BAD_INPUT };

/* Split line in place at commas into at most max fields; returns the count. */
static int split_csv(char *line, char **f, int max) {
  int n = 0;
  f[n++] = line;
  for (char *p = line; *p && n < max; p++)
    if (*p == ',') {
      *p = '\0';
      f[n++] = p + 1;
    }
  return n;
}

/* A number of the table as montecarlo writes it (%.17g): finite, or "nan" for a missing value
 * (which the strict parser refuses); 0 or -1. */
static int table_number(const char *s, double *v) {
  if (strcmp(s, "nan") == 0) {
    *v = NAN;
    return 0;
  }
  char *end;
  if (s[0] == '\0' || strspn(s, "0123456789+-.eE") != strlen(s)) return -1; /* no hex, inf */
  *v = strtod(s, &end);
  return *end == '\0' && isfinite(*v) ? 0 : -1;
}

/* A hinge column: empty (none), or "J-S" with J a joint number >= 1 and S 'I' or 'E'. */
static int table_hinge(const char *s, int *joint, char *side) {
  *joint = 0, *side = 0;
  if (s[0] == '\0') return 0;
  char num[16];
  const size_t k = strcspn(s, "-");
  long j;
  if (k == 0 || k >= sizeof num || (s[k + 1] != 'I' && s[k + 1] != 'E') || s[k + 2] != '\0')
    return -1;
  memcpy(num, s, k);
  num[k] = '\0';
  if (vs_parse_long(num, &j) != VS_NUM_OK || j < 1 || j > INT_MAX) return -1;
  *joint = (int)j, *side = s[k + 1];
  return 0;
}

/* One row of a table into x, each column checked against what montecarlo writes: NULL, or what
 * is wrong (the column and what it allows). A table that is not montecarlo's is refused, rather
 * than summarised as if it were. */
static const char *parse_row(char *line, vs_mc_sample *x) {
  char *f[14];
  line[strcspn(line, "\r\n")] = '\0';
  if (split_csv(line, f, 14) != 14) return "not 14 columns";
  memset(x, 0, sizeof *x);
  long smp = -1, mode = 0;
  if (vs_parse_long(f[0], &smp) != VS_NUM_OK || smp < 0 || smp > INT_MAX)
    return "sample: not an integer in [0, 2147483647]";
  x->sample = (int)smp;
  if (strcmp(f[1], "collapse") == 0) x->status = VS_MC_COLLAPSE;
  else if (strcmp(f[1], "max_displacement") == 0) x->status = VS_MC_NO_COLLAPSE;
  else if (strcmp(f[1], "failed") == 0) x->status = VS_MC_FAILED;
  else return "status: not collapse, max_displacement or failed";
  static const char *const NUMBER[4] = {"first_limit_mm: not a finite number or nan",
                                         "delta_u_mm: not a finite number or nan",
                                         "dz_u_mm: not a finite number or nan",
                                         "dx_u_mm: not a finite number or nan"};
  double *num[4] = {&x->first_limit_mm, &x->delta_u_mm, &x->dz_u_mm, &x->dx_u_mm};
  for (int k = 0; k < 4; k++)
    if (table_number(f[2 + k], num[k]) != 0) return NUMBER[k];
  if (x->status == VS_MC_COLLAPSE &&
      !(isfinite(x->delta_u_mm) && isfinite(x->dz_u_mm) && isfinite(x->dx_u_mm)))
    return "delta_u_mm, dz_u_mm, dx_u_mm: nan in a collapse";
  if (vs_parse_long(f[6], &mode) != VS_NUM_OK || mode < 0 || mode > 3)
    return "mode: not an integer in [0, 3]";
  x->mode = (int)mode;
  if (strlen(f[7]) >= sizeof x->pattern || strspn(f[7], "IE-") != strlen(f[7]))
    return "pattern: not hinge sides I, E joined by '-' (at most 15 characters)";
  memcpy(x->pattern, f[7], strlen(f[7]) + 1);
  static const char *const HINGE[VS_MC_LABELS] = {
      "A: not empty nor JOINT-I or JOINT-E (JOINT >= 1)",
      "B: not empty nor JOINT-I or JOINT-E (JOINT >= 1)",
      "C: not empty nor JOINT-I or JOINT-E (JOINT >= 1)",
      "D: not empty nor JOINT-I or JOINT-E (JOINT >= 1)",
      "E: not empty nor JOINT-I or JOINT-E (JOINT >= 1)"};
  for (int l = 0; l < VS_MC_LABELS; l++)
    if (table_hinge(f[8 + l], &x->hinge_joint[l], &x->hinge_side[l]) != 0) return HINGE[l];
  if (strlen(f[13]) >= sizeof x->error || strpbrk(f[13], ",\"") != NULL)
    return "error: longer than 399 characters, or holding a comma or a quote";
  memcpy(x->error, f[13], strlen(f[13]) + 1);
  return NULL;
}

/* Append the samples of DIR/samples.csv to *all; the header line must equal *header (set by the
 * first directory). */
static int read_shard(const char *dir, char *header, size_t hsize, vs_mc_sample **all, int *n,
                      int *cap) {
  char path[1200], line[1024];
  snprintf(path, sizeof path, "%s/samples.csv", dir);
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    fprintf(stderr, "voussoir merge: %s: cannot open: %s\n", path, strerror(errno));
    return -1;
  }
  int rc = 0;
  if (fgets(line, sizeof line, f) == NULL || strncmp(line, "# voussoir montecarlo ", 22) != 0) {
    fprintf(stderr, "voussoir merge: %s: not a montecarlo table\n", path);
    rc = -1;
  } else if (header[0] == '\0') {
    snprintf(header, hsize, "%s", line);
  } else if (strcmp(header, line) != 0) {
    fprintf(stderr, "voussoir merge: %s: another case or seed than the first directory\n", path);
    rc = -1;
  }
  if (rc == 0 && (fgets(line, sizeof line, f) == NULL ||
                  strncmp(line, VS_MC_TABLE_COLUMNS, strlen(VS_MC_TABLE_COLUMNS)) != 0 ||
                  strcspn(line + strlen(VS_MC_TABLE_COLUMNS), "\r\n") != 0)) {
    fprintf(stderr, "voussoir merge: %s: line 2: not the column names of a montecarlo table\n",
            path);
    rc = -1;
  }
  for (int ln = 3; rc == 0 && fgets(line, sizeof line, f) != NULL; ln++) {
    if (*n == *cap) {
      const int nc = *cap ? 2 * *cap : 256;
      vs_mc_sample *b = realloc(*all, (size_t)nc * sizeof *b);
      if (b == NULL) {
        rc = -1;
        break;
      }
      *all = b;
      *cap = nc;
    }
    /* a row longer than the buffer would be read as two (montecarlo's are shorter) */
    const char *bad = strchr(line, '\n') == NULL && !feof(f) ? "longer than 1023 bytes"
                                                             : parse_row(line, &(*all)[*n]);
    if (bad != NULL) {
      fprintf(stderr, "voussoir merge: %s: line %d: %s\n", path, ln, bad);
      rc = -1;
    } else {
      (*n)++;
    }
  }
  fclose(f);
  return rc;
}

static int header_case(const char *header, vs_case *c) {
  vs_case_defaults(c);
  return sscanf(header,
                "# voussoir montecarlo seed=%d radius_mm=%lf embrace_deg=%lf max_mm=%lf "
                "alpha_deg=%lf voussoirs=%d",
                &c->seed, &c->radius_mm, &c->embrace_deg, &c->max_mm, &c->alpha_deg,
                &c->voussoirs) == 6
             ? 0
             : -1;
}

static int cmp_sample_no(const void *x, const void *y) {
  const int a = ((const vs_mc_sample *)x)->sample, b = ((const vs_mc_sample *)y)->sample;
  return (a > b) - (a < b);
}

int vs_merge_main(const char *const *dirs, int nd, const char *out) {
  if (vs_plugin_load(VS_PLUGIN_PLOT, "voussoir merge") != 0) return EXIT_FAIL;
  char header[1024] = "";
  vs_mc_sample *all = NULL;
  int n = 0, cap = 0, rc = EXIT_USAGE;
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
  for (int d = 0; d < nd; d++)
    if (read_shard(dirs[d], header, sizeof header, &all, &n, &cap) != 0) goto done;
  if (n > 0) qsort(all, (size_t)n, sizeof *all, cmp_sample_no); /* all: NULL if no row */
  for (int i = 1; i < n; i++)
    if (all[i].sample == all[i - 1].sample) {
      fprintf(stderr, "voussoir merge: sample %d appears twice\n", all[i].sample);
      goto done;
    }
  vs_case c;
  vs_error err;
  vs_error_clear(&err);
  if (n == 0 || header_case(header, &c) != 0) {
    fprintf(stderr, "voussoir merge: no samples, or an unreadable table header\n");
    goto done;
  }
  rc = EXIT_FAIL;
  if (vs_mc_write_summary(out, &c, all, n, &err) != VS_OK) {
    fprintf(stderr, "voussoir merge: %s\n", err.msg);
    goto done;
  }
  printf("%d samples from %d directories; summary: %s/summary.h5\n", n, nd, out);
  rc = 0;
done:
  free(all);
  free(tables);
  free(others);
  vs_plot_release();
  return rc;
}
