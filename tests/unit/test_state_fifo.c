/* Issue 27, break 2: a FIFO (or any file that is not a regular file) in
 * the state directory, or as the config file, is refused at once with its
 * name and what it is, never waited on: an open() of a FIFO with no writer
 * or reader blocks for ever, so the start hung, and a FIFO at
 * verdicts.jsonl hung the first scan beyond SIGTERM.
 *
 * Each call runs under a 2 s alarm whose handler does nothing, so a
 * blocking open() is cut short with EINTR and the test fails rather than
 * hangs. */
#include "unity.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "state/baseline_store.h"
#include "state/state_open.h"
#include "state/store.h"
#include "state/verdict_log.h"
#include "scratch_support.h"
#include "uwb/monotonic.h"
#include "uwb/read_file.h"

#define WINDOW_END_S 2e-9
/* A refusal is one open and one fstat: far below this. */
#define PROMPT_S 1.0
#define ALARM_S 2

static char dir[64];
static char err[2048];
static struct uwbd_store store;
static double started_s;

static void on_alarm(int sig)
{
    (void)sig;
}

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "state-fifo");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_store_open(&store, dir, NULL, err, sizeof err), err);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_alarm; /* no SA_RESTART: a blocked open() returns EINTR */
    sigemptyset(&sa.sa_mask);
    TEST_ASSERT_EQUAL_INT(0, sigaction(SIGALRM, &sa, NULL));
    err[0] = '\0';
}

void tearDown(void)
{
    alarm(0);
    scratch_remove_tree(dir);
}

/* A FIFO at rel (under the state directory); the deadline starts. */
static void fifo_at(char *path, size_t n, const char *rel)
{
    snprintf(path, n, "%s/%s", store.root, rel);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, mkfifo(path, 0644), path);
    started_s = uwb_monotonic_s();
    alarm(ALARM_S);
}

/* The refusal came at once and names the path and what is there. */
static void assert_refused_promptly(const char *path)
{
    double took_s = uwb_monotonic_s() - started_s;
    alarm(0);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, path), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is a FIFO, not a regular file"), err);
    TEST_ASSERT_TRUE_MESSAGE(took_s < PROMPT_S, err);
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, lstat(path, &st)); /* refused, left where it was */
    TEST_ASSERT_TRUE(S_ISFIFO(st.st_mode));
}

static void test_a_fifo_at_pending_json_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "baseline/pending.json");
    int scans = 0, force = 0;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_baseline_pending_read(&store, &scans, &force, err, sizeof err));
    assert_refused_promptly(p);
}

static void test_a_fifo_at_current_json_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "baseline/current.json");
    struct uwbd_baseline_info info;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_baseline_info_read(p, &info, err, sizeof err));
    assert_refused_promptly(p);
}

static void test_a_fifo_at_the_baseline_scan_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "baseline/current.uwbscan");
    struct uwb_scan scan = {0};
    struct uwbd_baseline_info info;
    TEST_ASSERT_EQUAL_INT(UWBD_BASELINE_ERROR,
                          uwbd_baseline_load(&store, WINDOW_END_S, &scan, &info, NULL, err, sizeof err));
    assert_refused_promptly(p);
}

static void test_a_fifo_at_latest_json_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "latest.json");
    char *json = NULL;
    TEST_ASSERT_EQUAL_INT(-1, uwbd_latest_read(&store, &json, err, sizeof err));
    TEST_ASSERT_NULL(json);
    assert_refused_promptly(p);
}

/* The start refuses it (the repair), and so does the append a scan makes. */
static void test_a_fifo_at_verdicts_jsonl_is_refused_at_start_and_at_append(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "verdicts.jsonl");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_state_open(&store, dir, NULL, err, sizeof err));
    assert_refused_promptly(p);
    started_s = uwb_monotonic_s();
    alarm(ALARM_S);
    err[0] = '\0';
    TEST_ASSERT_EQUAL_INT(-1, uwbd_verdict_log_append(&store, "{\"scan_id\":\"a\"}", err, sizeof err));
    assert_refused_promptly(p);
}

static void test_a_fifo_at_the_lock_file_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "uwbd.lock");
    TEST_ASSERT_EQUAL_INT(-1, uwbd_store_lock(dir, err, sizeof err));
    assert_refused_promptly(p);
}

/* The config, the MQTT password and the queue's files are read through
 * uwb_read_file. */
static void test_a_fifo_given_as_a_file_to_read_is_refused(void)
{
    char p[2048];
    fifo_at(p, sizeof p, "uwbd.json");
    char *text = NULL;
    size_t len = 0;
    TEST_ASSERT_EQUAL_INT(UWB_READ_FAILED, uwb_read_file(p, 4096, &text, &len, err, sizeof err));
    TEST_ASSERT_NULL(text);
    assert_refused_promptly(p);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_fifo_at_pending_json_is_refused);
    RUN_TEST(test_a_fifo_at_current_json_is_refused);
    RUN_TEST(test_a_fifo_at_the_baseline_scan_is_refused);
    RUN_TEST(test_a_fifo_at_latest_json_is_refused);
    RUN_TEST(test_a_fifo_at_verdicts_jsonl_is_refused_at_start_and_at_append);
    RUN_TEST(test_a_fifo_at_the_lock_file_is_refused);
    RUN_TEST(test_a_fifo_given_as_a_file_to_read_is_refused);
    return UNITY_END();
}
