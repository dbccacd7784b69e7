/* The rig's configuration: defaults and the checks that keep a bad value
 * from ever reaching the hardware. Every single-key limit and default comes
 * from the rig's key rows (rig_keys.h), the specs the configuration key
 * table (src/config/config_keys.c) builds its rows from, so the loader,
 * `uwbd --config-keys` and the manual pages say the same; what is left here
 * is what involves several fields or the hardware's own rules. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "rig/carriage.h"
#include "rig/rig_keys.h"
#include "uwb/frame.h"
#include "uwb/rig.h"
#include "uwb/scan.h"
#include "util/value_range.h"

/* The default of every key of the rig's that has one. */
static void key_defaults(struct uwb_rig_config *cfg)
{
    for (size_t i = 0; i < uwb_rig_key_total; i++) {
        const struct uwb_rig_key *k = &uwb_rig_keys[i];
        if (k->required)
            continue;
        char *p = (char *)cfg + k->offset;
        if (k->type == UWB_RIG_KEY_NUMBER)
            // cppcheck-suppress invalidPointerCast ; points at a double member (the row's offsetof)
            *(double *)p = k->default_number * k->scale;
        else if (k->type == UWB_RIG_KEY_INT || k->type == UWB_RIG_KEY_BOOL)
            *(int *)p = (int)k->default_number;
    }
}

void uwb_rig_config_defaults(struct uwb_rig_config *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    uwb_gpio_config_defaults(&cfg->gpio);
    key_defaults(cfg);

    /* Required keys have no default in the rows; these match the
     * emulated board's (so `uwbemu` + defaults scans out of the box). */
    struct uwb_digitiser_config *d = &cfg->digitiser;
    d->samples = 2048;
    d->sample_interval_s = 1e-11;

    /* A T8x2 lead screw (2 mm per turn, self-locking), 200-step motor at
     * full step: board/raspberry-pi-4/pinmap.md. */
    struct uwb_carriage_config *c = &cfg->carriage;
    c->steps_per_mm = 100;
    c->travel_mm = 650;
    c->home_offset_mm = -20;

    cfg->positions = 21;
    cfg->first_position_mm = 0;
    cfg->step_mm = 30;
    cfg->tx_m[0] = -0.02;
    cfg->rx_m[0] = 0.02;
    cfg->eps_r = 2.2;
}

/* Every number of the rig's keys against its range, read back into the key's unit. */
static int check_key_ranges(const struct uwb_rig_config *cfg, char *err, size_t errlen)
{
    for (size_t i = 0; i < uwb_rig_key_total; i++) {
        const struct uwb_rig_key *k = &uwb_rig_keys[i];
        const char *p = (const char *)cfg + k->offset;
        double values[2];
        int n = 1;
        if (k->type == UWB_RIG_KEY_INT) {
            values[0] = *(const int *)p;
        } else if (k->type == UWB_RIG_KEY_NUMBER) {
            // cppcheck-suppress invalidPointerCast ; points at a double member (the row's offsetof)
            values[0] = *(const double *)p / k->scale;
        } else if (k->type == UWB_RIG_KEY_PAIR) {
            if (k->flag_offset && !*(const int *)((const char *)cfg + k->flag_offset))
                continue; /* an optional pair not given */
            // cppcheck-suppress invalidPointerCast ; points at a double member (the row's offsetof)
            values[0] = ((const double *)p)[0] / k->scale;
            // cppcheck-suppress invalidPointerCast ; points at a double member (the row's offsetof)
            values[1] = ((const double *)p)[1] / k->scale;
            n = 2;
        } else {
            continue;
        }
        const struct uwb_value_range range = {k->min, k->max, k->min_exclusive, k->unit, k->below_min_why};
        for (int j = 0; j < n; j++) {
            char problem[160];
            if (uwb_value_range_check(&range, values[j], problem, sizeof problem) != 0) {
                snprintf(err, errlen, "rig config: key `%s`: %s", k->path, problem);
                return UWB_RIG_ERR_CONFIG;
            }
        }
    }
    return UWB_RIG_OK;
}

/* One rule between fields broken: the key at fault and why. */
static int broken(const char **key, const char *name, char *problem, size_t len, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

static int broken(const char **key, const char *name, char *problem, size_t len, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(problem, len, fmt, ap);
    va_end(ap);
    *key = name;
    return UWB_RIG_ERR_CONFIG;
}

/* Every position, the backlash overshoot below it included, must lie above
 * home and inside the travel; the first and the last bound all the others
 * (step_mm is positive). */
static int check_positions(const struct uwb_rig_config *r, const char **key, char *problem, size_t len)
{
    const struct uwb_carriage_config *c = &r->carriage;
    double lowest = c->home_offset_mm, highest = c->home_offset_mm + c->travel_mm;
    double first = r->first_position_mm, last = first + (r->positions - 1) * r->step_mm;
    if (first - c->backlash_mm < lowest - 1e-9)
        return broken(
            key, "scan.first_position_mm", problem, len,
            "%g mm minus the backlash overshoot (%g mm) lies below home (carriage.home_offset_mm = %g mm)",
            first, c->backlash_mm, lowest);
    /* A scan the reader refuses may not be recorded. */
    if ((r->positions - 1) * r->step_mm > UWBSCAN_MAX_TRAVEL_M * 1e3)
        return broken(
            key, "scan.positions", problem, len,
            "%d positions %g mm apart span %g mm, over the largest travel a scan file may hold (%g mm)",
            r->positions, r->step_mm, (r->positions - 1) * r->step_mm, UWBSCAN_MAX_TRAVEL_M * 1e3);
    size_t samples_per_scan = (size_t)r->positions * (size_t)r->digitiser.samples;
    if (samples_per_scan > UWBSCAN_MAX_SAMPLE_COUNT)
        return broken(key, "digitiser.samples", problem, len,
                      "%d samples x %d positions = %zu samples per scan, over the limit of %zu (%d MiB of "
                      "float32) a scan file may hold",
                      r->digitiser.samples, r->positions, samples_per_scan, UWBSCAN_MAX_SAMPLE_COUNT,
                      UWBSCAN_MAX_SAMPLE_MIB);
    if (last > highest + 1e-9)
        return broken(key, "scan.positions", problem, len,
                      "the last position, %g mm, lies beyond the travel (home_offset_mm + travel_mm = %g mm)",
                      last, highest);
    return UWB_RIG_OK;
}

int uwb_rig_config_check_rules(const struct uwb_rig_config *r, const char **key, char *problem, size_t len)
{
    const struct uwb_carriage_config *c = &r->carriage;
    if (check_positions(r, key, problem, len) != UWB_RIG_OK)
        return UWB_RIG_ERR_CONFIG;
    if (c->park_mm > c->travel_mm)
        return broken(key, "carriage.park_mm", problem, len, "%g mm lies beyond the travel (%g mm)",
                      c->park_mm, c->travel_mm);
    if (r->has_target_z && !(r->target_z_m[1] > r->target_z_m[0]))
        return broken(key, "geometry.target_z_mm", problem, len, "near (%g mm) must be below far (%g mm)",
                      r->target_z_m[0] * 1e3, r->target_z_m[1] * 1e3);
    if (c->home_rate_hz > c->max_rate_hz)
        return broken(key, "carriage.home_rate_hz", problem, len,
                      "%g Hz is above carriage.max_rate_hz (%g Hz)", c->home_rate_hz, c->max_rate_hz);
    return UWB_RIG_OK;
}

static int bad(char *err, size_t errlen, const char *field, double value, const char *rule)
{
    snprintf(err, errlen, "rig config: %s = %g: %s", field, value, rule);
    return UWB_RIG_ERR_CONFIG;
}

/* The rules the loader leaves to the rig's own words: the carriage's
 * limits against its travel, and position 0 at least one microstep (the
 * smallest overshoot) above home. */
static int check_carriage(const struct uwb_rig_config *r, char *err, size_t errlen)
{
    const struct uwb_carriage_config *c = &r->carriage;
    if (!(c->backlash_mm < c->travel_mm))
        return bad(err, errlen, "carriage.backlash_mm", c->backlash_mm, "must be less than the travel");
    if (!(c->home_backoff_mm <= c->travel_mm))
        return bad(err, errlen, "carriage.home_backoff_mm", c->home_backoff_mm, "must be at most the travel");
    double lowest = fmax(c->backlash_mm, 1.0 / c->steps_per_mm);
    double above_home = r->first_position_mm - c->home_offset_mm;
    if (above_home < lowest - 1e-9) {
        snprintf(err, errlen,
                 "rig config: position 0 at y = %g mm is %g mm above the home switch "
                 "(home_offset_mm %g); it must lie between %g (backlash overshoot) and travel_mm = %g",
                 r->first_position_mm, above_home, c->home_offset_mm, lowest, c->travel_mm);
        return UWB_RIG_ERR_CONFIG;
    }
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
        snprintf(err, errlen, "rig config: gpio.backend '%s' unknown (expected libgpiod or emulated)",
                 g->backend);
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
                snprintf(err, errlen, "rig config: gpio %s and %s lines both use offset %d",
                         uwb_gpio_line_name(j), uwb_gpio_line_name(i), g->offset[i]);
                return UWB_RIG_ERR_CONFIG;
            }
    }
    return UWB_RIG_OK;
}

int uwb_rig_config_check(const struct uwb_rig_config *cfg, char *err, size_t errlen)
{
    int rc = check_gpio(&cfg->gpio, err, errlen);
    if (rc == UWB_RIG_OK)
        rc = check_key_ranges(cfg, err, errlen);
    if (rc == UWB_RIG_OK)
        rc = check_digitiser(&cfg->digitiser, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    const char *key = NULL;
    char problem[512];
    if (uwb_rig_config_check_rules(cfg, &key, problem, sizeof problem) != UWB_RIG_OK) {
        snprintf(err, errlen, "rig config: key `%s`: %s", key, problem);
        return UWB_RIG_ERR_CONFIG;
    }
    return check_carriage(cfg, err, errlen);
}
