/* A scan's edges against the baseline's: displacement, its uncertainty, and
 * whether it matters. */
#ifndef UWB_COMPARE_H
#define UWB_COMPARE_H

#include <stddef.h>

#include "uwb/scan.h"
#include "uwb/verdict.h"

struct uwb_compare_options {
    struct uwb_thresholds thresholds;
    struct uwb_thresholds radial_thresholds; /* on the radial change (radial.watch_mm, radial.alarm_mm) */
    double systematic_displacement_m;        /* 1-sigma term: what two scans do not share */
    double least_displacement_uncertainty_m; /* no displacement's 1-sigma is given smaller */
    double axial_sigma_per_shift;            /* the displacement's 1-sigma model term per metre moved */
    double max_uncertainty_m; /* above this 1-sigma a figure is given only when its 95 % interval lies in
                                 one status band (uwb_figure_given) */
    double max_height_uncertainty_m; /* above this 1-sigma the height change is withheld */
    double height_change_per_shift;  /* its 1-sigma term per metre moved: the static scene's share */
    /* its 1-sigma term per metre the face's range moved, times the
     * winding's height over its range: an oil whose wave speed changed
     * (its temperature) focuses the image differently */
    double height_change_per_face_range;
    double baseline_repeatability_m; /* 1-sigma of the baseline's centre from the spread of its commissioning
                                        scans */
};

void uwb_compare_defaults(struct uwb_compare_options *opt);

/* Nonzero when two scans can be compared, else 0 with the difference named. */
int uwb_scans_comparable(const struct uwb_scan *current, const struct uwb_scan *baseline, char *why,
                         size_t whylen);

/* Fill v's status, reason and figures from the edges (baseline may be NULL). */
void uwb_compare_edges(struct uwb_verdict *v, const struct uwb_edges *current,
                       const struct uwb_edges *baseline, const struct uwb_compare_options *opt);

/* What is measured on the two scans together (src/imaging): when valid, the
 * displacement comes from here instead of the difference of the centres. */
struct uwb_pair_figures {
    int valid;
    double displacement_m;
    int noise_measured; /* the two noise terms below replace the per-scan ones */
    double sigma_noise_current_m, sigma_noise_baseline_m;
    /* The shift fitted on each shoulder alone (uwb_measure_shoulder_shifts):
     * upper - lower reads the height change a second way. */
    int has_shoulders;
    double lower_shift_m, upper_shift_m;
    /* Per scan, the noise read on the pair's difference over the noise the
     * scan's own edges were judged with (0: not measured): on its own a scan
     * takes the static scene's echoes for noise. */
    double noise_ratio_current, noise_ratio_baseline;
    /* The face's radial change (uwb/radial.h), and the axial shift fitted
     * again without the changed rows (has_refit): how far it parts from
     * displacement_m is the axial figure's deformation term. */
    int has_radial;                      /* radial filled; else radial.withheld says why */
    struct uwb_radial_verdict radial;    /* its status is graded in compare.c */
    double radial_profile_uncertainty_m; /* the profile's own, at a row: whether it can tell a change */
    int has_refit;
    double refit_displacement_m;
    int deformed_at_end; /* the change reaches the face's end: the axial figure cannot be parted from it */
    /* No axial figure (valid 0): the faces did not match as a whole, yet
     * part of the face still does at a shift, and the radial change was
     * measured there (has_radial): why the axial figure is withheld. */
    char axial_withheld[224];
};

/* The terms of a displacement's 1-sigma uncertainty, all independent. */
struct uwb_uncertainty_terms {
    double noise_current_m; /* each scan's noise carried into the displacement */
    double noise_baseline_m;
    double systematic_m;             /* the floor: what the static scene and sampling leave */
    double baseline_repeatability_m; /* spread of the baseline's commissioning scans (baseline set N) */
    double model_m;       /* the fit's own error, growing with the move (axial_sigma_per_shift x |shift|) */
    double deformation_m; /* the face deformed: the shift with and without its changed rows disagree, or
                             the face leans (a third of the tilt past the watch limit) */
    double least_m;       /* the least the sum may be (uwb_compare_options) */
};

/* Their sum in quadrature, never under least_m: the one place the
 * verdict's sigma is composed. */
double uwb_displacement_uncertainty(const struct uwb_uncertainty_terms *t);

/* The reason the axial figure has on a deformed face: no reading of it is
 * shown to people as a number (issue 44). */
#define UWB_AXIAL_NOT_MEASURED_DEFORMED "axial: not measured while the face is deformed (see radial)"

/* The decision rule for a figure of 1-sigma sigma_m: it is given when
 * sigma_m is at most max_sigma_m, or when its whole 95 % interval
 * (UWB_SIGMAS_95 sigma either side) lies in one status band of t (ok
 * below watch, watch to alarm, alarm from alarm), so the band it is graded
 * in is the band of every value the interval holds. */
int uwb_figure_given(double figure_m, double sigma_m, double max_sigma_m, const struct uwb_thresholds *t);

/* uwb_compare_edges with the pair's own figures (pair may be NULL). */
void uwb_compare_pair(struct uwb_verdict *v, const struct uwb_edges *current,
                      const struct uwb_edges *baseline, const struct uwb_pair_figures *pair,
                      const struct uwb_compare_options *opt);

#endif
