/* Image grids aligned with the antenna heights, and intensity images. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>

#include "migrate_plan.h"
#include "uwb/envelope.h"

/* The most pixels along either side of an imaging grid: 5 m of travel (the
 * scan file's limit) plus margins at 0.1 mm, or 10 m of range at 1 mm, are
 * well inside it. Computed in double and checked before any conversion to
 * int, so a degenerate pixel size or span is a message, not undefined
 * behaviour. */
#define IMAGING_GRID_MAX_SIDE 200000

static int grid_side(double span_m, double pixel_m, int *n)
{
    if (!(pixel_m > 0.0) || !isfinite(span_m) || !isfinite(pixel_m))
        return -1;
    double cells = floor(span_m / pixel_m + 1e-9) + 1.0;
    if (!(cells >= 0.0 && cells <= IMAGING_GRID_MAX_SIDE))
        return -1;
    *n = (int)cells;
    return 0;
}

int uwb_imaging_grid(struct uwb_image *img, const struct uwb_scan *scan, double y_margin_m, double dy_m,
                     double z_lo_m, double z_hi_m, double dz_m, char *err, size_t errlen)
{
    double lo = scan->antenna_y_m[0], hi = lo;
    for (int k = 1; k < scan->positions; k++) {
        if (scan->antenna_y_m[k] < lo)
            lo = scan->antenna_y_m[k];
        if (scan->antenna_y_m[k] > hi)
            hi = scan->antenna_y_m[k];
    }
    double y0 = lo - ceil(y_margin_m / dy_m) * dy_m;
    int ny = 0, nz = 0;
    if (grid_side(hi + y_margin_m - y0, dy_m, &ny) != 0 || grid_side(z_hi_m - z_lo_m, dz_m, &nz) != 0) {
        snprintf(err, errlen,
                 "imaging: a grid over %g m x %g m in %g m x %g m pixels is not at most %d pixels a side",
                 hi + y_margin_m - y0, z_hi_m - z_lo_m, dy_m, dz_m, IMAGING_GRID_MAX_SIDE);
        return -1;
    }
    if (ny < 2 || nz < 8) {
        snprintf(err, errlen, "imaging: grid of %d x %d pixels is too small", ny, nz);
        return -1;
    }
    if (uwb_image_alloc(img, ny, nz, err, errlen) != 0)
        return -1;
    img->y0_m = y0;
    img->dy_m = dy_m;
    img->z0_m = z_lo_m;
    img->dz_m = dz_m;
    return 0;
}

int uwb_imaging_intensity(enum uwb_migration_kind kind, const struct uwb_scan *conditioned,
                          const struct uwb_geometry *g, struct uwb_image *img, char *err, size_t errlen)
{
    if (uwb_migrate(kind, conditioned, g, img, err, errlen) != 0)
        return -1;
    return uwb_envelope_along_z(img, err, errlen);
}

int uwb_imaging_intensity_planned(struct uwb_migration_plan *plan, enum uwb_migration_kind kind,
                                  const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                                  struct uwb_image *img, char *err, size_t errlen)
{
    if (!uwb_migration_plan_serves(plan, kind, img)) {
        uwb_migration_plan_free(plan);
        if (uwb_migration_plan_init(plan, kind, conditioned, g, img, err, errlen) != 0)
            return -1;
    }
    if (uwb_migration_plan_run(plan, conditioned, g, img, err, errlen) != 0)
        return -1;
    return uwb_envelope_along_z(img, err, errlen);
}
