/* A compact static reflector level with the winding's face and just beyond
 * one of its ends (a clamping plate's front edge above it): found on the
 * face row, removed from the traces (private to src/imaging). */
#ifndef UWB_SIDE_REFLECTOR_H
#define UWB_SIDE_REFLECTOR_H

#include <complex.h>
#include <stddef.h>

#include "uwb/geometry.h"
#include "uwb/scan.h"

struct side_reflector {
    int found;
    double y_m, z_m;      /* where it images */
    double complex amp;   /* its echo relative to the echo model */
    double explained;     /* share of the face row's asymmetry it accounts for */
    double relative_peak; /* its image's peak over the face's */
    /* The echo model: the face's own echo at the antenna nearest the
     * winding's centre, and its quadrature (Hilbert) partner. */
    int len;
    double lead_s; /* time of model sample 0 relative to the echo's delay */
    float *echo, *quadrature;
};

/* Look on the face row at range z_face for one reflector beside a winding
 * centred at centre_m with half height half_height_m. `quadrature` is the
 * conditioned scan's Hilbert partner (same layout), weight the per-position
 * aperture taper. near_y_m: NAN to search beyond both ends, or where an
 * earlier pass found the reflector, to look only near there. Fills *r
 * (r->found = 0 when nothing beside the winding explains the row's
 * asymmetry). Returns 0, or -1 with err filled. */
int uwb_side_reflector_find(const struct uwb_scan *conditioned, const struct uwb_scan *quadrature,
                            const double *weight, const struct uwb_geometry *g, double z_face_m,
                            double centre_m, double half_height_m, double dominant_hz, double near_y_m,
                            struct side_reflector *r, char *err, size_t errlen);

/* Subtract the found reflector's echo from every trace of scan. */
void uwb_side_reflector_remove(const struct side_reflector *r, const struct uwb_geometry *g,
                               struct uwb_scan *scan);

void uwb_side_reflector_free(struct side_reflector *r);

/* The Hilbert partner of every trace (for the complex face row). */
int uwb_quadrature_scan(const struct uwb_scan *in, struct uwb_scan *out, char *err, size_t errlen);

#endif
