/* The published verdict as a CSV row (see the header). */
#include "uwb/verdict_csv.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* The columns, named as the JSON keys (their unit in the name), in the
 * order of uwb_verdict_csv_row's fields. */
static const char header[] =
    "created,scan_id,status,axial_displacement_mm,uncertainty_mm,height_change_mm,"
    "height_change_uncertainty_mm,lower_edge_mm,upper_edge_mm,center_mm,height_mm,"
    "face_range_mm,snr_db,baseline_scan_id,baseline_set,fault,reason,trigger,asset_id,"
    "radial_status,radial_max_change_mm,radial_at_mm,radial_from_mm,radial_to_mm,"
    "radial_uncertainty_mm,radial_tilt_mm,radial_tilt_uncertainty_mm\r\n";

const char *uwb_verdict_csv_header(void)
{
    return header;
}

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

int uwb_verdict_csv_row(const struct uwb_verdict_record *r, char *buf, size_t len)
{
    struct row w = {.buf = buf, .len = len};
    if (len == 0)
        return -1;
    text_field(&w, r->created);
    text_field(&w, r->scan_id);
    text_field(&w, uwb_status_name(r->status));
    number_field(&w, r->has_displacement, r->axial_displacement_mm);
    number_field(&w, r->has_displacement, r->uncertainty_mm);
    number_field(&w, r->has_height_change, r->height_change_mm);
    number_field(&w, r->has_height_change, r->height_change_uncertainty_mm);
    number_field(&w, r->has_edges, r->lower_edge_mm);
    number_field(&w, r->has_edges, r->upper_edge_mm);
    number_field(&w, r->has_edges, r->center_mm);
    number_field(&w, r->has_edges, r->height_mm);
    number_field(&w, r->has_edges, r->face_range_mm);
    number_field(&w, r->has_edges, r->snr_db);
    text_field(&w, r->has_baseline ? r->baseline_scan_id : "");
    text_field(&w, !r->cycle.has_baseline_set ? "" : r->cycle.baseline_set ? "true" : "false");
    text_field(&w, r->fault);
    reason_field(&w, r);
    text_field(&w, r->cycle.trigger);
    text_field(&w, r->cycle.asset_id);
    text_field(&w, r->has_radial ? uwb_status_name(r->radial_status) : "");
    int radial = r->has_radial && r->radial_measured;
    number_field(&w, radial, r->radial_max_change_mm);
    number_field(&w, radial, r->radial_at_mm);
    number_field(&w, radial && r->radial_has_span, r->radial_from_mm);
    number_field(&w, radial && r->radial_has_span, r->radial_to_mm);
    number_field(&w, radial, r->radial_uncertainty_mm);
    number_field(&w, radial && r->radial_has_tilt, r->radial_tilt_mm);
    number_field(&w, radial && r->radial_has_tilt && r->radial_has_tilt_uncertainty,
                 r->radial_tilt_uncertainty_mm);
    put(&w, "\r\n", 2);
    if (w.full) {
        buf[0] = '\0';
        return -1;
    }
    buf[w.at] = '\0';
    return (int)w.at;
}
