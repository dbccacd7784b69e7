/* Averaging acquisitions within a cycle (see the header). */
#include "daemon/acquire_more.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

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
    if (rc != UWBD_ACQUIRE_OK) {
        uwb_scan_free(added);
        return rc;
    }
    if (uwbd_scan_accumulate(scan, added, err, errlen) != 0) {
        uwb_scan_free(added);
        return UWBD_ACQUIRE_FAILED;
    }
    return UWBD_ACQUIRE_OK;
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

int uwbd_acquisitions_needed(const struct uwb_verdict *v, double max_m, int pulses_now, int pulses_each)
{
    double total2 = v->uncertainty_m * v->uncertainty_m;
    double noise2 = v->current.sigma_center_noise_m * v->current.sigma_center_noise_m;
    if (!(noise2 > 0)) /* no noise term given: take it all as noise; the fit corrects it */
        noise2 = total2;
    double rest2 = total2 - noise2;
    if (rest2 < 0)
        rest2 = 0;
    double room2 = max_m * max_m - rest2;
    if (!(room2 > 0) || !(noise2 > 0) || pulses_each < 1)
        return -1;
    double pulses_needed = noise2 * pulses_now / room2;
    if (pulses_needed <= pulses_now)
        return 0;
    double more = ceil((pulses_needed - pulses_now) / pulses_each);
    return more > 1e6 ? -1 : (int)more;
}

int uwbd_acquisitions_needed_fit(double sigma1, int pulses1, double sigma2, int pulses2, double max_m,
                                 int pulses_each)
{
    if (pulses2 <= pulses1 || pulses_each < 1)
        return -1;
    double scaling = (sigma1 * sigma1 - sigma2 * sigma2) / (1.0 / pulses1 - 1.0 / pulses2);
    if (!(scaling > 0))
        return -1; /* sigma did not fall with more pulses: more will not help */
    double fixed = sigma2 * sigma2 - scaling / pulses2;
    if (fixed < 0)
        fixed = 0;
    double room = max_m * max_m - fixed;
    if (!(room > 0))
        return -1;
    double pulses_needed = scaling / room;
    if (pulses_needed <= pulses2)
        return 0;
    double more = ceil((pulses_needed - pulses2) / pulses_each);
    return more > 1e6 ? -1 : (int)more;
}
