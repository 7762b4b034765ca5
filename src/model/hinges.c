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
  double *gap_i, *gap_e; /* per joint, edge openings at the previous update (m) */
  double delta_prev;     /* support displacement of the previous update (NaN before one) */
  int named;             /* 1 once the first hinges have their labels */
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
  h->gap_i = calloc((size_t)n_joints, sizeof *h->gap_i);
  h->gap_e = calloc((size_t)n_joints, sizeof *h->gap_e);
  h->delta_prev = NAN;
  if (h->side == NULL || h->gap_i == NULL || h->gap_e == NULL) {
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
  free((*h)->gap_i);
  free((*h)->gap_e);
  free(*h);
  *h = NULL;
}

char vs_hinges_joint_side(const vs_hinge_opts *opts, const vs_joint_state *st) {
  if (fmax(st->gap_i, st->gap_e) <= opts->open) return 0;
  return (st->gap_e > st->gap_i) ? 'I' : 'E';
}

/* How many joints the interval [a0, a1] is from [b0, b1]: 0 when they overlap, 1 for
 * neighbouring joints, and so on. */
static int interval_gap(int a0, int a1, int b0, int b1) {
  if (a1 < b0) return b0 - a1;
  if (b1 < a0) return a0 - b1;
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

char vs_hinges_label(int i) {
  if (i < 0) return '?';
  if (i < 26) return (char)('A' + i);
  if (i < 52) return (char)('a' + (i - 26));
  return '#';
}

/* Name the first n (at most three) hinges A, B, C from left to right; later ones get the next
 * letters in order of appearance. */
static void label_first(vs_hinges *h, int n) {
  vs_hinge *first[3];
  for (int i = 0; i < n; i++) first[i] = &h->h[i];
  qsort(first, (size_t)n, sizeof first[0], cmp_first);
  for (int i = 0; i < n; i++) first[i]->label = vs_hinges_label(i);
  h->named = 1;
}

void vs_hinges_name_first(vs_hinges *h, int n) {
  if (n > 3) n = 3;
  if (n > h->count) n = h->count;
  if (n <= 0) return;
  label_first(h, n);
  for (int i = n; i < h->count; i++) h->h[i].label = vs_hinges_label(i);
}

/* Open joints grouped into maximal runs of the same side. */
typedef struct {
  int first, last; /* 1-based joints */
  char side;
  int hinge;       /* matched hinge, -1 if new */
} group;

/* Candidate pairing of a group with a hinge, ranked: open hinges before closed ones (which
 * reopen), then the smaller distance, then left to right. */
typedef struct {
  int g, h, closed, dist;
} pairing;

static int cmp_pairing(const void *x, const void *y) {
  const pairing *a = x, *b = y;
  if (a->closed != b->closed) return a->closed - b->closed;
  if (a->dist != b->dist) return a->dist - b->dist;
  if (a->g != b->g) return a->g - b->g;
  return a->h - b->h;
}

static int collect_groups(const vs_hinges *h, group *gr) {
  int n = 0;
  for (int k = 0; k < h->n_joints;) {
    if (h->side[k] == 0) {
      k++;
      continue;
    }
    int e = k;
    while (e + 1 < h->n_joints && h->side[e + 1] == h->side[k]) e++;
    gr[n++] = (group){.first = k + 1, .last = e + 1, .side = h->side[k], .hinge = -1};
    k = e + 1;
  }
  return n;
}

/* Give each group the nearest same-side hinge within the migration distance, nearest pairs
 * first, each hinge and each group used once: a hinge that moves keeps its identity even when
 * another group opens on its other side. */
static int match_groups(vs_hinges *h, group *gr, int ng) {
  pairing *p = malloc((size_t)(ng > 0 ? ng : 1) * (size_t)(h->count > 0 ? h->count : 1) * sizeof *p);
  if (p == NULL) return -1;
  int np = 0;
  for (int g = 0; g < ng; g++)
    for (int i = 0; i < h->count; i++) {
      const vs_hinge *hg = &h->h[i];
      if (hg->side != gr[g].side) continue;
      int d = interval_gap(gr[g].first, gr[g].last, hg->first, hg->last);
      if (d <= h->opts.migrate) p[np++] = (pairing){.g = g, .h = i, .closed = !hg->open, .dist = d};
    }
  qsort(p, (size_t)np, sizeof *p, cmp_pairing);
  for (int k = 0; k < np; k++)
    if (gr[p[k].g].hinge < 0 && !h->matched[p[k].h]) {
      gr[p[k].g].hinge = p[k].h;
      h->matched[p[k].h] = 1;
    }
  free(p);
  return 0;
}

/* Support displacement at which the group's largest opening (on its open edge) crossed the
 * threshold, by linear interpolation between the previous update and this one. */
static double onset_delta(const vs_hinges *h, const group *g, double delta,
                          const vs_joint_state *st) {
  if (!isfinite(h->delta_prev)) return delta;
  double now = -INFINITY, before = -INFINITY;
  for (int k = g->first - 1; k < g->last; k++) {
    /* a hinge at the intrados ('I') has its extrados edge open */
    now = fmax(now, g->side == 'I' ? st[k].gap_e : st[k].gap_i);
    before = fmax(before, g->side == 'I' ? h->gap_e[k] : h->gap_i[k]);
  }
  if (!(now > before)) return delta;
  const double f = fmin(fmax((h->opts.open - before) / (now - before), 0.0), 1.0);
  return h->delta_prev + f * (delta - h->delta_prev);
}

int vs_hinges_update(vs_hinges *h, double delta, const vs_joint_state *st) {
  for (int k = 0; k < h->n_joints; k++) h->side[k] = vs_hinges_joint_side(&h->opts, &st[k]);
  for (int i = 0; i < h->count; i++) h->matched[i] = 0;
  group *gr = malloc((size_t)h->n_joints * sizeof *gr);
  if (gr == NULL) return -1;
  const int ng = collect_groups(h, gr), before = h->count;
  int formed = 0;
  if (match_groups(h, gr, ng) != 0) {
    free(gr);
    return -1;
  }
  for (int g = 0; g < ng; g++) { /* left to right, so same-update hinges are ordered by place */
    int i = gr[g].hinge;
    if (i < 0) {
      if (grow(h) != 0) { /* no hinge is dropped without saying so */
        free(gr);
        return -1;
      }
      i = h->count++;
      vs_hinge *hg = &h->h[i];
      memset(hg, 0, sizeof *hg);
      hg->label = '?';
      hg->side = gr[g].side;
      hg->onset_first = gr[g].first;
      hg->onset_last = gr[g].last;
      hg->delta_onset = onset_delta(h, &gr[g], delta, st);
      hg->order = i + 1;
      h->matched[i] = 1;
      formed++;
    }
    vs_hinge *hg = &h->h[i];
    hg->first = gr[g].first;
    hg->last = gr[g].last;
    hg->open = 1;
    hg->delta_closed = NAN;
  }
  free(gr);
  for (int k = 0; k < h->n_joints; k++) {
    h->gap_i[k] = st[k].gap_i;
    h->gap_e[k] = st[k].gap_e;
  }
  h->delta_prev = delta;
  for (int i = 0; i < before; i++) {
    if (!h->matched[i] && h->h[i].open) {
      h->h[i].open = 0;
      h->h[i].delta_closed = delta;
    }
  }
  if (!h->named && h->count >= 3) label_first(h, 3);
  for (int i = before; h->named && i < h->count; i++)
    if (h->h[i].label == '?') h->h[i].label = vs_hinges_label(i);
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

void vs_hinges_side_pattern(const vs_hinge *h, int n, char *buf, size_t size) {
  size_t used = 0;
  if (size == 0) return;
  for (int i = 0; i < n; i++) {
    const size_t need = i + 1 < n ? 2 : 1; /* the side and, but after the last, a '-' */
    if (used + need >= size) break;      /* cut after the last '-' written */
    buf[used++] = h[i].side;
    if (i + 1 < n) buf[used++] = '-';
  }
  buf[used] = '\0';
}

/* "A:8-I" (sep: " " between entries), hinge hg's entry of a list, into buf; its length. */
static size_t list_entry(const vs_hinge *hg, const char *sep, char *buf, size_t size) {
  char name[96];
  vs_hinge_name(hg, 0, name, sizeof name);
  const int n = snprintf(buf, size, "%s%c:%s", sep, hg->label, name);
  return n > 0 ? (size_t)n : 0;
}

/* "+K more" for k hinges left out after `listed` ones, into buf; its length (0 for k = 0). */
static size_t list_more(int listed, int k, char *buf, size_t size) {
  if (k == 0) return 0;
  const int n = snprintf(buf, size, "%s+%d more", listed ? " " : "", k);
  return n > 0 ? (size_t)n : 0;
}

void vs_hinges_list(const vs_hinge *h, int n, int open_only, char *buf, size_t size) {
  if (size == 0) return;
  buf[0] = '\0';
  int total = 0;
  for (int i = 0; i < n; i++) total += !open_only || h[i].open;
  /* the most entries k that fit with the marker of the total - k left out */
  char tmp[128];
  size_t len = 0;
  int k = 0, fit = 0;
  for (int i = 0; i < n && len < size; i++) {
    if (open_only && !h[i].open) continue;
    len += list_entry(&h[i], k ? " " : "", tmp, sizeof tmp);
    k++;
    if (len + list_more(k, total - k, tmp, sizeof tmp) < size) fit = k;
  }
  size_t used = 0;
  for (int i = 0, listed = 0; i < n && listed < fit; i++) {
    if (open_only && !h[i].open) continue;
    used += list_entry(&h[i], listed++ ? " " : "", buf + used, size - used);
  }
  list_more(fit, total - fit, buf + used, size - used);
}

static int cmp_hinge_first(const void *x, const void *y) {
  const vs_hinge *a = x, *b = y;
  return (a->first > b->first) - (a->first < b->first);
}

void vs_hinges_pattern_first(const vs_hinges *h, char *buf, size_t size) {
  buf[0] = '\0';
  if (h->count < 3) return;
  vs_hinge abc[3];
  for (int i = 0; i < 3; i++) abc[i] = h->h[i];
  qsort(abc, 3, sizeof abc[0], cmp_hinge_first);
  vs_hinges_side_pattern(abc, 3, buf, size);
}

const char *vs_hinges_mode(const char *pattern_first, const char *pattern_collapse) {
  const char *p0 = pattern_first, *pu = pattern_collapse;
  if (strcmp(p0, "I-E-E") == 0 && strcmp(pu, "E-I-E-E") == 0) return "I";
  if (strcmp(p0, "I-E-E") == 0 && strcmp(pu, "E-I-E-I") == 0) return "II";
  if (strcmp(p0, "I-E-I") == 0 && (strcmp(pu, "E-I-E-I") == 0 || strcmp(pu, "E-I-E-I-E") == 0))
    return "III";
  return NULL;
}
