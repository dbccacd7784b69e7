/* uwbd ctl: send one command to the running daemon over its control socket
 * and print the reply line, for an engineer logged in over SSH. */
#include <errno.h>
#include <getopt.h>
#include <locale.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "uwb/reply_text.h"
#include "uwb/cli.h"
#include "control/command.h"
#include "config/config_load.h"
#include "control/control_socket.h"
#include "control/exit_codes.h"
#include "uwb/monotonic.h"

/* A scan takes as long as the carriage needs; everything else is instant. */
#define SCAN_TIMEOUT_S 900
#define OTHER_TIMEOUT_S 10
/* HISTORY 100 is the longest reply; leave room. */
#define MAX_REPLY ((size_t)4 * 1024 * 1024)

void uwbd_ctl_usage(FILE *f)
{
    fprintf(
        f,
        "usage: uwbd ctl [--socket PATH | --config FILE] [--timeout S] [--json | --text | --csv] COMMAND...\n"
        "\n"
        "Sends COMMAND to the running daemon and prints its reply: as text for people when standard\n"
        "output is a terminal, else as the daemon's JSON line (a pipe, a file, a script). Options may\n"
        "come before or after COMMAND (`uwbd ctl status --text`); after `--` every word is COMMAND's.\n"
        "\n"
        "Commands (read case-insensitively; a mistyped one is answered with the one meant):\n");
    /* The daemon's own table, so that this list is what the daemon takes. */
    for (size_t i = 0; i < uwb_command_help_count; i++)
        fprintf(f, "  %-19s  %s\n", uwb_command_help[i].usage, uwb_command_help[i].brief);
    fprintf(f,
            "\n"
            "`contacts test [S]` energises each alarm contact (watch, alarm, fault) alone in turn for S s\n"
            "(default 10) for a point-to-point check with the RTU, then returns them to what the verdicts\n"
            "call for; it is refused while a scan runs, and ends on time even when uwbd ctl has gone.\n"
            "Only root, uwbd's own user and contacts.test_group may, once per contacts.test_min_interval_s;\n"
            "while a watch or alarm stands, say `contacts test force` (the RTU sees it clear; logged).\n"
            "`scan` draws a progress bar on stderr when it is a terminal (PROGRESS lines\n"
            "otherwise); `watch` prints every PROGRESS and VERDICT line until the daemon\n"
            "closes the connection or --timeout S passes (then exit 0).\n"
            "\n"
            "  --socket PATH    the control socket (default " UWBD_DEFAULT_CONTROL_SOCKET ")\n"
            "  --config FILE    take the socket's path from this configuration\n"
            "  --timeout S      wait at most S seconds for the daemon to accept the connection, and as\n"
            "                   long for the reply (default %d for scan, %d otherwise; %d to connect)\n"
            "  --json           print the reply's JSON line as the daemon sent it (the default when\n"
            "                   standard output is not a terminal; for programs)\n"
            "  --text           print the reply for people (the default on a terminal): status as a\n"
            "                   page of \"Name : value\" lines (MQTT, Modbus, contacts, baseline\n"
            "                   age, free space), history and trend as tables, help as a list,\n"
            "                   a verdict as lines (its time and scan, status, displacement or\n"
            "                   edges or reason, images), ack and contacts test in words, an\n"
            "                   error as \"error: MESSAGE\"; watch as a line each; +/- and sigma\n"
            "                   in ASCII unless the locale's codeset is UTF-8\n"
            "  --csv            with history only: print the verdicts as CSV for a spreadsheet\n"
            "                   (a header naming each column and its unit, then a row per\n"
            "                   verdict, oldest first; a figure not given is an empty cell)\n"
            "\n"
            "Exit status: 0 a reply; 1 the daemon refused the command (ERROR reply); 64 bad usage;\n"
            "69 no daemon on the socket; 75 not accepted or no reply in time; 77 you may not open\n"
            "the socket (the message names its group).\n",
            SCAN_TIMEOUT_S, OTHER_TIMEOUT_S, OTHER_TIMEOUT_S);
}

static int is_error_reply(const char *line)
{
    cJSON *o = cJSON_Parse(line);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    int error = !cJSON_IsString(cls) || strcmp(cls->valuestring, "ERROR") == 0;
    cJSON_Delete(o);
    return error;
}

/* Reply lines from the daemon; bytes after a line are kept for the next. */
struct reply_reader {
    int fd;
    char *buf;
    size_t len, cap;
};

/* The next line (without its newline) in *out, valid until the next call;
 * 0, or an exit status. timeout_s <= 0: wait as long as it takes. */
static int read_line(struct reply_reader *r, double timeout_s, char **out)
{
    static char *line;
    free(line);
    line = NULL;
    double deadline = uwb_monotonic_s() + timeout_s;
    for (;;) {
        char *nl = r->len ? memchr(r->buf, '\n', r->len) : NULL;
        if (nl) {
            size_t n = (size_t)(nl - r->buf);
            line = malloc(n + 1);
            if (!line)
                return UWBD_CTL_NO_DAEMON;
            memcpy(line, r->buf, n);
            line[n] = '\0';
            memmove(r->buf, nl + 1, r->len - n - 1);
            r->len -= n + 1;
            *out = line;
            return 0;
        }
        double left = deadline - uwb_monotonic_s();
        struct pollfd pfd = {.fd = r->fd, .events = POLLIN};
        int ready = timeout_s <= 0 ? poll(&pfd, 1, -1) : left > 0 ? poll(&pfd, 1, (int)(left * 1000) + 1) : 0;
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready <= 0) {
            fprintf(stderr, "uwbd ctl: no reply within %.0f s\n", timeout_s);
            return UWBD_CTL_TIMEOUT;
        }
        if (r->len + 1 >= r->cap) {
            if (r->cap >= MAX_REPLY) {
                fprintf(stderr, "uwbd ctl: reply longer than %zu bytes\n", MAX_REPLY);
                return UWBD_CTL_NO_DAEMON;
            }
            size_t cap = r->cap ? r->cap * 2 : 4096;
            char *grown = realloc(r->buf, cap);
            if (!grown)
                return UWBD_CTL_NO_DAEMON;
            r->buf = grown;
            r->cap = cap;
        }
        ssize_t got = recv(r->fd, r->buf + r->len, r->cap - 1 - r->len, 0);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0) {
            fprintf(stderr, "uwbd ctl: the daemon closed the connection%s\n",
                    r->len ? " in the middle of a line" : "");
            return UWBD_CTL_NO_DAEMON;
        }
        r->len += (size_t)got;
    }
}

static int has_class(const char *line, const char *class_name)
{
    cJSON *o = cJSON_Parse(line);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    int yes = cJSON_IsString(cls) && strcmp(cls->valuestring, class_name) == 0;
    cJSON_Delete(o);
    return yes;
}

/* A PROGRESS line on stderr: a bar redrawn in place on a terminal, the
 * line as it is otherwise (logs, pipes). */
static void show_progress(const char *line, int on_terminal)
{
    if (!on_terminal) {
        fprintf(stderr, "%s\n", line);
        return;
    }
    struct uwbd_progress p;
    if (uwbd_progress_read(line, &p) != 0 || !(p.positions > 0))
        return;
    enum { WIDTH = 30 };
    char bar[WIDTH + 1];
    /* One bar over every pass of the cycle (a daemon without "fraction": this pass). */
    double whole = p.has_fraction ? p.fraction : p.position / p.positions;
    /* Within 0..1 whatever the line says (NaN too), so the cast cannot overflow;
     * 1e-3 makes 0.3333 of 30 the 10 it means. */
    whole = whole > 0 ? whole < 1 ? whole : 1 : 0;
    int filled = (int)(whole * WIDTH + 1e-3);
    for (int i = 0; i < WIDTH; i++)
        bar[i] = i < filled ? '#' : '-';
    bar[WIDTH] = '\0';
    fprintf(stderr, "\r[%s] ", bar);
    if (p.passes > 1)
        fprintf(stderr, "pass %.0f of %.0f, ", p.pass, p.passes);
    fprintf(stderr, "%.0f/%.0f positions  %.0f s", p.position, p.positions,
            p.has_elapsed ? p.elapsed_s : 0.0);
    if (p.has_left)
        fprintf(stderr, ", about %.0f s left", p.left_s);
    fputs("\033[K", stderr);
    fflush(stderr);
}

/* Long options only (but -h): values past any character, so that `-t`
 * is an unknown option rather than --timeout missing its value. */
enum { OPT_SOCKET = 256, OPT_CONFIG, OPT_TIMEOUT, OPT_TEXT, OPT_JSON, OPT_CSV };
static const struct option ctl_options[] = {
    {"socket", required_argument, 0, OPT_SOCKET},
    {"config", required_argument, 0, OPT_CONFIG},
    {"timeout", required_argument, 0, OPT_TIMEOUT},
    {"text", no_argument, 0, OPT_TEXT},
    {"json", no_argument, 0, OPT_JSON},
    {"csv", no_argument, 0, OPT_CSV},
    {"help", no_argument, 0, 'h'},
    {0, 0, 0, 0},
};

/* Returned by the steps below when uwbd ctl goes on (exit statuses are >= 0). */
#define CTL_GOES_ON (-1)

/* What the command line asks for. */
struct ctl_args {
    const char *socket_path, *config_path;
    double timeout_s; /* 0: not given */
    int as_text, as_csv, as_json;
    enum uwbd_charset charset;           /* the locale's: "±" or "+/-" */
    char line[UWB_COMMAND_MAX_LINE + 2]; /* the command words joined, room for its newline */
    size_t len;
    struct uwb_command cmd;
};

/* The options: CTL_GOES_ON, or the exit status (--help, an error). */
static int read_ctl_options(int argc, char **argv, struct ctl_args *a)
{
    int c;
    /* Options anywhere before `--`: getopt moves the command words after
     * them in argv, in their order (`history 5` stays a command). */
    opterr = 0; /* one line of our own instead of getopt's and the usage */
    while ((c = getopt_long(argc, argv, "h", ctl_options, NULL)) != -1) {
        char *end;
        switch (c) {
        case OPT_SOCKET: a->socket_path = optarg; break;
        case OPT_CONFIG: a->config_path = optarg; break;
        case OPT_TIMEOUT:
            a->timeout_s = strtod(optarg, &end);
            if (*end || !(a->timeout_s > 0)) {
                fprintf(stderr, "uwbd ctl: --timeout: '%s' is not a positive number of seconds\n", optarg);
                return UWBD_CTL_USAGE;
            }
            break;
        case OPT_TEXT: a->as_text = 1; break;
        case OPT_JSON: a->as_json = 1; break;
        case OPT_CSV: a->as_csv = 1; break;
        case 'h': uwbd_ctl_usage(stdout); return UWBD_CTL_OK;
        default:
            uwb_cli_option_error("uwbd ctl", "uwbd ctl --help", argv, argc, ctl_options);
            return UWBD_CTL_USAGE;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "uwbd ctl: no command (try: uwbd ctl help)\n");
        return UWBD_CTL_USAGE;
    }
    if (a->socket_path && a->config_path) {
        fprintf(stderr, "uwbd ctl: give either --socket or --config\n");
        return UWBD_CTL_USAGE;
    }
    if (a->as_json + a->as_text + a->as_csv > 1) {
        fprintf(stderr, "uwbd ctl: give one of --json, --text or --csv\n");
        return UWBD_CTL_USAGE;
    }
    /* People at a terminal read text; a pipe or a file gets the JSON line
     * scripts have always parsed. */
    if (!a->as_json && !a->as_csv && isatty(STDOUT_FILENO))
        a->as_text = 1;
    return CTL_GOES_ON;
}

/* The command words after the options, joined and parsed as the daemon
 * will: CTL_GOES_ON, or UWBD_CTL_USAGE. */
static int read_command(int argc, char **argv, struct ctl_args *a)
{
    a->len = 0;
    for (int i = optind; i < argc; i++) {
        size_t n = strlen(argv[i]);
        if (a->len + n + 1 > UWB_COMMAND_MAX_LINE) {
            fprintf(stderr, "uwbd ctl: command longer than %d bytes\n", UWB_COMMAND_MAX_LINE);
            return UWBD_CTL_USAGE;
        }
        if (a->len)
            a->line[a->len++] = ' ';
        memcpy(a->line + a->len, argv[i], n);
        a->len += n;
    }
    a->line[a->len] = '\0';
    char err[1024];
    if (uwb_command_parse(a->line, a->len, &a->cmd, err, sizeof err) != UWB_COMMAND_OK) {
        fprintf(stderr, "uwbd ctl: %s\n", err[0] ? err : "empty command");
        return UWBD_CTL_USAGE;
    }
    if (a->as_csv && a->cmd.kind != UWB_COMMAND_HISTORY) {
        fprintf(stderr, "uwbd ctl: --csv is for `history [N]` only, not `%s`\n", a->line);
        return UWBD_CTL_USAGE;
    }
    return CTL_GOES_ON;
}

/* The socket to use: --socket, the one --config names, or the default. */
static int choose_socket(struct ctl_args *a)
{
    static struct uwbd_config cfg;
    if (a->config_path) {
        char err[1024];
        if (uwbd_config_load(a->config_path, NULL, 0, &cfg, err, sizeof err) != 0) {
            fprintf(stderr, "uwbd ctl: %s\n", err);
            return UWBD_CTL_USAGE;
        }
        a->socket_path = cfg.control_socket;
    }
    if (!a->socket_path)
        a->socket_path = UWBD_DEFAULT_CONTROL_SOCKET;
    return CTL_GOES_ON;
}

/* The command (after `watch progress` for a scan's bar): CTL_GOES_ON, or
 * the exit status, the daemon's refusal printed as its reply. */
static int send_command(int fd, struct ctl_args *a)
{
    static const char progress_first[] = "watch progress\n";
    char refusal[1024];
    a->line[a->len++] = '\n';
    if ((a->cmd.kind != UWB_COMMAND_SCAN ||
         uwbd_control_send(fd, progress_first, sizeof progress_first - 1, refusal, sizeof refusal) == 0) &&
        uwbd_control_send(fd, a->line, a->len, refusal, sizeof refusal) == 0)
        return CTL_GOES_ON;
    int e = errno;
    if (refusal[0]) {
        /* The daemon turned the connection away and said why (e.g. too
         * many clients): that is its reply, as if it had come after. */
        if (!a->as_text || uwbd_reply_text_in(refusal, stdout, a->charset) != 0)
            puts(refusal);
        return is_error_reply(refusal) ? UWBD_CTL_REFUSED : UWBD_CTL_OK;
    }
    fprintf(stderr, "uwbd ctl: %s: cannot send: %s\n", a->socket_path, strerror(e));
    return UWBD_CTL_NO_DAEMON;
}

/* `watch`: every line as it comes, until the daemon goes or --timeout
 * (explicit_s > 0) passes. */
static int follow(struct reply_reader *reader, double explicit_s, const struct ctl_args *a)
{
    double until = explicit_s > 0 ? uwb_monotonic_s() + explicit_s : 0;
    char *reply = NULL;
    for (int first = 1;; first = 0) {
        double left = explicit_s > 0 ? until - uwb_monotonic_s() : 0;
        if (explicit_s > 0 && left <= 0)
            return UWBD_CTL_OK;
        int rc = read_line(reader, explicit_s > 0 ? left : (first ? OTHER_TIMEOUT_S : 0), &reply);
        if (rc == UWBD_CTL_TIMEOUT && explicit_s > 0 && !first)
            return UWBD_CTL_OK; /* --timeout ended it; reply is no longer a line */
        if (rc != 0)
            return rc;
        if (!a->as_text || uwbd_reply_text_in(reply, stdout, a->charset) != 0)
            puts(reply);
        fflush(stdout);
        if (first && is_error_reply(reply))
            return UWBD_CTL_REFUSED;
    }
}

/* The one reply line in *reply, a scan's PROGRESS lines drawn on stderr
 * on the way (after the answer to its `watch progress`). */
static int await_reply(struct reply_reader *reader, double timeout_s, int scan_progress, char **reply)
{
    int on_terminal = isatty(STDERR_FILENO), bar_drawn = 0, acked = !scan_progress, rc;
    for (;;) {
        rc = read_line(reader, timeout_s, reply);
        if (rc != 0)
            break;
        if (!acked) {
            acked = 1; /* the WATCH answer (an ERROR from a daemon without `watch`) */
            continue;
        }
        if (!scan_progress || !has_class(*reply, "PROGRESS"))
            break;
        show_progress(*reply, on_terminal);
        bar_drawn = on_terminal;
    }
    if (bar_drawn)
        fputs("\n", stderr);
    return rc;
}

/* A HISTORY reply as CSV: the exit status (an unreadable reply is the
 * daemon's fault, as a reply without a line would be). */
static int print_csv(const char *reply)
{
    char err[512];
    if (uwbd_history_csv(reply, stdout, err, sizeof err) == 0)
        return UWBD_CTL_OK;
    fprintf(stderr, "uwbd ctl: --csv: %s\n", err);
    return UWBD_CTL_NO_DAEMON;
}

/* Connect, send, and read the reply (or follow): the exit status. */
static int talk(struct ctl_args *a)
{
    int explicit_timeout = a->timeout_s > 0;
    double timeout_s = explicit_timeout                  ? a->timeout_s
                       : a->cmd.kind == UWB_COMMAND_SCAN ? SCAN_TIMEOUT_S
                                                         : OTHER_TIMEOUT_S;
    char err[1024];
    /* Connecting waits for a daemon whose backlog is full: --timeout bounds
     * that too (without one, the shorter default). */
    int fd =
        uwbd_control_connect(a->socket_path, explicit_timeout ? timeout_s : OTHER_TIMEOUT_S, err, sizeof err);
    if (fd == UWBD_CONTROL_CONNECT_TIMEOUT) {
        fprintf(stderr, "uwbd ctl: %s\n", err);
        return UWBD_CTL_TIMEOUT;
    }
    if (fd == UWBD_CONTROL_CONNECT_DENIED) {
        fprintf(stderr, "uwbd ctl: %s\n", err);
        return UWBD_CTL_NO_PERM;
    }
    if (fd < 0) {
        fprintf(stderr, "uwbd ctl: %s (is uwbd running?)\n", err);
        return UWBD_CTL_NO_DAEMON;
    }
    struct reply_reader reader = {.fd = fd};
    char *reply = NULL;
    int rc = send_command(fd, a);
    if (rc != CTL_GOES_ON)
        goto done;
    if (a->cmd.kind == UWB_COMMAND_WATCH && a->cmd.watch != 0) {
        rc = follow(&reader, explicit_timeout ? timeout_s : 0, a);
        goto done;
    }
    rc = await_reply(&reader, timeout_s, a->cmd.kind == UWB_COMMAND_SCAN, &reply);
    if (rc != 0)
        goto done;
    rc = is_error_reply(reply) ? UWBD_CTL_REFUSED : UWBD_CTL_OK;
    if (a->as_csv && rc == UWBD_CTL_OK)
        rc = print_csv(reply);
    else if (!a->as_text || uwbd_reply_text_in(reply, stdout, a->charset) != 0)
        puts(reply);
done:
    close(fd);
    free(reader.buf);
    return rc;
}

int uwbd_ctl_main(int argc, char **argv)
{
    struct ctl_args a = {0};
    /* The terminal's codeset decides "±" or "+/-" (issue 48: LC_ALL=C and
     * serial consoles are not UTF-8). LC_CTYPE only: the figures keep
     * their decimal point whatever LC_NUMERIC says. */
    setlocale(LC_CTYPE, "");
    a.charset = uwbd_charset_of_locale();
    int rc = read_ctl_options(argc, argv, &a);
    if (rc == CTL_GOES_ON)
        rc = read_command(argc, argv, &a);
    if (rc == CTL_GOES_ON)
        rc = choose_socket(&a);
    return rc == CTL_GOES_ON ? talk(&a) : rc;
}
