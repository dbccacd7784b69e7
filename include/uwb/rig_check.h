/* The rig checks itself against the baseline: the static scene (echoes in
 * front of the winding that do not move when it moves: a window frame, a
 * clamp plate, a reference target on the rig's frame) must image at the
 * same heights as in the baseline. A home switch that slipped shifts the
 * whole image, the winding with it; a steps-per-mm mismatch stretches it;
 * either would otherwise read as a displacement of the winding. The
 * appliance carries a fixed reference target for this (a small metal strip
 * on the window frame, clear of the winding's edges; uwbsim's `reference`,
 * on in scenes/tank-3d.json): without a static echo that varies with height
 * the check stands aside and a slipped home reads as a displacement. */
#ifndef UWB_RIG_CHECK_H
#define UWB_RIG_CHECK_H

#include <stddef.h>

#include "uwb/analysis.h"

struct uwb_rig_check {
    int checked;       /* 0: no static echo to check against (why says so) */
    int moved;         /* 1: the rig's geometry changed (why says how) */
    double shift_m;    /* how far the static scene moved (current against baseline), + = up */
    double sigma_m;    /* 1-sigma of shift_m from the residual */
    double similarity; /* normalised correlation of the static scenes at shift_m (1 = alike) */
    double structure_current, structure_baseline; /* the static scene's height-varying power / the noise's */
    double below_winding_db;                      /* the baseline's, against the winding's peak power (dB) */
    char why[256];
};

/* Compare the static scene of two analysed scans of one rig (their
 * conditioned traces, same positions and samples) before the baseline's
 * winding, moved by up to 60 mm, can reply; the baseline must have found
 * the winding. displacement_m (NULL: not measured) is the winding's, named
 * in the reason: any significant shift of the static scene is a rig fault,
 * whatever the winding read. checked = 0 when that part holds no echo
 * that varies with height (under 4 x the noise power, or under -45 dB
 * of the winding's peak). Returns 0, or -1 with err (memory). */
int uwb_rig_check(const struct uwb_analysis *current, const struct uwb_analysis *baseline,
                  const double *displacement_m, struct uwb_rig_check *out, char *err, size_t errlen);

#endif
