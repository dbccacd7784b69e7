/* Migration onto one grid, repeated (private to src/imaging): the delay
 * table, a real part of a migration's cost, is built once. The noise
 * re-fits (pair_uncertainty.c) migrate many draws per scan onto one grid. */
#ifndef UWB_MIGRATE_PLAN_H
#define UWB_MIGRATE_PLAN_H

#include <stddef.h>

#include "delay_table.h"
#include "uwb/migrate.h"

struct uwb_migration_plan {
    int planned;
    enum uwb_migration_kind kind;
    int ny, nz; /* the grid the table was built for */
    double y0_m, dy_m, z0_m, dz_m;
    struct delay_table table;
};

/* Build the delay table for this scan's antennas and geometry onto img's
 * grid. Returns 0, or -1 with err filled. */
int uwb_migration_plan_init(struct uwb_migration_plan *p, enum uwb_migration_kind kind,
                            const struct uwb_scan *scan, const struct uwb_geometry *geom,
                            const struct uwb_image *img, char *err, size_t errlen);
/* Migrate scan (same antennas and geometry as planned) onto img (same
 * grid): what uwb_migrate gives. Returns 0, or -1 with err filled. */
int uwb_migration_plan_run(struct uwb_migration_plan *p, const struct uwb_scan *scan,
                           const struct uwb_geometry *geom, struct uwb_image *img, char *err, size_t errlen);
/* 1 if the plan was built for this kind and img's grid. */
int uwb_migration_plan_serves(const struct uwb_migration_plan *p, enum uwb_migration_kind kind,
                              const struct uwb_image *img);
void uwb_migration_plan_free(struct uwb_migration_plan *p);

#endif
