/* Fuzzing the daemon's config loader on its text (uwbd_config_parse, what
 * uwbd_config_load does after reading the file): the input is the file's
 * bytes, not NUL-terminated, as the loader holds them.
 *
 * Contract: a refusal says why, naming the input; an accepted config has
 * every string terminated inside its field, the paths it needs, a mode
 * that fits in 07777, finite numbers, and passes the rig's own checks. */
#include <math.h>
#include <string.h>

#include "fuzz_harness.h"
#include "config/config_load.h"
#include "uwb/frame.h"

#define NAME "fuzz.json"

#define TERMINATED(field) (memchr((field), '\0', sizeof(field)) != NULL)

static int check_config(const struct uwbd_config *cfg, char *why, size_t whylen)
{
    const struct uwb_rig_config *r = &cfg->rig;
    if (!TERMINATED(cfg->state_dir) || !TERMINATED(cfg->console_endpoint) ||
        !TERMINATED(cfg->control_socket) || !TERMINATED(cfg->control_mode_text) ||
        !TERMINATED(cfg->control_group) || !TERMINATED(r->gpio.backend) || !TERMINATED(r->gpio.chip) ||
        !TERMINATED(r->gpio.endpoint) || !TERMINATED(r->digitiser.endpoint) || !TERMINATED(r->source))
        return fuzz_broken(why, whylen, "accepted with an unterminated string");
    for (int i = 0; i < UWB_LINE_COUNT; i++)
        if (!TERMINATED(r->gpio.name[i]))
            return fuzz_broken(why, whylen, "accepted with an unterminated GPIO line name");
    if (!cfg->state_dir[0] || !cfg->control_socket[0] || !r->digitiser.endpoint[0])
        return fuzz_broken(why, whylen, "accepted without state_dir, control.socket or digitiser.endpoint");
    if (cfg->control_mode > 07777)
        return fuzz_broken(why, whylen, "accepted control.mode %o", cfg->control_mode);
    double numbers[] = {cfg->interval_s,
                        cfg->retention_max_age_days,
                        cfg->evaluate.direct_coupling.window_end_s,
                        cfg->evaluate.direct_coupling.tolerance_s,
                        r->first_position_mm,
                        r->step_mm,
                        r->tx_m[0],
                        r->tx_m[1],
                        r->rx_m[0],
                        r->rx_m[1],
                        r->eps_r,
                        r->trigger_pulse_us,
                        r->time_scale,
                        r->digitiser.sample_interval_s,
                        r->digitiser.t0_s};
    for (size_t i = 0; i < sizeof numbers / sizeof numbers[0]; i++)
        if (!isfinite(numbers[i]))
            return fuzz_broken(why, whylen, "accepted a non-finite number (#%zu)", i);
    if (cfg->interval_s < 0 || cfg->retention_max_scans < 0 || cfg->retention_max_age_days < 0)
        return fuzz_broken(why, whylen, "accepted a negative schedule or retention");
    if (r->positions < 1 || r->digitiser.samples < 1 || r->digitiser.samples > UWB_FRAME_MAX_SAMPLES ||
        !(r->digitiser.sample_interval_s > 0) || r->digitiser.frame_timeout_ms < 1 ||
        r->digitiser.frame_retries < 0)
        return fuzz_broken(why, whylen,
                           "accepted %d positions, %d samples at %g s, timeout %d ms, %d retries",
                           r->positions, r->digitiser.samples, r->digitiser.sample_interval_s,
                           r->digitiser.frame_timeout_ms, r->digitiser.frame_retries);
    char err[512];
    if (uwb_rig_config_check(r, err, sizeof err) != UWB_RIG_OK)
        return fuzz_broken(why, whylen, "accepted, but the rig refuses it: %s", err);
    return FUZZ_ACCEPTED;
}

int fuzz_config_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    struct uwbd_config cfg;
    memset(&cfg, 0, sizeof cfg);
    why[0] = '\0';
    if (uwbd_config_parse((const char *)data, size, NAME, NULL, 0, &cfg, why, whylen) != 0) {
        if (strncmp(why, NAME ": ", strlen(NAME ": ")) != 0) {
            char message[256];
            snprintf(message, sizeof message, "%s", why);
            return fuzz_broken(why, whylen, "refused without naming the input: '%s'", message);
        }
        return FUZZ_REJECTED;
    }
    return check_config(&cfg, why, whylen);
}

UWB_FUZZ_TARGET(fuzz_config_input)
