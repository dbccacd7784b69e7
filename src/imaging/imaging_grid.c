/* Image grids aligned with the antenna heights, and intensity images. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>

#include "uwb/envelope.h"

int imaging_grid(struct uwb_image *img, const struct uwb_scan *scan, double y_margin_m,
                 double dy_m, double z_lo_m, double z_hi_m, double dz_m,
                 char *err, size_t errlen)
{
    double lo = scan->antenna_y_m[0], hi = lo;
    for (int k = 1; k < scan->positions; k++) {
        if (scan->antenna_y_m[k] < lo)
            lo = scan->antenna_y_m[k];
        if (scan->antenna_y_m[k] > hi)
            hi = scan->antenna_y_m[k];
    }
    double y0 = lo - ceil(y_margin_m / dy_m) * dy_m;
    int ny = (int)floor((hi + y_margin_m - y0) / dy_m + 1e-9) + 1;
    int nz = (int)floor((z_hi_m - z_lo_m) / dz_m + 1e-9) + 1;
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

int imaging_intensity(enum uwb_migration_kind kind, const struct uwb_scan *conditioned,
                      const struct uwb_geometry *g, struct uwb_image *img,
                      char *err, size_t errlen)
{
    if (uwb_migrate(kind, conditioned, g, img, err, errlen) != 0)
        return -1;
    return uwb_envelope_along_z(img, err, errlen);
}
