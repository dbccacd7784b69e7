/* The "did you mean" rules every hint shares (util/edit_distance.h): the
 * distance itself, and the nearest candidate within two edits. */
#include "unity.h"

#include <string.h>

#include "util/edit_distance.h"

void setUp(void)
{
}

void tearDown(void)
{
}

static size_t distance(const char *a, const char *b)
{
    return uwb_edit_distance(a, strlen(a), b, strlen(b));
}

static const char *nearest(const char *word, const char *const *candidates)
{
    static struct uwb_nearest near;
    uwb_nearest_start(&near, word, strlen(word));
    for (const char *const *c = candidates; *c; c++)
        uwb_nearest_offer(&near, *c, strlen(*c));
    return near.best;
}

static void test_distance_counts_inserts_deletes_and_substitutions(void)
{
    TEST_ASSERT_EQUAL_UINT64(0, distance("status", "status"));
    TEST_ASSERT_EQUAL_UINT64(2, distance("stauts", "status")); /* a swap is two substitutions */
    TEST_ASSERT_EQUAL_UINT64(1, distance("statu", "status"));
    TEST_ASSERT_EQUAL_UINT64(1, distance("statuss", "status"));
    TEST_ASSERT_EQUAL_UINT64(6, distance("", "status"));
    char long_name[UWB_EDIT_NAME_MAX + 2];
    memset(long_name, 'a', sizeof long_name - 1);
    long_name[sizeof long_name - 1] = '\0';
    TEST_ASSERT_EQUAL_UINT64((size_t)-1, distance(long_name, "a"));
}

static void test_nearest_is_within_two_edits_and_never_the_word_itself(void)
{
    const char *const verbs[] = {"status", "scan", "history", "trend", NULL};
    TEST_ASSERT_EQUAL_STRING("status", nearest("stauts", verbs));
    TEST_ASSERT_EQUAL_STRING("history", nearest("histroy", verbs));
    TEST_ASSERT_NULL(nearest("baseline", verbs)); /* no candidate near */
    TEST_ASSERT_NULL(nearest("xyzzy", verbs));
    const char *const with_itself[] = {"scan", NULL};
    TEST_ASSERT_NULL(nearest("scan", with_itself)); /* an exact match is no hint */
}

static void test_first_of_equally_near_candidates_wins(void)
{
    const char *const names[] = {"cat", "car", "cap", NULL};
    TEST_ASSERT_EQUAL_STRING("cat", nearest("cax", names));
    const char *const reversed[] = {"cap", "car", "cat", NULL};
    TEST_ASSERT_EQUAL_STRING("cap", nearest("cax", reversed));
    const char *const nearer_later[] = {"cart", "cat", NULL};
    TEST_ASSERT_EQUAL_STRING("cat", nearest("cst", nearer_later)); /* 1 edit beats 2 */
}

static void test_a_candidate_may_be_a_prefix_of_a_longer_name(void)
{
    /* Configuration keys offer only their part at the word's depth. */
    struct uwb_nearest near;
    uwb_nearest_start(&near, "digitsier", strlen("digitsier"));
    const char *key = "digitiser.samples";
    uwb_nearest_offer(&near, key, strlen("digitiser"));
    TEST_ASSERT_EQUAL_PTR(key, near.best);
    TEST_ASSERT_EQUAL_UINT64(strlen("digitiser"), near.best_len);
    TEST_ASSERT_EQUAL_UINT64(2, near.best_distance);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_distance_counts_inserts_deletes_and_substitutions);
    RUN_TEST(test_nearest_is_within_two_edits_and_never_the_word_itself);
    RUN_TEST(test_first_of_equally_near_candidates_wins);
    RUN_TEST(test_a_candidate_may_be_a_prefix_of_a_longer_name);
    return UNITY_END();
}
