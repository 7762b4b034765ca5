/* The tests' check of a number against an expected value (included after cmocka.h): CHECK(got,
 * want, rtol, atol) fails the test, naming the expression, its line and both values, unless
 * |got - want| <= rtol |want| + atol. */
#ifndef VS_TEST_CHECK_H
#define VS_TEST_CHECK_H

#include <math.h>

static inline void check_close(double got, double want, double rtol, double atol,
                               const char *what, int line) {
  if (!(fabs(got - want) <= rtol * fabs(want) + atol))
    fail_msg("line %d: %s = %.17g, expected %.17g (rtol %g, atol %g, diff %g)", line, what, got,
             want, rtol, atol, got - want);
}
#define CHECK(got, want, rtol, atol) check_close((got), (want), (rtol), (atol), #got, __LINE__)

#endif
