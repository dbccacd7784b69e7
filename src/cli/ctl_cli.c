/* uwbd ctl: send one command to the running daemon over its control socket
 * and print the reply line, for an engineer logged in over SSH. */
#include <errno.h>
#include <getopt.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "uwb/cli.h"
#include "uwb/daemon/command.h"
#include "uwb/daemon/config.h"
#include "uwb/daemon/control_socket.h"
#include "uwb/daemon/exit_codes.h"
#include "uwb/monotonic.h"

/* A scan takes as long as the carriage needs; everything else is instant. */
#define SCAN_TIMEOUT_S 900
#define OTHER_TIMEOUT_S 10
/* HISTORY 100 is the longest reply; leave room. */
#define MAX_REPLY (4 * 1024 * 1024)

void uwbd_ctl_usage(FILE *f)
{
    fprintf(f,
        "usage: uwbd ctl [--socket PATH | --config FILE] [--timeout S] [--text] COMMAND...\n"
        "\n"
        "Sends COMMAND to the running daemon and prints its reply (one JSON line).\n"
        "Commands: status, scan, verdict, history [N], baseline set [N], help.\n"
        "\n"
        "  --socket PATH    the control socket (default " UWBD_DEFAULT_CONTROL_SOCKET ")\n"
        "  --config FILE    take the socket's path from this configuration\n"
        "  --timeout S      wait at most S seconds for the reply (default %d for scan, %d otherwise)\n"
        "  --text           print a verdict as lines for people (status, displacement or\n"
        "                   edges or reason, images) instead of its JSON line\n"
        "\n"
        "Exit status: 0 a reply; 1 the daemon refused the command (ERROR reply); 64 bad usage;\n"
        "69 no daemon on the socket; 75 no reply in time.\n",
        SCAN_TIMEOUT_S, OTHER_TIMEOUT_S);
}

static int is_error_reply(const char *line)
{
    cJSON *o = cJSON_Parse(line);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    int error = !cJSON_IsString(cls) || strcmp(cls->valuestring, "ERROR") == 0;
    cJSON_Delete(o);
    return error;
}

/* Read up to the first newline; 0, or an exit status. */
static int read_reply(int fd, double timeout_s, char **out)
{
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    if (!buf)
        return UWBD_CTL_NO_DAEMON;
    double deadline = uwb_monotonic_s() + timeout_s;
    for (;;) {
        double left = deadline - uwb_monotonic_s();
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        int ready = left > 0 ? poll(&pfd, 1, (int)(left * 1000) + 1) : 0;
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready <= 0) {
            free(buf);
            fprintf(stderr, "uwbd ctl: no reply within %.0f s\n", timeout_s);
            return UWBD_CTL_TIMEOUT;
        }
        if (len + 1 >= cap) {
            if (cap >= MAX_REPLY) {
                free(buf);
                fprintf(stderr, "uwbd ctl: reply longer than %d bytes\n", MAX_REPLY);
                return UWBD_CTL_NO_DAEMON;
            }
            cap *= 2;
            char *grown = realloc(buf, cap);
            if (!grown) {
                free(buf);
                return UWBD_CTL_NO_DAEMON;
            }
            buf = grown;
        }
        ssize_t r = recv(fd, buf + len, cap - 1 - len, 0);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            free(buf);
            fprintf(stderr, "uwbd ctl: the daemon closed the connection without a reply\n");
            return UWBD_CTL_NO_DAEMON;
        }
        char *nl = memchr(buf + len, '\n', (size_t)r);
        len += (size_t)r;
        if (nl) {
            *nl = '\0';
            *out = buf;
            return 0;
        }
    }
}

int uwbd_ctl_main(int argc, char **argv)
{
    static const struct option longopts[] = {
        {"socket", required_argument, 0, 's'},
        {"config", required_argument, 0, 'c'},
        {"timeout", required_argument, 0, 't'},
        {"text", no_argument, 0, 'T'},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0},
    };
    const char *socket_path = NULL, *config_path = NULL;
    double timeout_s = 0;
    int as_text = 0;
    int c;
    /* "+": stop at the first command word, so "history 5" is not an option. */
    opterr = 0;   /* one line of our own instead of getopt's and the usage */
    while ((c = getopt_long(argc, argv, "+h", longopts, NULL)) != -1) {
        switch (c) {
        case 's': socket_path = optarg; break;
        case 'c': config_path = optarg; break;
        case 't': {
            char *end;
            timeout_s = strtod(optarg, &end);
            if (*end || !(timeout_s > 0)) {
                fprintf(stderr, "uwbd ctl: --timeout: '%s' is not a positive number of seconds\n", optarg);
                return UWBD_CTL_USAGE;
            }
            break;
        }
        case 'T': as_text = 1; break;
        case 'h': uwbd_ctl_usage(stdout); return UWBD_CTL_OK;
        default: uwb_cli_option_error("uwbd ctl", "uwbd ctl --help", argv, argc, longopts); return UWBD_CTL_USAGE;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "uwbd ctl: no command (try: uwbd ctl help)\n");
        return UWBD_CTL_USAGE;
    }
    if (socket_path && config_path) {
        fprintf(stderr, "uwbd ctl: give either --socket or --config\n");
        return UWBD_CTL_USAGE;
    }
    char line[UWB_COMMAND_MAX_LINE + 2];
    size_t len = 0;
    for (int i = optind; i < argc; i++) {
        size_t n = strlen(argv[i]);
        if (len + n + 1 > UWB_COMMAND_MAX_LINE) {
            fprintf(stderr, "uwbd ctl: command longer than %d bytes\n", UWB_COMMAND_MAX_LINE);
            return UWBD_CTL_USAGE;
        }
        if (len)
            line[len++] = ' ';
        memcpy(line + len, argv[i], n);
        len += n;
    }
    line[len] = '\0';
    struct uwb_command cmd;
    char err[1024];
    if (uwb_command_parse(line, len, &cmd, err, sizeof err) != UWB_COMMAND_OK) {
        fprintf(stderr, "uwbd ctl: %s\n", err[0] ? err : "empty command");
        return UWBD_CTL_USAGE;
    }
    static struct uwbd_config cfg;
    if (config_path) {
        if (uwbd_config_load(config_path, NULL, 0, &cfg, err, sizeof err) != 0) {
            fprintf(stderr, "uwbd ctl: %s\n", err);
            return UWBD_CTL_USAGE;
        }
        socket_path = cfg.control_socket;
    }
    if (!socket_path)
        socket_path = UWBD_DEFAULT_CONTROL_SOCKET;
    if (timeout_s <= 0)
        timeout_s = cmd.kind == UWB_COMMAND_SCAN ? SCAN_TIMEOUT_S : OTHER_TIMEOUT_S;

    int fd = uwbd_control_connect(socket_path, err, sizeof err);
    if (fd < 0) {
        fprintf(stderr, "uwbd ctl: %s (is uwbd running?)\n", err);
        return UWBD_CTL_NO_DAEMON;
    }
    line[len++] = '\n';
    if (send(fd, line, len, MSG_NOSIGNAL) != (ssize_t)len) {
        fprintf(stderr, "uwbd ctl: %s: cannot send: %s\n", socket_path, strerror(errno));
        close(fd);
        return UWBD_CTL_NO_DAEMON;
    }
    char *reply = NULL;
    int rc = read_reply(fd, timeout_s, &reply);
    close(fd);
    if (rc != 0)
        return rc;
    if (!as_text || uwbd_verdict_text(reply, stdout) != 0)
        puts(reply);
    rc = is_error_reply(reply) ? UWBD_CTL_REFUSED : UWBD_CTL_OK;
    free(reply);
    return rc;
}
