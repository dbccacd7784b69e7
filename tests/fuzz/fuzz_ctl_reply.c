/* Fuzzing what `uwbd ctl` makes of the daemon's reply line: the --text
 * renderings (uwbd_verdict_text, uwbd_trend_text), which read a VERDICT's
 * or a TREND's fields (issues 17, 19), and uwbd_reply_text, which prints
 * any reply with a class (issue 31: status, history, help...; the console
 * prints the same).
 *
 * Contract, for each: its class of object is printed as text (0),
 * anything else is refused (-1) with nothing printed. And the one verdict
 * reader (issue 29): a line it takes, written back as JSON, reads back to
 * the same JSON text, so a state file read at start is published as read. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/reply_text.h"
#include "uwb/cli.h"
#include "uwb/verdict_json.h"
#include "uwb/verdict_record.h"

static int render(int (*as_text)(const char *, FILE *), const char *line, const char *kind, char *why,
                  size_t whylen)
{
    char *text = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&text, &len);
    if (!out)
        return fuzz_broken(why, whylen, "open_memstream failed");
    int rc = as_text(line, out);
    fclose(out);
    int outcome = FUZZ_ACCEPTED;
    if (rc != 0 && rc != -1)
        outcome = fuzz_broken(why, whylen, "returned %d", rc);
    else if (rc == -1 && len != 0)
        outcome = fuzz_broken(why, whylen, "refused, yet printed %zu bytes", len);
    else if (rc == 0 && len == 0)
        outcome = fuzz_broken(why, whylen, "accepted, printed nothing");
    else if (rc == -1) {
        snprintf(why, whylen, "not a %s reply", kind);
        outcome = FUZZ_REJECTED;
    }
    free(text);
    return outcome;
}

/* FUZZ_BROKEN when a record read from line does not survive its own JSON. */
static int record_round_trip(const char *line, char *why, size_t whylen)
{
    static struct uwb_verdict_record first, second;
    char err[256];
    if (uwb_record_from_json(line, &first, err, sizeof err) != 0)
        return err[0] ? FUZZ_REJECTED : fuzz_broken(why, whylen, "record refused without a message");
    char *written = uwb_record_to_json(&first);
    if (!written)
        return fuzz_broken(why, whylen, "record accepted, not written");
    int outcome = FUZZ_ACCEPTED;
    if (uwb_record_from_json(written, &second, err, sizeof err) != 0)
        outcome = fuzz_broken(why, whylen, "record written as JSON, refused when read back: %s", err);
    else {
        char *again = uwb_record_to_json(&second);
        if (!again || strcmp(written, again) != 0)
            outcome = fuzz_broken(why, whylen, "record read back writes other JSON");
        free(again);
    }
    free(written);
    return outcome;
}

int fuzz_ctl_reply_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    char *line = malloc(size + 1);
    if (!line)
        return fuzz_broken(why, whylen, "out of memory");
    memcpy(line, data, size);
    line[size] = '\0';
    int verdict = render(uwbd_verdict_text, line, "VERDICT", why, whylen);
    int trend = verdict == FUZZ_BROKEN ? verdict : render(uwbd_trend_text, line, "TREND", why, whylen);
    int any = trend == FUZZ_BROKEN ? trend : render(uwbd_reply_text, line, "reply", why, whylen);
    int record = any == FUZZ_BROKEN ? any : record_round_trip(line, why, whylen);
    free(line);
    if (verdict == FUZZ_BROKEN || trend == FUZZ_BROKEN || any == FUZZ_BROKEN || record == FUZZ_BROKEN)
        return FUZZ_BROKEN;
    if (verdict == FUZZ_ACCEPTED || trend == FUZZ_ACCEPTED) {
        why[0] = '\0';
        return FUZZ_ACCEPTED;
    }
    snprintf(why, whylen, "neither a VERDICT nor a TREND reply");
    return FUZZ_REJECTED;
}

UWB_FUZZ_TARGET(fuzz_ctl_reply_input)
