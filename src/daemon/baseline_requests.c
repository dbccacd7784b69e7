/* `baseline set [N]` from request to baseline: the request is kept in
 * baseline/pending.json until a scan satisfies it (or refuses it for good),
 * so a restart does not forget it; each scan is told which baseline the
 * daemon commissioned, so a missing or damaged one is a fault, not silence. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "daemon_internal.h"
#include "util/log.h"
#include "control/reply.h"

char *uwbd_baseline_request(struct daemon *d, int scans, int force)
{
    d->baseline_requests++;
    d->baseline_scans = scans > 0 ? scans : d->cfg.baseline_scans;
    d->baseline_force = force;
    char err[1024];
    if (uwbd_baseline_pending_write(&d->store, d->baseline_scans, force, time(NULL), err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_WARNING,
                 "baseline set: the request holds until the next good scan but is not kept "
                 "across a restart: %s",
                 err);
    uwbd_log(UWBD_LOG_NOTICE,
             "baseline set requested: the next good scan, averaged over %d acquisition%s, becomes "
             "the baseline%s",
             d->baseline_scans, d->baseline_scans == 1 ? "" : "s",
             force ? " even if it is an alarm against the current one (force)" : "");
    return uwbd_reply_baseline(1, d->has_baseline, &d->baseline);
}

void uwbd_baseline_requests_restore(struct daemon *d)
{
    char err[1024];
    int scans = 0, force = 0;
    int rc = uwbd_baseline_pending_read(&d->store, &scans, &force, err, sizeof err);
    if (rc < 0) {
        uwbd_log(UWBD_LOG_WARNING, "baseline: %s; no `baseline set` is pending", err);
        return;
    }
    if (rc == 0)
        return;
    d->baseline_requests = d->baseline_done + 1;
    d->baseline_scans = scans;
    d->baseline_force = force;
    uwbd_log(UWBD_LOG_NOTICE,
             "baseline set (%d scan%s) pending from before the restart: the next good scan "
             "becomes the baseline",
             scans, scans == 1 ? "" : "s");
}

void uwbd_baseline_request_fill(struct daemon *d, struct uwbd_cycle_request *req)
{
    req->make_baseline = d->baseline_requests > d->baseline_done;
    req->baseline_scans = req->make_baseline ? d->baseline_scans : 1;
    req->force_baseline = req->make_baseline && d->baseline_force;
    req->has_expected = d->has_baseline;
    if (d->has_baseline)
        req->expected = d->baseline;
}

void uwbd_baseline_request_finished(struct daemon *d, unsigned long request,
                                    const struct uwbd_cycle_result *res)
{
    if (res->baseline_checked) {
        if (res->fault[0] && strcmp(res->fault, d->fault) != 0)
            uwbd_log(UWBD_LOG_WARNING, "device fault: %s", res->fault);
        else if (!res->fault[0] && d->fault[0])
            uwbd_log(UWBD_LOG_NOTICE, "device fault cleared: the baseline checks again");
        snprintf(d->fault, sizeof d->fault, "%s", res->fault);
    }
    if (!request || !(res->baseline_set || res->baseline_refused))
        return;
    d->baseline_done = request;
    char err[1024];
    if (d->baseline_requests == d->baseline_done &&
        uwbd_baseline_pending_clear(&d->store, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_WARNING, "baseline: %s; the request may be applied again after a restart", err);
    if (res->baseline_set) {
        d->has_baseline = uwbd_baseline_load(&d->store, d->cfg.evaluate.direct_coupling.window_end_s, NULL,
                                             &d->baseline, NULL, err, sizeof err) == UWBD_BASELINE_LOADED;
        if (!d->has_baseline)
            uwbd_log(UWBD_LOG_ERR, "baseline: just set, but cannot be read back: %s", err);
    }
}
