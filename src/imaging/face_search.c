/* Which reflector is the winding: the strongest one whose two ends are both
 * seen and that stands taller than a point. Core legs, barriers and the far
 * wall run past the aperture; the winding's face starts and stops inside
 * it; a plate's edge is a point. */
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
/* A clamp plate shows the antennas its edge, or its corner with the
 * winding's end, which image as the blur of a point, as bright as the face
 * and often nearer. The winding is a stack of disks: at half its peak it
 * stands at least this many times as tall as that blur (see
 * uwb_point_blur_m). Full-wave scenes: windings 2.4-6.6 times, plate edges
 * and corners 0.7-1.35; the family's shortest build, 5 disks of 14 mm,
 * simulated at 1.6-2.0 GHz: 1.77 and more (test_imaging_sim). */
#define FACE_OVER_POINT_BLUR 1.7
/* Reflectors looked at in one range column after its peak is passed over:
 * the face between a plate above and a plate below is the third. */
#define MAX_IN_COLUMN 3

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

/* Where range column iz falls below END_FRACTION of its peak on either side
 * of peak_row: the rows, and whether it does inside the image at all. */
struct column_ends {
    int lower_row, upper_row;
    int lower_drops, upper_drops;
};

static struct column_ends column_ends(const struct uwb_image *img, int iz, int peak_row, double peak)
{
    struct column_ends e;
    int iy = peak_row;
    while (iy > 0 && img->pix[(size_t)iy * img->nz + iz] >= END_FRACTION * peak)
        iy--;
    e.lower_row = iy;
    e.lower_drops = img->pix[(size_t)iy * img->nz + iz] < END_FRACTION * peak;
    iy = peak_row;
    while (iy < img->ny - 1 && img->pix[(size_t)iy * img->nz + iz] >= END_FRACTION * peak)
        iy++;
    e.upper_row = iy;
    e.upper_drops = img->pix[(size_t)iy * img->nz + iz] < END_FRACTION * peak;
    return e;
}

/* The rows of range column iz that belong to the reflector peaking at
 * peak_row: down both of its skirts while the column keeps falling, to the
 * valley that parts it from whatever else the column holds. */
static void column_skirts(const struct uwb_image *img, int iz, int peak_row, int *lo, int *hi)
{
    int iy = peak_row;
    while (iy > 0 && img->pix[(size_t)(iy - 1) * img->nz + iz] <= img->pix[(size_t)iy * img->nz + iz])
        iy--;
    *lo = iy;
    iy = peak_row;
    while (iy < img->ny - 1 &&
           img->pix[(size_t)(iy + 1) * img->nz + iz] <= img->pix[(size_t)iy * img->nz + iz])
        iy++;
    *hi = iy;
}

static double row_y(const struct uwb_image *img, int iy)
{
    return img->y0_m + iy * img->dy_m;
}

static int ends_seen(const struct uwb_image *img, const struct column_ends *e, double lo_m, double hi_m)
{
    return e->lower_drops && row_y(img, e->lower_row) >= lo_m && e->upper_drops &&
           row_y(img, e->upper_row) <= hi_m;
}

/* How tall delay-and-sum draws a point at (y, z) at half its peak: the
 * aperture lo..hi sees it over angles whose sines reach s1 below and s2
 * above, so the two-way image resolves lambda / (2 (s1 + s2)) along y. */
double uwb_point_blur_m(double wavelength_m, double y_m, double z_m, double lo_m, double hi_m)
{
    double below = fmax(y_m - lo_m, 0.0), above = fmax(hi_m - y_m, 0.0);
    double s1 = below / hypot(below, z_m), s2 = above / hypot(above, z_m);
    return s1 + s2 > 0.0 ? wavelength_m / (2.0 * (s1 + s2)) : INFINITY;
}

/* The brightest row of column iz not yet taken; -1 when none. */
static int column_peak_untaken(const struct uwb_image *img, int iz, const char *taken)
{
    int best = -1;
    for (int iy = 0; iy < img->ny; iy++)
        if (!taken[iy] &&
            (best < 0 || img->pix[(size_t)iy * img->nz + iz] > img->pix[(size_t)best * img->nz + iz]))
            best = iy;
    return best;
}

static void take_rows(char *taken, int lo, int hi)
{
    for (int iy = lo; iy <= hi; iy++)
        taken[iy] = 1;
}

/* A plate's front edge level with the face shares its range column and may
 * outshine the face there (the 3-D tanks' lower plate, 5 mm in front of
 * the face, twice as bright; the other plate's edge may come next): when
 * the column's peak is no winding (a point, or outside the drawings'
 * span), its next reflectors, each beyond the valleys that part it from
 * those passed over and held to the same tests, may be. Returns 1 with *e
 * and *value the face's ends and peak. */
static int next_face_in_column(const struct uwb_image *img, int iz, int peak_row, double z_m,
                               double wavelength_m, double aperture_lo_m, double aperture_hi_m,
                               double inner_lo, double inner_hi, const double *span_m, struct column_ends *e,
                               double *value)
{
    char *taken = calloc((size_t)img->ny, 1);
    if (!taken)
        return 0;
    int found = 0;
    int at = peak_row;
    for (int k = 0; k < MAX_IN_COLUMN && !found; k++) {
        int skirt_lo, skirt_hi;
        column_skirts(img, iz, at, &skirt_lo, &skirt_hi);
        take_rows(taken, skirt_lo, skirt_hi);
        at = column_peak_untaken(img, iz, taken);
        if (at < 0)
            break;
        double v = img->pix[(size_t)at * img->nz + iz];
        if (v <= 0.0)
            break;
        struct column_ends n = column_ends(img, iz, at, v);
        double y = row_y(img, at);
        int apart = 1;
        for (int iy = n.lower_row; iy <= n.upper_row; iy++)
            if (taken[iy])
                apart = 0;
        int in_span = !span_m || (y >= span_m[0] && y <= span_m[1]);
        double tall = (n.upper_row - n.lower_row) * img->dy_m;
        if (apart && in_span && ends_seen(img, &n, inner_lo, inner_hi) &&
            tall >=
                FACE_OVER_POINT_BLUR * uwb_point_blur_m(wavelength_m, y, z_m, aperture_lo_m, aperture_hi_m)) {
            *e = n;
            *value = v;
            found = 1;
        }
    }
    free(taken);
    return found;
}

/* A face at range z_m between its column's ends e. */
static struct face_candidate candidate_at(const struct uwb_image *img, double z_m,
                                          const struct column_ends *e, double peak, int beside_brighter)
{
    struct face_candidate c = {.z_m = z_m,
                               .peak = peak,
                               .lower_m = row_y(img, e->lower_row),
                               .upper_m = row_y(img, e->upper_row),
                               .beside_brighter = beside_brighter};
    return c;
}

/* The winding shadows what stands behind it (the core leg), and once the
 * static clutter is removed that shadow images as a compact reflector of
 * its own, sometimes brighter than the winding, but always farther. So
 * among the candidates within SHADOW_MARGIN of the strongest of them, the
 * nearest is the winding: 1 and *face, or 0 when there is none. */
static int nearest_of_the_strong(const struct face_candidate *c, int n, struct face_candidate *face)
{
    double strongest = 0.0;
    for (int i = 0; i < n; i++)
        strongest = fmax(strongest, c[i].peak);
    int found = 0;
    for (int i = 0; i < n; i++)
        if (c[i].peak >= SHADOW_MARGIN * strongest && (!found || c[i].z_m < face->z_m)) {
            *face = c[i];
            found = 1;
        }
    return found;
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
                    double wavelength_m, const double *excluded_z_m, int n_excluded, const double *span_m,
                    struct face_candidate *face, char *reason, size_t reasonlen)
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
    double strongest_rejected_z = -1.0;
    int rejected_at_limit = 0;
    double point_z = -1.0, point_tall = 0.0, point_blur = 0.0;
    double outside_z = -1.0, outside_y = 0.0;
    struct face_candidate seen[MAX_CANDIDATES] = {{0}};
    int n_seen = 0;
    /* Faces found behind a brighter reflector whose blur runs past the
     * travel: taken only where no other face is seen. */
    struct face_candidate behind[MAX_CANDIDATES] = {{0}};
    int n_behind = 0;
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
        double z = img->z0_m + best * img->dz_m;
        if (excluded_range(z, excluded_z_m, n_excluded))
            continue;
        /* Brightest at the range searched's own limit: the flank of a
         * reflector beyond it (the winding's, when a target range given at
         * commissioning misses it), whatever its ends do. (Not every
         * flank: a scan stretched by a steps-per-mm error finds its face
         * on one, which the rig check then reads as the fault it is.) */
        int at_limit = best == 0 || best == img->nz - 1;
        struct column_ends e = column_ends(img, best, row[best], peak[best]);
        /* A reflector near the travel's end outshining the face in its own
         * range column (a plate's edge level with the face, 150 mm above
         * the winding's top and 15 mm below the travel's end) blurs past
         * the travel: the face may be the column's next reflector. Only
         * where no column shows a face of its own: a plate's column nearer
         * than the face holds other next reflectors (fresh s102's read +2.24
         * mm for +30 on one). */
        double next_peak = peak[best];
        struct column_ends next;
        if (!at_limit && !ends_seen(img, &e, inner_lo, inner_hi) &&
            next_face_in_column(img, best, row[best], z, wavelength_m, aperture_lo_m, aperture_hi_m, inner_lo,
                                inner_hi, span_m, &next, &next_peak)) {
            behind[n_behind++] = candidate_at(img, z, &next, next_peak, 1);
            continue;
        }
        if (!at_limit && ends_seen(img, &e, inner_lo, inner_hi)) {
            /* The drawings' span, when given, says where the winding is: a
             * reflector brightest outside it is a plate's or the core's
             * (the 3-D family's lower plate, its front edge level with the
             * face, outshines the face in the face's own range column). */
            double y_peak = row_y(img, row[best]);
            double tall = (e.upper_row - e.lower_row) * img->dy_m;
            double blur = uwb_point_blur_m(wavelength_m, y_peak, z, aperture_lo_m, aperture_hi_m);
            int outside = span_m && (y_peak < span_m[0] || y_peak > span_m[1]);
            int point = !outside && tall < FACE_OVER_POINT_BLUR * blur;
            double column_peak = peak[best];
            if ((outside || point) &&
                next_face_in_column(img, best, row[best], z, wavelength_m, aperture_lo_m, aperture_hi_m,
                                    inner_lo, inner_hi, span_m, &e, &column_peak))
                outside = point = 0;
            if (outside) {
                if (outside_z < 0.0) {
                    outside_z = z;
                    outside_y = y_peak;
                }
                continue;
            }
            if (point) {
                if (point_z < 0.0) {
                    point_z = z;
                    point_tall = tall;
                    point_blur = blur;
                }
                continue;
            }
            seen[n_seen++] = candidate_at(img, z, &e, column_peak, column_peak < peak[best]);
        } else if (strongest_rejected_z < 0.0) {
            strongest_rejected_z = z;
            rejected_at_limit = at_limit;
        }
    }
    int found = n_seen > 0 ? nearest_of_the_strong(seen, n_seen, face)
                           : nearest_of_the_strong(behind, n_behind, face);
    if (!found) {
        if (outside_z >= 0.0)
            snprintf(
                reason, reasonlen,
                "winding not found at %.0f..%.0f mm, the drawings' span and its tolerance: the strongest "
                "reflector with both ends seen, at %.3f m range, is brightest at %.0f mm, outside it",
                span_m[0] * 1e3, span_m[1] * 1e3, outside_z, outside_y * 1e3);
        else if (n_excluded > 0)
            snprintf(reason, reasonlen,
                     "winding not found: no reflector between %.3f and %.3f m range besides the %d measured "
                     "and rejected",
                     img->z0_m, img->z0_m + (img->nz - 1) * img->dz_m, n_excluded);
        else if (point_z >= 0.0)
            snprintf(reason, reasonlen,
                     "winding not found: the strongest reflector with both ends seen, at %.3f m range, is a "
                     "point (%.0f mm tall at half its peak, where the imaging draws a point %.0f mm tall): "
                     "a plate's edge or corner, not a winding's face",
                     point_z, point_tall * 1e3, point_blur * 1e3);
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
