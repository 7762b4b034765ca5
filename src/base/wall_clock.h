/* Wall-clock and CPU seconds for the runs' timings (C11 timespec_get, C clock; differences
 * only), and the monotonic clock of the solvers' deadlines. */
#ifndef VS_WALL_CLOCK_H
#define VS_WALL_CLOCK_H

#include <time.h>

static inline double vs_wall_now(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Monotonic seconds (CLOCK_MONOTONIC: setting the system clock does not move it), the clock of
 * the solvers' deadlines (vs_path_opts, vs_dyn_opts, vs_fall_opts: deadline); wall_clock.c. */
double vs_monotonic_s(void);

/* 1 once the deadline *deadline (vs_monotonic_s seconds; NULL, or 0: none) has passed. It reads
 * the clock: the solvers call it once a step or a solve, never once a residual. */
static inline int vs_deadline_passed(const double *deadline) {
  return deadline != NULL && *deadline > 0.0 && vs_monotonic_s() >= *deadline;
}

/* The current UTC time as "2024-05-01T12:00:00Z" into buf ("unknown" if it cannot be read). */
void vs_iso8601_utc(char *buf, size_t size);

/* CPU time of the process (user and system, all its threads), s. */
static inline double vs_cpu_now(void) { return (double)clock() / (double)CLOCKS_PER_SEC; }

#endif
