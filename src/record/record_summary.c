/* The record's /summary, written when the run is finished: limit points, first limit point,
 * collapse, hinges, mode, solver totals, damping and modes, the ground of the fall. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#include "record_internal.h"
#include "voussoir/damping.h"
#include "voussoir/limit.h"
#include "voussoir/support.h"
#include "voussoir/units.h"

typedef struct {
  char label, side;
  const char *name, *name_onset;
  int32_t first, last, onset_first, onset_last;
  double delta_onset, time_onset;
  int32_t order;
  int8_t open;
  double delta_closed;
  int8_t during_fall;
} hinge_row;

static const char HINGE_UNITS[] = ",,,,,,,,m,s,,,m,";

static hid_t hinge_mtype(void) {
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(hinge_row)), c1 = vs_h5_fixed_str_type(1),
        vs = vs_h5_vlstr_type();
  herr_t rc = (t >= 0 && c1 >= 0 && vs >= 0) ? 0 : -1;
#define INS(field, type) \
  if (rc >= 0) rc = H5Tinsert(t, #field, HOFFSET(hinge_row, field), type)
  INS(label, c1);
  INS(side, c1);
  INS(name, vs);
  INS(name_onset, vs);
  INS(first, H5T_NATIVE_INT32);
  INS(last, H5T_NATIVE_INT32);
  INS(onset_first, H5T_NATIVE_INT32);
  INS(onset_last, H5T_NATIVE_INT32);
  INS(delta_onset, H5T_NATIVE_DOUBLE);
  INS(time_onset, H5T_NATIVE_DOUBLE);
  INS(order, H5T_NATIVE_INT32);
  INS(open, H5T_NATIVE_INT8);
  INS(delta_closed, H5T_NATIVE_DOUBLE);
  INS(during_fall, H5T_NATIVE_INT8);
#undef INS
  vs_h5_close(c1);
  vs_h5_close(vs);
  if (rc < 0) vs_h5_close(t);
  return rc < 0 ? H5I_INVALID_HID : t;
}

/* A compound table: memory type mt, packed in the file, with unit and description. */
static herr_t table_write(hid_t loc, const char *name, hid_t mt, size_t n, const void *rows,
                          const char *unit, const char *description) {
  hid_t ft = H5Tcopy(mt);
  hsize_t dims[1] = {n};
  herr_t rc = ft >= 0 ? H5Tpack(ft) : -1;
  hid_t sp = H5Screate_simple(1, dims, NULL);
  hid_t d = (rc >= 0 && sp >= 0)
                ? H5Dcreate2(loc, name, ft, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)
                : H5I_INVALID_HID;
  rc = d >= 0 ? 0 : -1;
  if (rc >= 0 && n > 0) rc = H5Dwrite(d, mt, H5S_ALL, H5S_ALL, H5P_DEFAULT, rows);
  if (rc >= 0) rc = vs_h5_attr_str(d, "unit", unit);
  if (rc >= 0) rc = vs_h5_attr_str(d, "description", description);
  vs_h5_close(d);
  vs_h5_close(sp);
  vs_h5_close(ft);
  return rc;
}

/* Hinge table name of hinges h[0..n); during_fall from index fall_from on. */
static herr_t hinge_table(hid_t loc, const char *name, const vs_hinge *h, int n, int fall_from,
                          double rate, const char *description) {
  typedef char name_buf[96];
  hinge_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  name_buf *names = calloc((size_t)(n > 0 ? n : 1), 2 * sizeof *names);
  hid_t mt = hinge_mtype();
  herr_t rc = (rows != NULL && names != NULL && mt >= 0) ? 0 : -1;
  for (int i = 0; rc >= 0 && i < n; i++) {
    vs_hinge_name(&h[i], 0, names[2 * i], sizeof names[0]);
    vs_hinge_name(&h[i], 1, names[2 * i + 1], sizeof names[0]);
    rows[i] = (hinge_row){.label = h[i].label,
                          .side = h[i].side,
                          .name = names[2 * i],
                          .name_onset = names[2 * i + 1],
                          .first = h[i].first,
                          .last = h[i].last,
                          .onset_first = h[i].onset_first,
                          .onset_last = h[i].onset_last,
                          .delta_onset = h[i].delta_onset,
                          .time_onset = h[i].delta_onset / rate,
                          .order = h[i].order,
                          .open = (int8_t)h[i].open,
                          .delta_closed = h[i].delta_closed,
                          .during_fall = (int8_t)(i >= fall_from)};
  }
  if (rc >= 0) rc = table_write(loc, name, mt, (size_t)n, rows, HINGE_UNITS, description);
  vs_h5_close(mt);
  free(rows);
  free(names);
  return rc;
}

typedef struct {
  double delta;
  const char *kind;
  double delta_settled;
  const char *hinges_before, *hinges_after;
} limit_row;

static herr_t limits_table(hid_t loc, const vs_run *run) {
  const int n = vs_run_limit_count(run);
  limit_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(limit_row)), vs = vs_h5_vlstr_type();
  herr_t rc = (rows != NULL && mt >= 0 && vs >= 0) ? 0 : -1;
  if (rc >= 0) rc = H5Tinsert(mt, "delta", HOFFSET(limit_row, delta), H5T_NATIVE_DOUBLE);
  if (rc >= 0) rc = H5Tinsert(mt, "kind", HOFFSET(limit_row, kind), vs);
  if (rc >= 0)
    rc = H5Tinsert(mt, "delta_settled", HOFFSET(limit_row, delta_settled), H5T_NATIVE_DOUBLE);
  if (rc >= 0) rc = H5Tinsert(mt, "hinges_before", HOFFSET(limit_row, hinges_before), vs);
  if (rc >= 0) rc = H5Tinsert(mt, "hinges_after", HOFFSET(limit_row, hinges_after), vs);
  for (int i = 0; rc >= 0 && i < n; i++) {
    const vs_limit_record *l = vs_run_limit(run, i);
    rows[i] = (limit_row){.delta = l->delta,
                          .delta_settled = l->delta_settled,
                          .kind = l->collapse                  ? "collapse"
                                  : isfinite(l->delta_settled) ? "snap"
                                                               : "unfollowed",
                          .hinges_before = l->hinges_before,
                          .hinges_after = l->hinges_after};
  }
  if (rc >= 0)
    rc = table_write(loc, "limit_points", mt, (size_t)n, rows, "m,,m,,",
                     "limit points of the quasi-static path in order; kind: snap (the motion "
                     "settled at delta_settled), collapse, unfollowed (dynamic.follow = 0)");
  vs_h5_close(vs);
  vs_h5_close(mt);
  free(rows);
  return rc;
}

/* The collapse's slips (vs_slip): joint, side (the direction), slip (m). */
static herr_t slips_table(hid_t loc, const vs_collapse_record *c) {
  typedef struct {
    int32_t joint;
    char side;
    double slip;
  } slip_row;
  const int n = c->found ? c->n_slips : 0;
  slip_row *rows = calloc((size_t)(n > 0 ? n : 1), sizeof *rows);
  hid_t mt = H5Tcreate(H5T_COMPOUND, sizeof(slip_row)), c1 = vs_h5_fixed_str_type(1);
  herr_t rc = (rows != NULL && mt >= 0 && c1 >= 0) ? 0 : -1;
  if (rc >= 0) rc = H5Tinsert(mt, "joint", HOFFSET(slip_row, joint), H5T_NATIVE_INT32);
  if (rc >= 0) rc = H5Tinsert(mt, "side", HOFFSET(slip_row, side), c1);
  if (rc >= 0) rc = H5Tinsert(mt, "slip", HOFFSET(slip_row, slip), H5T_NATIVE_DOUBLE);
  for (int i = 0; rc >= 0 && i < n; i++)
    rows[i] = (slip_row){.joint = c->slips[i].joint, .side = c->slips[i].side,
                         .slip = c->slips[i].slip};
  if (rc >= 0)
    rc = table_write(loc, "slips", mt, (size_t)n, rows, ",,m",
                     "joints that slid in the collapse's mechanism, left to right: side = the "
                     "edge toward which the voussoir slid relative to the body across the joint, "
                     "slip = how far, from the departure to the collapse's onset");
  vs_h5_close(c1);
  vs_h5_close(mt);
  free(rows);
  return rc;
}

static herr_t summary_collapse(hid_t sum, const vs_run *run) {
  const vs_collapse_record *c = vs_run_collapse(run);
  const vs_case *cs = vs_run_case(run);
  const double L = vs_run_geometry(run)->span;
  const vs_support_dir sd = vs_support_direction(cs->alpha_deg * VS_DEG);
  const double rate = cs->rate_mm_s * VS_MM;
  hid_t g = vs_h5_group_create(sum, "collapse");
  herr_t rc = g >= 0 ? vs_h5_attr_int(g, "found", c->found) : -1;
  if (rc >= 0) rc = vs_h5_attr_str(g, "pattern", vs_run_pattern_collapse(run));
  if (rc >= 0) rc = vs_h5_attr_str(g, "mechanism", c->found ? c->mechanism : "");
  if (rc >= 0) rc = slips_table(g, c);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "delta", c->found ? c->delta : NAN, "m");
  if (rc >= 0)
    rc = vs_h5_dset_scalar(g, "dz_over_L", c->found ? c->delta * sd.dz / L : NAN, "1");
  if (rc >= 0)
    rc = vs_h5_dset_scalar(g, "dx_over_L", c->found ? c->delta * sd.dx / L : NAN, "1");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "time", c->found ? c->t : NAN, "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "delta_detected", c->found ? c->delta_detected : NAN, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "time_detected", c->found ? c->t_criterion : NAN, "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "time_onset", c->found ? c->t_onset : NAN, "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "delta_onset", c->found ? c->t_onset * rate : NAN, "m");
  if (rc >= 0)
    rc = hinge_table(g, "hinges", c->hinges, c->found ? c->n_hinges : 0, 1 << 30, rate,
                     "hinges open at the collapse's onset, left to right");
  if (rc >= 0)
    rc = vs_h5_attr_str(
        g, "description",
        "collapse: delta (delta_u) is the support displacement at which the arch "
        "departs from its last stable equilibrium: the collapsing limit point, or "
        "with --dynamic the kinetic energy's last rise through the rest level (an "
        "IDA root); delta_detected when the kinetic energy passed the collapse "
        "threshold; time_onset when the final motion began (NaN if the arch was never "
        "at rest); NaN everywhere when found = 0. mechanism: rotational (hinges alone), "
        "sliding (slips alone) or mixed; for a sliding mechanism that the support drives "
        "(the force on it stationary while joints slide) delta is where they all slid, "
        "delta_detected where the force was seen stationary, and no motion follows");
  vs_h5_close(g);
  return rc;
}

static herr_t summary_first_limit(hid_t sum, const vs_run *run) {
  const vs_path_result *p = vs_run_path(run);
  const int found = p->end == VS_PATH_LIMIT_POINT && vs_run_limit_count(run) > 0;
  hid_t g = vs_h5_group_create(sum, "first_limit");
  herr_t rc = g >= 0 ? vs_h5_attr_int(g, "found", found) : -1;
  if (rc >= 0) rc = vs_h5_attr_int(g, "det_sign", found ? p->evidence.det_sign : 0);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "delta", found ? p->delta_limit : NAN, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "delta_fail", found ? p->delta_fail : NAN, "m");
  if (rc >= 0)
    rc = vs_h5_dset_scalar(g, "lambda_start", found ? p->evidence.lambda_start : NAN, "N/m");
  if (rc >= 0)
    rc = vs_h5_dset_scalar(g, "lambda_last", found ? p->evidence.lambda_last : NAN, "N/m");
  if (rc >= 0)
    rc = vs_h5_dset_scalar(g, "delta_extrapolated", found ? p->evidence.delta_extrap : NAN, "m");
  vs_h5_close(g);
  return rc;
}

static herr_t summary_totals(hid_t sum, const vs_run *run) {
  const vs_path_result *p = vs_run_path_totals(run);
  const vs_dyn_result *d = vs_run_dynamic_totals(run);
  hid_t g = vs_h5_group_create(sum, "quasistatic");
  herr_t rc = g >= 0 ? vs_h5_attr_int(g, "steps", p->steps) : -1;
  if (rc >= 0) rc = vs_h5_attr_int(g, "rejected", p->rejected);
  if (rc >= 0) rc = vs_h5_attr_int(g, "newton_iterations", p->newton_iterations);
  if (rc >= 0) rc = vs_h5_attr_int(g, "jacobian_evals", p->jacobian_evals);
  if (rc >= 0) rc = vs_h5_attr_int(g, "floor_limited", p->floor_limited);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "max_residual", p->max_residual, "1");
  vs_h5_close(g);
  g = rc >= 0 ? vs_h5_group_create(sum, "dynamic") : H5I_INVALID_HID;
  rc = g >= 0 ? vs_h5_attr_int(g, "steps", d->steps) : -1;
  if (rc >= 0) rc = vs_h5_attr_int(g, "newton_iterations", d->newton_iterations);
  if (rc >= 0) rc = vs_h5_attr_int(g, "root_events", d->root_events);
  if (rc >= 0) rc = vs_h5_attr_int(g, "jacobian_evals", d->jac_evals);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "max_kinetic", d->max_kinetic, "J");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "balance_error_rel", d->balance_error_rel, "1");
  if (rc >= 0)
    rc = vs_h5_attr_str(
        g, "description",
        "totals of all dynamic phases; balance_error_rel: the worst |energy balance| "
        "relative to the largest energy term");
  vs_h5_close(g);
  return rc;
}

/* /summary/damping: the model and the natural frequencies under self-weight with the damping
 * ratio the model gives each mode. */
static herr_t summary_damping(hid_t sum, const vs_run *run) {
  const vs_case *c = vs_run_case(run);
  const vs_modal *md = vs_run_modal(run);
  double alpha, beta, col[3][VS_MODAL_MAX];
  vs_run_rayleigh(run, &alpha, &beta);
  hid_t g = vs_h5_group_create(sum, "damping");
  herr_t rc =
      g >= 0 ? vs_h5_attr_str(g, "model", vs_damping_model_name((vs_damping_model)c->damping_model))
             : -1;
  if (rc >= 0) rc = vs_h5_attr_double(g, "ratio", c->damping);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "rayleigh_alpha", alpha, "1/s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "rayleigh_beta", beta, "s");
  if (rc >= 0) rc = vs_h5_attr_int(g, "impacts", vs_run_dynamic_totals(run)->impacts);
  for (int i = 0; i < md->n_modes; i++) {
    col[0][i] = md->freq_hz[i];
    col[1][i] = md->omega[i];
    col[2][i] = md->zeta[i];
  }
  const hsize_t dims[1] = {(hsize_t)md->n_modes};
  if (rc >= 0)
    rc =
        vs_h5_dset_write(g, "freq", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[0], "Hz", NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(g, "omega", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[1], "rad/s",
                          NULL);
  if (rc >= 0)
    rc = vs_h5_dset_write(g, "damping_ratio", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, dims, col[2],
                          "1", NULL);
  if (rc >= 0)
    rc = vs_h5_attr_str(
        g, "description",
        "the lowest natural modes about the self-weight equilibrium (tangent stiffness, "
        "block masses) and the damping ratio phi^T C phi / (2 omega) the damping model "
        "gives each; empty when not computed (more than 5000 voussoirs)");
  vs_h5_close(g);
  return rc;
}

/* /summary/ground, when the fall landed on the ground (contact.h): its level, a segment of it
 * for the pictures and the sidecar (two span widths, centred on the arch), the penetrations and
 * whether the debris came to rest, and the fall's cost. */
static herr_t summary_ground(hid_t sum, const vs_run *run) {
  const double z = vs_run_ground(run), L = vs_run_geometry(run)->span;
  if (!isfinite(z)) return 0;
  const vs_dyn_result *d = vs_run_dynamic_totals(run);
  const double pts[4] = {-L, z, L, z};
  const hsize_t dims[2] = {2, 2};
  hid_t g = vs_h5_group_create(sum, "ground");
  herr_t rc = g >= 0 ? vs_h5_dset_scalar(g, "level", z, "m") : -1;
  if (rc >= 0)
    rc = vs_h5_dset_write(g, "points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dims, pts, "m,m",
                          "x,z");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "penetration_final", vs_run_penetration(run), "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "penetration_max", d->max_penetration, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "overlap_max", d->max_overlap, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "rest_level", vs_run_rest_ke(run), "J");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "fall_wall_time", d->fall_wall_s, "s");
  if (rc >= 0) rc = vs_h5_attr_int(g, "at_rest", d->fall_at_rest);
  if (rc >= 0)
    rc = vs_h5_attr_str(
        g, "description",
        "the ground the collapsed arch fell onto (z up, the geometry's frame): level; "
        "points, a segment of it; penetration_final, the deepest block vertex below it "
        "at the last state (< 0: none touches), penetration_max over the fall; overlap_max, "
        "the deepest vertex inside another block or a pier over the fall; rest_level, the "
        "kinetic energy the debris stays below for the rest window to be at rest; at_rest "
        "= 1 if the fall ended with the debris at rest; fall_wall_time, its cost");
  vs_h5_close(g);
  return rc;
}

/* /summary/fall, when the rigid fall (fall.h) followed the collapse: its scheme, step, solver
 * work and how well it held (overlaps, energy balance), and its cost. */
static herr_t summary_fall(hid_t sum, const vs_run *run) {
  const vs_fall_result *fr = vs_run_fall(run);
  if (fr == NULL) return 0;
  hid_t g = vs_h5_group_create(sum, "fall");
  herr_t rc = g >= 0 ? vs_h5_attr_str(g, "scheme", "rigid") : -1;
  if (rc >= 0) rc = vs_h5_attr_str(g, "solver", vs_fall_solver_name(fr->solver));
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "step", fr->step, "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "slow_step", fr->slow_step, "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "duration", fr->t_end - vs_run_collapse(run)->t_criterion, "s");
  if (rc >= 0) rc = vs_h5_attr_int(g, "steps", fr->steps);
  if (rc >= 0) rc = vs_h5_attr_int(g, "chain_steps", fr->chain_steps);
  if (rc >= 0) rc = vs_h5_attr_int(g, "chain_solves", fr->solves);
  if (rc >= 0) rc = vs_h5_attr_int(g, "sweeps", fr->sweeps);
  if (rc >= 0) rc = vs_h5_attr_int(g, "max_sweeps", fr->cap);
  if (rc >= 0) rc = vs_h5_attr_int(g, "capped_steps", fr->unconverged);
  if (rc >= 0) rc = vs_h5_attr_int(g, "calm_steps", fr->calm_steps);
  if (rc >= 0) rc = vs_h5_attr_int(g, "slow_steps", fr->slow_steps);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "last_change_max", fr->residual, "m/s");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "overlap_max", fr->max_overlap, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "joint_overlap_max", fr->max_joint_overlap, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "released", fr->released, "J");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "recovered", fr->recovered, "J");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "balance_error_rel", fr->balance_error_rel, "1");
  if (rc >= 0)
    rc = vs_h5_attr_str(
        g, "description",
        "the fall after the collapse as rigid blocks with impulsive contacts (fall.h): step, "
        "slow_step (while no point of a block moves faster than fall.slow_mm_s), duration (to "
        "rest or fall_s); steps, of which slow_steps of slow_step, chain_steps had only joint "
        "contacts and were solved at once (chain_solves solves), calm_steps were near rest and "
        "solved to a tenth of the tolerance; solver, how the impulses were solved (nncg: "
        "Gauss-Seidel sweeps each followed by a nonsmooth conjugate gradient step; "
        "gauss_seidel: the sweeps alone); sweeps (each island of bodies joined "
        "by contacts solved on its own: a step's sweeps are those of the island that took the "
        "most), capped_steps had an island stop at the cap (max_sweeps), with the largest "
        "last-sweep velocity change last_change_max; "
        "overlap_max of a vertex into another block or a pier, joint_overlap_max of a face end "
        "behind its joint's other face; released, the joints' elastic energy at the switch; "
        "recovered, the work of the overlaps' recovery against gravity; balance_error_rel, the "
        "scheme's energy balance");
  vs_h5_close(g);
  return rc;
}

/* /summary/load/forces: the live load as the run applied it (vs_limit_live_load), one row per
 * force at lambda = 1: block (0-based), fx, fz (N), px, pz (m, the reference configuration). */
static herr_t load_forces(hid_t g, const vs_run *run) {
  vs_limit_force *lf = NULL;
  int n = 0;
  vs_error err;
  vs_error_clear(&err);
  const vs_run_def *rd = vs_run_def_of(run);
  if (vs_limit_live_load(vs_run_geometry(run), &rd->load, &rd->fill, &lf, &n, &err) != VS_OK)
    return -1;
  double *v = calloc(5 * (size_t)(n > 0 ? n : 1), sizeof *v);
  herr_t rc = v != NULL ? 0 : -1;
  for (int i = 0; rc >= 0 && i < n; i++) {
    const double row[5] = {lf[i].block, lf[i].fx, lf[i].fz, lf[i].px, lf[i].pz};
    for (int c = 0; c < 5; c++) v[5 * i + c] = row[c];
  }
  const hsize_t dims[2] = {(hsize_t)n, 5};
  if (rc >= 0)
    rc = vs_h5_dset_write(g, "forces", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dims, v,
                          "1,N,N,m,m", "block,fx,fz,px,pz");
  free(v);
  free(lf);
  return rc;
}

/* analysis.type = load: /summary/load, the load factor, the first peak, the mechanism and the
 * load-deflection curve (vs_run_load). Nothing for the other analyses. */
static herr_t summary_load(hid_t sum, const vs_run *run) {
  const vs_run_load_result *l = vs_run_load(run);
  if (!l->done) return 0;
  static const char *const ENDS[] = {"none", "peak", "sliding", "max_displacement", "stalled"};
  const char *end = l->held_limit ? "held_limit"
                    : l->end >= 0 && l->end <= 4 ? ENDS[l->end]
                                                 : "?";
  hid_t g = vs_h5_group_create(sum, "load");
  herr_t rc = g >= 0 ? vs_h5_attr_str(g, "end", end) : -1;
  if (rc >= 0) rc = vs_h5_attr_str(g, "mechanism", l->mechanism);
  if (rc >= 0) rc = vs_h5_attr_str(g, "cause", l->cause);
  if (rc >= 0) rc = vs_h5_attr_int(g, "snap_back", l->snap_back);
  if (rc >= 0) rc = vs_h5_attr_int(g, "settled", l->settled);
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "load_factor", l->load_factor, "1");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "first_peak", l->first_peak, "1");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "deflection", l->deflection, "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(g, "hold", l->hold, "m");
  double *c = calloc(2 * (size_t)(l->n > 0 ? l->n : 1), sizeof *c);
  if (c == NULL) rc = -1;
  for (int i = 0; rc >= 0 && i < l->n; i++) {
    c[2 * i] = l->lambda[i];
    c[2 * i + 1] = l->u[i];
  }
  const hsize_t dims[2] = {(hsize_t)l->n, 2};
  if (rc >= 0)
    rc = vs_h5_dset_write(g, "curve", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dims, c, "1,m",
                          "load_factor,deflection");
  free(c);
  if (rc >= 0) rc = load_forces(g, run);
  vs_h5_close(g);
  return rc;
}

vs_status vs_record_summary_write(vs_output *o, const vs_run *run) {
  hid_t sum = H5Gopen2(o->file, "summary", H5P_DEFAULT);
  const char *mode = vs_run_mode(run);
  char open[512];
  vs_run_open_hinges(run, open, sizeof open);
  herr_t rc = sum >= 0 ? vs_h5_attr_str(sum, "mode", mode != NULL ? mode : "") : -1;
  if (rc >= 0) rc = vs_h5_attr_str(sum, "pattern_initial", vs_run_pattern_initial(run));
  if (rc >= 0) rc = vs_h5_attr_str(sum, "pattern_collapse", vs_run_pattern_collapse(run));
  if (rc >= 0) rc = vs_h5_attr_str(sum, "open_hinges", open);
  if (rc >= 0 && vs_run_mechanism_count(run) > 0) { /* a mortared arch's (docs/mortar.md) */
    rc = vs_h5_attr_str(sum, "pattern_turning", vs_run_pattern_mechanism(run));
    if (rc >= 0)
      rc = vs_h5_attr_str(sum, "mode_from", vs_run_mode_from_mechanism(run) ? "turning" : "onset");
  }
  if (rc >= 0) rc = vs_h5_attr_int(sum, "rows", o->rows);
  if (rc >= 0) rc = vs_h5_attr_int(sum, "events", o->n_events);
  if (rc >= 0) rc = vs_h5_dset_scalar(sum, "delta_final", vs_run_delta(run), "m");
  if (rc >= 0) rc = vs_h5_dset_scalar(sum, "time_final", vs_run_time(run), "s");
  if (rc >= 0) rc = vs_h5_dset_scalar(sum, "wall_time", vs_run_wall_s(run), "s");
  if (rc >= 0) rc = limits_table(sum, run);
  if (rc >= 0) rc = summary_first_limit(sum, run);
  if (rc >= 0) rc = summary_collapse(sum, run);
  if (rc >= 0) rc = summary_totals(sum, run);
  if (rc >= 0) rc = summary_damping(sum, run);
  if (rc >= 0) rc = summary_ground(sum, run);
  if (rc >= 0) rc = summary_fall(sum, run);
  if (rc >= 0) rc = summary_load(sum, run);
  const vs_hinges *h = vs_run_hinges(run);
  const int n = vs_hinges_count(h);
  vs_hinge *all = calloc((size_t)(n > 0 ? n : 1), sizeof *all);
  if (all == NULL) rc = -1;
  for (int i = 0; rc >= 0 && i < n; i++) all[i] = *vs_run_hinge(run, i);
  if (rc >= 0)
    rc = hinge_table(sum, "hinges", all, n, vs_run_hinge_count(run),
                     vs_run_case(run)->rate_mm_s * VS_MM,
                     "hinges in order of appearance. label A-E; side: the edge that stays in "
                     "contact (I intrados, E extrados); name: joints (e.g. 44-45-46-I, "
                     "after a collapse those at its onset, not at the end of the fall; "
                     "a hinge spread over consecutive joints), name_onset: joints when it formed; "
                     "during_fall = 1: opened as the arch fell after the collapse's onset");
  free(all);
  vs_h5_close(sum);
  return rc < 0 ? vs_h5_fail(&o->err, o->path, "cannot write /summary") : VS_OK;
}
