/* The analysis's limits on a scan's data (see uwb/analysis.h), checked
 * before it runs so that a refusal is told apart from a fault. */
#include <math.h>
#include <stdio.h>

#include "uwb/analysis.h"

int uwb_analysis_check_input(const struct uwb_scan *scan, char *err, size_t errlen)
{
    if (scan->samples < UWB_ANALYSIS_MIN_SAMPLES || scan->positions < 1) {
        snprintf(err, errlen,
                 "%d positions x %d samples: the analysis needs at least %d samples per trace (a spectrum)",
                 scan->positions, scan->samples, UWB_ANALYSIS_MIN_SAMPLES);
        return -1;
    }
    size_t count = (size_t)scan->positions * (size_t)scan->samples;
    for (size_t i = 0; i < count; i++)
        if (!(fabsf(scan->data[i]) <= UWB_ANALYSIS_MAX_SAMPLE_MAGNITUDE)) {
            snprintf(err, errlen,
                     "sample %zu of position %zu is %g: beyond the %g the analysis can image in single "
                     "precision",
                     i % (size_t)scan->samples, i / (size_t)scan->samples, (double)scan->data[i],
                     UWB_ANALYSIS_MAX_SAMPLE_MAGNITUDE);
            return -1;
        }
    return 0;
}
