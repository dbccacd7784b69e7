/* The alarm contacts as a module (contacts.*): their logic follows every
 * verdict and `ack`, their lines are the site's (output_site_io.c). The
 * logic runs with the contacts off too: the fault contact's state is the
 * appliance's health in MQTT's report. Opened again on a reload only when
 * the site's configuration changed. The latch is kept in the state
 * directory (contacts_latch.c) so that a restart does not clear an alarm
 * nobody acknowledged. */
#include <stdio.h>
#include <string.h>

#include "state/contacts_latch.h"
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

/* Writes contacts-latch.json when what it would hold changed. A failure
 * (a full disk) is logged once and tried again at the next change; the
 * contacts go on from memory meanwhile. */
static void contacts_keep(struct daemon *d)
{
    if (!d->cfg.site.contacts_enabled)
        return;
    struct uwbd_contacts_memory now;
    uwbd_contacts_remember(&d->contacts, &now);
    if (d->contacts_kept_valid && memcmp(&now, &d->contacts_kept, sizeof now) == 0)
        return;
    char path[UWBD_PATH_MAX + 64], err[UWBD_PATH_MAX + 256];
    if (uwbd_contacts_latch_path(&d->store, path, sizeof path) != 0 ||
        uwbd_contacts_latch_write(path, &now, err, sizeof err) != 0) {
        if (!d->contacts_latch_failing)
            uwbd_log(UWBD_LOG_ERR, "alarm contacts: cannot keep the latch: %s; a restart now would lose it",
                     uwbd_contacts_latch_path(&d->store, path, sizeof path) != 0 ? "path too long" : err);
        d->contacts_latch_failing = 1;
        d->contacts_kept_valid = 0;
        return;
    }
    if (d->contacts_latch_failing)
        uwbd_log(UWBD_LOG_NOTICE, "alarm contacts: the latch is kept again (%s)", path);
    d->contacts_latch_failing = 0;
    d->contacts_kept = now;
    d->contacts_kept_valid = 1;
}

/* The contacts come back from the latch kept before this start and the
 * verdict recorded last. A reload that opens the site's lines again ends a
 * running test. */
static int contacts_open(struct daemon *d)
{
    const struct uwbd_site_config *c = &d->cfg.site;
    if (uwbd_contacts_testing(d)) {
        d->contacts_test.phase = 0;
        uwbd_log(UWBD_LOG_NOTICE, "contacts test: ended by a reload of the site's configuration");
    }
    struct uwbd_contacts_memory kept = {0};
    enum uwbd_contacts_kept how = UWBD_CONTACTS_KEPT_NONE;
    char path[UWBD_PATH_MAX + 64], why[UWBD_PATH_MAX + 256];
    if (uwbd_contacts_latch_path(&d->store, path, sizeof path) == 0)
        how = uwbd_contacts_latch_read(path, &kept, why, sizeof why);
    if (how == UWBD_CONTACTS_KEPT_UNREADABLE)
        uwbd_log(UWBD_LOG_WARNING,
                 "alarm contacts: the latch kept before this start cannot be read (%s): watch and alarm held "
                 "as unacknowledged until `ack`",
                 why);
    uwbd_contacts_init(&d->contacts, c->watch_latch, c->alarm_latch);
    uwbd_contacts_restore(&d->contacts, how, &kept, d->latest ? uwb_status_name(d->latest->status) : NULL,
                          d->latest && d->latest->fault[0] != '\0');
    d->contacts_kept = kept;
    d->contacts_kept_valid = how == UWBD_CONTACTS_KEPT;
    contacts_keep(d);
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
    contacts_keep(d);
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
    contacts_keep(d);
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
