/* One scan, raw traces to edges: the method's steps in order, each a
 * function over one run context (struct analysis_run), one cleanup path.
 *
 *   1. read_scan_basics         geometry, aperture, dominant frequency
 *   2. choose_search_range      the ranges searched for the winding
 *   3. search_for_face          conditioning against the travel's ends,
 *                               coarse image, the strongest falling-off face
 *   4. condition_around_face    conditioning against positions that cannot
 *                               hear the winding where the search put it
 *   5. measure_face             fine image and face profile, the aperture
 *                               made symmetric about the winding (taper
 *                               passes), then a side reflector taken out
 *   6. image_for_display        the envelope image the PNGs draw
 *   7. judge_edges              SNR, edges inside the travel, uncertainties
 */
#include "uwb/analysis.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "imaging_internal.h"
#include "side_reflector.h"

/* ---- tuning constants, each with why it has its value ------------------ */

/* The search image: 5 mm rows and 2 mm range pixels. A winding is at
 * least a few tens of millimetres tall, so it spans many rows, and the
 * search only needs the face's range and rough ends (rough_window widens
 * them by a wavelength): 10 times fewer pixels than the fine grid. */
#define SEARCH_DY_M 0.005
#define SEARCH_DZ_M 0.002
/* Fine image: 1 mm pixels; edges are interpolated to a fraction of this. */
#define FINE_DY_M 0.001
#define FINE_DZ_M 0.001
/* Heights imaged beyond the antenna travel. The face's image fades past
 * the travel's ends, so the profile must run on past them for an edge
 * near an end to be seen falling: 0.1 m for the search and display, 0.15 m
 * for the fine image whose profile the edges are read from. */
#define SEARCH_Y_MARGIN_M 0.1
#define FINE_Y_MARGIN_M 0.15
#define DISPLAY_Y_MARGIN_M 0.1
/* The fine image's range window about the face: +-0.6 wavelength (at least
 * 60 mm) holds about two range cycles of the pulse, so the envelope (a
 * Hilbert transform along range) sees the echo's whole cycle on both sides
 * of the face rather than a cut one. */
#define FACE_WINDOW_WAVELENGTHS 0.6
#define FACE_WINDOW_MIN_M 0.06
/* No image starts nearer than 10 mm: inside the window's own thickness
 * nothing but the direct coupling replies. */
#define NEAREST_RANGE_M 0.01
/* How far each edge of the face may lie from where the drawings put the
 * winding's, as a fraction of the drawings' height: the imaging blurs an
 * absolute edge by a few to 10 mm (edge_uncertainty_mm), a drawing and
 * its installation differ by some more; a plate's image beside the
 * winding is off by half the height and more. */
#define SPAN_TOLERANCE 0.25
/* The display image's pixels: about what a PNG pixel spans (0.8 m of
 * height in 400 px, 0.5 m of range in 255 px, drawn bilinearly); finer
 * costs migration time and shows nothing more. */
#define DISPLAY_DY_M 0.002
#define DISPLAY_DZ_M 0.002
/* The search must span at least 20 mm of range (ten search pixels) to
 * have a face to find. */
#define MIN_SEARCH_SPAN_M 0.02
/* The aperture taper: passes of the taper alone (each re-centres it on the
 * profile the last one gave; the centre's lean shrinks each pass), then at
 * most SIDE_PASSES with a side reflector taken out, stopping once the
 * centre moves less than SIDE_SETTLED_M (20 um, a fiftieth of a pixel). A
 * fixed number of passes bounds the work per scan. */
#define TAPER_PASSES 3
#define SIDE_PASSES 8
#define SIDE_SETTLED_M 0.00002
/* Flat part of the Tukey taper, as a fraction of its half width: positions
 * near the winding's centre keep full weight (the face's echo is strongest
 * there), and the cosine shoulders over the remaining 80 % make the weights
 * move smoothly as the winding moves. */
#define TAPER_FLAT 0.2
/* The symmetry centre compares the profile with its mirror out to 1.5
 * half heights (both shoulders and some of the floor beyond them),
 * searching 20 mm either side of the crossings' midpoint. */
#define SYMMETRY_SPAN 1.5
#define SYMMETRY_SEARCH_M 0.02
/* The point model of a plate leaves up to about half a millimetre when the
 * plate is within 50 mm of an end (measured on the simulator's flush
 * plate, README): a term of the absolute centre. Between two scans it is
 * no separate term: the plate and the winding's place against it are the
 * same at no move, so what is left cancels, and it grows with the move,
 * where the axial model term (compare.c) covers it. */
#define SIDE_REFLECTOR_SYSTEMATIC_M 0.00025
/* The passes before the last read the profile only around the winding:
 * its crossings and its mirror symmetry out to SYMMETRY_SPAN half heights
 * plus SYMMETRY_SEARCH_M. They image those rows only (row by row the
 * pixels are the same as in the full image), with 30 mm to spare for the
 * winding's move between passes and the interpolation's neighbours; the
 * last pass is measured again on every row. */
#define PASS_ROWS_MARGIN_M 0.03
/* SNR reported when the noise reads exactly 0 (a noiseless simulated
 * scan): far above any real scan's and still a finite number for the
 * verdict's JSON. */
#define NOISELESS_SNR_DB 200.0
/* Reflectors measured as the winding at most: the search's pick, then the
 * next ones when the pick's fine profile does not fall off inside the
 * travel or is too weak (a barrier or a plate's edge can pass the coarse
 * test; on the full-wave tank family a plate 20-130 mm in front of the face
 * did in three tanks of eight). Each costs one analysis. */
#define MAX_FACE_TRIES 3

/* The largest |sample| the analysis images (see uwb/analysis.h). */
#define MAX_SAMPLE_MAGNITUDE UWB_ANALYSIS_MAX_SAMPLE_MAGNITUDE

void uwb_analysis_defaults(struct uwb_analysis_options *opt)
{
    memset(opt, 0, sizeof *opt);
    opt->migration = UWB_MIGRATE_FIXED;
    opt->search_z_min_m = 0.15;
    opt->search_z_max_m = 1.6;
    opt->edge_fraction = 0.5;
    opt->min_snr_db = 12.0;
    opt->systematic_edge_m = 0.0005;
    /* How far an absolute edge may lie along its shoulder: the imaging
     * reads it where the profile crosses half its peak, while the disks'
     * ripple, the end rings and a window's focus put the true end
     * elsewhere on the shoulder. The smallest share of the shoulder's
     * width (25-75 % of the peak) that puts every edge of the noiseless
     * 2-D full-wave scans (paper, tank, family, fresh draws) within 2 sigma
     * is 0.040 (fresh s108 -24: 7.8 mm off at 3.6 mm, shoulder 37 mm),
     * rounded up with a margin for other draws. */
    opt->edge_sigma_per_shoulder = 0.05;
    opt->remove_side_reflector = 1;
    opt->display_half_range_m = 0.25;
    uwb_condition_defaults(&opt->condition);
}

/* ---- grids and the face measurement -------------------------------------- */

/* Spacing of the antenna positions (the first two; 0 for a single one). */
static double antenna_step(const struct uwb_scan *scan)
{
    return scan->positions < 2 ? 0.0 : fabs(scan->antenna_y_m[1] - scan->antenna_y_m[0]);
}

/* The largest pixel size not above `target` that divides the antenna step,
 * so rows fall on antenna heights (one shared delay table). */
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
 * image spans the aperture and FINE_Y_MARGIN_M beyond, or, when
 * y_lo_m < y_hi_m, only those heights (rows still on the antenna-aligned
 * grid). plan: a migration plan kept across calls on one grid, or NULL. */
int uwb_face_grid(const struct uwb_scan *conditioned, const struct uwb_geometry *g, double z_centre,
                  double dominant_hz, double y_lo_m, double y_hi_m, struct uwb_image *fine, char *err,
                  size_t errlen)
{
    double wavelength = g->velocity_m_s / dominant_hz;
    double half = fmax(FACE_WINDOW_WAVELENGTHS * wavelength, FACE_WINDOW_MIN_M);
    double z_lo = fmax(z_centre - half, NEAREST_RANGE_M);
    if (uwb_imaging_grid(fine, conditioned, FINE_Y_MARGIN_M, aligned_dy(conditioned, FINE_DY_M), z_lo,
                         z_centre + half, FINE_DZ_M, err, errlen) != 0)
        return -1;
    if (y_lo_m < y_hi_m) {
        /* Keep the grid's rows (aligned with the antennas), only fewer of them. */
        int first = (int)floor((y_lo_m - fine->y0_m) / fine->dy_m);
        int last = (int)ceil((y_hi_m - fine->y0_m) / fine->dy_m);
        first = first < 0 ? 0 : first;
        last = last > fine->ny - 1 ? fine->ny - 1 : last;
        if (last - first >= 8) {
            fine->y0_m += first * fine->dy_m;
            fine->ny = last - first + 1;
        }
    }
    return 0;
}

/* The brightest pixel of range column iz on the face's rows (rows_m, or
 * anywhere when it is 0..0): a plate's edge level with the face, above or
 * below it, may outshine the face in its own column. */
static double face_column_peak(const struct uwb_image *img, int iz, const double rows_m[2], int *row)
{
    if (!(rows_m[0] < rows_m[1]))
        return uwb_image_column_peak(img, iz, row);
    double best = -1.0;
    *row = 0;
    for (int iy = 0; iy < img->ny; iy++) {
        double y = img->y0_m + iy * img->dy_m;
        double v = img->pix[(size_t)iy * img->nz + iz];
        if (y >= rows_m[0] && y <= rows_m[1] && v > best) {
            best = v;
            *row = iy;
        }
    }
    return best < 0.0 ? uwb_image_column_peak(img, iz, row) : best;
}

static int measure_face_rows(const struct uwb_scan *conditioned, const struct uwb_geometry *g,
                             const struct uwb_analysis_options *opt, double z_centre, double dominant_hz,
                             double y_lo_m, double y_hi_m, const double face_rows_m[2],
                             struct uwb_migration_plan *plan, double *z_face,
                             struct uwb_face_profile *profile, struct uwb_face_profile *range,
                             struct profile_edges *edges, char *err, size_t errlen)
{
    double wavelength = g->velocity_m_s / dominant_hz;
    struct uwb_image fine = {0};
    if (uwb_face_grid(conditioned, g, z_centre, dominant_hz, y_lo_m, y_hi_m, &fine, err, errlen) != 0)
        return -1;
    int rc = plan ? uwb_imaging_intensity_planned(plan, opt->migration, conditioned, g, &fine, err, errlen)
                  : uwb_imaging_intensity(opt->migration, conditioned, g, &fine, err, errlen);
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
        double v = face_column_peak(&fine, iz, face_rows_m, &row);
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
        double before = face_column_peak(&fine, best - 1, face_rows_m, &row);
        double after = face_column_peak(&fine, best + 1, face_rows_m, &row);
        double den = before - 2.0 * best_v + after;
        if (den < 0.0)
            offset = 0.5 * (before - after) / den;
        if (fabs(offset) > 0.5)
            offset = 0.0;
    }
    *z_face = fine.z0_m + (best + offset) * fine.dz_m;
    /* The ridge within a quarter wavelength: the face's range cell, wide
     * enough that which 1 mm row the peak fell on does not matter. */
    rc = uwb_face_profile_measure(&fine, *z_face, wavelength / 4, profile, range, err, errlen);
    uwb_image_free(&fine);
    if (rc != 0)
        return -1;
    uwb_profile_edges_within(profile, opt->edge_fraction, face_rows_m[0], face_rows_m[1], edges);
    return 0;
}

static double symmetric_centre(const struct uwb_face_profile *p, const struct profile_edges *e)
{
    double mid = 0.5 * (e->lower_m + e->upper_m);
    return uwb_profile_symmetry_centre(p, mid, SYMMETRY_SPAN * 0.5 * (e->upper_m - e->lower_m),
                                       SYMMETRY_SEARCH_M);
}

/* Weights that make the aperture symmetric about the winding: with more
 * positions on one side, the image of the face leans toward the middle of
 * the travel and a displacement reads short by a few per cent. A Tukey
 * window (flat centre, cosine shoulders) reaching to the nearer end of the
 * travel removes that lean and moves smoothly as the winding moves. */
void uwb_taper_weights(const struct uwb_scan *in, double y_centre, double lo, double hi, double *weight)
{
    double half = fmin(y_centre - lo, hi - y_centre);
    double step = antenna_step(in);
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

/* Where the search says the winding is: its range and rough ends, widened
 * by a wavelength, so conditioning can keep its echoes out of the static
 * reference. */
static void rough_window(const struct uwb_image *coarse, double z_face, const double face_rows_m[2],
                         double wavelength, double ap_lo, double ap_hi, struct uwb_target_window *w)
{
    struct uwb_face_profile p = {0};
    struct profile_edges e = {0};
    char err[128];
    w->y_lo_m = ap_lo;
    w->y_hi_m = ap_hi;
    if (uwb_face_profile_measure(coarse, z_face, 0.0, &p, NULL, err, sizeof err) == 0) {
        uwb_profile_edges_within(&p, 0.5, face_rows_m[0], face_rows_m[1], &e);
        if (e.ok) {
            w->y_lo_m = e.lower_m - wavelength;
            w->y_hi_m = e.upper_m + wavelength;
        }
    }
    free(p.value);
    w->z_near_m = z_face - wavelength;
    w->z_far_m = z_face + wavelength;
}

/* ---- the run ------------------------------------------------------------- */

/* A step's outcome: go on, stop with the analysis done (the winding not
 * established, edges.reason says why), or a hard error (err filled). */
enum step { STEP_NEXT, STEP_DONE, STEP_FAILED };

struct analysis_run {
    const struct uwb_scan *scan;
    const struct uwb_analysis_options *opt;
    struct uwb_analysis *out;
    char *err;
    size_t errlen;
    struct uwb_geometry g;
    double wavelength;
    double z_lo_m, z_hi_m;      /* ranges searched */
    struct uwb_scan prepared;   /* band-passed and aligned: both conditionings start here */
    struct face_candidate face; /* what the search found */
    struct uwb_scan quadrature; /* Hilbert partner of out->conditioned (side reflector fit) */
    struct profile_edges pe;    /* crossings of out->profile */
    double z_face_m;            /* the face's range, sub-pixel */
    /* The last taper pass: the range it was centred on and the reflector
     * it took out, to measure it again on every row (measure_face). */
    int passes;
    double pass_z_centre_m;
    struct side_reflector pass_side;
    /* Reflectors measured before and rejected (passed over by the search),
     * and whether this one was rejected too (worth trying the next). */
    const double *excluded_z_m;
    int n_excluded;
    int face_rejected;
};

static enum step read_scan_basics(struct analysis_run *r)
{
    struct uwb_analysis *out = r->out;
    size_t count = (size_t)r->scan->positions * (size_t)r->scan->samples;
    for (size_t i = 0; i < count; i++)
        if (fabsf(r->scan->data[i]) > MAX_SAMPLE_MAGNITUDE) {
            snprintf(r->err, r->errlen,
                     "sample %zu of position %zu is %g: beyond the %g the analysis can image in single "
                     "precision",
                     i % (size_t)r->scan->samples, i / (size_t)r->scan->samples, (double)r->scan->data[i],
                     MAX_SAMPLE_MAGNITUDE);
            return STEP_FAILED;
        }
    uwb_geometry_from_scan(&r->g, r->scan, r->opt->time_zero_offset_s);
    aperture(r->scan, &out->aperture_lo_m, &out->aperture_hi_m);
    if (r->opt->has_dominant_hz && r->opt->dominant_hz > 0.0)
        out->dominant_hz = r->opt->dominant_hz;
    else if (uwb_dominant_frequency(r->scan, &out->dominant_hz, r->err, r->errlen) != 0)
        return STEP_FAILED;
    r->wavelength = r->g.velocity_m_s / out->dominant_hz;
    out->wavelength_m = r->wavelength;
    return STEP_NEXT;
}

/* The options' target range, else the scan header's, else the options'
 * search range; never past the record's end. */
static enum step choose_search_range(struct analysis_run *r)
{
    const struct uwb_analysis_options *opt = r->opt;
    r->z_lo_m = opt->search_z_min_m;
    r->z_hi_m = opt->search_z_max_m;
    if (opt->has_target_z) {
        r->z_lo_m = opt->target_z_m[0];
        r->z_hi_m = opt->target_z_m[1];
    } else if (r->scan->has_target_z) {
        r->z_lo_m = r->scan->target_z_m[0];
        r->z_hi_m = r->scan->target_z_m[1];
    }
    double t_end = r->g.t0_s + (r->scan->samples - 1) * r->g.dt_s;
    double z_record = 0.5 * r->g.velocity_m_s * t_end;
    if (r->z_hi_m > z_record)
        r->z_hi_m = z_record;
    r->out->search_z_lo_m = r->z_lo_m; /* the B-scan marks it */
    r->out->search_z_hi_m = r->z_hi_m;
    if (r->z_hi_m - r->z_lo_m < MIN_SEARCH_SPAN_M) {
        snprintf(r->out->edges.reason, sizeof r->out->edges.reason,
                 "record too short: it ends at %.3f m range, the search starts at %.3f m", z_record,
                 r->z_lo_m);
        return STEP_DONE;
    }
    return STEP_NEXT;
}

/* Where the face search looks with the drawings' span given: the span
 * widened by the tolerance its ends are held to (uwb_face_within_drawings:
 * a drawing is only so exact); NULL without one. */
static const double *search_span(const struct uwb_analysis_options *opt, double span[2])
{
    if (!opt->has_winding_span)
        return NULL;
    double tolerance = SPAN_TOLERANCE * (opt->winding_span_m[1] - opt->winding_span_m[0]);
    span[0] = opt->winding_span_m[0] - tolerance;
    span[1] = opt->winding_span_m[1] + tolerance;
    return span;
}

/* Stage 1: find the winding, static clutter estimated at the travel's ends.
 * The coarse image stays in r->out->intensity until the display image
 * replaces it, so a failed search still shows what was searched. */
static enum step search_for_face(struct analysis_run *r)
{
    double span[2];
    const struct uwb_analysis_options *opt = r->opt;
    struct uwb_analysis *out = r->out;
    if (uwb_condition_prepare(r->scan, &r->g, &opt->condition, out->dominant_hz, &r->prepared, r->err,
                              r->errlen) != 0)
        return STEP_FAILED;
    struct uwb_scan searched = {0};
    if (uwb_condition_finish(&r->prepared, &r->g, &opt->condition, out->dominant_hz, NULL, &searched, r->err,
                             r->errlen) != 0)
        return STEP_FAILED;
    int rc = uwb_imaging_grid(&out->intensity, &searched, SEARCH_Y_MARGIN_M, aligned_dy(r->scan, SEARCH_DY_M),
                              r->z_lo_m, r->z_hi_m, SEARCH_DZ_M, r->err, r->errlen);
    if (rc == 0)
        rc = uwb_imaging_intensity(opt->migration, &searched, &r->g, &out->intensity, r->err, r->errlen);
    if (rc == 0)
        out->noise_sigma = uwb_noise_sigma(
            &searched, uwb_condition_first_open_sample(&searched, &r->g, &opt->condition, out->dominant_hz));
    out->searched = searched;
    if (rc != 0)
        return STEP_FAILED;
    if (uwb_face_search(&out->intensity, out->aperture_lo_m, out->aperture_hi_m, antenna_step(r->scan),
                        r->wavelength, r->excluded_z_m, r->n_excluded, search_span(r->opt, span), &r->face,
                        out->edges.reason, sizeof out->edges.reason) != 0)
        return STEP_DONE;
    /* Rows the caller gives (another scan's face of the winding) stand
     * over the search's own. */
    if (r->opt->has_face_rows) {
        out->face_rows_m[0] = r->opt->face_rows_m[0];
        out->face_rows_m[1] = r->opt->face_rows_m[1];
        return STEP_NEXT;
    }
    /* Where the search found the face beside a brighter reflector in its
     * own range column (a plate's edge, passed over), later measurements
     * seek the face's peak on the face's rows as the search saw them,
     * widened by a point's blur (its ends are coarse). Elsewhere the
     * profile's peak is its own, and judge_edges names a reflector that
     * outshines the face beyond them. */
    if (!r->face.beside_brighter)
        return STEP_NEXT;
    double blur = uwb_point_blur_m(r->wavelength, 0.5 * (r->face.lower_m + r->face.upper_m), r->face.z_m,
                                   out->aperture_lo_m, out->aperture_hi_m);
    out->face_rows_m[0] = r->face.lower_m - blur;
    out->face_rows_m[1] = r->face.upper_m + blur;
    return STEP_NEXT;
}

/* Stage 2: clutter estimated where the winding cannot be heard. */
static enum step condition_around_face(struct analysis_run *r)
{
    struct uwb_analysis *out = r->out;
    struct uwb_target_window window;
    rough_window(&out->intensity, r->face.z_m, out->face_rows_m, r->wavelength, out->aperture_lo_m,
                 out->aperture_hi_m, &window);
    if (uwb_condition_finish(&r->prepared, &r->g, &r->opt->condition, out->dominant_hz, &window,
                             &out->conditioned, r->err, r->errlen) != 0)
        return STEP_FAILED;
    return STEP_NEXT;
}

/* Measure the face on the conditioned traces as they are (no taper yet). */
static enum step measure_face_plain(struct analysis_run *r)
{
    struct uwb_analysis *out = r->out;
    r->z_face_m = r->face.z_m;
    if (measure_face_rows(&out->conditioned, &r->g, r->opt, r->face.z_m, out->dominant_hz, 0.0, 0.0,
                          out->face_rows_m, NULL, &r->z_face_m, &out->profile, &out->face_range, &r->pe,
                          r->err, r->errlen) != 0)
        return STEP_FAILED;
    out->weight = malloc((size_t)r->scan->positions * sizeof *out->weight);
    if (!out->weight) {
        snprintf(r->err, r->errlen, "out of memory for the aperture taper");
        return STEP_FAILED;
    }
    for (int k = 0; k < r->scan->positions; k++)
        out->weight[k] = 1.0;
    return STEP_NEXT;
}

/* The winding's centre on the current profile, if the taper can be built
 * on it (edges found, centre inside the travel). */
static int usable_centre(const struct analysis_run *r, double *centre)
{
    if (!r->pe.ok)
        return 0;
    *centre = symmetric_centre(&r->out->profile, &r->pe);
    return *centre > r->out->aperture_lo_m && *centre < r->out->aperture_hi_m;
}

/* Whether the rows of out->profile hold all the next pass reads: both
 * crossings found inside them, and the mirror comparison's span about them
 * with room for the interpolation's neighbours. */
static int reads_within(const struct analysis_run *r)
{
    const struct uwb_face_profile *p = &r->out->profile;
    if (!r->pe.ok)
        return 0;
    double mid = 0.5 * (r->pe.lower_m + r->pe.upper_m);
    double span = SYMMETRY_SPAN * 0.5 * (r->pe.upper_m - r->pe.lower_m) + SYMMETRY_SEARCH_M + 3.0 * p->dy_m;
    return mid - span > p->y0_m && mid + span < p->y0_m + (p->n - 1) * p->dy_m;
}

/* Measure again on the conditioned traces with `side` taken out (when found)
 * and out->weight applied: out->measured, out->profile, r->pe, r->z_face_m.
 * A pass (every_row 0) images only the rows about the winding that the next
 * pass reads (PASS_ROWS_MARGIN_M); it takes over `side`. */
static enum step measure_weighted(struct analysis_run *r, struct side_reflector *side, int every_row)
{
    struct uwb_analysis *out = r->out;
    double y_lo = 0.0, y_hi = 0.0, z_centre = r->z_face_m;
    if (every_row) {
        z_centre = r->pass_z_centre_m;
    } else {
        double mid = 0.5 * (r->pe.lower_m + r->pe.upper_m);
        double span =
            SYMMETRY_SPAN * 0.5 * (r->pe.upper_m - r->pe.lower_m) + SYMMETRY_SEARCH_M + PASS_ROWS_MARGIN_M;
        y_lo = mid - span;
        y_hi = mid + span;
        uwb_side_reflector_free(&r->pass_side);
        r->pass_side = *side;
        memset(side, 0, sizeof *side);
        r->pass_z_centre_m = z_centre;
        r->passes++;
    }
    uwb_scan_free(&out->measured);
    free(out->profile.value);
    out->profile.value = NULL;
    free(out->face_range.value);
    out->face_range.value = NULL;
    if (uwb_scan_copy(&out->measured, &out->conditioned, r->err, r->errlen) != 0)
        return STEP_FAILED;
    uwb_side_reflector_remove(&r->pass_side, &r->g, &out->measured);
    apply_weights(&out->measured, out->weight);
    double z_face_before = r->z_face_m;
    if (measure_face_rows(&out->measured, &r->g, r->opt, z_centre, out->dominant_hz, y_lo, y_hi,
                          out->face_rows_m, NULL, &r->z_face_m, &out->profile, &out->face_range, &r->pe,
                          r->err, r->errlen) != 0)
        return STEP_FAILED;
    if (every_row || reads_within(r))
        return STEP_NEXT;
    /* What the next pass reads runs past the rows imaged (the face does not
     * fall off inside them): this pass on every row after all. */
    free(out->profile.value);
    out->profile.value = NULL;
    free(out->face_range.value);
    out->face_range.value = NULL;
    r->z_face_m = z_face_before;
    if (measure_face_rows(&out->measured, &r->g, r->opt, z_centre, out->dominant_hz, 0.0, 0.0,
                          out->face_rows_m, NULL, &r->z_face_m, &out->profile, &out->face_range, &r->pe,
                          r->err, r->errlen) != 0)
        return STEP_FAILED;
    return STEP_NEXT;
}

/* The taper alone, TAPER_PASSES times, each centred on the last profile.
 * Returns STEP_DONE when the profile gave no usable centre (no further
 * passes then). */
static enum step taper_passes(struct analysis_run *r)
{
    for (int pass = 0; pass < TAPER_PASSES; pass++) {
        double centre;
        if (!usable_centre(r, &centre))
            return STEP_DONE;
        uwb_taper_weights(&r->out->conditioned, centre, r->out->aperture_lo_m, r->out->aperture_hi_m,
                          r->out->weight);
        r->out->has_taper = 1;
        r->out->taper_centre_m = centre;
        struct side_reflector none = {0};
        if (measure_weighted(r, &none, 0) != STEP_NEXT)
            return STEP_FAILED;
    }
    return STEP_NEXT;
}

/* Then with a side reflector taken out: its fit reads the row's asymmetry,
 * and a centre still off by the aperture's lean would pass for a
 * reflector, hence after the taper's passes. Each pass's fit absorbs a
 * little of the remaining error, so the centre creeps in: stop once it
 * moves less than SIDE_SETTLED_M, or when no reflector is found. */
static enum step side_reflector_passes(struct analysis_run *r)
{
    struct uwb_analysis *out = r->out;
    if (uwb_quadrature_scan(&out->conditioned, &r->quadrature, r->err, r->errlen) != 0)
        return STEP_FAILED;
    double last_centre = NAN, side_y = NAN;
    for (int pass = 0; pass < SIDE_PASSES; pass++) {
        double centre;
        if (!usable_centre(r, &centre))
            break;
        if (pass > 0 && (isnan(side_y) || fabs(centre - last_centre) < SIDE_SETTLED_M))
            break;
        last_centre = centre;
        uwb_taper_weights(&out->conditioned, centre, out->aperture_lo_m, out->aperture_hi_m, out->weight);
        out->taper_centre_m = centre;
        struct side_reflector side = {0};
        if (uwb_side_reflector_find(&out->conditioned, &r->quadrature, out->weight, &r->g, r->z_face_m,
                                    centre, 0.5 * (r->pe.upper_m - r->pe.lower_m), out->dominant_hz, side_y,
                                    &side, r->err, r->errlen) != 0)
            return STEP_FAILED;
        side_y = side.found ? side.y_m : NAN;
        out->edges.side_reflector = side.found;
        out->edges.side_reflector_y_m = side.found ? side.y_m : 0.0;
        if (measure_weighted(r, &side, 0) != STEP_NEXT)
            return STEP_FAILED;
    }
    return STEP_NEXT;
}

/* Stage 3: the face measured with the aperture made symmetric about it. */
static enum step measure_face(struct analysis_run *r)
{
    if (measure_face_plain(r) != STEP_NEXT)
        return STEP_FAILED;
    enum step rc = taper_passes(r);
    if (rc == STEP_FAILED)
        return STEP_FAILED;
    if (rc == STEP_NEXT && r->opt->remove_side_reflector && side_reflector_passes(r) != STEP_NEXT)
        return STEP_FAILED;
    /* The last pass again, on every row: the profile the edges are read from. */
    if (r->passes > 0 && measure_weighted(r, &r->pass_side, 1) != STEP_NEXT)
        return STEP_FAILED;
    r->out->edges.face_z_m = r->z_face_m;
    return STEP_NEXT;
}

/* The envelope around the face for the PNGs: the conditioned traces, no
 * taper, over the options' range either side of the face. */
static enum step image_for_display(struct analysis_run *r)
{
    const struct uwb_analysis_options *opt = r->opt;
    struct uwb_analysis *out = r->out;
    uwb_image_free(&out->intensity);
    double z_lo = fmax(r->z_face_m - opt->display_half_range_m, NEAREST_RANGE_M);
    if (uwb_imaging_grid(&out->intensity, &out->conditioned, DISPLAY_Y_MARGIN_M,
                         aligned_dy(&out->conditioned, DISPLAY_DY_M), z_lo,
                         r->z_face_m + opt->display_half_range_m, DISPLAY_DZ_M, r->err, r->errlen) != 0 ||
        uwb_imaging_intensity(opt->migration, &out->conditioned, &r->g, &out->intensity, r->err, r->errlen) !=
            0)
        return STEP_FAILED;
    return STEP_NEXT;
}

int uwb_face_within_drawings(const struct uwb_analysis_options *opt, double face_z_m, double lower_m,
                             double upper_m, char *why, size_t whylen)
{
    if (!opt->has_winding_span)
        return 1;
    double tolerance = SPAN_TOLERANCE * (opt->winding_span_m[1] - opt->winding_span_m[0]);
    if (fabs(lower_m - opt->winding_span_m[0]) <= tolerance &&
        fabs(upper_m - opt->winding_span_m[1]) <= tolerance)
        return 1;
    snprintf(
        why, whylen,
        "the face found at %.3f m range spans %.0f..%.0f mm; the drawings put the winding at %.0f..%.0f mm",
        face_z_m, lower_m * 1e3, upper_m * 1e3, opt->winding_span_m[0] * 1e3, opt->winding_span_m[1] * 1e3);
    return 0;
}

static enum step judge_edges(struct analysis_run *r)
{
    const struct uwb_analysis_options *opt = r->opt;
    struct uwb_analysis *out = r->out;
    struct uwb_edges *edges = &out->edges;
    const struct profile_edges *pe = &r->pe;
    double ap_lo = out->aperture_lo_m, ap_hi = out->aperture_hi_m;
    double image_noise = out->noise_sigma * sqrt((double)r->scan->positions);
    edges->snr_db = image_noise > 0.0 ? 20.0 * log10(pe->peak / image_noise) : NOISELESS_SNR_DB;
    /* The search saw the winding's rows; a profile brightest well beyond
     * them at the face's range is another reflector's there (a clamp
     * plate's corner with the winding's end, level with the face), and
     * edges read on it would be that reflector's. */
    double beyond = uwb_point_blur_m(r->wavelength, pe->peak_y_m, r->z_face_m, ap_lo, ap_hi);
    if (pe->peak_y_m < r->face.lower_m - beyond || pe->peak_y_m > r->face.upper_m + beyond) {
        snprintf(edges->reason, sizeof edges->reason,
                 "a reflector level with the face outshines the winding: at %.3f m range the brightest "
                 "height is %.0f mm, beyond the face seen at %.0f..%.0f mm (a plate's corner with the "
                 "winding's end?)",
                 r->z_face_m, pe->peak_y_m * 1e3, r->face.lower_m * 1e3, r->face.upper_m * 1e3);
        r->face_rejected = 1;
        return STEP_DONE;
    }
    if (!pe->ok || pe->lower_m < ap_lo || pe->upper_m > ap_hi) {
        snprintf(edges->reason, sizeof edges->reason,
                 "edge outside the seen aperture: the face at %.3f m does not fall off inside the "
                 "antenna travel %.3f..%.3f m",
                 r->z_face_m, ap_lo, ap_hi);
        r->face_rejected = 1;
        return STEP_DONE;
    }
    /* Each pass takes the brightest column within a quarter wavelength of
     * the last: a face that crept out of the range searched is another
     * reflector's. */
    if (r->z_face_m < r->z_lo_m - r->wavelength / 4 || r->z_face_m > r->z_hi_m + r->wavelength / 4) {
        snprintf(edges->reason, sizeof edges->reason,
                 "the face measured at %.3f m lies outside the range searched, %.3f..%.3f m", r->z_face_m,
                 r->z_lo_m, r->z_hi_m);
        r->face_rejected = 1;
        return STEP_DONE;
    }
    /* What the installer read off the transformer's drawings: a face whose
     * ends lie elsewhere is another reflector's (a clamp plate level with
     * the face, nearer than it: the 3-D family's), whatever else holds. */
    if (!uwb_face_within_drawings(opt, r->z_face_m, pe->lower_m, pe->upper_m, edges->reason,
                                  sizeof edges->reason)) {
        r->face_rejected = 1;
        return STEP_DONE;
    }
    if (edges->snr_db < opt->min_snr_db) {
        /* Where: a refusal names the reflector it judged, like the others. */
        snprintf(edges->reason, sizeof edges->reason,
                 "too little SNR: the face echo at %.3f m range is %.1f dB over the noise, at least %.1f dB "
                 "needed",
                 r->z_face_m, edges->snr_db, opt->min_snr_db);
        r->face_rejected = 1;
        return STEP_DONE;
    }
    /* Noise moves a crossing by noise / slope. An absolute edge also carries
     * a floor for how the imaging blurs it; between two scans of the same
     * installation that blur is common and cancels (see compare.c). */
    double sn_lo = image_noise / fmax(fabs(pe->slope_lower), 1e-30); /* slopes are > 0 at a crossing */
    double sn_hi = image_noise / fmax(fabs(pe->slope_upper), 1e-30);
    double height = pe->upper_m - pe->lower_m;
    edges->found = 1;
    edges->center_m = symmetric_centre(&out->profile, pe);
    edges->lower_m = edges->center_m - 0.5 * height;
    edges->upper_m = edges->center_m + 0.5 * height;
    edges->height_m = height;
    edges->sigma_lower_m = hypot(sn_lo, opt->systematic_edge_m);
    edges->sigma_upper_m = hypot(sn_hi, opt->systematic_edge_m);
    /* The centre is the profile's symmetry point, not the crossings'
     * midpoint: the shoulders' share below is the edges' alone. */
    edges->sigma_center_m = 0.5 * hypot(edges->sigma_lower_m, edges->sigma_upper_m);
    edges->sigma_lower_m = hypot(edges->sigma_lower_m, opt->edge_sigma_per_shoulder *
                                                           uwb_shoulder_width_m(pe->peak, pe->slope_lower));
    edges->sigma_upper_m = hypot(edges->sigma_upper_m, opt->edge_sigma_per_shoulder *
                                                           uwb_shoulder_width_m(pe->peak, pe->slope_upper));
    edges->sigma_center_noise_m = 0.5 * hypot(sn_lo, sn_hi);
    if (edges->side_reflector)
        edges->sigma_center_m = hypot(edges->sigma_center_m, SIDE_REFLECTOR_SYSTEMATIC_M);
    return STEP_DONE;
}

/* One attempt: every step on the search's pick, passing over `excluded`. */
static int analyse_once(const struct uwb_scan *scan, const struct uwb_analysis_options *opt,
                        const double *excluded_z_m, int n_excluded, struct uwb_analysis *out,
                        double *face_z_m, int *rejected, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    struct analysis_run run = {.scan = scan,
                               .opt = opt,
                               .out = out,
                               .err = err,
                               .errlen = errlen,
                               .excluded_z_m = excluded_z_m,
                               .n_excluded = n_excluded};
    static enum step (*const steps[])(struct analysis_run *) = {
        read_scan_basics, choose_search_range, search_for_face, condition_around_face,
        measure_face,     image_for_display,   judge_edges,
    };
    enum step rc = STEP_NEXT;
    for (size_t i = 0; i < sizeof steps / sizeof steps[0] && rc == STEP_NEXT; i++)
        rc = steps[i](&run);
    uwb_scan_free(&run.prepared);
    uwb_scan_free(&run.quadrature);
    uwb_side_reflector_free(&run.pass_side);
    if (rc == STEP_FAILED) {
        uwb_analysis_free(out);
        return -1;
    }
    *face_z_m = run.face.z_m;
    *rejected = run.face_rejected;
    return 0;
}

int uwb_analyse_scan(const struct uwb_scan *scan, const struct uwb_analysis_options *opt,
                     struct uwb_analysis *out, char *err, size_t errlen)
{
    double excluded[MAX_FACE_TRIES];
    /* The first pick's analysis, kept while the next reflectors are tried:
     * when none holds it is the answer, with its conditioned traces and
     * images, which the rig check and the B-scan still need (a later try
     * can stop before conditioning). */
    struct uwb_analysis first;
    memset(&first, 0, sizeof first);
    for (int n = 0; n < MAX_FACE_TRIES; n++) {
        int rejected = 0;
        if (analyse_once(scan, opt, excluded, n, out, &excluded[n], &rejected, err, errlen) != 0) {
            uwb_analysis_free(&first);
            return -1;
        }
        if (out->edges.found || (n == 0 && !rejected)) {
            uwb_analysis_free(&first);
            return 0;
        }
        if (n == 0)
            first = *out;
        else
            uwb_analysis_free(out);
        if (n > 0 && (!rejected || n + 1 == MAX_FACE_TRIES)) {
            /* None held: the first pick (the likeliest), and why it was rejected. */
            *out = first;
            size_t len = strlen(out->edges.reason);
            snprintf(out->edges.reason + len, sizeof out->edges.reason - len, " (and %d more tried)", n);
            return 0;
        }
        memset(out, 0, sizeof *out);
    }
    *out = first;
    return 0;
}

void uwb_analysis_free(struct uwb_analysis *a)
{
    uwb_image_free(&a->intensity);
    free(a->profile.value);
    free(a->face_range.value);
    uwb_scan_free(&a->searched);
    uwb_scan_free(&a->conditioned);
    uwb_scan_free(&a->measured);
    free(a->weight);
    memset(a, 0, sizeof *a);
}

int uwb_analysis_measure_again(const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                               const struct uwb_scan *added, double scale, double y_lo_m, double y_hi_m,
                               struct uwb_migration_plan *plan, struct uwb_face_profile *p,
                               double *z_face_out, char *err, size_t errlen)
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
    int rc = measure_face_rows(&s, &g, opt, a->edges.face_z_m, a->dominant_hz, y_lo_m, y_hi_m, a->face_rows_m,
                               plan, &z_face, p, NULL, &pe, err, errlen);
    uwb_scan_free(&s);
    if (z_face_out)
        *z_face_out = z_face;
    return rc;
}

double uwb_profile_centre(const struct uwb_face_profile *p, double fraction, double guess_m, double search_m)
{
    struct profile_edges e;
    uwb_profile_edges(p, fraction, &e);
    if (!e.ok)
        return NAN;
    return uwb_profile_symmetry_centre(p, isnan(guess_m) ? 0.5 * (e.lower_m + e.upper_m) : guess_m,
                                       SYMMETRY_SPAN * 0.5 * (e.upper_m - e.lower_m),
                                       isnan(guess_m) ? SYMMETRY_SEARCH_M : search_m);
}

int uwb_profile_centre_gradient(const struct uwb_face_profile *p, double fraction, double c_m, double *grad)
{
    struct profile_edges e;
    uwb_profile_edges(p, fraction, &e);
    if (!e.ok)
        return -1;
    return uwb_profile_symmetry_centre_gradient(p, c_m, SYMMETRY_SPAN * 0.5 * (e.upper_m - e.lower_m), grad);
}
