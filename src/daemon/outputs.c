/* The output modules' table and its walks (see the header). A new output is
 * one file with its module and one row here. */
#include "daemon/outputs.h"

#include "daemon/output_contacts.h"
#include "daemon/output_csv.h"
#include "daemon/output_modbus.h"
#include "daemon/output_mqtt.h"
#include "daemon/output_site_io.h"
#include "daemon/output_textfile.h"
#include "util/log.h"

/* The order is what the modules rely on, said here only: the site's lines
 * before what drives them; the contacts before the textfile and MQTT's
 * health report, which carry their states; the textfile (the verdict
 * counts) before the health report. The control clients hear a verdict
 * after every module (daemon.c), so a client that reads the CSV file or
 * the registers on its verdict finds them written. */
static const struct uwbd_output_module *const modules[] = {
    &uwbd_output_site_io,     /* the site's lines, the event input */
    &uwbd_output_mqtt,        /* mqtt.*: the verdict line, before the contacts move (as ever) */
    &uwbd_output_contacts,    /* contacts.*: watch, alarm, fault; `contacts test` */
    &uwbd_output_textfile,    /* prometheus.*: after the contacts, whose states it carries */
    &uwbd_output_mqtt_health, /* mqtt.*: the health report, last of the site's */
    &uwbd_output_modbus,      /* registers read at each request: nothing to hear */
    &uwbd_output_csv,         /* csv.*: the verdict history for spreadsheets */
};
#define MODULE_COUNT (sizeof modules / sizeof modules[0])

int uwbd_outputs_open(const struct uwbd_daemon_port *port)
{
    for (size_t i = 0; i < MODULE_COUNT; i++) {
        int code = modules[i]->open ? modules[i]->open(port) : 0;
        if (code != 0)
            return code;
    }
    return 0;
}

void uwbd_outputs_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->reload)
            modules[i]->reload(port, previous);
}

void uwbd_outputs_verdict(const struct uwbd_daemon_port *port, const char *json, double duration_s)
{
    const struct uwb_verdict_record *latest = port->latest(port->daemon);
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->verdict)
            modules[i]->verdict(port, latest, json, duration_s);
}

void uwbd_outputs_report(const struct uwbd_daemon_port *port)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->report)
            modules[i]->report(port);
}

int uwbd_outputs_acknowledge(const struct uwbd_daemon_port *port, char *err, size_t errlen)
{
    if (uwbd_contacts_acknowledge(err, errlen) != 0)
        return -1;
    uwbd_outputs_report(port);
    return 0;
}

int uwbd_outputs_watch(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->watch && modules[i]->watch(port, loop) != 0) {
            uwbd_log(UWBD_LOG_ERR, "%s: the event loop is full (%d entries)", modules[i]->name,
                     UWBD_EVENT_LOOP_MAX);
            return -1;
        }
    return 0;
}

void uwbd_outputs_close(const struct uwbd_daemon_port *port)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->close)
            modules[i]->close(port);
}
