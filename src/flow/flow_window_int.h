/* flow_window_int.h: bit masks over a cell's 3x3 window, shared by src/flow/flow.c and
 * src/flow/flow_fill.c.  Not public.
 *
 * Bit s = 3 (dy + 1) + (dx + 1); bit 4 is the cell itself:
 *
 *     bit:  0 1 2      offset  -w-1  -w  -w+1
 *           3 4 5                -1   0    +1
 *           6 7 8              +w-1  +w  +w+1
 *
 * Each mask is found for a whole row of three at once (SSE2 compares and a
 * move mask), without a branch per neighbour: on a noisy DEM such tests
 * are coin flips.  The cell i must not be on the grid edge.  Rows are read
 * 4 wide: the row above and the cell's row from x - 1 (to x + 2: still in
 * the buffer, the next row follows), the row below from x - 2 (so never
 * past the end of the grid). */
#ifndef TD_WINDOW3_H
#define TD_WINDOW3_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

static inline uint32_t w3_load4(const uint8_t *v)
{
    uint32_t u;
    memcpy(&u, v, sizeof u);
    return u;
}

/* Bits 0-2, 4-6, 8-10 of a lane mask (rows 0, 1, 2) -> bits 0-8. */
static inline unsigned w3_pick9(unsigned m)
{
    return (m & 7u) | (m >> 1 & 0x38u) | (m >> 2 & 0x1C0u);
}

#ifdef __SSSE3__
#include <tmmintrin.h>
/* Byte lanes 0-2, 4-6, 8-10 -> lanes 0-8 (one shuffle instead of
 * w3_pick9 on the mask). */
static inline __m128i w3_pack(__m128i v)
{
    return _mm_shuffle_epi8(v, _mm_set_epi8(-1, -1, -1, -1, -1, -1, -1, 10,
                                            9, 8, 6, 5, 4, 2, 1, 0));
}
#define W3_MASK(v) ((unsigned)_mm_movemask_epi8(w3_pack(v)))
#elif defined(__SSE2__)
#define W3_MASK(v) w3_pick9((unsigned)_mm_movemask_epi8(v))
#endif

#ifdef __SSE2__
/* The window's bytes as 3 rows of 4 lanes (the last lane unused). */
static inline __m128i w3_bytes(const uint8_t *b, size_t i, size_t w)
{
    return _mm_set_epi32(0, (int)(w3_load4(b + i + w - 2) >> 8),
                         (int)w3_load4(b + i - 1),
                         (int)w3_load4(b + i - w - 1));
}
#endif

/* Bytes with (b & mask) == val. */
static inline unsigned w3_eq8(const uint8_t *b, size_t i, size_t w,
                              uint8_t mask, uint8_t val)
{
#ifdef __SSE2__
    __m128i f = _mm_and_si128(w3_bytes(b, i, w), _mm_set1_epi8((char)mask));
    return W3_MASK(_mm_cmpeq_epi8(f, _mm_set1_epi8((char)val)));
#else
    unsigned m = 0, s;
    for (s = 0; s < 9; s++)
        m |= (unsigned)((b[i + (s / 3) * w + s % 3 - w - 1] & mask) == val)
             << s;
    return m;
#endif
}

/* Bytes <= val (unsigned). */
static inline unsigned w3_le8(const uint8_t *b, size_t i, size_t w,
                              uint8_t val)
{
#ifdef __SSE2__
    __m128i v = w3_bytes(b, i, w);
    return W3_MASK(_mm_cmpeq_epi8(_mm_min_epu8(v, _mm_set1_epi8((char)val)),
                                  v));
#else
    unsigned m = 0, s;
    for (s = 0; s < 9; s++)
        m |= (unsigned)(b[i + (s / 3) * w + s % 3 - w - 1] <= val) << s;
    return m;
#endif
}

/* 16-bit values other than l. */
static inline unsigned w3_ne16(const uint16_t *v, size_t i, size_t w,
                               uint16_t l)
{
#ifdef __SSE2__
    __m128i a, b, L = _mm_set1_epi16((short)l);
    uint64_t r0, r1, r2;
    memcpy(&r0, v + i - w - 1, sizeof r0);
    memcpy(&r1, v + i - 1, sizeof r1);
    memcpy(&r2, v + i + w - 2, sizeof r2);
    a = _mm_set_epi64x((long long)r1, (long long)r0);
    b = _mm_set_epi64x(0, (long long)(r2 >> 16));
    return ~W3_MASK(_mm_packs_epi16(_mm_cmpeq_epi16(a, L),
                                    _mm_cmpeq_epi16(b, L))) & 0x1FFu;
#else
    unsigned m = 0, s;
    for (s = 0; s < 9; s++)
        m |= (unsigned)(v[i + (s / 3) * w + s % 3 - w - 1] != l) << s;
    return m;
#endif
}

enum { W3_LT, W3_LE, W3_EQ };

/* Heights below (W3_LT), not above (W3_LE) or equal to (W3_EQ) zi. */
static inline unsigned w3_z(const float *z, size_t i, size_t w, float zi,
                            int rel)
{
#ifdef __SSE2__
    __m128 v = _mm_set1_ps(zi), r0 = _mm_loadu_ps(z + i - w - 1),
           r1 = _mm_loadu_ps(z + i - 1), r2 = _mm_loadu_ps(z + i + w - 2);
    unsigned a, b, c;
    if (rel == W3_LT) {
        r0 = _mm_cmplt_ps(r0, v), r1 = _mm_cmplt_ps(r1, v);
        r2 = _mm_cmplt_ps(r2, v);
    } else if (rel == W3_LE) {
        r0 = _mm_cmple_ps(r0, v), r1 = _mm_cmple_ps(r1, v);
        r2 = _mm_cmple_ps(r2, v);
    } else {
        r0 = _mm_cmpeq_ps(r0, v), r1 = _mm_cmpeq_ps(r1, v);
        r2 = _mm_cmpeq_ps(r2, v);
    }
    a = (unsigned)_mm_movemask_ps(r0);
    b = (unsigned)_mm_movemask_ps(r1);
    c = (unsigned)_mm_movemask_ps(r2);
    return (a & 7u) | (b & 7u) << 3 | (c >> 1 & 7u) << 6;
#else
    unsigned m = 0, s;
    for (s = 0; s < 9; s++) {
        float v = z[i + (s / 3) * w + s % 3 - w - 1];
        m |= (unsigned)(rel == W3_LT ? v < zi : rel == W3_LE ? v <= zi
                                                              : v == zi)
             << s;
    }
    return m;
#endif
}

#endif
