/* The carriage at run time: step pulses on the ramp's schedule, the home
 * search with a software-debounced switch, positions approached from below.
 * The stop flag is polled before every step. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rig/carriage.h"

/* How many readings make up one debounce window. */
#define DEBOUNCE_SAMPLES 4
/* The home search gives up after the whole travel plus this much (and 10 %). */
#define HOME_MARGIN_MM 10.0

void uwb_carriage_init(struct uwb_carriage *c, struct uwb_gpio *gpio, const struct uwb_carriage_config *cfg,
                       double time_scale, const volatile sig_atomic_t *stop)
{
    memset(c, 0, sizeof *c);
    c->gpio = gpio;
    c->cfg = *cfg;
    c->time_scale = time_scale;
    c->stop = stop;
    c->dir = -1;
}

static int stopped(const struct uwb_carriage *c, char *err, size_t errlen)
{
    if (c->stop && *c->stop) {
        snprintf(err, errlen, "stopped on request while moving the carriage");
        return 1;
    }
    return 0;
}

static int set_line(struct uwb_carriage *c, enum uwb_gpio_line line, int value, char *err, size_t errlen)
{
    return uwb_gpio_set(c->gpio, line, value, err, errlen) == UWB_GPIO_OK ? UWB_RIG_OK : UWB_RIG_ERR_GPIO;
}

int uwb_carriage_enable(struct uwb_carriage *c, int on, char *err, size_t errlen)
{
    int rc = set_line(c, UWB_LINE_ENABLE, on, err, errlen);
    if (rc == UWB_RIG_OK && on) {
        struct uwb_pacer p;
        uwb_pacer_start(&p, c->time_scale);
        uwb_pacer_wait_until(&p, UWB_ENABLE_WAKE_S);
    }
    return rc;
}

static int set_dir(struct uwb_carriage *c, int up, char *err, size_t errlen)
{
    if (c->dir == up)
        return UWB_RIG_OK;
    int rc = set_line(c, UWB_LINE_DIR, up, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    c->dir = up;
    struct uwb_pacer p;
    uwb_pacer_start(&p, c->time_scale);
    uwb_pacer_wait_until(&p, UWB_DIR_SETUP_S);
    return UWB_RIG_OK;
}

/* One STEP pulse at `at` seconds after the pacer's start. */
static int pulse_step(struct uwb_carriage *c, struct uwb_pacer *p, double at, char *err, size_t errlen)
{
    uwb_pacer_wait_until(p, at);
    int rc = set_line(c, UWB_LINE_STEP, 1, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    uwb_pacer_wait_until(p, at + UWB_STEP_PULSE_S);
    rc = set_line(c, UWB_LINE_STEP, 0, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    c->position += c->dir ? 1 : -1;
    c->steps_moved++;
    return UWB_RIG_OK;
}

/* A ramped move of `delta` microsteps (sign = direction). */
static int move_steps(struct uwb_carriage *c, long delta, char *err, size_t errlen)
{
    if (delta == 0)
        return UWB_RIG_OK;
    int rc = set_dir(c, delta > 0, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    struct uwb_ramp ramp;
    uwb_ramp_init(&ramp, delta > 0 ? delta : -delta, c->cfg.max_rate_hz, c->cfg.accel_hz_per_s);
    struct uwb_pacer p;
    uwb_pacer_start(&p, c->time_scale);
    for (long k = 1; k <= ramp.steps; k++) {
        if (stopped(c, err, errlen))
            return UWB_RIG_ERR_STOPPED;
        rc = pulse_step(c, &p, uwb_ramp_step_time_s(&ramp, k), err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
    }
    return UWB_RIG_OK;
}

static int read_home(struct uwb_carriage *c, int *active, char *err, size_t errlen)
{
    return uwb_gpio_get(c->gpio, UWB_LINE_HOME, active, err, errlen) == UWB_GPIO_OK ? UWB_RIG_OK
                                                                                    : UWB_RIG_ERR_GPIO;
}

/* Does the switch read `want` for the whole debounce window? Adds the
 * window to *nominal_s. */
static int home_settles(struct uwb_carriage *c, int want, int *settled, double *nominal_s, char *err,
                        size_t errlen)
{
    struct uwb_pacer p;
    uwb_pacer_start(&p, c->time_scale);
    double window = c->cfg.home_debounce_ms / 1000.0;
    *settled = 0;
    for (int i = 1; i <= DEBOUNCE_SAMPLES; i++) {
        uwb_pacer_wait_until(&p, window * i / DEBOUNCE_SAMPLES);
        int value;
        int rc = read_home(c, &value, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        if (value != want) {
            *nominal_s += window * i / DEBOUNCE_SAMPLES;
            return UWB_RIG_OK;
        }
    }
    *nominal_s += window;
    *settled = 1;
    return UWB_RIG_OK;
}

/* Step at a constant rate in one direction until the switch reads `want`
 * steadily, at most `limit` steps and until the nominal clock passes
 * home_timeout_s. *found: 1 found, 0 limit reached, -1 timed out. */
static int seek_switch(struct uwb_carriage *c, int up, int want, double rate, long limit, int *found,
                       double *nominal_s, char *err, size_t errlen)
{
    *found = 0;
    int rc = set_dir(c, up, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    struct uwb_pacer p;
    uwb_pacer_start(&p, c->time_scale);
    long k0 = 0; /* step count at the pacer's start */
    for (long k = 1; k <= limit; k++) {
        if (stopped(c, err, errlen))
            return UWB_RIG_ERR_STOPPED;
        if (*nominal_s > c->cfg.home_timeout_s) {
            *found = -1;
            return UWB_RIG_OK;
        }
        rc = pulse_step(c, &p, (double)(k - k0) / rate, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        *nominal_s += 1.0 / rate;
        int value;
        rc = read_home(c, &value, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        if (value != want)
            continue;
        int settled;
        rc = home_settles(c, want, &settled, nominal_s, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        if (settled) {
            *found = 1;
            return UWB_RIG_OK;
        }
        uwb_pacer_start(&p, c->time_scale); /* a bounce: go on stepping from now */
        k0 = k;
    }
    return UWB_RIG_OK;
}

int uwb_carriage_home(struct uwb_carriage *c, char *err, size_t errlen)
{
    const struct uwb_carriage_config *cfg = &c->cfg;
    double nominal_s = 0;
    c->homed = 0;
    c->position = 0;
    c->home_found_mm = 0;

    int active, settled = 0, found, rc = read_home(c, &active, err, errlen);
    if (rc == UWB_RIG_OK && active)
        rc = home_settles(c, 1, &settled, &nominal_s, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    if (!settled) {
        long limit = uwb_carriage_mm_to_steps(cfg, cfg->travel_mm * 1.1 + HOME_MARGIN_MM);
        rc = seek_switch(c, 0, 1, cfg->home_rate_hz, limit, &found, &nominal_s, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        c->home_found_mm = -c->position / cfg->steps_per_mm;
        if (found < 0) {
            snprintf(err, errlen, "home switch not seen within home_timeout_s = %g s (searched %.1f mm down)",
                     cfg->home_timeout_s, c->home_found_mm);
            return UWB_RIG_ERR_HOME;
        }
        if (!found) {
            snprintf(err, errlen,
                     "home switch never closed: searched %.1f mm down, more than the travel of %g mm "
                     "(switch wiring, home_active_low, or DIR reversed?)",
                     c->home_found_mm, cfg->travel_mm);
            return UWB_RIG_ERR_HOME;
        }
    }
    /* Back off until the switch opens, then close it again slowly: the
     * slow approach makes the zero repeatable, and a switch that never
     * opens is stuck. */
    double slow = cfg->home_rate_hz / 4.0;
    long backoff = uwb_carriage_mm_to_steps(cfg, cfg->home_backoff_mm);
    long before = c->position;
    rc = seek_switch(c, 1, 0, slow, backoff, &found, &nominal_s, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    if (found <= 0) {
        snprintf(err, errlen,
                 "home switch stays closed after backing off %.2f mm: stuck, shorted, or "
                 "home_active_low wrong",
                 (c->position - before) / cfg->steps_per_mm);
        return UWB_RIG_ERR_HOME;
    }
    long again = (c->position - before) + uwb_carriage_mm_to_steps(cfg, 1.0);
    rc = seek_switch(c, 0, 1, slow, again, &found, &nominal_s, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    if (found <= 0) {
        snprintf(err, errlen, "home switch opened when backing off but did not close again within %.2f mm",
                 again / cfg->steps_per_mm);
        return UWB_RIG_ERR_HOME;
    }
    c->position = 0;
    c->homed = 1;
    return UWB_RIG_OK;
}

int uwb_carriage_move_to(struct uwb_carriage *c, double mm, char *err, size_t errlen)
{
    if (!c->homed) {
        snprintf(err, errlen, "carriage: move to %.3f mm before homing", mm);
        return UWB_RIG_ERR_CONFIG;
    }
    long target = uwb_carriage_mm_to_steps(&c->cfg, mm);
    long waypoints[2];
    int n = uwb_carriage_plan(c->position, target, uwb_carriage_mm_to_steps(&c->cfg, c->cfg.backlash_mm),
                              waypoints);
    for (int i = 0; i < n; i++) {
        int rc = move_steps(c, waypoints[i] - c->position, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
    }
    return UWB_RIG_OK;
}

int uwb_carriage_park(struct uwb_carriage *c, char *err, size_t errlen)
{
    if (!c->homed) {
        snprintf(err, errlen, "carriage: park before homing");
        return UWB_RIG_ERR_CONFIG;
    }
    return move_steps(c, uwb_carriage_mm_to_steps(&c->cfg, c->cfg.park_mm) - c->position, err, errlen);
}

int uwb_carriage_check_home(struct uwb_carriage *c, double *off_mm, char *err, size_t errlen)
{
    const struct uwb_carriage_config *cfg = &c->cfg;
    *off_mm = 0;
    if (!c->homed) {
        snprintf(err, errlen, "carriage: home check before homing");
        return UWB_RIG_ERR_CONFIG;
    }
    double tolerance_mm = uwb_carriage_home_tolerance_mm(cfg);
    long approach = uwb_carriage_mm_to_steps(cfg, cfg->home_backoff_mm + tolerance_mm);
    int rc = UWB_RIG_OK;
    if (c->position > approach)
        rc = move_steps(c, approach - c->position, err, errlen);
    int active = 0;
    if (rc == UWB_RIG_OK)
        rc = read_home(c, &active, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    c->homed = 0; /* until the switch agrees with the count */
    double nominal_s = 0;
    int found = 0;
    if (active) {
        /* Already closed this high by the count: up slowly until it opens to
         * say by how much. */
        rc = seek_switch(c, 1, 0, cfg->home_rate_hz / 4.0, uwb_carriage_mm_to_steps(cfg, cfg->travel_mm),
                         &found, &nominal_s, err, errlen);
        if (rc != UWB_RIG_OK)
            return rc;
        /* The way down may have pressed the carriage into its bottom stop,
         * so this is the least that was lost; the causes are named because
         * a scale error shows up here too, once the top stop stalls it. */
        *off_mm = c->position / cfg->steps_per_mm;
        snprintf(err, errlen,
                 "steps lost: %.2f mm or more (the home switch opens %.2f mm above the counted home%s; "
                 "tolerance %.2f mm): stalled or slipped going up (obstruction, belt, or past the travel "
                 "into the top stop: steps_per_mm?)",
                 *off_mm, *off_mm, found > 0 ? "" : " or higher", tolerance_mm);
        return UWB_RIG_ERR_HOME;
    }
    /* Down at the homing's slow rate, as the zero was found: the switch
     * should close at position 0, within the tolerance. */
    long start = c->position;
    long limit = start + uwb_carriage_mm_to_steps(cfg, tolerance_mm + 1.0);
    rc = seek_switch(c, 0, 1, cfg->home_rate_hz / 4.0, limit, &found, &nominal_s, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    *off_mm = c->position / cfg->steps_per_mm;
    if (found <= 0) {
        snprintf(err, errlen,
                 "steps lost: %.2f mm or more (the home switch did not close within %.2f mm below the "
                 "counted home; tolerance %.2f mm)",
                 -*off_mm, -*off_mm, tolerance_mm);
        return UWB_RIG_ERR_HOME;
    }
    if (fabs(*off_mm) > tolerance_mm) {
        snprintf(err, errlen,
                 "steps lost: %.2f mm (the home switch closed %.2f mm %s the counted home; "
                 "tolerance %.2f mm)",
                 fabs(*off_mm), fabs(*off_mm), *off_mm > 0 ? "above" : "below", tolerance_mm);
        return UWB_RIG_ERR_HOME;
    }
    c->position = 0; /* the switch is the reference again */
    c->homed = 1;
    return UWB_RIG_OK;
}

double uwb_carriage_home_tolerance_mm(const struct uwb_carriage_config *cfg)
{
    /* The reversal before the check takes up the backlash; half a millimetre
     * more covers the switch's repeatability at the slow approach rate. */
    return cfg->backlash_mm + 0.5;
}
