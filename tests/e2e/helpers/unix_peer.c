/* unix_peer: the other end of uwbd's unix sockets for the e2e scripts, a
 * client that sends what `uwbd ctl` never would and a console peer, in C
 * instead of a Python interpreter, which a fresh Debian minbase does not have.
 *
 *   unix_peer ask SOCKET N < BYTES
 *       Connects, sends stdin as it is, prints the first N reply lines.
 *   unix_peer console SOCKET GO_FILE OUT_FILE LINE...
 *       Listens on SOCKET for the daemon's console to connect; once GO_FILE
 *       exists, sends each LINE and writes each reply line to OUT_FILE.
 *   unix_peer session SOCKET GO_FILE OUT_FILE LINE...
 *       Like console, for uwbd's console of text replies: waits for its
 *       prompt, and writes each reply's lines (between the echo and the
 *       next prompt, CRs dropped) to OUT_FILE.
 *   unix_peer terminal SOCKET GO_FILE OUT_FILE KEYS...
 *       Like console, but types each KEYS (C escapes: \r \n \b \e \xHH) a
 *       byte at a time as minicom or picocom would, waits for the prompt(s)
 *       it earns, and writes every byte the console sent to OUT_FILE. A KEYS
 *       of "@until:TEXT" types nothing: it waits for TEXT from the console.
 *   unix_peer screen FILE
 *       Prints what a terminal shows after FILE's bytes (a terminal
 *       transcript): one line per screen row.
 *   unix_peer slots SOCKET N
 *       Fills the daemon's N control-client slots with silent clients and
 *       checks: one more is told "too many control clients"; after 2.5 s
 *       of silence a new client is served, the longest-idle client was the
 *       one dropped, and the next one is still served.
 *       As root, then: N-1 clients of uid 65534 (in the socket's group)
 *       send `status` every 0.5 s and read the replies; after 2.5 s one more
 *       of them is refused with the slot kept for root named, and a root
 *       client is still answered. The socket's directories must let that
 *       uid through. Not root: that part is skipped, saying so.
 *   unix_peer invert SOCKET [CONNECT_TIMEOUT_S]
 *       The host end of a guest UART for make test-board's serial test
 *       (tests/board/test_serial_link.c): connects to qemu's chardev socket
 *       (retrying up to CONNECT_TIMEOUT_S, default 30), answers every byte
 *       with its bitwise inverse until qemu closes the socket, and prints
 *       how many bytes it answered.
 * Every wait is bounded (60 s); exit 0 when all went as expected, 1 not. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <grp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "uwb/monotonic.h"
#include "uwb/read_file.h"

#define WAIT_S 60.0
/* A console line that comes when a scan ends (@until): 21 positions and
 * the verdict took 51 s natively on a slow day, and past 60 s under
 * qemu-user (the aarch64 stage stopped at position 19 of 21). Still under
 * run-tests.sh's 300 s limit for the script. */
#define SCAN_WAIT_S 180.0
/* The console peer is told to go only after the script has run its scans
 * and control-socket checks: over a minute under ASan on a loaded 2-core
 * machine. Still under run-tests.sh's 300 s limit for the script. */
#define GO_WAIT_S 240.0
#define MAX_REPLY (4 * 1024 * 1024)

static int fail(const char *what)
{
    fprintf(stderr, "unix_peer: %s\n", what);
    return 1;
}

static void sleep_s(double s)
{
    struct timespec t = {.tv_sec = (time_t)s, .tv_nsec = (long)((s - (double)(time_t)s) * 1e9)};
    while (nanosleep(&t, &t) != 0 && errno == EINTR) {
    }
}

static int unix_address(const char *path, struct sockaddr_un *a)
{
    memset(a, 0, sizeof *a);
    a->sun_family = AF_UNIX;
    if (strlen(path) >= sizeof a->sun_path)
        return -1;
    strcpy(a->sun_path, path);
    return 0;
}

static int connect_to(const char *path)
{
    struct sockaddr_un a;
    int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0 || unix_address(path, &a) != 0 || connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        fprintf(stderr, "unix_peer: %s: cannot connect: %s\n", path, strerror(errno));
        if (fd >= 0)
            close(fd);
        return -1;
    }
    return fd;
}

static int send_all(int fd, const char *bytes, size_t len)
{
    while (len > 0) {
        ssize_t n = send(fd, bytes, len, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        bytes += n;
        len -= (size_t)n;
    }
    return 0;
}

struct inbox {
    char *buf;
    size_t len, cap;
};

/* Waits until `deadline` for bytes from fd and appends them to the inbox
 * (grown as needed, up to MAX_REPLY): 0 when some came, -1 on timeout, a
 * closed or failed socket, or an inbox that would grow past MAX_REPLY. */
static int receive_more(int fd, struct inbox *in, double deadline)
{
    for (;;) {
        double left = deadline - uwb_monotonic_s();
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (left <= 0 || poll(&p, 1, (int)(left * 1000) + 1) <= 0)
            return -1;
        if (in->len + 65536 > in->cap) {
            if (in->cap >= (size_t)MAX_REPLY)
                return -1;
            char *grown = realloc(in->buf, in->cap + 65536 + 1);
            if (!grown)
                return -1;
            in->buf = grown;
            in->cap += 65536;
        }
        ssize_t n = recv(fd, in->buf + in->len, in->cap - in->len, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return -1;
        in->len += (size_t)n;
        in->buf[in->len] = '\0';
        return 0;
    }
}

/* Reads until the buffer holds `lines` newlines: 0; -1 closed, timed out or too long. */
static int read_lines(int fd, struct inbox *in, int lines)
{
    double deadline = uwb_monotonic_s() + WAIT_S;
    for (;;) {
        int have = 0;
        for (size_t i = 0; i < in->len; i++)
            have += in->buf[i] == '\n';
        if (have >= lines)
            return 0;
        if (receive_more(fd, in, deadline) != 0)
            return -1;
    }
}

/* Takes the first line out of the inbox as a string the caller frees. */
static char *take_line(struct inbox *in)
{
    char *nl = memchr(in->buf, '\n', in->len);
    size_t n = (size_t)(nl - in->buf);
    char *line = strndup(in->buf, n);
    memmove(in->buf, nl + 1, in->len - n - 1);
    in->len -= n + 1;
    in->buf[in->len] = '\0';
    return line;
}

static int ask(const char *path, const char *count)
{
    int lines = atoi(count);
    char *bytes, err[1024];
    size_t len;
    if (lines <= 0)
        return fail("ask: N must be a positive number of lines");
    if (uwb_read_fd(STDIN_FILENO, "stdin", MAX_REPLY, &bytes, &len, err, sizeof err) != UWB_READ_OK)
        return fail(err);
    int fd = connect_to(path);
    struct inbox in = {0};
    int ok = fd >= 0 && send_all(fd, bytes, len) == 0 && read_lines(fd, &in, lines) == 0;
    if (fd >= 0 && !ok)
        fprintf(stderr, "unix_peer: %s: fewer than %d reply lines within %.0f s\n", path, lines, WAIT_S);
    for (int i = 0; ok && i < lines; i++) {
        char *line = take_line(&in);
        puts(line);
        free(line);
    }
    free(bytes);
    free(in.buf);
    if (fd >= 0)
        close(fd);
    return ok ? 0 : 1;
}

/* Listens on path, takes the daemon's console connection and waits for
 * go_file; the connection's fd, or -1 (said why). *srv: the listener. */
static int accept_console(const char *path, const char *go_file, int *srv_out)
{
    struct sockaddr_un a;
    int srv = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (srv < 0 || unix_address(path, &a) != 0 || bind(srv, (struct sockaddr *)&a, sizeof a) != 0 ||
        listen(srv, 1) != 0) {
        fprintf(stderr, "unix_peer: %s: cannot listen: %s\n", path, strerror(errno));
        return -1;
    }
    struct pollfd p = {.fd = srv, .events = POLLIN};
    if (poll(&p, 1, (int)(WAIT_S * 1000)) <= 0) {
        fail("console: uwbd did not connect");
        return -1;
    }
    int conn = accept(srv, NULL, NULL);
    if (conn < 0) {
        fail("console: accept failed");
        return -1;
    }
    double deadline = uwb_monotonic_s() + GO_WAIT_S;
    while (access(go_file, F_OK) != 0) {
        if (uwb_monotonic_s() > deadline) {
            fail("console: the go file never appeared");
            return -1;
        }
        sleep_s(0.05);
    }
    *srv_out = srv;
    return conn;
}

/* The daemon's console prompt; a line that starts with it is the prompt and
 * the echo of what was typed, not a reply. */
#define CONSOLE_PROMPT "uwbd> "

/* Reads until the inbox ends with the console's prompt and holds a line
 * end before it (the echo of what was sent): 0, or -1. */
static int read_to_prompt(int fd, struct inbox *in)
{
    size_t plen = strlen(CONSOLE_PROMPT);
    double deadline = uwb_monotonic_s() + WAIT_S;
    for (;;) {
        if (in->len >= plen && memcmp(in->buf + in->len - plen, CONSOLE_PROMPT, plen) == 0 &&
            memchr(in->buf, '\n', in->len))
            return 0;
        if (receive_more(fd, in, deadline) != 0)
            return -1;
    }
}

static int console(const char *path, const char *go_file, const char *out_path, int n_lines, char **lines)
{
    int srv = -1, conn = accept_console(path, go_file, &srv);
    if (conn < 0)
        return 1;
    FILE *out = fopen(out_path, "w");
    if (!out)
        return fail("console: cannot write the output file");
    struct inbox in = {0};
    int ok = 1;
    for (int i = 0; ok && i < n_lines; i++) {
        size_t n = strlen(lines[i]);
        char *line = malloc(n + 2);
        if (!line)
            return fail("out of memory");
        memcpy(line, lines[i], n);
        line[n] = '\n';
        ok = send_all(conn, line, n + 1) == 0 && read_lines(conn, &in, 1) == 0;
        free(line);
        if (!ok) {
            fprintf(stderr, "unix_peer: console: no reply to '%s' (uwbd closed the connection?)\n", lines[i]);
            break;
        }
        char *reply = take_line(&in);
        while (ok && strncmp(reply, CONSOLE_PROMPT, strlen(CONSOLE_PROMPT)) == 0) {
            free(reply);
            ok = read_lines(conn, &in, 1) == 0;
            reply = ok ? take_line(&in) : NULL;
        }
        if (!ok) {
            fprintf(stderr, "unix_peer: console: no reply after the echo of '%s'\n", lines[i]);
            break;
        }
        reply[strcspn(reply, "\r")] = '\0'; /* the console ends lines with CRLF */
        fprintf(out, "%s\n", reply);
        fflush(out);
        free(reply);
    }
    free(in.buf);
    fclose(out);
    close(conn);
    close(srv);
    return ok ? 0 : 1;
}

/* A line at a time, as a person would type it; OUT_FILE gets each reply's
 * lines (the text between the echo and the next prompt, CRs dropped). */
static int session(const char *path, const char *go_file, const char *out_path, int n_lines, char **lines)
{
    int srv = -1, conn = accept_console(path, go_file, &srv);
    if (conn < 0)
        return 1;
    FILE *out = fopen(out_path, "w");
    if (!out)
        return fail("session: cannot write the output file");
    struct inbox in = {0};
    size_t plen = strlen(CONSOLE_PROMPT);
    /* The prompt the console shows when it opens. */
    double deadline = uwb_monotonic_s() + WAIT_S;
    while (in.len < plen && uwb_monotonic_s() < deadline) {
        if (!in.buf && !(in.buf = calloc(1, (in.cap = 65536) + 1)))
            return fail("out of memory");
        struct pollfd p = {.fd = conn, .events = POLLIN};
        ssize_t n = poll(&p, 1, 1000) > 0 ? recv(conn, in.buf + in.len, plen - in.len, 0) : 0;
        if (n < 0 || (n == 0 && p.revents))
            break;
        in.len += (size_t)n;
    }
    int ok = in.len == plen && memcmp(in.buf, CONSOLE_PROMPT, plen) == 0;
    if (!ok)
        fprintf(stderr, "unix_peer: session: no prompt when the console opened\n");
    for (int i = 0; ok && i < n_lines; i++) {
        in.len = 0; /* the prompt before this line */
        size_t n = strlen(lines[i]);
        char *line = malloc(n + 2);
        if (!line)
            return fail("out of memory");
        memcpy(line, lines[i], n);
        line[n] = '\n';
        ok = send_all(conn, line, n + 1) == 0 && read_to_prompt(conn, &in) == 0;
        free(line);
        if (!ok) {
            fprintf(stderr, "unix_peer: session: no reply and prompt after '%s'\n", lines[i]);
            break;
        }
        const char *reply = memchr(in.buf, '\n', in.len) + 1; /* after the echo */
        for (const char *c = reply; c < in.buf + in.len - plen; c++)
            if (*c != '\r')
                fputc(*c, out);
        fflush(out);
    }
    free(in.buf);
    fclose(out);
    close(conn);
    close(srv);
    return ok ? 0 : 1;
}

/* KEYS with C escapes (\r \n \b \t \e \\ \xHH) as the bytes a terminal sends. */
static size_t unescape_keys(const char *keys, char *out)
{
    size_t n = 0;
    for (const char *k = keys; *k; k++) {
        if (*k != '\\' || !k[1]) {
            out[n++] = *k;
            continue;
        }
        k++;
        switch (*k) {
        case 'r': out[n++] = '\r'; break;
        case 'n': out[n++] = '\n'; break;
        case 'b': out[n++] = '\b'; break;
        case 't': out[n++] = '\t'; break;
        case 'e': out[n++] = 0x1b; break;
        case 'x': {
            unsigned v = 0;
            int digits = 0;
            while (digits < 2 && k[1] && strchr("0123456789abcdefABCDEF", k[1])) {
                char c = *++k;
                v = v * 16 + (unsigned)(c <= '9' ? c - '0' : (c | 0x20) - 'a' + 10);
                digits++;
            }
            out[n++] = (char)v;
            break;
        }
        default: out[n++] = *k; break;
        }
    }
    return n;
}

static size_t count_prompts(const char *buf, size_t len)
{
    size_t count = 0, plen = strlen(CONSOLE_PROMPT);
    for (size_t i = 0; i + plen <= len; i++)
        if (memcmp(buf + i, CONSOLE_PROMPT, plen) == 0)
            count++;
    return count;
}

/* unix_peer terminal SOCKET GO_FILE OUT_FILE KEYS...: a person at minicom.
 * Each KEYS is sent a byte at a time, 2 ms apart; the daemon has answered it
 * when one new prompt came per line end (CR, LF, CRLF) or Ctrl-C in it.
 * OUT_FILE gets every byte the console sent, as it came. */
static int terminal(const char *path, const char *go_file, const char *out_path, int n_keys, char **keys)
{
    int srv = -1, conn = accept_console(path, go_file, &srv);
    if (conn < 0)
        return 1;
    struct inbox in = {0};
    int ok = 1;
    size_t prompts_seen = 0;
    for (int i = 0; ok && i < n_keys; i++) {
        if (strncmp(keys[i], "@until:", 7) == 0) {
            /* Not keys: wait for TEXT from the console (an asynchronous line). */
            double until = uwb_monotonic_s() + SCAN_WAIT_S;
            while (ok && !(in.buf && strstr(in.buf, keys[i] + 7))) {
                if (in.len + 4096 > in.cap) {
                    char *grown = realloc(in.buf, in.cap + 65536 + 1);
                    if (!grown)
                        return fail("out of memory");
                    in.buf = grown;
                    in.cap += 65536;
                }
                double left = until - uwb_monotonic_s();
                struct pollfd p = {.fd = conn, .events = POLLIN};
                ssize_t r = left > 0 && poll(&p, 1, (int)(left * 1000) + 1) > 0
                                ? recv(conn, in.buf + in.len, in.cap - in.len, 0)
                                : -1;
                if (r <= 0) {
                    fprintf(stderr, "unix_peer: terminal: never saw '%s'\n", keys[i] + 7);
                    ok = 0;
                    break;
                }
                in.len += (size_t)r;
                in.buf[in.len] = '\0';
            }
            prompts_seen = count_prompts(in.buf ? in.buf : "", in.len);
            continue;
        }
        char *bytes = malloc(strlen(keys[i]) + 1);
        if (!bytes)
            return fail("out of memory");
        size_t n = unescape_keys(keys[i], bytes);
        size_t prompts_due = 0;
        for (size_t j = 0; j < n; j++) {
            prompts_due += bytes[j] == '\r' || bytes[j] == 0x03 ||
                           (bytes[j] == '\n' && (j == 0 || bytes[j - 1] != '\r'));
            if (send_all(conn, bytes + j, 1) != 0)
                ok = 0;
            sleep_s(0.002);
        }
        free(bytes);
        /* The prompt the console shows when it opens counts too. */
        size_t want = prompts_seen + prompts_due + (i == 0);
        double deadline = uwb_monotonic_s() + WAIT_S;
        while (ok && count_prompts(in.buf ? in.buf : "", in.len) < want) {
            if (in.len + 4096 > in.cap) {
                char *grown = realloc(in.buf, in.cap + 65536 + 1);
                if (!grown)
                    return fail("out of memory");
                in.buf = grown;
                in.cap += 65536;
            }
            double left = deadline - uwb_monotonic_s();
            struct pollfd p = {.fd = conn, .events = POLLIN};
            if (left <= 0 || poll(&p, 1, (int)(left * 1000) + 1) <= 0) {
                fprintf(stderr, "unix_peer: terminal: no prompt after '%s'\n", keys[i]);
                ok = 0;
                break;
            }
            ssize_t r = recv(conn, in.buf + in.len, in.cap - in.len, 0);
            if (r <= 0) {
                fprintf(stderr, "unix_peer: terminal: the console closed after '%s'\n", keys[i]);
                ok = 0;
                break;
            }
            in.len += (size_t)r;
            in.buf[in.len] = '\0';
        }
        prompts_seen = want;
    }
    FILE *out = fopen(out_path, "wb");
    if (!out || (in.len && fwrite(in.buf, 1, in.len, out) != in.len) || fclose(out) != 0)
        ok = fail("terminal: cannot write the output file") == 0;
    free(in.buf);
    close(conn);
    close(srv);
    return ok ? 0 : 1;
}

/* One line sent, one reply line read, and its "class". */
static int reply_class_is(int fd, const char *line, const char *want)
{
    struct inbox in = {0};
    if (send_all(fd, line, strlen(line)) != 0 || read_lines(fd, &in, 1) != 0) {
        free(in.buf);
        fprintf(stderr, "unix_peer: no reply to %s", line);
        return 0;
    }
    char *reply = take_line(&in);
    cJSON *o = cJSON_Parse(reply);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    int ok = cJSON_IsString(cls) && strcmp(cls->valuestring, want) == 0;
    if (!ok)
        fprintf(stderr, "unix_peer: reply to %.*s: %s, want class %s\n", (int)strcspn(line, "\n"), line,
                reply, want);
    cJSON_Delete(o);
    free(reply);
    free(in.buf);
    return ok;
}

#define FLOOD_UID 65534 /* nobody: neither root nor the daemon's user */
#define FLOOD_TICK_S 0.5
#define FLOOD_HOLD_S 2.5

/* In a child that has become FLOOD_UID (in the socket's group, as a
 * control-group member would be): `fresh` clients hold their slots by
 * sending `status` every FLOOD_TICK_S and reading the reply. After
 * FLOOD_HOLD_S, past the daemon's 2 s idle rule, one more such client must
 * be refused with the reserved slot named; then one byte on `ready` tells
 * the parent, and the flood goes on until the parent closes `stop`. */
static int flood_as_nobody(const char *path, int fresh, int ready, int stop)
{
    struct stat st;
    if (stat(path, &st) != 0 || setgroups(0, NULL) != 0 || setgid(st.st_gid) != 0 || setuid(FLOOD_UID) != 0)
        return fail("slots: cannot become an unprivileged control-group member");
    int *fds = calloc((size_t)fresh, sizeof *fds);
    if (!fds)
        return fail("out of memory");
    for (int i = 0; i < fresh; i++)
        if ((fds[i] = connect_to(path)) < 0)
            return fail("slots: an unprivileged client cannot connect (socket or directory permissions?)");
    int ok = 1, told = 0, rounds = 0;
    double start = uwb_monotonic_s();
    for (;;) {
        for (int i = 0; ok && i < fresh; i++)
            if (!reply_class_is(fds[i], "status\n", "STATUS")) {
                fprintf(stderr, "unix_peer: unprivileged client %d lost its slot after %d rounds\n", i + 1,
                        rounds);
                ok = 0;
            }
        rounds++;
        if (ok && !told && uwb_monotonic_s() - start >= FLOOD_HOLD_S) {
            int extra = connect_to(path);
            struct inbox in = {0};
            if (extra < 0 || read_lines(extra, &in, 1) != 0) {
                fprintf(stderr, "unix_peer: unprivileged client %d got no reply (want refused)\n", fresh + 1);
                ok = 0;
            } else {
                char *reply = take_line(&in);
                if (!strstr(reply, "too many control clients") || !strstr(reply, "kept for root")) {
                    fprintf(stderr, "unix_peer: unprivileged client %d: %s, want the reserved slot named\n",
                            fresh + 1, reply);
                    ok = 0;
                } else {
                    printf("slots: %d unprivileged clients fresh for %.1f s (%d rounds of status); the next: "
                           "%s\n",
                           fresh, uwb_monotonic_s() - start, rounds, reply);
                    fflush(stdout);
                }
                free(reply);
            }
            free(in.buf);
            if (extra >= 0)
                close(extra);
            told = 1;
            if (write(ready, ok ? "y" : "n", 1) != 1)
                ok = 0;
        }
        if (!ok)
            break;
        struct pollfd p = {.fd = stop, .events = POLLIN};
        int r = poll(&p, 1, (int)(FLOOD_TICK_S * 1000));
        if (r > 0 || (r < 0 && errno != EINTR))
            break; /* the parent is done */
        if (uwb_monotonic_s() - start > WAIT_S) {
            ok = fail("slots: the parent never finished");
            break;
        }
    }
    if (!told && write(ready, "n", 1) != 1)
        ok = 0;
    for (int i = 0; i < fresh; i++)
        close(fds[i]);
    free(fds);
    return ok ? 0 : 1;
}

/* The slot kept for the administrator: n-1 unprivileged clients that keep
 * sending commands fill what they may; the next is refused, and root is
 * still answered. */
static int reserved_slot(const char *path, int n)
{
    int ready[2], stop[2];
    if (pipe(ready) != 0 || pipe(stop) != 0)
        return fail("slots: pipe");
    fflush(stdout);
    pid_t child = fork();
    if (child < 0)
        return fail("slots: fork");
    if (child == 0) {
        close(ready[0]);
        close(stop[1]);
        _exit(flood_as_nobody(path, n - 1, ready[1], stop[0]));
    }
    close(ready[1]);
    close(stop[0]);
    char said = 'n';
    struct pollfd p = {.fd = ready[0], .events = POLLIN};
    int ok = poll(&p, 1, (int)(WAIT_S * 1000)) > 0 && read(ready[0], &said, 1) == 1 && said == 'y';
    if (ok) {
        int admin = connect_to(path);
        double asked = uwb_monotonic_s();
        ok = admin >= 0 && reply_class_is(admin, "status\n", "STATUS");
        if (ok)
            printf("slots: root client answered STATUS in %.3f s while they held on\n",
                   uwb_monotonic_s() - asked);
        else
            fprintf(stderr, "unix_peer: root was not answered while unprivileged clients held %d slots\n",
                    n - 1);
        if (admin >= 0)
            close(admin);
    }
    close(stop[1]);
    int status = 0;
    if (waitpid(child, &status, 0) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        ok = 0;
    close(ready[0]);
    return ok ? 0 : 1;
}

static int slots(const char *path, const char *count)
{
    int n = atoi(count);
    if (n <= 0 || n > 1000)
        return fail("slots: N must be a number of clients");
    int *idle = calloc((size_t)n, sizeof *idle);
    if (!idle)
        return fail("out of memory");
    int ok = 1;
    for (int i = 0; i < n; i++)
        ok = ok && (idle[i] = connect_to(path)) >= 0;
    if (!ok)
        return fail("slots: cannot connect the idle clients");
    sleep_s(0.3);

    int extra = connect_to(path);
    struct inbox in = {0};
    if (extra < 0 || read_lines(extra, &in, 1) != 0)
        return fail("slots: the client over the limit got no reply");
    char *reply = take_line(&in);
    cJSON *o = cJSON_Parse(reply);
    const cJSON *cls = cJSON_GetObjectItemCaseSensitive(o, "class");
    const cJSON *msg = cJSON_GetObjectItemCaseSensitive(o, "message");
    if (!cJSON_IsString(cls) || strcmp(cls->valuestring, "ERROR") != 0 || !cJSON_IsString(msg) ||
        !strstr(msg->valuestring, "too many control clients")) {
        fprintf(stderr, "unix_peer: the client over the limit: %s, want ERROR \"too many control clients\"\n",
                reply);
        ok = 0;
    }
    cJSON_Delete(o);
    free(reply);
    free(in.buf);

    sleep_s(2.5);
    int late = connect_to(path);
    if (late < 0 || !reply_class_is(late, "status\n", "STATUS"))
        return fail("slots: a client after 2.5 s of silence was not served");
    char byte;
    struct pollfd p = {.fd = idle[0], .events = POLLIN};
    if (poll(&p, 1, (int)(WAIT_S * 1000)) <= 0 || recv(idle[0], &byte, 1, 0) != 0) {
        fprintf(stderr, "unix_peer: the longest-idle client was not the one dropped\n");
        ok = 0;
    }
    if (!reply_class_is(idle[1], "status\n", "STATUS")) {
        fprintf(stderr, "unix_peer: another idle client lost its connection\n");
        ok = 0;
    }
    for (int i = 0; i < n; i++)
        close(idle[i]);
    close(extra);
    close(late);
    free(idle);
    if (!ok)
        return 1;

    sleep_s(0.3); /* the daemon sees them gone */
    if (geteuid() != 0) {
        printf("slots: SKIPPED the slot kept for root: it needs root to connect as another user (uid %d)\n",
               FLOOD_UID);
        return 0;
    }
    return reserved_slot(path, n);
}

/* unix_peer screen FILE: what a VT100 terminal shows after FILE's bytes (a
 * terminal transcript), a line each: CR, LF, BS, ESC [ K (clear to the
 * line's end) and ESC [ A (up a line) move and erase; a byte is a column. */
enum { SCREEN_ROWS = 4096, SCREEN_COLS = 512 };
static int screen(const char *path)
{
    static char rows[SCREEN_ROWS][SCREEN_COLS + 1];
    char *bytes, err[512];
    size_t len;
    if (uwb_read_file(path, (size_t)MAX_REPLY, &bytes, &len, err, sizeof err) != UWB_READ_OK)
        return fail(err);
    int row = 0, col = 0, last = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)bytes[i];
        if (c == '\r')
            col = 0;
        else if (c == '\n')
            row = row + 1 < SCREEN_ROWS ? row + 1 : row;
        else if (c == '\b')
            col = col > 0 ? col - 1 : 0;
        else if (c == 0x1b && i + 2 < len && bytes[i + 1] == '[' &&
                 (bytes[i + 2] == 'K' || bytes[i + 2] == 'A')) {
            if (bytes[i + 2] == 'K')
                rows[row][col] = '\0';
            else
                row = row > 0 ? row - 1 : 0;
            i += 2;
        } else if (c >= 0x20 && col < SCREEN_COLS) {
            size_t have = strlen(rows[row]);
            while ((int)have < col)
                rows[row][have++] = ' ';
            rows[row][col++] = (char)c;
            if ((size_t)col > have)
                rows[row][col] = '\0';
        }
        last = row > last ? row : last;
    }
    for (int r = 0; r <= last; r++)
        puts(rows[r]);
    free(bytes);
    return 0;
}

static int invert(const char *path, const char *timeout_arg)
{
    double deadline = uwb_monotonic_s() + (timeout_arg ? atof(timeout_arg) : 30.0);
    struct sockaddr_un a;
    int fd = -1;
    if (unix_address(path, &a) != 0)
        return fail("invert: socket path too long");
    for (;;) {
        fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
        if (fd >= 0 && connect(fd, (struct sockaddr *)&a, sizeof a) == 0)
            break;
        int why = errno;
        if (fd >= 0)
            close(fd);
        if (uwb_monotonic_s() > deadline) {
            fprintf(stderr, "unix_peer: cannot connect to %s: %s\n", path, strerror(why));
            return 1;
        }
        sleep_s(0.05);
    }
    unsigned char buf[65536];
    long long answered = 0;
    for (;;) {
        ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) /* qemu closed the socket (or reset it): the guest is done */
            break;
        for (ssize_t i = 0; i < n; i++)
            buf[i] = (unsigned char)~buf[i];
        if (send_all(fd, (const char *)buf, (size_t)n) != 0)
            break;
        answered += n;
    }
    close(fd);
    fprintf(stderr, "serial-peer: %lld bytes received and answered\n", answered);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && strcmp(argv[1], "ask") == 0)
        return ask(argv[2], argv[3]);
    if (argc >= 5 && strcmp(argv[1], "console") == 0)
        return console(argv[2], argv[3], argv[4], argc - 5, argv + 5);
    if (argc == 3 && strcmp(argv[1], "screen") == 0)
        return screen(argv[2]);
    if (argc >= 5 && strcmp(argv[1], "session") == 0)
        return session(argv[2], argv[3], argv[4], argc - 5, argv + 5);
    if (argc >= 5 && strcmp(argv[1], "terminal") == 0)
        return terminal(argv[2], argv[3], argv[4], argc - 5, argv + 5);
    if (argc == 4 && strcmp(argv[1], "slots") == 0)
        return slots(argv[2], argv[3]);
    if ((argc == 3 || argc == 4) && strcmp(argv[1], "invert") == 0)
        return invert(argv[2], argc == 4 ? argv[3] : NULL);
    fprintf(stderr, "usage: unix_peer ask SOCKET N < BYTES\n"
                    "       unix_peer console SOCKET GO_FILE OUT_FILE LINE...\n"
                    "       unix_peer session SOCKET GO_FILE OUT_FILE LINE...\n"
                    "       unix_peer terminal SOCKET GO_FILE OUT_FILE KEYS...\n"
                    "       unix_peer screen FILE\n"
                    "       unix_peer slots SOCKET N\n"
                    "       unix_peer invert SOCKET [CONNECT_TIMEOUT_S]\n");
    return 64;
}
