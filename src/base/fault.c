/* Fault injection for the crash tests (fault.h). */
#include "fault.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>

void vs_fault_point(const char *name) {
  const char *v = getenv("VS_FAULT_KILL");
  if (v != NULL && strcmp(v, name) == 0) raise(SIGKILL);
}
