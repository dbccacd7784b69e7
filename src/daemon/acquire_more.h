/* Acquiring again within one scan cycle: a baseline commissioned from N
 * scans (`baseline set N`), and a scan whose uncertainty is over the limit
 * only because of its noise, which more pulses average down. Scans are
 * averaged trace by trace, weighted by their pulses per position. */
#ifndef UWB_DAEMON_ACQUIRE_MORE_H
#define UWB_DAEMON_ACQUIRE_MORE_H

#include <signal.h>
#include <stddef.h>

#include "uwb/scan.h"
#include "uwb/verdict.h"

/* How an acquisition ends: the contract of the function the scan cycle
 * acquires through (here, below the cycle, which calls this file). */
enum uwbd_acquire_result {
    UWBD_ACQUIRE_OK = 0,
    UWBD_ACQUIRE_STOPPED = 1, /* *stop was raised: nothing to record */
    UWBD_ACQUIRE_FAILED = -1, /* err says why; the hardware has been made safe */
};

/* Fill *out with a new scan; returns an enum uwbd_acquire_result. */
typedef int (*uwbd_acquire_fn)(void *ctx, const volatile sig_atomic_t *stop, struct uwb_scan *out, char *err,
                               size_t errlen);

/* Acquire one more scan into *added and average it into *scan (same
 * geometry required); scan->stack becomes the pulses per position of the
 * average. The caller frees *added after OK. Returns an enum
 * uwbd_acquire_result. */
int uwbd_acquire_and_average(uwbd_acquire_fn acquire, void *ctx, const volatile sig_atomic_t *stop,
                             struct uwb_scan *scan, struct uwb_scan *added, char *err, size_t errlen);

/* Average `add` into `acc`, weighted by pulses (a stack of 0 counts as 1). */
int uwbd_scan_accumulate(struct uwb_scan *acc, const struct uwb_scan *add, char *err, size_t errlen);

/* The sample standard deviation of the finite values (0 with fewer than 2). */
double uwbd_spread(const double *values, int n, int *used);

/* How many more acquisitions of `pulses_each` pulses per position bring the
 * verdict's uncertainty under max_m, when only its current-scan noise part
 * (v->current.sigma_center_noise_m) falls, as the evaluation's pulse model
 * says (uwb_pulse_sigma_from_verdict); -1 when no number of pulses can
 * (the rest alone is over the limit). */
int uwbd_acquisitions_needed(const struct uwb_verdict *v, double max_m, int pulses_now, int pulses_each);

/* The same from two measurements of the uncertainty, sigma1 at pulses1 and
 * sigma2 at pulses2 (more): the model fitted through both
 * (uwb_pulse_sigma_fit), whatever the verdict's terms are. -1 when the fit
 * says no number of pulses can (or the two do not show sigma falling). */
int uwbd_acquisitions_needed_fit(double sigma1, int pulses1, double sigma2, int pulses2, double max_m,
                                 int pulses_each);

#endif
