/* |got - want| <= rtol |want| + atol, or the test fails saying both values, the tolerances and
 * the line: CHECK(got, want, rtol, atol). For a cmocka test (include cmocka.h first). */
#ifndef VS_TEST_CHECK_CLOSE_H
#define VS_TEST_CHECK_CLOSE_H

#include <math.h>

static inline void vs_test_check_close(double got, double want, double rtol, double atol,
                                       const char *what, int line) {
  if (!(fabs(got - want) <= rtol * fabs(want) + atol))
    fail_msg("line %d: %s = %.17g, expected %.17g (rtol %g, atol %g, diff %g)", line, what, got,
             want, rtol, atol, got - want);
}
#define CHECK(got, want, rtol, atol) vs_test_check_close((got), (want), (rtol), (atol), #got, __LINE__)

#endif
