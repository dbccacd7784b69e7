/* Envelope (magnitude of the analytic signal, via FFTW) along range. */
#ifndef UWB_ENVELOPE_H
#define UWB_ENVELOPE_H

#include <stddef.h>

#include "uwb/image.h"

/* Replace every row of img (a signal along z) by its envelope. */
int uwb_envelope_along_z(struct uwb_image *img, char *err, size_t errlen);

#endif
