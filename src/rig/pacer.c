/* Waits against absolute deadlines on the monotonic clock, so the time a
 * GPIO write takes does not add up over thousands of steps; scaled so that
 * emulated scans can run faster than real time. */
#include <errno.h>
#include <math.h>
#include <time.h>

#include "rig/carriage.h"

void uwb_pacer_start(struct uwb_pacer *p, double time_scale)
{
    p->scale = time_scale;
    clock_gettime(CLOCK_MONOTONIC, &p->base);
}

void uwb_pacer_wait_until(struct uwb_pacer *p, double offset_s)
{
    double scaled = offset_s * p->scale;
    if (!(scaled > 0))
        return;
    double whole = floor(scaled);
    struct timespec t = p->base;
    t.tv_sec += (time_t)whole;
    t.tv_nsec += (long)((scaled - whole) * 1e9);
    if (t.tv_nsec >= 1000000000L) {
        t.tv_sec++;
        t.tv_nsec -= 1000000000L;
    }
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, NULL) == EINTR) {
    }
}

void uwb_pacer_sleep(struct uwb_pacer *p, double seconds)
{
    uwb_pacer_start(p, p->scale);
    uwb_pacer_wait_until(p, seconds);
}
