/* One key table (src/config/config_keys.c) holds every configuration limit
 * and default (the rig's from its specs, src/rig/rig_keys.h). This walks it and asks everything else that
 * knows a limit or a default: the loader (file and --set), the rig's own checks and defaults, the shipped
 * sample configs and the documentation (board/config.md and the uwbd.json(5) page). At each limit the value
 * must be accepted everywhere; just past it, refused everywhere with the key named. */
#include "unity.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config/config_keys.h"
#include "rig/rig_keys.h"
#include "scratch_support.h"
#include "uwb/cli.h"
#include "config/config_load.h"

#define SAMPLE_EMULATED "board/emulated/uwbd.json"

static const char *const samples[] = {SAMPLE_EMULATED, "board/raspberry-pi-4/uwbd.json"};

static struct uwbd_config cfg;
static char err[1024];
static char *sample_text;

void setUp(void)
{
    sample_text = scratch_slurp(SAMPLE_EMULATED, NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(sample_text, SAMPLE_EMULATED);
    err[0] = '\0';
}

void tearDown(void)
{
    free(sample_text);
}

/* Other keys a limit needs to be reachable at all: without them a check
 * that involves several keys (alarm not below watch, positions inside the
 * travel, ...) would refuse the value for a reason that is not its range. */
struct partner {
    const char *key;
    int upper; /* which limit: 0 the lower, 1 the upper */
    const char *other, *value;
};

static const struct partner partners[] = {
    {"analysis.alarm_mm", 0, "analysis.watch_mm", "1e-9"},
    {"analysis.watch_mm", 1, "analysis.alarm_mm", "1000"},
    {"radial.alarm_mm", 0, "radial.watch_mm", "1e-9"},
    {"radial.watch_mm", 1, "radial.alarm_mm", "1000"},
    {"carriage.home_rate_hz", 1, "carriage.max_rate_hz", "100000"},
    {"carriage.max_rate_hz", 0, "carriage.home_rate_hz", "1e-9"},
    {"carriage.park_mm", 1, "carriage.travel_mm", "100000"},
    {"carriage.home_backoff_mm", 1, "carriage.travel_mm", "100000"},
    {"carriage.backlash_mm", 1, "scan.first_position_mm", "80"},
    {"carriage.backlash_mm", 1, "carriage.travel_mm", "100000"},
    {"carriage.home_offset_mm", 0, "carriage.travel_mm", "100000"},
    {"carriage.home_offset_mm", 0, "scan.first_position_mm", "-1000"},
    {"scan.positions", 1, "scan.step_mm", "1"},
    {"scan.positions", 1, "carriage.travel_mm", "100000"},
    {"scan.step_mm", 1, "scan.positions", "2"},
    {"scan.step_mm", 1, "carriage.travel_mm", "100000"},
    {"scan.first_position_mm", 1, "carriage.travel_mm", "100000"},
    {"scan.first_position_mm", 1, "carriage.home_offset_mm", "99000"},
    {"digitiser.t0_ps", 1, "direct_coupling.window_end_ns", "1000"},
    {"direct_coupling.window_end_ns", 0, "digitiser.t0_ps", "-1000000"},
};

/* Limits that other keys' ranges and checks make unreachable, each with the
 * reason, rather than silently skipped. */
static const struct partner unreachable_limits[] = {
    /* window_end_ns must lie after the first sample; t0_ps >= -1e6 ps = -1000 ns. */
    {"direct_coupling.window_end_ns", 0, NULL, NULL},
    /* Two positions at least 1 mm apart, above the backlash overshoot and a microstep. */
    {"carriage.travel_mm", 0, NULL, NULL},
    /* Position 0 (scan.first_position_mm <= 100000 mm) must lie a backlash above home. */
    {"carriage.home_offset_mm", 1, NULL, NULL},
    /* ...and home (carriage.home_offset_mm >= -100000 mm) a backlash below position 0. */
    {"scan.first_position_mm", 0, NULL, NULL},
};

static int unreachable(const char *key, int upper)
{
    for (size_t i = 0; i < sizeof unreachable_limits / sizeof unreachable_limits[0]; i++)
        if (strcmp(unreachable_limits[i].key, key) == 0 && unreachable_limits[i].upper == upper)
            return 1;
    return 0;
}

/* The emulated sample through the loader with --set overrides. */
static int load_with(const struct uwbd_override *o, size_t n)
{
    return uwbd_config_parse(sample_text, strlen(sample_text), "test.json", o, n, &cfg, err, sizeof err);
}

/* A pair tries the limit in one element, the other at the far end of the range. */
static void json_value(const struct config_key *k, int upper, double v, char *buf, size_t n)
{
    if (k->type == KEY_PAIR)
        snprintf(buf, n, "[%.17g, %.17g]", upper ? k->min : v, upper ? v : k->max);
    else
        snprintf(buf, n, "%.17g", v);
}

/* A value on the limit (or, for an excluded bound, next to it) and one past it. */
static void limit_values(const struct config_key *k, int upper, double *inside, double *outside)
{
    double bound = upper ? k->max : k->min;
    double nudge = k->type == KEY_INT ? 1 : fmax(fabs(bound), 1.0) * 1e-9;
    if (upper) {
        *inside = bound;
        *outside = bound + nudge;
    } else if (k->min_exclusive) {
        *inside = bound + nudge;
        *outside = bound;
    } else {
        *inside = bound;
        *outside = bound - nudge;
    }
}

/* The stored (SI) value of a rig key, as the rig's check reads it. */
static void set_in_rig(struct uwb_rig_config *rig, const struct config_key *k, int upper, double written)
{
    size_t at, flag_at;
    TEST_ASSERT_TRUE(uwbd_config_key_in_rig(k, &at, &flag_at));
    char *p = (char *)rig + at;
    if (k->type == KEY_INT)
        *(int *)p = (int)written;
    else if (k->type == KEY_PAIR)
        ((double *)p)[upper] = written * k->scale;
    else
        *(double *)p = written * k->scale;
}

static void assert_named_refusal(const char *where, const struct config_key *k, const char *message)
{
    char want[160];
    snprintf(want, sizeof want, "key `%s`: ", k->path);
    if (!strstr(message, want) || !strstr(message, "out of range")) {
        char msg[1400];
        snprintf(msg, sizeof msg, "%s: want a refusal naming %s, got \"%s\"", where, k->path, message);
        TEST_FAIL_MESSAGE(msg);
    }
}

static void check_limit(const struct config_key *k, int upper)
{
    double inside, outside;
    limit_values(k, upper, &inside, &outside);
    char in_text[96], out_text[96], label[200];
    json_value(k, upper, inside, in_text, sizeof in_text);
    json_value(k, upper, outside, out_text, sizeof out_text);
    struct uwbd_override set[4] = {{k->path, in_text}};
    size_t n = 1;
    for (size_t i = 0; i < sizeof partners / sizeof partners[0]; i++)
        if (strcmp(partners[i].key, k->path) == 0 && partners[i].upper == upper) {
            TEST_ASSERT_LESS_THAN(4, n);
            set[n++] = (struct uwbd_override){partners[i].other, partners[i].value};
        }

    /* On the limit: the loader (which also asks the rig) takes it... */
    int rc = load_with(set, n);
    char msg[1400];
    snprintf(msg, sizeof msg, "%s = %s: %s", k->path, in_text, rc ? err : "");
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, rc, msg);
    /* ...and so does the rig on its own, as uwb_rig_open would. */
    size_t at, flag_at;
    if (uwbd_config_key_in_rig(k, &at, &flag_at))
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg.rig, err, sizeof err), err);

    /* Past it: refused by both, naming the key. */
    set[0].value = out_text;
    snprintf(label, sizeof label, "--set %s=%s", k->path, out_text);
    TEST_ASSERT_EQUAL_INT_MESSAGE(-1, load_with(set, n), label);
    assert_named_refusal("loader", k, err);
    if (uwbd_config_key_in_rig(k, &at, &flag_at)) {
        set[0].value = in_text;
        TEST_ASSERT_EQUAL_INT(0, load_with(set, n));
        set_in_rig(&cfg.rig, k, upper, outside);
        snprintf(label, sizeof label, "rig check, %s = %s", k->path, out_text);
        TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_ERR_CONFIG, uwb_rig_config_check(&cfg.rig, err, sizeof err),
                                      label);
        assert_named_refusal("rig", k, err);
    }
}

/* Issue 18, item 5: the table and config.md allow 1e6 steps/mm, the rig
 * refused anything over 1e5, so a value between passed the key's check and
 * failed the rig's. */
static void test_steps_per_mm_up_to_the_documented_limit_is_accepted(void)
{
    struct uwbd_override set[] = {{"carriage.steps_per_mm", "200000"}};
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, load_with(set, 1), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(UWB_RIG_OK, uwb_rig_config_check(&cfg.rig, err, sizeof err), err);
    set[0].value = "1000001";
    TEST_ASSERT_EQUAL_INT(-1, load_with(set, 1));
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "key `carriage.steps_per_mm`: "), err);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(err, "is out of range [1, 1000000] steps/mm"), err);
}

static void test_every_limit_holds_in_the_loader_and_the_rig(void)
{
    int limits = 0;
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        if (k->type != KEY_NUMBER && k->type != KEY_INT && k->type != KEY_PAIR)
            continue;
        for (int upper = 0; upper < 2; upper++) {
            if (unreachable(k->path, upper))
                continue;
            check_limit(k, upper);
            limits++;
        }
    }
    /* Not an empty walk: 40-odd numeric keys, two limits each. */
    TEST_ASSERT_GREATER_THAN_INT(70, limits);
}

/* The rig's own defaults (for programs that drive it without the daemon)
 * are the table's. */
static void test_rig_defaults_are_the_table_defaults(void)
{
    struct uwb_rig_config rig;
    uwb_rig_config_defaults(&rig);
    int compared = 0;
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        size_t at, flag_at;
        if (k->required || !uwbd_config_key_in_rig(k, &at, &flag_at))
            continue;
        const char *p = (const char *)&rig + at;
        if (k->type == KEY_NUMBER)
            TEST_ASSERT_EQUAL_DOUBLE_MESSAGE(k->default_number * k->scale, *(const double *)p, k->path);
        else if (k->type == KEY_INT || k->type == KEY_BOOL)
            TEST_ASSERT_EQUAL_INT_MESSAGE((int)k->default_number, *(const int *)p, k->path);
        else
            continue;
        compared++;
    }
    TEST_ASSERT_GREATER_THAN_INT(15, compared);
}

/* Every value in the shipped samples is a key of the table, inside its range. */
static void walk_sample(const char *file, const cJSON *obj, const char *prefix, int *values)
{
    for (const cJSON *item = obj->child; item; item = item->next) {
        char path[160];
        snprintf(path, sizeof path, "%s%s%s", prefix, prefix[0] ? "." : "", item->string);
        if (cJSON_IsObject(item)) {
            walk_sample(file, item, path, values);
            continue;
        }
        const struct config_key *k = uwbd_config_key_find(path);
        char msg[400];
        snprintf(msg, sizeof msg, "%s: %s", file, path);
        TEST_ASSERT_NOT_NULL_MESSAGE(k, msg);
        char problem[200] = "";
        if ((k->type == KEY_NUMBER || k->type == KEY_INT) && cJSON_IsNumber(item))
            TEST_ASSERT_EQUAL_INT_MESSAGE(
                0, uwbd_config_key_check_range(k, item->valuedouble, problem, sizeof problem), msg);
        if (k->type == KEY_PAIR && cJSON_IsArray(item))
            for (const cJSON *e = item->child; e; e = e->next)
                TEST_ASSERT_EQUAL_INT_MESSAGE(
                    0, uwbd_config_key_check_range(k, e->valuedouble, problem, sizeof problem), msg);
        ++*values;
    }
}

static void test_samples_use_table_keys_within_their_ranges(void)
{
    for (size_t s = 0; s < sizeof samples / sizeof samples[0]; s++) {
        char *text = scratch_slurp(samples[s], NULL);
        TEST_ASSERT_NOT_NULL_MESSAGE(text, samples[s]);
        cJSON *root = cJSON_Parse(text);
        TEST_ASSERT_NOT_NULL_MESSAGE(root, samples[s]);
        int values = 0;
        walk_sample(samples[s], root, "", &values);
        TEST_ASSERT_GREATER_THAN_INT_MESSAGE(30, values, samples[s]);
        TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwbd_config_load(samples[s], NULL, 0, &cfg, err, sizeof err), err);
        cJSON_Delete(root);
        free(text);
    }
}

/* roff as config_keys_man.c writes it: '-' becomes "\-". */
static void roff_text(const char *in, char *out, size_t n)
{
    size_t j = 0;
    for (size_t i = 0; in[i] && j + 3 < n; i++) {
        if (in[i] == '-')
            out[j++] = '\\';
        out[j++] = in[i];
    }
    out[j] = '\0';
}

/* board/config.md and uwbd.json(5) give each key's range as the table has it. */
static void test_docs_give_each_range_as_the_table(void)
{
    char *doc = scratch_slurp("board/config.md", NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(doc, "board/config.md");
    char *man = NULL;
    size_t man_len = 0;
    FILE *out = open_memstream(&man, &man_len);
    TEST_ASSERT_NOT_NULL(out);
    TEST_ASSERT_EQUAL_INT(0, uwbd_config_print_keys_man(out));
    fclose(out);
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        if (k->type != KEY_NUMBER && k->type != KEY_INT && k->type != KEY_PAIR)
            continue;
        char range[96], row[200], roff_range[200], entry[400];
        uwbd_config_key_describe_range(k, range, sizeof range);
        *strrchr(range, ']') = '\0';
        snprintf(row, sizeof row, "| `%s` | ", k->path);
        const char *at = strstr(doc, row);
        TEST_ASSERT_NOT_NULL_MESSAGE(at, row);
        const char *end = strchr(at, '\n');
        TEST_ASSERT_NOT_NULL(end);
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)(end - at), at);
        char cell[120];
        snprintf(cell, sizeof cell, " | %s] | ", range);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(line, cell), line);
        roff_text(k->path, entry, sizeof entry);
        char *in_man = strstr(man, entry);
        TEST_ASSERT_NOT_NULL_MESSAGE(in_man, k->path);
        roff_text(range, roff_range, sizeof roff_range);
        char *next_entry = strstr(in_man, ".TP");
        char *found = strstr(in_man, roff_range);
        TEST_ASSERT_TRUE_MESSAGE(found && (!next_entry || found < next_entry), k->path);
    }
    free(man);
    free(doc);
}

/* The rig's rows and the table's for the same keys are built from one spec
 * each, but each names the member and the type itself: the two must land on
 * the same field as the same type, and every numeric rig key of the table
 * must have its rig row (else the rig would not check it). */
static void test_rig_rows_are_the_tables(void)
{
    static const enum config_key_type as_table[] = {
        [UWB_RIG_KEY_NUMBER] = KEY_NUMBER,
        [UWB_RIG_KEY_INT] = KEY_INT,
        [UWB_RIG_KEY_BOOL] = KEY_BOOL,
        [UWB_RIG_KEY_PAIR] = KEY_PAIR,
    };
    for (size_t i = 0; i < uwb_rig_key_total; i++) {
        const struct uwb_rig_key *r = &uwb_rig_keys[i];
        const struct config_key *k = uwbd_config_key_find(r->path);
        TEST_ASSERT_NOT_NULL_MESSAGE(k, r->path);
        size_t at, flag_at;
        TEST_ASSERT_TRUE_MESSAGE(uwbd_config_key_in_rig(k, &at, &flag_at), r->path);
        TEST_ASSERT_EQUAL_UINT64_MESSAGE(r->offset, at, r->path);
        TEST_ASSERT_EQUAL_UINT64_MESSAGE(r->flag_offset, flag_at, r->path);
        TEST_ASSERT_EQUAL_INT_MESSAGE(as_table[r->type], k->type, r->path);
    }
    size_t numeric = 0;
    for (size_t i = 0; i < uwbd_config_key_total; i++) {
        const struct config_key *k = &uwbd_config_keys[i];
        size_t at, flag_at;
        if (!uwbd_config_key_in_rig(k, &at, &flag_at) ||
            (k->type != KEY_NUMBER && k->type != KEY_INT && k->type != KEY_BOOL && k->type != KEY_PAIR))
            continue;
        size_t j = 0;
        while (j < uwb_rig_key_total && strcmp(uwb_rig_keys[j].path, k->path) != 0)
            j++;
        TEST_ASSERT_LESS_THAN_UINT64_MESSAGE(uwb_rig_key_total, j, k->path);
        numeric++;
    }
    TEST_ASSERT_EQUAL_UINT64(uwb_rig_key_total, numeric);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_steps_per_mm_up_to_the_documented_limit_is_accepted);
    RUN_TEST(test_every_limit_holds_in_the_loader_and_the_rig);
    RUN_TEST(test_rig_defaults_are_the_table_defaults);
    RUN_TEST(test_rig_rows_are_the_tables);
    RUN_TEST(test_samples_use_table_keys_within_their_ranges);
    RUN_TEST(test_docs_give_each_range_as_the_table);
    return UNITY_END();
}
