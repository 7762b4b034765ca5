/* Private to the run's report: the live load's path's part (report_load.c), only for
 * analysis.type = load. Not installed. */
#ifndef VOUSSOIR_REPORT_LOAD_H
#define VOUSSOIR_REPORT_LOAD_H

#include <stdio.h>

#include "voussoir/limit.h"
#include "voussoir/run.h"

/* The JSON fields ",\"load_factor\":...,\"load\":{...}", the text section, the run's status
 * name ("collapse", "limit_point": a limit point before the hold, "max_displacement"). */
void vs_report_load_json(FILE *out, const vs_run *r);
void vs_report_load_text(FILE *out, const vs_run *r);
const char *vs_report_load_status(const vs_run *r);

/* A limit analysis as the JSON object of the "limit" key ({"load_factor": ...}; report_limit.c):
 * kind (vs_load_kind) and value_N the live load's, thickness_mm the arch's, courses its piers'
 * (0: none; their joints named as the pier events name them). */
void vs_report_limit_object(FILE *out, const vs_limit_analysis *a, int kind, double value_N,
                            double thickness_mm, int courses);

#endif
