/* Hilditch thinning (Hilditch 1969; paper 001 §2.2, ALGORITHMS.md A.2).
 *
 * Neighbours of p, numbered counter-clockwise from the east as in
 * Hilditch's formulation:
 *
 *      x4 x3 x2          NW N NE
 *      x5 p  x1          W  p  E
 *      x6 x7 x8          SW S SE
 *
 * One pass visits the pixels in raster order.  A pixel deleted during the
 * pass is marked -1 (stored as 2) and only turned into paper when the pass
 * ends; this is Hilditch's sequential look-ahead.  p (= 1) is marked when
 * all six conditions hold (|x| = 1 for both 1 and -1):
 *
 *   1. p is ink.
 *   2. p is a border pixel: some 4-neighbour x1,x3,x5,x7 is paper (0, not -1).
 *   3. p is not an end point: sum |x_k| >= 2.
 *   4. p is not isolated: some neighbour is still 1 (not -1).
 *   5. deleting p keeps connectivity: the 8-connectivity number
 *      Nc8 = sum_{k=1,3,5,7} (b_k - b_k b_{k+1} b_{k+2}) = 1, with
 *      b_k = 1 - |x_k| and x9 = x1.
 *   6. lines of width 2 are not erased from both sides: for every x_k = -1,
 *      Nc8 computed with x_k = 0 is still 1.
 *
 * Passes repeat until one deletes nothing.  Only the four causal neighbours
 * (x2, x3, x4, x5: already visited in this pass) can be -1, so the whole
 * decision is a table of 2^8 (|x| pattern) x 2^4 (which causal neighbours
 * are -1) entries.  A pixel's decision changes between passes only if a
 * neighbour was deleted in the previous pass, so after the first pass only
 * rows next to a deletion are scanned.
 *
 * On threads, the same pass as a wavefront (ours; the paper's raster order
 * kept exactly): rows are dealt out in turn, and a row goes on to its
 * next WAVE_CHUNK columns only once the row above has finished every
 * column the chunk reads (up to the chunk's end + 1).  Each pixel then
 * sees the row above as marked in this pass, the pixel to its left as
 * marked, and the row below and to its right as the pass found them, as
 * in one pass down the rows, so the marks, and the skeleton, are the same
 * bytes on any number of threads.  At the end of a pass the marked rows
 * are swept (on threads) and their marks become paper. */
#include "scanner/thin.h"

#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include "src/core/core.h"
#ifdef _OPENMP
#include <omp.h>
#endif

#define WAVE_CHUNK 256
#define WAVE_MIN_ROWS 64  /* fewer rows: one thread */
#define WAVE_MAX_THREADS 8

#define LUT_SIZE 4096

/* Nc8 of the 8-bit |x| pattern (bit k-1 = |x_k|). */
static int nc8(unsigned pat)
{
    int b[10], k, n = 0;
    for (k = 1; k <= 8; k++)
        b[k] = !((pat >> (k - 1)) & 1);
    b[9] = b[1];
    for (k = 1; k <= 7; k += 2)
        n += b[k] - b[k] * b[k + 1] * b[k + 2];
    return n;
}

/* Causal neighbours x2..x5 -> mark bits 0..3 of the table index's top
 * nibble; their pattern bits are 1..4. */
static int lut_entry(unsigned pat, unsigned marks)
{
    int k, ones = 0, any = 0;
    if ((marks << 1) & ~pat)
        return 0; /* a -1 mark on a paper pixel cannot happen */
    if ((pat & 0x55) == 0x55)
        return 0; /* condition 2: x1,x3,x5,x7 all ink */
    for (k = 0; k < 8; k++)
        any += (pat >> k) & 1;
    if (any < 2)
        return 0; /* condition 3 */
    ones = any;
    for (k = 0; k < 4; k++)
        ones -= (marks >> k) & 1;
    if (ones < 1)
        return 0; /* condition 4 */
    if (nc8(pat) != 1)
        return 0; /* condition 5 */
    for (k = 0; k < 4; k++)
        if (((marks >> k) & 1) && nc8(pat & ~(1u << (k + 1))) != 1)
            return 0; /* condition 6 */
    return 1;
}

static void build_lut(uint8_t *lut)
{
    unsigned i;
    for (i = 0; i < LUT_SIZE; i++)
        lut[i] = (uint8_t)lut_entry(i & 0xff, i >> 8);
}

/* Table index from the eight neighbour values (0 paper, 1 ink, 2 ink
 * marked -1). */
static inline unsigned nb_pack(unsigned v1, unsigned v2, unsigned v3,
                               unsigned v4, unsigned v5, unsigned v6,
                               unsigned v7, unsigned v8)
{
    unsigned pat, marks;
    pat = ((v1 | v1 >> 1) & 1) | ((v2 | v2 >> 1) & 1) << 1 |
          ((v3 | v3 >> 1) & 1) << 2 | ((v4 | v4 >> 1) & 1) << 3 |
          ((v5 | v5 >> 1) & 1) << 4 | ((v6 | v6 >> 1) & 1) << 5 |
          ((v7 | v7 >> 1) & 1) << 6 | ((v8 | v8 >> 1) & 1) << 7;
    marks = (v2 >> 1) | (v3 >> 1) << 1 | (v4 >> 1) << 2 | (v5 >> 1) << 3;
    return pat | marks << 8;
}

/* Table index of the pixel at column x of row b (a above, c below; any may
 * be the zero row); columns outside the grid are paper. */
static inline unsigned nb_index(const uint8_t *a, const uint8_t *b,
                                const uint8_t *c, int x, int w)
{
    if (x > 0 && x + 1 < w)
        return nb_pack(b[x + 1], a[x + 1], a[x], a[x - 1], b[x - 1],
                       c[x - 1], c[x], c[x + 1]);
    return nb_pack(x + 1 < w ? b[x + 1] : 0, x + 1 < w ? a[x + 1] : 0, a[x],
                   x > 0 ? a[x - 1] : 0, x > 0 ? b[x - 1] : 0,
                   x > 0 ? c[x - 1] : 0, c[x], x + 1 < w ? c[x + 1] : 0);
}

typedef struct thin_state {
    td_grid_u8 *g;
    uint8_t lut[LUT_SIZE];
    uint8_t *zero;            /* a row of paper for outside the grid */
    uint8_t *cur, *next;      /* rows to scan in this / the next pass */
    atomic_int *done;         /* per row: its columns finished this pass */
    size_t *marked;           /* per row: pixels marked in this pass */
    int nt;                   /* threads */
} thin_state;

/* Wait until row y (of another thread) has finished need columns; how
 * many it has finished then. */
static int wait_row(const thin_state *s, int y, int need)
{
    int spins = 0, got;
    while ((got = atomic_load_explicit(&s->done[y], memory_order_acquire)) <
           need)
        if (++spins == 256) {
            spins = 0;
            sched_yield();
        }
    return got;
}

/* Scan one row, marking the pixels to delete; how many.  Ink bytes are
 * found eight at a time.  With threads, each chunk of columns first waits
 * for the row above. */
static size_t thin_row(thin_state *s, int y)
{
    td_grid_u8 *g = s->g;
    int w = g->w, x = 0, x1, seen = 0; /* seen: the row above's done */
    uint8_t *b = g->data + (size_t)y * g->stride;
    const uint8_t *a = y > 0 ? b - g->stride : s->zero;
    const uint8_t *c = y + 1 < g->h ? b + g->stride : s->zero;
    size_t n = 0;
    for (x = 0; x < w; x = x1) {
        int need;
        x1 = x + WAVE_CHUNK < w ? x + WAVE_CHUNK : w;
        need = x1 + 1 < w ? x1 + 1 : w;
        if (s->nt > 1 && y > 0 && seen < need)
            seen = wait_row(s, y - 1, need);
        while (x < x1) {
            uint64_t word;
            if (x + 8 <= x1) {
                memcpy(&word, b + x, 8);
                if (word == 0) {
                    x += 8;
                    continue;
                }
            }
            if (b[x] == 1 && s->lut[nb_index(a, b, c, x, w)]) {
                b[x] = 2;
                n++;
            }
            x++;
        }
        if (s->nt > 1)
            atomic_store_explicit(&s->done[y], x1, memory_order_release);
    }
    return n;
}

/* One pass over the rows marked in s->cur: marks, and per row how many
 * into s->marked. */
static void thin_pass(thin_state *s)
{
    td_grid_u8 *g = s->g;
    int y;
    if (s->nt <= 1) {
        for (y = 0; y < g->h; y++)
            s->marked[y] = s->cur[y] ? thin_row(s, y) : 0;
        return;
    }
    for (y = 0; y < g->h; y++) {
        atomic_init(&s->done[y], s->cur[y] ? 0 : g->w);
        s->marked[y] = 0;
    }
#pragma omp parallel num_threads(s->nt)
    {
#ifdef _OPENMP
        int t = omp_get_thread_num(), nt = omp_get_num_threads();
#else
        int t = 0, nt = 1;
#endif
        int yy;
        /* rows t, t + nt, ... in order (the team deals by its own size) */
        for (yy = t; yy < g->h; yy += nt)
            if (s->cur[yy]) {
                s->marked[yy] = thin_row(s, yy);
                atomic_store_explicit(&s->done[yy], g->w,
                                      memory_order_release);
            }
    }
}

/* The pass's marks turned into paper (rows on threads). */
static void apply_marks(thin_state *s)
{
    td_grid_u8 *g = s->g;
    int y;
#pragma omp parallel for schedule(dynamic, 64) num_threads(s->nt)
    for (y = 0; y < g->h; y++) {
        uint8_t *r = g->data + (size_t)y * g->stride;
        int x;
        if (!s->marked[y])
            continue;
        for (x = 0; x < g->w; x++)
            r[x] = r[x] == 2 ? 0 : r[x];
    }
}

/* Passes until nothing changes; s->cur holds the rows of the first pass. */
static int thin_passes(thin_state *s, td_thin_stats *st, td_ctx *cx)
{
    td_grid_u8 *g = s->g;
    int y, passes = 0;
    size_t removed = 0, n;
    for (;;) {
        thin_pass(s);
        apply_marks(s);
        for (y = 0, n = 0; y < g->h; y++) {
            n += s->marked[y];
            s->next[y] = s->marked[y] > 0 ||
                         (y > 0 && s->marked[y - 1] > 0) ||
                         (y + 1 < g->h && s->marked[y + 1] > 0);
        }
        removed += n;
        passes++;
        if (td_progress(cx, "thin", n ? 0.5 : 1.0) != 0)
            return TD_ECANCEL;
        if (n == 0)
            break;
        memcpy(s->cur, s->next, (size_t)g->h);
    }
    if (st) {
        st->passes = passes;
        st->removed = removed;
    }
    return 0;
}

static int thin_run(td_grid_u8 *g, const size_t *idx, size_t n,
                    td_thin_stats *st, td_ctx *cx)
{
    thin_state s;
    int rc = TD_ENOMEM;
    size_t i;
    memset(&s, 0, sizeof s);
    s.g = g;
    s.nt = 1;
#ifdef _OPENMP
    if (g->h >= WAVE_MIN_ROWS)
        s.nt = omp_get_max_threads();
#endif
    s.nt = s.nt < 1 ? 1 : s.nt > WAVE_MAX_THREADS ? WAVE_MAX_THREADS : s.nt;
    build_lut(s.lut);
    s.zero = calloc((size_t)g->w + 8, 1);
    s.cur = calloc((size_t)g->h, 1);
    s.next = calloc((size_t)g->h, 1);
    s.marked = calloc((size_t)g->h, sizeof *s.marked);
    s.done = s.nt > 1 ? malloc((size_t)g->h * sizeof *s.done) : NULL;
    if (!s.zero || !s.cur || !s.next || !s.marked || (s.nt > 1 && !s.done)) {
        td_seterr(cx, TD_ENOMEM, "thin: out of memory");
        goto fail;
    }
    if (!idx) {
        memset(s.cur, 1, (size_t)g->h);
    } else {
        for (i = 0; i < n; i++) {
            int y = (int)(idx[i] / g->stride);
            s.cur[y] = 1;
            if (y > 0)
                s.cur[y - 1] = 1;
            if (y + 1 < g->h)
                s.cur[y + 1] = 1;
        }
    }
    rc = thin_passes(&s, st, cx);
fail:
    free(s.zero);
    free(s.cur);
    free(s.next);
    free(s.marked);
    free((void *)s.done);
    return rc;
}

int td_thin_hilditch(td_grid_u8 *g, td_thin_stats *st, td_ctx *cx)
{
    int rc, y;
    if (st)
        memset(st, 0, sizeof *st);
    rc = thin_run(g, NULL, 0, st, cx);
    if (rc == 0 && st) {
        for (y = 0; y < g->h; y++) {
            const uint8_t *r = g->data + (size_t)y * g->stride;
            int x;
            for (x = 0; x < g->w; x++)
                st->remaining += r[x];
        }
    }
    return rc;
}

int td_thin_hilditch_near(td_grid_u8 *g, const size_t *idx, size_t n,
                          td_ctx *cx)
{
    if (n == 0)
        return 0;
    return thin_run(g, idx, n, NULL, cx);
}
