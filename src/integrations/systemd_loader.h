/* libsystemd's sd_notify family, loaded only when the service manager
 * asks for notifications (NOTIFY_SOCKET or WATCHDOG_USEC in the
 * environment; see library_loader.h). The entries have the types
 * sd-daemon.h declares. */
#ifndef UWBD_INTEGRATIONS_SYSTEMD_LOADER_H
#define UWBD_INTEGRATIONS_SYSTEMD_LOADER_H

#include <stddef.h>
#include <systemd/sd-daemon.h>

#define UWBD_SYSTEMD_LIBRARY "libsystemd.so.0"
/* Names another library file instead (tests: one that does not exist). */
#define UWBD_SYSTEMD_LIBRARY_ENV "UWB_SYSTEMD_LIB"

#define UWBD_SYSTEMD_FUNCTIONS(X) \
    X(notify) \
    X(notifyf) \
    X(watchdog_enabled)

struct uwbd_systemd_api {
// NOLINTNEXTLINE(bugprone-macro-parentheses): name is a member's name, not an expression
#define UWBD_SYSTEMD_ENTRY(name) __typeof__(sd_##name) *name;
    UWBD_SYSTEMD_FUNCTIONS(UWBD_SYSTEMD_ENTRY)
#undef UWBD_SYSTEMD_ENTRY
};

/* The table, loaded on the first call and kept; NULL with err naming the
 * library when it cannot be. */
const struct uwbd_systemd_api *uwbd_systemd_load(char *err, size_t errlen);

#endif
