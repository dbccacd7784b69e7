/* uwbd_log: "uwbd: LEVEL: text" lines on stderr, "<N>text" when stderr is
 * the journal's stream (JOURNAL_STREAM names its device and inode, exactly),
 * levels above the maximum dropped, an over-long line cut with its newline. */
#include "scratch_support.h"
#include "unity.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/log.h"

static char tmpdir[64];
static char path[128];
static int saved_stderr = -1;

void setUp(void)
{
    scratch_scratch_dir(tmpdir, sizeof tmpdir, "daemon-log");
    snprintf(path, sizeof path, "%s/stderr", tmpdir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    TEST_ASSERT_TRUE_MESSAGE(fd >= 0, path);
    fflush(stderr);
    saved_stderr = dup(STDERR_FILENO);
    TEST_ASSERT_TRUE(saved_stderr >= 0);
    TEST_ASSERT_EQUAL_INT(STDERR_FILENO, dup2(fd, STDERR_FILENO));
    close(fd);
    unsetenv("JOURNAL_STREAM");
}

void tearDown(void)
{
    if (saved_stderr >= 0) {
        dup2(saved_stderr, STDERR_FILENO);
        close(saved_stderr);
        saved_stderr = -1;
    }
    unsetenv("JOURNAL_STREAM");
    scratch_remove_tree(tmpdir);
}

/* What was written to stderr so far (malloc'd). */
static char *written(void)
{
    char *text = scratch_slurp(path, NULL);
    TEST_ASSERT_NOT_NULL(text);
    return text;
}

/* JOURNAL_STREAM naming the file stderr goes to, with `suffix` after it. */
static void set_journal_stream(const char *prefix, const char *suffix)
{
    struct stat st;
    TEST_ASSERT_EQUAL_INT(0, fstat(STDERR_FILENO, &st));
    char value[128];
    snprintf(value, sizeof value, "%s%llu:%llu%s", prefix, (unsigned long long)st.st_dev,
             (unsigned long long)st.st_ino, suffix);
    setenv("JOURNAL_STREAM", value, 1);
}

static void test_plain_lines_name_their_level_and_drop_those_above_the_maximum(void)
{
    uwbd_log_setup(UWBD_LOG_INFO, 0);
    uwbd_log(UWBD_LOG_ERR, "disk %s", "full");
    uwbd_log(UWBD_LOG_WARNING, "w%d", 1);
    uwbd_log(UWBD_LOG_NOTICE, "n");
    uwbd_log(UWBD_LOG_INFO, "i");
    uwbd_log(UWBD_LOG_DEBUG, "not shown");
    char *text = written();
    TEST_ASSERT_EQUAL_STRING("uwbd: error: disk full\nuwbd: warning: w1\nuwbd: notice: n\nuwbd: info: i\n",
                             text);
    free(text);
    uwbd_log_setup(UWBD_LOG_DEBUG, 0);
    uwbd_log(UWBD_LOG_DEBUG, "now shown");
    text = written();
    TEST_ASSERT_NOT_NULL(strstr(text, "uwbd: debug: now shown\n"));
    free(text);
}

static void test_journal_stream_matching_stderr_gives_priority_prefixes(void)
{
    set_journal_stream("", "");
    uwbd_log_setup(UWBD_LOG_INFO, 1); /* syslog asked, but the journal already has the line */
    uwbd_log(UWBD_LOG_WARNING, "to the journal");
    char *text = written();
    TEST_ASSERT_EQUAL_STRING("<4>to the journal\n", text);
    free(text);
}

static void test_journal_stream_not_exactly_dev_colon_inode_is_not_the_journal(void)
{
    static const char *const prefixes[] = {"-", " ", "+", "x", ""};
    static const char *const suffixes[] = {"", "", "", "", "x"};
    for (size_t i = 0; i < sizeof prefixes / sizeof prefixes[0]; i++) {
        set_journal_stream(prefixes[i], suffixes[i]);
        uwbd_log_setup(UWBD_LOG_INFO, 0);
        uwbd_log(UWBD_LOG_ERR, "case %zu", i);
    }
    static const char *const others[] = {"",       "12",     "12:", ":34",
                                         "12:-34", "12: 34", "1:2", "99999999999999999999999:1"};
    for (size_t i = 0; i < sizeof others / sizeof others[0]; i++) {
        setenv("JOURNAL_STREAM", others[i], 1);
        uwbd_log_setup(UWBD_LOG_INFO, 0);
        uwbd_log(UWBD_LOG_ERR, "other %zu", i);
    }
    char *text = written();
    TEST_ASSERT_NULL_MESSAGE(strchr(text, '<'), text);
    TEST_ASSERT_NOT_NULL(strstr(text, "uwbd: error: case 4\n"));
    TEST_ASSERT_NOT_NULL(strstr(text, "uwbd: error: other 7\n"));
    free(text);
}

static void test_an_over_long_line_is_cut_and_still_ends_in_a_newline(void)
{
    uwbd_log_setup(UWBD_LOG_INFO, 0);
    char big[3000];
    memset(big, 'a', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    uwbd_log(UWBD_LOG_ERR, "%s", big);
    size_t len = 0;
    char *text = scratch_slurp(path, &len);
    TEST_ASSERT_NOT_NULL(text);
    TEST_ASSERT_TRUE(len > 1000 && len < sizeof big);
    TEST_ASSERT_EQUAL_INT('\n', text[len - 1]);
    TEST_ASSERT_NULL(memchr(text, '\n', len - 1));
    TEST_ASSERT_EQUAL_INT(0, strncmp(text, "uwbd: error: aaa", 16));
    free(text);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_plain_lines_name_their_level_and_drop_those_above_the_maximum);
    RUN_TEST(test_journal_stream_matching_stderr_gives_priority_prefixes);
    RUN_TEST(test_journal_stream_not_exactly_dev_colon_inode_is_not_the_journal);
    RUN_TEST(test_an_over_long_line_is_cut_and_still_ends_in_a_newline);
    return UNITY_END();
}
