/* Lists of numbers for studies: comma-separated numbers and inclusive "first:last:step" ranges
 * ("0:90:5", "0,5,10", "0.1,1:10:1"), and log-spaced lists (src/base/list.c). */
#ifndef VS_LIST_H
#define VS_LIST_H

#include <stddef.h>

#include "voussoir/status.h"

/* Most values one list may hold, and most runs one sweep may make (the product of its lists'
 * lengths, checked without overflow): a sweep's summary table and its run directory stay
 * manageable, and a bigger study is better split into several sweeps. */
#define VS_LIST_MAX_VALUES 100000
#define VS_SWEEP_MAX_RUNS 100000

/* Parse a list of numbers (each in the forms of voussoir/parse.h): comma-separated items, each a number or an inclusive range
 * "first:last:step" (step > 0, last >= first; the last value is included when it falls on the
 * grid within 1e-9 of a step), at most VS_LIST_MAX_VALUES values in all. *values is malloc'd (caller frees); *n its length (>= 1).
 * Errors: VS_ERR_USAGE naming what (e.g. "--alpha") and the offending item. */
vs_status vs_parse_list(const char *what, const char *text, double **values, int *n,
                        vs_error *err);

/* Log-spaced list "a:b:n" helper for studies: n values from a to b (a, b > 0, n >= 2). */
vs_status vs_logspace(double a, double b, int n, double **values, vs_error *err);

#endif
