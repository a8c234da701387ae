/* pom_rng.h - explicit-state pseudo-random numbers (xoshiro256**), seeded by
 * (seed, stream) so that sample k of a study draws the same numbers on any
 * number of threads or MPI ranks. No global state. */
#ifndef POM_RNG_H
#define POM_RNG_H

#include <stdint.h>

typedef struct {
  uint64_t s[4]; /* xoshiro256** state, never all zero */
} pom_rng;

/* Seeds from a study seed and a stream index (e.g. the maneuver number)
 * through SplitMix64, so neighbouring streams are uncorrelated. */
void pom_rng_seed(pom_rng *rng, uint64_t seed, uint64_t stream);

/* Next 64 random bits. */
uint64_t pom_rng_next(pom_rng *rng);

/* Uniform double in [0, 1) with 53 random bits. */
double pom_rng_uniform(pom_rng *rng);

/* Uniform double in [lo, hi). */
double pom_rng_range(pom_rng *rng, double lo, double hi);

/* Standard normal deviate (Box-Muller, both values used in turn is avoided
 * for reproducibility: one call = two uniforms). */
double pom_rng_normal(pom_rng *rng);

#endif
