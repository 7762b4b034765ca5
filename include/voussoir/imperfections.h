/* Imperfect arches: the [imperfections] of a case drawn for one (seed, sample) and applied to the
 * geometry and the model. Every draw comes from a counter-based generator, so a value depends
 * only on (seed, sample, stream, index), never on the order or the process that draws it.
 *
 * The generator: u64 x = seed; for each key word w in (sample, stream, index):
 * x = splitmix64(x + (w + 1) * 0x9E3779B97F4A7C15), with splitmix64's finaliser
 * z = (z ^ z >> 30) * 0xBF58476D1CE4E5B9; z = (z ^ z >> 27) * 0x94D049BB133111EB; z ^ z >> 31.
 * A uniform in (0, 1) is ((x >> 11) + 0.5) 2^-53; a standard normal is Box-Muller on the uniforms
 * of indices 2i and 2i + 1 (the cosine branch). Streams: 1 k_n, 2 faces, 3 angles, 4 thickness,
 * 5 f_t, 6 G_f, 7 debonding.
 *
 * What is drawn (SI, as the definition, def.h):
 * - k_n of joint k: k_n exp(s z_k - s^2/2), s^2 = ln(1 + CoV^2) (lognormal, mean k_n, CoV kn_cov);
 *   k_s keeps its ratio. With a correlation length l_c the z_k are an Ornstein-Uhlenbeck process
 *   along the arch's centre line (correlation exp(-|s_i - s_j| / l_c)), else independent.
 * - faces: a_k = face z_k; joint k's faces touch at one edge and gap by |a_k| at the other
 *   (the extrados when a_k > 0): initial gap |a_k|/2 + (a_k/t) xi, xi from the joint centre.
 * - angles: each voussoir's angle nominal x lognormal(angle_cov), the deviations shifted by their
 *   mean so that the voussoirs still fill the embrace exactly (both springings in place).
 * - thickness: each voussoir's t nominal x lognormal(thickness_cov); a joint's faces are the
 *   overlap of its two voussoirs' (a support's, its voussoir's), from the intrados.
 * - support: the right support offset by (support_dx outward, support_dz down), entering
 *   as the arch's weight comes on (vs_model_set_support_offset).
 * - mortar: joint k debonded (f_t = c = 0, a dry joint) when the uniform of stream 7 is below
 *   debonded; else its f_t times lognormal(tensile_cov) and its G_f times lognormal(gf_cov),
 *   independent of one another and of the other streams. A joint whose G_f then falls to
 *   f_t^2 / (2 k_n) or below (its softening would end before its peak) gets 1.000001 times
 *   that bound: brittle.
 * With every amplitude 0 nothing is changed: the perfect arch, bit for bit. */
#ifndef VOUSSOIR_IMPERFECTIONS_H
#define VOUSSOIR_IMPERFECTIONS_H

#include "voussoir/api.h"

#include <stdint.h>

#include "voussoir/def.h"
#include "voussoir/geometry.h"
#include "voussoir/model.h"
#include "voussoir/status.h"

/* The generator (documented above). */
VS_API uint64_t vs_rng_key(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index);
VS_API double vs_rng_uniform(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index);
VS_API double vs_rng_normal(uint64_t seed, uint64_t sample, uint64_t stream, uint64_t index);

/* The drawn values of one sample (stored in the record). */
typedef struct {
  int n_joints, n_blocks;
  double *kn_factor; /* n_joints: k_n / nominal k_n */
  double *face_gap;  /* n_joints: a_k, the as-built gap at the open edge, m, signed (> 0 extrados) */
  double *angle;     /* n_blocks: angular size of each voussoir, rad */
  double *thickness; /* n_blocks: radial thickness of each voussoir, m */
  double support[2]; /* offset of the right support: outward, downward, m */
  double *ft_factor; /* n_joints: f_t / nominal f_t (0: debonded) */
  double *gf_factor; /* n_joints: G_f / nominal G_f */
} vs_imperfections;

/* Draw the imperfections d asks for (its seed and sample) on arch a. *out is owned by the
 * caller (vs_imperfections_destroy). VS_ERR_NOMEM only. */
VS_API vs_status vs_imperfections_draw(const vs_imperfection_def *d, const vs_arch_def *a,
                                       vs_imperfections **out, vs_error *err);
/* The same for an arch of n_blocks blocks and n_joints joints that a's voussoirs do not count
 * (a blocks file's: its joints' k_n scatter independent of one another). */
VS_API vs_status vs_imperfections_draw_counts(const vs_imperfection_def *d, const vs_arch_def *a,
                                              int n_blocks, int n_joints, vs_imperfections **out,
                                              vs_error *err);
VS_API void vs_imperfections_destroy(vs_imperfections **p);

/* 1 when d asks for any imperfection, else 0. */
VS_API int vs_imperfections_any(const vs_imperfection_def *d);

/* Build arch a with the drawn angles and thickness (vs_geometry_create_arch when d's CoVs of
 * them are 0; imp is then not read and may be NULL). A circular arch of sectors gets each
 * voussoir's drawn angle; any other shape each voussoir's length along the centre line scaled
 * by its drawn angle over the nominal embrace / n, and its thickness by its drawn thickness over
 * the nominal one. A blocks file's blocks are as drawn: VS_ERR_INVALID with angle or thickness
 * scatter. */
VS_API vs_status vs_imperfections_arch(const vs_imperfection_def *d, const vs_arch_def *a,
                                       const vs_imperfections *imp, vs_geometry **out,
                                       vs_error *err);

/* Apply the joint laws (k_n, faces, mortar) and the support offset d asks for to model m built
 * over that arch. */
VS_API vs_status vs_imperfections_apply(const vs_imperfection_def *d, const vs_imperfections *imp,
                                        vs_model *m, vs_error *err);

#endif
