/* `trend` and trend.png (see daemon/trend.h). */
#include "daemon/trend.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>

#include "state/verdict_log.h"
#include "uwb/verdict_json.h"
#include "output/render_trend.h"

int uwbd_trend_read(const struct uwbd_store *store, int n, struct uwb_trend *t, char *err, size_t errlen)
{
    char **lines = NULL;
    int count = 0, skipped = 0;
    /* The rate is read over the same window whatever n is (issue 48:
     * `trend 3` counted 1 figure since the last baseline change where
     * `trend` counted 3); the rows are the last n of it. */
    int window = n > UWBD_TREND_RATE_VERDICTS ? n : UWBD_TREND_RATE_VERDICTS;
    if (uwbd_verdict_log_tail(store, window, &lines, &count, &skipped, err, errlen) != 0)
        return -1;
    int shown = n < count ? n : count;
    struct uwb_trend whole;
    int rc = uwb_trend_from_lines(lines, count, &whole);
    if (rc == 0) {
        rc = uwb_trend_from_lines(lines + (count - shown), shown, t);
        if (rc == 0)
            t->rate = whole.rate;
        uwb_trend_free(&whole);
    }
    uwbd_verdict_lines_free(lines, count);
    if (rc != 0) {
        snprintf(err, errlen, "%s: out of memory for the trend", store->verdict_log);
        return -1;
    }
    t->unreadable += skipped;
    return 0;
}

void uwbd_trend_site_text(const struct uwbd_config *cfg, char *buf, size_t n)
{
    const char *asset = cfg->site.asset_id, *phase = cfg->site_phase, *label = cfg->site_label;
    snprintf(buf, n, "%s%s%s%s%s%s", asset, asset[0] && (phase[0] || label[0]) ? ", " : "",
             phase[0] ? "phase " : "", phase, phase[0] && label[0] ? ", " : "", label);
}

int uwbd_trend_png_path(const struct uwbd_store *store, char *path, size_t n)
{
    return uwbd_path_join(path, n, store->root, UWBD_TREND_PNG_NAME);
}

int uwbd_trend_png_update(const struct uwbd_config *cfg, const struct uwbd_store *store, const char *site,
                          char *err, size_t errlen)
{
    char path[UWBD_PATH_MAX + 32];
    if (uwbd_trend_png_path(store, path, sizeof path) != 0) {
        snprintf(err, errlen, "%.64s...: state directory path too long for %s", store->root,
                 UWBD_TREND_PNG_NAME);
        return -1;
    }
    struct uwb_trend t;
    if (uwbd_trend_read(store, UWBD_TREND_PNG_VERDICTS, &t, err, errlen) != 0)
        return -1;
    int rc = uwb_render_trend_png(path, &t, &cfg->evaluate.compare.thresholds, site, err, errlen);
    uwb_trend_free(&t);
    return rc;
}

/* Millimetres to 0.01 mm, as the verdicts give them. */
static void add_mm(cJSON *o, const char *key, double mm)
{
    cJSON_AddNumberToObject(o, key, round(mm * 100.0) / 100.0);
}

/* An entry: the record's trend summary, and where a new baseline starts. */
static cJSON *entry_object(const struct uwb_trend_entry *e)
{
    cJSON *o = uwb_record_trend_entry(&e->summary, e->became_baseline);
    if (o && e->baseline_change)
        cJSON_AddBoolToObject(o, "baseline_change", 1);
    return o;
}

char *uwbd_reply_trend(const struct uwb_trend *t, int requested, const struct uwb_thresholds *th,
                       const char *image)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "class", "TREND");
    cJSON_AddNumberToObject(o, "requested", requested);
    cJSON_AddNumberToObject(o, "count", t->count);
    if (t->unreadable)
        cJSON_AddNumberToObject(o, "unreadable_lines", t->unreadable);
    cJSON_AddStringToObject(o, "uncertainty", "1 sigma");
    cJSON *limits = cJSON_AddObjectToObject(o, "thresholds");
    if (limits) {
        add_mm(limits, "watch_mm", th->watch_m * 1e3);
        add_mm(limits, "alarm_mm", th->alarm_m * 1e3);
    }
    cJSON *rate = cJSON_AddObjectToObject(o, "rate");
    if (rate) {
        cJSON_AddNumberToObject(rate, "figures", t->rate.points);
        if (t->rate.known) {
            add_mm(rate, "mm_per_year", t->rate.mm_per_day * 365.25);
            add_mm(rate, "sigma_mm_per_year", t->rate.sigma_mm_per_day * 365.25);
        }
        if (t->rate.points >= 2)
            cJSON_AddNumberToObject(rate, "days", round(t->rate.days * 10.0) / 10.0);
        /* No figure where the span or the figures cannot support one:
         * why, in words (as a verdict's height_change_withheld). */
        if (!t->rate.known)
            cJSON_AddStringToObject(rate, "withheld", t->rate.withheld);
    }
    cJSON *list = cJSON_AddArrayToObject(o, "verdicts");
    for (int i = 0; list && i < t->count; i++) {
        cJSON *p = entry_object(&t->entries[i]);
        if (p)
            cJSON_AddItemToArray(list, p);
    }
    if (image)
        cJSON_AddStringToObject(o, "image", image);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}
