/* The verdict's field table: a figure added as one row (here to a
 * test-only copy of the table, over a record that extends the published
 * one) is rounded, written to JSON in its place, read back, given its CSV
 * column and its place in the summaries, with nothing else changed; and
 * the published table's places do not collide. */
#include "unity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/verdict_csv.h"
#include "uwb/verdict_fields.h"
#include "uwb/verdict_json.h"

/* A new figure: the winding's spread, in the analysis in metres. */
struct spread_verdict {
    struct uwb_verdict base;
    double spread_m;
};
struct spread_record {
    struct uwb_verdict_record base;
    int has_spread;
    double spread_mm;
    char spread_withheld[64];
};

static struct uwb_field rows[64];
static struct uwb_field_table with_spread;
static struct spread_verdict verdict;
static struct spread_record record;

/* The published table with one row added after snr_db. */
static void build_table(void)
{
    static const struct uwb_field_group top = {NULL, 0, 0};
    const struct uwb_field spread = {"spread_mm",
                                     &top,
                                     .kind = UWB_FIELD_NUMBER,
                                     .value = offsetof(struct spread_record, spread_mm),
                                     .given = offsetof(struct spread_record, has_spread),
                                     .decides = 1,
                                     .from = offsetof(struct spread_verdict, spread_m),
                                     .unit = "mm",
                                     .steps_per_si = 1e5,
                                     .steps_per_unit = 100.0,
                                     .withheld_key = "spread_withheld",
                                     .withheld = offsetof(struct spread_record, spread_withheld),
                                     .withheld_size = sizeof record.spread_withheld,
                                     .csv_column = 28,
                                     .summary = 10,
                                     .history = 22,
                                     .trend_key = "spread_mm",
                                     .trend = 14};
    size_t n = 0;
    TEST_ASSERT_LESS_THAN(sizeof rows / sizeof rows[0], uwb_verdict_fields.count + 1);
    for (size_t i = 0; i < uwb_verdict_fields.count; i++) {
        rows[n++] = uwb_verdict_fields.rows[i];
        if (strcmp(uwb_verdict_fields.rows[i].key, "snr_db") == 0)
            rows[n++] = spread;
    }
    TEST_ASSERT_EQUAL(uwb_verdict_fields.count + 1, n);
    with_spread = (struct uwb_field_table){rows, n};
}

void setUp(void)
{
    build_table();
    memset(&verdict, 0, sizeof verdict);
    memset(&record, 0, sizeof record);
    struct uwb_verdict *v = &verdict.base;
    v->status = UWB_STATUS_WATCH;
    snprintf(v->scan_id, sizeof v->scan_id, "s2");
    snprintf(v->created, sizeof v->created, "2026-12-07T10:00:00Z");
    v->has_baseline = 1;
    v->current.found = v->baseline.found = 1;
    v->current.lower_m = 0.1;
    v->current.upper_m = 0.9;
    v->current.center_m = 0.5;
    v->current.snr_db = 31.26;
    v->axial_displacement_m = 0.0031249;
    v->uncertainty_m = 0.00041;
    v->radial.withheld[0] = '\0';
    verdict.spread_m = 0.0012351;
}

void tearDown(void)
{
}

/* The record as uwbd makes it, and the added figure rounded by its row. */
static void publish(int has_spread)
{
    uwb_record_from_verdict(&record.base, &verdict.base);
    record.has_spread = has_spread;
    if (!has_spread)
        snprintf(record.spread_withheld, sizeof record.spread_withheld, "no spread without a baseline");
    uwb_fields_publish(&with_spread, &record, &verdict);
}

static char *json_of(const struct uwb_field_table *t)
{
    cJSON *o = cJSON_CreateObject();
    uwb_fields_write(t, &record, o);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static void test_an_added_row_is_rounded_and_written_in_its_place(void)
{
    publish(1);
    TEST_ASSERT_EQUAL_DOUBLE(1.24, record.spread_mm);
    char *text = json_of(&with_spread);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"snr_db\":31.3,\"spread_mm\":1.24,\"edge_uncertainty_mm\""),
                                 text);
    free(text);
}

static void test_without_its_flag_the_row_says_why_and_no_figure(void)
{
    publish(0);
    char *text = json_of(&with_spread);
    TEST_ASSERT_NULL_MESSAGE(strstr(text, "\"spread_mm\""), text);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(text, "\"spread_withheld\":\"no spread without a baseline\""), text);
    free(text);
}

static void test_the_added_row_leaves_the_published_keys_as_they_were(void)
{
    publish(1);
    char *with = json_of(&with_spread);
    char *without = json_of(&uwb_verdict_fields);
    char *at = strstr(with, ",\"spread_mm\":1.24");
    TEST_ASSERT_NOT_NULL(at);
    memmove(at, at + strlen(",\"spread_mm\":1.24"), strlen(at + strlen(",\"spread_mm\":1.24")) + 1);
    TEST_ASSERT_EQUAL_STRING(without, with);
    free(with);
    free(without);
}

static void test_the_added_row_is_read_back(void)
{
    publish(1);
    cJSON *o = cJSON_CreateObject();
    uwb_fields_write(&with_spread, &record, o);
    struct spread_record back;
    memset(&back, 0, sizeof back);
    char err[128] = "";
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_fields_read(&with_spread, o, &back, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT(1, back.has_spread);
    TEST_ASSERT_EQUAL_DOUBLE(1.24, back.spread_mm);
    TEST_ASSERT_EQUAL_DOUBLE(3.12, back.base.axial_displacement_mm);
    /* Its absence clears its flag; a wrong type names the key. */
    cJSON_DeleteItemFromObject(o, "spread_mm");
    back.has_spread = 1;
    TEST_ASSERT_EQUAL_INT(0, uwb_fields_read(&with_spread, o, &back, err, sizeof err));
    TEST_ASSERT_EQUAL_INT(0, back.has_spread);
    cJSON_AddStringToObject(o, "spread_mm", "wide");
    TEST_ASSERT_EQUAL_INT(-1, uwb_fields_read(&with_spread, o, &back, err, sizeof err));
    TEST_ASSERT_EQUAL_STRING("verdict: key `spread_mm`: not a number", err);
    cJSON_Delete(o);
}

static void test_the_added_row_gets_its_csv_column(void)
{
    publish(1);
    char header[2048], row[2048];
    TEST_ASSERT_EQUAL_INT(0, uwb_fields_csv_header(&with_spread, header, sizeof header));
    size_t published = strlen(uwb_verdict_csv_header());
    TEST_ASSERT_EQUAL_MEMORY(uwb_verdict_csv_header(), header, published - 2);
    TEST_ASSERT_EQUAL_STRING(",spread_mm\r\n", header + published - 2);
    TEST_ASSERT_GREATER_THAN(0, uwb_fields_csv_row(&with_spread, &record.base, row, sizeof row));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(row, ",1.24\r\n"), row);
    record.has_spread = 0;
    TEST_ASSERT_GREATER_THAN(0, uwb_fields_csv_row(&with_spread, &record.base, row, sizeof row));
    TEST_ASSERT_EQUAL_STRING(",\r\n", row + strlen(row) - 3);
}

static int has_key(const char *const *keys, size_t n, const char *key)
{
    for (size_t i = 0; i < n; i++)
        if (strcmp(keys[i], key) == 0)
            return 1;
    return 0;
}

static void test_the_added_row_is_in_the_summaries_it_names(void)
{
    const char *keys[UWB_FIELD_PLACES];
    size_t n = uwb_fields_keys(&with_spread, NULL, 0, 's', keys, UWB_FIELD_PLACES);
    TEST_ASSERT_EQUAL_STRING("spread_mm", keys[n - 1]);
    n = uwb_fields_keys(&with_spread, NULL, 0, 'h', keys, UWB_FIELD_PLACES);
    TEST_ASSERT_TRUE(has_key(keys, n, "spread_mm"));
    n = uwb_fields_keys(&with_spread, NULL, 0, 't', keys, UWB_FIELD_PLACES);
    TEST_ASSERT_TRUE(has_key(keys, n, "spread_mm"));
    n = uwb_fields_keys(&uwb_verdict_fields, NULL, 0, 's', keys, UWB_FIELD_PLACES);
    TEST_ASSERT_FALSE(has_key(keys, n, "spread_mm"));
}

/* Two rows at one place would drop one of them from a summary or a CSV row. */
static void test_no_two_published_rows_share_a_place(void)
{
    const struct uwb_field_table *t = &uwb_verdict_fields;
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *a = &t->rows[i];
        TEST_ASSERT_TRUE_MESSAGE(a->kind != UWB_FIELD_NUMBER || (a->unit && a->steps_per_unit > 0), a->key);
        for (size_t j = i + 1; j < t->count; j++) {
            const struct uwb_field *b = &t->rows[j];
            TEST_ASSERT_FALSE_MESSAGE(a->csv_column && a->csv_column == b->csv_column, b->key);
            TEST_ASSERT_FALSE_MESSAGE(a->summary && a->summary == b->summary, b->key);
            TEST_ASSERT_FALSE_MESSAGE(a->history && a->history == b->history, b->key);
            TEST_ASSERT_FALSE_MESSAGE(a->trend && a->trend == b->trend, b->key);
            TEST_ASSERT_FALSE_MESSAGE(a->group == b->group && strcmp(a->key, b->key) == 0, b->key);
        }
    }
}

/* The summary (what a trend keeps, the textfile's figures) is the start
 * of the record: every row must lie in it, or a walk over a summary would
 * read past its end. */
static void test_every_published_row_lies_in_the_records_summary(void)
{
    const struct uwb_field_table *t = &uwb_verdict_fields;
    size_t end = sizeof(struct uwb_verdict_summary);
    TEST_ASSERT_EQUAL(0, offsetof(struct uwb_verdict_record, summary));
    TEST_ASSERT_EQUAL(offsetof(struct uwb_verdict_summary, direct_coupling_shift_ps),
                      offsetof(struct uwb_verdict_record, direct_coupling_shift_ps));
    for (size_t i = 0; i < t->count; i++) {
        const struct uwb_field *f = &t->rows[i];
        size_t size = f->kind == UWB_FIELD_TEXT ? f->size : sizeof(double);
        TEST_ASSERT_TRUE_MESSAGE(f->value + size <= end, f->key);
        TEST_ASSERT_TRUE_MESSAGE(f->given + sizeof(int) <= end, f->key);
        TEST_ASSERT_TRUE_MESSAGE(f->group->given + sizeof(int) <= end, f->key);
        TEST_ASSERT_TRUE_MESSAGE(!f->withheld_key || f->withheld + f->withheld_size <= end, f->key);
    }
}

/* Rounding is the table's: half a step away from zero, and no -0. */
static void test_a_row_rounds_to_its_step_and_never_to_minus_zero(void)
{
    const struct uwb_field *mm = uwb_field_find(&uwb_verdict_fields, NULL, "axial_displacement_mm");
    const struct uwb_field *ps = uwb_field_find(&uwb_verdict_fields, NULL, "direct_coupling_ps");
    TEST_ASSERT_NOT_NULL(mm);
    TEST_ASSERT_NOT_NULL(ps);
    TEST_ASSERT_EQUAL_DOUBLE(-1.24, uwb_field_round(mm, -0.0012351));
    TEST_ASSERT_FALSE(signbit(uwb_field_round(mm, -0.000001)));
    TEST_ASSERT_EQUAL_DOUBLE(1234.6, uwb_field_round(ps, 1.23456e-9));
    TEST_ASSERT_NULL(uwb_field_find(&uwb_verdict_fields, "radial", "axial_displacement_mm"));
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_an_added_row_is_rounded_and_written_in_its_place);
    RUN_TEST(test_without_its_flag_the_row_says_why_and_no_figure);
    RUN_TEST(test_the_added_row_leaves_the_published_keys_as_they_were);
    RUN_TEST(test_the_added_row_is_read_back);
    RUN_TEST(test_the_added_row_gets_its_csv_column);
    RUN_TEST(test_the_added_row_is_in_the_summaries_it_names);
    RUN_TEST(test_no_two_published_rows_share_a_place);
    RUN_TEST(test_a_row_rounds_to_its_step_and_never_to_minus_zero);
    RUN_TEST(test_every_published_row_lies_in_the_records_summary);
    return UNITY_END();
}
