/* test_rng.h - the small seeded PRNG of the lib/qlearn tests and bench_qlearn: comlearn/math3d.h's
 * splitmix64 behind a struct, a uniform double in [0, 1) and a standard normal. Header-only.
 * rng_normal is one-sided Box-Muller on the [0, 1) uniform (clamped at 1e-300), not
 * cl_rng_normal2's pair on the open uniform: the noisy rows of docs/learner.md (bench_qlearn) were
 * measured with this stream, so it stays as long as those tables do. */
#ifndef COMLEARN_TESTS_TEST_RNG_H
#define COMLEARN_TESTS_TEST_RNG_H

#include <math.h>
#include <stdint.h>

#include "comlearn/math3d.h"

typedef struct {
  uint64_t s;
} rng_t;

static inline uint64_t rng_next(rng_t *r) { return cl_rng_next(&r->s); }

static inline double rng_uniform(rng_t *r) { return cl_rng_uniform(&r->s); }

static inline double rng_normal(rng_t *r) {
  double u1 = rng_uniform(r);
  double u2 = rng_uniform(r);
  if (u1 < 1e-300) u1 = 1e-300;
  return sqrt(-2.0 * log(u1)) * cos(2.0 * CL_PI * u2);
}

#endif
