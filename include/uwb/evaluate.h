/* From scans in memory to a verdict: where replay and the appliance meet
 * (data flows drivers -> scan -> here -> outputs). */
#ifndef UWB_EVALUATE_H
#define UWB_EVALUATE_H

#include <stddef.h>

#include "uwb/analysis.h"
#include "uwb/compare.h"
#include "uwb/scan.h"
#include "uwb/verdict.h"

struct uwb_evaluate_options {
    struct uwb_analysis_options analysis;
    struct uwb_compare_options compare;
};

void uwb_evaluate_defaults(struct uwb_evaluate_options *opt);

/* Analyse current (and baseline, may be NULL) and compare. The analyses are
 * returned for the images; free them with uwb_analysis_free. Returns 0 when
 * a verdict was produced (possibly inconclusive), -1 on a hard error. */
int uwb_evaluate(const struct uwb_scan *current, const struct uwb_scan *baseline,
                 const struct uwb_evaluate_options *opt, struct uwb_verdict *v,
                 struct uwb_analysis *current_analysis, struct uwb_analysis *baseline_analysis,
                 char *err, size_t errlen);

/* Write the migrated, B-scan and comparison PNGs into dir, named after
 * `stem`, and list them in v->images; without a migrated image (analysis
 * stopped before imaging) only the B-scan. */
int uwb_write_images(const char *dir, const char *stem, const struct uwb_scan *current,
                     const struct uwb_analysis *current_analysis,
                     const struct uwb_analysis *baseline_analysis, struct uwb_verdict *v,
                     char *err, size_t errlen);

#endif
