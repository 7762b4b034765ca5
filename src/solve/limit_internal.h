/* Private to the limit analysis (limit.c, limit_analysis.c): warm starts between like LPs, the
 * same assembly rebuilt with another thickness (the same rows and columns). */
#ifndef VS_LIMIT_INTERNAL_H
#define VS_LIMIT_INTERNAL_H

#include <stddef.h>

#include "voussoir/limit.h"

/* Bytes of a basis of l: CLP's status of each column and row. */
size_t vs_limit_basis_size(const vs_limit *l);
/* The basis of l's last solve into to (vs_limit_basis_size bytes). */
void vs_limit_basis_save(const vs_limit *l, unsigned char *to);
/* l's next solves start from basis from (the dual simplex from there, no presolve). */
void vs_limit_basis_start(vs_limit *l, const unsigned char *from);

#endif
