/* Delay tables shared by both migration paths (private to src/imaging). */
#ifndef UWB_DELAY_TABLE_H
#define UWB_DELAY_TABLE_H

#include <stdint.h>
#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/image.h"
#include "uwb/scan.h"

/* How a delay of d samples after sample 0 is split into index + fraction.
 * FLOAT: index = floor(d), frac in [0, 1). FIXED: the fraction rounded to
 * Q15; one that rounds to a whole sample moves to the next index with
 * weight 0, so weights stay in [0, 32767] and fit int16. Either way a delay
 * outside the record gets the index `samples`, where the traces carry a
 * zero pad, and fraction 0. */
enum delay_format { DELAY_FLOAT, DELAY_FIXED };

/* The delay to a pixel depends only on its height above the antenna and its
 * range, so when every antenna height sits on the image's y grid one table
 * over height offsets serves all traces: trace k reads rows starting at
 * row_of_trace[k]. Otherwise each trace gets its own table (shared = 0).
 *
 * With Tx and Rx at the same range offset, the two-way path is the same at
 * heights mirrored about their midpoint (the two legs swap), so a row whose
 * mirror is also in the table shares its storage: row r's entries start at
 * row_start[r]. That halves the table's memory and the time to build it. */
struct delay_table {
    enum delay_format format;
    int shared;
    int rows, nz;
    int stored_rows;     /* rows with storage of their own */
    int *row_of_trace;   /* positions entries */
    size_t *row_start;   /* rows entries: offset of row r in index / frac / weight_q15 */
    int32_t *index;      /* stored_rows * nz sample indices */
    float *frac;         /* stored_rows * nz (FLOAT) */
    int16_t *weight_q15; /* stored_rows * nz (FIXED) */
    double *delay_row;   /* nz: scratch for one row's delays in samples */
};

/* Offset of the entries for trace k's pixel row iy. */
static inline size_t delay_table_row(const struct delay_table *t, int k, int iy)
{
    return t->row_start[iy + t->row_of_trace[k]];
}

/* Build the table for all traces (shared case) or prepare one for trace `k`
 * (per-trace case: call delay_table_fill_trace for each k). */
int uwb_delay_table_plan(struct delay_table *t, enum delay_format format, const struct uwb_scan *scan,
                         const struct uwb_geometry *g, const struct uwb_image *img, char *err, size_t errlen);
void uwb_delay_table_fill_trace(struct delay_table *t, const struct uwb_scan *scan,
                                const struct uwb_geometry *g, const struct uwb_image *img, int k);
void uwb_delay_table_free(struct delay_table *t);

#endif
