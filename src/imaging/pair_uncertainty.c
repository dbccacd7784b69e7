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
 * Its effect: noise of that rms, band-limited as conditioning limits it and
 * weighted by the aperture taper, added to one scan's measured traces at a
 * time; the rms change of the displacement is that scan's share. The
 * verdict's figure propagates the noise linearly through the fit, the
 * envelope and the migration (one adjoint pass per scan, below): at the
 * noise levels a figure is given for, the displacement moves linearly
 * with the noise (against 96 to 400 seeded draws of the fit repeated on
 * noisy traces, the paper and tank fixtures, clean and at 20 and 32 dB,
 * agreed within 7 %, inside the draws' own scatter), it costs a few ms a
 * scan against 34 ms for 48 draws, and it carries no draws' luck
 * (48 draws scatter by about 9 %). The draws stay as the tests' oracle
 * (uwb_shift_noise_draws) and decide where the fit has no curvature to
 * linearise about. */
#include "imaging_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "delay_table.h"
#include "fft_plans.h"
#include "uwb/migrate.h"
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
    double u1 = ((double)(splitmix64(state) >> 11) + 1.0) * 0x1.0p-53; /* (0, 1] */
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
    int n;                   /* transform length, a power of two >= the samples */
    int first_bin, last_bin; /* the band's non-zero bins */
    double *gain;            /* per bin */
    float *trace;
    fftwf_complex *spec;
    fftwf_plan inverse;
    fftwf_plan forward; /* for the linear propagation's spectra */
};

static void noise_source_free(struct noise_source *ns)
{
    uwb_fft_plan_release(ns->inverse);
    uwb_fft_plan_release(ns->forward);
    fftwf_free(ns->trace);
    fftwf_free(ns->spec);
    free(ns->gain);
    *ns = (struct noise_source){0};
}

static int noise_source_init(struct noise_source *ns, const struct uwb_scan *shape,
                             const struct uwb_analysis *a, const struct uwb_analysis_options *opt, char *err,
                             size_t errlen)
{
    *ns = (struct noise_source){0};
    ns->n = uwb_fft_padded_length(shape->samples);
    int nh = ns->n / 2 + 1;
    /* Zeroed though the loop below sets every bin: the static analyser
     * cannot see that the padded length is at least 2. */
    ns->gain = calloc((size_t)nh, sizeof *ns->gain);
    ns->trace = fftwf_alloc_real((size_t)ns->n);
    ns->spec = fftwf_alloc_complex((size_t)nh);
    ns->inverse = uwb_fft_plan_acquire(FFT_C2R, ns->n);
    ns->forward = uwb_fft_plan_acquire(FFT_R2C, ns->n);
    if (!ns->gain || !ns->trace || !ns->spec || !ns->inverse || !ns->forward) {
        noise_source_free(ns);
        snprintf(err, errlen, "pair uncertainty: out of memory for noise traces of %d samples",
                 shape->samples);
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
static void noise_draw(struct noise_source *ns, struct uwb_scan *noise, const double *weight, uint64_t *state)
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

/* ---- linear propagation ---------------------------------------------------
 *
 * For noise as small as the data's, the displacement moves linearly with it:
 * d - d0 = sum over samples of dd/ds * scale * w_k * n. Its rms over the
 * band-limited noise the draws model is then one quadratic form per trace,
 * sum over bins of c_b gain_b^2 |DFT(dd/ds)_b|^2 / (the noise's variance per
 * sample), with c_b the bin's share (4 inside the band's half spectrum, 1
 * at DC and Nyquist) — no draws, so no draws' luck either. The gradient
 * dd/ds goes back through each step of the face measurement:
 *   the fit:        dd/dp per profile row (profile_shift.c, implicit);
 *   the profile:    p(y) = |A(y, z*)| at the row's brightest range z* in
 *                   the face window, so dp = Re(conj(A)/|A| dA) there;
 *   the envelope:   A = R + i H R along range, H the padded transform's
 *                   Hilbert kernel (envelope.c): Im A(z) = sum_s h(z-s) R(s);
 *   the migration:  R = delay-and-sum with linear interpolation, whose
 *                   adjoint spreads each pixel's weight back onto the two
 *                   samples it read. */

/* Im of the analytic signal uwb_envelope_along_z makes (transform length n,
 * zero-padded), per unit sample at lag m: (2/n) sum_{k=1}^{n/2-1}
 * sin(2 pi k m / n), which sums to (2/n) cot(pi m / n) at odd lags and 0 at
 * even ones. Stored for lags -(nz-1)..nz-1 at kernel[m + nz - 1]. */
static double *hilbert_kernel(int n, int nz)
{
    double *h = malloc((size_t)(2 * nz - 1) * sizeof *h);
    if (!h)
        return NULL;
    for (int m = -(nz - 1); m <= nz - 1; m++)
        h[m + nz - 1] = (m % 2 != 0) ? 2.0 / n / tan(M_PI * m / n) : 0.0;
    return h;
}

/* The weight on each real-image pixel of sum_y grad[y] * p(y): the
 * profile's row maxima of |R + iHR| within [lo, hi]. h as hilbert_kernel. */
static void profile_adjoint(const struct uwb_image *real, const double *grad, int lo, int hi, const double *h,
                            double *weight)
{
    int nz = real->nz;
    memset(weight, 0, (size_t)real->ny * nz * sizeof *weight);
    for (int iy = 0; iy < real->ny; iy++) {
        if (grad[iy] == 0.0)
            continue;
        const float *r = real->pix + (size_t)iy * nz;
        double best = -1.0, br = 0.0, bi = 0.0;
        int bz = lo;
        for (int iz = lo; iz <= hi; iz++) {
            const double *hz = h + iz + nz - 1; /* hz[-s] = h(iz - s) */
            double im = 0.0;
            for (int s = (iz + 1) % 2; s < nz; s += 2) /* h is 0 at even lags */
                im += hz[-s] * r[s];
            double e = sqrt((double)r[iz] * r[iz] + im * im);
            if (e > best) {
                best = e;
                bz = iz;
                br = r[iz];
                bi = im;
            }
        }
        if (!(best > 0.0))
            continue;
        double *w = weight + (size_t)iy * nz;
        const double *hz = h + bz + nz - 1;
        w[bz] += grad[iy] * br / best;
        for (int s = (bz + 1) % 2; s < nz; s += 2)
            w[s] += grad[iy] * (bi / best) * hz[-s];
    }
}

/* rms of sum_k scale * w_k * <v_k, n_k> over the noise source's draws. */
static double propagated_rms(const struct noise_source *ns, const double *v, int positions, int samples,
                             const double *aperture_weight, float *pad, fftwf_complex *spec)
{
    int nh = ns->n / 2 + 1;
    double per_sample = 0.0, total = 0.0;
    for (int i = ns->first_bin; i <= ns->last_bin; i++) {
        double share = (i == 0 || i == nh - 1) ? 1.0 : 4.0;
        per_sample += share * ns->gain[i] * ns->gain[i];
    }
    if (!(per_sample > 0.0))
        return 0.0;
    for (int k = 0; k < positions; k++) {
        double wk = aperture_weight[k];
        if (!(wk > 0.0))
            continue;
        for (int i = 0; i < samples; i++)
            pad[i] = (float)v[(size_t)k * (samples + 2) + i];
        memset(pad + samples, 0, (size_t)(ns->n - samples) * sizeof *pad);
        fftwf_execute_dft_r2c(ns->forward, pad, spec);
        double q = 0.0;
        for (int i = ns->first_bin; i <= ns->last_bin; i++) {
            double share = (i == 0 || i == nh - 1) ? 1.0 : 4.0;
            q += share * ns->gain[i] * ns->gain[i] *
                 ((double)spec[i][0] * spec[i][0] + (double)spec[i][1] * spec[i][1]);
        }
        total += wk * wk * q;
    }
    return sqrt(total / per_sample);
}

/* The interpolation weight of the later sample for table entry e. */
static double table_fraction(const struct delay_table *t, size_t e)
{
    return t->format == DELAY_FLOAT ? (double)t->frac[e] : t->weight_q15[e] / 32768.0;
}

/* ---- the taper's path ------------------------------------------------------
 *
 * Each scan's aperture taper is centred on the winding's centre as that
 * scan's own (noisy) profile reads it, so the noise also moves the
 * weights the profile is measured with, and with them the displacement:
 * on the full-wave pairs the displacement moves by some 0.17 mm per mm of
 * taper centre, and the centre's noise is the profile's own, so it adds
 * to the fit's with the same sign (frozen at the noiseless weights, the
 * same noise spread the displacement 10 to 17 % less). The taper is
 * rebuilt pass after pass on the last pass's centre: at its fixed point
 * c = c_tap + C(p(c)) - C(p(c_tap)), so c moves with the noise by
 * (dC/dp . dp/dnoise) / (1 - dC/dc), C the centre the analysis reads on a
 * profile. */
#define TAPER_STEP_M 0.0005   /* the central differences' step in taper centre */
#define CENTRE_SEARCH_M 0.002 /* re-reading a centre near a known one */
#define TAPER_ITERATIONS 3    /* the oracle's passes, as the analysis' TAPER_PASSES */

/* The face profile of `a` measured again with its taper centred on
 * centre_m (and noise * rms added, weighted alike, when noise is not
 * NULL): the measured traces rescaled by the new weights over the old.
 * Positions the old taper weighs 0 stay out (the taper moves by a fraction
 * of a pixel; its cosine shoulders are near 0 there). */
static int measure_retapered(const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                             double centre_m, const struct uwb_scan *noise, double rms, double y_lo,
                             double y_hi, struct uwb_migration_plan *plan, struct uwb_scan *work,
                             struct uwb_face_profile *p, char *err, size_t errlen)
{
    int K = a->measured.positions, S = a->measured.samples;
    double *w = malloc((size_t)K * sizeof *w);
    if (!w) {
        snprintf(err, errlen, "pair uncertainty: out of memory for the taper");
        return -1;
    }
    uwb_taper_weights(&a->conditioned, centre_m, a->aperture_lo_m, a->aperture_hi_m, w);
    for (int k = 0; k < K; k++) {
        float *out = work->data + (size_t)k * S;
        const float *m = a->measured.data + (size_t)k * S;
        const float *n = noise ? noise->data + (size_t)k * S : NULL;
        double old = a->weight[k];
        if (!(old > 0.0)) {
            memset(out, 0, (size_t)S * sizeof *out);
            continue;
        }
        /* measure_again adds old * out: make it m (w/old - 1) + rms w n. */
        float fm = (float)((w[k] - old) / (old * old)), fn = (float)(rms * w[k] / old);
        for (int i = 0; i < S; i++)
            out[i] = m[i] * fm + (n ? n[i] * fn : 0.0f);
    }
    free(w);
    return uwb_analysis_measure_again(a, opt, work, 1.0, y_lo, y_hi, plan, p, NULL, err, errlen);
}

/* The displacement with p in place of scan `which`'s own profile (0: the
 * current scan's, 1: the baseline's). */
static double fit_with(const struct uwb_face_profile *p, int which, const struct uwb_analysis *ca,
                       const struct uwb_analysis *ba, double shift_m)
{
    return which == 0 ? uwb_analysis_shift(p, &ba->profile, ba, shift_m)
                      : uwb_analysis_shift(&ca->profile, p, ba, shift_m);
}

/* Add the taper's path to grad (dd/dp over p0's rows): grad += s / (1 - k)
 * * dC/dp, s = dd/dc_tap and k = dC/dc_tap by central differences. plan:
 * p0's, on the same grid (its delay table is not built again).
 * Returns 0 (grad unchanged when the scan had no taper), -1 on error. */
static int add_taper_path(const struct uwb_analysis *a, const struct uwb_analysis *ca,
                          const struct uwb_analysis *ba, int which, const struct uwb_analysis_options *opt,
                          double y_lo, double y_hi, double shift_m, const struct uwb_face_profile *p0,
                          struct uwb_migration_plan *plan, double *grad, char *err, size_t errlen)
{
    if (!a->has_taper)
        return 0;
    double c_ref = uwb_profile_centre(p0, opt->edge_fraction, NAN, 0.0);
    if (isnan(c_ref))
        return 0;
    struct uwb_scan work = {0};
    if (uwb_scan_copy(&work, &a->measured, err, errlen) != 0)
        return -1;
    double d[2], c[2];
    int rc = 0;
    for (int side = 0; side < 2 && rc == 0; side++) {
        struct uwb_face_profile p;
        double centre = a->taper_centre_m + (side ? TAPER_STEP_M : -TAPER_STEP_M);
        rc = measure_retapered(a, opt, centre, NULL, 0.0, y_lo, y_hi, plan, &work, &p, err, errlen);
        if (rc != 0)
            break;
        d[side] = fit_with(&p, which, ca, ba, shift_m);
        c[side] = uwb_profile_centre(&p, opt->edge_fraction, c_ref, CENTRE_SEARCH_M);
        free(p.value);
    }
    uwb_scan_free(&work);
    if (rc != 0)
        return -1;
    double s = (d[1] - d[0]) / (2.0 * TAPER_STEP_M), k = (c[1] - c[0]) / (2.0 * TAPER_STEP_M);
    if (!isfinite(s) || !isfinite(k) || fabs(k) > 0.9)
        return 0; /* no fixed point to linearise about */
    /* dC/dp: implicit differentiation of the mirror asymmetry's slope
     * (it agrees within 2 % with nudging each row by a thousandth of the
     * peak, which also lets the crossings and so the mirror span move). */
    double c0 = uwb_profile_centre(p0, opt->edge_fraction, c_ref, CENTRE_SEARCH_M);
    double *g = calloc((size_t)p0->n, sizeof *g);
    if (!g) {
        snprintf(err, errlen, "pair uncertainty: out of memory for the centre's gradient");
        return -1;
    }
    if (!isnan(c0) && uwb_profile_centre_gradient(p0, opt->edge_fraction, c0, g) == 0)
        for (int i = 0; i < p0->n; i++)
            grad[i] += s / (1.0 - k) * g[i];
    free(g);
    return 0;
}

/* One scan's share by linear propagation: 0 and *sigma, 1 when the fit has
 * no curvature at the displacement (the draws decide then), -1 on error. */
static int share_linear(const struct uwb_analysis *a, const struct uwb_analysis *ca,
                        const struct uwb_analysis *ba, int which, const struct uwb_analysis_options *opt,
                        const struct noise_source *ns, double rms, double y_lo, double y_hi, double shift_m,
                        double *sigma, char *err, size_t errlen)
{
    /* The noiseless measurement the draws scatter about, and its delay
     * table (kept in the plan) for the real image and its adjoint. */
    struct uwb_migration_plan plan;
    memset(&plan, 0, sizeof plan);
    struct uwb_face_profile p0;
    double z_face = a->edges.face_z_m;
    if (uwb_analysis_measure_again(a, opt, &a->measured, 0.0, y_lo, y_hi, &plan, &p0, &z_face, err, errlen) !=
        0) {
        uwb_migration_plan_free(&plan);
        return -1;
    }
    struct uwb_geometry g;
    uwb_geometry_from_scan(&g, &a->measured, opt->time_zero_offset_s);
    struct uwb_image real = {0};
    int rc = -1, K = a->measured.positions, S = a->measured.samples;
    double *grad = malloc((size_t)p0.n * sizeof *grad), *h = NULL, *weight = NULL, *v = NULL;
    float *pad = fftwf_alloc_real((size_t)ns->n);
    fftwf_complex *spec = fftwf_alloc_complex((size_t)ns->n / 2 + 1);
    if (!grad || !pad || !spec) {
        snprintf(err, errlen, "pair uncertainty: out of memory for the displacement's gradient");
        goto done;
    }
    int flat = which == 0 ? uwb_profile_shift_gradient(&p0, &ba->profile, ba->edges.center_m,
                                                       0.5 * ba->edges.height_m, shift_m, grad, NULL)
                          : uwb_profile_shift_gradient(&ca->profile, &p0, ba->edges.center_m,
                                                       0.5 * ba->edges.height_m, shift_m, NULL, grad);
    if (flat != 0) {
        rc = 1;
        goto done;
    }
    if (add_taper_path(a, ca, ba, which, opt, y_lo, y_hi, shift_m, &p0, &plan, grad, err, errlen) != 0)
        goto done;
    if (uwb_face_grid(&a->measured, &g, a->edges.face_z_m, a->dominant_hz, y_lo, y_hi, &real, err, errlen) !=
        0)
        goto done;
    if (real.ny != p0.n || fabs(real.y0_m - p0.y0_m) > 1e-9 ||
        !uwb_migration_plan_serves(&plan, opt->migration, &real)) {
        snprintf(err, errlen, "pair uncertainty: the face grid does not match the measurement's");
        goto done;
    }
    const struct delay_table *table = &plan.table;
    int nz = real.nz, n = 2;
    while (n < 2 * nz)
        n *= 2;
    double wavelength = g.velocity_m_s / a->dominant_hz;
    int lo = (int)floor((z_face - wavelength / 4 - real.z0_m) / real.dz_m);
    int hi = (int)ceil((z_face + wavelength / 4 - real.z0_m) / real.dz_m);
    lo = lo < 0 ? 0 : lo;
    hi = hi > nz - 1 ? nz - 1 : hi;
    h = hilbert_kernel(n, nz);
    weight = malloc((size_t)real.ny * nz * sizeof *weight);
    v = calloc((size_t)K * (S + 2), sizeof *v);
    if (!h || !weight || !v || lo > hi) {
        snprintf(err, errlen, "pair uncertainty: out of memory for the displacement's gradient");
        goto done;
    }
    /* The real image (before the envelope), as the migration sums it: on
     * the rows the fit reads only (grad 0 elsewhere), which the adjoint
     * below alone uses. */
    memset(real.pix, 0, (size_t)real.ny * nz * sizeof *real.pix);
    for (int k = 0; k < K; k++) {
        if (!(a->weight[k] > 0.0))
            continue;
        uwb_delay_table_fill_trace(&plan.table, &a->measured, &g, &real, k);
        const float *tr = a->measured.data + (size_t)k * S;
        for (int iy = 0; iy < real.ny; iy++) {
            if (grad[iy] == 0.0)
                continue;
            size_t row = delay_table_row(table, k, iy);
            float *out = real.pix + (size_t)iy * nz;
            for (int iz = 0; iz < nz; iz++) {
                int32_t i = table->index[row + iz];
                double x0 = i < S ? tr[i] : 0.0, x1 = i + 1 < S ? tr[i + 1] : 0.0;
                out[iz] += (float)(x0 + (x1 - x0) * table_fraction(table, row + iz));
            }
        }
    }
    profile_adjoint(&real, grad, lo, hi, h, weight);
    /* The migration's adjoint: each pixel's weight back onto the two
     * samples it read. */
    for (int k = 0; k < K; k++) {
        if (!(a->weight[k] > 0.0))
            continue;
        uwb_delay_table_fill_trace(&plan.table, &a->measured, &g, &real, k);
        double *vk = v + (size_t)k * (S + 2);
        for (int iy = 0; iy < real.ny; iy++) {
            if (grad[iy] == 0.0)
                continue; /* its weights are all 0 (profile_adjoint) */
            size_t row = delay_table_row(table, k, iy);
            const double *w = weight + (size_t)iy * nz;
            for (int iz = 0; iz < nz; iz++) {
                int32_t i = table->index[row + iz];
                double f = table_fraction(table, row + iz);
                vk[i] += w[iz] * (1.0 - f);
                vk[i + 1] += w[iz] * f;
            }
        }
    }
    *sigma = rms * propagated_rms(ns, v, K, S, a->weight, pad, spec);
    rc = 0;
done:
    uwb_migration_plan_free(&plan);
    uwb_image_free(&real);
    free(p0.value);
    free(grad);
    free(h);
    free(weight);
    free(v);
    fftwf_free(pad);
    fftwf_free(spec);
    return rc;
}

/* ---- both ways ------------------------------------------------------------ */

struct noise_setup {
    double rms;
    double y_lo, y_hi;             /* the rows the fit reads */
    struct noise_source source[2]; /* current, baseline */
};

static void noise_setup_free(struct noise_setup *s)
{
    noise_source_free(&s->source[0]);
    noise_source_free(&s->source[1]);
}

/* The noise rms and the sources; 1 when the noise is not measurable or
 * zero (out says so), 0 when set up, -1 on error. */
static int noise_setup(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                       const struct uwb_analysis_options *opt, double shift_m, struct uwb_shift_noise *out,
                       struct noise_setup *s, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    memset(s, 0, sizeof *s);
    s->rms = pair_noise_rms(ca, ba, opt);
    if (isnan(s->rms))
        return 1; /* not measurable: the per-scan figures stand */
    out->measured = 1;
    out->noise_rms = s->rms;
    if (!(s->rms > 0.0))
        return 1;
    if (noise_source_init(&s->source[0], &ca->conditioned, ca, opt, err, errlen) != 0)
        return -1;
    if (noise_source_init(&s->source[1], &ca->conditioned, ba, opt, err, errlen) != 0) {
        noise_source_free(&s->source[0]);
        return -1;
    }
    /* Only the heights the fit reads: the baseline's winding, and the current's
     * within the fit's search, with room for the interpolation. */
    double half = 0.5 * ba->edges.height_m + ROWS_MARGIN_M;
    s->y_lo = ba->edges.center_m + fmin(0.0, shift_m) - half;
    s->y_hi = ba->edges.center_m + fmax(0.0, shift_m) + half;
    /* ...and where each scan's taper centre is read: its mirror span of
     * 1.5 half heights about its centre (uwb_profile_centre). */
    for (int which = 0; which < 2; which++) {
        const struct uwb_edges *e = which == 0 ? &ca->edges : &ba->edges;
        double reach = 0.75 * e->height_m + CENTRE_SEARCH_M + ROWS_MARGIN_M;
        s->y_lo = fmin(s->y_lo, e->center_m - reach);
        s->y_hi = fmax(s->y_hi, e->center_m + reach);
    }
    return 0;
}

/* The oracle's measurement of `a` with noise * rms added: with the taper
 * rebuilt on the noisy profile's centre as the analysis' passes rebuild it
 * (c = c_tap + C(noisy) - C(noiseless), TAPER_ITERATIONS measurements),
 * or at the analysis' own weights when it had no taper. c0_m: C on the
 * noiseless profile (NAN: no taper to rebuild). */
static int measure_noisy(const struct uwb_analysis *a, const struct uwb_analysis_options *opt,
                         const struct uwb_scan *noise, double rms, double c0_m, double y_lo, double y_hi,
                         struct uwb_migration_plan *plan, struct uwb_scan *work, struct uwb_face_profile *p,
                         char *err, size_t errlen)
{
    if (isnan(c0_m))
        return uwb_analysis_measure_again(a, opt, noise, rms, y_lo, y_hi, plan, p, NULL, err, errlen);
    double centre = a->taper_centre_m;
    for (int pass = 0; pass < TAPER_ITERATIONS; pass++) {
        if (measure_retapered(a, opt, centre, noise, rms, y_lo, y_hi, plan, work, p, err, errlen) != 0)
            return -1;
        if (pass == TAPER_ITERATIONS - 1)
            break;
        double c = uwb_profile_centre(p, opt->edge_fraction, NAN, 0.0);
        if (isnan(c))
            break; /* the noisy profile gave no centre: the taper stays */
        centre = a->taper_centre_m + (c - c0_m);
        free(p->value);
        p->value = NULL;
    }
    return 0;
}

/* Each scan's share by repeating the fit over `draws` noise draws per scan. */
static int shares_by_draws(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                           const struct uwb_analysis_options *opt, double shift_m, int draws,
                           struct noise_setup *s, int which_lo, int which_hi, double sigma[2], char *err,
                           size_t errlen)
{
    struct uwb_scan noise = {0};
    if (uwb_scan_copy(&noise, &ca->conditioned, err, errlen) != 0)
        return -1;
    struct uwb_scan work = {0};
    if (uwb_scan_copy(&work, &ca->measured, err, errlen) != 0) {
        uwb_scan_free(&noise);
        return -1;
    }
    struct uwb_migration_plan plan[2];
    memset(plan, 0, sizeof plan);
    uint64_t state = NOISE_SEED;
    double ss[2] = {0.0, 0.0}, c0[2] = {NAN, NAN};
    int rc = 0;
    for (int which = which_lo; which <= which_hi && rc == 0; which++) {
        const struct uwb_analysis *a = which == 0 ? ca : ba;
        struct uwb_face_profile p;
        if (!a->has_taper)
            continue;
        rc = measure_retapered(a, opt, a->taper_centre_m, NULL, 0.0, s->y_lo, s->y_hi, &plan[which], &work,
                               &p, err, errlen);
        if (rc == 0)
            c0[which] = uwb_profile_centre(&p, opt->edge_fraction, NAN, 0.0);
        free(p.value);
    }
    for (int r = 0; r < draws && rc == 0; r++) {
        for (int which = 0; which < 2 && rc == 0; which++) {
            const struct uwb_analysis *a = which == 0 ? ca : ba;
            struct uwb_face_profile p;
            noise_draw(&s->source[which], &noise, a->weight, &state);
            if (which < which_lo || which > which_hi)
                continue; /* the draw is still taken: the other scan's draws stay the same */
            rc = measure_noisy(a, opt, &noise, s->rms, c0[which], s->y_lo, s->y_hi, &plan[which], &work, &p,
                               err, errlen);
            if (rc != 0)
                break;
            double d = fit_with(&p, which, ca, ba, shift_m);
            free(p.value);
            if (isnan(d)) {
                snprintf(err, errlen, "pair uncertainty: out of memory for the profiles' fit");
                rc = -1;
                break;
            }
            ss[which] += (d - shift_m) * (d - shift_m);
        }
    }
    uwb_migration_plan_free(&plan[0]);
    uwb_migration_plan_free(&plan[1]);
    uwb_scan_free(&noise);
    uwb_scan_free(&work);
    for (int which = which_lo; which <= which_hi; which++)
        sigma[which] = sqrt(ss[which] / draws);
    return rc;
}

int uwb_shift_noise_draws(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                          const struct uwb_analysis_options *opt, double shift_m, int draws,
                          struct uwb_shift_noise *out, char *err, size_t errlen)
{
    struct noise_setup s;
    int rc = noise_setup(ca, ba, opt, shift_m, out, &s, err, errlen);
    if (rc != 0)
        return rc < 0 ? -1 : 0;
    double sigma[2] = {0.0, 0.0};
    rc = shares_by_draws(ca, ba, opt, shift_m, draws, &s, 0, 1, sigma, err, errlen);
    noise_setup_free(&s);
    out->sigma_current_m = sigma[0];
    out->sigma_baseline_m = sigma[1];
    return rc;
}

int uwb_shift_noise(const struct uwb_analysis *ca, const struct uwb_analysis *ba,
                    const struct uwb_analysis_options *opt, double shift_m, struct uwb_shift_noise *out,
                    char *err, size_t errlen)
{
    struct noise_setup s;
    int rc = noise_setup(ca, ba, opt, shift_m, out, &s, err, errlen);
    if (rc != 0)
        return rc < 0 ? -1 : 0;
    double sigma[2] = {0.0, 0.0};
    for (int which = 0; which < 2 && rc == 0; which++) {
        const struct uwb_analysis *a = which == 0 ? ca : ba;
        rc = share_linear(a, ca, ba, which, opt, &s.source[which], s.rms, s.y_lo, s.y_hi, shift_m,
                          &sigma[which], err, errlen);
        if (rc == 1) /* no curvature to linearise about: the draws decide */
            rc = shares_by_draws(ca, ba, opt, shift_m, NOISE_DRAWS, &s, which, which, sigma, err, errlen);
    }
    noise_setup_free(&s);
    out->sigma_current_m = sigma[0];
    out->sigma_baseline_m = sigma[1];
    return rc;
}
