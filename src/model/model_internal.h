/* Private to the model's sources (model*.c): the model's state, its CSC patterns and the memo of
 * the joints' points, where a body's coordinates are in the states, and the functions the files
 * share. Not installed. */
#ifndef VOUSSOIR_MODEL_INTERNAL_H
#define VOUSSOIR_MODEL_INTERNAL_H

#include <string.h>

#include "model_matrix.h"
#include "voussoir/model.h"
#include "voussoir/support.h"

/* A CSC pattern over the unknowns of a system: dof[3 slot + c] is the unknown of component c
 * (ux, uz, theta) of body slot (block i: slot i; left support: n_blocks, right: n_blocks + 1),
 * -1 where that component is prescribed. Per column, its rows are sorted. */
typedef struct {
  int n; /* unknowns */
  int *dof;
  sunindextype *colptr, *rowind;
  int nnz;
  sunindextype *scatter; /* per joint, 36: CSC position of K[6 i + j] (-1: prescribed) */
  int *jdof;             /* per joint, 6: the unknowns of its components (joint_dofs) */
  unsigned char *full;   /* per joint: all six are unknowns (none prescribed) */
} vs_pattern;

struct vs_model {
  const vs_geometry *g;
  vs_joint_law law;
  vs_joint_law *laws; /* per joint: the law (the nominal one unless an imperfection changed it) */
  vs_support_motion mo[2]; /* left, right: each support's motion in delta (support.h) */
  double offset[2]; /* initial offset of the right support, m (imperfections) */
  double mscale;    /* misfit factor: fraction of the face gaps and support offset applied */
  int n;           /* unknowns, 3 per block */
  double *ra, *rb; /* per joint: reference point of body a/b -> joint centre, m */
  double *slip_p;  /* per joint: committed plastic slip, m */
  double cracking; /* energy dissipated by the mortar's cracking, J (vs_model_cracking_energy) */
  double zeta;     /* damping ratio */
  double alpha_m;  /* mass-proportional damping coefficient (Rayleigh), 1/s */
  double beta_k;   /* stiffness-proportional damping coefficient (Rayleigh), s */
  int damped;      /* any joint dashpot coefficient > 0 */
  double gscale;   /* gravity load factor (1: the arch's own weight) */
  vs_model_force *loads; /* external dead forces (model_loads.c), n_loads of them ... */
  int n_loads;
  double lscale;         /* ... times this load factor (default 0) */
  vs_model_force *dead;  /* dead forces besides the weight (the fill's), n_dead, factor 1 */
  int n_dead;
  double *cn, *cs; /* per joint: damping coefficients, N s/m^3 */
  int pinned[2];   /* left, right: 1 if the support is pinned (its rotation free) */
  vs_pattern pat;  /* statics: the blocks' 3 n_blocks unknowns, then the pinned supports' rotations */
  struct vs_model_memo *memo; /* the joints' points at the last residual or joints' states */
  vs_pattern pate; /* with the two supports as bodies n_blocks (left) and n_blocks + 1 (right) */
  /* workspaces of one evaluation (written by the const functions: the pointers are the model's,
   * the contents scratch): every body's half angle (vs_joint_half_angle; slots as body_slot),
   * and damping forces over the extended unknowns; the rotation each half angle is of */
  double *rot, *fdw, *rot_of;
};

/* The joints' points (vs_joint_point) of the last static residual or joints' states, with the
 * block states and support states they are of: a Jacobian, residual or joints' states at the
 * same states (bit for bit) takes them instead of evaluating the joints again -- KINSOL's
 * Jacobian at the iterate its line search just evaluated, the scaled residual and the stability
 * test at a converged equilibrium. Whatever else the joints depend on (plastic slips, laws, the
 * misfit factor) drops it when it changes (memo_drop). Written by const functions: scratch. */
struct vs_model_memo {
  int ok;
  double *q, qs[6];   /* the blocks' (3 n_blocks) and the supports' states */
  vs_joint_point *pt; /* per joint */
};

static inline int body_is_block(int body) { return body >= 0; }

/* Where the (ux, uz, theta) of a body are -- or its velocities: a block's in q, a support's in qs
 * (left (ux, uz, theta), then right). */
static inline const double *body_ptr(const double *q, const double qs[6], int body) {
  return body >= 0 ? q + 3 * body : qs + (body == VS_SUPPORT_LEFT ? 0 : 3);
}

/* The (ux, uz, theta) of a body -- or its velocities: a block's from q, a support's from qs
 * (left (ux, uz, theta), then right). */
static inline void body_q(const double *q, const double qs[6], int body, double out[3]) {
  const double *src = body_is_block(body) ? q + 3 * body : qs + (body == VS_SUPPORT_LEFT ? 0 : 3);
  memcpy(out, src, 3 * sizeof(double));
}

/* Slot of a body in a pattern's dof map: a block's index, n_blocks (left), n_blocks + 1. */
static inline int body_slot(const vs_model *m, int body) {
  if (body_is_block(body)) return body;
  return m->g->n_blocks + (body == VS_SUPPORT_LEFT ? 0 : 1);
}

/* A body's half angle in m->rot (vs_model_half_angles). */
static inline const double *body_rot(const vs_model *m, int body) {
  return m->rot + 2 * body_slot(m, body);
}

/* The supports' states prescribed by delta: each one's motion (struct vs_model's mo) at delta; a
 * pinned support's rotation is the static unknown q[dof] (NULL q: zero). */
static inline void sup_state_q(const vs_model *m, const double *q, double delta, double qs[6]) {
  for (int s = 0; s < 2; s++) {
    vs_support_motion_at(&m->mo[s], delta, qs + 3 * s, NULL);
    const int d = m->pat.dof[3 * (m->g->n_blocks + s) + 2];
    if (d >= 0) qs[3 * s + 2] = q != NULL ? q[d] : 0.0;
  }
}

/* The supports' velocities at delta, given d(delta)/dt: each one's motion's rate times it; a
 * pinned support's rotation rate is v[dof] (NULL v: zero). */
static inline void sup_vel_q(const vs_model *m, const double *v, double delta, double ddelta_dt,
                             double vs[6]) {
  for (int s = 0; s < 2; s++) {
    vs_support_motion_at(&m->mo[s], delta, NULL, vs + 3 * s);
    for (int c = 0; c < 3; c++) vs[3 * s + c] *= ddelta_dt;
    const int d = m->pat.dof[3 * (m->g->n_blocks + s) + 2];
    if (d >= 0) vs[3 * s + 2] = v != NULL ? v[d] : 0.0;
  }
}

/* The supports' positions: sup_state_q and the right support's initial offset (an
 * imperfection, times the misfit factor); velocities do not have it. */
static inline void sup_pos_q(const vs_model *m, const double *q, double delta, double qs[6]) {
  sup_state_q(m, q, delta, qs);
  if (m->offset[0] != 0.0 || m->offset[1] != 0.0) {
    qs[3] += m->mscale * m->offset[0];
    qs[4] += m->mscale * m->offset[1];
  }
}

/* The law of joint k at the current misfit factor (vs_model_set_misfit_scale). */
static inline const vs_joint_law *law_at(const vs_model *m, int k, vs_joint_law *tmp) {
  const vs_joint_law *l = &m->laws[k];
  if (m->mscale == 1.0 || (l->gap0 == 0.0 && l->gap1 == 0.0)) return l;
  *tmp = *l;
  tmp->gap0 *= m->mscale;
  tmp->gap1 *= m->mscale;
  return tmp;
}

/* The memo no longer holds the joints' points (struct vs_model_memo). */
static inline void memo_drop(const vs_model *m) { m->memo->ok = 0; }

/* memo_out and scatter_joint run per joint in the assembly's loops: inline, as they were when
 * the model was one file (out of line they cost 0.4 % more instructions on the reference run). */

/* Joint k's outputs from the memo (as vs_model_eval_joint's at the memo's states). */
static inline void memo_out(const vs_model *m, int k, vs_joint_state *st, double f[6],
                            double K[36]) {
  vs_joint_law tmp;
  vs_joint_point_out(&m->g->joints[k], law_at(m, k, &tmp), &m->memo->pt[k], st, f, K);
}

/* Add joint k's 6x6 matrix (row-major, rows and columns (body a, body b)) into the CSC values
 * of p, through its scatter map (column by column, as the pattern). */
static inline void scatter_joint(const vs_pattern *p, int k, const double Kj[36], double *data) {
  const sunindextype *pos = p->scatter + 36 * k;
  for (int j = 0; j < 6; j++)
    for (int i = 0; i < 6; i++)
      if (pos[6 * i + j] >= 0) data[pos[6 * i + j]] += Kj[6 * i + j];
}

/* model_pattern.c: the CSC patterns, built once */
/* Dof maps and CSC patterns of m: statics (blocks, then the pinned supports' rotations) and the
 * extended system (blocks, then all six components of the two supports); VS_ERR_NOMEM. */
vs_status vs_model_build_patterns(vs_model *m, vs_error *err);
void vs_model_pattern_free(vs_pattern *p);
/* The unknowns of joint k's six components (body a's, then b's) in pattern p, -1 if prescribed. */
void vs_model_joint_dofs(const vs_model *m, const vs_pattern *p, int k, int d[6]);
/* Position in the CSC data of entry (row, col); the rows of a column are sorted. */
sunindextype vs_model_csc_pos(const vs_pattern *p, int row, int col);
/* Write the CSC pattern into A, zero its values and return them. */
double *vs_model_csc_reset(const vs_pattern *p, SUNMatrix A);

/* model_joints.c: the joints evaluated at a state */
/* Every body's half angle at block states q and support states qs into m->rot (each computed
 * only when its rotation changed); vs_model_eval_joint with rot = 1 then reads them. */
void vs_model_half_angles(const vs_model *m, const double *q, const double qs[6]);
/* One joint at block states q and support states qs; rot: m->rot holds the half angles of this
 * state (vs_model_half_angles), else they are computed for the two bodies (a pass over a few
 * joints). */
void vs_model_eval_joint(const vs_model *m, const double *q, const double qs[6], int k, int rot,
                         vs_joint_state *st, double f[6], double K[36]);
/* The memo holds the points at block states q and support states qs. */
int vs_model_memo_hit(const vs_model *m, const double *q, const double qs[6]);
/* Joint k's point at (q, qs) into the memo (half angles done). */
void vs_model_memo_eval(const vs_model *m, const double *q, const double qs[6], int k);
/* Evaluate every joint at (q, qs) into the memo (half angles done) and key it. */
void vs_model_memo_fill(const vs_model *m, const double *q, const double qs[6]);

/* model_loads.c: external forces */
/* The loads times the load factor over pattern p: G -= lambda f(q) (G may be NULL), and their
 * stiffness into the CSC values kdata (NULL: none). */
void vs_model_loads_add(const vs_model *m, const vs_pattern *p, const double *q, double *G,
                        double *kdata);
/* Their potential, -sum f . u of the dead loads and -lambda sum f . u of the live ones (J). */
double vs_model_load_energy(const vs_model *m, const double *q);

#endif
