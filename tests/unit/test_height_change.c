/* The height change on the full-wave fixtures (paper, tank, a family
 * tank's squeezed spacer and its long pure shift), noiseless, default settings: given with its
 * 1-sigma (height_change_uncertainty_mm) and within 2 sigma of the truth,
 * or withheld with a reason (height_change_withheld), never a bare figure.
 * The truth files are read here, by the test, never by the processing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "fixture_support.h"
#include "unity.h"
#include "uwb/evaluate.h"
#include "uwb/verdict_json.h"

#define FIXTURE(name) "tests/fixtures/" name ".uwbscan"

void setUp(void)
{
}

void tearDown(void)
{
}

static const char *const pairs[][2] = {
    {FIXTURE("fdtd2d-paper-intact"), FIXTURE("fdtd2d-paper-up20mm")},
    {FIXTURE("fdtd2d-tank-d+00.0"), FIXTURE("fdtd2d-tank-d+04.0")},
    {FIXTURE("fdtd2d-tank-d+00.0"), FIXTURE("fdtd2d-tank-d+10.0")},
    {FIXTURE("fdtd2d-tank-d+00.0"), FIXTURE("fdtd2d-tank-d+16.0")},
    {FIXTURE("fdtd2d-tank-d+00.0"), FIXTURE("fdtd2d-tank-d+30.0")},
    {FIXTURE("fdtd2d-tank-d+00.0"), FIXTURE("fdtd2d-tank-d-08.0")},
    {FIXTURE("fdtd2d-var-s01-d+00"), FIXTURE("fdtd2d-var-s01-d+02")},
    /* A clamp plate below the winding, nearer the antenna than its face:
     * the lower shoulder reads 2 mm more move than the upper on a pure
     * 26 mm shift, the crossings and the shoulders' fits alike. */
    {FIXTURE("fdtd2d-var-s01-d+00"), FIXTURE("fdtd2d-var-s01-d+26")},
};
#define N_PAIRS (int)(sizeof pairs / sizeof pairs[0])

static void test_height_change_has_its_sigma_and_covers_the_truth_or_is_withheld(void)
{
    int given = 0;
    for (int i = 0; i < N_PAIRS; i++) {
        struct uwb_scan base, cur;
        struct fixture_truth bt, ct;
        fixture_load_scan(pairs[i][0], &base);
        fixture_load_scan(pairs[i][1], &cur);
        fixture_load_truth(pairs[i][0], &bt);
        fixture_load_truth(pairs[i][1], &ct);
        double true_mm = 1e3 * ((ct.y2_m - ct.y1_m) - (bt.y2_m - bt.y1_m));
        struct uwb_evaluate_options opt;
        uwb_evaluate_defaults(&opt);
        struct uwb_verdict v;
        struct uwb_analysis ca, ba;
        char err[256];
        struct uwb_baseline_record rec = {.scan = &base};
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_evaluate(&cur, &rec, &opt, &v, &ca, &ba, err, sizeof err), err);
        uwb_analysis_free(&ca);
        uwb_analysis_free(&ba);
        uwb_scan_free(&cur);
        uwb_scan_free(&base);
        char *json = uwb_verdict_to_json(&v);
        TEST_ASSERT_NOT_NULL(json);
        printf("%s: true %+.2f mm: %s\n", pairs[i][1], true_mm, json);
        cJSON *o = cJSON_Parse(json);
        free(json);
        TEST_ASSERT_NOT_NULL(o);
        TEST_ASSERT_NOT_EQUAL_MESSAGE(UWB_STATUS_INCONCLUSIVE, v.status, v.reason);
        const cJSON *h = cJSON_GetObjectItemCaseSensitive(o, "height_change_mm");
        const cJSON *s = cJSON_GetObjectItemCaseSensitive(o, "height_change_uncertainty_mm");
        const cJSON *why = cJSON_GetObjectItemCaseSensitive(o, "height_change_withheld");
        if (cJSON_IsNumber(h)) {
            TEST_ASSERT_TRUE_MESSAGE(cJSON_IsNumber(s), "a height change without its sigma");
            TEST_ASSERT_NULL(why);
            char msg[160];
            snprintf(msg, sizeof msg, "%s: height change %+.2f +- %.2f mm for %+.2f", pairs[i][1],
                     h->valuedouble, s->valuedouble, true_mm);
            TEST_ASSERT_TRUE_MESSAGE(fabs(h->valuedouble - true_mm) <= 2.0 * s->valuedouble + 0.005, msg);
            given++;
        } else {
            TEST_ASSERT_NULL(s);
            TEST_ASSERT_TRUE_MESSAGE(cJSON_IsString(why) && strlen(why->valuestring) > 10,
                                     "neither a height change nor why it is withheld");
        }
        cJSON_Delete(o);
    }
    /* Not all withheld: where the two readings agree, a figure. */
    TEST_ASSERT_TRUE(given >= 2);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_height_change_has_its_sigma_and_covers_the_truth_or_is_withheld);
    return UNITY_END();
}
