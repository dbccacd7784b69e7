/* verdicts.jsonl and latest.json: the record of every scan cycle.
 * verdicts.jsonl only grows by whole lines: each line goes out in one
 * write() and is fsync'd; a write that falls short is tried once more for
 * the rest and, short again (disk full), cut back off with the system's
 * reason; a reader skips a torn or unparsable line instead of failing.
 * Retention trims its oldest lines by replacing the file atomically. */
#ifndef UWB_STATE_VERDICT_LOG_H
#define UWB_STATE_VERDICT_LOG_H

#include <stddef.h>
#include <time.h>

#include "state/store.h"

/* Append one JSON object (no newline inside) as a line. */
int uwbd_verdict_log_append(const struct uwbd_store *store, const char *json, char *err, size_t errlen);

/* The last n (at most) parseable lines, oldest first, as malloc'd strings
 * in a malloc'd array (free with uwbd_verdict_lines_free). The log is read
 * back from its end, one block at a time, until n lines parse or it
 * begins: lines that do not parse hide none before them. *skipped counts
 * them (may be NULL). A missing log is zero lines. */
int uwbd_verdict_log_tail(const struct uwbd_store *store, int n, char ***lines, int *count, int *skipped,
                          char *err, size_t errlen);
void uwbd_verdict_lines_free(char **lines, int count);

/* If the log does not end with a newline (a crash mid-line), cut the torn
 * tail off. *dropped gets the number of bytes removed. */
int uwbd_verdict_log_repair(const struct uwbd_store *store, long *dropped, char *err, size_t errlen);

/* Keep the newest lines within the archive's retention limits: at most
 * max_lines (0: no limit), and none whose verdict was created more than
 * max_age_days before `now` (0: no limit; a line without a readable
 * "created" is dated like the line before it). The file is replaced
 * atomically (temporary, fsync, rename), and only when a line goes.
 * *dropped (may be NULL) counts the lines removed. */
int uwbd_verdict_log_trim(const struct uwbd_store *store, int max_lines, double max_age_days, time_t now,
                          int *dropped, char *err, size_t errlen);

/* The "created" time (UTC text) of the newest line of verdicts.jsonl into
 * created; 1 when there is one, else 0 and "". */
int uwbd_verdict_log_latest_created(const struct uwbd_store *store, char *created, size_t n);

/* latest.json, written atomically / read whole (malloc'd; NULL and 0 when
 * there is none yet). */
int uwbd_latest_write(const struct uwbd_store *store, const char *json, char *err, size_t errlen);
int uwbd_latest_read(const struct uwbd_store *store, char **json, char *err, size_t errlen);

/* The latest verdict's line when the daemon starts (malloc'd; NULL when
 * there is none): latest.json, or when that is missing, unreadable or
 * older (by "created") than the newest line of verdicts.jsonl that
 * parses, that line. note gets what the log should say about it ("" when
 * nothing). */
char *uwbd_latest_line_at_start(const struct uwbd_store *store, char *note, size_t n);

#endif
