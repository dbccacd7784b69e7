/* Retention of the archive by count and by age. Baselines (baseline/) are
 * never deleted; verdicts.jsonl is trimmed to the same limits
 * (uwbd_verdict_log_trim), never deleted. */
#ifndef UWB_DAEMON_RETENTION_H
#define UWB_DAEMON_RETENTION_H

#include <stddef.h>
#include <time.h>

#include "uwb/daemon/store.h"

/* Delete the oldest archived scans beyond max_scans (0: no limit) and those
 * older than max_age_days (0: no limit) at `now`. A scan's age is its
 * verdict file's modification time. Empty day, month and year directories
 * go too. *removed (may be NULL) counts deleted scans. */
int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int *removed, char *err, size_t errlen);

/* Number of scans in the archive (for status and tests). */
int uwbd_archive_count(const struct uwbd_store *store);

#endif
