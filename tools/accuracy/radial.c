#include "accuracy/radial.h"
#include "accuracy/accuracy.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "uwb/evaluate.h"
#include "uwb/scan.h"

#define TANK "fdtd2d-tank-d+00.0.uwbscan"

/* Truth: the radial files' `radial` (heights in the scan's own y). */
const struct radial_case radial_cases[] = {
    {"tank disks 2-4 +4 mm", TANK, "fdtd2d-tank-radial-r2-4+4-d+00.0.uwbscan", 0.004, 0.254, 0.320,
     .disks = 3},
    {"tank disks 3-5 -4 mm", TANK, "fdtd2d-tank-radial-r3-5-4-d+00.0.uwbscan", -0.004, 0.278, 0.344,
     .disks = 3},
    {"tank disks 5-7 +8 mm", TANK, "fdtd2d-tank-radial-r5-7+8-d+00.0.uwbscan", 0.008, 0.326, 0.392,
     .disks = 3},
    {"tank disks 4-5 +6 mm, up 10 mm", TANK, "fdtd2d-tank-radial-r4-5+6-d+10.0.uwbscan", 0.006, 0.312, 0.354,
     .disks = 2},
    /* The fresh draws' bulges, dents and leans (tools/fdtd/draw_deformed.py;
     * a lean on the 2 mm grid is a staircase: its tilt as uwbd reads one). */
    {"fresh s101 leaning, top disk +4 mm", "fdtd2d-fresh-s101-d+00.uwbscan",
     "fdtd2d-fresh-s101-lean+3.uwbscan", 0, 0, 0, .tilt_m = 0.00424, .clean_only = 1},
    {"fresh s101 leaning, top disk +6 mm", "fdtd2d-fresh-s101-d+00.uwbscan",
     "fdtd2d-fresh-s101-lean+6.uwbscan", 0, 0, 0, .tilt_m = 0.00620, .clean_only = 1},
    {"fresh s101 disks 2-4 +6 mm", "fdtd2d-fresh-s101-d+00.uwbscan", "fdtd2d-fresh-s101-r2-4+6.uwbscan",
     0.006, 0.244, 0.320, .disks = 3, .clean_only = 1},
    {"fresh s101 disks 3-4 -4 mm", "fdtd2d-fresh-s101-d+00.uwbscan", "fdtd2d-fresh-s101-r3-4-4.uwbscan",
     -0.004, 0.272, 0.320, .disks = 2, .clean_only = 1},
    {"fresh s102 leaning, top disk +6 mm", "fdtd2d-fresh-s102-d+00.uwbscan",
     "fdtd2d-fresh-s102-lean+6.uwbscan", 0, 0, 0, .tilt_m = 0.00653, .clean_only = 1},
    {"fresh s102 disks 2-5 +8 mm", "fdtd2d-fresh-s102-d+00.uwbscan", "fdtd2d-fresh-s102-r2-5+8.uwbscan",
     0.008, 0.268, 0.360, .disks = 4, .clean_only = 1},
    {"fresh s102 disks 6-7 +4 mm", "fdtd2d-fresh-s102-d+00.uwbscan", "fdtd2d-fresh-s102-r6-7+4.uwbscan",
     0.004, 0.364, 0.408, .disks = 2, .clean_only = 1},
    {"fresh s105 leaning, top disk +4 mm", "fdtd2d-fresh-s105-d+00.uwbscan",
     "fdtd2d-fresh-s105-lean+3.uwbscan", 0, 0, 0, .tilt_m = 0.00381, .clean_only = 1},
    {"fresh s105 disks 1-2 -6 mm", "fdtd2d-fresh-s105-d+00.uwbscan", "fdtd2d-fresh-s105-r1-2-6.uwbscan",
     -0.006, 0.256, 0.296, .disks = 2, .clean_only = 1},
    {"fresh s105 disks 3-5 +6 mm", "fdtd2d-fresh-s105-d+00.uwbscan", "fdtd2d-fresh-s105-r3-5+6.uwbscan",
     0.006, 0.304, 0.368, .disks = 3, .clean_only = 1},
    {"fresh s106 leaning, top disk +6 mm", "fdtd2d-fresh-s106-d+00.uwbscan",
     "fdtd2d-fresh-s106-lean+6.uwbscan", 0, 0, 0, .tilt_m = 0.00685, .clean_only = 1},
    {"fresh s106 disks 4-6 +4 mm", "fdtd2d-fresh-s106-d+00.uwbscan", "fdtd2d-fresh-s106-r4-6+4.uwbscan",
     0.004, 0.320, 0.394, .disks = 3, .clean_only = 1},
    {"fresh s107 leaning, top disk -6 mm", "fdtd2d-fresh-s107-d+00.uwbscan",
     "fdtd2d-fresh-s107-lean-6.uwbscan", 0, 0, 0, .tilt_m = -0.00624, .clean_only = 1},
    {"fresh s107 disks 1-3 -4 mm", "fdtd2d-fresh-s107-d+00.uwbscan", "fdtd2d-fresh-s107-r1-3-4.uwbscan",
     -0.004, 0.256, 0.322, .disks = 3, .clean_only = 1},
    {"fresh s107 disks 4-5 +8 mm", "fdtd2d-fresh-s107-d+00.uwbscan", "fdtd2d-fresh-s107-r4-5+8.uwbscan",
     0.008, 0.328, 0.370, .disks = 2, .clean_only = 1},
    {"fresh s102 disk 3 +4 mm", "fdtd2d-fresh-s102-d+00.uwbscan", "fdtd2d-fresh-s102-r3-3+4.uwbscan", 0.004,
     0.292, 0.312, .disks = 1, .clean_only = 1},
    {"fresh s105 disk 4 +4 mm", "fdtd2d-fresh-s105-d+00.uwbscan", "fdtd2d-fresh-s105-r4-4+4.uwbscan", 0.004,
     0.328, 0.344, .disks = 1, .clean_only = 1},
    /* Drawn after the radial and tilt terms were set: the deformation of
     * each by a rule, not by choice (tank seed s: random.Random(1000 + s)
     * draws the first disk, 1-3 disks, the size from -6, -4, +4, +6, +8 and
     * the lean from -6, -3, +3, +6 mm). */
    {"fresh s111 leaning, top disk -4 mm", "fdtd2d-fresh-s111-d+00.uwbscan",
     "fdtd2d-fresh-s111-lean-3.uwbscan", 0, 0, 0, .tilt_m = -0.00429, .clean_only = 1},
    {"fresh s111 disks 2-3 +4 mm", "fdtd2d-fresh-s111-d+00.uwbscan", "fdtd2d-fresh-s111-r2-3+4.uwbscan",
     0.004, 0.268, 0.314, .disks = 2, .clean_only = 1},
    {"fresh s112 leaning, top disk -6 mm", "fdtd2d-fresh-s112-d+00.uwbscan",
     "fdtd2d-fresh-s112-lean-6.uwbscan", 0, 0, 0, .tilt_m = -0.00624, .clean_only = 1},
    {"fresh s112 disks 3-4 +4 mm", "fdtd2d-fresh-s112-d+00.uwbscan", "fdtd2d-fresh-s112-r3-4+4.uwbscan",
     0.004, 0.264, 0.306, .disks = 2, .clean_only = 1},
    {"fresh s113 leaning, top disk -6 mm", "fdtd2d-fresh-s113-d+00.uwbscan",
     "fdtd2d-fresh-s113-lean-6.uwbscan", 0, 0, 0, .tilt_m = -0.00670, .clean_only = 1},
    {"fresh s113 disks 1-2 -4 mm", "fdtd2d-fresh-s113-d+00.uwbscan", "fdtd2d-fresh-s113-r1-2-4.uwbscan",
     -0.004, 0.224, 0.274, .disks = 2, .clean_only = 1},
    {"fresh s114 leaning, top disk +6 mm", "fdtd2d-fresh-s114-d+00.uwbscan",
     "fdtd2d-fresh-s114-lean+6.uwbscan", 0, 0, 0, .tilt_m = 0.00677, .clean_only = 1},
    {"fresh s114 disks 5-7 +6 mm", "fdtd2d-fresh-s114-d+00.uwbscan", "fdtd2d-fresh-s114-r5-7+6.uwbscan",
     0.006, 0.310, 0.382, .disks = 3, .clean_only = 1},
    /* The five fresh tanks not deformed before, by rule after the fixes of
     * issue 45 (random.Random(4000 + s): 2-4 disks, the first, the size
     * from -6, -4, +4, +6, +8 mm, the lean from -6, -3, +3, +6 mm). */
    {"fresh s103 leaning, top disk +6 mm", "fdtd2d-fresh-s103-d+00.uwbscan",
     "fdtd2d-fresh-s103-lean+6.uwbscan", 0, 0, 0, .tilt_m = 0.00668, .clean_only = 1},
    {"fresh s103 disks 1-3 -4 mm", "fdtd2d-fresh-s103-d+00.uwbscan", "fdtd2d-fresh-s103-r1-3-4.uwbscan",
     -0.004, 0.234, 0.306, .disks = 3, .clean_only = 1},
    {"fresh s104 leaning, top disk -2 mm", "fdtd2d-fresh-s104-d+00.uwbscan",
     "fdtd2d-fresh-s104-lean-3.uwbscan", 0, 0, 0, .tilt_m = -0.00291, .clean_only = 1},
    {"fresh s104 disks 1-4 +6 mm", "fdtd2d-fresh-s104-d+00.uwbscan", "fdtd2d-fresh-s104-r1-4+6.uwbscan",
     0.006, 0.204, 0.312, .disks = 4, .clean_only = 1},
    {"fresh s108 leaning, top disk +2 mm", "fdtd2d-fresh-s108-d+00.uwbscan",
     "fdtd2d-fresh-s108-lean+3.uwbscan", 0, 0, 0, .tilt_m = 0.00288, .clean_only = 1},
    {"fresh s108 disks 2-5 -6 mm", "fdtd2d-fresh-s108-d+00.uwbscan", "fdtd2d-fresh-s108-r2-5-6.uwbscan",
     -0.006, 0.254, 0.330, .disks = 4, .clean_only = 1},
    {"fresh s109 leaning, top disk -4 mm", "fdtd2d-fresh-s109-d+00.uwbscan",
     "fdtd2d-fresh-s109-lean-3.uwbscan", 0, 0, 0, .tilt_m = -0.00479, .clean_only = 1},
    {"fresh s109 disks 1-3 +4 mm", "fdtd2d-fresh-s109-d+00.uwbscan", "fdtd2d-fresh-s109-r1-3+4.uwbscan",
     0.004, 0.254, 0.332, .disks = 3, .clean_only = 1},
    {"fresh s110 leaning, top disk -4 mm", "fdtd2d-fresh-s110-d+00.uwbscan",
     "fdtd2d-fresh-s110-lean-3.uwbscan", 0, 0, 0, .tilt_m = -0.00477, .clean_only = 1},
    {"fresh s110 disks 2-4 -4 mm", "fdtd2d-fresh-s110-d+00.uwbscan", "fdtd2d-fresh-s110-r2-4-4.uwbscan",
     -0.004, 0.252, 0.324, .disks = 3, .clean_only = 1},
    /* The paper's scene deformed (tools/fdtd/draw_paper.py; its intact scan
     * is the shared one, sample for sample). */
    {"paper scene disks 1-3 +8 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r1-3+8.uwbscan", 0.008,
     0.230, 0.304, .disks = 3, .clean_only = 1, .in_air = 1},
    {"paper scene disks 2-4 +4 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r2-4+4.uwbscan", 0.004,
     0.256, 0.330, .disks = 3, .clean_only = 1, .in_air = 1},
    {"paper scene disks 3-5 -6 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r3-5-6.uwbscan", -0.006,
     0.282, 0.356, .disks = 3, .clean_only = 1, .in_air = 1},
    {"paper scene disks 4-6 +8 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r4-6+8.uwbscan", 0.008,
     0.308, 0.382, .disks = 3, .clean_only = 1, .in_air = 1},
    /* Drawn by rule (random.Random(3000 + k): the first disk, 2-4 disks, the
     * size), after the size's sigma was set: 4 of 6 disks, one reaching the
     * face's top. */
    {"paper scene disks 2-5 +6 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r2-5+6.uwbscan", 0.006,
     0.256, 0.356, .disks = 4, .clean_only = 1, .in_air = 1},
    {"paper scene disks 3-6 +6 mm", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paperscene-r3-6+6.uwbscan", 0.006,
     0.282, 0.382, .disks = 4, .clean_only = 1, .in_air = 1},
    /* The shared tank (tools/fdtd/draw_tank_radial.py) bulged over 2 and 4
     * of its 7 disks, the kind the kept-back scenes were, one pair
     * reaching the face's top with the winding moved up 10 mm. */
    {"tank disks 1-4 +8 mm", TANK, "fdtd2d-tankfresh-radial-r1-4+8.uwbscan", 0.008, 0.230, 0.320, .disks = 4,
     .clean_only = 1},
    {"tank disks 5-6 +4 mm", TANK, "fdtd2d-tankfresh-radial-r5-6+4.uwbscan", 0.004, 0.326, 0.368, .disks = 2,
     .clean_only = 1},
    {"tank disks 5-6 +8 mm", TANK, "fdtd2d-tankfresh-radial-r5-6+8.uwbscan", 0.008, 0.326, 0.368, .disks = 2,
     .clean_only = 1},
    {"tank disks 6-7 +8 mm, up 10 mm", TANK, "fdtd2d-tankfresh-radial-r6-7+8-d+10.uwbscan", 0.008, 0.360,
     0.402, .disks = 2, .clean_only = 1},
    /* Drawn by rule after those were read right (random.Random(2000 + k),
     * k = 1..8: 2-4 disks, the first, the size from -6, -4, +4, +6, +8 mm,
     * moved up 0 or 10 mm; k = 4 is disks 1-4 +8 above). */
    {"tank disks 1-4 +4 mm", TANK, "fdtd2d-tankfresh-radial-r1-4+4.uwbscan", 0.004, 0.230, 0.320, .disks = 4,
     .clean_only = 1},
    {"tank disks 1-4 +8 mm, up 10 mm", TANK, "fdtd2d-tankfresh-radial-r1-4+8-d+10.uwbscan", 0.008, 0.240,
     0.330, .disks = 4, .clean_only = 1},
    {"tank disks 6-7 +8 mm", TANK, "fdtd2d-tankfresh-radial-r6-7+8.uwbscan", 0.008, 0.350, 0.392, .disks = 2,
     .clean_only = 1},
    {"tank disks 1-3 -6 mm, up 10 mm", TANK, "fdtd2d-tankfresh-radial-r1-3-6-d+10.uwbscan", -0.006, 0.240,
     0.306, .disks = 3, .clean_only = 1},
    {"tank disks 4-7 -6 mm", TANK, "fdtd2d-tankfresh-radial-r4-7-6.uwbscan", -0.006, 0.302, 0.392, .disks = 4,
     .clean_only = 1},
    {"tank disks 6-7 -6 mm, up 10 mm", TANK, "fdtd2d-tankfresh-radial-r6-7-6-d+10.uwbscan", -0.006, 0.360,
     0.402, .disks = 2, .clean_only = 1},
    {"tank disks 5-6 +6 mm", TANK, "fdtd2d-tankfresh-radial-r5-6+6.uwbscan", 0.006, 0.326, 0.368, .disks = 2,
     .clean_only = 1},
    {"paper up 20 mm (no change)", "fdtd2d-paper-intact.uwbscan", "fdtd2d-paper-up20mm.uwbscan", 0, 0, 0,
     .tilt_m = 0},
    {"tank +4 mm (no change)", TANK, "fdtd2d-tank-d+04.0.uwbscan", 0, 0, 0, .tilt_m = 0},
    {"tank +10 mm (no change)", TANK, "fdtd2d-tank-d+10.0.uwbscan", 0, 0, 0, .tilt_m = 0},
    {"tank +16 mm (no change)", TANK, "fdtd2d-tank-d+16.0.uwbscan", 0, 0, 0, .tilt_m = 0},
    {"tank +30 mm (no change)", TANK, "fdtd2d-tank-d+30.0.uwbscan", 0, 0, 0, .tilt_m = 0},
    {"tank -8 mm (no change)", TANK, "fdtd2d-tank-d-08.0.uwbscan", 0, 0, 0, .tilt_m = 0},
    {"family s01 +2 mm, spacer -2 mm (no change)", "fdtd2d-var-s01-d+00.uwbscan",
     "fdtd2d-var-s01-d+02.uwbscan", 0, 0, 0, .tilt_m = 0},
};
const int radial_case_count = (int)(sizeof radial_cases / sizeof radial_cases[0]);

/* Whether a change was read with the truth's sign, or in its place: right
 * or wrong on a clean pair, the share over noisy ones; "—" for a pure
 * shift (no change to place) or nothing measured. */
static void right_or_wrong(char *out, size_t outlen, const struct radial_case *c,
                           const struct accuracy_level *level, const struct radial_row *r, double share)
{
    if (c->change_m == 0.0 || r->measured == 0)
        snprintf(out, outlen, "—");
    else if (!level)
        snprintf(out, outlen, "%s", share == 1.0 ? "right" : "**wrong**");
    else
        snprintf(out, outlen, "%.0f %%", 100.0 * share);
}

/* One pair's verdict at the defaults: 0, or -1 with err. */
static int evaluate_pair(const struct uwb_scan *cur, const struct uwb_scan *base, struct uwb_verdict *v,
                         char *err, size_t errlen)
{
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    return accuracy_evaluate_pair(cur, base, &opt, v, err, errlen);
}

struct tally {
    double *error, *sigma, *noise;
    int measured, within, located, sign_right, watch, alarm, n, tilt_withheld, tilt_within;
    double tilt_worst;
    int least, least_right, least_watch;
    double least_m;
};

/* A change read with the truth's sign and in its place (+-10 mm). */
static int sign_and_place_right(const struct radial_case *c, double change_m, double at_m)
{
    return c->change_m != 0.0 && (change_m > 0.0) == (c->change_m > 0.0) && at_m >= c->from_m - 0.010 &&
           at_m <= c->to_m + 0.010;
}

static void count(struct tally *t, const struct radial_case *c, const struct uwb_verdict *v)
{
    t->n++;
    const struct uwb_radial_verdict *r = &v->radial;
    if (!r->measured && r->change_least_m != 0.0) {
        t->least++;
        t->least_m = r->change_least_m;
        t->least_watch += r->status == UWB_STATUS_WATCH || r->status == UWB_STATUS_ALARM;
        t->least_right += sign_and_place_right(c, r->change_least_m, r->at_m);
    }
    if (!r->measured)
        return;
    double e = r->max_change_m - c->change_m;
    t->error[t->measured] = e;
    t->sigma[t->measured] = r->uncertainty_m;
    t->noise[t->measured] = r->uncertainty_noise_m;
    t->measured++;
    t->within += fabs(e) <= 2.0 * r->uncertainty_m;
    t->located += c->change_m != 0.0 && r->at_m >= c->from_m - 0.010 && r->at_m <= c->to_m + 0.010;
    t->sign_right += c->change_m != 0.0 && (r->max_change_m > 0.0) == (c->change_m > 0.0);
    t->watch += r->status == UWB_STATUS_WATCH || r->status == UWB_STATUS_ALARM;
    t->alarm += r->status == UWB_STATUS_ALARM;
    if (r->tilt_withheld[0]) {
        t->tilt_withheld++; /* no lean read: not a 0 to count */
    } else {
        t->tilt_worst = fmax(t->tilt_worst, fabs(r->tilt_m - c->tilt_m));
        t->tilt_within += fabs(r->tilt_m - c->tilt_m) <= 2.0 * r->tilt_uncertainty_m;
    }
}

static void summarise(struct tally *t, struct radial_row *row)
{
    row->pairs = t->n;
    row->measured = t->measured;
    row->least = t->least;
    row->least_right = t->least > 0 ? (double)t->least_right / t->least : 0.0;
    row->least_m = t->least_m;
    if (t->measured == 0 && t->least > 0)
        row->watch_or_worse = (double)t->least_watch / t->least;
    if (t->measured == 0)
        return;
    double sum = 0.0, worst = 0.0;
    for (int j = 0; j < t->measured; j++) {
        sum += t->error[j];
        worst = fmax(worst, fabs(t->error[j]));
    }
    double mean = sum / t->measured, ss = 0.0;
    for (int j = 0; j < t->measured; j++)
        ss += (t->error[j] - mean) * (t->error[j] - mean);
    int m = t->measured;
    row->median_noise_sigma_m = accuracy_median(t->noise, m);
    row->bias_m = mean;
    row->spread_m = m > 1 ? sqrt(ss / (m - 1)) : 0.0;
    row->worst_m = worst;
    row->median_sigma_m = accuracy_median(t->sigma, m);
    row->within_2sigma = (double)t->within / m;
    row->located = (double)t->located / m;
    row->sign_right = (double)t->sign_right / m;
    row->watch_or_worse = (double)t->watch / m;
    row->alarm = (double)t->alarm / m;
    row->tilt_worst_m = t->tilt_worst;
    row->tilt_withheld = t->tilt_withheld;
    row->tilt_within_2sigma =
        t->measured > t->tilt_withheld ? (double)t->tilt_within / (t->measured - t->tilt_withheld) : 0.0;
}

int radial_run_case(const char *dir, const struct radial_case *c, const struct accuracy_level *level,
                    int pairs, unsigned long long seed_base, struct radial_row *row, char *err, size_t errlen)
{
    memset(row, 0, sizeof *row);
    if (!level)
        pairs = 1;
    struct uwb_scan base = {0}, cur = {0};
    struct tally t = {.error = calloc((size_t)pairs, sizeof(double)),
                      .sigma = calloc((size_t)pairs, sizeof(double)),
                      .noise = calloc((size_t)pairs, sizeof(double))};
    int rc = -1;
    if (!t.error || !t.sigma || !t.noise) {
        snprintf(err, errlen, "radial accuracy: out of memory");
        goto done;
    }
    if (accuracy_read_scan(dir, c->baseline, &base, err, errlen) != 0 ||
        accuracy_read_scan(dir, c->current, &cur, err, errlen) != 0)
        goto done;
    for (int j = 0; j < pairs; j++) {
        struct uwb_scan nb = {0}, nc = {0};
        unsigned long long seed = seed_base + 2ull * (unsigned long long)j;
        if (level && (accuracy_impaired(&base, level, seed, &nb, err, errlen) != 0 ||
                      accuracy_impaired(&cur, level, seed + 1, &nc, err, errlen) != 0)) {
            uwb_scan_free(&nb);
            goto done;
        }
        struct uwb_verdict v;
        int ok = evaluate_pair(level ? &nc : &cur, level ? &nb : &base, &v, err, errlen);
        uwb_scan_free(&nb);
        uwb_scan_free(&nc);
        if (ok != 0)
            goto done;
        count(&t, c, &v);
    }
    summarise(&t, row);
    rc = 0;
done:
    free(t.error);
    free(t.sigma);
    free(t.noise);
    uwb_scan_free(&base);
    uwb_scan_free(&cur);
    return rc;
}

void radial_print_header(FILE *out)
{
    fprintf(out,
            "| pair | noise | pairs | true change | read (bias) | spread (1σ) | worst error | σ reported "
            "(median) | spread / σ | its noise part | spread / that | within 2σ | sign right | place right "
            "(±10 mm) "
            "| watch or alarm | true tilt | tilt's largest error (within 2σ) |\n");
    fprintf(out, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

void radial_print_row(FILE *out, const struct radial_case *c, const struct accuracy_level *level,
                      const struct radial_row *r)
{
    char noise[32], pairs[48], read[24], spread[16], ratio[16], noise_ratio[16], located[32], sign[16],
        tilt[64];
    snprintf(noise, sizeof noise, level ? "%.0f dB" : "none", level ? level->snr_db : 0.0);
    if (r->measured == r->pairs)
        snprintf(pairs, sizeof pairs, "%d", r->pairs);
    else
        snprintf(pairs, sizeof pairs, "%d (%d measured)", r->pairs, r->measured);
    snprintf(spread, sizeof spread, level ? "%.2f" : "—", r->spread_m * 1e3);
    snprintf(ratio, sizeof ratio, level && r->median_sigma_m > 0 ? "%.2f" : "—",
             r->median_sigma_m > 0 ? r->spread_m / r->median_sigma_m : 0.0);
    snprintf(noise_ratio, sizeof noise_ratio, level && r->median_noise_sigma_m > 0 ? "%.2f" : "—",
             r->median_noise_sigma_m > 0 ? r->spread_m / r->median_noise_sigma_m : 0.0);
    /* Nothing measured: no reading to show (the bias of none is 0); a size
     * withheld as a least value: that least, its sign and place, and its
     * status, watch or alarm, in the columns' stead. */
    snprintf(read, sizeof read, r->measured > 0 ? "%+.2f" : "withheld", (c->change_m + r->bias_m) * 1e3);
    right_or_wrong(located, sizeof located, c, level, r, r->located);
    right_or_wrong(sign, sizeof sign, c, level, r, r->sign_right);
    if (r->measured == 0 && r->least > 0 && !level) {
        snprintf(read, sizeof read, "≥ %+.2f", r->least_m * 1e3);
        snprintf(located, sizeof located, "%s (size withheld)",
                 r->least_right == 1.0 ? "right" : "**wrong**");
        snprintf(sign, sizeof sign, "%s", r->least_right == 1.0 ? "right" : "**wrong**");
    }
    if (r->measured > 0 && r->tilt_withheld == r->measured)
        snprintf(tilt, sizeof tilt, "withheld");
    else if (r->tilt_withheld > 0)
        snprintf(tilt, sizeof tilt, "%.2f (%.0f %%; %d withheld)", r->tilt_worst_m * 1e3,
                 100.0 * r->tilt_within_2sigma, r->tilt_withheld);
    else
        snprintf(tilt, sizeof tilt, "%.2f (%.0f %%)", r->tilt_worst_m * 1e3, 100.0 * r->tilt_within_2sigma);
    fprintf(out,
            "| %s | %s | %s | %+.2f | %s | %s | %.2f | %.2f | %s | %.2f | %s | %.0f %% | %s | %s | %.0f %% "
            "| %+.2f | %s |\n",
            c->name, noise, pairs, c->change_m * 1e3, read, spread, r->worst_m * 1e3, r->median_sigma_m * 1e3,
            ratio, r->median_noise_sigma_m * 1e3, noise_ratio, 100.0 * r->within_2sigma, sign, located,
            100.0 * r->watch_or_worse, c->tilt_m * 1e3, tilt);
}
