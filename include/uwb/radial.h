/* Radial deformation: how far the winding's face moved toward the antenna
 * (or away) along its height, between the baseline and this scan, once
 * the axial shift is taken out (src/imaging/radial_profile.c). */
#ifndef UWB_RADIAL_H
#define UWB_RADIAL_H

#include "uwb/analysis.h"
#include "uwb/oil_reference.h"

/* At most this many rows (1 mm each) of the face are compared: a winding
 * taller than the antenna travel is not imaged anyway. */
#define UWB_RADIAL_MAX_ROWS 1024

struct uwb_radial {
    /* The figures as the verdict gives them (their status aside, which
     * compare.c grades): measured, else withheld says why; the largest
     * change, signed, and where it lies in this scan's y; where |change|
     * exceeds the watch limit around it (has_span); the line through the
     * face's unchanged rows and its tilt; the shift compared at. The
     * change's 1-sigma holds the two scans' range noise over the changed
     * rows; the model term, the scatter of the unchanged rows about their
     * line (what the imaging leaves of a pure shift), as large as the
     * largest of the profile's stretches reads by chance; the blur's
     * share of a change's size; and, for a change that reaches the face's
     * end (the line then level, the tilt withheld: tilt_withheld says
     * why), how far a sloped line would read it. The tilt's 1-sigma
     * (tilt_uncertainty_m, 0 when withheld) holds the line's slope error
     * from the rows' scatter and noise, a share of the shift, a share of
     * the tilt (the blur), and how far the rows clear of a change lean
     * off the line (its flank). */
    struct uwb_radial_verdict figures;
    /* The change profile over the baseline's face, edge to edge, in the
     * baseline's own y: change_m[i] at y0_m + i dy_m, + toward the antenna,
     * relative to the line through the face's unchanged rows (a change
     * common to the whole face, such as the oil's wave speed with its
     * temperature, is no deformation and is taken out). */
    int n;
    double y0_m, dy_m;
    double change_m[UWB_RADIAL_MAX_ROWS];
    /* The profile's own 1-sigma at a row (noise and model term, neither
     * the chance of the largest nor the size's share): whether the
     * profile can tell a change at all. */
    double uncertainty_profile_m;
    /* Baseline rows (its own y) a second axial fit leaves out: the change
     * past the watch limit, down to a quarter of it (has_excluded). */
    int has_excluded;
    double excluded_lo_m, excluded_hi_m;
    int excluded_at_end; /* ...and they reach the face's end (its edge moved with them) */
};

/* The baseline's face range at its height y less at y + shift_m (0
 * where either is off its image): a ripple held in place by the tank and
 * the aperture shows in a pure shift's offsets as this, times the line's
 * frame_share. */
double uwb_radial_frame_ripple(const struct uwb_face_profile *baseline_range, double y_m, double shift_m);

/* Compare the two analyses' face ranges with the current one shifted back
 * by shift_m. watch_m sets the span reported; noise_rms is the noise per
 * sample of each scan's conditioned traces (the pair's, where measured).
 * r is 8 kB: the caller's, not on a small stack. Returns 0 (measured or
 * not, see r->figures.measured). */
int uwb_radial_measure(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                       double shift_m, double watch_m, double noise_rms, struct uwb_radial *r);

/* The same with the oil's own offset at the face (uwb/oil_reference.h;
 * NULL or not measured: none) as the absolute reference that tells a
 * change over half the face from its complement: of the two levels the
 * rows gather at, the one the oil's offset lies nearer is the unchanged
 * rows', where the two lie more than 4 of its sigma apart, and where that
 * one still lies off the oil's offset, the offset nearest it that a
 * quarter wavelength of rows agrees with; else the level most rows agree
 * with. */
int uwb_radial_measure_referenced(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                                  double shift_m, double watch_m, double noise_rms,
                                  const struct uwb_oil_reference *oil, struct uwb_radial *r);

#endif
