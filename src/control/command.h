/* The line commands engineers type on the serial console or send with
 * `uwbd ctl`. The parser is pure (no I/O, no allocation) and bounded, so it
 * can face a noisy serial line and a fuzzer alike. No command names a path. */
#ifndef UWB_CONTROL_COMMAND_H
#define UWB_CONTROL_COMMAND_H

#include <stddef.h>

/* Longest accepted command line, without its line ending. */
#define UWB_COMMAND_MAX_LINE 64
#define UWB_HISTORY_DEFAULT 10
#define UWB_HISTORY_MAX 100
#define UWB_TREND_DEFAULT 20
/* `baseline set N`: at most this many scans averaged (UWBD_BASELINE_SCANS_MAX). */
#define UWB_BASELINE_SCANS_MAX 16
/* `contacts test [S]`: each relay held S seconds (1..60, default 10). */
#define UWB_CONTACTS_TEST_DEFAULT_S 10
#define UWB_CONTACTS_TEST_MAX_S 60

enum uwb_command_kind {
    UWB_COMMAND_STATUS,       /* status         daemon state, baseline, last verdict */
    UWB_COMMAND_SCAN,         /* scan           scan now; the reply is its verdict */
    UWB_COMMAND_VERDICT,      /* verdict        the latest verdict */
    UWB_COMMAND_HISTORY,      /* history [N]    the last N verdicts, newest last */
    UWB_COMMAND_BASELINE_SET, /* baseline set   the next good scan becomes the baseline */
    UWB_COMMAND_HELP,         /* help           the commands */
    UWB_COMMAND_WATCH, /* watch [off|progress], ?WATCH={"enable":true}  stream PROGRESS and VERDICT lines */
    UWB_COMMAND_TREND, /* trend [N]      the last N verdicts as a displacement series, with its rate */
    UWB_COMMAND_ACK,   /* ack            latched alarm contacts fall back to the latest verdict */
    UWB_COMMAND_EVENT, /* event          a through-fault happened: scan as soon as the running one ends */
    UWB_COMMAND_CONTACTS_TEST, /* contacts test [S]  energise each alarm relay in turn, for the RTU */
    /* CONTACTS_TEST is the last kind: tests/fuzz/fuzz_command.c checks kinds against it. */
};

struct uwb_command {
    enum uwb_command_kind kind;
    int count; /* history, trend: how many; baseline set: scans to average (0 = the configured default);
                  contacts test: seconds each relay is held */
    int force; /* baseline set force: also on a scan that is an alarm against the current baseline */
    int watch; /* watch: 1 PROGRESS and VERDICT lines, 2 PROGRESS only, 0 off */
};

enum uwb_command_result {
    UWB_COMMAND_OK = 0,
    UWB_COMMAND_EMPTY = 1,    /* blank line: nothing to do, no reply */
    UWB_COMMAND_INVALID = -1, /* err says why */
};

/* Parse one line (a trailing "\n" or "\r\n" is allowed; no other control
 * characters, at most UWB_COMMAND_MAX_LINE bytes, words separated by
 * spaces or tabs). Returns an enum uwb_command_result. */
int uwb_command_parse(const char *line, size_t len, struct uwb_command *out, char *err, size_t errlen);

const char *uwb_command_name(enum uwb_command_kind kind);

/* One line per command for the HELP reply: "usage" and "what it does";
 * `brief`, its meaning in at most 56 columns, for `uwbd ctl --help`. */
struct uwb_command_help {
    const char *usage;
    const char *description;
    const char *brief;
};
extern const struct uwb_command_help uwb_command_help[];
extern const size_t uwb_command_help_count;

#endif
