/* Why connecting to the control socket was refused (EACCES, EPERM): the
 * directory or the socket that shuts this user out, its owner, group and
 * mode, and what to do, so that `uwbd ctl` does not blame a missing daemon.
 * access() checks the real ids, which are `uwbd ctl`'s own (not setuid). */
#define _GNU_SOURCE /* getgrouplist */
#include "control/control_socket.h"

#include <errno.h>
#include <grp.h>
#include <pwd.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_GROUPS 256

/* The first directory on the way to path that this user may not search,
 * copied to dir; 0 when every one lets them through. */
static int blocking_directory(const char *path, char *dir, size_t dirlen)
{
    for (const char *slash = strchr(path + 1, '/'); slash; slash = strchr(slash + 1, '/')) {
        size_t n = (size_t)(slash - path);
        if (n >= dirlen)
            return 0;
        memcpy(dir, path, n);
        dir[n] = '\0';
        if (access(dir, X_OK) != 0 && errno == EACCES)
            return 1;
    }
    return 0;
}

static int in_session_group(gid_t gid)
{
    gid_t groups[MAX_GROUPS];
    int n = getgroups(MAX_GROUPS, groups);
    if (getegid() == gid)
        return 1;
    for (int i = 0; i < n; i++)
        if (groups[i] == gid)
            return 1;
    return 0;
}

/* Whether the group database lists the user in gid (a membership this
 * login may predate). */
static int listed_in_group(const char *user, gid_t primary, gid_t gid)
{
    gid_t groups[MAX_GROUPS];
    int n = MAX_GROUPS;
    if (!user || getgrouplist(user, primary, groups, &n) < 0)
        return 0;
    for (int i = 0; i < n; i++)
        if (groups[i] == gid)
            return 1;
    return 0;
}

void uwbd_control_explain_denied(const char *path, int error, char *err, size_t errlen)
{
    char dir[108], what[160];
    struct stat st;
    int is_dir = blocking_directory(path, dir, sizeof dir);
    const char *blocker = is_dir ? dir : path;
    if (stat(blocker, &st) != 0) {
        snprintf(err, errlen, "%s: permission denied: %s", path, strerror(error));
        return;
    }
    if (is_dir)
        snprintf(what, sizeof what, "you may not enter its directory %s", dir);
    else
        snprintf(what, sizeof what, "you may not connect to it");
    const struct group *gr = getgrgid(st.st_gid);
    char group[64], owner[64];
    if (gr)
        snprintf(group, sizeof group, "%s", gr->gr_name);
    else
        snprintf(group, sizeof group, "%u", (unsigned)st.st_gid);
    const struct passwd *own = getpwuid(st.st_uid);
    if (own)
        snprintf(owner, sizeof owner, "%s", own->pw_name);
    else
        snprintf(owner, sizeof owner, "%u", (unsigned)st.st_uid);
    const struct passwd *me = getpwuid(getuid());
    char user[64];
    snprintf(user, sizeof user, "%s", me ? me->pw_name : "$USER");

    char advice[512];
    if (!is_dir && access(path, W_OK) == 0)
        snprintf(advice, sizeof advice, "its mode lets you in, so the system refused (AppArmor or SELinux?)");
    else if (getuid() == st.st_uid)
        snprintf(advice, sizeof advice, "its mode shuts out its owner too (control.mode, or chmod)");
    else if (in_session_group(st.st_gid))
        snprintf(advice, sizeof advice, "you are in group \"%s\", but its mode gives the group no access%s",
                 group, is_dir ? "" : " (control.mode \"0660\")");
    else if (me && listed_in_group(me->pw_name, me->pw_gid, st.st_gid))
        snprintf(advice, sizeof advice,
                 "you were added to group \"%s\" after this login began: log in again (or run newgrp %s)",
                 group, group);
    else
        snprintf(
            advice, sizeof advice,
            "add yourself to group \"%s\" (sudo adduser %s %s) and log in again, or run uwbd ctl as root",
            group, user, group);
    snprintf(err, errlen, "%s: permission denied: %s (mode %04o, owner %s, group \"%s\"); %s", path, what,
             (unsigned)(st.st_mode & 07777), owner, group, advice);
}
