#include "delay_table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Antenna heights within this fraction of a pixel of the grid count as on it. */
#define ON_GRID_TOLERANCE 1e-3
/* Mirrored rows share storage only when the mirror is exact to a nanometre. */
#define MIRROR_TOLERANCE_M 1e-9

/* One row's delays in samples after sample 0. Building the table is a real
 * part of a migration's cost, so the path lengths come from plain square
 * roots: hypot's care against overflow is not needed at metre scale and
 * costs several times more. */
static void row_delays(double *restrict delay, int nz, double dy_above_antenna, const struct uwb_geometry *g,
                       const struct uwb_image *img)
{
    double ty = dy_above_antenna - g->tx_dy, ry = dy_above_antenna - g->rx_dy;
    double ty2 = ty * ty, ry2 = ry * ry;
    double samples_per_metre = 1.0 / (g->velocity_m_s * g->dt_s);
    double t0_samples = g->t0_s / g->dt_s;
    for (int iz = 0; iz < nz; iz++) {
        double z = img->z0_m + iz * img->dz_m;
        double tz = z - g->tx_dz, rz = z - g->rx_dz;
        delay[iz] = (sqrt(ty2 + tz * tz) + sqrt(ry2 + rz * rz)) * samples_per_metre - t0_samples;
    }
}

static void split_float(const double *restrict delay, int nz, int samples, int32_t *restrict index,
                        float *restrict frac)
{
    double last = (double)(samples - 1);
    for (int iz = 0; iz < nz; iz++) {
        double d = delay[iz];
        if (!(d >= 0.0 && d < last)) {
            index[iz] = samples;
            frac[iz] = 0.0f;
            continue;
        }
        int32_t i = (int32_t)d;
        index[iz] = i;
        frac[iz] = (float)(d - i);
    }
}

static void split_fixed(const double *restrict delay, int nz, int samples, int32_t *restrict index,
                        int16_t *restrict weight)
{
    double last = (double)(samples - 1);
    for (int iz = 0; iz < nz; iz++) {
        double d = delay[iz];
        if (!(d >= 0.0 && d < last)) {
            index[iz] = samples;
            weight[iz] = 0;
            continue;
        }
        /* Whole samples above bit 15, the rounded Q15 fraction below: a
         * fraction that rounds up to 1 carries into the index. */
        int64_t q = (int64_t)(d * 32768.0 + 0.5);
        index[iz] = (int32_t)(q >> 15);
        weight[iz] = (int16_t)(q & 32767);
    }
}

static void fill_row(struct delay_table *t, size_t at, double dy_above_antenna, const struct uwb_scan *scan,
                     const struct uwb_geometry *g, const struct uwb_image *img)
{
    row_delays(t->delay_row, t->nz, dy_above_antenna, g, img);
    if (t->format == DELAY_FIXED)
        split_fixed(t->delay_row, t->nz, scan->samples, t->index + at, t->weight_q15 + at);
    else
        split_float(t->delay_row, t->nz, scan->samples, t->index + at, t->frac + at);
}

/* Rows r and sum - r lie at heights mirrored about the phase centres'
 * midpoint when Tx and Rx share a range offset and that midpoint falls on
 * the row grid or half-way between rows. Returns 0 and *sum, or -1. */
static int mirror_sum(const struct uwb_geometry *g, double first_row_dy, double dy, long *sum)
{
    if (fabs(g->tx_dz - g->rx_dz) > MIRROR_TOLERANCE_M)
        return -1;
    double m = (g->tx_dy + g->rx_dy - 2.0 * first_row_dy) / dy;
    if (!(fabs(m) < 1e9))
        return -1;
    long mm = lround(m);
    if (fabs(m - mm) * dy > MIRROR_TOLERANCE_M)
        return -1;
    *sum = mm;
    return 0;
}

int uwb_delay_table_plan(struct delay_table *t, enum delay_format format, const struct uwb_scan *scan,
                         const struct uwb_geometry *g, const struct uwb_image *img, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    t->format = format;
    int K = scan->positions;
    t->nz = img->nz;
    t->row_of_trace = calloc((size_t)K, sizeof *t->row_of_trace);
    t->delay_row = malloc((size_t)img->nz * sizeof *t->delay_row);
    if (!t->row_of_trace || !t->delay_row)
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
    t->row_start = malloc((size_t)t->rows * sizeof *t->row_start);
    if (!t->row_start)
        goto oom;

    /* Trace k is m_k rows below the top antenna, so its pixel row iy sits at
     * height y0 - y_top + (iy + m_k) * dy above it: table row iy + m_k. */
    double first_row_dy = img->y0_m - y_top;
    long sum = -1;
    int mirrored = t->shared && mirror_sum(g, first_row_dy, img->dy_m, &sum) == 0;
    for (int r = 0; r < t->rows; r++) {
        long partner = mirrored ? sum - r : -1;
        if (partner >= 0 && partner < r)
            t->row_start[r] = t->row_start[partner];
        else
            t->row_start[r] = (size_t)t->stored_rows++ * (size_t)t->nz;
    }

    size_t n = (size_t)t->stored_rows * t->nz;
    t->index = malloc(n * sizeof *t->index);
    if (format == DELAY_FIXED)
        t->weight_q15 = malloc(n * sizeof *t->weight_q15);
    else
        t->frac = malloc(n * sizeof *t->frac);
    if (!t->index || (!t->weight_q15 && !t->frac))
        goto oom;

    if (t->shared) {
        for (int r = 0; r < t->rows; r++) {
            long partner = mirrored ? sum - r : -1;
            if (!(partner >= 0 && partner < r))
                fill_row(t, t->row_start[r], first_row_dy + r * img->dy_m, scan, g, img);
        }
    }
    return 0;
oom:
    snprintf(err, errlen, "migration: out of memory for a %d x %d delay table", img->ny, img->nz);
    uwb_delay_table_free(t);
    return -1;
}

void uwb_delay_table_fill_trace(struct delay_table *t, const struct uwb_scan *scan,
                                const struct uwb_geometry *g, const struct uwb_image *img, int k)
{
    if (t->shared)
        return;
    t->row_of_trace[k] = 0;
    for (int iy = 0; iy < img->ny; iy++)
        fill_row(t, t->row_start[iy], img->y0_m + iy * img->dy_m - scan->antenna_y_m[k], scan, g, img);
}

void uwb_delay_table_free(struct delay_table *t)
{
    free(t->row_of_trace);
    free(t->row_start);
    free(t->index);
    free(t->frac);
    free(t->weight_q15);
    free(t->delay_row);
    memset(t, 0, sizeof *t);
}
