/* Monte Carlo over imperfect arches: the statistics of many samples (mean, CoV, 5 % quantile,
 * fragility curve with its DKW band, hinge histograms, running statistics) and the summary files
 * (CSV, HDF5; its charts: `voussoir plot DIR/summary.h5`, matplotlib's), in the plot plugin.
 * One sample's run is in
 * src/run/montecarlo_sample.c (the core library); the process pool and the CLI in
 * src/study/montecarlo_cmd.c and src/cli/cli_montecarlo.c. */
#define _POSIX_C_SOURCE 200809L /* mkdir */
#include "voussoir/montecarlo.h"

#include "h5util.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "outpath.h"
#include "voussoir/geometry.h"
#include "voussoir/run.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

/* Confidence of the fragility band: Dvoretzky-Kiefer-Wolfowitz (Massart's constant), a band that
 * holds for the whole curve at once with probability 1 - VS_MC_BAND_ALPHA. */
static const double VS_MC_BAND_ALPHA = 0.05;
static const double VS_MC_QUANTILE = 0.05; /* the low quantile of delta_u / L reported */
enum { VS_MC_FRAGILITY_POINTS = 201, VS_MC_RUNNING = 1000 };

/* ---------------------------------------------------------------------------------------------
 * Statistics */

typedef struct {
  int n, n_collapse, n_none, n_failed;
  double mean_pct, cov, q05_pct;  /* of delta_u / L over the collapses */
  double mean_dz_pct, mean_dx_pct, mean_first_pct;
  int modes[4];                   /* unclassified, I, II, III */
  int n_run;                      /* checkpoints of the running statistics (<= VS_MC_RUNNING) */
  double *run_n, *run_mean, *run_cov, *run_q05; /* running statistics at n_run sample counts */
  double frag_delta[VS_MC_FRAGILITY_POINTS], frag_p[VS_MC_FRAGILITY_POINTS];
  double frag_lo[VS_MC_FRAGILITY_POINTS], frag_hi[VS_MC_FRAGILITY_POINTS], band_eps;
  int n_joints;
  double *hist; /* VS_MC_LABELS x n_joints counts */
  int load;     /* analysis.type = load: the load factor's statistics below */
  int n_lf;     /* samples with a load factor (0 for one that collapsed before the hold) */
  double lf_mean, lf_cov, lf_q05;
} mc_stats;

static int cmp_double(const void *x, const void *y) {
  const double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

static int cmp_sample(const void *x, const void *y) {
  const int a = ((const vs_mc_sample *)x)->sample, b = ((const vs_mc_sample *)y)->sample;
  return (a > b) - (a < b);
}

/* Hyndman-Fan type 7 quantile of sorted x[0..n-1]. */
static double quantile(const double *x, int n, double p) {
  if (n < 1) return NAN;
  const double h = (n - 1) * p;
  const int i = (int)floor(h);
  return i + 1 < n ? x[i] + (h - i) * (x[i + 1] - x[i]) : x[n - 1];
}

/* mean, CoV and low quantile of the first n values of v (NaN skipped); w is scratch. */
static void moments(const double *v, int n, double *w, double *mean, double *cov, double *q) {
  int m = 0;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; i++)
    if (isfinite(v[i])) {
      w[m++] = v[i];
      s += v[i];
    }
  *mean = m > 0 ? s / m : NAN;
  for (int i = 0; i < m; i++) s2 += (w[i] - *mean) * (w[i] - *mean);
  *cov = m > 1 ? sqrt(s2 / (m - 1)) / *mean : NAN;
  qsort(w, (size_t)m, sizeof *w, cmp_double);
  *q = quantile(w, m, VS_MC_QUANTILE);
}

static void fragility(const vs_mc_sample *s, int n, const vs_case *c, mc_stats *st) {
  const int valid = st->n_collapse + st->n_none;
  st->band_eps = valid > 0 ? sqrt(log(2.0 / VS_MC_BAND_ALPHA) / (2.0 * valid)) : NAN;
  double top = 0.0; /* the grid runs to 1.2 x the largest collapse (at most support.max_mm) */
  for (int i = 0; i < n; i++)
    if (s[i].status == VS_MC_COLLAPSE) top = fmax(top, s[i].delta_u_mm);
  top = top > 0.0 ? fmin(c->max_mm, 1.2 * top) : c->max_mm;
  for (int k = 0; k < VS_MC_FRAGILITY_POINTS; k++) {
    const double d = top * k / (VS_MC_FRAGILITY_POINTS - 1);
    int below = 0;
    for (int i = 0; i < n; i++) below += s[i].status == VS_MC_COLLAPSE && s[i].delta_u_mm <= d;
    const double p = valid > 0 ? (double)below / valid : NAN;
    st->frag_delta[k] = d * VS_MM;
    st->frag_p[k] = p;
    st->frag_lo[k] = fmax(0.0, p - st->band_eps);
    st->frag_hi[k] = fmin(1.0, p + st->band_eps);
  }
}

/* The span the statistics are of, mm: the case's, or (a blocks file that does not give it) the
 * arch's own, as each run's JSON (span_mm); NaN when the file cannot be read. */
static double mc_span_mm(const vs_case *c) {
  double L = vs_case_span_mm(c);
  if (isfinite(L)) return L;
  vs_run_def *d = malloc(sizeof *d);
  vs_geometry *g = NULL;
  vs_error e;
  if (d != NULL) vs_case_to_def(c, d);
  if (d != NULL && vs_geometry_create_arch(&d->arch, &g, &e) == VS_OK) L = g->span / VS_MM;
  vs_geometry_destroy(&g);
  free(d);
  return L;
}

static vs_status compute(const vs_mc_sample *s, int n, const vs_case *c, mc_stats *st,
                         vs_error *err) {
  memset(st, 0, sizeof *st);
  st->n = n;
  st->n_joints = c->voussoirs + 1;
  const double L = mc_span_mm(c);
  double *v = calloc((size_t)n + 1, sizeof *v), *w = calloc((size_t)n + 1, sizeof *w);
  st->run_n = malloc((size_t)n * sizeof(double));
  st->run_mean = malloc((size_t)n * sizeof(double));
  st->run_cov = malloc((size_t)n * sizeof(double));
  st->run_q05 = malloc((size_t)n * sizeof(double));
  st->hist = calloc((size_t)VS_MC_LABELS * (size_t)st->n_joints, sizeof(double));
  if (v == NULL || w == NULL || st->run_n == NULL || st->run_mean == NULL || st->run_cov == NULL ||
      st->run_q05 == NULL || st->hist == NULL) {
    free(v);
    free(w);
    return vs_error_set(err, VS_ERR_NOMEM, "montecarlo: out of memory");
  }
  double sdz = 0, sdx = 0, sfirst = 0;
  int nfirst = 0;
  for (int i = 0; i < n; i++) {
    const vs_mc_sample *x = &s[i];
    st->n_collapse += x->status == VS_MC_COLLAPSE;
    st->n_none += x->status == VS_MC_NO_COLLAPSE;
    st->n_failed += x->status == VS_MC_FAILED;
    v[i] = x->status == VS_MC_COLLAPSE ? 100.0 * x->delta_u_mm / L : NAN;
    if (isfinite(x->first_limit_mm)) {
      sfirst += 100.0 * x->first_limit_mm / L;
      nfirst++;
    }
    if (x->status != VS_MC_COLLAPSE) continue;
    sdz += 100.0 * x->dz_u_mm / L;
    sdx += 100.0 * x->dx_u_mm / L;
    st->modes[x->mode >= 0 && x->mode <= 3 ? x->mode : 0]++;
    for (int l = 0; l < VS_MC_LABELS; l++)
      if (x->hinge_joint[l] >= 1 && x->hinge_joint[l] <= st->n_joints)
        st->hist[l * st->n_joints + x->hinge_joint[l] - 1] += 1.0;
  }
  moments(v, n, w, &st->mean_pct, &st->cov, &st->q05_pct);
  st->load = c->type == VS_ANALYSIS_LOAD; /* or (merge: the table's header has no type) any
                                             sample with a load factor */
  for (int i = 0; i < n && !st->load; i++) st->load = isfinite(s[i].load_factor) != 0;
  if (st->load) { /* the load factor over the samples that did not fail and have one */
    for (int i = 0; i < n; i++) {
      v[i] = s[i].status != VS_MC_FAILED ? s[i].load_factor : NAN;
      st->n_lf += isfinite(v[i]) != 0;
    }
    moments(v, n, w, &st->lf_mean, &st->lf_cov, &st->lf_q05);
    for (int i = 0; i < n; i++) v[i] = s[i].status == VS_MC_COLLAPSE ? 100.0 * s[i].delta_u_mm / L : NAN;
  }
  st->mean_dz_pct = st->n_collapse ? sdz / st->n_collapse : NAN;
  st->mean_dx_pct = st->n_collapse ? sdx / st->n_collapse : NAN;
  st->mean_first_pct = nfirst ? sfirst / nfirst : NAN;
  /* every sample count up to VS_MC_RUNNING samples, evenly spread checkpoints beyond */
  st->n_run = n < VS_MC_RUNNING ? n : VS_MC_RUNNING;
  for (int i = 0; i < st->n_run; i++) {
    const int k = (int)(((long long)n * (i + 1)) / st->n_run);
    st->run_n[i] = k;
    moments(v, k, w, &st->run_mean[i], &st->run_cov[i], &st->run_q05[i]);
  }
  fragility(s, n, c, st);
  free(v);
  free(w);
  return VS_OK;
}

static void stats_free(mc_stats *st) {
  free(st->run_n);
  free(st->run_mean);
  free(st->run_cov);
  free(st->run_q05);
  free(st->hist);
}

/* ---------------------------------------------------------------------------------------------
 * Files: each written as "<name>.part" and renamed into place */

/* The sizes of a summary file's path and of its working file's. */
enum { MC_PATH = 1200, MC_PART = MC_PATH + sizeof ".part" };

/* dir/name into path (MC_PATH bytes) and dir/name.part into part (MC_PART). */
static void target(const char *dir, const char *name, char *path, char *part) {
  snprintf(path, MC_PATH, "%s/%s", dir, name);
  snprintf(part, MC_PART, "%s.part", path);
}

static vs_status cannot(const char *path, vs_error *err) {
  return vs_error_set(err, VS_ERR_IO, "montecarlo: %s: cannot write: %s", path, strerror(errno));
}

/* After part was written with status st: renamed over path (checked just before: never over
 * anything but a regular file), or removed. */
static vs_status publish(const char *path, const char *part, vs_status st, vs_error *err) {
  if (st == VS_OK) st = vs_outpath_publish(part, path, err);
  if (st != VS_OK) vs_outpath_discard(part);
  return st;
}

static const char *status_name(int s) {
  return s == VS_MC_COLLAPSE ? "collapse" : s == VS_MC_NO_COLLAPSE ? "max_displacement" : "failed";
}

/* A path as the table's header writes it: its text without spaces (one word), "none" if none. */
static void header_path(const vs_case *c, const char *key, char *buf, size_t size) {
  const char *sec = NULL, *name = NULL;
  char text[1024] = "";
  for (int i = 0; vs_case_text_key(c, i, &sec, &name, text, sizeof text) == 0; i++)
    if (strcmp(sec, "support") == 0 && strcmp(name, key) == 0) break;
  size_t k = 0;
  for (const char *p = text; *p && k + 1 < size; p++)
    if (*p != ' ') buf[k++] = *p;
  buf[k] = '\0';
  if (k == 0) snprintf(buf, size, "none");
}

/* One row per sample, in sample order; no timings, so the file depends only on the inputs.
 * Written at part (created anew), named path in messages. Line 1 names what `voussoir merge`
 * needs to write the summary again: the case keys, the span L (L_mm) and the supports'
 * motion. */
static vs_status write_samples_csv(const char *path, const char *part, const vs_case *c,
                                   const vs_mc_sample *s, int n, vs_error *err) {
  FILE *f;
  vs_status st = vs_outpath_fopen(part, &f, err);
  if (st != VS_OK) return st;
  char lp[1024], rp[1024];
  header_path(c, "left_path", lp, sizeof lp);
  header_path(c, "right_path", rp, sizeof rp);
  fprintf(f, "# voussoir montecarlo seed=%d radius_mm=%.17g embrace_deg=%.17g max_mm=%.17g "
             "alpha_deg=%.17g voussoirs=%d L_mm=%.17g rate_mm_s=%.17g left_alpha_deg=%.17g "
             "left_rate_mm_s=%.17g left_path=%s right_path=%s\n",
          c->seed, c->radius_mm, c->embrace_deg, c->max_mm, c->alpha_deg, c->voussoirs,
          mc_span_mm(c), c->rate_mm_s, c->left_alpha_deg, c->left_rate_mm_s, lp, rp);
  int mortar = 0; /* a mortared study's table: the first crack's columns */
  for (int i = 0; i < n; i++) mortar |= s[i].mortared;
  fputs(mortar ? VS_MC_TABLE_COLUMNS VS_MC_CRACK_COLUMNS "\n" : VS_MC_TABLE_COLUMNS "\n", f);
  for (int i = 0; i < n; i++) {
    const vs_mc_sample *x = &s[i];
    fprintf(f, "%d,%s,%.17g,%.17g,%.17g,%.17g,%d,%s", x->sample, status_name(x->status),
            x->first_limit_mm, x->delta_u_mm, x->dz_u_mm, x->dx_u_mm, x->mode, x->pattern);
    for (int l = 0; l < VS_MC_LABELS; l++) {
      if (x->hinge_joint[l] > 0) fprintf(f, ",%d-%c", x->hinge_joint[l], x->hinge_side[l]);
      else fputs(",", f);
    }
    char e[sizeof x->error];
    snprintf(e, sizeof e, "%s", x->error);
    for (char *p = e; *p; p++)
      if (*p == ',' || *p == '\n' || *p == '"') *p = ';';
    double t[4];
    vs_mc_travel(c, x->status == VS_MC_COLLAPSE ? x->delta_u_mm : NAN, t);
    fprintf(f, ",%s,%.17g,%.17g,%.17g,%.17g,%.17g", e, t[0], t[1], t[2], t[3], x->load_factor);
    if (mortar) {
      const char side[2] = {x->first_crack_side, '\0'};
      fprintf(f, ",%.17g,%d,%s", x->first_crack_mm, x->first_crack_joint, side);
    }
    fputc('\n', f);
  }
  return fclose(f) == 0 ? VS_OK : cannot(path, err);
}

static vs_status write_stats_csv(const char *path, const char *part, const mc_stats *st,
                                 vs_error *err) {
  FILE *f;
  const vs_status s = vs_outpath_fopen(part, &f, err);
  if (s != VS_OK) return s;
  fputs("quantity,value,unit\n", f);
  fprintf(f, "samples,%d,\ncollapses,%d,\nno_collapse_within_max,%d,\nfailed,%d,\n", st->n,
          st->n_collapse, st->n_none, st->n_failed);
  fprintf(f, "mean_delta_u_over_L,%.6f,%%\ncov_delta_u,%.6f,\nq05_delta_u_over_L,%.6f,%%\n",
          st->mean_pct, st->cov, st->q05_pct);
  fprintf(f, "mean_dz_u_over_L,%.6f,%%\nmean_dx_u_over_L,%.6f,%%\nmean_first_limit_over_L,%.6f,%%\n",
          st->mean_dz_pct, st->mean_dx_pct, st->mean_first_pct);
  fprintf(f, "mode_I,%d,\nmode_II,%d,\nmode_III,%d,\nmode_unclassified,%d,\n", st->modes[1],
          st->modes[2], st->modes[3], st->modes[0]);
  fprintf(f, "fragility_band_halfwidth,%.6f,(DKW %.0f %% simultaneous)\n", st->band_eps,
          100.0 * (1.0 - VS_MC_BAND_ALPHA));
  if (st->load)
    fprintf(f, "load_factor_samples,%d,\nmean_load_factor,%.6f,\ncov_load_factor,%.6f,\n"
               "q05_load_factor,%.6f,\n",
            st->n_lf, st->lf_mean, st->lf_cov, st->lf_q05);
  return fclose(f) == 0 ? VS_OK : cannot(path, err);
}

/* A double dataset of rank 1 or 2 (rank 0: scalar) with its unit ("1" dimensionless). */
static herr_t h5_dset(hid_t loc, const char *name, int rank, const hsize_t *dims,
                      const double *data, const char *unit) {
  hid_t s = rank == 0 ? H5Screate(H5S_SCALAR) : H5Screate_simple(rank, dims, NULL);
  hid_t d = s >= 0 ? H5Dcreate2(loc, name, H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT,
                                H5P_DEFAULT)
                   : H5I_INVALID_HID;
  herr_t rc = d >= 0 ? H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) : -1;
  if (rc >= 0) rc = vs_h5_attr_cstr(d, "unit", unit);
  if (d >= 0) H5Dclose(d);
  if (s >= 0) H5Sclose(s);
  return rc;
}

static herr_t h5_scalar(hid_t loc, const char *name, double v, const char *unit) {
  return h5_dset(loc, name, 0, NULL, &v, unit);
}

static herr_t write_samples_h5(hid_t file, const vs_mc_sample *s, int n) {
  hid_t g = H5Gcreate2(file, "samples", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  double *col = malloc((size_t)(n > 0 ? n : 1) * VS_MC_LABELS * sizeof *col);
  herr_t rc = g >= 0 && col != NULL ? 0 : -1;
  const hsize_t dn = (hsize_t)n, d2[2] = {(hsize_t)n, VS_MC_LABELS};
  static const char *names[] = {"sample", "status", "first_limit", "delta_u", "dz_u", "dx_u", "mode",
                                "load_factor"};
  static const char *units[] = {"1", "1", "m", "m", "m", "m", "1", "1"};
  for (int c = 0; rc >= 0 && c < 8; c++) {
    for (int i = 0; i < n; i++) {
      const vs_mc_sample *x = &s[i];
      const double v[8] = {x->sample, x->status, x->first_limit_mm * VS_MM, x->delta_u_mm * VS_MM,
                           x->dz_u_mm * VS_MM, x->dx_u_mm * VS_MM, x->mode, x->load_factor};
      col[i] = v[c];
    }
    rc = h5_dset(g, names[c], 1, &dn, col, units[c]);
  }
  for (int i = 0; rc >= 0 && i < n; i++)
    for (int l = 0; l < VS_MC_LABELS; l++)
      col[i * VS_MC_LABELS + l] = s[i].hinge_joint[l] * (s[i].hinge_side[l] == 'E' ? -1.0 : 1.0);
  if (rc >= 0) rc = h5_dset(g, "hinge_joint", 2, d2, col, "1");
  int mortar = 0;
  for (int i = 0; i < n; i++) mortar |= s[i].mortared;
  for (int i = 0; rc >= 0 && mortar && i < n; i++) col[i] = s[i].first_crack_mm * VS_MM;
  if (rc >= 0 && mortar) rc = h5_dset(g, "first_crack", 1, &dn, col, "m");
  for (int i = 0; rc >= 0 && mortar && i < n; i++)
    col[i] = s[i].first_crack_joint * (s[i].first_crack_side == 'E' ? -1.0 : 1.0);
  if (rc >= 0 && mortar) rc = h5_dset(g, "first_crack_joint", 1, &dn, col, "1");
#define SAMPLES_DESCRIPTION                                                                        \
  "per sample: status 0 collapse, 1 none within support.max_mm, 2 failed; mode "                 \
  "1..3 (0 unclassified); load_factor: analysis.type = load's (NaN otherwise); hinge_joint[sample][A..E]: middle joint at collapse, " \
  "positive at the intrados, negative at the extrados, 0 none"
  /* (a dry study's as it was) */
  if (rc >= 0)
    rc = vs_h5_attr_cstr(g, "description",
                         mortar ? SAMPLES_DESCRIPTION
                             "; first_crack (m, the support displacement at the first crack, "
                             "NaN none) and first_crack_joint (the joint, positive when its "
                             "intrados edge cracks, negative its extrados, 0 none)"
                                : SAMPLES_DESCRIPTION);
#undef SAMPLES_DESCRIPTION
  free(col);
  if (g >= 0) H5Gclose(g);
  return rc;
}

static herr_t write_stats_h5(hid_t file, const mc_stats *st) {
  hid_t g = H5Gcreate2(file, "statistics", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  herr_t rc = g >= 0 ? 0 : -1;
  if (rc >= 0) rc = h5_scalar(g, "samples", st->n, "1");
  if (rc >= 0) rc = h5_scalar(g, "collapses", st->n_collapse, "1");
  if (rc >= 0) rc = h5_scalar(g, "no_collapse", st->n_none, "1");
  if (rc >= 0) rc = h5_scalar(g, "failed", st->n_failed, "1");
  if (rc >= 0) rc = h5_scalar(g, "mean_delta_u_over_L", st->mean_pct / 100.0, "1");
  if (rc >= 0) rc = h5_scalar(g, "cov_delta_u", st->cov, "1");
  if (rc >= 0) rc = h5_scalar(g, "q05_delta_u_over_L", st->q05_pct / 100.0, "1");
  if (rc >= 0) rc = h5_scalar(g, "mean_dz_u_over_L", st->mean_dz_pct / 100.0, "1");
  if (rc >= 0) rc = h5_scalar(g, "mean_dx_u_over_L", st->mean_dx_pct / 100.0, "1");
  const double modes[4] = {st->modes[0], st->modes[1], st->modes[2], st->modes[3]};
  const hsize_t four = 4;
  if (rc >= 0) rc = h5_dset(g, "modes", 1, &four, modes, "1");
  if (rc >= 0) rc = vs_h5_attr_cstr(g, "modes", "counts: unclassified, I, II, III");
  if (rc >= 0 && st->load) rc = h5_scalar(g, "load_factor_samples", st->n_lf, "1");
  if (rc >= 0 && st->load) rc = h5_scalar(g, "mean_load_factor", st->lf_mean, "1");
  if (rc >= 0 && st->load) rc = h5_scalar(g, "cov_load_factor", st->lf_cov, "1");
  if (rc >= 0 && st->load) rc = h5_scalar(g, "q05_load_factor", st->lf_q05, "1");
  if (g >= 0) H5Gclose(g);
  hid_t f = H5Gcreate2(file, "fragility", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t nf = VS_MC_FRAGILITY_POINTS;
  if (rc >= 0 && f < 0) rc = -1;
  if (rc >= 0) rc = h5_dset(f, "delta", 1, &nf, st->frag_delta, "m");
  if (rc >= 0) rc = h5_dset(f, "probability", 1, &nf, st->frag_p, "1");
  if (rc >= 0) rc = h5_dset(f, "lower", 1, &nf, st->frag_lo, "1");
  if (rc >= 0) rc = h5_dset(f, "upper", 1, &nf, st->frag_hi, "1");
  if (rc >= 0)
    rc = vs_h5_attr_cstr(
        f, "band",
        "P(collapse at a support displacement <= delta): the empirical CDF of delta_u "
        "over the samples that did not fail; lower/upper: the Dvoretzky-Kiefer-"
        "Wolfowitz band, 95 % simultaneous, half-width sqrt(ln(2/0.05)/(2n))");
  if (f >= 0) H5Gclose(f);
  hid_t c = H5Gcreate2(file, "convergence", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t nn = (hsize_t)st->n_run, dh[2] = {VS_MC_LABELS, (hsize_t)st->n_joints};
  if (rc >= 0 && c < 0) rc = -1;
  if (rc >= 0 && st->n > 0) rc = h5_dset(c, "samples", 1, &nn, st->run_n, "1");
  double *frac = malloc((size_t)(st->n_run > 0 ? st->n_run : 1) * sizeof *frac);
  if (frac == NULL) rc = -1;
  for (int i = 0; rc >= 0 && i < st->n_run; i++) frac[i] = st->run_mean[i] / 100.0;
  if (rc >= 0 && st->n > 0) rc = h5_dset(c, "mean_delta_u_over_L", 1, &nn, frac, "1");
  if (rc >= 0 && st->n > 0) rc = h5_dset(c, "cov_delta_u", 1, &nn, st->run_cov, "1");
  for (int i = 0; rc >= 0 && i < st->n_run; i++) frac[i] = st->run_q05[i] / 100.0;
  if (rc >= 0 && st->n > 0) rc = h5_dset(c, "q05_delta_u_over_L", 1, &nn, frac, "1");
  free(frac);
  if (c >= 0) H5Gclose(c);
  if (rc >= 0) rc = h5_dset(file, "hinge_histogram", 2, dh, st->hist, "1");
  return rc;
}

/* summary.h5 (named path in messages) written at part. */
static vs_status write_h5(const char *path, const char *part, const vs_case *cs,
                          const vs_mc_sample *s, int n, const mc_stats *st, vs_error *err) {
  hid_t file = vs_h5_create(part, H5P_DEFAULT, err);
  if (file < 0) return err->status;
  char desc[256];
  snprintf(desc, sizeof desc, "voussoir montecarlo: %d samples, seed %d, alpha %g deg, L %.6g mm",
           n, cs->seed, cs->alpha_deg, mc_span_mm(cs));
  herr_t rc = vs_h5_attr_cstr(file, "description", desc);
  if (rc >= 0)
    rc = vs_h5_attr_cstr(file, "hinge_histogram",
                         "[label A..E][joint 1..n+1]: collapses with that hinge there");
  if (rc >= 0) rc = write_samples_h5(file, s, n);
  if (rc >= 0) rc = write_stats_h5(file, st);
  if (H5Fclose(file) < 0) rc = -1;
  return rc >= 0 ? VS_OK : vs_error_set(err, VS_ERR_IO, "montecarlo: %s: cannot write", path);
}

vs_status vs_mc_write_summary(const char *dir, const vs_case *c, vs_mc_sample *s, int n,
                              vs_error *err) {
  if (mkdir(dir, 0755) != 0 && errno != EEXIST)
    return vs_error_set(err, VS_ERR_IO, "montecarlo: %s: cannot create: %s", dir, strerror(errno));
  qsort(s, (size_t)n, sizeof *s, cmp_sample);
  mc_stats st;
  vs_status rc = compute(s, n, c, &st, err);
  char path[MC_PATH], part[MC_PART];
  target(dir, "samples.csv", path, part);
  if (rc == VS_OK) rc = publish(path, part, write_samples_csv(path, part, c, s, n, err), err);
  target(dir, "statistics.csv", path, part);
  if (rc == VS_OK) rc = publish(path, part, write_stats_csv(path, part, &st, err), err);
  target(dir, "summary.h5", path, part);
  if (rc == VS_OK) rc = publish(path, part, write_h5(path, part, c, s, n, &st, err), err);
  stats_free(&st);
  return rc;
}
