#include "accuracy/accuracy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "impair/impair.h"
#include "uwb/evaluate.h"
#include "uwb/geometry.h"
#include "uwb/scan.h"

const struct accuracy_case accuracy_cases[] = {
    {"paper intact -> up 20 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paper-up20mm.uwbscan", 0.020,
     "fdtd2d-paper-intact.uwbscan", "fdtd2d-paper-up20mm.uwbscan", 0.020, 0, 0},
    {"tank 0 -> +4 mm", "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004,
     "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004, 0, 0},
    {"tank 0 -> +10 mm", "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+10.0.uwbscan", 0.010,
     "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004, 0, 0},
    {"tank 0 -> +16 mm", "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+16.0.uwbscan", 0.016,
     "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004, 0, 0},
    {"tank 0 -> +30 mm", "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+30.0.uwbscan", 0.030,
     "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004, 0, 0},
    {"tank 0 -> -8 mm", "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d-08.0.uwbscan", -0.008,
     "fdtd2d-tank-d+00.0.uwbscan", "fdtd2d-tank-d+04.0.uwbscan", 0.004, 0, 0},
    /* Two members of the shared family of random tanks, pure shifts (no
     * spacer squeezed, so the truth is the shift): the derivative for the
     * bound is the pair's own secant, as for the paper's. */
    {"family s04 0 -> +26 mm", "fdtd2d-var-s04-d+00.uwbscan", "fdtd2d-var-s04-d+26.uwbscan", 0.026,
     "fdtd2d-var-s04-d+00.uwbscan", "fdtd2d-var-s04-d+26.uwbscan", 0.026, 1, 1},
    {"family s08 0 -> +14 mm", "fdtd2d-var-s08-d+00.uwbscan", "fdtd2d-var-s08-d+14.uwbscan", 0.014,
     "fdtd2d-var-s08-d+00.uwbscan", "fdtd2d-var-s08-d+14.uwbscan", 0.014, 1, 0},
};
const int accuracy_case_count = (int)(sizeof accuracy_cases / sizeof accuracy_cases[0]);

const struct accuracy_level accuracy_levels[] = {
    {20.0, 3e-12, 0.02, 0.02},
    {32.0, 3e-12, 0.02, 0.02},
};
const int accuracy_level_count = (int)(sizeof accuracy_levels / sizeof accuracy_levels[0]);

int accuracy_read_scan(const char *dir, const char *name, struct uwb_scan *s, char *err, size_t errlen)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return uwbscan_read_file(path, s, err, errlen);
}

double accuracy_crb_m(const char *path_a, const char *path_b, double shift_m, double noise_sigma,
                      double *face_cell_m, char *err, size_t errlen)
{
    struct uwb_scan a, b;
    *face_cell_m = NAN;
    if (uwbscan_read_file(path_a, &a, err, errlen) != 0)
        return NAN;
    if (uwbscan_read_file(path_b, &b, err, errlen) != 0) {
        uwb_scan_free(&a);
        return NAN;
    }
    if (a.positions != b.positions || a.samples != b.samples) {
        snprintf(err, errlen, "%s and %s differ in size", path_a, path_b);
        uwb_scan_free(&a);
        uwb_scan_free(&b);
        return NAN;
    }
    /* Where the winding's face replies, from the analysis of scan a: each
     * position's delays to the face between its edges, one period either side. */
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis an;
    int have_face = uwb_analyse_scan(&a, &opt, &an, err, errlen) == 0 && an.edges.found;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &a, 0.0);
    double all = 0.0, cell = 0.0;
    for (int k = 0; k < a.positions; k++) {
        double t_first = INFINITY, t_last = -INFINITY;
        if (have_face) {
            double ya = a.antenna_y_m[k], lo = an.edges.lower_m, hi = an.edges.upper_m, z = an.edges.face_z_m;
            double yn = ya < lo ? lo : ya > hi ? hi : ya, period = 1.0 / an.dominant_hz;
            t_first = uwb_two_way_delay(&g, yn - ya, z) - period;
            t_last = fmax(uwb_two_way_delay(&g, lo - ya, z), uwb_two_way_delay(&g, hi - ya, z)) + period;
        }
        for (int i = 0; i < a.samples; i++) {
            size_t j = (size_t)k * a.samples + i;
            double d = ((double)b.data[j] - a.data[j]) / shift_m, t = g.t0_s + i * g.dt_s;
            all += d * d;
            if (t >= t_first && t <= t_last)
                cell += d * d;
        }
    }
    if (have_face)
        uwb_analysis_free(&an);
    uwb_scan_free(&a);
    uwb_scan_free(&b);
    if (have_face && cell > 0.0)
        *face_cell_m = sqrt(2.0) * noise_sigma / sqrt(cell);
    return sqrt(2.0) * noise_sigma / sqrt(all);
}

static FILE *pair_log;

void accuracy_log_pairs(FILE *out)
{
    pair_log = out;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double accuracy_median(double *x, int n)
{
    qsort(x, (size_t)n, sizeof *x, cmp_double);
    return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

int accuracy_impaired(const struct uwb_scan *in, const struct accuracy_level *level, unsigned long long seed,
                      struct uwb_scan *out, char *err, size_t errlen)
{
    if (uwb_scan_copy(out, in, err, errlen) != 0)
        return -1;
    struct uwb_impairment imp = {level->snr_db > 0.0, level->snr_db,       level->jitter_s,
                                 level->drift_linear, level->drift_random, seed};
    if (uwb_impair_scan(out, &imp, NULL, err, errlen) != 0) {
        uwb_scan_free(out);
        return -1;
    }
    return 0;
}

int accuracy_run_case(const char *dir, const struct accuracy_case *c, const struct accuracy_level *level,
                      int pairs, unsigned long long seed_base, struct accuracy_row *row, char *err,
                      size_t errlen)
{
    memset(row, 0, sizeof *row);
    struct uwb_scan base, cur;
    if (accuracy_read_scan(dir, c->baseline, &base, err, errlen) != 0)
        return -1;
    if (accuracy_read_scan(dir, c->current, &cur, err, errlen) != 0) {
        uwb_scan_free(&base);
        return -1;
    }
    if (!level)
        pairs = 1;
    double *error = calloc((size_t)pairs, sizeof *error), *sigma = calloc((size_t)pairs, sizeof *sigma);
    double *noise_sigma = calloc((size_t)pairs, sizeof *noise_sigma);
    int rc = error && sigma && noise_sigma ? 0 : -1;
    if (rc)
        snprintf(err, errlen, "accuracy: out of memory");
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    int within = 0, figure = 0, measured = 0;
    for (int j = 0; j < pairs && rc == 0; j++) {
        struct uwb_scan nb = {0}, nc = {0};
        const struct uwb_scan *b = &base, *s = &cur;
        if (level) {
            unsigned long long seed = seed_base + 2ull * (unsigned long long)j;
            if (accuracy_impaired(&base, level, seed, &nb, err, errlen) != 0 ||
                accuracy_impaired(&cur, level, seed + 1, &nc, err, errlen) != 0) {
                uwb_scan_free(&nb);
                rc = -1;
                break;
            }
            b = &nb;
            s = &nc;
        }
        struct uwb_verdict v;
        struct uwb_analysis ca, ba;
        struct uwb_baseline_record rec = {.scan = b};
        rc = uwb_evaluate(s, b ? &rec : NULL, &opt, &v, &ca, &ba, err, errlen);
        if (rc == 0) {
            uwb_analysis_free(&ca);
            uwb_analysis_free(&ba);
        }
        if (level) {
            uwb_scan_free(&nb);
            uwb_scan_free(&nc);
        }
        if (rc != 0)
            break;
        figure += v.status != UWB_STATUS_INCONCLUSIVE;
        /* A scan where the winding was not established gives no displacement:
         * it counts against "given a figure" only. */
        if (!v.current.found || !v.baseline.found)
            continue;
        error[measured] = v.axial_displacement_m - c->true_shift_m;
        sigma[measured] = v.uncertainty_m;
        noise_sigma[measured] = v.uncertainty_noise_m;
        within += fabs(error[measured]) <= 2.0 * sigma[measured];
        if (pair_log && level)
            fprintf(pair_log, "%s pair %d: error %+.3f sigma %.3f side reflector %d/%d ratio %+.2f\n",
                    c->name, j, error[measured] * 1e3, sigma[measured] * 1e3, v.current.side_reflector,
                    v.baseline.side_reflector, error[measured] / sigma[measured]);
        measured++;
    }
    if (rc == 0 && measured == 0) {
        snprintf(err, errlen, "%s: the winding was not established in any of %d pairs", c->name, pairs);
        rc = -1;
    }
    if (rc == 0) {
        int all = pairs;
        pairs = measured;
        double sum = 0.0, worst = 0.0;
        for (int j = 0; j < pairs; j++) {
            sum += error[j];
            worst = fmax(worst, fabs(error[j]));
        }
        double mean = sum / pairs, ss = 0.0;
        for (int j = 0; j < pairs; j++)
            ss += (error[j] - mean) * (error[j] - mean);
        row->pairs = all;
        row->measured = measured;
        row->noisy = level != NULL;
        row->bias_m = mean;
        row->spread_m = pairs > 1 ? sqrt(ss / (pairs - 1)) : 0.0;
        row->worst_m = worst;
        row->median_sigma_m = accuracy_median(sigma, pairs);
        row->median_noise_sigma_m = accuracy_median(noise_sigma, pairs);
        row->within_2sigma = (double)within / measured; /* of the errors: a pair without one gave no figure */
        row->with_figure = (double)figure / all;
        if (level) {
            struct uwb_impairment_report rep;
            struct uwb_impairment none = {1, level->snr_db, 0.0, 0.0, 0.0, 0};
            struct uwb_scan copy;
            rc = uwb_scan_copy(&copy, &base, err, errlen);
            if (rc == 0)
                rc = uwb_impair_scan(&copy, &none, &rep, err, errlen);
            if (rc == 0) {
                char pa[4096], pb[4096];
                snprintf(pa, sizeof pa, "%s/%s", dir, c->deriv_a);
                snprintf(pb, sizeof pb, "%s/%s", dir, c->deriv_b);
                row->crb_m = accuracy_crb_m(pa, pb, c->deriv_shift_m, rep.noise_sigma, &row->crb_face_cell_m,
                                            err, errlen);
                if (isnan(row->crb_m))
                    rc = -1;
                uwb_scan_free(&copy);
            }
        }
    }
    free(error);
    free(sigma);
    free(noise_sigma);
    uwb_scan_free(&base);
    uwb_scan_free(&cur);
    return rc;
}

void accuracy_print_header(FILE *out)
{
    fprintf(out, "| pair | noise | pairs | bias | spread (1σ) | worst | σ reported (median) | spread / σ "
                 "| σ's noise part (median) | spread / that | within 2σ | given a figure | Cramér–Rao bound "
                 "| spread / bound | bound, face cell only "
                 "| spread / that |\n");
    fprintf(out, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

void accuracy_print_row(FILE *out, const struct accuracy_case *c, const struct accuracy_level *level,
                        const struct accuracy_row *r)
{
    char pairs[48];
    if (r->measured == r->pairs)
        snprintf(pairs, sizeof pairs, "%d", r->pairs);
    else /* the winding not established in some: they have no error */
        snprintf(pairs, sizeof pairs, "%d (%d measured)", r->pairs, r->measured);
    if (!level) {
        fprintf(out, "| %s | none | 1 | %+.2f | — | %.2f | %.2f | — | %.2f | — | %s | %s | — | — | — | — |\n",
                c->name, r->bias_m * 1e3, r->worst_m * 1e3, r->median_sigma_m * 1e3,
                r->median_noise_sigma_m * 1e3, r->within_2sigma > 0.5 ? "yes" : "no",
                r->with_figure > 0.5 ? "yes" : "no");
        return;
    }
    fprintf(out,
            "| %s | %.0f dB | %s | %+.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f %% | %.0f %% | "
            "%.3f | %.1f | "
            "%.3f | %.1f |\n",
            c->name, level->snr_db, pairs, r->bias_m * 1e3, r->spread_m * 1e3, r->worst_m * 1e3,
            r->median_sigma_m * 1e3, r->median_sigma_m > 0 ? r->spread_m / r->median_sigma_m : INFINITY,
            r->median_noise_sigma_m * 1e3,
            r->median_noise_sigma_m > 0 ? r->spread_m / r->median_noise_sigma_m : INFINITY,
            100.0 * r->within_2sigma, 100.0 * r->with_figure, r->crb_m * 1e3,
            r->crb_m > 0 ? r->spread_m / r->crb_m : INFINITY, r->crb_face_cell_m * 1e3,
            r->crb_face_cell_m > 0 ? r->spread_m / r->crb_face_cell_m : INFINITY);
}

int accuracy_evaluate_pair(const struct uwb_scan *cur, const struct uwb_scan *base,
                           const struct uwb_evaluate_options *opt, struct uwb_verdict *v, char *err,
                           size_t errlen)
{
    struct uwb_analysis ca, ba;
    struct uwb_baseline_record rec = {.scan = base};
    if (uwb_evaluate(cur, &rec, opt, v, &ca, &ba, err, errlen) != 0)
        return -1;
    uwb_analysis_free(&ca);
    uwb_analysis_free(&ba);
    return 0;
}
