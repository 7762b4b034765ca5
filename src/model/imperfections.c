/* Imperfect arches: the counter-based generator, the draws of one sample, and their application
 * to the arch's geometry and the joint laws (see include/voussoir/imperfections.h). */
#include "voussoir/imperfections.h"

#include "outline.h"
#include "piers.h"
#include "shape.h"

#include "voussoir/units.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { STREAM_KN = 1, STREAM_FACE = 2, STREAM_ANGLE = 3, STREAM_THICK = 4, STREAM_FT = 5,
       STREAM_GF = 6, STREAM_DEBOND = 7 };

static const uint64_t GOLDEN = 0x9E3779B97F4A7C15u;

static uint64_t splitmix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
  return z ^ (z >> 31);
}

uint64_t vs_rng_key(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index) {
  uint64_t x = seed;
  x = splitmix(x + (sample + 1) * GOLDEN);
  x = splitmix(x + (stream + 1) * GOLDEN);
  return splitmix(x + (index + 1) * GOLDEN);
}

double vs_rng_uniform(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index) {
  return ((double)(vs_rng_key(seed, sample, stream, index) >> 11) + 0.5) * 0x1.0p-53;
}

double vs_rng_normal(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index) {
  const double pi = 3.14159265358979323846;
  const double u1 = vs_rng_uniform(seed, sample, stream, 2 * index);
  const double u2 = vs_rng_uniform(seed, sample, stream, 2 * index + 1);
  return sqrt(-2.0 * log(u1)) * cos(2.0 * pi * u2);
}

/* Lognormal factor of mean 1 and coefficient of variation cov from the standard normal z. */
static double lognormal(double cov, double z) {
  const double s2 = log1p(cov * cov);
  return exp(sqrt(s2) * z - 0.5 * s2);
}

/* d scatters the joints' mortar. */
static int mortar_scatter(const vs_imperfection_def *d) {
  return d->tensile_cov > 0.0 || d->gf_cov > 0.0 || d->debonded > 0.0;
}

int vs_imperfections_any(const vs_imperfection_def *d) {
  return d->kn_cov > 0.0 || d->face > 0.0 || d->angle_cov > 0.0 || d->thickness_cov > 0.0 ||
         d->support_dx != 0.0 || d->support_dz != 0.0 || mortar_scatter(d);
}

void vs_imperfections_destroy(vs_imperfections **p) {
  if (p == NULL || *p == NULL) return;
  free((*p)->kn_factor);
  free((*p)->face_gap);
  free((*p)->angle);
  free((*p)->thickness);
  free((*p)->ft_factor);
  free((*p)->gf_factor);
  free(*p);
  *p = NULL;
}

/* The joints' mean spacing along the centre line, m: the circle's closed form, else the
 * shape's centre line over the voussoirs (a blocks file: 0, its joints independent). */
static vs_status joint_spacing(const vs_arch_def *a, double *ds, vs_error *err) {
  if (a->shape == VS_SHAPE_CIRCULAR && a->span == 0.0 && a->rise == 0.0) {
    const double dphi = a->embrace / a->voussoirs;
    *ds = (a->radius + 0.5 * a->thickness) * dphi;
    return VS_OK;
  }
  *ds = 0.0;
  if (a->shape == VS_SHAPE_FILE) return VS_OK;
  vs_status st = vs_shape_centre_length(a, ds, err);
  *ds /= a->voussoirs;
  return st;
}

/* The angle the voussoirs' drawn angles fill, rad: a circle's embrace (also when its span and
 * rise give it); for another shape a nominal one (arch.embrace_deg), each voussoir's size
 * scaled by its drawn angle over the nominal share (scattered_shape). */
static vs_status nominal_embrace(const vs_arch_def *a, double *embrace, vs_error *err) {
  double radius = 0.0, half = 0.5 * a->embrace;
  const vs_status st = a->shape == VS_SHAPE_CIRCULAR ? vs_shape_circle(a, &radius, &half, err) : VS_OK;
  *embrace = 2.0 * half;
  return st;
}

/* k_n factors: lognormal over an Ornstein-Uhlenbeck (or white) normal field along the arch
 * (joints ds apart, m). */
static void draw_kn(const vs_imperfection_def *d, double ds, vs_imperfections *p) {
  const uint64_t seed = (uint64_t)d->seed, smp = (uint64_t)d->sample;
  const double rho = d->kn_corr > 0.0 ? exp(-ds / d->kn_corr) : 0.0;
  double z = 0.0;
  for (int k = 0; k < p->n_joints; k++) {
    const double e = vs_rng_normal(seed, smp, STREAM_KN, (uint64_t)k);
    z = k == 0 ? e : rho * z + sqrt(1.0 - rho * rho) * e;
    p->kn_factor[k] = d->kn_cov > 0.0 ? lognormal(d->kn_cov, z) : 1.0;
  }
}

vs_status vs_imperfections_draw(const vs_imperfection_def *d, const vs_arch_def *a,
                                vs_imperfections **out, vs_error *err) {
  return vs_imperfections_draw_counts(d, a, a->voussoirs, a->voussoirs + 1, out, err);
}

vs_status vs_imperfections_draw_counts(const vs_imperfection_def *d, const vs_arch_def *a,
                                       int nb, int nj, vs_imperfections **out, vs_error *err) {
  *out = NULL;
  if (nb < 1 || nj < 1)
    return vs_error_set(err, VS_ERR_INVALID, "imperfections: %d blocks, %d joints (allowed: >= 1 "
                        "each)", nb, nj);
  vs_imperfections *p = calloc(1, sizeof *p);
  if (p != NULL) {
    p->n_joints = nj;
    p->n_blocks = nb;
    p->kn_factor = malloc((size_t)nj * sizeof(double));
    p->face_gap = malloc((size_t)nj * sizeof(double));
    p->angle = malloc((size_t)nb * sizeof(double));
    p->thickness = malloc((size_t)nb * sizeof(double));
    p->ft_factor = malloc((size_t)nj * sizeof(double));
    p->gf_factor = malloc((size_t)nj * sizeof(double));
  }
  if (p == NULL || p->kn_factor == NULL || p->face_gap == NULL || p->angle == NULL ||
      p->thickness == NULL || p->ft_factor == NULL || p->gf_factor == NULL) {
    vs_imperfections_destroy(&p);
    return vs_error_set(err, VS_ERR_NOMEM, "imperfections: out of memory");
  }
  const uint64_t seed = (uint64_t)d->seed, smp = (uint64_t)d->sample;
  double ds = 0.0;
  vs_status st = d->kn_corr > 0.0 ? joint_spacing(a, &ds, err) : VS_OK;
  if (st != VS_OK) {
    vs_imperfections_destroy(&p);
    return st;
  }
  draw_kn(d, ds, p);
  for (int k = 0; k < nj; k++)
    p->face_gap[k] =
        d->face > 0.0 ? d->face * vs_rng_normal(seed, smp, STREAM_FACE, (uint64_t)k) : 0.0;
  /* angles: deviations from nominal, shifted by their mean so that they fill the embrace (a
   * circle's, also when span and rise give it; another shape's voussoirs scale by the angle
   * over this nominal one, scattered_shape) */
  double embrace = 0.0;
  st = nominal_embrace(a, &embrace, err);
  if (st != VS_OK) {
    vs_imperfections_destroy(&p);
    return st;
  }
  const double dphi = embrace / nb;
  double mean = 0.0;
  for (int i = 0; i < nb; i++) {
    const double f = d->angle_cov > 0.0
                         ? lognormal(d->angle_cov, vs_rng_normal(seed, smp, STREAM_ANGLE, (uint64_t)i))
                         : 1.0;
    p->angle[i] = dphi * (f - 1.0);
    mean += p->angle[i] / nb;
  }
  for (int i = 0; i < nb; i++) p->angle[i] = dphi + (p->angle[i] - mean);
  for (int i = 0; i < nb; i++)
    p->thickness[i] =
        d->thickness_cov > 0.0
            ? a->thickness *
                  lognormal(d->thickness_cov, vs_rng_normal(seed, smp, STREAM_THICK, (uint64_t)i))
            : a->thickness;
  p->support[0] = d->support_dx;
  p->support[1] = d->support_dz;
  for (int k = 0; k < nj; k++) {
    const uint64_t i = (uint64_t)k;
    const int off = d->debonded > 0.0 && vs_rng_uniform(seed, smp, STREAM_DEBOND, i) < d->debonded;
    p->ft_factor[k] = off ? 0.0
                      : d->tensile_cov > 0.0 ? lognormal(d->tensile_cov, vs_rng_normal(seed, smp, STREAM_FT, i))
                                             : 1.0;
    p->gf_factor[k] =
        d->gf_cov > 0.0 ? lognormal(d->gf_cov, vs_rng_normal(seed, smp, STREAM_GF, i)) : 1.0;
  }
  *out = p;
  return VS_OK;
}

/* Any shape but the circle of equal sectors: the generator, each voussoir's length along the
 * centre line scaled by its drawn angle over the nominal one and its thickness by its drawn
 * thickness over the nominal one. */
static vs_status scattered_shape(const vs_imperfection_def *d, const vs_arch_def *a,
                                 const vs_imperfections *imp, vs_geometry **out, vs_error *err) {
  const int n = a->voussoirs;
  double embrace = 0.0;
  vs_status st = nominal_embrace(a, &embrace, err);
  if (st != VS_OK) return st;
  double *size = malloc((size_t)n * sizeof *size), *thick = malloc((size_t)n * sizeof *thick);
  st = size != NULL && thick != NULL ? VS_OK
                                     : vs_error_set(err, VS_ERR_NOMEM, "imperfections: out of memory");
  for (int i = 0; st == VS_OK && i < n; i++) {
    size[i] = imp->angle[i] / (embrace / n);
    thick[i] = imp->thickness[i] / a->thickness;
    if (!(size[i] > 0.0))
      st = vs_error_set(err, VS_ERR_INVALID, "imperfections.angle_cov = %g: voussoir %d of sample "
                        "%d drawn %g times its size (allowed: > 0; lower the CoV)", d->angle_cov,
                        i + 1, d->sample, size[i]);
  }
  if (st == VS_OK) st = vs_shape_build(a, size, thick, out, err);
  free(size), free(thick);
  return st;
}

/* The ring of arch a, scattered as imp draws it (NULL: as built). */
static vs_status imperfect_ring(const vs_imperfection_def *d, const vs_arch_def *a,
                                const vs_imperfections *imp, vs_geometry **out, vs_error *err) {
  const int scattered = d->angle_cov != 0.0 || d->thickness_cov != 0.0;
  if (scattered && a->shape == VS_SHAPE_FILE)
    return vs_error_set(err, VS_ERR_INVALID, "imperfections.angle_cov = %g, thickness_cov = %g: "
                        "a blocks file's blocks are as drawn (allowed: 0 with arch.shape = file)",
                        d->angle_cov, d->thickness_cov);
  if (scattered && (!vs_shape_is_sectors(a) || a->n_positions > 0 || a->keystone > 0.0))
    return scattered_shape(d, a, imp, out, err);
  vs_status st = vs_arch_ring(a, out, err);
  if (st != VS_OK || !scattered) return st;
  vs_geometry *g = *out;
  const int n = g->n_blocks;
  const double ri = g->radius, beta = 0.5 * g->embrace, dphi = g->embrace / n;
  double phi0 = -beta, dev = 0.0; /* accumulated deviation from the nominal joint angle */
  for (int i = 0; i < n; i++) {
    if (!(imp->angle[i] > 0.0)) {
      vs_geometry_destroy(out);
      return vs_error_set(err, VS_ERR_INVALID,
                          "imperfections.angle_cov = %g: voussoir %d of sample %d drawn with angle "
                          "%g deg (allowed: > 0; lower the CoV)",
                          d->angle_cov, i + 1, d->sample, imp->angle[i] / VS_DEG);
    }
    dev += imp->angle[i] - dphi;
    const double phi1 = i == n - 1 ? beta : -beta + (i + 1) * dphi + dev;
    vs_sector_block(ri, ri + imp->thickness[i], phi0, phi1, a->density * a->depth, &g->blocks[i]);
    vs_sector_edges(ri, ri + imp->thickness[i], phi0, phi1, i, i + 1,
                    g->edges + g->blocks[i].edge0);
    phi0 = phi1;
  }
  for (int k = 0; k <= n; k++) {
    const double phi = k == 0 ? -beta : g->blocks[k - 1].phi1;
    const double ta = k > 0 ? imp->thickness[k - 1] : INFINITY;
    const double tb = k < n ? imp->thickness[k] : INFINITY;
    const double t = fmin(ta, tb), rm = ri + 0.5 * t;
    vs_joint_geom *j = &g->joints[k];
    j->px = rm * sin(phi);
    j->pz = rm * cos(phi);
    j->nx = cos(phi);
    j->nz = -sin(phi);
    j->length = t;
  }
  return VS_OK;
}

vs_status vs_imperfections_arch(const vs_imperfection_def *d, const vs_arch_def *a,
                                const vs_imperfections *imp, vs_geometry **out, vs_error *err) {
  vs_status st = imperfect_ring(d, a, imp, out, err);
  if (st == VS_OK) st = vs_piers_add(out, &a->piers, a->density, a->depth, err);
  return st;
}

/* Joint k's mortar as drawn (imperfections.h): debonded, or f_t and G_f scattered, G_f kept
 * beyond its bound f_t^2 / (2 k_n) (at k_n as drawn). */
static void mortar_draw(const vs_imperfections *imp, int k, vs_joint_law *law) {
  if (imp->ft_factor[k] == 0.0) law->c = 0.0;
  law->ft *= imp->ft_factor[k];
  law->gf *= imp->gf_factor[k];
  const double bound = law->ft * law->ft / (2.0 * law->kn);
  if (law->ft > 0.0 && !(law->gf > bound)) law->gf = bound * 1.000001;
}

vs_status vs_imperfections_apply(const vs_imperfection_def *d, const vs_imperfections *imp,
                                 vs_model *m, vs_error *err) {
  const vs_geometry *g = vs_model_geometry(m);
  if (d->kn_cov > 0.0 || d->face > 0.0 || mortar_scatter(d)) {
    /* the joints drawn: the arch's (a pier's joints, after them, keep the nominal law) */
    for (int k = 0; k < g->n_joints && k < imp->n_joints; k++) {
      vs_joint_law law = *vs_model_joint_law(m, k);
      law.kn *= imp->kn_factor[k];
      law.ks *= imp->kn_factor[k];
      const double a = imp->face_gap[k], t = g->joints[k].length;
      law.gap0 = 0.5 * fabs(a);
      law.gap1 = a / t;
      mortar_draw(imp, k, &law);
      vs_status st = vs_model_set_joint_law(m, k, &law, err);
      if (st != VS_OK) return st;
    }
  }
  if (d->support_dx != 0.0 || d->support_dz != 0.0) {
    const double off[2] = {d->support_dx, -d->support_dz};
    vs_model_set_support_offset(m, off);
  }
  return VS_OK;
}
