/* The serial console's line editing (src/control/console_line.c): the keys a
 * terminal program sends, the lines that come out, and the echo. */
#define _GNU_SOURCE /* memmem */
#include "unity.h"

#include <string.h>

#include "control/console_line.h"

static struct uwbd_console_line cl;
static char lines[8][UWB_COMMAND_MAX_LINE + 1];
static int events[8];
static int n_events;
static char echo[4096];
static size_t echo_len;

void setUp(void)
{
    memset(&cl, 0, sizeof cl);
    n_events = 0;
    echo_len = 0;
}

void tearDown(void)
{
}

/* Feeds the keys in chunks of `chunk` bytes, as reads would deliver them. */
static void type_chunked(const char *keys, size_t n, size_t chunk)
{
    for (size_t start = 0; start < n; start += chunk) {
        size_t len = n - start < chunk ? n - start : chunk, used = 0;
        const char *line;
        size_t line_len;
        int ev;
        do {
            ev = uwbd_console_line_feed(&cl, keys + start, len, &used, &line, &line_len);
            memcpy(echo + echo_len, cl.echo, cl.echo_len);
            echo_len += cl.echo_len;
            cl.echo_len = 0;
            if (ev != UWBD_LINE_NONE && n_events < 8) {
                events[n_events] = ev;
                snprintf(lines[n_events], sizeof lines[n_events], "%s", ev == UWBD_LINE_READY ? line : "");
                n_events++;
            }
        } while (ev != UWBD_LINE_NONE);
    }
}

static void type(const char *keys)
{
    type_chunked(keys, strlen(keys), 512);
}

static void test_cr_lf_and_crlf_each_end_one_line(void)
{
    type("status\rhelp\r\nverdict\n\r\n");
    TEST_ASSERT_EQUAL_INT(4, n_events);
    TEST_ASSERT_EQUAL_STRING("status", lines[0]);
    TEST_ASSERT_EQUAL_STRING("help", lines[1]);
    TEST_ASSERT_EQUAL_STRING("verdict", lines[2]);
    /* "\r\n" after the LF-ended line is one empty line, not two. */
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY, events[3]);
    TEST_ASSERT_EQUAL_STRING("", lines[3]);
}

static void test_crlf_split_across_reads_is_one_line_end(void)
{
    type_chunked("status\r\nhelp\r\n", 14, 7); /* "status\r" | "\nhelp\r\n" */
    TEST_ASSERT_EQUAL_INT(2, n_events);
    TEST_ASSERT_EQUAL_STRING("status", lines[0]);
    TEST_ASSERT_EQUAL_STRING("help", lines[1]);
}

static void test_backspace_and_del_edit_and_rub_out(void)
{
    type("stax\b\x7f"
         "atus\r");
    TEST_ASSERT_EQUAL_INT(1, n_events);
    TEST_ASSERT_EQUAL_STRING("status", lines[0]);
    TEST_ASSERT_EQUAL_MEMORY("stax\b \b\b \batus\r\n", echo, echo_len);
    TEST_ASSERT_EQUAL_UINT64(strlen("stax\b \b\b \batus\r\n"), echo_len);
}

static void test_backspace_on_an_empty_line_does_nothing(void)
{
    type("\b\x7fhelp\r");
    TEST_ASSERT_EQUAL_STRING("help", lines[0]);
    TEST_ASSERT_EQUAL_MEMORY("help\r\n", echo, echo_len);
}

static void test_cursor_keys_and_control_keys_are_ignored(void)
{
    type("\x1b[A\x1bOBhis\x1b[1;5Dtory\x01 2\r");
    TEST_ASSERT_EQUAL_STRING("history 2", lines[0]);
}

static void test_ctrl_u_and_ctrl_c_drop_the_line(void)
{
    type("bogus\x15help\r"
         "more\x03verdict\r");
    TEST_ASSERT_EQUAL_INT(2, n_events);
    TEST_ASSERT_EQUAL_STRING("help", lines[0]);
    TEST_ASSERT_EQUAL_STRING("verdict", lines[1]);
    TEST_ASSERT_NOT_NULL(
        memmem(echo, echo_len, "more^C\r\n" UWBD_CONSOLE_PROMPT, 8 + strlen(UWBD_CONSOLE_PROMPT)));
}

static void test_an_overlong_line_is_reported_once_and_the_next_is_whole(void)
{
    char keys[UWB_COMMAND_MAX_LINE + 40];
    memset(keys, 'x', UWB_COMMAND_MAX_LINE + 20);
    keys[UWB_COMMAND_MAX_LINE + 20] = '\b'; /* too late to fix it */
    strcpy(keys + UWB_COMMAND_MAX_LINE + 21, "\rstatus\r");
    type(keys);
    TEST_ASSERT_EQUAL_INT(2, n_events);
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_TOO_LONG, events[0]);
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY, events[1]);
    TEST_ASSERT_EQUAL_STRING("status", lines[1]);
    TEST_ASSERT_NOT_NULL(memchr(echo, '\a', echo_len));
}

static void test_a_line_of_exactly_the_limit_is_kept(void)
{
    char keys[UWB_COMMAND_MAX_LINE + 2];
    memset(keys, 'y', UWB_COMMAND_MAX_LINE);
    keys[UWB_COMMAND_MAX_LINE] = '\r';
    keys[UWB_COMMAND_MAX_LINE + 1] = '\0';
    type(keys);
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY, events[0]);
    TEST_ASSERT_EQUAL_UINT64(UWB_COMMAND_MAX_LINE, strlen(lines[0]));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_cr_lf_and_crlf_each_end_one_line);
    RUN_TEST(test_crlf_split_across_reads_is_one_line_end);
    RUN_TEST(test_backspace_and_del_edit_and_rub_out);
    RUN_TEST(test_backspace_on_an_empty_line_does_nothing);
    RUN_TEST(test_cursor_keys_and_control_keys_are_ignored);
    RUN_TEST(test_ctrl_u_and_ctrl_c_drop_the_line);
    RUN_TEST(test_an_overlong_line_is_reported_once_and_the_next_is_whole);
    RUN_TEST(test_a_line_of_exactly_the_limit_is_kept);
    return UNITY_END();
}
