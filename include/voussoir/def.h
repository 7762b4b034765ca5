/* The definition of a run: plain data, in SI units (m, rad, kg, N, s), that a user or a front
 * end fills and the engine reads. The structure (the arch, its joints, its supports), how the
 * supports move, and the settings of each solver. The engine (the model, the solvers, the fall,
 * the run) takes this, never a case file's own structure: the INI front end (case.h) is one way
 * to fill it (vs_case_to_def), code is another. vs_run_def_default gives the reference specimen.
 *
 * Every struct here is plain data: copy it, fill it field by field, keep it on the stack. */
#ifndef VOUSSOIR_DEF_H
#define VOUSSOIR_DEF_H

#include "voussoir/api.h"

/* Each enum below ends with its count, VS_..._COUNT: not a value but the number of values
 * (0 .. COUNT - 1), so that a table with an entry per value (its names) is checked against the
 * enum when it compiles. */

/* A support: clamped, or rotating freely about the centre of its springing face. */
typedef enum {
  VS_SUPPORT_FIXED = 0,
  VS_SUPPORT_PINNED = 1,
  VS_SUPPORT_KIND_COUNT
} vs_support_kind;

/* Damping of the dynamic phase (damping.h). */
typedef enum {
  VS_DAMPING_NONE = 0,
  VS_DAMPING_JOINT = 1,
  VS_DAMPING_RAYLEIGH = 2,
  VS_DAMPING_IMPACT = 3,
  VS_DAMPING_MODEL_COUNT
} vs_damping_model;

/* How the fall after the collapse is integrated: rigid blocks with impulsive contacts (fall.h),
 * or the joints' law at every contact under IDA (contact.h, collide.h). */
typedef enum {
  VS_FALL_RIGID = 0,
  VS_FALL_PENALTY = 1,
  VS_FALL_SCHEME_COUNT
} vs_fall_scheme;

/* The rigid fall's contact solver (fall.h). */
typedef enum {
  VS_FALL_NNCG = 0,        /* Gauss-Seidel sweeps, each followed by a nonsmooth nonlinear
                              conjugate gradient step (the default) */
  VS_FALL_GAUSS_SEIDEL = 1, /* Gauss-Seidel sweeps alone */
  VS_FALL_SOLVER_COUNT
} vs_fall_solver;

/* The live load (issue 28; limit.h): none, a vertical point load on the extrados, a knife-edge
 * line load across the barrel, a patch (uniform over a horizontal width), or "tilt": a
 * horizontal body force lambda x each block's weight (a quasi-static seismic coefficient). */
typedef enum {
  VS_LOAD_NONE = 0,
  VS_LOAD_POINT = 1,
  VS_LOAD_LINE = 2,
  VS_LOAD_PATCH = 3,
  VS_LOAD_TILT = 4,
  VS_LOAD_KIND_COUNT
} vs_load_kind;

/* What a run computes: the support's path (today's), the live load's path to collapse (not yet
 * available), or the limit analysis alone (limit.h). */
typedef enum {
  VS_ANALYSIS_SUPPORT = 0,
  VS_ANALYSIS_LOAD = 1,
  VS_ANALYSIS_LIMIT = 2,
  VS_ANALYSIS_TYPE_COUNT
} vs_analysis_type;

/* The shape of an arch (geometry.h; docs/model.md, "Shapes"). */
typedef enum {
  VS_SHAPE_CIRCULAR = 0,   /* segmental or semicircular: radius and embrace, or span and rise */
  VS_SHAPE_POINTED = 1,    /* two-centred: span and eccentricity */
  VS_SHAPE_ELLIPTICAL = 2, /* a half-ellipse on the springing line: span and rise */
  VS_SHAPE_BASKET = 3,     /* three-centred, tangent arcs: span, rise and the haunch arcs' angle */
  VS_SHAPE_PARABOLIC = 4,  /* span and rise */
  VS_SHAPE_CATENARY = 5,   /* span and rise */
  VS_SHAPE_FILE = 6,       /* the blocks of a JSON file (blocks_file) */
  VS_SHAPE_COUNT
} vs_arch_shape;

/* How the voussoirs are cut: joints normal to the centre line (radial on a circle), or
 * vertical; the springing faces are normal to it either way. */
typedef enum {
  VS_JOINTS_NORMAL = 0,
  VS_JOINTS_VERTICAL = 1,
  VS_JOINT_CUT_COUNT
} vs_joint_cut;

/* Most interior joints a list of joint positions gives, and the longest blocks file name. */
#define VS_ARCH_MAX_POSITIONS 64
#define VS_ARCH_PATH_MAX 1024

/* Piers under the springings (issue 28; docs/model.md, "Piers"): under each springing a stack
 * of equal courses, its inner face flush with the springing's intrados point, its width outward
 * from there, its height from the ground up to that point, its top course cut along the
 * springing joint (a skewback). Each course is a rigid block, the course joints have the joints'
 * law, and the pier stands on the support, now its foundation, across an interface of friction
 * base_friction. height 0: no piers (the springings on the supports). */
#define VS_PIERS_MAX_COURSES 100
typedef struct {
  double height;        /* m; 0: no piers */
  double width;         /* m, > the springing face's horizontal extent */
  int courses;          /* 1 .. VS_PIERS_MAX_COURSES */
  double density;       /* kg/m^3; 0: the arch's */
  double base_friction; /* friction of the foundation interface; 0: the joints' */
} vs_piers_def;

/* An arch: by default (the fields after gravity all 0) a segmental circular arch of equal
 * voussoirs with radial joints (geometry.h). */
typedef struct {
  double radius;    /* intrados radius, m */
  double thickness; /* radial thickness (at the crown), m */
  double embrace;   /* angle of embrace, rad, symmetric about the crown */
  double depth;     /* out-of-plane depth, m */
  int voussoirs;    /* number of voussoirs */
  double density;   /* kg/m^3 */
  double gravity;   /* m/s^2 */
  /* shapes and stereotomy (issue 27; docs/model.md, "Shapes") */
  vs_arch_shape shape;
  double span, rise;          /* intrados span and rise, m (0: those of radius and embrace) */
  double eccentricity;        /* pointed: each centre's offset from the crown line, a fraction
                                 of the half-span (0: semicircle, 1: equilateral) */
  double haunch;              /* basket: the angle each haunch arc subtends, rad */
  double thickness_springing; /* thickness at the springings, m (0: thickness throughout);
                                 between, t(x) = t_c + (t_s - t_c) (x / (span/2))^2 */
  vs_joint_cut joints;
  double keystone;            /* the keystone's width along the centre line (across, with
                                 vertical joints), m (0: as the other voussoirs) */
  int n_positions;            /* interior joints at positions[0 .. n_positions - 1], fractions
                                 of the centre line's length (of the intrados span, with
                                 vertical joints; 0: equal voussoirs) */
  double positions[VS_ARCH_MAX_POSITIONS];
  char blocks_file[VS_ARCH_PATH_MAX]; /* VS_SHAPE_FILE: the JSON file of blocks */
  vs_piers_def piers; /* the piers under the springings (issue 28; zero: none) */
} vs_arch_def;

/* The interfaces' law (joint.h): no-tension elastic normal response, elastic shear limited by
 * Coulomb friction; with mortar (ft, c > 0; vs_joint_normal_mortar) tension and cohesion that
 * soften to zero (vs_run checks their ranges). */
typedef struct {
  double kn; /* normal stiffness per unit area, N/m^3 */
  double ks; /* shear stiffness per unit area, N/m^3 */
  double mu; /* friction coefficient */
  double ft, c;  /* mortar's tensile strength and cohesion, Pa (0: dry) */
  double gf, gc; /* mode-I and mode-II fracture energies, N/m (J/m^2) */
} vs_joints_def;

/* Points of a support's path in time (vs_support_def): the support stands in place at t = 0,
 * reaches point i at time t[i], moves linearly in between and along the last segment beyond. */
#define VS_SUPPORT_PATH_MAX 32
typedef struct {
  int n;                          /* points, 0 .. VS_SUPPORT_PATH_MAX; 0: no path */
  double t[VS_SUPPORT_PATH_MAX];  /* s, increasing, >= 0 (the first may be 0: the origin) */
  double dx[VS_SUPPORT_PATH_MAX]; /* outward displacement, m (the right support: +x, left: -x) */
  double dz[VS_SUPPORT_PATH_MAX]; /* downward displacement, m */
  double rot[VS_SUPPORT_PATH_MAX]; /* rotation about the centre of the springing face, rad,
                                      outward positive (the right support clockwise, the left
                                      counter-clockwise); a pinned support takes none */
} vs_support_path_def;

/* The supports. The right one moves by delta along a direction alpha from the vertical (0: down,
 * pi/2: outward) at a constant rate: the loading time is t = delta / rate. Each support may
 * move on its own besides (support.h, docs/model.md "Both supports move"): the left one along
 * left_alpha, mirrored (pi/2: outward, to the left), at left_rate, or either along a path in
 * time, which replaces its straight motion. delta is always the loading rate times t, the
 * loading rate being rate, or left_rate when rate is 0 (the right support then stays, unless
 * its path moves it): with the right support alone moving, delta is its travel. */
typedef struct {
  vs_support_kind left_kind, right_kind;
  double alpha;     /* rad */
  double rate;      /* m/s, >= 0 (0: the right support does not move along alpha) */
  double max_delta; /* largest support displacement followed, m */
  /* both supports on their own paths (all zero: the left fixed, no path) */
  double left_alpha; /* rad, mirrored: 0 down, pi/2 outward (-x) */
  double left_rate;  /* m/s, >= 0 (0: fixed) */
  vs_support_path_def left_path, right_path;
} vs_support_def;

/* The quasi-static path (quasistatic.h). */
typedef struct {
  double step, step_max; /* initial and largest increment of delta, m */
  double limit_tol;      /* bisection tolerance on a limit point, m */
  double newton_tol;     /* scaled residual tolerance (fraction of a voussoir's weight) */
  int newton_maxiter;    /* Newton iterations per increment */
} vs_path_def;

/* What counts as a hinge (hinges.h). */
typedef struct {
  double open; /* edge opening beyond which a joint is open, m */
  int migrate; /* a hinge reappearing within this many joints on its side is the same hinge */
} vs_hinge_def;

/* Beyond the limit points (dynamic.h). */
typedef struct {
  int follow; /* 1: every limit point followed to the collapse; 0: stop at the first */
  int full;   /* 1: the whole loading dynamic from rest */
  vs_damping_model damping_model;
  double damping;                 /* damping ratio (joint: of each joint's critical; rayleigh:
                                     of the two lowest modes) */
  double rtol;                    /* IDA relative tolerance */
  double atol_q;                  /* IDA absolute tolerance on positions, m */
  double rest_factor;             /* at rest below this many times the kinetic energy of the arch
                                     moving bodily at the support's rate ... */
  double rest_time;               /* ... for this long, s */
  double ring_periods;            /* a mortared arch's ringing window, in periods of its lowest
                                     mode under self-weight (0: none; vs_dyn_opts's
                                     ring_window) */
  double collapse_ke;             /* collapsing beyond this fraction of weight x thickness,
                                     J/(N m) */
  double fall_time;               /* the fall followed at most this long after the collapse, s */
  double sample_dt;               /* at most one dynamic sample per this interval, s */
} vs_dynamic_def;

/* The ground and the fall after the collapse (fall.h, contact.h). */
typedef struct {
  double ground;          /* the ground's height above the lower springing at the collapse, m */
  vs_fall_scheme scheme;
  double step;            /* rigid scheme's time step, s ... */
  double slow_step;       /* ... and its step while every block is slow, s */
  double slow_speed;      /* "slow": no point of a block faster than this, m/s */
  int max_sweeps;         /* Gauss-Seidel sweeps per step at most */
  vs_fall_solver solver;
  double restitution;     /* penalty scheme: restitution of a block landing flat */
} vs_fall_def;

/* Imperfections drawn per (seed, sample) (imperfections.h); all amplitudes 0: the perfect arch. */
typedef struct {
  int seed, sample;
  double kn_cov;        /* CoV of each joint's k_n (lognormal) */
  double kn_corr;       /* correlation length of that scatter along the arch, m (0 independent) */
  double face;          /* std. dev. of the as-built gap at a joint's open edge, m */
  double angle_cov;     /* CoV of the voussoirs' angular sizes */
  double thickness_cov; /* CoV of the voussoirs' thickness */
  double support_dx;    /* initial offset of the moving support, outward, m */
  double support_dz;    /* ... downward, m */
  /* mortar (joints' ft, gf > 0): each joint's f_t and G_f scattered (lognormal, mean the
   * nominal), and a fraction of the joints debonded (f_t = c = 0: dry) */
  double tensile_cov;   /* CoV of each joint's tensile strength f_t */
  double gf_cov;        /* CoV of each joint's fracture energy G_f */
  double debonded;      /* probability that a joint is debonded, [0, 1] */
} vs_imperfection_def;

/* The live load, scaled by the load factor lambda (limit.h). */
typedef struct {
  vs_load_kind kind;
  double value; /* point, line, patch: the load, N, downward (tilt: unused) */
  double x;     /* its position: horizontal distance from the left springing's intrados point, m */
  double width; /* patch: its horizontal width, centred on x, m */
  double spread; /* point, line, patch: the load's spread angle through the fill, rad (0: none),
                    from the vertical: on the extrados, width + 2 h tan(spread), h the fill's
                    depth over the extrados at x (limit.h vs_limit_live_load) */
} vs_load_def;

/* What the run computes (vs_analysis_type) and, for a load path, the support displacement held
 * before loading. */
typedef struct {
  vs_analysis_type type;
  double hold; /* m */
} vs_analysis_def;

/* The fill over the arch as a dead load (issue 28, item 2; limit.h vs_limit_fill_load): its unit
 * weight (0: no fill) up to a level above the crown's extrados, on the extrados, and its
 * horizontal pressure on the haunches with a stated coefficient. */
typedef struct {
  double unit_weight; /* N/m^3 */
  double level;       /* the fill's surface above the crown's extrados, m */
  double k_horizontal; /* the coefficient of its horizontal pressure on the extrados (0: none):
                          k_horizontal x unit_weight x the depth below the surface, inward */
} vs_fill_def;

typedef struct {
  vs_arch_def arch;
  vs_joints_def joints;
  vs_support_def support;
  vs_path_def path;
  vs_hinge_def hinges;
  vs_dynamic_def dynamic;
  vs_fall_def fall;
  vs_imperfection_def imperfections;
  vs_load_def load;         /* the live load (issue 28) */
  vs_analysis_def analysis; /* what the run computes (issue 28) */
  vs_fill_def fill;         /* the fill's dead load (issue 28) */
  double max_wall_s; /* wall-time limit of the run, s (0: none): it then stops, as after the
                        stop flag, with VS_ERR_WALL_TIME */
} vs_run_def;

/* The case file's name of a load kind (load.kind: "point"), "?" when k is none of them. */
VS_API const char *vs_load_kind_name(vs_load_kind k);

/* Fill d with the defaults: the reference specimen with k_n = 3 N/mm^3, settlement (alpha = 0),
 * the defaults of every solver; the same values as the case file's defaults (case.h). */
VS_API void vs_run_def_default(vs_run_def *d);

#endif
