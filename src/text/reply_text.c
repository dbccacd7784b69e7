/* Any reply line as text for people: `uwbd ctl --text` and the serial
 * console. A status page of aligned "Name : value" lines (as chronyc's
 * `tracking`), a history table, the help list, and a line or two for the
 * short replies; a VERDICT and a TREND as verdict_text.c and trend_text.c
 * print them. The control socket's JSON stays the programs' form. */
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "text/text_layout.h"
#include "uwb/reply_text.h"
#include "uwb/verdict_json.h"

/* The status page's names are padded to this many columns. */
#define NAME_WIDTH 16
/* The help list wraps its descriptions to fit a terminal's 80 columns. */
#define HELP_USAGE_WIDTH 22
#define HELP_LINE_WIDTH 79

static const cJSON *item(const cJSON *o, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(o, key);
}

static const char *text(const cJSON *o, const char *key)
{
    const cJSON *v = item(o, key);
    return cJSON_IsString(v) && v->valuestring ? v->valuestring : NULL;
}

/* Never NULL: what is printed where the key is missing. */
static const char *text_or(const cJSON *o, const char *key, const char *otherwise)
{
    const char *t = text(o, key);
    return t ? t : otherwise;
}

static int number(const cJSON *o, const char *key, double *out)
{
    const cJSON *v = item(o, key);
    if (!cJSON_IsNumber(v))
        return 0;
    *out = v->valuedouble;
    return 1;
}

static int yes(const cJSON *o, const char *key)
{
    return cJSON_IsTrue(item(o, key));
}

static void name(FILE *out, const char *label)
{
    fprintf(out, "%-*s: ", NAME_WIDTH, label);
}

/* 3 d 4 h, 2 h 5 min, 40 s: the two largest units. */
static void print_duration(FILE *out, double s)
{
    long t = s > 0 ? (long)(s + 0.5) : 0;
    if (t >= 86400)
        fprintf(out, "%ld d %ld h", t / 86400, t % 86400 / 3600);
    else if (t >= 3600)
        fprintf(out, "%ld h %ld min", t / 3600, t % 3600 / 60);
    else if (t >= 60)
        fprintf(out, "%ld min %ld s", t / 60, t % 60);
    else
        fprintf(out, "%ld s", t);
}

static void print_bytes(FILE *out, double bytes)
{
    static const char *const units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int u = 0;
    while (bytes >= 1024 && u < 4) {
        bytes /= 1024;
        u++;
    }
    fprintf(out, u ? "%.1f %s" : "%.0f %s", bytes, units[u]);
}

static void print_upper(FILE *out, const char *s)
{
    for (; s && *s; s++)
        fputc(*s >= 'a' && *s <= 'z' ? *s - 'a' + 'A' : *s, out);
}

/* "ALARM +11.97 ± 0.35 mm", or the status and its reason: the summary
 * read through the published record, as any verdict's figure is. */
static void print_figure(FILE *out, const cJSON *v, const struct text_marks *m)
{
    char err[160];
    struct uwb_verdict_record *r = malloc(sizeof *r);
    print_upper(out, text(v, "status"));
    if (r && uwb_record_from_summary(v, r, err, sizeof err) == 0) {
        if (r->has_displacement)
            fprintf(out, " %+.2f %s %.2f mm", r->axial_displacement_mm, m->plus_minus, r->uncertainty_mm);
        else if (r->reason[0])
            fprintf(out, " (%s)", r->reason);
    }
    free(r);
}

static int progress_of(const cJSON *o, struct uwbd_progress *p)
{
    memset(p, 0, sizeof *p);
    if (!number(o, "position", &p->position) || !number(o, "positions", &p->positions))
        return -1;
    if (!number(o, "pass", &p->pass) || !number(o, "passes", &p->passes))
        p->pass = p->passes = 1.0;
    p->has_elapsed = number(o, "elapsed_s", &p->elapsed_s);
    p->has_left = number(o, "left_s", &p->left_s);
    p->has_fraction = number(o, "fraction", &p->fraction);
    return 0;
}

int uwbd_progress_read(const char *reply, struct uwbd_progress *p)
{
    cJSON *o = cJSON_Parse(reply);
    int rc = cJSON_IsObject(o) ? progress_of(o, p) : -1;
    cJSON_Delete(o);
    return rc;
}

static void print_progress(FILE *out, const cJSON *o)
{
    struct uwbd_progress p;
    if (progress_of(o, &p) != 0)
        return;
    fprintf(out, "position %.0f of %.0f", p.position, p.positions);
    if (p.passes > 1)
        fprintf(out, ", pass %.0f of %.0f", p.pass, p.passes);
    if (p.has_elapsed)
        fprintf(out, ", %.0f s", p.elapsed_s);
    if (p.has_left)
        fprintf(out, ", about %.0f s left", p.left_s);
}

static void status_baseline(FILE *out, const cJSON *o)
{
    const cJSON *b = item(o, "baseline");
    double age, scans, rep;
    name(out, "Baseline");
    if (!cJSON_IsObject(b)) {
        fputs("none", out);
    } else {
        fputs(text_or(b, "scan_id", "?"), out);
        if (text(b, "set_at"))
            fprintf(out, ", set %s", text(b, "set_at"));
        if (number(b, "age_s", &age)) {
            fputs(" (", out);
            print_duration(out, age);
            fputs(" ago)", out);
        }
        if (number(b, "scans", &scans))
            fprintf(out, ", %.0f scans", scans);
        if (number(b, "repeatability_mm", &rep))
            fprintf(out, ", repeatability %.2f mm", rep);
        if (text(b, "check"))
            fprintf(out, ", check %s", text(b, "check"));
    }
    if (yes(o, "baseline_pending"))
        fputs("; the next good scan becomes the baseline", out);
    fputc('\n', out);
}

/* Issue 43, break 6: a state directory that refuses the cycles' writes (a
 * full disk) is said plainly, with what still works. */
static void status_state_writes(FILE *out, const cJSON *w)
{
    double cycles = 0;
    if (!cJSON_IsObject(w))
        return;
    name(out, "Archive");
    fprintf(out, "NOT WRITING%s since %s", yes(w, "disk_full") ? ", the disk is full," : "",
            text_or(w, "since", "?"));
    if (number(w, "cycles", &cycles))
        fprintf(out, " (%.0f scan%s)", cycles, cycles == 1 ? "" : "s");
    fprintf(out, ": %s; scans are still evaluated and published\n", text_or(w, "error", "?"));
}

static void status_integrations(FILE *out, const cJSON *o)
{
    const cJSON *mqtt = item(o, "mqtt"), *modbus = item(o, "modbus"), *contacts = item(o, "contacts");
    double queued, free_bytes;
    name(out, "MQTT");
    if (cJSON_IsObject(mqtt)) {
        fputs(text_or(mqtt, "link", "?"), out);
        if (number(mqtt, "queued", &queued))
            fprintf(out, ", %.0f verdict%s queued", queued, queued == 1 ? "" : "s");
        if (text(mqtt, "reason"))
            fprintf(out, " (%s)", text(mqtt, "reason"));
        fputc('\n', out);
    } else {
        fputs("off\n", out);
    }
    name(out, "Modbus");
    if (cJSON_IsObject(modbus))
        fprintf(out, "%s %s\n", yes(modbus, "listening") ? "listening on" : "NOT listening on",
                text_or(modbus, "endpoint", "?"));
    else
        fputs("off\n", out);
    name(out, "Contacts");
    if (cJSON_IsObject(contacts)) {
        static const char *const which[] = {"watch", "alarm", "fault"};
        int any = 0;
        for (int i = 0; i < 3; i++)
            if (yes(contacts, which[i]))
                fprintf(out, "%s%s", any++ ? ", " : "", which[i]);
        fprintf(out, "%s energised\n", any ? "" : "none");
    } else {
        fputs("off\n", out);
    }
    name(out, "State directory");
    fputs(text_or(o, "state_dir", "?"), out);
    if (number(o, "state_dir_free_bytes", &free_bytes)) {
        fputs(", ", out);
        print_bytes(out, free_bytes);
        fputs(" free", out);
    }
    fputc('\n', out);
    status_state_writes(out, item(o, "state_dir_writes"));
}

static void status_text(FILE *out, const cJSON *o, const struct text_marks *m)
{
    double v, major, minor;
    const cJSON *site = item(o, "site"), *latest = item(o, "latest"), *progress = item(o, "progress");
    name(out, "State");
    fprintf(out, "%s\n", text_or(o, "state", "?"));
    if (cJSON_IsObject(progress)) {
        name(out, "Scan");
        print_progress(out, progress);
        fputc('\n', out);
    }
    if (text(o, "fault")) {
        name(out, "Fault");
        fprintf(out, "%s\n", text(o, "fault"));
    }
    if (text(o, "asset_id")) {
        name(out, "Asset");
        fprintf(out, "%s\n", text(o, "asset_id"));
    }
    if (cJSON_IsObject(site)) {
        name(out, "Site");
        if (text(site, "phase"))
            fprintf(out, "phase %s%s", text(site, "phase"), text(site, "label") ? ", " : "");
        fprintf(out, "%s\n", text_or(site, "label", ""));
    }
    name(out, "Latest verdict");
    if (cJSON_IsObject(latest)) {
        print_figure(out, latest, m);
        fprintf(out, ", %s, scan %s\n", text_or(latest, "created", "?"), text_or(latest, "scan_id", "?"));
    } else {
        fputs("none\n", out);
    }
    status_baseline(out, o);
    name(out, "Schedule");
    if (number(o, "interval_s", &v) && v > 0) {
        fputs("every ", out);
        print_duration(out, v);
    } else {
        fputs("on request only", out);
    }
    if (number(o, "next_scan_in_s", &v)) {
        fputs(", next in ", out);
        print_duration(out, v);
    }
    if (yes(o, "scan_queued"))
        fputs("; a scan is queued", out);
    fputc('\n', out);
    if (number(o, "scans_this_run", &v)) {
        name(out, "Scans this run");
        fprintf(out, "%.0f\n", v);
    }
    name(out, "Rig");
    fprintf(out, "%s\n", text_or(o, "rig", "?"));
    status_integrations(out, o);
    if (text(o, "console")) {
        name(out, "Console");
        fprintf(out, "%s\n", text(o, "console"));
    }
    name(out, "Version");
    fputs(text_or(o, "version", "?"), out);
    if (number(o, "proto_major", &major) && number(o, "proto_minor", &minor))
        fprintf(out, " (protocol %.0f.%.0f)", major, minor);
    if (number(o, "uptime_s", &v)) {
        fputs(", up ", out);
        print_duration(out, v);
    }
    fputc('\n', out);
}

/* The history table's columns; a reason goes under its row from
 * HISTORY_REASON_INDENT, wrapped to HELP_LINE_WIDTH, never cut. */
#define HISTORY_STATUS_WIDTH 12
#define HISTORY_FIGURE_WIDTH 18
#define HISTORY_HEIGHT_WIDTH 13
#define HISTORY_RADIAL_WIDTH 24
#define HISTORY_REASON_INDENT 22

/* A history row's radial change: "+0.20 ± 0.10 mm ok", the status alone
 * where it made no figure, "-" where the verdict has none. */
static void radial_cell(char *buf, size_t n, const struct uwb_verdict_record *r, const struct text_marks *m)
{
    const char *status = r->has_radial ? uwb_status_name(r->radial_status) : NULL;
    if (r->radial_measured)
        snprintf(buf, n, "%+.2f %s %.2f mm %s", r->radial_max_change_mm, m->plus_minus,
                 r->radial_uncertainty_mm, status ? status : "");
    else
        snprintf(buf, n, "%s", status ? status : "-");
}

static void history_text(FILE *out, const cJSON *o, const struct text_marks *m)
{
    const cJSON *list = item(o, "verdicts"), *v;
    double skipped;
    char figure_header[64], radial_header[64];
    snprintf(figure_header, sizeof figure_header, "displacement %s %s", m->plus_minus, m->one_sigma);
    snprintf(radial_header, sizeof radial_header, "radial %s %s", m->plus_minus, m->one_sigma);
    int figure_width = uwb_text_layout_at_least(HISTORY_FIGURE_WIDTH, figure_header);
    fprintf(out, "%-20s  %-*s  ", "time (UTC)", HISTORY_STATUS_WIDTH, "status");
    uwb_text_layout_column(out, figure_header, figure_width);
    fprintf(out, "  %-*s  ", HISTORY_HEIGHT_WIDTH, "height change");
    uwb_text_layout_column(out, radial_header, HISTORY_RADIAL_WIDTH);
    fputs("  scan\n", out);
    /* Each entry's figures read through the published record, as any
     * verdict's are (r: room for one). */
    struct uwb_verdict_record *r = malloc(sizeof *r);
    cJSON_ArrayForEach(v, list)
    {
        char status[16] = "", figure[64] = "-", height[32] = "-", radial[64], err[160];
        if (!r || uwb_record_from_summary(v, r, err, sizeof err) != 0) {
            fprintf(out, "(an entry that is not a verdict: %s)\n", r ? err : "out of memory");
            continue;
        }
        const char *s = uwb_status_name(r->status);
        size_t i = 0;
        for (; s[i] && i + 1 < sizeof status; i++)
            status[i] = (char)(s[i] >= 'a' && s[i] <= 'z' ? s[i] - 'a' + 'A' : s[i]);
        status[i] = '\0';
        if (r->has_displacement && isfinite(r->uncertainty_mm))
            snprintf(figure, sizeof figure, "%+.2f %s %.2f mm", r->axial_displacement_mm, m->plus_minus,
                     r->uncertainty_mm);
        else if (r->has_displacement)
            snprintf(figure, sizeof figure, "%+.2f mm", r->axial_displacement_mm);
        if (r->has_height_change)
            snprintf(height, sizeof height, "%+.2f mm", r->height_change_mm);
        radial_cell(radial, sizeof radial, r, m);
        fprintf(out, "%-20s  %-*s  ", r->created[0] ? r->created : "?", HISTORY_STATUS_WIDTH, status);
        uwb_text_layout_column(out, figure, figure_width);
        fprintf(out, "  %-*s  ", HISTORY_HEIGHT_WIDTH, height);
        uwb_text_layout_column(out, radial, HISTORY_RADIAL_WIDTH);
        fprintf(out, "  %s%s\n", r->scan_id[0] ? r->scan_id : "?",
                yes(v, "baseline_set") ? " (baseline)" : "");
        /* Why, whole, under the row (issue 48: it was cut mid-word). */
        if (r->reason[0]) {
            fprintf(out, "%*s", HISTORY_REASON_INDENT, "");
            uwb_text_layout_wrapped(out, r->reason, HISTORY_REASON_INDENT, HISTORY_REASON_INDENT,
                                    HELP_LINE_WIDTH);
        }
    }
    free(r);
    if (cJSON_GetArraySize(list) == 0)
        fputs("(no verdicts yet)\n", out);
    if (number(o, "unreadable_lines", &skipped))
        fprintf(out, "%.0f line%s of the log could not be read\n", skipped, skipped == 1 ? "" : "s");
}

/* Words of s from column `from`, wrapped at HELP_LINE_WIDTH and indented. */
static void print_wrapped(FILE *out, const char *s, int from)
{
    int column = from;
    while (*s) {
        size_t n = strcspn(s, " ");
        if (column > HELP_USAGE_WIDTH && column + 1 + (int)n > HELP_LINE_WIDTH) {
            fprintf(out, "\n%*s", HELP_USAGE_WIDTH, "");
            column = HELP_USAGE_WIDTH;
        } else if (column > HELP_USAGE_WIDTH) {
            fputc(' ', out);
            column++;
        }
        fwrite(s, 1, n, out);
        column += (int)n;
        s += n;
        while (*s == ' ')
            s++;
    }
    fputc('\n', out);
}

static void help_text(FILE *out, const cJSON *o)
{
    const cJSON *c;
    fputs("Commands (case does not matter):\n", out);
    cJSON_ArrayForEach(c, item(o, "commands"))
    {
        const char *usage = text_or(c, "command", "?");
        int used = fprintf(out, "  %-*s", HELP_USAGE_WIDTH - 3, usage);
        if ((int)strlen(usage) > HELP_USAGE_WIDTH - 3) {
            fprintf(out, "\n%*s", HELP_USAGE_WIDTH, "");
            used = HELP_USAGE_WIDTH;
        } else {
            fputc(' ', out);
            used++;
        }
        print_wrapped(out, text_or(c, "description", ""), used);
    }
}

static void contacts_text(FILE *out, const cJSON *contacts)
{
    fprintf(
        out, "contacts: watch %s, alarm %s, fault %s\n", yes(contacts, "watch") ? "energised" : "released",
        yes(contacts, "alarm") ? "energised" : "released", yes(contacts, "fault") ? "energised" : "released");
}

/* The latest verdict as `ack` names it: its figure (and a radial change),
 * its time and its scan. */
static void print_latest(FILE *out, const cJSON *latest, const struct text_marks *m)
{
    double change, at;
    const cJSON *radial = item(latest, "radial");
    print_figure(out, latest, m);
    if (number(radial, "max_change_mm", &change) && number(radial, "at_mm", &at))
        fprintf(out, ", radial change %+.1f mm at %.0f mm", change, at);
    fprintf(out, " (%s, scan %s)\n", text_or(latest, "created", "?"), text_or(latest, "scan_id", "?"));
}

/* `ack`: said done, then what still holds a contact (the latest verdict
 * calls for it), or that nothing does. */
static void ack_text(FILE *out, const cJSON *o, const struct text_marks *m)
{
    const cJSON *contacts = item(o, "contacts"), *latest = item(o, "latest");
    int watch = yes(contacts, "watch"), alarm = yes(contacts, "alarm");
    fputs("acknowledged: the watch and alarm latches are released\n", out);
    if (!cJSON_IsObject(latest)) {
        fputs(watch || alarm ? "still energised by the verdicts\n"
                             : "watch and alarm released (no verdict yet)\n",
              out);
    } else if (watch || alarm) {
        fprintf(out, "still energised: %s%s%s, as the latest verdict calls for: ", watch ? "watch" : "",
                watch && alarm ? ", " : "", alarm ? "alarm" : "");
        print_latest(out, latest, m);
    } else {
        fputs("watch and alarm released: the latest verdict is ", out);
        print_latest(out, latest, m);
    }
    contacts_text(out, contacts);
}

/* `contacts test`: the sequence the RTU is about to see, in words. */
static void contacts_test_text(FILE *out, const cJSON *o)
{
    const cJSON *sequence = item(o, "sequence"), *c;
    double hold = 0, gap = 0, duration = 0;
    number(o, "hold_s", &hold);
    number(o, "gap_s", &gap);
    number(o, "duration_s", &duration);
    int n = cJSON_GetArraySize(sequence), i = 0;
    fprintf(out, "contacts test started: all contacts released for %.0f s, then ", gap);
    cJSON_ArrayForEach(c, sequence)
    {
        fprintf(out, "%s%s",
                i == 0       ? ""
                : i == n - 1 ? " and "
                             : ", ",
                cJSON_IsString(c) ? c->valuestring : "?");
        i++;
    }
    fprintf(out, " %s energised alone for %.0f s with %.0f s released between;\n", n > 1 ? "each" : "is",
            hold, gap);
    fprintf(out, "%.0f s in all, then the contacts return to what the verdicts call for\n", duration);
}

/* The short replies: a line each. */
static int short_text(FILE *out, const char *cls, const cJSON *o, const struct text_marks *m)
{
    if (strcmp(cls, "ERROR") == 0)
        fprintf(out, "error: %s\n", text_or(o, "message", "?"));
    else if (strcmp(cls, "WATCH") == 0)
        fputs(yes(o, "verdicts")   ? "watching: progress and verdicts\n"
              : yes(o, "progress") ? "watching: progress\n"
                                   : "not watching\n",
              out);
    else if (strcmp(cls, "PROGRESS") == 0) {
        fputs("scan: ", out);
        print_progress(out, o);
        fputc('\n', out);
    } else if (strcmp(cls, "EVENT") == 0 || strcmp(cls, "SCAN") == 0)
        fprintf(out, "scan %s\n", text_or(o, "scan", "?"));
    else if (strcmp(cls, "ACK") == 0)
        ack_text(out, o, m);
    else if (strcmp(cls, "CONTACTS_TEST") == 0)
        contacts_test_text(out, o);
    else if (strcmp(cls, "BASELINE") == 0) {
        fprintf(out, "%s\n", text_or(o, "message", "?"));
        const cJSON *b = item(o, "current");
        if (cJSON_IsObject(b))
            fprintf(out, "current baseline: %s%s%s\n", text_or(b, "scan_id", "?"),
                    text(b, "set_at") ? ", set " : "", text_or(b, "set_at", ""));
    } else
        return -1;
    return 0;
}

/* Any other reply: its class, then "key: value" for each plain value. */
static void generic_text(FILE *out, const char *cls, const cJSON *o)
{
    const cJSON *v;
    fprintf(out, "%s\n", cls);
    cJSON_ArrayForEach(v, o)
    {
        if (strcmp(v->string, "class") == 0)
            continue;
        if (cJSON_IsString(v))
            fprintf(out, "  %s: %s\n", v->string, v->valuestring);
        else if (cJSON_IsNumber(v))
            fprintf(out, "  %s: %g\n", v->string, v->valuedouble);
        else if (cJSON_IsBool(v))
            fprintf(out, "  %s: %s\n", v->string, cJSON_IsTrue(v) ? "yes" : "no");
    }
}

int uwbd_reply_text(const char *reply, FILE *out)
{
    return uwbd_reply_text_in(reply, out, UWBD_CHARSET_UTF8);
}

int uwbd_reply_text_in(const char *reply, FILE *out, enum uwbd_charset charset)
{
    const struct text_marks *m = uwb_text_layout_marks_of(charset);
    cJSON *o = cJSON_Parse(reply);
    const char *cls = text(o, "class");
    if (!cls) {
        cJSON_Delete(o);
        return -1;
    }
    int rc = 0;
    if (strcmp(cls, "VERDICT") == 0)
        rc = uwbd_verdict_text_in(reply, out, charset);
    else if (strcmp(cls, "TREND") == 0)
        rc = uwbd_trend_text_in(reply, out, charset);
    else if (strcmp(cls, "STATUS") == 0)
        status_text(out, o, m);
    else if (strcmp(cls, "HISTORY") == 0)
        history_text(out, o, m);
    else if (strcmp(cls, "HELP") == 0)
        help_text(out, o);
    else if (short_text(out, cls, o, m) != 0)
        generic_text(out, cls, o);
    cJSON_Delete(o);
    return rc;
}
