/* The verdict JSON and the daemon's state as Modbus registers (the map is
 * in modbus_registers.h). Read from the JSON line the daemon already keeps,
 * so the registers can never say something `uwbd ctl verdict` does not. */
#include "integrations/modbus_registers.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "uwb/utc_time.h"

static const char *const status_names[] = {"edges", "ok", "watch", "alarm", "inconclusive", "error"};

static uint16_t status_code(const cJSON *verdict)
{
    const cJSON *status = cJSON_GetObjectItemCaseSensitive(verdict, "status");
    if (!cJSON_IsString(status))
        return 0;
    for (size_t i = 0; i < sizeof status_names / sizeof status_names[0]; i++)
        if (strcmp(status->valuestring, status_names[i]) == 0)
            return (uint16_t)(i + 1);
    return 0;
}

/* mm -> 0.01 mm, clipped so that it never reads as the "none" value. */
static uint16_t mm16(const cJSON *obj, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return UWBD_MODBUS_NONE16;
    double hundredths = round(v->valuedouble * 100.0);
    if (hundredths > 32767.0)
        hundredths = 32767.0;
    if (hundredths < -32767.0)
        hundredths = -32767.0;
    return (uint16_t)(int16_t)hundredths;
}

static void put32(uint16_t *regs, uint32_t value)
{
    regs[0] = (uint16_t)(value >> 16);
    regs[1] = (uint16_t)(value & 0xffffu);
}

static void mm32(uint16_t *regs, const cJSON *obj, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) {
        put32(regs, UWBD_MODBUS_NONE32);
        return;
    }
    double hundredths = round(v->valuedouble * 100.0);
    if (hundredths > 2147483647.0)
        hundredths = 2147483647.0;
    if (hundredths < -2147483647.0)
        hundredths = -2147483647.0;
    put32(regs, (uint32_t)(int32_t)hundredths);
}

/* "YYYY-MM-DDTHH:MM:SSZ" as Unix seconds; 0 when absent or malformed. */
static uint32_t created_seconds(const cJSON *verdict)
{
    const cJSON *created = cJSON_GetObjectItemCaseSensitive(verdict, "created");
    time_t t;
    if (!cJSON_IsString(created) || uwb_utc_parse(created->valuestring, &t) != 0)
        return 0;
    return t < 0 || t > (time_t)UINT32_MAX ? 0 : (uint32_t)t;
}

void uwbd_modbus_registers_fill(const char *verdict_json, const struct uwbd_modbus_status *status,
                                uint16_t regs[UWBD_MODBUS_REGISTER_COUNT])
{
    cJSON *verdict = verdict_json ? cJSON_Parse(verdict_json) : NULL;
    uint16_t code = status_code(verdict);
    regs[UWBD_MODBUS_REG_MAP_VERSION] = UWBD_MODBUS_MAP_VERSION;
    regs[UWBD_MODBUS_REG_STATUS] = code;
    regs[UWBD_MODBUS_REG_DISPLACEMENT] = mm16(verdict, "axial_displacement_mm");
    regs[UWBD_MODBUS_REG_SIGMA] = mm16(verdict, "uncertainty_mm");
    regs[UWBD_MODBUS_REG_HEIGHT_CHANGE] = mm16(verdict, "height_change_mm");
    mm32(&regs[UWBD_MODBUS_REG_LOWER_EDGE], verdict, "lower_edge_mm");
    mm32(&regs[UWBD_MODBUS_REG_UPPER_EDGE], verdict, "upper_edge_mm");
    put32(&regs[UWBD_MODBUS_REG_SCAN_COUNT], (uint32_t)status->scan_count);
    put32(&regs[UWBD_MODBUS_REG_SCAN_TIME], code ? created_seconds(verdict) : 0);
    unsigned health = 0;
    if (status->device_fault)
        health |= UWBD_MODBUS_HEALTH_DEVICE_FAULT;
    if (status->rig_down)
        health |= UWBD_MODBUS_HEALTH_RIG_DOWN;
    if (status->scanning)
        health |= UWBD_MODBUS_HEALTH_SCANNING;
    if (status->has_baseline)
        health |= UWBD_MODBUS_HEALTH_BASELINE;
    if (code)
        health |= UWBD_MODBUS_HEALTH_VERDICT;
    regs[UWBD_MODBUS_REG_HEALTH] = (uint16_t)health;
    regs[UWBD_MODBUS_REG_CONTACTS] =
        (uint16_t)(status->contacts &
                   (UWBD_MODBUS_CONTACT_WATCH | UWBD_MODBUS_CONTACT_ALARM | UWBD_MODBUS_CONTACT_FAULT));
    cJSON_Delete(verdict);
}
