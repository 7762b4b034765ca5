/* libFuzzer target for `voussoir merge`: the Monte Carlo shards' tables (samples.csv) read and
 * joined by vs_merge_main (src/montecarlo_merge.c), their summary written by the real
 * vs_mc_write_summary (src/montecarlo.c) into a temporary directory, the pictures left out.
 * The input is up to 4 shards' tables, separated by a line "--shard--". Besides crashes and
 * sanitizer reports it checks meaning:
 *  - merge ends with 0 or 2 (bad input), never 1: a table it accepts can be summarised;
 *  - what merge hands to the summary's writer is what `voussoir montecarlo` could have
 *    written: at least one sample, in increasing sample order, each with a known status and
 *    mode, its displacements finite or NaN (finite in a collapse), its pattern of sides I, E
 *    and '-', its error text without a comma, its hinges on joints 1.. with side I or E;
 *  - merge is idempotent: the merged table merged again gives the same samples.csv and
 *    statistics.csv, byte for byte.
 * Run it with tests/fuzz/run.sh [SECONDS] merge. Seams (run.sh links this file with the sources
 * named there): the plot plugin is not loaded (its code is linked in); the pictures are not
 * rasterised (vs_plot_emit is wrapped: ld --wrap); vs_mc_write_summary is wrapped to see what
 * merge passes it; vs_mc_check_outputs (the output directory's checks, src/montecarlo_cmd.c,
 * not what this target is about) accepts. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <hdf5.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define FUZZ_NAME "fuzz_merge"
#include "fuzz.h"

#include "cli.h"
#include "montecarlo_cmd.h"
#include "plot_draw.h"
#include "plugin.h"
#include "voussoir/montecarlo.h"
#include "voussoir/plot.h"

enum { MAX_SHARDS = 4 };
static const char SEPARATOR[] = "--shard--\n";
static char g_root[4096];  /* the scratch directory: shards s0..s3, summaries m1 and m2 */
static int g_writes;       /* calls of the summary's writer by the current merge */

/* --- seams --- */

int vs_plugin_load(vs_plugin_kind kind, const char *name) {
  (void)kind, (void)name;
  return 0;
}

/* The pictures: everything but the pixels (the summary draws none: its charts are matplotlib's,
 * voussoir plot's); an empty
 * file is written, which the summary renames into place as it would a picture. */
vs_status __wrap_vs_plot_emit(const char *path, vs_plot_format fmt, int w, int h,
                              vs_plot_draw_fn draw, const void *data, vs_error *err) {
  (void)fmt, (void)draw, (void)data, (void)err;
  CHECK(path != NULL && w > 0 && h > 0);
  FILE *f = fopen(path, "w");
  CHECK(f != NULL && fclose(f) == 0);
  return VS_OK;
}

int vs_mc_check_outputs(const char *cmd, const char *dir, const vs_outpath_other *others,
                        int n_others, int state) {
  (void)cmd, (void)dir, (void)others, (void)n_others, (void)state;
  return 0;
}

vs_status __real_vs_mc_write_summary(const char *dir, const vs_case *base, vs_mc_sample *samples,
                                     int n, vs_error *err);

static int terminated(const char *s, size_t size) { return memchr(s, '\0', size) != NULL; }

/* What merge passes the writer: samples montecarlo could have written. */
vs_status __wrap_vs_mc_write_summary(const char *dir, const vs_case *base, vs_mc_sample *samples,
                                     int n, vs_error *err) {
  g_writes++;
  CHECK(n >= 1 && samples != NULL);
  for (int i = 0; i < n; i++) {
    const vs_mc_sample *x = &samples[i];
    CHECK(x->sample >= 0 && (i == 0 || x->sample > samples[i - 1].sample));
    CHECK(x->status == VS_MC_COLLAPSE || x->status == VS_MC_NO_COLLAPSE ||
          x->status == VS_MC_FAILED);
    CHECK(x->mode >= 0 && x->mode <= 3);
    const double d[4] = {x->first_limit_mm, x->delta_u_mm, x->dz_u_mm, x->dx_u_mm};
    for (int k = 0; k < 4; k++) CHECK(isfinite(d[k]) || isnan(d[k]));
    CHECK(x->status != VS_MC_COLLAPSE || (isfinite(d[1]) && isfinite(d[2]) && isfinite(d[3])));
    CHECK(terminated(x->pattern, sizeof x->pattern) && terminated(x->error, sizeof x->error));
    CHECK(strspn(x->pattern, "IE-") == strlen(x->pattern) && strpbrk(x->error, ",\n") == NULL);
    for (int l = 0; l < VS_MC_LABELS; l++)
      CHECK(x->hinge_joint[l] == 0 ||
            (x->hinge_joint[l] >= 1 && (x->hinge_side[l] == 'I' || x->hinge_side[l] == 'E')));
  }
  /* the shards' header is a case merge has validated (issue 25, defect 8) */
  vs_error verr;
  CHECK(vs_case_validate(base, &verr) == VS_OK);
  return __real_vs_mc_write_summary(dir, base, samples, n, err);
}

/* --- the scratch directory --- */

static void path_of(char *buf, size_t size, const char *dir, const char *name) {
  CHECK((size_t)snprintf(buf, size, "%s/%s%s%s", g_root, dir, name ? "/" : "", name ? name : "") <
        size);
}

static void empty_dir(const char *dir) {
  char path[4200];
  path_of(path, sizeof path, dir, NULL);
  DIR *d = opendir(path);
  if (d == NULL) return;
  for (struct dirent *e = readdir(d); e != NULL; e = readdir(d)) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    char f[4200 + 256];
    snprintf(f, sizeof f, "%s/%s", path, e->d_name);
    CHECK(unlink(f) == 0);
  }
  closedir(d);
}

static void remove_root(void) {
  static const char *dirs[] = {"s0", "s1", "s2", "s3", "m1", "m2"};
  for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
    char path[4200];
    empty_dir(dirs[i]);
    path_of(path, sizeof path, dirs[i], NULL);
    rmdir(path);
  }
  rmdir(g_root);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  fuzz_report_open();
  H5set_free_list_limits(-1, -1, -1, -1, -1, -1); /* see fuzz_record.c */
  fuzz_scratch(g_root, sizeof g_root);
  for (int k = 0; k < MAX_SHARDS; k++) {
    char dir[8], path[4200];
    snprintf(dir, sizeof dir, "s%d", k);
    path_of(path, sizeof path, dir, NULL);
    CHECK(mkdir(path, 0755) == 0);
  }
  atexit(remove_root);
  return 0;
}

static void write_file(const char *path, const uint8_t *data, size_t size) {
  FILE *f = fopen(path, "wb");
  CHECK(f != NULL);
  CHECK(fwrite(data, 1, size, f) == size || size == 0);
  CHECK(fclose(f) == 0);
}

/* The shards of data (split at SEPARATOR) into s0/samples.csv ...; returns their count. */
static int write_shards(const uint8_t *data, size_t size) {
  int nd = 0;
  const uint8_t *p = data, *end = data + size;
  const size_t sl = strlen(SEPARATOR);
  while (nd < MAX_SHARDS) {
    const uint8_t *cut = NULL;
    for (const uint8_t *q = p; q + sl <= end && cut == NULL; q++)
      if (memcmp(q, SEPARATOR, sl) == 0) cut = q;
    char dir[8], path[4200];
    snprintf(dir, sizeof dir, "s%d", nd);
    path_of(path, sizeof path, dir, "samples.csv");
    const uint8_t *stop = cut != NULL && nd + 1 < MAX_SHARDS ? cut : end;
    write_file(path, p, (size_t)(stop - p));
    nd++;
    if (stop == end) break;
    p = stop + sl;
  }
  return nd;
}

static void same_file(const char *name) {
  char a[4200], b[4200];
  path_of(a, sizeof a, "m1", name);
  path_of(b, sizeof b, "m2", name);
  size_t na, nb;
  char *x = fuzz_slurp(a, &na), *y = fuzz_slurp(b, &nb);
  CHECK(x != NULL && y != NULL);
  if (na != nb || memcmp(x, y, na) != 0) {
    fprintf(FUZZ_REPORT, "fuzz_merge: %s differs when merged again:\n--- first\n%s--- again\n%s",
            name, x, y);
    abort();
  }
  free(x);
  free(y);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const int nd = write_shards(data, size);
  char dirs[MAX_SHARDS][4200], m1[4200], m2[4200];
  const char *dp[MAX_SHARDS];
  for (int k = 0; k < nd; k++) {
    char dir[8];
    snprintf(dir, sizeof dir, "s%d", k);
    path_of(dirs[k], sizeof dirs[k], dir, NULL);
    dp[k] = dirs[k];
  }
  path_of(m1, sizeof m1, "m1", NULL);
  path_of(m2, sizeof m2, "m2", NULL);
  empty_dir("m1");
  empty_dir("m2");
  g_writes = 0;
  const int rc = vs_merge_main(dp, nd, m1);
  CHECK(rc == 0 || rc == 2);
  if (rc != 0) return 0;
  CHECK(g_writes == 1);
  const char *again[1] = {m1};
  g_writes = 0;
  CHECK(vs_merge_main(again, 1, m2) == 0 && g_writes == 1);
  same_file("samples.csv");
  same_file("statistics.csv");
  return 0;
}
