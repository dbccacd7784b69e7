/* Inner loops of the fixed-point migration: portable C, SSE2, NEON. */
#include "migrate_kernel.h"

#include <math.h>
#include <string.h>

#if defined(__SSE2__)
#include <emmintrin.h>
#define MIGRATE_SSE2 1
#elif defined(__ARM_NEON) && defined(__aarch64__) && defined(__BYTE_ORDER__) && \
    __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
/* vpaddq_s32 and vmull_high_s16 are AArch64; the pair word's halves are
 * (-a, b) in lane order only on little-endian. */
#include <arm_neon.h>
#define MIGRATE_NEON 1
#endif

static int16_t to_q15(float x, float scale)
{
    long q = lrintf(x * scale);
    return (int16_t)(q > 32767 ? 32767 : q < -32767 ? -32767 : q);
}

void uwb_migrate_fill_pairs(const float *trace, int samples, float scale, int16_t *pairs)
{
    int16_t here = samples > 0 ? to_q15(trace[0], scale) : 0;
    for (int s = 0; s < samples; s++) {
        int16_t next = s + 1 < samples ? to_q15(trace[s + 1], scale) : 0;
        pairs[2 * (size_t)s] = (int16_t)-here;
        pairs[2 * s + 1] = next;
        here = next;
    }
    pairs[2 * (size_t)samples] = 0;
    pairs[2 * samples + 1] = 0;
}

/* (-a) * (w - 32768) + b * w == a * 32768 + (b - a) * w, and a * 32768 is a
 * whole multiple of the divisor, so this is the same integer the SIMD loops
 * get. |b - a| <= 65534 and w <= 32767 keep the product inside int32. The
 * right shift of a negative value is arithmetic on gcc and clang. */
void uwb_migrate_row_fixed_portable(const int32_t *restrict index, const int16_t *restrict weight,
                                    const int16_t *restrict pairs, int32_t *restrict out, int n)
{
    for (int i = 0; i < n; i++) {
        const int16_t *p = pairs + 2 * (size_t)index[i];
        int32_t minus_a = p[0], b = p[1];
        out[i] += ((((b + minus_a) * weight[i]) + 16384) >> 15) - minus_a;
    }
}

#if defined(MIGRATE_SSE2) || defined(MIGRATE_NEON)
/* Sample and neighbour as one 32-bit word (memcpy: no aliasing games). */
static inline int32_t pair_word(const int16_t *pairs, int32_t s)
{
    int32_t word;
    memcpy(&word, pairs + 2 * (size_t)s, sizeof word);
    return word;
}
#endif

#if defined(MIGRATE_SSE2)
/* Eight pixels a step: gather eight pair words, interleave the weights as
 * (w - 32768, w) — w with its sign bit flipped is w - 32768 — and let
 * pmaddwd form -a * (w - 32768) + b * w. Its one overflow, -32768 * -32768
 * twice, cannot happen: samples stop at -32767. */
static inline __m128i gather4(const int16_t *pairs, const int32_t *index)
{
    __m128i p0 = _mm_cvtsi32_si128(pair_word(pairs, index[0]));
    __m128i p1 = _mm_cvtsi32_si128(pair_word(pairs, index[1]));
    __m128i p2 = _mm_cvtsi32_si128(pair_word(pairs, index[2]));
    __m128i p3 = _mm_cvtsi32_si128(pair_word(pairs, index[3]));
    return _mm_unpacklo_epi64(_mm_unpacklo_epi32(p0, p1), _mm_unpacklo_epi32(p2, p3));
}

void uwb_migrate_row_fixed_simd(const int32_t *restrict index, const int16_t *restrict weight,
                                const int16_t *restrict pairs, int32_t *restrict out, int n)
{
    const __m128i half = _mm_set1_epi32(16384);
    const __m128i sign = _mm_set1_epi16(INT16_MIN);
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        __m128i lo = gather4(pairs, index + i), hi = gather4(pairs, index + i + 4);
        __m128i w = _mm_loadu_si128((const __m128i *)(weight + i));
        __m128i w_minus_one = _mm_xor_si128(w, sign);
        __m128i sum_lo = _mm_madd_epi16(lo, _mm_unpacklo_epi16(w_minus_one, w));
        __m128i sum_hi = _mm_madd_epi16(hi, _mm_unpackhi_epi16(w_minus_one, w));
        sum_lo = _mm_srai_epi32(_mm_add_epi32(sum_lo, half), 15);
        sum_hi = _mm_srai_epi32(_mm_add_epi32(sum_hi, half), 15);
        __m128i *o = (__m128i *)(out + i);
        _mm_storeu_si128(o, _mm_add_epi32(_mm_loadu_si128(o), sum_lo));
        _mm_storeu_si128(o + 1, _mm_add_epi32(_mm_loadu_si128(o + 1), sum_hi));
    }
    uwb_migrate_row_fixed_portable(index + i, weight + i, pairs, out + i, n - i);
}

const char *uwb_migrate_simd_name(void)
{
    return "SSE2";
}

#elif defined(MIGRATE_NEON)
/* Eight pixels a step: gather eight pair words, interleave the weights as
 * (w - 32768, w), widen-multiply and add neighbouring products pairwise;
 * the rounding shift is (x + 16384) >> 15 without intermediate overflow. */
static inline int16x8_t gather4(const int16_t *pairs, const int32_t *index)
{
    int32x4_t v = vdupq_n_s32(0);
    v = vsetq_lane_s32(pair_word(pairs, index[0]), v, 0);
    v = vsetq_lane_s32(pair_word(pairs, index[1]), v, 1);
    v = vsetq_lane_s32(pair_word(pairs, index[2]), v, 2);
    v = vsetq_lane_s32(pair_word(pairs, index[3]), v, 3);
    return vreinterpretq_s16_s32(v);
}

static inline int32x4_t interpolate4(int16x8_t samples, int16x8_t weights)
{
    int32x4_t first = vmull_s16(vget_low_s16(samples), vget_low_s16(weights));
    int32x4_t second = vmull_high_s16(samples, weights);
    return vrshrq_n_s32(vpaddq_s32(first, second), 15);
}

void uwb_migrate_row_fixed_simd(const int32_t *restrict index, const int16_t *restrict weight,
                                const int16_t *restrict pairs, int32_t *restrict out, int n)
{
    const int16x8_t sign = vdupq_n_s16(INT16_MIN);
    int i = 0;
    for (; i + 8 <= n; i += 8) {
        int16x8_t w = vld1q_s16(weight + i);
        int16x8x2_t wz = vzipq_s16(veorq_s16(w, sign), w);
        int32x4_t lo = interpolate4(gather4(pairs, index + i), wz.val[0]);
        int32x4_t hi = interpolate4(gather4(pairs, index + i + 4), wz.val[1]);
        vst1q_s32(out + i, vaddq_s32(vld1q_s32(out + i), lo));
        vst1q_s32(out + i + 4, vaddq_s32(vld1q_s32(out + i + 4), hi));
    }
    uwb_migrate_row_fixed_portable(index + i, weight + i, pairs, out + i, n - i);
}

const char *uwb_migrate_simd_name(void)
{
    return "NEON";
}

#else
void uwb_migrate_row_fixed_simd(const int32_t *restrict index, const int16_t *restrict weight,
                                const int16_t *restrict pairs, int32_t *restrict out, int n)
{
    uwb_migrate_row_fixed_portable(index, weight, pairs, out, n);
}

const char *uwb_migrate_simd_name(void)
{
    return "none";
}
#endif
