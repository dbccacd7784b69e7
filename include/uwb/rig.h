/* The acquisition hardware as one rig: GPIO lines (pulser trigger, stepper,
 * home switch), the antenna carriage they move, and the digitiser link.
 * uwb_rig_scan runs one scan cycle and hands back a struct uwb_scan; the
 * daemon above it never touches a line or a frame. */
#ifndef UWB_RIG_H
#define UWB_RIG_H

#include <signal.h>
#include <stddef.h>

#include "uwb/digitiser.h"
#include "uwb/gpio.h"
#include "uwb/link.h"
#include "uwb/scan.h"

struct uwb_carriage_config {
    double steps_per_mm;     /* microsteps per millimetre of travel */
    double max_rate_hz;      /* top step rate */
    double accel_hz_per_s;   /* linear ramp of the step rate */
    double travel_mm;        /* usable travel above home; positions must lie inside */
    double park_mm;          /* where the carriage rests between scans */
    double backlash_mm;      /* every position is approached from below by this overshoot */
    double settle_ms;        /* wait after a move before firing */
    double home_timeout_s;   /* give up homing after this */
    double home_debounce_ms; /* switch must read stable this long */
    double home_offset_mm;   /* y of the home switch in scan coordinates (mm) */
    double home_rate_hz;     /* step rate seeking the switch (the final approach runs at a quarter) */
    double home_backoff_mm;  /* a switch still closed after backing off this far is stuck */
};

/* Pulses averaged per position unless configured: at the emulated board's
 * 20 dB per pulse, 64 bring a 12 mm rise well inside the default 1 mm
 * uncertainty limit (README, Accuracy). One default for the key table, the
 * rig and the sample configs. */
#define UWB_DEFAULT_STACK 64

struct uwb_rig_config {
    struct uwb_gpio_config gpio;
    struct uwb_digitiser_config digitiser;
    struct uwb_carriage_config carriage;
    int positions;            /* K */
    double first_position_mm; /* y of position 0 in scan coordinates */
    double step_mm;           /* spacing between positions */
    double tx_m[2], rx_m[2];  /* antenna phase centres, written to the header */
    double eps_r;
    int has_target_z;
    double target_z_m[2];
    double trigger_pulse_us; /* trigger line high time */
    /* Multiplies every wait (step timing, settle, debounce, trigger pulse):
     * 1 = real time; below 1 runs emulated scans faster, 0 = no waiting at
     * all. Timeouts of the home search count nominal (unscaled) time. */
    double time_scale;
    char source[128]; /* header `source` prefix, e.g. "uwbd 1.0 on HOST"; "" = "uwbd" */
    /* Leads the scan id (site.asset_id), so the rig's log line and the
     * scan's header name the asset; "" = none. */
    char asset_id[64];
};

enum uwb_rig_error {
    UWB_RIG_OK = 0,
    UWB_RIG_ERR_GPIO = -1,      /* see the gpio error inside err */
    UWB_RIG_ERR_LINK = -2,      /* digitiser endpoint could not be opened */
    UWB_RIG_ERR_HOME = -3,      /* home switch never seen / stuck */
    UWB_RIG_ERR_DIGITISER = -4, /* frames bad beyond the retries, timeout */
    UWB_RIG_ERR_STOPPED = -5,   /* *stop became non-zero */
    UWB_RIG_ERR_CONFIG = -6,
};

struct uwb_rig;

/* The configuration key table's defaults (src/config/config_keys.c); keys
 * the table requires get the emulated board's values. */
void uwb_rig_config_defaults(struct uwb_rig_config *cfg);
/* Checks the config without touching hardware (for --check-config too):
 * each value against its key's range in the same table, then the rules
 * between fields. UWB_RIG_OK or UWB_RIG_ERR_CONFIG with err naming the key. */
int uwb_rig_config_check(const struct uwb_rig_config *cfg, char *err, size_t errlen);
/* The rules between fields that the config loader reports naming the key
 * (uwb_rig_config_check checks them too, after the ranges): every
 * position, the backlash overshoot below it included, above home and
 * inside the travel; a scan a scan file can hold; park and home rate
 * inside their limits; the target's near below its far. UWB_RIG_OK, or
 * UWB_RIG_ERR_CONFIG with *key the key at fault and `problem` why. */
int uwb_rig_config_check_rules(const struct uwb_rig_config *cfg, const char **key, char *problem, size_t len);
/* Open the GPIO backend and the digitiser link. On failure returns an enum
 * uwb_rig_error (the underlying gpio/link error in *detail if not NULL). */
int uwb_rig_open(const struct uwb_rig_config *cfg, struct uwb_rig **rig, int *detail, char *err,
                 size_t errlen);
/* One scan cycle: home, every position (move from below, settle, `stack`
 * pulses each answered by one checked frame, average), park, motor
 * disabled, pulser idle. Fills *out (positions, samples, geometry, stack,
 * created, scan_id, source). The hardware is left safe on every return.
 * `stop` may be NULL; it is polled between pulses and steps. */
int uwb_rig_scan(struct uwb_rig *rig, const volatile sig_atomic_t *stop, struct uwb_scan *out, char *err,
                 size_t errlen);
/* Pulser idle, motor disabled; safe to call at any time, e.g. from cleanup. */
void uwb_rig_make_safe(struct uwb_rig *rig);
void uwb_rig_close(struct uwb_rig *rig);

/* Optional log sink (priority as syslog's LOG_ERR..LOG_DEBUG): homing,
 * retried frames, the scan's summary. */
typedef void (*uwb_rig_log_fn)(void *ctx, int priority, const char *message);
void uwb_rig_set_log(struct uwb_rig *rig, uwb_rig_log_fn log, void *ctx);
/* Optional: called after each position is acquired (done of total), on the
 * thread that runs uwb_rig_scan; and with done 0 as a scan starts. */
typedef void (*uwb_rig_progress_fn)(void *ctx, int done, int total);
void uwb_rig_set_progress(struct uwb_rig *rig, uwb_rig_progress_fn progress, void *ctx);

/* Counts since uwb_rig_open (frames, retries, ...) and of the last scan. */
struct uwb_rig_stats {
    unsigned long scans;
    unsigned long traces, fired, retries, timeouts, bad_frames, bad_payloads, stale, ahead, reconnects;
    long last_scan_steps;      /* microsteps moved in the last scan, homing included */
    double last_home_found_mm; /* how far the home search went down in the last scan */
};
void uwb_rig_get_stats(const struct uwb_rig *rig, struct uwb_rig_stats *stats);

#endif
