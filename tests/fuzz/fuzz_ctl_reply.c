/* Fuzzing what `uwbd ctl` makes of the daemon's reply line: the --text
 * rendering (uwbd_verdict_text), which reads a VERDICT's fields (issue 17).
 *
 * Contract: a VERDICT object is printed as text (0), anything else is
 * refused (-1) with nothing printed. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/cli.h"

int fuzz_ctl_reply_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    char *line = malloc(size + 1);
    if (!line)
        return fuzz_broken(why, whylen, "out of memory");
    memcpy(line, data, size);
    line[size] = '\0';
    char *text = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&text, &len);
    if (!out) {
        free(line);
        return fuzz_broken(why, whylen, "open_memstream failed");
    }
    int rc = uwbd_verdict_text(line, out);
    fclose(out);
    int outcome = FUZZ_ACCEPTED;
    if (rc != 0 && rc != -1)
        outcome = fuzz_broken(why, whylen, "returned %d", rc);
    else if (rc == -1 && len != 0)
        outcome = fuzz_broken(why, whylen, "refused, yet printed %zu bytes", len);
    else if (rc == 0 && len == 0)
        outcome = fuzz_broken(why, whylen, "accepted, printed nothing");
    else if (rc == -1) {
        snprintf(why, whylen, "not a VERDICT reply");
        outcome = FUZZ_REJECTED;
    }
    free(text);
    free(line);
    return outcome;
}

UWB_FUZZ_TARGET(fuzz_ctl_reply_input)
