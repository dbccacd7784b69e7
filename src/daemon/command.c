/* Parsing console and control-socket command lines. Everything is checked
 * against fixed bounds before it is looked at: the length, the bytes, the
 * number of words and each word's length. */
#include "daemon/command.h"

#include <stdio.h>
#include <string.h>

#define MAX_WORDS 3
#define MAX_WORD 16

const struct uwb_command_help uwb_command_help[] = {
    {"status", "daemon state, schedule, baseline and the latest verdict"},
    {"scan", "scan now; the reply is that scan's verdict"},
    {"verdict", "the latest verdict"},
    {"history [N]", "the last N verdicts, oldest first (N 1..100, default 10)"},
    {"trend [N]",
     "the last N verdicts (N 1..100, default 20) as a series: time, status, displacement +/- 1 sigma, "
     "height change, baseline changes, the rate of change since the last baseline change, and the "
     "trend image"},
    {"baseline set [N]",
     "the next good scan, averaged over N acquisitions (1..16; default baseline.scans), becomes "
     "the baseline (the old one is kept in baseline/history)"},
    {"baseline set force",
     "the same, also when the scan is an alarm against the current baseline (after a repair "
     "that moved the winding); logged"},
    {"watch",
     "stream PROGRESS lines (position k of N, elapsed, time left) while scanning and a VERDICT line for "
     "every verdict to this connection, until it closes; gpsd's ?WATCH={\"enable\":true} is the same"},
    {"watch progress", "stream PROGRESS lines only (what `uwbd ctl scan` asks for its progress bar)"},
    {"watch off", "stop the stream"},
    {"ack",
     "acknowledge the alarm contacts: a latched watch or alarm contact falls back to what the latest verdict "
     "calls for"},
    {"event",
     "a through-fault (or another event) happened: scan as soon as the running scan ends; the verdict says "
     "\"trigger\": \"event\""},
    {"help", "this list"},
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

/* gpsd's form, for clients written against gpsd: ?WATCH={"enable":true} (or
 * false), spaces allowed; nothing else of its JSON is understood. */
static int parse_gpsd_watch(const char *line, size_t len, struct uwb_command *out, char *err, size_t errlen)
{
    char compact[UWB_COMMAND_MAX_LINE + 1];
    size_t n = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)line[i];
        if (c == ' ' || c == '\t')
            continue;
        if (c < 0x21 || c > 0x7e) {
            set_error(err, errlen, "command contains a byte that is not printable ASCII", NULL);
            return UWB_COMMAND_INVALID;
        }
        compact[n++] = (char)c;
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
    char words[MAX_WORDS][MAX_WORD + 1];
    int n_words = 0;
    size_t i = 0;
    while (i < len) {
        unsigned char c = (unsigned char)line[i];
        if (c == ' ' || c == '\t') {
            i++;
            continue;
        }
        if (c < 0x21 || c > 0x7e) {
            set_error(err, errlen, "command contains a byte that is not printable ASCII", NULL);
            return UWB_COMMAND_INVALID;
        }
        if (n_words == MAX_WORDS) {
            set_error(err, errlen, "too many words (see help)", NULL);
            return UWB_COMMAND_INVALID;
        }
        size_t start = i;
        while (i < len && line[i] != ' ' && line[i] != '\t') {
            c = (unsigned char)line[i];
            if (c < 0x21 || c > 0x7e) {
                set_error(err, errlen, "command contains a byte that is not printable ASCII", NULL);
                return UWB_COMMAND_INVALID;
            }
            i++;
        }
        if (i - start > MAX_WORD) {
            set_error(err, errlen, "unknown command or argument (too long; see help)", NULL);
            return UWB_COMMAND_INVALID;
        }
        memcpy(words[n_words], line + start, i - start);
        words[n_words][i - start] = '\0';
        n_words++;
    }
    if (n_words == 0)
        return UWB_COMMAND_EMPTY;

    const char *verb = words[0];
    struct uwb_command cmd = {.count = 0};
    int max_args = 0;
    if (strcmp(verb, "status") == 0) {
        cmd.kind = UWB_COMMAND_STATUS;
    } else if (strcmp(verb, "scan") == 0) {
        cmd.kind = UWB_COMMAND_SCAN;
    } else if (strcmp(verb, "verdict") == 0) {
        cmd.kind = UWB_COMMAND_VERDICT;
    } else if (strcmp(verb, "help") == 0) {
        cmd.kind = UWB_COMMAND_HELP;
    } else if (strcmp(verb, "ack") == 0) {
        cmd.kind = UWB_COMMAND_ACK;
    } else if (strcmp(verb, "event") == 0) {
        cmd.kind = UWB_COMMAND_EVENT;
    } else if (strcmp(verb, "watch") == 0) {
        cmd.kind = UWB_COMMAND_WATCH;
        cmd.watch = 1;
        max_args = 1;
        if (n_words == 2 && strcmp(words[1], "off") == 0)
            cmd.watch = 0;
        else if (n_words == 2 && strcmp(words[1], "progress") == 0)
            cmd.watch = 2;
        else if (n_words == 2) {
            set_error(err, errlen, "watch: say `watch`, `watch progress` or `watch off`, not", words[1]);
            return UWB_COMMAND_INVALID;
        }
    } else if (strcmp(verb, "history") == 0) {
        cmd.kind = UWB_COMMAND_HISTORY;
        cmd.count = UWB_HISTORY_DEFAULT;
        max_args = 1;
        if (n_words == 2 && parse_count(words[1], &cmd.count) != 0) {
            set_error(err, errlen, "history: N must be a whole number from 1 to 100, not", words[1]);
            return UWB_COMMAND_INVALID;
        }
    } else if (strcmp(verb, "trend") == 0) {
        cmd.kind = UWB_COMMAND_TREND;
        cmd.count = UWB_TREND_DEFAULT;
        max_args = 1;
        if (n_words == 2 && parse_count(words[1], &cmd.count) != 0) {
            set_error(err, errlen, "trend: N must be a whole number from 1 to 100, not", words[1]);
            return UWB_COMMAND_INVALID;
        }
    } else if (strcmp(verb, "baseline") == 0) {
        if (n_words < 2 || strcmp(words[1], "set") != 0) {
            set_error(err, errlen,
                      "say `baseline set` (or `baseline set N`) to make the next good scan the baseline",
                      NULL);
            return UWB_COMMAND_INVALID;
        }
        cmd.kind = UWB_COMMAND_BASELINE_SET;
        max_args = 2;
        if (n_words == 3 && strcmp(words[2], "force") == 0)
            cmd.force = 1;
        else if (n_words == 3 &&
                 (parse_count(words[2], &cmd.count) != 0 || cmd.count > UWB_BASELINE_SCANS_MAX)) {
            set_error(
                err, errlen,
                "baseline set: N (scans to average) must be a whole number from 1 to 16, or `force`, not",
                words[2]);
            return UWB_COMMAND_INVALID;
        }
    } else {
        set_error(err, errlen, "unknown command (try help):", verb);
        return UWB_COMMAND_INVALID;
    }
    if (n_words - 1 > max_args) {
        set_error(err, errlen, "unexpected argument (see help):", words[max_args + 1]);
        return UWB_COMMAND_INVALID;
    }
    *out = cmd;
    return UWB_COMMAND_OK;
}
