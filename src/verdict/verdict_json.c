/* The VERDICT object written from the published record, and read back into
 * it: the one place that knows the verdict's keys. */
#include "uwb/verdict_json.h"

#include "uwb/verdict_fields.h"
#include "verdict/json_key_reader.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void uwb_json_add_ps(cJSON *obj, const char *key, double seconds)
{
    cJSON_AddNumberToObject(
        obj, key, uwb_field_round(uwb_field_find(&uwb_verdict_fields, NULL, "direct_coupling_ps"), seconds));
}

static void add_text(cJSON *o, const char *key, const char *text)
{
    if (text[0])
        cJSON_AddStringToObject(o, key, text);
}

static void add_cycle(cJSON *o, const struct uwb_verdict_cycle *c)
{
    if (c->has_scan_file)
        cJSON_AddStringToObject(o, "scan_file", c->scan_file);
    if (c->has_baseline_set) {
        cJSON_AddBoolToObject(o, "baseline_set", c->baseline_set);
        add_text(o, "baseline_note", c->baseline_note);
    }
    if (c->pulses_per_position > 0) {
        cJSON_AddNumberToObject(o, "pulses_per_position", c->pulses_per_position);
        cJSON_AddNumberToObject(o, "acquisitions", c->acquisitions);
    }
    add_text(o, "reacquire_note", c->reacquire_note);
    if (c->baseline_scans > 0) {
        cJSON_AddNumberToObject(o, "baseline_scans", c->baseline_scans);
        if (c->has_baseline_repeatability)
            cJSON_AddNumberToObject(o, "baseline_repeatability_mm", c->baseline_repeatability_mm);
    }
    add_text(o, "asset_id", c->asset_id);
    add_text(o, "trigger", c->trigger);
    if (!c->archive_error_late)
        add_text(o, "archive_error", c->archive_error);
    add_text(o, "clock_warning", c->clock_warning);
    if (c->archive_error_late)
        add_text(o, "archive_error", c->archive_error);
    add_text(o, "record_error", c->record_error);
}

cJSON *uwb_record_object(const struct uwb_verdict_record *r)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "class", "VERDICT");
    uwb_fields_write(&uwb_verdict_fields, r, o);
    cJSON *images = cJSON_AddArrayToObject(o, "images");
    for (int i = 0; images && i < r->n_images; i++)
        cJSON_AddItemToArray(images, cJSON_CreateString(r->images[i]));
    add_cycle(o, &r->cycle);
    return o;
}

/* The single-line text of o, which is freed; NULL when o is. */
static char *print_and_delete(cJSON *o)
{
    char *text = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    return text;
}

char *uwb_record_to_json(const struct uwb_verdict_record *r)
{
    return print_and_delete(uwb_record_object(r));
}

cJSON *uwb_verdict_object(const struct uwb_verdict *v)
{
    struct uwb_verdict_record *r = malloc(sizeof *r);
    if (!r)
        return NULL;
    uwb_record_from_verdict(r, v);
    cJSON *o = uwb_record_object(r);
    free(r);
    return o;
}

char *uwb_verdict_to_json(const struct uwb_verdict *v)
{
    return print_and_delete(uwb_verdict_object(v));
}

/* The record's object with only `keys` (those it has), in their order. */
static cJSON *object_with(const struct uwb_verdict_record *r, const char *const *keys, size_t n)
{
    cJSON *full = uwb_record_object(r);
    cJSON *s = full ? cJSON_CreateObject() : NULL;
    for (size_t i = 0; s && i < n; i++) {
        cJSON *item = cJSON_DetachItemFromObjectCaseSensitive(full, keys[i]);
        if (item)
            cJSON_AddItemToObject(s, keys[i], item);
    }
    cJSON_Delete(full);
    return s;
}

/* What the summaries carry from the cycle, beside the table's rows. */
static const struct uwb_field_extra summary_extra[] = {
    {"baseline_set", 9, 9},
    {"height_change_withheld", 0, 11},
    {"trigger", 0, 19},
    {"asset_id", 0, 20},
};

static cJSON *summary_of(const struct uwb_verdict_record *r, char which)
{
    const char *keys[UWB_FIELD_PLACES];
    size_t n = uwb_fields_keys(&uwb_verdict_fields, summary_extra,
                               sizeof summary_extra / sizeof summary_extra[0], which, keys, UWB_FIELD_PLACES);
    return object_with(r, keys, n);
}

cJSON *uwb_record_summary(const struct uwb_verdict_record *r)
{
    return summary_of(r, 's');
}

cJSON *uwb_record_history_entry(const struct uwb_verdict_record *r)
{
    /* The summary's keys first, as before; then what else a CSV row shows (uwb/verdict_csv.h). */
    return summary_of(r, 'h');
}

cJSON *uwb_record_trend_entry(const struct uwb_verdict_summary *s, int became_baseline)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    uwb_fields_write_trend(&uwb_verdict_fields, s, o);
    /* The reason only where it stands for the figure. */
    if (s->has_displacement)
        cJSON_DeleteItemFromObjectCaseSensitive(o, "reason");
    if (became_baseline)
        cJSON_AddBoolToObject(o, "baseline_set", 1);
    return o;
}

int uwb_record_from_trend_entry(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    if (!cJSON_IsObject(o)) {
        snprintf(err, errlen, "verdict: a trend entry that is not an object");
        return -1;
    }
    if (uwb_fields_read_trend(&uwb_verdict_fields, o, r, err, errlen) != 0)
        return -1;
    const cJSON *set = cJSON_GetObjectItemCaseSensitive(o, "baseline_set");
    r->cycle.has_baseline_set = cJSON_IsBool(set);
    r->cycle.baseline_set = cJSON_IsTrue(set);
    return 0;
}

/* ---- reading ------------------------------------------------------------------ */

/* Reading one object's cycle keys and images, the first problem kept. */
struct reader {
    const cJSON *o;
    struct uwb_json_key_reader keys;
};

static int int_at(struct reader *rd, const cJSON *o, const char *key, int *out)
{
    double x = 0;
    if (!uwb_json_key_number(&rd->keys, o, key, &x))
        return 0;
    if (x != floor(x) || x < 0 || x > 1e9) {
        uwb_json_key_refuse(&rd->keys, key, "not a whole number");
        return 0;
    }
    *out = (int)x;
    return 1;
}

/* Which of two keys comes first in o: 1 when a is after b. */
static int after(const cJSON *o, const char *a, const char *b)
{
    int seen_b = 0;
    for (const cJSON *it = o->child; it; it = it->next) {
        if (it->string && strcmp(it->string, b) == 0)
            seen_b = 1;
        if (it->string && strcmp(it->string, a) == 0)
            return seen_b;
    }
    return 0;
}

static void read_cycle(struct reader *rd, struct uwb_verdict_cycle *c)
{
    const cJSON *o = rd->o;
    c->has_scan_file = uwb_json_key_text(&rd->keys, o, "scan_file", c->scan_file, sizeof c->scan_file);
    const cJSON *set = cJSON_GetObjectItemCaseSensitive(o, "baseline_set");
    if (set && !cJSON_IsBool(set))
        uwb_json_key_refuse(&rd->keys, "baseline_set", "not true or false");
    c->has_baseline_set = cJSON_IsBool(set);
    c->baseline_set = cJSON_IsTrue(set);
    uwb_json_key_text(&rd->keys, o, "baseline_note", c->baseline_note, sizeof c->baseline_note);
    int_at(rd, o, "pulses_per_position", &c->pulses_per_position);
    int_at(rd, o, "acquisitions", &c->acquisitions);
    uwb_json_key_text(&rd->keys, o, "reacquire_note", c->reacquire_note, sizeof c->reacquire_note);
    int_at(rd, o, "baseline_scans", &c->baseline_scans);
    c->has_baseline_repeatability =
        uwb_json_key_number(&rd->keys, o, "baseline_repeatability_mm", &c->baseline_repeatability_mm);
    uwb_json_key_text(&rd->keys, o, "asset_id", c->asset_id, sizeof c->asset_id);
    uwb_json_key_text(&rd->keys, o, "trigger", c->trigger, sizeof c->trigger);
    uwb_json_key_text(&rd->keys, o, "archive_error", c->archive_error, sizeof c->archive_error);
    uwb_json_key_text(&rd->keys, o, "clock_warning", c->clock_warning, sizeof c->clock_warning);
    c->archive_error_late = c->clock_warning[0] && after(o, "archive_error", "clock_warning");
    uwb_json_key_text(&rd->keys, o, "record_error", c->record_error, sizeof c->record_error);
}

static void read_images(struct reader *rd, struct uwb_verdict_record *r)
{
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(rd->o, "images");
    if (images && !cJSON_IsArray(images))
        uwb_json_key_refuse(&rd->keys, "images", "not an array");
    const cJSON *it;
    cJSON_ArrayForEach(it, images)
    {
        if (r->n_images == UWB_MAX_IMAGES || !cJSON_IsString(it) ||
            strlen(it->valuestring) >= sizeof r->images[0]) {
            uwb_json_key_refuse(&rd->keys, "images", "too many paths, or one not a path");
            return;
        }
        memcpy(r->images[r->n_images++], it->valuestring, strlen(it->valuestring) + 1);
    }
}

/* The keys of a verdict, or of a summary of one, into *r: 0, or -1. */
static int read_record(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen)
{
    if (uwb_fields_read(&uwb_verdict_fields, o, r, err, errlen) != 0)
        return -1;
    struct reader rd = {.o = o, .keys = {.err = err, .errlen = errlen}};
    read_images(&rd, r);
    read_cycle(&rd, &r->cycle);
    return rd.keys.failed ? -1 : 0;
}

int uwb_record_from_object(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    if (!cJSON_IsObject(o) || !cJSON_IsString(cls) || strcmp(cls->valuestring, "VERDICT") != 0) {
        snprintf(err, errlen, "verdict: not a VERDICT object");
        return -1;
    }
    return read_record(o, r, err, errlen);
}

int uwb_record_from_summary(const cJSON *o, struct uwb_verdict_record *r, char *err, size_t errlen)
{
    memset(r, 0, sizeof *r);
    if (!cJSON_IsObject(o)) {
        snprintf(err, errlen, "verdict: a summary that is not an object");
        return -1;
    }
    if (read_record(o, r, err, errlen) != 0)
        return -1;
    /* The summary gives the height change without its sigma: not known, not 0. */
    if (r->has_height_change && !cJSON_HasObjectItem(o, "height_change_uncertainty_mm"))
        r->height_change_uncertainty_mm = NAN;
    return 0;
}

int uwb_history_each(const char *reply, int (*each)(const struct uwb_verdict_record *r, void *ctx), void *ctx,
                     char *err, size_t errlen)
{
    cJSON *o = reply ? cJSON_Parse(reply) : NULL;
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(o, "verdicts");
    struct uwb_verdict_record *r = malloc(sizeof *r);
    int rc = -1, i = 0;
    if (!r) {
        snprintf(err, errlen, "history: out of memory");
        goto done;
    }
    if (!cJSON_IsString(cls) || strcmp(cls->valuestring, "HISTORY") != 0 || !cJSON_IsArray(list)) {
        snprintf(err, errlen, "history: not a HISTORY reply with a list of verdicts");
        goto done;
    }
    const cJSON *it;
    cJSON_ArrayForEach(it, list)
    {
        char why[256];
        if (uwb_record_from_summary(it, r, why, sizeof why) != 0) {
            snprintf(err, errlen, "history: verdict %d: %s", i, why);
            goto done;
        }
        if (each(r, ctx) != 0) {
            snprintf(err, errlen, "history: verdict %d: not written", i);
            goto done;
        }
        i++;
    }
    rc = 0;
done:
    free(r);
    cJSON_Delete(o);
    return rc;
}

int uwb_record_from_json(const char *text, struct uwb_verdict_record *r, char *err, size_t errlen)
{
    cJSON *o = text ? cJSON_Parse(text) : NULL;
    if (!o) {
        memset(r, 0, sizeof *r);
        snprintf(err, errlen, "verdict: not JSON");
        return -1;
    }
    int rc = uwb_record_from_object(o, r, err, errlen);
    cJSON_Delete(o);
    return rc;
}
