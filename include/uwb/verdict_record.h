/* The published verdict: what every output says about a scan, filled once
 * where the verdict is made and read by all of them (the archive, MQTT,
 * Modbus, the contacts, the textfile, the control replies). Its figures are
 * held as published, in millimetres to 0.01 mm (snr to 0.1 dB, time zero
 * to 0.1 ps), so no output can say more, or other, than the JSON does.
 * JSON is written from it and read into it in one place: verdict_json.h. */
#ifndef UWB_VERDICT_RECORD_H
#define UWB_VERDICT_RECORD_H

#include "uwb/verdict.h"

/* What the daemon adds about the cycle that made the verdict; empty
 * strings and zero flags are left out of the JSON. */
struct uwb_verdict_cycle {
    int has_scan_file;
    char scan_file[4608]; /* where the scan is archived */
    int has_baseline_set; /* a `baseline set` was pending for this scan */
    int baseline_set;     /* ...and this scan became the baseline */
    char baseline_note[256];
    int pulses_per_position; /* 0: not said */
    int acquisitions;
    char reacquire_note[256];
    int baseline_scans; /* 0: not said */
    int has_baseline_repeatability;
    double baseline_repeatability_mm; /* to 0.001 mm */
    char asset_id[64];
    char trigger[16]; /* "schedule", "command", "event" */
    char archive_error[512];
    char clock_warning[200];
    int archive_error_late; /* archive_error was learnt after the rest was printed: it comes last */
    char record_error[512];
};

/* The record's figures, their flags and why they were withheld: what the
 * summaries, a TREND entry and the textfile carry. Listed once, so that
 * struct uwb_verdict_summary and the start of every record are one
 * layout: the field table's offsets (uwb/verdict_fields.h) hold in both,
 * and a trend of 200 verdicts keeps 200 summaries (~1.4 kB each), not
 * 200 records with their image paths and cycle notes (~24 kB). */
#define UWB_VERDICT_SUMMARY_MEMBERS \
    enum uwb_status status; \
    char reason[256]; \
    char fault[16]; \
    char scan_id[128]; \
    char created[64]; \
    int has_displacement; /* compared with a baseline: the displacement and its 1-sigma */ \
    double axial_displacement_mm, uncertainty_mm; \
    int has_edges; /* the winding's edges in this scan */ \
    double lower_edge_mm, upper_edge_mm, center_mm, height_mm; \
    int has_height_change; \
    double height_change_mm, height_change_uncertainty_mm; \
    char height_change_withheld[192]; /* compared, but the height change not given: why */ \
    /* Compared: the face's radial change (measured), or why not (withheld). */ \
    int has_radial; \
    enum uwb_status radial_status; \
    int radial_measured; \
    double radial_max_change_mm, radial_at_mm, radial_uncertainty_mm; \
    /* Measured, and the face's lean given (tilt_mm); else radial_tilt_withheld says why. */ \
    int radial_has_tilt; \
    double radial_tilt_mm; \
    int radial_has_tilt_uncertainty; /* with the tilt, its 1-sigma (absent from records before it) */ \
    double radial_tilt_uncertainty_mm; \
    char radial_tilt_withheld[128]; \
    int radial_has_span; \
    double radial_from_mm, radial_to_mm; \
    char radial_withheld[160]; \
    /* with has_edges; edge_uncertainty_mm covers the baseline's edges too when given */ \
    double face_range_mm, snr_db, edge_uncertainty_mm; \
    char edges_withheld[160]; /* the face found, its edges not published: why */ \
    int has_side_reflector; \
    double side_reflector_mm; \
    int has_baseline; /* the baseline's edges */ \
    double baseline_lower_edge_mm, baseline_upper_edge_mm, baseline_center_mm; \
    char baseline_scan_id[128]; \
    int has_direct_coupling; \
    double direct_coupling_ps; \
    int has_direct_coupling_shift; \
    double direct_coupling_shift_ps;

struct uwb_verdict_summary {
    UWB_VERDICT_SUMMARY_MEMBERS
};

struct uwb_verdict_record {
    union {
        struct uwb_verdict_summary summary; /* the figures as one value */
        struct {
            UWB_VERDICT_SUMMARY_MEMBERS
        };
    };
    int n_images;
    char images[UWB_MAX_IMAGES][4096];
    struct uwb_verdict_cycle cycle;
};

/* The record of the evaluation's verdict, its figures rounded as published;
 * cycle left empty. */
void uwb_record_from_verdict(struct uwb_verdict_record *r, const struct uwb_verdict *v);

#endif
