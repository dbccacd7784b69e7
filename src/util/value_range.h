/* A number's allowed range and the words for a value outside it, shared by
 * the configuration loader and the rig's own checks so that they cannot
 * word the same problem two ways. */
#ifndef UWB_UTIL_VALUE_RANGE_H
#define UWB_UTIL_VALUE_RANGE_H

#include <stddef.h>

struct uwb_value_range {
    double min, max;           /* in the written unit */
    int min_exclusive;         /* value must be > min rather than >= */
    const char *unit;          /* written unit, "" for none */
    const char *below_min_why; /* said after "out of range" when a value is under min; NULL: nothing */
};

/* "[lo, hi] unit" or "(lo, hi] unit". */
void uwb_value_range_describe(const struct uwb_value_range *r, char *buf, size_t n);
/* 0 when `written` lies in the range; else -1 with
 * problem = "V is out of range [lo, hi] unit" (and ": why" under min). */
int uwb_value_range_check(const struct uwb_value_range *r, double written, char *problem, size_t n);

#endif
