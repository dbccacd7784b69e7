#include "pulse.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static double ricker(double fc, double t)
{
    double a = M_PI * fc * t;
    a *= a;
    return (1.0 - 2.0 * a) * exp(-a);
}

/* First derivative of a Gaussian whose spectrum peaks at fc; first lobe
 * positive, peak magnitude 1 at t = -+tau. */
static double monocycle(double fc, double t)
{
    double tau = 1.0 / (2.0 * M_PI * fc);
    double x = t / tau;
    return -x * exp(0.5 * (1.0 - x * x));
}

static int load_file(const char *path, struct sim_pulse *p, char *err, size_t errlen)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    size_t cap = 0;
    char line[512];
    int lineno = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char *s = line;
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s == '#' || *s == '\n' || *s == '\r' || *s == '\0')
            continue;
        char *end;
        double t = strtod(s, &end);
        char *end2;
        double v = strtod(end, &end2);
        while (*end2 == ' ' || *end2 == '\t' || *end2 == '\r' || *end2 == '\n' || *end2 == ',')
            end2++;
        if (end == s || end2 == end || *end2 != '\0' || !isfinite(t) || !isfinite(v)) {
            snprintf(err, errlen, "%s: line %d: expected 'time_s value'", path, lineno);
            fclose(f);
            return -1;
        }
        if (p->n > 0 && t <= p->t[p->n - 1]) {
            snprintf(err, errlen, "%s: line %d: times must increase", path, lineno);
            fclose(f);
            return -1;
        }
        if (p->n == cap) {
            cap = cap ? 2 * cap : 256;
            double *nt = realloc(p->t, cap * sizeof *nt);
            if (nt)
                p->t = nt;
            double *nv = realloc(p->v, cap * sizeof *nv);
            if (nv)
                p->v = nv;
            if (!nt || !nv) {
                snprintf(err, errlen, "%s: out of memory", path);
                fclose(f);
                return -1;
            }
        }
        p->t[p->n] = t;
        p->v[p->n] = v;
        p->n++;
    }
    fclose(f);
    if (p->n < 4) {
        snprintf(err, errlen, "%s: a pulse needs at least 4 samples", path);
        return -1;
    }
    double peak = 0;
    for (size_t i = 0; i < p->n; i++)
        peak = fmax(peak, fabs(p->v[i]));
    if (peak == 0) {
        snprintf(err, errlen, "%s: the pulse is all zero", path);
        return -1;
    }
    for (size_t i = 0; i < p->n; i++)
        p->v[i] /= peak;
    return 0;
}

int sim_pulse_load(const struct sim_scene *scene, struct sim_pulse *pulse, char *err, size_t errlen)
{
    memset(pulse, 0, sizeof *pulse);
    pulse->kind = scene->pulse;
    pulse->fc_hz = scene->centre_frequency_hz;
    if (pulse->kind == SIM_PULSE_FILE && load_file(scene->pulse_file, pulse, err, errlen) != 0) {
        sim_pulse_free(pulse);
        return -1;
    }
    return 0;
}

void sim_pulse_free(struct sim_pulse *pulse)
{
    free(pulse->t);
    free(pulse->v);
    memset(pulse, 0, sizeof *pulse);
}

double sim_pulse_value(const struct sim_pulse *p, double t)
{
    switch (p->kind) {
    case SIM_PULSE_RICKER: return ricker(p->fc_hz, t);
    case SIM_PULSE_MONOCYCLE: return monocycle(p->fc_hz, t);
    default: break;
    }
    if (t < p->t[0] || t > p->t[p->n - 1])
        return 0.0;
    size_t lo = 0, hi = p->n - 1;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        if (p->t[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    double f = (t - p->t[lo]) / (p->t[hi] - p->t[lo]);
    return p->v[lo] + f * (p->v[hi] - p->v[lo]);
}

double sim_pulse_half_span_s(const struct sim_pulse *p)
{
    if (p->kind == SIM_PULSE_FILE)
        return fmax(fabs(p->t[0]), fabs(p->t[p->n - 1]));
    /* exp(-(pi fc t)^2) < 1e-7 beyond pi fc t = 4.1 */
    return 4.2 / (M_PI * p->fc_hz);
}
