/* The state directory's write trouble across cycles (see state_writes.h). */
#include "state/state_writes.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "state/store.h"
#include "util/log.h"

/* The failed write's text ends in the system's reason (strerror, in this
 * process's own words), so a full file system is recognised by it. */
static int says_disk_full(const char *error)
{
    return strstr(error, strerror(ENOSPC)) != NULL || strstr(error, strerror(EDQUOT)) != NULL;
}

void uwbd_state_writes_after_cycle(struct uwbd_state_writes *w, const char *write_error, time_t now)
{
    if (!write_error || !write_error[0]) {
        if (w->failing)
            uwbd_log(UWBD_LOG_NOTICE,
                     "state directory: writing again; %d scan cycle%s since %s could not write everything",
                     w->cycles, w->cycles == 1 ? "" : "s", w->since);
        memset(w, 0, sizeof *w);
        return;
    }
    if (!w->failing) {
        w->failing = 1;
        w->cycles = 0;
        uwbd_utc_text(now, w->since, sizeof w->since);
    }
    w->cycles++;
    int was_full = w->disk_full;
    w->disk_full = says_disk_full(write_error);
    snprintf(w->error, sizeof w->error, "%s", write_error);
    if (w->cycles == 1 || w->disk_full != was_full)
        uwbd_log(UWBD_LOG_WARNING,
                 "state directory: %s (%s); scans are still evaluated and their verdicts published, and "
                 "every cycle tries again",
                 w->disk_full ? "the disk is full" : "cannot write", w->error);
}
