/* The CSV output module's file: the header first, a row per verdict, the
 * newest rows kept as the archive keeps its scans, a quoted line break not
 * taken for the end of a row, a torn tail dropped. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "unity.h"

#include "daemon/output_csv.h"
#include "scratch_support.h"
#include "uwb/verdict_csv.h"

static char dir[512], path[600], err[1024], expected[4096];

void setUp(void)
{
    scratch_scratch_dir(dir, sizeof dir, "output_csv");
    snprintf(path, sizeof path, "%s/verdicts.csv", dir);
    err[0] = '\0';
}

void tearDown(void)
{
    scratch_remove_tree(dir);
}

static void add(const char *row, int max_rows)
{
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_csv_file_add(path, row, max_rows, err, sizeof err), err);
}

static void test_a_new_file_starts_with_the_header(void)
{
    add("a,1\r\n", 0);
    snprintf(expected, sizeof expected, "%sa,1\r\n", uwb_verdict_csv_header());
    scratch_assert_file_holds(path, expected, strlen(expected));
}

static void test_the_newest_rows_are_kept(void)
{
    add("a\r\n", 2);
    add("\"b\r\nstill b\"\r\n", 2); /* a quoted line break inside one row */
    add("c\r\n", 2);
    snprintf(expected, sizeof expected, "%s\"b\r\nstill b\"\r\nc\r\n", uwb_verdict_csv_header());
    scratch_assert_file_holds(path, expected, strlen(expected));
    add("d\r\n", 0);
    add("e\r\n", 0);
    snprintf(expected, sizeof expected, "%s\"b\r\nstill b\"\r\nc\r\nd\r\ne\r\n", uwb_verdict_csv_header());
    scratch_assert_file_holds(path, expected, strlen(expected));
    add("f\r\n", 1);
    snprintf(expected, sizeof expected, "%sf\r\n", uwb_verdict_csv_header());
    scratch_assert_file_holds(path, expected, strlen(expected));
}

static void test_a_torn_tail_and_an_old_header_are_replaced(void)
{
    scratch_spit(path, "old header\r\na\r\nhalf a ro");
    add("b\r\n", 0);
    snprintf(expected, sizeof expected, "%sa\r\nb\r\n", uwb_verdict_csv_header());
    scratch_assert_file_holds(path, expected, strlen(expected));
}

static void test_an_unwritable_place_is_an_error_naming_it(void)
{
    snprintf(path, sizeof path, "%s/no-such-dir/verdicts.csv", dir);
    TEST_ASSERT_EQUAL_INT(-1, uwbd_csv_file_add(path, "a\r\n", 0, err, sizeof err));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "no-such-dir"), err);
}

/* Issue 47: the module needs nothing of the daemon but its port: the
 * configuration in force; a verdict's row appended, none when the verdict
 * line could not be written or csv.enabled is false. */
static void test_the_module_runs_on_a_port_alone(void)
{
    static struct uwbd_config cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.csv.enabled = 1;
    snprintf(cfg.csv.path, sizeof cfg.csv.path, "%s", path);
    const struct uwbd_daemon_port port = {.cfg = &cfg};
    static struct uwb_verdict_record rec;
    memset(&rec, 0, sizeof rec);
    char row[4096];
    TEST_ASSERT_GREATER_THAN(0, uwb_verdict_csv_row(&rec, row, sizeof row));

    uwbd_output_csv.verdict(&port, &rec, NULL, 1.0); /* no verdict line: no row */
    FILE *f = fopen(path, "r");
    TEST_ASSERT_NULL(f);
    uwbd_output_csv.verdict(&port, &rec, "{}", 1.0);
    snprintf(expected, sizeof expected, "%s%s", uwb_verdict_csv_header(), row);
    scratch_assert_file_holds(path, expected, strlen(expected));
    cfg.csv.enabled = 0;
    uwbd_output_csv.verdict(&port, &rec, "{}", 1.0);
    scratch_assert_file_holds(path, expected, strlen(expected));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_a_new_file_starts_with_the_header);
    RUN_TEST(test_the_newest_rows_are_kept);
    RUN_TEST(test_a_torn_tail_and_an_old_header_are_replaced);
    RUN_TEST(test_an_unwritable_place_is_an_error_naming_it);
    RUN_TEST(test_the_module_runs_on_a_port_alone);
    return UNITY_END();
}
