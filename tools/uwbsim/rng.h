/* A seeded random stream of our own: the same seed gives the same numbers on
 * every run, which the simulator's "same seed, same file" promise rests on.
 * No Debian library offers a portable seeded generator with a fixed, documented
 * stream (rand_r/random differ between libcs), so this is xoshiro256** seeded
 * through splitmix64 (both public-domain algorithms, written here from their
 * published descriptions). */
#ifndef UWBSIM_RNG_H
#define UWBSIM_RNG_H

#include <stdint.h>

struct sim_rng {
    uint64_t s[4];
    int has_spare; /* Box-Muller gives normals in pairs */
    double spare;
};

void sim_rng_seed(struct sim_rng *rng, uint64_t seed);
uint64_t sim_rng_next(struct sim_rng *rng);
/* Uniform in [0, 1): 53 random bits. */
double sim_rng_uniform(struct sim_rng *rng);
/* Standard normal (mean 0, variance 1). */
double sim_rng_normal(struct sim_rng *rng);

#endif
