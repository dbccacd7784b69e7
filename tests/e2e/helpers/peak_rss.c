/* peak_rss OUT_FILE SECONDS COMMAND [ARG...]: runs COMMAND (stdin, stdout
 * and stderr its own), kills it after SECONDS, and writes its peak
 * resident set (the kernel's ru_maxrss, KiB) to OUT_FILE, one number.
 * Exit: COMMAND's status, 128 + signal if killed, 124 after the deadline,
 * 2 on a usage error. For the e2e checks of a bounded replay's memory. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

int main(int argc, char **argv)
{
    char *end;
    double seconds = argc >= 4 ? strtod(argv[2], &end) : 0;
    if (argc < 4 || *end || !(seconds > 0)) {
        fprintf(stderr, "usage: peak_rss OUT_FILE SECONDS COMMAND [ARG...]\n");
        return 2;
    }
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "peak_rss: fork: %s\n", strerror(errno));
        return 2;
    }
    if (pid == 0) {
        execvp(argv[3], argv + 3);
        fprintf(stderr, "peak_rss: %s: %s\n", argv[3], strerror(errno));
        _exit(127);
    }
    int status = 0, timed_out = 0;
    struct rusage ru;
    /* Polled every 10 ms: the deadline holds without signals or threads. */
    for (long waited_ms = 0;; waited_ms += 10) {
        pid_t got = wait4(pid, &status, WNOHANG, &ru);
        if (got == pid)
            break;
        if (got < 0 && errno != EINTR) {
            fprintf(stderr, "peak_rss: wait: %s\n", strerror(errno));
            return 2;
        }
        if (!timed_out && waited_ms >= (long)(seconds * 1000)) {
            kill(pid, SIGKILL);
            timed_out = 1;
        }
        nanosleep(&(struct timespec){.tv_nsec = 10000000L}, NULL);
    }
    FILE *out = fopen(argv[1], "w");
    if (!out || fprintf(out, "%ld\n", ru.ru_maxrss) < 0 || fclose(out) != 0) {
        fprintf(stderr, "peak_rss: %s: %s\n", argv[1], strerror(errno));
        return 2;
    }
    if (timed_out)
        return 124;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
