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
} vs_arch_def;

/* The interfaces' law (joint.h): no-tension elastic normal response, elastic shear limited by
 * Coulomb friction. */
typedef struct {
  double kn; /* normal stiffness per unit area, N/m^3 */
  double ks; /* shear stiffness per unit area, N/m^3 */
  double mu; /* friction coefficient */
} vs_joints_def;

/* The supports: the left one is fixed in place, the right one moves by delta along a direction
 * alpha from the vertical (0: down, pi/2: outward) at a constant rate. */
typedef struct {
  vs_support_kind left_kind, right_kind;
  double alpha;     /* rad */
  double rate;      /* m/s */
  double max_delta; /* largest support displacement followed, m */
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
} vs_imperfection_def;

typedef struct {
  vs_arch_def arch;
  vs_joints_def joints;
  vs_support_def support;
  vs_path_def path;
  vs_hinge_def hinges;
  vs_dynamic_def dynamic;
  vs_fall_def fall;
  vs_imperfection_def imperfections;
  double max_wall_s; /* wall-time limit of the run, s (0: none): it then stops, as after the
                        stop flag, with VS_ERR_WALL_TIME */
} vs_run_def;

/* Fill d with the defaults: the reference specimen with k_n = 3 N/mm^3, settlement (alpha = 0),
 * the defaults of every solver; the same values as the case file's defaults (case.h). */
VS_API void vs_run_def_default(vs_run_def *d);

#endif
