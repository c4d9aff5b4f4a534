/* test_rng.h - the small seeded PRNG of the lib/qlearn tests and bench_qlearn: splitmix64, a
 * uniform double in [0, 1) and a standard normal (Box-Muller). Header-only. */
#ifndef COMLEARN_TESTS_TEST_RNG_H
#define COMLEARN_TESTS_TEST_RNG_H

#include <math.h>
#include <stdint.h>

typedef struct {
  uint64_t s;
} rng_t;

static inline uint64_t rng_next(rng_t *r) {
  uint64_t z = (r->s += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

static inline double rng_uniform(rng_t *r) { return (double)(rng_next(r) >> 11) * 0x1.0p-53; }

static inline double rng_normal(rng_t *r) {
  double u1 = rng_uniform(r);
  double u2 = rng_uniform(r);
  if (u1 < 1e-300) u1 = 1e-300;
  return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

#endif
