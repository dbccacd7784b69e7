/* The accuracy report's 3-D rows and the radial rows' right-or-wrong
 * columns (make accuracy; issue 45 item 5).
 * - Every moved scan of the shared 3-D tanks and of those drawn here
 *   (tools/fdtd/draw_tank3d.py), without and with the drawings' span: a
 *   figure lies within 2 sigma of the truth, or there is none and the
 *   refusal names where (a range) what it found instead.
 * - The radial table says whether a change was read with the truth's sign
 *   and in its place, right or wrong, and "withheld" where nothing was
 *   read (it printed the truth plus a bias of 0 before, and no sign). */
#define _GNU_SOURCE /* open_memstream */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy/radial.h"
#include "accuracy/tank3d.h"
#include "unity.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static int emulated(void)
{
    const char *prefix = getenv("UWB_EXEC_PREFIX");
    return prefix && *prefix;
}

static void test_each_3d_pair_is_within_two_sigma_or_names_where(void)
{
    char err[512];
    for (int c = 0; c < tank3d_case_count; c++) {
        if (emulated() && c > 0)
            break; /* FFTW under qemu-user: the first case only */
        for (int with_span = 0; with_span <= 1; with_span++) {
            struct tank3d_row row;
            TEST_ASSERT_EQUAL_INT_MESSAGE(
                0, tank3d_run_case("tests/fixtures", &tank3d_cases[c], with_span, &row, err, sizeof err),
                err);
            char what[400];
            snprintf(what, sizeof what, "%s, span %s: %s %+.2f +- %.2f mm: %s", tank3d_cases[c].name,
                     with_span ? "given" : "not given", row.status, row.figure_m * 1e3, row.sigma_m * 1e3,
                     row.why);
            printf("%s\n", what);
            if (row.has_figure) {
                TEST_ASSERT_TRUE_MESSAGE(row.within_2sigma, what);
            } else if (strstr(row.why, "no shift within")) {
                /* The fit's own refusal: the faces were found and measured,
                 * and it names the centres' difference it searched about. */
                TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row.why, "the centres' difference"), what);
            } else {
                TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row.why, " m range"), what);
            }
        }
    }
}

/* Issue 45's goal for the shared 3-D tanks: at least three of the four
 * moved scans give a figure within 2 sigma, drawings or not. None did
 * while the lower plate's front edge, level with the face and twice as
 * bright in its range column, was all the face search looked at there. */
static void test_three_of_four_3d_pairs_give_a_figure_within_two_sigma(void)
{
    if (emulated())
        return; /* FFTW under qemu-user: the first case only, above */
    char err[512];
    for (int with_span = 0; with_span <= 1; with_span++) {
        int right = 0, shared = 0;
        for (int c = 0; c < tank3d_case_count; c++) {
            if (tank3d_cases[c].fresh)
                continue;
            shared++;
            struct tank3d_row row;
            TEST_ASSERT_EQUAL_INT_MESSAGE(
                0, tank3d_run_case("tests/fixtures", &tank3d_cases[c], with_span, &row, err, sizeof err),
                err);
            right += row.has_figure && row.within_2sigma;
        }
        TEST_ASSERT_EQUAL_INT_MESSAGE(4, shared, "the shared 3-D tanks' moved scans");
        TEST_ASSERT_GREATER_OR_EQUAL_INT_MESSAGE(3, right, with_span ? "span given" : "span not given");
    }
}

/* One printed row, into buf. */
static void print_radial(const struct radial_case *c, const struct radial_row *r, char *buf, size_t len)
{
    char *text = NULL;
    size_t n = 0;
    FILE *mem = open_memstream(&text, &n);
    TEST_ASSERT_NOT_NULL(mem);
    radial_print_row(mem, c, NULL, r);
    fclose(mem);
    snprintf(buf, len, "%s", text);
    free(text);
}

static void test_the_radial_table_says_sign_and_place_right_or_wrong(void)
{
    const struct radial_case bulge = {"a bulge", "b", "c", 0.006, 0.256, 0.330, .disks = 3};
    struct radial_row r = {.pairs = 1,
                           .measured = 1,
                           .bias_m = -0.01326,
                           .median_sigma_m = 0.0011,
                           .sign_right = 0.0,
                           .located = 0.0,
                           .watch_or_worse = 1.0};
    char line[1024];
    print_radial(&bulge, &r, line, sizeof line);
    /* The complement read: -7.26 mm for +6, elsewhere. */
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "| -7.26 |"), line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "| **wrong** | **wrong** |"), line);
    r.bias_m = 0.0004;
    r.sign_right = r.located = 1.0;
    print_radial(&bulge, &r, line, sizeof line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "| right | right |"), line);
    r = (struct radial_row){.pairs = 1, .measured = 0};
    print_radial(&bulge, &r, line, sizeof line);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, "| withheld |"), line);
    TEST_ASSERT_NULL_MESSAGE(strstr(line, "+6.00 | +6.00"), line);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_each_3d_pair_is_within_two_sigma_or_names_where);
    RUN_TEST(test_three_of_four_3d_pairs_give_a_figure_within_two_sigma);
    RUN_TEST(test_the_radial_table_says_sign_and_place_right_or_wrong);
    return UNITY_END();
}
