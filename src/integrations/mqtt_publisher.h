/* Verdicts and status to an MQTT broker (src/integrations/mqtt_publisher.c,
 * libmosquitto): PREFIX/ASSET/verdict carries each verdict line as `uwbd
 * ctl verdict` prints it, QoS 1, retained; PREFIX/ASSET/status is
 * "online" while connected, retained, and "offline" as the last will and
 * on a clean stop. Every verdict goes to an on-disk queue first
 * (STATE_DIR/mqtt-queue, bounded) and leaves it when the broker has
 * acknowledged it, one at a time and in order, so none is lost while the
 * broker is away or the daemon restarts. Reconnecting backs off from 1 s
 * to mqtt.reconnect_max_s. */
#ifndef UWB_DAEMON_MQTT_PUBLISHER_H
#define UWB_DAEMON_MQTT_PUBLISHER_H

#include <stddef.h>

#include "config/site_config.h"

struct uwbd_mqtt;

/* Starts connecting (in libmosquitto's thread); a broker that is not there
 * yet is no error. Returns 0, or -1 with err (the queue directory, the
 * password file, TLS files, out of memory, libmosquitto missing). */
int uwbd_mqtt_open(struct uwbd_mqtt **mqtt, const struct uwbd_site_config *cfg, const char *state_dir,
                   char *err, size_t errlen);
/* Queues one verdict line and sends what the queue holds when it can. */
void uwbd_mqtt_verdict(struct uwbd_mqtt *mqtt, const char *verdict_json);
/* With mqtt.commands: an eventfd that is readable while commands from
 * PREFIX/ASSET/cmd wait (-1 without), the next of them (malloc'd text, NULL
 * when none), and the answer to one, published on PREFIX/ASSET/reply. */
int uwbd_mqtt_command_fd(const struct uwbd_mqtt *mqtt);
char *uwbd_mqtt_next_command(struct uwbd_mqtt *mqtt);
void uwbd_mqtt_reply(struct uwbd_mqtt *mqtt, const char *reply_json);
/* The health report (one JSON line), on PREFIX/ASSET/health, retained:
 * sent now when connected, again on every (re)connection, and again each
 * time a queued verdict is delivered. Its "mqtt_queued", if present, is set
 * to the verdicts waiting when it is sent (not when it was made). */
void uwbd_mqtt_health(struct uwbd_mqtt *mqtt, const char *health_json);
/* Verdicts waiting for the broker. */
size_t uwbd_mqtt_queued(struct uwbd_mqtt *mqtt);
/* The link as `status` shows it: "connected", "connecting" (the first
 * attempt, or again after a loss) or "failing" with the last attempt's
 * reason (TLS handshake, refused by the broker with its code, unreachable
 * or no answer within 10 s), and the verdicts queued. Each kind of failure
 * is logged once until the link is up again. */
struct uwbd_mqtt_link {
    const char *state;
    char reason[512]; /* "" unless failing */
    size_t queued;
};
void uwbd_mqtt_link(struct uwbd_mqtt *mqtt, struct uwbd_mqtt_link *out);
/* Says "offline" (briefly waiting for the broker's acknowledgement) and
 * disconnects; what is queued stays on disk for the next start. NULL is a no-op. */
void uwbd_mqtt_close(struct uwbd_mqtt *mqtt);

#endif
