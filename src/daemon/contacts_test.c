/* `contacts test [force] [S]`: the point-to-point check of the alarm
 * contacts with the RTU at commissioning. Every contact is released for GAP_S, then
 * watch, alarm and fault are each energised alone for S seconds with GAP_S
 * released between, so that the RTU sees every input rise and fall on its
 * own; then the contacts go back to what the verdicts call for. The steps
 * run on the main loop's clock, not on the connection that asked, so the
 * contacts come back even when that client is long gone. Who may ask is
 * peers.c's to say; one test per contacts.test_min_interval_s, and during
 * a standing watch or alarm only with `force`. */
#define _GNU_SOURCE /* struct ucred */
#include <cjson/cJSON.h>
#include <errno.h>
#include <grp.h>
#include <math.h>
#include <pwd.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include "control/command.h"
#include "daemon/outputs.h"
#include "control/reply.h"
#include "daemon_internal.h"
#include "uwb/monotonic.h"
#include "util/log.h"

#define GAP_S 1
/* Phases 1..LAST_PHASE: released, watch, released, alarm, released, fault. */
#define LAST_PHASE (2 * UWBD_CONTACT_COUNT)

/* The contact a phase energises, or -1 for a released one. */
static int phase_contact(int phase)
{
    return phase % 2 == 0 ? phase / 2 - 1 : -1;
}

static void enter_phase(struct daemon *d, int phase)
{
    struct uwbd_contacts_test *t = &d->contacts_test;
    int energised[UWBD_CONTACT_COUNT] = {0};
    int contact = phase_contact(phase);
    if (contact >= 0)
        energised[contact] = 1;
    t->phase = phase;
    t->phase_end_s = uwb_monotonic_s() + (contact >= 0 ? t->hold_s : GAP_S);
    uwbd_site_io_contacts(d->site_io, energised);
    if (contact >= 0)
        uwbd_log(UWBD_LOG_NOTICE, "contacts test: %s energised for %d s, the others released",
                 uwbd_contact_name((enum uwbd_contact)contact), t->hold_s);
}

int uwbd_contacts_testing(const struct daemon *d)
{
    return d->contacts_test.phase != 0;
}

void uwbd_contacts_test_end(struct daemon *d, const char *why)
{
    if (!uwbd_contacts_testing(d))
        return;
    d->contacts_test.phase = 0;
    uwbd_contacts_drive(d);
    uwbd_log(UWBD_LOG_NOTICE, "contacts test: %s; contacts back to watch %d, alarm %d, fault %d", why,
             uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH),
             uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM),
             uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_FAULT));
}

static char *started_reply(int hold_s)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "class", "CONTACTS_TEST");
    cJSON *sequence = cJSON_AddArrayToObject(o, "sequence");
    for (int c = 0; c < UWBD_CONTACT_COUNT; c++)
        cJSON_AddItemToArray(sequence, cJSON_CreateString(uwbd_contact_name((enum uwbd_contact)c)));
    cJSON_AddNumberToObject(o, "hold_s", hold_s);
    cJSON_AddNumberToObject(o, "gap_s", GAP_S);
    cJSON_AddNumberToObject(o, "duration_s", UWBD_CONTACT_COUNT * (hold_s + GAP_S));
    char *line = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return line;
}

#ifndef SO_PEERGROUPS
#define SO_PEERGROUPS 59 /* Linux 4.13; older headers lack the name */
#endif

/* Whether the peer on `fd` has `gid` as its primary or a supplementary
 * group, as the kernel recorded at connect (no lookup of the user). */
static int peer_in_group(int fd, gid_t gid)
{
    struct ucred cred;
    socklen_t len = sizeof cred;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0 && len == sizeof cred && cred.gid == gid)
        return 1;
    gid_t small[64], *groups = small;
    len = sizeof small;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups, &len) != 0) {
        if (errno != ERANGE || !(groups = malloc(len)))
            return 0;
        if (getsockopt(fd, SOL_SOCKET, SO_PEERGROUPS, groups, &len) != 0)
            len = 0;
    }
    int found = 0;
    for (size_t i = 0; i < len / sizeof *groups && !found; i++)
        found = groups[i] == gid;
    if (groups != small)
        free(groups);
    return found;
}

int uwbd_contacts_test_permitted(const struct daemon *d, const struct peer *p, char *why, size_t n)
{
    if (p->kind == PEER_CONSOLE || p->privileged)
        return 0; /* at the board, root, or the daemon's own user */
    const char *group = d->cfg.contacts_test_group;
    char buf[4096];
    struct group gr, *found = NULL;
    if (group[0] && getgrnam_r(group, &gr, buf, sizeof buf, &found) == 0 && found &&
        peer_in_group(p->fd, found->gr_gid))
        return 0;
    struct passwd pw, *me = NULL;
    char self[64] = "";
    if (getpwuid_r(geteuid(), &pw, buf, sizeof buf, &me) == 0 && me)
        snprintf(self, sizeof self, " (%s)", me->pw_name);
    if (group[0])
        snprintf(why, n,
                 "contacts test: refused for uid %u: only root, the service's user%s and members of group "
                 "\"%s\" (contacts.test_group) may test the contacts",
                 (unsigned)p->uid, self, group);
    else
        snprintf(
            why, n,
            "contacts test: refused for uid %u: only root and the service's user%s may test the contacts "
            "(contacts.test_group names a group that may too)",
            (unsigned)p->uid, self);
    return -1;
}

char *uwbd_contacts_test_start(struct daemon *d, int hold_s, int force, const char *who)
{
    if (!d->cfg.site.contacts_enabled)
        return uwbd_reply_error("contacts test: there are no alarm contacts (contacts.enabled is false)");
    if (!d->site_io)
        return uwbd_reply_error("contacts test: the alarm contacts are off: a reload could not open the "
                                "site's lines (see the log)");
    if (d->stopping)
        return uwbd_reply_error("contacts test: the daemon is stopping");
    if (d->scanning)
        return uwbd_reply_error("contacts test: refused while a scan runs; try again when status says idle");
    if (uwbd_contacts_testing(d))
        return uwbd_reply_error("contacts test: one is already running; wait for it to end (see the log)");
    if (hold_s < 1 || hold_s > UWB_CONTACTS_TEST_MAX_S)
        return uwbd_reply_error("contacts test: S must be from 1 to 60 seconds");
    char why[200];
    double now = uwb_monotonic_s(), interval = d->cfg.contacts_test_min_interval_s;
    struct uwbd_contacts_test *t = &d->contacts_test;
    if (interval > 0 && t->last_start_s > 0 && now - t->last_start_s < interval) {
        snprintf(why, sizeof why,
                 "contacts test: one per %g s (contacts.test_min_interval_s); the next is allowed in %.0f s",
                 interval, interval - (now - t->last_start_s) + 0.5);
        return uwbd_reply_error(why);
    }
    /* A test releases every contact in turn: during a standing alarm the
     * RTU would see it clear, so only on purpose. */
    const char *standing = uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_ALARM)   ? "an alarm"
                           : uwbd_contacts_energised(&d->contacts, UWBD_CONTACT_WATCH) ? "a watch"
                                                                                       : NULL;
    if (standing && !force) {
        snprintf(why, sizeof why,
                 "contacts test: refused while %s stands (the RTU would see it clear and return); say "
                 "`contacts test force` to test anyway",
                 standing);
        return uwbd_reply_error(why);
    }
    if (standing)
        uwbd_log(UWBD_LOG_WARNING, "contacts test: forced by %s while %s stands: the RTU sees it clear", who,
                 standing);
    t->hold_s = hold_s;
    t->last_start_s = now;
    uwbd_log(UWBD_LOG_NOTICE,
             "contacts test: started by %s: watch, alarm and fault energised alone in turn, %d s each, %d s "
             "released between",
             who, hold_s, GAP_S);
    enter_phase(d, 1);
    return started_reply(hold_s);
}

/* Milliseconds until the running phase ends, so poll() wakes for it. */
static int test_prepare(void *ctx)
{
    const struct daemon *d = ctx;
    if (!uwbd_contacts_testing(d))
        return -1;
    double left_ms = (d->contacts_test.phase_end_s - uwb_monotonic_s()) * 1000.0;
    return left_ms > 0 ? (int)ceil(left_ms) : 0;
}

static void test_after(void *ctx)
{
    struct daemon *d = ctx;
    if (!uwbd_contacts_testing(d) || uwb_monotonic_s() < d->contacts_test.phase_end_s)
        return;
    if (d->contacts_test.phase == LAST_PHASE)
        uwbd_contacts_test_end(d, "done");
    else
        enter_phase(d, d->contacts_test.phase + 1);
}

int uwbd_contacts_test_watch(struct daemon *d, struct uwbd_event_loop *loop)
{
    return uwbd_event_loop_add_hook(loop, test_prepare, test_after, d) < 0 ? -1 : 0;
}
