/* Issue 31, finding 2: people get text. The status page (aligned
 * "Name : value" lines, as chronyc's `tracking`), the history table and
 * the help list that `uwbd ctl --text` and the serial console print. */
#define _GNU_SOURCE /* open_memstream */
#include "unity.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "control/reply.h"
#include "control/scan_progress.h"
#include "state/state_writes.h"
#include "integrations/site_io.h"
#include "uwb/reply_text.h"
#include "uwb/cli.h"
#include "uwb/verdict_record.h"

static char *printed;

void setUp(void)
{
    printed = NULL;
}
void tearDown(void)
{
    free(printed);
}

static const char *as_text(char *reply)
{
    size_t n;
    FILE *f = open_memstream(&printed, &n);
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_reply_text(reply, f), reply);
    fclose(f);
    free(reply);
    return printed;
}

static const char *as_text_in(char *reply, enum uwbd_charset charset)
{
    size_t n;
    FILE *f = open_memstream(&printed, &n);
    TEST_ASSERT_NOT_NULL(f);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_reply_text_in(reply, f, charset), reply);
    fclose(f);
    free(reply);
    return printed;
}

static void assert_has(const char *text, const char *part)
{
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, part), text);
}

static void test_status_is_a_page_of_names_and_values(void)
{
    struct uwbd_contact_states contacts = {.watch = 0, .alarm = 1, .fault = 1};
    struct uwbd_status st = {
        .version = "1.2",
        .state = "idle",
        .uptime_s = 7500,
        .interval_s = 3600,
        .state_dir = "/var/lib/uwbd",
        .rig = "ready",
        .asset_id = "GT2-L1",
        .modbus_endpoint = "tcp:0.0.0.0:502",
        .modbus_listening = 1,
        .contacts = &contacts,
        .has_baseline = 1,
        .now = 1700000000 + 3 * 86400 + 3600,
        .has_state_dir_free = 1,
        .state_dir_free_bytes = 5ULL * 1024 * 1024 * 1024,
    };
    snprintf(st.baseline.scan_id, sizeof st.baseline.scan_id, "b1");
    snprintf(st.baseline.set_at, sizeof st.baseline.set_at, "2023-11-14T22:13:20Z");
    const char *t = as_text(uwbd_reply_status(&st));
    TEST_ASSERT_NULL_MESSAGE(strchr(t, '{'), t);
    assert_has(t, "State           : idle\n");
    assert_has(t, "Asset           : GT2-L1\n");
    assert_has(t, "Baseline        : b1, set 2023-11-14T22:13:20Z (3 d 1 h ago)\n");
    assert_has(t, "Latest verdict  : none\n");
    assert_has(t, "Schedule        : every 1 h 0 min\n");
    assert_has(t, "MQTT            : off\n");
    assert_has(t, "Modbus          : listening on tcp:0.0.0.0:502\n");
    assert_has(t, "Contacts        : alarm, fault energised\n");
    assert_has(t, "State directory : /var/lib/uwbd, 5.0 GiB free\n");
    assert_has(t, "Version         : 1.2 (protocol 1.0), up 2 h 5 min\n");
}

/* Issue 43, break 6: a full disk is said in words on the status page, with
 * what still works; a healthy page has no such line. */
static void test_status_says_the_disk_is_full(void)
{
    struct uwbd_state_writes w = {.failing = 1, .disk_full = 1, .cycles = 2};
    snprintf(w.since, sizeof w.since, "2030-01-02T00:00:00Z");
    snprintf(w.error, sizeof w.error, "/s/a.uwbscan: cannot write temporary file: No space left on device");
    struct uwbd_status st = {
        .version = "1.2", .state = "idle", .state_dir = "/s", .rig = "ready", .writes = &w};
    const char *t = as_text(uwbd_reply_status(&st));
    assert_has(t, "Archive         : NOT WRITING, the disk is full, since 2030-01-02T00:00:00Z (2 scans): "
                  "/s/a.uwbscan: cannot write temporary file: No space left on device; scans are still "
                  "evaluated and published\n");
    free(printed);
    w.failing = 0;
    st.writes = NULL;
    t = as_text(uwbd_reply_status(&st));
    TEST_ASSERT_NULL_MESSAGE(strstr(t, "Archive"), t);
}

static void test_help_is_a_list_that_fits_a_terminal(void)
{
    const char *t = as_text(uwbd_reply_help());
    TEST_ASSERT_NULL_MESSAGE(strstr(t, "{\"class\""), t);
    assert_has(t, "\n  status              daemon state");
    assert_has(t, "\n  baseline set force");
    for (const char *line = t; *line; line += strcspn(line, "\n") + (line[strcspn(line, "\n")] != 0)) {
        size_t n = strcspn(line, "\n");
        TEST_ASSERT_TRUE_MESSAGE(n <= 79, line);
    }
}

static void test_history_is_a_table(void)
{
    char *lines[] = {
        "{\"class\":\"VERDICT\",\"scan_id\":\"s1\",\"created\":\"2026-11-27T08:00:00Z\",\"status\":\"edges\","
        "\"baseline_set\":true}",
    };
    char *reply = uwbd_reply_history(lines, 1, 10, 0);
    TEST_ASSERT_NOT_NULL(reply);
    /* Whatever the verdict reader makes of this minimal line, the table has its header and no JSON. */
    const char *t = as_text(reply);
    TEST_ASSERT_NULL_MESSAGE(strchr(t, '{'), t);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, strncmp(t, "time ", 5), t);
}

/* The lines of t (each without its newline) wider than `columns`
 * characters: 0 expected. */
static int lines_wider_than(const char *t, int columns)
{
    int wide = 0;
    while (*t) {
        size_t n = strcspn(t, "\n");
        int shown = 0;
        for (size_t i = 0; i < n; i++)
            shown += ((unsigned char)t[i] & 0xC0) != 0x80;
        wide += shown > columns;
        t += n + (t[n] == '\n');
    }
    return wide;
}

static int has_non_ascii(const char *t)
{
    for (; *t; t++)
        if ((unsigned char)*t >= 0x80)
            return 1;
    return 0;
}

/* A reason long enough to have been cut (at 160 bytes: "...without its
 * changed" and no closing parenthesis), as evaluate.c writes it. */
#define LONG_REASON \
    "the face changed shape (the ends moved apart by 4 mm and the echo weakened at 420 mm, not a shift " \
    "without its changed rows): radial change read where its rows still match, axial figure withheld"

static char *history_of_three(void)
{
    char *lines[] = {
        "{\"class\":\"VERDICT\",\"scan_id\":\"T3-north-uwb-20261127T080000.101Z\",\"created\":\"2026-11-"
        "27T08:"
        "00:00Z\",\"status\":\"edges\",\"baseline_set\":true}",
        "{\"class\":\"VERDICT\",\"scan_id\":\"T3-north-uwb-20261128T080000.202Z\",\"created\":\"2026-11-"
        "28T08:"
        "00:00Z\",\"status\":\"ok\",\"axial_displacement_mm\":0.12,\"uncertainty_mm\":0.3,"
        "\"lower_edge_mm\":200,\"upper_edge_mm\":600,\"height_change_mm\":-0.05,\"height_change_uncertainty_"
        "mm\":0.1,\"radial\":{\"status\":\"ok\",\"max_change_mm\":0.2,\"at_mm\":300,"
        "\"uncertainty_mm\":0.1}}",
        "{\"class\":\"VERDICT\",\"scan_id\":\"T3-north-uwb-20261129T080000.303Z\",\"created\":\"2026-11-"
        "29T08:"
        "00:00Z\",\"status\":\"inconclusive\",\"reason\":\"" LONG_REASON "\",\"radial\":{\"status\":"
        "\"alarm\",\"max_change_mm\":6.1,\"at_mm\":420,\"uncertainty_mm\":0.4}}",
    };
    char *reply = uwbd_reply_history(lines, 3, 3, 0);
    TEST_ASSERT_NOT_NULL(reply);
    return reply;
}

/* Issue 48, finding 5: the history table cuts no text: the reason whole
 * (every word, the parenthesis closed), wrapped under its row within 79
 * columns; the height column says it holds the change; a radial column. */
static void test_history_wraps_a_reason_and_has_a_radial_column(void)
{
    const char *t = as_text(history_of_three());
    assert_has(t, "height change");
    assert_has(t, "radial \u00b1 1\u03c3");
    assert_has(t, "+0.20 \u00b1 0.10 mm ok");
    assert_has(t, "+6.10 \u00b1 0.40 mm alarm");
    assert_has(t, "-0.05 mm");
    /* The reason, words joined again, is the whole reason. */
    const char *start = strstr(t, "the face changed shape");
    TEST_ASSERT_NOT_NULL_MESSAGE(start, t);
    char joined[1024] = "";
    size_t k = 0;
    for (const char *c = start; *c && k + 1 < sizeof joined; c++) {
        if (*c == '\n') {
            while (c[1] == ' ')
                c++;
            if (k && joined[k - 1] != ' ')
                joined[k++] = ' ';
            continue;
        }
        joined[k++] = *c;
    }
    joined[k] = '\0';
    TEST_ASSERT_EQUAL_STRING_LEN(LONG_REASON, joined, strlen(LONG_REASON));
    /* Only the rows (time, figures, scan) may pass 79 columns; the
     * reason's lines do not. */
    while (start > t && start[-1] != '\n')
        start--;
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, lines_wider_than(start, 79), t);
}

/* Issue 48, finding 6: in ASCII no byte past 127 (status, history, ack). */
static void test_ascii_text_has_no_byte_past_127(void)
{
    const char *t = as_text_in(history_of_three(), UWBD_CHARSET_ASCII);
    TEST_ASSERT_FALSE_MESSAGE(has_non_ascii(t), t);
    assert_has(t, "radial +/- 1 sigma");
    assert_has(t, "+0.12 +/- 0.30 mm");
    free(printed);
    struct uwbd_contact_states held = {.watch = 1, .alarm = 1, .fault = 1};
    struct uwb_verdict_record latest = {.status = UWB_STATUS_ALARM, .has_displacement = 1};
    latest.axial_displacement_mm = 11.97;
    latest.uncertainty_mm = 0.35;
    t = as_text_in(uwbd_reply_ack(&held, &latest), UWBD_CHARSET_ASCII);
    TEST_ASSERT_FALSE_MESSAGE(has_non_ascii(t), t);
    assert_has(t, "ALARM +11.97 +/- 0.35 mm");
}

/* Issue 48, finding 4: the status page's latest verdict names its scan. */
static void test_status_names_the_latest_verdicts_scan(void)
{
    struct uwb_verdict_record latest = {.status = UWB_STATUS_ERROR};
    snprintf(latest.scan_id, sizeof latest.scan_id, "T3-north-uwb-20261207T032403.120Z");
    snprintf(latest.created, sizeof latest.created, "2026-12-07T03:24:03Z");
    snprintf(latest.reason, sizeof latest.reason, "digitiser did not answer");
    struct uwbd_status st = {
        .version = "1.2", .state = "idle", .state_dir = "/s", .rig = "ready", .latest = &latest};
    const char *t = as_text_in(uwbd_reply_status(&st), UWBD_CHARSET_ASCII);
    assert_has(t, "Latest verdict  : ERROR (digitiser did not answer), 2026-12-07T03:24:03Z, scan "
                  "T3-north-uwb-20261207T032403.120Z\n");
}

static void test_errors_and_short_replies_are_a_line(void)
{
    TEST_ASSERT_EQUAL_STRING(
        "error: unknown command `stauts` (did you mean `status`? try help)\n",
        as_text(uwbd_reply_error("unknown command `stauts` (did you mean `status`? try help)")));
    free(printed);
    TEST_ASSERT_EQUAL_STRING("watching: progress and verdicts\n", as_text(uwbd_reply_watch(1)));
    free(printed);
    printed = NULL;
    size_t n;
    FILE *f = open_memstream(&printed, &n);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_reply_text("not json", f));
    fclose(f);
    TEST_ASSERT_EQUAL_STRING("", printed);
}

/* Issue 31, finding 10: a PROGRESS line of a commissioning says its pass. */
static void test_progress_says_its_pass(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate_passes(2, 3, 7, 21, 0.0, 2.0, 40.0, 40.0, &p);
    TEST_ASSERT_EQUAL_STRING("scan: position 7 of 21, pass 2 of 3, 40 s, about 49 s left\n",
                             as_text(uwbd_reply_progress(&p)));
    free(printed);
    uwbd_scan_progress_estimate(7, 21, 0.0, 2.0, 14.0, 14.0, &p);
    TEST_ASSERT_EQUAL_STRING("scan: position 7 of 21, 14 s, about 28 s left\n",
                             as_text(uwbd_reply_progress(&p)));
}

/* The console's line and uwbd ctl's bar read a PROGRESS line's figures
 * through one reader: what the daemon sends is what both get. */
static void test_progress_figures_read_back(void)
{
    struct uwbd_scan_progress sent;
    uwbd_scan_progress_estimate_passes(2, 3, 7, 21, 0.0, 2.0, 40.0, 40.0, &sent);
    char *line = uwbd_reply_progress(&sent);
    struct uwbd_progress got;
    TEST_ASSERT_EQUAL_INT(0, uwbd_progress_read(line, &got));
    free(line);
    TEST_ASSERT_EQUAL_DOUBLE(7.0, got.position);
    TEST_ASSERT_EQUAL_DOUBLE(21.0, got.positions);
    TEST_ASSERT_EQUAL_DOUBLE(2.0, got.pass);
    TEST_ASSERT_EQUAL_DOUBLE(3.0, got.passes);
    TEST_ASSERT_TRUE(got.has_elapsed && got.has_left && got.has_fraction);
    TEST_ASSERT_DOUBLE_WITHIN(1e-9, 40.0, got.elapsed_s);
    TEST_ASSERT_DOUBLE_WITHIN(0.5, 49.0, got.left_s);
    TEST_ASSERT_DOUBLE_WITHIN(1e-3, (1.0 + 7.0 / 21.0) / 3.0, got.fraction);
    /* An older daemon's line: no passes, no fraction, no estimate. */
    TEST_ASSERT_EQUAL_INT(
        0, uwbd_progress_read("{\"class\":\"PROGRESS\",\"position\":3,\"positions\":9}", &got));
    TEST_ASSERT_EQUAL_DOUBLE(1.0, got.passes);
    TEST_ASSERT_FALSE(got.has_elapsed || got.has_left || got.has_fraction);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_progress_read("{\"class\":\"PROGRESS\",\"position\":3}", &got));
    TEST_ASSERT_EQUAL_INT(-1, uwbd_progress_read("not json", &got));
}

/* Issue 48, finding 8: `ack` says the alarm was acknowledged and what
 * still holds a contact: the latest verdict's condition, with its time. */
static void test_ack_says_what_still_holds_the_contacts(void)
{
    struct uwbd_contact_states held = {.watch = 1, .alarm = 1, .fault = 1};
    struct uwb_verdict_record latest = {.status = UWB_STATUS_ALARM, .has_displacement = 1};
    latest.axial_displacement_mm = 11.97;
    latest.uncertainty_mm = 0.35;
    snprintf(latest.scan_id, sizeof latest.scan_id, "T3-north-uwb-20261207T032316.813Z");
    snprintf(latest.created, sizeof latest.created, "2026-12-07T03:23:16Z");
    const char *t = as_text(uwbd_reply_ack(&held, &latest));
    assert_has(t, "acknowledged: the watch and alarm latches are released\n");
    assert_has(t, "still energised: watch, alarm, as the latest verdict calls for: ALARM +11.97");
    assert_has(t, "(2026-12-07T03:23:16Z, scan T3-north-uwb-20261207T032316.813Z)\n");
    free(printed);
    struct uwbd_contact_states released = {.fault = 1};
    latest.status = UWB_STATUS_OK;
    latest.axial_displacement_mm = 0.1;
    t = as_text(uwbd_reply_ack(&released, &latest));
    assert_has(t, "acknowledged: the watch and alarm latches are released\n");
    assert_has(t, "watch and alarm released: the latest verdict is OK +0.10");
    TEST_ASSERT_NULL_MESSAGE(strstr(t, "still energised"), t);
    free(printed);
    t = as_text(uwbd_reply_ack(&released, NULL));
    assert_has(t, "watch and alarm released (no verdict yet)\n");
}

/* Issue 48, finding 8: `contacts test` says its sequence in words. */
static void test_contacts_test_says_its_sequence(void)
{
    char reply[] = "{\"class\":\"CONTACTS_TEST\",\"sequence\":[\"watch\",\"alarm\",\"fault\"],"
                   "\"hold_s\":2,\"gap_s\":1,\"duration_s\":9}";
    char *line = malloc(sizeof reply);
    TEST_ASSERT_NOT_NULL(line);
    memcpy(line, reply, sizeof reply);
    TEST_ASSERT_EQUAL_STRING("contacts test started: all contacts released for 1 s, then watch, alarm and "
                             "fault each energised alone for 2 s with 1 s released between;\n"
                             "9 s in all, then the contacts return to what the verdicts call for\n",
                             as_text(line));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_status_is_a_page_of_names_and_values);
    RUN_TEST(test_status_says_the_disk_is_full);
    RUN_TEST(test_help_is_a_list_that_fits_a_terminal);
    RUN_TEST(test_history_is_a_table);
    RUN_TEST(test_history_wraps_a_reason_and_has_a_radial_column);
    RUN_TEST(test_ascii_text_has_no_byte_past_127);
    RUN_TEST(test_status_names_the_latest_verdicts_scan);
    RUN_TEST(test_errors_and_short_replies_are_a_line);
    RUN_TEST(test_progress_says_its_pass);
    RUN_TEST(test_progress_figures_read_back);
    RUN_TEST(test_ack_says_what_still_holds_the_contacts);
    RUN_TEST(test_contacts_test_says_its_sequence);
    return UNITY_END();
}
