#include "uwb/evaluate.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void uwb_evaluate_defaults(struct uwb_evaluate_options *opt)
{
    uwb_analysis_defaults(&opt->analysis);
    uwb_compare_defaults(&opt->compare);
}

static void copy_text(char *dst, size_t n, const char *src)
{
    snprintf(dst, n, "%s", src ? src : "");
}

#define SAME_REFLECTOR_M 0.02

static int one_side_reflector(const struct uwb_edges *a, const struct uwb_edges *b)
{
    return a->side_reflector && (!b->side_reflector ||
                                 fabs(a->side_reflector_y_m - b->side_reflector_y_m) > SAME_REFLECTOR_M);
}

/* A reflector beside the winding (a clamping plate) belongs to the static
 * scene: both scans see it, at one height. Taken out of one scan and not the
 * other, its removal would stand for a movement of the winding (on the
 * full-wave tank scans the fit found a static echo 190 mm above the winding
 * in some scans and not in the baseline, and +4 mm read 3.70). So a scan whose
 * reflector the other scan does not share is measured again without the
 * removal. */
static int keep_common_side_reflector(const struct uwb_scan *cur, const struct uwb_scan *base,
                                      const struct uwb_analysis_options *aopt, struct uwb_analysis *ca,
                                      struct uwb_analysis *ba, char *err, size_t errlen)
{
    if (!ca->edges.found || !ba->edges.found)
        return 0;
    int redo_cur = one_side_reflector(&ca->edges, &ba->edges);
    int redo_base = one_side_reflector(&ba->edges, &ca->edges);
    struct uwb_analysis_options plain = *aopt;
    plain.remove_side_reflector = 0;
    struct uwb_analysis again;
    if (redo_cur) {
        if (uwb_analyse_scan(cur, &plain, &again, err, errlen) != 0)
            return -1;
        uwb_analysis_free(ca);
        *ca = again;
    }
    if (redo_base) {
        if (uwb_analyse_scan(base, &plain, &again, err, errlen) != 0)
            return -1;
        uwb_analysis_free(ba);
        *ba = again;
    }
    return 0;
}

int uwb_evaluate(const struct uwb_scan *current, const struct uwb_scan *baseline,
                 const struct uwb_evaluate_options *opt, struct uwb_verdict *v,
                 struct uwb_analysis *cur_a, struct uwb_analysis *base_a,
                 char *err, size_t errlen)
{
    memset(v, 0, sizeof *v);
    memset(cur_a, 0, sizeof *cur_a);
    memset(base_a, 0, sizeof *base_a);
    copy_text(v->scan_id, sizeof v->scan_id, current->scan_id);
    copy_text(v->created, sizeof v->created, current->created);
    if (baseline)
        copy_text(v->baseline_scan_id, sizeof v->baseline_scan_id, baseline->scan_id);

    if (uwb_analyse_scan(current, &opt->analysis, cur_a, err, errlen) != 0)
        return -1;
    if (!baseline) {
        uwb_compare_edges(v, &cur_a->edges, NULL, &opt->compare);
        return 0;
    }
    char why[200];
    if (!uwb_scans_comparable(current, baseline, why, sizeof why)) {
        uwb_compare_edges(v, &cur_a->edges, NULL, &opt->compare);
        v->has_baseline = 1;
        v->status = UWB_STATUS_INCONCLUSIVE;
        snprintf(v->reason, sizeof v->reason, "not comparable with the baseline: %s", why);
        return 0;
    }
    if (uwb_analyse_scan(baseline, &opt->analysis, base_a, err, errlen) != 0 ||
        keep_common_side_reflector(current, baseline, &opt->analysis, cur_a, base_a, err, errlen) != 0) {
        uwb_analysis_free(cur_a);
        uwb_analysis_free(base_a);
        return -1;
    }
    struct uwb_pair_figures pair = {0};
    if (cur_a->edges.found && base_a->edges.found &&
        uwb_measure_shift(cur_a, base_a, &pair.displacement_m, err, errlen) == 0) {
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
    }
    uwb_compare_pair(v, &cur_a->edges, &base_a->edges, &pair, &opt->compare);
    return 0;
}
