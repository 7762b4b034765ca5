/* The tests' deterministic generator (xorshift64*): urand, uniform in [lo, hi); rsign, -1 or 1.
 * Seed it with a non-zero state: rng r = {seed}. */
#ifndef VS_TEST_RNG_H
#define VS_TEST_RNG_H

#include <stdint.h>

typedef struct {
  uint64_t s;
} rng;
static inline double urand(rng *r, double lo, double hi) {
  r->s ^= r->s >> 12;
  r->s ^= r->s << 25;
  r->s ^= r->s >> 27;
  uint64_t x = r->s * 2685821657736338717ULL;
  return lo + (hi - lo) * ((double)(x >> 11) / 9007199254740992.0);
}
static inline double rsign(rng *r) { return urand(r, 0.0, 1.0) < 0.5 ? -1.0 : 1.0; }

#endif
