/* Private to `voussoir plot` (plot_cmd.c, plot_record.c): a run's record as the arch pictures
 * read it and the hinges a picture labels. */
#ifndef VS_PLOT_CMD_H
#define VS_PLOT_CMD_H

#include <hdf5.h>
#include <math.h>
#include <stdio.h>

#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/limit.h"

typedef struct {
  char label, side;
  int first, last, onset_first, onset_last, order, during_fall, open;
  double delta_onset;
} rec_hinge;

typedef struct {
  hid_t file;
  vs_case c;
  vs_geometry *g;
  int rows, nb, nj;
  double *delta, *pos, *gap_i, *gap_e, *react, *jN, *jM;
  double *sup; /* rows x 6: both supports (/observables/supports); NULL in an older record */
  signed char *hinge; /* rows x nj: 0 closed, 1 intrados, 2 extrados */
  rec_hinge *h;
  int nh;
  double *limits, *settled;
  int nl;
  double collapse; /* m, NaN if none */
  double ground;   /* the ground the fall landed on, z in m; NaN if none */
  char msg[512];
  double *thick;   /* per voussoir thickness, m, when the case scatters it; else NULL */
  FILE *json;      /* plots.json: what each picture shows (NULL: not written) */
  int n_pictures;  /* entries written to json so far */
  vs_limit_force *loads; /* the live load of an analysis.type = load run (vs_limit_live_load) */
  int n_loads;
  char load_note[200]; /* what it is, for the pictures ("" without one) */
} vs_plotrec;

/* Which recorded hinges a picture labels, and where. */
typedef enum {
  PIC_ROW,      /* a state: the open groups of joints, each named after a recorded hinge */
  PIC_ONSET,    /* hinge `focus` forming: it at its onset joints, earlier ones as PIC_ROW */
  PIC_COLLAPSE  /* the collapse: the record's hinges open at its onset, at their joints then */
} pic_kind;

/* One state to draw: positions (3 nb), joint gaps, N, M (nj each), the support displacement,
 * the row whose open joints are labelled and how (pic_kind, the forming hinge). */
typedef struct {
  const double *pos, *gap_i, *gap_e, *N, *M;
  double delta;
  int hinge_row;
  pic_kind kind;
  int focus;
  const double *sup; /* both supports' (ux, uz, theta), left then right; NULL: not recorded */
} state;

/* Open the record at path and read what the pictures need: 0, or -1 with r->msg set (free r
 * with vs_plotrec_free either way). */
int vs_plotrec_open(const char *path, vs_plotrec *r);
void vs_plotrec_free(vs_plotrec *r);
/* First row at or after delta (the last row if none). */
int vs_plotrec_row_at(const vs_plotrec *r, double delta);
/* The hinges a picture of row `row` at delta labels (see plot_record.c) into out, which has room
 * for r->nh (each recorded hinge is labelled once at most): their count, or -1 when out of
 * memory. */
int vs_plotrec_hinges_at(const vs_plotrec *r, int row, double delta, pic_kind kind, int focus,
                         vs_hinge *out);
/* The recorded state of row `row`, labelled as PIC_ROW. */
state vs_plotrec_state(const vs_plotrec *r, int row);

/* A JSON number: v as %.9g, or null when it is not finite (JSON has no NaN nor infinity; a
 * record may hold them). */
static inline void vs_plot_json_num(FILE *f, double v) {
  if (isfinite(v)) fprintf(f, "%.9g", v);
  else fputs("null", f);
}

#endif
