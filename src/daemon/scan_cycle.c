/* One scan cycle, from an acquired scan to the archived verdict (see the
 * header). The order of writes matters: the raw scan first (the data is
 * never lost once acquired), then images, the baseline, and last the
 * verdict records, so a verdict never names files that are not there. */
#include "uwb/daemon/scan_cycle.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "uwb/daemon/baseline_store.h"
#include "uwb/daemon/direct_coupling.h"
#include "uwb/daemon/log.h"
#include "uwb/daemon/retention.h"
#include "uwb/daemon/verdict_log.h"
#include "uwb/evaluate.h"
#include "uwb/verdict_json.h"

/* What the daemon adds to the imaging core's verdict. */
struct verdict_extras {
    const char *scan_file;
    int has_direct_coupling;
    double direct_coupling_s;
    int has_shift;
    double direct_coupling_shift_s;
    int baseline_requested;
    int baseline_set;
    char baseline_note[256];
    const char *archive_error;   /* a file of this cycle the archive did not take */
    const char *record_error;    /* why the verdict is not in verdicts.jsonl */
    const char *clock_note;      /* this scan is dated before the newest recorded one */
};

struct cycle {
    const struct uwbd_config *cfg;
    const struct uwbd_store *store;
    const struct uwbd_cycle_request *req;
    struct uwbd_cycle_result *res;
    char day_dir[UWBD_PATH_MAX + 32];
    int have_day_dir;
    char day_dir_error[512];
    char id[UWBD_SCAN_ID_MAX + 1];
    char created[64];
    char archive_error[512];     /* the first file of this cycle that could not be archived */
    char clock_note[200];        /* "" unless the clock went back (issue 17) */
};

static int file_exists_in(const char *dir, const char *id, const char *suffix)
{
    char path[UWBD_PATH_MAX + 200];
    snprintf(path, sizeof path, "%s/%s%s", dir, id, suffix);
    return access(path, F_OK) == 0;
}

/* Give the scan an archive name not used yet that day. */
static void choose_id(struct cycle *c, const char *wanted)
{
    char base[UWBD_SCAN_ID_MAX + 1];
    uwbd_safe_scan_id(wanted ? wanted : "", base, sizeof base);
    if (!base[0]) {
        struct tm tm;
        gmtime_r(&c->req->now, &tm);
        strftime(base, sizeof base, "uwbd-%Y%m%dT%H%M%SZ", &tm);
    }
    snprintf(c->id, sizeof c->id, "%s", base);
    for (int n = 2; c->have_day_dir && n < 10000 &&
                    (file_exists_in(c->day_dir, c->id, ".json") || file_exists_in(c->day_dir, c->id, ".uwbscan"));
         n++) {
        char suffix[16];
        int len = snprintf(suffix, sizeof suffix, "-%d", n);
        snprintf(c->id, sizeof c->id, "%.*s%s", UWBD_SCAN_ID_MAX - len, base, suffix);
    }
}

static char *verdict_text(const struct uwb_verdict *v, const struct verdict_extras *x)
{
    char *core = uwb_verdict_to_json(v);
    cJSON *o = core ? cJSON_Parse(core) : NULL;
    free(core);
    if (!o)
        return NULL;
    if (x->scan_file)
        cJSON_AddStringToObject(o, "scan_file", x->scan_file);
    if (x->has_direct_coupling)
        cJSON_AddNumberToObject(o, "direct_coupling_ps", round(x->direct_coupling_s * 1e13) / 10.0);
    if (x->has_shift)
        cJSON_AddNumberToObject(o, "direct_coupling_shift_ps", round(x->direct_coupling_shift_s * 1e13) / 10.0);
    if (x->baseline_requested) {
        cJSON_AddBoolToObject(o, "baseline_set", x->baseline_set);
        if (x->baseline_note[0])
            cJSON_AddStringToObject(o, "baseline_note", x->baseline_note);
    }
    if (x->archive_error)
        cJSON_AddStringToObject(o, "archive_error", x->archive_error);
    if (x->record_error)
        cJSON_AddStringToObject(o, "record_error", x->record_error);
    if (x->clock_note)
        cJSON_AddStringToObject(o, "clock_warning", x->clock_note);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static void problem(struct cycle *c, const char *what, const char *err)
{
    uwbd_log(UWBD_LOG_ERR, "scan %s: %s: %s", c->id, what, err);
    c->res->archive_problems++;
}

/* A file of the scan's archive was not written (a full or read-only disk):
 * the verdict says which, so it never silently lacks an image. */
static void archive_problem(struct cycle *c, const char *what, const char *err)
{
    problem(c, what, err);
    if (!c->archive_error[0])
        snprintf(c->archive_error, sizeof c->archive_error, "%s", err);
}

/* Replace the result's verdict text after the extras changed. */
static int retext(struct cycle *c, const struct uwb_verdict *v, const struct verdict_extras *x)
{
    char *text = verdict_text(v, x);
    if (!text)
        return -1;
    free(c->res->verdict_json);
    c->res->verdict_json = text;
    return 0;
}

static int write_verdict_file(struct cycle *c, const char *text, char *err, size_t errlen)
{
    char path[UWBD_PATH_MAX + 200];
    snprintf(path, sizeof path, "%s/%s.json", c->day_dir, c->id);
    return uwbd_write_json_file(path, text, err, errlen);
}

/* The verdict file in the archive, its line in verdicts.jsonl, latest.json.
 * What could not be written is added to the verdict that goes on: the
 * verdicts.jsonl line says its archive copy is missing, and when the line
 * itself is refused (the state directory full or read-only) the reply and
 * the status say so, which is then the verdict's only record besides the log. */
static void record(struct cycle *c, const struct uwb_verdict *v, const struct verdict_extras *extras)
{
    struct uwbd_cycle_result *res = c->res;
    struct verdict_extras x = *extras;
    res->outcome = UWBD_CYCLE_RECORDED;
    res->status = v->status;
    snprintf(res->scan_id, sizeof res->scan_id, "%s", c->id);
    snprintf(res->reason, sizeof res->reason, "%s", v->reason);
    res->baseline_set = x.baseline_set;
    x.archive_error = c->archive_error[0] ? c->archive_error : NULL;
    x.clock_note = c->clock_note[0] ? c->clock_note : NULL;
    if (retext(c, v, &x) != 0) {
        problem(c, "verdict", "out of memory");
        return;
    }
    char err[512];
    if (c->have_day_dir && write_verdict_file(c, res->verdict_json, err, sizeof err) != 0) {
        archive_problem(c, "archive", err);
        x.archive_error = c->archive_error;
        if (retext(c, v, &x) != 0)
            problem(c, "verdict", "out of memory");
    }
    char log_err[512];
    if (uwbd_verdict_log_append(c->store, res->verdict_json, log_err, sizeof log_err) != 0) {
        problem(c, "verdict log", log_err);
        x.record_error = log_err;
        if (retext(c, v, &x) != 0)
            problem(c, "verdict", "out of memory");
    }
    if (uwbd_latest_write(c->store, res->verdict_json, err, sizeof err) != 0)
        problem(c, "latest verdict", err);
}

static void record_error(struct cycle *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void record_error(struct cycle *c, const char *fmt, ...)
{
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.status = UWB_STATUS_ERROR;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v.reason, sizeof v.reason, fmt, ap);
    va_end(ap);
    if (!c->id[0])
        choose_id(c, NULL);
    snprintf(v.scan_id, sizeof v.scan_id, "%s", c->id);
    snprintf(v.created, sizeof v.created, "%s", c->created);
    uwbd_log(UWBD_LOG_ERR, "scan %s lost: %s", c->id, v.reason);
    struct verdict_extras x = {0};
    record(c, &v, &x);
}

static int replace_text(char **field, const char *text)
{
    char *copy = strdup(text);
    if (!copy)
        return -1;
    free(*field);
    *field = copy;
    return 0;
}

/* Why this scan must not be compared with the baseline, or "" when it may. */
static void direct_coupling_check(const struct cycle *c, int dc_ok, double arrival_s, const char *dc_why,
                                  const struct uwbd_baseline_info *base, char *why, size_t n)
{
    why[0] = '\0';
    if (!dc_ok)
        snprintf(why, n, "direct coupling not found in this scan (%s): cable or antenna disconnected?", dc_why);
    else if (!base->has_direct_coupling)
        snprintf(why, n, "the baseline has no direct-coupling time zero to check this scan against");
    else if (fabs(arrival_s - base->direct_coupling_s) > c->cfg->direct_coupling_tolerance_s)
        snprintf(why, n,
                 "direct coupling moved %+.0f ps since the baseline (tolerance %.0f ps): cable or antenna changed?",
                 (arrival_s - base->direct_coupling_s) * 1e12, c->cfg->direct_coupling_tolerance_s * 1e12);
}

static void set_baseline_if_good(struct cycle *c, const struct uwb_scan *scan, const struct uwb_verdict *v,
                                 int dc_ok, double arrival_s, const char *dc_why, struct verdict_extras *x)
{
    x->baseline_requested = 1;
    if (!v->current.found) {
        snprintf(x->baseline_note, sizeof x->baseline_note,
                 "not set: the winding's edges were not found in this scan; the next good scan will be tried");
        return;
    }
    if (!dc_ok) {
        snprintf(x->baseline_note, sizeof x->baseline_note,
                 "not set: no direct coupling to take time zero from (%.120s); the next good scan will be tried",
                 dc_why);
        return;
    }
    struct uwbd_baseline_info info = {0};
    snprintf(info.scan_id, sizeof info.scan_id, "%s", c->id);
    snprintf(info.created, sizeof info.created, "%s", scan->created ? scan->created : "");
    uwbd_utc_text(c->req->now, info.set_at, sizeof info.set_at);
    info.has_direct_coupling = 1;
    info.direct_coupling_s = arrival_s;
    char err[512];
    if (uwbd_baseline_set(c->store, scan, &info, c->cfg->direct_coupling_window_end_s, err, sizeof err) != 0) {
        problem(c, "baseline", err);
        snprintf(x->baseline_note, sizeof x->baseline_note, "not set: %.200s", err);
        return;
    }
    x->baseline_set = 1;
    uwbd_log(UWBD_LOG_NOTICE, "scan %s is the new baseline (direct coupling at %.1f ps)", c->id, arrival_s * 1e12);
}

/* Everything after a successful acquisition. */
static void process_scan(struct cycle *c, struct uwb_scan *scan)
{
    struct uwb_verdict v;
    char err[512];
    choose_id(c, scan->scan_id);
    if (replace_text(&scan->scan_id, c->id) != 0 || (!scan->created && replace_text(&scan->created, c->created) != 0)) {
        record_error(c, "out of memory");
        return;
    }
    if (!c->have_day_dir) {
        record_error(c, "archive: cannot store the scan: %s", c->day_dir_error);
        return;
    }
    char scan_path[UWBD_PATH_MAX + 200];
    snprintf(scan_path, sizeof scan_path, "%s/%s.uwbscan", c->day_dir, c->id);
    if (uwbscan_write_file(scan_path, scan, err, sizeof err) != 0) {
        record_error(c, "archive: cannot store the scan: %s", err);
        return;
    }

    double arrival = 0;
    char dc_why[200] = "";
    int dc_ok = uwb_direct_coupling_arrival(scan, c->cfg->direct_coupling_window_end_s, &arrival, dc_why,
                                            sizeof dc_why) == 0;
    struct uwb_scan base = {0};
    struct uwbd_baseline_info info;
    int repaired = 0;
    char base_err[512] = "";
    int b = uwbd_baseline_load(c->store, c->cfg->direct_coupling_window_end_s, &base, &info, &repaired, base_err,
                               sizeof base_err);
    if (b == UWBD_BASELINE_ERROR)
        uwbd_log(UWBD_LOG_ERR, "baseline unreadable, scan %s not compared: %s", c->id, base_err);
    if (repaired)
        uwbd_log(UWBD_LOG_WARNING, "baseline/current.json did not describe current.uwbscan; rebuilt it");
    char not_compared[256] = "";
    if (b == UWBD_BASELINE_LOADED)
        direct_coupling_check(c, dc_ok, arrival, dc_why, &info, not_compared, sizeof not_compared);
    else if (b == UWBD_BASELINE_ERROR)
        snprintf(not_compared, sizeof not_compared, "baseline unreadable: %.200s", base_err);
    int compare = b == UWBD_BASELINE_LOADED && !not_compared[0];

    struct uwb_analysis cur_a, base_a;
    if (uwb_evaluate(scan, compare ? &base : NULL, &c->cfg->evaluate, &v, &cur_a, &base_a, err, sizeof err) != 0) {
        uwb_scan_free(&base);
        record_error(c, "evaluation failed: %s", err);
        return;
    }
    if (not_compared[0]) {
        char edges_reason[256];
        snprintf(edges_reason, sizeof edges_reason, "%s", v.current.found ? "" : v.reason);
        v.status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v.reason, sizeof v.reason, "%.200s%s%.50s", not_compared, edges_reason[0] ? "; " : "",
                 edges_reason);
        if (b == UWBD_BASELINE_LOADED)
            snprintf(v.baseline_scan_id, sizeof v.baseline_scan_id, "%s", info.scan_id);
    }
    if (uwb_write_images(c->day_dir, c->id, scan, &cur_a, compare ? &base_a : NULL, &v, err, sizeof err) != 0)
        archive_problem(c, "images", err);
    uwb_analysis_free(&cur_a);
    uwb_analysis_free(&base_a);
    uwb_scan_free(&base);

    struct verdict_extras x = {.scan_file = scan_path, .has_direct_coupling = dc_ok, .direct_coupling_s = arrival};
    if (compare) {
        x.has_shift = 1;
        x.direct_coupling_shift_s = arrival - info.direct_coupling_s;
    }
    if (c->req->make_baseline)
        set_baseline_if_good(c, scan, &v, dc_ok, arrival, dc_why, &x);
    record(c, &v, &x);
    uwbd_log(UWBD_LOG_INFO, "scan %s: %s%s%s", c->id, uwb_status_name(v.status), v.reason[0] ? ": " : "", v.reason);
}

int uwbd_cycle_run(const struct uwbd_config *cfg, const struct uwbd_store *store, uwbd_acquire_fn acquire,
                   void *acquire_ctx, const volatile sig_atomic_t *stop, const struct uwbd_cycle_request *req,
                   struct uwbd_cycle_result *res)
{
    memset(res, 0, sizeof *res);
    struct cycle c = {.cfg = cfg, .store = store, .req = req, .res = res};
    uwbd_utc_text(req->now, c.created, sizeof c.created);
    char newest[64];
    if (uwbd_verdict_log_latest_created(store, newest, sizeof newest) && strcmp(c.created, newest) < 0)
        snprintf(c.clock_note, sizeof c.clock_note,
                 "this scan's time %s is earlier than the newest recorded scan's (%.40s): the clock went back", c.created,
                 newest);
    if (c.clock_note[0])
        uwbd_log(UWBD_LOG_WARNING, "%s", c.clock_note);
    struct tm utc;
    gmtime_r(&req->now, &utc);
    char err[512];
    c.have_day_dir = uwbd_store_day_dir(store, &utc, c.day_dir, sizeof c.day_dir, c.day_dir_error,
                                        sizeof c.day_dir_error) == 0;

    struct uwb_scan scan = {0};
    int rc = acquire(acquire_ctx, stop, &scan, err, sizeof err);
    if (rc == UWBD_ACQUIRE_STOPPED) {
        uwb_scan_free(&scan);
        res->outcome = UWBD_CYCLE_STOPPED;
        return 0;
    }
    if (rc != UWBD_ACQUIRE_OK) {
        uwb_scan_free(&scan);
        record_error(&c, "acquisition failed: %s", err);
    } else {
        process_scan(&c, &scan);
        uwb_scan_free(&scan);
    }
    int removed = 0, synchronised = uwbd_clock_synchronised();
    static int said_unsynchronised;   /* once per run, not once per scan */
    if (cfg->retention_max_age_days > 0 && !synchronised && !said_unsynchronised++)
        uwbd_log(UWBD_LOG_NOTICE, "retention: the system clock is not synchronised: "
                                  "retention.max_age_days waits for it (max_scans still applies)");
    if (uwbd_retention_apply(store, cfg->retention_max_scans, cfg->retention_max_age_days, req->now, synchronised,
                             &removed, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "retention: %s", err);
    else if (removed)
        uwbd_log(UWBD_LOG_INFO, "retention: deleted %d archived scan%s", removed, removed == 1 ? "" : "s");
    return 0;
}

void uwbd_cycle_result_free(struct uwbd_cycle_result *res)
{
    free(res->verdict_json);
    res->verdict_json = NULL;
}
