/* The serial N_Vector's operations compiled with this library's optimisation. Debian 12 builds
 * SUNDIALS 6.4.1 without optimisation (-O0), and IDA and KINSOL spend most of their own time in
 * the vector operations (linear sums, scalings, weighted norms: a quarter of a run's
 * instructions). These do the same floating-point operations in the same order as SUNDIALS'
 * serial vector (the same special cases of a linear sum, the same summation order of every
 * reduction), so results are identical bit for bit (tested against SUNDIALS' own functions). */
#ifndef VOUSSOIR_NVECTOR_OPS_H
#define VOUSSOIR_NVECTOR_OPS_H

#include <sundials/sundials_nvector.h>

/* Replace the standard and local-reduction operations of v, a serial vector (N_VNew_Serial or
 * N_VMake_Serial), by this library's. Vectors cloned from v (as IDA and KINSOL clone their
 * workspace from the vectors given to IDAInit and KINInit) inherit them. The fused and
 * vector-array operations stay unset, as SUNDIALS leaves them: its generic fall-backs then call
 * these. NULL, or a vector that is not serial, is left alone. */
void vs_nvector_fast_ops(N_Vector v);

#endif
