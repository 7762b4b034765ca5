/* Hinges: which joints are open, on which side, grouped into (possibly spread) hinges, tracked
 * as the support moves (onset, migration, closing) and labelled as docs/model.md ("Vocabulary")
 * defines. */
#ifndef VOUSSOIR_HINGES_H
#define VOUSSOIR_HINGES_H

#include "voussoir/api.h"

#include <stddef.h>

#include "voussoir/joint.h"
#include "voussoir/status.h"

typedef struct {
  double open;   /* edge opening (m) beyond which a joint counts as open */
  int migrate;   /* a same-side group within this many joints of a hinge is that hinge */
} vs_hinge_opts;

typedef struct {
  char label;            /* 'A'..'E' ('F'.. beyond: vs_hinges_label), '?' until three hinges
                            have formed (or vs_hinges_name_first) */
  char side;             /* 'I' intrados or 'E' extrados: the edge that stays in contact */
  int first, last;       /* current joints (1-based); last > first for a spread hinge */
  int onset_first, onset_last; /* joints when it formed */
  double delta_onset;    /* support displacement at onset, m: where the opening crossed the
                            threshold, interpolated linearly between consecutive updates */
  int order;             /* order of appearance, 1-based */
  int open;              /* 1 while open */
  double delta_closed;   /* support displacement at which it closed, m (NaN while open) */
} vs_hinge;

/* One hinge of the mechanism a motion turns about (docs/mortar.md, "The mode of a mortared
 * arch"): joints first..last (1-based) whose bodies turn relative to each other. */
typedef struct {
  int first, last;
  char side;     /* 'I' or 'E': the edge it turns about (that of its open joints, else the edge
                    its rate turns it about) */
  char label;    /* the tracked hinge (vs_hinge) it is, by side and place; 0 none */
  int open;      /* 1 when one of its joints is open (past the hinge threshold) */
  int closing;   /* 1 when it turns against its opening (it is closing) */
  double rate;   /* relative rotation rate summed over its joints, rad/s (> 0 counter-clockwise
                    of the body on the right) */
  double share;  /* |rate| over the largest hinge's */
} vs_active_hinge;

typedef struct vs_hinges vs_hinges;

/* Tracker for n_joints joints. */
VS_API vs_status vs_hinges_create(int n_joints, const vs_hinge_opts *opts, vs_hinges **out,
                                  vs_error *err);
VS_API void vs_hinges_destroy(vs_hinges **h);

/* Open side of one joint: 'I' (hinge at the intrados: the extrados opened), 'E', or 0 closed. */
VS_API char vs_hinges_joint_side(const vs_hinge_opts *opts, const vs_joint_state *st);

/* Classify every joint at support displacement delta (m) and update the hinges.
 * Returns the number of hinges that formed in this update, or -1 when out of memory. */
VS_API int vs_hinges_update(vs_hinges *h, double delta, const vs_joint_state *st);

/* Name the first n hinges (at most three) A, B, C from left to right and every later one by
 * its order of appearance (the fourth D, ...), replacing the labels they had. For a mechanism
 * that forms with fewer than three hinges (a pinned springer needs only two in the arch), or a
 * run that ends with fewer: n = the hinges formed by then, so that none stays '?' and none
 * formed later (in the fall) takes their letters. */
VS_API void vs_hinges_name_first(vs_hinges *h, int n);

/* The label of the hinge named i-th (0-based): 'A'..'Z', then 'a'..'z' (a fall can open more than
 * 26 hinges), then '#' for every later one; '?' for i < 0. One character, as the record stores it. */
VS_API char vs_hinges_label(int i);

/* Hinges in order of appearance: vs_hinges_get(h, i) for i in 0 .. vs_hinges_count(h) - 1, one
 * array (vs_hinges_get(h, 0) + i is hinge i), valid until the next vs_hinges_update; NULL for
 * an i outside. */
VS_API int vs_hinges_count(const vs_hinges *h);
VS_API const vs_hinge *vs_hinges_get(const vs_hinges *h, int i);

/* Number of hinges open now. */
VS_API int vs_hinges_open_count(const vs_hinges *h);

/* "9-I" or "44-45-46-I" for the current joints (onset = 0) or the onset joints (onset = 1). */
VS_API void vs_hinge_name(const vs_hinge *hg, int onset, char *buf, size_t size);

/* "A:8-I B:30-E C:56-E": the label and name (vs_hinge_name, current joints) of each of h[0..n),
 * or of the open ones only when open_only is 1, in the order given, into buf (size bytes,
 * NUL-ended). A list longer than size is never cut silently: as many hinges as fit, then
 * "+K more" (K the hinges left out). */
VS_API void vs_hinges_list(const vs_hinge *h, int n, int open_only, char *buf, size_t size);

/* The sides of h[0..n) in the order given, "I-E-E", into buf (size bytes, NUL-ended; 2 n bytes
 * hold any). A pattern longer than size is cut after a '-', so that it ends with '-', which a
 * whole pattern never does. */
VS_API void vs_hinges_side_pattern(const vs_hinge *h, int n, char *buf, size_t size);

/* The side pattern of the first three hinges to appear, left to right (by first joint), into
 * buf; "" while fewer than three have formed. */
VS_API void vs_hinges_pattern_first(const vs_hinges *h, char *buf, size_t size);

/* The mode (docs/model.md, "Vocabulary") from pattern_first (vs_hinges_pattern_first) and
 * pattern_collapse (the sides of the hinges open at the collapse, left to right): "I" for I-E-E then E-I-E-E, "II"
 * for I-E-E then E-I-E-I, "III" for I-E-I then E-I-E-I or E-I-E-I-E; NULL when they fit none. */
VS_API const char *vs_hinges_mode(const char *pattern_first, const char *pattern_collapse);

#endif
