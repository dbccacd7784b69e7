/* The daemon: one poll() loop over a signalfd (SIGTERM/SIGINT stop,
 * SIGHUP reloads the config), a timerfd (the schedule), the control socket
 * and its clients, and the serial console; scans run on a worker thread so
 * that commands are answered while the carriage moves. */
#ifndef UWB_DAEMON_DAEMON_H
#define UWB_DAEMON_DAEMON_H

#include <stddef.h>

#include "config/config_load.h"
#include "uwb/version.h"

#define UWBD_MAX_OVERRIDES 64

struct uwbd_options {
    const char *config_path;
    struct uwbd_override overrides[UWBD_MAX_OVERRIDES];
    size_t n_overrides;
    int log_level; /* syslog priority, UWBD_LOG_INFO by default */
    int use_syslog;
};

/* Runs until SIGTERM/SIGINT; returns an exit status (exit_codes.h). */
int uwbd_daemon_run(const struct uwbd_options *opt);

#endif
