/* The verdict and the daemon's state as Modbus registers (the map is in
 * modbus_registers.h). Read from the published record the verdict's JSON
 * is written from, so the registers can never say something `uwbd ctl
 * verdict` does not. */
#include "integrations/modbus_registers.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "uwb/utc_time.h"

/* 1 edges .. 6 error, 0 no verdict: the status enum's order, one up. */
static uint16_t status_code(const struct uwb_verdict_record *verdict)
{
    return verdict ? (uint16_t)(verdict->status - UWB_STATUS_EDGES + 1) : 0;
}

/* The radial status coded as register 1's; 0 when the verdict has none. */
static uint16_t radial_status_code(const struct uwb_verdict_record *v)
{
    return v->has_radial ? (uint16_t)(v->radial_status - UWB_STATUS_EDGES + 1) : 0;
}

/* mm -> 0.01 mm, clipped so that it never reads as the "none" value. */
static uint16_t mm16(int present, double mm)
{
    if (!present || !isfinite(mm))
        return UWBD_MODBUS_NONE16;
    double hundredths = round(mm * 100.0);
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

static void mm32(uint16_t *regs, int present, double mm)
{
    if (!present || !isfinite(mm)) {
        put32(regs, UWBD_MODBUS_NONE32);
        return;
    }
    double hundredths = round(mm * 100.0);
    if (hundredths > 2147483647.0)
        hundredths = 2147483647.0;
    if (hundredths < -2147483647.0)
        hundredths = -2147483647.0;
    put32(regs, (uint32_t)(int32_t)hundredths);
}

/* "YYYY-MM-DDTHH:MM:SSZ" as Unix seconds; 0 when absent or malformed. */
static uint32_t created_seconds(const struct uwb_verdict_record *verdict)
{
    time_t t;
    if (uwb_utc_parse(verdict->created, &t) != 0)
        return 0;
    return t < 0 || t > (time_t)UINT32_MAX ? 0 : (uint32_t)t;
}

void uwbd_modbus_registers_fill(const struct uwb_verdict_record *verdict,
                                const struct uwbd_modbus_status *status,
                                uint16_t regs[UWBD_MODBUS_REGISTER_COUNT])
{
    static const struct uwb_verdict_record none;
    const struct uwb_verdict_record *v = verdict ? verdict : &none;
    uint16_t code = status_code(verdict);
    regs[UWBD_MODBUS_REG_MAP_VERSION] = UWBD_MODBUS_MAP_VERSION;
    regs[UWBD_MODBUS_REG_STATUS] = code;
    regs[UWBD_MODBUS_REG_DISPLACEMENT] = mm16(v->has_displacement, v->axial_displacement_mm);
    regs[UWBD_MODBUS_REG_SIGMA] = mm16(v->has_displacement, v->uncertainty_mm);
    regs[UWBD_MODBUS_REG_HEIGHT_CHANGE] = mm16(v->has_height_change, v->height_change_mm);
    mm32(&regs[UWBD_MODBUS_REG_LOWER_EDGE], v->has_edges, v->lower_edge_mm);
    mm32(&regs[UWBD_MODBUS_REG_UPPER_EDGE], v->has_edges, v->upper_edge_mm);
    put32(&regs[UWBD_MODBUS_REG_SCAN_COUNT], (uint32_t)status->scan_count);
    put32(&regs[UWBD_MODBUS_REG_SCAN_TIME], code ? created_seconds(v) : 0);
    int radial = v->has_radial && v->radial_measured;
    regs[UWBD_MODBUS_REG_RADIAL_STATUS] = radial_status_code(v);
    regs[UWBD_MODBUS_REG_RADIAL_CHANGE] = mm16(radial, v->radial_max_change_mm);
    regs[UWBD_MODBUS_REG_RADIAL_SIGMA] = mm16(radial, v->radial_uncertainty_mm);
    mm32(&regs[UWBD_MODBUS_REG_RADIAL_AT], radial, v->radial_at_mm);
    regs[UWBD_MODBUS_REG_RADIAL_TILT] = mm16(radial && v->radial_has_tilt, v->radial_tilt_mm);
    regs[UWBD_MODBUS_REG_RADIAL_TILT_SIGMA] =
        mm16(radial && v->radial_has_tilt && v->radial_has_tilt_uncertainty, v->radial_tilt_uncertainty_mm);
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
}
