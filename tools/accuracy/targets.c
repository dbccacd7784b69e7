/* The accuracy targets (issue 44, "Done when"): on every noiseless
 * full-wave pair each figure given (the displacement, the height change,
 * the edges) lies within 2 sigma of its truth, the displacement's sigma
 * stays below max(0.5 mm, 8 % of the move), and at least half of the
 * shared family's squeezed spacers are read within 0.5 mm. Each pair is
 * replayed as the outputs publish it (the verdict record); a figure that
 * misses fails the target, printed with the pair. */
#include "accuracy/targets.h"
#include "accuracy/accuracy.h"
#include "accuracy/truth_file.h"

#include <cjson/cJSON.h>
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/scan.h"
#include "uwb/verdict_record.h"

/* A squeezed spacer is read when its height change is within this. */
#define COMPRESSION_READ_MM 0.5

/* A pair's truth, its winding's drawn span required (the edges are judged on it). */
static int read_truth(const char *scan_path, struct accuracy_truth *t, char *err, size_t errlen)
{
    if (accuracy_truth_read(scan_path, t, err, errlen) != 0)
        return -1;
    if (!t->has_span) {
        snprintf(err, errlen, "%s: its truth has no y1_m or y2_m", scan_path);
        return -1;
    }
    return 0;
}

static const char *pair_name(const char *path, char *buf, size_t n)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    snprintf(buf, n, "%.*s", (int)strcspn(base, "."), base);
    return buf;
}

/* The largest |error| / sigma of the published edges (this scan's and
 * the baseline's against their truths). */
static double edges_ratio(const struct uwb_verdict_record *r, const struct accuracy_truth *cur,
                          const struct accuracy_truth *base)
{
    double s = r->edge_uncertainty_mm > 0.0 ? r->edge_uncertainty_mm : INFINITY;
    double worst = fmax(fabs(r->lower_edge_mm - cur->y1_mm), fabs(r->upper_edge_mm - cur->y2_mm));
    worst = fmax(worst, fabs(r->center_mm - 0.5 * (cur->y1_mm + cur->y2_mm)));
    if (r->has_baseline)
        worst = fmax(worst, fmax(fabs(r->baseline_lower_edge_mm - base->y1_mm),
                                 fabs(r->baseline_upper_edge_mm - base->y2_mm)));
    return worst / s;
}

static void missed(FILE *out, struct accuracy_targets *t, const char *name, const char *what)
{
    t->missed++;
    fprintf(out, "TARGET MISSED: %s: %s\n", name, what);
}

/* One pair: replayed, its row printed, the tallies and targets counted. */
static int judge_pair(FILE *out, FILE *misses, const char *group, const char *moved, const char *baseline,
                      int compression_group, const struct uwb_evaluate_options *opt,
                      struct accuracy_targets *t, char *err, size_t errlen)
{
    struct accuracy_truth tc, tb;
    if (read_truth(moved, &tc, err, errlen) != 0 || read_truth(baseline, &tb, err, errlen) != 0)
        return -1;
    struct uwb_scan cur, base;
    if (uwbscan_read_file(moved, &cur, err, errlen) != 0)
        return -1;
    if (uwbscan_read_file(baseline, &base, err, errlen) != 0) {
        uwb_scan_free(&cur);
        return -1;
    }
    struct uwb_verdict v;
    int rc = accuracy_evaluate_pair(&cur, &base, opt, &v, err, errlen);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    if (rc != 0)
        return -1;
    struct uwb_verdict_record r;
    uwb_record_from_verdict(&r, &v);
    char name[128], what[256];
    pair_name(moved, name, sizeof name);
    t->pairs++;
    /* The centre's move: the shift plus half the height change. */
    double truth_mm = tc.shift_mm + 0.5 * tc.height_change_mm;
    fprintf(out, "| %s | %s | %+.2f | ", name, group, truth_mm);
    if (r.has_displacement) {
        double s = r.uncertainty_mm, e = r.axial_displacement_mm - truth_mm;
        double noise = v.uncertainty_noise_m * 1e3;
        double model = opt->compare.axial_sigma_per_shift * fabs(v.axial_displacement_m) * 1e3;
        double other = sqrt(fmax(0.0, s * s - noise * noise - model * model));
        double bound = fmax(0.5, 0.08 * fabs(truth_mm));
        t->given++;
        fprintf(out, "%+.2f ± %.2f | %.2f / %.2f / %.2f | %+.1f | ", r.axial_displacement_mm, s, noise, model,
                other, e / s);
        if (fabs(e) <= 2.0 * s)
            t->within++;
        else {
            snprintf(what, sizeof what, "displacement %+.2f ± %.2f mm for %+.2f (%.1f sigma)",
                     r.axial_displacement_mm, s, truth_mm, e / s);
            missed(misses, t, name, what);
        }
        if (s > bound + 1e-9) {
            t->wide++;
            snprintf(what, sizeof what, "sigma %.2f mm over max(0.5 mm, 8 %% of the move) = %.2f mm", s,
                     bound);
            missed(misses, t, name, what);
        }
    } else {
        fprintf(out, "withheld | | | ");
    }
    if (r.has_height_change) {
        double s = r.height_change_uncertainty_mm, e = r.height_change_mm - tc.height_change_mm;
        t->heights_given++;
        fprintf(out, "%+.2f ± %.2f for %+.0f (%+.1f) | ", r.height_change_mm, s, tc.height_change_mm,
                s > 0 ? e / s : INFINITY);
        if (fabs(e) <= 2.0 * s)
            t->heights_within++;
        else {
            snprintf(what, sizeof what, "height change %+.2f ± %.2f mm for %+.0f", r.height_change_mm, s,
                     tc.height_change_mm);
            missed(misses, t, name, what);
        }
    } else
        fprintf(out, "withheld | ");
    if (compression_group && tc.height_change_mm != 0.0) {
        t->compressions++;
        t->compressions_read +=
            r.has_height_change && fabs(r.height_change_mm - tc.height_change_mm) <= COMPRESSION_READ_MM;
    }
    if (r.has_edges) {
        double ratio = edges_ratio(&r, &tc, &tb);
        t->edges_given++;
        fprintf(out, "%.0f..%.0f ± %.1f (%.1f) | %s |\n", r.lower_edge_mm, r.upper_edge_mm,
                r.edge_uncertainty_mm, ratio, uwb_status_name(r.status));
        if (ratio <= 2.0)
            t->edges_within++;
        else {
            snprintf(what, sizeof what,
                     "edges %.1f..%.1f mm (baseline %.1f..%.1f) for %.1f..%.1f (%.1f..%.1f) at "
                     "sigma %.2f",
                     r.lower_edge_mm, r.upper_edge_mm, r.baseline_lower_edge_mm, r.baseline_upper_edge_mm,
                     tc.y1_mm, tc.y2_mm, tb.y1_mm, tb.y2_mm, r.edge_uncertainty_mm);
            missed(misses, t, name, what);
        }
    } else
        fprintf(out, "withheld | %s |\n", uwb_status_name(r.status));
    return 0;
}

/* Every moved scan of a pattern against its baseline: a fixed one, or its
 * tank's intact scan (the name up to its last "-d", then "-d+00"). */
static int judge_glob(FILE *out, FILE *misses, const char *group, const char *dir, const char *pattern,
                      const char *fixed_baseline, int compression_group,
                      const struct uwb_evaluate_options *opt, struct accuracy_targets *t, char *err,
                      size_t errlen)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, pattern);
    glob_t g;
    if (glob(path, 0, NULL, &g) != 0)
        return 0; /* none of that kind in the directory */
    int rc = 0;
    for (size_t i = 0; i < g.gl_pathc && rc == 0; i++) {
        const char *moved = g.gl_pathv[i];
        char baseline[4096];
        if (fixed_baseline)
            snprintf(baseline, sizeof baseline, "%s/%s", dir, fixed_baseline);
        else {
            const char *d = strrchr(moved, 'd');
            if (!d || d == moved || d[-1] != '-')
                continue;
            snprintf(baseline, sizeof baseline, "%.*sd+00.uwbscan", (int)(d - moved), moved);
        }
        if (!strcmp(moved, baseline) || (!fixed_baseline && strstr(moved, "-d+00.")))
            continue;
        rc = judge_pair(out, misses, group, moved, baseline, compression_group, opt, t, err, errlen);
    }
    globfree(&g);
    return rc;
}

int accuracy_targets_run(FILE *out, const char *data_dir, const char *fresh_dir,
                         const struct uwb_evaluate_options *opt, struct accuracy_targets *t, char *err,
                         size_t errlen)
{
    memset(t, 0, sizeof *t);
    char *miss_text = NULL;
    size_t miss_len = 0;
    FILE *misses = open_memstream(&miss_text, &miss_len);
    if (!misses) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    fprintf(out, "| pair | kind | true move | read ± σ | σ's terms: noise / model / other | error/σ "
                 "| height change (error/σ) | edges ± σ (worst error/σ) | status |\n");
    fprintf(out, "|---|---|---|---|---|---|---|---|---|\n");
    int rc = judge_glob(out, misses, "paper", data_dir, "fdtd2d-paper-up20mm.uwbscan",
                        "fdtd2d-paper-intact.uwbscan", 0, opt, t, err, errlen);
    if (rc == 0)
        rc = judge_glob(out, misses, "tank", data_dir, "fdtd2d-tank-d[+-]*.uwbscan",
                        "fdtd2d-tank-d+00.0.uwbscan", 0, opt, t, err, errlen);
    if (rc == 0)
        rc = judge_glob(out, misses, "radial", data_dir, "fdtd2d-tank-radial-*.uwbscan",
                        "fdtd2d-tank-d+00.0.uwbscan", 0, opt, t, err, errlen);
    struct accuracy_targets before = *t;
    if (rc == 0)
        rc = judge_glob(out, misses, "family", data_dir, "fdtd2d-var-s*-d[+-]*.uwbscan", NULL, 1, opt, t, err,
                        errlen);
    struct accuracy_targets family = *t;
    if (rc == 0)
        rc = judge_glob(out, misses, "fresh", fresh_dir, "fdtd2d-fresh-s*-d[+-]*.uwbscan", NULL, 0, opt, t,
                        err, errlen);
    struct accuracy_targets fresh = *t;
    if (rc == 0)
        rc = judge_glob(out, misses, "3-D", data_dir, "fdtd3d-var-s*-d[+-]*.uwbscan", NULL, 0, opt, t, err,
                        errlen);
    fclose(misses);
    if (rc != 0) {
        free(miss_text);
        return -1;
    }
    fprintf(out, "\n");
    const struct accuracy_targets *from[] = {&before, &family}, *to[] = {&family, &fresh};
    const char *names[] = {"shared family", "fresh draws (and their no-plate controls)"};
    for (int k = 0; k < 2; k++)
        fprintf(out,
                "%s: %d pairs, %d displacements given (%d within 2σ, %d with σ over max(0.5 mm, 8 %% of the "
                "move)), %d height changes given (%d within 2σ), %d with edges published (%d within 2σ)\n",
                names[k], to[k]->pairs - from[k]->pairs, to[k]->given - from[k]->given,
                to[k]->within - from[k]->within, to[k]->wide - from[k]->wide,
                to[k]->heights_given - from[k]->heights_given,
                to[k]->heights_within - from[k]->heights_within, to[k]->edges_given - from[k]->edges_given,
                to[k]->edges_within - from[k]->edges_within);
    fprintf(out,
            "every pair: %d, %d displacements given (%d within 2σ, %d with σ over the bound), "
            "%d height changes given (%d within 2σ), %d with edges published (%d within 2σ)\n",
            t->pairs, t->given, t->within, t->wide, t->heights_given, t->heights_within, t->edges_given,
            t->edges_within);
    fprintf(out, "the family's squeezed spacers: %d, read within %.1f mm: %d (the target: at least half)\n",
            t->compressions, COMPRESSION_READ_MM, t->compressions_read);
    if (t->compressions > 0 && 2 * t->compressions_read < t->compressions) {
        t->missed++;
        fprintf(out, "TARGET MISSED: the family's squeezed spacers: %d of %d read within %.1f mm\n",
                t->compressions_read, t->compressions, COMPRESSION_READ_MM);
    }
    fputs(miss_text, out);
    fprintf(out, "targets missed: %d\n", t->missed);
    free(miss_text);
    return 0;
}
