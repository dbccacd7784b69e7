/* The accuracy report's radial rows, reduced (make accuracy runs 150
 * pairs): every radial and pure-shift fixture clean, and the radial changes
 * over 20 noisy pairs at 32 dB (3 ps jitter, 2 % + 2 % drift). What is
 * asserted, as the README's radial table reads today:
 * - clean: every figure within 2 sigma of the truth, the tilt too (where
 *   given); each change located (its largest inside the changed disks
 *   +-10 mm), read with its sign and at least watch, and over 3 disks or
 *   more sized within max(1 mm, 20 %) (issue 45), or its size withheld as
 *   a least value with its sign, place and status; a lean of 5 mm or
 *   more given (within 2 sigma, above) and an alarm, one of 2-5 mm at
 *   least watch; every pure shift radially ok (the goal of a
 *   6 mm lean within 1.5 mm is make accuracy's target, missed on fresh
 *   s103: tools/accuracy/main.c);
 * - noisy: the noise part of sigma honest (spread / that part within
 *   NOISE_RATIO_MIN..MAX; the 0.8-1.25 printed beside it) where it
 *   is what scatters the figure (the changes in the middle of the face),
 *   and 90 % within 2 sigma. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "accuracy/accuracy.h"
#include "accuracy/radial.h"
#include "unity.h"
#include "uwb/evaluate.h"

#define PAIRS 20
/* 20 pairs scatter a spread by about 16 % (1/sqrt(2*19)); reached over 60
 * pairs: 1.17 and 0.90 on the bulge and the dent in the middle of the face;
 * not asserted: 2.2 on the top three disks' bulge (the line through the
 * lower rows, extrapolated, adds its own noise, which sigma leaves out),
 * 0.74 on the bulge with a rise. */
#define NOISE_RATIO_MIN 0.6
#define NOISE_RATIO_MAX 1.5
#define WITHIN_MIN 0.9
#define NOISY_LEVEL 1 /* accuracy_levels[1]: 32 dB */

void setUp(void)
{
}
void tearDown(void)
{
}

static int emulated(void)
{
    const char *prefix = getenv("UWB_EXEC_PREFIX");
    return prefix && *prefix;
}

static void test_clean_radial_figures_are_right_or_within_their_sigma(void)
{
    char err[512];
    struct uwb_evaluate_options opt; /* the radial limits the rows are graded on */
    uwb_evaluate_defaults(&opt);
    const struct uwb_thresholds *limits = &opt.compare.radial_thresholds;
    for (int c = 0; c < radial_case_count; c++) {
        if (emulated() && c > 0)
            break; /* FFTW under qemu-user: the first case only */
        const struct radial_case *rc = &radial_cases[c];
        struct radial_row row;
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            0, radial_run_case("tests/fixtures", rc, NULL, 1, 0, &row, err, sizeof err), err);
        printf("%s: error %+.2f mm, sigma %.2f mm, tilt error %.2f mm\n", rc->name, row.bias_m * 1e3,
               row.median_sigma_m * 1e3, row.tilt_worst_m * 1e3);
        if (row.measured == 0) {
            /* Withheld as a least value (a change read short by its own
             * flank): a change is there, with its sign and place right and
             * its status kept. */
            TEST_ASSERT_TRUE_MESSAGE(rc->change_m != 0.0, rc->name);
            TEST_ASSERT_EQUAL_INT_MESSAGE(1, row.least, rc->name);
            TEST_ASSERT_TRUE_MESSAGE(row.least_right == 1.0, rc->name);
            TEST_ASSERT_TRUE_MESSAGE(row.watch_or_worse == 1.0, rc->name);
            TEST_ASSERT_TRUE_MESSAGE(fabs(row.least_m) <= fabs(rc->change_m), rc->name);
            continue;
        }
        TEST_ASSERT_TRUE_MESSAGE(row.within_2sigma == 1.0, rc->name);
        TEST_ASSERT_TRUE_MESSAGE(row.tilt_withheld == 1 || row.tilt_within_2sigma == 1.0, rc->name);
        if (rc->change_m != 0.0) {
            TEST_ASSERT_TRUE_MESSAGE(row.sign_right == 1.0, rc->name);
            TEST_ASSERT_TRUE_MESSAGE(row.located == 1.0, rc->name);
            TEST_ASSERT_TRUE_MESSAGE(row.watch_or_worse == 1.0, rc->name);
            /* Every size given, in oil and in air (the paper's scene's
             * +4 mm over disks 2-4 read +2.59 and -6 over 3-5 -3.98 while
             * their line's rows lay within their blur: now withheld). */
            if (rc->disks >= 3) {
                TEST_ASSERT_TRUE_MESSAGE(fabs(row.bias_m) <= fmax(0.001, 0.2 * fabs(rc->change_m)), rc->name);
            }
        } else if (fabs(rc->tilt_m) >= limits->watch_m) {
            /* A lean past the watch limit alerts whether or not its tilt is
             * given (a 4 mm lean's interval may cross the alarm limit); a
             * 6 mm one gives its tilt, an alarm. */
            TEST_ASSERT_TRUE_MESSAGE(row.watch_or_worse == 1.0, rc->name);
            if (fabs(rc->tilt_m) >= limits->alarm_m) {
                TEST_ASSERT_EQUAL_INT_MESSAGE(0, row.tilt_withheld, rc->name);
                TEST_ASSERT_TRUE_MESSAGE(row.alarm == 1.0, rc->name);
            }
        } else {
            TEST_ASSERT_TRUE_MESSAGE(row.watch_or_worse == 0.0, rc->name);
        }
    }
}

static void test_noisy_radial_sigma_is_honest(void)
{
    if (emulated())
        TEST_IGNORE_MESSAGE("too slow under emulation; make accuracy covers it natively");
    char err[512];
    int cases = 2; /* the bulge and the dent in the middle of the face */
#ifdef __SANITIZE_ADDRESS__
    cases = 1;
#endif
    for (int c = 0; c < cases; c++) {
        const struct radial_case *rc = &radial_cases[c];
        struct radial_row row;
        unsigned long long seed = 7000000ull + 10000ull * (unsigned long long)c;
        TEST_ASSERT_EQUAL_INT_MESSAGE(0,
                                      radial_run_case("tests/fixtures", rc, &accuracy_levels[NOISY_LEVEL],
                                                      PAIRS, seed, &row, err, sizeof err),
                                      err);
        double ratio = row.spread_m / row.median_noise_sigma_m;
        char what[200];
        snprintf(what, sizeof what,
                 "%s: spread %.2f mm / noise sigma %.2f mm = %.2f (issue: 0.8-1.25), within 2 "
                 "sigma %.0f %%",
                 rc->name, row.spread_m * 1e3, row.median_noise_sigma_m * 1e3, ratio,
                 100.0 * row.within_2sigma);
        printf("%s\n", what);
        TEST_ASSERT_TRUE_MESSAGE(ratio >= NOISE_RATIO_MIN && ratio <= NOISE_RATIO_MAX, what);
        TEST_ASSERT_TRUE_MESSAGE(row.within_2sigma >= WITHIN_MIN, what);
        TEST_ASSERT_TRUE_MESSAGE(row.located >= WITHIN_MIN, what);
    }
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_clean_radial_figures_are_right_or_within_their_sigma);
    RUN_TEST(test_noisy_radial_sigma_is_honest);
    return UNITY_END();
}
