/* The rig's own rows for its keys with a range or a default: where each
 * lands in struct uwb_rig_config, with the spec of rig_keys.h. */
#include "rig/rig_keys.h"

#include <stddef.h>

// NOLINTBEGIN(bugprone-macro-parentheses)
#define ROW(t, m, spec) \
    { \
        .type = t, .offset = offsetof(struct uwb_rig_config, m), spec \
    }
// NOLINTEND(bugprone-macro-parentheses)

const struct uwb_rig_key uwb_rig_keys[] = {
    ROW(UWB_RIG_KEY_BOOL, gpio.home_active_low, UWB_RIG_HOME_ACTIVE_LOW),
    ROW(UWB_RIG_KEY_BOOL, gpio.home_pull_up, UWB_RIG_HOME_PULL_UP),
    ROW(UWB_RIG_KEY_BOOL, gpio.enable_active_low, UWB_RIG_ENABLE_ACTIVE_LOW),

    ROW(UWB_RIG_KEY_INT, digitiser.samples, UWB_RIG_SAMPLES),
    ROW(UWB_RIG_KEY_NUMBER, digitiser.sample_interval_s, UWB_RIG_SAMPLE_INTERVAL_PS),
    ROW(UWB_RIG_KEY_NUMBER, digitiser.t0_s, UWB_RIG_T0_PS),
    ROW(UWB_RIG_KEY_INT, digitiser.stack, UWB_RIG_STACK),
    ROW(UWB_RIG_KEY_INT, digitiser.frame_timeout_ms, UWB_RIG_FRAME_TIMEOUT_MS),
    ROW(UWB_RIG_KEY_INT, digitiser.frame_retries, UWB_RIG_FRAME_RETRIES),

    ROW(UWB_RIG_KEY_NUMBER, carriage.steps_per_mm, UWB_RIG_STEPS_PER_MM),
    ROW(UWB_RIG_KEY_NUMBER, carriage.max_rate_hz, UWB_RIG_MAX_RATE_HZ),
    ROW(UWB_RIG_KEY_NUMBER, carriage.accel_hz_per_s, UWB_RIG_ACCEL_HZ_PER_S),
    ROW(UWB_RIG_KEY_NUMBER, carriage.travel_mm, UWB_RIG_TRAVEL_MM),
    ROW(UWB_RIG_KEY_NUMBER, carriage.park_mm, UWB_RIG_PARK_MM),
    ROW(UWB_RIG_KEY_NUMBER, carriage.backlash_mm, UWB_RIG_BACKLASH_MM),
    ROW(UWB_RIG_KEY_NUMBER, carriage.settle_ms, UWB_RIG_SETTLE_MS),
    ROW(UWB_RIG_KEY_NUMBER, carriage.home_timeout_s, UWB_RIG_HOME_TIMEOUT_S),
    ROW(UWB_RIG_KEY_NUMBER, carriage.home_debounce_ms, UWB_RIG_HOME_DEBOUNCE_MS),
    ROW(UWB_RIG_KEY_NUMBER, carriage.home_offset_mm, UWB_RIG_HOME_OFFSET_MM),
    ROW(UWB_RIG_KEY_NUMBER, carriage.home_rate_hz, UWB_RIG_HOME_RATE_HZ),
    ROW(UWB_RIG_KEY_NUMBER, carriage.home_backoff_mm, UWB_RIG_HOME_BACKOFF_MM),

    ROW(UWB_RIG_KEY_INT, positions, UWB_RIG_POSITIONS),
    ROW(UWB_RIG_KEY_NUMBER, first_position_mm, UWB_RIG_FIRST_POSITION_MM),
    ROW(UWB_RIG_KEY_NUMBER, step_mm, UWB_RIG_STEP_MM),
    ROW(UWB_RIG_KEY_NUMBER, trigger_pulse_us, UWB_RIG_TRIGGER_PULSE_US),
    ROW(UWB_RIG_KEY_NUMBER, time_scale, UWB_RIG_TIME_SCALE),

    ROW(UWB_RIG_KEY_PAIR, tx_m, UWB_RIG_TX_MM),
    ROW(UWB_RIG_KEY_PAIR, rx_m, UWB_RIG_RX_MM),
    ROW(UWB_RIG_KEY_NUMBER, eps_r, UWB_RIG_EPS_R),
    {.type = UWB_RIG_KEY_PAIR,
     .offset = offsetof(struct uwb_rig_config, target_z_m),
     .flag_offset = offsetof(struct uwb_rig_config, has_target_z),
     UWB_RIG_TARGET_Z_MM},
};

const size_t uwb_rig_key_total = sizeof uwb_rig_keys / sizeof uwb_rig_keys[0];
