/* MQTT as two modules over one link (mqtt.*): the verdict line, published
 * before the contacts move, and the health report, published after the
 * contacts and the textfile (it carries the contacts' states and the
 * verdict counts). Commands from the cmd topic go to the daemon (its
 * port's site_command: site_commands.c), their replies back.
 * Opened again on a reload only when the site's configuration changed. */
#include "daemon/output_mqtt.h"

#include <cjson/cJSON.h>
#include <poll.h>
#include <stdlib.h>
#include <time.h>

#include "control/exit_codes.h"
#include "daemon/output_contacts.h"
#include "daemon/output_textfile.h"
#include "util/log.h"

static struct uwbd_mqtt *mqtt; /* NULL: MQTT off */
static int command_id = -1;    /* the cmd topic's fd in the main loop */

static int mqtt_start(const struct uwbd_daemon_port *port, char *err, size_t errlen)
{
    if (!port->cfg->site.mqtt_enabled)
        return 0;
    return uwbd_mqtt_open(&mqtt, &port->cfg->site, port->cfg->state_dir, err, errlen);
}

static int mqtt_open(const struct uwbd_daemon_port *port)
{
    char err[1024];
    if (mqtt_start(port, err, sizeof err) == 0)
        return 0;
    int code = uwbd_exit_for_rig_open(UWB_RIG_ERR_GPIO, UWB_GPIO_ERR_CONFIG);
    uwbd_log(UWBD_LOG_ERR, "%s (exit %d)", err, code);
    return code;
}

static void mqtt_close(const struct uwbd_daemon_port *port)
{
    (void)port;
    uwbd_mqtt_close(mqtt);
    mqtt = NULL;
}

static void mqtt_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous)
{
    if (!uwbd_site_changed(port->cfg, previous))
        return;
    mqtt_close(port);
    char err[1024];
    if (mqtt_start(port, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "reload: %s; MQTT is off until the next reload", err);
}

static void mqtt_verdict(const struct uwbd_daemon_port *port, const struct uwb_verdict_record *v,
                         const char *json, double duration_s)
{
    (void)port, (void)duration_s;
    if (json && v)
        uwbd_mqtt_verdict(mqtt, json);
}

/* The commands the cmd topic brought, each answered on the reply topic. */
static void mqtt_commands(void *ctx, int fd, short revents)
{
    (void)fd, (void)revents;
    const struct uwbd_daemon_port *port = ctx;
    char *text;
    while ((text = uwbd_mqtt_next_command(mqtt))) {
        char *reply = port->site_command(port->daemon, text);
        uwbd_mqtt_reply(mqtt, reply);
        free(reply);
        free(text);
    }
}

/* The link changes when a reload opens it again; commands wait while the daemon stops. */
static int mqtt_prepare(void *ctx)
{
    const struct uwbd_daemon_port *port = ctx;
    uwbd_event_loop_set(port->events, command_id,
                        port->stopping(port->daemon) ? -1 : uwbd_mqtt_command_fd(mqtt), POLLIN);
    return -1;
}

static int mqtt_watch(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop)
{
    command_id = uwbd_event_loop_add(loop, -1, POLLIN, mqtt_commands, (void *)port);
    if (command_id < 0)
        return -1;
    return uwbd_event_loop_add_hook(loop, mqtt_prepare, NULL, (void *)port) < 0 ? -1 : 0;
}

int uwbd_mqtt_link_now(struct uwbd_mqtt_link *out)
{
    if (!mqtt)
        return 0;
    uwbd_mqtt_link(mqtt, out);
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
static void publish_health(const struct uwbd_daemon_port *port)
{
    if (!mqtt)
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
    cJSON_AddStringToObject(o, "asset_id", port->cfg->site.asset_id);
    cJSON_AddStringToObject(o, "time", now);
    cJSON_AddBoolToObject(o, "healthy", uwbd_appliance_healthy());
    const char *latest = uwbd_latest_status();
    if (latest)
        cJSON_AddStringToObject(o, "latest_status", latest);
    cJSON_AddNumberToObject(o, "verdicts_since_start", (double)uwbd_verdicts_since_start());
    cJSON_AddNumberToObject(o, "mqtt_queued", (double)uwbd_mqtt_queued(mqtt));
    if (port->cfg->site.contacts_enabled) {
        struct uwbd_contact_states st;
        uwbd_contact_states(&st);
        const int energised[UWBD_CONTACT_COUNT] = {st.watch, st.alarm, st.fault};
        cJSON *c = cJSON_AddObjectToObject(o, "contacts");
        for (int i = 0; i < UWBD_CONTACT_COUNT; i++)
            cJSON_AddBoolToObject(c, uwbd_contact_name(i), energised[i]);
    }
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    uwbd_mqtt_health(mqtt, text);
    free(text);
}

static int health_open(const struct uwbd_daemon_port *port)
{
    publish_health(port);
    return 0;
}

static void health_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(port->cfg, previous))
        publish_health(port);
}

static void health_verdict(const struct uwbd_daemon_port *port, const struct uwb_verdict_record *v,
                           const char *json, double duration_s)
{
    (void)duration_s;
    if (json && v)
        publish_health(port);
}

const struct uwbd_output_module uwbd_output_mqtt_health = {
    .name = "mqtt health",
    .open = health_open,
    .reload = health_reload,
    .verdict = health_verdict,
    .report = publish_health,
};
