/* The physics of one antenna position: the surface integral (physical
 * optics / Kirchhoff) over every lit element, the fringe term of the
 * physical theory of diffraction along the stack's edges, folded with the
 * pulse through the propagation operator, plus the static returns (direct
 * coupling, window echoes, far wall). An engine is built once per scene
 * (geometry, FFTW plans, kernels) and then answers any number of positions.
 *
 * Model, per element of area dA at P, with Tx at distance R1 and Rx at R2
 * (unit directions k1 = (P-Tx)/R1, k2 = (P-Rx)/R2, outward normal n):
 *   lit and seen iff n.k1 < 0 and n.k2 < 0;
 *   obliquity  q = -(n.k1 + n.k2) / 2, near-field q' = -(n.k1/R1 + n.k2/R2) / 2;
 *   3-D:  u(t) += G g1 g2 dA / (2 pi v R1 R2) * (q d/dt + v q') f(t - tau)
 *   2-D:  u(t) += G g1 g2 dl / sqrt(2 pi v R1 R2) * q D^1/2 f(t - tau)
 * with G the surface's reflection coefficient (-1 for metal), g the antenna
 * patterns, tau = (R1 + R2)/v plus the window's and barrier's extra delay,
 * and f the incident field 1 m from Tx (3-D: f(t-R/v)/R; 2-D:
 * f(t-R/v)/sqrt(R)). These constants make a large flat plate return its
 * image: G f(t - L/v)/L in 3-D (exactly, with q'), G f(t - L/v)/sqrt(L) in
 * 2-D (to O(1/8kR)). Each edge piece dl adds (D_wedge - D_PO) f(t - tau) dl
 * / (2 pi R1 R2) in 3-D, (D_wedge - D_PO) sqrt(v / 2 pi) D^-1/2 f(t - tau)
 * / sqrt(R1 R2) in 2-D: Keller's exact wedge coefficient minus the one
 * physical optics already gives, so corners diffract as strongly as they do
 * in a full-wave solution. Elements are deposited into a fine time grid with
 * linear weights; one FFT per position applies the operators, the pulse, the
 * grid's own smoothing (undone) and the trigger jitter (a phase ramp). */
#ifndef UWBSIM_ENGINE_H
#define UWBSIM_ENGINE_H

#include <stddef.h>
#include <stdint.h>

#include "rng.h"
#include "scene.h"
#include "surfaces.h"

struct sim_engine;

int sim_engine_create(const struct sim_scene *scene, struct sim_engine **engine, char *err, size_t errlen);
void sim_engine_free(struct sim_engine *engine);

const struct sim_scene *sim_engine_scene(const struct sim_engine *engine);
size_t sim_engine_element_count(const struct sim_engine *engine);
/* Peak |winding echo| over the scene's positions, noiseless: the SNR's
 * reference (V). Computed on first use (one pass over the positions), then
 * kept; -1 if out of memory. */
double sim_engine_peak_echo(struct sim_engine *engine);

/* The noiseless received voltage at one position, `parts` (enum sim_part
 * mask) only, the whole trace delayed by shift_s (jitter). out: samples values.
 * Not thread-safe: an engine owns its FFT buffers. */
void sim_engine_clean_trace(struct sim_engine *engine, double antenna_y_m, unsigned parts, double shift_s,
                            double *out);

/* Keep up to `responses` positions' whole noiseless responses (SIM_PART_ALL; least recently
 * used dropped first), so a position acquired again, e.g. each pulse of a
 * stack, costs one inverse FFT instead of the surface integral. The traces
 * are the very numbers an engine without it gives. 0 turns it off (the
 * default: a pass over a scan visits each position once). -1 if out of
 * memory (the engine then keeps none). */
int sim_engine_cache_responses(struct sim_engine *engine, int responses);
/* How many responses the engine has integrated since it was created, and
 * how many it holds now. */
unsigned long sim_engine_responses_computed(const struct sim_engine *engine);
int sim_engine_responses_cached(const struct sim_engine *engine);

/* The digitiser's state carried from one acquisition to the next. */
struct sim_acq {
    struct sim_rng rng;
    double drift_db; /* current gain offset of the random walk */
};
void sim_acq_init(struct sim_acq *acq, uint64_t seed);

/* One recorded trace as the digitiser would give it: trigger jitter, gain
 * drift, then `stack` pulses (0: the scene's) each with fresh noise,
 * quantised and clipped, averaged. This is what the emulated board calls
 * for every acquisition. */
int sim_engine_acquire(struct sim_engine *engine, double antenna_y_m, int stack, struct sim_acq *acq,
                       float *out, char *err, size_t errlen);

#endif
