/* Same seed, same file; another seed, other noise. Also the per-position
 * interface the emulated board uses. */
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

static void serialised(const struct sim_scene *sc, uint64_t seed, unsigned char **buf, size_t *len)
{
    struct uwb_scan s;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(sc, seed, &s, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbscan_serialise(&s, buf, len, err, sizeof err), err);
    uwb_scan_free(&s);
}

static void test_same_seed_gives_identical_bytes(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    unsigned char *a, *b;
    size_t la, lb;
    serialised(&sc, 42, &a, &la);
    /* disturb the heap between the two runs: nothing may depend on addresses */
    void *junk = malloc(12345);
    memset(junk, 0xA5, 12345);
    serialised(&sc, 42, &b, &lb);
    free(junk);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)la, (uint64_t)lb);
    TEST_ASSERT_EQUAL_INT(0, memcmp(a, b, la));
    free(a);
    free(b);
}

static void test_other_seed_gives_other_noise(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    unsigned char *a, *b;
    size_t la, lb;
    serialised(&sc, 1, &a, &la);
    serialised(&sc, 2, &b, &lb);
    TEST_ASSERT_EQUAL_UINT64((uint64_t)la, (uint64_t)lb);
    const unsigned char *nl = memchr(a, '\n', la);
    TEST_ASSERT_NOT_NULL(nl);
    size_t header = (size_t)(nl - a) + 1;
    TEST_ASSERT_EQUAL_INT(0, memcmp(a, b, header)); /* same scene, same header */
    const float *fa = (const float *)(const void *)(a + header),
                *fb = (const float *)(const void *)(b + header);
    size_t n = (la - header) / sizeof(float), differ = 0;
    float va, vb;
    for (size_t i = 0; i < n; i++) {
        memcpy(&va, fa + i, sizeof va);
        memcpy(&vb, fb + i, sizeof vb);
        differ += va != vb;
    }
    TEST_ASSERT_TRUE_MESSAGE(differ > n * 9 / 10, "another seed should change (nearly) every sample");
    free(a);
    free(b);
}

/* The emulated board's path: one acquisition at a time, fresh noise each time,
 * reproducible from the seed. */
static void test_board_acquisitions(void)
{
    struct sim_scene sc;
    TEST_ASSERT_EQUAL_INT(0, sim_scene_default(&sc));
    struct sim_engine *e;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_engine_create(&sc, &e, err, sizeof err), err);
    int S = sc.samples;
    float *a = malloc((size_t)S * sizeof *a), *b = malloc((size_t)S * sizeof *b),
          *c = malloc((size_t)S * sizeof *c);
    struct sim_acq acq;
    sim_acq_init(&acq, 9);
    TEST_ASSERT_EQUAL_INT(0, sim_engine_acquire(e, 0.3, 0, &acq, a, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, sim_engine_acquire(e, 0.3, 0, &acq, b, err, sizeof err));
    TEST_ASSERT_TRUE_MESSAGE(memcmp(a, b, (size_t)S * sizeof *a) != 0, "two acquisitions share their noise");
    sim_acq_init(&acq, 9);
    TEST_ASSERT_EQUAL_INT(0, sim_engine_acquire(e, 0.3, 0, &acq, c, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, memcmp(a, c, (size_t)S * sizeof *a));
    /* and the whole-scan path is the same acquisitions in order */
    struct uwb_scan s;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, sim_make_scan(&sc, 9, &s, err, sizeof err), err);
    sim_acq_init(&acq, 9);
    for (int k = 0; k < sc.positions; k++) {
        TEST_ASSERT_EQUAL_INT(
            0, sim_engine_acquire(e, sim_scene_antenna_y_m(&sc, k), 0, &acq, c, err, sizeof err));
        TEST_ASSERT_EQUAL_INT(0, memcmp(s.data + (size_t)k * S, c, (size_t)S * sizeof *c));
    }
    uwb_scan_free(&s);
    free(a);
    free(b);
    free(c);
    sim_engine_free(e);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_same_seed_gives_identical_bytes);
    RUN_TEST(test_other_seed_gives_other_noise);
    RUN_TEST(test_board_acquisitions);
    return UNITY_END();
}
