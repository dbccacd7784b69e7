/* The pulse shape s(t): Ricker, Gaussian monocycle or a measured waveform.
 * t = 0 is the instant the pulse leaves the transmitter (Ricker: its peak;
 * monocycle: its central zero crossing; file: whatever the file says). The
 * shape is normalised to a peak magnitude of 1; pulse_amplitude and
 * pulse_derivative are applied by the engine. */
#ifndef UWBSIM_PULSE_H
#define UWBSIM_PULSE_H

#include <stddef.h>

#include "scene.h"

struct sim_pulse {
    int kind; /* enum sim_pulse_kind */
    double fc_hz;
    double *t, *v; /* file pulse samples, increasing t */
    size_t n;
};

int sim_pulse_load(const struct sim_scene *scene, struct sim_pulse *pulse, char *err, size_t errlen);
void sim_pulse_free(struct sim_pulse *pulse);
/* s(t); 0 outside a file pulse's span. */
double sim_pulse_value(const struct sim_pulse *pulse, double t);
/* Half-width of the time span outside which s is negligible (< 1e-7). */
double sim_pulse_half_span_s(const struct sim_pulse *pulse);

#endif
