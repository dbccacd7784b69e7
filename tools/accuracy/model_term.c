/* The axial sigma's model term (compare.c's axial_sigma_per_shift): every
 * noiseless full-wave pair replayed with the term and the least sigma off
 * and no limit on sigma, so each figure comes with the sum of its other
 * terms; the share of the move each pair needs for its error to lie within
 * 2 sigma; the largest, rounded up; then each pair's published figure under
 * that share and the decision rule (uwb_figure_given), with its error over
 * sigma and the tallies. */
#include "accuracy/model_term.h"
#include "accuracy/accuracy.h"
#include "accuracy/truth_file.h"

#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/compare.h"
#include "uwb/evaluate.h"
#include "uwb/read_file.h"
#include "uwb/scan.h"

#define MAX_PAIRS 128

struct term_pair {
    char name[64];
    int given;        /* the replay gave a figure (not withheld for a deformed face, two reflectors...) */
    char reason[256]; /* why not */
    double truth_mm, read_mm;
    double others_mm; /* sigma's other terms in quadrature, without the least */
    double noise_mm;  /* ...of which the scans' noise */
    double needed;    /* the share of the move this pair needs */
    int group;        /* enum pair_group */
};

/* The tallies' groups, in the order the pairs are replayed. */
enum pair_group { GROUP_FAMILY, GROUP_DEVELOPED, GROUP_FRESH, GROUPS };
static const char *const group_name[GROUPS] = {"shared family", "tank and paper", "fresh draws"};

/* The truth of the centre's move: the shift plus half the height change (a
 * squeezed spacer, data/README.md). */
static int truth_of(const char *scan_path, double *mm, char *err, size_t errlen)
{
    struct accuracy_truth t;
    if (accuracy_truth_read(scan_path, &t, err, errlen) != 0)
        return -1;
    *mm = t.shift_mm + 0.5 * t.height_change_mm;
    return 0;
}

static int replay(const char *moved, const char *baseline, struct term_pair *p, char *err, size_t errlen)
{
    memset(p, 0, sizeof *p);
    const char *base = strrchr(moved, '/');
    snprintf(p->name, sizeof p->name, "%.*s", (int)strcspn(base ? base + 1 : moved, "."),
             base ? base + 1 : moved);
    if (truth_of(moved, &p->truth_mm, err, errlen) != 0)
        return -1;
    struct uwb_scan cur, bas;
    if (uwbscan_read_file(moved, &cur, err, errlen) != 0)
        return -1;
    if (uwbscan_read_file(baseline, &bas, err, errlen) != 0) {
        uwb_scan_free(&cur);
        return -1;
    }
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    opt.compare.axial_sigma_per_shift = 0.0;
    opt.compare.least_displacement_uncertainty_m = 0.0;
    opt.compare.max_uncertainty_m = INFINITY;
    struct uwb_verdict v;
    int rc = accuracy_evaluate_pair(&cur, &bas, &opt, &v, err, errlen);
    if (rc == 0) {
        p->given = !v.axial_withheld && v.status != UWB_STATUS_INCONCLUSIVE && v.status != UWB_STATUS_ERROR;
        snprintf(p->reason, sizeof p->reason, "%s", v.reason);
        p->read_mm = v.axial_displacement_m * 1e3;
        p->others_mm = v.uncertainty_m * 1e3;
        p->noise_mm = v.uncertainty_noise_m * 1e3;
    }
    uwb_scan_free(&cur);
    uwb_scan_free(&bas);
    return rc;
}

/* The share of the move that puts the error within 2 sigma, with the
 * least sigma a figure carries (a figure within it needs none). */
static double needed_share(const struct term_pair *p, double least_mm)
{
    double half = 0.5 * fabs(p->read_mm - p->truth_mm);
    if (half <= fmax(p->others_mm, least_mm) || p->read_mm == 0.0)
        return 0.0;
    return sqrt(half * half - p->others_mm * p->others_mm) / fabs(p->read_mm);
}

/* Pairs of a glob: each moved scan against its own tank's intact one
 * (the moved scan's name up to "-d", then intact_suffix). */
static int add_glob(const char *pattern, const char *intact_suffix, const char *fixed_baseline, int group,
                    struct term_pair *pairs, int *n, char *err, size_t errlen)
{
    glob_t g;
    if (glob(pattern, 0, NULL, &g) != 0)
        return 0; /* none: that kind is not in the directory */
    int rc = 0;
    for (size_t i = 0; i < g.gl_pathc && rc == 0; i++) {
        const char *moved = g.gl_pathv[i];
        char baseline[4096];
        if (fixed_baseline) {
            if (!strcmp(moved, fixed_baseline))
                continue;
            snprintf(baseline, sizeof baseline, "%s", fixed_baseline);
        } else {
            const char *d = strstr(moved, "-d");
            if (!d || strstr(moved, intact_suffix))
                continue; /* the intact scan itself */
            snprintf(baseline, sizeof baseline, "%.*s%s", (int)(d - moved), moved, intact_suffix);
        }
        if (*n >= MAX_PAIRS) {
            snprintf(err, errlen, "more than %d pairs", MAX_PAIRS);
            rc = -1;
            break;
        }
        rc = replay(moved, baseline, &pairs[*n], err, errlen);
        if (rc == 0)
            pairs[(*n)++].group = group;
    }
    globfree(&g);
    return rc;
}

int accuracy_model_term(FILE *out, const char *data_dir, const char *fresh_dir, double *share_out, char *err,
                        size_t errlen)
{
    struct term_pair *pairs = calloc(MAX_PAIRS, sizeof *pairs);
    if (!pairs) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    char pattern[4096], fixed[4096];
    int n = 0, rc = 0;
    snprintf(pattern, sizeof pattern, "%s/fdtd2d-var-s*-d[+-]*.uwbscan", data_dir);
    rc = add_glob(pattern, "-d+00.uwbscan", NULL, GROUP_FAMILY, pairs, &n, err, errlen);
    snprintf(pattern, sizeof pattern, "%s/fdtd2d-tank-d[+-]*.uwbscan", data_dir);
    snprintf(fixed, sizeof fixed, "%s/fdtd2d-tank-d+00.0.uwbscan", data_dir);
    if (rc == 0)
        rc = add_glob(pattern, NULL, fixed, GROUP_DEVELOPED, pairs, &n, err, errlen);
    snprintf(pattern, sizeof pattern, "%s/fdtd2d-paper-up20mm.uwbscan", data_dir);
    snprintf(fixed, sizeof fixed, "%s/fdtd2d-paper-intact.uwbscan", data_dir);
    if (rc == 0)
        rc = add_glob(pattern, NULL, fixed, GROUP_DEVELOPED, pairs, &n, err, errlen);
    snprintf(pattern, sizeof pattern, "%s/fdtd2d-fresh-s[0-9][0-9][0-9]-d[+-]*.uwbscan", fresh_dir);
    if (rc == 0)
        rc = add_glob(pattern, "-d+00.uwbscan", NULL, GROUP_FRESH, pairs, &n, err, errlen);
    if (rc == 0 && n == 0) {
        snprintf(err, errlen, "no full-wave pairs in %s or %s", data_dir, fresh_dir);
        rc = -1;
    }
    if (rc != 0) {
        free(pairs);
        return -1;
    }
    struct uwb_compare_options copt;
    uwb_compare_defaults(&copt);
    double least_mm = copt.least_displacement_uncertainty_m * 1e3, largest = 0.0;
    const char *worst = "";
    for (int i = 0; i < n; i++)
        if (pairs[i].given && needed_share(&pairs[i], least_mm) > largest) {
            largest = needed_share(&pairs[i], least_mm);
            worst = pairs[i].name;
        }
    double share = ceil(largest * 1000.0 - 1e-9) / 1000.0;
    fprintf(out,
            "axial sigma's model term: the largest share needed is %.4f (%s); rounded up %.3f "
            "(compare.c uses %.3f)\n\n",
            largest, worst, share, copt.axial_sigma_per_shift);
    fprintf(out, "| pair | truth | read | sigma | noise | model | other | error/sigma | figure |\n");
    fprintf(out, "|---|---|---|---|---|---|---|---|---|\n");
    int count[GROUPS] = {0}, given[GROUPS] = {0}, within[GROUPS] = {0}, withheld[GROUPS] = {0},
        wide[GROUPS] = {0};
    for (int i = 0; i < n; i++) {
        const struct term_pair *p = &pairs[i];
        int g = p->group;
        count[g]++;
        if (!p->given) {
            withheld[g]++;
            fprintf(out, "| %s | %+.2f | — | | | | | | withheld: %.90s |\n", p->name, p->truth_mm, p->reason);
            continue;
        }
        double model = share * fabs(p->read_mm);
        double sigma = fmax(hypot(p->others_mm, model), least_mm);
        double other = sqrt(fmax(0.0, p->others_mm * p->others_mm - p->noise_mm * p->noise_mm));
        struct uwb_thresholds t = copt.thresholds;
        int shown = uwb_figure_given(p->read_mm * 1e-3, sigma * 1e-3, copt.max_uncertainty_m, &t);
        double ratio = (p->read_mm - p->truth_mm) / sigma;
        if (!shown) {
            withheld[g]++;
            fprintf(out,
                    "| %s | %+.2f | (%+.2f) | %.2f | %.2f | %.2f | %.2f | %+.1f | withheld: between "
                    "%+.1f and %+.1f mm |\n",
                    p->name, p->truth_mm, p->read_mm, sigma, p->noise_mm, model, other, ratio,
                    p->read_mm - 2.0 * sigma, p->read_mm + 2.0 * sigma);
            continue;
        }
        given[g]++;
        within[g] += fabs(ratio) <= 2.0;
        wide[g] += sigma > fmax(0.5, 0.08 * fabs(p->truth_mm));
        fprintf(out, "| %s | %+.2f | %+.2f | %.2f | %.2f | %.2f | %.2f | %+.1f | %s |\n", p->name,
                p->truth_mm, p->read_mm, sigma, p->noise_mm, model, other, ratio,
                fabs(ratio) <= 2.0 ? "within 2σ" : "OUTSIDE 2σ");
    }
    fprintf(out, "\n");
    for (int g = 0; g < GROUPS; g++)
        fprintf(out,
                "%s: %d pairs, %d figures given, %d within 2 sigma, %d withheld; %d with sigma over "
                "max(0.5 mm, 8 %% of the move)\n",
                group_name[g], count[g], given[g], within[g], withheld[g], wide[g]);
    free(pairs);
    *share_out = share;
    return 0;
}
