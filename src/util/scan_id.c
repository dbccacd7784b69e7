/* A scan's id (see uwb/scan_id.h). One form: every archive file, verdict
 * and log line of a scan names its asset and its start the same way. */
#include "uwb/scan_id.h"

#include <stdio.h>

int uwb_scan_id_make(char *out, size_t n, const char *asset, time_t utc_s, long ms)
{
    struct tm tm;
    char stamp[32] = "";
    if (gmtime_r(&utc_s, &tm))
        strftime(stamp, sizeof stamp, "%Y%m%dT%H%M%S", &tm);
    ms = ms < 0 ? 0 : ms > 999 ? 999 : ms;
    int with_asset = asset && asset[0];
    return snprintf(out, n, "%s%suwb-%s.%03ldZ", with_asset ? asset : "", with_asset ? "-" : "", stamp, ms);
}
