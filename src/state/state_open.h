/* Opening the state directory at start-up: the store (directories,
 * leftovers of interrupted writes), then the verdict log's repair. Kept
 * apart from both so the store does not depend on the log that writes
 * through it. */
#ifndef UWB_STATE_STATE_OPEN_H
#define UWB_STATE_STATE_OPEN_H

#include <stddef.h>

#include "state/store.h"

/* uwbd_store_open, then uwbd_verdict_log_repair: a torn last line is cut off
 * verdicts.jsonl. *repairs (may be NULL) counts the leftovers removed, plus
 * one when the log was cut. Returns 0 or -1 with err. */
int uwbd_state_open(struct uwbd_store *store, const char *state_dir, int *repairs, char *err, size_t errlen);

#endif
