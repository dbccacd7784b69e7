/* The Prometheus textfile as a module (prometheus.*): the latest verdict's
 * figures, the verdict counts since start and the contacts' states,
 * written after every verdict and `ack`. The figures are kept with the
 * textfile off too: MQTT's health report carries the counts. Opened again
 * on a reload only when the site's configuration changed. */
#include <string.h>

#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

static void write_textfile(struct daemon *d)
{
    if (!d->cfg.site.prometheus_enabled)
        return;
    struct uwbd_contact_states st;
    uwbd_contact_states(d, &st);
    d->prom.has_contacts = d->cfg.site.contacts_enabled;
    d->prom.contact[0] = st.watch;
    d->prom.contact[1] = st.alarm;
    d->prom.contact[2] = st.fault;
    char err[512];
    if (uwbd_prometheus_write(d->cfg.site.prometheus_textfile, &d->prom, err, sizeof err) != 0) {
        if (!d->prom_failing)
            uwbd_log(UWBD_LOG_ERR, "prometheus textfile: %s (tried again at every verdict)", err);
        d->prom_failing = 1;
        return;
    }
    if (d->prom_failing)
        uwbd_log(UWBD_LOG_NOTICE, "prometheus textfile written again");
    d->prom_failing = 0;
}

/* The figures start from the verdict recorded before this start. */
static int textfile_open(struct daemon *d)
{
    memset(&d->prom, 0, sizeof d->prom);
    d->prom_failing = 0;
    d->prom.asset_id = d->cfg.site.asset_id;
    uwbd_prometheus_from_record(&d->prom, d->latest);
    write_textfile(d);
    return 0;
}

static void textfile_reload(struct daemon *d, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(d, previous))
        textfile_open(d);
}

static void textfile_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                             double duration_s)
{
    if (!json || !v)
        return;
    uwbd_prometheus_from_record(&d->prom, v);
    d->prom.has_duration = 1;
    d->prom.scan_duration_s = duration_s;
    int index = uwbd_prometheus_status_index(uwb_status_name(v->status));
    if (index >= 0)
        d->prom.verdicts[index]++;
    if (strcmp(v->cycle.trigger, "event") == 0)
        d->prom.event_scans++;
    write_textfile(d);
}

const char *uwbd_latest_status(const struct daemon *d)
{
    return d->prom.has_verdict ? uwbd_prometheus_status_name(d->prom.status) : NULL;
}

unsigned long uwbd_verdicts_since_start(const struct daemon *d)
{
    unsigned long verdicts = 0;
    for (int i = 0; i < UWBD_PROM_STATUSES; i++)
        verdicts += d->prom.verdicts[i];
    return verdicts;
}

const struct uwbd_output_module uwbd_output_textfile = {
    .name = "prometheus textfile",
    .open = textfile_open,
    .reload = textfile_reload,
    .verdict = textfile_verdict,
    .report = write_textfile,
};
