/* The alarm contacts as a module (contacts.*): their logic follows every
 * verdict and `ack`, their lines are the site's (output_site_io.c). The
 * logic runs with the contacts off too: the fault contact's state is the
 * appliance's health in MQTT's report. Opened again on a reload only when
 * the site's configuration changed. */
#include <stdio.h>

#include "daemon/outputs.h"
#include "daemon_internal.h"
#include "util/log.h"

void uwbd_contacts_drive(struct daemon *d)
{
    /* A verdict or `ack` during a test changes the logic; the lines follow
     * it when the test ends. */
    if (!d->cfg.site.contacts_enabled || uwbd_contacts_testing(d))
        return;
    const int energised[UWBD_CONTACT_COUNT] = {
        uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH),
        uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM),
        uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_FAULT),
    };
    uwbd_site_io_contacts(d->site_io, energised);
}

/* Latched contacts come back from the verdict recorded before this start.
 * A reload that opens the site's lines again ends a running test. */
static int contacts_open(struct daemon *d)
{
    const struct uwbd_site_config *c = &d->cfg.site;
    if (uwbd_contacts_testing(d)) {
        d->contacts_test.phase = 0;
        uwbd_log(UWBD_LOG_NOTICE, "contacts test: ended by a reload of the site's configuration");
    }
    uwbd_contacts_init(&d->contacts, c->watch_latch, c->alarm_latch);
    if (d->latest)
        uwbd_contacts_restore(&d->contacts, uwb_status_name(d->latest->status));
    uwbd_contacts_drive(d);
    if (c->contacts_enabled)
        uwbd_log(UWBD_LOG_INFO, "alarm contacts: watch %d, alarm %d, fault %d (energised = 1)",
                 uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH),
                 uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM),
                 uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_FAULT));
    return 0;
}

static void contacts_reload(struct daemon *d, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(d, previous))
        contacts_open(d);
}

static void contacts_verdict(struct daemon *d, const struct uwb_verdict_record *v, const char *json,
                             double duration_s)
{
    (void)duration_s;
    if (!json || !v)
        return;
    uwbd_contacts_verdict(&d->contacts, uwb_status_name(v->status), v->fault[0] != '\0');
    uwbd_contacts_drive(d);
}

int uwbd_contacts_acknowledge(struct daemon *d, char *err, size_t errlen)
{
    if (!d->cfg.site.contacts_enabled) {
        snprintf(err, errlen, "ack: there are no alarm contacts to acknowledge (contacts.enabled is false)");
        return -1;
    }
    if (!d->site_io) {
        snprintf(err, errlen,
                 "ack: the alarm contacts are off: a reload could not open the site's lines (see the log)");
        return -1;
    }
    uwbd_contacts_ack(&d->contacts);
    uwbd_contacts_drive(d);
    uwbd_log(UWBD_LOG_NOTICE, "alarm contacts acknowledged: watch %d, alarm %d",
             uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH),
             uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM));
    uwbd_outputs_report(d);
    return 0;
}

void uwbd_contact_states(const struct daemon *d, struct uwbd_contact_states *out)
{
    /* Lines a failed reload left closed drive nothing: none to report. */
    int on = d->cfg.site.contacts_enabled && d->site_io;
    out->watch = on ? uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH) : -1;
    out->alarm = on ? uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM) : -1;
    out->fault = on ? uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_FAULT) : -1;
}

int uwbd_appliance_healthy(const struct daemon *d)
{
    return uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_FAULT);
}

const struct uwbd_output_module uwbd_output_contacts = {
    .name = "alarm contacts",
    .open = contacts_open,
    .reload = contacts_reload,
    .verdict = contacts_verdict,
    .watch = uwbd_contacts_test_watch,
};
