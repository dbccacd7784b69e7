/* Measurements on traces, used to check the simulator against full-wave
 * data and against geometry: envelope, its peak, cross-correlation lag. */
#ifndef UWBSIM_MEASURE_H
#define UWBSIM_MEASURE_H

/* |analytic signal| of x[0..n) into env[0..n). Returns 0, -1 on allocation failure. */
int sim_envelope(const float *x, int n, double *env);
/* Fractional sample index of the envelope's maximum within [i0, i1)
 * (parabolic refinement); -1 on failure. */
double sim_envelope_peak(const float *x, int n, int i0, int i1);
/* Lag L (fractional samples, |L| <= max_lag) maximising sum a[i] b[i+L] over
 * i in [i0, i1): b is a delayed by L. */
double sim_xcorr_lag(const float *a, const float *b, int n, int i0, int i1, int max_lag);
/* Pearson correlation of a and b over [i0, i1). */
double sim_correlation(const float *a, const float *b, int i0, int i1);

#endif
