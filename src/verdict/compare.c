#include "uwb/compare.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void uwb_compare_defaults(struct uwb_compare_options *opt)
{
    opt->thresholds.watch_m = 0.002;
    opt->thresholds.alarm_m = 0.005;
    opt->systematic_displacement_m = 0.0001;
    opt->max_uncertainty_m = 0.001;
    /* The height change should tell a squeezed spacer (2 mm) from none:
     * past 1 mm of 1-sigma it cannot. */
    opt->max_height_uncertainty_m = 0.001;
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
    return sqrt(t->noise_current_m * t->noise_current_m + t->noise_baseline_m * t->noise_baseline_m +
                t->clutter_current_m * t->clutter_current_m + t->clutter_baseline_m * t->clutter_baseline_m +
                t->systematic_m * t->systematic_m +
                t->baseline_repeatability_m * t->baseline_repeatability_m);
}

/* The height change's 1-sigma, or withheld (why filled): each scan's noise
 * at its two crossings (scaled to the noise the pair's difference shows,
 * when measured), and the model term: how far the crossings' reading
 * disagrees with the shoulders' own fits (upper minus lower shift). Both
 * read the same height change when the profile's ends only move; where the
 * disks' sampling or a reflector beside the winding changes a shoulder's
 * shape, they part. */
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
    v->height_change_uncertainty_m =
        sqrt(noise_c * noise_c + noise_b * noise_b + model * model +
             2.0 * opt->systematic_displacement_m * opt->systematic_displacement_m);
    if (v->height_change_uncertainty_m > opt->max_height_uncertainty_m)
        snprintf(v->height_change_withheld, sizeof v->height_change_withheld,
                 "height change uncertainty %.2f mm exceeds %.2f mm (crossings read %+.2f mm, shoulders "
                 "%+.2f mm)",
                 v->height_change_uncertainty_m * 1e3, opt->max_height_uncertainty_m * 1e3,
                 v->height_change_m * 1e3, (pair->upper_shift_m - pair->lower_shift_m) * 1e3);
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
        return;
    }
    v->axial_displacement_m = pair && pair->valid ? pair->displacement_m : cur->center_m - base->center_m;
    v->height_change_m = cur->height_m - base->height_m;
    height_change_uncertainty(v, cur, base, pair, opt);
    /* Both scans blur their edges alike, so only their noise, what removing
     * a plate beside the winding may leave, and a floor for what the two
     * scans do not share (sampling, drift) enter, and what the baseline's
     * commissioning scans showed of its repeatability (baseline set N). */
    struct uwb_uncertainty_terms terms = {
        .noise_current_m = cur->sigma_center_noise_m,
        .noise_baseline_m = base->sigma_center_noise_m,
        .clutter_current_m = cur->sigma_center_clutter_m,
        .clutter_baseline_m = base->sigma_center_clutter_m,
        .systematic_m = opt->systematic_displacement_m,
        .baseline_repeatability_m = opt->baseline_repeatability_m,
    };
    if (pair && pair->valid && pair->noise_measured) {
        terms.noise_current_m = pair->sigma_noise_current_m;
        terms.noise_baseline_m = pair->sigma_noise_baseline_m;
    }
    v->uncertainty_m = uwb_displacement_uncertainty(&terms);
    double d = fabs(v->axial_displacement_m);
    if (v->uncertainty_m > opt->max_uncertainty_m) {
        v->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v->reason, sizeof v->reason,
                 "uncertainty %.2f mm exceeds %.2f mm: too little signal for a figure",
                 v->uncertainty_m * 1e3, opt->max_uncertainty_m * 1e3);
    } else if (d >= opt->thresholds.alarm_m) {
        v->status = UWB_STATUS_ALARM;
    } else if (d >= opt->thresholds.watch_m) {
        v->status = UWB_STATUS_WATCH;
    } else {
        v->status = UWB_STATUS_OK;
    }
}
