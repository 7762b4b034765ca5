/* The case: every input parameter of a run, in the units engineers use for the specimen
 * (mm, N/mm^3, deg, kg/m^3), read from an INI file and validated before anything runs.
 * The engine never reads this struct: vs_case_to_def turns it into the run's definition
 * (def.h), in SI, once. */
#ifndef VOUSSOIR_CASE_H
#define VOUSSOIR_CASE_H

#include "voussoir/api.h"

#include <stddef.h>

#include "voussoir/def.h"
#include "voussoir/status.h"

/* A support's path in time as the case file gives it (support.left_path, support.right_path:
 * "t_s:dx_mm:dz_mm[:rot_deg], ..."), in its units; n = 0: none. def.h's vs_support_path_def
 * says what the points mean. */
typedef struct {
  int n;
  double t_s[VS_SUPPORT_PATH_MAX], dx_mm[VS_SUPPORT_PATH_MAX], dz_mm[VS_SUPPORT_PATH_MAX],
      rot_deg[VS_SUPPORT_PATH_MAX];
} vs_case_path;

typedef struct {
  /* [arch] segmental circular arch */
  double radius_mm;     /* intrados radius R, > 0, default 300 */
  double thickness_mm;  /* radial thickness t, > 0, default 24 */
  double embrace_deg;   /* angle of embrace, (0, 180], default 125 (symmetric about the crown) */
  int voussoirs;        /* number of voussoirs, 1..20000, default 55 */
  double depth_mm;      /* out-of-plane depth b, > 0, default 120 */
  double density_kg_m3; /* density, > 0, default 1640 */
  double gravity_m_s2;  /* gravitational acceleration, > 0, default 9.81 */
  /* [arch] shapes and stereotomy (docs/model.md, "Shapes"); the defaults: the circular arch */
  int shape;            /* vs_arch_shape by name: circular (default), pointed, elliptical, basket,
                           parabolic, catenary, file */
  double span_mm;       /* intrados span, [0, 1e6] mm; 0 (default): 2 R sin(embrace/2) */
  double rise_mm;       /* intrados rise, [0, 1e6] mm; 0 (default): R (1 - cos(embrace/2)) */
  double eccentricity;  /* pointed: each centre's offset from the crown line over the half-span,
                           [0, 10], default 0 (a semicircle) */
  double haunch_deg;    /* basket: the angle each haunch arc subtends, (0, 90), default 60 */
  double thickness_springing_mm; /* thickness at the springings, [0, 1e6] mm; 0 (default):
                                    thickness_mm throughout */
  int joints;           /* vs_joint_cut by name: normal (default) or vertical */
  double keystone_mm;   /* the keystone's width along the centre line (across, with vertical
                           joints), [0, 1e6] mm; 0 (default): as the other voussoirs */
  int n_joint_positions; /* joint_positions: the interior joints at these fractions of the
                            centre line's length (of the intrados span, with vertical joints),
                            increasing in (0, 1), voussoirs - 1 of them; none (default): equal
                            voussoirs */
  double joint_positions[VS_ARCH_MAX_POSITIONS];
  char blocks_file[VS_ARCH_PATH_MAX]; /* shape = file: the JSON of blocks, relative to the case
                                         file's folder (docs/blocks-file.md); default none */

  /* [piers] a pier under each springing (issue 28; docs/model.md, "Piers"); height 0: none */
  double pier_height_mm;  /* piers.height_mm: from the ground to the springing's intrados point,
                             [0, 1e6] mm, 0 (default): no piers */
  double pier_width_mm;   /* piers.width_mm: outward from the inner face, [1e-3, 1e6] mm, default
                             150 (more than the springing face's horizontal extent) */
  int pier_courses;       /* piers.courses: equal courses, 1 .. 100, default 4 */
  double pier_density_kg_m3; /* piers.density_kg_m3: 0 (default): the arch's, or [10, 1e5] */
  double pier_base_friction; /* piers.base_friction: of the foundation interface, 0 (default):
                                joints.friction, or (0, 100] */

  /* [joints] no-tension, frictional, elastic interfaces */
  double kn_N_mm3; /* normal stiffness per unit area, > 0, default 3 */
  double ks_ratio; /* shear stiffness k_s / k_n, > 0, default 0.5 */
  double friction; /* Coulomb friction coefficient mu, > 0, default 0.7 */
  /* mortar (joint.h, vs_joint_normal_mortar); all 0 by default: dry joints. Not yet used by the
   * model: vs_case_validate refuses a case that sets any of them */
  double tensile_MPa;  /* tensile strength f_t, [0, 100] */
  double cohesion_MPa; /* cohesion c, [0, 100] */
  double gf_N_mm;      /* mode-I fracture energy G_f, [0, 1000]; > f_t^2 / (2 k_n) with f_t > 0 */
  double gc_N_mm;      /* mode-II fracture energy G_c, [0, 1000]; > c^2 / (2 k_s) with c > 0 */

  /* [support] the right support moves, the left is fixed */
  double alpha_deg; /* direction from the vertical: 0 = settlement down, 90 = outward; [-180, 180], default 0 */
  double rate_mm_s; /* the right support's speed, 0 or [1e-6, 1e6], default 0.04; 0: it stays
                       (then left_rate_mm_s must be > 0) */
  double max_mm;    /* largest support displacement followed, > 0, default 300 */
  int left_kind;    /* vs_support_kind (model.h), by name: fixed (clamped) or pinned (the springer
                       rotates freely about the centre of its springing face); default fixed */
  int right_kind;   /* the same for the right (moving) support; default fixed */
  /* [support] both supports on their own paths (docs/model.md, "Both supports move") */
  double left_alpha_deg; /* direction of the left support's motion, mirrored: 0 = down, 90 =
                            outward (to the left); [-180, 180], default 0 */
  double left_rate_mm_s; /* its speed; 0 (the default): fixed. The loading rate (delta = rate
                            x time) is rate_mm_s, or this when rate_mm_s is 0 */
  vs_case_path left_path, right_path; /* text keys (vs_case_text_key): a path in time replaces
                                         the support's straight motion */

  /* [solver] quasi-static path (KINSOL) */
  double step_mm;      /* initial increment of the support displacement, > 0, default 0.5 */
  double step_max_mm;  /* largest increment, >= step_mm, default 2 */
  double limit_tol_mm; /* bisection tolerance on a limit point, (0, step_mm], default 1e-3 */
  double newton_tol;   /* scaled residual tolerance (fraction of a voussoir's weight), (0, 1e-2], default 1e-8 */
  int newton_maxiter;  /* Newton iterations per increment, 2..1000, default 8 (an increment that needs more is cut) */

  /* [hinges] what counts as a hinge */
  double open_mm;     /* edge opening beyond which a joint is open (a hinge), > 0, default 0.05 */
  int migrate_joints; /* a hinge that reappears within this many joints of where it was, on the
                         same side, is the same hinge that migrated; 0..100, default 3 */

  /* [dynamic] beyond the limit points (IDA) */
  int follow;          /* 1: follow every limit point dynamically to the collapse; 0: stop at the
                          first limit point. Default 1 */
  int full;            /* 1: integrate the whole loading dynamically from rest (no quasi-static
                          phase). Default 0 */
  int damping_model;   /* vs_damping_model (damping.h): none, joint, rayleigh, impact; written by
                          name in the file. Default joint */
  double damping;      /* damping ratio, [0, 1], default 0.05: joint, of each joint's critical
                          damping; rayleigh, of the two lowest modes under self-weight; none does
                          not use it */
  double rtol;         /* IDA relative tolerance, (0, 1e-2], default 1e-6 */
  double atol_mm;      /* IDA absolute tolerance on positions, > 0, default 1e-5 mm */
  double rest_factor;  /* at rest when the kinetic energy stays below this many times that of the
                          whole arch moving at the support's rate, [1, 1e12], default 100 */
  double rest_s;       /* ... for this long, > 0, default 1 s */
  double ring_periods; /* a mortared arch's snap is also over once it has rung this many periods
                          of its lowest natural frequency under self-weight with nothing
                          changing and its kinetic energy's peak falling (docs/mortar.md "Cost"),
                          [0, 1000], default 1; 0: the rest criterion alone; dry arches: unused */
  double collapse_ke;  /* collapsing when the kinetic energy exceeds this fraction of the arch's
                          weight times its thickness, > 0, default 0.1 */
  double fall_s;       /* after the collapse criterion, the fall is followed at most this long
                          (it ends once the debris is at rest on the ground), >= 0, default 5 s
                          (the reference arch is at rest 0.9 s after the detection) */
  double sample_s;     /* at most one dynamic sample per this interval, > 0, default 0.01 s */

  /* [fall] the ground the collapsed arch falls onto (contact.h) */
  double ground_mm;    /* the ground's height above the lower springing's base at the collapse,
                          [-1e6, 0] mm, default 0 */
  int scheme;          /* vs_fall_scheme: rigid (default: rigid blocks with impulsive contacts,
                          fall.h) or penalty (the joints' law at every contact, IDA: contact.h,
                          collide.h); written by name */
  double step_ms;      /* time step of the rigid scheme, [1e-3, 10] ms, default 1 ... */
  double slow_factor;  /* ... this many times longer, [1, 10], default 2, while no point of a
                          block moves faster than slow_mm_s, [0, 1e6] mm/s, default 500 */
  double slow_mm_s;
  int max_sweeps;      /* rigid scheme: Gauss-Seidel sweeps per step at most, 1..10000, default
                          15 (VS_FALL_MAX_SWEEPS; near rest at least VS_FALL_CALM_SWEEPS) */
  int solver;          /* rigid scheme: vs_fall_solver (fall.h), nncg (default) or gauss_seidel;
                          written by name */
  double restitution;  /* penalty scheme: coefficient of restitution of a block landing flat on
                          the ground, (0, 1], default 0.5 */

  /* [imperfections] drawn per (seed, sample) by src/model/imperfections.c; all zero: the perfect arch */
  int seed;             /* generator seed, 0..2147483647, default 1 */
  int sample;           /* sample number (montecarlo sets it), 0..2147483647, default 0 */
  double kn_cov;        /* CoV of each joint's k_n (lognormal, mean k_n), [0, 3], default 0 */
  double kn_corr_mm;    /* correlation length of that scatter along the arch, [0, 1e6] mm (0 independent) */
  double face_mm;       /* non-coplanar faces: std. dev. of the as-built gap at a joint's open edge, [0, 10] mm */
  double angle_cov;     /* CoV of the voussoirs' angular sizes (lognormal, closed), [0, 0.5] */
  double thickness_cov; /* CoV of the voussoirs' thickness (lognormal), [0, 0.5] */
  double support_dx_mm; /* initial offset of the moving support, outward, [-100, 100] mm, default 0 */
  double support_dz_mm; /* ... downward, [-100, 100] mm, default 0 */
  double tensile_cov;   /* mortar: CoV of each joint's f_t (lognormal, mean f_t), [0, 3], default 0 */
  double gf_cov;        /* mortar: CoV of each joint's G_f (lognormal, mean G_f), [0, 3], default 0 */
  double debonded;      /* mortar: probability that a joint is debonded (dry), [0, 1], default 0 */

  /* [load] the live load, scaled by the load factor (issue 28: limit.h) */
  int kind;          /* vs_load_kind: none (default), point, line, patch, tilt; written by name */
  double value_N;    /* point, line, patch: the load, N, downward, (0, 1e9], default 1 */
  double x_mm;       /* its position from the left springing's intrados point, horizontal,
                        [-1e6, 1e6] mm, default 0 */
  double width_mm;   /* patch: its horizontal width centred on x_mm, [0, 1e6] mm, default 0 */
  double spread_deg; /* point, line, patch: the spread angle through the fill from the
                        vertical, [0, 80] deg, 0 (the default): none */

  /* [analysis] what the run computes (issue 28) */
  int type;          /* vs_analysis_type: support (default: the support's path), load (the
                        live load's path to collapse), limit (the limit analysis alone, limit.h); by name */
  double hold_mm;    /* load: the support displacement held before loading, [0, 1e6] mm,
                        default 0 */

  /* [fill] the fill over the arch, a dead load on its extrados (issue 28) */
  double unit_weight_kN_m3; /* its unit weight, [0, 1000] kN/m^3, 0 (the default): no fill */
  double level_mm;          /* its surface above the crown's extrados, [0, 1e6] mm, default 0 */
  double k_horizontal;      /* the coefficient of its horizontal pressure on the extrados,
                               [0, 100], 0 (the default): none */

  /* [run] how long a run may take */
  double max_wall_s;    /* wall-time limit of a run, [0, 1e6] s, 0 (the default): none. Once
                           passed, the run stops at its next step (VS_ERR_WALL_TIME): its
                           record is closed, marked "stopped: wall-time limit S s reached" */
} vs_case;

/* Fill c with the defaults: the reference specimen (docs/model.md, "The reference specimen")
 * with k_n = 3 N/mm^3, alpha = 0. */
VS_API void vs_case_defaults(vs_case *c);

/* Read an INI case file (libinih) over the current contents of c (call vs_case_defaults first).
 * Every value is parsed and range-checked; the first problem is reported in err as
 * "FILE:LINE: section.key = value: reason (allowed: ...)" with VS_ERR_PARSE (malformed line,
 * unknown section or key, not a number, empty value, nan/inf) or VS_ERR_INVALID (out of range);
 * a file that cannot be opened or read gives VS_ERR_IO ("FILE: cannot open: reason").
 * Numbers take the forms of voussoir/parse.h (decimal; no hex, inf or nan). Only a regular file
 * of at most VS_CASE_MAX_BYTES is read (a FIFO, a device or a directory gives VS_ERR_IO, without
 * blocking). Lines end at LF, CR LF or CR; a key on the line of its section header
 * ("[arch] radius_mm = 3") is an error. Section and key names are case-sensitive; a key may appear twice, the later value wins.
 * Comments start with ';' or '#' at the beginning of a line or after a blank; leading blanks are
 * ignored (there are no continuation lines). c is changed only if the whole file is accepted.
 * If text_out is not NULL, *text_out receives a malloc'd copy of the file's text (caller frees)
 * for echoing, or NULL on failure. */
VS_API vs_status vs_case_read(vs_case *c, const char *path, char **text_out, vs_error *err);

/* Largest case file read, in bytes (1 MiB): a real case is a few hundred bytes; the text is also
 * copied into the record, so an unbounded file (or /dev/zero) must not reach it. */
#define VS_CASE_MAX_BYTES (1 << 20)

/* As vs_case_read, from text in memory (len bytes, need not be NUL-terminated; a NUL byte is an
 * error); name stands for the file in messages. Same rules, same messages, except that len above
 * VS_CASE_MAX_BYTES fails with VS_ERR_IO. */
VS_API vs_status vs_case_parse(vs_case *c, const char *name, const char *text, size_t len,
                               vs_error *err);

/* Apply one "section.key=value" override (the CLI's --set); blanks around the parts are
 * ignored. Errors as vs_case_read, with "--set section.key=value" in place of FILE:LINE;
 * c is unchanged on failure. */
VS_API vs_status vs_case_set(vs_case *c, const char *assignment, vs_error *err);

/* One assignment section.key = value (text), as a line of a case file makes it: checked against
 * the table (the key, the number or name, the range), c written only when the value is
 * accepted. where starts every message ("FILE:LINE", "--set ..."), as in "FILE:LINE:
 * arch.voussoirs = 0: out of range (allowed: integer in [1, 2000])". The file reader and --set
 * use it, and so do readers of other files that carry case keys (a Monte Carlo shard's table).
 * VS_ERR_PARSE or VS_ERR_INVALID with the message in err. */
VS_API vs_status vs_case_assign(vs_case *c, const char *section, const char *key, const char *value,
                                const char *where, vs_error *err);

/* Check every field's range again (fields may have been set in code) and the relations between
 * fields: limit_tol_mm <= step_mm <= step_max_mm and step_mm < max_mm; analysis.type = load
 * needs a live load and dynamic.full = 0; a non-zero analysis.hold_mm needs analysis.type =
 * load and is < max_mm; a live load (load.kind) needs analysis.type = load or limit. Call it after all overrides. Fails with VS_ERR_INVALID; err names the
 * field(s) and the allowed range. */
VS_API vs_status vs_case_validate(const vs_case *c, vs_error *err);

/* VS_OK when c follows a path that `command` (a name, "sweep") can study: the support's
 * (analysis.type = support), or the live load's (load) for any command but "calibrate"; else
 * VS_ERR_INVALID saying so: the study commands' check. */
VS_API vs_status vs_case_check_path(const vs_case *c, const char *command, vs_error *err);

/* The case's keys, from the one table that defines them (so that records and tools cannot miss
 * a key): how many, and key i (0-based, in the table's order) with its section, name, unit ("" if
 * dimensionless), whether it is an integer, and its value in c. Returns 0, or -1 when i is out of
 * range (the outputs are then untouched). Any output pointer may be NULL. */
VS_API int vs_case_key_count(void);
VS_API int vs_case_key(const vs_case *c, int i, const char **section, const char **key,
                       const char **unit, int *is_int, double *value);

/* For a key whose value is text (arch.blocks_file) or a list (arch.joint_positions): its value
 * in c as a case file writes it, into buf (size bytes, cut short if longer); returns 1. Returns
 * 0 for a number or a named choice (buf untouched), -1 when i is out of range. vs_case_key gives
 * such a key the value NaN. */
VS_API int vs_case_key_text(const vs_case *c, int i, char *buf, size_t size);

/* The range number key section.key accepts, from the key table: its ends and whether each is
 * included (joints, kn_N_mm3: [1e-4, 1e6], both included; an end may be -/+INFINITY; a key that
 * also takes 0, such as a support's rate, takes it besides this range). Returns 0, or -1 when
 * there is no such key or it is text, a list or a named choice (the outputs are then untouched).
 * Any output pointer may be NULL. A tool's option that sets a key takes its range from here. */
VS_API int vs_case_key_range(const char *section, const char *key, double *min, int *min_incl,
                             double *max, int *max_incl);

/* For a key that is a named choice (support.left_kind, support.right_kind, dynamic.damping_model), the name of value `value` of key i;
 * NULL when key i is a number or value is out of range. */
VS_API const char *vs_case_key_name_of(int i, int value);

/* The keys whose value is text, not a number (support.left_path, support.right_path): they are
 * not among vs_case_key's. (Two mechanisms for text values, this one and vs_case_key_text's keys
 * in the main table: folding the paths into the main table would change vs_case_key_count, the
 * records' /parameters and the study manifests, and drop these two exported functions, an ABI
 * change: left for a release that raises VS_SOVERSION.) How many, and key i's section and name, and its value in c as the
 * case file would give it ("" when unset; text of at most size - 1 bytes, cut short beyond).
 * Returns 0, or -1 when i is out of range. Any output pointer may be NULL. */
VS_API int vs_case_text_key_count(void);
VS_API int vs_case_text_key(const vs_case *c, int i, const char **section, const char **key,
                            char *text, size_t size);

/* The loading rate in mm/s: rate_mm_s, or left_rate_mm_s when it is 0 (delta = this x time;
 * the same as vs_support_loading_rate of the case's definition, in mm/s). */
VS_API double vs_case_loading_rate_mm_s(const vs_case *c);

/* Intrados span L, in mm: the length the study normalises by; arch.span_mm when it is given,
 * else 2 R sin(embrace/2) (a blocks file's arch: NaN when span_mm is not given, the run's
 * geometry knows it). */
VS_API double vs_case_span_mm(const vs_case *c);

/* The engine's definition of the run case c asks for (def.h): every length, angle, stiffness
 * and speed converted to SI once, here (units.h factors; nothing else is derived). */
VS_API void vs_case_to_def(const vs_case *c, vs_run_def *d);

#endif
