/* One scan from raw traces to the winding's edges: conditioning, migration,
 * envelope, finding the winding's face, edges with uncertainties. */
#ifndef UWB_ANALYSIS_H
#define UWB_ANALYSIS_H

#include <stddef.h>

#include "uwb/condition.h"
#include "uwb/image.h"
#include "uwb/migrate.h"
#include "uwb/scan.h"
#include "uwb/verdict.h"

struct uwb_analysis_options {
    enum uwb_migration_kind migration;
    double time_zero_offset_s; /* calibration added to the header's t0 */
    int has_target_z;          /* overrides the header's target_z_m */
    double target_z_m[2];
    int has_winding_span;     /* where the drawings put the winding's ends (commissioning) */
    double winding_span_m[2]; /* lower, upper: in the scans' own y */
    double search_z_min_m;    /* face search without a target range */
    double search_z_max_m;
    double edge_fraction;           /* edge where the face profile crosses this fraction of its peak */
    double min_snr_db;              /* below this the winding is "not established" */
    double systematic_edge_m;       /* 1-sigma floor of an edge's position */
    double edge_sigma_per_shoulder; /* an edge's 1-sigma term per metre of its shoulder's width */
    int remove_side_reflector;      /* take a compact reflector beside the winding out (clamping plate) */
    int has_dominant_hz;            /* process at dominant_hz (the pair's baseline's), not the scan's own */
    double dominant_hz;
    double display_half_range_m; /* the display image (migrated PNG) spans the face's range +- this (0.25) */
    /* The rows the face's peak is sought on (another scan's face of the
     * same winding, widened by how far it may have moved): a reflector
     * beyond them, level with the face, is not the face's peak. */
    int has_face_rows;
    double face_rows_m[2];
    struct uwb_condition_options condition;
};

void uwb_analysis_defaults(struct uwb_analysis_options *opt);

/* Whether a face's ends (this scan's y) lie where the drawings put the
 * winding's (opt->winding_span_m, within a quarter of its height): 1, or
 * when they are given and do not, 0 with why filled. */
int uwb_face_within_drawings(const struct uwb_analysis_options *opt, double face_z_m, double lower_m,
                             double upper_m, char *why, size_t whylen);

struct uwb_face_profile {
    int n;
    double y0_m, dy_m;
    float *value; /* envelope along y at the face range */
};

/* What was measured, for the verdict and for the images to draw as it is
 * (src/output draws these; it measures nothing again). */
struct uwb_analysis {
    struct uwb_edges edges;          /* incl. the side reflector taken out (side_reflector, _y_m) */
    struct uwb_image intensity;      /* display image: envelope around the face (or the search area) */
    struct uwb_face_profile profile; /* the profile the edges were read from (tapered, reflector out) */
    /* On the same rows, the range (m) of each row's brightest pixel within
     * the profile's window: the face's radial position along the height. */
    struct uwb_face_profile face_range;
    double dominant_hz;
    double wavelength_m;                 /* at the dominant frequency, in the medium */
    double noise_sigma;                  /* per-sample noise of the conditioned traces */
    double aperture_lo_m, aperture_hi_m; /* antenna travel */
    double search_z_lo_m, search_z_hi_m; /* the ranges the face was searched in (0, 0: none yet) */
    /* What the last face measurement ran on, kept so that a comparison can
     * measure again with noise added (src/imaging/pair_uncertainty.c): the
     * conditioned traces, the per-position aperture weights, and the traces
     * the profile was measured on (weighted, a side reflector taken out). */
    struct uwb_scan conditioned;
    struct uwb_scan measured;
    /* The traces the face was searched on: conditioned with the static
     * reference from the travel's ends, before the winding was located.
     * Kept whether or not it was found, so that the rig check can compare
     * two scans conditioned alike when the current one's winding is not
     * found (a scale error smears it: src/evaluate/rig_check.c). */
    struct uwb_scan searched;
    double *weight; /* per position, 0..1 (1 everywhere before any taper pass) */
    /* The centre the taper (weight) was built about: the winding's centre
     * on the pass before, so it moves with the scan's noise too. */
    int has_taper;
    double taper_centre_m;
    /* The rows the face search saw the winding's face on, widened by a
     * point's blur: the profile's peak is sought there, not on a plate's
     * edge level with the face (both 0: anywhere). */
    double face_rows_m[2];
};

/* What the analysis refuses in a scan the format takes (bad input, not a
 * fault): a |sample| over UWB_ANALYSIS_MAX_SAMPLE_MAGNITUDE (it images in
 * single precision, and its intensity squares sums over up to 4096
 * positions: (1e12 x 4096)^2 stays far below FLT_MAX; a digitiser frame
 * carries at most 32767 counts x 1e6 V per count, 3.3e10), or fewer than
 * UWB_ANALYSIS_MIN_SAMPLES per trace (no spectrum). */
#define UWB_ANALYSIS_MAX_SAMPLE_MAGNITUDE 1e12
#define UWB_ANALYSIS_MIN_SAMPLES 2
/* 0 when the analysis can take the scan's data, -1 with the reason, so
 * that a caller tells bad input (exit 65) from an internal fault. */
int uwb_analysis_check_input(const struct uwb_scan *scan, char *err, size_t errlen);

/* Returns 0 when the analysis ran (edges.found tells whether the winding
 * was established, with edges.reason otherwise), -1 on a hard error (out
 * then holds nothing to free). */
int uwb_analyse_scan(const struct uwb_scan *scan, const struct uwb_analysis_options *opt,
                     struct uwb_analysis *out, char *err, size_t errlen);
/* The displacement between two analysed scans of one installation: the
 * shift that best maps the baseline's face profile onto the current one
 * (src/imaging/profile_shift.c). Both analyses must have found the winding.
 * Returns 0; 1 with err saying why when the fit's best lies on the edge of
 * its search (no minimum: the profiles are not one face shifted; *shift_m
 * holds where the search stopped); or -1 with err filled. */
int uwb_measure_shift(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                      double *shift_m, char *err, size_t errlen);

/* The same fit leaving out the baseline's rows skip_lo_m..skip_hi_m (where
 * the face moved in range: src/evaluate/evaluate.c). */
int uwb_measure_shift_skipping(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                               double skip_lo_m, double skip_hi_m, double *shift_m, char *err, size_t errlen);

/* The same fit on each shoulder alone (the baseline's lower and upper edge,
 * a quarter of the height either side): how far each end moved. Their
 * difference is a second reading of the height change, independent of the
 * half-peak crossings. Returns 0, or -1 with err filled. */
int uwb_measure_shoulder_shifts(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                                double *lower_m, double *upper_m, char *err, size_t errlen);

/* The noise of that displacement (src/imaging/pair_uncertainty.c): the noise
 * rms per sample read on the two scans' difference where the winding cannot
 * reply, and the displacement's rms change when noise of that rms is added
 * to each scan in turn (propagated linearly through the fit). measured = 0
 * when the noise could not be read (too few samples before the winding
 * replies). */
struct uwb_shift_noise {
    int measured;
    double noise_rms; /* per sample, conditioned traces, each scan */
    double sigma_current_m, sigma_baseline_m;
};
int uwb_shift_noise(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                    const struct uwb_analysis_options *opt, double shift_m, struct uwb_shift_noise *out,
                    char *err, size_t errlen);

void uwb_analysis_free(struct uwb_analysis *a);

#endif
