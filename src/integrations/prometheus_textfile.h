/* The Prometheus textfile output (src/integrations/prometheus_textfile.c):
 * the latest verdict's figures and the daemon's counters in the text
 * exposition format, written atomically where node_exporter's textfile
 * collector reads (--collector.textfile.directory, files *.prom). Base
 * units, as Prometheus asks: metres and seconds. The figures' gauges
 * are the field table's rows (uwb/verdict_fields.h). */
#ifndef UWB_DAEMON_PROMETHEUS_TEXTFILE_H
#define UWB_DAEMON_PROMETHEUS_TEXTFILE_H

#include <stddef.h>

#include "uwb/verdict_record.h"

#define UWBD_PROM_STATUSES 6 /* edges, ok, watch, alarm, inconclusive, error */

struct uwbd_prometheus_metrics {
    const char *asset_id;
    int has_verdict;
    int status;                         /* index into uwbd_prometheus_status_name */
    struct uwb_verdict_summary figures; /* the latest verdict's: its gauges are the field table's */
    double created_s;                   /* the verdict's time, Unix seconds; 0: unknown */
    int has_duration;
    double scan_duration_s;                     /* the latest scan cycle, start to verdict */
    unsigned long verdicts[UWBD_PROM_STATUSES]; /* recorded since the daemon started */
    unsigned long event_scans;                  /* scans the event input or command started */
    int has_contacts;
    int contact[3]; /* watch, alarm, fault energised */
};

const char *uwbd_prometheus_status_name(int status);
/* The index of a verdict status name, -1 when unknown. */
int uwbd_prometheus_status_index(const char *name);
/* The latest verdict's figures (and its status) from its published record
 * into m, the counters left alone; nothing when v is NULL or its status unknown. */
void uwbd_prometheus_from_record(struct uwbd_prometheus_metrics *m, const struct uwb_verdict_record *v);
/* The metrics as exposition text (malloc'd), NULL when out of memory. */
char *uwbd_prometheus_text(const struct uwbd_prometheus_metrics *m);
/* Writes them to path atomically. Returns 0, or -1 with err. */
int uwbd_prometheus_write(const char *path, const struct uwbd_prometheus_metrics *m, char *err,
                          size_t errlen);

#endif
