/* The case: every input parameter of a run. One table (section, key, type, range, unit, default)
 * drives the defaults, the INI reader, --set overrides, the range checks and every message, so a
 * key cannot exist in one of them and be missing from another. The file reader itself is
 * case_read.c: its assignments come here (case_internal.h). */
#include "voussoir/case.h"

#include "case_internal.h"
#include "parse.h"
#include "voussoir/units.h"
#include "quote.h"

#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * The table */

/* KEY_TEXT: a char array of VS_ARCH_PATH_MAX bytes; KEY_LIST: an array of
 * VS_ARCH_MAX_POSITIONS doubles, each in the key's range, strictly increasing, with its count
 * in the int at count_offset. */
typedef enum { KEY_DOUBLE, KEY_INT, KEY_TEXT, KEY_LIST } key_type;

typedef struct {
  const char *section;
  const char *name;
  key_type type;
  size_t offset; /* of the field in vs_case */
  double def;
  double min, max; /* -INFINITY / INFINITY: unbounded on that side */
  bool min_incl, max_incl;
  const char *unit; /* "" when dimensionless */
  const char *what;
  const char *const *names; /* a named choice: the names of values 0, 1, ... (NULL-terminated),
                               written in the file as names; NULL for a number */
  bool zero_ok; /* 0 is accepted besides the range (a support's rate: 0, at rest) */
  size_t count_offset; /* KEY_LIST: of its count in vs_case */
} key_spec;

/* The field's own type picks the storage, so a row cannot write a double into an int. */
#define FIELD_TYPE(field) _Generic(((vs_case *)0)->field, double: KEY_DOUBLE, int: KEY_INT)
#define KEY(sec, field, def, lo, lo_in, hi, hi_in, unit, what)                                    \
  {#sec, #field, FIELD_TYPE(field), offsetof(vs_case, field), def, lo, hi, lo_in, hi_in, unit, what, \
   NULL, false, 0}
/* A number that may also be 0 ("0 or [lo, hi]"). */
#define KEY_OR_ZERO(sec, field, def, lo, hi, unit, what)                                          \
  {#sec, #field, KEY_DOUBLE, offsetof(vs_case, field), def, lo, hi, true, true, unit, what, NULL, \
   true, 0}
/* A named choice stored as an int field: value i is names[i], i in 0 .. (the names) - 1. */
#define KEY_NAMED(sec, field, def, names, what)                                                 \
  {#sec, #field, KEY_INT, offsetof(vs_case, field), def, 0.0,                                  \
   (double)(sizeof names / sizeof names[0]) - 2.0, true, true, "", what, names, false, 0}

/* A file name (KEY_TEXT), and a list of numbers in (lo, hi) with its count field (KEY_LIST). */
/* A number whose field is named otherwise than its key (piers.height_mm: pier_height_mm). */
#define KEY_AS(sec, name, field, def, lo, lo_in, hi, hi_in, unit, what)                          \
  {#sec, #name, FIELD_TYPE(field), offsetof(vs_case, field), def, lo, hi, lo_in, hi_in, unit,    \
   what, NULL, false, 0}
#define KEY_AS_OR_ZERO(sec, name, field, def, lo, hi, unit, what)                                 \
  {#sec, #name, KEY_DOUBLE, offsetof(vs_case, field), def, lo, hi, true, true, unit, what, NULL,  \
   true, 0}
#define KEY_TEXT_ROW(sec, field, what)                                                          \
  {#sec, #field, KEY_TEXT, offsetof(vs_case, field), 0.0, 0.0, 0.0, true, true, "", what, NULL,  \
   false, 0}
#define KEY_LIST_ROW(sec, field, count, lo, hi, what)                                           \
  {#sec, #field, KEY_LIST, offsetof(vs_case, field), 0.0, lo, hi, false, false, "", what, NULL,  \
   false, offsetof(vs_case, count)}

/* The names of each named choice, in the order of its enum (def.h), NULL-terminated: one name
 * for every value, checked against the enum's count when this compiles. */
#define NAMES_OF(names, count)                                                                  \
  _Static_assert(sizeof names / sizeof names[0] == (count) + 1, "a name for every value of " #count)
/* support.left_kind, support.right_kind: vs_support_kind */
static const char *const support_kinds[] = {"fixed", "pinned", NULL};
NAMES_OF(support_kinds, VS_SUPPORT_KIND_COUNT);
/* dynamic.damping_model: vs_damping_model */
static const char *const damping_models[] = {"none", "joint", "rayleigh", "impact", NULL};
NAMES_OF(damping_models, VS_DAMPING_MODEL_COUNT);
/* fall.scheme: vs_fall_scheme */
static const char *const fall_schemes[] = {"rigid", "penalty", NULL};
NAMES_OF(fall_schemes, VS_FALL_SCHEME_COUNT);
/* fall.solver: vs_fall_solver */
static const char *const fall_solvers[] = {"nncg", "gauss_seidel", NULL};
NAMES_OF(fall_solvers, VS_FALL_SOLVER_COUNT);
/* arch.shape: vs_arch_shape */
static const char *const arch_shapes[] = {"circular", "pointed", "elliptical", "basket",
                                          "parabolic", "catenary", "file", NULL};
NAMES_OF(arch_shapes, VS_SHAPE_COUNT);
/* arch.joints: vs_joint_cut */
static const char *const joint_cuts[] = {"normal", "vertical", NULL};
NAMES_OF(joint_cuts, VS_JOINT_CUT_COUNT);

/* load.kind: vs_load_kind; analysis.type: vs_analysis_type */
static const char *const load_kinds[] = {"none", "point", "line", "patch", "tilt", NULL};
NAMES_OF(load_kinds, VS_LOAD_KIND_COUNT);
static const char *const analysis_types[] = {"support", "load", "limit", NULL};
NAMES_OF(analysis_types, VS_ANALYSIS_TYPE_COUNT);

#define INF INFINITY
/* Every bound is finite (except where a sign is all that matters) so that every quantity derived
 * from the case (areas, masses, weights, times delta / rate, the span) stays a finite, non-zero
 * double; docs/case-file.md ("Why the ranges are bounded") gives the reason for each. Lengths: 1 um to 1 km. */
#define LEN_MIN 1e-3
#define LEN_MAX 1e6
static const key_spec keys[] = {
    /*  section  key           default  min  incl   max   incl   unit      meaning */
    KEY(arch, radius_mm, 300.0, LEN_MIN, true, LEN_MAX, true, "mm", "intrados radius R"),
    KEY(arch, thickness_mm, 24.0, LEN_MIN, true, LEN_MAX, true, "mm", "radial thickness t"),
    KEY(arch, embrace_deg, 125.0, 1.0, true, 180.0, true, "deg",
        "angle of embrace, symmetric about the crown (below 1 deg the arch is a flat beam)"),
    KEY(arch, voussoirs, 55.0, 1.0, true, 2000.0, true, "",
        "number of voussoirs, equal angles (per voussoir a run takes ~10 kB of memory and ~1 ms "
        "of CPU to the collapse, its record ~200 bytes a state: 2000 write up to ~400 MB)"),
    KEY(arch, depth_mm, 120.0, LEN_MIN, true, LEN_MAX, true, "mm", "out-of-plane depth b"),
    KEY(arch, density_kg_m3, 1640.0, 10.0, true, 1e5, true, "kg/m^3",
        "density of the blocks (foams to beyond any metal; lighter blocks weigh less than the "
        "Newton tolerance can resolve against the joint stiffness)"),
    KEY(arch, gravity_m_s2, 9.81, 0.1, true, 1000.0, true, "m/s^2",
        "gravitational acceleration (up to 100 g, as in a centrifuge model)"),
    /* shapes and stereotomy: src/model/shape.c, docs/model.md "Shapes" */
    KEY_NAMED(arch, shape, 0.0, arch_shapes,
              "the arch's shape: circular (radius, embrace; or span, rise), pointed (span, "
              "eccentricity), elliptical, basket, parabolic, catenary (span, rise), or the blocks "
              "of blocks_file"),
    KEY(arch, span_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "intrados span (0: that of radius_mm and embrace_deg)"),
    KEY(arch, rise_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "intrados rise (0: that of radius_mm and embrace_deg; a pointed arch's follows from its "
        "eccentricity)"),
    KEY(arch, eccentricity, 0.0, 0.0, true, 10.0, true, "",
        "pointed: each centre's offset from the crown line over the half-span (0 semicircle, 1 "
        "equilateral)"),
    KEY(arch, haunch_deg, 60.0, 0.0, false, 90.0, false, "deg",
        "basket: the angle each haunch arc subtends"),
    KEY(arch, thickness_springing_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "thickness at the springings (0: thickness_mm throughout)"),
    KEY_NAMED(arch, joints, 0.0, joint_cuts,
              "joints normal to the centre line (radial on a circle) or vertical"),
    KEY(arch, keystone_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "the keystone's width along the centre line, across with vertical joints (0: as the "
        "other voussoirs)"),
    KEY_LIST_ROW(arch, joint_positions, n_joint_positions, 0.0, 1.0,
                 "the interior joints at these fractions of the centre line's length, of the "
                 "span with vertical joints (none: equal voussoirs)"),
    KEY_TEXT_ROW(arch, blocks_file, "shape = file: the JSON file of blocks"),
    /* piers under the springings (issue 28): src/model/piers.c, docs/model.md "Piers" */
    KEY_AS(piers, height_mm, pier_height_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
           "each pier's height, from the ground to the springing's intrados point (0: no piers, "
           "the springings on the supports)"),
    KEY_AS(piers, width_mm, pier_width_mm, 150.0, LEN_MIN, true, LEN_MAX, true, "mm",
           "each pier's width, outward from its inner face (more than the springing face's "
           "horizontal extent)"),
    KEY_AS(piers, courses, pier_courses, 4.0, 1.0, true, (double)VS_PIERS_MAX_COURSES, true, "",
           "equal courses in each pier, each a rigid block; the top one a skewback cut along "
           "the springing joint"),
    KEY_AS_OR_ZERO(piers, density_kg_m3, pier_density_kg_m3, 0.0, 10.0, 1e5, "kg/m^3",
                   "density of the piers' blocks (0: arch.density_kg_m3)"),
    KEY_AS_OR_ZERO(piers, base_friction, pier_base_friction, 0.0, 1e-3, 100.0, "",
                   "friction coefficient of each pier's foundation interface (0: "
                   "joints.friction)"),
    KEY(joints, kn_N_mm3, 3.0, 1e-4, true, 1e6, true, "N/mm^3",
        "normal stiffness k_n (above 1e6 the round-off floor of the joint forces nears 1e-5 of a "
        "voussoir's weight; below 1e-4 a lab arch sinks by its own thickness under self-weight)"),
    KEY(joints, ks_ratio, 0.5, 0.0, false, 100.0, true, "", "shear stiffness ratio k_s / k_n"),
    KEY(joints, friction, 0.7, 0.0, false, 100.0, true, "", "Coulomb friction coefficient mu"),
    /* mortar: joint.h, vs_joint_normal_mortar; docs/model.md "Mortar joints" */
    KEY(joints, tensile_MPa, 0.0, 0.0, true, 100.0, true, "MPa",
        "mortar's tensile strength f_t (0: dry, no tension)"),
    KEY(joints, cohesion_MPa, 0.0, 0.0, true, 100.0, true, "MPa",
        "mortar's cohesion c (0: dry)"),
    KEY(joints, gf_N_mm, 0.0, 0.0, true, 1000.0, true, "N/mm",
        "mode-I fracture energy G_f, the softening after f_t (> f_t^2 / (2 k_n))"),
    KEY(joints, gc_N_mm, 0.0, 0.0, true, 1000.0, true, "N/mm",
        "mode-II fracture energy G_c, the softening after c"),
    KEY(support, alpha_deg, 0.0, -180.0, true, 180.0, true, "deg",
        "direction of the right support's motion from the vertical (0 down, 90 outward)"),
    KEY_OR_ZERO(support, rate_mm_s, 0.04, 1e-6, 1e6, "mm/s",
                "speed of the right support, 0: at rest (times are delta / rate: bounded both "
                "ways)"),
    KEY(support, max_mm, 300.0, 0.0, false, LEN_MAX, true, "mm",
        "largest support displacement followed"),
    KEY_NAMED(support, left_kind, 0.0, support_kinds,
              "left support: fixed (clamped) or pinned (free to rotate about its pivot)"),
    KEY_NAMED(support, right_kind, 0.0, support_kinds,
              "right (moving) support: fixed (clamped) or pinned (free to rotate about its pivot)"),
    /* both supports on their own paths: the left one's straight motion (the paths are text
     * keys, text_keys below) */
    KEY(support, left_alpha_deg, 0.0, -180.0, true, 180.0, true, "deg",
        "direction of the left support's motion from the vertical, mirrored (0 down, 90 outward, "
        "to the left)"),
    KEY_OR_ZERO(support, left_rate_mm_s, 0.0, 1e-6, 1e6, "mm/s",
                "speed of the left support, 0: fixed (the loading rate when rate_mm_s is 0)"),
    KEY(solver, step_mm, 0.5, 0.0, false, LEN_MAX, true, "mm",
        "initial increment of the support displacement"),
    KEY(solver, step_max_mm, 2.0, 0.0, false, LEN_MAX, true, "mm", "largest increment"),
    KEY(solver, limit_tol_mm, 1e-3, 1e-9, true, LEN_MAX, true, "mm",
        "bisection tolerance on a limit point (below 1e-9 mm it is under the round-off of positions)"),
    KEY(solver, newton_tol, 1e-8, 0.0, false, 1e-2, true, "",
        "scaled residual tolerance (fraction of a voussoir's weight)"),
    KEY(solver, newton_maxiter, 8.0, 2.0, true, 1000.0, true, "",
        "Newton iterations per increment"),
    KEY(hinges, open_mm, 0.05, 0.0, false, LEN_MAX, true, "mm",
        "edge opening beyond which a joint counts as a hinge"),
    KEY(hinges, migrate_joints, 3.0, 0.0, true, 100.0, true, "joints",
        "a hinge reappearing within this many joints, same side, has migrated"),
    KEY(dynamic, follow, 1.0, 0.0, true, 1.0, true, "",
        "1: follow the limit points dynamically to the collapse; 0: stop at the first"),
    KEY(dynamic, full, 0.0, 0.0, true, 1.0, true, "",
        "1: integrate the whole loading dynamically from rest"),
    KEY_NAMED(dynamic, damping_model, 1.0, damping_models,
              "damping: none, joint (dashpots), rayleigh (alpha M + beta K), impact (Housner)"),
    KEY(dynamic, damping, 0.05, 0.0, true, 1.0, true, "",
        "damping ratio: joint, of each joint's critical damping; rayleigh, of the two lowest modes"),
    KEY(dynamic, rtol, 1e-6, 0.0, false, 1e-2, true, "", "IDA relative tolerance"),
    KEY(dynamic, atol_mm, 1e-5, 0.0, false, LEN_MAX, true, "mm",
        "IDA absolute tolerance on positions"),
    KEY(dynamic, rest_factor, 100.0, 1.0, true, 1e12, true, "",
        "at rest below this many times the kinetic energy of the arch moving at the support rate"),
    KEY(dynamic, rest_s, 1.0, 0.0, false, 1e6, true, "s", "... for this long"),
    KEY(dynamic, ring_periods, 0.0, 0.0, true, 1000.0, true, "",
        "0: the rest criterion alone; mortared arches: N > 0 ends a snap also once it has rung "
        "N periods of the lowest mode with nothing changing and its energy falling"),
    KEY(dynamic, collapse_ke, 0.1, 0.0, false, 1e6, true, "",
        "collapsing beyond this kinetic energy, as a fraction of weight x thickness"),
    KEY(dynamic, fall_s, 5.0, 0.0, true, 1e6, true, "s",
        "the fall is followed at most this long (it ends earlier once the debris is at rest)"),
    KEY(dynamic, sample_s, 0.01, 1e-6, true, 1e6, true, "s", "interval between dynamic samples"),
    KEY(fall, ground_mm, 0.0, -LEN_MAX, true, 0.0, true, "mm",
        "the ground's height above the lower springing's base when the fall starts (above it, "
        "it would cut the standing springers)"),
    KEY_NAMED(fall, scheme, 0.0, fall_schemes,
              "rigid: rigid blocks, impulsive contacts, time stepping (fall.h); penalty: the "
              "joints' elastic law at every contact, integrated by IDA (20-100 times slower)"),
    KEY(fall, step_ms, 1.0, 1e-3, true, 10.0, true, "ms",
        "time step of the rigid scheme (a block falling at 2 m/s moves 2 mm in 1 ms)"),
    KEY(fall, slow_factor, 2.0, 1.0, true, 10.0, true, "",
        "rigid scheme: the step is this many times step_ms while no point of a block moves "
        "faster than slow_mm_s (1: always step_ms)"),
    KEY(fall, slow_mm_s, 500.0, 0.0, true, 1e6, true, "mm/s",
        "... that speed (0: always step_ms)"),
    KEY(fall, max_sweeps, 15.0, 1.0, true, 10000.0, true, "",
        "rigid scheme: Gauss-Seidel sweeps at most per step (100 near rest if fewer)"),
    KEY_NAMED(fall, solver, 0.0, fall_solvers,
              "rigid scheme: the contacts' impulses by Gauss-Seidel sweeps, each followed by a "
              "nonsmooth conjugate gradient step (nncg), or the sweeps alone (gauss_seidel)"),
    KEY(fall, restitution, 0.5, 0.0, false, 1.0, true, "",
        "penalty scheme: coefficient of restitution of a block landing flat on the ground (the "
        "rigid scheme's impacts are perfectly plastic)"),
    /* imperfections: src/model/imperfections.c; all amplitudes 0 give the perfect arch exactly */
    KEY(imperfections, seed, 1.0, 0.0, true, 2147483647.0, true, "", "seed of the generator"),
    KEY(imperfections, sample, 0.0, 0.0, true, 2147483647.0, true, "",
        "sample number (each sample draws its own imperfections)"),
    KEY(imperfections, kn_cov, 0.0, 0.0, true, 3.0, true, "",
        "coefficient of variation of each joint's k_n (lognormal, mean the nominal k_n)"),
    KEY(imperfections, kn_corr_mm, 0.0, 0.0, true, 1e6, true, "mm",
        "correlation length of the k_n scatter along the arch (0: independent joints)"),
    KEY(imperfections, face_mm, 0.0, 0.0, true, 10.0, true, "mm",
        "non-coplanar faces: standard deviation of the as-built gap at a joint's open edge"),
    KEY(imperfections, angle_cov, 0.0, 0.0, true, 0.5, true, "",
        "coefficient of variation of the voussoirs' angular sizes (the arch still closes)"),
    KEY(imperfections, thickness_cov, 0.0, 0.0, true, 0.5, true, "",
        "coefficient of variation of the voussoirs' thickness"),
    KEY(imperfections, support_dx_mm, 0.0, -100.0, true, 100.0, true, "mm",
        "initial offset of the moving support, outward"),
    KEY(imperfections, support_dz_mm, 0.0, -100.0, true, 100.0, true, "mm",
        "initial offset of the moving support, downward"),
    KEY(imperfections, tensile_cov, 0.0, 0.0, true, 3.0, true, "",
        "mortar: coefficient of variation of each joint's tensile strength f_t (lognormal, mean "
        "joints.tensile_MPa)"),
    KEY(imperfections, gf_cov, 0.0, 0.0, true, 3.0, true, "",
        "mortar: coefficient of variation of each joint's fracture energy G_f (lognormal, mean "
        "joints.gf_N_mm)"),
    KEY(imperfections, debonded, 0.0, 0.0, true, 1.0, true, "",
        "mortar: probability that a joint is debonded (no tension, no cohesion: a dry joint)"),
    KEY(run, max_wall_s, 0.0, 0.0, true, 1e6, true, "s",
        "wall-time limit of a run (0: none); once passed the run stops at its next step, its "
        "record marked stopped"),
    /* the live load and what the run computes (issue 28): src/solve/limit*.c */
    KEY_NAMED(load, kind, 0.0, load_kinds,
              "the live load: none, point (on the extrados at x_mm), line (a knife-edge across "
              "the barrel at x_mm), patch (uniform over width_mm centred on x_mm), tilt (lambda "
              "x each block's weight, horizontal, toward the right support)"),
    KEY(load, value_N, 1.0, 0.0, false, 1e9, true, "N",
        "point, line, patch: the live load (downward) that the load factor scales"),
    KEY(load, x_mm, 0.0, -LEN_MAX, true, LEN_MAX, true, "mm",
        "the load's position: horizontal distance from the left springing's intrados point"),
    KEY(load, width_mm, 0.0, 0.0, true, LEN_MAX, true, "mm", "patch: its horizontal width"),
    KEY(load, spread_deg, 0.0, 0.0, true, 80.0, true, "deg",
        "point, line, patch: the load's spread through the fill from the vertical (0: none): on "
        "the extrados, uniform over width_mm + 2 h tan(spread_deg), h the fill's depth at x_mm"),
    KEY_NAMED(analysis, type, 0.0, analysis_types,
              "what a run computes: support (the support's path to collapse), load (the live "
              "load's path to collapse, at the support held at hold_mm), limit (the limit "
              "analysis: of the initial configuration alone, no path; with hold_mm > 0 of the arch held "
              "there)"),
    KEY(analysis, hold_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "load: the support displacement along the support's path held before loading; limit: "
        "the support displacement at which the deformed arch is analysed (0: the initial one)"),
    KEY(fill, unit_weight_kN_m3, 0.0, 0.0, true, 1000.0, true, "kN/m^3",
        "the fill's unit weight (0: no fill): a dead load on the extrados, the weight of the fill "
        "above each voussoir up to level_mm"),
    KEY(fill, level_mm, 0.0, 0.0, true, LEN_MAX, true, "mm",
        "the fill's surface above the crown's extrados"),
    KEY(fill, k_horizontal, 0.0, 0.0, true, 100.0, true, "",
        "the coefficient of the fill's horizontal pressure on the extrados (0: none): "
        "k_horizontal x unit_weight x the depth below the fill's surface, inward"),
};
#undef LEN_MIN
#undef LEN_MAX
#undef INF
#undef KEY
#undef KEY_OR_ZERO
#undef KEY_AS
#undef KEY_AS_OR_ZERO
#undef KEY_NAMED
#undef NAMES_OF
#undef FIELD_TYPE

#define NKEYS (sizeof keys / sizeof keys[0])

/* Relations between fields checked by vs_case_validate: lo < hi (strict) or lo <= hi. */
typedef struct {
  const char *lo_section, *lo_name, *hi_section, *hi_name;
  bool strict;
  const char *rule;
} relation;

static const relation relations[] = {
    {"solver", "limit_tol_mm", "solver", "step_mm", false,
     "limit_tol_mm <= step_mm <= step_max_mm, mm"},
    {"solver", "step_mm", "solver", "step_max_mm", false,
     "limit_tol_mm <= step_mm <= step_max_mm, mm"},
    {"solver", "step_mm", "support", "max_mm", true, "solver.step_mm < support.max_mm, mm"},
};

/* ---------------------------------------------------------------------------------------------
 * Text keys: a support's path in time, "t_s:dx_mm:dz_mm[:rot_deg], ..." (def.h,
 * vs_support_path_def). Points are separated by ',' and not ';', which starts a comment after a
 * blank in a case file and would cut the path short without a word. */

typedef struct {
  const char *section, *name;
  size_t offset; /* of the vs_case_path field */
} text_key_spec;

static const text_key_spec text_keys[] = {
    {"support", "left_path", offsetof(vs_case, left_path)},
    {"support", "right_path", offsetof(vs_case, right_path)},
};
#define NTEXT (sizeof text_keys / sizeof text_keys[0])

/* The bounds of a path's values: times up to ~30 years, lengths as the table's, a lean below a
 * right angle either way. */
#define PATH_T_MAX 1e9
#define PATH_LEN_MAX 1e6
#define PATH_ROT_MAX 90.0
#define PATH_ALLOWED                                                                              \
  "none, or up to 32 points t_s:dx_mm:dz_mm[:rot_deg] separated by ',', times increasing from "  \
  "0 (a point at 0 is the origin 0:0:0), t in [0, 1e9] s, dx, dz in [-1e6, 1e6] mm, rot in "     \
  "[-90, 90] deg"
_Static_assert(VS_SUPPORT_PATH_MAX == 32, "PATH_ALLOWED says 32 points");

static void append(char *buf, size_t size, const char *s);

static const text_key_spec *find_text_key(const char *section, const char *name) {
  for (size_t i = 0; i < NTEXT; i++)
    if (strcmp(text_keys[i].section, section) == 0 && strcmp(text_keys[i].name, name) == 0)
      return &text_keys[i];
  return NULL;
}

/* One number of a path's point, blanks around it allowed (tok is writable). */
static int path_number(char *tok, double *out) {
  while (*tok == ' ' || *tok == '\t') tok++;
  size_t n = strlen(tok);
  while (n > 0 && (tok[n - 1] == ' ' || tok[n - 1] == '\t')) tok[--n] = '\0';
  return vs_parse_double(tok, out) == VS_NUM_OK ? 0 : -1;
}

/* Parse one point "t:dx:dz[:rot]" (writable) as point i of p; why says what is wrong. */
static int path_point_parse(char *pt, vs_case_path *p, int i, char *why, size_t size) {
  double v[4] = {0.0, 0.0, 0.0, 0.0};
  int f = 0;
  for (char *tok = pt, *next; tok != NULL; tok = next, f++) {
    next = strchr(tok, ':');
    if (next != NULL) *next++ = '\0';
    if (f == 4 || path_number(tok, &v[f]) != 0) {
      snprintf(why, size, "point %d: %s", i + 1, f == 4 ? "more than 4 numbers" : "not a number");
      return -1;
    }
  }
  if (f < 3) {
    snprintf(why, size, "point %d: %d number%s (t_s:dx_mm:dz_mm[:rot_deg])", i + 1, f,
             f == 1 ? "" : "s");
    return -1;
  }
  p->t_s[i] = v[0], p->dx_mm[i] = v[1], p->dz_mm[i] = v[2], p->rot_deg[i] = v[3];
  return 0;
}

/* The rules of a path's points (PATH_ALLOWED); 0, or -1 with the reason in why. */
static int path_check(const vs_case_path *p, char *why, size_t size) {
  if (p->n < 0 || p->n > VS_SUPPORT_PATH_MAX) {
    snprintf(why, size, "%d points", p->n);
    return -1;
  }
  for (int i = 0; i < p->n; i++) {
    const double t = p->t_s[i], dx = p->dx_mm[i], dz = p->dz_mm[i], rot = p->rot_deg[i];
    if (!(t >= 0.0 && t <= PATH_T_MAX) || !(fabs(dx) <= PATH_LEN_MAX) ||
        !(fabs(dz) <= PATH_LEN_MAX) || !(fabs(rot) <= PATH_ROT_MAX)) {
      snprintf(why, size, "point %d: out of range", i + 1);
      return -1;
    }
    if (i > 0 && !(t > p->t_s[i - 1])) {
      snprintf(why, size, "point %d: t = %g s not after %g s", i + 1, t, p->t_s[i - 1]);
      return -1;
    }
    if (t == 0.0 && (dx != 0.0 || dz != 0.0 || rot != 0.0)) {
      snprintf(why, size, "point %d: at t = 0 away from the origin", i + 1);
      return -1;
    }
  }
  return 0;
}

/* Parse a path's text into *out (written only when the whole text is accepted); "none": no
 * path. Returns 0, or -1 with the reason in why. */
static int path_parse(const char *text, vs_case_path *out, char *why, size_t size) {
  vs_case_path p = {.n = 0};
  if (strcmp(text, "none") != 0) {
    const size_t len = strlen(text);
    char *copy = malloc(len + 1);
    if (copy == NULL) {
      snprintf(why, size, "out of memory");
      return -1;
    }
    memcpy(copy, text, len + 1);
    int rc = 0;
    for (char *pt = copy, *next; pt != NULL && rc == 0; pt = next) {
      next = strchr(pt, ',');
      if (next != NULL) *next++ = '\0';
      if (p.n == VS_SUPPORT_PATH_MAX) {
        snprintf(why, size, "more than %d points", VS_SUPPORT_PATH_MAX);
        rc = -1;
      } else {
        rc = path_point_parse(pt, &p, p.n, why, size);
        p.n += rc == 0;
      }
    }
    free(copy);
    if (rc != 0 || path_check(&p, why, size) != 0) return -1;
  }
  *out = p;
  return 0;
}

static vs_case_path *path_field(vs_case *c, const text_key_spec *k) {
  return (vs_case_path *)(void *)((char *)c + k->offset);
}

/* A path as the case file gives it ("" when there is none), %.17g: read back, the same bits. */
static void path_text(const vs_case_path *p, char *buf, size_t size) {
  buf[0] = '\0';
  for (int i = 0; i < p->n && i < VS_SUPPORT_PATH_MAX; i++) {
    char pt[128];
    int n = snprintf(pt, sizeof pt, "%s%.17g:%.17g:%.17g", i > 0 ? ", " : "", p->t_s[i],
                     p->dx_mm[i], p->dz_mm[i]);
    if (p->rot_deg[i] != 0.0 && n > 0 && (size_t)n < sizeof pt)
      snprintf(pt + n, sizeof pt - (size_t)n, ":%.17g", p->rot_deg[i]);
    append(buf, size, pt);
  }
}

/* ---------------------------------------------------------------------------------------------
 * Table access */

static const key_spec *find_key(const char *section, const char *name) {
  for (size_t i = 0; i < NKEYS; i++)
    if (strcmp(keys[i].section, section) == 0 && strcmp(keys[i].name, name) == 0) return &keys[i];
  return NULL;
}

/* section need not be NUL-terminated: the reader checks "[name]" in place. */
bool vs_case_section_known(const char *section, size_t len) {
  for (size_t i = 0; i < NKEYS; i++)
    if (strlen(keys[i].section) == len && memcmp(keys[i].section, section, len) == 0) return true;
  return false;
}

/* A text or list key's value is not a number: NaN. */
static double get_value(const vs_case *c, const key_spec *k) {
  const char *p = (const char *)c + k->offset;
  if (k->type == KEY_TEXT || k->type == KEY_LIST) return NAN;
  return k->type == KEY_INT ? (double)*(const int *)(const void *)p
                            : *(const double *)(const void *)p;
}

/* v has been range-checked, so the int conversion is exact. A text or list key is emptied. */
static void set_value(vs_case *c, const key_spec *k, double v) {
  char *p = (char *)c + k->offset;
  if (k->type == KEY_TEXT)
    p[0] = '\0';
  else if (k->type == KEY_LIST)
    *(int *)(void *)((char *)c + k->count_offset) = 0;
  else if (k->type == KEY_INT)
    *(int *)(void *)p = (int)v;
  else
    *(double *)(void *)p = v;
}

static bool in_range(const key_spec *k, double v) {
  if (!isfinite(v)) return false;
  if (k->zero_ok && v == 0.0) return true;
  if (k->min_incl ? v < k->min : v <= k->min) return false;
  if (k->max_incl ? v > k->max : v >= k->max) return false;
  return true;
}

/* ---------------------------------------------------------------------------------------------
 * Message pieces */

static void append(char *buf, size_t size, const char *s) {
  size_t used = strlen(buf);
  if (used + 1 < size) snprintf(buf + used, size - used, "%s", s);
}

/* "> 0 N/mm^3", "(0, 180] deg", "integer in [1, 20000]" */
static void range_text(const key_spec *k, char *buf, size_t size) {
  if (k->type == KEY_TEXT) {
    snprintf(buf, size, "a file name of at most %d bytes", VS_ARCH_PATH_MAX - 1);
    return;
  }
  if (k->type == KEY_LIST) {
    snprintf(buf, size, "at most %d numbers in (%g, %g), comma-separated, increasing",
             VS_ARCH_MAX_POSITIONS, k->min, k->max);
    return;
  }
  if (k->names != NULL) {
    snprintf(buf, size, "one of ");
    for (int i = 0; k->names[i] != NULL; i++) {
      if (i > 0) append(buf, size, ", ");
      append(buf, size, k->names[i]);
    }
    return;
  }
  bool lo = isfinite(k->min), hi = isfinite(k->max);
  const char *integer = k->type == KEY_INT ? "integer " : "";
  /* an integer's bounds whole ("[0, 2147483647]", not 2.14748e+09) */
  const char *f = k->type == KEY_INT ? "%.0f" : "%g";
  char a[32], b[32];
  snprintf(a, sizeof a, f, k->min);
  snprintf(b, sizeof b, f, k->max);
  if (lo && hi)
    snprintf(buf, size, "%s%s%s%c%s, %s%c", k->zero_ok ? "0 or " : "", integer,
             *integer ? "in " : "", k->min_incl ? '[' : '(', a, b, k->max_incl ? ']' : ')');
  else if (lo)
    snprintf(buf, size, "%s%s %s", integer, k->min_incl ? ">=" : ">", a);
  else if (hi)
    snprintf(buf, size, "%s%s %s", integer, k->max_incl ? "<=" : "<", b);
  else
    snprintf(buf, size, "%sany finite value", integer);
  if (k->unit[0] != '\0') {
    append(buf, size, " ");
    append(buf, size, k->unit);
  }
}

void vs_case_list_sections(char *buf, size_t size) {
  buf[0] = '\0';
  for (size_t i = 0; i < NKEYS; i++) {
    if (i > 0 && strcmp(keys[i].section, keys[i - 1].section) == 0) continue;
    if (i > 0) append(buf, size, ", ");
    append(buf, size, keys[i].section);
  }
}

static void list_keys(const char *section, char *buf, size_t size) {
  buf[0] = '\0';
  for (size_t i = 0; i < NKEYS; i++) {
    if (strcmp(keys[i].section, section) != 0) continue;
    if (buf[0] != '\0') append(buf, size, ", ");
    append(buf, size, keys[i].name);
  }
  for (size_t i = 0; i < NTEXT; i++) {
    if (strcmp(text_keys[i].section, section) != 0) continue;
    if (buf[0] != '\0') append(buf, size, ", ");
    append(buf, size, text_keys[i].name);
  }
}

/* Echo user text into a message (case_internal.h: vs_case_echo), quoted: a case file's token
 * may hold an escape sequence. */
const char *vs_case_clip(const char *s, vs_case_echo *b) { return vs_quote(s, b->s, sizeof b->s); }

/* ---------------------------------------------------------------------------------------------
 * Numbers: the one parser of parse.h (same accepted forms as every command-line option). */

static vs_num_status parse_value(const key_spec *k, const char *s, double *out) {
  if (k->type == KEY_DOUBLE) return vs_parse_double(s, out);
  long v = 0;
  vs_num_status st = vs_parse_long(s, &v);
  if (st != VS_NUM_OK) return st;
  if (v < INT_MIN || v > INT_MAX) return VS_NUM_OUT_OF_RANGE;
  *out = (double)v;
  return VS_NUM_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Text and lists */

/* A list's items into out (n of them): each a number of the key's open range, increasing. */
static vs_status parse_items(const key_spec *k, const char *value, double *out, int *n,
                             const char *where, const char *sec, const char *key,
                             const char *val, const char *range, vs_error *err) {
  char item[64];
  *n = 0;
  for (const char *p = value; *p != '\0';) {
    const char *end = strchr(p, ',');
    const size_t len = end != NULL ? (size_t)(end - p) : strlen(p);
    double v = 0.0;
    vs_num_status r = VS_NUM_OK;
    if (*n == VS_ARCH_MAX_POSITIONS)
      return vs_error_set(err, VS_ERR_INVALID, "%s: %s.%s = %s: too many numbers (allowed: %s)",
                          where, sec, key, val, range);
    if (len >= sizeof item) r = VS_NUM_TRAILING;
    else {
      memcpy(item, p, len);
      item[len] = '\0';
      char *t = item;
      while (vs_case_is_blank(*t)) t++;
      for (size_t e = strlen(t); e > 0 && vs_case_is_blank(t[e - 1]); e--) t[e - 1] = '\0';
      r = vs_parse_double(t, &v);
    }
    if (r == VS_NUM_OK && (!in_range(k, v) || (*n > 0 && !(v > out[*n - 1]))))
      r = VS_NUM_OUT_OF_RANGE;
    if (r != VS_NUM_OK)
      return vs_error_set(err, r == VS_NUM_OUT_OF_RANGE ? VS_ERR_INVALID : VS_ERR_PARSE,
                          "%s: %s.%s = %s: number %d: %s (allowed: %s)", where, sec, key, val,
                          *n + 1, r == VS_NUM_OUT_OF_RANGE ? "out of range or not increasing"
                                                           : vs_num_reason(r), range);
    out[(*n)++] = v;
    p = end != NULL ? end + 1 : p + len;
    if (end != NULL && *p == '\0')
      return vs_error_set(err, VS_ERR_PARSE, "%s: %s.%s = %s: a comma at the end (allowed: %s)",
                          where, sec, key, val, range);
  }
  return VS_OK;
}

/* Text a case file's line "key = text" gives back as it is: no control character, no blank at
 * either end, no ';' or '#' first or after a blank (a comment there). */
static bool text_writable(const char *s) {
  const size_t n = strlen(s);
  if (n > 0 && (vs_case_is_blank(s[0]) || vs_case_is_blank(s[n - 1]))) return false;
  for (size_t i = 0; i < n; i++) {
    if ((unsigned char)s[i] < 0x20 || s[i] == 0x7f) return false;
    if ((s[i] == ';' || s[i] == '#') && (i == 0 || vs_case_is_blank(s[i - 1]))) return false;
  }
  return true;
}

/* A text key takes the value as it is (empty: none); a list key its numbers (empty: none). */
static vs_status assign_text(vs_case *c, const key_spec *k, const char *value, const char *where,
                             const char *sec, const char *key, const char *val, const char *range,
                             vs_error *err) {
  char *p = (char *)c + k->offset;
  if (k->type == KEY_TEXT) {
    if (strlen(value) >= VS_ARCH_PATH_MAX)
      return vs_error_set(err, VS_ERR_INVALID, "%s: %s.%s = %s: too long (allowed: %s)", where,
                          sec, key, val, range);
    if (!text_writable(value))
      return vs_error_set(err, VS_ERR_INVALID, "%s: %s.%s = %s: a name a case file cannot hold "
                          "(allowed: %s without control characters, blanks at either end, or "
                          "';' or '#' first or after a blank)", where, sec, key, val, range);
    memcpy(p, value, strlen(value) + 1);
    return VS_OK;
  }
  double items[VS_ARCH_MAX_POSITIONS];
  int n = 0;
  vs_status st = parse_items(k, value, items, &n, where, sec, key, val, range, err);
  if (st != VS_OK) return st;
  memcpy(p, items, (size_t)n * sizeof *items);
  *(int *)(void *)((char *)c + k->count_offset) = n;
  return VS_OK;
}

/* ---------------------------------------------------------------------------------------------
 * One assignment, shared by the file reader and --set. where is "FILE:LINE" or "--set ...".
 * c is written only when the value is accepted. */

vs_status vs_case_assign(vs_case *c, const char *section, const char *name, const char *value,
                         const char *where, vs_error *err) {
  vs_case_echo bs, bn, bv;
  const char *sec = vs_case_clip(section, &bs), *key = vs_case_clip(name, &bn),
             *val = vs_case_clip(value, &bv);
  char list[384];
  const text_key_spec *tk = find_text_key(section, name);
  if (tk != NULL) {
    char why[96];
    if (path_parse(value, path_field(c, tk), why, sizeof why) == 0) return VS_OK;
    return vs_error_set(err, value[0] == '\0' ? VS_ERR_PARSE : VS_ERR_INVALID,
                        "%s: %s.%s = %s: %s (allowed: %s)", where, sec, key, val,
                        value[0] == '\0' ? "empty value" : why, PATH_ALLOWED);
  }
  const key_spec *k = find_key(section, name);
  if (k == NULL) {
    if (vs_case_section_known(section, strlen(section))) {
      list_keys(section, list, sizeof list);
      return vs_error_set(err, VS_ERR_PARSE, "%s: %s.%s = %s: unknown key (allowed keys in [%s]: %s)",
                          where, sec, key, val, sec, list);
    }
    vs_case_list_sections(list, sizeof list);
    if (section[0] == '\0')
      return vs_error_set(err, VS_ERR_PARSE,
                          "%s: %s = %s: key outside any [section] (allowed sections: %s)", where, key,
                          val, list);
    return vs_error_set(err, VS_ERR_PARSE, "%s: %s.%s = %s: unknown section (allowed sections: %s)",
                        where, sec, key, val, list);
  }

  char range[96];
  range_text(k, range, sizeof range);
  double v = 0.0;
  if (k->type == KEY_TEXT || k->type == KEY_LIST)
    return assign_text(c, k, value, where, sec, key, val, range, err);
  if (k->names != NULL) {
    for (int i = 0; k->names[i] != NULL; i++)
      if (strcmp(value, k->names[i]) == 0) {
        set_value(c, k, (double)i);
        return VS_OK;
      }
    return vs_error_set(err, value[0] == '\0' ? VS_ERR_PARSE : VS_ERR_INVALID,
                        "%s: %s.%s = %s: %s (allowed: %s)", where, sec, key, val,
                        value[0] == '\0' ? "empty value" : "unknown name", range);
  }
  vs_num_status r = parse_value(k, value, &v);
  if (r == VS_NUM_OK && !in_range(k, v)) r = VS_NUM_OUT_OF_RANGE;
  if (r != VS_NUM_OK)
    return vs_error_set(err, r == VS_NUM_OUT_OF_RANGE ? VS_ERR_INVALID : VS_ERR_PARSE,
                        "%s: %s.%s = %s: %s (allowed: %s)", where, sec, key, val, vs_num_reason(r),
                        range);
  set_value(c, k, v);
  return VS_OK;
}

/* ---------------------------------------------------------------------------------------------
 * Public functions */

void vs_case_defaults(vs_case *c) {
  if (c == NULL) return;
  memset(c, 0, sizeof *c);
  for (size_t i = 0; i < NKEYS; i++) set_value(c, &keys[i], keys[i].def);
}


static char *trim(char *s) {
  while (vs_case_is_blank(*s)) s++;
  size_t n = strlen(s);
  while (n > 0 && vs_case_is_blank(s[n - 1])) s[--n] = '\0';
  return s;
}

vs_status vs_case_set(vs_case *c, const char *assignment, vs_error *err) {
  if (c == NULL || assignment == NULL)
    return vs_error_set(err, VS_ERR_INVALID, "vs_case_set: %s is NULL",
                        c == NULL ? "case" : "assignment");
  vs_case_echo b;
  char where[sizeof err->msg];
  snprintf(where, sizeof where, "--set %s", vs_case_clip(assignment, &b));

  size_t n = strlen(assignment) + 1;
  char *copy = malloc(n);
  if (copy == NULL) return vs_error_set(err, VS_ERR_NOMEM, "%s: out of memory", where);
  memcpy(copy, assignment, n);

  vs_status st;
  char *eq = strchr(copy, '=');
  char *dot = eq != NULL ? memchr(copy, '.', (size_t)(eq - copy)) : NULL;
  char *section = copy, *key = NULL;
  if (dot != NULL) {
    *eq = '\0';
    *dot = '\0';
    section = trim(copy);
    key = trim(dot + 1);
  }
  if (dot == NULL || section[0] == '\0' || key[0] == '\0')
    st = vs_error_set(err, VS_ERR_PARSE, "%s: malformed (expected section.key=value)", where);
  else
    st = vs_case_assign(c, section, key, trim(eq + 1), where, err);
  free(copy);
  return st;
}

/* The supports' motion as a whole: a loading rate, each path's points again (a field may have
 * been set in code), no rotation of a pinned support (the same checks as the definition's,
 * vs_support_motion_from_def, in the case's words). */
static vs_status supports_validate(const vs_case *c, vs_error *err) {
  if (!(vs_case_loading_rate_mm_s(c) > 0.0))
    return vs_error_set(err, VS_ERR_INVALID,
                        "support.rate_mm_s = 0 and support.left_rate_mm_s = 0: no support moves "
                        "at a rate (allowed: at least one > 0: delta = that rate x time, also "
                        "with paths)");
  for (size_t i = 0; i < NTEXT; i++) {
    const vs_case_path *p = path_field((vs_case *)(uintptr_t)c, &text_keys[i]);
    char why[96];
    if (path_check(p, why, sizeof why) != 0)
      return vs_error_set(err, VS_ERR_INVALID, "support.%s: %s (allowed: %s)", text_keys[i].name,
                          why, PATH_ALLOWED);
    const int kind = strcmp(text_keys[i].name, "left_path") == 0 ? c->left_kind : c->right_kind;
    for (int k = 0; k < p->n; k++)
      if (kind == VS_SUPPORT_PINNED && p->rot_deg[k] != 0.0)
        return vs_error_set(err, VS_ERR_INVALID,
                            "support.%s: point %d turns the support by %g deg, and it is pinned "
                            "(allowed: a rotation only on a fixed support; a pinned one turns "
                            "freely)",
                            text_keys[i].name, k + 1, p->rot_deg[k]);
  }
  return VS_OK;
}

/* What each analysis takes (issue 28): the live load's path needs a live load and follows it
 * quasi-statically, a held displacement is its, and the support's path carries no live load. */
static vs_status validate_analysis(const vs_case *c, vs_error *err) {
  if (c->type == VS_ANALYSIS_LOAD && c->kind == VS_LOAD_NONE)
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.type = load needs a live load (load.kind = none; allowed: "
                        "point, line, patch, tilt)");
  if (c->type == VS_ANALYSIS_LOAD && c->full)
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.type = load with dynamic.full = 1: the load path is "
                        "quasi-static (allowed: dynamic.full = 0)");
  if (c->hold_mm != 0.0 && c->type != VS_ANALYSIS_LOAD && c->type != VS_ANALYSIS_LIMIT)
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.hold_mm = %.15g: a held support displacement needs "
                        "analysis.type = load or limit",
                        c->hold_mm);
  if (c->hold_mm >= c->max_mm)
    return vs_error_set(err, VS_ERR_INVALID,
                        "analysis.hold_mm = %.15g: must be < support.max_mm = %.15g (allowed: "
                        "[0, support.max_mm), mm)",
                        c->hold_mm, c->max_mm);
  if (c->kind != VS_LOAD_NONE && c->type == VS_ANALYSIS_SUPPORT)
    return vs_error_set(err, VS_ERR_INVALID,
                        "load.kind = %s: the support's path carries no live load (allowed with "
                        "analysis.type = support: none; a live load: analysis.type = load or "
                        "limit)",
                        vs_load_kind_name((vs_load_kind)c->kind));
  return VS_OK;
}

/* A text or list key set in code: a terminated text, a list within its range, increasing. */
static vs_status validate_text(const vs_case *c, const key_spec *k, vs_error *err) {
  char range[96];
  range_text(k, range, sizeof range);
  const char *p = (const char *)c + k->offset;
  if (k->type == KEY_TEXT) {
    if (memchr(p, '\0', VS_ARCH_PATH_MAX) != NULL) return VS_OK;
    return vs_error_set(err, VS_ERR_INVALID, "%s.%s: not terminated (allowed: %s)", k->section,
                        k->name, range);
  }
  const int n = *(const int *)(const void *)((const char *)c + k->count_offset);
  const double *v = (const double *)(const void *)p;
  if (n < 0 || n > VS_ARCH_MAX_POSITIONS)
    return vs_error_set(err, VS_ERR_INVALID, "%s.%s: %d numbers (allowed: %s)", k->section,
                        k->name, n, range);
  for (int i = 0; i < n; i++)
    if (!in_range(k, v[i]) || (i > 0 && !(v[i] > v[i - 1])))
      return vs_error_set(err, VS_ERR_INVALID, "%s.%s: number %d = %.15g: out of range or not "
                          "increasing (allowed: %s)", k->section, k->name, i + 1, v[i], range);
  return VS_OK;
}

/* The shape keys' relations (docs/case-file.md, "Relations between keys"); what needs the
 * geometry (a joint that misses the intrados, a keystone wider than the centre line) is the
 * generator's to refuse. */
static vs_status validate_shape(const vs_case *c, vs_error *err) {
  if (c->shape == VS_SHAPE_CIRCULAR && (c->span_mm > 0.0) != (c->rise_mm > 0.0))
    return vs_error_set(err, VS_ERR_INVALID, "arch.span_mm = %.15g, arch.rise_mm = %.15g: a "
                        "circular arch takes both or neither (allowed: both > 0, or both 0 for "
                        "radius_mm and embrace_deg)", c->span_mm, c->rise_mm);
  if ((c->shape == VS_SHAPE_CIRCULAR || c->shape == VS_SHAPE_BASKET) && c->span_mm > 0.0 &&
      c->rise_mm > 0.5 * c->span_mm)
    return vs_error_set(err, VS_ERR_INVALID, "arch.rise_mm = %.15g: must be <= arch.span_mm / 2 "
                        "= %.15g for arch.shape = %s (allowed: rise_mm <= span_mm / 2)",
                        c->rise_mm, 0.5 * c->span_mm, arch_shapes[c->shape]);
  if (c->pier_height_mm > 0.0 &&
      (c->left_kind != VS_SUPPORT_FIXED || c->right_kind != VS_SUPPORT_FIXED))
    return vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %.15g with support.%s_kind = "
                        "pinned: a pier on a pinned foundation turns freely about the pin "
                        "(allowed: fixed supports under piers; a pier's base rocks by itself)",
                        c->pier_height_mm, c->left_kind != VS_SUPPORT_FIXED ? "left" : "right");
  if (c->shape == VS_SHAPE_FILE && c->pier_height_mm > 0.0)
    return vs_error_set(err, VS_ERR_INVALID, "piers.height_mm = %.15g with arch.shape = file "
                        "(allowed: 0; a blocks file draws its own piers)", c->pier_height_mm);
  if (c->shape == VS_SHAPE_POINTED && c->rise_mm != 0.0)
    return vs_error_set(err, VS_ERR_INVALID, "arch.rise_mm = %.15g: a pointed arch's rise follows "
                        "from its span and arch.eccentricity (allowed: 0)", c->rise_mm);
  if (c->n_joint_positions > 0 && c->n_joint_positions != c->voussoirs - 1)
    return vs_error_set(err, VS_ERR_INVALID, "arch.joint_positions: %d positions, arch.voussoirs "
                        "= %d (allowed: voussoirs - 1 positions)", c->n_joint_positions,
                        c->voussoirs);
  if (c->keystone_mm > 0.0 && (c->n_joint_positions > 0 || c->voussoirs % 2 == 0 ||
                               c->voussoirs < 3))
    return vs_error_set(err, VS_ERR_INVALID, "arch.keystone_mm = %.15g with arch.voussoirs = %d%s "
                        "(allowed: an odd number of voussoirs >= 3, no joint_positions)",
                        c->keystone_mm, c->voussoirs,
                        c->n_joint_positions > 0 ? " and arch.joint_positions" : "");
  if (c->shape == VS_SHAPE_FILE && c->blocks_file[0] == '\0')
    return vs_error_set(err, VS_ERR_INVALID, "arch.shape = file: no arch.blocks_file (allowed: "
                        "the JSON file of blocks)");
  return VS_OK;
}

/* Mortar (docs/model.md "Mortar joints"): the softening must end beyond the peak's opening,
 * G_f > f_t^2 / (2 k_n), and the cohesion's be slower than the shear's unloading,
 * G_c > c^2 / (2 k_s) (no snap-back within a joint). */
static vs_status validate_mortar(const vs_case *c, vs_error *err) {
  const double gf_min = c->tensile_MPa * c->tensile_MPa / (2.0 * c->kn_N_mm3);
  if (c->tensile_MPa > 0.0 && !(c->gf_N_mm > gf_min))
    return vs_error_set(err, VS_ERR_INVALID, "joints.gf_N_mm = %.15g: with joints.tensile_MPa = "
                        "%.15g must be > tensile_MPa^2 / (2 kn_N_mm3) = %.15g (allowed: the "
                        "softening ends beyond the peak's opening)", c->gf_N_mm, c->tensile_MPa,
                        gf_min);
  const double gc_min = c->cohesion_MPa * c->cohesion_MPa / (2.0 * c->ks_ratio * c->kn_N_mm3);
  if (c->cohesion_MPa > 0.0 && !(c->gc_N_mm > gc_min))
    return vs_error_set(err, VS_ERR_INVALID, "joints.gc_N_mm = %.15g: with joints.cohesion_MPa = "
                        "%.15g must be > cohesion_MPa^2 / (2 ks_ratio kn_N_mm3) = %.15g (allowed: "
                        "the cohesion softens more slowly than the joint unloads)", c->gc_N_mm,
                        c->cohesion_MPa, gc_min);
  return VS_OK;
}

vs_status vs_case_validate(const vs_case *c, vs_error *err) {
  if (c == NULL) return vs_error_set(err, VS_ERR_INVALID, "vs_case_validate: case is NULL");
  char range[96];
  for (size_t i = 0; i < NKEYS; i++) {
    const key_spec *k = &keys[i];
    if (k->type == KEY_TEXT || k->type == KEY_LIST) {
      vs_status st = validate_text(c, k, err);
      if (st != VS_OK) return st;
      continue;
    }
    double v = get_value(c, k);
    if (in_range(k, v)) continue;
    range_text(k, range, sizeof range);
    return vs_error_set(err, VS_ERR_INVALID, "%s.%s = %.15g: out of range (allowed: %s)",
                        k->section, k->name, v, range);
  }
  vs_status st = validate_shape(c, err);
  if (st == VS_OK) st = validate_mortar(c, err);
  if (st != VS_OK) return st;
  for (size_t i = 0; i < sizeof relations / sizeof relations[0]; i++) {
    const relation *r = &relations[i];
    double lo = get_value(c, find_key(r->lo_section, r->lo_name));
    double hi = get_value(c, find_key(r->hi_section, r->hi_name));
    if (r->strict ? lo < hi : lo <= hi) continue;
    return vs_error_set(err, VS_ERR_INVALID, "%s.%s = %.15g: must be %s %s.%s = %.15g (allowed: %s)",
                        r->lo_section, r->lo_name, lo, r->strict ? "<" : "<=", r->hi_section,
                        r->hi_name, hi, r->rule);
  }
  st = supports_validate(c, err);
  return st != VS_OK ? st : validate_analysis(c, err);
}

vs_status vs_case_check_path(const vs_case *c, const char *command, vs_error *err) {
  if (c->type == VS_ANALYSIS_SUPPORT) return VS_OK;
  /* sweep and montecarlo follow the load path too (their tables gain load_factor); calibrate
   * fits the support's collapse displacement */
  if (c->type == VS_ANALYSIS_LOAD && strcmp(command, "calibrate") != 0) return VS_OK;
  return vs_error_set(err, VS_ERR_INVALID,
                      "analysis.type = %s: %s follows the support's path (allowed: support%s; a "
                      "limit analysis: voussoir run CASE --set analysis.type=limit, with "
                      "analysis.hold_mm of the arch held there%s)",
                      analysis_types[c->type], command,
                      strcmp(command, "calibrate") != 0 ? ", load" : "",
                      strcmp(command, "calibrate") != 0
                          ? "; each load run's JSON carries the held arch's as limit"
                          : "");
}

double vs_case_span_mm(const vs_case *c) {
  const double pi = 3.14159265358979323846;
  if (c == NULL) return NAN;
  if (c->span_mm > 0.0) return c->span_mm;
  if (c->shape == VS_SHAPE_FILE) return NAN;
  return 2.0 * c->radius_mm * sin(0.5 * c->embrace_deg * pi / 180.0);
}

int vs_case_key_count(void) { return (int)NKEYS; }

int vs_case_text_key_count(void) { return (int)NTEXT; }

int vs_case_text_key(const vs_case *c, int i, const char **section, const char **key, char *text,
                     size_t size) {
  if (i < 0 || (size_t)i >= NTEXT) return -1;
  if (section != NULL) *section = text_keys[i].section;
  if (key != NULL) *key = text_keys[i].name;
  if (text != NULL && size > 0) path_text(path_field((vs_case *)(uintptr_t)c, &text_keys[i]), text, size);
  return 0;
}

double vs_case_loading_rate_mm_s(const vs_case *c) {
  return c->rate_mm_s > 0.0 ? c->rate_mm_s : c->left_rate_mm_s > 0.0 ? c->left_rate_mm_s : 0.0;
}

/* A case path in SI (def.h). */
static vs_support_path_def path_def(const vs_case_path *p) {
  vs_support_path_def d = {.n = p->n};
  for (int i = 0; i < p->n && i < VS_SUPPORT_PATH_MAX; i++) {
    d.t[i] = p->t_s[i];
    d.dx[i] = p->dx_mm[i] * VS_MM;
    d.dz[i] = p->dz_mm[i] * VS_MM;
    d.rot[i] = p->rot_deg[i] * VS_DEG;
  }
  return d;
}

int vs_case_key_text(const vs_case *c, int i, char *buf, size_t size) {
  if (i < 0 || (size_t)i >= NKEYS) return -1;
  const key_spec *k = &keys[i];
  if (k->type != KEY_TEXT && k->type != KEY_LIST) return 0;
  if (size == 0) return 1;
  const char *p = (const char *)c + k->offset;
  buf[0] = '\0';
  if (k->type == KEY_TEXT) {
    snprintf(buf, size, "%.*s", VS_ARCH_PATH_MAX - 1, p);
    return 1;
  }
  const int n = *(const int *)(const void *)((const char *)c + k->count_offset);
  const double *v = (const double *)(const void *)p;
  for (int j = 0; j < n && j < VS_ARCH_MAX_POSITIONS; j++) {
    char item[32];
    snprintf(item, sizeof item, "%s%.17g", j > 0 ? "," : "", v[j]);
    append(buf, size, item);
  }
  return 1;
}

int vs_case_key_range(const char *section, const char *key, double *min, int *min_incl,
                      double *max, int *max_incl) {
  const key_spec *k = section != NULL && key != NULL ? find_key(section, key) : NULL;
  if (k == NULL || k->type == KEY_TEXT || k->type == KEY_LIST || k->names != NULL) return -1;
  if (min != NULL) *min = k->min;
  if (min_incl != NULL) *min_incl = k->min_incl;
  if (max != NULL) *max = k->max;
  if (max_incl != NULL) *max_incl = k->max_incl;
  return 0;
}

const char *vs_case_key_name_of(int i, int value) {
  if (i < 0 || (size_t)i >= NKEYS || keys[i].names == NULL || value < 0) return NULL;
  for (int v = 0; keys[i].names[v] != NULL; v++)
    if (v == value) return keys[i].names[v];
  return NULL;
}

int vs_case_key(const vs_case *c, int i, const char **section, const char **key, const char **unit,
                int *is_int, double *value) {
  if (i < 0 || (size_t)i >= NKEYS) return -1;
  const key_spec *k = &keys[i];
  const char *field = (const char *)c + k->offset;
  if (section != NULL) *section = k->section;
  if (key != NULL) *key = k->name;
  if (unit != NULL) *unit = k->unit;
  if (is_int != NULL) *is_int = k->type == KEY_INT;
  if (value != NULL)
    *value = k->type == KEY_TEXT || k->type == KEY_LIST ? NAN
             : k->type == KEY_INT ? (double)*(const int *)(const void *)field
                                  : *(const double *)(const void *)field;
  return 0;
}

void vs_case_to_def(const vs_case *c, vs_run_def *d) {
  d->arch = (vs_arch_def){.radius = c->radius_mm * VS_MM,
                          .thickness = c->thickness_mm * VS_MM,
                          .embrace = c->embrace_deg * VS_DEG,
                          .depth = c->depth_mm * VS_MM,
                          .voussoirs = c->voussoirs,
                          .density = c->density_kg_m3,
                          .gravity = c->gravity_m_s2,
                          .shape = (vs_arch_shape)c->shape,
                          .span = c->span_mm * VS_MM,
                          .rise = c->rise_mm * VS_MM,
                          .eccentricity = c->eccentricity,
                          .haunch = c->haunch_deg * VS_DEG,
                          .thickness_springing = c->thickness_springing_mm * VS_MM,
                          .joints = (vs_joint_cut)c->joints,
                          .keystone = c->keystone_mm * VS_MM,
                          .n_positions = c->n_joint_positions};
  memcpy(d->arch.positions, c->joint_positions, sizeof d->arch.positions);
  memcpy(d->arch.blocks_file, c->blocks_file, sizeof d->arch.blocks_file);
  d->arch.piers = (vs_piers_def){.height = c->pier_height_mm * VS_MM,
                                 .width = c->pier_width_mm * VS_MM,
                                 .courses = c->pier_courses,
                                 .density = c->pier_density_kg_m3,
                                 .base_friction = c->pier_base_friction};
  d->joints = (vs_joints_def){.kn = c->kn_N_mm3 * VS_N_MM3,
                              .ks = c->ks_ratio * c->kn_N_mm3 * VS_N_MM3,
                              .mu = c->friction,
                              .ft = c->tensile_MPa * VS_MPA,
                              .c = c->cohesion_MPa * VS_MPA,
                              .gf = c->gf_N_mm * VS_N_MM,
                              .gc = c->gc_N_mm * VS_N_MM};
  d->support = (vs_support_def){.left_kind = (vs_support_kind)c->left_kind,
                                .right_kind = (vs_support_kind)c->right_kind,
                                .alpha = c->alpha_deg * VS_DEG,
                                .rate = c->rate_mm_s * VS_MM,
                                .max_delta = c->max_mm * VS_MM,
                                .left_alpha = c->left_alpha_deg * VS_DEG,
                                .left_rate = c->left_rate_mm_s * VS_MM,
                                .left_path = path_def(&c->left_path),
                                .right_path = path_def(&c->right_path)};
  d->path = (vs_path_def){.step = c->step_mm * VS_MM,
                          .step_max = c->step_max_mm * VS_MM,
                          .limit_tol = c->limit_tol_mm * VS_MM,
                          .newton_tol = c->newton_tol,
                          .newton_maxiter = c->newton_maxiter};
  d->hinges = (vs_hinge_def){.open = c->open_mm * VS_MM, .migrate = c->migrate_joints};
  d->dynamic = (vs_dynamic_def){.follow = c->follow,
                                .full = c->full,
                                .damping_model = (vs_damping_model)c->damping_model,
                                .damping = c->damping,
                                .rtol = c->rtol,
                                .atol_q = c->atol_mm * VS_MM,
                                .rest_factor = c->rest_factor,
                                .rest_time = c->rest_s,
                                .ring_periods = c->ring_periods,
                                .collapse_ke = c->collapse_ke,
                                .fall_time = c->fall_s,
                                .sample_dt = c->sample_s};
  d->fall = (vs_fall_def){.ground = c->ground_mm * VS_MM,
                          .scheme = (vs_fall_scheme)c->scheme,
                          .step = c->step_ms * 1e-3,
                          .slow_step = c->slow_factor * c->step_ms * 1e-3,
                          .slow_speed = c->slow_mm_s * VS_MM,
                          .max_sweeps = c->max_sweeps,
                          .solver = (vs_fall_solver)c->solver,
                          .restitution = c->restitution};
  d->imperfections = (vs_imperfection_def){.seed = c->seed,
                                           .sample = c->sample,
                                           .kn_cov = c->kn_cov,
                                           .kn_corr = c->kn_corr_mm * VS_MM,
                                           .face = c->face_mm * VS_MM,
                                           .angle_cov = c->angle_cov,
                                           .thickness_cov = c->thickness_cov,
                                           .support_dx = c->support_dx_mm * VS_MM,
                                           .support_dz = c->support_dz_mm * VS_MM,
                                           .tensile_cov = c->tensile_cov,
                                           .gf_cov = c->gf_cov,
                                           .debonded = c->debonded};
  d->max_wall_s = c->max_wall_s;
  d->load = (vs_load_def){.kind = (vs_load_kind)c->kind,
                          .value = c->value_N,
                          .x = c->x_mm * VS_MM,
                          .width = c->width_mm * VS_MM,
                          .spread = c->spread_deg * VS_DEG};
  d->analysis = (vs_analysis_def){.type = (vs_analysis_type)c->type, .hold = c->hold_mm * VS_MM};
  d->fill = (vs_fill_def){.unit_weight = c->unit_weight_kN_m3 * 1e3,
                          .level = c->level_mm * VS_MM,
                          .k_horizontal = c->k_horizontal};

}

const char *vs_load_kind_name(vs_load_kind k) {
  return k >= 0 && k < VS_LOAD_KIND_COUNT ? load_kinds[k] : "?";
}

void vs_run_def_default(vs_run_def *d) {
  vs_case c;
  vs_case_defaults(&c);
  vs_case_to_def(&c, d);
}
