/* notify_listen SOCKET OUT_FILE SECONDS: the service manager's end of
 * sd_notify for tests/e2e/test_systemd_notify.sh. Binds a unix datagram
 * socket at SOCKET (what NOTIFY_SOCKET names) and, for at most SECONDS or
 * until SIGTERM, writes every assignment received to OUT_FILE as
 * "SECONDS_SINCE_START NAME=VALUE", one a line, flushed at once.
 * Exit 0, or 1 if the socket cannot be made. */
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "uwb/monotonic.h"

static volatile sig_atomic_t stop;

static void on_term(int sig)
{
    (void)sig;
    stop = 1;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: notify_listen SOCKET OUT_FILE SECONDS\n");
        return 64;
    }
    struct sockaddr_un a = {.sun_family = AF_UNIX};
    if (strlen(argv[1]) >= sizeof a.sun_path) {
        fprintf(stderr, "notify_listen: %s: path too long\n", argv[1]);
        return 1;
    }
    strcpy(a.sun_path, argv[1]);
    int fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        fprintf(stderr, "notify_listen: %s: cannot bind: %s\n", argv[1], strerror(errno));
        return 1;
    }
    FILE *out = fopen(argv[2], "w");
    if (!out) {
        fprintf(stderr, "notify_listen: %s: cannot write: %s\n", argv[2], strerror(errno));
        return 1;
    }
    struct sigaction sa = {.sa_handler = on_term};
    sigaction(SIGTERM, &sa, NULL);
    double start = uwb_monotonic_s(), end = start + atof(argv[3]);
    char buf[4096];
    while (!stop) {
        double left = end - uwb_monotonic_s();
        if (left <= 0)
            break;
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (poll(&p, 1, (int)(left * 1000) + 1) <= 0)
            continue;
        ssize_t n = recv(fd, buf, sizeof buf - 1, 0);
        if (n <= 0)
            continue;
        buf[n] = '\0';
        double t = uwb_monotonic_s() - start;
        for (char *line = strtok(buf, "\n"); line; line = strtok(NULL, "\n"))
            fprintf(out, "%.3f %s\n", t, line);
        fflush(out);
    }
    fclose(out);
    close(fd);
    unlink(argv[1]);
    return 0;
}
