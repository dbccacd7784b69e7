/* The Prometheus textfile as a module (prometheus.*): the latest verdict's
 * figures, the verdict counts since start and the contacts' states,
 * written after every verdict and `ack`. The figures are kept with the
 * textfile off too: MQTT's health report carries the counts. Opened again
 * on a reload only when the site's configuration changed. */
#include "daemon/output_textfile.h"

#include <string.h>

#include "daemon/output_contacts.h"
#include "integrations/prometheus_textfile.h"
#include "util/log.h"

static struct uwbd_prometheus_metrics prom; /* the textfile's figures */
static int prom_failing;                    /* log a failing textfile once, not every verdict */

static void write_textfile(const struct uwbd_daemon_port *port)
{
    if (!port->cfg->site.prometheus_enabled)
        return;
    struct uwbd_contact_states st;
    uwbd_contact_states(&st);
    prom.has_contacts = port->cfg->site.contacts_enabled;
    prom.contact[0] = st.watch;
    prom.contact[1] = st.alarm;
    prom.contact[2] = st.fault;
    char err[512];
    if (uwbd_prometheus_write(port->cfg->site.prometheus_textfile, &prom, err, sizeof err) != 0) {
        if (!prom_failing)
            uwbd_log(UWBD_LOG_ERR, "prometheus textfile: %s (tried again at every verdict)", err);
        prom_failing = 1;
        return;
    }
    if (prom_failing)
        uwbd_log(UWBD_LOG_NOTICE, "prometheus textfile written again");
    prom_failing = 0;
}

/* The figures start from the verdict recorded before this start. */
static int textfile_open(const struct uwbd_daemon_port *port)
{
    memset(&prom, 0, sizeof prom);
    prom_failing = 0;
    prom.asset_id = port->cfg->site.asset_id;
    uwbd_prometheus_from_record(&prom, port->latest(port->daemon));
    write_textfile(port);
    return 0;
}

static void textfile_reload(const struct uwbd_daemon_port *port, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(port->cfg, previous))
        textfile_open(port);
}

static void textfile_verdict(const struct uwbd_daemon_port *port, const struct uwb_verdict_record *v,
                             const char *json, double duration_s)
{
    if (!json || !v)
        return;
    uwbd_prometheus_from_record(&prom, v);
    prom.has_duration = 1;
    prom.scan_duration_s = duration_s;
    int index = uwbd_prometheus_status_index(uwb_status_name(v->status));
    if (index >= 0)
        prom.verdicts[index]++;
    if (strcmp(v->cycle.trigger, "event") == 0)
        prom.event_scans++;
    write_textfile(port);
}

const char *uwbd_latest_status(void)
{
    return prom.has_verdict ? uwbd_prometheus_status_name(prom.status) : NULL;
}

unsigned long uwbd_verdicts_since_start(void)
{
    unsigned long verdicts = 0;
    for (int i = 0; i < UWBD_PROM_STATUSES; i++)
        verdicts += prom.verdicts[i];
    return verdicts;
}

const struct uwbd_output_module uwbd_output_textfile = {
    .name = "prometheus textfile",
    .open = textfile_open,
    .reload = textfile_reload,
    .verdict = textfile_verdict,
    .report = write_textfile,
};
