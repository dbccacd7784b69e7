/* The site's lines behind one handle (see the header). A line that fails
 * (the emulated board's link went away) closes the handle, which is opened
 * again on the next tick or contact change; the contacts are then set
 * afresh from the levels last asked for, so nothing is lost but time. */
#include "integrations/site_io.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "integrations/event_trigger.h"
#include "util/log.h"
#include "uwb/gpio.h"
#include "uwb/monotonic.h"

/* How often a failed handle is opened again when nothing else ticks. */
#define REOPEN_S 5.0
#define CONTACTS 3

struct uwbd_site_io {
    struct uwbd_site_config cfg;
    struct uwb_gpio *gpio; /* NULL: no lines, or closed after a failure */
    int failing;           /* log a lost handle once, not every retry */
    int has_contacts;      /* the contacts' levels were given */
    int energised[CONTACTS];
    struct uwbd_event_trigger event;
    int timer_fd;
};

static const enum uwb_gpio_line contact_line[CONTACTS] = {UWB_LINE_WATCH, UWB_LINE_ALARM, UWB_LINE_FAULT};

static void lost(struct uwbd_site_io *s, const char *err)
{
    if (!s->failing)
        uwbd_log(UWBD_LOG_ERR, "site lines: %s; opened again every %.0f s", err, REOPEN_S);
    s->failing = 1;
    uwb_gpio_close(s->gpio);
    s->gpio = NULL;
}

/* The contacts' lines from the levels given. */
static void drive_contacts(struct uwbd_site_io *s)
{
    if (!s->has_contacts || !s->gpio)
        return;
    char err[512];
    for (int i = 0; i < CONTACTS; i++)
        if (uwb_gpio_set(s->gpio, contact_line[i], s->energised[i], err, sizeof err) != UWB_GPIO_OK) {
            lost(s, err);
            return;
        }
}

static int open_lines(struct uwbd_site_io *s, char *err, size_t errlen)
{
    if (s->gpio || !s->cfg.io.lines)
        return UWB_GPIO_OK;
    int rc = uwb_gpio_open(&s->cfg.io, &s->gpio, err, errlen);
    if (rc != UWB_GPIO_OK) {
        s->gpio = NULL;
        return rc;
    }
    if (s->failing)
        uwbd_log(UWBD_LOG_NOTICE, "site lines open again");
    s->failing = 0;
    drive_contacts(s);
    return UWB_GPIO_OK;
}

static void reopen(struct uwbd_site_io *s)
{
    char err[512];
    if (!s->gpio && s->cfg.io.lines && open_lines(s, err, sizeof err) != UWB_GPIO_OK)
        lost(s, err);
}

static void arm_timer(struct uwbd_site_io *s)
{
    double every = s->cfg.event_enabled ? s->cfg.event_poll_s : REOPEN_S;
    struct timespec ts = {.tv_sec = (time_t)every, .tv_nsec = (long)((every - (double)(time_t)every) * 1e9)};
    if (ts.tv_sec == 0 && ts.tv_nsec == 0)
        ts.tv_nsec = 1000000;
    struct itimerspec its = {.it_value = ts, .it_interval = ts};
    timerfd_settime(s->timer_fd, 0, &its, NULL);
}

int uwbd_site_io_open(struct uwbd_site_io **io, const struct uwbd_site_config *cfg, char *err, size_t errlen)
{
    *io = NULL;
    struct uwbd_site_io *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "site: out of memory");
        return UWB_GPIO_ERR_CONFIG;
    }
    s->cfg = *cfg;
    s->timer_fd = -1;
    uwbd_event_trigger_init(&s->event, s->cfg.event_debounce_s, s->cfg.event_min_interval_s);
    int rc = open_lines(s, err, errlen);
    if (rc != UWB_GPIO_OK)
        goto fail;
    if (s->cfg.io.lines) {
        s->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
        if (s->timer_fd < 0) {
            snprintf(err, errlen, "site: timerfd: out of resources");
            rc = UWB_GPIO_ERR_CONFIG;
            goto fail;
        }
        arm_timer(s);
    }
    *io = s;
    return UWB_GPIO_OK;
fail:
    uwb_gpio_close(s->gpio);
    free(s);
    return rc;
}

void uwbd_site_io_contacts(struct uwbd_site_io *s, const int energised[3])
{
    if (!s)
        return;
    s->has_contacts = 1;
    for (int i = 0; i < CONTACTS; i++)
        s->energised[i] = energised[i];
    reopen(s);
    drive_contacts(s);
}

int uwbd_site_io_timer_fd(const struct uwbd_site_io *s)
{
    return s ? s->timer_fd : -1;
}

int uwbd_site_io_tick(struct uwbd_site_io *s)
{
    uint64_t count;
    if (!s || read(s->timer_fd, &count, sizeof count) != sizeof count)
        return 0;
    reopen(s);
    if (!s->cfg.event_enabled || !s->gpio)
        return 0;
    int active = 0;
    char err[512];
    if (uwb_gpio_get(s->gpio, UWB_LINE_EVENT, &active, err, sizeof err) != UWB_GPIO_OK) {
        lost(s, err);
        return 0;
    }
    switch (uwbd_event_trigger_sample(&s->event, active, uwb_monotonic_s())) {
    case UWBD_EVENT_FIRE:
        uwbd_log(UWBD_LOG_NOTICE, "event input: active for %.0f ms; a scan follows as soon as possible",
                 s->cfg.event_debounce_s * 1e3);
        return 1;
    case UWBD_EVENT_SUPPRESSED:
        uwbd_log(UWBD_LOG_WARNING,
                 "event input: active again within event.min_interval_s (%.0f s) of the last "
                 "event scan; no scan (%lu dropped so far)",
                 s->cfg.event_min_interval_s, s->event.suppressed);
        return 0;
    case UWBD_EVENT_NONE: break;
    }
    return 0;
}

void uwbd_site_io_close(struct uwbd_site_io *s)
{
    if (!s)
        return;
    /* uwb_gpio_close drives every output low: contacts de-energised, so the
     * fault contact reports the monitor gone. */
    uwb_gpio_close(s->gpio);
    if (s->timer_fd >= 0)
        close(s->timer_fd);
    free(s);
}
