/* The height change's sigma covers a warmer or colder oil (issue 44, item
 * 2): the same tank, nothing moved, the oil's eps_r a little off the
 * header's between baseline and scan (held back, a tank read -0.96 mm at
 * sigma 0.24 mm). The pairs are make accuracy's (tools/accuracy/warm_oil.c:
 * the shared full-wave tank's winding in the simulator drawn over the
 * family's ranges, eps_r 2.16 and 2.26 against the header's 2.2): each
 * height change given lies within 2 sigma of none, and the shift too.
 * Before the oil term the tank's read -0.656 mm at sigma 0.182. */
#include <stdio.h>

#include "accuracy/warm_oil.h"
#include "unity.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static void test_a_changed_oil_reads_no_height_change_outside_its_sigma(void)
{
    struct warm_oil_tally t;
    char err[512];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, accuracy_warm_oil(stdout, &t, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(12, t.pairs);
    TEST_ASSERT_EQUAL_INT(t.pairs, t.shift_within);
    TEST_ASSERT_EQUAL_INT(t.given, t.within);
    /* Each tank's oil changes by less than its 1 mm limit: not a test that
     * passes by withholding everything. */
    TEST_ASSERT_GREATER_OR_EQUAL_INT(8, t.given);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_changed_oil_reads_no_height_change_outside_its_sigma);
    return UNITY_END();
}
