/* flow.c: rain-flow pass counts (paper 000 §3.1; ALGORITHMS.md C2) and the
 * linear-time D8 / D-infinity improvement over a priority-flood filled DEM.
 *
 * Neighbour codes k (dx, dy with y downwards, row 0 at the top):
 *
 *        5 NW   6 N   7 NE          off[k] = dy * w + dx
 *        4 W     c    0 E           opposite(k) = (k + 4) & 7
 *        3 SW   2 S   1 SE          odd k: diagonal, distance sqrt 2
 *
 * One byte per cell (`code`) carries everything but the heights: low
 * nibble = direction 0..7, ROOT (no receiver: the water leaves the grid),
 * NODATA, DONE, STOP (Sobel: the drop stays), UNSEEN while flooding; high
 * nibble = number of upstream neighbours still to be added (0..8). */
#include "src/flow/flow.h"
#include "src/flow/flow_int.h"
#include "src/flow/flow_window_int.h"

#include <math.h>
#include <omp.h>
#if defined(__AVX2__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

enum { ROOT = TD_FL_ROOT, NODATA = TD_FL_NODATA, DONE = 10, STOP = 11,
       UNSEEN = 0xFF };

static const int DX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
static const int DY[8] = {0, 1, 1, 1, 0, -1, -1, -1};
#define INV_SQRT2 0.70710678118654752440
#define PI_4 0.78539816339744830962

typedef struct u32vec {
    uint32_t *v;
    size_t n, cap;
} u32vec;

/* What every method works on: sizes, the heights being routed (the raw DEM
 * for Sobel, the filled DEM for D8/D-inf), the code bytes. */
typedef struct fgrid {
    int w, h;
    size_t n;
    const float *dem;  /* input heights */
    float *z;          /* heights routed on (filled), later D8 counts */
    uint8_t *code;
    ptrdiff_t off[8];
    td_ctx *cx;
} fgrid;

static int u32_push(u32vec *a, uint32_t x, td_ctx *cx)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? a->cap * 2 : 4096;
        uint32_t *v = realloc(a->v, cap * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "flow: out of memory");
        a->v = v;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return 0;
}

/* The k-th neighbour of cell i = (x, y) into *j; 0 when off the grid. */
static int nbr(const fgrid *g, size_t i, int k, size_t *j)
{
    int x = (int)(i % (size_t)g->w) + DX[k], y = (int)(i / (size_t)g->w) + DY[k];
    if (x < 0 || y < 0 || x >= g->w || y >= g->h)
        return 0;
    *j = i + (size_t)g->off[k];
    return 1;
}

/* As nbrs for a cell known to be off the grid edge (every valid cell that
 * is not a flood seed, i.e. not ROOT): all 8 on the grid, no division. */
static unsigned nbrs_in(const fgrid *g, size_t i, size_t j[8])
{
    int k;
    for (k = 0; k < 8; k++)
        j[k] = i + (size_t)g->off[k];
    return 0xFFu;
}

static int is_valid(const fgrid *g, size_t i)
{
    return (g->code[i] & 15) != NODATA;
}

/* Shared set-up: sizes, offsets, code = NODATA or `fill` per cell. */
static int fgrid_init(fgrid *g, const td_grid_f32 *dem, td_grid_f32 *out,
                      uint8_t fill, double *valid, td_ctx *cx)
{
    size_t nv = 0;
    int hn = dem && dem->has_nodata != 0;
    float nodata = dem ? dem->nodata : 0;
    ptrdiff_t i;
    int k;
    memset(g, 0, sizeof *g);
    if (!dem || !out || !dem->data || !out->data)
        return td_seterr(cx, TD_EINVAL, "flow: no grid given");
    if (td_check_dims(dem->w, dem->h, "flow: DEM", cx) != 0)
        return TD_EINVAL;
    if (out->w != dem->w || out->h != dem->h ||
        dem->stride != (size_t)dem->w || out->stride != (size_t)out->w)
        return td_seterr(cx, TD_EINVAL, "flow: output %dx%d does not match "
                         "the DEM %dx%d (or strides differ from widths)",
                         out->w, out->h, dem->w, dem->h);
    g->w = dem->w;
    g->h = dem->h;
    g->n = (size_t)dem->w * (size_t)dem->h;
    g->dem = dem->data;
    g->z = out->data;
    g->cx = cx;
    for (k = 0; k < 8; k++)
        g->off[k] = (ptrdiff_t)DY[k] * g->w + DX[k];
    if (!(g->code = td_malloc(g->n, cx)))
        return TD_ENOMEM;
#pragma omp parallel for schedule(static) reduction(+ : nv)
    for (i = 0; i < (ptrdiff_t)g->n; i++) { /* no branch: vectorised */
        float v = dem->data[i];
        int nd = (v != v) | (hn & (v == nodata));
        g->code[i] = nd ? NODATA : fill;
        nv += (size_t)!nd;
    }
    *valid = (double)nv;
    out->nodata = dem->nodata;
    out->has_nodata = dem->has_nodata;
    return 0;
}

/* ---- filling and directions -------------------------------------------
 * src/flow/flow_fill.c fills the DEM (tiled priority flood) and marks the outlets.
 * Then every other cell drains by steepest descent (drop / distance, the
 * first of equals in k order) to a strictly lower neighbour on the filled
 * DEM; a cell with none is on a flat (a filled pit or a real flat) and
 * drains breadth-first towards the flat's exits: the cells of the same
 * height that are outlets or have a lower neighbour, all exits together.
 * Every edge goes strictly down or one step nearer an exit along a flat,
 * so the graph has no cycles. */
/* Steepest descent of the n cells from zc on (not on the grid edge): into
 * best[] the slot k of the steepest strictly lower neighbour (the first of
 * equals), or -1.  One pass per neighbour over a block of STEEP_BLOCK
 * cells (the scratch stays in L1), without a branch: intrinsics with
 * AVX2 (four doubles at a time) or SSE2 (two), since compilers turn the
 * plain C selects into masked stores behind a branch that noisy terrain
 * mispredicts half the time. */
#define STEEP_BLOCK 512

static void steepest_row(const fgrid *g, const float *restrict zc, int n,
                         double *restrict bs, double *restrict best)
{
    int x = 0, k;
    for (x = 0; x < n; x++) {
        bs[x] = 0;
        best[x] = -1;
    }
    for (k = 0; k < 8; k++) {
        const float *restrict zn = zc + g->off[k];
        double f = (k & 1) ? INV_SQRT2 : 1.0, kd = k;
        x = 0;
#if defined(__AVX2__)
        {
            __m256d vf = _mm256_set1_pd(f), vk = _mm256_set1_pd(kd);
            for (; x + 4 <= n; x += 4) {
                __m256d a = _mm256_cvtps_pd(_mm_loadu_ps(zc + x)),
                        b = _mm256_cvtps_pd(_mm_loadu_ps(zn + x)),
                        d = _mm256_mul_pd(_mm256_sub_pd(a, b), vf),
                        o = _mm256_loadu_pd(bs + x),
                        m = _mm256_cmp_pd(d, o, _CMP_GT_OQ);
                _mm256_storeu_pd(bs + x, _mm256_blendv_pd(o, d, m));
                _mm256_storeu_pd(best + x, _mm256_blendv_pd(
                                     _mm256_loadu_pd(best + x), vk, m));
            }
        }
#elif defined(__SSE2__)
        {
            __m128d vf = _mm_set1_pd(f), vk = _mm_set1_pd(kd);
            for (; x + 2 <= n; x += 2) {
                __m128d a = _mm_cvtps_pd(_mm_castsi128_ps(
                            _mm_loadl_epi64((const __m128i *)(zc + x)))),
                        b = _mm_cvtps_pd(_mm_castsi128_ps(
                            _mm_loadl_epi64((const __m128i *)(zn + x)))),
                        d = _mm_mul_pd(_mm_sub_pd(a, b), vf),
                        o = _mm_loadu_pd(bs + x),
                        m = _mm_cmpgt_pd(d, o);
                _mm_storeu_pd(bs + x, _mm_or_pd(_mm_and_pd(m, d),
                                                _mm_andnot_pd(m, o)));
                _mm_storeu_pd(best + x, _mm_or_pd(
                    _mm_and_pd(m, vk), _mm_andnot_pd(m,
                                                     _mm_loadu_pd(best + x))));
            }
        }
#endif
        for (; x < n; x++) {
            double d = ((double)zc[x] - (double)zn[x]) * f;
            if (d > bs[x]) {
                bs[x] = d;
                best[x] = kd;
            }
        }
    }
}

/* Every valid cell that is not an outlet (all its neighbours are valid
 * and on the grid) gets its steepest descent, or UNSEEN (a flat); returns
 * the number of flat cells, or -1 out of memory.  rows (may be NULL):
 * the flat cells of each row. */
static double steepest(fgrid *g, int nth, uint32_t *rows)
{
    double flat = 0;
    int y, fail = 0;
#pragma omp parallel num_threads(nth) reduction(+ : flat)
    {
        double *bs = malloc(STEEP_BLOCK * sizeof *bs);
        double *best = malloc(STEEP_BLOCK * sizeof *best);
#pragma omp for schedule(dynamic, 16)
        for (y = 1; y < g->h - 1; y++) {
            uint8_t *code = g->code + (size_t)y * (size_t)g->w;
            const float *z = g->z + (size_t)y * (size_t)g->w;
            int x0, x, nb;
            size_t nf = 0;
            if (!bs || !best) {
                fail = 1;
                continue;
            }
            for (x0 = 1; x0 < g->w - 1; x0 += nb) {
                nb = g->w - 1 - x0 < STEEP_BLOCK ? g->w - 1 - x0
                                                 : STEEP_BLOCK;
                steepest_row(g, z + x0, nb, bs, best);
                for (x = 0; x < nb; x++) { /* selects, no branch */
                    uint8_t c = code[x0 + x];
                    int k = (int)best[x], open = c == 0;
                    code[x0 + x] = open ? (k < 0 ? UNSEEN : (uint8_t)k) : c;
                    nf += (size_t)(open & (k < 0));
                }
            }
            flat += (double)nf;
            if (rows)
                rows[y] = (uint32_t)nf;
        }
        free(bs);
        free(best);
    }
    return fail ? -1 : flat;
}

/* Window slot s (flow_window_int.h) -> neighbour code k, and back. */
static const int SLOT_K[9] = {5, 6, 7, 4, -1, 0, 3, 2, 1};

/* The neighbours of flat cell i (never on the grid edge) whose code is
 * `want`, or (want < 0) that are exits (outlets, cells with a direction)
 * of the same height, as a window mask.  Flat cells next to each other
 * have the same height (neither has a lower neighbour), so only exits
 * need the height test. */
static unsigned flat_nbrs(const fgrid *g, size_t i, int want)
{
    size_t w = (size_t)g->w;
    if (want >= 0)
        return w3_eq8(g->code, i, w, 0xFF, (uint8_t)want) & ~0x10u;
    return w3_le8(g->code, i, w, ROOT) &
           w3_z(g->z, i, w, g->z[i], W3_EQ) & ~0x10u;
}

enum { COMP = 0xFE, LATER = 0xFD, FIRST = 0x80 }; /* flat cell: in the
    flat being searched; in a flat left for later; first step chosen */

/* The flat neighbours of flat cell i not yet taken: UNSEEN, and (late)
 * LATER too (0xFD, 0xFF: both have the bits of 0xFD). */
static unsigned flat_open(const fgrid *g, size_t i, int late)
{
    uint8_t m = late ? LATER : UNSEEN;
    return w3_eq8(g->code, i, (size_t)g->w, m, m) & ~0x10u;
}

/* Offset of window slot s. */
static ptrdiff_t slot_off(const fgrid *g, unsigned s)
{
    return (ptrdiff_t)((int)s / 3 - 1) * g->w + (int)s % 3 - 1;
}

/* The first neighbour code k (E, SE, S, ... order) of a window mask. */
static int first_k(unsigned m)
{
    unsigned km = 0;
    for (; m; m &= m - 1)
        km |= 1u << SLOT_K[__builtin_ctz(m)];
    return __builtin_ctz(km);
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* One flat, from its cell i: gather it (connected cells of the same height
 * with no direction) into a, then search breadth-first from all its cells
 * next to an exit at once (each takes its first exit) into b.  Every cell
 * drains one step nearer an exit.  The flat must lie in cells [lo, hi)
 * (whole rows), else its cells there are marked LATER (-3).  Returns the
 * flat's cells, or -1 out of memory, -2 no exit, -3 not inside. */
static double flat_one(fgrid *g, size_t i, size_t lo, size_t hi, int late,
                       u32vec *a, u32vec *b)
{
    size_t h;
    unsigned m;
    int out = 0;
    a->n = b->n = 0;
    if (!flat_open(g, i, late)) { /* one cell (a filled pit, mostly) */
        m = flat_nbrs(g, i, -1);
        if (!m)
            return -2;
        g->code[i] = (uint8_t)first_k(m);
        return 1;
    }
    g->code[i] = COMP;
    if (u32_push(a, (uint32_t)i, NULL) != 0)
        return -1;
    for (h = 0; h < a->n; h++)
        for (m = flat_open(g, a->v[h], late); m; m &= m - 1) {
            size_t j = a->v[h] + (size_t)slot_off(g, __builtin_ctz(m));
            if (j < lo || j >= hi) { /* another band's: later, alone */
                out = 1;
                continue;
            }
            g->code[j] = COMP;
            if (u32_push(a, (uint32_t)j, NULL) != 0)
                return -1;
        }
    if (out) { /* all of it in [lo, hi) marked, so the scan skips it */
        for (h = 0; h < a->n; h++)
            g->code[a->v[h]] = LATER;
        return -3;
    }
    for (h = 0; h < a->n; h++)
        if ((m = flat_nbrs(g, a->v[h], -1)) != 0) {
            g->code[a->v[h]] = (uint8_t)(FIRST | first_k(m));
            if (u32_push(b, a->v[h], NULL) != 0)
                return -1;
        }
    for (h = 0; h < b->n; h++)
        g->code[b->v[h]] &= 7;
    /* seeds in raster order: the same search as one over the whole grid
     * (the flat drains to its nearest exit in short, evenly spread paths) */
    if (b->n > 16)
        qsort(b->v, b->n, sizeof *b->v, cmp_u32);
    else /* insertion sort: most flats are small */
        for (h = 1; h < b->n; h++) {
            uint32_t v = b->v[h];
            size_t j = h;
            for (; j > 0 && b->v[j - 1] > v; j--)
                b->v[j] = b->v[j - 1];
            b->v[j] = v;
        }
    for (h = 0; h < b->n; h++)
        for (m = flat_nbrs(g, b->v[h], COMP); m; m &= m - 1) {
            unsigned s = (unsigned)__builtin_ctz(m);
            size_t j = b->v[h] + (size_t)slot_off(g, s);
            g->code[j] = (uint8_t)((SLOT_K[s] + 4) & 7);
            if (u32_push(b, (uint32_t)j, NULL) != 0)
                return -1;
        }
    return b->n == a->n ? (double)a->n : -2;
}

/* The flats with a cell in [s0, s1) that lie in cells [lo, hi) (late:
 * any flat, its cells UNSEEN or LATER); adds their cells to *got.  0, or
 * -1 out of memory, -2 a flat with no exit. */
static int flats_in(fgrid *g, size_t lo, size_t hi, size_t s0, size_t s1,
                    int late, double *got)
{
    u32vec a = {NULL, 0, 0}, b = {NULL, 0, 0};
    size_t i;
    int rc = 0;
    for (i = s0; i < s1 && rc == 0; i++)
        if (g->code[i] == UNSEEN) {
            double r = flat_one(g, i, lo, hi, late, &a, &b);
            if (r > 0)
                *got += r;
            else if (r > -2.5) /* -1, -2; -3: not inside, left */
                rc = (int)r;
        }
    free(a.v);
    free(b.v);
    return rc;
}

/* Band t of nb: rows [yb[t], yb[t + 1]), each of them at least 2 rows,
 * with about the same number of flat cells (rows: per row, or NULL: the
 * same number of rows). */
static void flat_bands(const fgrid *g, const uint32_t *rows, double nflat,
                       int nb, int *yb)
{
    double cum = 0;
    int t, y = 0;
    yb[0] = 0;
    yb[nb] = g->h;
    for (t = 1; t < nb; t++) {
        int lo = yb[t - 1] + 2, hi = g->h - 2 * (nb - t);
        if (rows)
            for (; y < g->h && cum + rows[y] <= nflat * t / nb; y++)
                cum += rows[y];
        else
            y = (int)((long long)g->h * t / nb);
        yb[t] = y < lo ? lo : y > hi ? hi : y;
    }
}

/* Flats (nflat cells in all), one at a time: each is small and stays in
 * the cache (a breadth-first search over all flats at once sweeps the
 * whole grid at every step).  On threads: each takes a band of rows
 * (about the same number of flat cells in each: on the noisy bench
 * terrain an even split left one thread 0.08 s and the other 0.13 s) and
 * the flats inside it without its first and last row (so no thread reads
 * what another writes).  A flat it cannot finish reaches into one of
 * those rows (the search steps one row at a time), so the flats left
 * are found there after, on one thread, taking their LATER cells along.
 * The directions do not depend on the order.  0, TD_ENOMEM,
 * TD_EINTERNAL. */
static int flats(fgrid *g, double nflat, int nth, const uint32_t *rows)
{
    double got = 0;
    size_t w = (size_t)g->w;
    int t, bad = 0, nb = nth > 1 && g->h >= 16 * nth ? nth : 1;
    int yb[65];
    if (nflat == 0)
        return 0;
    nb = nb > 64 ? 64 : nb;
    if (nb == 1)
        bad = flats_in(g, 0, g->n, 0, g->n, 0, &got);
    else {
        flat_bands(g, rows, nflat, nb, yb);
#pragma omp parallel for num_threads(nb) reduction(+ : got) \
    reduction(min : bad)
        for (t = 0; t < nb; t++) {
            size_t y0 = (size_t)yb[t], y1 = (size_t)yb[t + 1];
            int r = flats_in(g, (y0 + 1) * w, (y1 - 1) * w, (y0 + 1) * w,
                             (y1 - 1) * w, 0, &got);
            bad = r < bad ? r : bad;
        }
        for (t = 0; t < nb && bad == 0; t++) { /* the rows left out */
            size_t y0 = (size_t)yb[t], y1 = (size_t)yb[t + 1];
            bad = flats_in(g, 0, g->n, y0 * w, (y0 + 1) * w, 1, &got);
            if (bad == 0)
                bad = flats_in(g, 0, g->n, (y1 - 1) * w, y1 * w, 1, &got);
        }
    }
    if (bad == -1)
        return td_seterr(g->cx, TD_ENOMEM, "flow: out of memory");
    if (bad == -2 || got != nflat)
        return td_seterr(g->cx, TD_EINTERNAL, "flow: a flat has no way out "
                         "after filling");
    return 0;
}

/* Fill, then a direction (or ROOT) for every valid cell; progress p0..p1. */
static int route(fgrid *g, const td_flow_params *p, double p0, double p1,
                 td_flow_stats *st)
{
    int nth = p->threads > 0 ? p->threads : omp_get_max_threads();
    int rc = td_flow_fill_tiles(g->dem, g->z, g->code, g->w, g->h, p->tile, nth,
                       &st->raised, p0, p0 + 0.8 * (p1 - p0), g->cx);
    if (rc == 0) {
        uint32_t *rows = calloc((size_t)g->h, sizeof *rows); /* NULL: fine */
        double nflat = steepest(g, nth, rows);
        rc = nflat < 0 ? td_seterr(g->cx, TD_ENOMEM, "flow: out of memory")
                       : flats(g, nflat, nth, rows);
        free(rows);
    }
    if (rc == 0)
        rc = td_progress(g->cx, "flow", p1);
    return rc;
}

int td_flow_fill(const td_grid_f32 *dem, td_grid_f32 *filled, int tile,
                 td_ctx *cx)
{
    fgrid g;
    double valid = 0.0;
    size_t i;
    int rc = fgrid_init(&g, dem, filled, 0, &valid, cx);
    if (rc == 0)
        rc = td_flow_fill_tiles(g.dem, g.z, g.code, g.w, g.h, tile, 0, NULL, 0.0, 1.0,
                       cx);
    if (rc == 0)
        for (i = 0; i < g.n; i++)
            if (g.code[i] == NODATA)
                g.z[i] = dem->nodata;
    free(g.code);
    return rc;
}

/* ---- D8 -----------------------------------------------------------------
 * Outlets (edge cells, cells next to nodata, ROOT): their water leaves the
 * grid.  Other cells: the direction from route() (steepest descent on the
 * filled DEM, or one step nearer a flat's exit).  Counts: src/flow/flow_d8.c.
 * D8 counts are uint32 stored in the float buffer g->z (after the filled
 * heights are no longer needed); memcpy keeps that free of aliasing. */
static uint32_t getu(const fgrid *g, size_t i)
{
    uint32_t v;
    memcpy(&v, &g->z[i], sizeof v);
    return v;
}

static void setu(fgrid *g, size_t i, uint32_t v)
{
    memcpy(&g->z[i], &v, sizeof v);
}

/* D8 counts (src/flow/flow_d8.c, in row bands on nth threads) into g->z as
 * uint32. */
static int d8_accumulate(fgrid *g, double valid, int nth, td_flow_stats *st)
{
    double done = 0;
    int rc = td_d8_accumulate(g->code, (uint32_t *)(void *)g->z, g->w, g->h,
                              nth, &st->outflow, &st->outlets, &done, g->cx);
    if (rc == 0 && done != valid)
        rc = td_seterr(g->cx, TD_EINTERNAL, "flow: D8 accumulated %.0f of "
                       "%.0f cells", done, valid);
    return rc;
}

/* ---- D-infinity (Tarboton 1997) -----------------------------------------
 * Eight triangular facets, each a cardinal neighbour e1 and the diagonal e2
 * next to it.  s1 = e0 - e1, s2 = e1 - e2 (unit spacing); direction
 * r = atan(s2 / s1) clamped to [0, pi/4] (slope s1 at 0, (e0 - e2)/sqrt 2 at
 * pi/4, else hypot(s1, s2)); the steepest facet's flow is split e1 : e2 =
 * (1 - r/(pi/4)) : r/(pi/4).  Every receiver with a share is strictly lower;
 * with no positive facet the D8 direction is used (flats as in D8). */
static const int FCARD[8] = {0, 2, 2, 4, 4, 6, 6, 0};
static const int FDIAG[8] = {1, 1, 3, 3, 5, 5, 7, 7};

/* Receivers of valid cell i into r[], shares into fr[]; returns 0..2. */
static int dinf_recv(const fgrid *g, size_t i, size_t r[2], double fr[2])
{
    double e0 = g->z[i], bs = 0, s1b = 0, s2b = 0;
    size_t nb[8], n1, n2, b1 = 0, b2 = 0;
    int j, k = g->code[i] & 15, nr = 0;
    unsigned m;
    if (k == ROOT)
        return 0;
    m = nbrs_in(g, i, nb); /* not ROOT: off the edge */
    for (j = 0; j < 8; j++) {
        double s1, s2, s;
        n1 = nb[FCARD[j]];
        n2 = nb[FDIAG[j]];
        if (!(m >> FCARD[j] & 1) || !is_valid(g, n1) ||
            !(m >> FDIAG[j] & 1) || !is_valid(g, n2))
            continue;
        s1 = e0 - g->z[n1];
        s2 = (double)g->z[n1] - g->z[n2];
        s = s2 <= 0 ? s1 : s2 >= s1 ? (s1 + s2) * INV_SQRT2 : hypot(s1, s2);
        if (s > bs) {
            bs = s;
            b1 = n1, b2 = n2, s1b = s1, s2b = s2;
        }
    }
    if (bs > 0) {
        double a = s2b <= 0 ? 0 : s2b >= s1b ? 1 : atan(s2b / s1b) / PI_4;
        if (a < 1)
            r[nr] = b1, fr[nr++] = 1 - a;
        if (a > 0)
            r[nr] = b2, fr[nr++] = a;
        return nr;
    }
    if (k < 8) {
        r[0] = i + (size_t)g->off[k];
        fr[0] = 1;
        return 1;
    }
    return 0;
}

/* Add cell c's count to its receivers; push those left with no upstream. */
static int dinf_step(fgrid *g, double *acc, size_t c, u32vec *todo,
                     td_flow_stats *st)
{
    size_t r[2];
    double fr[2];
    int m, nr = dinf_recv(g, c, r, fr), rc = 0;
    g->code[c] = DONE;
    if (nr == 0) {
        st->outflow += acc[c];
        st->outlets++;
    }
    for (m = 0; m < nr && rc == 0; m++) {
        acc[r[m]] += acc[c] * fr[m];
        g->code[r[m]] = (uint8_t)(g->code[r[m]] - 16);
        if ((g->code[r[m]] >> 4) == 0)
            rc = u32_push(todo, (uint32_t)r[m], g->cx);
    }
    return rc;
}

static int dinf_accumulate(fgrid *g, double *acc, double valid,
                           td_flow_stats *st)
{
    u32vec todo = {NULL, 0, 0};
    size_t i, r[2];
    double fr[2], done = 0;
    int m, nr, rc = 0;
    for (i = 0; i < g->n; i++) {
        acc[i] = is_valid(g, i) ? 1.0 : 0.0;
        nr = is_valid(g, i) ? dinf_recv(g, i, r, fr) : 0;
        for (m = 0; m < nr; m++)
            g->code[r[m]] += 16;
    }
    for (i = 0; i < g->n && rc == 0; i++) {
        uint8_t c = g->code[i];
        if ((c & 15) > ROOT || (c >> 4) != 0)
            continue;
        rc = u32_push(&todo, (uint32_t)i, g->cx);
        while (rc == 0 && todo.n > 0) {
            rc = dinf_step(g, acc, todo.v[--todo.n], &todo, st);
            done++;
        }
        if (rc == 0 && (i & 0xFFFFF) == 0)
            rc = td_progress(g->cx, "flow", 0.7 + 0.3 * (double)i / g->n);
    }
    free(todo.v);
    if (rc == 0 && done != valid)
        rc = td_seterr(g->cx, TD_EINTERNAL, "flow: D-inf accumulated %.0f "
                       "of %.0f cells", done, valid);
    return rc;
}

/* ---- the paper's method: Sobel-gradient drop tracing (000 §3.1) ---------
 * Sobel operator on the raw DEM (edge cells repeat the border; a nodata
 * cell in the window counts as the centre's height):
 *
 *   gx = | -1  0 +1 |      gy = | -1 -2 -1 |     (y downwards)
 *        | -2  0 +2 |           |  0  0  0 |
 *        | -1  0 +1 |           | +1 +2 +1 |
 *
 * Each drop moves to the neighbour nearest the direction of (-gx, -gy) when
 * that neighbour is lower; otherwise it stays (STOP).  Off the grid or onto
 * nodata it leaves (ROOT).  Every cell a drop is on counts one pass. */
static float zat(const fgrid *g, int x, int y, float zc)
{
    size_t i;
    x = x < 0 ? 0 : x >= g->w ? g->w - 1 : x;
    y = y < 0 ? 0 : y >= g->h ? g->h - 1 : y;
    i = (size_t)y * (size_t)g->w + (size_t)x;
    return is_valid(g, i) ? g->dem[i] : zc;
}

static uint8_t sobel_dir(const fgrid *g, size_t i)
{
    int x = (int)(i % (size_t)g->w), y = (int)(i / (size_t)g->w), k;
    float zc = g->dem[i];
    double gx, gy;
    size_t j;
    gx = (zat(g, x + 1, y - 1, zc) + 2.0 * zat(g, x + 1, y, zc) +
          zat(g, x + 1, y + 1, zc)) -
         (zat(g, x - 1, y - 1, zc) + 2.0 * zat(g, x - 1, y, zc) +
          zat(g, x - 1, y + 1, zc));
    gy = (zat(g, x - 1, y + 1, zc) + 2.0 * zat(g, x, y + 1, zc) +
          zat(g, x + 1, y + 1, zc)) -
         (zat(g, x - 1, y - 1, zc) + 2.0 * zat(g, x, y - 1, zc) +
          zat(g, x + 1, y - 1, zc));
    if (gx == 0 && gy == 0)
        return STOP;
    k = (int)lround(atan2(-gy, -gx) / PI_4);
    k = (k + 8) & 7;
    if (!nbr(g, i, k, &j) || !is_valid(g, j))
        return ROOT;
    return g->dem[j] < zc ? (uint8_t)k : STOP;
}

static int sobel_run(fgrid *g, long max_steps, td_flow_stats *st)
{
    size_t i;
    for (i = 0; i < g->n; i++) {
        if (is_valid(g, i))
            g->code[i] = sobel_dir(g, i);
        setu(g, i, 0);
    }
    for (i = 0; i < g->n; i++) {
        size_t c = i;
        long steps = 0;
        if (!is_valid(g, i))
            continue;
        for (;;) {
            int k = g->code[c];
            setu(g, c, getu(g, c) + 1);
            if (k == ROOT || k == STOP || steps == max_steps) {
                st->outflow += k == ROOT;
                st->pit_stops += k == STOP;
                st->capped += k < 8;
                break;
            }
            c += (size_t)g->off[k];
            steps++;
        }
        st->moves += (double)steps;
        if ((i & 0xFFFF) == 0 &&
            td_progress(g->cx, "flow", 0.05 + 0.95 * (double)i / g->n) != 0)
            return TD_ECANCEL;
    }
    for (i = 0; i < g->n; i++)
        st->outlets += g->code[i] == ROOT;
    return 0;
}

/* ---- driver -------------------------------------------------------------- */
td_flow_params td_flow_defaults(void)
{
    td_flow_params p;
    memset(&p, 0, sizeof p);
    p.method = TD_FLOW_SOBEL;
    p.max_steps = 0;
    return p;
}

/* Counts (uint32 in g->z, or acc) -> floats; nodata where there is none. */
static void store(fgrid *g, const double *acc, float nodata, int nth,
                  td_flow_stats *st)
{
    ptrdiff_t i, n = (ptrdiff_t)g->n;
    double mx = 0;
#pragma omp parallel for num_threads(nth) schedule(static) \
    reduction(max : mx)
    for (i = 0; i < n; i++) {
        double v = acc ? acc[i] : (double)getu(g, (size_t)i);
        if (!is_valid(g, (size_t)i)) {
            g->z[i] = nodata;
            continue;
        }
        g->z[i] = (float)v;
        mx = v > mx ? v : mx;
    }
    st->max_pass = mx;
}

int td_flow_run(const td_grid_f32 *dem, const td_flow_params *p,
                td_grid_f32 *passes, td_flow_stats *st, td_ctx *cx)
{
    fgrid g;
    td_flow_stats s;
    double *acc = NULL;
    int rc;
    memset(&s, 0, sizeof s);
    memset(&g, 0, sizeof g);
    if (!p || p->method < TD_FLOW_SOBEL || p->method > TD_FLOW_DINF ||
        p->max_steps < 0 || p->threads < 0 || p->threads > 1024 ||
        p->tile < 0) {
        rc = td_seterr(cx, TD_EINVAL, "flow: bad parameters");
        goto fail;
    }
    rc = fgrid_init(&g, dem, passes, 0,
                    &s.cells, cx);
    if (rc == 0)
        rc = td_progress(cx, "flow", 0.0);
    if (rc != 0)
        goto fail;
    if (p->method == TD_FLOW_SOBEL) {
        long ms = p->max_steps ? p->max_steps : 4L * (g.w + g.h);
        rc = sobel_run(&g, ms, &s);
    } else if ((rc = route(&g, p, 0.0, p->method == TD_FLOW_D8 ? 0.8
                                                  : 0.6, &s)) == 0) {
        if (p->method == TD_FLOW_D8)
            rc = d8_accumulate(&g, s.cells, p->threads > 0 ? p->threads
                               : omp_get_max_threads(), &s);
        else if ((acc = td_malloc(g.n * sizeof *acc, cx)) == NULL)
            rc = TD_ENOMEM;
        else
            rc = dinf_accumulate(&g, acc, s.cells, &s);
    }
    if (rc != 0)
        goto fail;
    store(&g, acc, dem->nodata, p->threads > 0 ? p->threads
                                          : omp_get_max_threads(), &s);
    rc = td_progress(cx, "flow", 1.0);
fail:
    if (st)
        *st = s;
    free(acc);
    free(g.code);
    return rc;
}

/* ---- classes by quantiles ------------------------------------------------ */

/* Rearrange a[0..n) so a[k] holds the k-th smallest (Hoare selection). */
static float select_k(float *a, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        float m = a[lo + (hi - lo) / 2], t;
        size_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < m)
                i++;
            while (a[j] > m)
                j--;
            if (i <= j) {
                t = a[i], a[i] = a[j], a[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return a[k];
}

int td_flow_classify(const td_grid_f32 *passes, double ridge_q,
                     double valley_q, td_grid_u8 *classes, td_ctx *cx)
{
    float *v = NULL, qr = 0, qv = 0;
    size_t i, n = 0, total;
    int rc = 0;
    if (!passes || !classes || !passes->data || !classes->data ||
        passes->w != classes->w || passes->h != classes->h ||
        passes->stride != (size_t)passes->w ||
        classes->stride != (size_t)classes->w)
        return td_seterr(cx, TD_EINVAL, "flow: class grid does not match");
    if (!(ridge_q >= 0 && ridge_q < valley_q && valley_q <= 1))
        return td_seterr(cx, TD_EINVAL, "flow: need 0 <= ridge quantile "
                         "(%g) < valley quantile (%g) <= 1", ridge_q,
                         valley_q);
    total = (size_t)passes->w * (size_t)passes->h;
#define ND(x) (isnan(x) || (passes->has_nodata && (x) == passes->nodata))
    if (!(v = td_malloc(total * sizeof *v, cx)))
        return TD_ENOMEM;
    for (i = 0; i < total; i++)
        if (!ND(passes->data[i]))
            v[n++] = passes->data[i];
    if (n > 0) {
        qr = select_k(v, n, (size_t)floor(ridge_q * (double)(n - 1)));
        qv = select_k(v, n, (size_t)floor(valley_q * (double)(n - 1)));
    }
    for (i = 0; i < total; i++) {
        float x = passes->data[i];
        classes->data[i] = ND(x) ? TD_FLOW_NODATA
                           : x <= qr ? TD_FLOW_RIDGE
                           : x >= qv ? TD_FLOW_VALLEY : TD_FLOW_SLOPE;
    }
#undef ND
    free(v);
    return rc;
}
