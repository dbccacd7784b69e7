/* Starting uwbd so that its peak RSS is its own.
 *
 * The kernel's ru_maxrss for a child counts what its address space held
 * before exec too, and a forked child starts with a copy of its parent's:
 * fork uwbd from this bench after it has allocated images and uwbd would be
 * charged for them. So at start-up, before any big allocation, the bench
 * forks a small launcher; later it sends the launcher argument lists
 * through a pipe, and the launcher forks and execs them, waits with wait4
 * and sends back the time, the time it waited for a CPU, the peak RSS and
 * the program's stdout. */
#include "bench.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_ARGS 24
#define MAX_REQUEST 4096

struct launch_reply {
    int ok;     /* 0: could not start or wait (message in text) */
    int status; /* exit status, or 128 + signal */
    double seconds;
    double cpu_seconds; /* user + system, wait4's rusage */
    long maxrss_kib;
    double queue_wait_seconds; /* -1: not known */
    size_t text_len;           /* stdout (or the error message) follows */
};

static pid_t launcher_pid = -1;
static int to_launcher = -1, from_launcher = -1;

static int write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

static int read_all(int fd, void *buf, size_t n)
{
    char *p = buf;
    while (n > 0) {
        ssize_t r = read(fd, p, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        p += r;
        n -= (size_t)r;
    }
    return 0;
}

/* The time `pid` (exited, not yet reaped) waited on a run queue for a CPU:
 * the second field of /proc/PID/schedstat, in ns; -1 when there is none. */
static double queue_wait_of(pid_t pid)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/schedstat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return -1.0;
    char line[128];
    int got = fgets(line, sizeof line, f) != NULL;
    fclose(f);
    if (!got)
        return -1.0;
    char *after_on_cpu, *end;
    strtoull(line, &after_on_cpu, 10); /* the time on a CPU, first */
    errno = 0;
    unsigned long long waited_ns = strtoull(after_on_cpu, &end, 10);
    return end != after_on_cpu && errno == 0 ? 1e-9 * (double)waited_ns : -1.0;
}

/* In the launcher: run one argument list, reply. */
static void launch_one(char *request, size_t len, int reply_fd)
{
    char *argv[MAX_ARGS + 1];
    int argc = 0;
    for (size_t at = 0; at < len && argc < MAX_ARGS; at += strlen(request + at) + 1)
        argv[argc++] = request + at;
    argv[argc] = NULL;
    struct launch_reply rep = {0};
    static char text[BENCH_CHILD_OUTPUT];
    size_t used = 0;
    int out[2];
    if (argc == 0 || pipe(out) != 0) {
        used = (size_t)snprintf(text, sizeof text, "launcher: cannot start: %s", strerror(errno));
        goto reply;
    }
    double t0 = uwb_monotonic_s();
    pid_t pid = fork();
    if (pid < 0) {
        used = (size_t)snprintf(text, sizeof text, "launcher: fork: %s", strerror(errno));
        close(out[0]);
        close(out[1]);
        goto reply;
    }
    if (pid == 0) {
        dup2(out[1], STDOUT_FILENO);
        close(out[0]);
        close(out[1]);
        execvp(argv[0], argv);
        fprintf(stderr, "uwbbench: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    close(out[1]);
    /* Keep what fits, drain the rest so the child never blocks on its stdout. */
    char sink[4096];
    for (;;) {
        char *dst = used + 1 < sizeof text ? text + used : sink;
        size_t room = used + 1 < sizeof text ? sizeof text - 1 - used : sizeof sink;
        ssize_t got = read(out[0], dst, room);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            break;
        if (dst != sink)
            used += (size_t)got;
    }
    close(out[0]);
    /* Exited but not reaped, so that its schedstat can still be read. */
    siginfo_t exited;
    while (waitid(P_PID, (id_t)pid, &exited, WEXITED | WNOWAIT) < 0 && errno == EINTR)
        ;
    double seconds = uwb_monotonic_s() - t0;
    rep.queue_wait_seconds = queue_wait_of(pid);
    int wstatus;
    struct rusage ru;
    pid_t waited;
    while ((waited = wait4(pid, &wstatus, 0, &ru)) < 0 && errno == EINTR)
        ;
    if (waited != pid) {
        used = (size_t)snprintf(text, sizeof text, "launcher: wait4: %s", strerror(errno));
        goto reply;
    }
    rep.ok = 1;
    rep.seconds = seconds;
    rep.maxrss_kib = ru.ru_maxrss; /* Linux: kibibytes */
    rep.cpu_seconds = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
                      (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
    rep.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 128 + WTERMSIG(wstatus);
reply:
    if (used >= sizeof text)
        used = sizeof text - 1;
    rep.text_len = used;
    if (write_all(reply_fd, &rep, sizeof rep) != 0 || write_all(reply_fd, text, used) != 0)
        _exit(1);
}

static void launcher_loop(int request_fd, int reply_fd)
{
    static char request[MAX_REQUEST];
    size_t len;
    while (read_all(request_fd, &len, sizeof len) == 0) {
        if (len == 0 || len > sizeof request || read_all(request_fd, request, len) != 0)
            break;
        request[len - 1] = '\0';
        launch_one(request, len, reply_fd);
    }
    _exit(0);
}

int bench_launcher_start(char *err, size_t errlen)
{
    int down[2], up[2];
    if (pipe(down) != 0 || pipe(up) != 0) {
        snprintf(err, errlen, "bench: pipe: %s", strerror(errno));
        return -1;
    }
    fflush(NULL); /* the launcher must not repeat buffered output */
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(err, errlen, "bench: fork: %s", strerror(errno));
        return -1;
    }
    if (pid == 0) {
        close(down[1]);
        close(up[0]);
        launcher_loop(down[0], up[1]);
    }
    close(down[0]);
    close(up[1]);
    launcher_pid = pid;
    to_launcher = down[1];
    from_launcher = up[0];
    signal(SIGPIPE, SIG_IGN);
    return 0;
}

int bench_launcher_run(char *const args[], struct bench_child *out, char *err, size_t errlen)
{
    if (launcher_pid < 0) {
        snprintf(err, errlen, "bench: launcher not started");
        return -1;
    }
    char request[MAX_REQUEST];
    size_t len = 0;
    for (int i = 0; args[i]; i++) {
        size_t n = strlen(args[i]) + 1;
        if (i >= MAX_ARGS || len + n > sizeof request) {
            snprintf(err, errlen, "bench: command line too long for the launcher");
            return -1;
        }
        memcpy(request + len, args[i], n);
        len += n;
    }
    struct launch_reply rep;
    if (write_all(to_launcher, &len, sizeof len) != 0 || write_all(to_launcher, request, len) != 0 ||
        read_all(from_launcher, &rep, sizeof rep) != 0 || rep.text_len >= sizeof out->output ||
        read_all(from_launcher, out->output, rep.text_len) != 0) {
        snprintf(err, errlen, "bench: the launcher process stopped answering");
        return -1;
    }
    out->output[rep.text_len] = '\0';
    if (!rep.ok) {
        snprintf(err, errlen, "%s", out->output);
        return -1;
    }
    out->seconds = rep.seconds;
    out->maxrss_kib = rep.maxrss_kib;
    out->cpu_seconds = rep.cpu_seconds;
    out->queue_wait_seconds = rep.queue_wait_seconds;
    out->status = rep.status;
    return 0;
}

void bench_launcher_stop(void)
{
    if (launcher_pid < 0)
        return;
    close(to_launcher);
    close(from_launcher);
    waitpid(launcher_pid, NULL, 0);
    launcher_pid = -1;
}
