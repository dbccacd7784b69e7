/* The daemon's outputs as modules of one table (outputs.c): each opens from
 * its own config section, hears every recorded verdict, registers the fds
 * it needs with the event loop, reloads on SIGHUP by its own rule and
 * closes. Each keeps its own state and sees the daemon only through the
 * port it is given (output_module.h). The table's order, said once in
 * outputs.c, is the order they open, hear a verdict and close. */
#ifndef UWBD_DAEMON_OUTPUTS_H
#define UWBD_DAEMON_OUTPUTS_H

#include <stddef.h>

#include "daemon/output_module.h"

/* The table walked in order. */
int uwbd_outputs_open(const struct uwbd_daemon_port *port);
void uwbd_outputs_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous);
void uwbd_outputs_verdict(const struct uwbd_daemon_port *port, const char *json, double duration_s);
void uwbd_outputs_report(const struct uwbd_daemon_port *port);
int uwbd_outputs_watch(const struct uwbd_daemon_port *port, struct uwbd_event_loop *loop);
void uwbd_outputs_close(const struct uwbd_daemon_port *port);
/* `ack`: latched contacts fall back to what the latest verdict calls for,
 * then every module reports. -1 (err says why) when there are no contacts. */
int uwbd_outputs_acknowledge(const struct uwbd_daemon_port *port, char *err, size_t errlen);

#endif
