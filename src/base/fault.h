/* Fault injection for the crash tests: the process kills itself with SIGKILL at a named point
 * when the environment variable VS_FAULT_KILL names that point (the record's points: see
 * vs_output_finish; "mid-append": in a write of rows after the first, once half the time series
 * have theirs; "before-snapshot": as a snapshot is about to read the working file). Nothing
 * happens when it is unset. For the link tests, VS_FAULT_RELINK = "POINT:PATH=TARGET" replaces
 * PATH by a symbolic link to TARGET at the point POINT, as another process could during the
 * run (a file the program created, re-opened by name later, must not be followed). */
#ifndef VS_FAULT_H
#define VS_FAULT_H

void vs_fault_point(const char *name);
/* A point of the link tests only where the file at stake is path: VS_FAULT_RELINK relinks PATH
 * there when PATH is path ("before-replace": a finished working file about to be renamed over
 * its output, vs_outpath_replace). */
void vs_fault_point_at(const char *name, const char *path);

#endif
