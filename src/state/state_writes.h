/* Whether the state directory takes what the scan cycles write. A full or
 * read-only disk does not stop the scans (they are evaluated and their
 * verdicts published all the same); this keeps the trouble in view for
 * `status` until a cycle writes everything again, and logs it once when it
 * begins and once when it ends, not at every cycle. */
#ifndef UWB_STATE_STATE_WRITES_H
#define UWB_STATE_STATE_WRITES_H

#include <time.h>

struct uwbd_state_writes {
    int failing;     /* the latest cycle could not write everything */
    int disk_full;   /* ...and the file system said it is full (ENOSPC, EDQUOT) */
    char error[512]; /* the latest cycle's first failed write */
    char since[32];  /* UTC of the first cycle that failed, this time */
    int cycles;      /* cycles in a row that could not write everything */
};

/* After a recorded cycle: write_error is "" when it wrote everything, else
 * its first failed write (struct uwbd_cycle_result's write_error). */
void uwbd_state_writes_after_cycle(struct uwbd_state_writes *w, const char *write_error, time_t now);

#endif
