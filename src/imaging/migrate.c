/* Delay-and-sum migration: float reference and fixed-point paths. */
#include "uwb/migrate.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "delay_table.h"
#include "migrate_kernel.h"
#include "migrate_plan.h"

const char *uwb_migration_kind_name(enum uwb_migration_kind kind)
{
    switch (kind) {
    case UWB_MIGRATE_FLOAT: return "float";
    case UWB_MIGRATE_FIXED_PORTABLE: return "fixed-portable";
    default: return "fixed";
    }
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

const char *uwb_migration_simd(void)
{
    return uwb_migrate_simd_name();
}

static void sum_row_float(const int32_t *restrict idx, const float *restrict frac,
                          const float *restrict trace, float *restrict out, int nz)
{
    for (int iz = 0; iz < nz; iz++) {
        float a = trace[idx[iz]], b = trace[idx[iz] + 1];
        out[iz] += a + (b - a) * frac[iz];
    }
}

/* A trace of zeros adds nothing to any pixel: the aperture taper weighs the
 * positions beyond its reach 0 (a tenth of the traces on the paper scans),
 * and every face measurement after the first migrates such traces. */
static int silent(const float *trace, int samples)
{
    for (int i = 0; i < samples; i++)
        if (trace[i] != 0.0f)
            return 0;
    return 1;
}

static int migrate_float(struct delay_table *t, const struct uwb_scan *scan, const struct uwb_geometry *g,
                         struct uwb_image *img, char *err, size_t errlen)
{
    int S = scan->samples;
    float *trace = malloc(((size_t)S + 2) * sizeof *trace);
    if (!trace) {
        snprintf(err, errlen, "migration: out of memory");
        return -1;
    }
    memset(img->pix, 0, (size_t)img->ny * img->nz * sizeof *img->pix);
    for (int k = 0; k < scan->positions; k++) {
        if (silent(scan->data + (size_t)k * S, S))
            continue;
        memcpy(trace, scan->data + (size_t)k * S, (size_t)S * sizeof *trace);
        trace[S] = trace[S + 1] = 0.0f; /* out-of-range delays read zeros */
        uwb_delay_table_fill_trace(t, scan, g, img, k);
        for (int iy = 0; iy < img->ny; iy++) {
            size_t row = delay_table_row(t, k, iy);
            sum_row_float(t->index + row, t->frac + row, trace, img->pix + (size_t)iy * img->nz, img->nz);
        }
    }
    free(trace);
    return 0;
}

/* Fixed point: int16 samples on one scale for the whole scan (keeping the
 * traces' relative amplitudes), Q15 interpolation rounded back to sample
 * units, int32 accumulation: each term is at most 32767 in magnitude, so
 * 4096 traces stay far inside int32. */
static int migrate_fixed(int simd, struct delay_table *t, const struct uwb_scan *scan,
                         const struct uwb_geometry *g, struct uwb_image *img, char *err, size_t errlen)
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
    float scale = 32767.0f / peak;

    int16_t *pairs = malloc(((size_t)S + 1) * 2 * sizeof *pairs);
    int32_t *acc = calloc(npix, sizeof *acc);
    if (!pairs || !acc) {
        free(pairs);
        free(acc);
        snprintf(err, errlen, "migration: out of memory for a %d x %d image", img->ny, img->nz);
        return -1;
    }
    void (*sum_row)(const int32_t *restrict, const int16_t *restrict, const int16_t *restrict,
                    int32_t *restrict, int) =
        simd ? uwb_migrate_row_fixed_simd : uwb_migrate_row_fixed_portable;
    for (int k = 0; k < K; k++) {
        if (silent(scan->data + (size_t)k * S, S))
            continue;
        uwb_migrate_fill_pairs(scan->data + (size_t)k * S, S, scale, pairs);
        uwb_delay_table_fill_trace(t, scan, g, img, k);
        for (int iy = 0; iy < img->ny; iy++) {
            size_t row = delay_table_row(t, k, iy);
            sum_row(t->index + row, t->weight_q15 + row, pairs, acc + (size_t)iy * img->nz, img->nz);
        }
    }
    for (size_t i = 0; i < npix; i++)
        img->pix[i] = (float)acc[i] / scale;
    free(pairs);
    free(acc);
    return 0;
}

static enum delay_format format_of(enum uwb_migration_kind kind)
{
    return kind == UWB_MIGRATE_FLOAT ? DELAY_FLOAT : DELAY_FIXED;
}

/* The grid a plan was built for, to tell whether it serves another image. */
static int same_grid(const struct uwb_migration_plan *p, const struct uwb_image *img)
{
    return p->ny == img->ny && p->nz == img->nz && p->y0_m == img->y0_m && p->dy_m == img->dy_m &&
           p->z0_m == img->z0_m && p->dz_m == img->dz_m;
}

int uwb_migration_plan_init(struct uwb_migration_plan *p, enum uwb_migration_kind kind,
                            const struct uwb_scan *scan, const struct uwb_geometry *geom,
                            const struct uwb_image *img, char *err, size_t errlen)
{
    memset(p, 0, sizeof *p);
    if (!img->pix || img->ny <= 0 || img->nz <= 0) {
        snprintf(err, errlen, "migration: image grid not allocated");
        return -1;
    }
    if (uwb_delay_table_plan(&p->table, format_of(kind), scan, geom, img, err, errlen) != 0)
        return -1;
    p->planned = 1;
    p->kind = kind;
    p->ny = img->ny;
    p->nz = img->nz;
    p->y0_m = img->y0_m;
    p->dy_m = img->dy_m;
    p->z0_m = img->z0_m;
    p->dz_m = img->dz_m;
    return 0;
}

int uwb_migration_plan_run(struct uwb_migration_plan *p, const struct uwb_scan *scan,
                           const struct uwb_geometry *geom, struct uwb_image *img, char *err, size_t errlen)
{
    if (!p->planned || !same_grid(p, img)) {
        snprintf(err, errlen, "migration: the plan was made for another grid");
        return -1;
    }
    switch (p->kind) {
    case UWB_MIGRATE_FLOAT: return migrate_float(&p->table, scan, geom, img, err, errlen);
    case UWB_MIGRATE_FIXED_PORTABLE: return migrate_fixed(0, &p->table, scan, geom, img, err, errlen);
    default: return migrate_fixed(1, &p->table, scan, geom, img, err, errlen);
    }
}

int uwb_migration_plan_serves(const struct uwb_migration_plan *p, enum uwb_migration_kind kind,
                              const struct uwb_image *img)
{
    return p->planned && p->kind == kind && same_grid(p, img);
}

void uwb_migration_plan_free(struct uwb_migration_plan *p)
{
    if (p->planned)
        uwb_delay_table_free(&p->table);
    memset(p, 0, sizeof *p);
}

int uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan, const struct uwb_geometry *geom,
                struct uwb_image *img, char *err, size_t errlen)
{
    struct uwb_migration_plan plan;
    if (uwb_migration_plan_init(&plan, kind, scan, geom, img, err, errlen) != 0)
        return -1;
    int rc = uwb_migration_plan_run(&plan, scan, geom, img, err, errlen);
    uwb_migration_plan_free(&plan);
    return rc;
}
