/* sd_notify through libsystemd (see service_notify.h). */
#include "daemon/service_notify.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>

#include <systemd/sd-daemon.h>

long uwbd_service_watchdog_ping_ms(void)
{
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) <= 0 || usec == 0)
        return 0;
    long half_ms = (long)(usec / 2000);
    return half_ms > 0 ? half_ms : 1;
}

void uwbd_service_notify(const char *state)
{
    sd_notify(0, state);
}

void uwbd_service_status(const char *fmt, ...)
{
    char text[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    sd_notifyf(0, "STATUS=%s", text);
}
