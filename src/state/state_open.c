/* The state directory opened for the daemon: the store first, then the
 * verdict log repairs itself (see state/state_open.h). */
#include "state/state_open.h"

#include "state/verdict_log.h"

int uwbd_state_open(struct uwbd_store *store, const char *state_dir, int *repairs, char *err, size_t errlen)
{
    int removed = 0;
    if (uwbd_store_open(store, state_dir, &removed, err, errlen) != 0)
        return -1;
    long dropped = 0;
    if (uwbd_verdict_log_repair(store, &dropped, err, errlen) != 0)
        return -1;
    if (repairs)
        *repairs = removed + (dropped > 0);
    return 0;
}
