/* The rig's configuration keys that have a range or a default, each written
 * once here as a spec: its name, unit, scale (stored = written x scale),
 * range and default, as designated initializers. The rig sets its defaults
 * and checks its ranges from its own rows built of these (rig_keys.c); the
 * key table (src/config/config_keys.c) builds its rows for the same keys
 * from them, adding where each lands in struct uwbd_config and what it
 * means. So the limits live with the rig and the table only points at them. */
#ifndef UWB_RIG_RIG_KEYS_H
#define UWB_RIG_RIG_KEYS_H

#include <stddef.h>

#include "uwb/frame.h"
#include "uwb/rig.h"
#include "uwb/scan.h"

enum uwb_rig_key_type {
    UWB_RIG_KEY_NUMBER, /* double, stored = written * scale */
    UWB_RIG_KEY_INT,    /* int */
    UWB_RIG_KEY_BOOL,   /* int 0/1 */
    UWB_RIG_KEY_PAIR,   /* double[2], stored = written * scale; optional ones set a flag */
};

/* The spec's fields bear the names of struct config_key's. */
struct uwb_rig_key {
    const char *path; /* dotted, e.g. "digitiser.samples" */
    enum uwb_rig_key_type type;
    size_t offset;             /* into struct uwb_rig_config */
    size_t flag_offset;        /* an optional pair's "given" flag; 0 = none */
    double scale;              /* written unit -> stored unit */
    double min, max;           /* allowed range in written units */
    int min_exclusive;         /* value must be > min rather than >= */
    const char *below_min_why; /* said after "out of range" when a value is under min; NULL: nothing */
    int required;              /* no default: the configuration must give it */
    double default_number;     /* when not required */
    const char *unit;          /* written unit, "" for none */
};

/* In the order `uwbd --config-keys` lists them, the first broken one being
 * the one a check names. */
extern const struct uwb_rig_key uwb_rig_keys[];
extern const size_t uwb_rig_key_total;

// NOLINTBEGIN(bugprone-macro-parentheses)
#define UWB_RIG_FLAG(p, def) .path = p, .scale = 1, .max = 1, .default_number = def, .unit = ""

#define UWB_RIG_HOME_ACTIVE_LOW UWB_RIG_FLAG("gpio.home_active_low", 1)
#define UWB_RIG_HOME_PULL_UP UWB_RIG_FLAG("gpio.home_pull_up", 1)
#define UWB_RIG_ENABLE_ACTIVE_LOW UWB_RIG_FLAG("gpio.enable_active_low", 1)

#define UWB_RIG_SAMPLES \
    .path = "digitiser.samples", .scale = 1, .min = 16, .max = UWB_FRAME_MAX_SAMPLES, .required = 1, \
    .unit = ""
#define UWB_RIG_SAMPLE_INTERVAL_PS \
    .path = "digitiser.sample_interval_ps", .scale = 1e-12, .min = 0, .max = 1e6, .min_exclusive = 1, \
    .required = 1, .unit = "ps"
#define UWB_RIG_T0_PS \
    .path = "digitiser.t0_ps", .scale = 1e-12, .min = -1e6, .max = 1e6, .default_number = 0, .unit = "ps"
#define UWB_RIG_STACK \
    .path = "digitiser.stack", .scale = 1, .min = 1, .max = 65536, .default_number = UWB_DEFAULT_STACK, \
    .unit = ""
#define UWB_RIG_FRAME_TIMEOUT_MS \
    .path = "digitiser.frame_timeout_ms", .scale = 1, .min = 1, .max = 600000, .default_number = 1000, \
    .unit = "ms"
#define UWB_RIG_FRAME_RETRIES \
    .path = "digitiser.frame_retries", .scale = 1, .min = 0, .max = 100, .default_number = 3, .unit = ""

#define UWB_RIG_STEPS_PER_MM \
    .path = "carriage.steps_per_mm", .scale = 1, .min = 1, .max = 1e6, .required = 1, .unit = "steps/mm"
/* At most 1e5 Hz: the STEP pulse (UWB_STEP_PULSE_S, 5 us) and the gap after it fit one period. */
#define UWB_RIG_MAX_RATE_HZ \
    .path = "carriage.max_rate_hz", .scale = 1, .min = 0, .max = 1e5, .min_exclusive = 1, \
    .default_number = 4000, .unit = "Hz"
#define UWB_RIG_ACCEL_HZ_PER_S \
    .path = "carriage.accel_hz_per_s", .scale = 1, .min = 0, .max = 1e9, .min_exclusive = 1, \
    .default_number = 8000, .unit = "Hz/s"
#define UWB_RIG_TRAVEL_MM \
    .path = "carriage.travel_mm", .scale = 1, .min = 0, .max = 1e5, .min_exclusive = 1, .required = 1, \
    .unit = "mm"
#define UWB_RIG_PARK_MM \
    .path = "carriage.park_mm", .scale = 1, .min = 0, .max = 1e5, .default_number = 5, .unit = "mm"
#define UWB_RIG_BACKLASH_MM \
    .path = "carriage.backlash_mm", .scale = 1, .min = 0, .max = 100, .default_number = 0.5, .unit = "mm"
#define UWB_RIG_SETTLE_MS \
    .path = "carriage.settle_ms", .scale = 1, .min = 0, .max = 60000, .default_number = 50, .unit = "ms"
#define UWB_RIG_HOME_TIMEOUT_S \
    .path = "carriage.home_timeout_s", .scale = 1, .min = 0, .max = 3600, .min_exclusive = 1, \
    .default_number = 60, .unit = "s"
#define UWB_RIG_HOME_DEBOUNCE_MS \
    .path = "carriage.home_debounce_ms", .scale = 1, .min = 0, .max = 1000, .default_number = 5, .unit = "ms"
#define UWB_RIG_HOME_OFFSET_MM \
    .path = "carriage.home_offset_mm", .scale = 1, .min = -1e5, .max = 1e5, .required = 1, .unit = "mm"
#define UWB_RIG_HOME_RATE_HZ \
    .path = "carriage.home_rate_hz", .scale = 1, .min = 0, .max = 1e5, .min_exclusive = 1, \
    .default_number = 1500, .unit = "Hz"
#define UWB_RIG_HOME_BACKOFF_MM \
    .path = "carriage.home_backoff_mm", .scale = 1, .min = 0, .max = 1e5, .min_exclusive = 1, \
    .default_number = 5, .unit = "mm"

#define UWB_RIG_POSITIONS \
    .path = "scan.positions", .scale = 1, .min = 2, .max = UWBSCAN_MAX_POSITIONS, .required = 1, .unit = ""
#define UWB_RIG_FIRST_POSITION_MM \
    .path = "scan.first_position_mm", .scale = 1, .min = -1e5, .max = 1e5, .required = 1, .unit = "mm"
#define UWB_RIG_STEP_MM \
    .path = "scan.step_mm", .scale = 1, .min = UWBSCAN_MIN_STEP_M * 1e3, .max = UWBSCAN_MAX_TRAVEL_M * 1e3, \
    .required = 1, .unit = "mm", \
    .below_min_why = "under the smallest step a scan file may hold (1 mm, uwb/scan.h)"
#define UWB_RIG_TRIGGER_PULSE_US \
    .path = "scan.trigger_pulse_us", .scale = 1, .min = 0, .max = 1e6, .min_exclusive = 1, \
    .default_number = 10, .unit = "us"
#define UWB_RIG_TIME_SCALE \
    .path = "scan.time_scale", .scale = 1, .min = 0, .max = 100, .default_number = 1, .unit = ""

#define UWB_RIG_TX_MM \
    .path = "geometry.tx_mm", .scale = 1e-3, .min = -1e4, .max = 1e4, .required = 1, .unit = "mm"
#define UWB_RIG_RX_MM \
    .path = "geometry.rx_mm", .scale = 1e-3, .min = -1e4, .max = 1e4, .required = 1, .unit = "mm"
#define UWB_RIG_EPS_R .path = "geometry.eps_r", .scale = 1, .min = 1, .max = 100, .required = 1, .unit = ""
#define UWB_RIG_TARGET_Z_MM .path = "geometry.target_z_mm", .scale = 1e-3, .min = 0, .max = 1e5, .unit = "mm"
// NOLINTEND(bugprone-macro-parentheses)

#endif
