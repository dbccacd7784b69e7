/* sd_notify through libsystemd (see service_notify.h), which is loaded
 * only under a service manager that listens: outside systemd there is
 * nothing to tell, and a replay or `uwbd --version` does not map it. */
#include "daemon/service_notify.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "util/log.h"
#include "integrations/systemd_loader.h"

/* The library's table when systemd listens, NULL otherwise. A library that
 * cannot be loaded is said once: systemd then never hears READY=1. */
static const struct uwbd_systemd_api *systemd_api(void)
{
    static int tried;
    static const struct uwbd_systemd_api *api;
    if (tried)
        return api;
    tried = 1;
    if (!getenv("NOTIFY_SOCKET") && !getenv("WATCHDOG_USEC"))
        return NULL;
    char err[512];
    api = uwbd_systemd_load(err, sizeof err);
    if (!api)
        uwbd_log(UWBD_LOG_ERR, "%s", err);
    return api;
}

long uwbd_service_watchdog_ping_ms(void)
{
    const struct uwbd_systemd_api *sd = systemd_api();
    uint64_t usec = 0;
    if (!sd || sd->watchdog_enabled(0, &usec) <= 0 || usec == 0)
        return 0;
    long half_ms = (long)(usec / 2000);
    return half_ms > 0 ? half_ms : 1;
}

void uwbd_service_notify(const char *state)
{
    const struct uwbd_systemd_api *sd = systemd_api();
    if (sd)
        sd->notify(0, state);
}

void uwbd_service_status(const char *fmt, ...)
{
    const struct uwbd_systemd_api *sd = systemd_api();
    if (!sd)
        return;
    char text[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    sd->notifyf(0, "STATUS=%s", text);
}
