/* Wall-clock seconds for the runs' timings (C11 timespec_get; differences only). */
#ifndef VS_WALL_CLOCK_H
#define VS_WALL_CLOCK_H

#include <time.h>

static inline double vs_wall_now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
