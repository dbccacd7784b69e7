/* The daemon's outputs as modules of one table (outputs.c): each opens from
 * its own config section, hears every recorded verdict, registers the fds
 * it needs with the event loop, reloads on SIGHUP by its own rule and
 * closes. The table's order is the order they open, hear a verdict and
 * close: the site's lines (event input), MQTT's verdict line, the alarm
 * contacts, the Prometheus textfile and MQTT's health report (which carry
 * the contacts' states and the verdict counts, read through the functions
 * below), then the control clients' verdict line, Modbus and the CSV file.
 * Each module keeps its state in struct daemon, where the commands that
 * reach it (`ack`, `status`, MQTT commands, Modbus coils) find it too. */
#ifndef UWBD_DAEMON_OUTPUTS_H
#define UWBD_DAEMON_OUTPUTS_H

#include <stddef.h>

#include "loop/event_loop.h"
#include "integrations/mqtt_publisher.h"
#include "integrations/site_io.h"
#include "uwb/verdict_record.h"

struct daemon;
struct uwbd_config;

struct uwbd_output_module {
    const char *name;
    /* At start, after the hardware and the latest verdict: 0, or the exit
     * code the daemon stops with (the module logged why). */
    int (*open)(struct daemon *d);
    /* A reload was applied; previous: the configuration before it. */
    void (*reload)(struct daemon *d, const struct uwbd_config *previous);
    /* A scan cycle ended with verdict line json (NULL: none could be
     * written) and record v (d->latest), having taken duration_s. */
    void (*verdict)(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                    double duration_s);
    /* The contacts changed outside a verdict (`ack`): report them again. */
    void (*report)(struct daemon *d);
    /* Registers its fds and hooks: 0, or -1 when the loop is full. */
    int (*watch)(struct daemon *d, struct uwbd_event_loop *loop);
    /* At exit or a failed start; safe when open did not run or failed. */
    void (*close)(struct daemon *d);
};

extern const struct uwbd_output_module uwbd_output_site_io;
extern const struct uwbd_output_module uwbd_output_mqtt;
extern const struct uwbd_output_module uwbd_output_contacts;
extern const struct uwbd_output_module uwbd_output_textfile;
extern const struct uwbd_output_module uwbd_output_mqtt_health;
extern const struct uwbd_output_module uwbd_output_clients;
extern const struct uwbd_output_module uwbd_output_modbus;
extern const struct uwbd_output_module uwbd_output_csv;

/* The CSV module's file: row (CRLF-terminated) appended after the header
 * and the newest old rows, max_rows in all (0: no limit), the file replaced
 * atomically. 0, or -1 with err naming the file. */
int uwbd_csv_file_add(const char *path, const char *row, int max_rows, char *err, size_t errlen);

/* Facts the site's modules share. The contacts' states (-1 where there
 * are none); whether the appliance is healthy (the fault contact's state,
 * contacts or not); the latest status (NULL: none) and the verdicts since
 * start; the MQTT link for `status` (1 with *out filled, 0: MQTT off). */
void uwbd_contact_states(const struct daemon *d, struct uwbd_contact_states *out);
int uwbd_appliance_healthy(const struct daemon *d);
const char *uwbd_latest_status(const struct daemon *d);
unsigned long uwbd_verdicts_since_start(const struct daemon *d);
int uwbd_mqtt_link_now(const struct daemon *d, struct uwbd_mqtt_link *out);
/* `ack`: latched contacts fall back to what the latest verdict calls for,
 * then every module reports. -1 (err says why) when there are no contacts. */
int uwbd_contacts_acknowledge(struct daemon *d, char *err, size_t errlen);
/* The contact lines set from the logic (when there are contacts and no
 * `contacts test` holds them). */
void uwbd_contacts_drive(struct daemon *d);
/* Whether a reload changed the site's configuration (site.*, contacts.*,
 * event.*, prometheus.*, mqtt.*): the site's modules open again only then. */
int uwbd_site_changed(const struct daemon *d, const struct uwbd_config *previous);

/* The table walked in order. */
int uwbd_outputs_open(struct daemon *d);
void uwbd_outputs_reload(struct daemon *d, const struct uwbd_config *previous);
void uwbd_outputs_verdict(struct daemon *d, const char *json, double duration_s);
void uwbd_outputs_report(struct daemon *d);
int uwbd_outputs_watch(struct daemon *d, struct uwbd_event_loop *loop);
void uwbd_outputs_close(struct daemon *d);

#endif
