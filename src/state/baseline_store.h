/* The baseline: the scan of the intact winding every later scan is compared
 * with. It changes only through uwbd_baseline_set (the `baseline set`
 * command); the one it replaces is kept in baseline/history/. */
#ifndef UWB_STATE_BASELINE_STORE_H
#define UWB_STATE_BASELINE_STORE_H

#include <stddef.h>
#include <time.h>

#include "state/store.h"
#include "uwb/scan.h"

/* `baseline set N`: at most this many scans averaged into one baseline. */
#define UWBD_BASELINE_SCANS_MAX 16 /* = UWB_BASELINE_SCANS_MAX of command.h */

struct uwbd_baseline_info {
    char scan_id[UWBD_SCAN_ID_MAX + 1];
    char created[64]; /* when the baseline scan was taken */
    char set_at[64];  /* when it became the baseline */
    int has_direct_coupling;
    double direct_coupling_s; /* time zero recorded at commissioning */
    int has_checksum;
    unsigned long checksum; /* CRC-32 of current.uwbscan's bytes, recorded at commissioning */
    int scans;              /* acquisitions averaged into it (0: not recorded, one) */
    int has_repeatability;
    double repeatability_m; /* spread (1-sigma) of the centre across those scans */
};

/* Read a baseline description (current.json, history/ID.json): 0 read, 1
 * absent, -1 unreadable or malformed (err says which). */
int uwbd_baseline_info_read(const char *path, struct uwbd_baseline_info *info, char *err, size_t errlen);

enum uwbd_baseline_result {
    UWBD_BASELINE_LOADED = 0,
    UWBD_BASELINE_NONE = 1, /* never set */
    UWBD_BASELINE_ERROR = -1,
    UWBD_BASELINE_DAMAGED = -2, /* readable, but not the bytes commissioned (checksum) */
    UWBD_BASELINE_FAULT = -3,   /* uwbd_baseline_watch: missing, damaged or replaced */
};

/* Read baseline/current.uwbscan and current.json. current.uwbscan is the
 * truth: if current.json is missing or names another scan (a crash between
 * the two writes), it is rebuilt from the scan, with the direct coupling
 * measured up to window_end_s, and *repaired is set. If it cannot be
 * written now (a full disk), the description taken from the scan is used
 * all the same (logged) and the rebuild is tried at the next load. `scan`
 * may be NULL when only the info is wanted. */
int uwbd_baseline_load(const struct uwbd_store *store, double window_end_s, struct uwb_scan *scan,
                       struct uwbd_baseline_info *info, int *repaired, char *err, size_t errlen);

/* Make `scan` the baseline: the current one (if any) is first copied to
 * baseline/history/<its scan_id>.uwbscan (+ .json), then current.uwbscan
 * and current.json are replaced, each atomically. Returns 0 once
 * current.uwbscan is replaced: that is the baseline, even if current.json
 * could not be written (logged; rebuilt from the scan at the next load).
 * -1 with err otherwise: the old baseline stays as it was. */
int uwbd_baseline_set(const struct uwbd_store *store, const struct uwb_scan *scan,
                      const struct uwbd_baseline_info *info, double window_end_s, char *err, size_t errlen);

/* The baseline a scan is compared with, verified: current.uwbscan must be
 * whole (its checksum the one recorded at commissioning) and, when the
 * daemon knows which baseline it commissioned (`expected`, NULL when none),
 * that one. Returns LOADED (scan and info filled), NONE (never commissioned
 * and none expected) or FAULT with `why` ("baseline missing: ...",
 * "baseline damaged: ...", "baseline replaced outside uwbd: ..."). */
int uwbd_baseline_watch(const struct uwbd_store *store, double window_end_s,
                        const struct uwbd_baseline_info *expected, struct uwb_scan *scan,
                        struct uwbd_baseline_info *info, char *why, size_t whylen);

/* A `baseline set` waiting for its scan, kept in baseline/pending.json so
 * that a restart does not forget it. read: 1 and *scans when one is
 * pending (and *force: `baseline set force`), 0 when none, -1 unreadable
 * (err; treated as none). */
int uwbd_baseline_pending_write(const struct uwbd_store *store, int scans, int force, time_t requested,
                                char *err, size_t errlen);
int uwbd_baseline_pending_read(const struct uwbd_store *store, int *scans, int *force, char *err,
                               size_t errlen);
int uwbd_baseline_pending_clear(const struct uwbd_store *store, char *err, size_t errlen);

#endif
