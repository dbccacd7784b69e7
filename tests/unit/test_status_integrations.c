/* Issue 31, finding 7: `status` tells the engineer at the tank how the
 * integrations stand: the asset, Modbus (listening, on what), the alarm
 * contacts energised, the baseline's age and the free space in the state
 * directory, beside the MQTT link it already gave. Additive keys only: the
 * reply's other keys stay as they were. */
#include "unity.h"

#include <cjson/cJSON.h>
#include <stdlib.h>
#include <string.h>

#include "control/reply.h"
#include "control/scan_progress.h"
#include "state/state_writes.h"
#include "integrations/site_io.h"

void setUp(void)
{
}
void tearDown(void)
{
}

static cJSON *status(const struct uwbd_status *st)
{
    char *line = uwbd_reply_status(st);
    TEST_ASSERT_NOT_NULL(line);
    cJSON *o = cJSON_Parse(line);
    TEST_ASSERT_NOT_NULL_MESSAGE(o, line);
    free(line);
    return o;
}

static const cJSON *item(const cJSON *o, const char *path)
{
    char key[64];
    const char *dot = strchr(path, '.');
    if (!dot)
        return cJSON_GetObjectItemCaseSensitive(o, path);
    snprintf(key, sizeof key, "%.*s", (int)(dot - path), path);
    return item(cJSON_GetObjectItemCaseSensitive(o, key), dot + 1);
}

static void test_the_integrations_are_shown(void)
{
    struct uwbd_contact_states contacts = {.watch = 0, .alarm = 1, .fault = 1};
    struct uwbd_status st = {
        .version = "test",
        .state = "idle",
        .state_dir = "/var/lib/uwbd",
        .rig = "ready",
        .asset_id = "GT2-L1",
        .modbus_endpoint = "tcp:0.0.0.0:502",
        .modbus_listening = 1,
        .contacts = &contacts,
        .has_baseline = 1,
        .now = 1700000000 + 3 * 86400 + 60,
        .has_state_dir_free = 1,
        .state_dir_free_bytes = 123456789,
    };
    snprintf(st.baseline.scan_id, sizeof st.baseline.scan_id, "b1");
    snprintf(st.baseline.set_at, sizeof st.baseline.set_at, "2023-11-14T22:13:20Z"); /* 1700000000 */
    cJSON *o = status(&st);
    TEST_ASSERT_EQUAL_STRING("GT2-L1", cJSON_GetStringValue(item(o, "asset_id")));
    TEST_ASSERT_TRUE(cJSON_IsTrue(item(o, "modbus.listening")));
    TEST_ASSERT_EQUAL_STRING("tcp:0.0.0.0:502", cJSON_GetStringValue(item(o, "modbus.endpoint")));
    TEST_ASSERT_TRUE(cJSON_IsFalse(item(o, "contacts.watch")));
    TEST_ASSERT_TRUE(cJSON_IsTrue(item(o, "contacts.alarm")));
    TEST_ASSERT_TRUE(cJSON_IsTrue(item(o, "contacts.fault")));
    TEST_ASSERT_EQUAL_DOUBLE(3 * 86400 + 60, cJSON_GetNumberValue(item(o, "baseline.age_s")));
    TEST_ASSERT_EQUAL_DOUBLE(123456789, cJSON_GetNumberValue(item(o, "state_dir_free_bytes")));
    /* The keys that were there stay. */
    TEST_ASSERT_EQUAL_STRING("b1", cJSON_GetStringValue(item(o, "baseline.scan_id")));
    TEST_ASSERT_EQUAL_STRING("/var/lib/uwbd", cJSON_GetStringValue(item(o, "state_dir")));
    cJSON_Delete(o);
}

static void test_what_is_off_is_left_out_or_says_so(void)
{
    struct uwbd_status st = {
        .version = "test",
        .state = "idle",
        .state_dir = "/var/lib/uwbd",
        .rig = "ready",
        .modbus_endpoint = "tcp:0.0.0.0:502",
        .modbus_listening = 0, /* enabled, but its port could not be opened */
    };
    cJSON *o = status(&st);
    TEST_ASSERT_TRUE(cJSON_IsFalse(item(o, "modbus.listening")));
    TEST_ASSERT_NULL(item(o, "asset_id"));
    TEST_ASSERT_NULL(item(o, "contacts"));
    TEST_ASSERT_NULL(item(o, "state_dir_free_bytes"));
    TEST_ASSERT_NULL(item(o, "baseline"));
    cJSON_Delete(o);
    st.modbus_endpoint = NULL; /* Modbus off */
    o = status(&st);
    TEST_ASSERT_NULL(item(o, "modbus"));
    cJSON_Delete(o);
}

/* Issue 43, break 6: a state directory that refuses the cycles' writes
 * shows in `status` (the disk full said as such) from the first cycle that
 * could not write everything until one writes everything again; a
 * healthy status has no such key. */
static void test_a_state_directory_refusing_writes_shows_until_it_takes_them(void)
{
    const time_t t0 = 1893542400; /* 2030-01-02T00:00:00Z */
    struct uwbd_state_writes w;
    memset(&w, 0, sizeof w);
    uwbd_state_writes_after_cycle(&w, "", t0);
    TEST_ASSERT_EQUAL_INT(0, w.failing);
    uwbd_state_writes_after_cycle(
        &w, "/s/archive/2030/01/02/a.uwbscan: cannot write temporary file: No space left on device", t0);
    uwbd_state_writes_after_cycle(&w, "/s/verdicts.jsonl: cannot append a verdict: No space left on device",
                                  t0 + 3600);
    TEST_ASSERT_EQUAL_INT(1, w.failing);
    TEST_ASSERT_EQUAL_INT(1, w.disk_full);
    TEST_ASSERT_EQUAL_INT(2, w.cycles);
    TEST_ASSERT_EQUAL_STRING("2030-01-02T00:00:00Z", w.since);

    struct uwbd_status st = {
        .version = "test", .state = "idle", .state_dir = "/s", .rig = "ready", .writes = &w};
    cJSON *o = status(&st);
    TEST_ASSERT_TRUE(cJSON_IsTrue(item(o, "state_dir_writes.failing")));
    TEST_ASSERT_TRUE(cJSON_IsTrue(item(o, "state_dir_writes.disk_full")));
    TEST_ASSERT_EQUAL_INT(2, (int)item(o, "state_dir_writes.cycles")->valuedouble);
    TEST_ASSERT_EQUAL_STRING("2030-01-02T00:00:00Z", item(o, "state_dir_writes.since")->valuestring);
    TEST_ASSERT_NOT_NULL(strstr(item(o, "state_dir_writes.error")->valuestring, "verdicts.jsonl"));
    cJSON_Delete(o);

    uwbd_state_writes_after_cycle(&w,
                                  "/s/archive/2030/01/02/b.uwbscan: cannot create temporary file: "
                                  "Read-only file system",
                                  t0 + 7200);
    TEST_ASSERT_EQUAL_INT(0, w.disk_full); /* refused, but not for want of room */
    TEST_ASSERT_EQUAL_INT(3, w.cycles);

    uwbd_state_writes_after_cycle(&w, "", t0 + 10800);
    TEST_ASSERT_EQUAL_INT(0, w.failing);
    TEST_ASSERT_EQUAL_INT(0, w.cycles);
    o = status(&st);
    TEST_ASSERT_NULL(item(o, "state_dir_writes"));
    cJSON_Delete(o);
}

/* Issue 47: `status` nests the running scan's progress as the PROGRESS
 * line's fields, in the same order and the same figures, without its
 * "class" (built once, not printed and parsed back). */
static void test_progress_is_the_progress_line_without_its_class(void)
{
    struct uwbd_scan_progress p;
    uwbd_scan_progress_estimate_passes(2, 3, 7, 21, 0.0, 2.0, 40.0, 41.3, &p);
    struct uwbd_status st = {.version = "x", .state = "scanning", .progress = &p};
    cJSON *o = status(&st);
    char *nested = cJSON_PrintUnformatted(cJSON_GetObjectItemCaseSensitive(o, "progress"));
    char *line = uwbd_reply_progress(&p);
    TEST_ASSERT_NOT_NULL(nested);
    TEST_ASSERT_NOT_NULL(line);
    const char *after_class = "{\"class\":\"PROGRESS\",";
    TEST_ASSERT_EQUAL_INT(0, strncmp(line, after_class, strlen(after_class)));
    TEST_ASSERT_EQUAL_STRING(line + strlen(after_class), nested + 1);
    TEST_ASSERT_NOT_NULL(strstr(nested, "\"left_s\":"));
    free(line);
    free(nested);
    cJSON_Delete(o);
    /* No scan: no progress. */
    st.progress = NULL;
    o = status(&st);
    TEST_ASSERT_NULL(cJSON_GetObjectItemCaseSensitive(o, "progress"));
    cJSON_Delete(o);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_the_integrations_are_shown);
    RUN_TEST(test_what_is_off_is_left_out_or_says_so);
    RUN_TEST(test_a_state_directory_refusing_writes_shows_until_it_takes_them);
    RUN_TEST(test_progress_is_the_progress_line_without_its_class);
    return UNITY_END();
}
