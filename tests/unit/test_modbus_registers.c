/* The Modbus register map from a verdict line and the daemon's state:
 * 0.01 mm signed figures, 32-bit values high word first, "none" markers
 * for figures a verdict does not carry, clipping that never reads as
 * "none", the health and contact bits, and the radial change appended. */
#include "scratch_support.h"
#include "unity.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "integrations/modbus_registers.h"
#include "uwb/verdict_json.h"

static uint16_t regs[UWBD_MODBUS_REGISTER_COUNT];

/* The registers for a verdict line (its class taken as VERDICT when the
 * line leaves it out), read into a record as the daemon reads latest.json. */
static void fill_from_line(const char *line, const struct uwbd_modbus_status *st, uint16_t *out)
{
    static struct uwb_verdict_record record;
    char err[256];
    cJSON *o = cJSON_Parse(line);
    if (o && !cJSON_HasObjectItem(o, "class"))
        cJSON_AddStringToObject(o, "class", "VERDICT");
    int ok = o && uwb_record_from_object(o, &record, err, sizeof err) == 0;
    cJSON_Delete(o);
    uwbd_modbus_registers_fill(ok ? &record : NULL, st, out);
}

void setUp(void)
{
    memset(regs, 0xA5, sizeof regs); /* every register must be written */
}

void tearDown(void)
{
}

static int32_t reg32(int at)
{
    return (int32_t)(((uint32_t)regs[at] << 16) | regs[at + 1]);
}

static const char *const compared =
    "{\"class\":\"VERDICT\",\"status\":\"watch\",\"created\":\"2026-11-24T05:30:00Z\","
    "\"axial_displacement_mm\":-1.23,\"uncertainty_mm\":0.45,\"lower_edge_mm\":412.35,"
    "\"upper_edge_mm\":1105.6,\"height_change_mm\":0.07,\"images\":[]}";

static void test_compared_verdict_in_hundredths_of_a_millimetre(void)
{
    struct uwbd_modbus_status st = {.scan_count = 70000, .has_baseline = 1};
    fill_from_line(compared, &st, regs);
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_MAP_VERSION, regs[UWBD_MODBUS_REG_MAP_VERSION]);
    TEST_ASSERT_EQUAL_UINT16(3, regs[UWBD_MODBUS_REG_STATUS]); /* watch */
    TEST_ASSERT_EQUAL_INT16(-123, (int16_t)regs[UWBD_MODBUS_REG_DISPLACEMENT]);
    TEST_ASSERT_EQUAL_INT16(45, (int16_t)regs[UWBD_MODBUS_REG_SIGMA]);
    TEST_ASSERT_EQUAL_INT16(7, (int16_t)regs[UWBD_MODBUS_REG_HEIGHT_CHANGE]);
    TEST_ASSERT_EQUAL_INT32(41235, reg32(UWBD_MODBUS_REG_LOWER_EDGE));
    TEST_ASSERT_EQUAL_INT32(110560, reg32(UWBD_MODBUS_REG_UPPER_EDGE));
    /* 70000 = 0x0001 0x1170: the high word first */
    TEST_ASSERT_EQUAL_UINT16(1, regs[UWBD_MODBUS_REG_SCAN_COUNT]);
    TEST_ASSERT_EQUAL_UINT16(0x1170, regs[UWBD_MODBUS_REG_SCAN_COUNT + 1]);
    TEST_ASSERT_EQUAL_INT32(1795498200, reg32(UWBD_MODBUS_REG_SCAN_TIME)); /* date -u -d ... +%s */
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_HEALTH_BASELINE | UWBD_MODBUS_HEALTH_VERDICT,
                             regs[UWBD_MODBUS_REG_HEALTH]);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_CONTACTS]);
}

static void test_no_verdict_reads_status_zero_and_none_markers(void)
{
    struct uwbd_modbus_status st = {.rig_down = 1};
    fill_from_line(NULL, &st, regs);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_DISPLACEMENT]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_SIGMA]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_HEIGHT_CHANGE]);
    TEST_ASSERT_EQUAL_HEX32(UWBD_MODBUS_NONE32, (uint32_t)reg32(UWBD_MODBUS_REG_LOWER_EDGE));
    TEST_ASSERT_EQUAL_HEX32(UWBD_MODBUS_NONE32, (uint32_t)reg32(UWBD_MODBUS_REG_UPPER_EDGE));
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_COUNT));
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_TIME));
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_HEALTH_RIG_DOWN, regs[UWBD_MODBUS_REG_HEALTH]);

    fill_from_line("not json", &st, regs);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_STATUS]);
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_HEALTH_RIG_DOWN, regs[UWBD_MODBUS_REG_HEALTH]);
}

static void test_edges_only_verdict_has_edges_but_no_displacement(void)
{
    struct uwbd_modbus_status st = {.scan_count = 1, .scanning = 1};
    fill_from_line("{\"status\":\"edges\",\"created\":\"2026-11-24T05:30:00Z\",\"lower_edge_mm\":-0.5,"
                   "\"upper_edge_mm\":700}",
                   &st, regs);
    TEST_ASSERT_EQUAL_UINT16(1, regs[UWBD_MODBUS_REG_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_DISPLACEMENT]);
    TEST_ASSERT_EQUAL_INT32(-50, reg32(UWBD_MODBUS_REG_LOWER_EDGE));
    TEST_ASSERT_EQUAL_INT32(70000, reg32(UWBD_MODBUS_REG_UPPER_EDGE));
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_HEALTH_SCANNING | UWBD_MODBUS_HEALTH_VERDICT,
                             regs[UWBD_MODBUS_REG_HEALTH]);
}

static void test_every_status_has_its_code(void)
{
    const char *names[] = {"edges", "ok", "watch", "alarm", "inconclusive", "error"};
    struct uwbd_modbus_status st = {0};
    char line[128];
    for (int i = 0; i < 6; i++) {
        snprintf(line, sizeof line, "{\"status\":\"%s\"}", names[i]);
        fill_from_line(line, &st, regs);
        TEST_ASSERT_EQUAL_UINT16_MESSAGE(i + 1, regs[UWBD_MODBUS_REG_STATUS], names[i]);
    }
    fill_from_line("{\"status\":\"bogus\"}", &st, regs);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_STATUS]);
}

static void test_large_figures_clip_and_never_read_as_none(void)
{
    struct uwbd_modbus_status st = {0};
    fill_from_line("{\"status\":\"alarm\",\"axial_displacement_mm\":-400,\"uncertainty_mm\":400,"
                   "\"height_change_mm\":-327.68}",
                   &st, regs);
    TEST_ASSERT_EQUAL_INT16(-32767, (int16_t)regs[UWBD_MODBUS_REG_DISPLACEMENT]);
    TEST_ASSERT_EQUAL_INT16(32767, (int16_t)regs[UWBD_MODBUS_REG_SIGMA]);
    TEST_ASSERT_EQUAL_INT16(-32767, (int16_t)regs[UWBD_MODBUS_REG_HEIGHT_CHANGE]);
}

/* The radial change (registers 15-20, after the version 1 map): its status
 * coded as register 1's, the change + toward the antenna, its sigma and
 * tilt in int16 0.01 mm, its height in int32 like the edges. */
static void test_radial_change_in_the_registers_after_the_first_map(void)
{
    struct uwbd_modbus_status st = {.scan_count = 3, .has_baseline = 1};
    /* A radial alarm with the axial figure withheld, as the emulated board's bulge gives. */
    fill_from_line("{\"status\":\"alarm\",\"created\":\"2026-11-24T05:30:00Z\",\"lower_edge_mm\":230.1,"
                   "\"upper_edge_mm\":382.2,\"radial\":{\"status\":\"alarm\",\"max_change_mm\":-5.75,"
                   "\"at_mm\":359.59,\"from_mm\":332.59,\"to_mm\":384.59,\"uncertainty_mm\":0.46,"
                   "\"tilt_mm\":2,\"tilt_uncertainty_mm\":0.31}}",
                   &st, regs);
    TEST_ASSERT_EQUAL_UINT16(4, regs[UWBD_MODBUS_REG_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_DISPLACEMENT]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_SIGMA]);
    TEST_ASSERT_EQUAL_INT32(23010, reg32(UWBD_MODBUS_REG_LOWER_EDGE));
    TEST_ASSERT_EQUAL_UINT16(4, regs[UWBD_MODBUS_REG_RADIAL_STATUS]);
    TEST_ASSERT_EQUAL_INT16(-575, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    TEST_ASSERT_EQUAL_INT16(46, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_SIGMA]);
    TEST_ASSERT_EQUAL_INT32(35959, reg32(UWBD_MODBUS_REG_RADIAL_AT));
    TEST_ASSERT_EQUAL_INT16(200, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_TILT]);
    TEST_ASSERT_EQUAL_INT16(31, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA]);

    /* Withheld: the status told, every figure "none". */
    fill_from_line("{\"status\":\"inconclusive\",\"radial\":{\"status\":\"inconclusive\","
                   "\"withheld\":\"the face's range was not compared\"}}",
                   &st, regs);
    TEST_ASSERT_EQUAL_UINT16(5, regs[UWBD_MODBUS_REG_RADIAL_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_SIGMA]);
    TEST_ASSERT_EQUAL_HEX32(UWBD_MODBUS_NONE32, (uint32_t)reg32(UWBD_MODBUS_REG_RADIAL_AT));
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT]);

    /* Measured, the tilt withheld (a change at the face's end): its register "none", not 0. */
    fill_from_line(
        "{\"status\":\"alarm\",\"radial\":{\"status\":\"alarm\",\"max_change_mm\":8.45,"
        "\"at_mm\":341,\"uncertainty_mm\":1.57,\"tilt_withheld\":\"the change reaches the face's end\"}}",
        &st, regs);
    TEST_ASSERT_EQUAL_INT16(845, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA]);

    /* A record from before the tilt's sigma: the tilt, its sigma "none". */
    fill_from_line("{\"status\":\"ok\",\"radial\":{\"status\":\"ok\",\"max_change_mm\":0.4,"
                   "\"at_mm\":300,\"uncertainty_mm\":0.5,\"tilt_mm\":-1.5}}",
                   &st, regs);
    TEST_ASSERT_EQUAL_INT16(-150, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_TILT]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA]);

    /* Not compared (no radial object), and no verdict at all: status 0, "none". */
    fill_from_line(compared, &st, regs);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_RADIAL_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    TEST_ASSERT_EQUAL_HEX32(UWBD_MODBUS_NONE32, (uint32_t)reg32(UWBD_MODBUS_REG_RADIAL_AT));
    fill_from_line(NULL, &st, regs);
    TEST_ASSERT_EQUAL_UINT16(0, regs[UWBD_MODBUS_REG_RADIAL_STATUS]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_SIGMA]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT]);
    TEST_ASSERT_EQUAL_HEX16(UWBD_MODBUS_NONE16, regs[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA]);

    /* Beyond int16: clipped, never "none". */
    fill_from_line("{\"status\":\"alarm\",\"radial\":{\"status\":\"alarm\",\"max_change_mm\":-400,"
                   "\"at_mm\":1,\"uncertainty_mm\":0.5,\"tilt_mm\":400}}",
                   &st, regs);
    TEST_ASSERT_EQUAL_INT16(-32767, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_CHANGE]);
    TEST_ASSERT_EQUAL_INT16(32767, (int16_t)regs[UWBD_MODBUS_REG_RADIAL_TILT]);
}

static void test_time_without_zone_or_malformed_is_zero(void)
{
    struct uwbd_modbus_status st = {0};
    fill_from_line("{\"status\":\"ok\",\"created\":\"2026-11-24T05:30:00\"}", &st, regs);
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_TIME));
    fill_from_line("{\"status\":\"ok\",\"created\":\"yesterday\"}", &st, regs);
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_TIME));
    /* A field out of range, and a time past what 32 bits of seconds hold. */
    fill_from_line("{\"status\":\"ok\",\"created\":\"2026-13-24T05:30:00Z\"}", &st, regs);
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_TIME));
    fill_from_line("{\"status\":\"ok\",\"created\":\"2200-01-01T00:00:00Z\"}", &st, regs);
    TEST_ASSERT_EQUAL_INT32(0, reg32(UWBD_MODBUS_REG_SCAN_TIME));
    fill_from_line("{\"status\":\"ok\",\"created\":\"2106-02-07T06:28:15Z\"}", &st, regs);
    TEST_ASSERT_EQUAL_UINT32(4294967295u, (uint32_t)reg32(UWBD_MODBUS_REG_SCAN_TIME));
}

static void test_fault_and_contact_bits(void)
{
    struct uwbd_modbus_status st = {.device_fault = 1,
                                    .contacts = UWBD_MODBUS_CONTACT_ALARM | UWBD_MODBUS_CONTACT_FAULT | 0x80};
    fill_from_line(compared, &st, regs);
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_HEALTH_DEVICE_FAULT | UWBD_MODBUS_HEALTH_VERDICT,
                             regs[UWBD_MODBUS_REG_HEALTH]);
    /* bits outside the map are not passed on */
    TEST_ASSERT_EQUAL_UINT16(UWBD_MODBUS_CONTACT_ALARM | UWBD_MODBUS_CONTACT_FAULT,
                             regs[UWBD_MODBUS_REG_CONTACTS]);
}

/* The manual page's register map (uwbd-modbus(7), which the README points to)
 * gives every address as the enum has it. */
static void test_manual_page_documents_the_map(void)
{
    char *page = scratch_slurp("board/man/uwbd-modbus.7.scd", NULL);
    TEST_ASSERT_NOT_NULL_MESSAGE(page, "board/man/uwbd-modbus.7.scd");
    const struct {
        int at, width;
        const char *what;
    } rows[] = {
        {UWBD_MODBUS_REG_MAP_VERSION, 1, "map version"},
        {UWBD_MODBUS_REG_STATUS, 1, "status"},
        {UWBD_MODBUS_REG_DISPLACEMENT, 1, "axial displacement"},
        {UWBD_MODBUS_REG_SIGMA, 1, "its uncertainty"},
        {UWBD_MODBUS_REG_HEIGHT_CHANGE, 1, "height change"},
        {UWBD_MODBUS_REG_LOWER_EDGE, 2, "lower edge"},
        {UWBD_MODBUS_REG_UPPER_EDGE, 2, "upper edge"},
        {UWBD_MODBUS_REG_SCAN_COUNT, 2, "scan counter"},
        {UWBD_MODBUS_REG_SCAN_TIME, 2, "the verdict's time"},
        {UWBD_MODBUS_REG_HEALTH, 1, "health bits"},
        {UWBD_MODBUS_REG_CONTACTS, 1, "contact states"},
        {UWBD_MODBUS_REG_RADIAL_STATUS, 1, "radial status"},
        {UWBD_MODBUS_REG_RADIAL_CHANGE, 1, "radial change"},
        {UWBD_MODBUS_REG_RADIAL_SIGMA, 1, "its uncertainty"},
        {UWBD_MODBUS_REG_RADIAL_AT, 2, "height of the radial change"},
        {UWBD_MODBUS_REG_RADIAL_TILT, 1, "face tilt"},
        {UWBD_MODBUS_REG_RADIAL_TILT_SIGMA, 1, "its uncertainty"},
    };
    char row[128];
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        if (rows[i].width == 1)
            snprintf(row, sizeof row, "\n*%d*: %s", rows[i].at, rows[i].what);
        else
            snprintf(row, sizeof row, "\n*%d\u2013%d*: %s", rows[i].at, rows[i].at + 1, rows[i].what);
        TEST_ASSERT_NOT_NULL_MESSAGE(strstr(page, row), row);
    }
    snprintf(row, sizeof row, "\n*0*: map version\n\t%d\n", UWBD_MODBUS_MAP_VERSION);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(page, row), row);
    snprintf(row, sizeof row, "coil %d *ack*, coil %d *event*", UWBD_MODBUS_COIL_ACK, UWBD_MODBUS_COIL_EVENT);
    TEST_ASSERT_NOT_NULL_MESSAGE(strstr(page, row), row);
    free(page);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_compared_verdict_in_hundredths_of_a_millimetre);
    RUN_TEST(test_no_verdict_reads_status_zero_and_none_markers);
    RUN_TEST(test_edges_only_verdict_has_edges_but_no_displacement);
    RUN_TEST(test_every_status_has_its_code);
    RUN_TEST(test_large_figures_clip_and_never_read_as_none);
    RUN_TEST(test_radial_change_in_the_registers_after_the_first_map);
    RUN_TEST(test_time_without_zone_or_malformed_is_zero);
    RUN_TEST(test_fault_and_contact_bits);
    RUN_TEST(test_manual_page_documents_the_map);
    return UNITY_END();
}
