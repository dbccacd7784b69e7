/* The fixed-point migration's inner loop (private to src/imaging): a
 * portable C loop and, where the target has them, SIMD intrinsics (SSE2 on
 * x86-64, NEON on aarch64). Both compute the same integers, so the images
 * are bit-identical whichever runs. */
#ifndef UWB_MIGRATE_KERNEL_H
#define UWB_MIGRATE_KERNEL_H

#include <stdint.h>

/* A trace as the kernels read it: pairs[2s] = -q[s], pairs[2s + 1] = q[s + 1]
 * for s = 0 .. samples, with q the int16 samples and q[samples] =
 * q[samples + 1] = 0 (the pad that out-of-record delays point at). Sample
 * and its neighbour sit in one 32-bit word, so SIMD gathers one word per
 * pixel and multiplies both by their weights (-a * (w - 32768) + b * w) in
 * one multiply-add. Samples never reach -32768, so -q[s] fits int16. */
void uwb_migrate_fill_pairs(const float *trace, int samples, float scale, int16_t *pairs);

/* out[i] += round(q[s] + (q[s+1] - q[s]) * w / 32768) with s = index[i],
 * w = weight[i] in [0, 32767], for i < n. The rounding is floor(x + 1/2),
 * as (x * 32768 + 16384) >> 15. */
void uwb_migrate_row_fixed_portable(const int32_t *restrict index, const int16_t *restrict weight,
                                    const int16_t *restrict pairs, int32_t *restrict out, int n);
/* The same with SIMD; the portable loop where the target has none. */
void uwb_migrate_row_fixed_simd(const int32_t *restrict index, const int16_t *restrict weight,
                                const int16_t *restrict pairs, int32_t *restrict out, int n);
/* "SSE2", "NEON" or "none". */
const char *uwb_migrate_simd_name(void);

#endif
