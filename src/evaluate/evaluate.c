/* The one path from a scan (and a baseline with what was recorded with it)
 * to a verdict; see uwb/evaluate.h. */
#include "uwb/evaluate.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/direct_coupling.h"
#include "uwb/radial.h"
#include "uwb/rig_check.h"

void uwb_evaluate_defaults(struct uwb_evaluate_options *opt)
{
    uwb_analysis_defaults(&opt->analysis);
    uwb_compare_defaults(&opt->compare);
    /* The pulse leaves the transmitter at t = 0 and crosses the few
     * centimetres between the antennas in well under 1 ns: 2 ns holds the
     * direct coupling and ends before any echo from inside the tank. */
    opt->direct_coupling.window_end_s = 2e-9;
    /* Several times its spread from scan to scan on one rig (within 3 ps on
     * the simulated tank, test_direct_coupling), far under what a changed
     * cable moves it (5 cm more coax: about 240 ps). */
    opt->direct_coupling.tolerance_s = 20e-12;
}

static void copy_text(char *dst, size_t n, const char *src)
{
    snprintf(dst, n, "%s", src ? src : "");
}

#define SAME_REFLECTOR_M 0.02

static int one_side_reflector(const struct uwb_edges *a, const struct uwb_edges *b)
{
    return a->side_reflector &&
           (!b->side_reflector || fabs(a->side_reflector_y_m - b->side_reflector_y_m) > SAME_REFLECTOR_M);
}

/* A reflector beside the winding (a clamping plate) belongs to the static
 * scene: both scans see it, at one height. Taken out of one scan and not the
 * other, its removal would stand for a movement of the winding (on the
 * full-wave tank scans the fit found a static echo 190 mm above the winding
 * in some scans and not in the baseline, and +4 mm read 3.70). So a scan whose
 * reflector the other scan does not share is measured again without the
 * removal. */
static int keep_common_side_reflector(const struct uwb_scan *cur, const struct uwb_scan *base,
                                      const struct uwb_analysis_options *cur_opt,
                                      const struct uwb_analysis_options *base_opt, struct uwb_analysis *ca,
                                      struct uwb_analysis *ba, char *err, size_t errlen)
{
    if (!ca->edges.found || !ba->edges.found)
        return 0;
    int redo_cur = one_side_reflector(&ca->edges, &ba->edges);
    int redo_base = one_side_reflector(&ba->edges, &ca->edges);
    struct uwb_analysis again;
    if (redo_cur) {
        struct uwb_analysis_options plain = *cur_opt;
        plain.remove_side_reflector = 0;
        if (uwb_analyse_scan(cur, &plain, &again, err, errlen) != 0)
            return -1;
        uwb_analysis_free(ca);
        *ca = again;
    }
    if (redo_base) {
        struct uwb_analysis_options plain = *base_opt;
        plain.remove_side_reflector = 0;
        if (uwb_analyse_scan(base, &plain, &again, err, errlen) != 0)
            return -1;
        uwb_analysis_free(ba);
        *ba = again;
    }
    return 0;
}

/* Both scans must describe one reflector: the faces within this many
 * wavelengths in range (a quarter: the fine measurement's own range cell,
 * far more than a radial bulge moves the face), and searched again within
 * half a wavelength of the other scan's face when they are not. A plate's
 * edge or a barrier is 20-130 mm from the face in the full-wave tank family,
 * 0.2-1.5 wavelengths. */
#define SAME_FACE_WAVELENGTHS 0.25
#define SEARCH_NEAR_WAVELENGTHS 0.5
/* ...and heights within this fraction of each other: on pure shifts the
 * height read changes by up to 3.1 % (full-wave tank, +30 mm), a squeezed
 * spacer by 1.3-3 % in the full-wave family; a face read on another
 * reflector differs by a third (a plate below the winding, 3-D family). */
#define SAME_HEIGHT_FRACTION 0.10

static double face_wavelength(const struct uwb_analysis *a, const struct uwb_scan *scan)
{
    return a->dominant_hz > 0.0 ? 299792458.0 / sqrt(scan->eps_r) / a->dominant_hz : 0.1;
}

/* Analyse `scan` again with its face searched within half a wavelength of
 * `near` (another scan's face), and, not found so, with its peak sought on
 * near's rows widened as much; the new analysis replaces *a when it finds
 * the winding there. */
static int analyse_near(const struct uwb_scan *scan, const struct uwb_analysis_options *aopt,
                        const struct uwb_analysis *near, const struct uwb_scan *near_scan,
                        struct uwb_analysis *a, char *err, size_t errlen)
{
    double half = SEARCH_NEAR_WAVELENGTHS * face_wavelength(near, near_scan);
    /* Within the range the scan would be searched anyway (the options'
     * target, else the header's, else the whole search range). */
    double lo = aopt->search_z_min_m, hi = aopt->search_z_max_m;
    if (aopt->has_target_z) {
        lo = aopt->target_z_m[0];
        hi = aopt->target_z_m[1];
    } else if (scan->has_target_z) {
        lo = scan->target_z_m[0];
        hi = scan->target_z_m[1];
    }
    struct uwb_analysis_options o = *aopt;
    o.has_target_z = 1;
    o.target_z_m[0] = fmax(lo, near->edges.face_z_m - half);
    o.target_z_m[1] = fmin(hi, near->edges.face_z_m + half);
    if (o.target_z_m[1] <= o.target_z_m[0])
        return 0;
    struct uwb_analysis again;
    if (uwb_analyse_scan(scan, &o, &again, err, errlen) != 0)
        return -1;
    /* Not found near it: a reflector level with the face may outshine the
     * winding's peak (a plate's underside at a bulge's range); sought
     * again on the rows the other face and a move of the same reach allow. */
    if (!again.edges.found) {
        struct uwb_analysis on_rows;
        o.has_face_rows = 1;
        o.face_rows_m[0] = near->edges.lower_m - half;
        o.face_rows_m[1] = near->edges.upper_m + half;
        if (uwb_analyse_scan(scan, &o, &on_rows, err, errlen) != 0) {
            uwb_analysis_free(&again);
            return -1;
        }
        if (on_rows.edges.found) {
            uwb_analysis_free(&again);
            again = on_rows;
        } else {
            uwb_analysis_free(&on_rows);
        }
    }
    if (!again.edges.found && a->edges.found) {
        uwb_analysis_free(&again);
        return 0;
    }
    uwb_analysis_free(a);
    *a = again;
    return 0;
}

static int same_face(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                     const struct uwb_scan *base)
{
    return fabs(ca->edges.face_z_m - ba->edges.face_z_m) <= SAME_FACE_WAVELENGTHS * face_wavelength(ba, base);
}

/* The winding's face once for the pair: each scan searched on its own may
 * settle on different reflectors (a plate's edge in one, the winding in the
 * other), and their edges then compare two things. The current scan is
 * searched again near the baseline's face, or, when the baseline found
 * none, the baseline near the current's. */
static int match_faces(const struct uwb_scan *cur, const struct uwb_scan *base,
                       const struct uwb_analysis_options *cur_opt,
                       const struct uwb_analysis_options *base_opt, struct uwb_analysis *ca,
                       struct uwb_analysis *ba, char *err, size_t errlen)
{
    if (ba->edges.found && (!ca->edges.found || !same_face(ca, ba, base)))
        return analyse_near(cur, cur_opt, ba, base, ca, err, errlen);
    if (!ba->edges.found && ca->edges.found)
        return analyse_near(base, base_opt, ca, cur, ba, err, errlen);
    return 0;
}

/* Why the two scans' faces cannot be taken for one reflector, or "". */
static void faces_differ(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                         const struct uwb_scan *base, char *why, size_t n)
{
    why[0] = '\0';
    const struct uwb_edges *c = &ca->edges, *b = &ba->edges;
    if (!c->found || !b->found)
        return;
    int range_differs = !same_face(ca, ba, base);
    int height_differs =
        fabs(c->height_m - b->height_m) > SAME_HEIGHT_FRACTION * fmax(c->height_m, b->height_m);
    if (range_differs || height_differs)
        snprintf(why, n,
                 "not the same reflector in both scans: this scan's face at %.0f mm range, %.0f..%.0f mm, "
                 "the baseline's at %.0f mm, %.0f..%.0f mm; figures withheld",
                 c->face_z_m * 1e3, c->lower_m * 1e3, c->upper_m * 1e3, b->face_z_m * 1e3, b->lower_m * 1e3,
                 b->upper_m * 1e3);
}

/* Why this scan must not be compared with the baseline for its time zero,
 * or "" when it may: its direct coupling must be found and within the
 * tolerance of the one recorded with the baseline (else a cable or an
 * antenna changed, and a shift of the image would read as a movement). */
static void time_zero_check(const struct uwb_verdict *v, const struct uwb_direct_coupling_options *dc,
                            char *why, size_t n)
{
    why[0] = '\0';
    if (!v->has_direct_coupling)
        snprintf(why, n, "direct coupling not found in this scan (%.150s): cable or antenna disconnected?",
                 v->direct_coupling_why);
    else if (!v->has_direct_coupling_shift)
        snprintf(why, n, "the baseline has no direct-coupling time zero to check this scan against");
    else if (fabs(v->direct_coupling_shift_s) > dc->tolerance_s)
        snprintf(why, n,
                 "direct coupling moved %+.0f ps since the baseline (tolerance %.0f ps): cable or antenna "
                 "changed?",
                 v->direct_coupling_shift_s * 1e12, dc->tolerance_s * 1e12);
}

/* The baseline's time zero: the one recorded at commissioning, else
 * measured on the baseline scan the same way. */
static int baseline_time_zero(const struct uwb_baseline_record *base,
                              const struct uwb_direct_coupling_options *dc, double *arrival_s)
{
    if (base->has_direct_coupling) {
        *arrival_s = base->direct_coupling_s;
        return 1;
    }
    char why[200];
    return uwb_direct_coupling_arrival(base->scan, dc->window_end_s, arrival_s, why, sizeof why) == 0;
}

/* Not compared: the current scan's edges alone, inconclusive, with why. */
static void not_compared(struct uwb_verdict *v, const struct uwb_edges *cur, const char *why,
                         const struct uwb_compare_options *copt)
{
    uwb_compare_edges(v, cur, NULL, copt);
    char edges_reason[256];
    snprintf(edges_reason, sizeof edges_reason, "%s", cur->found ? "" : v->reason);
    v->status = UWB_STATUS_INCONCLUSIVE;
    snprintf(v->reason, sizeof v->reason, "%.200s%s%.50s", why, edges_reason[0] ? "; " : "", edges_reason);
}

/* A rig whose home or scale changed moves the static scene with the winding
 * (uwb/rig_check.h): an error with the fault contact open, not a
 * displacement. -1 (analyses freed) on a hard error. */
static int rig_unchanged(struct uwb_analysis *cur_a, struct uwb_analysis *base_a,
                         const struct uwb_pair_figures *pair, struct uwb_verdict *v, char *err, size_t errlen)
{
    struct uwb_rig_check rig;
    if (uwb_rig_check(cur_a, base_a, pair->valid ? &pair->displacement_m : NULL, &rig, err, errlen) != 0) {
        uwb_analysis_free(cur_a);
        uwb_analysis_free(base_a);
        return -1;
    }
    if (rig.moved) {
        v->status = UWB_STATUS_ERROR;
        snprintf(v->reason, sizeof v->reason, "%s", rig.why);
        snprintf(v->fault, sizeof v->fault, "rig");
    }
    return 0;
}

/* The face's radial change at the pair's shift, and the shift fitted again
 * without its changed rows: a bulge changes the echo's strength about it,
 * which the whole face's fit reads in part as a movement, while leaving
 * its rows out loses the lean the imaging's blur spreads beyond them.
 * Neither fit is then the movement; how far they part is the axial
 * figure's deformation term (compare.c). */
static int measure_radial(const struct uwb_scan *current, const struct uwb_scan *baseline,
                          const struct uwb_analysis *cur_a, const struct uwb_analysis *base_a,
                          const struct uwb_compare_options *copt, double noise_rms,
                          struct uwb_pair_figures *pair, char *err, size_t errlen)
{
    /* 8 kB of profile, once an evaluation: off the worker's stack. */
    struct uwb_radial *radial = malloc(sizeof *radial);
    if (!radial) {
        snprintf(err, errlen, "radial profile: out of memory");
        return -1;
    }
    /* The oil's own offset at the face, from the static scene: the radial
     * profile's absolute reference (uwb/oil_reference.h). */
    struct uwb_oil_reference oil;
    uwb_oil_reference_measure(current, baseline, 299792458.0 / sqrt(baseline->eps_r), base_a->edges.face_z_m,
                              face_wavelength(base_a, baseline), &oil);
    uwb_radial_measure_referenced(cur_a, base_a, pair->displacement_m, copt->radial_thresholds.watch_m,
                                  noise_rms, &oil, radial);
    pair->radial = radial->figures;
    if (radial->figures.measured) {
        pair->has_radial = 1;
        pair->radial_profile_uncertainty_m = radial->uncertainty_profile_m;
        pair->deformed_at_end = radial->has_excluded && radial->excluded_at_end;
        char why[256];
        if (radial->has_excluded &&
            uwb_measure_shift_skipping(cur_a, base_a, radial->excluded_lo_m, radial->excluded_hi_m,
                                       &pair->refit_displacement_m, why, sizeof why) == 0)
            pair->has_refit = 1;
    }
    free(radial);
    return 0;
}

/* Rows of a radial profile that did not change (within half the watch
 * limit of its line; rows not read hold exactly 0 and are not counted),
 * and rows read. */
static void rows_unchanged(const struct uwb_radial *r, double watch_m, int *unchanged, int *read)
{
    *unchanged = *read = 0;
    for (int i = 0; i < r->n; i++) {
        if (r->change_m[i] == 0.0)
            continue;
        (*read)++;
        *unchanged += fabs(r->change_m[i]) <= 0.5 * watch_m;
    }
}

/* A face that changed shape (a buckle over a few disks) moves its echo's
 * strength and its ends, so the faces do not match whole (why: the
 * reflector match or the axial fit failing); yet the rows that did not
 * change still match at the shift one of its ends, or its centre, moved
 * by. The radial change is measured at the one of those that leaves the
 * most rows unchanged, where at least a third are, the change is past
 * the watch limit (a change that explains the mismatch) and the profile
 * can tell a change at all (its scatter within the largest sigma, or the
 * change past the watch limit by its 95 % interval: an 8 mm bulge over
 * two disks of seven reads a scatter of 1.1 mm), and the
 * axial figure is withheld with why. 1 when pair is filled so, 0 when not. */
static int radial_alone(const struct uwb_scan *current, const struct uwb_scan *baseline,
                        const struct uwb_analysis *cur_a, const struct uwb_analysis *base_a,
                        const struct uwb_compare_options *copt, const char *why,
                        struct uwb_pair_figures *pair)
{
    const struct uwb_edges *c = &cur_a->edges, *b = &base_a->edges;
    if (!c->found || !b->found ||
        fabs(c->face_z_m - b->face_z_m) > SEARCH_NEAR_WAVELENGTHS * face_wavelength(base_a, baseline))
        return 0;
    struct uwb_radial *radial = malloc(sizeof *radial);
    if (!radial)
        return 0;
    struct uwb_oil_reference oil;
    uwb_oil_reference_measure(current, baseline, 299792458.0 / sqrt(baseline->eps_r), b->face_z_m,
                              face_wavelength(base_a, baseline), &oil);
    double watch = copt->radial_thresholds.watch_m;
    double noise = 0.5 * (cur_a->noise_sigma + base_a->noise_sigma);
    const double shifts[] = {c->lower_m - b->lower_m, c->upper_m - b->upper_m, c->center_m - b->center_m};
    int best = -1, best_unchanged = 0;
    for (int k = 0; k < 3; k++) {
        uwb_radial_measure_referenced(cur_a, base_a, shifts[k], watch, noise, &oil, radial);
        int unchanged, read;
        rows_unchanged(radial, watch, &unchanged, &read);
        double change = fabs(radial->figures.max_change_m), scatter = radial->uncertainty_profile_m;
        if (radial->figures.measured && change > watch &&
            (scatter <= copt->max_uncertainty_m || change - UWB_SIGMAS_95 * scatter > watch) &&
            3 * unchanged >= read && unchanged > best_unchanged) {
            best = k;
            best_unchanged = unchanged;
        }
    }
    if (best >= 0) {
        uwb_radial_measure_referenced(cur_a, base_a, shifts[best], watch, noise, &oil, radial);
        pair->has_radial = 1;
        pair->radial = radial->figures;
        pair->radial_profile_uncertainty_m = radial->uncertainty_profile_m;
        snprintf(pair->axial_withheld, sizeof pair->axial_withheld,
                 "the face changed shape (%.120s): radial change read where its rows still match, axial "
                 "figure withheld",
                 why);
    }
    free(radial);
    return best >= 0;
}

int uwb_evaluate(const struct uwb_scan *current, const struct uwb_baseline_record *baseline,
                 const struct uwb_evaluate_options *opt, struct uwb_verdict *v, struct uwb_analysis *cur_a,
                 struct uwb_analysis *base_a, char *err, size_t errlen)
{
    memset(v, 0, sizeof *v);
    memset(cur_a, 0, sizeof *cur_a);
    memset(base_a, 0, sizeof *base_a);
    copy_text(v->scan_id, sizeof v->scan_id, current->scan_id);
    copy_text(v->created, sizeof v->created, current->created);
    v->has_direct_coupling =
        uwb_direct_coupling_arrival(current, opt->direct_coupling.window_end_s, &v->direct_coupling_s,
                                    v->direct_coupling_why, sizeof v->direct_coupling_why) == 0;
    if (baseline) {
        copy_text(v->baseline_scan_id, sizeof v->baseline_scan_id, baseline->scan->scan_id);
        double base_arrival;
        if (v->has_direct_coupling && baseline_time_zero(baseline, &opt->direct_coupling, &base_arrival)) {
            v->has_direct_coupling_shift = 1;
            v->direct_coupling_shift_s = v->direct_coupling_s - base_arrival;
        }
    }

    /* The drawings' winding span is checked against the baseline's image
     * (and a scan with no baseline, which may become one): this scan's face
     * is the baseline's reflector wherever the winding has moved to. */
    struct uwb_analysis_options cur_opt = opt->analysis;
    if (baseline)
        cur_opt.has_winding_span = 0;
    char zero_why[256] = "", apart_why[256] = "";
    int compare = 0;
    if (baseline) {
        time_zero_check(v, &opt->direct_coupling, zero_why, sizeof zero_why);
        compare = !zero_why[0] && uwb_scans_comparable(current, baseline->scan, apart_why, sizeof apart_why);
    }
    /* One frequency for the pair, the baseline's: each scan's own is the
     * highest bin of its spectrum, and where two bins nearly tie a bulge
     * or the noise tips one scan to the other bin. The faces' ranges, read
     * at two frequencies, then differ by more than a radial change (the
     * demo's 6 mm bulge read -6.9 mm, at other disks), and the shift moves
     * with them (s04 of the full-wave family, baseline and current at
     * 2.45 and 1.45 GHz: 0.8 mm). */
    if (compare) {
        if (uwb_analyse_scan(baseline->scan, &opt->analysis, base_a, err, errlen) != 0)
            return -1;
        cur_opt.has_dominant_hz = 1;
        cur_opt.dominant_hz = base_a->dominant_hz;
    }
    if (uwb_analyse_scan(current, &cur_opt, cur_a, err, errlen) != 0) {
        uwb_analysis_free(base_a);
        return -1;
    }
    if (!baseline) {
        uwb_compare_edges(v, &cur_a->edges, NULL, &opt->compare);
        return 0;
    }
    if (zero_why[0]) {
        not_compared(v, &cur_a->edges, zero_why, &opt->compare);
        return 0;
    }
    if (!compare) {
        uwb_compare_edges(v, &cur_a->edges, NULL, &opt->compare);
        v->has_baseline = 1;
        v->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v->reason, sizeof v->reason, "not comparable with the baseline: %.200s", apart_why);
        return 0;
    }
    if (match_faces(current, baseline->scan, &cur_opt, &opt->analysis, cur_a, base_a, err, errlen) != 0 ||
        keep_common_side_reflector(current, baseline->scan, &cur_opt, &opt->analysis, cur_a, base_a, err,
                                   errlen) != 0) {
        uwb_analysis_free(cur_a);
        uwb_analysis_free(base_a);
        return -1;
    }
    char why[256];
    /* The baseline's mean over N commissioning scans carries their spread / sqrt(N). */
    struct uwb_compare_options copt = opt->compare;
    if (baseline->has_repeatability)
        copt.baseline_repeatability_m =
            baseline->repeatability_m / sqrt(baseline->scans > 1 ? baseline->scans : 1);
    faces_differ(cur_a, base_a, baseline->scan, why, sizeof why);
    struct uwb_pair_figures alone = {0};
    if (why[0] && radial_alone(current, baseline->scan, cur_a, base_a, &copt,
                               "not the same reflector in both scans", &alone)) {
        uwb_compare_pair(v, &cur_a->edges, &base_a->edges, &alone, &copt);
        return 0;
    }
    if (why[0]) {
        uwb_compare_edges(v, &cur_a->edges, &base_a->edges, &copt);
        v->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v->reason, sizeof v->reason, "%s", why);
        snprintf(v->edges_withheld, sizeof v->edges_withheld,
                 "not the same reflector in both scans: this face may be another reflector's");
        return 0;
    }
    struct uwb_pair_figures pair = {0};
    int fit = cur_a->edges.found && base_a->edges.found
                  ? uwb_measure_shift(cur_a, base_a, &pair.displacement_m, why, sizeof why)
                  : -1;
    if (fit == 1 &&
        radial_alone(current, baseline->scan, cur_a, base_a, &copt, "no shift maps it whole", &alone)) {
        uwb_compare_pair(v, &cur_a->edges, &base_a->edges, &alone, &copt);
        return 0;
    }
    if (fit == 1) {
        /* No shift maps one face onto the other: whatever figure the search
         * stopped at is not a measurement. */
        uwb_compare_edges(v, &cur_a->edges, &base_a->edges, &copt);
        v->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v->reason, sizeof v->reason, "%.200s; figures withheld", why);
        snprintf(v->edges_withheld, sizeof v->edges_withheld,
                 "no shift maps the baseline's face onto this one: its edges are no measurement");
        return 0;
    }
    if (fit == 0) {
        pair.valid = 1;
        struct uwb_shift_noise noise;
        if (uwb_shift_noise(cur_a, base_a, &opt->analysis, pair.displacement_m, &noise, err, errlen) != 0) {
            uwb_analysis_free(cur_a);
            uwb_analysis_free(base_a);
            return -1;
        }
        pair.noise_measured = noise.measured;
        pair.sigma_noise_current_m = noise.sigma_current_m;
        pair.sigma_noise_baseline_m = noise.sigma_baseline_m;
        if (noise.measured && cur_a->noise_sigma > 0.0 && base_a->noise_sigma > 0.0) {
            /* A pair with no noise at all reads a ratio of 0: the floor stands. */
            pair.noise_ratio_current = fmax(noise.noise_rms / cur_a->noise_sigma, 1e-9);
            pair.noise_ratio_baseline = fmax(noise.noise_rms / base_a->noise_sigma, 1e-9);
        }
        if (measure_radial(current, baseline->scan, cur_a, base_a, &copt,
                           noise.measured ? noise.noise_rms
                                          : 0.5 * (cur_a->noise_sigma + base_a->noise_sigma),
                           &pair, err, errlen) != 0) {
            uwb_analysis_free(cur_a);
            uwb_analysis_free(base_a);
            return -1;
        }
        pair.has_shoulders = uwb_measure_shoulder_shifts(cur_a, base_a, &pair.lower_shift_m,
                                                         &pair.upper_shift_m, err, errlen) == 0;
    }
    uwb_compare_pair(v, &cur_a->edges, &base_a->edges, &pair, &copt);
    /* With no winding found in this scan there is no movement to tell a
     * rig fault from, and a baseline face found on another reflector (a
     * target range that misses the winding) would put the winding itself
     * in the static scene the check compares: the verdict stays that the
     * winding was not found. */
    if (!cur_a->edges.found)
        return 0;
    return rig_unchanged(cur_a, base_a, &pair, v, err, errlen);
}
