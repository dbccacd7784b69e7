/* Fuzzing the whole analysis on every scan the reader accepts (issue 17,
 * break 5): bytes through uwbscan_parse, then uwb_evaluate on the scan
 * alone and against itself as its own baseline, as `uwbd --replay` and the
 * daemon would. The rig's limits checked at reading (uwb/scan.h) must make
 * every accepted scan bounded work (libFuzzer's -timeout and -rss_limit_mb
 * catch one that is not) and every double-to-int conversion defined (the
 * fuzz build has -fsanitize=float-cast-overflow).
 *
 * Contract: the analysis gives a verdict or refuses with a message; a
 * verdict with a figure has finite edges and, against the same scan, no
 * displacement beyond its uncertainty. */
#include <math.h>
#include <string.h>

#include "fuzz_harness.h"
#include "uwb/evaluate.h"
#include "uwb/scan.h"

static int check_edges(const struct uwb_edges *e, char *why, size_t whylen)
{
    if (e->found && !(isfinite(e->lower_m) && isfinite(e->upper_m) && isfinite(e->center_m) &&
                      isfinite(e->sigma_center_m) && e->lower_m <= e->upper_m))
        return fuzz_broken(why, whylen, "edges [%g, %g] centre %g +- %g", e->lower_m, e->upper_m, e->center_m,
                           e->sigma_center_m);
    return FUZZ_ACCEPTED;
}

static int evaluate(const struct uwb_scan *scan, const struct uwb_scan *baseline, char *why, size_t whylen)
{
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    struct uwb_verdict v;
    struct uwb_analysis cur, base;
    memset(&cur, 0, sizeof cur);
    memset(&base, 0, sizeof base);
    char err[512];
    memset(err, 'x', sizeof err);
    err[sizeof err - 1] = '\0';
    err[0] = '\0';
    struct uwb_baseline_record rec = {.scan = baseline};
    int rc = uwb_evaluate(scan, baseline ? &rec : NULL, &opt, &v, &cur, &base, err, sizeof err);
    int outcome = FUZZ_ACCEPTED;
    if (rc != 0) {
        if (!err[0])
            outcome = fuzz_broken(why, whylen, "analysis failed without a message");
        else
            snprintf(why, whylen, "analysis: %s", err);
    } else if ((unsigned)v.status > UWB_STATUS_ERROR) {
        outcome = fuzz_broken(why, whylen, "verdict of status %d", (int)v.status);
    } else if (check_edges(&v.current, why, whylen) == FUZZ_BROKEN) {
        outcome = FUZZ_BROKEN;
    } else if (baseline &&
               (v.status == UWB_STATUS_OK || v.status == UWB_STATUS_WATCH || v.status == UWB_STATUS_ALARM) &&
               !(fabs(v.axial_displacement_m) <= 1e-9 + 3 * v.uncertainty_m)) {
        outcome = fuzz_broken(why, whylen, "a scan against itself moved %g m +- %g m (status %s)",
                              v.axial_displacement_m, v.uncertainty_m, uwb_status_name(v.status));
    }
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
    return outcome;
}

int fuzz_analysis_input(const uint8_t *data, size_t size, char *why, size_t whylen)
{
    why[0] = '\0';
    struct uwb_scan scan;
    char err[512] = "";
    if (uwbscan_parse(data, size, "fuzz.uwbscan", &scan, err, sizeof err) != 0) {
        if (!err[0])
            return fuzz_broken(why, whylen, "reader refused without a message");
        snprintf(why, whylen, "%s", err);
        return FUZZ_REJECTED;
    }
    int outcome = evaluate(&scan, NULL, why, whylen);
    if (outcome != FUZZ_BROKEN)
        outcome = evaluate(&scan, &scan, why, whylen);
    uwb_scan_free(&scan);
    return outcome == FUZZ_BROKEN ? FUZZ_BROKEN : FUZZ_ACCEPTED;
}

UWB_FUZZ_TARGET(fuzz_analysis_input)
