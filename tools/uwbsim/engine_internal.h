/* Inside the engine: its state and the pieces its files share. Not for
 * users of the library (they include engine.h). */
#ifndef UWBSIM_ENGINE_INTERNAL_H
#define UWBSIM_ENGINE_INTERNAL_H

#include <complex.h> /* before fftw3.h: fftwf_complex is then float complex */
#include <fftw3.h>

#include "engine.h"

#define C0 299792458.0

struct sim_engine {
    struct sim_scene scene;
    struct sim_geometry geo;
    int mode2d;
    double n_oil, inv_v; /* inv_v: s/m in the oil */
    double beam_n;       /* pattern cos^n; 0: isotropic */
    double lambda_c;     /* wavelength in the oil at the centre frequency */
    /* tank window, seen from antennas at z = 0 */
    int has_window;
    double win_gap, win_t, n_win;
    double win_T2; /* two-way transmission through its interfaces */
    double bar_T;  /* one pass through the barrier */
    /* time grid and FFT */
    int nfft, pad, samples;
    double dt, grid_t0; /* buffer index i is time grid_t0 + i dt */
    double *acc, *acc_edge;
    double complex *spec;
    float *rbuf;
    fftwf_complex *cbuf;
    fftwf_plan r2c, c2r;
    double complex *surface_kernel; /* operator x pulse x PO constant / N / grid smoothing */
    double complex *edge_kernel;    /* the same for the edges' fringe term */
    double complex *static_direct;  /* direct coupling + window echoes, / N */
    double complex *static_clutter; /* far wall, / N */
    double peak_echo;
    /* responses kept (sim_engine_cache_responses): one per position and
     * part mask, the spectrum before the jitter's shift */
    struct sim_response_slot *cache;
    int cache_cap, cache_len;
    unsigned long cache_clock;
    unsigned long responses_computed;
};

struct sim_response_slot {
    double y_ref;
    unsigned parts;
    unsigned long last_used;
    double complex *spectrum; /* nfft/2 + 1 bins */
};

/* FFT grid (engine.c) */
double sim_omega_k(const struct sim_engine *e, int k);
double complex sim_frac_derivative(double w, double a);

/* Rays between antennas and scatterers (paths.c) */
double sim_pattern(const struct sim_engine *e, double cos_theta);
double sim_window_transmission(const struct sim_scene *s, double n_oil);
double sim_window_delay(const struct sim_engine *e, double gap, double cz);
double sim_window_apparent(const struct sim_engine *e, double gap);
double sim_barrier_leg(const struct sim_engine *e, const double a[3], const double p[3], double r,
                       double *tau);
double sim_gap_lit(const struct sim_engine *e, const struct sim_element *el, const double a[3]);

/* Wedge diffraction (fringe.c) */
double sim_fringe(double phi, double phip, double n, int soft);
double sim_wedge_angle(const struct sim_edge *ed, const double u[3]);

/* Returns that are the same at every position (statics.c) */
void sim_build_statics(struct sim_engine *e, const double complex *F);

/* The surface and edge integrals of one position into e->acc, e->acc_edge (integrate.c) */
void sim_deposit(const struct sim_engine *e, double *acc, double tau, double amp);
void sim_integrate_surfaces(struct sim_engine *e, double y_ref, unsigned parts);

#endif
