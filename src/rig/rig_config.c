/* The rig's configuration: defaults that match the emulated board's
 * defaults (so `uwbemu` + defaults scans out of the box), and the checks
 * that keep a bad value from ever reaching the hardware. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "uwb/carriage.h"
#include "uwb/frame.h"
#include "uwb/rig.h"
#include "uwb/scan.h"

void uwb_rig_config_defaults(struct uwb_rig_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    uwb_gpio_config_defaults(&cfg->gpio);

    struct uwb_digitiser_config *d = &cfg->digitiser;
    d->samples = 2048;
    d->sample_interval_s = 1e-11;
    d->t0_s = -1e-9;
    d->stack = UWB_DEFAULT_STACK;
    d->frame_timeout_ms = 1000;
    d->frame_retries = 3;

    /* A T8x2 lead screw (2 mm per turn, self-locking), 200-step motor at
     * full step: board/raspberry-pi-4/pinmap.md. */
    struct uwb_carriage_config *c = &cfg->carriage;
    c->steps_per_mm = 100;
    c->max_rate_hz = 4000;
    c->accel_hz_per_s = 8000;
    c->travel_mm = 650;
    c->park_mm = 5;
    c->backlash_mm = 0.5;
    c->settle_ms = 50;
    c->home_timeout_s = 60;
    c->home_debounce_ms = 5;
    c->home_offset_mm = -20;
    c->home_rate_hz = 1500;
    c->home_backoff_mm = 5;

    cfg->positions = 21;
    cfg->first_position_mm = 0;
    cfg->step_mm = 30;
    cfg->tx_m[0] = -0.02;
    cfg->rx_m[0] = 0.02;
    cfg->eps_r = 2.2;
    cfg->trigger_pulse_us = 10;
    cfg->time_scale = 1;
}

static int bad(char *err, size_t errlen, const char *field, double value, const char *rule)
{
    snprintf(err, errlen, "rig config: %s = %g: %s", field, value, rule);
    return UWB_RIG_ERR_CONFIG;
}

#define REQUIRE(cond, field, value, rule) \
    do { \
        if (!(cond)) \
            return bad(err, errlen, field, (double)(value), rule); \
    } while (0)

static int check_carriage(const struct uwb_carriage_config *c, char *err, size_t errlen)
{
    REQUIRE(isfinite(c->steps_per_mm) && c->steps_per_mm > 0 && c->steps_per_mm <= 1e5, "carriage.steps_per_mm",
            c->steps_per_mm, "must be above 0 and at most 100000");
    /* The STEP pulse and the gap after it must both fit one period. */
    REQUIRE(c->max_rate_hz > 0 && c->max_rate_hz <= 0.5 / UWB_STEP_PULSE_S, "carriage.max_rate_hz", c->max_rate_hz,
            "must be above 0 and at most 100000");
    REQUIRE(c->accel_hz_per_s > 0 && isfinite(c->accel_hz_per_s), "carriage.accel_hz_per_s", c->accel_hz_per_s,
            "must be above 0");
    REQUIRE(c->travel_mm > 0 && isfinite(c->travel_mm), "carriage.travel_mm", c->travel_mm, "must be above 0");
    REQUIRE(c->park_mm >= 0 && c->park_mm <= c->travel_mm, "carriage.park_mm", c->park_mm,
            "must lie inside the travel (0..travel_mm)");
    REQUIRE(c->backlash_mm >= 0 && c->backlash_mm < c->travel_mm, "carriage.backlash_mm", c->backlash_mm,
            "must be 0 or more and less than the travel");
    REQUIRE(c->settle_ms >= 0 && c->settle_ms <= 60000, "carriage.settle_ms", c->settle_ms, "must be 0..60000");
    REQUIRE(c->home_timeout_s > 0 && c->home_timeout_s <= 3600, "carriage.home_timeout_s", c->home_timeout_s,
            "must be above 0 and at most 3600");
    REQUIRE(c->home_debounce_ms >= 0 && c->home_debounce_ms <= 1000, "carriage.home_debounce_ms",
            c->home_debounce_ms, "must be 0..1000");
    REQUIRE(isfinite(c->home_offset_mm), "carriage.home_offset_mm", c->home_offset_mm, "must be a number");
    REQUIRE(c->home_rate_hz > 0 && c->home_rate_hz <= c->max_rate_hz, "carriage.home_rate_hz", c->home_rate_hz,
            "must be above 0 and at most max_rate_hz");
    REQUIRE(c->home_backoff_mm > 0 && c->home_backoff_mm <= c->travel_mm, "carriage.home_backoff_mm",
            c->home_backoff_mm, "must be above 0 and at most the travel");
    return UWB_RIG_OK;
}

static int check_digitiser(const struct uwb_digitiser_config *d, char *err, size_t errlen)
{
    struct uwb_endpoint ep;
    char why[512];
    if (uwb_endpoint_parse(d->endpoint, &ep, why, sizeof why) != UWB_LINK_OK) {
        snprintf(err, errlen, "rig config: digitiser.endpoint: %s", why);
        return UWB_RIG_ERR_CONFIG;
    }
    REQUIRE(d->samples >= 1 && d->samples <= UWB_FRAME_MAX_SAMPLES, "digitiser.samples", d->samples,
            "must be 1..65536");
    REQUIRE(d->sample_interval_s > 0 && d->sample_interval_s < 1e-3, "digitiser.sample_interval_s",
            d->sample_interval_s, "must be above 0 and below 1 ms");
    REQUIRE(isfinite(d->t0_s), "digitiser.t0_s", d->t0_s, "must be a number");
    REQUIRE(d->stack >= 1 && d->stack <= 65536, "digitiser.stack", d->stack, "must be 1..65536");
    REQUIRE(d->frame_timeout_ms >= 1 && d->frame_timeout_ms <= 600000, "digitiser.frame_timeout_ms",
            d->frame_timeout_ms, "must be 1..600000");
    REQUIRE(d->frame_retries >= 0 && d->frame_retries <= 100, "digitiser.frame_retries", d->frame_retries,
            "must be 0..100");
    return UWB_RIG_OK;
}

static int check_gpio(const struct uwb_gpio_config *g, char *err, size_t errlen)
{
    if (strcmp(g->backend, "emulated") == 0) {
        struct uwb_endpoint ep;
        char why[512];
        if (uwb_endpoint_parse(g->endpoint, &ep, why, sizeof why) != UWB_LINK_OK) {
            snprintf(err, errlen, "rig config: gpio.endpoint: %s", why);
            return UWB_RIG_ERR_CONFIG;
        }
        return UWB_RIG_OK;
    }
    if (strcmp(g->backend, "libgpiod") != 0) {
        snprintf(err, errlen, "rig config: gpio.backend '%s' unknown (expected libgpiod or emulated)", g->backend);
        return UWB_RIG_ERR_CONFIG;
    }
    if (!g->chip[0]) {
        snprintf(err, errlen, "rig config: gpio.chip is empty (gpiochip0, a label or a /dev path)");
        return UWB_RIG_ERR_CONFIG;
    }
    for (int i = 0; i < UWB_LINE_RIG; i++) {
        if (g->offset[i] < 0 && !g->name[i][0]) {
            snprintf(err, errlen, "rig config: gpio %s line has neither an offset (0 or more) nor a name",
                     uwb_gpio_line_name(i));
            return UWB_RIG_ERR_CONFIG;
        }
        for (int j = 0; j < i; j++)
            if (g->offset[i] >= 0 && g->offset[i] == g->offset[j]) {
                snprintf(err, errlen, "rig config: gpio %s and %s lines both use offset %d", uwb_gpio_line_name(j),
                         uwb_gpio_line_name(i), g->offset[i]);
                return UWB_RIG_ERR_CONFIG;
            }
    }
    return UWB_RIG_OK;
}

int uwb_rig_config_check(const struct uwb_rig_config *cfg, char *err, size_t errlen)
{
    int rc = check_gpio(&cfg->gpio, err, errlen);
    if (rc == UWB_RIG_OK)
        rc = check_digitiser(&cfg->digitiser, err, errlen);
    if (rc == UWB_RIG_OK)
        rc = check_carriage(&cfg->carriage, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    REQUIRE(cfg->positions >= 1 && cfg->positions <= UWBSCAN_MAX_POSITIONS, "positions", cfg->positions,
            "must be 1..4096");
    REQUIRE(isfinite(cfg->first_position_mm), "first_position_mm", cfg->first_position_mm, "must be a number");
    REQUIRE(isfinite(cfg->step_mm) && (cfg->step_mm != 0 || cfg->positions == 1), "step_mm", cfg->step_mm,
            "must be a number, not 0 with more than one position");
    /* Every position, backlash overshoot included, must stay above home and
     * inside the travel. */
    const struct uwb_carriage_config *c = &cfg->carriage;
    double lowest = fmax(c->backlash_mm, 1.0 / c->steps_per_mm);
    for (int k = 0; k < cfg->positions; k += cfg->positions - 1 > 0 ? cfg->positions - 1 : 1) {
        double y = cfg->first_position_mm + k * cfg->step_mm;
        double above_home = y - c->home_offset_mm;
        if (above_home < lowest - 1e-9 || above_home > c->travel_mm + 1e-9) {
            snprintf(err, errlen, "rig config: position %d at y = %g mm is %g mm above the home switch "
                     "(home_offset_mm %g); it must lie between %g (backlash overshoot) and travel_mm = %g",
                     k, y, above_home, c->home_offset_mm, lowest, c->travel_mm);
            return UWB_RIG_ERR_CONFIG;
        }
    }
    REQUIRE(cfg->eps_r >= 1 && cfg->eps_r <= 100, "eps_r", cfg->eps_r, "must be 1..100");
    for (int i = 0; i < 2; i++) {
        REQUIRE(isfinite(cfg->tx_m[i]) && fabs(cfg->tx_m[i]) <= 1, "tx_m", cfg->tx_m[i], "must be within 1 m");
        REQUIRE(isfinite(cfg->rx_m[i]) && fabs(cfg->rx_m[i]) <= 1, "rx_m", cfg->rx_m[i], "must be within 1 m");
    }
    if (cfg->has_target_z)
        REQUIRE(cfg->target_z_m[0] >= 0 && cfg->target_z_m[1] > cfg->target_z_m[0], "target_z_m[1]",
                cfg->target_z_m[1], "must be above target_z_m[0] >= 0");
    REQUIRE(cfg->trigger_pulse_us > 0 && cfg->trigger_pulse_us <= 1e6, "trigger_pulse_us", cfg->trigger_pulse_us,
            "must be above 0 and at most 1 s");
    REQUIRE(cfg->time_scale >= 0 && cfg->time_scale <= 100, "time_scale", cfg->time_scale, "must be 0..100");
    return UWB_RIG_OK;
}
