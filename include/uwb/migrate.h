/* Time-arrival (delay-and-sum) migration, paper eq. 4-5 in bistatic form:
 * every pixel sums, over antenna positions, the trace value at the pixel's
 * two-way delay, interpolated linearly between samples.
 *
 * Two implementations of the same function: a float reference and the
 * fixed-point path the appliance uses (int16 samples, integer delay tables
 * with Q15 fractional weights, int32 accumulation). */
#ifndef UWB_MIGRATE_H
#define UWB_MIGRATE_H

#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/image.h"
#include "uwb/scan.h"

enum uwb_migration_kind {
    UWB_MIGRATE_FIXED = 0, /* default on the appliance */
    UWB_MIGRATE_FLOAT = 1,
    /* The fixed-point path with its portable C inner loop instead of the
     * SIMD one (SSE2 / NEON, when compiled in): the same image bit for bit,
     * kept so tests and the bench can run both. */
    UWB_MIGRATE_FIXED_PORTABLE = 2
};

/* Migrate `scan` (already conditioned) onto the grid described by `img`
 * (ny, nz, y0_m, dy_m, z0_m, dz_m set; pix allocated). */
int uwb_migrate(enum uwb_migration_kind kind, const struct uwb_scan *scan, const struct uwb_geometry *geom,
                struct uwb_image *img, char *err, size_t errlen);

/* "fixed", "float", "fixed-portable"; parse accepts the first two (the
 * command line's choices). */
const char *uwb_migration_kind_name(enum uwb_migration_kind kind);
int uwb_migration_kind_parse(const char *name, enum uwb_migration_kind *kind);

/* The SIMD instruction set of UWB_MIGRATE_FIXED's inner loop in this build:
 * "SSE2", "NEON", or "none" (then it is the portable loop). */
const char *uwb_migration_simd(void);

#endif
