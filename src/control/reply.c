/* Building the JSON reply lines (see the header). */
#include "control/reply.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "control/command.h"
#include "state/state_writes.h"
#include "integrations/mqtt_publisher.h"
#include "integrations/site_io.h"
#include "uwb/utc_time.h"
#include "uwb/verdict_json.h"

static char *finish(cJSON *o)
{
    if (!o)
        return NULL;
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return text;
}

static cJSON *start(const char *class_name)
{
    cJSON *o = cJSON_CreateObject();
    if (o)
        cJSON_AddStringToObject(o, "class", class_name);
    return o;
}

char *uwbd_reply_error(const char *message)
{
    cJSON *o = start("ERROR");
    if (o)
        cJSON_AddStringToObject(o, "message", message);
    return finish(o);
}

char *uwbd_reply_help(void)
{
    cJSON *o = start("HELP");
    if (!o)
        return NULL;
    cJSON_AddNumberToObject(o, "proto_major", UWBD_PROTOCOL_MAJOR);
    cJSON_AddNumberToObject(o, "proto_minor", UWBD_PROTOCOL_MINOR);
    cJSON *list = cJSON_AddArrayToObject(o, "commands");
    for (size_t i = 0; list && i < uwb_command_help_count; i++) {
        cJSON *c = cJSON_CreateObject();
        if (!c)
            break;
        cJSON_AddStringToObject(c, "command", uwb_command_help[i].usage);
        cJSON_AddStringToObject(c, "description", uwb_command_help[i].description);
        cJSON_AddItemToArray(list, c);
    }
    return finish(o);
}

/* A verdict line from verdicts.jsonl as `history` lists it; NULL when the
 * line is not a verdict this uwbd reads. */
static cJSON *history_entry(const char *verdict_line)
{
    struct uwb_verdict_record *r = malloc(sizeof *r);
    char err[256];
    cJSON *s =
        r && uwb_record_from_json(verdict_line, r, err, sizeof err) == 0 ? uwb_record_history_entry(r) : NULL;
    free(r);
    return s;
}

static cJSON *baseline_object(const struct uwbd_baseline_info *b)
{
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "scan_id", b->scan_id);
    if (b->created[0])
        cJSON_AddStringToObject(o, "created", b->created);
    if (b->set_at[0])
        cJSON_AddStringToObject(o, "set_at", b->set_at);
    if (b->has_direct_coupling)
        uwb_json_add_ps(o, "direct_coupling_ps", b->direct_coupling_s);
    if (b->scans > 0)
        cJSON_AddNumberToObject(o, "scans", b->scans);
    if (b->has_repeatability)
        cJSON_AddNumberToObject(o, "repeatability_mm", round(b->repeatability_m * 1e6) / 1e3);
    return o;
}

/* Seconds since the baseline was set (or, for an older one without set_at,
 * taken). */
static void add_baseline_age(cJSON *baseline, const struct uwbd_baseline_info *b, time_t now)
{
    time_t at;
    const char *when = b->set_at[0] ? b->set_at : b->created;
    if (baseline && now > 0 && uwb_utc_parse(when, &at) == 0 && now >= at)
        cJSON_AddNumberToObject(baseline, "age_s", (double)(now - at));
}

/* Issue 31: what the site's integrations are doing, after the older keys. */
static void add_integrations(cJSON *o, const struct uwbd_status *st)
{
    if (st->asset_id && st->asset_id[0])
        cJSON_AddStringToObject(o, "asset_id", st->asset_id);
    cJSON *modbus = st->modbus_endpoint ? cJSON_AddObjectToObject(o, "modbus") : NULL;
    if (modbus) {
        cJSON_AddBoolToObject(modbus, "listening", st->modbus_listening);
        cJSON_AddStringToObject(modbus, "endpoint", st->modbus_endpoint);
    }
    cJSON *contacts = st->contacts ? cJSON_AddObjectToObject(o, "contacts") : NULL;
    if (contacts) {
        cJSON_AddBoolToObject(contacts, "watch", st->contacts->watch > 0);
        cJSON_AddBoolToObject(contacts, "alarm", st->contacts->alarm > 0);
        cJSON_AddBoolToObject(contacts, "fault", st->contacts->fault > 0);
    }
    if (st->has_state_dir_free)
        cJSON_AddNumberToObject(o, "state_dir_free_bytes", (double)st->state_dir_free_bytes);
    /* Issue 43, break 6: only while writes fail, so a healthy reply is as it was. */
    cJSON *writes = st->writes && st->writes->failing ? cJSON_AddObjectToObject(o, "state_dir_writes") : NULL;
    if (writes) {
        cJSON_AddBoolToObject(writes, "failing", 1);
        cJSON_AddBoolToObject(writes, "disk_full", st->writes->disk_full);
        cJSON_AddStringToObject(writes, "since", st->writes->since);
        cJSON_AddNumberToObject(writes, "cycles", st->writes->cycles);
        cJSON_AddStringToObject(writes, "error", st->writes->error);
    }
}

char *uwbd_reply_status(const struct uwbd_status *st)
{
    cJSON *o = start("STATUS");
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "version", st->version);
    cJSON_AddNumberToObject(o, "proto_major", UWBD_PROTOCOL_MAJOR);
    cJSON_AddNumberToObject(o, "proto_minor", UWBD_PROTOCOL_MINOR);
    cJSON_AddStringToObject(o, "state", st->state);
    if (st->progress) {
        cJSON *p = cJSON_AddObjectToObject(o, "progress");
        if (p && uwbd_progress_add_fields(p, st->progress) != 0)
            cJSON_DeleteItemFromObjectCaseSensitive(o, "progress");
    }
    cJSON_AddNumberToObject(o, "uptime_s", (double)st->uptime_s);
    cJSON_AddNumberToObject(o, "interval_s", st->interval_s);
    if (st->has_next_scan)
        cJSON_AddNumberToObject(o, "next_scan_in_s", (double)st->next_scan_in_s);
    cJSON_AddNumberToObject(o, "scans_this_run", st->scans_this_run);
    cJSON_AddBoolToObject(o, "scan_queued", st->scan_queued);
    if (st->fault)
        cJSON_AddStringToObject(o, "fault", st->fault);
    cJSON_AddBoolToObject(o, "baseline_pending", st->baseline_pending);
    if (st->has_baseline)
        cJSON_AddItemToObject(o, "baseline", baseline_object(&st->baseline));
    if (st->has_baseline)
        add_baseline_age(cJSON_GetObjectItemCaseSensitive(o, "baseline"), &st->baseline, st->now);
    if (st->has_baseline && st->fault)
        cJSON_AddStringToObject(cJSON_GetObjectItemCaseSensitive(o, "baseline"), "check", "failed");
    if (st->latest) {
        cJSON *latest = uwb_record_summary(st->latest);
        if (latest)
            cJSON_AddItemToObject(o, "latest", latest);
    }
    int has_phase = st->site_phase && st->site_phase[0], has_label = st->site_label && st->site_label[0];
    cJSON *site = has_phase || has_label ? cJSON_AddObjectToObject(o, "site") : NULL;
    if (site && has_phase)
        cJSON_AddStringToObject(site, "phase", st->site_phase);
    if (site && has_label)
        cJSON_AddStringToObject(site, "label", st->site_label);
    cJSON *mqtt = st->mqtt ? cJSON_AddObjectToObject(o, "mqtt") : NULL;
    if (mqtt) {
        cJSON_AddStringToObject(mqtt, "link", st->mqtt->state);
        if (st->mqtt->reason[0])
            cJSON_AddStringToObject(mqtt, "reason", st->mqtt->reason);
        cJSON_AddNumberToObject(mqtt, "queued", (double)st->mqtt->queued);
    }
    cJSON_AddStringToObject(o, "state_dir", st->state_dir);
    cJSON_AddStringToObject(o, "rig", st->rig);
    if (st->console)
        cJSON_AddStringToObject(o, "console", st->console);
    add_integrations(o, st);
    return finish(o);
}

char *uwbd_reply_history(char *const *verdict_lines, int count, int requested, int skipped)
{
    cJSON *o = start("HISTORY");
    if (!o)
        return NULL;
    cJSON *list = cJSON_CreateArray();
    int listed = 0;
    for (int i = 0; list && i < count; i++) {
        cJSON *s = history_entry(verdict_lines[i]);
        if (s && cJSON_AddItemToArray(list, s))
            listed++;
        else if (!s)
            skipped++; /* a JSON object, but not a verdict this uwbd reads */
    }
    cJSON_AddNumberToObject(o, "requested", requested);
    cJSON_AddNumberToObject(o, "count", listed);
    if (skipped)
        cJSON_AddNumberToObject(o, "unreadable_lines", skipped);
    if (!list || !cJSON_AddItemToObject(o, "verdicts", list)) {
        cJSON_Delete(list);
        cJSON_Delete(o);
        return NULL;
    }
    return finish(o);
}

char *uwbd_reply_baseline(int pending, int has_current, const struct uwbd_baseline_info *current)
{
    cJSON *o = start("BASELINE");
    if (!o)
        return NULL;
    cJSON_AddBoolToObject(o, "pending", pending);
    cJSON_AddStringToObject(
        o, "message", pending ? "the next good scan becomes the baseline" : "no baseline change pending");
    if (has_current)
        cJSON_AddItemToObject(o, "current", baseline_object(current));
    return finish(o);
}

char *uwbd_reply_watch(int watch)
{
    cJSON *o = start("WATCH");
    if (!o)
        return NULL;
    cJSON_AddBoolToObject(o, "enable", watch != 0);
    cJSON_AddBoolToObject(o, "progress", watch != 0);
    cJSON_AddBoolToObject(o, "verdicts", watch == 1);
    return finish(o);
}

char *uwbd_reply_ack(const struct uwbd_contact_states *st, const struct uwb_verdict_record *latest)
{
    cJSON *o = start("ACK");
    if (!o)
        return NULL;
    cJSON *contacts = cJSON_AddObjectToObject(o, "contacts");
    cJSON_AddBoolToObject(contacts, "watch", st->watch > 0);
    cJSON_AddBoolToObject(contacts, "alarm", st->alarm > 0);
    cJSON_AddBoolToObject(contacts, "fault", st->fault > 0);
    /* What the contacts follow now the latches are released: a person
     * reads from it why a contact still holds. */
    cJSON *summary = latest ? uwb_record_history_entry(latest) : NULL;
    if (summary)
        cJSON_AddItemToObject(o, "latest", summary);
    return finish(o);
}

char *uwbd_reply_event(int queued)
{
    cJSON *o = start("EVENT");
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "scan", queued ? "queued" : "started");
    return finish(o);
}

char *uwbd_reply_scan_requested(int queued)
{
    cJSON *o = start("SCAN");
    if (!o)
        return NULL;
    cJSON_AddStringToObject(o, "scan", queued ? "queued" : "started");
    return finish(o);
}
