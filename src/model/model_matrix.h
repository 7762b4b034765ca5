/* The model's sparse matrices (SUNDIALS CSC matrices, the pattern of vs_model_nnz or
 * vs_model_ext_nnz): the Jacobians and damping matrices the solvers factor. Private to the engine
 * (the public model.h needs no SUNDIALS header). */
#ifndef VS_MODEL_MATRIX_H
#define VS_MODEL_MATRIX_H

#include <sundials/sundials_matrix.h>

#include "voussoir/model.h"

/* Jacobian dG/dq at (q, delta) into J, a CSC SUNSparseMatrix of size vs_model_size and
 * capacity >= vs_model_nnz; the pattern is written too (it never changes). Returns 0. */
int vs_model_jacobian(const vs_model *m, const double *q, double delta, SUNMatrix J);

/* Damping forces at (q, v) with the right support moving at ddelta_dt (m/s): fd (3n entries,
 * may be NULL) adds to the residual of the equations of motion; *dissipated = power dissipated
 * in all joints (W, >= 0); *support_power = power of the damping force on the moving support
 * (W, part of the support's work); C (may be NULL): dfd/dv as a CSC matrix with the pattern of
 * vs_model_jacobian. */
void vs_model_damping(const vs_model *m, const double *q, const double *v, double delta,
                      double ddelta_dt, double *fd, double *dissipated,
                      double *support_power, SUNMatrix C);

/* dGe/dqe (CSC, its own pattern of vs_model_ext_nnz entries, written too). */
void vs_model_ext_jacobian(const vs_model *m, const double *qe, SUNMatrix J);

/* Damping forces over qe at velocities ve (3 n_blocks + 6), dissipated power and dfd/dve (any
 * output may be NULL). */
void vs_model_ext_damping(const vs_model *m, const double *qe, const double *ve, double *fd,
                          double *dissipated, SUNMatrix C);

/* One pass over the joints at (qe, ve) for the equations of motion: F = vs_model_ext_residual
 * plus the damping forces of vs_model_ext_damping, *dissipated (their power), *friction
 * (vs_model_ext_friction_power), K = vs_model_ext_jacobian and C = vs_model_ext_damping's
 * matrix, each joint's kinematics and law evaluated once. Any output may be NULL; ve NULL: no
 * damping and no friction power. */
void vs_model_ext_motion(const vs_model *m, const double *qe, const double *ve, double *F,
                         double *dissipated, double *friction, SUNMatrix K, SUNMatrix C);

#endif
