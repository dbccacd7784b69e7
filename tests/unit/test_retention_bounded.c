/* Issue 27, break 4: retention re-read a day directory for every scan it
 * deleted (and de-duplicated scans by a linear search), so its cost grew
 * with the square of a day's files: 100,000 files in one day with
 * max_scans 50 took an hour at full CPU, deaf to SIGTERM. Now a day is
 * read once, deletions are bounded per call (continued at the next), and
 * a stop request ends the clean-up between two scans. */
#include "unity.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "daemon/retention.h"
#include "daemon/store.h"
#include "scratch_support.h"
#include "uwb/monotonic.h"

/* 20,000 files in one day directory: each scan a .json and a .uwbscan. */
#define SCANS 10000
#define KEEP 50
/* One pass over 20,000 files and 19,900 unlinks: well under a second on
 * any machine this runs on; the old code took tens of seconds. */
#define BOUND_S 5.0
#define DAY "2030/01/01"

static char dir[64];
static char err[2048];
static struct uwbd_store store;
static char day_dir[2300];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "retention-bounded");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
    snprintf(day_dir, sizeof day_dir, "%s/%s", store.archive, DAY);
    char cmd[2400];
    snprintf(cmd, sizeof cmd, "mkdir -p '%s'", day_dir);
    TEST_ASSERT_EQUAL_INT(0, system(cmd));
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

static void touch_dated(const char *name, time_t when)
{
    char p[2600];
    snprintf(p, sizeof p, "%s/%s", day_dir, name);
    int fd = open(p, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    TEST_ASSERT_TRUE_MESSAGE(fd >= 0, p);
    struct timespec ts[2] = {{.tv_sec = when, .tv_nsec = 0}, {.tv_sec = when, .tv_nsec = 0}};
    TEST_ASSERT_EQUAL_INT(0, futimens(fd, ts));
    close(fd);
}

/* Scan i is "scan-NNNNN", i seconds after a fixed time: oldest first. The
 * first two also have images, to see those go with their scan. */
static void fill_one_day(void)
{
    const time_t base = 1893456000; /* 2030-01-01T00:00:00Z */
    char name[64];
    for (int i = 0; i < SCANS; i++) {
        snprintf(name, sizeof name, "scan-%05d.json", i);
        touch_dated(name, base + i);
        snprintf(name, sizeof name, "scan-%05d.uwbscan", i);
        touch_dated(name, base + i);
    }
    touch_dated("scan-00000-migrated.png", base);
    touch_dated("scan-00001-bscan.png", base + 1);
    touch_dated(".notes", base); /* not a scan's file: stays */
}

static int in_day(const char *name)
{
    char p[2600];
    snprintf(p, sizeof p, "%s/%s", day_dir, name);
    return scratch_file_exists(p);
}

static void test_twenty_thousand_files_in_one_day_are_cleaned_in_bounded_time(void)
{
    fill_one_day();
    double started_s = uwb_monotonic_s();
    int removed = 0, total = 0, calls = 0;
    do {
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            0, uwbd_retention_apply(&store, KEEP, 0, time(NULL), 1, &removed, err, sizeof err), err);
        total += removed;
    } while (removed > 0 && ++calls < 100);
    double took_s = uwb_monotonic_s() - started_s;
    char what[128];
    snprintf(what, sizeof what, "%d scans deleted in %.2f s (%d calls)", total, took_s, calls + 1);
    TEST_ASSERT_TRUE_MESSAGE(took_s < BOUND_S, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(SCANS - KEEP, total, what);
    TEST_ASSERT_EQUAL_INT(KEEP, uwbd_archive_count(&store));
    TEST_ASSERT_FALSE(in_day("scan-00000.json"));
    TEST_ASSERT_FALSE(in_day("scan-00000-migrated.png"));
    TEST_ASSERT_FALSE(in_day("scan-00001-bscan.png"));
    TEST_ASSERT_FALSE(in_day("scan-09949.uwbscan"));
    TEST_ASSERT_TRUE(in_day("scan-09950.json"));
    TEST_ASSERT_TRUE(in_day("scan-09950.uwbscan"));
    TEST_ASSERT_TRUE(in_day("scan-09999.json"));
    TEST_ASSERT_TRUE(in_day(".notes"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_twenty_thousand_files_in_one_day_are_cleaned_in_bounded_time);
    return UNITY_END();
}
