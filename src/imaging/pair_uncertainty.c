/* How far the displacement moves with the noise the two scans carry.
 *
 * The noise: a scan alone cannot tell its noise from the static scene's
 * echoes (in the full-wave tank, noiseless, the conditioned traces' median
 * |sample| read 38 where 32 dB of noise gives 6), so it is read on the
 * difference of the two conditioned scans, where the static scene cancels,
 * over each position's samples between the early-time gate and the first
 * moment either scan's winding (widened by a wavelength and two periods)
 * can reply: there the difference is the two scans' noise alone.
 *
 * Its effect: the fit is repeated with fresh noise of that rms, band-limited
 * as conditioning limits it and weighted by the aperture taper, added to one
 * scan's measured traces at a time; the rms change of the displacement over
 * the draws is that scan's share. The draws come from a fixed seed, so a
 * verdict is reproducible. */
#include "imaging_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fft_plans.h"
#include "migrate_plan.h"
#include "select.h"

#include <fftw3.h>

/* Draws per scan. A sigma from N draws scatters by about 1/sqrt(2N) of
 * itself (an rms of N normal deviates): measured on the paper pair over 12
 * seeds, 24 draws gave sigmas 0.0014..0.0023 mm (13 % rms scatter about
 * 0.0018), 48 draws about 9 %. The seed is fixed, so every verdict carries
 * the same draws' luck: 48 keeps it under a tenth. */
#define NOISE_DRAWS 48
#define NOISE_SEED 0x5577424400000001ull
#define MIN_NOISE_SAMPLES 500
#define QUIET_PERIODS 2.0
#define ROWS_MARGIN_M 0.01

static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Standard normal by Box-Muller, one per pair of uniforms. */
static double normal(uint64_t *state)
{
    double u1 = ((double)(splitmix64(state) >> 11) + 1.0) * 0x1.0p-53;   /* (0, 1] */
    double u2 = (double)(splitmix64(state) >> 11) * 0x1.0p-53;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

static double pair_noise_rms(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                             const struct uwb_analysis_options *opt)
{
    const struct uwb_scan *c = &ca->conditioned, *b = &ba->conditioned;
    if (!c->data || !b->data || c->positions != b->positions || c->samples != b->samples)
        return NAN;
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, c, opt->time_zero_offset_s);
    double wavelength = g.velocity_m_s / ca->dominant_hz, period = 1.0 / ca->dominant_hz;
    double y_lo = fmin(ca->edges.lower_m, ba->edges.lower_m) - wavelength;
    double y_hi = fmax(ca->edges.upper_m, ba->edges.upper_m) + wavelength;
    double z_near = fmin(ca->edges.face_z_m, ba->edges.face_z_m) - wavelength;
    int first = uwb_condition_first_open_sample(c, &g, &opt->condition, ca->dominant_hz);
    float *diff = malloc((size_t)c->positions * c->samples * sizeof *diff);
    if (!diff)
        return NAN;
    size_t n = 0;
    for (int k = 0; k < c->positions; k++) {
        double ya = c->antenna_y_m[k];
        double y_near = ya < y_lo ? y_lo : ya > y_hi ? y_hi : ya;
        double t_first = uwb_two_way_delay(&g, y_near - ya, z_near) - QUIET_PERIODS * period;
        int last = (int)floor((t_first - g.t0_s) / g.dt_s);
        if (last > c->samples)
            last = c->samples;
        const float *tc = c->data + (size_t)k * c->samples, *tb = b->data + (size_t)k * c->samples;
        for (int i = first; i < last; i++)
            diff[n++] = fabsf(tc[i] - tb[i]);
    }
    double rms = n >= MIN_NOISE_SAMPLES ? uwb_median_float(diff, n) / 0.6745 / sqrt(2.0) : NAN;
    free(diff);
    return rms;
}

/* Band-limited Gaussian noise, drawn in the frequency domain: each bin of
 * the conditioning's band gets a complex normal times the band's gain, one
 * inverse transform makes the trace. That is white noise filtered as
 * conditioning filters it (circularly, so stationary), with normals for the
 * band's bins only, and on a power-of-two length: a record's own length can
 * be prime (1697 samples in the paper scans), where FFTW is 18 times
 * slower. Positions the aperture taper weighs 0 get none: it could not
 * reach the fit. */
struct noise_source {
    int n;                     /* transform length, a power of two >= the samples */
    int first_bin, last_bin;   /* the band's non-zero bins */
    double *gain;              /* per bin */
    float *trace;
    fftwf_complex *spec;
    fftwf_plan inverse;
};

static void noise_source_free(struct noise_source *ns)
{
    uwb_fft_plan_release(ns->inverse);
    fftwf_free(ns->trace);
    fftwf_free(ns->spec);
    free(ns->gain);
    memset(ns, 0, sizeof *ns);
}

static int noise_source_init(struct noise_source *ns, const struct uwb_scan *shape,
                             const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                             char *err, size_t errlen)
{
    memset(ns, 0, sizeof *ns);
    ns->n = 2;
    while (ns->n < shape->samples)
        ns->n *= 2;
    int nh = ns->n / 2 + 1;
    ns->gain = malloc((size_t)nh * sizeof *ns->gain);
    ns->trace = fftwf_alloc_real((size_t)ns->n);
    ns->spec = fftwf_alloc_complex((size_t)nh);
    ns->inverse = uwb_fft_plan_acquire(FFT_C2R, ns->n);
    if (!ns->gain || !ns->trace || !ns->spec || !ns->inverse) {
        noise_source_free(ns);
        snprintf(err, errlen, "pair uncertainty: out of memory for noise traces of %d samples", shape->samples);
        return -1;
    }
    double df = 1.0 / (ns->n * shape->sample_interval_s);
    ns->first_bin = nh;
    ns->last_bin = -1;
    for (int i = 0; i < nh; i++) {
        ns->gain[i] = uwb_condition_band_gain(&opt->condition, a->dominant_hz, i * df);
        if (ns->gain[i] > 0.0) {
            if (ns->first_bin > i)
                ns->first_bin = i;
            ns->last_bin = i;
        }
    }
    return 0;
}

/* One draw of band-limited Gaussian noise of rms 1 per sample over the
 * positions the taper keeps (weight > 0); zero elsewhere. */
static void noise_draw(struct noise_source *ns, struct uwb_scan *noise, const double *weight,
                       uint64_t *state)
{
    int S = noise->samples, nh = ns->n / 2 + 1;
    double ss = 0.0;
    size_t count = 0;
    for (int k = 0; k < noise->positions; k++) {
        float *tr = noise->data + (size_t)k * S;
        if (!(weight[k] > 0.0)) {
            memset(tr, 0, (size_t)S * sizeof *tr);
            continue;
        }
        memset(ns->spec, 0, (size_t)nh * sizeof *ns->spec);
        for (int i = ns->first_bin; i <= ns->last_bin; i++) {
            ns->spec[i][0] = (float)(ns->gain[i] * normal(state));
            ns->spec[i][1] = (float)(ns->gain[i] * normal(state));
        }
        fftwf_execute_dft_c2r(ns->inverse, ns->spec, ns->trace);
        for (int i = 0; i < S; i++) {
            tr[i] = ns->trace[i];
            ss += (double)tr[i] * tr[i];
        }
        count += (size_t)S;
    }
    float scale = ss > 0.0 ? (float)(1.0 / sqrt(ss / (double)count)) : 0.0f;
    size_t n = (size_t)noise->positions * S;
    for (size_t i = 0; i < n; i++)
        noise->data[i] *= scale;
}

int uwb_shift_noise(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                    const struct uwb_analysis_options *opt, double shift_m, struct uwb_shift_noise *out,
                    char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    double rms = pair_noise_rms(ca, ba, opt);
    if (isnan(rms))
        return 0;   /* not measurable: the per-scan figures stand */
    out->measured = 1;
    out->noise_rms = rms;
    if (!(rms > 0.0))
        return 0;
    struct uwb_scan noise = {0};
    if (uwb_scan_copy(&noise, &ca->conditioned, err, errlen) != 0)
        return -1;
    struct noise_source source[2];
    if (noise_source_init(&source[0], &noise, ca, opt, err, errlen) != 0) {
        uwb_scan_free(&noise);
        return -1;
    }
    if (noise_source_init(&source[1], &noise, ba, opt, err, errlen) != 0) {
        noise_source_free(&source[0]);
        uwb_scan_free(&noise);
        return -1;
    }
    /* Only the heights the fit reads: the baseline's winding, and the current's
     * within the fit's search, with room for the interpolation. */
    double half = 0.5 * ba->edges.height_m + ROWS_MARGIN_M;
    double y_lo = ba->edges.center_m + fmin(0.0, shift_m) - half;
    double y_hi = ba->edges.center_m + fmax(0.0, shift_m) + half;
    struct uwb_migration_plan plan[2];
    memset(plan, 0, sizeof plan);
    uint64_t state = NOISE_SEED;
    double ss_cur = 0.0, ss_base = 0.0;
    int rc = 0;
    for (int r = 0; r < NOISE_DRAWS && rc == 0; r++) {
        for (int which = 0; which < 2 && rc == 0; which++) {
            const struct uwb_analysis *a = which == 0 ? ca : ba;
            struct uwb_face_profile p;
            noise_draw(&source[which], &noise, a->weight, &state);
            rc = uwb_analysis_measure_again(a, opt, &noise, rms, y_lo, y_hi, &plan[which], &p, err, errlen);
            if (rc != 0)
                break;
            double d = which == 0 ? uwb_analysis_shift(&p, &ba->profile, ba, shift_m)
                                  : uwb_analysis_shift(&ca->profile, &p, ba, shift_m);
            free(p.value);
            if (isnan(d)) {
                snprintf(err, errlen, "pair uncertainty: out of memory for the profiles' fit");
                rc = -1;
                break;
            }
            if (which == 0)
                ss_cur += (d - shift_m) * (d - shift_m);
            else
                ss_base += (d - shift_m) * (d - shift_m);
        }
    }
    noise_source_free(&source[0]);
    noise_source_free(&source[1]);
    uwb_migration_plan_free(&plan[0]);
    uwb_migration_plan_free(&plan[1]);
    uwb_scan_free(&noise);
    out->sigma_current_m = sqrt(ss_cur / NOISE_DRAWS);
    out->sigma_baseline_m = sqrt(ss_base / NOISE_DRAWS);
    return rc;
}
