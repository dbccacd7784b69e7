/* Delay tables shared by both migration paths (private to src/imaging). */
#ifndef UWB_DELAY_TABLE_H
#define UWB_DELAY_TABLE_H

#include <stdint.h>
#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/image.h"
#include "uwb/scan.h"

/* The delay to a pixel depends only on its height above the antenna and its
 * range, so when every antenna height sits on the image's y grid one table
 * over height offsets serves all traces: trace k reads rows starting at
 * row_of_trace[k]. Otherwise each trace gets its own table (shared = 0). */
struct delay_table {
    int shared;
    int rows, nz;
    int *row_of_trace;       /* positions entries */
    int32_t *index;          /* rows * nz: sample index, or `samples` (a zero pad) when out of range */
    float *frac;             /* rows * nz: fraction toward index + 1 (float path) */
    int16_t *weight_q15;     /* rows * nz: the same fraction in Q15 (fixed path) */
};

/* Build the table for all traces (shared case) or for trace `k` (per-trace
 * case, call again for each k). want_float / want_fixed pick the arrays. */
int delay_table_plan(struct delay_table *t, const struct uwb_scan *scan,
                     const struct uwb_geometry *g, const struct uwb_image *img,
                     int want_float, int want_fixed, char *err, size_t errlen);
void delay_table_fill_trace(struct delay_table *t, const struct uwb_scan *scan,
                            const struct uwb_geometry *g, const struct uwb_image *img, int k);
void delay_table_free(struct delay_table *t);

#endif
