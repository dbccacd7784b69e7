/* The monotonic clock, for deadlines and idle times (never wall time). */
#ifndef UWB_MONOTONIC_H
#define UWB_MONOTONIC_H

/* CLOCK_MONOTONIC in milliseconds. */
long long uwb_monotonic_ms(void);
/* CLOCK_MONOTONIC in seconds. */
double uwb_monotonic_s(void);

#endif
