/* Console and control commands: every command, the bounds, and garbage of
 * every kind (including a seeded stream of random lines) is refused
 * cleanly. Also the line cutter that feeds the parser. */
#include "unity.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "control/command.h"
#include "control/line_buffer.h"

static struct uwb_command cmd;
static char err[160];

void setUp(void)
{
}
void tearDown(void)
{
}

static int parse(const char *line)
{
    memset(&cmd, 0x5a, sizeof cmd);
    return uwb_command_parse(line, strlen(line), &cmd, err, sizeof err);
}

static void assert_command(const char *line, enum uwb_command_kind kind)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_COMMAND_OK, parse(line), line);
    TEST_ASSERT_EQUAL_INT_MESSAGE(kind, cmd.kind, line);
}

static void assert_invalid(const char *line, const char *words)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_COMMAND_INVALID, parse(line), line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, words), err);
}

static void test_every_command(void)
{
    assert_command("status", UWB_COMMAND_STATUS);
    assert_command("scan", UWB_COMMAND_SCAN);
    assert_command("verdict", UWB_COMMAND_VERDICT);
    assert_command("help", UWB_COMMAND_HELP);
    assert_command("baseline set", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(0, cmd.count); /* the configured baseline.scans */
    assert_command("baseline set 4", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(4, cmd.count);
    assert_command("baseline set 16", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(16, cmd.count);
    TEST_ASSERT_EQUAL_INT(0, cmd.force);
    assert_command("baseline set force", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(1, cmd.force);
    TEST_ASSERT_EQUAL_INT(0, cmd.count);
    assert_command("history", UWB_COMMAND_HISTORY);
    TEST_ASSERT_EQUAL_INT(UWB_HISTORY_DEFAULT, cmd.count);
    assert_command("history 7", UWB_COMMAND_HISTORY);
    TEST_ASSERT_EQUAL_INT(7, cmd.count);
    assert_command("history 100", UWB_COMMAND_HISTORY);
    TEST_ASSERT_EQUAL_INT(100, cmd.count);
    assert_command("history 1", UWB_COMMAND_HISTORY);
    TEST_ASSERT_EQUAL_INT(1, cmd.count);
}

/* `watch` and gpsd's ?WATCH form (longer than any word: once refused as "too long"). */
static void test_watch_forms(void)
{
    assert_command("watch", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(1, cmd.watch);
    assert_command("watch progress", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(2, cmd.watch);
    assert_command("watch off", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(0, cmd.watch);
    assert_command("?WATCH={\"enable\":true}", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(1, cmd.watch);
    assert_command("?WATCH={\"enable\": true};\r\n", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(1, cmd.watch);
    assert_command("?WATCH={\"enable\":false}", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(0, cmd.watch);
    assert_invalid("?WATCH={\"json\":true}", "?WATCH");
    TEST_ASSERT_NULL_MESSAGE(strstr(err, "too long"), err);
    assert_invalid("watch on", "watch off");
    assert_invalid("watch off now", "unexpected argument");
}

/* Does `line` (lower case, single spaces) match the help usage `usage`:
 * its words in order, where "[N]" or "[S]" is an optional number? */
static int matches_usage(const char *usage, const char *line)
{
    char u[64], l[64];
    snprintf(u, sizeof u, "%s", usage);
    snprintf(l, sizeof l, "%s", line);
    char *us = NULL, *ls = NULL;
    char *uw = strtok_r(u, " ", &us), *lw = strtok_r(l, " ", &ls);
    for (; uw; uw = strtok_r(NULL, " ", &us)) {
        int optional_number = uw[0] == '[';
        if (optional_number && lw && strspn(lw, "0123456789") == strlen(lw))
            lw = strtok_r(NULL, " ", &ls);
        else if (!optional_number) {
            if (!lw || strcmp(uw, lw) != 0)
                return 0;
            lw = strtok_r(NULL, " ", &ls);
        }
    }
    return lw == NULL;
}

/* Issue 31, finding 9: the help list is the table of what the daemon
 * dispatches on. Every line of one to three words drawn from the help's
 * words, every kind's name and a few likely extras that the parser accepts
 * has its help line, and every help line (with and without its number) is
 * accepted; every kind has a help line. */
static void test_help_lists_exactly_the_commands_accepted(void)
{
    const char *vocabulary[64];
    size_t n = 0;
    const char *extras[] = {"1",     "on",     "all",  "now",      "get",   "clear",
                            "reset", "test",   "off",  "progress", "force", "set",
                            "relay", "reload", "stop", "version",  "quit",  "list"};
    for (size_t i = 0; i < sizeof extras / sizeof extras[0]; i++)
        vocabulary[n++] = extras[i];
    for (int kind = 0; kind <= UWB_COMMAND_CONTACTS_TEST; kind++) {
        const char *name = uwb_command_name((enum uwb_command_kind)kind);
        TEST_ASSERT_TRUE_MESSAGE(n < 64, "vocabulary too small");
        vocabulary[n++] = strchr(name, ' ') ? NULL : name;
        if (!vocabulary[n - 1])
            n--;
        int listed = 0;
        for (size_t h = 0; h < uwb_command_help_count; h++)
            listed |= strncmp(uwb_command_help[h].usage, name, strlen(name)) == 0;
        TEST_ASSERT_TRUE_MESSAGE(listed, name);
    }
    static char help_words[64][24];
    size_t n_help_words = 0;
    for (size_t h = 0; h < uwb_command_help_count; h++) {
        char usage[64];
        snprintf(usage, sizeof usage, "%s", uwb_command_help[h].usage);
        char *save = NULL;
        for (char *w = strtok_r(usage, " ", &save); w; w = strtok_r(NULL, " ", &save))
            if (w[0] != '[' && n_help_words < 64 && n < 64) {
                snprintf(help_words[n_help_words], sizeof help_words[0], "%s", w);
                vocabulary[n++] = help_words[n_help_words++];
            }
        /* uwbd ctl --help prints the brief meaning after 23 columns, within 78. */
        TEST_ASSERT_NOT_NULL_MESSAGE(uwb_command_help[h].brief, uwb_command_help[h].usage);
        TEST_ASSERT_TRUE_MESSAGE(strlen(uwb_command_help[h].brief) <= 55, uwb_command_help[h].brief);
        TEST_ASSERT_TRUE_MESSAGE(strlen(uwb_command_help[h].usage) <= 19, uwb_command_help[h].usage);
        /* Each help line is accepted, with its optional number and without. */
        char line[64];
        snprintf(line, sizeof line, "%s", uwb_command_help[h].usage);
        char *bracket = strchr(line, '[');
        if (bracket) {
            snprintf(bracket, sizeof line - (size_t)(bracket - line), "3");
            TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_COMMAND_OK, parse(line), line);
            bracket[bracket > line ? -1 : 0] = '\0';
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_COMMAND_OK, parse(line), line);
    }
    char line[64];
    int accepted = 0;
    for (size_t a = 0; a < n; a++)
        for (size_t b = 0; b <= n; b++)
            for (size_t c = 0; c <= (b < n ? n : 0); c++) {
                snprintf(line, sizeof line, "%s%s%s%s%s", vocabulary[a], b < n ? " " : "",
                         b < n ? vocabulary[b] : "", c < n ? " " : "", c < n ? vocabulary[c] : "");
                if (parse(line) != UWB_COMMAND_OK)
                    continue;
                accepted++;
                int listed = 0;
                for (size_t h = 0; h < uwb_command_help_count && !listed; h++)
                    listed = matches_usage(uwb_command_help[h].usage, line);
                TEST_ASSERT_TRUE_MESSAGE(listed, line);
            }
    TEST_ASSERT_GREATER_THAN_INT(15, accepted);
}

/* `contacts test [S]`: the seconds each relay is held, bounded. */
static void test_contacts_test(void)
{
    assert_command("contacts test", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(UWB_CONTACTS_TEST_DEFAULT_S, cmd.count);
    assert_command("contacts test 1", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(1, cmd.count);
    assert_command("contacts  test 60\r\n", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(60, cmd.count);
    TEST_ASSERT_EQUAL_STRING("contacts test", uwb_command_name(UWB_COMMAND_CONTACTS_TEST));
    assert_invalid("contacts", "contacts test");
    assert_invalid("contacts energise", "contacts test");
    assert_invalid("contacts test 0", "1 to 60");
    assert_invalid("contacts test 61", "1 to 60");
    assert_invalid("contacts test forever", "1 to 60");
    assert_invalid("contacts test 5 now", "force");
    assert_invalid("contacts test 5 force now", "too many words");
}

/* Issue 43, break 2: `contacts test force [S]` tests during a standing
 * watch or alarm; the word may come before or after S. */
static void test_contacts_test_force(void)
{
    assert_command("contacts test", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(0, cmd.force);
    assert_command("contacts test force", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(1, cmd.force);
    TEST_ASSERT_EQUAL_INT(UWB_CONTACTS_TEST_DEFAULT_S, cmd.count);
    assert_command("contacts test force 3", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(1, cmd.force);
    TEST_ASSERT_EQUAL_INT(3, cmd.count);
    assert_command("contacts test 4 FORCE", UWB_COMMAND_CONTACTS_TEST);
    TEST_ASSERT_EQUAL_INT(1, cmd.force);
    TEST_ASSERT_EQUAL_INT(4, cmd.count);
    assert_invalid("contacts test force force", "1 to 60");
    assert_invalid("contacts test 3 4", "force");
}

static void test_line_endings_and_spacing(void)
{
    assert_command("status\n", UWB_COMMAND_STATUS);
    assert_command("status\r\n", UWB_COMMAND_STATUS);
    assert_command("  \tbaseline   set \t", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_EMPTY, parse(""));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_EMPTY, parse(" \t \r\n"));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_EMPTY, uwb_command_parse("x", 0, &cmd, err, sizeof err));
}

static void test_bad_arguments(void)
{
    assert_invalid("history 0", "1 to 100");
    assert_invalid("history 101", "1 to 100");
    assert_invalid("history -3", "1 to 100");
    assert_invalid("history 5x", "1 to 100");
    assert_invalid("history 0005", "1 to 100");
    assert_invalid("history 5 6", "unexpected argument");
    assert_invalid("status now", "unexpected argument");
    assert_invalid("scan /etc/passwd", "unexpected argument");
    assert_invalid("baseline", "baseline set");
    assert_invalid("baseline reset", "baseline set");
    assert_invalid("baseline set now", "baseline set");
    assert_invalid("baseline set now please", "unexpected argument (see help): `please`");
    assert_invalid("baseline set now please thanks", "too many words");
    assert_invalid("baseline set 0", "1 to 16");
    assert_invalid("baseline set 17", "1 to 16");
    assert_invalid("baseline set 4 now", "unexpected argument (see help): `now`");
    assert_invalid("rm -rf", "unknown command");
}

/* Issue 31: people type `Baseline set` and `stauts`. Commands are read
 * case-insensitively; a near miss names the command meant. */
static void test_case_and_near_misses(void)
{
    assert_command("Status", UWB_COMMAND_STATUS);
    assert_command("Baseline set", UWB_COMMAND_BASELINE_SET);
    assert_command("BASELINE SET FORCE", UWB_COMMAND_BASELINE_SET);
    TEST_ASSERT_EQUAL_INT(1, cmd.force);
    assert_command("Watch Off", UWB_COMMAND_WATCH);
    TEST_ASSERT_EQUAL_INT(0, cmd.watch);
    assert_command("HISTORY 5", UWB_COMMAND_HISTORY);
    TEST_ASSERT_EQUAL_INT(5, cmd.count);
    assert_invalid("stauts", "did you mean `status`?");
    assert_invalid("histroy 3", "did you mean `history`?");
    assert_invalid("baselin set", "did you mean `baseline`?");
    assert_invalid("verdit", "did you mean `verdict`?");
    /* Nothing near: no guess. */
    assert_invalid("frobnicate", "unknown command");
    TEST_ASSERT_NULL_MESSAGE(strstr(err, "did you mean"), err);
}

static void test_bounds_and_bytes(void)
{
    char line[200];
    /* 64 bytes is the limit: a padded "status" of exactly 64 passes, 65 does not. */
    memset(line, ' ', sizeof line);
    memcpy(line, "status", 6);
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_OK,
                          uwb_command_parse(line, UWB_COMMAND_MAX_LINE, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID,
                          uwb_command_parse(line, UWB_COMMAND_MAX_LINE + 1, &cmd, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "too long"), err);
    assert_invalid("statusstatusstatusstatus", "too long");
    assert_invalid("stat\x01us", "not printable");
    assert_invalid("st\xc3\xa4tus", "not printable");
    assert_invalid("status\rnow", "not printable");
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse("scan\0junk", 9, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse(NULL, 3, &cmd, err, sizeof err));
    /* A tiny error buffer is still NUL-terminated. */
    char tiny[4];
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_INVALID, uwb_command_parse("bogus", 5, &cmd, tiny, sizeof tiny));
    TEST_ASSERT_EQUAL_INT(3, (int)strlen(tiny));
}

/* xorshift64: the same stream every run. */
static uint64_t next_random(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return *s;
}

static void test_random_lines_never_crash_and_are_classified(void)
{
    static const char alphabet[] = "statusscanverdicthistorybaselinesethelp 0123456789\t\r\n\x01\xff";
    uint64_t seed = 0x9e3779b97f4a7c15ull;
    int ok = 0, invalid = 0, empty = 0;
    for (int i = 0; i < 200000; i++) {
        char line[100];
        size_t len = (size_t)(next_random(&seed) % sizeof line);
        for (size_t j = 0; j < len; j++) {
            uint64_t r = next_random(&seed);
            line[j] = (r & 0x100) ? (char)(r & 0xff) : alphabet[r % (sizeof alphabet - 1)];
        }
        err[0] = 'x';
        int rc = uwb_command_parse(line, len, &cmd, err, sizeof err);
        TEST_ASSERT_TRUE(rc == UWB_COMMAND_OK || rc == UWB_COMMAND_EMPTY || rc == UWB_COMMAND_INVALID);
        if (rc == UWB_COMMAND_INVALID) {
            TEST_ASSERT_TRUE(strlen(err) > 0 && strlen(err) < sizeof err);
            invalid++;
        } else if (rc == UWB_COMMAND_OK) {
            TEST_ASSERT_TRUE(cmd.kind <= UWB_COMMAND_HELP);
            if (cmd.kind == UWB_COMMAND_HISTORY) {
                TEST_ASSERT_TRUE(cmd.count >= 1 && cmd.count <= UWB_HISTORY_MAX);
            }
            ok++;
        } else {
            empty++;
        }
    }
    TEST_ASSERT_TRUE(invalid > 0 && empty > 0);
    (void)ok;
}

static void test_line_buffer_cuts_lines_across_reads(void)
{
    struct uwbd_line_buffer lb = {0};
    const char *line;
    size_t len, used = 0;
    const char part1[] = "sta", part2[] = "tus\r\nscan\nhis";
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_NONE, uwbd_line_buffer_feed(&lb, part1, 3, &used, &line, &len));
    used = 0;
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY,
                          uwbd_line_buffer_feed(&lb, part2, strlen(part2), &used, &line, &len));
    TEST_ASSERT_EQUAL_STRING("status\r", line);
    TEST_ASSERT_EQUAL_INT(UWB_COMMAND_OK, uwb_command_parse(line, len, &cmd, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY,
                          uwbd_line_buffer_feed(&lb, part2, strlen(part2), &used, &line, &len));
    TEST_ASSERT_EQUAL_STRING("scan", line);
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_NONE,
                          uwbd_line_buffer_feed(&lb, part2, strlen(part2), &used, &line, &len));
    TEST_ASSERT_EQUAL_UINT64(strlen(part2), used);
}

static void test_line_buffer_drops_an_overlong_line_whole(void)
{
    struct uwbd_line_buffer lb = {0};
    char data[400];
    memset(data, 'a', 300);
    /* The tail of the long line is itself a valid command: it must not run. */
    memcpy(data + 290, "scan\nhelp\n", 10);
    const char *line;
    size_t len, used = 0;
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_TOO_LONG, uwbd_line_buffer_feed(&lb, data, 300, &used, &line, &len));
    TEST_ASSERT_EQUAL_INT(UWBD_LINE_READY, uwbd_line_buffer_feed(&lb, data, 300, &used, &line, &len));
    TEST_ASSERT_EQUAL_STRING("help", line);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_every_command);
    RUN_TEST(test_watch_forms);
    RUN_TEST(test_contacts_test);
    RUN_TEST(test_contacts_test_force);
    RUN_TEST(test_help_lists_exactly_the_commands_accepted);
    RUN_TEST(test_line_endings_and_spacing);
    RUN_TEST(test_bad_arguments);
    RUN_TEST(test_bounds_and_bytes);
    RUN_TEST(test_case_and_near_misses);
    RUN_TEST(test_random_lines_never_crash_and_are_classified);
    RUN_TEST(test_line_buffer_cuts_lines_across_reads);
    RUN_TEST(test_line_buffer_drops_an_overlong_line_whole);
    return UNITY_END();
}
