/* Migration figures at one size: fixed point (with its SIMD inner loop and
 * with the portable one), float and the yardstick on the same conditioned
 * scan and grid, runs interleaved so a busy moment on the shared machine
 * hits all alike; and the fast paths' accuracy as an SNR against the
 * yardstick's double-precision image. */
#include "bench.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "uwb/image.h"
#include "uwb/migrate.h"

/* Signal: the reference image's energy; noise: the difference's. */
static double snr_db(const double *ref, const float *test, size_t n)
{
    double signal = 0.0, noise = 0.0;
    for (size_t i = 0; i < n; i++) {
        double d = (double)test[i] - ref[i];
        signal += ref[i] * ref[i];
        noise += d * d;
    }
    return noise > 0.0 ? 10.0 * log10(signal / noise) : INFINITY;
}

static int timed_migrate(enum uwb_migration_kind kind, const struct uwb_scan *s, const struct uwb_geometry *g,
                         struct uwb_image *img, struct bench_series *series, char *err, size_t errlen)
{
    double t0 = uwb_monotonic_s();
    if (uwb_migrate(kind, s, g, img, err, errlen) != 0)
        return -1;
    bench_series_add(series, uwb_monotonic_s() - t0);
    return 0;
}

int bench_migration(const struct bench_case *c, int runs, struct migration_figures *f, char *err,
                    size_t errlen)
{
    if (runs < 1) { /* the SNRs read the yardstick image the runs fill */
        snprintf(err, errlen, "bench: %d runs: at least 1 is needed", runs);
        return -1;
    }
    struct uwb_scan scan;
    if (bench_simulate(c, 0.0, NULL, &scan, err, errlen) != 0)
        return -1;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &scan, 0.0);
    struct uwb_image fixed = {0}, portable = {0}, flt = {0};
    size_t npix = (size_t)c->ny * (size_t)c->nz;
    double *reference = malloc(npix * sizeof *reference);
    int rc = -1;
    if (!reference) {
        snprintf(err, errlen, "bench: out of memory for a %d x %d image", c->ny, c->nz);
        goto done;
    }
    struct uwb_image *images[3] = {&fixed, &portable, &flt};
    for (int i = 0; i < 3; i++) {
        if (uwb_image_alloc(images[i], c->ny, c->nz, err, errlen) != 0)
            goto done;
        images[i]->y0_m = c->y0_m;
        images[i]->dy_m = 0.001;
        images[i]->z0_m = c->z0_m;
        images[i]->dz_m = 0.001;
    }

    struct bench_series t_fixed = {0}, t_portable = {0}, t_float = {0}, t_yard = {0};
    for (int r = 0; r < runs; r++) {
        if (timed_migrate(UWB_MIGRATE_FIXED, &scan, &g, &fixed, &t_fixed, err, errlen) != 0 ||
            timed_migrate(UWB_MIGRATE_FIXED_PORTABLE, &scan, &g, &portable, &t_portable, err, errlen) != 0 ||
            timed_migrate(UWB_MIGRATE_FLOAT, &scan, &g, &flt, &t_float, err, errlen) != 0)
            goto done;
        double t0 = uwb_monotonic_s();
        yardstick_migrate(&scan, &g, c->ny, c->nz, c->y0_m, 0.001, c->z0_m, 0.001, reference);
        bench_series_add(&t_yard, uwb_monotonic_s() - t0);
    }
    f->name = c->name;
    f->pixel_traces = (long long)npix * scan.positions;
    f->fixed_ms = 1e3 * bench_series_median(&t_fixed);
    f->portable_ms = 1e3 * bench_series_median(&t_portable);
    f->portable_best_ms = 1e3 * bench_series_best(&t_portable);
    f->float_ms = 1e3 * bench_series_median(&t_float);
    f->yardstick_ms = 1e3 * bench_series_median(&t_yard);
    f->fixed_best_ms = 1e3 * bench_series_best(&t_fixed);
    f->float_best_ms = 1e3 * bench_series_best(&t_float);
    f->yardstick_best_ms = 1e3 * bench_series_best(&t_yard);
    f->snr_fixed_db = snr_db(reference, fixed.pix, npix);
    f->snr_float_db = snr_db(reference, flt.pix, npix);
    f->snr_portable_db = snr_db(reference, portable.pix, npix);
    rc = 0;
done:
    free(reference);
    uwb_image_free(&fixed);
    uwb_image_free(&portable);
    uwb_image_free(&flt);
    uwb_scan_free(&scan);
    return rc;
}
