/* Delay-and-sum migration: float reference and fixed-point paths. */
#include "uwb/migrate.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "delay_table.h"

const char *uwb_migration_kind_name(enum uwb_migration_kind kind)
{
    return kind == UWB_MIGRATE_FLOAT ? "float" : "fixed";
}

int uwb_migration_kind_parse(const char *name, enum uwb_migration_kind *kind)
{
    if (strcmp(name, "fixed") == 0)
        *kind = UWB_MIGRATE_FIXED;
    else if (strcmp(name, "float") == 0)
        *kind = UWB_MIGRATE_FLOAT;
    else
        return -1;
    return 0;
}

static void sum_trace_float(const struct delay_table *t, const float *trace,
                            const struct uwb_image *img, int k)
{
    for (int iy = 0; iy < img->ny; iy++) {
        size_t row = (size_t)(iy + t->row_of_trace[k]) * t->nz;
        const int32_t *idx = t->index + row;
        const float *frac = t->frac + row;
        float *out = img->pix + (size_t)iy * img->nz;
        for (int iz = 0; iz < img->nz; iz++) {
            float a = trace[idx[iz]], b = trace[idx[iz] + 1];
            out[iz] += a + (b - a) * frac[iz];
        }
    }
}

static int migrate_float(const struct uwb_scan *scan, const struct uwb_geometry *g,
                         struct uwb_image *img, char *err, size_t errlen)
{
    struct delay_table t;
    if (delay_table_plan(&t, scan, g, img, 1, 0, err, errlen) != 0)
        return -1;
    int S = scan->samples;
    float *trace = malloc(((size_t)S + 2) * sizeof *trace);
    if (!trace) {
        delay_table_free(&t);
        snprintf(err, errlen, "migration: out of memory");
        return -1;
    }
    memset(img->pix, 0, (size_t)img->ny * img->nz * sizeof *img->pix);
    for (int k = 0; k < scan->positions; k++) {
        memcpy(trace, scan->data + (size_t)k * S, (size_t)S * sizeof *trace);
        trace[S] = trace[S + 1] = 0.0f;   /* out-of-range delays read zeros */
        delay_table_fill_trace(&t, scan, g, img, k);
        sum_trace_float(&t, trace, img, k);
    }
    free(trace);
    delay_table_free(&t);
    return 0;
}

/* One trace, fixed point: Q15 interpolation (|a|(1-w) + |b|w <= 2^30, no
 * overflow) back to int16 range, then int32 accumulation (4096 traces x 2^15
 * stays inside int32). The right shift of a
 * negative value is arithmetic on every compiler we target (gcc, clang). */
static void sum_trace_fixed(const struct delay_table *t, const int16_t *trace,
                            int32_t *acc, int ny, int nz, int k)
{
    for (int iy = 0; iy < ny; iy++) {
        size_t row = (size_t)(iy + t->row_of_trace[k]) * t->nz;
        const int32_t *idx = t->index + row;
        const int16_t *w = t->weight_q15 + row;
        int32_t *out = acc + (size_t)iy * nz;
        for (int iz = 0; iz < nz; iz++) {
            int32_t a = trace[idx[iz]], b = trace[idx[iz] + 1];
            out[iz] += (a * (32768 - w[iz]) + b * w[iz] + 16384) >> 15;
        }
    }
}

static int migrate_fixed(const struct uwb_scan *scan, const struct uwb_geometry *g,
                         struct uwb_image *img, char *err, size_t errlen)
{
    int S = scan->samples, K = scan->positions;
    size_t npix = (size_t)img->ny * img->nz;
    float peak = 0.0f;
    for (size_t i = 0; i < (size_t)K * S; i++) {
        float a = fabsf(scan->data[i]);
        if (a > peak)
            peak = a;
    }
    memset(img->pix, 0, npix * sizeof *img->pix);
    if (peak == 0.0f)
        return 0;
    /* One scale for the whole scan keeps the traces' relative amplitudes. */
    float scale = 32767.0f / peak;

    struct delay_table t;
    if (delay_table_plan(&t, scan, g, img, 0, 1, err, errlen) != 0)
        return -1;
    int16_t *trace = malloc(((size_t)S + 2) * sizeof *trace);
    int32_t *acc = calloc(npix, sizeof *acc);
    if (!trace || !acc) {
        free(trace);
        free(acc);
        delay_table_free(&t);
        snprintf(err, errlen, "migration: out of memory for a %d x %d image", img->ny, img->nz);
        return -1;
    }
    for (int k = 0; k < K; k++) {
        const float *src = scan->data + (size_t)k * S;
        for (int s = 0; s < S; s++)
            trace[s] = (int16_t)lrintf(src[s] * scale);
        trace[S] = trace[S + 1] = 0;
        delay_table_fill_trace(&t, scan, g, img, k);
        sum_trace_fixed(&t, trace, acc, img->ny, img->nz, k);
    }
    for (size_t i = 0; i < npix; i++)
        img->pix[i] = (float)acc[i] / scale;
    free(trace);
    free(acc);
    delay_table_free(&t);
    return 0;
}

int uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan,
                const struct uwb_geometry *geom, struct uwb_image *img,
                char *err, size_t errlen)
{
    if (!img->pix || img->ny <= 0 || img->nz <= 0) {
        snprintf(err, errlen, "migration: image grid not allocated");
        return -1;
    }
    if (kind == UWB_MIGRATE_FLOAT)
        return migrate_float(scan, geom, img, err, errlen);
    return migrate_fixed(scan, geom, img, err, errlen);
}
