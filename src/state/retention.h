/* Retention of the archive by count and by age. Baselines (baseline/) are
 * never deleted; verdicts.jsonl is trimmed to the same limits
 * (uwbd_verdict_log_trim), never deleted. */
#ifndef UWB_STATE_RETENTION_H
#define UWB_STATE_RETENTION_H

#include <signal.h>
#include <stddef.h>
#include <time.h>

#include "state/store.h"

/* Delete the oldest archived scans beyond max_scans (0: no limit) and those
 * older than max_age_days (0: no limit) at `now`. A scan's age is its
 * verdict file's modification time. Age counts only while the clock is
 * synchronised (clock_synchronised, from uwbd_clock_synchronised), and
 * never deletes the newest scan. Empty day, month and year directories go
 * too; symlinks in the archive are never followed. *removed (may be NULL)
 * counts deleted scans. */
int uwbd_retention_apply(const struct uwbd_store *store, int max_scans, double max_age_days, time_t now,
                         int clock_synchronised, int *removed, char *err, size_t errlen);

/* What one scan cycle may spend on retention: the rest waits for the next
 * cycle, so a huge archive is cleaned over several cycles while the
 * daemon stays responsive and the worker well within its stall limit. */
#define UWBD_RETENTION_SCANS_PER_CYCLE 10000
#define UWBD_RETENTION_SECONDS_PER_CYCLE 5.0

struct uwbd_retention_budget {
    int max_deletions;                 /* scans deleted per call at most, the oldest; 0: no limit */
    double max_seconds;                /* per call, looked at between two scans; 0: no limit */
    const volatile sig_atomic_t *stop; /* raised: end between two scans (NULL: never) */
    int cut_short;                     /* out: 1 when scans due for deletion are left for later */
};

/* uwbd_retention_apply within a budget (NULL: none). Each day directory is
 * read once, whatever its size; a scan's verdict record is its last file
 * to go, so a scan cut short is still listed next time. When stopped,
 * verdicts.jsonl is not trimmed this time. */
int uwbd_retention_apply_within(const struct uwbd_store *store, int max_scans, double max_age_days,
                                time_t now, int clock_synchronised, struct uwbd_retention_budget *budget,
                                int *removed, char *err, size_t errlen);

/* systemd-timesyncd creates this once it has synchronised the clock. */
#define UWBD_TIMESYNC_FLAG "/run/systemd/timesync/synchronized"

/* 1 when the kernel says the system clock is synchronised (ntp_adjtime,
 * read only: not TIME_ERROR, STA_UNSYNC clear), as NTP or
 * systemd-timesyncd sets it. When a syscall filter refuses even that
 * read, 1 when timesync_flag (may be NULL) exists. *how (may be NULL)
 * gets who said so, in words for the log. */
int uwbd_clock_synchronised_from(const char *timesync_flag, const char **how);

/* uwbd_clock_synchronised_from(UWBD_TIMESYNC_FLAG, NULL). */
int uwbd_clock_synchronised(void);

/* Number of scans in the archive (for status and tests). */
int uwbd_archive_count(const struct uwbd_store *store);

#endif
