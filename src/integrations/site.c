/* The site's integrations behind one object (see the header): the alarm
 * contacts and the event input on the site's GPIO handle. A line that
 * fails (the emulated board's link went away) closes the handle, which is
 * opened again on the next tick or verdict; the contacts are then set
 * afresh from their state, so nothing is lost but time. */
#include "uwb/daemon/site.h"

#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "uwb/daemon/alarm_contacts.h"
#include "uwb/daemon/event_trigger.h"
#include "uwb/daemon/log.h"
#include "uwb/gpio.h"
#include "uwb/monotonic.h"

/* How often a failed handle is opened again when nothing else ticks. */
#define REOPEN_S 5.0

struct uwbd_site {
    struct uwbd_site_config cfg;
    struct uwb_gpio *gpio;         /* NULL: no lines, or closed after a failure */
    int failing;                   /* log a lost handle once, not every retry */
    struct uwbd_contacts contacts;
    struct uwbd_event_trigger event;
    int timer_fd;
};

static const enum uwb_gpio_line contact_line[UWBD_CONTACT_COUNT] = {UWB_LINE_WATCH, UWB_LINE_ALARM, UWB_LINE_FAULT};

static void lost(struct uwbd_site *s, const char *err)
{
    if (!s->failing)
        uwbd_log(UWBD_LOG_ERR, "site lines: %s; opened again every %.0f s", err, REOPEN_S);
    s->failing = 1;
    uwb_gpio_close(s->gpio);
    s->gpio = NULL;
}

/* The contacts' lines from their state. */
static void drive_contacts(struct uwbd_site *s)
{
    if (!s->cfg.contacts_enabled || !s->gpio)
        return;
    char err[512];
    for (int i = 0; i < UWBD_CONTACT_COUNT; i++)
        if (uwb_gpio_set(s->gpio, contact_line[i], uwbd_contacts_energised(&s->contacts, i), err, sizeof err) !=
            UWB_GPIO_OK) {
            lost(s, err);
            return;
        }
}

static int open_lines(struct uwbd_site *s, char *err, size_t errlen)
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

static void reopen(struct uwbd_site *s)
{
    char err[512];
    if (!s->gpio && s->cfg.io.lines && open_lines(s, err, sizeof err) != UWB_GPIO_OK)
        lost(s, err);
}

static void arm_timer(struct uwbd_site *s)
{
    double every = s->cfg.event_enabled ? s->cfg.event_poll_s : REOPEN_S;
    struct timespec ts = {.tv_sec = (time_t)every, .tv_nsec = (long)((every - (double)(time_t)every) * 1e9)};
    if (ts.tv_sec == 0 && ts.tv_nsec == 0)
        ts.tv_nsec = 1000000;
    struct itimerspec its = {.it_value = ts, .it_interval = ts};
    timerfd_settime(s->timer_fd, 0, &its, NULL);
}

static const char *verdict_status(const cJSON *v, int *device_fault)
{
    const cJSON *status = cJSON_GetObjectItemCaseSensitive(v, "status");
    *device_fault = cJSON_IsString(cJSON_GetObjectItemCaseSensitive(v, "fault"));
    return cJSON_IsString(status) ? status->valuestring : NULL;
}

int uwbd_site_open(struct uwbd_site **site, const struct uwbd_config *cfg, const char *latest_verdict, char *err,
                   size_t errlen)
{
    *site = NULL;
    struct uwbd_site *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "site: out of memory");
        return UWB_GPIO_ERR_CONFIG;
    }
    s->cfg = cfg->site;
    s->timer_fd = -1;
    uwbd_contacts_init(&s->contacts, s->cfg.watch_latch, s->cfg.alarm_latch);
    uwbd_event_trigger_init(&s->event, s->cfg.event_debounce_s, s->cfg.event_min_interval_s);
    cJSON *latest = latest_verdict ? cJSON_Parse(latest_verdict) : NULL;
    int fault;
    const char *status = verdict_status(latest, &fault);
    if (status)
        uwbd_contacts_restore(&s->contacts, status);
    cJSON_Delete(latest);
    int rc = open_lines(s, err, errlen);
    if (rc != UWB_GPIO_OK) {
        free(s);
        return rc;
    }
    if (s->cfg.io.lines) {
        s->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
        if (s->timer_fd < 0) {
            snprintf(err, errlen, "site: timerfd: out of resources");
            uwb_gpio_close(s->gpio);
            free(s);
            return UWB_GPIO_ERR_CONFIG;
        }
        arm_timer(s);
    }
    if (s->cfg.contacts_enabled)
        uwbd_log(UWBD_LOG_INFO, "alarm contacts: watch %d, alarm %d, fault %d (energised = 1)",
                 uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_WATCH),
                 uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_ALARM),
                 uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_FAULT));
    *site = s;
    return UWB_GPIO_OK;
}

void uwbd_site_verdict(struct uwbd_site *s, const char *verdict_json)
{
    if (!s || !s->cfg.contacts_enabled)
        return;
    cJSON *v = verdict_json ? cJSON_Parse(verdict_json) : NULL;
    int fault;
    const char *status = verdict_status(v, &fault);
    if (status)
        uwbd_contacts_verdict(&s->contacts, status, fault);
    cJSON_Delete(v);
    if (!status)
        return;
    reopen(s);
    drive_contacts(s);
}

int uwbd_site_ack(struct uwbd_site *s, char *err, size_t errlen)
{
    if (!s || !s->cfg.contacts_enabled) {
        snprintf(err, errlen, "ack: there are no alarm contacts to acknowledge (contacts.enabled is false)");
        return -1;
    }
    uwbd_contacts_ack(&s->contacts);
    reopen(s);
    drive_contacts(s);
    uwbd_log(UWBD_LOG_NOTICE, "alarm contacts acknowledged: watch %d, alarm %d",
             uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_WATCH),
             uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_ALARM));
    return 0;
}

void uwbd_site_contact_states(const struct uwbd_site *s, struct uwbd_contact_states *out)
{
    int on = s && s->cfg.contacts_enabled;
    out->watch = on ? uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_WATCH) : -1;
    out->alarm = on ? uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_ALARM) : -1;
    out->fault = on ? uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_FAULT) : -1;
}

int uwbd_site_timer_fd(const struct uwbd_site *s)
{
    return s ? s->timer_fd : -1;
}

int uwbd_site_tick(struct uwbd_site *s)
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
        uwbd_log(UWBD_LOG_WARNING, "event input: active again within event.min_interval_s (%.0f s) of the last "
                                   "event scan; no scan (%lu dropped so far)",
                 s->cfg.event_min_interval_s, s->event.suppressed);
        return 0;
    case UWBD_EVENT_NONE:
        break;
    }
    return 0;
}

void uwbd_site_close(struct uwbd_site *s)
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
