/* Wall-clock and CPU seconds for the runs' timings (C11 timespec_get, C clock; differences
 * only). */
#ifndef VS_WALL_CLOCK_H
#define VS_WALL_CLOCK_H

#include <time.h>

static inline double vs_wall_now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of the process (user and system, all its threads), s. */
static inline double vs_cpu_now(void) { return (double)clock() / (double)CLOCKS_PER_SEC; }

#endif
