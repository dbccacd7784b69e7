/* FFTW plans kept for the process's life (private to src/imaging).
 *
 * Planning costs more than transforming: 0.4-1 ms for a plan of a few
 * thousand samples against a few microseconds to run it, and the replay of
 * one pair asks for the same few lengths thousands of times. So each
 * (kind, length) is planned once and reused through FFTW's new-array
 * execute functions, whose arrays must come from fftwf_alloc_* (the
 * alignment the plan was made for) and be out of place.
 *
 * Like FFTW's planner itself, this is for one thread at a time: the daemon
 * analyses in one worker thread at a time (src/daemon/worker.c). */
#ifndef UWB_FFT_PLANS_H
#define UWB_FFT_PLANS_H

#include <fftw3.h>

enum fft_kind {
    FFT_R2C, /* n reals -> n/2+1 complex, out of place */
    FFT_C2R, /* n/2+1 complex -> n reals, out of place (destroys its input) */
};

/* A plan for this kind and length: a cached one, or (when the cache is
 * full) a new one that uwb_fft_plan_release destroys. NULL if FFTW has no
 * memory for it. */
fftwf_plan uwb_fft_plan_acquire(enum fft_kind kind, int n);
void uwb_fft_plan_release(fftwf_plan plan);

/* The length a record of n samples is transformed at, zeros after it: the
 * next power of two. FFTW takes some ten times as long on a prime length
 * (the full-wave scans' 1697 and 2333 samples: 39 us a trace against
 * 2.2 us at 2048). A filter applied in the spectrum needs more zeros than
 * that: uwb_trace_spectrum_length. */
int uwb_fft_padded_length(int n);

#endif
