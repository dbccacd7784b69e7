/* Who talks to the daemon: control-socket clients and the serial console.
 * Both send command lines and get one JSON line per reply; a `scan` reply
 * is sent when that scan's verdict exists. */
/* struct ucred (SO_PEERCRED) is a GNU extension of <sys/socket.h>. */
#define _GNU_SOURCE
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/statvfs.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "daemon_internal.h"
#include "control/command.h"
#include "daemon/output_contacts.h"
#include "daemon/output_modbus.h"
#include "daemon/output_mqtt.h"
#include "daemon/outputs.h"
#include "util/log.h"
#include "control/reply.h"
#include "daemon/trend.h"
#include "state/verdict_log.h"
#include "uwb/reply_text.h"
#include "uwb/monotonic.h"
#include "uwb/version.h"

void uwbd_peers_init(struct daemon *d)
{
    for (int i = 0; i < MAX_CLIENTS; i++) {
        memset(&d->clients[i], 0, sizeof d->clients[i]);
        d->clients[i].kind = PEER_CONTROL;
        d->clients[i].fd = -1;
    }
    memset(&d->console, 0, sizeof d->console);
    d->console.kind = PEER_CONSOLE;
    d->console.fd = -1;
}

void uwbd_peer_close(struct peer *p)
{
    if (p->kind == PEER_CONTROL && p->fd >= 0)
        close(p->fd);
    if (p->kind == PEER_CONSOLE && p->link)
        uwb_link_close(p->link);
    p->fd = -1;
    p->link = NULL;
    p->in_use = 0;
    p->watching = 0;
    p->waiting_for = 0;
    free(p->out);
    p->out = NULL;
    p->out_len = p->out_cap = 0;
    memset(&p->lines, 0, sizeof p->lines);
    memset(&p->console_line, 0, sizeof p->console_line);
    p->console_at_prompt = p->console_progress_shown = 0;
}

static void drop_client(struct peer *p, const char *why)
{
    uwbd_log(UWBD_LOG_INFO, "control client dropped: %s", why);
    uwbd_peer_close(p);
}

/* Send as much of the queue as the socket takes now, never waiting. */
static void flush_queue(struct peer *p)
{
    size_t sent = 0;
    while (sent < p->out_len) {
        ssize_t w = send(p->fd, p->out + sent, p->out_len - sent, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (w > 0) {
            sent += (size_t)w;
            continue;
        }
        if (w < 0 && errno == EINTR)
            continue;
        if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK))
            break;
        drop_client(p, "gone while a reply was sent");
        return;
    }
    if (sent > 0) {
        memmove(p->out, p->out + sent, p->out_len - sent);
        p->out_len -= sent;
        p->out_progress_s = uwb_monotonic_s();
    }
}

/* Queue a whole line for a control client; one that lets its queue grow
 * past CLIENT_QUEUE_MAX does not read and is dropped. */
static void queue_line(struct peer *p, const char *text, size_t n)
{
    if (p->out_len + n > CLIENT_QUEUE_MAX) {
        drop_client(p, "it does not read its replies (queue full)");
        return;
    }
    if (p->out_len + n > p->out_cap) {
        size_t cap = p->out_cap ? p->out_cap : 4096;
        while (cap < p->out_len + n)
            cap *= 2;
        char *grown = realloc(p->out, cap);
        if (!grown) {
            drop_client(p, "out of memory for its replies");
            return;
        }
        p->out = grown;
        p->out_cap = cap;
    }
    if (p->out_len == 0)
        p->out_progress_s = uwb_monotonic_s();
    memcpy(p->out + p->out_len, text, n);
    p->out_len += n;
    flush_queue(p);
}

void uwbd_peer_writable(struct daemon *d, struct peer *p)
{
    (void)d;
    if (p->in_use && p->kind == PEER_CONTROL && p->out_len)
        flush_queue(p);
}

int uwbd_peers_expire(struct daemon *d)
{
    double now = uwb_monotonic_s(), next = -1;
    for (int i = 0; i < MAX_CLIENTS; i++) {
        struct peer *p = &d->clients[i];
        if (!p->in_use)
            continue;
        double deadline;
        const char *why;
        if (p->out_len) {
            deadline = p->out_progress_s + SEND_TIMEOUT_MS / 1000.0;
            why = "it does not read its replies";
        } else if (!p->waiting_for && !p->watching) {
            deadline = p->line_since_s + CLIENT_LINE_TIMEOUT_S;
            why = "no complete command line in time";
        } else {
            continue; /* waits for a scan's verdict, or watches */
        }
        if (now >= deadline) {
            drop_client(p, why);
            continue;
        }
        if (next < 0 || deadline < next)
            next = deadline;
    }
    return next < 0 ? -1 : (int)((next - now) * 1000.0) + 1;
}

static void console_lost(struct daemon *d, const char *why);

/* Bytes to the console as they are (echo, prompt); a console that cannot
 * take them within the timeout is closed and retried. */
static void console_write(struct daemon *d, struct peer *p, const char *bytes, size_t n)
{
    if (!p->in_use || n == 0)
        return;
    /* A serial line may be slow: allow a millisecond a byte (9600 baud) on top. */
    int timeout_ms = SEND_TIMEOUT_MS + (int)(n < 600000 ? n : 600000);
    char err[256];
    if (uwb_link_write_all(p->link, bytes, n, timeout_ms, err, sizeof err) != UWB_LINK_OK)
        console_lost(d, err);
}

static void console_prompt(struct daemon *d, struct peer *p)
{
    console_write(d, p, UWBD_CONSOLE_PROMPT, strlen(UWBD_CONSOLE_PROMPT));
    p->console_at_prompt = 1;
}

/* ESC sequences every terminal program (VT100 on) knows: the cursor to the
 * line's start and the line cleared; one line up. */
#define CLEAR_LINE "\r\033[K"
#define LINE_UP "\033[A"

/* The text of a reply as the console shows it (CRLF line ends), with what
 * goes before it (clearing the prompt's line when something was typed or
 * prompted) and after it (the prompt, and what the person had typed). */
static char *console_text(struct peer *p, const char *line, size_t *len)
{
    char *text = NULL, *shown = NULL;
    size_t n = 0, k = 0;
    FILE *f = open_memstream(&text, &n);
    if (!f)
        return NULL;
    /* ASCII: a serial console's terminal is not known to be UTF-8 (the
     * getty's and most terminal programs' default is not), and "±" would
     * show as "Â±" there (issue 48; uwbd(8), CONSOLE). */
    if (uwbd_reply_text_in(line, f, UWBD_CHARSET_ASCII) != 0)
        fprintf(f, "%s\n", line);
    if (fclose(f) != 0) {
        free(text);
        return NULL;
    }
    int progress = strncmp(line, "{\"class\":\"PROGRESS\"", 19) == 0;
    int on_prompt_line = p->console_at_prompt || p->console_line.len > 0;
    const char *before = !on_prompt_line                         ? ""
                         : progress && p->console_progress_shown ? CLEAR_LINE LINE_UP CLEAR_LINE
                                                                 : CLEAR_LINE;
    size_t typed = p->console_line.overlong ? 0 : p->console_line.len;
    size_t cap = strlen(before) + 2 * n + strlen(UWBD_CONSOLE_PROMPT) + typed + 1;
    shown = malloc(cap);
    if (shown) {
        k = (size_t)snprintf(shown, cap, "%s", before);
        for (size_t i = 0; i < n; i++) {
            if (text[i] == '\n')
                shown[k++] = '\r';
            shown[k++] = text[i];
        }
        k += (size_t)snprintf(shown + k, cap - k, "%s%.*s", UWBD_CONSOLE_PROMPT, (int)typed,
                              p->console_line.text);
        p->console_at_prompt = 1;
        p->console_progress_shown = progress;
    }
    free(text);
    *len = k;
    return shown;
}

static void send_line(struct daemon *d, struct peer *p, const char *line)
{
    if (!p->in_use)
        return; /* dropped meanwhile (e.g. an earlier reply of a pipeline) */
    if (!line) {
        uwbd_log(UWBD_LOG_ERR, "out of memory building a reply");
        return;
    }
    size_t n = strlen(line);
    /* The console is for people: the reply as text, then a prompt. */
    char *text = p->kind == PEER_CONTROL ? malloc(n + 1) : console_text(p, line, &n);
    if (!text) {
        uwbd_log(UWBD_LOG_ERR, "out of memory sending a reply");
        return;
    }
    if (p->kind == PEER_CONTROL) {
        // NOLINTNEXTLINE(bugprone-not-null-terminated-result): a counted reply (newline-framed), not a C string
        memcpy(text, line, n);
        text[n] = '\n';
        queue_line(p, text, n + 1);
    } else {
        console_write(d, p, text, n);
    }
    free(text);
}

/* Send and free a reply built by reply.c. */
static void reply(struct daemon *d, struct peer *p, char *line)
{
    send_line(d, p, line);
    free(line);
}

static long seconds_until(const struct timespec *t)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    long s = (long)(t->tv_sec - now.tv_sec) + (t->tv_nsec >= now.tv_nsec ? 0 : -1);
    return s < 0 ? 0 : s;
}

static char *status_reply(struct daemon *d)
{
    struct uwbd_scan_progress progress;
    int has_progress = uwbd_scan_progress_now(d, &progress);
    struct uwbd_mqtt_link mqtt;
    int has_mqtt = uwbd_mqtt_link_now(&mqtt);
    struct uwbd_contact_states contacts;
    uwbd_contact_states(&contacts);
    struct statvfs fs;
    int has_free = statvfs(d->store.root, &fs) == 0;
    struct uwbd_status st = {
        .version = UWBD_VERSION,
        .state = d->stopping   ? "stopping"
                 : d->scanning ? "scanning"
                               : "idle",
        .uptime_s = (long)(time(NULL) - d->started),
        .interval_s = d->cfg.interval_s,
        .has_next_scan = d->has_next_scan && !d->scanning,
        .next_scan_in_s = d->has_next_scan ? seconds_until(&d->next_scan) : 0,
        .scans_this_run = d->scans_this_run,
        .scan_queued = d->scan_queued,
        .baseline_pending = d->baseline_requests > d->baseline_done,
        .has_baseline = d->has_baseline,
        .baseline = d->baseline,
        .fault = d->fault[0] ? d->fault : NULL,
        .latest = d->latest,
        .state_dir = d->store.root,
        /* The rig belongs to the scan thread while it runs. */
        .rig = d->scanning ? "scanning" : d->rig_state,
        .console = d->cfg.console_endpoint[0] ? d->cfg.console_endpoint : NULL,
        .progress = has_progress ? &progress : NULL,
        .site_phase = d->cfg.site_phase,
        .site_label = d->cfg.site_label,
        .mqtt = has_mqtt ? &mqtt : NULL,
        .asset_id = d->cfg.site.asset_id,
        .modbus_endpoint = d->cfg.modbus.enabled ? d->cfg.modbus.endpoint : NULL,
        .modbus_listening = uwbd_modbus_listening(),
        .contacts = contacts.watch >= 0 ? &contacts : NULL,
        .now = time(NULL),
        .has_state_dir_free = has_free,
        .state_dir_free_bytes = has_free ? (unsigned long long)fs.f_bavail * fs.f_frsize : 0,
        .writes = d->writes.failing ? &d->writes : NULL,
    };
    return uwbd_reply_status(&st);
}

/* `trend N`: read from verdicts.jsonl, like `history`. */
static char *trend_reply(struct daemon *d, int n)
{
    struct uwb_trend t;
    char err[512], image[UWBD_PATH_MAX + 32];
    if (uwbd_trend_read(&d->store, n, &t, err, sizeof err) != 0) {
        uwbd_log(UWBD_LOG_ERR, "trend: %s", err);
        return uwbd_reply_error(err);
    }
    int has_image = uwbd_trend_png_path(&d->store, image, sizeof image) == 0 && access(image, F_OK) == 0;
    char *line = uwbd_reply_trend(&t, n, &d->cfg.evaluate.compare.thresholds, has_image ? image : NULL);
    uwb_trend_free(&t);
    return line;
}

/* control.scan_min_interval_s: an ordinary user (not root, not the daemon's
 * user, not the console) starts a scan at most once per interval, so one
 * member cannot keep the carriage running. 0, or -1 with the refusal in why. */
static int scan_allowed(struct daemon *d, const struct peer *p, char *why, size_t n)
{
    double interval = d->cfg.control_scan_min_interval_s;
    if (p->kind != PEER_CONTROL || p->privileged || interval <= 0)
        return 0;
    double now = uwb_monotonic_s();
    struct scan_start *entry = NULL, *oldest = &d->scan_starts[0];
    for (int i = 0; i < MAX_CLIENTS; i++) {
        struct scan_start *e = &d->scan_starts[i];
        if (e->at_s > 0 && e->uid == p->uid)
            entry = e;
        if (e->at_s < oldest->at_s)
            oldest = e;
    }
    if (entry && now - entry->at_s < interval) {
        snprintf(
            why, n,
            "scan refused: uid %u may start a scan once per %g s (control.scan_min_interval_s); the next "
            "is allowed in %.0f s",
            (unsigned)p->uid, interval, interval - (now - entry->at_s) + 0.5);
        return -1;
    }
    if (!entry)
        entry = oldest; /* a free entry, or the one longest past */
    entry->uid = p->uid;
    entry->at_s = now;
    return 0;
}

static void run_command(struct daemon *d, struct peer *p, const struct uwb_command *cmd)
{
    char limited[200];
    switch (cmd->kind) {
    case UWB_COMMAND_STATUS: reply(d, p, status_reply(d)); return;
    case UWB_COMMAND_HELP: reply(d, p, uwbd_reply_help()); return;
    case UWB_COMMAND_VERDICT:
        if (d->latest_verdict)
            send_line(d, p, d->latest_verdict);
        else
            reply(d, p, uwbd_reply_error("no verdict yet: no scan has been recorded"));
        return;
    case UWB_COMMAND_HISTORY: {
        char **lines = NULL, err[512];
        int count = 0, skipped = 0;
        if (uwbd_verdict_log_tail(&d->store, cmd->count, &lines, &count, &skipped, err, sizeof err) != 0) {
            uwbd_log(UWBD_LOG_ERR, "history: %s", err);
            reply(d, p, uwbd_reply_error(err));
            return;
        }
        reply(d, p, uwbd_reply_history(lines, count, cmd->count, skipped));
        uwbd_verdict_lines_free(lines, count);
        return;
    }
    case UWB_COMMAND_TREND: reply(d, p, trend_reply(d, cmd->count)); return;
    case UWB_COMMAND_BASELINE_SET: reply(d, p, uwbd_baseline_request(d, cmd->count, cmd->force)); return;
    case UWB_COMMAND_WATCH:
        p->watching = cmd->watch;
        reply(d, p, uwbd_reply_watch(cmd->watch));
        return;
    case UWB_COMMAND_SCAN:
        if (d->stopping) {
            reply(d, p, uwbd_reply_error("the daemon is stopping; no new scan"));
            return;
        }
        if (p->waiting_for) {
            /* One connection waits for one verdict: a second `scan` sent before
             * the first one's verdict is refused, not silently merged. */
            reply(d, p,
                  uwbd_reply_error("a scan is already pending on this connection; wait for its verdict"));
            return;
        }
        if (scan_allowed(d, p, limited, sizeof limited) != 0) {
            uwbd_log(UWBD_LOG_DEBUG, "control: %s", limited); /* a flood must not flood the log */
            reply(d, p, uwbd_reply_error(limited));
            return;
        }
        /* The peer waits for the cycle that starts now, or the one queued after the running one. */
        p->waiting_for = d->cycles_started + 1;
        uwbd_peers_request_scan(d, TRIGGER_COMMAND);
        return;
    case UWB_COMMAND_ACK: {
        char err[160];
        struct uwbd_contact_states st;
        if (uwbd_outputs_acknowledge(&d->port, err, sizeof err) != 0) {
            reply(d, p, uwbd_reply_error(err));
            return;
        }
        uwbd_contact_states(&st);
        reply(d, p, uwbd_reply_ack(&st, d->latest));
        return;
    }
    case UWB_COMMAND_EVENT:
        if (d->stopping) {
            reply(d, p, uwbd_reply_error("the daemon is stopping; no new scan"));
            return;
        }
        if (scan_allowed(d, p, limited, sizeof limited) != 0) {
            uwbd_log(UWBD_LOG_DEBUG, "control: %s", limited); /* a flood must not flood the log */
            reply(d, p, uwbd_reply_error(limited));
            return;
        }
        uwbd_log(UWBD_LOG_NOTICE, "%s: event: a scan follows as soon as possible",
                 p->kind == PEER_CONSOLE ? "console" : "control");
        reply(d, p, uwbd_reply_event(d->scanning));
        uwbd_peers_request_scan(d, TRIGGER_EVENT);
        return;
    case UWB_COMMAND_CONTACTS_TEST: {
        char who[48], refused[300];
        if (uwbd_contacts_test_permitted(d, p, refused, sizeof refused) != 0) {
            uwbd_log(UWBD_LOG_NOTICE, "control: %s", refused);
            reply(d, p, uwbd_reply_error(refused));
            return;
        }
        if (p->kind == PEER_CONSOLE)
            snprintf(who, sizeof who, "the console");
        else
            snprintf(who, sizeof who, "a control client (uid %u)", (unsigned)p->uid);
        reply(d, p, uwbd_contacts_test_start(d, cmd->count, cmd->force, who));
        return;
    }
    }
}

static void handle_line(struct daemon *d, struct peer *p, const char *line, size_t len)
{
    struct uwb_command cmd;
    char err[160];
    int rc = uwb_command_parse(line, len, &cmd, err, sizeof err);
    if (rc == UWB_COMMAND_EMPTY) {
        if (p->kind == PEER_CONSOLE)
            console_prompt(d, p);
        return;
    }
    if (rc != UWB_COMMAND_OK) {
        uwbd_log(UWBD_LOG_INFO, "%s: refused a command: %s", p->kind == PEER_CONSOLE ? "console" : "control",
                 err);
        reply(d, p, uwbd_reply_error(err));
        return;
    }
    uwbd_log(UWBD_LOG_DEBUG, "%s: %s", p->kind == PEER_CONSOLE ? "console" : "control",
             uwb_command_name(cmd.kind));
    run_command(d, p, &cmd);
}

/* The console: a person types; echo what the editor says, then act on the line. */
static void feed_console(struct daemon *d, struct peer *p, const char *buf, size_t n)
{
    size_t used = 0;
    const char *line;
    size_t len;
    int ev;
    do {
        ev = uwbd_console_line_feed(&p->console_line, buf, n, &used, &line, &len);
        const char *echo = p->console_line.echo;
        size_t echo_len = p->console_line.echo_len, plen = strlen(UWBD_CONSOLE_PROMPT);
        console_write(d, p, echo, echo_len);
        p->console_line.echo_len = 0;
        if (!p->in_use)
            return;
        if (ev != UWBD_LINE_NONE) /* Enter: the cursor left the prompt's line */
            p->console_at_prompt = p->console_progress_shown = 0;
        else if (echo_len >= plen && memcmp(echo + echo_len - plen, UWBD_CONSOLE_PROMPT, plen) == 0) {
            /* Ctrl-C: a new line, a prompt */
            p->console_at_prompt = 1;
            p->console_progress_shown = 0;
        }
        if (ev == UWBD_LINE_TOO_LONG) {
            char msg[96];
            snprintf(msg, sizeof msg, "command line too long (at most %d bytes); ignored",
                     UWB_COMMAND_MAX_LINE);
            reply(d, p, uwbd_reply_error(msg));
        } else if (ev == UWBD_LINE_READY) {
            handle_line(d, p, line, len);
        }
    } while (ev != UWBD_LINE_NONE && p->in_use);
}

static void feed(struct daemon *d, struct peer *p, const char *buf, size_t n)
{
    size_t used = 0;
    const char *line;
    size_t len;
    int ev;
    if (p->kind == PEER_CONSOLE) {
        feed_console(d, p, buf, n);
        return;
    }
    while (p->in_use &&
           (ev = uwbd_line_buffer_feed(&p->lines, buf, n, &used, &line, &len)) != UWBD_LINE_NONE) {
        p->line_since_s = uwb_monotonic_s();
        if (ev == UWBD_LINE_TOO_LONG) {
            char msg[96];
            snprintf(msg, sizeof msg, "command line too long (at most %d bytes); ignored",
                     UWB_COMMAND_MAX_LINE);
            reply(d, p, uwbd_reply_error(msg));
        } else {
            handle_line(d, p, line, len);
        }
    }
}

/* With every slot the newcomer may use taken, the client whose current
 * command line began longest ago, at least CLIENT_IDLE_EVICT_S before (and
 * that is not waiting for a scan), makes room; only an ordinary one when
 * ordinary clients are at their limit, and only one of the newcomer's own
 * user (`own`; NULL: anyone's) when that user is at its share,
 * control.max_clients_per_user. Counted from its last complete line, not
 * its last byte: clients that trickle a byte a second or say nothing
 * cannot lock the operators out for more than that. */
static struct peer *client_to_drop(struct daemon *d, double now, int ordinary_only, const uid_t *own)
{
    struct peer *oldest = NULL;
    for (int i = 0; i < MAX_CLIENTS; i++) {
        struct peer *p = &d->clients[i];
        if (!p->in_use || p->waiting_for || now - p->line_since_s < CLIENT_IDLE_EVICT_S ||
            (ordinary_only && p->privileged) || (own && (p->privileged || p->uid != *own)))
            continue;
        if (!oldest || p->line_since_s < oldest->line_since_s)
            oldest = p;
    }
    return oldest;
}

/* Root and the daemon's own user are privileged; an unknown peer counts as
 * ordinary, with uid (uid_t)-1. */
static int peer_is_privileged(int fd, uid_t *uid)
{
    struct ucred cred;
    socklen_t len = sizeof cred;
    *uid = (uid_t)-1;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0 || len != sizeof cred)
        return 0;
    *uid = cred.uid;
    return cred.uid == 0 || cred.uid == geteuid();
}

void uwbd_peer_accept(struct daemon *d)
{
    int fd = accept(d->control.fd, NULL, NULL);
    if (fd < 0) {
        if (errno != EAGAIN && errno != EINTR)
            uwbd_log(UWBD_LOG_WARNING, "control socket: accept: %s", strerror(errno));
        return;
    }
    /* accept4 would do this in one call, but it is a GNU extension. */
    if (fcntl(fd, F_SETFD, FD_CLOEXEC) != 0 || fcntl(fd, F_SETFL, O_NONBLOCK) != 0) {
        close(fd);
        return;
    }
    double now = uwb_monotonic_s();
    uid_t uid;
    int privileged = peer_is_privileged(fd, &uid), ordinary = 0, mine = 0;
    struct peer *slot = NULL;
    for (int i = 0; i < MAX_CLIENTS; i++) {
        if (!d->clients[i].in_use && !slot)
            slot = &d->clients[i];
        ordinary += d->clients[i].in_use && !d->clients[i].privileged;
        mine += d->clients[i].in_use && !d->clients[i].privileged && d->clients[i].uid == uid;
    }
    /* One user cannot hold every ordinary slot: over its share, only one of
     * its own idle clients may make room. */
    int per_user = d->cfg.control_max_clients_per_user;
    int user_full = !privileged && per_user > 0 && mine >= per_user;
    int ordinary_full = !privileged && ordinary >= MAX_ORDINARY_CLIENTS;
    if (ordinary_full || user_full)
        slot = NULL;
    if (!slot && (slot = client_to_drop(d, now, ordinary_full, user_full ? &uid : NULL)) != NULL) {
        uwbd_log(
            UWBD_LOG_NOTICE,
            "control: %d clients connected%s; dropping one idle for %.1f s (no complete command line) to "
            "make room",
            user_full       ? mine
            : ordinary_full ? MAX_ORDINARY_CLIENTS
                            : MAX_CLIENTS,
            user_full ? " of this user" : "", now - slot->line_since_s);
        uwbd_peer_close(slot);
    }
    if (slot) {
        slot->in_use = 1;
        slot->fd = fd;
        slot->privileged = privileged;
        slot->uid = uid;
        slot->last_active_s = slot->line_since_s = now;
        return;
    }
    char why[200];
    if (user_full && !ordinary_full)
        snprintf(
            why, sizeof why,
            "too many control clients for uid %u (%d, its limit: control.max_clients_per_user); close one "
            "or try again later",
            (unsigned)uid, mine);
    else if (ordinary_full)
        snprintf(why, sizeof why,
                 "too many control clients (%d of %d; the last is kept for root and the daemon's user); try "
                 "again later",
                 MAX_ORDINARY_CLIENTS, MAX_CLIENTS);
    else
        snprintf(why, sizeof why, "too many control clients (%d of %d); try again later", MAX_CLIENTS,
                 MAX_CLIENTS);
    uwbd_log(UWBD_LOG_INFO, "control: a client was turned away: %s", why);
    struct peer turned_away = {.kind = PEER_CONTROL, .in_use = 1, .fd = fd};
    reply(d, &turned_away, uwbd_reply_error(why));
    uwbd_peer_close(&turned_away);
}

static void console_lost(struct daemon *d, const char *why)
{
    uwbd_log(d->console_failing ? UWBD_LOG_DEBUG : UWBD_LOG_WARNING, "console %s: %s; retrying every %d s",
             d->cfg.console_endpoint, why, CONSOLE_RETRY_S);
    d->console_failing = 1;
    uwbd_peer_close(&d->console);
    struct itimerspec its = {.it_value = {.tv_sec = CONSOLE_RETRY_S},
                             .it_interval = {.tv_sec = CONSOLE_RETRY_S}};
    timerfd_settime(d->console_retry_fd, 0, &its, NULL);
}

void uwbd_console_open(struct daemon *d)
{
    if (!d->cfg.console_endpoint[0] || d->console.in_use)
        return;
    char err[512];
    struct uwb_link *link;
    if (uwb_link_open(d->cfg.console_endpoint, &link, err, sizeof err) != UWB_LINK_OK) {
        console_lost(d, err);
        return;
    }
    struct itimerspec off = {0};
    timerfd_settime(d->console_retry_fd, 0, &off, NULL);
    d->console.in_use = 1;
    d->console.link = link;
    d->console_failing = 0;
    uwbd_log(UWBD_LOG_INFO, "console on %s", d->cfg.console_endpoint);
    console_prompt(d, &d->console);
}

void uwbd_peer_readable(struct daemon *d, struct peer *p)
{
    char buf[512];
    if (p->kind == PEER_CONTROL) {
        ssize_t r = recv(p->fd, buf, sizeof buf, MSG_DONTWAIT);
        if (r > 0) {
            p->last_active_s = uwb_monotonic_s();
            feed(d, p, buf, (size_t)r);
        } else if (r == 0 || (errno != EAGAIN && errno != EINTR))
            uwbd_peer_close(p);
        return;
    }
    char err[256];
    ssize_t r = uwb_link_read(p->link, buf, sizeof buf, 0, err, sizeof err);
    if (r > 0)
        feed(d, p, buf, (size_t)r);
    else if (r != UWB_LINK_ERR_TIMEOUT)
        console_lost(d, err);
}

/* The control clients' slots and the console: every peer a verdict or a
 * progress line may go to. Returns how many there are. */
static int every_peer(struct daemon *d, struct peer *all[MAX_CLIENTS + 1])
{
    int n = 0;
    for (int i = 0; i < MAX_CLIENTS; i++)
        all[n++] = &d->clients[i];
    all[n++] = &d->console;
    return n;
}

void uwbd_peers_send_verdict(struct daemon *d, unsigned long cycle, const char *line, const char *error)
{
    struct peer *all[MAX_CLIENTS + 1];
    int n = every_peer(d, all);
    for (int i = 0; i < n; i++) {
        struct peer *p = all[i];
        if (p->in_use && p->watching == WATCH_ALL && p->waiting_for != cycle && line)
            send_line(d, p, line);
        if (!p->in_use || p->waiting_for != cycle)
            continue;
        p->waiting_for = 0;
        if (line)
            send_line(d, p, line);
        else
            reply(d, p, uwbd_reply_error(error));
    }
}

void uwbd_peers_send_progress(struct daemon *d)
{
    struct uwbd_scan_progress progress;
    if (!uwbd_scan_progress_now(d, &progress))
        return;
    char *line = NULL;
    struct peer *all[MAX_CLIENTS + 1];
    int n = every_peer(d, all);
    for (int i = 0; i < n; i++) {
        if (!all[i]->in_use || !all[i]->watching)
            continue;
        if (!line && !(line = uwbd_reply_progress(&progress)))
            return;
        send_line(d, all[i], line);
    }
    free(line);
}

void uwbd_peers_request_scan(struct daemon *d, enum scan_trigger why)
{
    const char *cannot = uwbd_scan_start(d, why);
    if (cannot)
        uwbd_peers_send_verdict(d, d->cycles_started + 1, NULL, cannot);
}
