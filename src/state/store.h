/* The daemon's state directory (layout in board/state-dir.md):
 *   archive/YYYY/MM/DD/<scan_id>.uwbscan, .json, -<kind>.png
 *   verdicts.jsonl      one verdict per line, append-only
 *   latest.json         the latest verdict
 *   baseline/current.uwbscan, baseline/current.json
 *   baseline/history/<scan_id>.uwbscan (+ .json), earlier baselines
 *   uwbd.lock           held by the running daemon
 * Every file is written atomically; verdicts.jsonl grows by whole lines. */
#ifndef UWB_STATE_STORE_H
#define UWB_STATE_STORE_H

#include <stddef.h>
#include <time.h>

#include "config/config_load.h"

#define UWBD_SCAN_ID_MAX 100

struct uwbd_store {
    char root[UWBD_PATH_MAX]; /* absolute */
    char archive[UWBD_PATH_MAX + 16];
    char baseline_dir[UWBD_PATH_MAX + 16];
    char baseline_history[UWBD_PATH_MAX + 32];
    char verdict_log[UWBD_PATH_MAX + 32];
    char latest[UWBD_PATH_MAX + 32];
};

/* Create the directories if missing, make the root absolute, remove
 * temporaries a crash left behind; *repairs (may be NULL) counts them.
 * The verdict log is repaired by its own code (uwbd_state_open does both).
 * Returns 0 or -1 with err. */
int uwbd_store_open(struct uwbd_store *store, const char *state_dir, int *repairs, char *err, size_t errlen);

/* Create state_dir if missing and hold an exclusive lock on its uwbd.lock
 * for the life of the process, so a second daemon never tidies or writes
 * the same state. Returns the lock's fd, or -1 with err (another uwbd holds
 * it, or the directory is unusable). */
int uwbd_store_lock(const char *state_dir, char *err, size_t errlen);

/* archive/YYYY/MM/DD for that UTC day, created if missing. */
int uwbd_store_day_dir(const struct uwbd_store *store, const struct tm *utc, char *dir, size_t n, char *err,
                       size_t errlen);

/* A scan id made safe as a file name: [A-Za-z0-9._-], not starting with a
 * dot, at most UWBD_SCAN_ID_MAX bytes; empty input gives "". */
void uwbd_safe_scan_id(const char *in, char *out, size_t n);

/* One JSON text and a newline as the whole of `path`, written atomically
 * (atomic_file.h). Returns 0 or -1 with err. */
int uwbd_write_json_file(const char *path, const char *json, char *err, size_t errlen);

/* "%Y-%m-%dT%H:%M:%SZ" of t. */
void uwbd_utc_text(time_t t, char *buf, size_t n);

/* Join two path parts with '/'; -1 if it does not fit. */
int uwbd_path_join(char *out, size_t n, const char *dir, const char *name);

#endif
