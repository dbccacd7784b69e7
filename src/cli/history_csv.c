/* A HISTORY reply as CSV for a spreadsheet (uwbd ctl history --csv): the
 * header, then one row per verdict, oldest first. */
#include <stdio.h>

#include "uwb/cli.h"
#include "uwb/verdict_csv.h"
#include "uwb/verdict_json.h"

struct csv_out {
    FILE *out;
    int header_done;
};

/* The header once the reply is known to be a HISTORY (none for an ERROR). */
static int header_once(struct csv_out *c)
{
    if (c->header_done++)
        return 0;
    return fputs(uwb_verdict_csv_header(), c->out) == EOF ? -1 : 0;
}

static int print_row(const struct uwb_verdict_record *r, void *ctx)
{
    struct csv_out *c = ctx;
    /* A row is bounded by the record's strings, quotes doubled: 16 KiB holds any. */
    char row[16384];
    int n = uwb_verdict_csv_row(r, row, sizeof row);
    if (n < 0 || header_once(c) != 0)
        return -1;
    return fwrite(row, 1, (size_t)n, c->out) == (size_t)n ? 0 : -1;
}

int uwbd_history_csv(const char *reply, FILE *out, char *err, size_t errlen)
{
    struct csv_out c = {.out = out};
    if (uwb_history_each(reply, print_row, &c, err, errlen) != 0)
        return -1;
    if (header_once(&c) != 0 || fflush(out) == EOF) {
        snprintf(err, errlen, "cannot write the CSV");
        return -1;
    }
    return 0;
}
