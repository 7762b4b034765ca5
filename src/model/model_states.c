/* What the joints' states give at a state of the model (model.h): the states themselves, the
 * commit of their plastic slips, the support reactions and force, and the energies (elastic and
 * gravity), of the static unknowns and of the extended state. */
#include "joint_law.h"
#include "model_internal.h"

#include <string.h>

/* The joints' states at (q, qs); keep: through the memo (a static state: the Jacobian or
 * commit that follows at the same state takes them), else evaluated directly (the dynamic
 * phase's states, which never recur). */
static void joint_states_core(const vs_model *m, const double *q, const double qs[6],
                              vs_joint_state *st, int keep) {
  if (keep && vs_model_memo_hit(m, q, qs)) {
    for (int k = 0; k < m->g->n_joints; k++) memo_out(m, k, &st[k], NULL, NULL);
    return;
  }
  vs_model_half_angles(m, q, qs);
  if (keep) {
    vs_model_memo_fill(m, q, qs);
    for (int k = 0; k < m->g->n_joints; k++) memo_out(m, k, &st[k], NULL, NULL);
    return;
  }
  for (int k = 0; k < m->g->n_joints; k++)
    vs_model_eval_joint(m, q, qs, k, 1, &st[k], NULL, NULL);
}

void vs_model_joint_states(const vs_model *m, const double *q, double delta, vs_joint_state *st) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  joint_states_core(m, q, qs, st, 1);
}

/* A joint that slid is committed a hair behind its return-mapped plastic slip, by this fraction
 * of its elastic slip: at the committed state it then evaluates as sliding (its trial force past
 * the Coulomb limit by this fraction, its force still mu N), so that the tangent there, which
 * predicts the next increment and tests stability, is the sliding branch's, as the increment
 * that ended there was; committed exactly, the trial would sit on the limit and the tangent
 * would be the sticking one. The fraction is far above the round-off of the slip (a relative
 * 1e-16 of the joint's displacement) and far below the Newton tolerance. */
static const double VS_SLIP_HOLD = 1e-9;

/* A mortared joint's damage after the converged state st of joint k: its damage envelope and
 * cracks grown (the energy dissipated into m->cracking) and its cohesion's slip kept. Returns 1
 * when any changed (its point in the memo is then evaluated again). */
static int damage_commit(vs_model *m, int k, const vs_joint_state *st) {
  vs_joint_law *l = &m->laws[k];
  if (!(l->ft > 0.0 || l->c > 0.0)) return 0;
  const vs_joint_geom *j = &m->g->joints[k];
  /* the law's penetration and slope: the kinematic ones less the initial gap (law_at's) */
  const double a = st->a - m->mscale * l->gap0, w = st->w - m->mscale * l->gap1;
  const double before[3] = {l->crack[0], l->crack[1], l->kappa};
  const int env_n = l->env_n;
  double env_k[VS_JOINT_ENV_MAX];
  memcpy(env_k, l->env_k, sizeof env_k);
  m->cracking += vs_joint_damage_update(l, j->depth, j->length, a, w);
  l->kappa = st->kappa;
  return before[0] != l->crack[0] || before[1] != l->crack[1] || before[2] != l->kappa ||
         env_n != l->env_n || memcmp(env_k, l->env_k, sizeof env_k) != 0;
}

/* The plastic slips change. With the memo at these states, a joint whose slip moved is
 * evaluated again into it, so that it stays the joints' points (the joints' states of the
 * equilibrium just committed, which the hinge tracker reads next, are then taken from it);
 * otherwise the memo is dropped. */
static int commit_core(vs_model *m, const double *q, const double qs[6]) {
  int slid = 0, rot = 0;
  const int hit = vs_model_memo_hit(m, q, qs);
  if (!hit) vs_model_half_angles(m, q, qs);
  for (int k = 0; k < m->g->n_joints; k++) {
    vs_joint_state st;
    if (hit) memo_out(m, k, &st, NULL, NULL);
    else vs_model_eval_joint(m, q, qs, k, 1, &st, NULL, NULL);
    if (st.sliding && st.N > 0.0) slid++;
    const double old = m->slip_p[k];
    m->slip_p[k] = st.sliding ? st.slip_p - VS_SLIP_HOLD * (st.slip - st.slip_p) : st.slip_p;
    const int damaged = damage_commit(m, k, &st);
    if (!hit || (!damaged && memcmp(&old, &m->slip_p[k], sizeof old) == 0)) continue;
    if (!rot) vs_model_half_angles(m, q, qs), rot = 1; /* m->rot may hold another state's */
    vs_model_memo_eval(m, q, qs, k);
  }
  if (!hit) memo_drop(m);
  return slid;
}

int vs_model_commit(vs_model *m, const double *q, double delta) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  return commit_core(m, q, qs);
}

int vs_model_commit_states(vs_model *m, const vs_joint_state *st) {
  int slid = 0;
  memo_drop(m);
  for (int k = 0; k < m->g->n_joints; k++) {
    if (st[k].sliding && st[k].N > 0.0) slid++;
    m->slip_p[k] = st[k].slip_p;
    damage_commit(m, k, &st[k]);
  }
  return slid;
}

int vs_model_set_branches(vs_model *m, const double *q, double delta, const signed char *branch) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  vs_model_half_angles(m, q, qs);
  int put = 0;
  for (int k = 0; k < m->g->n_joints; k++) {
    if (branch[k] == VS_BRANCH_KEEP) continue;
    vs_joint_state st;
    vs_model_eval_joint(m, q, qs, k, 1, &st, NULL, NULL);
    const vs_joint_geom *j = &m->g->joints[k];
    vs_joint_law tmp;
    const vs_joint_law *law = law_at(m, k, &tmp);
    const double kst = law->ks * j->depth * j->length;
    /* the slip limit: mu N over k_s b t; a mortared joint's shear limit is c(kappa) A_c + mu N
     * (vs_joint_shear_mortar, its trial at the committed slip: the limit at the committed
     * kappa, the bonded length its cracks leave) */
    double limit = law->mu * st.N / kst;
    if (vs_joint_law_is_mortar(law)) { /* the law law_eval follows */
      vs_shear_response sr;
      vs_joint_shear_mortar(law, j->depth, j->length, law->crack, st.N, m->slip_p[k],
                            m->slip_p[k], law->kappa, &sr);
      limit = sr.limit / kst;
    }
    if (branch[k] == VS_BRANCH_STICK) {
      if (!st.sliding || !(limit > 0.0)) continue; /* inside the limit already */
      /* the trial just inside the limit: its force unchanged, the elastic tangent */
      m->slip_p[k] = st.slip - (st.T > 0.0 ? 1.0 : -1.0) * limit * (1.0 - VS_SLIP_HOLD);
    } else {
      /* past the limit by the commit's margin, and by a margin of the joint's length besides,
       * so that a joint without normal force (limit 0) is on its sliding branch too */
      const double over = limit * (1.0 + VS_SLIP_HOLD) + VS_SLIP_HOLD * j->length;
      m->slip_p[k] = st.slip - (branch[k] > 0 ? over : -over);
    }
    put++;
  }
  memo_drop(m);
  return put;
}

void vs_model_set_slips(vs_model *m, const double *slips) {
  memcpy(m->slip_p, slips, (size_t)m->g->n_joints * sizeof *slips);
  memo_drop(m);
}

void vs_model_reactions(const vs_model *m, const double *q, double delta, double left[2],
                        double right[2]) {
  /* the forces on the supports: the negated forces of the supports on the arch */
  double on_arch[6];
  vs_model_support_reactions(m, q, delta, on_arch);
  for (int c = 0; c < 2; c++) left[c] = -on_arch[c], right[c] = -on_arch[3 + c];
}

void vs_model_support_reactions(const vs_model *m, const double *q, double delta, double out[6]) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  memset(out, 0, 6 * sizeof *out);
  for (int k = 0; k < m->g->n_joints; k++) {
    const vs_joint_geom *j = &m->g->joints[k];
    if (body_is_block(j->a) && body_is_block(j->b)) continue; /* not at a support */
    double f[6];
    vs_model_eval_joint(m, q, qs, k, 0, NULL, f, NULL);
    /* f on a support's coordinates is dE/dq_support: the arch pulls the support with -f, the
     * support pushes the arch with +f */
    const int body[2] = {j->a, j->b};
    for (int s = 0; s < 2; s++)
      if (!body_is_block(body[s]))
        for (int c = 0; c < 3; c++) out[(body[s] == VS_SUPPORT_LEFT ? 0 : 3) + c] += f[3 * s + c];
  }
}

double vs_model_support_force(const vs_model *m, const double *q, double delta) {
  double f[6], rate[6], x = 0.0;
  vs_model_support_reactions(m, q, delta, f); /* what the supports exert on the arch */
  for (int s = 0; s < 2; s++) {
    vs_support_motion_at(&m->mo[s], delta, NULL, rate + 3 * s);
    if (m->pinned[s]) rate[3 * s + 2] = 0.0;
    for (int c = 0; c < 3; c++)
      if (rate[3 * s + c] != 0.0) x += f[3 * s + c] * rate[3 * s + c];
  }
  return x;
}

double vs_model_gravity_energy(const vs_model *m, const double *q) {
  const vs_geometry *g = m->g;
  double eg = 0.0;
  for (int i = 0; i < g->n_blocks; i++)
    eg += m->gscale * g->blocks[i].mass * g->gravity * q[3 * i + 1];
  return eg + vs_model_load_energy(m, q); /* and the external forces' (none by default) */
}

/* The elastic energy of the joints and the potential energy of gravity at (q, qs). */
static void energies_core(const vs_model *m, const double *q, const double qs[6], double *elastic,
                          double *gravity) {
  const vs_geometry *g = m->g;
  double ee = 0.0;
  const double eg = vs_model_gravity_energy(m, q);
  vs_model_half_angles(m, q, qs);
  for (int k = 0; k < g->n_joints; k++) {
    vs_joint_state st;
    vs_model_eval_joint(m, q, qs, k, 1, &st, NULL, NULL);
    ee += st.energy;
  }
  *elastic = ee;
  *gravity = eg;
}

void vs_model_energies(const vs_model *m, const double *q, double delta, double *elastic,
                       double *gravity) {
  double qs[6];
  sup_pos_q(m, q, delta, qs);
  energies_core(m, q, qs, elastic, gravity);
}

double vs_model_energy(const vs_model *m, const double *q, double delta) {
  double ee, eg;
  vs_model_energies(m, q, delta, &ee, &eg);
  return ee + eg;
}

/* --- the extended state qe = (blocks, left support, right support) --- */

void vs_model_ext_joint_states(const vs_model *m, const double *qe, vs_joint_state *st) {
  joint_states_core(m, qe, qe + 3 * m->g->n_blocks, st, 0);
}

int vs_model_ext_commit(vs_model *m, const double *qe) {
  return commit_core(m, qe, qe + 3 * m->g->n_blocks);
}

void vs_model_ext_energies(const vs_model *m, const double *qe, double *elastic, double *gravity) {
  energies_core(m, qe, qe + 3 * m->g->n_blocks, elastic, gravity);
}
