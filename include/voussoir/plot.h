/* Pictures with cairo, PNG or SVG: the arch in a deformed state at true scale (voussoirs, open
 * joints, hinges, supports). A pure drawing module: it reads no records; the caller passes the
 * data, in SI units. The charts (curves against the support displacement, a sweep's domain, a
 * Monte Carlo study's fragility) are drawn with matplotlib by the Python package's
 * voussoir.figures. */
#ifndef VOUSSOIR_PLOT_H
#define VOUSSOIR_PLOT_H

#include "voussoir/api.h"

#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/limit.h"
#include "voussoir/status.h"

typedef enum { VS_PLOT_PNG = 0, VS_PLOT_SVG = 1 } vs_plot_format;

/* Picture sizes, px (SVG: the same size in CSS px). */
#define VS_PLOT_ARCH_WIDTH 1200
#define VS_PLOT_ARCH_HEIGHT 700

/* Format named by a file name's extension: ".svg" (any case) is SVG, anything else PNG. */
VS_API vs_plot_format vs_plot_format_from_path(const char *path);

/* Release the caches that cairo and fontconfig keep for the whole process (fonts, font
 * patterns), so that a leak checker (the sanitizer build) reports only real leaks. Call it at the
 * end of a process that drew pictures (main's cleanup, a test's teardown), when no other thread
 * draws; pictures drawn afterwards still work, the caches are rebuilt. */
VS_API void vs_plot_release(void);

/* ---------------------------------------------------------------------------------------------
 * The arch */

/* Mapping of the arch picture from model coordinates (x right, z up, m) to picture coordinates
 * (px from the top-left corner, y down): px = x0 + scale x, py = y0 - scale z. One scale for x
 * and z: the picture is at true scale. */
typedef struct {
  int width, height; /* picture size, px */
  double scale;      /* px per m */
  double x0, y0;     /* picture position of the model origin (the arch's centre), px */
} vs_plot_frame;

static inline void vs_plot_to_px(const vs_plot_frame *f, double x, double z, double *px,
                                 double *py) {
  *px = f->x0 + f->scale * x;
  *py = f->y0 - f->scale * z;
}

/* One arch picture: the arch of g in state q with its supports, open joints, hinges, thrust
 * line and the ground of a fall. Plain data; a field left zero (a designated initialiser) is
 * "none" or the nominal arch, so { .g = g, .q = q } draws the bare arch.
 *   - g: the arch (any geometry whose blocks have outlines, vs_geometry_set_outline, and whose
 *     first and last joints are on the left and the right support);
 *   - q: 3 n_blocks entries (ux, uz in m, theta in rad per block, as vs_model); NULL: the
 *     reference configuration;
 *   - delta_m, alpha_rad: the right support moved by delta_m along alpha_rad from the vertical,
 *     (sin alpha, -cos alpha);
 *   - hinges[0..n_hinges-1]: the hinges worth naming (those of the report; NULL when n_hinges
 *     is 0), each open one drawn and labelled, closed ones skipped;
 *   - joint_gap_i, joint_gap_e: joint k's edge openings at [k-1] (m, > 0 open, n_joints entries
 *     each, as vs_joint_state); a joint opening beyond open_m (m, >= 0) is shaded. Either
 *     array NULL: no joint is shaded;
 *   - joint_N, joint_M: the joints' forces (n_joints entries each, N and N m, as
 *     vs_joint_state: compression > 0, moment about the joint centre > 0 when the extrados
 *     carries more) for the thrust line; either NULL: no thrust line;
 *   - title: drawn on top (NULL or "": none);
 *   - block_thickness: each voussoir's radial thickness, m (n_blocks; NULL: none), for an arch
 *     whose thickness scatters (the record's imperfections): checked only, the outlines being
 *     the geometry's own (vs_imperfections_arch builds them at those thicknesses);
 *   - pinned[s], support_theta[s] (s = 0 left, 1 right): a pinned support's springer, drawn as a
 *     plate under the springing face turned by support_theta (rad, counter-clockwise) about the
 *     pin at the face's centre, and the support's side of that joint turned with it. A fixed
 *     support (pinned 0) must have support_theta 0;
 *   - has_ground, ground_z: the ground the fall landed on (contact.h), the plane z = ground_z
 *     (m), drawn across the picture, hatched below, named and kept in the frame (has_ground 0:
 *     none).
 * Errors of every function taking it: VS_ERR_INVALID for a NULL a or g, a geometry that is not
 * an arch, non-finite q, delta_m or alpha_rad, n_hinges < 0 (or > 0 with NULL hinges), a hinge
 * whose joints are outside 1..n_joints or whose side is not 'I'/'E', a negative open_m, a block
 * thickness not > 0, a non-finite springer rotation or a non-zero one on a fixed
 * support, a non-finite ground_z with has_ground. */
typedef struct {
  const vs_geometry *g;
  const double *q;
  double delta_m, alpha_rad;
  const vs_hinge *hinges;
  int n_hinges;
  const double *joint_gap_i, *joint_gap_e;
  double open_m;
  const double *joint_N, *joint_M;
  const char *title;
  const double *block_thickness;
  int pinned[2];
  double support_theta[2];
  int has_ground; /* 1: draw the ground the fall landed on, the plane z = ground_z (m) */
  double ground_z;
  /* both supports (model.h, vs_model_support_position): left (ux, uz, theta), then right (m, m,
   * rad), as the record's /observables/supports; each drawn where it is, a moved one with its
   * arrow, a fixed one turned by its path turned. NULL: the right one by delta_m along
   * alpha_rad, the left one in place. Non-finite values: VS_ERR_INVALID. */
  const double *supports;
  /* the live load (issue 28): loads[0 .. n_loads-1] as vs_limit_live_load gives them (the
   * reference configuration; NULL, 0: none), each vertical force drawn as an arrow down onto its
   * point moved with its block, its length growing with the force; a horizontal one (tilt) is
   * not drawn as arrows: load_note (NULL or "": none) names it under the title. Forces or points
   * not finite, or a block out of range: VS_ERR_INVALID. */
  const vs_limit_force *loads;
  int n_loads;
  const char *load_note;
} vs_plot_arch_args;

/* Draw the arch picture a into the file path (created anew: a regular file there is replaced;
 * a symbolic link, FIFO, device or directory is refused, never written through) as a PNG or SVG
 * picture of VS_PLOT_ARCH_WIDTH x VS_PLOT_ARCH_HEIGHT at true scale (vs_plot_arch_frame):
 *   - the reference arch faint in the background, each voussoir of state q as a filled polygon
 *     (its outline's curved edges sampled at least every degree, moved rigidly:
 *     x = c + u + R(theta)(X - c));
 *   - the supports: the left fixed; the right moved, its fixed position dashed and an arrow for
 *     the displacement; a pinned one's springer turned;
 *   - open joints: a wedge between the two moved faces and the joint line, in red;
 *   - each open hinge as a dot in its label's colour on the side that stays in contact ('I'
 *     intrados, 'E' extrados) of its middle joint (between the two middle ones of an even
 *     spread), smaller dots on the other joints of a spread hinge, and its label beside it,
 *     outside the section on that side: "A  9-I", "B  27-28-29-30-E", beyond four joints
 *     "E  12-...-40-E";
 *   - the thrust line through the joints' centres of pressure (vs_plot_thrust_points), broken
 *     where a joint carries no compression, named in the key;
 *   - the ground, the title, "delta = .. mm (dz .. mm, dx .. mm)", a scale bar in mm and a key.
 * Errors: as vs_plot_arch_args, and VS_ERR_INVALID for a NULL path or a format outside
 * vs_plot_format; VS_ERR_IO when the file cannot be created (something other than a regular
 * file at path included) or written or cairo fails ("PATH: ...: cairo's status string"; a
 * partly written file is removed); VS_ERR_NOMEM. Nothing is printed. */
VS_API vs_status vs_plot_arch_draw(const char *path, vs_plot_format fmt, const vs_plot_arch_args *a,
                                   vs_error *err);

/* The frame vs_plot_arch_draw uses for a: the smallest box holding the reference arch, the
 * deformed voussoirs, both supports (the right one at its fixed and its moved position) and the
 * ground, fitted with margins into VS_PLOT_ARCH_WIDTH x VS_PLOT_ARCH_HEIGHT and centred. Errors
 * as vs_plot_arch_args. */
VS_API vs_status vs_plot_arch_frame(const vs_plot_arch_args *a, vs_plot_frame *f, vs_error *err);

/* The points the thrust line of vs_plot_arch_draw joins, in model coordinates (m): x[k], z[k]
 * for joint k + 1 (n_joints entries each), the centre of pressure e = M/N from the centre of
 * the moved joint (the mean of its two moved faces) towards its extrados; NaN where the joint
 * carries no compression (N <= 0). Errors: as vs_plot_arch_args, and VS_ERR_INVALID for a NULL
 * joint_N, joint_M, x or z. */
VS_API vs_status vs_plot_thrust_points(const vs_plot_arch_args *a, double *x, double *z,
                                       vs_error *err);

#endif
