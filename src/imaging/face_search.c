/* Which reflector is the winding: the strongest one whose two ends are both
 * seen. Core legs, barriers and the far wall run past the aperture; the
 * winding's face starts and stops inside it. */
#include "imaging_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define MAX_CANDIDATES 8
#define CANDIDATE_SEPARATION_M 0.03
#define WEAKEST_CANDIDATE 0.01 /* -40 dB below the strongest reflector */
#define END_FRACTION 0.5       /* the profile must drop below this inside the travel */
/* ...and that far inside it: residues of clutter the winding shadows (the
 * core leg behind it) end at the travel's ends; a seen edge has positions
 * beyond it. */
#define END_MARGIN_STEPS 2.0
#define SHADOW_MARGIN 0.316 /* -10 dB */

double uwb_image_column_peak(const struct uwb_image *img, int iz, int *row)
{
    double best = -1.0;
    *row = 0; /* an image without rows: -1 at row 0 */
    for (int iy = 0; iy < img->ny; iy++) {
        double v = img->pix[(size_t)iy * img->nz + iz];
        if (v > best) {
            best = v;
            *row = iy;
        }
    }
    return best;
}

static int ends_seen(const struct uwb_image *img, int iz, int peak_row, double peak, double lo_m, double hi_m)
{
    int iy = peak_row;
    while (iy > 0 && img->pix[(size_t)iy * img->nz + iz] >= END_FRACTION * peak)
        iy--;
    int lower_ok =
        img->pix[(size_t)iy * img->nz + iz] < END_FRACTION * peak && img->y0_m + iy * img->dy_m >= lo_m;
    iy = peak_row;
    while (iy < img->ny - 1 && img->pix[(size_t)iy * img->nz + iz] >= END_FRACTION * peak)
        iy++;
    int upper_ok =
        img->pix[(size_t)iy * img->nz + iz] < END_FRACTION * peak && img->y0_m + iy * img->dy_m <= hi_m;
    return lower_ok && upper_ok;
}

/* Whether range z lies within a candidate's separation of one already
 * measured and rejected. */
static int excluded_range(double z_m, const double *excluded_z_m, int n_excluded)
{
    for (int i = 0; i < n_excluded; i++)
        if (fabs(z_m - excluded_z_m[i]) <= CANDIDATE_SEPARATION_M)
            return 1;
    return 0;
}

int uwb_face_search(const struct uwb_image *img, double aperture_lo_m, double aperture_hi_m, double step_m,
                    const double *excluded_z_m, int n_excluded, struct face_candidate *face, char *reason,
                    size_t reasonlen)
{
    double inner_lo = aperture_lo_m + END_MARGIN_STEPS * step_m;
    double inner_hi = aperture_hi_m - END_MARGIN_STEPS * step_m;
    double *peak = malloc((size_t)img->nz * sizeof *peak);
    int *row = malloc((size_t)img->nz * sizeof *row);
    char *used = calloc((size_t)img->nz, 1);
    if (!peak || !row || !used) {
        free(peak);
        free(row);
        free(used);
        snprintf(reason, reasonlen, "out of memory in the face search");
        return 1;
    }
    double strongest = 0.0;
    for (int iz = 0; iz < img->nz; iz++) {
        peak[iz] = uwb_image_column_peak(img, iz, &row[iz]);
        if (peak[iz] > strongest)
            strongest = peak[iz];
    }
    int sep = (int)ceil(CANDIDATE_SEPARATION_M / img->dz_m);
    int found = 0;
    double strongest_rejected_z = -1.0;
    int rejected_at_limit = 0;
    struct face_candidate seen[MAX_CANDIDATES] = {{0}};
    int n_seen = 0;
    double strongest_seen = 0.0;
    for (int c = 0; c < MAX_CANDIDATES; c++) {
        int best = -1;
        for (int iz = 0; iz < img->nz; iz++)
            if (!used[iz] && (best < 0 || peak[iz] > peak[best]))
                best = iz;
        if (best < 0 || peak[best] <= WEAKEST_CANDIDATE * strongest || peak[best] <= 0.0)
            break;
        for (int iz = best - sep; iz <= best + sep; iz++)
            if (iz >= 0 && iz < img->nz)
                used[iz] = 1;
        if (excluded_range(img->z0_m + best * img->dz_m, excluded_z_m, n_excluded))
            continue;
        /* Brightest at the range searched's own limit: the flank of a
         * reflector beyond it (the winding's, when a target range given at
         * commissioning misses it), whatever its ends do. (Not every
         * flank: a scan stretched by a steps-per-mm error finds its face
         * on one, which the rig check then reads as the fault it is.) */
        int at_limit = best == 0 || best == img->nz - 1;
        if (!at_limit && ends_seen(img, best, row[best], peak[best], inner_lo, inner_hi)) {
            seen[n_seen].z_m = img->z0_m + best * img->dz_m;
            seen[n_seen].peak = peak[best];
            if (peak[best] > strongest_seen)
                strongest_seen = peak[best];
            n_seen++;
        } else if (strongest_rejected_z < 0.0) {
            strongest_rejected_z = img->z0_m + best * img->dz_m;
            rejected_at_limit = at_limit;
        }
    }
    /* The winding shadows what stands behind it (the core leg), and once the
     * static clutter is removed that shadow images as a compact reflector of
     * its own, sometimes brighter than the winding, but always farther. So
     * among the reflectors with both ends seen and within SHADOW_MARGIN of
     * the strongest of them, the nearest is the winding. */
    for (int i = 0; i < n_seen; i++)
        if (seen[i].peak >= SHADOW_MARGIN * strongest_seen && (!found || seen[i].z_m < face->z_m)) {
            *face = seen[i];
            found = 1;
        }
    if (!found) {
        if (n_excluded > 0)
            snprintf(reason, reasonlen,
                     "winding not found: no reflector between %.3f and %.3f m range besides the %d measured "
                     "and rejected",
                     img->z0_m, img->z0_m + (img->nz - 1) * img->dz_m, n_excluded);
        else if (strongest_rejected_z >= 0.0)
            snprintf(reason, reasonlen,
                     "winding not found: no reflector between %.3f and %.3f m range has both ends inside "
                     "the antenna travel (strongest, at %.3f m, %s)",
                     img->z0_m, img->z0_m + (img->nz - 1) * img->dz_m, strongest_rejected_z,
                     rejected_at_limit ? "is the range's limit: a reflector beyond it" : "runs past it");
        else
            snprintf(reason, reasonlen, "winding not found: no reflector between %.3f and %.3f m range",
                     img->z0_m, img->z0_m + (img->nz - 1) * img->dz_m);
    }
    free(peak);
    free(row);
    free(used);
    return found ? 0 : 1;
}
