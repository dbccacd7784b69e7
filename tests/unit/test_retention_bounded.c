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
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include "state/retention.h"
#include "state/store.h"
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
    static const char *const levels[] = {"2030", "2030/01", DAY};
    for (size_t i = 0; i < 3; i++) {
        snprintf(day_dir, sizeof day_dir, "%s/%s", store.archive, levels[i]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, mkdir(day_dir, 0755), day_dir);
    }
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
    printf("%s\n", what);
}

static volatile sig_atomic_t stop_flag;

static void raise_stop(int sig)
{
    (void)sig;
    stop_flag = 1;
}

/* A stop request (the worker's SIGUSR1 on SIGTERM) during the clean-up
 * ends it between two scans: promptly, with scans left for later and every
 * scan that remains still listed (no image left without its record); the
 * next call finishes. The request comes once the listing (timed first) is
 * taken again, so it lands among the deletions. */
static void test_a_stop_request_ends_the_clean_up_promptly(void)
{
    fill_one_day();
    double listing_s = uwb_monotonic_s();
    TEST_ASSERT_EQUAL_INT(SCANS, uwbd_archive_count(&store));
    listing_s = uwb_monotonic_s() - listing_s;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = raise_stop;
    sa.sa_flags = SA_RESTART;
    sigemptyset(&sa.sa_mask);
    TEST_ASSERT_EQUAL_INT(0, sigaction(SIGALRM, &sa, NULL));
    stop_flag = 0;
    double stop_after_s = 1.5 * listing_s + 0.005;
    struct itimerval later = {
        .it_value = {.tv_sec = (time_t)stop_after_s,
                     .tv_usec = (suseconds_t)((stop_after_s - (time_t)stop_after_s) * 1e6)}};
    struct uwbd_retention_budget budget = {.stop = &stop_flag};
    int removed = -1;
    double started_s = uwb_monotonic_s();
    TEST_ASSERT_EQUAL_INT(0, setitimer(ITIMER_REAL, &later, NULL));
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply_within(&store, KEEP, 0, time(NULL), 1, &budget, &removed, err, sizeof err),
        err);
    double took_s = uwb_monotonic_s() - started_s;
    char what[128];
    snprintf(what, sizeof what, "stop requested at %.3f s, ended at %.3f s with %d scans deleted",
             stop_after_s, took_s, removed);
    TEST_ASSERT_TRUE_MESSAGE(stop_flag, what); /* the stop came before the end */
    /* The stop, then one scan at most: 1 s of slack for a loaded machine. */
    TEST_ASSERT_TRUE_MESSAGE(took_s < stop_after_s + 1.0, what);
    TEST_ASSERT_EQUAL_INT_MESSAGE(1, budget.cut_short, what);
    TEST_ASSERT_TRUE_MESSAGE(removed < SCANS - KEEP, what);
    TEST_ASSERT_EQUAL_INT(SCANS - removed, uwbd_archive_count(&store));
    printf("%s\n", what);

    budget.stop = NULL;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply_within(&store, KEEP, 0, time(NULL), 1, &budget, &removed, err, sizeof err),
        err);
    TEST_ASSERT_EQUAL_INT(0, budget.cut_short);
    TEST_ASSERT_EQUAL_INT(KEEP, uwbd_archive_count(&store));
    TEST_ASSERT_TRUE(in_day("scan-09950.json"));
}

/* A cycle's share: at most max_deletions scans, the oldest, per call. */
static void test_a_cycle_deletes_at_most_its_share_and_the_next_continues(void)
{
    fill_one_day();
    struct uwbd_retention_budget budget = {.max_deletions = 4000};
    int removed = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_retention_apply_within(&store, KEEP, 0, time(NULL), 1, &budget, &removed, err, sizeof err),
        err);
    TEST_ASSERT_EQUAL_INT(4000, removed);
    TEST_ASSERT_EQUAL_INT(1, budget.cut_short);
    TEST_ASSERT_FALSE(in_day("scan-03999.json")); /* the oldest went first */
    TEST_ASSERT_TRUE(in_day("scan-04000.json"));
    int calls = 1;
    while (budget.cut_short && calls++ < 10)
        TEST_ASSERT_EQUAL_INT_MESSAGE(
            0,
            uwbd_retention_apply_within(&store, KEEP, 0, time(NULL), 1, &budget, &removed, err, sizeof err),
            err);
    TEST_ASSERT_EQUAL_INT(3, calls);
    TEST_ASSERT_EQUAL_INT(KEEP, uwbd_archive_count(&store));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_twenty_thousand_files_in_one_day_are_cleaned_in_bounded_time);
    RUN_TEST(test_a_stop_request_ends_the_clean_up_promptly);
    RUN_TEST(test_a_cycle_deletes_at_most_its_share_and_the_next_continues);
    return UNITY_END();
}
