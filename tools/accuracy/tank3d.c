#include "accuracy/tank3d.h"

#include <math.h>
#include <string.h>

#include "accuracy/accuracy.h"
#include "uwb/evaluate.h"
#include "uwb/scan.h"
#include "uwb/verdict_record.h"

#define S011 "fdtd3d-var-s011-d+00.uwbscan"
#define S012 "fdtd3d-var-s012-d+00.uwbscan"
#define S201 "fdtd3d-fresh-s201-d+00.uwbscan"
#define S203 "fdtd3d-fresh-s203-d+00.uwbscan"

/* Truth: y1_m, y2_m of each tank's intact scan (the span) and the moved
 * scan's displacement_mm + height_change_mm / 2. */
const struct tank3d_case tank3d_cases[] = {
    {"3-D s011 +5 mm", 0, S011, "fdtd3d-var-s011-d+05.uwbscan", 0.005, {0.230, 0.395}},
    {"3-D s011 -25 mm, spacer -5 mm", 0, S011, "fdtd3d-var-s011-d-25.uwbscan", -0.0275, {0.230, 0.395}},
    {"3-D s012 +10 mm, spacer -5 mm", 0, S012, "fdtd3d-var-s012-d+10.uwbscan", 0.0075, {0.230, 0.420}},
    {"3-D s012 -20 mm", 0, S012, "fdtd3d-var-s012-d-20.uwbscan", -0.020, {0.230, 0.420}},
    /* Drawn here (tools/fdtd/draw_tank3d.py): its intact scan found the face
     * search's column past a plate edge blurred past the travel. */
    {"3-D fresh s201 -30 mm", 1, S201, "fdtd3d-fresh-s201-d-30.uwbscan", -0.030, {0.235, 0.430}},
    /* The second drawn (7 disks, its lower plate 10 mm in front of the face),
     * scanned after the fixes of this issue. */
    {"3-D fresh s203 +20 mm", 1, S203, "fdtd3d-fresh-s203-d+20.uwbscan", 0.020, {0.220, 0.420}},
};
const int tank3d_case_count = (int)(sizeof tank3d_cases / sizeof tank3d_cases[0]);

int tank3d_run_case(const char *dir, const struct tank3d_case *c, int with_span, struct tank3d_row *row,
                    char *err, size_t errlen)
{
    memset(row, 0, sizeof *row);
    row->with_span = with_span;
    struct uwb_scan base = {0}, cur = {0};
    if (accuracy_read_scan(dir, c->baseline, &base, err, errlen) != 0)
        return -1;
    if (accuracy_read_scan(dir, c->current, &cur, err, errlen) != 0) {
        uwb_scan_free(&base);
        return -1;
    }
    struct uwb_evaluate_options opt;
    uwb_evaluate_defaults(&opt);
    if (with_span) {
        opt.analysis.has_winding_span = 1;
        opt.analysis.winding_span_m[0] = c->span_m[0];
        opt.analysis.winding_span_m[1] = c->span_m[1];
    }
    struct uwb_verdict v;
    int rc = accuracy_evaluate_pair(&cur, &base, &opt, &v, err, errlen);
    uwb_scan_free(&cur);
    uwb_scan_free(&base);
    if (rc != 0)
        return -1;
    /* What the outputs publish: the verdict record's figure, not the
     * evaluation's working value. */
    struct uwb_verdict_record r;
    uwb_record_from_verdict(&r, &v);
    row->status = uwb_status_name(v.status);
    row->has_figure = r.has_displacement;
    row->figure_m = r.axial_displacement_mm * 1e-3;
    row->sigma_m = r.uncertainty_mm * 1e-3;
    row->within_2sigma = row->has_figure && fabs(row->figure_m - c->centre_move_m) <= 2.0 * row->sigma_m;
    row->has_radial = v.radial.measured;
    row->radial_m = v.radial.max_change_m;
    row->radial_at_m = v.radial.at_m;
    snprintf(row->why, sizeof row->why, "%s", v.reason);
    return 0;
}

void tank3d_print_header(FILE *out)
{
    fprintf(out, "| pair | drawings' span | true move | status | read ± σ | within 2σ | radial change (at) | "
                 "why withheld |\n");
    fprintf(out, "|---|---|---|---|---|---|---|---|\n");
}

/* A reason in a table cell: no '|' to split it. */
static void cell_text(char *out, size_t outlen, const char *text)
{
    size_t j = 0;
    for (size_t i = 0; text[i] && j + 1 < outlen; i++)
        out[j++] = text[i] == '|' ? '/' : text[i];
    out[j] = '\0';
}

void tank3d_print_row(FILE *out, const struct tank3d_case *c, const struct tank3d_row *r)
{
    char span[48], figure[48], within[8], radial[48], why[256];
    if (r->with_span)
        snprintf(span, sizeof span, "%.0f..%.0f mm", c->span_m[0] * 1e3, c->span_m[1] * 1e3);
    else
        snprintf(span, sizeof span, "not given");
    if (r->has_figure)
        snprintf(figure, sizeof figure, "%+.2f ± %.2f", r->figure_m * 1e3, r->sigma_m * 1e3);
    else
        snprintf(figure, sizeof figure, "—");
    snprintf(within, sizeof within, "%s", r->has_figure ? (r->within_2sigma ? "yes" : "**no**") : "—");
    if (r->has_radial)
        snprintf(radial, sizeof radial, "%+.2f mm (%.0f mm)", r->radial_m * 1e3, r->radial_at_m * 1e3);
    else
        snprintf(radial, sizeof radial, "—");
    cell_text(why, sizeof why, r->has_figure ? "" : r->why);
    fprintf(out, "| %s | %s | %+.2f | %s | %s | %s | %s | %s |\n", c->name, span, c->centre_move_m * 1e3,
            r->status, figure, within, radial, why);
}

void tank3d_print_count(FILE *out, int fresh, int within_without, int within_with, int cases)
{
    fprintf(out,
            "%s moved scans with a figure within 2σ of the truth: %d of %d without the drawings' span, "
            "%d of %d with it.\n",
            fresh ? "Tanks drawn here:" : "\nShared tanks:", within_without, cases, within_with, cases);
}
