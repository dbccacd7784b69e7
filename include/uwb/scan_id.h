/* The one form of a scan id, made in one place for the rig (a scan) and
 * the daemon (a cycle that made no scan: an error verdict). */
#ifndef UWB_SCAN_ID_H
#define UWB_SCAN_ID_H

#include <stddef.h>
#include <time.h>

/* "T3-north-uwb-20261207T032316.813Z": the asset (left out when asset is
 * NULL or ""), "uwb-", the UTC start to the millisecond. ms is clamped to
 * 0..999. Returns what snprintf returns. */
int uwb_scan_id_make(char *out, size_t n, const char *asset, time_t utc_s, long ms);

#endif
