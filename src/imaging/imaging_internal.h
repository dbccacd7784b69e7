/* Steps of the single-scan analysis (private to src/imaging). */
#ifndef UWB_IMAGING_INTERNAL_H
#define UWB_IMAGING_INTERNAL_H

#include <stddef.h>

#include "uwb/analysis.h"
#include "uwb/geometry.h"

/* A grid over y whose rows fall on the antenna heights when the antenna
 * step is a multiple of dy (so migration can share one delay table). */
int uwb_imaging_grid(struct uwb_image *img, const struct uwb_scan *scan, double y_margin_m, double dy_m,
                     double z_lo_m, double z_hi_m, double dz_m, char *err, size_t errlen);

/* Migrate onto img and take the envelope along range. */
int uwb_imaging_intensity(enum uwb_migration_kind kind, const struct uwb_scan *conditioned,
                          const struct uwb_geometry *g, struct uwb_image *img, char *err, size_t errlen);

/* The same with a migration plan kept by the caller: (re)built when it was
 * made for another grid, reused otherwise (repeated images of one grid). */
struct uwb_migration_plan;
int uwb_imaging_intensity_planned(struct uwb_migration_plan *plan, enum uwb_migration_kind kind,
                                  const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                                  struct uwb_image *img, char *err, size_t errlen);

/* The grid a face measurement images on: the face's range window around
 * z_centre, rows on the antenna-aligned 1 mm grid, only y_lo_m..y_hi_m when
 * y_lo_m < y_hi_m (as uwb_analysis_measure_again images). */
int uwb_face_grid(const struct uwb_scan *conditioned, const struct uwb_geometry *g, double z_centre,
                  double dominant_hz, double y_lo_m, double y_hi_m, struct uwb_image *fine, char *err,
                  size_t errlen);

/* The brightest pixel of range column iz: its value, and its row in *row. */
double uwb_image_column_peak(const struct uwb_image *img, int iz, int *row);

struct face_candidate {
    double z_m;
    double peak;
    double lower_m, upper_m; /* where its column falls below half its peak */
    /* Its column's peak was passed over (a point, or outside the drawings'
     * span) and the face is the column's next reflector: a plate's edge
     * outshines it at its own range. */
    int beside_brighter;
};

/* The winding's face range: the strongest reflector in [z_lo, z_hi] whose
 * profile along y falls off before both ends of the antenna travel (at
 * least two antenna steps inside them) and stands taller than the imaging
 * draws a point (wavelength_m: the pulse's, in the medium), passing over
 * the n_excluded ranges (reflectors already measured and rejected;
 * excluded_z_m may be NULL when n_excluded is 0). With span_m (the
 * drawings' lower and upper end of the winding, or NULL) a reflector
 * brightest outside it is passed over, and named when none qualifies.
 * Returns 0 and fills *face, or 1 with reason filled when none qualifies. */
int uwb_face_search(const struct uwb_image *intensity, double aperture_lo_m, double aperture_hi_m,
                    double step_m, double wavelength_m, const double *excluded_z_m, int n_excluded,
                    const double *span_m, struct face_candidate *face, char *reason, size_t reasonlen);

/* How tall delay-and-sum over the antenna travel lo_m..hi_m draws a point
 * at height y_m and range z_m, at half its peak. */
double uwb_point_blur_m(double wavelength_m, double y_m, double z_m, double lo_m, double hi_m);

/* Profile along y at the face: the largest envelope within +-half_width_m
 * of z_face; and, when range is not NULL, the range (m) where each row's
 * largest lies (the face's radial position along the height). */
int uwb_face_profile_measure(const struct uwb_image *intensity, double z_face_m, double half_width_m,
                             struct uwb_face_profile *p, struct uwb_face_profile *range, char *err,
                             size_t errlen);

struct profile_edges {
    int ok;
    double lower_m, upper_m;
    double slope_lower, slope_upper; /* |dP/dy| at the crossings */
    double peak, peak_y_m;
};

/* Lower and upper crossings of fraction*peak, walking out from the peak,
 * interpolated between samples. ok = 0 when a side never drops below it. */
void uwb_profile_edges(const struct uwb_face_profile *p, double fraction, struct profile_edges *e);

/* The same with the peak sought among the rows within lo_m..hi_m only (the
 * crossings still walk out past them); the whole profile when lo_m >= hi_m
 * or no row lies within. */
void uwb_profile_edges_within(const struct uwb_face_profile *p, double fraction, double lo_m, double hi_m,
                              struct profile_edges *e);
/* How far a shoulder that crosses at `slope` (profile units per metre)
 * climbs from 25 to 75 % of `peak`, taken as a straight ramp: on the
 * full-wave scans within a tenth of the profile's own 25-75 % span. */
static inline double uwb_shoulder_width_m(double peak, double slope)
{
    return slope > 0.0 ? 0.5 * peak / slope : 0.0;
}

/* Catmull-Rom weights of v[i-1..i+2] at fraction t of the way from v[i]
 * to v[i+1], and of its slope (per pixel): the interpolation the face
 * profile and the shift fit read between rows, term by term for their
 * gradients. */
static inline void uwb_catmull_rom_weights(double t, double w[4], double dw[4])
{
    w[0] = 0.5 * (-t + 2.0 * t * t - t * t * t);
    w[1] = 1.0 + 0.5 * (-5.0 * t * t + 3.0 * t * t * t);
    w[2] = 0.5 * (t + 4.0 * t * t - 3.0 * t * t * t);
    w[3] = 0.5 * (-t * t + t * t * t);
    dw[0] = 0.5 * (-1.0 + 4.0 * t - 3.0 * t * t);
    dw[1] = 0.5 * (-10.0 * t + 9.0 * t * t);
    dw[2] = 0.5 * (1.0 + 8.0 * t - 9.0 * t * t);
    dw[3] = 0.5 * (-2.0 * t + 3.0 * t * t);
}

/* The profile's centre of mirror symmetry: the c that minimises
 * sum over u in (0, half_span] of (P(c+u) - P(c-u))^2, searched within
 * +-search_m of guess_m. It weighs every point of both shoulders, where a
 * threshold crossing uses one point each, so noise moves it less; and a
 * change of the bump's height or width that keeps it symmetric (pulse
 * timing jitter decorrelating the sum) does not move it at all. */
double uwb_profile_symmetry_centre(const struct uwb_face_profile *p, double guess_m, double half_span_m,
                                   double search_m);

/* How that centre c_m (the asymmetry's minimum) moves with each profile
 * value, added to grad (p->n long): implicit differentiation of the
 * asymmetry's slope. Returns 0, or -1 where it has no curvature. */
int uwb_profile_symmetry_centre_gradient(const struct uwb_face_profile *p, double c_m, double half_span_m,
                                         double *grad);

/* The shift d that best maps base onto cur: cur(y + d) against g * base(y)
 * on the squared envelope, y within +-half_span_m of base_centre_m, searched
 * within 5 mm of guess_m (profile_shift.c says why). NAN when out of memory. */
double uwb_profile_shift_fit(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                             double base_centre_m, double half_span_m, double guess_m);

/* The displacement between a current and a baseline profile of these
 * analyses (profile_shift_fit over the baseline's winding). */
double uwb_analysis_shift(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                          const struct uwb_analysis *base_analysis, double guess_m);

/* How the fit's optimum d moves with each profile value (implicit
 * differentiation of the misfit's stationarity in d): grad_cur[i] =
 * dd/dcur->value[i], grad_base likewise (either may be NULL). Returns 0, or
 * -1 when out of memory or the misfit is not convex at d. */
int uwb_profile_shift_gradient(const struct uwb_face_profile *cur, const struct uwb_face_profile *base,
                               double base_centre_m, double half_span_m, double d_m, double *grad_cur,
                               double *grad_base);

/* The face profile of an analysis measured again on its kept traces plus
 * scale * added (weighted by the analysis' aperture weights): what the same
 * scan with that noise would have given, imaged between y_lo_m and y_hi_m
 * only (the whole aperture when y_lo_m >= y_hi_m). plan: a migration plan
 * the caller keeps across repeated calls (initialised to zeros, freed with
 * uwb_migration_plan_free). Returns 0, or -1 with err filled. */
int uwb_analysis_measure_again(const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                               const struct uwb_scan *added, double scale, double y_lo_m, double y_hi_m,
                               struct uwb_migration_plan *plan, struct uwb_face_profile *p,
                               double *z_face_out, char *err, size_t errlen);

/* The aperture taper (a Tukey window about y_centre reaching to the nearer
 * end of the travel lo..hi) the face measurement weighs positions with. */
void uwb_taper_weights(const struct uwb_scan *in, double y_centre, double lo, double hi, double *weight);

/* The winding's centre on a profile as the analysis reads it (the mirror
 * symmetry about its crossings of fraction * peak); with guess_m not NAN,
 * searched within search_m of it. NAN when the profile does not fall off. */
double uwb_profile_centre(const struct uwb_face_profile *p, double fraction, double guess_m, double search_m);
/* Its gradient at c_m with each profile value, added to grad (the mirror
 * span held at the crossings'). Returns 0, or -1 (edges, curvature). */
int uwb_profile_centre_gradient(const struct uwb_face_profile *p, double fraction, double c_m, double *grad);

/* uwb_condition in its two parts: what depends on the scan alone (band-pass,
 * alignment on the direct coupling), done once per analysis, and what
 * depends on where the winding is (static clutter removal, early gate). */
int uwb_condition_prepare(const struct uwb_scan *in, const struct uwb_geometry *g,
                          const struct uwb_condition_options *opt, double dominant_hz, struct uwb_scan *out,
                          char *err, size_t errlen);
int uwb_condition_finish(const struct uwb_scan *prepared, const struct uwb_geometry *g,
                         const struct uwb_condition_options *opt, double dominant_hz,
                         const struct uwb_target_window *winding, struct uwb_scan *out, char *err,
                         size_t errlen);

/* The gain conditioning's band-pass gives frequency f_hz (0..1). */
double uwb_condition_band_gain(const struct uwb_condition_options *opt, double dominant_hz, double f_hz);

/* The displacement's noise by repeating the fit over `draws` seeded noise
 * draws per scan (what uwb_shift_noise's linear propagation must agree
 * with: the tests' oracle). Returns as uwb_shift_noise. */
int uwb_shift_noise_draws(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                          const struct uwb_analysis_options *opt, double shift_m, int draws,
                          struct uwb_shift_noise *out, char *err, size_t errlen);

#endif
