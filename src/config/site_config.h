/* What the daemon tells the site (src/integrations/): the asset's name,
 * the alarm contacts, the event input, the Prometheus textfile. Every
 * integration is off by default; one that is on without what it needs
 * (its lines or endpoint, its file, the asset id) is refused at load with
 * the key named (uwbd_site_config_check). */
#ifndef UWB_CONFIG_SITE_CONFIG_H
#define UWB_CONFIG_SITE_CONFIG_H

#include <stddef.h>

#include "uwb/gpio.h"

/* An asset id names MQTT topics and metrics: letters, digits, . _ - only. */
#define UWBD_ASSET_ID_MAX 64
#define UWBD_SITE_PATH_MAX 1024

struct uwbd_site_config {
    char asset_id[UWBD_ASSET_ID_MAX]; /* "": not set */
    /* The site's GPIO handle: its backend and chip are the rig's (gpio.*);
     * its lines (contacts.lines.*, event.line), their active levels and, on
     * the emulated board, its endpoint (gpio.site_endpoint) are its own. */
    struct uwb_gpio_config io;

    int contacts_enabled;
    int watch_latch, alarm_latch; /* stays energised after the condition clears, until `ack` */

    int event_enabled;
    double event_debounce_s;     /* the input must read active this long */
    double event_min_interval_s; /* at most one event scan per this long */
    double event_poll_s;         /* how often the input is read */

    int prometheus_enabled;
    char prometheus_textfile[UWBD_SITE_PATH_MAX]; /* node_exporter's textfile directory/NAME.prom */

    int mqtt_enabled;
    char mqtt_endpoint[UWB_ENDPOINT_MAX];        /* tcp:HOST:PORT of the broker */
    char mqtt_username[64];                      /* "": anonymous */
    char mqtt_password_file[UWBD_SITE_PATH_MAX]; /* the password, one line, readable by the service only */
    char mqtt_ca_file[UWBD_SITE_PATH_MAX];       /* "": no TLS */
    char mqtt_cert_file[UWBD_SITE_PATH_MAX];     /* client certificate, with mqtt_key_file */
    char mqtt_key_file[UWBD_SITE_PATH_MAX];
    char mqtt_topic_prefix[64];
    int mqtt_queue_max;          /* verdicts kept on disk while the broker is away */
    double mqtt_reconnect_max_s; /* the back-off's ceiling */
    int mqtt_commands;           /* take scan, event, ack, baseline set from PREFIX/ASSET/cmd */
};

struct uwbd_config;

/* Checks that need more than one key. Returns 0, or -1 with `key` naming
 * the key at fault and `why` the problem. */
int uwbd_site_config_check(const struct uwbd_config *cfg, const char **key, char *why, size_t whylen);
/* Whether any integration is on (then site.asset_id is required). */
int uwbd_site_any_enabled(const struct uwbd_config *cfg);
/* Fills cfg->site.io's backend, chip and line mask from the rig's GPIO and
 * the enabled integrations (after loading). */
void uwbd_site_config_finish(struct uwbd_config *cfg);

#endif
