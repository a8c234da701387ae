/* pom_rng.c - xoshiro256** (Blackman & Vigna 2018) seeded with SplitMix64. */
#include "pom_rng.h"

#include <math.h>

static uint64_t splitmix64(uint64_t *x) {
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void pom_rng_seed(pom_rng *rng, uint64_t seed, uint64_t stream) {
  uint64_t x = seed;
  uint64_t h = splitmix64(&x);
  x = h ^ (stream * 0xd1b54a32d192ed03ULL + 0x8cb92ba72f3d8dd7ULL);
  for (int k = 0; k < 4; ++k)
    rng->s[k] = splitmix64(&x);
  if ((rng->s[0] | rng->s[1] | rng->s[2] | rng->s[3]) == 0) rng->s[0] = 1;
}

static inline uint64_t rotl(uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

uint64_t pom_rng_next(pom_rng *rng) {
  uint64_t *s = rng->s;
  uint64_t result = rotl(s[1] * 5, 7) * 9;
  uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rotl(s[3], 45);
  return result;
}

double pom_rng_uniform(pom_rng *rng) {
  return (double)(pom_rng_next(rng) >> 11) * 0x1.0p-53;
}

double pom_rng_range(pom_rng *rng, double lo, double hi) {
  return lo + (hi - lo) * pom_rng_uniform(rng);
}

double pom_rng_normal(pom_rng *rng) {
  double u1 = 1.0 - pom_rng_uniform(rng); /* (0, 1] */
  double u2 = pom_rng_uniform(rng);
  return sqrt(-2.0 * log(u1)) * cos(2.0 * 3.14159265358979323846 * u2);
}
