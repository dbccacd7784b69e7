/* One scan cycle, from an acquired scan to the archived verdict (see the
 * header). The order of writes matters: the raw scan first (the data is
 * never lost once acquired), then images, the baseline, and last the
 * verdict records, so a verdict never names files that are not there. A
 * raw scan the archive refuses (a full disk) is evaluated all the same and
 * its verdict says so: the evaluation never waits on the disk. */
#include "daemon/scan_cycle.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "daemon/acquire_more.h"
#include "state/baseline_store.h"
#include "util/log.h"
#include "state/retention.h"
#include "daemon/trend.h"
#include "state/verdict_log.h"
#include "uwb/evaluate.h"
#include "uwb/monotonic.h"
#include "uwb/render.h"
#include "uwb/scan_id.h"
#include "uwb/verdict_json.h"

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
    char archive_error[512]; /* the first file of this cycle that could not be archived */
    uwbd_acquire_fn acquire;
    void *acquire_ctx;
    const volatile sig_atomic_t *stop;
    double started_s, acquire_s; /* CLOCK_MONOTONIC at the start; one acquisition's duration */
    int acquisitions, pulses_each;
    int baseline_scans, has_repeatability;
    double repeatability_m;
    char reacquire_note[256]; /* why no more were acquired while inconclusive */
    char clock_note[200];     /* "" unless the clock went back (issue 17) */
    char baseline_note[256];  /* after `baseline set`: why it was not set, or how */
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
    /* No scan (an error before one was made): the id the rig would have
     * given it, in the one form of uwb/scan_id.h. */
    if (!base[0])
        uwb_scan_id_make(base, sizeof base, NULL, c->req->now, c->req->now_ms);
    /* The asset in the id, so every archive file, verdict and log line of
     * the scan names it ("T3-north-uwb-20300102T000000.000Z"); the rig's
     * scans have it already, a replayed scan's may not. */
    const char *asset = c->cfg->site.asset_id;
    size_t asset_len = strlen(asset);
    if (asset_len && !(strncmp(base, asset, asset_len) == 0 && base[asset_len] == '-')) {
        char with_asset[2 * (UWBD_SCAN_ID_MAX + 1)];
        snprintf(with_asset, sizeof with_asset, "%s-%s", asset, base);
        uwbd_safe_scan_id(with_asset, base, sizeof base);
    }
    snprintf(c->id, sizeof c->id, "%s", base);
    for (int n = 2;
         c->have_day_dir && n < 10000 &&
         (file_exists_in(c->day_dir, c->id, ".json") || file_exists_in(c->day_dir, c->id, ".uwbscan"));
         n++) {
        char suffix[16];
        int len = snprintf(suffix, sizeof suffix, "-%d", n);
        snprintf(c->id, sizeof c->id, "%.*s%s", UWBD_SCAN_ID_MAX - len, base, suffix);
    }
}

static void problem(struct cycle *c, const char *what, const char *err)
{
    uwbd_log(UWBD_LOG_ERR, "scan %s: %s: %s", c->id, what, err);
    c->res->archive_problems++;
}

/* A file of the state directory was not written (a full or read-only
 * disk): logged, and the first of the cycle goes to the daemon, which
 * shows it in `status` until a cycle writes everything again. */
static void write_problem(struct cycle *c, const char *what, const char *err)
{
    problem(c, what, err);
    if (!c->res->write_error[0])
        snprintf(c->res->write_error, sizeof c->res->write_error, "%s", err);
}

/* A file of the scan's archive was not written: the verdict says which, so
 * it never silently lacks an image or its raw scan. */
static void archive_problem(struct cycle *c, const char *what, const char *err)
{
    write_problem(c, what, err);
    if (!c->archive_error[0])
        snprintf(c->archive_error, sizeof c->archive_error, "%s", err);
}

/* The record's text becomes the result's (the reply, `status` and
 * latest.json carry it). Written once, and again only when a record of it
 * failed and the verdict says so. */
static int print_verdict(struct cycle *c)
{
    char *text = uwb_record_to_json(c->res->verdict);
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

/* What the daemon adds to the evaluation's verdict: where the scan is
 * archived (scan_file NULL: it is not), how it was acquired, what became
 * of a `baseline set`, and what of the cycle went wrong. A field only the
 * daemon knows is added here and nowhere else. */
static void add_cycle_fields(const struct cycle *c, struct uwb_verdict_cycle *out, const char *scan_file,
                             int pulses)
{
    out->has_scan_file = scan_file != NULL;
    snprintf(out->scan_file, sizeof out->scan_file, "%s", scan_file ? scan_file : "");
    if (c->req->make_baseline) {
        out->has_baseline_set = 1;
        out->baseline_set = c->res->baseline_set != 0;
        snprintf(out->baseline_note, sizeof out->baseline_note, "%s", c->baseline_note);
    }
    if (pulses > 0) {
        out->pulses_per_position = pulses;
        out->acquisitions = c->acquisitions;
    }
    snprintf(out->reacquire_note, sizeof out->reacquire_note, "%s", c->reacquire_note);
    if (c->res->baseline_set && c->baseline_scans > 0) {
        out->baseline_scans = c->baseline_scans;
        out->has_baseline_repeatability = c->has_repeatability;
        if (c->has_repeatability)
            out->baseline_repeatability_mm = round(c->repeatability_m * 1e6) / 1e3;
    }
}

/* The verdict file in the archive, its line in verdicts.jsonl, latest.json.
 * What could not be written is added to the verdict that goes on: the
 * verdicts.jsonl line says its archive copy is missing, and when the line
 * itself is refused (the state directory full or read-only) the reply and
 * the status say so, which is then the verdict's only record besides the log.
 * Takes the evaluation's verdict and its record (malloc'd, its cycle fields
 * filled or not; NULL: out of memory), which the result keeps. */
static void record(struct cycle *c, const struct uwb_verdict *v, struct uwb_verdict_record *r)
{
    struct uwbd_cycle_result *res = c->res;
    res->outcome = UWBD_CYCLE_RECORDED;
    res->status = v->status;
    snprintf(res->scan_id, sizeof res->scan_id, "%s", c->id);
    snprintf(res->reason, sizeof res->reason, "%s", v->reason);
    free(res->verdict);
    res->verdict = r;
    if (!r) {
        problem(c, "verdict", "out of memory");
        return;
    }
    struct uwb_verdict_cycle *cy = &r->cycle;
    /* Who the appliance is and what started this scan: for the site's systems. */
    snprintf(cy->asset_id, sizeof cy->asset_id, "%s", c->cfg->site.asset_id);
    snprintf(cy->trigger, sizeof cy->trigger, "%s", c->req->trigger ? c->req->trigger : "");
    snprintf(cy->archive_error, sizeof cy->archive_error, "%s", c->archive_error);
    snprintf(cy->clock_warning, sizeof cy->clock_warning, "%s", c->clock_note);
    if (print_verdict(c) != 0) {
        problem(c, "verdict", "out of memory");
        return;
    }
    char err[512];
    if (c->have_day_dir && write_verdict_file(c, res->verdict_json, err, sizeof err) != 0) {
        int said = c->archive_error[0] != '\0';
        archive_problem(c, "archive", err);
        if (!said) {
            snprintf(cy->archive_error, sizeof cy->archive_error, "%s", c->archive_error);
            cy->archive_error_late = 1;
            if (print_verdict(c) != 0)
                problem(c, "verdict", "out of memory");
        }
    }
    char log_err[512];
    if (uwbd_verdict_log_append(c->store, res->verdict_json, log_err, sizeof log_err) != 0) {
        write_problem(c, "verdict log", log_err);
        snprintf(cy->record_error, sizeof cy->record_error, "%s", log_err);
        if (print_verdict(c) != 0)
            problem(c, "verdict", "out of memory");
    }
    if (uwbd_latest_write(c->store, res->verdict_json, err, sizeof err) != 0)
        write_problem(c, "latest verdict", err);
}

/* The published record of the evaluation's verdict (malloc'd), or NULL when out of memory. */
static struct uwb_verdict_record *new_record(const struct uwb_verdict *v)
{
    struct uwb_verdict_record *r = malloc(sizeof *r);
    if (r)
        uwb_record_from_verdict(r, v);
    return r;
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
    record(c, &v, new_record(&v));
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

/* The commissioning rules beyond edges and time zero: a scan that says the
 * winding moved past the alarm threshold against the current baseline is
 * never made the baseline, or the alarm would be silenced for good. The
 * request is then refused (not kept for a later scan) with the reason. */
static int commissioning_refusal(const struct cycle *c, const struct uwb_verdict *v, char *note, size_t n)
{
    int moved = v->has_baseline && v->current.found && v->baseline.found &&
                fabs(v->axial_displacement_m) >= c->cfg->evaluate.compare.thresholds.alarm_m;
    if (v->status != UWB_STATUS_ALARM && !moved)
        return 0;
    if (c->req->force_baseline) { /* the operator's decision after a repair: said, not silent */
        uwbd_log(UWBD_LOG_WARNING,
                 "scan %s: baseline set force: taking it as the baseline although it is %+.2f mm from the "
                 "current one",
                 c->id, v->axial_displacement_m * 1e3);
        snprintf(note, n,
                 "forced (`baseline set force`): made the baseline although it is %s against the previous "
                 "one (%+.2f mm)",
                 v->status == UWB_STATUS_ALARM ? "an alarm" : "past the alarm threshold",
                 v->axial_displacement_m * 1e3);
        return 0;
    }
    snprintf(
        note, n,
        "refused: this scan is %s against the current baseline (%+.2f mm): a winding that moved is not made "
        "the baseline; inspect it, and if the move is known (a repair), send `baseline set force`",
        v->status == UWB_STATUS_ALARM ? "an alarm" : "past the alarm threshold",
        v->axial_displacement_m * 1e3);
    return 1;
}

/* A pending `baseline set`: make this scan the baseline when it is good;
 * c->baseline_note says why not, or how. Its time zero is the direct
 * coupling the evaluation found in it. */
static void set_baseline_if_good(struct cycle *c, const struct uwb_scan *scan, const struct uwb_verdict *v)
{
    if (commissioning_refusal(c, v, c->baseline_note, sizeof c->baseline_note)) {
        c->res->baseline_refused = 1;
        uwbd_log(UWBD_LOG_WARNING, "scan %s: baseline set %s", c->id, c->baseline_note);
        return;
    }
    if (!v->current.found) {
        snprintf(
            c->baseline_note, sizeof c->baseline_note,
            "not set: the winding's edges were not found in this scan; the next good scan will be tried");
        return;
    }
    char why[200];
    if (!uwb_face_within_drawings(&c->cfg->evaluate.analysis, v->current.face_z_m, v->current.lower_m,
                                  v->current.upper_m, why, sizeof why)) {
        c->res->baseline_refused = 1;
        snprintf(c->baseline_note, sizeof c->baseline_note, "not set: %.200s", why);
        uwbd_log(UWBD_LOG_WARNING, "scan %s: baseline %s", c->id, c->baseline_note);
        return;
    }
    if (!v->has_direct_coupling) {
        snprintf(
            c->baseline_note, sizeof c->baseline_note,
            "not set: no direct coupling to take time zero from (%.120s); the next good scan will be tried",
            v->direct_coupling_why);
        return;
    }
    struct uwbd_baseline_info info = {0};
    snprintf(info.scan_id, sizeof info.scan_id, "%s", c->id);
    snprintf(info.created, sizeof info.created, "%s", scan->created ? scan->created : "");
    uwbd_utc_text(c->req->now, info.set_at, sizeof info.set_at);
    info.has_direct_coupling = 1;
    info.direct_coupling_s = v->direct_coupling_s;
    info.scans = c->baseline_scans > 0 ? c->baseline_scans : 1;
    info.has_repeatability = c->has_repeatability;
    info.repeatability_m = c->repeatability_m;
    c->baseline_scans = info.scans;
    char err[512];
    if (uwbd_baseline_set(c->store, scan, &info, c->cfg->evaluate.direct_coupling.window_end_s, err,
                          sizeof err) != 0) {
        write_problem(c, "baseline", err);
        snprintf(c->baseline_note, sizeof c->baseline_note, "not set: %.200s", err);
        return;
    }
    c->res->baseline_set = 1;
    uwbd_log(UWBD_LOG_NOTICE, "scan %s is the new baseline (direct coupling at %.1f ps)", c->id,
             v->direct_coupling_s * 1e12);
}

/* The centre of the winding in one scan alone (NaN when not found): what
 * the commissioning scans' spread is measured on. */
static double scan_centre(const struct cycle *c, const struct uwb_scan *scan)
{
    struct uwb_verdict v;
    struct uwb_analysis a, unused;
    char err[256];
    if (uwb_evaluate(scan, NULL, &c->cfg->evaluate, &v, &a, &unused, err, sizeof err) != 0)
        return NAN;
    uwb_analysis_free(&a);
    uwb_analysis_free(&unused);
    return v.current.found ? v.current.center_m : NAN;
}

/* `baseline set N`: N acquisitions back to back, averaged into *scan; the
 * spread of their centres is the baseline's repeatability. */
static int acquire_baseline_scans(struct cycle *c, struct uwb_scan *scan, char *err, size_t errlen)
{
    int n =
        c->req->baseline_scans > UWBD_BASELINE_SCANS_MAX ? UWBD_BASELINE_SCANS_MAX : c->req->baseline_scans;
    double centres[UWBD_BASELINE_SCANS_MAX];
    centres[0] = scan_centre(c, scan);
    for (int i = 1; i < n; i++) {
        struct uwb_scan added;
        int rc = uwbd_acquire_and_average(c->acquire, c->acquire_ctx, c->stop, scan, &added, err, errlen);
        if (rc == UWBD_ACQUIRE_STOPPED)
            return rc;
        if (rc != UWBD_ACQUIRE_OK) { /* keep what was acquired: the scans so far make the baseline */
            uwbd_log(UWBD_LOG_WARNING,
                     "baseline: acquisition %d of %d failed (%s); averaging the %d acquired", i + 1, n, err,
                     i);
            n = i;
            break;
        }
        centres[i] = scan_centre(c, &added);
        uwb_scan_free(&added);
        c->acquisitions++;
    }
    int used = 0;
    c->repeatability_m = uwbd_spread(centres, n, &used);
    c->has_repeatability = used >= 2;
    c->baseline_scans = n;
    uwbd_log(UWBD_LOG_INFO,
             "baseline: %d scans averaged; their centres spread %.3f mm (1-sigma, %d with edges)", n,
             c->repeatability_m * 1e3, used);
    return UWBD_ACQUIRE_OK;
}

/* Inconclusive only for noise that more pulses would average down: acquire
 * again and average, within analysis.reacquire_budget_s of the cycle's
 * start, re-evaluating each time. Why it stopped short goes to the verdict.
 * -1 (err) when the evaluation itself fails. */
static int reacquire_until_decisive(struct cycle *c, struct uwb_scan *scan,
                                    const struct uwb_baseline_record *base,
                                    const struct uwb_evaluate_options *opt, struct uwb_verdict *v,
                                    struct uwb_analysis *cur_a, struct uwb_analysis *base_a,
                                    const char *scan_path, char *err, size_t errlen)
{
    double max_m = opt->compare.max_uncertainty_m, budget = c->cfg->reacquire_budget_s;
    int added_any = 0;
    double sigma_before = 0;
    int pulses_before = 0;
    while (budget > 0 && v->status == UWB_STATUS_INCONCLUSIVE && v->has_baseline && v->current.found &&
           v->baseline.found && v->uncertainty_m > max_m) {
        int pulses = scan->stack > 0 ? scan->stack : 1;
        /* First from the verdict's noise term; once sigma has been seen at two
         * pulse counts, from how it actually fell. */
        int more = added_any ? uwbd_acquisitions_needed_fit(sigma_before, pulses_before, v->uncertainty_m,
                                                            pulses, max_m, c->pulses_each)
                             : uwbd_acquisitions_needed(v, max_m, pulses, c->pulses_each);
        sigma_before = v->uncertainty_m;
        pulses_before = pulses;
        double spent = uwb_monotonic_s() - c->started_s;
        if (more < 0) {
            snprintf(c->reacquire_note, sizeof c->reacquire_note,
                     "more pulses cannot bring the uncertainty under %.2f mm: its part that does not average "
                     "down is over it",
                     max_m * 1e3);
            break;
        }
        if (more < 1)
            more = 1;
        if (spent + more * c->acquire_s > budget) {
            snprintf(c->reacquire_note, sizeof c->reacquire_note,
                     "%d more acquisition%s (about %.0f s) would be needed, over analysis.reacquire_budget_s "
                     "%.0f s",
                     more, more == 1 ? "" : "s", more * c->acquire_s, budget);
            break;
        }
        struct uwb_scan added;
        char why[256];
        int rc = uwbd_acquire_and_average(c->acquire, c->acquire_ctx, c->stop, scan, &added, why, sizeof why);
        if (rc != UWBD_ACQUIRE_OK) {
            snprintf(c->reacquire_note, sizeof c->reacquire_note, "acquiring again failed: %.200s", why);
            break;
        }
        uwb_scan_free(&added);
        c->acquisitions++;
        added_any = 1;
        uwb_analysis_free(cur_a);
        uwb_analysis_free(base_a);
        if (uwb_evaluate(scan, base, opt, v, cur_a, base_a, err, errlen) != 0)
            return -1;
        uwbd_log(UWBD_LOG_INFO, "scan %s: acquired again (%d pulses per position): uncertainty %.2f mm",
                 c->id, scan->stack, v->uncertainty_m * 1e3);
    }
    /* The archive keeps the scan the verdict was made from (scan_path NULL:
     * the first acquisition could not be stored either). */
    char write_err[512];
    if (added_any && scan_path && uwbscan_write_file(scan_path, scan, write_err, sizeof write_err) != 0)
        archive_problem(c, "archive", write_err);
    return 0;
}

/* Everything after a successful acquisition. */
static void process_scan(struct cycle *c, struct uwb_scan *scan)
{
    struct uwb_verdict v;
    char err[512];
    choose_id(c, scan->scan_id);
    if (replace_text(&scan->scan_id, c->id) != 0 ||
        (!scan->created && replace_text(&scan->created, c->created) != 0)) {
        record_error(c, "out of memory");
        return;
    }
    /* A scan that cannot be stored (the disk full, the archive read-only)
     * is evaluated all the same, from memory: a full disk must not hide a
     * winding that moved from the contacts and the site. Its verdict says
     * the raw scan is not archived; no image or baseline is made of it. */
    char scan_path[UWBD_PATH_MAX + 200];
    int stored = 0;
    if (!c->have_day_dir) {
        archive_problem(c, "archive (the scan is evaluated all the same)", c->day_dir_error);
    } else {
        snprintf(scan_path, sizeof scan_path, "%s/%s.uwbscan", c->day_dir, c->id);
        if (uwbscan_write_file(scan_path, scan, err, sizeof err) != 0)
            archive_problem(c, "archive (the scan is evaluated all the same)", err);
        else
            stored = 1;
    }

    struct uwb_scan base = {0};
    struct uwbd_baseline_info info = {0};
    int b = uwbd_baseline_watch(c->store, c->cfg->evaluate.direct_coupling.window_end_s,
                                c->req->has_expected ? &c->req->expected : NULL, &base, &info, c->res->fault,
                                sizeof c->res->fault);
    c->res->baseline_checked = 1;
    if (b == UWBD_BASELINE_FAULT)
        uwbd_log(UWBD_LOG_WARNING, "scan %s not compared: fault: %s", c->id, c->res->fault);
    /* The baseline with what was recorded with it at commissioning. */
    struct uwb_baseline_record against = {.scan = &base,
                                          .has_direct_coupling = info.has_direct_coupling,
                                          .direct_coupling_s = info.direct_coupling_s,
                                          .scans = info.scans,
                                          .has_repeatability = info.has_repeatability,
                                          .repeatability_m = info.repeatability_m};
    const struct uwb_baseline_record *baseline = b == UWBD_BASELINE_LOADED ? &against : NULL;

    struct uwb_analysis cur_a, base_a;
    if (uwb_evaluate(scan, baseline, &c->cfg->evaluate, &v, &cur_a, &base_a, err, sizeof err) != 0 ||
        (baseline && reacquire_until_decisive(c, scan, baseline, &c->cfg->evaluate, &v, &cur_a, &base_a,
                                              stored ? scan_path : NULL, err, sizeof err) != 0)) {
        uwb_scan_free(&base);
        record_error(c, "evaluation failed: %s", err);
        return;
    }
    uwb_scan_free(&base);

    if (c->req->make_baseline && !stored)
        snprintf(c->baseline_note, sizeof c->baseline_note,
                 "not set: the scan could not be archived (%.160s); the next good scan will be tried",
                 c->archive_error);
    else if (c->req->make_baseline)
        set_baseline_if_good(c, scan, &v);
    if (b == UWBD_BASELINE_FAULT) {
        if (c->res->baseline_set) {
            snprintf(c->baseline_note, sizeof c->baseline_note,
                     "replaced a baseline that failed its check: %.200s", c->res->fault);
            c->res->fault[0] = '\0';
        } else {
            v.status = UWB_STATUS_ERROR;
            snprintf(v.reason, sizeof v.reason, "fault: %.240s", c->res->fault);
            snprintf(v.fault, sizeof v.fault, "baseline");
        }
    }
    /* The images after the baseline was set, so a commissioning scan's
     * say it became the baseline (not "none given"). */
    char asset[256];
    uwbd_trend_site_text(c->cfg, asset, sizeof asset);
    struct uwb_provenance site = {.asset = asset,
                                  .thresholds = &c->cfg->evaluate.compare.thresholds,
                                  .radial_thresholds = &c->cfg->evaluate.compare.radial_thresholds,
                                  .became_baseline = c->res->baseline_set};
    if (stored && uwb_write_images(c->day_dir, c->id, &site, scan, &cur_a, &base_a, &v, err, sizeof err) != 0)
        archive_problem(c, "images", err);
    uwb_analysis_free(&cur_a);
    uwb_analysis_free(&base_a);
    struct uwb_verdict_record *r = new_record(&v);
    if (r)
        add_cycle_fields(c, &r->cycle, stored ? scan_path : NULL, scan->stack);
    record(c, &v, r);
    uwbd_log(UWBD_LOG_INFO, "scan %s: %s%s%s", c->id, uwb_status_name(v.status), v.reason[0] ? ": " : "",
             v.reason);
}

int uwbd_cycle_run(const struct uwbd_config *cfg, const struct uwbd_store *store, uwbd_acquire_fn acquire,
                   void *acquire_ctx, const volatile sig_atomic_t *stop, const struct uwbd_cycle_request *req,
                   struct uwbd_cycle_result *res)
{
    memset(res, 0, sizeof *res);
    struct cycle c = {.cfg = cfg,
                      .store = store,
                      .req = req,
                      .res = res,
                      .acquire = acquire,
                      .acquire_ctx = acquire_ctx,
                      .stop = stop,
                      .started_s = uwb_monotonic_s()};
    uwbd_utc_text(req->now, c.created, sizeof c.created);
    char newest[64];
    if (uwbd_verdict_log_latest_created(store, newest, sizeof newest) && strcmp(c.created, newest) < 0)
        snprintf(
            c.clock_note, sizeof c.clock_note,
            "this scan's time %s is earlier than the newest recorded scan's (%.40s): the clock went back",
            c.created, newest);
    if (c.clock_note[0])
        uwbd_log(UWBD_LOG_WARNING, "%s", c.clock_note);
    struct tm utc;
    gmtime_r(&req->now, &utc);
    char err[512];
    c.have_day_dir = uwbd_store_day_dir(store, &utc, c.day_dir, sizeof c.day_dir, c.day_dir_error,
                                        sizeof c.day_dir_error) == 0;

    struct uwb_scan scan = {0};
    int rc = acquire(acquire_ctx, stop, &scan, err, sizeof err);
    c.acquire_s = uwb_monotonic_s() - c.started_s;
    c.acquisitions = 1;
    c.pulses_each = scan.stack > 0 ? scan.stack : 1;
    if (rc == UWBD_ACQUIRE_OK && req->make_baseline && req->baseline_scans > 1)
        rc = acquire_baseline_scans(&c, &scan, err, sizeof err);
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
    const char *clock_how = NULL;
    int removed = 0, synchronised = uwbd_clock_synchronised_from(UWBD_TIMESYNC_FLAG, &clock_how);
    static int said_unsynchronised; /* once per run, not once per scan */
    if (cfg->retention_max_age_days > 0 && !synchronised && !said_unsynchronised++)
        uwbd_log(UWBD_LOG_NOTICE,
                 "retention: the system clock is not synchronised (%s): "
                 "retention.max_age_days waits for it (max_scans still applies)",
                 clock_how);
    struct uwbd_retention_budget budget = {.max_deletions = UWBD_RETENTION_SCANS_PER_CYCLE,
                                           .max_seconds = UWBD_RETENTION_SECONDS_PER_CYCLE,
                                           .stop = stop};
    if (uwbd_retention_apply_within(store, cfg->retention_max_scans, cfg->retention_max_age_days, req->now,
                                    synchronised, &budget, &removed, err, sizeof err) != 0)
        uwbd_log(UWBD_LOG_ERR, "retention: %s", err);
    else if (removed || budget.cut_short)
        uwbd_log(UWBD_LOG_INFO, "retention: deleted %d archived scan%s%s", removed, removed == 1 ? "" : "s",
                 budget.cut_short ? *stop ? "; stopped, the rest at the next cycle"
                                          : "; the rest at the next cycle (a cycle's share is done)"
                                  : "");
    return 0;
}

void uwbd_cycle_result_free(struct uwbd_cycle_result *res)
{
    free(res->verdict_json);
    res->verdict_json = NULL;
    free(res->verdict);
    res->verdict = NULL;
}
