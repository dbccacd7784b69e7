/* Issue 18: the face profile drawn in the comparison PNG is the one the
 * edges were read from. On the paper pair, each scan's drawn curve (the
 * points the drawing code plots) crosses half its peak at the heights the
 * analysis reports as that scan's edges. */
#include "unity.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixture_support.h"
#include "uwb/analysis.h"
#include "output/render_internal.h"

void setUp(void)
{
}
void tearDown(void)
{
}

/* The row (fractional) where the polyline crosses column x_half walking out
 * from its rightmost point toward decreasing (dir -1) or increasing (+1)
 * rows; NAN if it never does. */
static double crossing_row(const int *xs, const int *ys, int n, double x_half, int dir)
{
    int top = 0;
    for (int i = 1; i < n; i++)
        if (xs[i] > xs[top])
            top = i;
    /* Polyline points run along the profile (rows decreasing as y rises). */
    for (int i = top; i + dir >= 0 && i + dir < n; i += dir) {
        int j = i + dir;
        if (xs[i] >= x_half && xs[j] < x_half) {
            double f = (xs[i] - x_half) / (double)(xs[i] - xs[j]);
            return ys[i] + f * (ys[j] - ys[i]);
        }
    }
    return NAN;
}

static void check_curve_crosses_half_at_edges(const struct uwb_plot *pp, const struct uwb_analysis *a,
                                              const char *which)
{
    int *xs = malloc(sizeof *xs * (size_t)a->profile.n), *ys = malloc(sizeof *ys * (size_t)a->profile.n);
    TEST_ASSERT_NOT_NULL(xs);
    TEST_ASSERT_NOT_NULL(ys);
    int n = uwb_comparison_profile_polyline(pp, &a->profile, xs, ys);
    TEST_ASSERT_TRUE_MESSAGE(n > 50, which);
    double x_half = uwb_plot_px_x(pp, 0.5);
    /* ys grow with the sample index downward on the page: y up = row down. */
    double row_upper = crossing_row(xs, ys, n, x_half, +1), row_lower = crossing_row(xs, ys, n, x_half, -1);
    double want_lower = uwb_plot_px_y(pp, a->edges.lower_m), want_upper = uwb_plot_px_y(pp, a->edges.upper_m);
    char msg[200];
    snprintf(msg, sizeof msg,
             "%s: curve crosses half at rows %.1f / %.1f, edges %.3f / %.3f m at rows %.1f / %.1f", which,
             row_lower, row_upper, a->edges.lower_m, a->edges.upper_m, want_lower, want_upper);
    printf("%s\n", msg);
    /* A pixel row here is about 1.2 mm; the curve's points are whole pixels. */
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(1.5, want_lower, row_lower, msg);
    TEST_ASSERT_DOUBLE_WITHIN_MESSAGE(1.5, want_upper, row_upper, msg);
    free(xs);
    free(ys);
}

static void test_drawn_profiles_cross_half_peak_at_the_reported_edges(void)
{
    struct uwb_scan cur_scan, base_scan;
    fixture_load_scan(FIXTURE_UP20, &cur_scan);
    fixture_load_scan(FIXTURE_INTACT, &base_scan);
    struct uwb_analysis_options opt;
    uwb_analysis_defaults(&opt);
    struct uwb_analysis cur, base;
    char err[256];
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(&cur_scan, &opt, &cur, err, sizeof err), err);
    TEST_ASSERT_EQUAL_INT_MESSAGE(0, uwb_analyse_scan(&base_scan, &opt, &base, err, sizeof err), err);
    TEST_ASSERT_TRUE_MESSAGE(cur.edges.found && base.edges.found, "both scans' windings found");
    struct uwb_verdict v;
    memset(&v, 0, sizeof v);
    v.status = UWB_STATUS_ALARM;
    v.current = cur.edges;
    v.baseline = base.edges;
    v.has_baseline = 1;
    struct uwb_plot pb, pc, pd, pp;
    int bar_x, bar_w;
    uwb_render_comparison_layout(&cur, &base, &v, NULL, &pb, &pc, &pd, &pp, &bar_x, &bar_w);
    check_curve_crosses_half_at_edges(&pp, &cur, "up 20 mm");
    check_curve_crosses_half_at_edges(&pp, &base, "intact");
    uwb_analysis_free(&cur);
    uwb_analysis_free(&base);
    uwb_scan_free(&cur_scan);
    uwb_scan_free(&base_scan);
}

int main(void)
{
    UNITY_BEGIN();
    RUN_TEST(test_drawn_profiles_cross_half_peak_at_the_reported_edges);
    return UNITY_END();
}
