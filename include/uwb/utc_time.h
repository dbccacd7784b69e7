/* The UTC time stamps uwbd writes ("created" in verdicts and scans) read back. */
#ifndef UWB_UTC_TIME_H
#define UWB_UTC_TIME_H

#include <time.h>

/* "YYYY-MM-DDTHH:MM:SSZ" exactly (strftime's "%Y-%m-%dT%H:%M:%SZ", what uwbd
 * writes) to seconds since the epoch. Returns 0, or -1 for NULL, any other
 * shape, or a field out of range (month 1-12, day 1-31, hour 0-23,
 * minute 0-59, second 0-60), leaving *out alone. */
int uwb_utc_parse(const char *text, time_t *out);

#endif
