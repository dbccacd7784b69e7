/* Issue 43, break 1: the alarm contacts' latch kept in the state directory
 * (contacts-latch.json): written whole, read back, and a file that is not
 * what uwbd writes read as unreadable (the alarm is then held). */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "unity.h"

#include "state/contacts_latch.h"
#include "scratch_support.h"

static char dir[256], path[512];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "contacts-latch");
    snprintf(path, sizeof path, "%s/%s", dir, UWBD_CONTACTS_LATCH_FILE);
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

static void test_no_file_is_nothing_kept(void)
{
    struct uwbd_contacts_memory m;
    char why[600] = "";
    TEST_ASSERT_EQUAL(UWBD_CONTACTS_KEPT_NONE, uwbd_contacts_latch_read(path, &m, why, sizeof why));
}

static void test_written_latch_reads_back(void)
{
    const struct uwbd_contacts_memory kept = {
        .watch_called = 0, .alarm_called = 1, .watch_unacked = 1, .alarm_unacked = 1};
    char err[600] = "", why[600] = "";
    TEST_ASSERT_EQUAL_MESSAGE(0, uwbd_contacts_latch_write(path, &kept, err, sizeof err), err);
    struct uwbd_contacts_memory back = {0};
    TEST_ASSERT_EQUAL_MESSAGE(UWBD_CONTACTS_KEPT, uwbd_contacts_latch_read(path, &back, why, sizeof why),
                              why);
    TEST_ASSERT_EQUAL_MEMORY(&kept, &back, sizeof kept);
    /* Nothing but the file itself is left in the directory (no temporary). */
    struct stat st;
    TEST_ASSERT_EQUAL(0, stat(path, &st));
    TEST_ASSERT_TRUE(S_ISREG(st.st_mode));
}

static void expect_unreadable(const char *content, const char *named)
{
    scratch_spit(path, content);
    struct uwbd_contacts_memory m;
    char why[600] = "";
    TEST_ASSERT_EQUAL_MESSAGE(UWBD_CONTACTS_KEPT_UNREADABLE,
                              uwbd_contacts_latch_read(path, &m, why, sizeof why), content);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, path), why);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, named), why);
}

static void test_corrupt_latch_is_unreadable_and_named(void)
{
    expect_unreadable("", "not a JSON object");
    expect_unreadable("{\"watch_called\":false,\"alarm_cal", "not a JSON object");
    expect_unreadable("[true]", "not a JSON object");
    expect_unreadable("{\"watch_called\":false,\"alarm_called\":true,\"watch_unacked\":true}",
                      "alarm_unacked");
    expect_unreadable(
        "{\"watch_called\":false,\"alarm_called\":1,\"watch_unacked\":true,\"alarm_unacked\":true}",
        "alarm_called");
}

static void test_latch_that_is_a_fifo_is_refused_at_once(void)
{
    TEST_ASSERT_EQUAL(0, mkfifo(path, 0600));
    struct uwbd_contacts_memory m;
    char why[600] = "";
    TEST_ASSERT_EQUAL(UWBD_CONTACTS_KEPT_UNREADABLE, uwbd_contacts_latch_read(path, &m, why, sizeof why));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(why, "FIFO"), why);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_no_file_is_nothing_kept);
    RUN_TEST(test_written_latch_reads_back);
    RUN_TEST(test_corrupt_latch_is_unreadable_and_named);
    RUN_TEST(test_latch_that_is_a_fifo_is_refused_at_once);
    return UNITY_END();
}
