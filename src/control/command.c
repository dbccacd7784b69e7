/* Parsing console and control-socket command lines. Everything is checked
 * against fixed bounds before it is looked at: the length, the bytes, the
 * number of words and each word's length. */
#include "control/command.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "util/edit_distance.h"

#define MAX_WORDS 4
#define MAX_WORD 16

const struct uwb_command_help uwb_command_help[] = {
    {"status", "daemon state, schedule, baseline and the latest verdict",
     "daemon state, baseline, latest verdict, integrations"},
    {"scan", "scan now; the reply is that scan's verdict", "scan now; the reply is its verdict"},
    {"verdict", "the latest verdict", "the latest verdict"},
    {"history [N]", "the last N verdicts, oldest first (N 1..100, default 10)",
     "the last N verdicts, oldest first (1..100, default 10)"},
    {"trend [N]",
     "the last N verdicts (N 1..100, default 20) as a series: time, status, displacement +/- 1 sigma, "
     "height change, baseline changes, the rate of change since the last baseline change, and the "
     "trend image",
     "the last N verdicts as a series, with the rate (1..100)"},
    {"baseline set [N]",
     "the next good scan, averaged over N acquisitions (1..16; default baseline.scans), becomes "
     "the baseline (the old one is kept in baseline/history)",
     "the next good scan, mean of N (1..16), is the baseline"},
    {"baseline set force",
     "the same, also when the scan is an alarm against the current baseline (after a repair "
     "that moved the winding); logged",
     "the same, even if that scan is an alarm (a repair)"},
    {"watch",
     "stream PROGRESS lines (position k of N, elapsed, time left) while scanning and a VERDICT line for "
     "every verdict to this connection, until it closes; gpsd's ?WATCH={\"enable\":true} is the same",
     "stream PROGRESS and VERDICT lines"},
    {"watch progress", "stream PROGRESS lines only (what `uwbd ctl scan` asks for its progress bar)",
     "stream PROGRESS lines only"},
    {"watch off", "stop the stream", "stop the stream"},
    {"ack",
     "acknowledge the alarm contacts: a latched watch or alarm contact falls back to what the latest verdict "
     "calls for",
     "latched alarm contacts follow the latest verdict again"},
    {"event",
     "a through-fault (or another event) happened: scan as soon as the running scan ends; the verdict says "
     "\"trigger\": \"event\"",
     "a through-fault happened: scan after the running scan"},
    {"contacts test [S]",
     "point-to-point check with the RTU: every alarm contact released for 1 s, then watch, alarm and fault "
     "each energised alone for S s (1..60, default 10) with 1 s released between, then back to what the "
     "verdicts call for; refused while a scan runs; only root, the service's user and contacts.test_group "
     "may, once per contacts.test_min_interval_s; logged",
     "energise each alarm contact in turn, S s, for the RTU"},
    {"contacts test force",
     "`contacts test [S]` while a watch or alarm stands, which the RTU then sees clear and return (force "
     "before or after S); logged with the user",
     "the same during a standing watch or alarm"},
    {"help", "this list", "the commands, with what each does"},
};
const size_t uwb_command_help_count = sizeof uwb_command_help / sizeof uwb_command_help[0];

const char *uwb_command_name(enum uwb_command_kind kind)
{
    switch (kind) {
    case UWB_COMMAND_STATUS: return "status";
    case UWB_COMMAND_SCAN: return "scan";
    case UWB_COMMAND_VERDICT: return "verdict";
    case UWB_COMMAND_HISTORY: return "history";
    case UWB_COMMAND_BASELINE_SET: return "baseline set";
    case UWB_COMMAND_HELP: return "help";
    case UWB_COMMAND_WATCH: return "watch";
    case UWB_COMMAND_TREND: return "trend";
    case UWB_COMMAND_ACK: return "ack";
    case UWB_COMMAND_EVENT: return "event";
    case UWB_COMMAND_CONTACTS_TEST: return "contacts test";
    }
    return "?";
}

static void set_error(char *err, size_t errlen, const char *text, const char *word)
{
    if (err && errlen)
        snprintf(err, errlen, "%s%s%s%s", text, word ? " `" : "", word ? word : "", word ? "`" : "");
}

/* A count of 1..UWB_HISTORY_MAX in plain decimal digits. */
static int parse_count(const char *word, int *count)
{
    size_t n = strlen(word);
    if (n == 0 || n > 3 || strspn(word, "0123456789") != n)
        return -1;
    int v = 0;
    for (size_t i = 0; i < n; i++)
        v = v * 10 + (word[i] - '0');
    if (v < 1 || v > UWB_HISTORY_MAX)
        return -1;
    *count = v;
    return 0;
}

static int printable(char c)
{
    return (unsigned char)c >= 0x21 && (unsigned char)c <= 0x7e;
}

/* gpsd's form, for clients written against gpsd: ?WATCH={"enable":true} (or
 * false), spaces allowed; nothing else of its JSON is understood. */
static int parse_gpsd_watch(const char *line, size_t len, struct uwb_command *out, char *err, size_t errlen)
{
    char compact[UWB_COMMAND_MAX_LINE + 1];
    size_t n = 0;
    for (size_t i = 0; i < len; i++) {
        if (line[i] == ' ' || line[i] == '\t')
            continue;
        if (!printable(line[i])) {
            set_error(err, errlen, "command contains a byte that is not printable ASCII", NULL);
            return UWB_COMMAND_INVALID;
        }
        compact[n++] = line[i];
    }
    compact[n] = '\0';
    struct uwb_command cmd = {.kind = UWB_COMMAND_WATCH};
    if (strcmp(compact, "?WATCH={\"enable\":true}") == 0 || strcmp(compact, "?WATCH={\"enable\":true};") == 0)
        cmd.watch = 1;
    else if (strcmp(compact, "?WATCH={\"enable\":false}") == 0 ||
             strcmp(compact, "?WATCH={\"enable\":false};") == 0)
        cmd.watch = 0;
    else {
        set_error(err, errlen,
                  "?WATCH: only gpsd's ?WATCH={\"enable\":true} or {\"enable\":false} is understood (or say "
                  "`watch`)",
                  NULL);
        return UWB_COMMAND_INVALID;
    }
    *out = cmd;
    return UWB_COMMAND_OK;
}

/* The line's words, each checked for printable ASCII and its length. */
struct words {
    char word[MAX_WORDS][MAX_WORD + 1];
    int n;
};

static int split_words(const char *line, size_t len, struct words *w, char *err, size_t errlen)
{
    w->n = 0;
    size_t i = 0;
    while (i < len) {
        if (line[i] == ' ' || line[i] == '\t') {
            i++;
            continue;
        }
        size_t start = i;
        for (; i < len && line[i] != ' ' && line[i] != '\t'; i++)
            if (!printable(line[i])) {
                set_error(err, errlen, "command contains a byte that is not printable ASCII", NULL);
                return UWB_COMMAND_INVALID;
            } else if (w->n == MAX_WORDS) {
                set_error(err, errlen, "too many words (see help)", NULL);
                return UWB_COMMAND_INVALID;
            }
        if (i - start > MAX_WORD) {
            set_error(err, errlen, "unknown command or argument (too long; see help)", NULL);
            return UWB_COMMAND_INVALID;
        }
        /* Case-insensitive: every word is a keyword or a number. */
        for (size_t k = 0; k < i - start; k++)
            w->word[w->n][k] = (char)tolower((unsigned char)line[start + k]);
        w->word[w->n][i - start] = '\0';
        w->n++;
    }
    return w->n == 0 ? UWB_COMMAND_EMPTY : UWB_COMMAND_OK;
}

static int watch_args(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen)
{
    cmd->watch = 1;
    if (w->n == 2 && strcmp(w->word[1], "off") == 0)
        cmd->watch = 0;
    else if (w->n == 2 && strcmp(w->word[1], "progress") == 0)
        cmd->watch = 2;
    else if (w->n == 2) {
        set_error(err, errlen, "watch: say `watch`, `watch progress` or `watch off`, not", w->word[1]);
        return UWB_COMMAND_INVALID;
    }
    return UWB_COMMAND_OK;
}

static int history_args(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen)
{
    cmd->count = UWB_HISTORY_DEFAULT;
    if (w->n == 2 && parse_count(w->word[1], &cmd->count) != 0) {
        set_error(err, errlen, "history: N must be a whole number from 1 to 100, not", w->word[1]);
        return UWB_COMMAND_INVALID;
    }
    return UWB_COMMAND_OK;
}

static int trend_args(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen)
{
    cmd->count = UWB_TREND_DEFAULT;
    if (w->n == 2 && parse_count(w->word[1], &cmd->count) != 0) {
        set_error(err, errlen, "trend: N must be a whole number from 1 to 100, not", w->word[1]);
        return UWB_COMMAND_INVALID;
    }
    return UWB_COMMAND_OK;
}

static int baseline_args(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen)
{
    if (w->n < 2 || strcmp(w->word[1], "set") != 0) {
        set_error(err, errlen,
                  "say `baseline set` (or `baseline set N`) to make the next good scan the baseline", NULL);
        return UWB_COMMAND_INVALID;
    }
    if (w->n == 3 && strcmp(w->word[2], "force") == 0)
        cmd->force = 1;
    else if (w->n == 3 &&
             (parse_count(w->word[2], &cmd->count) != 0 || cmd->count > UWB_BASELINE_SCANS_MAX)) {
        set_error(err, errlen,
                  "baseline set: N (scans to average) must be a whole number from 1 to 16, or `force`, not",
                  w->word[2]);
        return UWB_COMMAND_INVALID;
    }
    return UWB_COMMAND_OK;
}

/* `contacts test [force] [S]`, force before or after S. */
static int contacts_args(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen)
{
    if (w->n < 2 || strcmp(w->word[1], "test") != 0) {
        set_error(err, errlen, "say `contacts test` (or `contacts test S`) to energise each relay in turn",
                  NULL);
        return UWB_COMMAND_INVALID;
    }
    cmd->count = UWB_CONTACTS_TEST_DEFAULT_S;
    int have_count = 0;
    for (int i = 2; i < w->n; i++) {
        if (strcmp(w->word[i], "force") == 0 && !cmd->force) {
            cmd->force = 1;
            continue;
        }
        if (have_count) {
            set_error(err, errlen, "contacts test: after S only `force` may follow, not", w->word[i]);
            return UWB_COMMAND_INVALID;
        }
        if (parse_count(w->word[i], &cmd->count) != 0 || cmd->count > UWB_CONTACTS_TEST_MAX_S) {
            set_error(
                err, errlen,
                "contacts test: S (seconds each relay is held) must be a whole number from 1 to 60, not",
                w->word[i]);
            return UWB_COMMAND_INVALID;
        }
        have_count = 1;
    }
    return UWB_COMMAND_OK;
}

/* Each verb: its kind, how many words may follow it, and what reads them
 * (NULL: none may). Not reflowed, so that a new verb is a line of its own. */
// clang-format off
static const struct verb {
    const char *name;
    enum uwb_command_kind kind;
    int max_args;
    int (*args)(const struct words *w, struct uwb_command *cmd, char *err, size_t errlen);
} verbs[] = {
    {"status", UWB_COMMAND_STATUS, 0, NULL},     {"scan", UWB_COMMAND_SCAN, 0, NULL},
    {"verdict", UWB_COMMAND_VERDICT, 0, NULL},   {"help", UWB_COMMAND_HELP, 0, NULL},
    {"ack", UWB_COMMAND_ACK, 0, NULL},           {"event", UWB_COMMAND_EVENT, 0, NULL},
    {"watch", UWB_COMMAND_WATCH, 1, watch_args}, {"history", UWB_COMMAND_HISTORY, 1, history_args},
    {"trend", UWB_COMMAND_TREND, 1, trend_args}, {"baseline", UWB_COMMAND_BASELINE_SET, 2, baseline_args},
    {"contacts", UWB_COMMAND_CONTACTS_TEST, 3, contacts_args},
};
// clang-format on

/* "unknown command", naming the verb at most 2 edits away when there is one
 * (`stauts`: did you mean `status`?). */
static void unknown_verb(const char *word, char *err, size_t errlen)
{
    struct uwb_nearest near;
    uwb_nearest_start(&near, word, strlen(word));
    for (size_t i = 0; i < sizeof verbs / sizeof verbs[0]; i++)
        uwb_nearest_offer(&near, verbs[i].name, strlen(verbs[i].name));
    const char *meant = near.best;
    if (!meant)
        set_error(err, errlen, "unknown command (try help):", word);
    else if (err && errlen)
        snprintf(err, errlen, "unknown command `%s` (did you mean `%s`? try help)", word, meant);
}

static int parse_words(const struct words *w, struct uwb_command *out, char *err, size_t errlen)
{
    const struct verb *v = NULL;
    for (size_t i = 0; i < sizeof verbs / sizeof verbs[0] && !v; i++)
        if (strcmp(w->word[0], verbs[i].name) == 0)
            v = &verbs[i];
    if (!v) {
        unknown_verb(w->word[0], err, errlen);
        return UWB_COMMAND_INVALID;
    }
    struct uwb_command cmd = {.kind = v->kind};
    if (v->args && v->args(w, &cmd, err, errlen) != UWB_COMMAND_OK)
        return UWB_COMMAND_INVALID;
    if (w->n - 1 > v->max_args) {
        set_error(err, errlen, "unexpected argument (see help):", w->word[v->max_args + 1]);
        return UWB_COMMAND_INVALID;
    }
    *out = cmd;
    return UWB_COMMAND_OK;
}

int uwb_command_parse(const char *line, size_t len, struct uwb_command *out, char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = '\0';
    if (!line || !out) {
        set_error(err, errlen, "no command", NULL);
        return UWB_COMMAND_INVALID;
    }
    if (len > 0 && line[len - 1] == '\n')
        len--;
    if (len > 0 && line[len - 1] == '\r')
        len--;
    if (len > UWB_COMMAND_MAX_LINE) {
        if (err && errlen)
            snprintf(err, errlen, "command line too long (at most %d bytes)", UWB_COMMAND_MAX_LINE);
        return UWB_COMMAND_INVALID;
    }
    if (len >= 6 && memcmp(line, "?WATCH", 6) == 0)
        return parse_gpsd_watch(line, len, out, err, errlen);
    struct words w;
    int rc = split_words(line, len, &w, err, errlen);
    return rc == UWB_COMMAND_OK ? parse_words(&w, out, err, errlen) : rc;
}
