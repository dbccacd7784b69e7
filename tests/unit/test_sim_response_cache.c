/* The emulated board's engine keeps each position's noiseless response and
 * adds every pulse's jitter, drift and noise to it: the traces are the very
 * numbers an engine without the cache gives for the same seed, the scene's
 * surfaces are integrated once per position, and the cache stays within
 * the size it was given. */
#include <stdlib.h>
#include <string.h>

#include "unity.h"
#include "uwbsim/uwbsim.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* The default scene with every per-pulse effect on, the noise band-limited
 * (that path runs FFTs of its own between the cached ones). */
static void noisy_scene(struct sim_scene *sc)
{
    char err[512];
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(sc));
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(sc, "jitter_s", "5e-12", err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(sc, "drift_db", "0.05", err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(sc, "snr_db", "25", err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_scene_set(sc, "noise_bandwidth_hz", "4e9", err, sizeof err), err);
}

/* Acquires `rounds` passes over `count` positions, `pulses` traces at each,
 * from both engines with the same seed; every trace must match bit for bit. */
static void assert_same_traces(struct sim_engine *plain, struct sim_engine *cached, const double *y,
                               int count, int rounds, int pulses, int samples)
{
    float *a = malloc((size_t)samples * sizeof *a), *b = malloc((size_t)samples * sizeof *b);
    TEST_ASSERT_NOT_NULL(a);
    TEST_ASSERT_NOT_NULL(b);
    struct sim_acq acq_plain, acq_cached;
    sim_acq_init(&acq_plain, 17);
    sim_acq_init(&acq_cached, 17);
    char err[512];
    for (int r = 0; r < rounds; r++)
        for (int k = 0; k < count; k++)
            for (int p = 0; p < pulses; p++) {
                TEST_ASSERT_EQUAL_INT_MESSAGE(
                    0, sim_engine_acquire(plain, y[k], 1, &acq_plain, a, err, sizeof err), err);
                TEST_ASSERT_EQUAL_INT_MESSAGE(
                    0, sim_engine_acquire(cached, y[k], 1, &acq_cached, b, err, sizeof err), err);
                TEST_ASSERT_EQUAL_MEMORY_MESSAGE(a, b, (size_t)samples * sizeof *a,
                                                 "a cached response gave another trace");
            }
    free(a);
    free(b);
}

static void test_cached_traces_are_the_uncached_ones(void)
{
    struct sim_scene sc;
    noisy_scene(&sc);
    struct sim_engine *plain, *cached;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &plain, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &cached, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, sim_engine_cache_responses(cached, 16));
    const double y[] = {0.25, 0.3, 0.35};
    /* the noise's reference (a pass over the scene) first, not counted */
    TEST_ASSERT_TRUE(sim_engine_peak_echo(plain) > 0 && sim_engine_peak_echo(cached) > 0);
    unsigned long plain_before = sim_engine_responses_computed(plain);
    unsigned long before = sim_engine_responses_computed(cached);
    assert_same_traces(plain, cached, y, 3, 2, 5, sc.samples);
    /* thirty traces at three positions: thirty integrations without the
     * cache, three with it */
    TEST_ASSERT_EQUAL_UINT32(30, (unsigned)(sim_engine_responses_computed(plain) - plain_before));
    TEST_ASSERT_EQUAL_UINT32(3, (unsigned)(sim_engine_responses_computed(cached) - before));
    TEST_ASSERT_EQUAL_UINT32(3, (unsigned)sim_engine_responses_cached(cached));
    sim_engine_free(plain);
    sim_engine_free(cached);
}

/* A cache smaller than the positions visited drops old responses and
 * computes them again: still the same numbers, never more than it holds. */
static void test_a_full_cache_recomputes_and_stays_right(void)
{
    struct sim_scene sc;
    noisy_scene(&sc);
    struct sim_engine *plain, *cached;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &plain, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &cached, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(0, sim_engine_cache_responses(cached, 2));
    const double y[] = {0.25, 0.3, 0.35};
    TEST_ASSERT_TRUE(sim_engine_peak_echo(plain) > 0 && sim_engine_peak_echo(cached) > 0);
    unsigned long before = sim_engine_responses_computed(cached);
    assert_same_traces(plain, cached, y, 3, 2, 2, sc.samples);
    /* each position's first pulse of each round misses (three positions
     * cycled through two slots), its second hits */
    TEST_ASSERT_EQUAL_UINT32(6, (unsigned)(sim_engine_responses_computed(cached) - before));
    TEST_ASSERT_EQUAL_UINT32(2, (unsigned)sim_engine_responses_cached(cached));
    sim_engine_free(plain);
    sim_engine_free(cached);
}

/* Without the call, an engine keeps nothing (uwbsim and the bench pass over
 * each position once and need no memory for it). */
static void test_no_cache_unless_asked(void)
{
    struct sim_scene sc;
    noisy_scene(&sc);
    struct sim_engine *plain;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &plain, err, sizeof err), err);
    const double y[] = {0.3};
    float *a = malloc((size_t)sc.samples * sizeof *a);
    TEST_ASSERT_NOT_NULL(a);
    struct sim_acq acq;
    sim_acq_init(&acq, 3);
    TEST_ASSERT_TRUE(sim_engine_peak_echo(plain) > 0);
    unsigned long before = sim_engine_responses_computed(plain);
    for (int p = 0; p < 4; p++)
        TEST_ASSERT_EQUAL_INT(0, sim_engine_acquire(plain, y[0], 1, &acq, a, err, sizeof err));
    TEST_ASSERT_EQUAL_UINT32(4, (unsigned)(sim_engine_responses_computed(plain) - before));
    TEST_ASSERT_EQUAL_UINT32(0, (unsigned)sim_engine_responses_cached(plain));
    free(a);
    sim_engine_free(plain);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cached_traces_are_the_uncached_ones);
    RUN_TEST(test_a_full_cache_recomputes_and_stays_right);
    RUN_TEST(test_no_cache_unless_asked);
    return UNITY_END();
}
