#include "uwb/evaluate.h"

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
    if (uwb_analyse_scan(baseline, &opt->analysis, base_a, err, errlen) != 0) {
        uwb_analysis_free(cur_a);
        return -1;
    }
    uwb_compare_edges(v, &cur_a->edges, &base_a->edges, &opt->compare);
    return 0;
}
