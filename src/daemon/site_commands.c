/* Commands from MQTT's cmd topic (mqtt.commands), run by the main loop:
 * what changes the appliance's state and needs no connection to wait on.
 * The MQTT module hands each over through its port (daemon.c) and sends
 * the answer back on the reply topic. */
#include <string.h>

#include "daemon_internal.h"
#include "control/command.h"
#include "daemon/output_contacts.h"
#include "daemon/outputs.h"
#include "util/log.h"
#include "control/reply.h"

char *uwbd_site_command(struct daemon *d, const char *text)
{
    struct uwb_command cmd;
    char err[160];
    int rc = uwb_command_parse(text, strlen(text), &cmd, err, sizeof err);
    if (rc == UWB_COMMAND_EMPTY)
        return uwbd_reply_error("empty command");
    if (rc != UWB_COMMAND_OK)
        return uwbd_reply_error(err);
    uwbd_log(UWBD_LOG_NOTICE, "mqtt: command %s", uwb_command_name(cmd.kind));
    int queued = d->scanning;
    switch (cmd.kind) {
    case UWB_COMMAND_SCAN:
    case UWB_COMMAND_EVENT:
        if (d->stopping)
            return uwbd_reply_error("the daemon is stopping; no new scan");
        uwbd_peers_request_scan(d, cmd.kind == UWB_COMMAND_EVENT ? TRIGGER_EVENT : TRIGGER_COMMAND);
        return cmd.kind == UWB_COMMAND_EVENT ? uwbd_reply_event(queued) : uwbd_reply_scan_requested(queued);
    case UWB_COMMAND_ACK: {
        struct uwbd_contact_states st;
        if (uwbd_outputs_acknowledge(&d->port, err, sizeof err) != 0)
            return uwbd_reply_error(err);
        uwbd_contact_states(&st);
        return uwbd_reply_ack(&st, d->latest);
    }
    case UWB_COMMAND_BASELINE_SET: return uwbd_baseline_request(d, cmd.count, cmd.force);
    default:
        return uwbd_reply_error("over MQTT only scan, event, ack and baseline set are taken (the verdict and "
                                "status topics carry the rest)");
    }
}
