/* verdicts.jsonl under retention: the newest lines within the count and
 * age limits stay, in order; the file is replaced whole (no temporary left,
 * its mode kept) and only when a line goes; retention of the archive trims
 * the log to the same span. */
#include "unity.h"

#include <dirent.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "scratch_support.h"
#include "uwb/atomic_file.h"
#include "state/retention.h"
#include "state/store.h"
#include "state/verdict_log.h"

#define DAY 86400

static char dir[64];
static char err[2048];
static struct uwbd_store store;
static time_t now;

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "trim");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
    now = time(NULL);
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

/* A verdict line numbered n, created `age_s` seconds before `now`. */
static void append_verdict(int n, long age_s)
{
    char created[32], line[160];
    uwbd_utc_text(now - age_s, created, sizeof created);
    snprintf(line, sizeof line, "{\"class\":\"VERDICT\",\"n\":%d,\"created\":\"%s\"}", n, created);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_verdict_log_append(&store, line, err, sizeof err), err);
}

/* The "n" of every line, oldest first, as "1,2,3"; "?" for a line without one. */
static void numbers_in_log(char *out, size_t size)
{
    char *text = scratch_slurp(store.verdict_log, NULL);
    TEST_ASSERT_NOT_NULL(text);
    out[0] = '\0';
    size_t used = 0;
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        const char *p = strstr(line, "\"n\":");
        int n;
        if (p && sscanf(p + 4, "%d", &n) == 1)
            used += (size_t)snprintf(out + used, size - used, "%s%d", used ? "," : "", n);
        else
            used += (size_t)snprintf(out + used, size - used, "%s?", used ? "," : "");
    }
    free(text);
}

static ino_t log_inode(void)
{
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(store.verdict_log, &st));
    return st.st_ino;
}

static int hidden_files_in_root(void)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "test -z \"$(find '%s' -maxdepth 1 -name '.*' ! -name .)\"", store.root);
    return system(cmd) != 0;
}

/* Trim to max_lines (0: any) and max_days, and check how many lines went
 * and which stayed. */
static void expect_trim(int max_lines, double max_days, int expect_dropped, const char *expect_kept)
{
    int dropped = -1;
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_verdict_log_trim(&store, max_lines, max_days, now, &dropped, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(expect_dropped, dropped);
    char got[256];
    numbers_in_log(got, sizeof got);
    TEST_ASSERT_EQUAL_STRING(expect_kept, got);
}

static void test_count_keeps_the_newest_lines_in_order(void)
{
    for (int n = 1; n <= 10; n++)
        append_verdict(n, 100 - n);
    chmod(store.verdict_log, 0640);
    expect_trim(4, 0, 6, "7,8,9,10");
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, stat(store.verdict_log, &st));
    TEST_ASSERT_EQUAL_UINT(0640, st.st_mode & 07777);
    TEST_ASSERT_FALSE_MESSAGE(hidden_files_in_root(), "a temporary file was left beside verdicts.jsonl");
    /* Appending goes on at the end of the new file. */
    append_verdict(11, 0);
    char got[256];
    numbers_in_log(got, sizeof got);
    TEST_ASSERT_EQUAL_STRING("7,8,9,10,11", got);
}

static void test_a_log_within_the_limits_is_not_rewritten(void)
{
    for (int n = 1; n <= 3; n++)
        append_verdict(n, 10);
    ino_t before = log_inode();
    int dropped = -1;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_trim(&store, 3, 30, now, &dropped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, dropped);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_trim(&store, 0, 0, now, &dropped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, dropped);
    TEST_ASSERT_TRUE_MESSAGE(before == log_inode(), "the log was replaced though nothing had to go");
    TEST_ASSERT_EQUAL_INT(3, scratch_count_lines(store.verdict_log));
}

static void test_age_drops_lines_created_before_the_cutoff(void)
{
    append_verdict(1, 50L * DAY);
    append_verdict(2, 40L * DAY);
    append_verdict(3, 31L * DAY);
    append_verdict(4, 29L * DAY);
    append_verdict(5, 0);
    expect_trim(0, 30, 3, "4,5");
}

/* A line without a readable time goes or stays with the line before it. */
static void test_a_line_without_a_time_is_dated_by_its_neighbour(void)
{
    append_verdict(1, 40L * DAY);
    TEST_ASSERT_EQUAL_INT(
        0, uwbd_verdict_log_append(&store, "{\"n\":2,\"created\":\"garbled\"}", err, sizeof err));
    append_verdict(3, 10L * DAY);
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, "{\"n\":4}", err, sizeof err));
    append_verdict(5, 0);
    expect_trim(0, 30, 2, "3,4,5");
}

/* Leading lines without a time take the first known one; a log where no
 * line has a time is never trimmed by age (only by count). */
static void test_lines_without_any_time_are_dated_by_the_first_known(void)
{
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_append(&store, "{\"n\":1}", err, sizeof err));
    append_verdict(2, 40L * DAY);
    append_verdict(3, 0);
    expect_trim(0, 30, 2, "3");

    scratch_spit(store.verdict_log, "{\"n\":1}\n{\"n\":2,\"created\":7}\n{\"n\":3}\n");
    expect_trim(0, 1, 0, "1,2,3");
    expect_trim(2, 1, 1, "2,3");
}

static void test_count_and_age_together_keep_the_smaller_span(void)
{
    for (int n = 1; n <= 6; n++)
        append_verdict(n, (7 - n) * (long)DAY); /* 6 days old ... 1 day old */
    expect_trim(4, 2.5, 4, "5,6");
}

static void test_a_torn_last_line_does_not_survive_a_rewrite(void)
{
    scratch_spit(store.verdict_log, "{\"n\":1}\n{\"n\":2}\n{\"n\":3}\n{\"n\":4,\"cut");
    int dropped = -1;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_trim(&store, 2, 0, now, &dropped, err, sizeof err));
    char *text = scratch_slurp(store.verdict_log, NULL);
    TEST_ASSERT_EQUAL_STRING("{\"n\":2}\n{\"n\":3}\n", text);
    free(text);
}

/* A trim that cannot write its new log (the disk full, here the file-size
 * limit) is an error naming the log, which stays whole; no temporary is
 * left behind. */
static void test_a_trim_that_cannot_write_leaves_the_log_whole(void)
{
    for (int n = 1; n <= 200; n++)
        append_verdict(n, 0);
    size_t before_len = 0;
    char *before = scratch_slurp(store.verdict_log, &before_len);
    TEST_ASSERT_NOT_NULL(before);
    TEST_ASSERT_TRUE(before_len > 8192); /* past stdio's buffer: fwrite itself fails */
    struct rlimit saved, tight;
    TEST_ASSERT_EQUAL_INT(0, getrlimit(RLIMIT_FSIZE, &saved));
    void (*old_handler)(int) = signal(SIGXFSZ, SIG_IGN);
    tight = saved;
    tight.rlim_cur = 1000;
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &tight));
    int dropped = -1;
    int rc = uwbd_verdict_log_trim(&store, 150, 0, now, &dropped, err, sizeof err);
    TEST_ASSERT_EQUAL_INT(0, setrlimit(RLIMIT_FSIZE, &saved));
    signal(SIGXFSZ, old_handler);
    TEST_ASSERT_EQUAL_INT(-1, rc);
    TEST_ASSERT_EQUAL_INT(0, dropped);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl: cannot write the trimmed log: File too large"),
                                 err);
    scratch_assert_file_holds(store.verdict_log, before, before_len);
    free(before);
    DIR *d = opendir(store.root);
    TEST_ASSERT_NOT_NULL(d);
    for (struct dirent *e = readdir(d); e; e = readdir(d))
        TEST_ASSERT_FALSE_MESSAGE(uwb_atomic_file_is_temporary_name(e->d_name), e->d_name);
    closedir(d);
}

static void test_no_log_yet_is_nothing_to_trim(void)
{
    int dropped = -1;
    TEST_ASSERT_EQUAL_INT(0, uwbd_verdict_log_trim(&store, 1, 1, now, &dropped, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, dropped);
    TEST_ASSERT_FALSE(scratch_file_exists(store.verdict_log));
}

static void test_an_unreadable_log_is_an_error_naming_it(void)
{
    TEST_ASSERT_EQUAL_INT(0, mkdir(store.verdict_log, 0755));
    err[0] = '\0';
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_trim(&store, 1, 0, now, NULL, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "verdicts.jsonl"), err);
}

/* Retention of the archive trims the log to the same number of cycles. */
static void test_retention_trims_the_log_with_the_archive(void)
{
    struct tm day = {.tm_year = 2030 - 1900, .tm_mon = 0, .tm_mday = 1};
    char day_dir[2300];
    TEST_ASSERT_EQUAL_INT_MESSAGE(
        0, uwbd_store_day_dir(&store, &day, day_dir, sizeof day_dir, err, sizeof err), err);
    for (int n = 1; n <= 5; n++) {
        char p[2400];
        snprintf(p, sizeof p, "%s/scan-%d.json", day_dir, n);
        scratch_spit(p, "{}\n");
        append_verdict(n, 10 - n);
    }
    int removed = 0;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_retention_apply(&store, 2, 0, now, 1, &removed, err, sizeof err),
                                  err);
    TEST_ASSERT_EQUAL_INT(2, uwbd_archive_count(&store));
    char got[256];
    numbers_in_log(got, sizeof got);
    TEST_ASSERT_EQUAL_STRING("4,5", got);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_count_keeps_the_newest_lines_in_order);
    RUN_TEST(test_a_log_within_the_limits_is_not_rewritten);
    RUN_TEST(test_age_drops_lines_created_before_the_cutoff);
    RUN_TEST(test_a_line_without_a_time_is_dated_by_its_neighbour);
    RUN_TEST(test_lines_without_any_time_are_dated_by_the_first_known);
    RUN_TEST(test_a_trim_that_cannot_write_leaves_the_log_whole);
    RUN_TEST(test_count_and_age_together_keep_the_smaller_span);
    RUN_TEST(test_a_torn_last_line_does_not_survive_a_rewrite);
    RUN_TEST(test_no_log_yet_is_nothing_to_trim);
    RUN_TEST(test_an_unreadable_log_is_an_error_naming_it);
    RUN_TEST(test_retention_trims_the_log_with_the_archive);
    return UNITY_END();
}
