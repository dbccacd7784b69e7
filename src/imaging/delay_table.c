#include "delay_table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Antenna heights within this fraction of a pixel of the grid count as on it. */
#define ON_GRID_TOLERANCE 1e-3

static void fill_row(struct delay_table *t, int row, double dy_above_antenna,
                     const struct uwb_scan *scan, const struct uwb_geometry *g,
                     const struct uwb_image *img)
{
    for (int iz = 0; iz < t->nz; iz++) {
        double z = img->z0_m + iz * img->dz_m;
        double f = (uwb_two_way_delay(g, dy_above_antenna, z) - g->t0_s) / g->dt_s;
        size_t at = (size_t)row * t->nz + iz;
        int32_t idx;
        double frac;
        if (!(f >= 0.0) || f >= (double)(scan->samples - 1)) {
            idx = scan->samples;   /* reads the zero pad */
            frac = 0.0;
        } else {
            idx = (int32_t)f;
            frac = f - idx;
        }
        t->index[at] = idx;
        if (t->frac)
            t->frac[at] = (float)frac;
        if (t->weight_q15) {
            long w = lround(frac * 32768.0);
            t->weight_q15[at] = (int16_t)(w > 32767 ? 32767 : w);
        }
    }
}

int delay_table_plan(struct delay_table *t, const struct uwb_scan *scan,
                     const struct uwb_geometry *g, const struct uwb_image *img,
                     int want_float, int want_fixed, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    int K = scan->positions;
    t->nz = img->nz;
    t->row_of_trace = calloc((size_t)K, sizeof *t->row_of_trace);
    if (!t->row_of_trace)
        goto oom;

    /* Rows are offsets of the pixel grid from the highest antenna. */
    double y_top = scan->antenna_y_m[0];
    for (int k = 1; k < K; k++)
        if (scan->antenna_y_m[k] > y_top)
            y_top = scan->antenna_y_m[k];
    t->shared = 1;
    int max_row = 0;
    for (int k = 0; k < K; k++) {
        double r = (y_top - scan->antenna_y_m[k]) / img->dy_m;
        long rr = lround(r);
        if (fabs(r - rr) > ON_GRID_TOLERANCE || rr > 1000000) {
            t->shared = 0;
            break;
        }
        t->row_of_trace[k] = (int)rr;
        if (rr > max_row)
            max_row = (int)rr;
    }
    t->rows = t->shared ? img->ny + max_row : img->ny;

    size_t n = (size_t)t->rows * t->nz;
    t->index = malloc(n * sizeof *t->index);
    t->frac = want_float ? malloc(n * sizeof *t->frac) : NULL;
    t->weight_q15 = want_fixed ? malloc(n * sizeof *t->weight_q15) : NULL;
    if (!t->index || (want_float && !t->frac) || (want_fixed && !t->weight_q15))
        goto oom;

    if (t->shared) {
        /* Trace k is m_k rows below the top antenna, so its pixel row iy sits
         * at height y0 - y_top + (iy + m_k) * dy above it: table row iy + m_k. */
        for (int r = 0; r < t->rows; r++)
            fill_row(t, r, img->y0_m - y_top + r * img->dy_m, scan, g, img);
    }
    return 0;
oom:
    snprintf(err, errlen, "migration: out of memory for a %d x %d delay table", img->ny, img->nz);
    delay_table_free(t);
    return -1;
}

void delay_table_fill_trace(struct delay_table *t, const struct uwb_scan *scan,
                            const struct uwb_geometry *g, const struct uwb_image *img, int k)
{
    if (t->shared)
        return;
    t->row_of_trace[k] = 0;
    for (int iy = 0; iy < img->ny; iy++)
        fill_row(t, iy, img->y0_m + iy * img->dy_m - scan->antenna_y_m[k], scan, g, img);
}

void delay_table_free(struct delay_table *t)
{
    free(t->row_of_trace);
    free(t->index);
    free(t->frac);
    free(t->weight_q15);
    memset(t, 0, sizeof *t);
}
