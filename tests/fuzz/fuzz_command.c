/* Fuzzing the console / control command parser (uwb_command_parse) and
 * the line cutter in front of it (uwbd_line_buffer_feed): the input is
 * what arrives on the serial console or the control socket. It is parsed
 * once whole, as one unterminated line, and once cut into lines in uneven
 * reads, as the daemon does.
 *
 * Contract: a line is a command, blank, or refused with a message; a
 * command is one of the kinds with a count in range; the cutter hands
 * over no line longer than the bound and loses no byte. */
#include <string.h>

#include "fuzz_harness.h"
#include "control/command.h"
#include "control/line_buffer.h"

static const size_t read_sizes[] = {5, 1, 64, 13, 200};

static int parse_line(const char *line, size_t len, int *accepted, char *why, size_t whylen)
{
    struct uwb_command cmd;
    char err[160];
    memset(&cmd, 0x5a, sizeof cmd);
    memset(err, 'x', sizeof err);
    int rc = uwb_command_parse(line, len, &cmd, err, sizeof err);
    if (!memchr(err, '\0', sizeof err))
        return fuzz_broken(why, whylen, "parser left err unterminated (result %d)", rc);
    switch (rc) {
    case UWB_COMMAND_OK:
        if ((unsigned)cmd.kind > UWB_COMMAND_CONTACTS_TEST) /* the last kind in command.h */
            return fuzz_broken(why, whylen, "command of kind %d", (int)cmd.kind);
        if (cmd.kind == UWB_COMMAND_HISTORY && (cmd.count < 1 || cmd.count > UWB_HISTORY_MAX))
            return fuzz_broken(why, whylen, "history of %d", cmd.count);
        if (cmd.kind == UWB_COMMAND_TREND && (cmd.count < 1 || cmd.count > UWB_HISTORY_MAX))
            return fuzz_broken(why, whylen, "trend of %d", cmd.count);
        if (!strcmp(uwb_command_name(cmd.kind), "?"))
            return fuzz_broken(why, whylen, "command without a name");
        ++*accepted;
        return FUZZ_ACCEPTED;
    case UWB_COMMAND_EMPTY: return FUZZ_ACCEPTED;
    case UWB_COMMAND_INVALID:
        if (!err[0])
            return fuzz_broken(why, whylen, "refused without a message");
        snprintf(why, whylen, "%s", err);
        return FUZZ_REJECTED;
    default: return fuzz_broken(why, whylen, "parser returned %d", rc);
    }
}

int fuzz_command_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    int accepted = 0;
    int whole = parse_line((const char *)data, size, &accepted, why, whylen);
    if (whole == FUZZ_BROKEN)
        return whole;

    struct uwbd_line_buffer lb;
    memset(&lb, 0, sizeof lb);
    size_t offset = 0, piece = 0, newlines = 0, events = 0;
    for (size_t i = 0; i < size; i++)
        newlines += data[i] == '\n';
    while (offset < size) {
        size_t n = read_sizes[piece++ % (sizeof read_sizes / sizeof read_sizes[0])];
        if (n > size - offset)
            n = size - offset;
        const char *chunk = (const char *)data + offset;
        size_t used = 0;
        for (;;) {
            const char *line = NULL;
            size_t len = 0;
            size_t before = used;
            int event = uwbd_line_buffer_feed(&lb, chunk, n, &used, &line, &len);
            if (used < before || used > n)
                return fuzz_broken(why, whylen, "line cutter moved from %zu to %zu of %zu", before, used, n);
            if (event == UWBD_LINE_NONE)
                break;
            events++;
            if (event == UWBD_LINE_TOO_LONG)
                continue;
            if (event != UWBD_LINE_READY)
                return fuzz_broken(why, whylen, "line cutter returned %d", event);
            if (len > UWB_COMMAND_MAX_LINE + 1 || line[len] != '\0')
                return fuzz_broken(why, whylen, "line cutter handed over %zu bytes", len);
            if (parse_line(line, len, &accepted, why, whylen) == FUZZ_BROKEN)
                return FUZZ_BROKEN;
        }
        if (used != n)
            return fuzz_broken(why, whylen, "line cutter stopped at %zu of %zu", used, n);
        offset += n;
    }
    if (events != newlines)
        return fuzz_broken(why, whylen, "%zu lines ended, %zu handed over or dropped", newlines, events);
    if (accepted)
        return FUZZ_ACCEPTED;
    if (!why[0])
        snprintf(why, whylen, "no command in %zu bytes", size);
    return FUZZ_REJECTED;
}

UWB_FUZZ_TARGET(fuzz_command_input)
