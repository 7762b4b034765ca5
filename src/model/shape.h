/* Private to the model: the arch shapes' generator (shape.c), which vs_geometry_create_arch and
 * the imperfect arches (imperfections.c) call. Not installed. */
#ifndef VOUSSOIR_SHAPE_H
#define VOUSSOIR_SHAPE_H

#include "voussoir/def.h"
#include "voussoir/geometry.h"
#include "voussoir/status.h"

/* Whether arch a is a circular arch of annular sectors (circular, normal joints, one thickness):
 * built by the sectors' closed forms (geometry.c), bit for bit as before shapes existed. */
int vs_shape_is_sectors(const vs_arch_def *a);

/* The circular arch's intrados radius and half-embrace (rad) from a's radius and embrace, or
 * from its span and rise when both are given. VS_ERR_INVALID when only one is, or the rise
 * exceeds half the span. */
vs_status vs_shape_circle(const vs_arch_def *a, double *radius, double *half_embrace,
                          vs_error *err);

/* The interior joints' positions as fractions of a length (the centre line's for normal joints,
 * the span for vertical ones; n - 1 of them into f): a's positions, or the keystone's and equal
 * voussoirs either side of it, or equal voussoirs. VS_ERR_INVALID naming the key when they do
 * not fit the voussoir count. length (m) gives the keystone's width its fraction. */
vs_status vs_shape_positions(const vs_arch_def *a, double length, double *f, vs_error *err);

/* Arch a (any shape but a file's) built from its intrados, centre line and extrados: joints cut
 * through the centre line at the positions (normal to it, or vertical), blocks with their
 * outlines and exact mass properties. size[i] scales voussoir i's length along the centre line
 * (the lengths then rescaled to fill it) and thick[i] its thickness (either NULL: 1). Errors
 * (VS_ERR_INVALID) name the case key at fault and what is allowed. */
vs_status vs_shape_build(const vs_arch_def *a, const double *size, const double *thick,
                         vs_geometry **out, vs_error *err);

/* The length of arch a's centre line (m), for a shape vs_shape_build builds. */
vs_status vs_shape_centre_length(const vs_arch_def *a, double *length, vs_error *err);

#endif
