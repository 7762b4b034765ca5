/* Hinge detection and tracking: open joints grouped into (spread) hinges, matched from one
 * state to the next so that a migrating hinge keeps its identity, labelled A-E. */
#include "voussoir/hinges.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct vs_hinges {
  vs_hinge_opts opts;
  int n_joints;
  int count, cap;
  vs_hinge *h;
  char *side;   /* per joint, this update */
  int *matched; /* per hinge, this update */
};

vs_status vs_hinges_create(int n_joints, const vs_hinge_opts *opts, vs_hinges **out,
                           vs_error *err) {
  *out = NULL;
  if (n_joints < 1 || !(opts->open > 0.0) || opts->migrate < 0)
    return vs_error_set(err, VS_ERR_INVALID,
                        "hinges: %d joints, open = %g m, migrate = %d (allowed: >= 1, > 0, >= 0)",
                        n_joints, opts->open, opts->migrate);
  vs_hinges *h = calloc(1, sizeof *h);
  if (h == NULL) return vs_error_set(err, VS_ERR_NOMEM, "hinges: out of memory");
  h->opts = *opts;
  h->n_joints = n_joints;
  h->side = calloc((size_t)n_joints, 1);
  if (h->side == NULL) {
    vs_hinges_destroy(&h);
    return vs_error_set(err, VS_ERR_NOMEM, "hinges: out of memory");
  }
  *out = h;
  return VS_OK;
}

void vs_hinges_destroy(vs_hinges **h) {
  if (h == NULL || *h == NULL) return;
  free((*h)->h);
  free((*h)->side);
  free((*h)->matched);
  free(*h);
  *h = NULL;
}

char vs_hinges_joint_side(const vs_hinge_opts *opts, const vs_joint_state *st) {
  if (fmax(st->gap_i, st->gap_e) <= opts->open) return 0;
  return (st->gap_e > st->gap_i) ? 'I' : 'E';
}

/* Joints between the intervals [a0, a1] and [b0, b1] (0 when they overlap or touch). */
static int interval_gap(int a0, int a1, int b0, int b1) {
  if (a1 < b0) return b0 - a1 - 1;
  if (b1 < a0) return a0 - b1 - 1;
  return 0;
}

static int grow(vs_hinges *h) {
  if (h->count < h->cap) return 0;
  int cap = h->cap ? 2 * h->cap : 8;
  vs_hinge *nh = realloc(h->h, (size_t)cap * sizeof *nh);
  if (nh == NULL) return -1;
  h->h = nh;
  int *nm = realloc(h->matched, (size_t)cap * sizeof *nm);
  if (nm == NULL) return -1;
  h->matched = nm;
  h->cap = cap;
  return 0;
}

static int cmp_first(const void *x, const void *y) {
  const vs_hinge *a = *(const vs_hinge *const *)x, *b = *(const vs_hinge *const *)y;
  return (a->onset_first > b->onset_first) - (a->onset_first < b->onset_first);
}

/* Once three hinges have formed, name the first three A, B, C from left to right. */
static void label_first_three(vs_hinges *h) {
  vs_hinge *first[3];
  for (int i = 0; i < 3; i++) first[i] = &h->h[i];
  qsort(first, 3, sizeof first[0], cmp_first);
  for (int i = 0; i < 3; i++) first[i]->label = (char)('A' + i);
}

/* Match the group [g0, g1] on side sd to a hinge: the nearest open one on the same side within
 * the migration distance, else the nearest closed one (it reopens). -1 if none. */
static int match_group(vs_hinges *h, int g0, int g1, char sd) {
  int best = -1, best_gap = 0, best_open = 0;
  for (int i = 0; i < h->count; i++) {
    const vs_hinge *hg = &h->h[i];
    if (hg->side != sd || h->matched[i]) continue;
    int gap = interval_gap(g0, g1, hg->first, hg->last);
    if (gap > h->opts.migrate) continue;
    if (best < 0 || hg->open > best_open || (hg->open == best_open && gap < best_gap)) {
      best = i;
      best_gap = gap;
      best_open = hg->open;
    }
  }
  return best;
}

int vs_hinges_update(vs_hinges *h, double delta, const vs_joint_state *st) {
  for (int k = 0; k < h->n_joints; k++) h->side[k] = vs_hinges_joint_side(&h->opts, &st[k]);
  for (int i = 0; i < h->count; i++) h->matched[i] = 0;
  int formed = 0, before = h->count;
  for (int k = 0; k < h->n_joints;) {
    if (h->side[k] == 0) {
      k++;
      continue;
    }
    int e = k;
    while (e + 1 < h->n_joints && h->side[e + 1] == h->side[k]) e++;
    const int g0 = k + 1, g1 = e + 1; /* 1-based joints */
    int i = match_group(h, g0, g1, h->side[k]);
    if (i < 0 && grow(h) == 0) {
      i = h->count++;
      vs_hinge *hg = &h->h[i];
      memset(hg, 0, sizeof *hg);
      hg->label = '?';
      hg->side = h->side[k];
      hg->onset_first = g0;
      hg->onset_last = g1;
      hg->delta_onset = delta;
      hg->order = i + 1;
      formed++;
    }
    if (i >= 0) {
      vs_hinge *hg = &h->h[i];
      hg->first = g0;
      hg->last = g1;
      hg->open = 1;
      hg->delta_closed = NAN;
      h->matched[i] = 1;
    }
    k = e + 1;
  }
  for (int i = 0; i < before; i++) {
    if (!h->matched[i] && h->h[i].open) {
      h->h[i].open = 0;
      h->h[i].delta_closed = delta;
    }
  }
  if (before < 3 && h->count >= 3) label_first_three(h);
  for (int i = (before > 3 ? before : 3); i < h->count; i++) h->h[i].label = (char)('A' + i);
  return formed;
}

int vs_hinges_count(const vs_hinges *h) { return h->count; }

const vs_hinge *vs_hinges_get(const vs_hinges *h, int i) {
  return (i >= 0 && i < h->count) ? &h->h[i] : NULL;
}

int vs_hinges_open_count(const vs_hinges *h) {
  int c = 0;
  for (int i = 0; i < h->count; i++) c += h->h[i].open;
  return c;
}

void vs_hinge_name(const vs_hinge *hg, int onset, char *buf, size_t size) {
  const int a = onset ? hg->onset_first : hg->first, b = onset ? hg->onset_last : hg->last;
  size_t used = 0;
  if (size == 0) return;
  buf[0] = '\0';
  for (int j = a; j <= b && used < size; j++) {
    int n = snprintf(buf + used, size - used, "%d-", j);
    if (n < 0) return;
    used += (size_t)n;
  }
  if (used < size) snprintf(buf + used, size - used, "%c", hg->side);
}
