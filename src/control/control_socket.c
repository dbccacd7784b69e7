/* Creating, removing and connecting to the control socket. */
#include "control/control_socket.h"

#include <errno.h>
#include <fcntl.h>
#include <grp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "uwb/monotonic.h"

#define BACKLOG 8
/* A listener whose backlog is full answers a non-blocking connect with
 * EAGAIN (a unix socket never says EINPROGRESS, so there is nothing to
 * poll): connecting is tried again this often until the deadline. */
#define CONNECT_RETRY_MS 20
/* Whether another uwbd listens on the path: a full backlog counts as yes. */
#define PROBE_TIMEOUT_S 1.0

static int fill_address(struct sockaddr_un *addr, const char *path)
{
    memset(addr, 0, sizeof *addr);
    addr->sun_family = AF_UNIX;
    if (strlen(path) >= sizeof addr->sun_path)
        return -1;
    memcpy(addr->sun_path, path, strlen(path) + 1);
    return 0;
}

int uwbd_control_connect(const char *path, double timeout_s, char *err, size_t errlen)
{
    struct sockaddr_un addr;
    if (fill_address(&addr, path) != 0) {
        snprintf(err, errlen, "%.64s...: socket path too long", path);
        return UWBD_CONTROL_CONNECT_FAILED;
    }
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        snprintf(err, errlen, "socket: %s", strerror(errno));
        return UWBD_CONTROL_CONNECT_FAILED;
    }
    double deadline = uwb_monotonic_s() + timeout_s;
    while (connect(fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        if (errno == EINTR)
            continue;
        if (errno == EACCES || errno == EPERM) {
            int e = errno;
            close(fd);
            uwbd_control_explain_denied(path, e, err, errlen);
            return UWBD_CONTROL_CONNECT_DENIED;
        }
        if (errno != EAGAIN) {
            snprintf(err, errlen, "%s: cannot connect: %s", path, strerror(errno));
            close(fd);
            return UWBD_CONTROL_CONNECT_FAILED;
        }
        double left_ms = (deadline - uwb_monotonic_s()) * 1000.0;
        if (left_ms <= 0) {
            snprintf(err, errlen,
                     "%s: the daemon did not accept the connection within %g s (its backlog is full: hung or "
                     "overloaded?)",
                     path, timeout_s);
            close(fd);
            return UWBD_CONTROL_CONNECT_TIMEOUT;
        }
        poll(NULL, 0, left_ms < CONNECT_RETRY_MS ? (int)left_ms + 1 : CONNECT_RETRY_MS);
    }
    /* The replies are read with poll() against their own deadline. */
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    return fd;
}

/* What the daemon wrote before it closed (e.g. "too many control clients"):
 * already in our receive queue, so it is read without waiting. */
static void read_refusal(int fd, char *reason, size_t reason_len)
{
    ssize_t got = recv(fd, reason, reason_len - 1, MSG_DONTWAIT);
    reason[got > 0 ? got : 0] = '\0';
    char *nl = strchr(reason, '\n');
    if (nl)
        *nl = '\0';
}

int uwbd_control_send(int fd, const char *text, size_t n, char *reason, size_t reason_len)
{
    reason[0] = '\0';
    size_t sent = 0;
    while (sent < n) {
        ssize_t w = send(fd, text + sent, n - sent, MSG_NOSIGNAL);
        if (w > 0) {
            sent += (size_t)w;
            continue;
        }
        if (w < 0 && errno == EINTR)
            continue;
        int e = w < 0 ? errno : EPIPE;
        if (e == EPIPE || e == ECONNRESET)
            read_refusal(fd, reason, reason_len);
        errno = e;
        return -1;
    }
    return 0;
}

static int lookup_group(const char *group, gid_t *gid, char *err, size_t errlen)
{
    char buf[4096];
    struct group gr, *found = NULL;
    int rc = getgrnam_r(group, &gr, buf, sizeof buf, &found);
    if (rc != 0 || !found) {
        snprintf(err, errlen, "control.group: no group named \"%s\"%s%s", group, rc ? ": " : "",
                 rc ? strerror(rc) : "");
        return -1;
    }
    *gid = found->gr_gid;
    return 0;
}

/* The socket's directory (e.g. a run directory in tests); systemd's
 * RuntimeDirectory makes it in production. */
static int ensure_parent(const char *path, gid_t gid, int set_group, char *err, size_t errlen)
{
    char dir[108];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (!slash || slash == dir)
        return 0;
    *slash = '\0';
    if (mkdir(dir, 0750) == 0) {
        if (set_group && chown(dir, (uid_t)-1, gid) != 0) {
            snprintf(err, errlen, "%s: cannot give the directory to the control group: %s", dir,
                     strerror(errno));
            return -1;
        }
        return 0;
    }
    if (errno == EEXIST)
        return 0;
    snprintf(err, errlen, "%s: cannot create the control socket's directory: %s", dir, strerror(errno));
    return -1;
}

int uwbd_control_listen(struct uwbd_control_socket *cs, const char *path, unsigned mode, const char *group,
                        char *err, size_t errlen)
{
    memset(cs, 0, sizeof *cs);
    cs->fd = -1;
    gid_t gid = 0;
    int set_group = group && group[0];
    if (set_group && lookup_group(group, &gid, err, errlen) != 0)
        return UWBD_CONTROL_ERR_CONFIG;
    char temp[108];
    struct sockaddr_un addr;
    if (snprintf(temp, sizeof temp, "%s.new%ld", path, (long)getpid()) >= (int)sizeof temp ||
        fill_address(&addr, temp) != 0) {
        snprintf(err, errlen, "%s: control socket path too long (the temporary name needs %zu more bytes)",
                 path, strlen(temp) + 1 - sizeof addr.sun_path);
        return UWBD_CONTROL_ERR_CREATE;
    }
    if (ensure_parent(path, gid, set_group, err, errlen) != 0)
        return UWBD_CONTROL_ERR_CREATE;

    /* Never delete what is not a stale socket of ours. */
    struct stat st;
    if (lstat(path, &st) == 0) {
        if (!S_ISSOCK(st.st_mode)) {
            snprintf(err, errlen, "%s: exists and is not a socket; not replacing it", path);
            return UWBD_CONTROL_ERR_CREATE;
        }
        char ignored[256];
        int other = uwbd_control_connect(path, PROBE_TIMEOUT_S, ignored, sizeof ignored);
        if (other >= 0 || other == UWBD_CONTROL_CONNECT_TIMEOUT) {
            if (other >= 0)
                close(other);
            snprintf(err, errlen, "%s: another uwbd is listening there%s", path,
                     other >= 0 ? "" : " (not accepting: its backlog is full)");
            return UWBD_CONTROL_ERR_CREATE;
        }
    }
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    if (fd < 0) {
        snprintf(err, errlen, "socket: %s", strerror(errno));
        return UWBD_CONTROL_ERR_CREATE;
    }
    unlink(temp);
    /* Bind with no permissions at all; the final mode is set before anyone can see the name. */
    mode_t old_mask = umask(0777);
    int bound = bind(fd, (struct sockaddr *)&addr, sizeof addr);
    int bind_errno = errno;
    umask(old_mask);
    const char *step = NULL;
    int e = 0;
    if (bound != 0) {
        step = "bind";
        e = bind_errno;
    } else if (set_group && chown(temp, (uid_t)-1, gid) != 0) {
        step = "chown to the control group";
        e = errno;
    } else if (chmod(temp, mode) != 0) {
        step = "chmod";
        e = errno;
    } else if (listen(fd, BACKLOG) != 0) {
        step = "listen";
        e = errno;
    } else if (lstat(temp, &st) != 0) {
        step = "stat";
        e = errno;
    } else if (rename(temp, path) != 0) {
        step = "rename into place";
        e = errno;
    }
    if (step) {
        close(fd);
        unlink(temp);
        if (e == EPERM && set_group && strcmp(step, "chown to the control group") == 0) {
            snprintf(err, errlen, "control.group: the daemon may not give %s to group \"%s\" (not a member?)",
                     path, group);
            return UWBD_CONTROL_ERR_CONFIG;
        }
        snprintf(err, errlen, "%s: cannot create the control socket (%s): %s", path, step, strerror(e));
        return UWBD_CONTROL_ERR_CREATE;
    }
    cs->fd = fd;
    snprintf(cs->path, sizeof cs->path, "%s", path);
    cs->dev = st.st_dev;
    cs->ino = st.st_ino;
    return UWBD_CONTROL_OK;
}

void uwbd_control_close(struct uwbd_control_socket *cs)
{
    if (cs->fd < 0)
        return;
    close(cs->fd);
    cs->fd = -1;
    struct stat st;
    if (lstat(cs->path, &st) == 0 && st.st_dev == cs->dev && st.st_ino == cs->ino)
        unlink(cs->path);
}
