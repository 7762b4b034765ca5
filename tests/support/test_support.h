/* What several tests share: building the engine's pieces from a case (the engine takes a
 * definition, def.h; the tests describe their arches as cases). */
#ifndef VS_TEST_SUPPORT_H
#define VS_TEST_SUPPORT_H

#include "voussoir/case.h"
#include "voussoir/geometry.h"
#include "voussoir/quasistatic.h"

/* The arch of case c (vs_geometry_create_arch on its definition). */
static inline vs_status vs_test_arch(const vs_case *c, vs_geometry **out, vs_error *err) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  return vs_geometry_create_arch(&d.arch, out, err);
}

/* The arch of case c and its model (the case's joints' law, the support direction alpha = 0);
 * the caller destroys both (either may be set when the other failed). */
static inline vs_status vs_test_model(const vs_case *c, vs_geometry **g, vs_model **m,
                                      vs_error *err) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  const vs_joint_law law = {.kn = d.joints.kn, .ks = d.joints.ks, .mu = d.joints.mu};
  vs_status st = vs_geometry_create_arch(&d.arch, g, err);
  return st == VS_OK ? vs_model_create(*g, &law, 0.0, m, err) : st;
}

/* The path options of case c (vs_path_opts_from_def on its definition). */
static inline void vs_test_path_opts(const vs_case *c, vs_path_opts *o) {
  vs_run_def d;
  vs_case_to_def(c, &d);
  vs_path_opts_from_def(&d, o);
}

#endif
