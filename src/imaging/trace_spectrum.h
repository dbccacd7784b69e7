/* Filtering every trace of a scan in the frequency domain (private to
 * src/imaging): one place owns the FFTW buffers, plans and round trip. */
#ifndef UWB_TRACE_SPECTRUM_H
#define UWB_TRACE_SPECTRUM_H

#include <fftw3.h>
#include <stddef.h>

#include "uwb/scan.h"

/* Called with trace k's spectrum (bins 0..n/2, spacing df_hz: FFTW's
 * unnormalised r2c output of n samples, the trace and zeros after it to
 * uwb_fft_padded_length); it changes spec in place, including the 1/n the
 * inverse transform needs. */
typedef void (*trace_spectrum_fn)(void *ctx, int k, fftwf_complex *spec, int n, double df_hz);

/* Transform every trace, let `filter` change its spectrum, transform back.
 * Traces for which skip (may be NULL) returns non-zero are left as they
 * are, untransformed. `what` names the step in an out-of-memory message.
 * Returns 0, or -1 with err filled. */
int uwb_filter_traces_in_spectrum(struct uwb_scan *scan, int (*skip)(void *ctx, int k),
                                  trace_spectrum_fn filter, void *ctx, const char *what, char *err,
                                  size_t errlen);

#endif
