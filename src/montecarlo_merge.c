/* The merge command's work (its command line is read by src/cli_montecarlo.c): the shards'
 * tables (voussoir montecarlo --shard K/M) joined into one summary. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
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

static int parse_row(char *line, vs_mc_sample *x) {
  char *f[14];
  line[strcspn(line, "\r\n")] = '\0';
  if (split_csv(line, f, 14) != 14) return -1;
  memset(x, 0, sizeof *x);
  long smp = -1, mode = 0;
  if (vs_parse_long(f[0], &smp) != VS_NUM_OK || smp < 0 || smp > INT_MAX ||
      vs_parse_long(f[6], &mode) != VS_NUM_OK || mode < 0 || mode > 3)
    return -1;
  x->sample = (int)smp;
  x->mode = (int)mode;
  x->status = strcmp(f[1], "collapse") == 0           ? VS_MC_COLLAPSE
              : strcmp(f[1], "max_displacement") == 0 ? VS_MC_NO_COLLAPSE
                                                      : VS_MC_FAILED;
  /* the table is ours: "nan" marks a missing value, which the strict parser refuses */
  x->first_limit_mm = strtod(f[2], NULL);
  x->delta_u_mm = strtod(f[3], NULL);
  x->dz_u_mm = strtod(f[4], NULL);
  x->dx_u_mm = strtod(f[5], NULL);
  snprintf(x->pattern, sizeof x->pattern, "%s", f[7]);
  for (int l = 0; l < VS_MC_LABELS; l++) {
    char side = 0;
    int j = 0;
    if (f[8 + l][0] != '\0' && sscanf(f[8 + l], "%d-%c", &j, &side) == 2) {
      x->hinge_joint[l] = j;
      x->hinge_side[l] = side;
    }
  }
  snprintf(x->error, sizeof x->error, "%s", f[13]);
  return 0;
}

/* Append the samples of DIR/samples.csv to *all; the header line must equal *header (set by the
 * first directory). */
static int read_shard(const char *dir, char *header, size_t hsize, vs_mc_sample **all, int *n,
                      int *cap) {
  char path[1200], line[1024];
  snprintf(path, sizeof path, "%s/samples.csv", dir);
  FILE *f = fopen(path, "r");
  if (f == NULL) {
    fprintf(stderr, "voussoir merge: %s: cannot open: %s\n", cli_q(path).s, strerror(errno));
    return -1;
  }
  int rc = 0;
  if (fgets(line, sizeof line, f) == NULL || strncmp(line, "# voussoir montecarlo ", 22) != 0) {
    fprintf(stderr, "voussoir merge: %s: not a montecarlo table\n", cli_q(path).s);
    rc = -1;
  } else if (header[0] == '\0') {
    snprintf(header, hsize, "%s", line);
  } else if (strcmp(header, line) != 0) {
    fprintf(stderr, "voussoir merge: %s: another case or seed than the first directory\n",
            cli_q(path).s);
    rc = -1;
  }
  if (rc == 0 && fgets(line, sizeof line, f) == NULL) rc = -1; /* column names */
  while (rc == 0 && fgets(line, sizeof line, f) != NULL) {
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
    if (parse_row(line, &(*all)[*n]) != 0) {
      fprintf(stderr, "voussoir merge: %s: malformed row %d\n", cli_q(path).s, *n + 1);
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
  qsort(all, (size_t)n, sizeof *all, cmp_sample_no);
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
