/* `contacts test [force] [S]`: the point-to-point check of the alarm
 * contacts with the RTU at commissioning. Every contact is released for GAP_S, then
 * watch, alarm and fault are each energised alone for S seconds with GAP_S
 * released between, so that the RTU sees every input rise and fall on its
 * own; then the contacts go back to what the verdicts call for. The steps
 * run in the contacts' module (output_contacts.c); this file says who may
 * ask and when: one test per contacts.test_min_interval_s, and during a
 * standing watch or alarm only with `force`. */
#define _GNU_SOURCE /* struct ucred */
#include <cjson/cJSON.h>
#include <errno.h>
#include <grp.h>
#include <pwd.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include "control/command.h"
#include "daemon/output_contacts.h"
#include "integrations/alarm_contacts.h"
#include "daemon/output_site_io.h"
#include "control/reply.h"
#include "daemon_internal.h"
#include "uwb/monotonic.h"
#include "util/log.h"

#define GAP_S UWBD_CONTACTS_TEST_GAP_S

static double last_start_s; /* CLOCK_MONOTONIC of the last test's start; 0: none yet */

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
    if (!uwbd_site_lines())
        return uwbd_reply_error("contacts test: the alarm contacts are off: a reload could not open the "
                                "site's lines (see the log)");
    if (d->stopping)
        return uwbd_reply_error("contacts test: the daemon is stopping");
    if (d->scanning)
        return uwbd_reply_error("contacts test: refused while a scan runs; try again when status says idle");
    if (uwbd_contacts_testing())
        return uwbd_reply_error("contacts test: one is already running; wait for it to end (see the log)");
    if (hold_s < 1 || hold_s > UWB_CONTACTS_TEST_MAX_S)
        return uwbd_reply_error("contacts test: S must be from 1 to 60 seconds");
    char why[200];
    double now = uwb_monotonic_s(), interval = d->cfg.contacts_test_min_interval_s;
    if (interval > 0 && last_start_s > 0 && now - last_start_s < interval) {
        snprintf(why, sizeof why,
                 "contacts test: one per %g s (contacts.test_min_interval_s); the next is allowed in %.0f s",
                 interval, interval - (now - last_start_s) + 0.5);
        return uwbd_reply_error(why);
    }
    /* A test releases every contact in turn: during a standing alarm the
     * RTU would see it clear, so only on purpose. */
    const char *standing = uwbd_contacts_standing();
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
    last_start_s = now;
    uwbd_log(UWBD_LOG_NOTICE,
             "contacts test: started by %s: watch, alarm and fault energised alone in turn, %d s each, %d s "
             "released between",
             who, hold_s, GAP_S);
    uwbd_contacts_test_run(hold_s);
    return started_reply(hold_s);
}
