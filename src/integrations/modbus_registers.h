/* The Modbus register map (README "Modbus", uwbd.json(5)): the latest
 * verdict and the appliance's health as 16-bit registers, without any I/O,
 * so the map is tested apart from the listener (modbus_server.c).
 *
 * Input registers (function 04), mirrored read-only as holding registers
 * (function 03) for masters that only read those; addresses from 0:
 *   0      map version (UWBD_MODBUS_MAP_VERSION)
 *   1      status: 0 no verdict yet, 1 edges (no baseline), 2 ok, 3 watch,
 *          4 alarm, 5 inconclusive, 6 error
 *   2      axial displacement, int16, 0.01 mm (+ = upwards)
 *   3      its uncertainty sigma, int16, 0.01 mm
 *   4      height change, int16, 0.01 mm
 *   5-6    lower edge, int32 (high word first), 0.01 mm
 *   7-8    upper edge, int32, 0.01 mm
 *   9-10   scan counter: verdicts since the daemon started, uint32
 *   11-12  the verdict's time (its "created"), uint32 Unix seconds
 *   13     health bits (UWBD_MODBUS_HEALTH_*)
 *   14     contact states (UWBD_MODBUS_CONTACT_*)
 * Added in map version 2 (0-14 as in version 1):
 *   15     radial status: 0 not compared, else coded as register 1
 *   16     the face's largest radial change, int16, 0.01 mm (+ = toward the antenna)
 *   17     its uncertainty sigma, int16, 0.01 mm
 *   18-19  the height of that change, int32, 0.01 mm
 *   20     the face's tilt (top minus bottom, + = top nearer), int16, 0.01 mm
 * Added in map version 3 (0-20 as in version 2):
 *   21     the tilt's uncertainty sigma, int16, 0.01 mm
 * A figure the verdict does not carry reads 0x8000 (int16) or 0x80000000
 * (int32): never a plausible value. Figures beyond int16 are clipped to
 * +-327.67 mm, the status still telling an alarm.
 * Coils (function 05/15 to write, 01 to read back, always 0): 0 `ack`,
 * 1 `event`; writing 1 does the command, writing 0 does nothing. */
#ifndef UWBD_INTEGRATIONS_MODBUS_REGISTERS_H
#define UWBD_INTEGRATIONS_MODBUS_REGISTERS_H

#include <stdint.h>

#include "uwb/verdict_record.h"

#define UWBD_MODBUS_MAP_VERSION 3

enum uwbd_modbus_register {
    UWBD_MODBUS_REG_MAP_VERSION = 0,
    UWBD_MODBUS_REG_STATUS = 1,
    UWBD_MODBUS_REG_DISPLACEMENT = 2,
    UWBD_MODBUS_REG_SIGMA = 3,
    UWBD_MODBUS_REG_HEIGHT_CHANGE = 4,
    UWBD_MODBUS_REG_LOWER_EDGE = 5, /* two registers */
    UWBD_MODBUS_REG_UPPER_EDGE = 7, /* two registers */
    UWBD_MODBUS_REG_SCAN_COUNT = 9, /* two registers */
    UWBD_MODBUS_REG_SCAN_TIME = 11, /* two registers */
    UWBD_MODBUS_REG_HEALTH = 13,
    UWBD_MODBUS_REG_CONTACTS = 14,
    UWBD_MODBUS_REG_RADIAL_STATUS = 15,
    UWBD_MODBUS_REG_RADIAL_CHANGE = 16,
    UWBD_MODBUS_REG_RADIAL_SIGMA = 17,
    UWBD_MODBUS_REG_RADIAL_AT = 18, /* two registers */
    UWBD_MODBUS_REG_RADIAL_TILT = 20,
    UWBD_MODBUS_REG_RADIAL_TILT_SIGMA = 21,
    UWBD_MODBUS_REGISTER_COUNT = 22,
};

enum uwbd_modbus_coil {
    UWBD_MODBUS_COIL_ACK = 0,
    UWBD_MODBUS_COIL_EVENT = 1,
    UWBD_MODBUS_COIL_COUNT = 2,
};

#define UWBD_MODBUS_NONE16 0x8000u
#define UWBD_MODBUS_NONE32 0x80000000u

enum uwbd_modbus_health {
    UWBD_MODBUS_HEALTH_DEVICE_FAULT = 1u << 0, /* the baseline found a device fault */
    UWBD_MODBUS_HEALTH_RIG_DOWN = 1u << 1,     /* the rig is not open (it is tried again at the next scan) */
    UWBD_MODBUS_HEALTH_SCANNING = 1u << 2,
    UWBD_MODBUS_HEALTH_BASELINE = 1u << 3, /* a baseline is set */
    UWBD_MODBUS_HEALTH_VERDICT = 1u << 4,  /* registers 1-12 and 15-21 hold a verdict */
};

enum uwbd_modbus_contact {
    UWBD_MODBUS_CONTACT_WATCH = 1u << 0,
    UWBD_MODBUS_CONTACT_ALARM = 1u << 1,
    UWBD_MODBUS_CONTACT_FAULT = 1u << 2, /* the fail-safe line, energised while healthy */
};

/* What the daemon knows besides the verdict. */
struct uwbd_modbus_status {
    unsigned long scan_count;
    int scanning;
    int device_fault;
    int rig_down;
    int has_baseline;
    unsigned contacts; /* UWBD_MODBUS_CONTACT_* energised */
};

/* The registers for the latest verdict (NULL: no verdict yet). */
void uwbd_modbus_registers_fill(const struct uwb_verdict_record *verdict,
                                const struct uwbd_modbus_status *status,
                                uint16_t regs[UWBD_MODBUS_REGISTER_COUNT]);

#endif
