/* A run's collapse as the studies tabulate it, in the JSON's terms (collapse_at.c). */
#ifndef VS_COLLAPSE_AT_H
#define VS_COLLAPSE_AT_H

#include "voussoir/run.h"

/* The span L the ratios are of, mm: the case's, or (a blocks file that does not give it) the
 * arch's own: the JSON's span_mm. */
double vs_study_span_mm(const vs_run *r);

/* Each support's own travel at delta (m), mm: left dx, dz, right dx, dz; outward and downward
 * positive; the motion the case prescribes, without an imperfect arch's offset (the JSON's
 * collapse.left and collapse.right). */
void vs_study_travel(const vs_run *r, double delta, double t[4]);

/* delta's components, % of L: along alpha when the right support moves alone, else the
 * supports' relative displacement (dz the right one's settlement below the left one, dx the
 * spreading); the JSON's dz_over_L_pct and dx_over_L_pct. */
void vs_study_components_pct(const vs_run *r, double delta, double *dz, double *dx);

#endif
