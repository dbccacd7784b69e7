/* The alarm contacts as a module (contacts.*): their logic follows every
 * verdict and `ack`, their lines are the site's (output_site_io.c). The
 * logic runs with the contacts off too: the fault contact's state is the
 * appliance's health in MQTT's report. Opened again on a reload only when
 * the site's configuration changed. The latch is kept in the state
 * directory (contacts_latch.c) so that a restart does not clear an alarm
 * nobody acknowledged. `contacts test` (contacts_test.c decides who may)
 * runs its sequence here, on the main loop's clock, so the contacts come
 * back even when the client that asked is long gone. */
#include "daemon/output_contacts.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "daemon/output_site_io.h"
#include "state/contacts_latch.h"
#include "util/log.h"
#include "uwb/monotonic.h"

/* Phases 1..LAST_PHASE of a test: released, watch, released, alarm, released, fault. */
#define LAST_PHASE (2 * UWBD_CONTACT_COUNT)

static const struct uwbd_daemon_port *port; /* NULL until opened */
static struct uwbd_contacts logic;
static struct uwbd_contacts_memory kept; /* what contacts-latch.json holds */
static int kept_valid;                   /* ...as far as known: 0 until written or read */
static int latch_failing;                /* log a latch file that cannot be written once */
static struct {
    int phase; /* 0: no test runs */
    int hold_s;
    double phase_end_s; /* CLOCK_MONOTONIC */
} test;

static int enabled(void)
{
    return port && port->cfg->site.contacts_enabled;
}

int uwbd_contacts_testing(void)
{
    return test.phase != 0;
}

/* The contact lines set from the logic (when there are contacts and no
 * `contacts test` holds them). */
static void drive(void)
{
    /* A verdict or `ack` during a test changes the logic; the lines follow
     * it when the test ends. */
    if (!enabled() || uwbd_contacts_testing())
        return;
    const int energised[UWBD_CONTACT_COUNT] = {
        uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH),
        uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM),
        uwbd_contacts_energised(&logic, UWBD_CONTACT_FAULT),
    };
    uwbd_site_io_contacts(uwbd_site_lines(), energised);
}

/* Writes contacts-latch.json when what it would hold changed. A failure
 * (a full disk) is logged once and tried again at the next change; the
 * contacts go on from memory meanwhile. */
static void keep(void)
{
    if (!enabled())
        return;
    struct uwbd_contacts_memory now;
    uwbd_contacts_remember(&logic, &now);
    if (kept_valid && memcmp(&now, &kept, sizeof now) == 0)
        return;
    char path[UWBD_PATH_MAX + 64], err[UWBD_PATH_MAX + 256];
    if (uwbd_contacts_latch_path(port->store, path, sizeof path) != 0 ||
        uwbd_contacts_latch_write(path, &now, err, sizeof err) != 0) {
        if (!latch_failing)
            uwbd_log(UWBD_LOG_ERR, "alarm contacts: cannot keep the latch: %s; a restart now would lose it",
                     uwbd_contacts_latch_path(port->store, path, sizeof path) != 0 ? "path too long" : err);
        latch_failing = 1;
        kept_valid = 0;
        return;
    }
    if (latch_failing)
        uwbd_log(UWBD_LOG_NOTICE, "alarm contacts: the latch is kept again (%s)", path);
    latch_failing = 0;
    kept = now;
    kept_valid = 1;
}

/* The contacts come back from the latch kept before this start and the
 * verdict recorded last. A reload that opens the site's lines again ends a
 * running test. */
static int contacts_open(const struct uwbd_daemon_port *daemon_port)
{
    port = daemon_port;
    const struct uwbd_site_config *c = &port->cfg->site;
    if (uwbd_contacts_testing()) {
        test.phase = 0;
        uwbd_log(UWBD_LOG_NOTICE, "contacts test: ended by a reload of the site's configuration");
    }
    struct uwbd_contacts_memory from_latch = {0};
    enum uwbd_contacts_kept how = UWBD_CONTACTS_KEPT_NONE;
    char path[UWBD_PATH_MAX + 64], why[UWBD_PATH_MAX + 256];
    if (uwbd_contacts_latch_path(port->store, path, sizeof path) == 0)
        how = uwbd_contacts_latch_read(path, &from_latch, why, sizeof why);
    if (how == UWBD_CONTACTS_KEPT_UNREADABLE)
        uwbd_log(UWBD_LOG_WARNING,
                 "alarm contacts: the latch kept before this start cannot be read (%s): watch and alarm held "
                 "as unacknowledged until `ack`",
                 why);
    const struct uwb_verdict_record *latest = port->latest(port->daemon);
    uwbd_contacts_init(&logic, c->watch_latch, c->alarm_latch);
    uwbd_contacts_restore(&logic, how, &from_latch, latest ? uwb_status_name(latest->status) : NULL,
                          latest && latest->fault[0] != '\0');
    kept = from_latch;
    kept_valid = how == UWBD_CONTACTS_KEPT;
    keep();
    drive();
    if (c->contacts_enabled)
        uwbd_log(UWBD_LOG_INFO, "alarm contacts: watch %d, alarm %d, fault %d (energised = 1)",
                 uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH),
                 uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM),
                 uwbd_contacts_energised(&logic, UWBD_CONTACT_FAULT));
    return 0;
}

static void contacts_reload(const struct uwbd_daemon_port *daemon_port, const struct uwbd_config *previous)
{
    if (uwbd_site_changed(daemon_port->cfg, previous))
        contacts_open(daemon_port);
}

static void contacts_verdict(const struct uwbd_daemon_port *daemon_port, const struct uwb_verdict_record *v,
                             const char *json, double duration_s)
{
    (void)daemon_port, (void)duration_s;
    if (!json || !v)
        return;
    uwbd_contacts_verdict(&logic, uwb_status_name(v->status), v->fault[0] != '\0');
    keep();
    drive();
}

int uwbd_contacts_acknowledge(char *err, size_t errlen)
{
    if (!enabled()) {
        snprintf(err, errlen, "ack: there are no alarm contacts to acknowledge (contacts.enabled is false)");
        return -1;
    }
    if (!uwbd_site_lines()) {
        snprintf(err, errlen,
                 "ack: the alarm contacts are off: a reload could not open the site's lines (see the log)");
        return -1;
    }
    uwbd_contacts_ack(&logic);
    keep();
    drive();
    uwbd_log(UWBD_LOG_NOTICE, "alarm contacts acknowledged: watch %d, alarm %d",
             uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH),
             uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM));
    return 0;
}

void uwbd_contact_states(struct uwbd_contact_states *out)
{
    /* Lines a failed reload left closed drive nothing: none to report. */
    int on = enabled() && uwbd_site_lines();
    out->watch = on ? uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH) : -1;
    out->alarm = on ? uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM) : -1;
    out->fault = on ? uwbd_contacts_energised(&logic, UWBD_CONTACT_FAULT) : -1;
}

int uwbd_appliance_healthy(void)
{
    return uwbd_contacts_energised(&logic, UWBD_CONTACT_FAULT);
}

const char *uwbd_contacts_standing(void)
{
    return uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM)   ? "an alarm"
           : uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH) ? "a watch"
                                                                 : NULL;
}

/* The contact a test's phase energises, or -1 for a released one. */
static int phase_contact(int phase)
{
    return phase % 2 == 0 ? phase / 2 - 1 : -1;
}

static void enter_phase(int phase)
{
    int energised[UWBD_CONTACT_COUNT] = {0};
    int contact = phase_contact(phase);
    if (contact >= 0)
        energised[contact] = 1;
    test.phase = phase;
    test.phase_end_s = uwb_monotonic_s() + (contact >= 0 ? test.hold_s : UWBD_CONTACTS_TEST_GAP_S);
    uwbd_site_io_contacts(uwbd_site_lines(), energised);
    if (contact >= 0)
        uwbd_log(UWBD_LOG_NOTICE, "contacts test: %s energised for %d s, the others released",
                 uwbd_contact_name((enum uwbd_contact)contact), test.hold_s);
}

void uwbd_contacts_test_run(int hold_s)
{
    test.hold_s = hold_s;
    enter_phase(1);
}

static void test_end(const char *why)
{
    if (!uwbd_contacts_testing())
        return;
    test.phase = 0;
    drive();
    uwbd_log(UWBD_LOG_NOTICE, "contacts test: %s; contacts back to watch %d, alarm %d, fault %d", why,
             uwbd_contacts_energised(&logic, UWBD_CONTACT_WATCH),
             uwbd_contacts_energised(&logic, UWBD_CONTACT_ALARM),
             uwbd_contacts_energised(&logic, UWBD_CONTACT_FAULT));
}

/* Milliseconds until the running phase ends, so poll() wakes for it. */
static int test_prepare(void *ctx)
{
    (void)ctx;
    if (!uwbd_contacts_testing())
        return -1;
    double left_ms = (test.phase_end_s - uwb_monotonic_s()) * 1000.0;
    return left_ms > 0 ? (int)ceil(left_ms) : 0;
}

static void test_after(void *ctx)
{
    (void)ctx;
    if (!uwbd_contacts_testing() || uwb_monotonic_s() < test.phase_end_s)
        return;
    if (test.phase == LAST_PHASE)
        test_end("done");
    else
        enter_phase(test.phase + 1);
}

static int contacts_watch(const struct uwbd_daemon_port *daemon_port, struct uwbd_event_loop *loop)
{
    (void)daemon_port;
    return uwbd_event_loop_add_hook(loop, test_prepare, test_after, NULL) < 0 ? -1 : 0;
}

const struct uwbd_output_module uwbd_output_contacts = {
    .name = "alarm contacts",
    .open = contacts_open,
    .reload = contacts_reload,
    .verdict = contacts_verdict,
    .watch = contacts_watch,
};
