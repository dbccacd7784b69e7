/* One validator for the winding span (see winding_span.h): the range is
 * the configuration key's own row, never a second copy of its limits. */
#include "config/winding_span.h"

#include <stdio.h>

#include "config/config_keys.h"

int uwbd_winding_span_check(const double span_m[2], char *problem, size_t n)
{
    const struct config_key *k = uwbd_config_key_find(UWBD_WINDING_SPAN_KEY);
    if (!k) {
        snprintf(problem, n, "internal error: no key %s", UWBD_WINDING_SPAN_KEY);
        return -1;
    }
    static const char *const end_name[2] = {"lower", "upper"};
    for (int i = 0; i < 2; i++) {
        char why[160];
        if (uwbd_config_key_check_range(k, span_m[i] / k->scale, why, sizeof why) != 0) {
            snprintf(problem, n, "%s end: %s", end_name[i], why);
            return -1;
        }
    }
    if (!(span_m[1] > span_m[0])) {
        snprintf(problem, n, "lower (%g mm) must be below upper (%g mm)", span_m[0] / k->scale,
                 span_m[1] / k->scale);
        return -1;
    }
    return 0;
}
