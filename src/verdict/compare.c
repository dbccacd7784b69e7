#include "uwb/compare.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The axial reading's share of a lean of the face (see uwb_compare_pair). */
#define TILT_TO_AXIAL (1.0 / 3.0)

void uwb_compare_defaults(struct uwb_compare_options *opt)
{
    opt->thresholds.watch_m = 0.002;
    opt->thresholds.alarm_m = 0.005;
    /* Radial like axial: 2 mm is about the face's own scatter on a pure
     * shift doubled, 5 mm a buckle the short-circuit forces left. */
    opt->radial_thresholds.watch_m = 0.002;
    opt->radial_thresholds.alarm_m = 0.005;
    opt->systematic_displacement_m = 0.0001;
    /* The least sigma a displacement carries, whatever its terms read (as a
     * calibration laboratory states the smallest uncertainty it claims):
     * the static scene beside the winding and the 30 mm antenna sampling
     * move the fit on tanks uwbd was not developed on by amounts no check
     * on the pair reads (README, issue 28). 0.3 mm is the robust scatter of
     * the noiseless full-wave pairs' errors, 1.4826 x their median absolute
     * error (tools/accuracy/family.sh prints it). */
    opt->least_displacement_uncertainty_m = 0.0003;
    /* The fit's own error grows with the move on tanks with clamp plates
     * near the winding's ends: the winding and the plates scatter into each
     * other, and no check on the pair reads it (README, "Fresh draws"; up
     * to 3.3 mm on a 30 mm move). The smallest share of the move that puts
     * every noiseless full-wave pair (the shared family, the fresh draws,
     * the tank, the paper's) within 2 sigma, rounded up: `make
     * accuracy-model-term` prints it (tools/accuracy/model_term.c). One
     * constant for every tank. */
    opt->axial_sigma_per_shift = 0.062;
    opt->max_uncertainty_m = 0.001;
    /* The height change should tell a squeezed spacer (2 mm) from none:
     * past 1 mm of 1-sigma it cannot. */
    opt->max_height_uncertainty_m = 0.001;
    /* The static scene's image leans each scan's shoulders by an amount
     * that changes as the winding moves past it (a clamp plate, a window
     * edge): the two scans' crossings differ by more than the winding's
     * height change, the farther it moved. On the noiseless full-wave
     * pairs (paper, tank, family) the height read on a move is off by
     * 1.4826 x the median of |error| / |shift| = 0.12 of the shift
     * (tools/accuracy/family.sh prints it). */
    opt->height_change_per_shift = 0.12;
    /* Oil warmer or colder than at the baseline changes its wave speed
     * while the header keeps one eps_r: the face's range moves and the
     * image, focused at the header's speed, blurs the shoulders
     * differently, so the crossings read a height change that is none.
     * In the simulator (tools/accuracy/warm_oil.c, make accuracy: the
     * full-wave tank's winding with 5, 7 and 8 disks, faces at 390-490 mm,
     * pulses of 1.8-2.6 GHz, eps_r 2.16-2.26 against 2.2) the false height
     * change is 0.26-0.61 x (range moved) x (height / range); 0.4 puts
     * each within 2 sigma with the term alone, 0.3 being the least that
     * does. */
    opt->height_change_per_face_range = 0.4;
    opt->baseline_repeatability_m = 0;
}

int uwb_scans_comparable(const struct uwb_scan *cur, const struct uwb_scan *base, char *why, size_t whylen)
{
    if (cur->positions != base->positions) {
        snprintf(why, whylen, "baseline has %d antenna positions, this scan %d", base->positions,
                 cur->positions);
        return 0;
    }
    for (int k = 0; k < cur->positions; k++)
        if (fabs(cur->antenna_y_m[k] - base->antenna_y_m[k]) > 1e-4) {
            snprintf(why, whylen, "antenna position %d is at %.4f m, in the baseline at %.4f m", k,
                     cur->antenna_y_m[k], base->antenna_y_m[k]);
            return 0;
        }
    for (int i = 0; i < 2; i++)
        if (fabs(cur->tx_m[i] - base->tx_m[i]) > 1e-4 || fabs(cur->rx_m[i] - base->rx_m[i]) > 1e-4) {
            snprintf(why, whylen, "antenna phase centres differ from the baseline's (antennas changed?)");
            return 0;
        }
    if (fabs(cur->eps_r - base->eps_r) > 1e-3) {
        snprintf(why, whylen, "eps_r %.3f differs from the baseline's %.3f", cur->eps_r, base->eps_r);
        return 0;
    }
    return 1;
}

static void copy_reason(struct uwb_verdict *v, const char *prefix, const char *reason)
{
    snprintf(v->reason, sizeof v->reason, "%.20s%.230s", prefix, reason);
}

double uwb_displacement_uncertainty(const struct uwb_uncertainty_terms *t)
{
    double measured =
        sqrt(t->noise_current_m * t->noise_current_m + t->noise_baseline_m * t->noise_baseline_m +
             t->systematic_m * t->systematic_m + t->baseline_repeatability_m * t->baseline_repeatability_m +
             t->model_m * t->model_m + t->deformation_m * t->deformation_m);
    return fmax(measured, t->least_m);
}

/* The height change's 1-sigma, or withheld (why filled): each scan's noise
 * at its two crossings (scaled to the noise the pair's difference shows,
 * when measured), the model term: how far the crossings' reading
 * disagrees with the shoulders' own fits (upper minus lower shift), and
 * the static scene's share, growing with the shift. The crossings and the
 * shoulders read the same height change when the profile's ends only
 * move; where the disks' sampling or a reflector beside the winding
 * changes a shoulder's shape, they part; where a reflector leans one
 * shoulder more after the move than before, both read it alike. */
static void height_change_uncertainty(struct uwb_verdict *v, const struct uwb_edges *cur,
                                      const struct uwb_edges *base, const struct uwb_pair_figures *pair,
                                      const struct uwb_compare_options *opt)
{
    v->height_change_uncertainty_m = 0.0;
    v->height_change_withheld[0] = '\0';
    if (!pair || !pair->valid || !pair->has_shoulders) {
        snprintf(v->height_change_withheld, sizeof v->height_change_withheld,
                 "the shoulders could not be fitted: no check of the crossings' height");
        return;
    }
    /* 2 sigma_center_noise = the two crossings' noise in quadrature. */
    double ratio_c = pair->noise_ratio_current > 0.0 ? pair->noise_ratio_current : 1.0;
    double ratio_b = pair->noise_ratio_baseline > 0.0 ? pair->noise_ratio_baseline : 1.0;
    double noise_c = 2.0 * cur->sigma_center_noise_m * ratio_c;
    double noise_b = 2.0 * base->sigma_center_noise_m * ratio_b;
    double model = fabs((pair->upper_shift_m - pair->lower_shift_m) - v->height_change_m);
    double scene = opt->height_change_per_shift * fabs(v->axial_displacement_m);
    double oil = base->face_z_m > 0.0
                     ? opt->height_change_per_face_range * fabs(cur->face_z_m - base->face_z_m) *
                           base->height_m / base->face_z_m
                     : 0.0;
    v->height_change_uncertainty_m =
        sqrt(noise_c * noise_c + noise_b * noise_b + model * model + scene * scene + oil * oil +
             2.0 * opt->systematic_displacement_m * opt->systematic_displacement_m);
    /* The reason names the largest term in words: the crossings' figure
     * and the move are readings of a withheld figure, or of one that may
     * itself be withheld, so neither is shown. */
    if (v->height_change_uncertainty_m > opt->max_height_uncertainty_m) {
        double noise = hypot(noise_c, noise_b);
        const char *cause = model >= scene && model >= noise && model >= oil
                                ? "the crossings and the shoulders' own fits disagree"
                            : oil >= scene && oil >= noise ? "the face's range moved (the oil's wave speed?)"
                            : scene >= noise               ? "the static scene's share grows with the move"
                                                           : "the scans' noise at the crossings";
        snprintf(v->height_change_withheld, sizeof v->height_change_withheld,
                 "height change uncertainty %.2f mm exceeds %.2f mm: %s",
                 v->height_change_uncertainty_m * 1e3, opt->max_height_uncertainty_m * 1e3, cause);
    }
}

static enum uwb_status graded(double magnitude_m, const struct uwb_thresholds *t)
{
    if (magnitude_m >= t->alarm_m)
        return UWB_STATUS_ALARM;
    return magnitude_m >= t->watch_m ? UWB_STATUS_WATCH : UWB_STATUS_OK;
}

/* The value of figure's 95 % interval nearest none, signed (0 when the
 * interval holds none). */
static double interval_least_m(double figure_m, double sigma_m)
{
    double lo = figure_m - UWB_SIGMAS_95 * sigma_m, hi = figure_m + UWB_SIGMAS_95 * sigma_m;
    return lo > 0.0 ? lo : hi < 0.0 ? hi : 0.0;
}

/* The lean a radial status is graded on: the tilt once told from none,
 * or, withheld across a status limit, the least its interval allows. */
static double lean_graded_m(const struct uwb_radial_verdict *r)
{
    if (r->tilt_withheld[0])
        return fabs(r->tilt_least_m);
    return fabs(r->tilt_m) > 2.0 * r->tilt_uncertainty_m ? fabs(r->tilt_m) : 0.0;
}

/* Whether the face's lean, not its largest change, grades the radial
 * status: a lean is a deformation like a bulge (the winding shifted in its
 * clamps), counted once told from none (past 2 sigma: pure shifts read up
 * to 0.055 mm of lean per mm moved) and graded worse than the change. */
static int radial_lean_decides(const struct uwb_radial_verdict *r, const struct uwb_compare_options *opt)
{
    return graded(lean_graded_m(r), &opt->radial_thresholds) >
           graded(fabs(r->max_change_m), &opt->radial_thresholds);
}

int uwb_figure_given(double figure_m, double sigma_m, double max_sigma_m, const struct uwb_thresholds *t)
{
    if (!(sigma_m > max_sigma_m))
        return 1;
    double s95 = UWB_SIGMAS_95 * sigma_m;
    double most = fmax(fabs(figure_m - s95), fabs(figure_m + s95));
    return graded(fabs(interval_least_m(figure_m, sigma_m)), t) == graded(most, t);
}

/* The reason of a figure the decision rule withholds: its 95 % interval. */
static void interval_reason(char *buf, size_t n, const char *what, double figure_m, double sigma_m)
{
    double s95 = UWB_SIGMAS_95 * sigma_m;
    snprintf(buf, n, "%s lies between %+.1f and %+.1f mm (95 %%), across a status limit: figure withheld",
             what, (figure_m - s95) * 1e3, (figure_m + s95) * 1e3);
}

/* The radial verdict from the pair's figures: graded on the change, or
 * inconclusive (no size published) when the decision rule withholds it. */
static void radial_verdict(struct uwb_verdict *v, const struct uwb_pair_figures *pair,
                           const struct uwb_compare_options *opt)
{
    struct uwb_radial_verdict *r = &v->radial;
    if (!pair || !(pair->valid || pair->axial_withheld[0]) || !pair->has_radial) {
        memset(r, 0, sizeof *r);
        r->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(r->withheld, sizeof r->withheld, "%s",
                 pair && pair->radial.withheld[0] ? pair->radial.withheld
                                                  : "the face's range was not compared");
        return;
    }
    *r = pair->radial;
    /* A change read short by its own flank: no size, its status by the
     * least it can be, its place kept. */
    if (r->change_least_m != 0.0) {
        r->measured = 0;
        r->status = graded(fabs(r->change_least_m), &opt->radial_thresholds);
        /* The least to a tenth, toward none: 2.06 is at least 2.0, not 2.1. */
        double least_mm = trunc(r->change_least_m * 1e4) / 10.0;
        snprintf(r->withheld, sizeof r->withheld,
                 "a change of at least %+.1f mm at %.0f mm, its size withheld: the face beside it lies "
                 "within its blur, which reads it short",
                 least_mm, r->at_m * 1e3);
        return;
    }
    /* Whether the profile can tell a change at all: its own scatter at a
     * row, not the share of the size a large change carries; past the
     * limit the size is still given when its whole 95 % interval lies in
     * one band (uwb_figure_given). */
    if (!uwb_figure_given(r->max_change_m, pair->radial_profile_uncertainty_m, opt->max_uncertainty_m,
                          &opt->radial_thresholds) &&
        !uwb_figure_given(r->max_change_m, r->uncertainty_m, 0.0, &opt->radial_thresholds)) {
        r->status = UWB_STATUS_INCONCLUSIVE;
        r->measured = 0;
        interval_reason(r->withheld, sizeof r->withheld, "the radial change", r->max_change_m,
                        fmax(r->uncertainty_m, pair->radial_profile_uncertainty_m));
        return;
    }
    /* The tilt follows the same rule on the same limits (a lean is graded
     * like a change); withheld, it still grades the status by the least
     * lean its interval allows: a lean of +2.4..+6.5 mm is one to watch. */
    if (!r->tilt_withheld[0] && !uwb_figure_given(r->tilt_m, r->tilt_uncertainty_m, opt->max_uncertainty_m,
                                                  &opt->radial_thresholds)) {
        r->tilt_least_m = interval_least_m(r->tilt_m, r->tilt_uncertainty_m);
        interval_reason(r->tilt_withheld, sizeof r->tilt_withheld, "the tilt", r->tilt_m,
                        r->tilt_uncertainty_m);
        r->tilt_m = 0.0;
        r->tilt_uncertainty_m = 0.0;
    }
    r->status = graded(fabs(r->max_change_m), &opt->radial_thresholds);
    if (radial_lean_decides(r, opt))
        r->status = graded(lean_graded_m(r), &opt->radial_thresholds);
}

/* How bad a status is for the verdict that combines the axial and the
 * radial one: a change past a limit outranks a figure withheld. */
static int severity(enum uwb_status s)
{
    switch (s) {
    case UWB_STATUS_ALARM: return 3;
    case UWB_STATUS_WATCH: return 2;
    case UWB_STATUS_INCONCLUSIVE: return 1;
    default: return 0;
    }
}

/* The verdict's status: the worse of the axial and the radial one, the
 * reason saying which when the radial decides. */
static void combine_radial(struct uwb_verdict *v, const struct uwb_compare_options *opt)
{
    const struct uwb_radial_verdict *r = &v->radial;
    if ((!r->measured && r->change_least_m == 0.0) || severity(r->status) <= severity(v->status))
        return;
    char axial[256];
    /* The axial part keeps its own "axial: " when it has one. */
    const char *own = strncmp(v->reason, "axial: ", 7) == 0 ? v->reason + 7 : v->reason;
    snprintf(axial, sizeof axial, "%s", own);
    if (!r->measured)
        snprintf(v->reason, sizeof v->reason, "radial: %.140s%s%.90s", r->withheld,
                 axial[0] ? "; axial: " : "", axial);
    else if (radial_lean_decides(r, opt) && r->tilt_withheld[0])
        snprintf(v->reason, sizeof v->reason,
                 "the face leans at least %+.1f mm top to bottom (95 %%; %s)%s%.100s", r->tilt_least_m * 1e3,
                 "the tilt withheld across a status limit", axial[0] ? "; axial: " : "", axial);
    else if (radial_lean_decides(r, opt))
        snprintf(v->reason, sizeof v->reason, "the face leans %+.2f mm top to bottom (sigma %.2f mm)%s%.150s",
                 r->tilt_m * 1e3, r->tilt_uncertainty_m * 1e3, axial[0] ? "; axial: " : "", axial);
    else if (r->has_span)
        snprintf(v->reason, sizeof v->reason, "radial change %+.2f mm at %.0f mm (%.0f..%.0f mm)%s%.150s",
                 r->max_change_m * 1e3, r->at_m * 1e3, r->from_m * 1e3, r->to_m * 1e3,
                 axial[0] ? "; axial: " : "", axial);
    else
        snprintf(v->reason, sizeof v->reason, "radial change %+.2f mm at %.0f mm%s%.150s",
                 r->max_change_m * 1e3, r->at_m * 1e3, axial[0] ? "; axial: " : "", axial);
    v->status = r->status;
}

void uwb_compare_edges(struct uwb_verdict *v, const struct uwb_edges *cur, const struct uwb_edges *base,
                       const struct uwb_compare_options *opt)
{
    uwb_compare_pair(v, cur, base, NULL, opt);
}

void uwb_compare_pair(struct uwb_verdict *v, const struct uwb_edges *cur, const struct uwb_edges *base,
                      const struct uwb_pair_figures *pair, const struct uwb_compare_options *opt)
{
    v->current = *cur;
    v->axial_withheld = 0;
    v->edges_withheld[0] = '\0';
    v->has_baseline = base != NULL;
    if (base)
        v->baseline = *base;
    v->reason[0] = '\0';
    if (!cur->found) {
        v->status = UWB_STATUS_INCONCLUSIVE;
        copy_reason(v, "", cur->reason);
        return;
    }
    if (!base) {
        v->status = UWB_STATUS_EDGES;
        return;
    }
    if (!base->found) {
        v->status = UWB_STATUS_INCONCLUSIVE;
        copy_reason(v, "baseline: ", base->reason);
        /* Nothing confirms this scan's face as the winding's: on the 3-D
         * full-wave tanks it lies 120-160 mm off where no baseline face is
         * found. */
        snprintf(v->edges_withheld, sizeof v->edges_withheld,
                 "the baseline's winding was not found: nothing confirms this face as the winding's");
        return;
    }
    /* A face that changed shape so that no shift maps it whole: the radial
     * change measured on the rows that still match decides, the axial
     * figure withheld (a change past a limit outranks it, combine_radial). */
    if (pair && !pair->valid && pair->axial_withheld[0]) {
        v->axial_displacement_m = cur->center_m - base->center_m;
        v->height_change_m = cur->height_m - base->height_m;
        v->status = UWB_STATUS_INCONCLUSIVE;
        v->axial_withheld = 1;
        snprintf(v->reason, sizeof v->reason, "%s", pair->axial_withheld);
        snprintf(v->height_change_withheld, sizeof v->height_change_withheld,
                 "the face changed shape: no shift maps it whole");
        snprintf(v->edges_withheld, sizeof v->edges_withheld,
                 "the face changed shape: its edges follow the echo's strength there");
        radial_verdict(v, pair, opt);
        combine_radial(v, opt);
        return;
    }
    v->axial_displacement_m = pair && pair->valid ? pair->displacement_m : cur->center_m - base->center_m;
    v->height_change_m = cur->height_m - base->height_m;
    height_change_uncertainty(v, cur, base, pair, opt);
    /* Both scans blur their edges alike, so only their noise, a floor for
     * what the two scans do not share (sampling, drift) and what the
     * baseline's commissioning scans showed of its repeatability (baseline
     * set N) enter; a plate taken out beside the winding leaves the same in
     * both at no move, and the model term covers what it leaves with one. */
    struct uwb_uncertainty_terms terms = {
        .noise_current_m = cur->sigma_center_noise_m,
        .noise_baseline_m = base->sigma_center_noise_m,
        .systematic_m = opt->systematic_displacement_m,
        .least_m = opt->least_displacement_uncertainty_m,
        .baseline_repeatability_m = opt->baseline_repeatability_m,
    };
    if (pair && pair->valid && pair->noise_measured) {
        terms.noise_current_m = pair->sigma_noise_current_m;
        terms.noise_baseline_m = pair->sigma_noise_baseline_m;
    }
    if (pair && pair->valid && pair->has_refit)
        terms.deformation_m = fabs(pair->refit_displacement_m - pair->displacement_m);
    terms.model_m = opt->axial_sigma_per_shift * fabs(v->axial_displacement_m);
    /* A leaning face changes the echo's strength along the height, which
     * the fit reads in part as a movement: a third of the lean in 2-D
     * physical optics (tools/accuracy/radial-limits.sh), counted once the
     * lean is past the radial watch limit (pure shifts read up to 1.5 mm
     * of lean that is none). */
    if (pair && pair->valid && pair->has_radial && !pair->radial.tilt_withheld[0] &&
        fabs(pair->radial.tilt_m) > opt->radial_thresholds.watch_m)
        terms.deformation_m = hypot(terms.deformation_m, TILT_TO_AXIAL * pair->radial.tilt_m);
    v->uncertainty_m = uwb_displacement_uncertainty(&terms);
    v->uncertainty_noise_m = hypot(terms.noise_current_m, terms.noise_baseline_m);
    int deformed_at_end = pair && pair->valid && pair->deformed_at_end;
    radial_verdict(v, pair, opt);
    /* A face deformed past the radial watch limit: every axial reading
     * follows the echo's strength there as much as the move (the whole
     * face's fit and the refit without the changed rows part by mm on the
     * full-wave bulges, and neither is the move), so none is shown. */
    int deformed_radially = (v->radial.measured || v->radial.change_least_m != 0.0) &&
                            severity(v->radial.status) >= severity(UWB_STATUS_WATCH);
    int deformed = deformed_at_end || deformed_radially;
    if (deformed_radially)
        snprintf(v->height_change_withheld, sizeof v->height_change_withheld,
                 "the face deformed radially: its crossings follow the echo's strength there");
    if (deformed || (pair && terms.deformation_m > opt->max_uncertainty_m && pair->has_refit)) {
        v->status = UWB_STATUS_INCONCLUSIVE;
        v->axial_withheld = 1;
        /* The crossings move with the echo's strength as the shift does
         * (the full-wave tank's disks 4-5 bulged 6 mm: lower edge 10 mm
         * off). */
        snprintf(v->edges_withheld, sizeof v->edges_withheld,
                 "the face deformed: its edges follow the echo's strength there");
        snprintf(v->reason, sizeof v->reason, "%s", UWB_AXIAL_NOT_MEASURED_DEFORMED);
    } else if (!uwb_figure_given(v->axial_displacement_m, v->uncertainty_m, opt->max_uncertainty_m,
                                 &opt->thresholds)) {
        v->status = UWB_STATUS_INCONCLUSIVE;
        v->axial_withheld = 1;
        if (pair && terms.deformation_m > opt->max_uncertainty_m && !v->radial.tilt_withheld[0])
            snprintf(v->reason, sizeof v->reason,
                     "the face leans %+.2f mm top to bottom, which moves the axial reading: axial figure "
                     "withheld",
                     v->radial.tilt_m * 1e3);
        else if (pair && terms.deformation_m > opt->max_uncertainty_m)
            snprintf(v->reason, sizeof v->reason,
                     "the face leans (see radial), which moves the axial reading: axial figure withheld");
        else
            interval_reason(v->reason, sizeof v->reason, "the axial shift", v->axial_displacement_m,
                            v->uncertainty_m);
    } else {
        v->status = graded(fabs(v->axial_displacement_m), &opt->thresholds);
    }
    combine_radial(v, opt);
}
