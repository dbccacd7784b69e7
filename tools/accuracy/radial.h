/* The accuracy report's radial rows (make accuracy): the face's radial
 * change read on the full-wave radial scans against the truth (the shared
 * tank's, clean and over noisy pairs; the fresh draws' bulges, dents and
 * leans, clean), and on the pure shifts, where none must be read. */
#ifndef UWB_ACCURACY_RADIAL_H
#define UWB_ACCURACY_RADIAL_H

#include <stddef.h>
#include <stdio.h>

#include "accuracy/accuracy.h"

struct radial_case {
    const char *name;
    const char *baseline, *current; /* fixture file names */
    /* The truth, typed from the fixtures' truth files: never read in
     * processing. change 0: a pure shift or a lean. */
    double change_m, from_m, to_m;
    double tilt_m;  /* the face's lean as uwbd gives it (top less bottom): 0 but for a lean */
    int disks;      /* disks changed (0: none) */
    int clean_only; /* no noisy rows (the fresh draws: one noiseless replay each) */
    int in_air;     /* the paper's scene: in air a wavelength (150 mm at 2 GHz) spans the face,
                       and a change over 3 disks is sized short (tests/accuracy.md) */
};

struct radial_row {
    int pairs, measured;
    double bias_m, spread_m, worst_m; /* of max_change against the truth */
    double median_sigma_m;
    double median_noise_sigma_m; /* its noise part */
    double within_2sigma;
    double located;    /* share with at_mm inside the changed span +-10 mm (changes only) */
    double sign_right; /* share read with the truth's sign (changes only) */
    double watch_or_worse;
    double alarm;              /* share graded alarm */
    double tilt_worst_m;       /* largest error of the tilts given */
    int tilt_withheld;         /* pairs whose tilt was withheld (a change at the face's end) */
    double tilt_within_2sigma; /* share of the given tilts within 2 sigma of the truth's */
    /* Pairs whose size was withheld as a least value (a change read short
     * by its own flank: uwb_radial_verdict's change_least_m): how many, the
     * share of them with the truth's sign and place, and the last one's
     * least; where none was measured, watch_or_worse is theirs. */
    int least;
    double least_right;
    double least_m;
};

extern const struct radial_case radial_cases[];
extern const int radial_case_count;

/* One case, clean (level NULL) or over `pairs` noisy pairs. 0, or -1 with err. */
int radial_run_case(const char *fixture_dir, const struct radial_case *c, const struct accuracy_level *level,
                    int pairs, unsigned long long seed_base, struct radial_row *row, char *err,
                    size_t errlen);

void radial_print_header(FILE *out);
void radial_print_row(FILE *out, const struct radial_case *c, const struct accuracy_level *level,
                      const struct radial_row *row);

#endif
