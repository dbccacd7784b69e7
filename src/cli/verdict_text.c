/* A VERDICT reply as a few lines an engineer reads at a glance (uwbd ctl
 * --text): the status and the displacement, or the edges of a scan without
 * a baseline, or why there is no verdict; then the images. */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "uwb/cli.h"
#include "uwb/verdict.h"

static const cJSON *item(const cJSON *o, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(o, key);
}

static int number(const cJSON *o, const char *key, double *out)
{
    const cJSON *v = item(o, key);
    if (!cJSON_IsNumber(v))
        return 0;
    *out = v->valuedouble;
    return 1;
}

static void print_upper(FILE *out, const char *s)
{
    for (; *s; s++)
        fputc(toupper((unsigned char)*s), out);
}

int uwbd_verdict_text(const char *reply, FILE *out)
{
    cJSON *v = cJSON_Parse(reply);
    const cJSON *cls = item(v, "class"), *status = item(v, "status");
    if (!cJSON_IsString(cls) || strcmp(cls->valuestring, "VERDICT") != 0 || !cJSON_IsString(status)) {
        cJSON_Delete(v);
        return -1;
    }
    const cJSON *baseline = item(v, "baseline"), *reason = item(v, "reason");
    double d, u, lo, hi, base_lo, base_hi, face;
    fputs("status ", out);
    print_upper(out, status->valuestring);
    if (number(v, "axial_displacement_mm", &d) && number(v, "uncertainty_mm", &u)) {
        /* uncertainty_mm is one sigma; the 95 % interval is what is acted on. */
        fprintf(out, ": displacement %+.2f \u00b1 %.2f mm 1\u03c3, 95 %%: %+.2f..%+.2f mm", d, u,
                d - UWB_SIGMAS_95 * u, d + UWB_SIGMAS_95 * u);
        if (number(v, "lower_edge_mm", &lo) && number(v, "upper_edge_mm", &hi) &&
            number(baseline, "lower_edge_mm", &base_lo) && number(baseline, "upper_edge_mm", &base_hi))
            fprintf(out, " (edges %.1f..%.1f mm, baseline %.1f..%.1f mm)", lo, hi, base_lo, base_hi);
    } else if (strcmp(status->valuestring, "edges") == 0 && number(v, "lower_edge_mm", &lo) &&
               number(v, "upper_edge_mm", &hi)) {
        fprintf(out, ": winding from %.1f to %.1f mm", lo, hi);
        if (number(v, "face_range_mm", &face))
            fprintf(out, ", face at %.0f mm", face);
        fprintf(out, "; became the baseline: %s", cJSON_IsTrue(item(v, "baseline_set")) ? "yes" : "no");
    } else if (cJSON_IsString(reason)) {
        fprintf(out, ": %s", reason->valuestring);
    }
    fputc('\n', out);
    double h, hs;
    const cJSON *withheld = item(v, "height_change_withheld");
    if (number(v, "height_change_mm", &h) && number(v, "height_change_uncertainty_mm", &hs))
        fprintf(out, "height change %+.2f \u00b1 %.2f mm 1\u03c3\n", h, hs);
    else if (cJSON_IsString(withheld))
        fprintf(out, "height change withheld: %s\n", withheld->valuestring);
    const cJSON *image;
    cJSON_ArrayForEach(image, item(v, "images"))
    {
        if (cJSON_IsString(image))
            fprintf(out, "image: %s\n", image->valuestring);
    }
    cJSON_Delete(v);
    return 0;
}
