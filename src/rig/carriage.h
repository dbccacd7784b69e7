/* The antenna carriage: a stepper on STEP/DIR/ENABLE and a home switch.
 * The motion maths (step timing of a trapezoidal ramp, the backlash
 * approach) are pure functions, tested on their own; the runtime below
 * turns them into line changes at the right instants. */
#ifndef UWB_CARRIAGE_H
#define UWB_CARRIAGE_H

#include <signal.h>
#include <stddef.h>
#include <time.h>

#include "uwb/gpio.h"
#include "uwb/rig.h"

/* Fixed driver timings (seconds, before time_scale): STEP high time (A4988
 * needs 1 us, TMC2209 0.1 us), DIR set-up before the next STEP edge, and
 * the driver's wake-up after ENABLE. */
#define UWB_STEP_PULSE_S 5e-6
#define UWB_DIR_SETUP_S 20e-6
#define UWB_ENABLE_WAKE_S 2e-3

/* A move of `steps` microsteps starting and ending at rest: constant
 * acceleration up to max_hz, cruise, symmetric deceleration (a triangle
 * when the move is too short to reach max_hz). */
struct uwb_ramp {
    long steps;
    double max_hz;
    double accel;       /* steps/s^2 */
    double accel_steps; /* steps spent accelerating (real-valued) */
    double accel_s;     /* time spent accelerating */
    double total_s;     /* duration of the whole move */
};

void uwb_ramp_init(struct uwb_ramp *ramp, long steps, double max_hz, double accel_hz_per_s);
/* Instant of step k's rising edge (k = 1..steps) after the move starts;
 * the last one is at total_s. */
double uwb_ramp_step_time_s(const struct uwb_ramp *ramp, long k);

/* Waypoints (in steps above home) that bring the carriage from `from` to
 * `to` so that the final segment runs upward at least max(backlash, 1)
 * steps: {to} when it already does, else {to - backlash, to}. Returns the
 * number of waypoints (1 or 2). */
int uwb_carriage_plan(long from, long to, long backlash_steps, long waypoints[2]);

/* Steps above home for a carriage coordinate in mm (nearest microstep). */
long uwb_carriage_mm_to_steps(const struct uwb_carriage_config *cfg, double mm);

/* Absolute-deadline waits scaled by time_scale (clock_nanosleep, no busy
 * waiting): offsets are nominal seconds after the last pacer_start. */
struct uwb_pacer {
    struct timespec base;
    double scale;
};
void uwb_pacer_start(struct uwb_pacer *pacer, double time_scale);
void uwb_pacer_wait_until(struct uwb_pacer *pacer, double offset_s);
/* Restart at now and wait `seconds` (nominal). */
void uwb_pacer_sleep(struct uwb_pacer *pacer, double seconds);

struct uwb_carriage {
    struct uwb_gpio *gpio;
    struct uwb_carriage_config cfg;
    double time_scale;
    const volatile sig_atomic_t *stop;
    long position; /* microsteps above the home switch, valid when homed */
    int homed;
    int dir;              /* DIR as last set, -1 unknown */
    long steps_moved;     /* microsteps issued since the counter was last cleared */
    double home_found_mm; /* distance the last home search went down */
};

/* Every function returns an enum uwb_rig_error (OK, ERR_GPIO, ERR_HOME,
 * ERR_STOPPED, ERR_CONFIG) with err filled on failure. */
void uwb_carriage_init(struct uwb_carriage *c, struct uwb_gpio *gpio, const struct uwb_carriage_config *cfg,
                       double time_scale, const volatile sig_atomic_t *stop);
int uwb_carriage_enable(struct uwb_carriage *c, int on, char *err, size_t errlen);
/* Seek the switch downward, back off until it opens, approach again slowly;
 * that point is position 0. Fails clearly when the switch never closes
 * (travel + margin, or home_timeout_s of nominal time) or never opens. */
int uwb_carriage_home(struct uwb_carriage *c, char *err, size_t errlen);
/* Move to mm above home, the last segment upward (backlash). */
int uwb_carriage_move_to(struct uwb_carriage *c, double mm, char *err, size_t errlen);
/* Straight to park_mm (no backlash approach needed to rest). */
int uwb_carriage_park(struct uwb_carriage *c, char *err, size_t errlen);
/* After the last position: back down to the home switch at the homing's
 * slow rate and compare where it closes with the counted steps (*off_mm,
 * positive when it closes above the counted home: upward steps lost). More
 * than uwb_carriage_home_tolerance_mm apart is UWB_RIG_ERR_HOME with
 * "steps lost: X mm" and the carriage no longer counts as homed; within it,
 * the switch is position 0 again. */
int uwb_carriage_check_home(struct uwb_carriage *c, double *off_mm, char *err, size_t errlen);
/* backlash_mm + 0.5 mm (the switch's repeatability at the slow rate). */
double uwb_carriage_home_tolerance_mm(const struct uwb_carriage_config *cfg);

#endif
