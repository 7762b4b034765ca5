/* The monotonic clock of the solvers' deadlines (wall_clock.h): POSIX's CLOCK_MONOTONIC, which
 * C's timespec_get does not offer. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include "wall_clock.h"

#include <stdio.h>
#include <time.h>

double vs_monotonic_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void vs_iso8601_utc(char *buf, size_t size) {
  time_t now = time(NULL);
  struct tm tmv;
  if (gmtime_r(&now, &tmv) == NULL || strftime(buf, size, "%Y-%m-%dT%H:%M:%SZ", &tmv) == 0)
    snprintf(buf, size, "unknown");
}
