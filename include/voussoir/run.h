/* A run: one case taken from self-weight along the quasi-static path to its first limit point,
 * with hinges tracked at every equilibrium. Owns its geometry, model and hinge tracker. */
#ifndef VOUSSOIR_RUN_H
#define VOUSSOIR_RUN_H

#include <stdio.h>

#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/hinges.h"
#include "voussoir/model.h"
#include "voussoir/quasistatic.h"

typedef struct vs_run vs_run;

/* Called after every equilibrium with the run (for progress and recording). Non-zero stops. */
typedef int (*vs_run_step_fn)(void *user, const vs_run *run, double delta, const double *q);

/* Build everything for case c (copied). Errors: VS_ERR_INVALID / VS_ERR_NOMEM. */
vs_status vs_run_create(const vs_case *c, vs_run **out, vs_error *err);
void vs_run_destroy(vs_run **r);

/* Follow the path. The status is that of the path (VS_OK at a confirmed limit point or at
 * max_mm); the run keeps the last equilibrium and everything recorded up to the failure. */
vs_status vs_run_execute(vs_run *r, vs_run_step_fn fn, void *user, vs_error *err);

const vs_case *vs_run_case(const vs_run *r);
const vs_geometry *vs_run_geometry(const vs_run *r);
const vs_model *vs_run_model(const vs_run *r);
const vs_hinges *vs_run_hinges(const vs_run *r);
const vs_path_result *vs_run_path(const vs_run *r);
const vs_hinge_opts *vs_run_hinge_opts(const vs_run *r);
/* Last equilibrium: state (vs_model_size entries) and support displacement (m). */
const double *vs_run_state(const vs_run *r);
double vs_run_delta(const vs_run *r);
/* Wall-clock time of vs_run_execute, s. */
double vs_run_wall_s(const vs_run *r);

#endif
