/* The joints evaluated at a state (model_internal.h): every body's half angle, kept until its
 * rotation changes; one joint's law at the block and support states; and the joints' points kept
 * for the Jacobian, residual and joints' states at the same states (struct vs_model_memo). */
#include "model_internal.h"

#include <string.h>

/* The half angle of body slot i at rotation theta into m->rot, unless it holds that of the same
 * rotation already (bit for bit): a Jacobian at the state of the last residual, the joints'
 * states at a converged equilibrium and the rotations a step leaves alone take no sincos. */
static void half_angle_of(const vs_model *m, int i, double theta) {
  if (memcmp(&m->rot_of[i], &theta, sizeof theta) == 0) return;
  vs_joint_half_angle(theta, m->rot + 2 * i);
  m->rot_of[i] = theta;
}

/* Every body's half angle at block states q and support states qs into m->rot (half_angle_of);
 * vs_model_eval_joint with rot = 1 then reads them. */
void vs_model_half_angles(const vs_model *m, const double *q, const double qs[6]) {
  const int nb = m->g->n_blocks;
  for (int i = 0; i < nb; i++) half_angle_of(m, i, q[3 * i + 2]);
  half_angle_of(m, nb, qs[2]);
  half_angle_of(m, nb + 1, qs[5]);
}

/* One joint at block states q and support states qs; rot: m->rot holds the half angles of this
 * state (vs_model_half_angles), else they are computed for the two bodies (a pass over a few
 * joints). */
void vs_model_eval_joint(const vs_model *m, const double *q, const double qs[6], int k, int rot,
                         vs_joint_state *st, double f[6], double K[36]) {
  const vs_joint_geom *j = &m->g->joints[k];
  double qa[3], qb[3], ha[2], hb[2];
  body_q(q, qs, j->a, qa);
  body_q(q, qs, j->b, qb);
  if (rot) {
    memcpy(ha, body_rot(m, j->a), sizeof ha);
    memcpy(hb, body_rot(m, j->b), sizeof hb);
  } else {
    vs_joint_half_angle(qa[2], ha);
    vs_joint_half_angle(qb[2], hb);
  }
  vs_joint_law tmp;
  vs_joint_eval_h(j, law_at(m, k, &tmp), qa, qb, ha, hb, m->ra + 2 * k, m->rb + 2 * k, m->slip_p[k],
                  st, f, K);
}

/* The memo holds the points at block states q and support states qs. */
int vs_model_memo_hit(const vs_model *m, const double *q, const double qs[6]) {
  const struct vs_model_memo *mm = m->memo;
  return mm->ok && memcmp(mm->qs, qs, sizeof mm->qs) == 0 &&
         memcmp(mm->q, q, 3 * (size_t)m->g->n_blocks * sizeof *q) == 0;
}

/* Joint k's point at (q, qs) into the memo (vs_model_half_angles done). */
void vs_model_memo_eval(const vs_model *m, const double *q, const double qs[6], int k) {
  const vs_joint_geom *j = &m->g->joints[k];
  double qa[3], qb[3];
  body_q(q, qs, j->a, qa);
  body_q(q, qs, j->b, qb);
  vs_joint_law tmp;
  vs_joint_point_eval(j, law_at(m, k, &tmp), qa, qb, body_rot(m, j->a), body_rot(m, j->b),
                      m->ra + 2 * k, m->rb + 2 * k, m->slip_p[k], &m->memo->pt[k]);
}

/* Evaluate every joint at (q, qs) into the memo (vs_model_half_angles done) and key it. */
void vs_model_memo_fill(const vs_model *m, const double *q, const double qs[6]) {
  struct vs_model_memo *mm = m->memo;
  for (int k = 0; k < m->g->n_joints; k++) vs_model_memo_eval(m, q, qs, k);
  memcpy(mm->q, q, 3 * (size_t)m->g->n_blocks * sizeof *q);
  memcpy(mm->qs, qs, sizeof mm->qs);
  mm->ok = 1;
}
