/* The output modules' table and its walks (see the header). A new output is
 * one file with its module and one row here. */
#include "daemon/outputs.h"

#include <string.h>

#include "daemon_internal.h"
#include "util/log.h"

static const struct uwbd_output_module *const modules[] = {
    &uwbd_output_site_io,     /* the site's lines, the event input */
    &uwbd_output_mqtt,        /* mqtt.*: the verdict line, before the contacts move (as ever) */
    &uwbd_output_contacts,    /* contacts.*: watch, alarm, fault */
    &uwbd_output_textfile,    /* prometheus.*: after the contacts, whose states it carries */
    &uwbd_output_mqtt_health, /* mqtt.*: the health report, last of the site's */
    &uwbd_output_clients,     /* the control socket's clients and the console: the verdict line */
    &uwbd_output_modbus,      /* registers read at each request: nothing to hear */
    &uwbd_output_csv,         /* csv.*: the verdict history for spreadsheets */
};
#define MODULE_COUNT (sizeof modules / sizeof modules[0])

int uwbd_outputs_open(struct daemon *d)
{
    for (size_t i = 0; i < MODULE_COUNT; i++) {
        int code = modules[i]->open ? modules[i]->open(d) : 0;
        if (code != 0)
            return code;
    }
    return 0;
}

void uwbd_outputs_reload(struct daemon *d, const struct uwbd_config *previous)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->reload)
            modules[i]->reload(d, previous);
}

void uwbd_outputs_verdict(struct daemon *d, const char *json, double duration_s)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->verdict)
            modules[i]->verdict(d, d->latest, json, duration_s);
}

void uwbd_outputs_report(struct daemon *d)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->report)
            modules[i]->report(d);
}

int uwbd_site_changed(const struct daemon *d, const struct uwbd_config *previous)
{
    /* Byte comparison on purpose (see reload() in daemon.c): both sides are
     * zeroed before filling and copied with memcpy. */
    // NOLINTNEXTLINE(bugprone-suspicious-memory-comparison,cert-exp42-c,cert-flp37-c): padding zeroed, see above
    return memcmp(&previous->site, &d->cfg.site, sizeof d->cfg.site) != 0;
}

int uwbd_outputs_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->watch && modules[i]->watch(d, loop) != 0) {
            uwbd_log(UWBD_LOG_ERR, "%s: the event loop is full (%d entries)", modules[i]->name,
                     UWBD_EVENT_LOOP_MAX);
            return -1;
        }
    return 0;
}

void uwbd_outputs_close(struct daemon *d)
{
    for (size_t i = 0; i < MODULE_COUNT; i++)
        if (modules[i]->close)
            modules[i]->close(d);
}
