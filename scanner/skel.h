/* skel.h: 3x3 neighbourhood facts about a skeleton pixel, shared by spur
 * removal and tracing (scanner-private).
 *
 *      3 2 1        direction k = 0..7 counter-clockwise from the east,
 *      4 p 0        dx = TD_DX[k], dy = TD_DY[k] (y grows downwards)
 *      5 6 7
 */
#ifndef TD_SKEL_H
#define TD_SKEL_H

#include "src/core/core.h"

#include <string.h>

#ifndef M_SQRT2
#define M_SQRT2 1.41421356237309504880
#endif

static const int TD_DX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
static const int TD_DY[8] = {0, -1, -1, -1, 0, 1, 1, 1};

/* Bit k set when the neighbour in direction k is nonzero (outside = 0).
 * Only bit 0 of each cell is looked at, so callers may keep flags in the
 * upper bits. */
static inline unsigned td_skel_nbits(const td_grid_u8 *g, int x, int y)
{
    unsigned bits = 0;
    int k;
    if (x > 0 && y > 0 && x + 1 < g->w && y + 1 < g->h) {
        const uint8_t *a = g->data + (size_t)(y - 1) * g->stride + x;
        const uint8_t *b = a + g->stride, *c = b + g->stride;
        return (b[1] & 1u) | (a[1] & 1u) << 1 | (a[0] & 1u) << 2 |
               (a[-1] & 1u) << 3 | (b[-1] & 1u) << 4 | (c[-1] & 1u) << 5 |
               (c[0] & 1u) << 6 | (c[1] & 1u) << 7;
    }
    for (k = 0; k < 8; k++) {
        int nx = x + TD_DX[k], ny = y + TD_DY[k];
        if (nx >= 0 && ny >= 0 && nx < g->w && ny < g->h &&
            (TD_AT(g, nx, ny) & 1))
            bits |= 1u << k;
    }
    return bits;
}

/* Number of paper->ink transitions going once around the 8 neighbours: 1 at
 * an end point, 2 inside a line, >= 3 at a junction (branches). */
static inline int td_skel_crossings(unsigned bits)
{
    int k, n = 0;
    for (k = 0; k < 8; k++)
        if (!((bits >> k) & 1) && ((bits >> ((k + 1) & 7)) & 1))
            n++;
    return n;
}

/* The first x' >= x with r[x'] != 0, or w; skips paper 8 bytes at a time. */
static inline int td_skel_next_ink(const uint8_t *r, int x, int w)
{
    while (x < w) {
        if ((x & 7) == 0 && x + 8 <= w) {
            uint64_t v;
            memcpy(&v, r + x, 8);
            if (v == 0) {
                x += 8;
                continue;
            }
        }
        if (r[x])
            return x;
        x++;
    }
    return w;
}

static inline int td_skel_count(unsigned bits)
{
    return __builtin_popcount(bits);
}

#endif
