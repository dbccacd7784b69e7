/* MQTT as two output modules over one link (output_mqtt.c): the verdict
 * line and the health report. */
#ifndef UWBD_DAEMON_OUTPUT_MQTT_H
#define UWBD_DAEMON_OUTPUT_MQTT_H

#include "daemon/output_module.h"
#include "integrations/mqtt_publisher.h"

extern const struct uwbd_output_module uwbd_output_mqtt;
extern const struct uwbd_output_module uwbd_output_mqtt_health;

/* The MQTT link for `status`: 1 with *out filled, 0: MQTT off. */
int uwbd_mqtt_link_now(struct uwbd_mqtt_link *out);

#endif
