/* The mechanism a motion turns about: the joints whose neighbouring bodies turn relative to each
 * other, grouped into (spread) hinges (docs/model.md, "Vocabulary"; docs/mortar.md, "The mode of a
 * mortared arch"). Private to the library (the run reads a mortared arch's collapse with it). */
#ifndef VOUSSOIR_MECHANISM_H
#define VOUSSOIR_MECHANISM_H

#include "voussoir/hinges.h"
#include "voussoir/model.h"

/* A joint turns in the mechanism when its relative rotation rate is at least VS_MECH_JOINT_SHARE
 * of the fastest joint's. A run of turning joints is one of the mechanism's hinges when one of
 * them is open and the run's rate is at least VS_MECH_OPEN_SHARE of the fastest run's (a rigid
 * four-bar's slowest hinge can turn at a few hundredths of its fastest: mode I's C), or, none of
 * them open (bonded joints bending), when its fastest joint turns at VS_MECH_CLOSED_SHARE of the
 * fastest joint's at least (the elastic joints' own turning, spread thin, stays below). */
#define VS_MECH_JOINT_SHARE 0.02
#define VS_MECH_OPEN_SHARE 0.02
#define VS_MECH_CLOSED_SHARE 0.1

/* The relative rotation rate of every joint, w[k] = omega_b - omega_a (rad/s, counter-clockwise;
 * a, b the joint's bodies, geometry.h), from the velocities v (vs_model_size entries, as q) at
 * support displacement delta (m) moving at ddelta = d(delta)/dt (m/s): a support's rotation rate
 * is its pinned rotation's velocity, or its prescribed motion's. w > 0 turns body b about the
 * joint's extrados edge (the intrados opens: a hinge at E), w < 0 about its intrados edge. */
void vs_mechanism_joint_rates(const vs_model *m, const double *v, double delta, double ddelta,
                              double *w);

/* The mechanism's hinges from the joints' rates w and states st (n joints; the states as the
 * hinge tracker sees them, to say which joints are open past opts->open): maximal runs of
 * consecutive joints that turn (VS_MECH_JOINT_SHARE) the same way, those that turn enough kept
 * (VS_MECH_OPEN_SHARE, VS_MECH_CLOSED_SHARE), then neighbouring ones of the same side within
 * opts->migrate joints of each other merged into one hinge (a spread or migrating one). A
 * hinge's side is the edge it turns about: the edge in contact of its most turning open joint
 * (which may be closing: turning against its opening), else the edge its rate turns it about.
 * Left to right into out (room for n); their count (0 when nothing turns). label is 0. */
int vs_mechanism_active(int n, const double *w, const vs_joint_state *st,
                        const vs_hinge_opts *opts, vs_active_hinge *out);

#endif
