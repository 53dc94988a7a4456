/* flow_fill.c: priority-flood depression filling in tiles.
 *
 * Barnes (2016) "Parallel priority-flood depression filling for trillion
 * cell digital elevation models": tiles flooded on their own, on threads.
 * That also keeps each flood's working set in the cache (a priority flood
 * over the whole grid pops cells in height order from anywhere, so every
 * popped cell's 3x3 block is cold; a 256 x 256 tile's heights, codes and
 * labels, 0.5 MB, and its queue, 1.3 MB, stay in the L2 cache).
 *
 *   0. Drained cells (a path to an outlet that never climbs) keep their
 *      height: found by two raster sweeps, label 0, never flooded.
 *   1. Each tile alone: a priority flood (Barnes, Lehman, Mulla 2014,
 *      Alg. 2: a FIFO for cells inside depressions; upslope tracing after
 *      Zhou, Sun, Fu 2016; a queue over the tile's cells ranked by
 *      height, see struct rq) from the tile's
 *      undrained perimeter cells at their own heights and from the drained
 *      cells next to undrained ones (label 0, OUTSIDE).  A perimeter cell
 *      popped before any flood reached it starts a new label; every cell
 *      the flood reaches takes the label of the cell it came from, and its
 *      level F (its height, or the level it is raised to inside the tile).
 *      When two labels meet, the edge (a, b) gets the spill max(F_a, F_b)
 *      (lowest per pair).
 *   2. Tile borders: each pair of 8-neighbours in different tiles joins
 *      their labels at max(F_p, F_q) (perimeter cells keep F = height).
 *   3. The label graph (a few labels per tile side): W(label) = the lowest
 *      level over paths to OUTSIDE of the highest spill on the way
 *      (Dijkstra with max for +), W(OUTSIDE) = -inf.
 *   4. Each cell's filled level is max(F, W(its label)).
 *
 * The result equals the flood over the whole grid for every tile size and
 * thread count (tests/test_flow.c checks it against a brute-force fill). */
#include "src/flow/flow_int.h"
#include "src/flow/flow_window_int.h"

#include <float.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Flood-time code bits (valid cells have low nibble 0 or TD_FL_ROOT;
 * TD_FL_NODATA = 9 is the only value with bit 0). */
enum { NOD = 0x01, DRAIN = 0x10, PERIM = 0x20, SEEN = 0x40 };

typedef struct u32vec {
    uint32_t *v;
    size_t n, cap;
} u32vec;

/* The flood's priority queue.  The flood queues a cell by height only at
 * its own height (a raised cell goes to the FIFO instead), so a tile's
 * candidates (its undrained cells and seeds) are sorted by height once
 * (LSD radix sort) and the queue is a bitset over their ranks: a push
 * sets the cell's bit, a pop takes the lowest set bit.  A push is always
 * above the last key popped (a cell is queued above the level it is
 * reached from, and an upslope-traced cell lies above that level too), so
 * the lowest set bit is never behind the scan word `pos`.  Against the
 * byte-digit radix heap it replaced (each entry moved about 1.6 times
 * between buckets), a third fewer mispredicted branches in the flood and
 * 6-10% less time on white-noise terrain on one thread; the same on
 * smooth terrain and on two threads.  20 bytes per tile cell per thread
 * (1.3 MB for a tile of 256). */
typedef struct rq {
    uint64_t *sk, *tmp; /* key << 32 | cell, sorted by key after rq_sort */
    uint32_t *rank;     /* tile cell (row dy, column dx) dy * tw + dx ->
                           rank */
    uint64_t *bits;     /* bit r: rank r queued */
    size_t ns, pos, n;  /* candidates, scan word, queued */
    size_t org;         /* the tile's first cell */
    size_t w;           /* grid width */
    int tw;             /* tile width */
    double inv_w;       /* 1 / w, for the tile row of a cell */
} rq;

/* Spill edges of one tile between local labels: open addressing on
 * key = lo << 16 | hi (lo < hi, so never 0 = empty). */
typedef struct ehash {
    uint32_t *key;
    float *w;
    size_t cap, n;
    size_t last; /* slot of the last key added (labels meet in runs) */
} ehash;

/* One thread's flood state, reused from tile to tile. */
typedef struct wk {
    rq queue;
    u32vec fifo, stack, seeds;
    size_t fhead;
    ehash eh;
} wk;

/* A tile's result: its number of labels and its spill edges (local). */
typedef struct tres {
    uint32_t *key;
    float *w;
    size_t n;
    unsigned nl;
} tres;

/* Label-graph edges between global labels. */
typedef struct gedge {
    uint32_t a, b;
    float w;
} gedge;

typedef struct pf {
    const float *dem;
    float *z;
    uint8_t *code;
    uint16_t *lab;
    int w, h, ts, ntx, nty, nth;
    ptrdiff_t off[9]; /* window slot s -> index offset */
    tres *tr;       /* per tile */
    uint32_t *base; /* per tile: global label = base + local label (>0) */
    gedge *e;
    size_t ne, ecap;
    uint32_t nlab; /* global labels, OUTSIDE (0) included */
    td_ctx *cx;
} pf;

static uint32_t fkey(float z)
{
    uint32_t u;
    z += 0.0f;
    memcpy(&u, &z, sizeof u);
    return (u & 0x80000000u) ? ~u : u | 0x80000000u;
}

/* Double *cap (first: c0) for elements of `size` bytes; -1 out of memory. */
static int grow(void **v, size_t *cap, size_t size, size_t c0)
{
    size_t c = *cap ? *cap * 2 : c0;
    void *p = realloc(*v, c * size);
    if (!p)
        return -1;
    *v = p;
    *cap = c;
    return 0;
}

static inline int u32_push(u32vec *a, uint32_t x)
{
    if (a->n == a->cap && grow((void **)&a->v, &a->cap, sizeof *a->v, 1024))
        return TD_ENOMEM;
    a->v[a->n++] = x;
    return 0;
}

/* Tile cell of grid cell i: dy * tw + dx (dy = (i - org) / w without a
 * division: the half keeps it exact for any cell count below 2^40). */
static inline size_t rq_local(const rq *h, size_t i)
{
    size_t d = i - h->org;
    size_t dy = (size_t)(int64_t)(((double)d + 0.5) * h->inv_w);
    return dy * (size_t)h->tw + (d - dy * h->w);
}

/* Room for a tile of side ts; -1 out of memory. */
static int rq_alloc(rq *h, int ts)
{
    size_t n = (size_t)ts * (size_t)ts;
    h->sk = malloc(n * sizeof *h->sk);
    h->tmp = malloc(n * sizeof *h->tmp);
    h->rank = malloc(n * sizeof *h->rank);
    h->bits = calloc(n / 64 + 1, sizeof *h->bits);
    return h->sk && h->tmp && h->rank && h->bits ? 0 : -1;
}

static void rq_free(rq *h)
{
    free(h->sk);
    free(h->tmp);
    free(h->rank);
    free(h->bits);
}

/* Candidate cell i at height z. */
static inline void rq_add(rq *h, float z, uint32_t i)
{
    h->sk[h->ns++] = (uint64_t)fkey(z) << 32 | i;
}

/* Sort the candidates by key (stable LSD radix sort with 11-bit digits; a
 * digit the same in all of them is skipped) and rank them. */
static void rq_sort(rq *h)
{
    static const int SH[3] = {32, 43, 54};
    uint32_t cnt[3][2048];
    uint64_t *restrict src = h->sk, *restrict dst = h->tmp;
    uint32_t *restrict rank = h->rank;
    size_t r, n = h->ns;
    int b, d;
    memset(cnt, 0, sizeof cnt);
    for (r = 0; r < n; r++) {
        uint64_t k = src[r];
        cnt[0][k >> 32 & 2047]++;
        cnt[1][k >> 43 & 2047]++;
        cnt[2][k >> 54]++;
    }
    for (b = 0; b < 3; b++) {
        uint32_t sum = 0, *c = cnt[b];
        uint64_t *t;
        if (n == 0 || c[src[0] >> SH[b] & 2047] == n)
            continue; /* one digit: nothing to order */
        for (d = 0; d < 2048; d++) {
            uint32_t v = c[d];
            c[d] = sum;
            sum += v;
        }
        for (r = 0; r < n; r++) {
            uint64_t k = src[r];
            dst[c[k >> SH[b] & 2047]++] = k;
        }
        t = src;
        src = dst;
        dst = t;
    }
    h->sk = src;
    h->tmp = dst;
    for (r = 0; r < n; r++)
        rank[rq_local(h, (uint32_t)src[r])] = (uint32_t)r;
    h->pos = 0;
    h->n = 0;
}

/* Queue candidate cell i. */
static inline void rq_push(rq *h, uint32_t i)
{
    uint32_t r = h->rank[rq_local(h, i)];
    h->bits[r >> 6] |= 1ull << (r & 63);
    h->n++;
}

/* The lowest queued cell (the queue is not empty), dequeued. */
static inline uint32_t rq_pop(rq *h)
{
    uint64_t m;
    uint32_t r;
    while (!(m = h->bits[h->pos]))
        h->pos++;
    r = (uint32_t)(h->pos * 64 + (size_t)__builtin_ctzll(m));
    h->bits[h->pos] = m & (m - 1);
    h->n--;
    return (uint32_t)h->sk[r];
}

/* ---- edges ----------------------------------------------------------- */

static int eh_grow(ehash *t)
{
    ehash o = *t;
    size_t s, cap = o.cap ? o.cap * 2 : 4096;
    t->key = calloc(cap, sizeof *t->key);
    t->w = malloc(cap * sizeof *t->w);
    t->cap = cap;
    t->n = 0;
    if (!t->key || !t->w) {
        free(t->key);
        free(t->w);
        *t = o;
        return TD_ENOMEM;
    }
    for (s = 0; s < o.cap; s++)
        if (o.key[s]) {
            size_t j = (o.key[s] * 2654435761u) & (cap - 1);
            while (t->key[j])
                j = (j + 1) & (cap - 1);
            t->key[j] = o.key[s];
            t->w[j] = o.w[s];
            t->n++;
        }
    free(o.key);
    free(o.w);
    return 0;
}

/* Local labels a != b meet at spill level s: keep the lowest. */
static int eh_add(ehash *t, unsigned a, unsigned b, float s)
{
    uint32_t k = a < b ? a << 16 | b : b << 16 | a;
    size_t j;
    if (t->cap && t->key[t->last] == k) {
        if (s < t->w[t->last])
            t->w[t->last] = s;
        return 0;
    }
    if (2 * (t->n + 1) > t->cap && eh_grow(t) != 0)
        return TD_ENOMEM;
    j = (k * 2654435761u) & (t->cap - 1);
    while (t->key[j] && t->key[j] != k)
        j = (j + 1) & (t->cap - 1);
    if (!t->key[j]) {
        t->key[j] = k;
        t->w[j] = s;
        t->n++;
    } else if (s < t->w[j])
        t->w[j] = s;
    t->last = j;
    return 0;
}

/* The table's edges into r (compact); empties the table. */
static int eh_take(ehash *t, tres *r)
{
    size_t s, n = 0;
    r->key = malloc((t->n + 1) * sizeof *r->key);
    r->w = malloc((t->n + 1) * sizeof *r->w);
    if (!r->key || !r->w)
        return TD_ENOMEM;
    for (s = 0; s < t->cap; s++)
        if (t->key[s]) {
            r->key[n] = t->key[s];
            r->w[n++] = t->w[s];
            t->key[s] = 0;
        }
    r->n = n;
    t->n = 0;
    return 0;
}

/* ---- one tile ---------------------------------------------------------- */

/* Codes of the window: *unseen (valid, no label) and *seen (valid, a
 * label). */
static void win_codes(const uint8_t *code, size_t i, size_t w,
                      unsigned *unseen, unsigned *seen)
{
    *unseen = w3_eq8(code, i, w, SEEN | NOD, 0);
    *seen = w3_eq8(code, i, w, SEEN | NOD, SEEN);
}

/* 1 when every unseen valid neighbour of interior cell i is higher. */
static int traceable(const pf *p, size_t i)
{
    return (w3_eq8(p->code, i, (size_t)p->w, SEEN | NOD, 0) &
            w3_z(p->z, i, (size_t)p->w, p->z[i], W3_LE)) == 0;
}

/* Window mask of tile-perimeter cell c within tile [x0,x1) x [y0,y1). */
static unsigned perim_mask(const pf *p, size_t c, const int t[4])
{
    int x = (int)(c % (size_t)p->w), y = (int)(c / (size_t)p->w), s;
    unsigned m = 0;
    for (s = 0; s < 9; s++) {
        int xx = x + s % 3 - 1, yy = y + s / 3 - 1;
        m |= (unsigned)(s != 4 && xx >= t[0] && xx < t[1] && yy >= t[2] &&
                        yy < t[3]) << s;
    }
    return m;
}

/* Unseen and met (valid, another label) neighbours of c. */
static void classify(const pf *p, size_t c, const int t[4],
                     unsigned *unseen, unsigned *meet)
{
    uint16_t lc = p->lab[c];
    unsigned s, m;
    if (!(p->code[c] & PERIM)) { /* all 8 in the tile, off the grid edge */
        win_codes(p->code, c, (size_t)p->w, unseen, &m);
        *meet = m & w3_ne16(p->lab, c, (size_t)p->w, lc);
        return;
    }
    m = perim_mask(p, c, t);
    *unseen = *meet = 0;
    for (s = 0; s < 9; s++)
        if (m >> s & 1) {
            size_t j = c + (size_t)p->off[s];
            unsigned f = p->code[j] & (SEEN | NOD);
            *unseen |= (unsigned)(f == 0) << s;
            *meet |= (unsigned)(f == SEEN && p->lab[j] != lc) << s;
        }
}

/* Reach c's neighbours in the tile.  in_order: c is at the lowest level
 * of the whole frontier, so unseen neighbours not above it are raised to
 * it (they drain through c). */
static int visit(const pf *p, wk *q, uint32_t c, int in_order,
                 const int t[4])
{
    float zc = p->z[c];
    uint16_t lc = p->lab[c];
    unsigned unseen, meet, s;
    int rc = 0;
    classify(p, c, t, &unseen, &meet);
    while (meet && rc == 0) {
        size_t j;
        s = (unsigned)__builtin_ctz(meet);
        meet &= meet - 1;
        j = c + (size_t)p->off[s];
        rc = eh_add(&q->eh, lc, p->lab[j], zc > p->z[j] ? zc : p->z[j]);
    }
    while (unseen && rc == 0) {
        size_t n;
        uint8_t cn;
        s = (unsigned)__builtin_ctz(unseen);
        unseen &= unseen - 1;
        n = c + (size_t)p->off[s];
        cn = p->code[n];
        p->lab[n] = lc;
        p->code[n] = cn | SEEN;
        if (cn & PERIM) /* a queued seed: keeps its height, pops in turn */
            continue;
        if (in_order && p->z[n] <= zc) {
            p->z[n] = zc;
            rc = u32_push(&q->fifo, (uint32_t)n);
        } else if (traceable(p, n))
            rc = u32_push(&q->stack, (uint32_t)n);
        else
            rq_push(&q->queue, (uint32_t)n);
    }
    return rc;
}

/* Seed cell i of tile t (perim: on the tile's perimeter): a candidate of
 * the queue unless it is drained, and a seed if it is one. */
static inline int seed_cell(const pf *p, wk *q, size_t i, int perim,
                            const int t[4])
{
    uint8_t c = p->code[i];
    unsigned m;
    if (c & NOD)
        return 0;
    if (perim)
        p->code[i] = c = (uint8_t)(c | PERIM);
    if (!(c & DRAIN)) {
        rq_add(&q->queue, p->z[i], (uint32_t)i);
        return perim ? u32_push(&q->seeds, (uint32_t)i) : 0;
    }
    p->code[i] = (uint8_t)(c | SEEN);
    if (perim) {
        unsigned s;
        m = perim_mask(p, i, t);
        for (s = 0; s < 9; s++)
            if ((m >> s & 1) &&
                !(p->code[i + (size_t)p->off[s]] & (DRAIN | NOD)))
                break;
        m = s < 9;
    } else
        m = w3_eq8(p->code, i, (size_t)p->w, DRAIN | NOD, 0);
    if (!m)
        return 0;
    rq_add(&q->queue, p->z[i], (uint32_t)i);
    return u32_push(&q->seeds, (uint32_t)i);
}

#ifdef __SSE2__
/* Cells [i, i + 16) inside a tile (off its perimeter) as seed_cell does
 * them: undrained ones are candidates, drained ones are SEEN (DRAIN << 2)
 * and seeds when a neighbour is undrained, found 16 at a time (smooth
 * DEMs: most cells are drained, and few of them seeds). */
static int seed_16(const pf *p, wk *q, size_t i)
{
    const __m128i dn = _mm_set1_epi8(DRAIN | NOD), zero = _mm_setzero_si128();
    __m128i c = _mm_loadu_si128((const __m128i *)(p->code + i)), und;
    unsigned cand, drained, m;
    int s, rc = 0;
    und = _mm_cmpeq_epi8(_mm_and_si128(c, dn), zero);
    cand = (unsigned)_mm_movemask_epi8(und);
    drained = (unsigned)_mm_movemask_epi8(_mm_slli_epi16(c, 3)); /* bit 4 */
    for (m = cand; m; m &= m - 1) {
        size_t j = i + (size_t)__builtin_ctz(m);
        rq_add(&q->queue, p->z[j], (uint32_t)j);
    }
    if (!drained)
        return 0;
    und = zero;
    for (s = 0; s < 9; s++)
        if (s != 4)
            und = _mm_or_si128(und, _mm_cmpeq_epi8(_mm_and_si128(
                      _mm_loadu_si128((const __m128i *)(p->code + i +
                                                        p->off[s])), dn),
                                                   zero));
    _mm_storeu_si128((__m128i *)(p->code + i),
                     _mm_or_si128(c, _mm_slli_epi16(_mm_and_si128(
                                      c, _mm_set1_epi8(DRAIN)), 2)));
    for (m = drained & (unsigned)_mm_movemask_epi8(und); m && rc == 0;
         m &= m - 1) {
        size_t j = i + (size_t)__builtin_ctz(m);
        rq_add(&q->queue, p->z[j], (uint32_t)j);
        rc = u32_push(&q->seeds, (uint32_t)j);
    }
    return rc;
}
#endif

/* Seeds of tile t: the drained cells next to undrained ones (label 0:
 * OUTSIDE, at their height; the other drained cells are done) and the
 * undrained cells of the perimeter (no label until popped or reached),
 * queued; every undrained cell is a candidate of the queue. */
static int tile_seeds(const pf *p, wk *q, const int t[4])
{
    rq *h = &q->queue;
    size_t k;
    int x, y, rc = 0;
    h->org = (size_t)t[2] * (size_t)p->w + (size_t)t[0];
    h->w = (size_t)p->w;
    h->tw = t[1] - t[0];
    h->inv_w = 1.0 / p->w;
    h->ns = 0;
    q->seeds.n = 0;
    for (y = t[2]; y < t[3] && rc == 0; y++) {
        size_t i = (size_t)y * (size_t)p->w + (size_t)t[0];
        if (y == t[2] || y == t[3] - 1) {
            for (x = t[0]; x < t[1] && rc == 0; x++, i++)
                rc = seed_cell(p, q, i, 1, t);
            continue;
        }
        rc = seed_cell(p, q, i++, 1, t);
        x = t[0] + 1;
#ifdef __SSE2__
        for (; x + 16 <= t[1] - 1 && rc == 0; x += 16, i += 16)
            rc = seed_16(p, q, i);
#endif
        for (; x < t[1] - 1 && rc == 0; x++, i++) {
            uint8_t c = p->code[i];
            if (!(c & (DRAIN | NOD))) /* white noise: almost all */
                rq_add(h, p->z[i], (uint32_t)i);
            else
                rc = seed_cell(p, q, i, 0, t);
        }
        if (rc == 0 && t[1] - 1 > t[0])
            rc = seed_cell(p, q, i, 1, t);
    }
    if (rc != 0)
        return rc;
    rq_sort(h);
    for (k = 0; k < q->seeds.n; k++)
        rq_push(h, q->seeds.v[k]);
    return 0;
}

/* Next cell of the flood into *c (0), or 1 when done; *in_order 0 for a
 * cell off the upslope stack. */
static int next_cell(wk *q, uint32_t *c, int *in_order)
{
    *in_order = 1;
    if (q->fhead < q->fifo.n) {
        *c = q->fifo.v[q->fhead++];
        return 0;
    }
    q->fhead = q->fifo.n = 0;
    if (q->stack.n > 0) {
        *c = q->stack.v[--q->stack.n];
        *in_order = 0;
        return 0;
    }
    if (q->queue.n == 0)
        return 1;
    *c = rq_pop(&q->queue);
    return 0;
}

static int tile_flood(const pf *p, wk *q, int ti)
{
    int t[4], rc, in_order, tx = ti % p->ntx, ty = ti / p->ntx;
    unsigned nl = 0;
    uint32_t c;
    t[0] = tx * p->ts;
    t[2] = ty * p->ts;
    t[1] = t[0] + p->ts < p->w ? t[0] + p->ts : p->w;
    t[3] = t[2] + p->ts < p->h ? t[2] + p->ts : p->h;
    rc = tile_seeds(p, q, t);
    while (rc == 0 && (rc = next_cell(q, &c, &in_order)) == 0) {
        if (!(p->code[c] & SEEN)) { /* a perimeter cell nobody reached */
            p->code[c] |= SEEN;
            p->lab[c] = (uint16_t)++nl;
        }
        rc = visit(p, q, c, in_order, t);
    }
    if (rc == 1)
        rc = eh_take(&q->eh, &p->tr[ti]);
    p->tr[ti].nl = nl;
    return rc;
}

static void wk_free(wk *q)
{
    if (!q)
        return;
    rq_free(&q->queue);
    free(q->seeds.v);
    free(q->fifo.v);
    free(q->stack.v);
    free(q->eh.key);
    free(q->eh.w);
    free(q);
}

/* Flood every tile, on as many threads as OpenMP gives. */
static int flood_tiles(pf *p, double p0, double p1)
{
    int nt = p->ntx * p->nty, ti, rc = 0, done = 0;
#pragma omp parallel num_threads(p->nth)
    {
        wk *q = calloc(1, sizeof *q);
        if (q && rq_alloc(&q->queue, p->ts) != 0) {
            wk_free(q);
            q = NULL;
        }
#pragma omp for schedule(dynamic, 1)
        for (ti = 0; ti < nt; ti++) {
            int r, stop;
#pragma omp atomic read
            stop = rc;
            if (stop)
                continue;
            r = q ? tile_flood(p, q, ti) : TD_ENOMEM;
#pragma omp critical(td_flow_fill_tiles)
            {
                if (r != 0 && rc == 0)
                    rc = td_seterr(p->cx, TD_ENOMEM, "flow: out of memory");
                else if (rc == 0)
                    rc = td_progress(p->cx, "flow", p0 + (p1 - p0) *
                                     (double)++done / nt);
            }
        }
        wk_free(q);
    }
    return rc;
}

/* Label bases from the tiles' label counts; their edges into p->e. */
static int gather(pf *p)
{
    int ti, nt = p->ntx * p->nty;
    size_t s, ne = 0;
    uint32_t base = 0;
    for (ti = 0; ti < nt; ti++) {
        p->base[ti] = base;
        base += p->tr[ti].nl;
        ne += p->tr[ti].n;
    }
    p->nlab = base + 1;
    p->ecap = ne + 4 * (size_t)(p->w + p->h) * (size_t)(p->ntx + p->nty);
    if (!(p->e = malloc(p->ecap * sizeof *p->e)))
        return td_seterr(p->cx, TD_ENOMEM, "flow: out of memory");
    for (ti = 0; ti < nt; ti++)
        for (s = 0; s < p->tr[ti].n; s++) {
            uint32_t a = p->tr[ti].key[s] >> 16, b = p->tr[ti].key[s] & 0xFFFF;
            gedge *e = &p->e[p->ne++];
            e->a = a ? p->base[ti] + a : 0;
            e->b = p->base[ti] + b;
            e->w = p->tr[ti].w[s];
        }
    return 0;
}

/* ---- tile borders and the label graph ---------------------------------- */

static int edge_add(pf *p, uint32_t a, uint32_t b, float w)
{
    gedge *e;
    if (p->ne == p->ecap &&
        grow((void **)&p->e, &p->ecap, sizeof *p->e, 1024) != 0)
        return td_seterr(p->cx, TD_ENOMEM, "flow: out of memory");
    e = &p->e[p->ne++];
    e->a = a;
    e->b = b;
    e->w = w;
    return 0;
}

static uint32_t glabel(const pf *p, size_t i)
{
    int x = (int)(i % (size_t)p->w), y = (int)(i / (size_t)p->w);
    unsigned l = p->lab[i];
    return l ? p->base[(y / p->ts) * p->ntx + x / p->ts] + l : 0;
}

/* Cell i (on a tile's right or bottom border) and its 8-neighbours j in
 * the next tiles: edges at max(z_i, z_j). */
static int border_pair(pf *p, size_t i, size_t j)
{
    uint32_t a, b;
    if ((p->code[i] & NOD) || (p->code[j] & NOD))
        return 0;
    a = glabel(p, i);
    b = glabel(p, j);
    if (a == b)
        return 0;
    return edge_add(p, a, b, p->z[i] > p->z[j] ? p->z[i] : p->z[j]);
}

static int tile_borders(pf *p)
{
    int x, y, d, rc = 0;
    size_t w = (size_t)p->w;
    for (x = p->ts - 1; x < p->w - 1 && rc == 0; x += p->ts) /* columns */
        for (y = 0; y < p->h && rc == 0; y++)
            for (d = -1; d <= 1 && rc == 0; d++)
                if (y + d >= 0 && y + d < p->h)
                    rc = border_pair(p, (size_t)y * w + (size_t)x,
                                     (size_t)(y + d) * w + (size_t)x + 1);
    for (y = p->ts - 1; y < p->h - 1 && rc == 0; y += p->ts) /* rows */
        for (x = 0; x < p->w && rc == 0; x++)
            for (d = -1; d <= 1 && rc == 0; d++)
                if (x + d >= 0 && x + d < p->w)
                    rc = border_pair(p, (size_t)y * w + (size_t)x,
                                     (size_t)(y + 1) * w + (size_t)(x + d));
    return rc;
}

typedef struct wnode {
    float w;
    uint32_t v;
} wnode;

/* Binary min-heap on w. */
static void wheap_push(wnode *h, size_t *n, wnode e)
{
    size_t i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].w > e.w) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = e;
}

static wnode wheap_pop(wnode *h, size_t *n)
{
    wnode top = h[0], e = h[--*n];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= *n)
            break;
        if (c + 1 < *n && h[c + 1].w < h[c].w)
            c++;
        if (!(h[c].w < e.w))
            break;
        h[i] = h[c];
        i = c;
    }
    if (*n > 0)
        h[i] = e;
    return top;
}

/* W[label] for every global label: Dijkstra from OUTSIDE with max. */
static int solve(pf *p, float *W)
{
    uint32_t n = p->nlab, *start = calloc((size_t)n + 1, sizeof *start);
    wnode *adj = malloc(2 * p->ne * sizeof *adj + 1);
    wnode *hp = malloc((2 * p->ne + 1) * sizeof *hp);
    size_t e, hn = 0;
    uint32_t v;
    int rc = 0;
    if (!start || !adj || !hp) {
        rc = td_seterr(p->cx, TD_ENOMEM, "flow: out of memory");
        goto fail;
    }
    for (e = 0; e < p->ne; e++)
        start[p->e[e].a + 1]++, start[p->e[e].b + 1]++;
    for (v = 0; v < n; v++)
        start[v + 1] += start[v];
    for (e = 0; e < p->ne; e++) { /* start[v] runs ahead while filling */
        gedge g = p->e[e];
        adj[start[g.a]].v = g.b, adj[start[g.a]++].w = g.w;
        adj[start[g.b]].v = g.a, adj[start[g.b]++].w = g.w;
    }
    for (v = n; v > 0; v--) /* back to the starts */
        start[v] = start[v - 1];
    start[0] = 0;
    for (v = 0; v < n; v++)
        W[v] = FLT_MAX;
    W[0] = -FLT_MAX;
    wheap_push(hp, &hn, (wnode){-FLT_MAX, 0});
    while (hn > 0) {
        wnode top = wheap_pop(hp, &hn);
        uint32_t a;
        if (top.w > W[top.v])
            continue;
        for (a = start[top.v]; a < start[top.v + 1]; a++) {
            float nw = adj[a].w > top.w ? adj[a].w : top.w;
            if (nw < W[adj[a].v]) {
                W[adj[a].v] = nw;
                wheap_push(hp, &hn, (wnode){nw, adj[a].v});
            }
        }
    }
fail:
    free(start);
    free(adj);
    free(hp);
    return rc;
}

/* ---- driver ------------------------------------------------------------- */

/* code: NODATA stays, outlets (grid edge, next to nodata) TD_FL_ROOT |
 * DRAIN, the rest 0; z = dem; labels 0. */
/* Row y of code, given whether rows y-1, y, y+1 hold nodata (nd3). */
static void outlet_row(pf *p, int y, int nd3)
{
    size_t w = (size_t)p->w;
    uint8_t *c = p->code + (size_t)y * w;
    int x, k;
    if (y == 0 || y == p->h - 1) { /* edge rows: all outlets */
        for (x = 0; x < p->w; x++)
            c[x] = c[x] == TD_FL_NODATA ? TD_FL_NODATA : TD_FL_ROOT | DRAIN;
        return;
    }
    if (!nd3) { /* no nodata nearby */
        memset(c, 0, w);
        c[0] = c[w - 1] = TD_FL_ROOT | DRAIN;
        return;
    }
    for (x = 0; x < p->w; x++) {
        int out = x == 0 || x == p->w - 1;
        if (c[x] == TD_FL_NODATA)
            continue;
        for (k = 0; k < 9 && !out; k++) /* k = 4: the cell, valid */
            out = c[x + p->off[k]] == TD_FL_NODATA;
        c[x] = out ? TD_FL_ROOT | DRAIN : 0;
    }
}

/* Rows on threads; a row next to nodata reads its neighbours' codes, so
 * those rows are done after, on one thread.  0 or TD_ENOMEM. */
static int mark_outlets(pf *p)
{
    size_t w = (size_t)p->w;
    uint8_t *nd = malloc((size_t)p->h + 2);
    int y, any = 0;
    if (!nd)
        return td_seterr(p->cx, TD_ENOMEM, "flow: out of memory");
    nd[0] = nd[p->h + 1] = 0; /* nd[y + 1]: row y holds nodata */
#pragma omp parallel for num_threads(p->nth) schedule(static) \
    reduction(| : any)
    for (y = 0; y < p->h; y++) {
        size_t o = (size_t)y * w;
        memcpy(p->z + o, p->dem + o, w * sizeof *p->z);
        memset(p->lab + o, 0, w * sizeof *p->lab);
        nd[y + 1] = memchr(p->code + o, TD_FL_NODATA, w) != NULL;
        any |= nd[y + 1];
    }
#pragma omp parallel for num_threads(p->nth) schedule(static)
    for (y = 0; y < p->h; y++)
        if (!(nd[y] | nd[y + 1] | nd[y + 2]))
            outlet_row(p, y, 0);
    for (y = 0; any && y < p->h; y++)
        if (nd[y] | nd[y + 1] | nd[y + 2])
            outlet_row(p, y, 1);
    free(nd);
    return 0;
}

/* ---- drained cells, 64 columns per word ------------------------------- */

/* Bit j: a[j] <= b[j], for j < n (n <= 64). */
static uint64_t le_bits(const float *a, const float *b, int n)
{
    uint64_t m = 0;
    int j = 0;
#ifdef __SSE2__
    for (; j + 4 <= n; j += 4)
        m |= (uint64_t)_mm_movemask_ps(_mm_cmple_ps(_mm_loadu_ps(a + j),
                                                    _mm_loadu_ps(b + j)))
             << j;
#endif
    for (; j < n; j++)
        m |= (uint64_t)(a[j] <= b[j]) << j;
    return m;
}

/* Bit j: (b[j] & mask) != 0, for j < n (n <= 64). */
static uint64_t byte_bits(const uint8_t *b, uint8_t mask, int n)
{
    uint64_t m = 0;
    int j = 0;
#ifdef __SSE2__
    const __m128i k = _mm_set1_epi8((char)mask), z = _mm_setzero_si128();
    for (; j + 16 <= n; j += 16) {
        __m128i v = _mm_and_si128(_mm_loadu_si128((const __m128i *)(b + j)),
                                  k);
        m |= (uint64_t)(~(unsigned)_mm_movemask_epi8(_mm_cmpeq_epi8(v, z)) &
                        0xFFFFu)
             << j;
    }
#endif
    for (; j < n; j++)
        m |= (uint64_t)((b[j] & mask) != 0) << j;
    return m;
}

/* The bits of columns [lo, hi) in the word whose bit 0 is column b. */
static uint64_t span_bits(int b, int lo, int hi)
{
    int l = lo - b < 0 ? 0 : lo - b, h = hi - b > 64 ? 64 : hi - b;
    if (h <= l)
        return 0;
    return (h == 64 ? ~0ull : (1ull << h) - 1) & ~((1ull << l) - 1);
}

/* Carry propagation (g and p disjoint): bit j of the result is g[j] |
 * (p[j] & result[j - 1]), result[-1] = *cin; *cin becomes bit 63.  The
 * carries of (g | p) + g are exactly that chain. */
static uint64_t spread(uint64_t g, uint64_t p, uint64_t *cin)
{
    uint64_t a = g | p, r = g | (p & ((a + g + *cin) ^ a ^ g));
    *cin = r >> 63;
    return r;
}

static uint64_t bit_reverse(uint64_t v)
{
    v = __builtin_bswap64(v);
    v = (v >> 4 & 0x0F0F0F0F0F0F0F0Full) | (v & 0x0F0F0F0F0F0F0F0Full) << 4;
    v = (v >> 2 & 0x3333333333333333ull) | (v & 0x3333333333333333ull) << 2;
    return (v >> 1 & 0x5555555555555555ull) |
           (v & 0x5555555555555555ull) << 1;
}

/* Drain step of row y from row py (the row before it in the sweep), in
 * columns [x0, x1): a cell drains when a drained cell of row py next to it
 * (or above/below it) is not higher, then along the row both ways through
 * cells not lower than the one before.  64 columns per word, no branch
 * per cell: the run along the row is the carry chain of an addition.
 * Scratch: 3 words per 64 columns.  Returns the drained cells of the
 * row. */
static size_t drain_row(pf *p, int y, int py, int x0, int x1, uint64_t *buf)
{
    size_t w = (size_t)p->w, got = 0;
    uint8_t *restrict c = p->code + (size_t)y * w;
    const uint8_t *restrict pc = p->code + (size_t)py * w;
    const float *z = p->z + (size_t)y * w, *pz = p->z + (size_t)py * w;
    int xa = x0 > 1 ? x0 : 1, xb = x1 < p->w - 1 ? x1 : p->w - 1;
    int lo = xa > x0 ? xa : x0 + 1, hi = xb < x1 ? xb : x1 - 1;
    int nw = (x1 - x0 + 63) / 64, k;
    uint64_t *dp = buf, *d = buf + nw, *v = buf + 2 * nw, cin = 0;
    for (k = 0; k < nw; k++) {
        int b = x0 + 64 * k, n = x1 - b < 64 ? x1 - b : 64;
        dp[k] = byte_bits(pc + b, DRAIN, n);
    }
    for (k = 0; k < nw; k++) { /* from row py */
        int b = x0 + 64 * k, n = x1 - b < 64 ? x1 - b : 64, last = k == nw - 1;
        uint64_t cm = le_bits(pz + b, z + b, n);
        uint64_t cl = k == 0 ? le_bits(pz + b, z + b + 1, n - 1) << 1
                             : le_bits(pz + b - 1, z + b, n);
        uint64_t cr = le_bits(pz + b + 1, z + b, last ? n - 1 : n);
        uint64_t dl = dp[k] << 1 | (k > 0 ? dp[k - 1] >> 63 : 0);
        uint64_t dr = dp[k] >> 1 | (!last ? dp[k + 1] << 63 : 0);
        v[k] = span_bits(b, b, b + n) & ~byte_bits(c + b, NOD, n);
        d[k] = byte_bits(c + b, DRAIN, n) |
               (v[k] & span_bits(b, xa, xb) &
                ((dp[k] & cm) | (dl & cl) | (dr & cr)));
    }
    for (k = 0; k < nw; k++) { /* along the row, left to right */
        int b = x0 + 64 * k, n = x1 - b < 64 ? x1 - b : 64;
        uint64_t e = k == 0 ? le_bits(z + b, z + b + 1, n - 1) << 1
                            : le_bits(z + b - 1, z + b, n);
        d[k] = spread(d[k], e & v[k] & span_bits(b, lo, xb) & ~d[k], &cin);
    }
    for (k = nw - 1, cin = 0; k >= 0; k--) { /* right to left */
        int b = x0 + 64 * k, n = x1 - b < 64 ? x1 - b : 64, last = k == nw - 1;
        uint64_t e = le_bits(z + b + 1, z + b, last ? n - 1 : n);
        uint64_t pm = e & v[k] & span_bits(b, xa, hi) & ~d[k];
        uint64_t m;
        d[k] = bit_reverse(spread(bit_reverse(d[k]), bit_reverse(pm), &cin));
        got += (size_t)__builtin_popcountll(d[k] & span_bits(b, xa, hi));
        for (m = d[k] & ~byte_bits(c + b, DRAIN, n); m; m &= m - 1)
            c[b + __builtin_ctzll(m)] |= DRAIN;
    }
    return got;
}

/* Drained cells: those with a path to an outlet that never climbs.  Their
 * level is their height, so the tile floods start from them and never
 * visit the others (on smooth DEMs most cells; on white noise almost
 * none).  Any subset would do: two raster sweeps (down, then up), each
 * propagating from the row before and along the row both ways, find on
 * generated hills as many as a full search uphill from the outlets (88.4%
 * of the cells; a third sweep adds none) at a third of its cost (the
 * search jumps about the grid).  The outlets carry DRAIN already.  A
 * sweep stops after 32 rows in a row with under 1% drained (white noise:
 * then the flood does it all and the sweeps would only cost).  On threads,
 * each in its own strip of columns, reading only its own cells (paths that
 * cross a strip border are not followed: fewer cells, the same fill). */
static void drain_sweeps(pf *p)
{
    int t, ns = p->nth > 1 && p->w >= 64 * p->nth ? p->nth : 1;
#pragma omp parallel for num_threads(ns) schedule(static, 1)
    for (t = 0; t < ns; t++) {
        int x0 = (int)((long long)p->w * t / ns);
        int x1 = (int)((long long)p->w * (t + 1) / ns), y, poor = 0;
        size_t few = (size_t)(x1 - x0) / 100;
        uint64_t *buf = malloc(3 * (size_t)((x1 - x0 + 63) / 64) *
                               sizeof *buf);
        if (!buf) /* no sweep: the floods do it all */
            continue;
        for (y = 1; y < p->h - 1 && poor < 32; y++)
            poor = drain_row(p, y, y - 1, x0, x1, buf) <= few ? poor + 1 : 0;
        for (y = p->h - 2, poor = 0; y >= 1 && poor < 32; y--)
            poor = drain_row(p, y, y + 1, x0, x1, buf) <= few ? poor + 1 : 0;
        free(buf);
    }
}

/* Raise every cell to its label's level; codes back to ROOT / 0.  No
 * branch per cell: label 0 (drained, nodata) reads W[0] = -FLT_MAX. */
static void apply(pf *p, const float *W, double *raised)
{
    int ty;
    size_t r = 0;
#pragma omp parallel for num_threads(p->nth) schedule(dynamic, 1) \
    reduction(+ : r)
    for (ty = 0; ty < p->nty; ty++) {
        int tx, x, y;
        for (y = ty * p->ts; y < p->h && y < (ty + 1) * p->ts; y++)
            for (tx = 0; tx < p->ntx; tx++) {
                uint32_t base = p->base[ty * p->ntx + tx];
                int xe = (tx + 1) * p->ts < p->w ? (tx + 1) * p->ts : p->w;
                size_t i = (size_t)y * (size_t)p->w + (size_t)tx * p->ts;
                uint8_t *restrict code = p->code;
                float *restrict z = p->z;
                for (x = tx * p->ts; x < xe; x++, i++) {
                    uint8_t c = code[i];
                    unsigned l = p->lab[i];
                    float wv = W[l ? base + l : 0], zz = z[i];
                    zz = wv > zz ? wv : zz;
                    z[i] = zz;
                    code[i] = c & (uint8_t)(15u | (0u - (c & NOD)));
                    r += zz > p->dem[i];
                }
            }
    }
    if (raised)
        *raised = (double)r;
}

int td_flow_fill_tiles(const float *dem, float *z, uint8_t *code, int w, int h,
              int tile, int threads, double *raised, double p0, double p1,
              td_ctx *cx)
{
    pf p;
    float *W = NULL;
    size_t nt;
    int k, rc = 0;
    memset(&p, 0, sizeof p);
    if ((double)w * h > (double)UINT32_MAX - 2)
        return td_seterr(cx, TD_EINVAL, "flow: %dx%d is more than 2^32 - 2 "
                         "cells", w, h);
    p.dem = dem;
    p.z = z;
    p.code = code;
    p.w = w;
    p.h = h;
    p.ts = tile <= 0 ? TD_PFLOOD_TILE : tile < 2 ? 2 : tile > 4096 ? 4096
                                                                   : tile;
    p.ntx = (w + p.ts - 1) / p.ts;
    p.nty = (h + p.ts - 1) / p.ts;
    p.nlab = 1;
    p.nth = threads > 0 ? threads : omp_get_max_threads();
    p.cx = cx;
    for (k = 0; k < 9; k++)
        p.off[k] = (ptrdiff_t)(k / 3 - 1) * w + k % 3 - 1;
    nt = (size_t)p.ntx * (size_t)p.nty;
    p.lab = malloc((size_t)w * (size_t)h * sizeof *p.lab);
    p.base = malloc(nt * sizeof *p.base);
    p.tr = calloc(nt, sizeof *p.tr);
    if (!p.lab || !p.base || !p.tr) {
        rc = td_seterr(cx, TD_ENOMEM, "flow: out of memory");
        goto fail;
    }
    rc = mark_outlets(&p);
    if (rc == 0) {
        drain_sweeps(&p);
        rc = flood_tiles(&p, p0, p0 + 0.9 * (p1 - p0));
    }
    if (rc == 0)
        rc = gather(&p);
    if (rc == 0)
        rc = tile_borders(&p);
    if (rc == 0 && !(W = malloc((size_t)p.nlab * sizeof *W)))
        rc = td_seterr(cx, TD_ENOMEM, "flow: out of memory");
    if (rc == 0)
        rc = solve(&p, W);
    if (rc == 0)
        apply(&p, W, raised);
fail:
    if (p.tr)
        for (k = 0; k < (int)nt; k++) {
            free(p.tr[k].key);
            free(p.tr[k].w);
        }
    free(p.tr);
    free(p.e);
    free(p.base);
    free(p.lab);
    free(W);
    return rc;
}
