/* A TREND reply as a table for people (uwbd ctl --text trend): one line
 * per verdict (axial figure, height change, radial change), oldest
 * first, then the rate and the image. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "text/text_layout.h"
#include "uwb/reply_text.h"
#include "uwb/verdict_json.h"

static const cJSON *item(const cJSON *o, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(o, key);
}

static const char *text(const cJSON *o, const char *key, const char *otherwise)
{
    const cJSON *v = item(o, key);
    return cJSON_IsString(v) && v->valuestring ? v->valuestring : otherwise;
}

static int number(const cJSON *o, const char *key, double *out)
{
    const cJSON *v = item(o, key);
    if (!cJSON_IsNumber(v))
        return 0;
    *out = v->valuedouble;
    return 1;
}

static void upper(char *dst, size_t n, const char *src)
{
    size_t i = 0;
    for (; src[i] && i + 1 < n; i++)
        dst[i] = (char)toupper((unsigned char)src[i]);
    dst[i] = '\0';
}

/* Columns of the table; a reason goes under its row from REASON_INDENT,
 * wrapped to LINE_WIDTH. */
#define FIGURE_WIDTH 20
#define RADIAL_WIDTH 24
#define REASON_INDENT 23
#define LINE_WIDTH 79

/* One entry, read through the published record (r: room for one). */
static void verdict_line(const cJSON *v, const struct text_marks *m, struct uwb_verdict_record *r, FILE *out)
{
    char status[16], figure[64], height[32], radial[64], header[64], err[160];
    if (uwb_record_from_trend_entry(v, r, err, sizeof err) != 0) {
        fprintf(out, "(an entry that is not a verdict: %s)\n", err);
        return;
    }
    upper(status, sizeof status, uwb_status_name(r->status));
    if (r->has_displacement)
        snprintf(figure, sizeof figure, "%+7.2f %s %.2f mm", r->axial_displacement_mm, m->plus_minus,
                 r->uncertainty_mm);
    else
        snprintf(figure, sizeof figure, "no figure");
    if (r->has_height_change)
        snprintf(height, sizeof height, "%+7.2f mm", r->height_change_mm);
    else
        snprintf(height, sizeof height, "-"); /* right-aligned under the figures' "mm" */
    /* The radial change with its status; "-" where the verdict has none
     * (older lines), the status alone where it made no figure. */
    const char *radial_status = r->has_radial ? uwb_status_name(r->radial_status) : NULL;
    if (r->radial_measured)
        snprintf(radial, sizeof radial, "%+6.2f %s %.2f mm %s", r->radial_max_change_mm, m->plus_minus,
                 r->radial_uncertainty_mm, radial_status ? radial_status : "");
    else
        snprintf(radial, sizeof radial, "%s", radial_status ? radial_status : "-");
    /* "*" marks a baseline change: the figures before and after it are
     * against different references. */
    fprintf(out, "%-20s %c %-12s  ", r->created[0] ? r->created : "(no time)",
            cJSON_IsTrue(item(v, "baseline_change")) ? '*' : ' ', status);
    snprintf(header, sizeof header, "displacement %s %s", m->plus_minus, m->one_sigma);
    uwb_text_layout_column(out, figure, uwb_text_layout_at_least(FIGURE_WIDTH, header));
    fprintf(out, "  %13s  ", height);
    uwb_text_layout_column(out, radial, RADIAL_WIDTH);
    fprintf(out, "  %s", r->scan_id);
    if (r->cycle.baseline_set)
        fputs("  (became the baseline)", out);
    fputc('\n', out);
    /* The reason whole, wrapped under the row (issue 48: it was cut). */
    const char *reason = r->reason[0] ? r->reason : NULL;
    if (reason) {
        fprintf(out, "%*s", REASON_INDENT, "");
        uwb_text_layout_wrapped(out, reason, REASON_INDENT, REASON_INDENT, LINE_WIDTH);
    }
}

int uwbd_trend_text(const char *reply, FILE *out)
{
    return uwbd_trend_text_in(reply, out, UWBD_CHARSET_UTF8);
}

int uwbd_trend_text_in(const char *reply, FILE *out, enum uwbd_charset charset)
{
    const struct text_marks *m = uwb_text_layout_marks_of(charset);
    cJSON *o = cJSON_Parse(reply);
    const cJSON *cls = item(o, "class"), *list = item(o, "verdicts");
    if (!cJSON_IsString(cls) || strcmp(cls->valuestring, "TREND") != 0 || !cJSON_IsArray(list)) {
        cJSON_Delete(o);
        return -1;
    }
    const cJSON *limits = item(o, "thresholds"), *rate = item(o, "rate");
    double count = 0, watch = 0, alarm = 0;
    number(o, "count", &count);
    fprintf(out, "trend: the last %.0f verdict%s", count, count == 1 ? "" : "s");
    if (number(limits, "watch_mm", &watch) && number(limits, "alarm_mm", &alarm))
        fprintf(out, " (watch from %.2f mm, alarm from %.2f mm)", watch, alarm);
    fputc('\n', out);
    char header[64];
    fprintf(out, "%-20s   %-12s  ", "created (UTC)", "status");
    snprintf(header, sizeof header, "displacement %s %s", m->plus_minus, m->one_sigma);
    uwb_text_layout_column(out, header, FIGURE_WIDTH);
    fprintf(out, "  %13s  ", "height change");
    snprintf(header, sizeof header, "radial %s %s", m->plus_minus, m->one_sigma);
    uwb_text_layout_column(out, header, RADIAL_WIDTH);
    fprintf(out, "  %s\n", "scan");
    struct uwb_verdict_record *r = malloc(sizeof *r);
    if (!r) {
        cJSON_Delete(o);
        return -1;
    }
    const cJSON *v;
    cJSON_ArrayForEach(v, list) verdict_line(v, m, r, out);
    free(r);
    double unreadable;
    if (number(o, "unreadable_lines", &unreadable))
        fprintf(out, "(%.0f line%s of verdicts.jsonl could not be read)\n", unreadable,
                unreadable == 1 ? "" : "s");
    double per_year, sigma, days, figures = 0;
    number(rate, "figures", &figures);
    if (number(rate, "mm_per_year", &per_year) && number(rate, "sigma_mm_per_year", &sigma) &&
        number(rate, "days", &days))
        fprintf(
            out,
            "rate: %+.2f %s %.2f mm/year (%s) over %.1f days, %.0f figure%s since the last baseline change\n",
            per_year, m->plus_minus, sigma, m->one_sigma, days, figures, figures == 1 ? "" : "s");
    else
        fprintf(out, "rate: not known yet (%s)\n",
                text(rate, "withheld", "the reply gives no rate and no reason"));
    const char *image = text(o, "image", NULL);
    if (image)
        fprintf(out, "image: %s\n", image);
    cJSON_Delete(o);
    return 0;
}
