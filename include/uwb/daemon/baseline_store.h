/* The baseline: the scan of the intact winding every later scan is compared
 * with. It changes only through uwbd_baseline_set (the `baseline set`
 * command); the one it replaces is kept in baseline/history/. */
#ifndef UWB_DAEMON_BASELINE_STORE_H
#define UWB_DAEMON_BASELINE_STORE_H

#include <stddef.h>

#include "uwb/daemon/store.h"
#include "uwb/scan.h"

struct uwbd_baseline_info {
    char scan_id[UWBD_SCAN_ID_MAX + 1];
    char created[64];                  /* when the baseline scan was taken */
    char set_at[64];                   /* when it became the baseline */
    int has_direct_coupling;
    double direct_coupling_s;          /* time zero recorded at commissioning */
};

enum uwbd_baseline_result {
    UWBD_BASELINE_LOADED = 0,
    UWBD_BASELINE_NONE = 1,            /* never set */
    UWBD_BASELINE_ERROR = -1,
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

#endif
