/* Averaging acquisitions within a cycle (see the header). */
#include "daemon/acquire_more.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "uwb/evaluate.h"

static int pulses_of(const struct uwb_scan *s)
{
    return s->stack > 0 ? s->stack : 1;
}

int uwbd_scan_accumulate(struct uwb_scan *acc, const struct uwb_scan *add, char *err, size_t errlen)
{
    if (acc->positions != add->positions || acc->samples != add->samples ||
        fabs(acc->t0_s - add->t0_s) > 1e-15 ||
        fabs(acc->sample_interval_s - add->sample_interval_s) > 1e-18) {
        snprintf(err, errlen,
                 "the repeated acquisition differs in its record (%d x %d) from the first (%d x %d)",
                 add->positions, add->samples, acc->positions, acc->samples);
        return -1;
    }
    for (int k = 0; k < acc->positions; k++)
        if (fabs(acc->antenna_y_m[k] - add->antenna_y_m[k]) > 1e-4) {
            snprintf(err, errlen,
                     "the repeated acquisition's position %d is at %.4f m, the first's at %.4f m", k,
                     add->antenna_y_m[k], acc->antenna_y_m[k]);
            return -1;
        }
    double wa = pulses_of(acc), wb = pulses_of(add), w = wa + wb;
    size_t n = (size_t)acc->positions * (size_t)acc->samples;
    for (size_t i = 0; i < n; i++)
        acc->data[i] = (float)((wa * acc->data[i] + wb * add->data[i]) / w);
    acc->stack = (int)w;
    return 0;
}

int uwbd_acquire_and_average(uwbd_acquire_fn acquire, void *ctx, const volatile sig_atomic_t *stop,
                             struct uwb_scan *scan, struct uwb_scan *added, char *err, size_t errlen)
{
    memset(added, 0, sizeof *added);
    int rc = acquire(ctx, stop, added, err, errlen);
    if (rc == UWBD_ACQUIRE_OK && uwbd_scan_accumulate(scan, added, err, errlen) != 0)
        rc = UWBD_ACQUIRE_FAILED;
    if (rc != UWBD_ACQUIRE_OK)
        uwb_scan_free(added);
    return rc;
}

double uwbd_spread(const double *values, int n, int *used)
{
    double sum = 0, sum2 = 0;
    int m = 0;
    for (int i = 0; i < n; i++)
        if (isfinite(values[i])) {
            sum += values[i];
            m++;
        }
    if (used)
        *used = m;
    if (m < 2)
        return 0;
    double mean = sum / m;
    for (int i = 0; i < n; i++)
        if (isfinite(values[i]))
            sum2 += (values[i] - mean) * (values[i] - mean);
    return sqrt(sum2 / (m - 1));
}

/* Whole acquisitions of pulses_each that bring the pulses from pulses_now
 * to what the model says sigma needs; -1 for no pulses per acquisition
 * (the one check of pulses_each, for both callers). */
static int acquisitions_for(const struct uwb_pulse_sigma *m, double max_m, int pulses_now, int pulses_each)
{
    double pulses_needed;
    if (pulses_each < 1 || uwb_pulse_sigma_pulses_for(m, max_m, &pulses_needed) != 0)
        return -1;
    if (pulses_needed <= pulses_now)
        return 0;
    double more = ceil((pulses_needed - pulses_now) / pulses_each);
    return more > 1e6 ? -1 : (int)more;
}

int uwbd_acquisitions_needed(const struct uwb_verdict *v, double max_m, int pulses_now, int pulses_each)
{
    struct uwb_pulse_sigma m;
    if (uwb_pulse_sigma_from_verdict(v, pulses_now, &m) != 0)
        return -1;
    return acquisitions_for(&m, max_m, pulses_now, pulses_each);
}

int uwbd_acquisitions_needed_fit(double sigma1, int pulses1, double sigma2, int pulses2, double max_m,
                                 int pulses_each)
{
    struct uwb_pulse_sigma m;
    if (uwb_pulse_sigma_fit(sigma1, pulses1, sigma2, pulses2, &m) != 0)
        return -1; /* sigma did not fall with more pulses: more will not help */
    return acquisitions_for(&m, max_m, pulses2, pulses_each);
}
