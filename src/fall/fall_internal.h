/* Private to the fall (fall.c: the time stepping and the impulses; fall_geom.c: the bodies'
 * outlines and joint faces, and the contacts found at a state). */
#ifndef VOUSSOIR_FALL_INTERNAL_H
#define VOUSSOIR_FALL_INTERNAL_H

#include <klu.h>

#include "voussoir/fall.h"
#include "voussoir/geometry.h"

/* A contact point for one step: vertex of body a against an edge (or joint face) of body b, or
 * the ground (b = -1). Rows J over (vx, vz, omega) of a and of b give the relative velocity of a
 * with respect to b at the point, normal then tangent. */
typedef struct {
  long long key;    /* identity from step to step (warm start): vertex, other body, edge */
  int a, b;         /* bodies (b = -1: the ground) */
  int joint;        /* joint of a face contact (0-based), -1 otherwise */
  double px, pz;    /* the point (the vertex), m */
  double n[2], t[2]; /* unit normal (from b towards a) and tangent t = n turned +90 degrees */
  double Ja[6], Jb[6]; /* normal row then tangential row, over a's and b's (vx, vz, omega) */
  double W[3];      /* Delassus block: nn, nt, tt (symmetric) */
  double Ka[6], Kb[6]; /* M^-1 J^T: a's and b's velocity change per unit impulse, as Ja, Jb
                          (0 for a driven support or the ground) */
  double gap;       /* signed gap at the step's start, m (< 0: overlap) */
  double bias;      /* normal law: u_n >= bias (fall.c: contact_law) */
  double iWnn;      /* 1 / W_nn */
  double iW[3];     /* W's inverse (nn, nt, tt) and, per sliding direction, the normal impulse */
  double slide[2][2]; /* per unit of its velocity deficit and the tangential one's ratio to it */
  double P[2];      /* impulse, normal and tangential, N s */
  double Ps[2];     /* NNCG (fall.c: solve_island): the impulse before the sweep ... */
  double Pd[2];     /* ... and the search direction, N s */
  double Pw;        /* normal pseudo-impulse of the overlaps' recovery, N s */
  double u0[2];     /* relative velocity at the step's start, m/s */
} vs_fall_contact;

/* A joint's faces as contact surfaces: the segment on each of its two bodies. */
typedef struct {
  int a, b;          /* bodies (supports: n_blocks, n_blocks + 1) */
  double ea[2][2];   /* the face's ends on a, from a's reference point (reference config.) */
  double eb[2][2];   /* ... on b */
  double na[2];      /* a's outward normal on it (reference configuration): the joint's n */
  double length;
  int vend[2][2];    /* the outline vertex at end e of body s's face (s 0: a, 1: b), or -1 */
  double fold_cos[2]; /* per end e: the cosine of the faces' turn from each other beyond which
                         the joint has folded there (fall_geom.c: VS_FALL_FOLD) */
} vs_fall_face;

struct vs_fall {
  vs_model *m;
  const vs_geometry *g;
  vs_fall_opts o;
  int n, nb, nv;          /* blocks, bodies (blocks and the two supports), vertices */
  int *first, *count;     /* per body: its vertices, counter-clockwise */
  int *body;              /* per vertex: its body */
  int *face_of;           /* per vertex: the joint whose face end it is (-1: none) */
  unsigned char *onface;  /* work: per vertex, 1 while a face contact of its joint holds it */
  double *rx, *rz;        /* per vertex: from its body's reference point, reference config. */
  double *n0x, *n0z;      /* per edge (numbered as its first vertex): outward unit normal */
  double *ref;            /* per body: reference point (x, z), reference configuration */
  double *minv;           /* per body: 1/m, 1/m, 1/I (supports: 0, they are driven) */
  double rmax;            /* largest distance of a vertex from its body's reference point, m */
  double *rmaxb;          /* ... per body */
  double *reach;          /* work: per body, how far its points can move in the step, m */
  vs_fall_face *faces;    /* per joint */
  int *adj_first, *adj_body, *adj_joint; /* per body b: its joints adj_first[b] .. adj_first[b
                                            + 1] - 1, each to body adj_body, joint adj_joint */
  /* the state: positions and velocities of every body (3 nb), the time */
  double *q, *v, *vk, *vs; /* vk: velocities at the step's start; vs: after a first solve */
  double *w;              /* work: the step's pseudo-velocities (overlaps' recovery), 3 nb */
  double t;
  double h;               /* the length of the step whose impulses the contacts and the warm
                             start hold (the last step's), s */
  double level;           /* the ground (NAN: none) */
  /* work at the current positions */
  double *px, *pz;        /* vertices */
  double *nx, *nz, *no;   /* edges: outward normal and n . (first vertex) */
  double *box;            /* per body: min x, max x, min z, max z */
  double *rot;            /* per body: cosine and sine of its rotation */
  int *order, *cand, ncand, candcap; /* bodies by their boxes' left ends; candidate pairs */
  /* contacts of this step, and the last step's impulses by contact key for the warm starts (a
   * hash table: fall.c, keep and warm) */
  vs_fall_contact *c;
  int nc, cap;
  /* the step's islands (fall.c: islands): bodies joined by contacts, which Gauss-Seidel solves
   * one at a time, each until its own bodies' velocities settle */
  int nisl;
  int *isl_first;         /* per island s: its contacts isl_c[isl_first[s] .. isl_first[s + 1]
                             - 1], in the order of f->c (nb + 1) */
  int *isl_bfirst;        /* ... its bodies isl_b[isl_bfirst[s] .. isl_bfirst[s + 1] - 1] */
  int *isl_c, iccap;      /* contacts by island (iccap: room) */
  int *isl_b, *isl_of;    /* bodies by island; work: per body, its root, then its island */
  long long *pkey;        /* per slot: a key, or none (fall.c: VS_FALL_NO_KEY) */
  double *pP;             /* per slot: its impulse (P_n, P_t) */
  int npc, pcap;          /* keys stored, slots (a power of two) */
  /* outputs at the current state */
  vs_joint_state *js;
  double react[6];
  double *qst, *vst;      /* the static state (vs_model_size) */
  double *jlo, *jhi;      /* work: per joint, the loaded face ends' extent along it */
  /* the joints' impulses solved together (fall_chain.c) */
  int chain;              /* 1 once set up */
  klu_common kc;
  klu_symbolic *Sym;      /* 3 unknowns per joint (two edges' P_n, one P_t): analysed once */
  klu_numeric *Num;
  int *Ap, *Ai;           /* the pattern (CSC, both triangles) */
  double *Ax, *rhs;       /* its values for the current statuses; right-hand side, solution */
  int *sc;                /* per joint edge (2 per joint): its contact in c, or -1 */
  int *sst;               /* ... 1 pressed, 0 open */
  int *ssign;             /* per joint: 0 sticking, or the sign of its friction when sliding */
  double *sp0;            /* per edge: the impulses (P_n, P_t) a solve started from (2 each) */
  double *vrest;          /* velocities without the edges' impulses */
  unsigned char *mask;    /* per unknown: held (not solved for) */
  double *sdiag, *sval;   /* W + eps I's diagonal; W's values in the pattern */
  double seps;            /* eps */
};

/* Is body b one the fall moves (a voussoir; not a driven support, not the ground, -1)? */
static inline int vs_fall_moving(const vs_fall *f, int b) { return b >= 0 && b < f->n; }

/* Relative velocity (normal, tangential) of contact c at the bodies' velocities v (3 nb). */
static inline void vs_fall_rel_velocity(const vs_fall_contact *c, const double *v, double u[2]) {
  const double *va = v + 3 * c->a;
  u[0] = c->Ja[0] * va[0] + c->Ja[1] * va[1] + c->Ja[2] * va[2];
  u[1] = c->Ja[3] * va[0] + c->Ja[4] * va[1] + c->Ja[5] * va[2];
  if (c->b >= 0) {
    const double *vb = v + 3 * c->b;
    u[0] += c->Jb[0] * vb[0] + c->Jb[1] * vb[1] + c->Jb[2] * vb[2];
    u[1] += c->Jb[3] * vb[0] + c->Jb[4] * vb[1] + c->Jb[5] * vb[2];
  }
}

/* Add to v (3 nb) the velocity change of impulse (pn, pt) of contact c; the driven supports and
 * the ground are left alone. */
static inline void vs_fall_apply(const vs_fall *f, const vs_fall_contact *c, double pn, double pt,
                                 double *v) {
  for (int s = 0; s < 2; s++) {
    const int b = s == 0 ? c->a : c->b;
    if (!vs_fall_moving(f, b)) continue;
    const double *J = s == 0 ? c->Ja : c->Jb, *mi = f->minv + 3 * b;
    for (int i = 0; i < 3; i++) v[3 * b + i] += mi[i] * (J[i] * pn + J[3 + i] * pt);
  }
}

/* fall_geom.c */
/* Outlines, reference points, masses, faces; VS_ERR_INVALID on a bad outline. */
vs_status vs_fall_geom_init(vs_fall *f, const int *count, const double *xz, vs_error *err);
void vs_fall_geom_free(vs_fall *f);
/* Vertices, edge normals and boxes at f->q. */
void vs_fall_positions(vs_fall *f);
/* The contacts at f->q that a step of h (s) at the velocities f->v, or v2 (NULL: none) if
 * faster, could close, into f->c (f->nc), each with its geometry, rows, Delassus block and gap
 * (bias and impulses are set by the caller). 0, or -1 when out of memory. */
int vs_fall_find_contacts(vs_fall *f, double h, const double *v2);
/* Largest overlap at f->q (after vs_fall_positions): of a vertex into another body that shares
 * no joint with it, and of a face end behind its joint's other face (m; 0 when none). */
void vs_fall_overlaps(vs_fall *f, double *bodies, double *joints);

/* fall_chain.c */
/* Solves for the joints' impulses per call at most. */
#define VS_FALL_CHAIN_SOLVES 8
/* Set up the joints' system (its pattern analysed once). 0, or -1 when out of memory. */
int vs_fall_chain_init(vs_fall *f);
void vs_fall_chain_free(vs_fall *f);
/* Solve the impulses of the joint contacts among f->c together, the others' held (f->v holds
 * every impulse before and after). tolv (m/s): an open edge approaching faster than this is
 * pressed, and the statuses settle once no correction exceeds it as a velocity. Returns 0 when
 * they settled, 1 when they had not after VS_FALL_CHAIN_SOLVES solves (the impulses it started
 * from are then left), -1 when KLU failed; *solves += the solves. */
int vs_fall_chain_solve(vs_fall *f, double mu, double tolv, int *solves);

/* fall_state.c: the bodies' state in the model's coordinates (qst, vst: a pinned support's
 * rotation where the model has it) for the record. */
void vs_fall_static_state(vs_fall *f);

#endif
