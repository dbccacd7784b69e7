/* Envelope (magnitude of the analytic signal, via FFTW) along range. */
#ifndef UWB_ENVELOPE_H
#define UWB_ENVELOPE_H

#include <stddef.h>

#include "uwb/image.h"
#include "uwb/scan.h"

/* Replace every row of img (a signal along z) by its envelope. */
int uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen);

/* Each trace's envelope along time into env (positions x samples), from
 * its quadrature as the traces' own filters take it (one transform length
 * for every per-trace job of a replay, where a row's envelope pads to
 * twice the row: 4096 for a 1697-sample trace). */
int uwb_envelope_of_traces(const struct uwb_scan *scan, float *env, char *err, size_t errlen);

#endif
