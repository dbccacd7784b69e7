/* What a scan says about the winding: its edges, and against a baseline,
 * how far it moved and whether that matters. */
#ifndef UWB_VERDICT_H
#define UWB_VERDICT_H

#include <stddef.h>

enum uwb_status {
    UWB_STATUS_EDGES, /* no baseline given: edges only */
    UWB_STATUS_OK,
    UWB_STATUS_WATCH,
    UWB_STATUS_ALARM,
    UWB_STATUS_INCONCLUSIVE, /* the data cannot support a figure; see reason */
    UWB_STATUS_ERROR         /* the appliance lost the scan (hardware, archive); see reason */
};

const char *uwb_status_name(enum uwb_status status);
/* The status name back to its enum: 0, or -1 if it is none of them. */
int uwb_status_from_name(const char *name, enum uwb_status *out);

struct uwb_edges {
    int found;                 /* 0: winding or an edge not established, see reason */
    double lower_m, upper_m;   /* Y1, Y2 in the scan's own y */
    double center_m, height_m; /* (Y1+Y2)/2, Y2-Y1 */
    double face_z_m;           /* range of the winding's face */
    double sigma_lower_m;      /* 1-sigma uncertainties */
    double sigma_upper_m;
    double sigma_center_m;
    double sigma_center_noise_m; /* the part of sigma_center from noise alone: what a comparison of two scans
                                    inherits */
    double snr_db;               /* face peak over image noise floor */
    int side_reflector;          /* a compact reflector beside the winding (clamping plate) was taken out */
    double side_reflector_y_m;   /* ...where it imaged */
    char reason[256];
};

struct uwb_thresholds {
    double watch_m; /* |displacement| from which status is watch (default 2 mm) */
    double alarm_m; /* from which it is alarm (default 5 mm) */
};

/* Sigmas either side of a figure for its 95 % interval: the images, `ctl
 * --text` and the trend say "1 sigma" and "95 %" with these figures. */
#define UWB_SIGMAS_95 2.0

#define UWB_MAX_IMAGES 4

/* The line the face's unchanged rows lie on (uwb/radial.h): the
 * baseline's face range less this scan's (+ nearer now) at the baseline's
 * height y is level_m + slope (y - y_mid_m), plus frame_share of the
 * baseline's own ripple over the shift (uwb_radial_frame_ripple). The
 * whole face's move (the oil's temperature) and a lean are no buckle: the
 * change is what stands off this line, the tilt its rise over the face.
 * frame_share (0..1, fitted on the pair's unchanged rows) is how much of
 * the face range's ripple stays in place as the winding moves (what the
 * tank and the aperture put there) rather than moving with it.
 * lean_slope is the unchanged rows' own rise, the share's ripple in it:
 * the tilt (uwb/radial.h says why). */
struct uwb_radial_line {
    double level_m;
    double slope;   /* m of range per m of height */
    double y_mid_m; /* in the baseline's y */
    double frame_share;
    double lean_slope; /* m of range per m of height */
};

static inline double uwb_radial_line_at(const struct uwb_radial_line *line, double y_m)
{
    return line->level_m + line->slope * (y_m - line->y_mid_m);
}

/* The face's radial change against the baseline (uwb/radial.h), as the
 * verdict gives it: + toward the antenna (a bulge), - away (a dent). */
struct uwb_radial_verdict {
    int measured;           /* 0: see withheld */
    enum uwb_status status; /* ok, watch, alarm or inconclusive */
    double max_change_m;    /* the largest change, signed */
    double at_m;            /* its height, in this scan's y */
    int has_span;           /* where |change| exceeds the watch limit */
    double from_m, to_m;
    double uncertainty_m;       /* 1-sigma of max_change */
    double uncertainty_noise_m; /* its part from the scans' noise alone */
    double tilt_m;              /* the face's top minus its bottom, + top nearer; 0 when withheld */
    double tilt_uncertainty_m;  /* 1-sigma of tilt_m; 0 when withheld */
    char tilt_withheld[128];    /* why the tilt is not given (measured, yet no lean can be read), or empty */
    double tilt_least_m; /* withheld across a status limit: the least lean its 95 % interval allows, signed */
    struct uwb_radial_line line; /* what the change is measured from (the images draw it so) */
    double shift_m; /* the axial shift the faces were compared at: baseline y + shift_m = this scan's y */
    /* A change past the watch limit whose line was fitted within its blur
     * (less than a quarter wavelength of the face's rows clear of it): the
     * flank lifts the line toward the change, which then reads short, so
     * its size is withheld (measured 0) and this, the reading, is the
     * least it can be, signed (its place in at_m); 0 otherwise. */
    double change_least_m;
    char withheld[160]; /* why not measured, or empty */
};

struct uwb_verdict {
    enum uwb_status status;
    char reason[256]; /* why inconclusive, or empty */
    char fault[16];   /* with status error: what failed ("baseline", "rig"), or empty */
    char scan_id[128];
    char created[64];
    struct uwb_edges current;
    int has_baseline;
    struct uwb_edges baseline;
    char baseline_scan_id[128];
    double axial_displacement_m; /* Yc - Yc(baseline), positive = up */
    double uncertainty_m;        /* 1-sigma of the displacement */
    double uncertainty_noise_m;  /* its part from the scans' noise alone (averages down with more pulses;
                                    not in the JSON: the accuracy report checks it against noisy spreads) */
    int axial_withheld;          /* the displacement is no figure (its sigma too large); the status may
                                    still be the radial one's */
    /* (the 95 % interval is UWB_SIGMAS_95 of these either side) */
    double height_change_m;
    double height_change_uncertainty_m; /* its 1-sigma: the edges' noise and the model term */
    char height_change_withheld[192];   /* why the height change is not given, or empty */
    /* Compared with a baseline, yet no displacement read on the faces (not
     * the same reflector, a deformed face, the baseline's winding not
     * found): this scan's edges describe no face a figure was read on and
     * are not published (the images still draw them); why, or empty. */
    char edges_withheld[160];
    struct uwb_radial_verdict radial; /* with a baseline, both faces found */
    /* Time zero: the direct coupling's arrival in this scan and, against a
     * baseline, how far it moved since the baseline's. */
    int has_direct_coupling;
    double direct_coupling_s;
    char direct_coupling_why[200]; /* why it was not found (not in the JSON: `reason` says it when it matters)
                                    */
    int has_direct_coupling_shift;
    double direct_coupling_shift_s;
    int n_images;
    char images[UWB_MAX_IMAGES][4096];
};

#endif
