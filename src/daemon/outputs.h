/* The daemon's outputs as modules of one table (outputs.c): each opens from
 * its own config section, hears every recorded verdict, registers the fds
 * it needs with the event loop, reloads on SIGHUP by its own rule and
 * closes. The table's order is the order they open, hear a verdict and
 * close: the site's contacts, textfile and MQTT before the control clients
 * hear the verdict line, and the Modbus server last. Each module keeps its
 * state in struct daemon, where the commands that reach it (`ack`,
 * `status`, MQTT commands, Modbus coils) find it too. */
#ifndef UWBD_DAEMON_OUTPUTS_H
#define UWBD_DAEMON_OUTPUTS_H

#include <stddef.h>

#include "daemon/event_loop.h"
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
    /* Registers its fds and hooks: 0, or -1 when the loop is full. */
    int (*watch)(struct daemon *d, struct uwbd_event_loop *loop);
    /* At exit or a failed start; safe when open did not run or failed. */
    void (*close)(struct daemon *d);
};

extern const struct uwbd_output_module uwbd_output_site;
extern const struct uwbd_output_module uwbd_output_clients;
extern const struct uwbd_output_module uwbd_output_modbus;
extern const struct uwbd_output_module uwbd_output_csv;

/* The CSV module's file: row (CRLF-terminated) appended after the header
 * and the newest old rows, max_rows in all (0: no limit), the file replaced
 * atomically. 0, or -1 with err naming the file. */
int uwbd_csv_file_add(const char *path, const char *row, int max_rows, char *err, size_t errlen);

/* The table walked in order. */
int uwbd_outputs_open(struct daemon *d);
void uwbd_outputs_reload(struct daemon *d, const struct uwbd_config *previous);
void uwbd_outputs_verdict(struct daemon *d, const char *json, double duration_s);
int uwbd_outputs_watch(struct daemon *d, struct uwbd_event_loop *loop);
void uwbd_outputs_close(struct daemon *d);

#endif
