/* Private to the run's reports (report.c): the piers' part of the text and JSON summaries
 * (report_piers.c). Not installed. */
#ifndef VOUSSOIR_REPORT_PIERS_H
#define VOUSSOIR_REPORT_PIERS_H

#include <stdio.h>

#include "voussoir/run.h"

/* The header's piers line (nothing without piers). */
void vs_report_piers_header(FILE *out, const vs_run *r);

/* What happened in the piers, in order: a pier rocking on its base, a course joint opening, a
 * base sliding (nothing without piers). */
void vs_report_piers_text(FILE *out, const vs_run *r);

/* ,"piers":{...} with its events (nothing without piers, so that a case without them keeps its
 * JSON). */
void vs_report_piers_json(FILE *out, const vs_run *r);

#endif
