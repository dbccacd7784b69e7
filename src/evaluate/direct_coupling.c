/* The direct-coupling arrival of a scan (see the header for why). */
#include "uwb/direct_coupling.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* Fewer samples than this in the window cannot show a leading edge. */
#define MIN_WINDOW_SAMPLES 8

int uwb_direct_coupling_arrival(const struct uwb_scan *scan, double window_end_s, double *arrival_s,
                                char *why, size_t whylen)
{
    if (scan->positions < 1 || scan->samples < 1 || !(scan->sample_interval_s > 0)) {
        snprintf(why, whylen, "empty scan");
        return -1;
    }
    double span = (window_end_s - scan->t0_s) / scan->sample_interval_s;
    int n = span >= scan->samples ? scan->samples : span > 0 ? (int)span + 1 : 0;
    if (n < MIN_WINDOW_SAMPLES) {
        snprintf(why, whylen, "the direct-coupling window (up to %.3f ns) holds %d samples of the record",
                 window_end_s * 1e9, n);
        return -1;
    }
    /* The coupling is the same at every position; the mean keeps it and
     * averages noise and the winding's position-dependent echoes down. */
    int rc = -1;
    double *mean = calloc((size_t)n, sizeof *mean);
    if (!mean) {
        snprintf(why, whylen, "out of memory");
        goto done;
    }
    for (int k = 0; k < scan->positions; k++) {
        const float *trace = scan->data + (size_t)k * (size_t)scan->samples;
        for (int i = 0; i < n; i++)
            mean[i] += trace[i];
    }
    double offset = 0.0;
    for (int i = 0; i < n; i++) {
        mean[i] /= scan->positions;
        offset += mean[i];
    }
    offset /= n; /* the digitiser's DC offset, not part of any arrival */
    double peak = 0.0;
    for (int i = 0; i < n; i++) {
        mean[i] = fabs(mean[i] - offset);
        if (mean[i] > peak)
            peak = mean[i];
    }
    if (!(peak > 0.0)) {
        snprintf(why, whylen, "no signal before %.3f ns", window_end_s * 1e9);
        goto done;
    }
    double level = UWB_DIRECT_COUPLING_FRACTION * peak;
    int first = 0;
    while (mean[first] < level)
        first++;
    if (first == 0) {
        snprintf(why, whylen, "the record starts inside the direct coupling (t0 too late?)");
        goto done;
    }
    double frac = (level - mean[first - 1]) / (mean[first] - mean[first - 1]);
    *arrival_s = scan->t0_s + (first - 1 + frac) * scan->sample_interval_s;
    rc = 0;
done:
    free(mean);
    return rc;
}
