/* The verdict as CSV for spreadsheets: the header, a compared verdict's
 * figures as the JSON prints them, withheld figures as empty cells (never
 * 0) with the reason saying why, RFC 4180 quoting, no partial row when the
 * buffer is short; and `uwbd ctl history --csv` from a HISTORY reply,
 * the daemon's own giving each verdict's row whole. */
#include "unity.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "control/reply.h"
#include "uwb/cli.h"
#include "uwb/verdict_csv.h"
#include "uwb/verdict_json.h"

static struct uwb_verdict_record rec;
static char row[4096];

void setUp(void)
{
    memset(&rec, 0, sizeof rec);
    memset(row, 'x', sizeof row);
}

void tearDown(void)
{
}

static void read_verdict(const char *json)
{
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_record_from_json(json, &rec, err, sizeof err), err);
}

static int count_fields(const char *line)
{
    int n = 1, quoted = 0;
    for (const char *c = line; *c && *c != '\r'; c++) {
        if (*c == '"')
            quoted = !quoted;
        else if (*c == ',' && !quoted)
            n++;
    }
    return n;
}

static void test_the_header_names_each_column_with_its_unit(void)
{
    TEST_ASSERT_EQUAL_STRING(
        "created,scan_id,status,axial_displacement_mm,uncertainty_mm,height_change_mm,"
        "height_change_uncertainty_mm,lower_edge_mm,upper_edge_mm,center_mm,height_mm,"
        "face_range_mm,snr_db,baseline_scan_id,baseline_set,fault,reason,trigger,"
        "asset_id,radial_status,radial_max_change_mm,radial_at_mm,radial_from_mm,"
        "radial_to_mm,radial_uncertainty_mm,radial_tilt_mm,radial_tilt_uncertainty_mm\r\n",
        uwb_verdict_csv_header());
}

static void test_a_compared_verdict_has_its_figures_as_published(void)
{
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"scan_id\":\"s2\",\"created\":\"2026-11-27T04:00:00Z\","
        "\"axial_displacement_mm\":12.04,\"uncertainty_mm\":0.23,\"lower_edge_mm\":212.04,"
        "\"upper_edge_mm\":612.5,\"center_mm\":412.27,\"height_mm\":400.46,\"height_change_mm\":-0.1,"
        "\"height_change_uncertainty_mm\":0.31,\"face_range_mm\":150,\"snr_db\":31.2,"
        "\"edge_uncertainty_mm\":0.2,\"baseline\":{\"lower_edge_mm\":200,\"upper_edge_mm\":600,"
        "\"center_mm\":400,\"scan_id\":\"s1\"},\"images\":[],\"asset_id\":\"T1\",\"trigger\":\"schedule\","
        "\"radial\":{\"status\":\"watch\",\"max_change_mm\":-4.03,\"at_mm\":318.3,\"from_mm\":291.3,"
        "\"to_mm\":349.3,\"uncertainty_mm\":0.55,\"tilt_mm\":-0.74,\"tilt_uncertainty_mm\":0.31}}");
    int n = uwb_verdict_csv_row(&rec, row, sizeof row);
    TEST_ASSERT_EQUAL_STRING(
        "2026-11-27T04:00:00Z,s2,alarm,12.04,0.23,-0.1,0.31,212.04,612.5,412.27,400.46,150,31.2,"
        "s1,,,,schedule,T1,watch,-4.03,318.3,291.3,349.3,0.55,-0.74,0.31\r\n",
        row);
    TEST_ASSERT_EQUAL_INT((int)strlen(row), n);
    TEST_ASSERT_EQUAL_INT(count_fields(uwb_verdict_csv_header()), count_fields(row));
}

/* The text after `after` up to the next comma (or the end), in out. */
static void up_to_comma(const char *text, const char *after, char *out, size_t n)
{
    const char *at = strstr(text, after);
    if (!at) {
        snprintf(out, n, "(no %s)", after);
        return;
    }
    at += strlen(after);
    snprintf(out, n, "%.*s", (int)strcspn(at, ",\r"), at);
}

/* Whatever the figure, the cell holds the digits the verdict's JSON holds. */
static void test_figures_read_as_the_json_prints_them(void)
{
    static const double figures[] = {0.1 + 0.2, 1e-7, -3.0, 123456.78, 2.5e10, -0.0};
    for (size_t i = 0; i < sizeof figures / sizeof figures[0]; i++) {
        memset(&rec, 0, sizeof rec);
        rec.has_displacement = 1;
        rec.axial_displacement_mm = figures[i];
        char *json = uwb_record_to_json(&rec);
        char want[64], cell[64];
        up_to_comma(json ? json : "", "\"axial_displacement_mm\":", want, sizeof want);
        free(json);
        TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
        up_to_comma(row, ",,edges,", cell, sizeof cell); /* created, scan_id empty; status edges */
        TEST_ASSERT_EQUAL_STRING(want, cell);
    }
}

static void test_withheld_figures_are_empty_cells_and_the_reason_says_why(void)
{
    read_verdict("{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"reason\":\"edges not found\","
                 "\"fault\":\"rig\",\"scan_id\":\"s3\",\"created\":\"c\",\"images\":[]}");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING("c,s3,inconclusive,,,,,,,,,,,,,rig,edges not found,,,,,,,,,,\r\n", row);

    /* Compared, but the height change withheld: its cells empty, its reason told. */
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"ok\",\"axial_displacement_mm\":0,\"uncertainty_mm\":0.2,"
        "\"lower_edge_mm\":1,\"upper_edge_mm\":2,\"center_mm\":1.5,\"height_mm\":1,"
        "\"height_change_withheld\":\"the upper edge is weak\",\"face_range_mm\":3,\"snr_db\":20,"
        "\"edge_uncertainty_mm\":0.1,\"images\":[]}");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING(
        ",,ok,0,0.2,,,1,2,1.5,1,3,20,,,,height change withheld: the upper edge is weak,,,,,,,,,,\r\n", row);

    /* The radial change withheld: its status told, its figures empty, the reason saying why;
     * measured without a span over the watch limit: those two cells empty. */
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"inconclusive\",\"reason\":\"not the same reflector\","
        "\"radial\":{\"status\":\"inconclusive\",\"withheld\":\"the face's range was not compared\"},"
        "\"images\":[]}");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING(
        ",,inconclusive,,,,,,,,,,,,,,not the same reflector; radial change withheld: the "
        "face's range was not compared,,,inconclusive,,,,,,,\r\n",
        row);
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"ok\",\"radial\":{\"status\":\"ok\",\"max_change_mm\":0.4,"
        "\"at_mm\":300,\"uncertainty_mm\":0.5,\"tilt_mm\":0},\"images\":[]}");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    /* A record from before the tilt's sigma: its cell empty. */
    TEST_ASSERT_EQUAL_STRING(",,ok,,,,,,,,,,,,,,,,,ok,0.4,300,,,0.5,0,\r\n", row);

    /* Measured, the tilt withheld (a change at the face's end): its cell empty, not 0; the reason says why.
     */
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"reason\":\"radial change +8.45 mm\","
        "\"radial\":{\"status\":\"alarm\",\"max_change_mm\":8.45,\"at_mm\":341,\"uncertainty_mm\":1.57,"
        "\"tilt_withheld\":\"the change reaches the face's end\"},\"images\":[]}");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING(",,alarm,,,,,,,,,,,,,,radial change +8.45 mm; tilt withheld: the change reaches "
                             "the face's end,,,alarm,8.45,341,,,1.57,,\r\n",
                             row);
}

static void test_a_reason_with_a_comma_and_a_quote_is_quoted(void)
{
    rec.status = UWB_STATUS_ERROR;
    strcpy(rec.reason, "carriage stalled, \"home\" not reached\nretry");
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING(
        ",,error,,,,,,,,,,,,,,\"carriage stalled, \"\"home\"\" not reached\nretry\",,,,,,,,,,\r\n", row);
}

static void test_a_short_buffer_gives_minus_one_and_no_partial_row(void)
{
    read_verdict(
        "{\"class\":\"VERDICT\",\"status\":\"watch\",\"reason\":\"a, b\",\"axial_displacement_mm\":3.5,"
        "\"uncertainty_mm\":0.2,\"images\":[]}");
    int n = uwb_verdict_csv_row(&rec, row, sizeof row);
    TEST_ASSERT_GREATER_THAN(0, n);
    char small[256];
    memset(small, 'x', sizeof small);
    TEST_ASSERT_EQUAL_INT(n, uwb_verdict_csv_row(&rec, small, (size_t)n + 1)); /* the row and its NUL */
    TEST_ASSERT_EQUAL_STRING(row, small);
    for (size_t len = 1; len <= (size_t)n; len++) {
        memset(small, 'x', sizeof small);
        TEST_ASSERT_EQUAL_INT(-1, uwb_verdict_csv_row(&rec, small, len));
        TEST_ASSERT_EQUAL_STRING("", small);
    }
    TEST_ASSERT_EQUAL_INT(-1, uwb_verdict_csv_row(&rec, small, 0));
}

static char *printed;
static size_t printed_len;

static int history_csv(const char *reply, char *err, size_t errlen)
{
    FILE *out = open_memstream(&printed, &printed_len);
    TEST_ASSERT_NOT_NULL(out);
    int rc = uwbd_history_csv(reply, out, err, errlen);
    fclose(out);
    return rc;
}

/* The HISTORY reply's summaries: the height change without its sigma
 * leaves that cell empty, not 0. */
static void test_a_history_reply_becomes_the_header_and_a_row_per_verdict(void)
{
    char err[256] = "";
    int rc = history_csv(
        "{\"class\":\"HISTORY\",\"requested\":5,\"count\":2,\"verdicts\":["
        "{\"scan_id\":\"a\",\"created\":\"t1\",\"status\":\"edges\",\"baseline_set\":true},"
        "{\"scan_id\":\"b\",\"created\":\"t2\",\"status\":\"alarm\",\"axial_displacement_mm\":5.01,"
        "\"uncertainty_mm\":0.2,\"center_mm\":405,\"height_change_mm\":0.4}]}",
        err, sizeof err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
    char want[2048];
    snprintf(want, sizeof want, "%s%s%s", uwb_verdict_csv_header(),
             "t1,a,edges,,,,,,,,,,,,true,,,,,,,,,,,,\r\n",
             "t2,b,alarm,5.01,0.2,0.4,,,,,,,,,,,,,,,,,,,,,\r\n");
    TEST_ASSERT_EQUAL_STRING(want, printed);
    free(printed);
}

/* The verdict line's own row, as the CSV file output writes it. */
static void append_row_of(const char *line, char *out, size_t n)
{
    read_verdict(line);
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));
    snprintf(out + strlen(out), n - strlen(out), "%s", row);
}

/* `uwbd ctl --csv history` from the daemon's HISTORY reply gives each
 * verdict's whole row: every column its verdict fills (the first fills
 * all 26), not only those a summary carries. */
static void test_the_daemons_history_reply_fills_every_column(void)
{
    char *lines[] = {
        "{\"class\":\"VERDICT\",\"status\":\"alarm\",\"reason\":\"over the alarm line\","
        "\"fault\":\"clock\",\"scan_id\":\"s2\",\"created\":\"2026-11-27T04:00:00Z\","
        "\"axial_displacement_mm\":12.04,\"uncertainty_mm\":0.23,\"lower_edge_mm\":212.04,"
        "\"upper_edge_mm\":612.5,\"center_mm\":412.27,\"height_mm\":400.46,\"height_change_mm\":-0.1,"
        "\"height_change_uncertainty_mm\":0.31,\"face_range_mm\":150,\"snr_db\":31.2,"
        "\"edge_uncertainty_mm\":0.2,\"baseline\":{\"lower_edge_mm\":200,\"upper_edge_mm\":600,"
        "\"center_mm\":400,\"scan_id\":\"s1\"},\"images\":[\"/a.png\"],\"scan_file\":\"/s2.uwbscan\","
        "\"baseline_set\":false,\"baseline_note\":\"an alarm is never the baseline\",\"asset_id\":\"T1\","
        "\"trigger\":\"event\",\"radial\":{\"status\":\"alarm\",\"max_change_mm\":5.75,\"at_mm\":359.59,"
        "\"from_mm\":332.59,\"to_mm\":384.59,\"uncertainty_mm\":0.46,\"tilt_mm\":2,\"tilt_uncertainty_mm\":0."
        "5}}",
        "{\"class\":\"VERDICT\",\"status\":\"ok\",\"scan_id\":\"s3\",\"created\":\"t3\","
        "\"axial_displacement_mm\":0,\"uncertainty_mm\":0.2,\"lower_edge_mm\":1,\"upper_edge_mm\":2,"
        "\"center_mm\":1.5,\"height_mm\":1,\"height_change_withheld\":\"the upper edge is weak\","
        "\"face_range_mm\":3,\"snr_db\":20,\"edge_uncertainty_mm\":0.1,\"images\":[],"
        "\"trigger\":\"schedule\"}",
        "{\"class\":\"VERDICT\",\"status\":\"error\",\"reason\":\"carriage stalled\",\"fault\":\"rig\","
        "\"scan_id\":\"s4\",\"created\":\"t4\",\"images\":[],\"trigger\":\"command\"}"};
    char *reply = uwbd_reply_history(lines, 3, 3, 0);
    TEST_ASSERT_NOT_NULL(reply);
    char err[256] = "";
    int rc = history_csv(reply, err, sizeof err);
    free(reply);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, err);
    char want[4096];
    snprintf(want, sizeof want, "%s", uwb_verdict_csv_header());
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++)
        append_row_of(lines[i], want, sizeof want);
    TEST_ASSERT_EQUAL_STRING(want, printed);
    const char *first = printed + strlen(uwb_verdict_csv_header());
    size_t first_len = strcspn(first, "\r");
    TEST_ASSERT_NULL_MESSAGE(memchr(first, '\0', first_len), "no first row");
    for (size_t i = 0; i + 1 < first_len; i++)
        TEST_ASSERT_FALSE_MESSAGE(first[i] == ',' && first[i + 1] == ',', first);
    TEST_ASSERT_TRUE_MESSAGE(first[0] != ',' && first[first_len - 1] != ',', first);
    free(printed);
}

static void test_a_reply_other_than_history_prints_nothing(void)
{
    char err[256] = "";
    TEST_ASSERT_EQUAL_INT(-1, history_csv("{\"class\":\"ERROR\",\"message\":\"no\"}", err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("", printed);
    TEST_ASSERT_NOT_NULL(strstr(err, "not a HISTORY reply"));
    free(printed);
    TEST_ASSERT_EQUAL_INT(
        -1, history_csv("{\"class\":\"HISTORY\",\"verdicts\":[{\"status\":\"maybe\"}]}", err, sizeof err));
    TEST_ASSERT_NOT_NULL(strstr(err, "verdict 0"));
    free(printed);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_the_header_names_each_column_with_its_unit);
    RUN_TEST(test_a_compared_verdict_has_its_figures_as_published);
    RUN_TEST(test_figures_read_as_the_json_prints_them);
    RUN_TEST(test_withheld_figures_are_empty_cells_and_the_reason_says_why);
    RUN_TEST(test_a_reason_with_a_comma_and_a_quote_is_quoted);
    RUN_TEST(test_a_short_buffer_gives_minus_one_and_no_partial_row);
    RUN_TEST(test_a_history_reply_becomes_the_header_and_a_row_per_verdict);
    RUN_TEST(test_the_daemons_history_reply_fills_every_column);
    RUN_TEST(test_a_reply_other_than_history_prints_nothing);
    return UNITY_END();
}
