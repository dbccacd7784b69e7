/* The engine: geometry, kernels and FFT plans built once per scene; one
 * noiseless trace per call. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "engine_internal.h"
#include "pulse.h"

static int next_pow2(int n)
{
    int p = 256;
    while (p < n)
        p *= 2;
    return p;
}

double sim_omega_k(const struct sim_engine *e, int k)
{
    return 2.0 * M_PI * k / (e->nfft * e->dt);
}

/* (i w)^a on the FFT's frequency grid (FFTW's forward sign is e^{-iwt}, so a
 * time derivative multiplies by +iw); the principal branch makes the
 * fractional derivative causal. */
double complex sim_frac_derivative(double w, double a)
{
    if (a == 0)
        return 1.0;
    if (w <= 0)
        return 0.0;
    return pow(w, a) * cexp(I * M_PI * a / 2.0);
}

/* The kept response for this position and parts, or NULL. */
static const double complex *cached_response(struct sim_engine *e, double y_ref, unsigned parts)
{
    for (int i = 0; i < e->cache_len; i++) {
        struct sim_response_slot *slot = &e->cache[i];
        if (slot->y_ref == y_ref && slot->parts == parts) {
            slot->last_used = ++e->cache_clock;
            return slot->spectrum;
        }
    }
    return NULL;
}

/* Keeps a copy of a response, in a free slot or the least recently used. */
static void keep_response(struct sim_engine *e, double y_ref, unsigned parts, const double complex *spectrum)
{
    if (e->cache_cap <= 0)
        return;
    struct sim_response_slot *slot;
    if (e->cache_len < e->cache_cap) {
        slot = &e->cache[e->cache_len++];
    } else {
        slot = &e->cache[0];
        for (int i = 1; i < e->cache_len; i++)
            if (e->cache[i].last_used < slot->last_used)
                slot = &e->cache[i];
    }
    slot->y_ref = y_ref;
    slot->parts = parts;
    slot->last_used = ++e->cache_clock;
    memcpy(slot->spectrum, spectrum, ((size_t)e->nfft / 2 + 1) * sizeof *spectrum);
}

static void free_cache(struct sim_engine *e)
{
    for (int i = 0; i < e->cache_cap; i++)
        free(e->cache[i].spectrum);
    free(e->cache);
    e->cache = NULL;
    e->cache_cap = e->cache_len = 0;
}

int sim_engine_cache_responses(struct sim_engine *e, int responses)
{
    free_cache(e);
    if (responses <= 0)
        return 0;
    e->cache = calloc((size_t)responses, sizeof *e->cache);
    if (!e->cache)
        return -1;
    e->cache_cap = responses;
    for (int i = 0; i < responses; i++) {
        e->cache[i].spectrum = malloc(((size_t)e->nfft / 2 + 1) * sizeof *e->cache[i].spectrum);
        if (!e->cache[i].spectrum) {
            free_cache(e);
            return -1;
        }
    }
    return 0;
}

unsigned long sim_engine_responses_computed(const struct sim_engine *e)
{
    return e->responses_computed;
}

int sim_engine_responses_cached(const struct sim_engine *e)
{
    return e->cache_len;
}

/* The noiseless spectrum of one position before the jitter's shift, into
 * e->spec: the surface and edge integrals through their kernels, plus the
 * static returns. */
static void compute_response(struct sim_engine *e, double y_ref, unsigned parts)
{
    int nh = e->nfft / 2;
    fftwf_complex *c = e->cbuf;
    double complex *spec = e->spec;
    memset(spec, 0, ((size_t)nh + 1) * sizeof *spec);
    if (parts & (SIM_PART_WINDING | SIM_PART_CLUTTER)) {
        memset(e->acc, 0, (size_t)e->nfft * sizeof *e->acc);
        memset(e->acc_edge, 0, (size_t)e->nfft * sizeof *e->acc_edge);
        sim_integrate_surfaces(e, y_ref, parts);
        for (int i = 0; i < e->nfft; i++)
            e->rbuf[i] = (float)e->acc[i];
        fftwf_execute(e->r2c);
        for (int k = 0; k <= nh; k++)
            spec[k] += (crealf(c[k]) + I * cimagf(c[k])) * e->surface_kernel[k];
        if (!e->mode2d || ((parts & SIM_PART_WINDING) && e->geo.edge_count > 0)) {
            for (int i = 0; i < e->nfft; i++)
                e->rbuf[i] = (float)e->acc_edge[i];
            fftwf_execute(e->r2c);
            for (int k = 0; k <= nh; k++)
                spec[k] += (crealf(c[k]) + I * cimagf(c[k])) * e->edge_kernel[k];
        }
    }
    for (int k = 0; k <= nh; k++) {
        if (parts & SIM_PART_DIRECT)
            spec[k] += e->static_direct[k];
        if (parts & SIM_PART_CLUTTER)
            spec[k] += e->static_clutter[k];
    }
    e->responses_computed++;
}

void sim_engine_clean_trace(struct sim_engine *e, double y_ref, unsigned parts, double shift_s, double *out)
{
    int nh = e->nfft / 2;
    fftwf_complex *c = e->cbuf;
    /* Only whole responses are kept: what acquisitions ask for, not the
     * noise reference's pass over the winding alone. */
    int keep = parts == SIM_PART_ALL;
    const double complex *spec = keep ? cached_response(e, y_ref, parts) : NULL;
    if (!spec) {
        compute_response(e, y_ref, parts);
        if (keep)
            keep_response(e, y_ref, parts, e->spec);
        spec = e->spec;
    }
    for (int k = 0; k <= nh; k++) {
        double complex v = spec[k];
        if (shift_s != 0)
            v *= cexp(-I * sim_omega_k(e, k) * shift_s);
        c[k] = (float)creal(v) + I * (float)cimag(v);
    }
    fftwf_execute(e->c2r);
    for (int i = 0; i < e->samples; i++)
        out[i] = e->rbuf[e->pad + i];
}

const struct sim_scene *sim_engine_scene(const struct sim_engine *e)
{
    return &e->scene;
}

size_t sim_engine_element_count(const struct sim_engine *e)
{
    return e->geo.count;
}

double sim_engine_peak_echo(struct sim_engine *e)
{
    if (e->peak_echo >= 0)
        return e->peak_echo;
    /* The SNR's reference: the noiseless winding echo's peak over the scan. */
    const struct sim_scene *s = &e->scene;
    double *trace = calloc((size_t)s->samples, sizeof *trace); /* zeroed for the analyzer */
    if (!trace)
        return -1.0;
    double peak = 0.0;
    for (int k = 0; k < s->positions; k++) {
        sim_engine_clean_trace(e, sim_scene_antenna_y_m(s, k), SIM_PART_WINDING, 0.0, trace);
        for (int i = 0; i < s->samples; i++)
            peak = fmax(peak, fabs(trace[i]));
    }
    free(trace);
    e->peak_echo = peak;
    return peak;
}

void sim_engine_free(struct sim_engine *e)
{
    if (!e)
        return;
    free_cache(e);
    sim_geometry_free(&e->geo);
    if (e->r2c)
        fftwf_destroy_plan(e->r2c);
    if (e->c2r)
        fftwf_destroy_plan(e->c2r);
    fftwf_free(e->rbuf);
    fftwf_free(e->cbuf);
    free(e->acc);
    free(e->acc_edge);
    free(e->spec);
    free(e->edge_kernel);
    free(e->surface_kernel);
    free(e->static_direct);
    free(e->static_clutter);
    free(e);
}

/* The pulse's spectrum on the FFT grid, scaled so the incident field 1 m
 * from Tx peaks at pulse_amplitude. */
static int pulse_spectrum(struct sim_engine *e, double complex *F, char *err, size_t errlen)
{
    struct sim_pulse pulse;
    if (sim_pulse_load(&e->scene, &pulse, err, errlen) != 0)
        return -1;
    int n = e->nfft, nh = n / 2;
    for (int i = 0; i < n; i++) {
        double t = (i < nh ? i : i - n) * e->dt; /* circular: negative times at the end */
        e->rbuf[i] = (float)sim_pulse_value(&pulse, t);
    }
    sim_pulse_free(&pulse);
    fftwf_execute(e->r2c);
    for (int k = 0; k <= nh; k++) {
        double complex sk = crealf(e->cbuf[k]) + I * cimagf(e->cbuf[k]);
        F[k] = k == nh ? 0.0 : sk * sim_frac_derivative(sim_omega_k(e, k), e->scene.pulse_derivative);
    }
    for (int k = 0; k <= nh; k++)
        e->cbuf[k] = (float)creal(F[k]) + I * (float)cimag(F[k]);
    fftwf_execute(e->c2r);
    double peak = 0;
    for (int i = 0; i < n; i++)
        peak = fmax(peak, fabs(e->rbuf[i] / n));
    if (!(peak > 0)) {
        snprintf(err, errlen,
                 "pulse: the radiated pulse is zero on this time grid (sample_interval_s too coarse?)");
        return -1;
    }
    for (int k = 0; k <= nh; k++)
        F[k] *= e->scene.pulse_amplitude / peak;
    return 0;
}

int sim_engine_create(const struct sim_scene *scene, struct sim_engine **out, char *err, size_t errlen)
{
    *out = NULL;
    if (sim_scene_validate(scene, err, errlen) != 0)
        return -1;
    struct sim_engine *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(err, errlen, "engine: out of memory");
        return -1;
    }
    e->scene = *scene;
    const struct sim_scene *s = &e->scene;
    e->mode2d = s->mode == SIM_MODE_2D;
    e->n_oil = sqrt(s->eps_r);
    e->inv_v = e->n_oil / C0;
    e->lambda_c = C0 / (e->n_oil * s->centre_frequency_hz);
    if (s->beamwidth_deg > 0 && s->beamwidth_deg < 180)
        e->beam_n = log(0.5) / (2.0 * log(cos(0.5 * s->beamwidth_deg * M_PI / 180.0)));
    e->has_window = s->window_gap_m > 0 || s->window_thickness_m > 0;
    e->win_gap = s->window_gap_m;
    e->win_t = s->window_thickness_m;
    e->n_win = sqrt(s->window_eps_r);
    e->win_T2 = sim_window_transmission(s, e->n_oil);
    {
        double nb = sqrt(s->barrier_eps_r), r = (e->n_oil - nb) / (e->n_oil + nb);
        e->bar_T = 1.0 - r * r;
    }

    if (sim_geometry_build(s, &e->geo, err, errlen) != 0) {
        sim_engine_free(e);
        return -1;
    }

    struct sim_pulse probe;
    if (sim_pulse_load(s, &probe, err, errlen) != 0) {
        sim_engine_free(e);
        return -1;
    }
    double half_span = sim_pulse_half_span_s(&probe);
    sim_pulse_free(&probe);
    e->dt = s->sample_interval_s;
    e->samples = s->samples;
    int m = (int)ceil(half_span / e->dt) + 8;
    if ((double)s->samples + 4.0 * m > 1e8) {
        snprintf(err, errlen, "pulse: %g s long at %g s per sample is too many samples", 2 * half_span,
                 e->dt);
        sim_engine_free(e);
        return -1;
    }
    /* Room on both sides of the record for pulse tails, so the FFT's circular
     * wrap lands in padding and never in the record. */
    e->nfft = next_pow2(2 * s->samples + 4 * m);
    e->pad = (e->nfft - s->samples) / 2;
    e->grid_t0 = s->t0_s - e->pad * e->dt;

    int nh = e->nfft / 2;
    e->acc = calloc((size_t)e->nfft, sizeof *e->acc);
    e->acc_edge = calloc((size_t)e->nfft, sizeof *e->acc_edge);
    e->spec = calloc((size_t)nh + 1, sizeof *e->spec);
    e->edge_kernel = calloc((size_t)nh + 1, sizeof *e->edge_kernel);
    e->rbuf = fftwf_alloc_real((size_t)e->nfft);
    e->cbuf = fftwf_alloc_complex((size_t)nh + 1);
    e->surface_kernel = calloc((size_t)nh + 1, sizeof *e->surface_kernel);
    e->static_direct = calloc((size_t)nh + 1, sizeof *e->static_direct);
    e->static_clutter = calloc((size_t)nh + 1, sizeof *e->static_clutter);
    double complex *F = calloc((size_t)nh + 1, sizeof *F);
    if (!e->acc || !e->acc_edge || !e->spec || !e->edge_kernel || !e->rbuf || !e->cbuf ||
        !e->surface_kernel || !e->static_direct || !e->static_clutter || !F) {
        free(F);
        snprintf(err, errlen, "engine: out of memory for a %d-point FFT", e->nfft);
        sim_engine_free(e);
        return -1;
    }
    /* FFTW's planner is not thread-safe: engines must be created from one thread. */
    e->r2c = fftwf_plan_dft_r2c_1d(e->nfft, e->rbuf, e->cbuf, FFTW_ESTIMATE);
    e->c2r = fftwf_plan_dft_c2r_1d(e->nfft, e->cbuf, e->rbuf, FFTW_ESTIMATE);
    if (!e->r2c || !e->c2r) {
        free(F);
        snprintf(err, errlen, "engine: FFTW could not plan a %d-point transform", e->nfft);
        sim_engine_free(e);
        return -1;
    }
    if (pulse_spectrum(e, F, err, errlen) != 0) {
        free(F);
        sim_engine_free(e);
        return -1;
    }

    double v = C0 / e->n_oil;
    double po = e->mode2d ? 1.0 / sqrt(2.0 * M_PI * v) : 1.0 / (2.0 * M_PI * v);
    double op_order = e->mode2d ? 0.5 : 1.0;
    /* edges: the surface integral's end-point carries one 1/(i w) less (3-D:
     * u = d F / (2 pi R1 R2) per metre of edge; 2-D: d sqrt(v / 2 pi) (iw)^-1/2 F) */
    double edge_const = e->mode2d ? sqrt(v / (2.0 * M_PI)) : 1.0 / (2.0 * M_PI);
    for (int k = 1; k < nh; k++) {
        /* linear deposit = sampling after a triangle filter: divide its sinc^2 out */
        double x = M_PI * k / e->nfft;
        double sinc = sin(x) / x;
        double complex common = F[k] * e->win_T2 / (e->nfft * sinc * sinc);
        double w = sim_omega_k(e, k);
        e->surface_kernel[k] = common * sim_frac_derivative(w, op_order) * po;
        e->edge_kernel[k] = common * (e->mode2d ? 1.0 / sim_frac_derivative(w, 0.5) : 1.0) * edge_const;
    }
    sim_build_statics(e, F);
    free(F);

    e->peak_echo = -1.0; /* computed when first needed */
    *out = e;
    return 0;
}
