/* flow_d8.c: D8 flow accumulation in row bands, one thread per band.
 *
 * Every valid cell has one receiver (code k = 0..7, see flow.c) or is an
 * outlet (TD_FL_ROOT).  A cell's count is the number of cells whose path
 * passes it (its own included).  Linear: each cell's in-degree is counted
 * (pulled from its 8 neighbours, so every thread writes only its own
 * band), then chains run downstream from the cells with nothing upstream,
 * adding counts, until a cell still waits for another upstream cell.
 *
 * Bands: thread t owns rows [y0, y1).  A chain that steps into another
 * band stops and hands (receiver, count) to that band; after a barrier
 * each band takes what it was handed (adding it, and going on downstream
 * where that was the last upstream cell).  Rounds repeat until nothing is
 * handed on.  A path that crosses band borders m times needs m rounds;
 * each round is a barrier, so even a river along a border costs little.
 * No cell is written by two threads, no atomics; the counts are exact
 * integers, so the result is the same for any number of threads.
 *
 * Blocks: inside its band a thread runs chains a block of rows (about
 * 768 KB of codes, in-degrees and counts) at a time, so a long river's
 * chain stays in the cache; a chain that steps into another block leaves
 * its count there, and the blocks take those in sweeps down and up.  On
 * smooth hills (long chains) that halves the accumulation time. */
#include "src/flow/flow_int.h"
#include "src/flow/flow_window_int.h"

#include <omp.h>
#include <stdlib.h>
#include <string.h>

enum { ROOT = TD_FL_ROOT, NODATA = TD_FL_NODATA, DONE = 10 };

static const int DX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
static const int DY[8] = {0, 1, 1, 1, 0, -1, -1, -1};

/* A hand-over: receiver cell and count. */
typedef struct hand {
    uint32_t r, a;
} hand;

typedef struct hvec {
    hand *v;
    size_t n, cap;
} hvec;

/* One band's state.  out[p][d]: handed to the band above (d = 0) or
 * below (d = 1) in rounds of parity p.  The band runs its chains a block
 * of rows at a time (block k: cells [lo + k bs, lo + (k + 1) bs)), so the
 * block's codes, in-degrees and counts stay in the cache; a chain that
 * steps into another block of the band leaves its count in that block's
 * pend list. */
typedef struct band {
    int y0, y1;
    size_t lo, hi;       /* cells [lo, hi) */
    size_t bs, blo, bhi; /* cells per block; the block chains run in now */
    int nblk;
    hvec *pend;   /* per block */
    size_t npend; /* entries in all pend lists */
    hvec out[2][2];
    double outflow, outlets;
    size_t done;
    int fail;
    char pad[128]; /* no cache line shared with the next band's thread */
} band;

typedef struct acc8 {
    uint8_t *code, *cnt;
    uint32_t *acc;
    int w, h, nb;
    ptrdiff_t off[8];
    band *b;
} acc8;

static int hv_push(hvec *v, uint32_t r, uint32_t a)
{
    if (v->n == v->cap) {
        size_t cap = v->cap ? v->cap * 2 : 256;
        hand *p = realloc(v->v, cap * sizeof *p);
        if (!p)
            return -1;
        v->v = p;
        v->cap = cap;
    }
    v->v[v->n].r = r;
    v->v[v->n++].a = a;
    return 0;
}

/* In-degree of cell i = (x, y): neighbours whose code points at i. */
static unsigned indegree(const acc8 *s, size_t i, int x, int y)
{
    /* slot s (flow_window_int.h) holds the neighbour at (dx, dy); it points at i
     * when its code is the direction (-dx, -dy) */
    static const uint8_t TO_ME[16] = {1, 2, 3, 0, 0xFF, 4, 7, 6, 5,
                                      0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF,
                                      0xFF};
    unsigned m = 0, k;
    if (x > 0 && y > 0 && x < s->w - 1 && y < s->h - 1) {
#ifdef __SSE2__
        __m128i v = w3_bytes(s->code, i, (size_t)s->w);
        /* lanes are rows of 4 (slot 3 r + d -> lane 4 r + d) */
        __m128i want = _mm_set_epi8(-1, -1, -1, -1, -1, TO_ME[8],
                                    (char)TO_ME[7], (char)TO_ME[6], -1,
                                    (char)TO_ME[5], -1, (char)TO_ME[3], -1,
                                    (char)TO_ME[2], (char)TO_ME[1],
                                    (char)TO_ME[0]);
        m = W3_MASK(_mm_cmpeq_epi8(v, want));
        return (unsigned)__builtin_popcount(m);
#endif
    }
    for (k = 0; k < 9; k++) {
        int xx = x + (int)k % 3 - 1, yy = y + (int)k / 3 - 1;
        if (k == 4 || xx < 0 || yy < 0 || xx >= s->w || yy >= s->h)
            continue;
        m += s->code[(size_t)yy * (size_t)s->w + (size_t)xx] == TO_ME[k];
    }
    return m;
}

/* Count (1: own rain, 0: nodata) and in-degree of cell i = (x, y). */
static void init_cell(acc8 *s, size_t i, int x, int y)
{
    s->acc[i] = s->code[i] != NODATA;
    s->cnt[i] = s->code[i] == NODATA ? 0 : (uint8_t)indegree(s, i, x, y);
}

#ifdef __SSE2__
/* Cells [i, i + 16) of an interior row, none on the grid edge: each
 * neighbour direction k is one compare of the row shifted by off[k] (the
 * neighbour points back when its code is k + 4 mod 8). */
static void init_16(acc8 *s, size_t i)
{
    const __m128i z = _mm_setzero_si128();
    __m128i c = _mm_loadu_si128((const __m128i *)(s->code + i));
    __m128i nod = _mm_cmpeq_epi8(c, _mm_set1_epi8(NODATA));
    __m128i n = z, one = _mm_andnot_si128(nod, _mm_set1_epi8(1));
    __m128i lo, hi;
    int k;
    for (k = 0; k < 8; k++) {
        __m128i v = _mm_loadu_si128((const __m128i *)(s->code + i +
                                                      s->off[k]));
        n = _mm_sub_epi8(n, _mm_cmpeq_epi8(v, _mm_set1_epi8(
                                                  (char)((k + 4) & 7))));
    }
    _mm_storeu_si128((__m128i *)(s->cnt + i), _mm_andnot_si128(nod, n));
    lo = _mm_unpacklo_epi8(one, z);
    hi = _mm_unpackhi_epi8(one, z);
    _mm_storeu_si128((__m128i *)(s->acc + i), _mm_unpacklo_epi16(lo, z));
    _mm_storeu_si128((__m128i *)(s->acc + i + 4), _mm_unpackhi_epi16(lo, z));
    _mm_storeu_si128((__m128i *)(s->acc + i + 8), _mm_unpacklo_epi16(hi, z));
    _mm_storeu_si128((__m128i *)(s->acc + i + 12),
                     _mm_unpackhi_epi16(hi, z));
}
#endif

/* Counts and in-degrees of the band's cells. */
static void band_init(acc8 *s, band *b)
{
    int x, y;
    for (y = b->y0; y < b->y1; y++) {
        size_t i = (size_t)y * (size_t)s->w;
        x = 0;
#ifdef __SSE2__
        if (y > 0 && y < s->h - 1) {
            init_cell(s, i, 0, y);
            for (x = 1, i++; x + 16 < s->w; x += 16, i += 16)
                init_16(s, i);
        }
#endif
        for (; x < s->w; x++, i++)
            init_cell(s, i, x, y);
    }
}

/* Chain from cell c of band b downstream. */
static inline __attribute__((always_inline)) void
chain(acc8 *s, band *b, size_t c, int par)
{
    uint8_t *restrict code = s->code, *restrict cnt = s->cnt;
    uint32_t *restrict acc = s->acc;
    const ptrdiff_t *off = s->off;
    const size_t lo = b->blo, hi = b->bhi;
    uint32_t a = acc[c];
    size_t done = 0;
    for (;;) {
        int k = code[c];
        size_t r;
        code[c] = DONE;
        done++;
        if (k == ROOT) {
            b->outflow += a;
            b->outlets++;
            break;
        }
        r = c + (size_t)off[k];
        if (r < lo || r >= hi) { /* another block, or another band */
            int f;
            if (r < b->lo || r >= b->hi)
                f = hv_push(&b->out[par][r >= b->hi], (uint32_t)r, a);
            else {
                f = hv_push(&b->pend[(r - b->lo) / b->bs], (uint32_t)r, a);
                b->npend++;
            }
            b->fail |= f != 0;
            break;
        }
        a += acc[r];
        acc[r] = a;
        if (--cnt[r])
            break;
        c = r;
    }
    b->done += done;
}

/* Block k of band b is where chains run now. */
static void set_block(band *b, int k)
{
    b->blo = b->lo + (size_t)k * b->bs;
    b->bhi = b->blo + b->bs < b->hi ? b->blo + b->bs : b->hi;
}

/* The counts left in the pend lists, block by block (sweeping down, then
 * up, ... until none is left: a chain only leaves counts in other
 * blocks). */
static void band_pending(acc8 *s, band *b, int par)
{
    int down = 1;
    while (b->npend > 0 && !b->fail) {
        int i;
        for (i = 0; i < b->nblk; i++) {
            int k = down ? i : b->nblk - 1 - i;
            hvec *p = &b->pend[k];
            size_t j;
            if (p->n == 0)
                continue;
            set_block(b, k);
            for (j = 0; j < p->n; j++) { /* chains here add to others */
                size_t r = p->v[j].r;
                s->acc[r] += p->v[j].a;
                if (--s->cnt[r] == 0)
                    chain(s, b, r, par);
            }
            b->npend -= p->n;
            p->n = 0;
        }
        down = !down;
    }
}

/* Sources of the band (nothing upstream), a block at a time in raster
 * order, then what the chains left in other blocks.  A chain only enters
 * a cell it brings to 0, never a source, so a 16-cell mask taken before
 * that mask's chains run stays right. */
static void band_sources(acc8 *s, band *b)
{
    int k;
    for (k = 0; k < b->nblk; k++) {
        size_t i;
        set_block(b, k);
        i = b->blo;
#ifdef __SSE2__
        for (; i + 16 <= b->bhi; i += 16) {
            __m128i c = _mm_loadu_si128((const __m128i *)(s->code + i));
            __m128i n = _mm_loadu_si128((const __m128i *)(s->cnt + i));
            __m128i src = _mm_and_si128(
                _mm_cmpeq_epi8(n, _mm_setzero_si128()),
                _mm_cmpeq_epi8(_mm_min_epu8(c, _mm_set1_epi8(ROOT)), c));
            unsigned m = (unsigned)_mm_movemask_epi8(src);
            for (; m; m &= m - 1)
                chain(s, b, i + (size_t)__builtin_ctz(m), 0);
        }
#endif
        for (; i < b->bhi; i++)
            if (s->cnt[i] == 0 && s->code[i] <= ROOT)
                chain(s, b, i, 0);
    }
    band_pending(s, b, 0);
}

/* Take what the bands next to b handed over in round parity par (into
 * the pend lists, then on as above). */
static int band_take(acc8 *s, band *b, int t, int par)
{
    int d, got = 0;
    for (d = 0; d < 2; d++) {
        int u = d == 0 ? t - 1 : t + 1; /* the band above / below */
        hvec *in;
        size_t j;
        if (u < 0 || u >= s->nb)
            continue;
        in = &s->b[u].out[par][d == 0]; /* u handed down (1) / up (0) */
        for (j = 0; j < in->n && b->pend; j++) {
            size_t r = in->v[j].r;
            got = 1;
            b->fail |= hv_push(&b->pend[(r - b->lo) / b->bs], (uint32_t)r,
                               in->v[j].a) != 0;
            b->npend++;
        }
    }
    band_pending(s, b, !par);
    return got;
}

/* nb bands of rows, as even as can be, in blocks of rows of about
 * BLOCK_BYTES (6 bytes a cell). */
#define BLOCK_BYTES (768 * 1024)
static void set_bands(acc8 *s, int nb)
{
    int t, rows = (int)(BLOCK_BYTES / (6 * (size_t)s->w));
    rows = rows < 4 ? 4 : rows;
    s->nb = nb;
    for (t = 0; t < nb; t++) {
        band *b = &s->b[t];
        b->y0 = (int)((long long)s->h * t / nb);
        b->y1 = (int)((long long)s->h * (t + 1) / nb);
        b->lo = (size_t)b->y0 * (size_t)s->w;
        b->hi = (size_t)b->y1 * (size_t)s->w;
        b->bs = (size_t)rows * (size_t)s->w;
        b->nblk = (b->y1 - b->y0 + rows - 1) / rows;
        b->pend = calloc((size_t)b->nblk + 1, sizeof *b->pend);
        if (!b->pend) { /* nothing runs; reported as out of memory */
            b->nblk = 0;
            b->fail = 1;
        }
    }
}

/* Every band on its own thread: in-degrees, then the sources' chains,
 * then rounds of hand-overs until no band hands anything on.  more[3]:
 * "something was handed on" per round, rotating (reset two rounds on). */
static void run_bands(acc8 *s, int *more)
{
#pragma omp parallel num_threads(s->nb)
    {
        int me, round;
        band *b;
#pragma omp single
        set_bands(s, omp_get_num_threads()); /* the team may be smaller */
        me = omp_get_thread_num();
        b = &s->b[me];
        band_init(s, b);
#pragma omp barrier
        band_sources(s, b);
        for (round = 0;; round++) {
            int par = round & 1, any = b->out[par][0].n + b->out[par][1].n;
            if (any)
#pragma omp atomic write
                more[round % 3] = 1;
#pragma omp barrier
            { /* the next round's flag is free again */
                int go;
#pragma omp atomic read
                go = more[round % 3];
                if (me == 0)
#pragma omp atomic write
                    more[(round + 2) % 3] = 0;
                if (!go)
                    break;
            }
            band_take(s, b, me, par);
#pragma omp barrier
            b->out[par][0].n = b->out[par][1].n = 0;
        }
    }
}

int td_d8_accumulate(uint8_t *code, uint32_t *acc, int w, int h,
                     int threads, double *outflow, double *outlets,
                     double *done, td_ctx *cx)
{
    acc8 s;
    int t, k, rc = 0, nb;
    int *more;
    memset(&s, 0, sizeof s);
    nb = threads < 1 ? 1 : threads;
    if (nb > h / 8)
        nb = h / 8 > 1 ? h / 8 : 1;
    s.code = code;
    s.acc = acc;
    s.w = w;
    s.h = h;
    s.nb = nb;
    for (k = 0; k < 8; k++)
        s.off[k] = (ptrdiff_t)DY[k] * w + DX[k];
    s.cnt = malloc((size_t)w * (size_t)h);
    s.b = calloc((size_t)nb, sizeof *s.b);
    more = calloc(3, sizeof *more);
    if (!s.cnt || !s.b || !more) {
        rc = td_seterr(cx, TD_ENOMEM, "flow: out of memory");
        goto fail;
    }
    run_bands(&s, more);
    *outflow = *outlets = *done = 0;
    for (t = 0; t < nb; t++) {
        *outflow += s.b[t].outflow;
        *outlets += s.b[t].outlets;
        *done += (double)s.b[t].done;
        if (s.b[t].fail)
            rc = td_seterr(cx, TD_ENOMEM, "flow: out of memory");
    }
fail:
    for (t = 0; s.b && t < nb; t++) {
        for (k = 0; k < 4; k++)
            free(s.b[t].out[k / 2][k % 2].v);
        for (k = 0; s.b[t].pend && k < s.b[t].nblk; k++)
            free(s.b[t].pend[k].v);
        free(s.b[t].pend);
    }
    free(s.b);
    free(s.cnt);
    free(more);
    return rc;
}
