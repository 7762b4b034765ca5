/* voussoir: masonry arches on moving supports. The one header for running a case:
 *
 *   vs_case c;                                   case.h: the case file's parameters (mm, deg)
 *   vs_case_defaults(&c);
 *   vs_case_read(&c, "arch.ini", NULL, &err);    or vs_case_set(&c, "support.alpha_deg=30", &err)
 *   vs_case_validate(&c, &err);
 *   vs_run *run;
 *   vs_run_create(&c, &run, &err);               run.h: one run (or vs_run_create_def, def.h)
 *   st = vs_run_execute(run, NULL, NULL, NULL, &err);   to the collapse
 *   vs_run_collapse(run)->delta;                 the collapse displacement, m
 *   vs_report_text(stdout, run, st, &err, "arch.ini");  report.h: the program's summary
 *   vs_run_destroy(&run);
 *
 * Every function returns a vs_status (status.h) or documents what it returns; the detail of an
 * error is in the vs_error passed in. Inside, everything is SI (units.h converts at the
 * boundary). Link with libvoussoir (pkg-config voussoir, or CMake's voussoir::core). The
 * engine's own headers (the model, the solvers, the fall) are a second tier: include them by
 * name; the record (output.h) and the pictures (plot.h) are in their own libraries. No
 * third-party header is needed to compile against this one. */
#ifndef VOUSSOIR_VOUSSOIR_H
#define VOUSSOIR_VOUSSOIR_H

#include "voussoir/case.h"
#include "voussoir/def.h"
#include "voussoir/report.h"
#include "voussoir/run.h"
#include "voussoir/status.h"
#include "voussoir/units.h"
#include "voussoir/version.h"

#endif
