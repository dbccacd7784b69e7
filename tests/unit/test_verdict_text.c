/* uwbd ctl --text: a verdict reply as lines for people, with every figure
 * the engineer needs, and anything that is not a verdict left alone. */
#include "unity.h"

#include <locale.h>
#include <stdio.h>
#include <stdlib.h>

#include "uwb/reply_text.h"
#include "uwb/cli.h"

static char *text;
static size_t text_len;
static FILE *out;

void setUp(void)
{
    text = NULL;
    out = open_memstream(&text, &text_len);
    TEST_ASSERT_NOT_NULL(out);
}

void tearDown(void)
{
    if (out)
        fclose(out);
    free(text);
}

static int render(const char *reply)
{
    int rc = uwbd_verdict_text(reply, out);
    fclose(out);
    out = NULL;
    return rc;
}

static void test_a_displacement_has_status_figure_edges_and_images(void)
{
    TEST_ASSERT_EQUAL_INT(
        0, render("{\"class\":\"VERDICT\",\"status\":\"alarm\",\"axial_displacement_mm\":12.0449,"
                  "\"uncertainty_mm\":0.234,\"lower_edge_mm\":212.04,\"upper_edge_mm\":612.49,"
                  "\"baseline\":{\"lower_edge_mm\":200.0,\"upper_edge_mm\":600.46},"
                  "\"images\":[\"/s/a.png\",\"/s/b.png\"]}"));
    TEST_ASSERT_EQUAL_STRING(
        "status ALARM: displacement +12.04 \u00b1 0.23 mm 1\u03c3, 95 %: +11.58..+12.51 mm "
        "(edges 212.0..612.5 mm, baseline 200.0..600.5 mm)\n"
        "image: /s/a.png\nimage: /s/b.png\n",
        text);
}

static void test_a_downward_shift_keeps_its_sign(void)
{
    TEST_ASSERT_EQUAL_INT(0,
                          render("{\"class\":\"VERDICT\",\"status\":\"watch\",\"axial_displacement_mm\":-3.5,"
                                 "\"uncertainty_mm\":0.4}"));
    TEST_ASSERT_EQUAL_STRING(
        "status WATCH: displacement -3.50 \u00b1 0.40 mm 1\u03c3, 95 %: -4.30..-2.70 mm\n", text);
}

static void test_a_height_change_is_given_with_its_sigma(void)
{
    TEST_ASSERT_EQUAL_INT(0, render("{\"class\":\"VERDICT\",\"status\":\"ok\",\"axial_displacement_mm\":1.16,"
                                    "\"uncertainty_mm\":0.1,\"height_change_mm\":-1.8,"
                                    "\"height_change_uncertainty_mm\":0.22}"));
    TEST_ASSERT_EQUAL_STRING("status OK: displacement +1.16 \u00b1 0.10 mm 1\u03c3, 95 %: +0.96..+1.36 mm\n"
                             "height change -1.80 \u00b1 0.22 mm 1\u03c3\n",
                             text);
}

static void test_a_withheld_height_change_says_why(void)
{
    TEST_ASSERT_EQUAL_INT(0, render("{\"class\":\"VERDICT\",\"status\":\"ok\",\"axial_displacement_mm\":1.16,"
                                    "\"uncertainty_mm\":0.1,\"height_change_withheld\":\"too uncertain\"}"));
    TEST_ASSERT_EQUAL_STRING("status OK: displacement +1.16 \u00b1 0.10 mm 1\u03c3, 95 %: +0.96..+1.36 mm\n"
                             "height change withheld: too uncertain\n",
                             text);
}

static void test_a_radial_change_gives_its_tilt(void)
{
    TEST_ASSERT_EQUAL_INT(
        0, render("{\"class\":\"VERDICT\",\"status\":\"ok\",\"radial\":{\"status\":\"ok\","
                  "\"max_change_mm\":0.4,\"at_mm\":300,\"uncertainty_mm\":0.5,\"tilt_mm\":-1.5}}"));
    TEST_ASSERT_EQUAL_STRING(
        "status OK\n"
        "radial change +0.40 \u00b1 0.50 mm 1\u03c3 at 300 mm; tilt -1.50 mm (+: top nearer): OK\n",
        text);
}

/* The tilt with its sigma, as every figure. */
static void test_a_tilt_gives_its_sigma(void)
{
    TEST_ASSERT_EQUAL_INT(0, render("{\"class\":\"VERDICT\",\"status\":\"ok\",\"radial\":{\"status\":\"ok\","
                                    "\"max_change_mm\":0.4,\"at_mm\":300,\"uncertainty_mm\":0.5,"
                                    "\"tilt_mm\":0.42,\"tilt_uncertainty_mm\":0.31}}"));
    TEST_ASSERT_EQUAL_STRING(
        "status OK\n"
        "radial change +0.40 \u00b1 0.50 mm 1\u03c3 at 300 mm; tilt +0.42 \u00b1 0.31 mm "
        "(+: top nearer): OK\n",
        text);
}

/* A change at the face's end: the tilt withheld, saying why, never "tilt +0.00". */
static void test_a_withheld_tilt_says_why(void)
{
    TEST_ASSERT_EQUAL_INT(0, render("{\"class\":\"VERDICT\",\"status\":\"alarm\",\"radial\":{\"status\":"
                                    "\"alarm\",\"max_change_mm\":8.45,\"at_mm\":341,\"uncertainty_mm\":1.57,"
                                    "\"tilt_withheld\":\"the change reaches the face's end\"}}"));
    TEST_ASSERT_EQUAL_STRING(
        "status ALARM\n"
        "radial change +8.45 \u00b1 1.57 mm 1\u03c3 at 341 mm; tilt withheld (the change "
        "reaches the face's end): ALARM\n",
        text);
}

static void test_edges_only_says_where_the_winding_is_and_whether_it_became_the_baseline(void)
{
    TEST_ASSERT_EQUAL_INT(0,
                          render("{\"class\":\"VERDICT\",\"status\":\"edges\",\"lower_edge_mm\":200.04,"
                                 "\"upper_edge_mm\":600.46,\"face_range_mm\":96.4,\"baseline_set\":true}"));
    TEST_ASSERT_EQUAL_STRING("status EDGES: winding from 200.0 to 600.5 mm, face at 96 mm; "
                             "became the baseline: yes\n",
                             text);
}

static void test_an_error_verdict_gives_its_reason(void)
{
    TEST_ASSERT_EQUAL_INT(0, render("{\"class\":\"VERDICT\",\"status\":\"error\","
                                    "\"reason\":\"acquisition failed: no frame within 300 ms\"}"));
    TEST_ASSERT_EQUAL_STRING("status ERROR: acquisition failed: no frame within 300 ms\n", text);
}

/* Issue 48, finding 4: a verdict in text carries its time and its scan,
 * an error verdict included (it was one line that could not be dated). */
static void test_an_error_verdict_is_dated_and_names_its_scan(void)
{
    TEST_ASSERT_EQUAL_INT(0,
                          render("{\"class\":\"VERDICT\",\"scan_id\":\"T3-north-uwb-20261207T032403.120Z\","
                                 "\"created\":\"2026-12-07T03:24:03Z\",\"status\":\"error\","
                                 "\"reason\":\"acquisition failed: no frame within 300 ms\"}"));
    TEST_ASSERT_EQUAL_STRING("verdict of 2026-12-07T03:24:03Z, scan T3-north-uwb-20261207T032403.120Z\n"
                             "status ERROR: acquisition failed: no frame within 300 ms\n",
                             text);
}

/* Issue 48, finding 6: where the terminal is not UTF-8 the text is ASCII:
 * "+/-" and "1 sigma" for "\u00b1" and "1\u03c3", the same figures. */
static void test_ascii_spells_plus_minus_and_sigma(void)
{
    TEST_ASSERT_EQUAL_INT(
        0,
        uwbd_verdict_text_in("{\"class\":\"VERDICT\",\"status\":\"alarm\",\"axial_displacement_mm\":12.0449,"
                             "\"uncertainty_mm\":0.234,\"height_change_mm\":-1.8,"
                             "\"height_change_uncertainty_mm\":0.22,\"radial\":{\"status\":\"ok\","
                             "\"max_change_mm\":0.4,\"at_mm\":300,\"uncertainty_mm\":0.5,"
                             "\"tilt_mm\":0.42,\"tilt_uncertainty_mm\":0.31}}",
                             out, UWBD_CHARSET_ASCII));
    fclose(out);
    out = NULL;
    TEST_ASSERT_EQUAL_STRING(
        "status ALARM: displacement +12.04 +/- 0.23 mm 1 sigma, 95 %: +11.58..+12.51 mm\n"
        "height change -1.80 +/- 0.22 mm 1 sigma\n"
        "radial change +0.40 +/- 0.50 mm 1 sigma at 300 mm; tilt +0.42 +/- 0.31 mm "
        "(+: top nearer): OK\n",
        text);
}

/* The locale decides: C is ASCII, C.UTF-8 (in every glibc since 2.35)
 * UTF-8. */
static void test_the_charset_is_the_locales(void)
{
    TEST_ASSERT_NOT_NULL(setlocale(LC_CTYPE, "C"));
    TEST_ASSERT_EQUAL_INT(UWBD_CHARSET_ASCII, uwbd_charset_of_locale());
    TEST_ASSERT_NOT_NULL_MESSAGE(setlocale(LC_CTYPE, "C.UTF-8"), "glibc's C.UTF-8 locale");
    TEST_ASSERT_EQUAL_INT(UWBD_CHARSET_UTF8, uwbd_charset_of_locale());
    setlocale(LC_CTYPE, "C");
}

static void test_other_replies_are_not_rendered(void)
{
    TEST_ASSERT_EQUAL_INT(-1, render("{\"class\":\"STATUS\",\"state\":\"idle\"}"));
    TEST_ASSERT_EQUAL_UINT(0, text_len);
}

static void test_a_reply_that_is_not_json_is_not_rendered(void)
{
    TEST_ASSERT_EQUAL_INT(-1, render("{\"class\":\"VERDICT\",\"status\":"));
    TEST_ASSERT_EQUAL_UINT(0, text_len);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_displacement_has_status_figure_edges_and_images);
    RUN_TEST(test_a_downward_shift_keeps_its_sign);
    RUN_TEST(test_a_height_change_is_given_with_its_sigma);
    RUN_TEST(test_a_withheld_height_change_says_why);
    RUN_TEST(test_a_radial_change_gives_its_tilt);
    RUN_TEST(test_a_tilt_gives_its_sigma);
    RUN_TEST(test_a_withheld_tilt_says_why);
    RUN_TEST(test_edges_only_says_where_the_winding_is_and_whether_it_became_the_baseline);
    RUN_TEST(test_an_error_verdict_gives_its_reason);
    RUN_TEST(test_an_error_verdict_is_dated_and_names_its_scan);
    RUN_TEST(test_ascii_spells_plus_minus_and_sigma);
    RUN_TEST(test_the_charset_is_the_locales);
    RUN_TEST(test_other_replies_are_not_rendered);
    RUN_TEST(test_a_reply_that_is_not_json_is_not_rendered);
    return UNITY_END();
}
