/* sigma against the pulses per position (see uwb/evaluate.h): the one
 * place that says how averaging more pulses shrinks the uncertainty. */
#include <math.h>

#include "uwb/evaluate.h"

int uwb_pulse_sigma_from_verdict(const struct uwb_verdict *v, int pulses, struct uwb_pulse_sigma *m)
{
    double total2 = v->uncertainty_m * v->uncertainty_m;
    double noise2 = v->current.sigma_center_noise_m * v->current.sigma_center_noise_m;
    if (!(noise2 > 0)) /* no noise term given: take it all as noise; a fit corrects it */
        noise2 = total2;
    double rest2 = total2 - noise2;
    m->fixed_m2 = rest2 < 0 ? 0 : rest2;
    m->scaling_m2 = noise2 * pulses;
    return noise2 > 0 ? 0 : -1;
}

int uwb_pulse_sigma_fit(double sigma1, int pulses1, double sigma2, int pulses2, struct uwb_pulse_sigma *m)
{
    if (pulses2 <= pulses1)
        return -1;
    m->scaling_m2 = (sigma1 * sigma1 - sigma2 * sigma2) / (1.0 / pulses1 - 1.0 / pulses2);
    double fixed = sigma2 * sigma2 - m->scaling_m2 / pulses2;
    m->fixed_m2 = fixed < 0 ? 0 : fixed;
    return m->scaling_m2 > 0 ? 0 : -1;
}

double uwb_pulse_sigma_at(const struct uwb_pulse_sigma *m, double pulses)
{
    return sqrt(m->fixed_m2 + m->scaling_m2 / pulses);
}

int uwb_pulse_sigma_pulses_for(const struct uwb_pulse_sigma *m, double max_m, double *pulses)
{
    double room = max_m * max_m - m->fixed_m2;
    if (!(room > 0))
        return -1;
    *pulses = m->scaling_m2 / room;
    return 0;
}
