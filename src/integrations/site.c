/* The site's integrations behind one object (see the header): the alarm
 * contacts and the event input on the site's GPIO handle. A line that
 * fails (the emulated board's link went away) closes the handle, which is
 * opened again on the next tick or verdict; the contacts are then set
 * afresh from their state, so nothing is lost but time. */
#include "integrations/site.h"

#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "integrations/alarm_contacts.h"
#include "integrations/event_trigger.h"
#include "util/log.h"
#include "integrations/mqtt_publisher.h"
#include "integrations/prometheus_textfile.h"
#include "uwb/gpio.h"
#include "uwb/monotonic.h"
#include "uwb/utc_time.h"

/* How often a failed handle is opened again when nothing else ticks. */
#define REOPEN_S 5.0

struct uwbd_site {
    struct uwbd_site_config cfg;
    struct uwb_gpio *gpio; /* NULL: no lines, or closed after a failure */
    int failing;           /* log a lost handle once, not every retry */
    struct uwbd_contacts contacts;
    struct uwbd_event_trigger event;
    struct uwbd_prometheus_metrics prom;
    int prom_failing;       /* log a failing textfile once, not every verdict */
    struct uwbd_mqtt *mqtt; /* NULL: MQTT off */
    int timer_fd;
};

static const enum uwb_gpio_line contact_line[UWBD_CONTACT_COUNT] = {UWB_LINE_WATCH, UWB_LINE_ALARM,
                                                                    UWB_LINE_FAULT};

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
        if (uwb_gpio_set(s->gpio, contact_line[i], uwbd_contacts_energised(&s->contacts, i), err,
                         sizeof err) != UWB_GPIO_OK) {
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

/* The figures a verdict gives the textfile. */
static void prom_from_verdict(struct uwbd_prometheus_metrics *m, const struct uwb_verdict_record *v)
{
    int index = v ? uwbd_prometheus_status_index(uwb_status_name(v->status)) : -1;
    if (index < 0)
        return;
    m->has_verdict = 1;
    m->status = index;
    m->has_displacement = v->has_displacement;
    m->displacement_m = m->has_displacement ? v->axial_displacement_mm / 1e3 : 0;
    m->uncertainty_m = m->has_displacement ? v->uncertainty_mm / 1e3 : 0;
    m->has_edges = v->has_edges;
    m->lower_edge_m = m->has_edges ? v->lower_edge_mm / 1e3 : 0;
    m->upper_edge_m = m->has_edges ? v->upper_edge_mm / 1e3 : 0;
    m->has_height_change = v->has_height_change;
    m->height_change_m = m->has_height_change ? v->height_change_mm / 1e3 : 0;
    time_t created_s;
    m->created_s = 0;
    if (uwb_utc_parse(v->created, &created_s) == 0)
        m->created_s = (double)created_s;
}

static void write_textfile(struct uwbd_site *s)
{
    if (!s->cfg.prometheus_enabled)
        return;
    struct uwbd_contact_states st;
    uwbd_site_contact_states(s, &st);
    s->prom.has_contacts = s->cfg.contacts_enabled;
    s->prom.contact[0] = st.watch;
    s->prom.contact[1] = st.alarm;
    s->prom.contact[2] = st.fault;
    char err[512];
    if (uwbd_prometheus_write(s->cfg.prometheus_textfile, &s->prom, err, sizeof err) != 0) {
        if (!s->prom_failing)
            uwbd_log(UWBD_LOG_ERR, "prometheus textfile: %s (tried again at every verdict)", err);
        s->prom_failing = 1;
        return;
    }
    if (s->prom_failing)
        uwbd_log(UWBD_LOG_NOTICE, "prometheus textfile written again");
    s->prom_failing = 0;
}

/* The health report MQTT carries: whether the appliance is healthy (as the
 * fault contact says), the latest verdict's status, what waits for the
 * broker, when. */
static void publish_health(struct uwbd_site *s)
{
    if (!s->mqtt)
        return;
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return;
    char now[32];
    time_t t = time(NULL);
    struct tm tm;
    gmtime_r(&t, &tm);
    strftime(now, sizeof now, "%Y-%m-%dT%H:%M:%SZ", &tm);
    cJSON_AddStringToObject(o, "class", "HEALTH");
    cJSON_AddStringToObject(o, "asset_id", s->cfg.asset_id);
    cJSON_AddStringToObject(o, "time", now);
    cJSON_AddBoolToObject(o, "healthy", uwbd_contacts_energised(&s->contacts, UWBD_CONTACT_FAULT));
    if (s->prom.has_verdict)
        cJSON_AddStringToObject(o, "latest_status", uwbd_prometheus_status_name(s->prom.status));
    unsigned long verdicts = 0;
    for (int i = 0; i < UWBD_PROM_STATUSES; i++)
        verdicts += s->prom.verdicts[i];
    cJSON_AddNumberToObject(o, "verdicts_since_start", (double)verdicts);
    cJSON_AddNumberToObject(o, "mqtt_queued", (double)uwbd_mqtt_queued(s->mqtt));
    if (s->cfg.contacts_enabled) {
        cJSON *c = cJSON_AddObjectToObject(o, "contacts");
        for (int i = 0; i < UWBD_CONTACT_COUNT; i++)
            cJSON_AddBoolToObject(c, uwbd_contact_name(i), uwbd_contacts_energised(&s->contacts, i));
    }
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    uwbd_mqtt_health(s->mqtt, text);
    free(text);
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

int uwbd_site_open(struct uwbd_site **site, const struct uwbd_config *cfg,
                   const struct uwb_verdict_record *latest, char *err, size_t errlen)
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
    s->prom.asset_id = s->cfg.asset_id;
    if (latest)
        uwbd_contacts_restore(&s->contacts, uwb_status_name(latest->status));
    prom_from_verdict(&s->prom, latest);
    int rc = open_lines(s, err, errlen);
    if (rc != UWB_GPIO_OK) {
        free(s);
        return rc;
    }
    if (s->cfg.mqtt_enabled && uwbd_mqtt_open(&s->mqtt, &s->cfg, cfg->state_dir, err, errlen) != 0) {
        uwb_gpio_close(s->gpio);
        free(s);
        return UWB_GPIO_ERR_CONFIG;
    }
    if (s->cfg.io.lines) {
        s->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
        if (s->timer_fd < 0) {
            snprintf(err, errlen, "site: timerfd: out of resources");
            uwbd_mqtt_close(s->mqtt);
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
    write_textfile(s);
    publish_health(s);
    *site = s;
    return UWB_GPIO_OK;
}

void uwbd_site_verdict(struct uwbd_site *s, const struct uwb_verdict_record *v, const char *verdict_json,
                       double duration_s)
{
    if (!s || !v || !verdict_json)
        return;
    const char *status = uwb_status_name(v->status);
    uwbd_contacts_verdict(&s->contacts, status, v->fault[0] != '\0');
    prom_from_verdict(&s->prom, v);
    s->prom.has_duration = 1;
    s->prom.scan_duration_s = duration_s;
    int index = uwbd_prometheus_status_index(status);
    if (index >= 0)
        s->prom.verdicts[index]++;
    if (strcmp(v->cycle.trigger, "event") == 0)
        s->prom.event_scans++;
    uwbd_mqtt_verdict(s->mqtt, verdict_json);
    if (s->cfg.contacts_enabled) {
        reopen(s);
        drive_contacts(s);
    }
    write_textfile(s);
    publish_health(s);
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
    write_textfile(s);
    publish_health(s);
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
        uwbd_log(UWBD_LOG_WARNING,
                 "event input: active again within event.min_interval_s (%.0f s) of the last "
                 "event scan; no scan (%lu dropped so far)",
                 s->cfg.event_min_interval_s, s->event.suppressed);
        return 0;
    case UWBD_EVENT_NONE: break;
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
    uwbd_mqtt_close(s->mqtt);
    free(s);
}

int uwbd_site_command_fd(const struct uwbd_site *s)
{
    return s ? uwbd_mqtt_command_fd(s->mqtt) : -1;
}

char *uwbd_site_next_command(struct uwbd_site *s)
{
    return s ? uwbd_mqtt_next_command(s->mqtt) : NULL;
}

int uwbd_site_mqtt_link(struct uwbd_site *s, struct uwbd_mqtt_link *out)
{
    if (!s || !s->mqtt)
        return 0;
    uwbd_mqtt_link(s->mqtt, out);
    return 1;
}

void uwbd_site_reply(struct uwbd_site *s, const char *reply_json)
{
    if (s)
        uwbd_mqtt_reply(s->mqtt, reply_json);
}
