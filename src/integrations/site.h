/* The site's integrations as the daemon sees them (src/integrations/site.c):
 * the alarm contacts, the event input and the Prometheus textfile as one object, opened at start, told of
 * every recorded verdict, asked to `ack`, ticking on a timer of its own while it reads the event input. It
 * reaches hardware only through the GPIO driver table, on a handle of its
 * own (the rig's belongs to the scan thread while it runs). */
#ifndef UWB_DAEMON_SITE_H
#define UWB_DAEMON_SITE_H

#include <stddef.h>

#include "config/config.h"
#include "integrations/mqtt_publisher.h"
#include "uwb/verdict_record.h"

struct uwbd_site;

/* The energised state of the three contacts, -1 where there are none. */
struct uwbd_contact_states {
    int watch, alarm, fault;
};

/* Opens the site's lines (none when no integration is on: *site is then
 * a valid object that does nothing). latest is the verdict
 * recorded before this start, or NULL: latched contacts come back from it.
 * Returns 0, or an enum uwb_gpio_error with err saying which line. */
int uwbd_site_open(struct uwbd_site **site, const struct uwbd_config *cfg,
                   const struct uwb_verdict_record *latest, char *err, size_t errlen);
/* A verdict was recorded, its scan cycle having taken duration_s: the
 * contacts follow its status and fault, the textfile its figures, MQTT
 * publishes its line (verdict_json, the text written from v). */
void uwbd_site_verdict(struct uwbd_site *site, const struct uwb_verdict_record *v, const char *verdict_json,
                       double duration_s);
/* `ack`: latched contacts fall back to what the latest verdict calls for.
 * Returns -1 (err says why) when there are no contacts. */
int uwbd_site_ack(struct uwbd_site *site, char *err, size_t errlen);
void uwbd_site_contact_states(const struct uwbd_site *site, struct uwbd_contact_states *out);
/* The timer the daemon polls for the site (-1: none), and what to do when
 * it fires: returns 1 when the event input asks for a scan. */
int uwbd_site_timer_fd(const struct uwbd_site *site);
int uwbd_site_tick(struct uwbd_site *site);
/* Commands from MQTT (mqtt.commands): an fd readable while some wait
 * (-1: none), the next (malloc'd, NULL when none), and the answer to one. */
int uwbd_site_command_fd(const struct uwbd_site *site);
char *uwbd_site_next_command(struct uwbd_site *site);
void uwbd_site_reply(struct uwbd_site *site, const char *reply_json);
/* The MQTT link for `status`: 1 with *out filled, 0 when MQTT is off. */
int uwbd_site_mqtt_link(struct uwbd_site *site, struct uwbd_mqtt_link *out);
/* Drives the contacts de-energised (the fault contact opens: the monitor
 * is stopping) and releases the lines. NULL is a no-op. */
void uwbd_site_close(struct uwbd_site *site);

#endif
