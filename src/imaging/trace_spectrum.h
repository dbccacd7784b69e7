/* Filtering every trace of a scan in the frequency domain (private to
 * src/imaging): one place owns the FFTW buffers, plans and round trip. */
#ifndef UWB_TRACE_SPECTRUM_H
#define UWB_TRACE_SPECTRUM_H

#include <fftw3.h>
#include <stddef.h>

#include "uwb/scan.h"

/* Called with trace k's spectrum (bins 0..n/2, spacing df_hz: FFTW's
 * unnormalised r2c output of n samples, the trace and zeros after it to
 * uwb_trace_spectrum_length); it changes spec in place, including the 1/n
 * the inverse transform needs. */
typedef void (*trace_spectrum_fn)(void *ctx, int k, fftwf_complex *spec, int n, double df_hz);

/* The length a trace of `samples` is filtered at: zeros after it to the
 * next power of two of at least twice its length. A filter here is
 * circular; its response (the band's high-pass rings for some 1/low_hz,
 * the quadrature's falls off as 1/t) must not wrap round onto the record.
 * The next power of two alone left 88 zeros after the 3-D scans' 936
 * samples: the coupling's ringing landed on the winding's echo, and its
 * edges moved by up to 0.8 mm with the transform's length. */
int uwb_trace_spectrum_length(int samples);

/* For tests only, never a setting: filter at `factor` (1..16; anything else
 * is 1) times that length, to show that no figure hangs on it
 * (test_fft_length). */
void uwb_trace_spectrum_set_padding_factor(int factor);

/* Transform every trace, let `filter` change its spectrum, transform back.
 * Traces for which skip (may be NULL) returns non-zero are left as they
 * are, untransformed. `what` names the step in an out-of-memory message.
 * Returns 0, or -1 with err filled. */
int uwb_filter_traces_in_spectrum(struct uwb_scan *scan, int (*skip)(void *ctx, int k),
                                  trace_spectrum_fn filter, void *ctx, const char *what, char *err,
                                  size_t errlen);

#endif
