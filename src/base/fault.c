/* Fault injection for the crash and link tests (fault.h). */
#define _DEFAULT_SOURCE /* symlink */
#include "fault.h"

#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* VS_FAULT_RELINK = "POINT:PATH=TARGET": at POINT, PATH replaced by a symbolic link to TARGET. */
static void relink(const char *name, const char *only) {
  const char *v = getenv("VS_FAULT_RELINK");
  const char *colon = v != NULL ? strchr(v, ':') : NULL;
  const char *eq = colon != NULL ? strchr(colon, '=') : NULL;
  if (eq == NULL || strlen(name) != (size_t)(colon - v) || strncmp(v, name, (size_t)(colon - v)))
    return;
  char path[4096];
  const size_t n = (size_t)(eq - colon - 1);
  if (n == 0 || n >= sizeof path) return;
  memcpy(path, colon + 1, n);
  path[n] = '\0';
  if (only != NULL && strcmp(only, path) != 0) return;
  (void)unlink(path);
  (void)symlink(eq + 1, path);
}

void vs_fault_point(const char *name) {
  relink(name, NULL);
  const char *v = getenv("VS_FAULT_KILL");
  if (v != NULL && strcmp(v, name) == 0) raise(SIGKILL);
}

void vs_fault_point_at(const char *name, const char *path) { relink(name, path); }
