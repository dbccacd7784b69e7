/* One scan cycle above the hardware: acquire a scan (through a function, so
 * tests can hand in simulated scans), archive it, verify the baseline,
 * evaluate it against the baseline (uwb_evaluate: time zero, comparability
 * and figures, as `uwbd --replay` does), write the images and the verdict
 * with what the daemon adds, set the baseline when asked, apply retention. A lost scan becomes an
 * `error` verdict with a reason; a scan the archive cannot take (a full
 * disk) is still evaluated, its verdict naming what was not written;
 * nothing is ever half-written. */
#ifndef UWB_DAEMON_SCAN_CYCLE_H
#define UWB_DAEMON_SCAN_CYCLE_H

#include <signal.h>
#include <stddef.h>
#include <time.h>

#include "daemon/acquire_more.h"
#include "state/baseline_store.h"
#include "config/config_load.h"
#include "state/store.h"
#include "uwb/scan.h"
#include "uwb/verdict_record.h"

struct uwbd_cycle_request {
    int make_baseline;  /* a `baseline set` is pending */
    int baseline_scans; /* ...to be made from this many scans averaged (0 or 1: this one) */
    int force_baseline; /* ...even from a scan that is an alarm against the current one */
    int has_expected;   /* the daemon commissioned `expected`: it must still be there, whole */
    struct uwbd_baseline_info expected;
    time_t now;  /* wall clock at the start (names the archive day) */
    long now_ms; /* its milliseconds, for the id of a cycle that made no scan */
    const char
        *trigger; /* what started it, for the verdict: "schedule", "command" or "event"; NULL: not said */
};

enum uwbd_cycle_outcome {
    UWBD_CYCLE_RECORDED, /* a verdict (maybe `error`) was produced */
    UWBD_CYCLE_STOPPED,  /* stopped by a signal: nothing recorded */
};

struct uwbd_cycle_result {
    enum uwbd_cycle_outcome outcome;
    enum uwb_status status;
    char scan_id[UWBD_SCAN_ID_MAX + 1];
    char reason[256];
    int baseline_set;     /* this scan became the baseline */
    int baseline_refused; /* the pending `baseline set` was refused for good (an alarm); see the verdict */
    int baseline_checked; /* the baseline was looked at: `fault` is current */
    char fault[512];      /* "" or why the baseline cannot be trusted (a device fault) */
    char *verdict_json;   /* malloc'd one-line VERDICT object (as archived), NULL when stopped */
    struct uwb_verdict_record *verdict; /* malloc'd: what verdict_json says, NULL when stopped */
    int archive_problems;               /* files that could not be written (logged) */
    char write_error[512]; /* "" or the cycle's first write into the state directory that failed */
};

int uwbd_cycle_run(const struct uwbd_config *cfg, const struct uwbd_store *store, uwbd_acquire_fn acquire,
                   void *acquire_ctx, const volatile sig_atomic_t *stop, const struct uwbd_cycle_request *req,
                   struct uwbd_cycle_result *res);
void uwbd_cycle_result_free(struct uwbd_cycle_result *res);

#endif
