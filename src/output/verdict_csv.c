/* The published verdict as a CSV row (see the header). */
#include "uwb/verdict_csv.h"

#include "uwb/verdict_fields.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* A row being written into a caller's buffer; `full` once it did not fit. */
struct row {
    char *buf;
    size_t len, at;
    int fields, full;
};

static void put(struct row *w, const char *s, size_t n)
{
    if (w->full || n >= w->len - w->at) { /* keep room for the NUL */
        w->full = 1;
        return;
    }
    memcpy(w->buf + w->at, s, n);
    w->at += n;
}

static void separator(struct row *w)
{
    if (w->fields++ > 0)
        put(w, ",", 1);
}

static void text_field(struct row *w, const char *s)
{
    separator(w);
    if (!strpbrk(s, ",\"\r\n")) {
        put(w, s, strlen(s));
        return;
    }
    put(w, "\"", 1);
    for (const char *q; (q = strchr(s, '"')); s = q + 1) {
        put(w, s, (size_t)(q - s));
        put(w, "\"\"", 2);
    }
    put(w, s, strlen(s));
    put(w, "\"", 1);
}

/* The figure as cJSON prints it in the verdict, so both say the same
 * digits; an empty cell when not given (or not known: NAN). */
static void number_field(struct row *w, int given, double x)
{
    char digits[64] = "";
    if (given && isfinite(x)) {
        cJSON number = {.type = cJSON_Number, .valuedouble = x};
        /* cJSON prints a whole number from valueint, as cJSON_CreateNumber sets it. */
        number.valueint = x >= 2147483647.0 ? 2147483647 : x <= -2147483648.0 ? -2147483647 - 1 : (int)x;
        if (!cJSON_PrintPreallocated(&number, digits, (int)sizeof digits, 0))
            digits[0] = '\0';
    }
    separator(w);
    put(w, digits, strlen(digits));
}

/* The record's reason, and why a height change, the radial change or the
 * face's tilt was withheld when it was. */
static void reason_field(struct row *w, const struct uwb_verdict_record *r)
{
    char why[sizeof r->reason + sizeof r->height_change_withheld + sizeof r->radial_withheld +
             sizeof r->radial_tilt_withheld + 96];
    const char *withheld = r->has_height_change ? "" : r->height_change_withheld;
    const char *radial = r->has_radial && !r->radial_measured ? r->radial_withheld : "";
    const char *tilt =
        r->has_radial && r->radial_measured && !r->radial_has_tilt ? r->radial_tilt_withheld : "";
    int n = snprintf(why, sizeof why, "%s%s%s%s", r->reason, r->reason[0] && withheld[0] ? "; " : "",
                     withheld[0] ? "height change withheld: " : "", withheld);
    if (radial[0] && n >= 0 && (size_t)n < sizeof why)
        n += snprintf(why + n, sizeof why - (size_t)n, "%sradial change withheld: %s", n > 0 ? "; " : "",
                      radial);
    if (tilt[0] && n >= 0 && (size_t)n < sizeof why)
        snprintf(why + n, sizeof why - (size_t)n, "%stilt withheld: %s", n > 0 ? "; " : "", tilt);
    text_field(w, why);
}

/* The columns that are no row of the field table: the cycle's, and the
 * reason, which gathers why each figure was withheld. */
enum extra_column { BASELINE_SET = 15, REASON = 17, TRIGGER = 18, ASSET_ID = 19 };

static const char *extra_name(int column)
{
    switch (column) {
    case BASELINE_SET: return "baseline_set";
    case REASON: return "reason";
    case TRIGGER: return "trigger";
    case ASSET_ID: return "asset_id";
    }
    return NULL;
}

static const struct uwb_field *column_row(const struct uwb_field_table *t, int column)
{
    for (size_t i = 0; i < t->count; i++)
        if (t->rows[i].csv_column == column)
            return &t->rows[i];
    return NULL;
}

static void extra_field(struct row *w, int column, const struct uwb_verdict_record *r)
{
    switch (column) {
    case BASELINE_SET:
        text_field(w, !r->cycle.has_baseline_set ? "" : r->cycle.baseline_set ? "true" : "false");
        break;
    case REASON: reason_field(w, r); break;
    case TRIGGER: text_field(w, r->cycle.trigger); break;
    case ASSET_ID: text_field(w, r->cycle.asset_id); break;
    }
}

static void table_field(struct row *w, const struct uwb_field *f, const struct uwb_verdict_record *r)
{
    int given = uwb_field_given(f, r);
    switch (f->kind) {
    case UWB_FIELD_STATUS:
        text_field(
            w, given ? uwb_status_name(*(const enum uwb_status *)(const void *)((const char *)r + f->value))
                     : "");
        break;
    case UWB_FIELD_TEXT: text_field(w, given ? (const char *)r + f->value : ""); break;
    case UWB_FIELD_NUMBER: number_field(w, given, *uwb_field_number(f, (void *)r)); break;
    }
}

/* The header's names, each as the JSON says it (a nested key after its
 * object's: radial_max_change_mm), in column order. */
int uwb_fields_csv_header(const struct uwb_field_table *t, char *buf, size_t len)
{
    struct row w = {.buf = buf, .len = len};
    for (int column = 1;; column++) {
        const struct uwb_field *f = column_row(t, column);
        char name[96];
        if (f && uwb_field_flat_name(f, name, sizeof name) != 0)
            return -1;
        if (!f && !extra_name(column))
            break;
        separator(&w);
        put(&w, f ? name : extra_name(column), strlen(f ? name : extra_name(column)));
    }
    put(&w, "\r\n", 2);
    if (w.full)
        return -1;
    buf[w.at] = '\0';
    return 0;
}

const char *uwb_verdict_csv_header(void)
{
    /* Built once per thread from the table (the daemon's worker and its
     * loop may both write CSV): the same bytes every time, no race. */
    static _Thread_local char header[2048];
    if (!header[0] && uwb_fields_csv_header(&uwb_verdict_fields, header, sizeof header) != 0)
        header[0] = '\0';
    return header;
}

int uwb_verdict_csv_row(const struct uwb_verdict_record *r, char *buf, size_t len)
{
    return uwb_fields_csv_row(&uwb_verdict_fields, r, buf, len);
}

int uwb_fields_csv_row(const struct uwb_field_table *t, const struct uwb_verdict_record *r, char *buf,
                       size_t len)
{
    struct row w = {.buf = buf, .len = len};
    if (len == 0)
        return -1;
    for (int column = 1;; column++) {
        const struct uwb_field *f = column_row(t, column);
        if (f)
            table_field(&w, f, r);
        else if (extra_name(column))
            extra_field(&w, column, r);
        else
            break;
    }
    put(&w, "\r\n", 2);
    if (w.full) {
        buf[0] = '\0';
        return -1;
    }
    buf[w.at] = '\0';
    return (int)w.at;
}
