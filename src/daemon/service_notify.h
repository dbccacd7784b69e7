/* Telling the service manager (systemd, Type=notify) how the daemon is:
 * ready, its status line, stopping, and the watchdog's pings. Outside
 * systemd (no NOTIFY_SOCKET) every call does nothing. */
#ifndef UWB_DAEMON_SERVICE_NOTIFY_H
#define UWB_DAEMON_SERVICE_NOTIFY_H

/* Half the watchdog interval systemd asked for (WatchdogSec=, i.e.
 * WATCHDOG_USEC), in milliseconds: how often to ping; 0 = no watchdog. */
long uwbd_service_watchdog_ping_ms(void);

/* One notification, e.g. "READY=1\nSTATUS=idle", "WATCHDOG=1", "STOPPING=1". */
void uwbd_service_notify(const char *state);

/* STATUS=<text>, formatted. */
void uwbd_service_status(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
