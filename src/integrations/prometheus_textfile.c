/* The Prometheus textfile (see the header): one file, replaced whole
 * after each verdict, so node_exporter never reads half of it. */
#include "integrations/prometheus_textfile.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/atomic_file.h"
#include "uwb/utc_time.h"

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
    m->has_displacement = v->has_displacement;
    m->displacement_m = m->has_displacement ? v->axial_displacement_mm / 1e3 : 0;
    m->uncertainty_m = m->has_displacement ? v->uncertainty_mm / 1e3 : 0;
    m->has_edges = v->has_edges;
    m->lower_edge_m = m->has_edges ? v->lower_edge_mm / 1e3 : 0;
    m->upper_edge_m = m->has_edges ? v->upper_edge_mm / 1e3 : 0;
    m->has_height_change = v->has_height_change;
    m->height_change_m = m->has_height_change ? v->height_change_mm / 1e3 : 0;
    m->radial_status = v->has_radial ? uwbd_prometheus_status_index(uwb_status_name(v->radial_status)) : -1;
    m->has_radial = m->radial_status >= 0;
    m->has_radial_change = m->has_radial && v->radial_measured;
    m->radial_change_m = m->has_radial_change ? v->radial_max_change_mm / 1e3 : 0;
    m->radial_uncertainty_m = m->has_radial_change ? v->radial_uncertainty_mm / 1e3 : 0;
    m->radial_at_m = m->has_radial_change ? v->radial_at_mm / 1e3 : 0;
    m->has_radial_tilt = m->has_radial_change && v->radial_has_tilt;
    m->radial_tilt_m = m->has_radial_tilt ? v->radial_tilt_mm / 1e3 : 0;
    m->has_radial_tilt_uncertainty = m->has_radial_tilt && v->radial_has_tilt_uncertainty;
    m->radial_tilt_uncertainty_m = m->has_radial_tilt_uncertainty ? v->radial_tilt_uncertainty_mm / 1e3 : 0;
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
    if (m->has_displacement) {
        gauge(&t, "uwbd_axial_displacement_meters",
              "The latest axial displacement of the winding from the baseline, positive up.",
              m->displacement_m);
        gauge(&t, "uwbd_axial_displacement_uncertainty_meters", "Its 1-sigma uncertainty.", m->uncertainty_m);
    }
    if (m->has_edges) {
        header(&t, "uwbd_edge_meters", "gauge", "The winding's lower and upper edges in the latest scan.");
        sample(&t, "uwbd_edge_meters", "edge=\"lower\"", m->lower_edge_m);
        sample(&t, "uwbd_edge_meters", "edge=\"upper\"", m->upper_edge_m);
    }
    if (m->has_height_change)
        gauge(&t, "uwbd_height_change_meters", "The winding's height change from the baseline (latest scan).",
              m->height_change_m);
    if (m->has_radial) {
        header(&t, "uwbd_radial_status", "gauge",
               "The latest verdict's radial status: 1 for the one it has, 0 for the others.");
        for (int i = 0; i < UWBD_PROM_STATUSES; i++) {
            snprintf(label, sizeof label, "status=\"%s\"", status_names[i]);
            sample(&t, "uwbd_radial_status", label, i == m->radial_status);
        }
    }
    if (m->has_radial_change) {
        gauge(&t, "uwbd_radial_max_change_meters",
              "The latest largest radial change of the winding's face from the baseline, positive toward the "
              "antenna.",
              m->radial_change_m);
        gauge(&t, "uwbd_radial_max_change_uncertainty_meters", "Its 1-sigma uncertainty.",
              m->radial_uncertainty_m);
        gauge(&t, "uwbd_radial_max_change_height_meters", "The height where it is largest.", m->radial_at_m);
    }
    if (m->has_radial_tilt)
        gauge(&t, "uwbd_radial_tilt_meters",
              "The face's tilt from the baseline, top minus bottom, positive top nearer.", m->radial_tilt_m);
    if (m->has_radial_tilt_uncertainty)
        gauge(&t, "uwbd_radial_tilt_uncertainty_meters", "The 1-sigma uncertainty of the face's tilt.",
              m->radial_tilt_uncertainty_m);
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
