/* One scan, raw traces to edges. */
#include "uwb/analysis.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "imaging_internal.h"
#include "side_reflector.h"

#define COARSE_DY_M 0.005
#define COARSE_DZ_M 0.002
#define FINE_DY_M 0.001
#define FINE_DZ_M 0.001
#define DISPLAY_DY_M 0.001
#define DISPLAY_DZ_M 0.001
#define DISPLAY_HALF_RANGE_M 0.25
#define TAPER_ITERATIONS 3
#define TAPER_FLAT 0.2          /* flat fraction of the aperture taper */
#define SIDE_ITERATIONS 8     /* at most, after the taper's own */
#define SIDE_SETTLED_M 0.00002
#define SIDE_REFLECTOR_SYSTEMATIC_M 0.00025

void uwb_analysis_defaults(struct uwb_analysis_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->migration = UWB_MIGRATE_FIXED;
    opt->search_z_min_m = 0.15;
    opt->search_z_max_m = 1.6;
    opt->edge_fraction = 0.5;
    opt->min_snr_db = 12.0;
    opt->systematic_edge_m = 0.0005;
    opt->remove_side_reflector = 1;
    uwb_condition_defaults(&opt->condition);
}

/* The largest pixel size not above `target` that divides the antenna step,
 * so rows fall on antenna heights (one shared delay table). */
/* Spacing of the antenna positions (the first two; 0 for a single one). */
static double antenna_step(const struct uwb_scan *scan)
{
    return scan->positions < 2 ? 0.0 : fabs(scan->antenna_y_m[1] - scan->antenna_y_m[0]);
}

static double aligned_dy(const struct uwb_scan *scan, double target)
{
    double step = antenna_step(scan);
    if (!(step > 0.0))
        return target;
    double n = ceil(step / target - 1e-9);
    return step / n;
}

static void aperture(const struct uwb_scan *scan, double *lo, double *hi)
{
    *lo = *hi = scan->antenna_y_m[0];
    for (int k = 1; k < scan->positions; k++) {
        if (scan->antenna_y_m[k] < *lo)
            *lo = scan->antenna_y_m[k];
        if (scan->antenna_y_m[k] > *hi)
            *hi = scan->antenna_y_m[k];
    }
}

/* Measure a scan's face: fine image around z_face, profile, edges. The
 * image spans the aperture and 0.15 m beyond, or, when y_lo_m < y_hi_m,
 * only those heights (rows still on the antenna-aligned grid). */
static int measure_face_rows(const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                             const struct uwb_analysis_options *opt, double z_centre,
                             double dominant_hz, double y_lo_m, double y_hi_m,
                             struct migration_plan *plan, double *z_face,
                             struct uwb_face_profile *profile, struct profile_edges *edges,
                             char *err, size_t errlen)
{
    double wavelength = g->velocity_m_s / dominant_hz;
    double half = 0.6 * wavelength > 0.06 ? 0.6 * wavelength : 0.06;   /* two range cycles for the envelope */
    double z_lo = z_centre - half > 0.01 ? z_centre - half : 0.01;
    struct uwb_image fine = {0};
    if (imaging_grid(&fine, conditioned, 0.15, aligned_dy(conditioned, FINE_DY_M), z_lo,
                     z_centre + half, FINE_DZ_M, err, errlen) != 0)
        return -1;
    if (y_lo_m < y_hi_m) {
        /* Keep the grid's rows (aligned with the antennas), only fewer of them. */
        int first = (int)floor((y_lo_m - fine.y0_m) / fine.dy_m);
        int last = (int)ceil((y_hi_m - fine.y0_m) / fine.dy_m);
        first = first < 0 ? 0 : first;
        last = last > fine.ny - 1 ? fine.ny - 1 : last;
        if (last - first >= 8) {
            fine.y0_m += first * fine.dy_m;
            fine.ny = last - first + 1;
        }
    }
    int rc = plan ? imaging_intensity_planned(plan, opt->migration, conditioned, g, &fine, err, errlen)
                  : imaging_intensity(opt->migration, conditioned, g, &fine, err, errlen);
    if (rc != 0) {
        uwb_image_free(&fine);
        return -1;
    }
    /* The face column: the brightest within a range cell of the coarse pick. */
    int lo = (int)floor((z_centre - wavelength / 4 - fine.z0_m) / fine.dz_m);
    int hi = (int)ceil((z_centre + wavelength / 4 - fine.z0_m) / fine.dz_m);
    if (lo < 0)
        lo = 0;
    if (hi > fine.nz - 1)
        hi = fine.nz - 1;
    int best = lo, row;
    double best_v = -1.0;
    for (int iz = lo; iz <= hi; iz++) {
        double v = image_column_peak(&fine, iz, &row);
        if (v > best_v) {
            best_v = v;
            best = iz;
        }
    }
    /* Sub-pixel range of the face (parabola through the column peaks): the
     * side reflector is modelled at this range, and a whole-pixel step of it
     * between two scans would move the model. */
    double offset = 0.0;
    if (best > 0 && best < fine.nz - 1) {
        double before = image_column_peak(&fine, best - 1, &row);
        double after = image_column_peak(&fine, best + 1, &row);
        double den = before - 2.0 * best_v + after;
        if (den < 0.0)
            offset = 0.5 * (before - after) / den;
        if (fabs(offset) > 0.5)
            offset = 0.0;
    }
    *z_face = fine.z0_m + (best + offset) * fine.dz_m;
    /* The ridge within a quarter wavelength: the face's range cell, wide
     * enough that which 1 mm row the peak fell on does not matter. */
    rc = face_profile(&fine, *z_face, wavelength / 4, profile, err, errlen);
    uwb_image_free(&fine);
    if (rc != 0)
        return -1;
    profile_edges(profile, opt->edge_fraction, edges);
    return 0;
}

static int measure_face(const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                        const struct uwb_analysis_options *opt, double z_centre, double dominant_hz,
                        double *z_face, struct uwb_face_profile *profile, struct profile_edges *edges,
                        char *err, size_t errlen)
{
    return measure_face_rows(conditioned, g, opt, z_centre, dominant_hz, 0.0, 0.0, NULL, z_face, profile,
                             edges, err, errlen);
}

#define SYMMETRY_SPAN 1.5         /* mirror comparison out to this times the half height */
#define SYMMETRY_SEARCH_M 0.02

static double symmetric_centre(const struct uwb_face_profile *p, const struct profile_edges *e)
{
    double mid = 0.5 * (e->lower_m + e->upper_m);
    return profile_symmetry_centre(p, mid, SYMMETRY_SPAN * 0.5 * (e->upper_m - e->lower_m),
                                   SYMMETRY_SEARCH_M);
}

/* Weights that make the aperture symmetric about the winding: with more
 * positions on one side, the image of the face leans toward the middle of
 * the travel and a displacement reads short by a few per cent. A Tukey
 * window (flat centre, cosine shoulders) reaching to the nearer end of the
 * travel removes that lean and moves smoothly as the winding moves. */
static void taper_weights(const struct uwb_scan *in, double y_centre, double lo, double hi,
                          double *weight)
{
    double half = fmin(y_centre - lo, hi - y_centre);
    double step = in->positions > 1 ? fabs(in->antenna_y_m[1] - in->antenna_y_m[0]) : 0.0;
    if (half < step)
        half = step;
    for (int k = 0; k < in->positions; k++) {
        double x = fabs(in->antenna_y_m[k] - y_centre) / half, w;
        if (x <= TAPER_FLAT)
            w = 1.0;
        else if (x < 1.0) {
            double c = cos(0.5 * M_PI * (x - TAPER_FLAT) / (1.0 - TAPER_FLAT));
            w = c * c;
        } else
            w = 0.0;
        weight[k] = w;
    }
}

static void apply_weights(struct uwb_scan *s, const double *weight)
{
    for (int k = 0; k < s->positions; k++) {
        float *tr = s->data + (size_t)k * s->samples;
        for (int i = 0; i < s->samples; i++)
            tr[i] *= (float)weight[k];
    }
}

static int display_image(const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                         const struct uwb_analysis_options *opt, double z_lo, double z_hi,
                         struct uwb_image *img, char *err, size_t errlen)
{
    if (imaging_grid(img, conditioned, 0.1, aligned_dy(conditioned, DISPLAY_DY_M), z_lo, z_hi,
                     DISPLAY_DZ_M, err, errlen) != 0)
        return -1;
    return imaging_intensity(opt->migration, conditioned, g, img, err, errlen);
}

/* Where the search says the winding is: its range and rough ends, widened
 * by a wavelength, so conditioning can keep its echoes out of the static
 * reference. */
static void rough_window(const struct uwb_image *coarse, double z_face, double wavelength,
                         double ap_lo, double ap_hi, struct uwb_target_window *w)
{
    struct uwb_face_profile p = {0};
    struct profile_edges e = {0};
    char err[128];
    w->y_lo_m = ap_lo;
    w->y_hi_m = ap_hi;
    if (face_profile(coarse, z_face, 0.0, &p, err, sizeof err) == 0) {
        profile_edges(&p, 0.5, &e);
        if (e.ok) {
            w->y_lo_m = e.lower_m - wavelength;
            w->y_hi_m = e.upper_m + wavelength;
        }
    }
    free(p.value);
    w->z_near_m = z_face - wavelength;
    w->z_far_m = z_face + wavelength;
}

static void finish_free(struct uwb_scan *a, struct uwb_scan *b, struct uwb_image *c)
{
    if (a)
        uwb_scan_free(a);
    if (b)
        uwb_scan_free(b);
    if (c)
        uwb_image_free(c);
}

int uwb_analyse_scan(const struct uwb_scan *scan, const struct uwb_analysis_options *opt,
                     struct uwb_analysis *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    struct uwb_edges *edges = &out->edges;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, scan, opt->time_zero_offset_s);
    aperture(scan, &out->aperture_lo_m, &out->aperture_hi_m);
    double ap_lo = out->aperture_lo_m, ap_hi = out->aperture_hi_m;

    if (uwb_dominant_frequency(scan, &out->dominant_hz, err, errlen) != 0)
        return -1;
    double wavelength = g.velocity_m_s / out->dominant_hz;

    double z_lo = opt->search_z_min_m, z_hi = opt->search_z_max_m;
    if (opt->has_target_z) {
        z_lo = opt->target_z_m[0];
        z_hi = opt->target_z_m[1];
    } else if (scan->has_target_z) {
        z_lo = scan->target_z_m[0];
        z_hi = scan->target_z_m[1];
    }
    double t_end = g.t0_s + (scan->samples - 1) * g.dt_s;
    double z_record = 0.5 * g.velocity_m_s * t_end;
    if (z_hi > z_record)
        z_hi = z_record;
    if (z_hi - z_lo < 0.02) {
        snprintf(edges->reason, sizeof edges->reason,
                 "record too short: it ends at %.3f m range, the search starts at %.3f m", z_record, z_lo);
        return 0;
    }

    /* Stage 1: find the winding, static clutter estimated at the travel's ends. */
    struct uwb_scan searched = {0};
    if (uwb_condition(scan, &g, &opt->condition, out->dominant_hz, NULL, &searched, err, errlen) != 0)
        return -1;
    struct uwb_image coarse = {0};
    if (imaging_grid(&coarse, &searched, 0.1, aligned_dy(scan, COARSE_DY_M), z_lo, z_hi,
                     COARSE_DZ_M, err, errlen) != 0 ||
        imaging_intensity(opt->migration, &searched, &g, &coarse, err, errlen) != 0) {
        finish_free(&searched, NULL, &coarse);
        return -1;
    }
    out->noise_sigma = uwb_noise_sigma(
        &searched, uwb_condition_first_open_sample(&searched, &g, &opt->condition, out->dominant_hz));
    uwb_scan_free(&searched);
    struct face_candidate face;
    if (face_search(&coarse, ap_lo, ap_hi, antenna_step(scan), &face, edges->reason,
                    sizeof edges->reason) != 0) {
        out->intensity = coarse;   /* show what was searched */
        return 0;
    }

    /* Stage 2: clutter estimated where the winding cannot be heard. */
    struct uwb_target_window window;
    rough_window(&coarse, face.z_m, wavelength, ap_lo, ap_hi, &window);
    uwb_image_free(&coarse);
    struct uwb_scan conditioned = {0};
    if (uwb_condition(scan, &g, &opt->condition, out->dominant_hz, &window, &conditioned, err,
                      errlen) != 0)
        return -1;

    /* Stage 3: measure the face with the aperture made symmetric about it. */
    struct profile_edges pe;
    double z_face = face.z_m;
    struct uwb_face_profile profile = {0};
    if (measure_face(&conditioned, &g, opt, face.z_m, out->dominant_hz, &z_face, &profile, &pe,
                     err, errlen) != 0) {
        finish_free(&conditioned, NULL, NULL);
        return -1;
    }
    double *weight = malloc((size_t)scan->positions * sizeof *weight);
    struct uwb_scan quadrature = {0};
    if (!weight || (opt->remove_side_reflector &&
                    quadrature_scan(&conditioned, &quadrature, err, errlen) != 0)) {
        if (!weight)
            snprintf(err, errlen, "out of memory for the aperture taper");
        free(weight);
        free(profile.value);
        finish_free(&conditioned, NULL, NULL);
        return -1;
    }
    /* First the taper alone, until the centre settles; then with a side
     * reflector taken out: its fit reads the row's asymmetry, and a centre
     * still off by the aperture's lean would pass for a reflector. Each
     * pass's fit absorbs a little of the remaining error, so the centre
     * creeps in: stop once it moves less than SIDE_SETTLED_M. */
    int iterations = TAPER_ITERATIONS + (opt->remove_side_reflector ? SIDE_ITERATIONS : 0);
    double last_centre = NAN, side_y = NAN;
    for (int it = 0; it < iterations && pe.ok; it++) {
        double centre = symmetric_centre(&profile, &pe);
        if (centre <= ap_lo || centre >= ap_hi)
            break;
        int side_pass = it >= TAPER_ITERATIONS;
        if (side_pass && it > TAPER_ITERATIONS && (isnan(side_y) ||
                                                   fabs(centre - last_centre) < SIDE_SETTLED_M))
            break;
        last_centre = centre;
        taper_weights(&conditioned, centre, ap_lo, ap_hi, weight);
        struct side_reflector side = {0};
        if (side_pass) {
            if (side_reflector_find(&conditioned, &quadrature, weight, &g, z_face, centre,
                                    0.5 * (pe.upper_m - pe.lower_m), out->dominant_hz, side_y,
                                    &side, err, errlen) != 0) {
                free(weight);
                free(profile.value);
                finish_free(&conditioned, &quadrature, NULL);
                return -1;
            }
            side_y = side.found ? side.y_m : NAN;
            edges->side_reflector = side.found;
            edges->side_reflector_y_m = side.found ? side.y_m : 0.0;
        }
        struct uwb_scan tapered = {0};
        free(profile.value);
        profile.value = NULL;
        int rc = uwb_scan_copy(&tapered, &conditioned, err, errlen);
        if (rc == 0) {
            side_reflector_remove(&side, &g, &tapered);
            apply_weights(&tapered, weight);
            rc = measure_face(&tapered, &g, opt, z_face, out->dominant_hz, &z_face, &profile, &pe,
                              err, errlen);
        }
        side_reflector_free(&side);
        uwb_scan_free(&out->measured);
        out->measured = tapered;
        if (rc != 0) {
            uwb_scan_free(&out->measured);
            free(weight);
            free(profile.value);
            finish_free(&conditioned, &quadrature, NULL);
            return -1;
        }
    }
    out->weight = weight;
    uwb_scan_free(&quadrature);
    out->profile = profile;
    edges->face_z_m = z_face;
    double dlo = z_face - DISPLAY_HALF_RANGE_M > 0.01 ? z_face - DISPLAY_HALF_RANGE_M : 0.01;
    int rc = display_image(&conditioned, &g, opt, dlo, z_face + DISPLAY_HALF_RANGE_M,
                           &out->intensity, err, errlen);
    out->conditioned = conditioned;
    if (rc != 0)
        return -1;

    double image_noise = out->noise_sigma * sqrt((double)scan->positions);
    edges->snr_db = image_noise > 0.0 ? 20.0 * log10(pe.peak / image_noise) : 200.0;
    if (!pe.ok || pe.lower_m < ap_lo || pe.upper_m > ap_hi) {
        snprintf(edges->reason, sizeof edges->reason,
                 "edge outside the seen aperture: the face at %.3f m does not fall off inside the "
                 "antenna travel %.3f..%.3f m", z_face, ap_lo, ap_hi);
        return 0;
    }
    if (edges->snr_db < opt->min_snr_db) {
        snprintf(edges->reason, sizeof edges->reason,
                 "too little SNR: face echo %.1f dB over the noise, at least %.1f dB needed",
                 edges->snr_db, opt->min_snr_db);
        return 0;
    }

    /* Noise moves a crossing by noise / slope. An absolute edge also carries
     * a floor for how the imaging blurs it; between two scans of the same
     * installation that blur is common and cancels (see compare.c). */
    double sn_lo = image_noise / fmax(fabs(pe.slope_lower), 1e-30);   /* slopes are > 0 at a crossing */
    double sn_hi = image_noise / fmax(fabs(pe.slope_upper), 1e-30);
    edges->found = 1;
    edges->lower_m = pe.lower_m;
    edges->upper_m = pe.upper_m;
    edges->center_m = symmetric_centre(&profile, &pe);
    edges->lower_m = edges->center_m - 0.5 * (pe.upper_m - pe.lower_m);
    edges->upper_m = edges->center_m + 0.5 * (pe.upper_m - pe.lower_m);
    edges->height_m = pe.upper_m - pe.lower_m;
    edges->sigma_lower_m = hypot(sn_lo, opt->systematic_edge_m);
    edges->sigma_upper_m = hypot(sn_hi, opt->systematic_edge_m);
    edges->sigma_center_m = 0.5 * hypot(edges->sigma_lower_m, edges->sigma_upper_m);
    edges->sigma_center_noise_m = 0.5 * hypot(sn_lo, sn_hi);
    /* The point model of a plate leaves up to about half a millimetre when
     * the plate is within 50 mm of an end (measured on the simulator's flush
     * plate, README); unlike blur, that does not cancel between two scans. */
    if (edges->side_reflector) {
        edges->sigma_center_clutter_m = SIDE_REFLECTOR_SYSTEMATIC_M;
        edges->sigma_center_m = hypot(edges->sigma_center_m, SIDE_REFLECTOR_SYSTEMATIC_M);
    }
    return 0;
}

void uwb_analysis_free(struct uwb_analysis *a)
{
    uwb_image_free(&a->intensity);
    free(a->profile.value);
    uwb_scan_free(&a->conditioned);
    uwb_scan_free(&a->measured);
    free(a->weight);
    memset(a, 0, sizeof *a);
}

int analysis_measure_again(const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                           const struct uwb_scan *added, double scale, double y_lo_m, double y_hi_m,
                           struct migration_plan *plan, struct uwb_face_profile *p, char *err,
                           size_t errlen)
{
    memset(p, 0, sizeof *p);
    if (!a->measured.data || !a->weight || added->positions != a->measured.positions ||
        added->samples != a->measured.samples) {
        snprintf(err, errlen, "measure again: the analysis kept no measured traces of this shape");
        return -1;
    }
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &a->measured, opt->time_zero_offset_s);
    struct uwb_scan s = {0};
    if (uwb_scan_copy(&s, &a->measured, err, errlen) != 0)
        return -1;
    for (int k = 0; k < s.positions; k++) {
        float *tr = s.data + (size_t)k * s.samples;
        const float *n = added->data + (size_t)k * s.samples;
        float w = (float)(scale * a->weight[k]);
        for (int i = 0; i < s.samples; i++)
            tr[i] += w * n[i];
    }
    double z_face = a->edges.face_z_m;
    struct profile_edges pe;
    int rc = measure_face_rows(&s, &g, opt, a->edges.face_z_m, a->dominant_hz, y_lo_m, y_hi_m, plan,
                               &z_face, p, &pe, err, errlen);
    uwb_scan_free(&s);
    return rc;
}
