/* From scans in memory to a verdict: the one place where a scan and a
 * baseline become a verdict, policy included (time zero, comparability,
 * thresholds). The daemon and `uwbd --replay` both call uwb_evaluate and
 * only add to its result (data flows drivers -> scan -> here -> outputs). */
#ifndef UWB_EVALUATE_H
#define UWB_EVALUATE_H

#include <stddef.h>

#include "uwb/analysis.h"
#include "uwb/compare.h"
#include "uwb/scan.h"
#include "uwb/verdict.h"

/* Time zero from the direct coupling (uwb/direct_coupling.h). */
struct uwb_direct_coupling_options {
    double window_end_s; /* the arrival is looked for from the first sample up to here (default 2 ns) */
    double tolerance_s;  /* moved more than this since the baseline: not compared (default 20 ps) */
};

struct uwb_evaluate_options {
    struct uwb_analysis_options analysis;
    struct uwb_compare_options compare;
    struct uwb_direct_coupling_options direct_coupling;
};

void uwb_evaluate_defaults(struct uwb_evaluate_options *opt);

/* How the displacement's 1-sigma depends on the pulses averaged per
 * position: sigma^2 = fixed + scaling / pulses. Only noise averages down,
 * as 1/sqrt(pulses); clutter, the systematic floor and the baseline's
 * share do not. The daemon asks this before it acquires again. */
struct uwb_pulse_sigma {
    double fixed_m2;   /* the part more pulses do not reduce (m^2) */
    double scaling_m2; /* the part that does, times the pulses (m^2) */
};

/* From a verdict at `pulses` per position: its current-scan noise part
 * (v->current.sigma_center_noise_m; all of v->uncertainty_m when that is
 * not given) scales. -1 when there is no noise part to average down. */
int uwb_pulse_sigma_from_verdict(const struct uwb_verdict *v, int pulses, struct uwb_pulse_sigma *m);
/* Fitted through two measured sigmas, sigma1 at pulses1 and sigma2 at
 * pulses2 (more), whatever the verdict's terms are. -1 when they do not
 * show sigma falling with pulses. */
int uwb_pulse_sigma_fit(double sigma1, int pulses1, double sigma2, int pulses2, struct uwb_pulse_sigma *m);
/* The 1-sigma that `pulses` per position would give. */
double uwb_pulse_sigma_at(const struct uwb_pulse_sigma *m, double pulses);
/* The pulses per position that bring the 1-sigma down to max_m; -1 when
 * none can (the part that does not average down is over it already). */
int uwb_pulse_sigma_pulses_for(const struct uwb_pulse_sigma *m, double max_m, double *pulses);

/* The baseline and what was recorded with it at commissioning (the
 * daemon's baseline/current.json). */
struct uwb_baseline_record {
    const struct uwb_scan *scan;
    int has_direct_coupling;  /* 0: not recorded; measured on `scan` as commissioning does */
    double direct_coupling_s; /* its time zero (direct-coupling arrival) */
    int scans;                /* acquisitions averaged into it (0: not recorded, one) */
    int has_repeatability;
    double repeatability_m; /* spread (1-sigma) of the centre across those scans */
};

/* Analyse current and, against a baseline (NULL: edges only), compare.
 * Against a baseline the policy comes first: a scan whose direct coupling
 * is not found, or moved more than direct_coupling.tolerance_s since the
 * baseline's, or whose rig differs from the baseline's, is `inconclusive`
 * and not compared (reason says why). The analyses are returned for the
 * images (the baseline's zeroed when it was not compared); free them with
 * uwb_analysis_free. Returns 0 when a verdict was produced (possibly
 * inconclusive), -1 on a hard error. */
int uwb_evaluate(const struct uwb_scan *current, const struct uwb_baseline_record *baseline,
                 const struct uwb_evaluate_options *opt, struct uwb_verdict *v,
                 struct uwb_analysis *current_analysis, struct uwb_analysis *baseline_analysis, char *err,
                 size_t errlen);

#endif
