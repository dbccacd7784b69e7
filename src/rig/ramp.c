/* Motion maths of the carriage, free of I/O: when each step of a
 * trapezoidal move happens, and how a target is approached from below. */
#include <math.h>

#include "rig/carriage.h"

void uwb_ramp_init(struct uwb_ramp *r, long steps, double max_hz, double accel)
{
    r->steps = steps > 0 ? steps : 0;
    r->max_hz = max_hz;
    r->accel = accel;
    /* From rest, x = a t^2 / 2 and v = a t, so max_hz is reached after
     * max_hz^2 / 2a steps; a move shorter than twice that never cruises. */
    double to_cruise = max_hz * max_hz / (2.0 * accel);
    if (r->steps >= 2.0 * to_cruise) {
        r->accel_steps = to_cruise;
        r->accel_s = max_hz / accel;
        r->total_s = r->steps / max_hz + max_hz / accel;
    } else {
        r->accel_steps = r->steps / 2.0;
        r->accel_s = sqrt(r->steps / accel);
        r->total_s = 2.0 * r->accel_s;
    }
}

double uwb_ramp_step_time_s(const struct uwb_ramp *r, long k)
{
    double x = (double)k;
    if (x <= r->accel_steps)
        return sqrt(2.0 * x / r->accel);
    if (x >= r->steps - r->accel_steps)
        return r->total_s - sqrt(2.0 * (r->steps - x) / r->accel);
    return r->accel_s + (x - r->accel_steps) / r->max_hz;
}

int uwb_carriage_plan(long from, long to, long backlash_steps, long waypoints[2])
{
    long overshoot = backlash_steps > 1 ? backlash_steps : 1;
    if (to - from >= overshoot) {
        waypoints[0] = to;
        return 1;
    }
    waypoints[0] = to - overshoot;
    waypoints[1] = to;
    return 2;
}

long uwb_carriage_mm_to_steps(const struct uwb_carriage_config *cfg, double mm)
{
    return lround(mm * cfg->steps_per_mm);
}
