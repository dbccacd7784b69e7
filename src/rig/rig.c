/* One scan cycle over the rig: home, then at every position move (from
 * below), settle, fire `stack` pulses each answered by one checked frame,
 * average; park, motor off, pulser idle. Whatever happens, the hardware is
 * left safe before returning. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <syslog.h>
#include <time.h>

#include "rig/carriage.h"
#include "uwb/digitiser.h"
#include "uwb/rig.h"
#include "uwb/scan_id.h"

struct uwb_rig {
    struct uwb_rig_config cfg;
    struct uwb_gpio *gpio;
    struct uwb_digitiser *dig;
    struct uwb_carriage carriage;
    uwb_rig_log_fn log;
    void *log_ctx;
    uwb_rig_progress_fn progress;
    void *progress_ctx;
    unsigned long scans;
    long last_scan_steps;
    double last_home_found_mm;
};

static void rig_log(struct uwb_rig *rig, int priority, const char *fmt, ...)
{
    if (!rig->log)
        return;
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    rig->log(rig->log_ctx, priority, msg);
}

void uwb_rig_set_log(struct uwb_rig *rig, uwb_rig_log_fn log, void *ctx)
{
    rig->log = log;
    rig->log_ctx = ctx;
}

void uwb_rig_set_progress(struct uwb_rig *rig, uwb_rig_progress_fn progress, void *ctx)
{
    rig->progress = progress;
    rig->progress_ctx = ctx;
}

int uwb_rig_open(const struct uwb_rig_config *cfg, struct uwb_rig **out, int *detail, char *err,
                 size_t errlen)
{
    *out = NULL;
    if (detail)
        *detail = 0;
    int rc = uwb_rig_config_check(cfg, err, errlen);
    if (rc != UWB_RIG_OK)
        return rc;
    struct uwb_rig *rig = calloc(1, sizeof *rig);
    if (!rig) {
        snprintf(err, errlen, "rig: out of memory");
        return UWB_RIG_ERR_CONFIG;
    }
    rig->cfg = *cfg;
    /* Step timing wants wake-ups near the deadline, not the default 50 us
     * of timer slack. */
    prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
    int gpio_rc = uwb_gpio_open(&cfg->gpio, &rig->gpio, err, errlen);
    if (gpio_rc != UWB_GPIO_OK) {
        if (detail)
            *detail = gpio_rc;
        free(rig);
        return UWB_RIG_ERR_GPIO;
    }
    int link_rc = UWB_LINK_OK;
    int dig_rc = uwb_digitiser_open(&cfg->digitiser, &rig->dig, &link_rc, err, errlen);
    if (dig_rc != UWB_DIGITISER_OK) {
        if (detail)
            *detail = link_rc;
        uwb_gpio_close(rig->gpio);
        free(rig);
        return dig_rc == UWB_DIGITISER_ERR_LINK ? UWB_RIG_ERR_LINK : UWB_RIG_ERR_DIGITISER;
    }
    *out = rig;
    return UWB_RIG_OK;
}

void uwb_rig_make_safe(struct uwb_rig *rig)
{
    if (!rig || !rig->gpio)
        return;
    char ignored[256];
    /* Each line on its own: one failing must not keep the others up. */
    uwb_gpio_set(rig->gpio, UWB_LINE_TRIGGER, 0, ignored, sizeof ignored);
    uwb_gpio_set(rig->gpio, UWB_LINE_STEP, 0, ignored, sizeof ignored);
    uwb_gpio_set(rig->gpio, UWB_LINE_ENABLE, 0, ignored, sizeof ignored);
}

void uwb_rig_close(struct uwb_rig *rig)
{
    if (!rig)
        return;
    uwb_rig_make_safe(rig);
    uwb_digitiser_close(rig->dig);
    uwb_gpio_close(rig->gpio);
    free(rig);
}

struct fire_ctx {
    struct uwb_rig *rig;
};

/* One trigger pulse; the pulser fires on the rising edge. */
static int fire(void *opaque, char *err, size_t errlen)
{
    struct uwb_rig *rig = ((struct fire_ctx *)opaque)->rig;
    if (uwb_gpio_set(rig->gpio, UWB_LINE_TRIGGER, 1, err, errlen) != UWB_GPIO_OK)
        return -1;
    struct uwb_pacer p;
    uwb_pacer_start(&p, rig->cfg.time_scale);
    uwb_pacer_wait_until(&p, rig->cfg.trigger_pulse_us * 1e-6);
    return uwb_gpio_set(rig->gpio, UWB_LINE_TRIGGER, 0, err, errlen) == UWB_GPIO_OK ? 0 : -1;
}

static int stop_requested(const volatile sig_atomic_t *stop, char *err, size_t errlen)
{
    if (stop && *stop) {
        snprintf(err, errlen, "scan stopped on request");
        return 1;
    }
    return 0;
}

static int dup_text(char **dst, const char *text)
{
    *dst = strdup(text);
    return *dst ? 0 : -1;
}

/* created (ISO-8601 UTC), scan_id (the asset and the same instant,
 * file-name safe, to the millisecond: uwb/scan_id.h) and source. */
static int fill_header(struct uwb_rig *rig, const struct timespec *started, struct uwb_scan *scan)
{
    const struct uwb_rig_config *cfg = &rig->cfg;
    struct tm tm;
    gmtime_r(&started->tv_sec, &tm);
    char created[64], scan_id[160], source[512];
    strftime(created, sizeof created, "%Y-%m-%dT%H:%M:%SZ", &tm);
    uwb_scan_id_make(scan_id, sizeof scan_id, cfg->asset_id, started->tv_sec, started->tv_nsec / 1000000);
    snprintf(source, sizeof source, "%s; digitiser '%s' at %s; gpio %s",
             cfg->source[0] ? cfg->source : "uwbd", uwb_digitiser_identity(rig->dig), cfg->digitiser.endpoint,
             cfg->gpio.backend);
    scan->sample_interval_s = cfg->digitiser.sample_interval_s;
    scan->t0_s = cfg->digitiser.t0_s;
    memcpy(scan->tx_m, cfg->tx_m, sizeof scan->tx_m);
    memcpy(scan->rx_m, cfg->rx_m, sizeof scan->rx_m);
    scan->eps_r = cfg->eps_r;
    scan->has_target_z = cfg->has_target_z;
    memcpy(scan->target_z_m, cfg->target_z_m, sizeof scan->target_z_m);
    scan->stack = cfg->digitiser.stack;
    return dup_text(&scan->created, created) || dup_text(&scan->scan_id, scan_id) ||
           dup_text(&scan->source, source);
}

/* The traces of one position, averaged over `stack` pulses, into out. */
static int acquire_position(struct uwb_rig *rig, const volatile sig_atomic_t *stop, int position, float *out,
                            double *sum, float *trace, char *err, size_t errlen)
{
    const struct uwb_digitiser_config *d = &rig->cfg.digitiser;
    struct fire_ctx ctx = {rig};
    memset(sum, 0, (size_t)d->samples * sizeof *sum);
    for (int p = 0; p < d->stack; p++) {
        if (stop_requested(stop, err, errlen))
            return UWB_RIG_ERR_STOPPED;
        unsigned long retries_before, retries_after;
        struct uwb_digitiser_stats st;
        uwb_digitiser_get_stats(rig->dig, &st);
        retries_before = st.retries;
        char why[768];
        int rc = uwb_digitiser_acquire(rig->dig, fire, &ctx, trace, why, sizeof why);
        if (rc == UWB_DIGITISER_ERR_FIRE) {
            snprintf(err, errlen, "position %d, pulse %d: trigger: %s", position, p + 1, why);
            return UWB_RIG_ERR_GPIO;
        }
        if (rc != UWB_DIGITISER_OK) {
            snprintf(err, errlen, "position %d, pulse %d: %s", position, p + 1, why);
            return UWB_RIG_ERR_DIGITISER;
        }
        uwb_digitiser_get_stats(rig->dig, &st);
        retries_after = st.retries;
        if (retries_after != retries_before)
            rig_log(rig, LOG_WARNING, "position %d, pulse %d: %lu frame%s bad or missing, fired again",
                    position, p + 1, retries_after - retries_before,
                    retries_after - retries_before == 1 ? "" : "s");
        for (int s = 0; s < d->samples; s++)
            sum[s] += trace[s];
    }
    for (int s = 0; s < d->samples; s++)
        out[s] = (float)(sum[s] / d->stack);
    return UWB_RIG_OK;
}

static int scan_cycle(struct uwb_rig *rig, const volatile sig_atomic_t *stop, struct uwb_scan *scan,
                      char *err, size_t errlen)
{
    const struct uwb_rig_config *cfg = &rig->cfg;
    const struct uwb_carriage_config *cc = &cfg->carriage;
    struct uwb_carriage *c = &rig->carriage;
    uwb_carriage_init(c, rig->gpio, cc, cfg->time_scale, stop);
    if (rig->progress)
        rig->progress(rig->progress_ctx, 0, cfg->positions);

    struct timespec started;
    clock_gettime(CLOCK_REALTIME, &started);
    if (uwb_scan_alloc(scan, cfg->positions, cfg->digitiser.samples, err, errlen) != 0)
        return UWB_RIG_ERR_CONFIG;
    double *sum = malloc((size_t)cfg->digitiser.samples * sizeof *sum);
    float *trace = malloc((size_t)cfg->digitiser.samples * sizeof *trace);
    int rc = UWB_RIG_OK;
    if (!sum || !trace) {
        snprintf(err, errlen, "scan: out of memory");
        rc = UWB_RIG_ERR_CONFIG;
    }
    if (rc == UWB_RIG_OK)
        rc = uwb_carriage_enable(c, 1, err, errlen);
    if (rc == UWB_RIG_OK && !stop_requested(stop, err, errlen)) {
        rc = uwb_carriage_home(c, err, errlen);
        rig->last_home_found_mm = c->home_found_mm;
        if (rc == UWB_RIG_OK)
            rig_log(rig, LOG_INFO, "homed after %.1f mm", c->home_found_mm);
    } else if (rc == UWB_RIG_OK) {
        rc = UWB_RIG_ERR_STOPPED;
    }
    struct uwb_pacer settle;
    uwb_pacer_start(&settle, cfg->time_scale);
    for (int k = 0; rc == UWB_RIG_OK && k < cfg->positions; k++) {
        double y_mm = cfg->first_position_mm + k * cfg->step_mm;
        rc = uwb_carriage_move_to(c, y_mm - cc->home_offset_mm, err, errlen);
        if (rc != UWB_RIG_OK)
            break;
        /* Where the carriage really is, to the microstep. */
        scan->antenna_y_m[k] = (cc->home_offset_mm + c->position / cc->steps_per_mm) / 1000.0;
        uwb_pacer_sleep(&settle, cc->settle_ms / 1000.0);
        rc = acquire_position(rig, stop, k, scan->data + (size_t)k * cfg->digitiser.samples, sum, trace, err,
                              errlen);
        /* Also the daemon's sign that its scan worker is alive (its watchdog). */
        if (rc == UWB_RIG_OK)
            rig_log(rig, LOG_DEBUG, "position %d of %d acquired", k + 1, cfg->positions);
        if (rc == UWB_RIG_OK && rig->progress)
            rig->progress(rig->progress_ctx, k + 1, cfg->positions);
    }
    if (rc == UWB_RIG_OK) {
        /* Lost steps would put every position elsewhere than recorded: the
         * home switch must agree with the count before the scan counts. */
        double off_mm;
        rc = uwb_carriage_check_home(c, &off_mm, err, errlen);
        if (rc == UWB_RIG_OK)
            rig_log(rig, LOG_INFO, "home switch within %.2f mm of the counted steps after the scan", off_mm);
    }
    if (rc == UWB_RIG_OK)
        rc = uwb_carriage_park(c, err, errlen);
    rig->last_scan_steps = c->steps_moved;
    free(sum);
    free(trace);
    if (rc == UWB_RIG_OK && fill_header(rig, &started, scan) != 0) {
        snprintf(err, errlen, "scan: out of memory");
        rc = UWB_RIG_ERR_CONFIG;
    }
    return rc;
}

int uwb_rig_scan(struct uwb_rig *rig, const volatile sig_atomic_t *stop, struct uwb_scan *out, char *err,
                 size_t errlen)
{
    memset(out, 0, sizeof *out);
    int rc = scan_cycle(rig, stop, out, err, errlen);
    uwb_rig_make_safe(rig);
    if (rc != UWB_RIG_OK) {
        uwb_scan_free(out);
        rig_log(rig, LOG_ERR, "scan failed: %s", err);
        return rc;
    }
    rig->scans++;
    struct uwb_digitiser_stats st;
    uwb_digitiser_get_stats(rig->dig, &st);
    rig_log(rig, LOG_INFO,
            "scan %s: %d positions x %d pulses, %ld steps; frames so far: %lu good, %lu retried",
            out->scan_id, rig->cfg.positions, rig->cfg.digitiser.stack, rig->last_scan_steps, st.traces,
            st.retries);
    return UWB_RIG_OK;
}

void uwb_rig_get_stats(const struct uwb_rig *rig, struct uwb_rig_stats *stats)
{
    struct uwb_digitiser_stats st;
    uwb_digitiser_get_stats(rig->dig, &st);
    memset(stats, 0, sizeof *stats);
    stats->scans = rig->scans;
    stats->traces = st.traces;
    stats->fired = st.fired;
    stats->retries = st.retries;
    stats->timeouts = st.timeouts;
    stats->bad_frames = st.bad_frames;
    stats->bad_payloads = st.bad_payloads;
    stats->stale = st.stale;
    stats->ahead = st.ahead;
    stats->reconnects = st.reconnects;
    stats->last_scan_steps = rig->last_scan_steps;
    stats->last_home_found_mm = rig->last_home_found_mm;
}
