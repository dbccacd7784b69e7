/* ctl_attack: hostile control-socket clients for the lockout tests
 * (tests/e2e/test_daemon_attacks.sh, issue 17 break 6), in C because a
 * fresh machine has no Python.
 *
 *   ctl_attack trickle SOCKET CLIENTS SECONDS
 *       CLIENTS connections that each send one byte ('h') every 0.9 s and
 *       never complete a line, for SECONDS; meanwhile an operator asks
 *       `status` every second (again every 0.2 s while turned away).
 *       Prints "worst status reply: X.XX s" and "trickling clients
 *       dropped: N of CLIENTS"; exit 1 if a `status` went unanswered 5 s.
 *   ctl_attack noread SOCKET CLIENTS REPEATS
 *       CLIENTS connections that each send "help\n" REPEATS times and never
 *       read; then a fresh client asks `status`. Prints "status reply: X.XX s";
 *       exit 1 if it took 5 s or more.
 *   ctl_attack send SOCKET TEXT LINES TIMEOUT_S
 *       Sends TEXT (with \n escapes) on one connection, prints the reply
 *       lines as they come; exit 0 when LINES lines came, 1 when TIMEOUT_S
 *       passed or the daemon closed first.
 *   ctl_attack backlog SOCKET SECONDS
 *       A daemon that stopped accepting (issue 27, break 3): listens on
 *       SOCKET with a backlog of 0, never accepts, and fills the backlog
 *       with its own connections; prints "backlog full: N queued" and holds
 *       it for SECONDS.
 *   ctl_attack scanhold SOCKET CLIENTS SECONDS   (root only)
 *       One control-group member locks out the others (issue 27, break 7):
 *       a child as uid 65534, in the socket's group, holds CLIENTS
 *       connections that each send `scan` and send it again after every
 *       reply; from 1.5 s on another member (uid 65533) asks `status` on a
 *       fresh connection every 0.5 s. After SECONDS prints "attacker: H of
 *       CLIENTS connections held, V verdicts, R scans refused", the first
 *       refusal, and "member: A of N status answered"; exit 0 when every
 *       `status` was answered within 5 s. */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <grp.h>
#include <unistd.h>

#include "uwb/monotonic.h"

#define MAX_ATTACKERS 64
#define UNANSWERED_S 5.0

static int connect_to(const char *path)
{
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    if (strlen(path) >= sizeof a.sun_path)
        return -1;
    memcpy(a.sun_path, path, strlen(path) + 1);
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd >= 0 && connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        fd = -1;
    }
    return fd;
}

/* Send `text` and read `lines` reply lines within timeout_s into out
 * (may be NULL: then printed). Returns the lines read. */
static int exchange(int fd, const char *text, int lines, double timeout_s, FILE *print)
{
    size_t n = strlen(text), sent = 0;
    while (sent < n) {
        ssize_t w = send(fd, text + sent, n - sent, MSG_NOSIGNAL);
        if (w <= 0)
            return 0;
        sent += (size_t)w;
    }
    double end = uwb_monotonic_s() + timeout_s;
    int got = 0;
    char buf[65536];
    while (got < lines) {
        double left = end - uwb_monotonic_s();
        if (left <= 0)
            break;
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (poll(&p, 1, (int)(left * 1000) + 1) <= 0)
            continue;
        ssize_t r = recv(fd, buf, sizeof buf, 0);
        if (r <= 0)
            break;
        if (print)
            fwrite(buf, 1, (size_t)r, print);
        for (ssize_t i = 0; i < r; i++)
            got += buf[i] == '\n';
    }
    if (print)
        fflush(print);
    return got;
}

/* One fresh `status`: 1 when a STATUS reply came within `timeout_s`. */
static int ask_status(const char *path, double timeout_s)
{
    int fd = connect_to(path);
    if (fd < 0)
        return 0;
    char line[4096] = "";
    FILE *mem = fmemopen(line, sizeof line, "w");
    int got = exchange(fd, "status\n", 1, timeout_s, mem);
    if (mem)
        fclose(mem);
    close(fd);
    return got == 1 && strstr(line, "\"class\":\"STATUS\"") != NULL;
}

/* Seconds until an operator asking `status` (again every 0.2 s while it is
 * turned away) gets its STATUS reply; UNANSWERED_S when it never does. */
static double status_time(const char *path)
{
    double t0 = uwb_monotonic_s();
    while (uwb_monotonic_s() - t0 < UNANSWERED_S) {
        if (ask_status(path, UNANSWERED_S - (uwb_monotonic_s() - t0)))
            return uwb_monotonic_s() - t0;
        usleep(200000);
    }
    return UNANSWERED_S;
}

static int trickle(const char *path, int clients, double seconds)
{
    int fd[MAX_ATTACKERS];
    for (int i = 0; i < clients; i++)
        fd[i] = connect_to(path);
    double worst = 0, end = uwb_monotonic_s() + seconds, next_byte = 0, next_status = uwb_monotonic_s() + 1.0;
    while (uwb_monotonic_s() < end) {
        double now = uwb_monotonic_s();
        if (now >= next_byte) {
            for (int i = 0; i < clients; i++)
                if (fd[i] >= 0 && send(fd[i], "h", 1, MSG_NOSIGNAL | MSG_DONTWAIT) != 1) {
                    close(fd[i]);
                    fd[i] = -1;
                }
            next_byte = now + 0.9;
        }
        if (now >= next_status) {
            double t = status_time(path);
            if (t > worst)
                worst = t;
            next_status = uwb_monotonic_s() + 1.0;
        }
        usleep(50000);
    }
    int dropped = 0;
    for (int i = 0; i < clients; i++) {
        char c;
        if (fd[i] < 0 || recv(fd[i], &c, 1, MSG_DONTWAIT) == 0)
            dropped++;
        if (fd[i] >= 0)
            close(fd[i]);
    }
    printf("worst status reply: %.2f s\ntrickling clients dropped: %d of %d\n", worst, dropped, clients);
    return worst < UNANSWERED_S ? 0 : 1;
}

static int noread(const char *path, int clients, int repeats)
{
    int fd[MAX_ATTACKERS];
    for (int i = 0; i < clients; i++) {
        fd[i] = connect_to(path);
        if (fd[i] < 0)
            continue;
        fcntl(fd[i], F_SETFL, O_NONBLOCK);
        for (int k = 0; k < repeats; k++)
            if (send(fd[i], "help\n", 5, MSG_NOSIGNAL) != 5)
                break; /* the daemon stopped reading it, or dropped it */
    }
    double t = status_time(path);
    printf("status reply: %.2f s\n", t);
    for (int i = 0; i < clients; i++)
        if (fd[i] >= 0)
            close(fd[i]);
    return t < UNANSWERED_S ? 0 : 1;
}

static int full_backlog(const char *path, double seconds)
{
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    if (strlen(path) >= sizeof a.sun_path)
        return 2;
    memcpy(a.sun_path, path, strlen(path) + 1);
    int listener = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    unlink(path);
    if (listener < 0 || bind(listener, (struct sockaddr *)&a, sizeof a) != 0 || listen(listener, 0) != 0) {
        fprintf(stderr, "ctl_attack: %s: cannot listen: %s\n", path, strerror(errno));
        return 1;
    }
    int queued[MAX_ATTACKERS], n = 0;
    while (n < MAX_ATTACKERS) {
        int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
        if (fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
            if (fd >= 0)
                close(fd);
            break; /* EAGAIN: the backlog is full */
        }
        queued[n++] = fd;
    }
    printf("backlog full: %d queued\n", n);
    fflush(stdout);
    usleep((useconds_t)(seconds * 1e6));
    for (int i = 0; i < n; i++)
        close(queued[i]);
    close(listener);
    unlink(path);
    return n > 0 ? 0 : 1;
}

#define ATTACKER_UID 65534
#define MEMBER_UID 65533

/* This process becomes `uid` in the socket's group: a control-group member. */
static int become_member(const char *path, uid_t uid)
{
    struct stat st;
    if (stat(path, &st) != 0 || setgroups(0, NULL) != 0 || setgid(st.st_gid) != 0 || setuid(uid) != 0) {
        fprintf(stderr, "ctl_attack: cannot become uid %u in the socket's group: %s\n", (unsigned)uid,
                strerror(errno));
        return -1;
    }
    return 0;
}

/* The attacker: `clients` connections re-sending `scan` after each reply. */
static int hold_scans(const char *path, int clients, double seconds)
{
    int fd[MAX_ATTACKERS], held = 0, verdicts = 0, refused = 0;
    char first_refusal[512] = "";
    for (int i = 0; i < clients; i++) {
        fd[i] = connect_to(path);
        if (fd[i] >= 0 && send(fd[i], "scan\n", 5, MSG_NOSIGNAL) != 5) {
            close(fd[i]);
            fd[i] = -1;
        }
    }
    double end = uwb_monotonic_s() + seconds;
    while (uwb_monotonic_s() < end) {
        struct pollfd p[MAX_ATTACKERS];
        for (int i = 0; i < clients; i++)
            p[i] = (struct pollfd){.fd = fd[i], .events = POLLIN};
        if (poll(p, (nfds_t)clients, 100) <= 0)
            continue;
        for (int i = 0; i < clients; i++) {
            if (fd[i] < 0 || !(p[i].revents & (POLLIN | POLLHUP)))
                continue;
            char buf[4096];
            ssize_t r = recv(fd[i], buf, sizeof buf - 1, 0);
            if (r <= 0) {
                close(fd[i]);
                fd[i] = -1;
                continue;
            }
            buf[r] = '\0';
            if (strstr(buf, "\"class\":\"VERDICT\""))
                verdicts++;
            if (strstr(buf, "\"class\":\"ERROR\"")) {
                refused++;
                if (!first_refusal[0])
                    snprintf(first_refusal, sizeof first_refusal, "%s", strtok(buf, "\n"));
            }
            if (send(fd[i], "scan\n", 5, MSG_NOSIGNAL) != 5) {
                close(fd[i]);
                fd[i] = -1;
            }
        }
    }
    for (int i = 0; i < clients; i++)
        if (fd[i] >= 0) {
            held++;
            close(fd[i]);
        }
    printf("attacker: %d of %d connections held, %d verdicts, %d scans refused\nfirst refusal: %s\n", held,
           clients, verdicts, refused, first_refusal);
    return 0;
}

/* The other member: `status` every 0.5 s until `seconds` passed. */
static int ask_status_meanwhile(const char *path, double seconds)
{
    int asked = 0, answered = 0;
    double end = uwb_monotonic_s() + seconds;
    while (uwb_monotonic_s() < end) {
        asked++;
        answered += ask_status(path, UNANSWERED_S);
        usleep(500000);
    }
    printf("member: %d of %d status answered\n", answered, asked);
    return asked > 0 && answered == asked ? 0 : 1;
}

static int scan_hold(const char *path, int clients, double seconds)
{
    fflush(stdout);
    pid_t attacker = fork();
    if (attacker == 0) {
        int rc = become_member(path, ATTACKER_UID) == 0 ? hold_scans(path, clients, seconds) : 2;
        fflush(stdout);
        _exit(rc);
    }
    usleep(1500000);
    fflush(stdout);
    pid_t member = fork();
    if (member == 0) {
        int rc = become_member(path, MEMBER_UID) == 0 ? ask_status_meanwhile(path, seconds - 2.0) : 2;
        fflush(stdout);
        _exit(rc);
    }
    int attacker_status = 0, member_status = 0;
    if (attacker < 0 || member < 0 || waitpid(member, &member_status, 0) < 0 ||
        waitpid(attacker, &attacker_status, 0) < 0)
        return 2;
    return WIFEXITED(member_status) && WEXITSTATUS(member_status) == 0 && WIFEXITED(attacker_status) &&
                   WEXITSTATUS(attacker_status) == 0
               ? 0
               : 1;
}

/* TEXT with "\n" written as backslash-n on the command line. */
static void unescape(char *s)
{
    char *o = s;
    for (; *s; s++) {
        if (s[0] == '\\' && s[1] == 'n') {
            *o++ = '\n';
            s++;
        } else {
            *o++ = *s;
        }
    }
    *o = '\0';
}

int main(int argc, char **argv)
{
    if (argc == 5 && strcmp(argv[1], "trickle") == 0 && atoi(argv[3]) <= MAX_ATTACKERS)
        return trickle(argv[2], atoi(argv[3]), atof(argv[4]));
    if (argc == 5 && strcmp(argv[1], "noread") == 0 && atoi(argv[3]) <= MAX_ATTACKERS)
        return noread(argv[2], atoi(argv[3]), atoi(argv[4]));
    if (argc == 5 && strcmp(argv[1], "scanhold") == 0 && atoi(argv[3]) <= MAX_ATTACKERS)
        return scan_hold(argv[2], atoi(argv[3]), atof(argv[4]));
    if (argc == 4 && strcmp(argv[1], "backlog") == 0)
        return full_backlog(argv[2], atof(argv[3]));
    if (argc == 6 && strcmp(argv[1], "send") == 0) {
        int fd = connect_to(argv[2]);
        if (fd < 0) {
            fprintf(stderr, "ctl_attack: %s: cannot connect: %s\n", argv[2], strerror(errno));
            return 1;
        }
        unescape(argv[3]);
        int want = atoi(argv[4]);
        int got = exchange(fd, argv[3], want, atof(argv[5]), stdout);
        close(fd);
        return got >= want ? 0 : 1;
    }
    fprintf(stderr, "usage: ctl_attack trickle|noread SOCKET CLIENTS SECONDS|REPEATS\n"
                    "       ctl_attack send SOCKET TEXT LINES TIMEOUT_S\n"
                    "       ctl_attack backlog SOCKET SECONDS\n"
                    "       ctl_attack scanhold SOCKET CLIENTS SECONDS\n");
    return 2;
}
