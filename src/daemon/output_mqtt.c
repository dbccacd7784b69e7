/* MQTT as two modules over one link (mqtt.*): the verdict line, published
 * before the contacts move, and the health report, published after the
 * contacts and the textfile (it carries the contacts' states and the
 * verdict counts). Commands from the cmd topic run in site_commands.c.
 * Opened again on a reload only when the site's configuration changed. */
#include <cjson/cJSON.h>
#include <poll.h>
#include <stdlib.h>
#include <time.h>

#include "control/exit_codes.h"
#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

static int mqtt_start(struct daemon *d, char *err, size_t errlen)
{
    if (!d->cfg.site.mqtt_enabled)
        return 0;
    return uwbd_mqtt_open(&d->mqtt, &d->cfg.site, d->cfg.state_dir, err, errlen);
}

static int mqtt_open(struct daemon *d)
{
    char err[1024];
    if (mqtt_start(d, err, sizeof err) == 0)
        return 0;
    int code = uwbd_exit_for_rig_open(UWB_RIG_ERR_GPIO, UWB_GPIO_ERR_CONFIG);
    uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
    return code;
}

static void mqtt_close(struct daemon *d)
{
    uwbd_mqtt_close(d->mqtt);
    d->mqtt = NULL;
}

static void mqtt_reload(struct daemon *d, const struct uwbd_config *previous)
{
    if (!uwbd_site_changed(d, previous))
        return;
    mqtt_close(d);
    char err[1024];
    if (mqtt_start(d, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "reload: %s; MQTT is off until the next reload", err);
}

static void mqtt_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                         double duration_s)
{
    (void)duration_s;
    if (json && v)
        uwbd_mqtt_verdict(d->mqtt, json);
}

static void mqtt_commands(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    uwbd_run_site_commands(ctx);
}

/* The link changes when a reload opens it again; commands wait while the daemon stops. */
static int mqtt_prepare(void *ctx)
{
    struct daemon *d = ctx;
    uwbd_event_loop_set(&d->events, d->mqtt_command_id, d->stopping ? -1 : uwbd_mqtt_command_fd(d->mqtt),
                        POLLIN);
    return -1;
}

static int mqtt_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    d->mqtt_command_id = uwbd_event_loop_add(loop, -1, POLLIN, mqtt_commands, d);
    if (d->mqtt_command_id < 0)
        return -1;
    return uwbd_event_loop_add_hook(loop, mqtt_prepare, NULL, d) < 0 ? -1 : 0;
}

int uwbd_mqtt_link_now(const struct daemon *d, struct uwbd_mqtt_link *out)
{
    if (!d->mqtt)
        return 0;
    uwbd_mqtt_link(d->mqtt, out);
    return 1;
}

const struct uwbd_output_module uwbd_output_mqtt = {
    .name = "mqtt",
    .open = mqtt_open,
    .reload = mqtt_reload,
    .verdict = mqtt_verdict,
    .watch = mqtt_watch,
    .close = mqtt_close,
};

/* The health report: whether the appliance is healthy (as the fault
 * contact says), the latest verdict's status, what waits for the broker,
 * when. */
static void publish_health(struct daemon *d)
{
    if (!d->mqtt)
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
    cJSON_AddStringToObject(o, "asset_id", d->cfg.site.asset_id);
    cJSON_AddStringToObject(o, "time", now);
    cJSON_AddBoolToObject(o, "healthy", uwbd_appliance_healthy(d));
    const char *latest = uwbd_latest_status(d);
    if (latest)
        cJSON_AddStringToObject(o, "latest_status", latest);
    cJSON_AddNumberToObject(o, "verdicts_since_start", (double)uwbd_verdicts_since_start(d));
    cJSON_AddNumberToObject(o, "mqtt_queued", (double)uwbd_mqtt_queued(d->mqtt));
    if (d->cfg.site.contacts_enabled) {
        struct uwbd_contact_states st;
        uwbd_contact_states(d, &st);
        const int energised[UWBD_CONTACT_COUNT] = {st.watch, st.alarm, st.fault};
        cJSON *c = cJSON_AddObjectToObject(o, "contacts");
        for (int i = 0; i < UWBD_CONTACT_COUNT; i++)
            cJSON_AddBoolToObject(c, uwbd_contact_name(i), energised[i]);
    }
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    uwbd_mqtt_health(d->mqtt, text);
    free(text);
}

static int health_open(struct daemon *d)
{
    publish_health(d);
    return 0;
}

static void health_reload(struct daemon *d, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(d, previous))
        publish_health(d);
}

static void health_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                           double duration_s)
{
    (void)duration_s;
    if (json && v)
        publish_health(d);
}

const struct uwbd_output_module uwbd_output_mqtt_health = {
    .name = "mqtt health",
    .open = health_open,
    .reload = health_reload,
    .verdict = health_verdict,
    .report = publish_health,
};
