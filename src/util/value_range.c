/* A number against its allowed range, and the message when it lies outside. */
#include "util/value_range.h"

#include <stdio.h>

void uwb_value_range_describe(const struct uwb_value_range *r, char *buf, size_t n)
{
    snprintf(buf, n, "%s%.10g, %.10g]%s%s", r->min_exclusive ? "(" : "[", r->min, r->max,
             r->unit[0] ? " " : "", r->unit);
}

int uwb_value_range_check(const struct uwb_value_range *r, double written, char *problem, size_t n)
{
    int low = r->min_exclusive ? !(written > r->min) : !(written >= r->min);
    if (!low && written <= r->max)
        return 0;
    char range[96];
    uwb_value_range_describe(r, range, sizeof range);
    if (low && r->below_min_why)
        snprintf(problem, n, "%g is out of range %s: %s", written, range, r->below_min_why);
    else
        snprintf(problem, n, "%g is out of range %s", written, range);
    return -1;
}
