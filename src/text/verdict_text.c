/* A VERDICT reply as a few lines an engineer reads at a glance (uwbd ctl
 * --text): the status and the displacement, or the edges of a scan without
 * a baseline, or why there is no verdict; then the images. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "text/text_layout.h"
#include "uwb/reply_text.h"
#include "uwb/verdict_json.h"
#include "uwb/verdict_record.h"

static void print_upper(FILE *out, const char *s)
{
    for (; *s; s++)
        fputc(toupper((unsigned char)*s), out);
}

/* The face's radial change, + toward the antenna (a bulge). */
static void print_radial(const struct uwb_verdict_record *v, const struct text_marks *m, FILE *out)
{
    if (!v->has_radial)
        return;
    if (!v->radial_measured) {
        fprintf(out, "radial change withheld: %s\n", v->radial_withheld);
        return;
    }
    fprintf(out, "radial change %+.2f %s %.2f mm %s at %.0f mm", v->radial_max_change_mm, m->plus_minus,
            v->radial_uncertainty_mm, m->one_sigma, v->radial_at_mm);
    if (v->radial_has_span)
        fprintf(out, ", past the watch limit from %.0f to %.0f mm", v->radial_from_mm, v->radial_to_mm);
    if (v->radial_has_tilt && v->radial_has_tilt_uncertainty)
        fprintf(out, "; tilt %+.2f %s %.2f mm (+: top nearer): ", v->radial_tilt_mm, m->plus_minus,
                v->radial_tilt_uncertainty_mm);
    else if (v->radial_has_tilt)
        fprintf(out, "; tilt %+.2f mm (+: top nearer): ", v->radial_tilt_mm);
    else
        fprintf(out, "; tilt withheld (%s): ", v->radial_tilt_withheld);
    print_upper(out, uwb_status_name(v->radial_status));
    if (v->radial_withheld[0])
        fprintf(out, " (%s)", v->radial_withheld);
    fputc('\n', out);
}

/* When and which scan: an error verdict is dated and named as any
 * (issue 48). Nothing where the reply carries neither. */
static void print_when(const struct uwb_verdict_record *v, FILE *out)
{
    if (!v->created[0] && !v->scan_id[0])
        return;
    fprintf(out, "verdict of %s", v->created[0] ? v->created : "(no time)");
    if (v->scan_id[0])
        fprintf(out, ", scan %s", v->scan_id);
    fputc('\n', out);
}

static void print_verdict(const struct uwb_verdict_record *v, const struct text_marks *m, FILE *out)
{
    print_when(v, out);
    fputs("status ", out);
    print_upper(out, uwb_status_name(v->status));
    if (v->has_displacement) {
        double d = v->axial_displacement_mm, u = v->uncertainty_mm;
        /* uncertainty_mm is one sigma; the 95 % interval is what is acted on. */
        fprintf(out, ": displacement %+.2f %s %.2f mm %s, 95 %%: %+.2f..%+.2f mm", d, m->plus_minus, u,
                m->one_sigma, d - UWB_SIGMAS_95 * u, d + UWB_SIGMAS_95 * u);
        if (v->has_edges && v->has_baseline)
            fprintf(out, " (edges %.1f..%.1f mm, baseline %.1f..%.1f mm)", v->lower_edge_mm, v->upper_edge_mm,
                    v->baseline_lower_edge_mm, v->baseline_upper_edge_mm);
    } else if (v->status == UWB_STATUS_EDGES && v->has_edges) {
        fprintf(out, ": winding from %.1f to %.1f mm", v->lower_edge_mm, v->upper_edge_mm);
        fprintf(out, ", face at %.0f mm", v->face_range_mm);
        fprintf(out, "; became the baseline: %s", v->cycle.baseline_set ? "yes" : "no");
    } else if (v->reason[0]) {
        fprintf(out, ": %s", v->reason);
    }
    fputc('\n', out);
    if (v->has_height_change)
        fprintf(out, "height change %+.2f %s %.2f mm %s\n", v->height_change_mm, m->plus_minus,
                v->height_change_uncertainty_mm, m->one_sigma);
    else if (v->height_change_withheld[0])
        fprintf(out, "height change withheld: %s\n", v->height_change_withheld);
    print_radial(v, m, out);
    for (int i = 0; i < v->n_images; i++)
        fprintf(out, "image: %s\n", v->images[i]);
}

int uwbd_verdict_text(const char *reply, FILE *out)
{
    return uwbd_verdict_text_in(reply, out, UWBD_CHARSET_UTF8);
}

int uwbd_verdict_text_in(const char *reply, FILE *out, enum uwbd_charset charset)
{
    struct uwb_verdict_record *v = malloc(sizeof *v);
    char err[256];
    if (!v || uwb_record_from_json(reply, v, err, sizeof err) != 0) {
        free(v);
        return -1;
    }
    print_verdict(v, uwb_text_layout_marks_of(charset), out);
    free(v);
    return 0;
}
