/* The accuracy report's 3-D rows (make accuracy): each moved scan of the
 * shared 3-D tanks (gprMax 3-D, 5 mm cells) replayed clean against its own
 * tank's intact scan, without and with the drawings' winding span
 * (--winding-span), its figure set against the truth, or the reason it is
 * withheld. */
#ifndef UWB_ACCURACY_TANK3D_H
#define UWB_ACCURACY_TANK3D_H

#include <stddef.h>
#include <stdio.h>

struct tank3d_case {
    const char *name;
    int fresh; /* 0: a shared tank (../shared/data), 1: one drawn here (tools/fdtd/draw_tank3d.py) */
    const char *baseline, *current; /* fixture file names */
    /* The truth, typed from the fixtures' truth files (never read in
     * processing): the centre's move (the shift plus half the height
     * change), and the baseline's winding span, what the drawings say. */
    double centre_move_m;
    double span_m[2];
};

struct tank3d_row {
    int with_span;
    int has_figure; /* an axial figure given (the verdict record's) */
    double figure_m, sigma_m;
    int within_2sigma;
    const char *status; /* the verdict's status word */
    int has_radial;
    double radial_m, radial_at_m;
    char why[256]; /* the verdict's reason, or why the axial figure is withheld */
};

extern const struct tank3d_case tank3d_cases[];
extern const int tank3d_case_count;

/* One case clean, the drawings' span given or not. 0, or -1 with err. */
int tank3d_run_case(const char *fixture_dir, const struct tank3d_case *c, int with_span,
                    struct tank3d_row *row, char *err, size_t errlen);

void tank3d_print_header(FILE *out);
void tank3d_print_row(FILE *out, const struct tank3d_case *c, const struct tank3d_row *row);
/* The closing count: moved scans with a figure within 2 sigma, per setting,
 * of the shared tanks (fresh 0) or of those drawn here (fresh 1). */
void tank3d_print_count(FILE *out, int fresh, int within_without, int within_with, int cases);

#endif
