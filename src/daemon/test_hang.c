/* The UWBD_TEST_HANG hook (see test_hang.h). */
#include "daemon/test_hang.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "util/log.h"

void uwbd_test_hang_point(const char *where)
{
    const char *want = getenv(UWBD_TEST_HANG_ENV);
    if (!want || strcmp(want, where) != 0)
        return;
    uwbd_log(UWBD_LOG_WARNING, "%s=%s: the %s hangs here on purpose (a test of the watchdog)",
             UWBD_TEST_HANG_ENV, where, where);
    for (;;) {
        struct timespec t = {.tv_sec = 3600};
        nanosleep(&t, NULL);
    }
}
