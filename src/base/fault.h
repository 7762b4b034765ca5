/* Fault injection for the crash tests: the process kills itself with SIGKILL at a named point
 * when the environment variable VS_FAULT_KILL names that point (the record's points: see
 * vs_output_finish; "mid-append": in a write of rows after the first, once half the time series
 * have theirs). Nothing happens when it is unset. */
#ifndef VS_FAULT_H
#define VS_FAULT_H

void vs_fault_point(const char *name);

#endif
