/* Retention of the archive by count and by age. Baselines (baseline/) are
 * never deleted; verdicts.jsonl is trimmed to the same limits
 * (uwbd_verdict_log_trim), never deleted. */
#ifndef UWB_DAEMON_RETENTION_H
#define UWB_DAEMON_RETENTION_H

#include <stddef.h>
#include <time.h>

#include "daemon/store.h"

/* Delete the oldest archived scans beyond max_scans (0: no limit) and those
 * older than max_age_days (0: no limit) at `now`. A scan's age is its
 * verdict file's modification time. Age counts only while the clock is
 * synchronised (clock_synchronised, from uwbd_clock_synchronised), and
 * never deletes the newest scan. Empty day, month and year directories go
 * too; symlinks in the archive are never followed. *removed (may be NULL)
 * counts deleted scans. */
int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int clock_synchronised, int *removed, char *err, size_t errlen);

/* 1 when the kernel says the system clock is synchronised (ntp_adjtime:
 * not TIME_ERROR, STA_UNSYNC clear), as NTP or systemd-timesyncd sets it. */
int uwbd_clock_synchronised(void);

/* Number of scans in the archive (for status and tests). */
int uwbd_archive_count(const struct uwbd_store *store);

#endif
