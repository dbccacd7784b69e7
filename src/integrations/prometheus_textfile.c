/* The Prometheus textfile (see the header): one file, replaced whole
 * after each verdict, so node_exporter never reads half of it. */
#include "integrations/prometheus_textfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/atomic_file.h"
#include "uwb/utc_time.h"
#include "uwb/verdict_fields.h"

static const char *const status_names[UWBD_PROM_STATUSES] = {"edges", "ok",           "watch",
                                                             "alarm", "inconclusive", "error"};
static const char *const contact_names[3] = {"watch", "alarm", "fault"};

const char *uwbd_prometheus_status_name(int status)
{
    return status >= 0 && status < UWBD_PROM_STATUSES ? status_names[status] : "unknown";
}

int uwbd_prometheus_status_index(const char *name)
{
    for (int i = 0; name && i < UWBD_PROM_STATUSES; i++)
        if (strcmp(name, status_names[i]) == 0)
            return i;
    return -1;
}

void uwbd_prometheus_from_record(struct uwbd_prometheus_metrics *m, const struct uwb_verdict_record *v)
{
    int index = v ? uwbd_prometheus_status_index(uwb_status_name(v->status)) : -1;
    if (index < 0)
        return;
    m->has_verdict = 1;
    m->status = index;
    m->figures = v->summary;
    time_t created_s;
    m->created_s = 0;
    if (uwb_utc_parse(v->created, &created_s) == 0)
        m->created_s = (double)created_s;
}

struct text {
    FILE *out;
    const char *labels; /* asset_id="..." */
};

static void header(struct text *t, const char *name, const char *type, const char *help)
{
    fprintf(t->out, "# HELP %s %s\n# TYPE %s %s\n", name, help, name, type);
}

/* Whole numbers (counters, Unix times) in full; the rest to 9 digits. */
static void sample(struct text *t, const char *name, const char *extra_label, double value)
{
    fprintf(t->out, "%s{%s%s%s} ", name, t->labels, extra_label ? "," : "", extra_label ? extra_label : "");
    if (value == floor(value) && fabs(value) < 1e15)
        fprintf(t->out, "%.0f\n", value);
    else
        fprintf(t->out, "%.9g\n", value);
}

static void gauge(struct text *t, const char *name, const char *help, double value)
{
    header(t, name, "gauge", help);
    sample(t, name, NULL, value);
}

/* A status row: one sample per status, 1 for the one it has. */
static void status_samples(struct text *t, const char *name, enum uwb_status status)
{
    char label[64];
    int index = uwbd_prometheus_status_index(uwb_status_name(status));
    for (int i = 0; i < UWBD_PROM_STATUSES; i++) {
        snprintf(label, sizeof label, "status=\"%s\"", status_names[i]);
        sample(t, name, label, i == index);
    }
}

/* The rows with a gauge, in their places: those the record gives. */
static void figure_gauges(struct text *t, const struct uwb_verdict_summary *r)
{
    const char *last = NULL;
    for (int at = 1; at <= UWB_FIELD_PLACES; at++) {
        const struct uwb_field *f = NULL;
        for (size_t i = 0; !f && i < uwb_verdict_fields.count; i++)
            if (uwb_verdict_fields.rows[i].prom == at && uwb_verdict_fields.rows[i].prom_name)
                f = &uwb_verdict_fields.rows[i];
        if (!f || f->kind == UWB_FIELD_TEXT || !uwb_field_given(f, r))
            continue;
        if (!last || strcmp(last, f->prom_name) != 0)
            header(t, f->prom_name, "gauge", f->prom_help);
        last = f->prom_name;
        if (f->kind == UWB_FIELD_STATUS)
            status_samples(t, f->prom_name,
                           *(const enum uwb_status *)(const void *)((const char *)r + f->value));
        else
            sample(t, f->prom_name, f->prom_label, uwb_field_si(f, *uwb_field_number(f, (void *)r)));
    }
}

char *uwbd_prometheus_text(const struct uwbd_prometheus_metrics *m)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    if (!out)
        return NULL;
    char labels[128];
    snprintf(labels, sizeof labels, "asset_id=\"%s\"", m->asset_id ? m->asset_id : "");
    struct text t = {.out = out, .labels = labels};
    char label[64];

    if (m->has_verdict) {
        header(&t, "uwbd_status", "gauge",
               "The latest verdict's status: 1 for the one it has, 0 for the others.");
        for (int i = 0; i < UWBD_PROM_STATUSES; i++) {
            snprintf(label, sizeof label, "status=\"%s\"", status_names[i]);
            sample(&t, "uwbd_status", label, i == m->status);
        }
        if (m->created_s > 0)
            gauge(&t, "uwbd_last_verdict_timestamp_seconds",
                  "When the latest verdict's scan was made (Unix time).", m->created_s);
    }
    if (m->has_verdict)
        figure_gauges(&t, &m->figures);
    if (m->has_duration)
        gauge(&t, "uwbd_scan_duration_seconds", "How long the latest scan cycle took, start to verdict.",
              m->scan_duration_s);
    header(&t, "uwbd_verdicts_total", "counter", "Verdicts recorded since the daemon started, by status.");
    for (int i = 0; i < UWBD_PROM_STATUSES; i++) {
        snprintf(label, sizeof label, "status=\"%s\"", status_names[i]);
        sample(&t, "uwbd_verdicts_total", label, (double)m->verdicts[i]);
    }
    header(&t, "uwbd_event_scans_total", "counter",
           "Scans started by the event input or command since the daemon started.");
    sample(&t, "uwbd_event_scans_total", NULL, (double)m->event_scans);
    if (m->has_contacts) {
        header(&t, "uwbd_contact_energised", "gauge",
               "The alarm contacts: 1 energised, 0 not (fault: 1 = healthy).");
        for (int i = 0; i < 3; i++) {
            snprintf(label, sizeof label, "contact=\"%s\"", contact_names[i]);
            sample(&t, "uwbd_contact_energised", label, m->contact[i] > 0);
        }
    }
    if (fclose(out) != 0) {
        free(buf);
        return NULL;
    }
    return buf;
}

int uwbd_prometheus_write(const char *path, const struct uwbd_prometheus_metrics *m, char *err, size_t errlen)
{
    char *text = uwbd_prometheus_text(m);
    if (!text) {
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    /* 0644 for a new file (node_exporter runs as a user of its own; the
     * figures are no secret), a replaced file's mode kept (atomic_file.c). */
    int rc = uwb_atomic_write_file(path, text, strlen(text), err, errlen);
    free(text);
    return rc;
}
