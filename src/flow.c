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
#include "flow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { ROOT = 8, NODATA = 9, DONE = 10, STOP = 11, UNSEEN = 0xFF };

static const int DX[8] = {1, 1, 0, -1, -1, -1, 0, 1};
static const int DY[8] = {0, 1, 1, 1, 0, -1, -1, -1};
#define INV_SQRT2 0.70710678118654752440
#define PI_4 0.78539816339744830962

typedef struct u32vec {
    uint32_t *v;
    size_t n, cap;
} u32vec;

typedef struct hnode {
    uint32_t key; /* order-preserving image of the height (fkey) */
    uint32_t i;
} hnode;

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

/* All neighbours of cell i at once into j[8]; returns the bit mask of
 * those on the grid (one division per cell instead of one per neighbour). */
static unsigned nbrs(const fgrid *g, size_t i, size_t j[8])
{
    int x = (int)(i % (size_t)g->w), y = (int)(i / (size_t)g->w), k;
    unsigned m = 0;
    for (k = 0; k < 8; k++) {
        int xx = x + DX[k], yy = y + DY[k];
        j[k] = i + (size_t)g->off[k];
        if (xx >= 0 && yy >= 0 && xx < g->w && yy < g->h)
            m |= 1u << k;
    }
    return m;
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
    size_t i;
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
    *valid = 0;
    for (i = 0; i < g->n; i++) {
        float v = dem->data[i];
        int nd = isnan(v) || (dem->has_nodata && v == dem->nodata);
        g->code[i] = nd ? NODATA : fill;
        *valid += !nd;
    }
    out->nodata = dem->nodata;
    out->has_nodata = dem->has_nodata;
    return 0;
}

/* ---- priority-flood depression filling ---------------------------------
 * Barnes, Lehman, Mulla (2014) "Priority-Flood", Alg. 2 (a FIFO for cells
 * inside depressions), plus upslope tracing (after Zhou, Sun, Fu 2016): a
 * cell higher than the current level whose unseen neighbours are all at
 * least as high gets its final level (its own height) whatever the order,
 * so it and its upslope cells are visited at once, off the heap.  code
 * holds UNSEEN, then the direction to the cell that reached it (the flood
 * tree: filled pits and flats drain along it) or ROOT for the seeds. */
typedef struct rbucket {
    hnode *v;
    size_t n, cap;
} rbucket;

/* A radix heap (Ahuja, Mehlhorn, Orlin, Tarjan 1990): a monotone priority
 * queue, valid because the flood never pushes a key below the last one
 * popped.  Bucket b holds keys whose highest bit differing from `last` is
 * bit b - 1 (bucket 0: equal to last); push is O(1), each entry moves to
 * lower buckets at most 32 times. */
typedef struct rheap {
    rbucket b[33];
    uint32_t last;
    size_t n;
} rheap;

typedef struct flood {
    fgrid *g;
    int dirs; /* D8: decide directions and upstream counts while flooding */
    rheap heap;
    u32vec fifo, stack;
    size_t fhead;
    double raised, peak;
} flood;

/* Heights -> unsigned keys with the same order (-0 as +0). */
static uint32_t fkey(float z)
{
    uint32_t u;
    z += 0.0f;
    memcpy(&u, &z, sizeof u);
    return (u & 0x80000000u) ? ~u : u | 0x80000000u;
}

static int rbucket_of(uint32_t x)
{
    return x ? 32 - __builtin_clz(x) : 0;
}

static int rb_push(rbucket *b, hnode e, td_ctx *cx)
{
    if (b->n == b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 1024;
        hnode *v = realloc(b->v, cap * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "flow: out of memory");
        b->v = v;
        b->cap = cap;
    }
    b->v[b->n++] = e;
    return 0;
}

static int heap_push(flood *f, float z, uint32_t i)
{
    hnode e;
    e.key = fkey(z);
    e.i = i;
    f->heap.n++;
    return rb_push(&f->heap.b[rbucket_of(e.key ^ f->heap.last)], e,
                   f->g->cx);
}

/* Pop an entry of the smallest key (the heap is not empty). */
static uint32_t heap_pop(flood *f)
{
    rheap *h = &f->heap;
    if (h->b[0].n == 0) {
        rbucket *src;
        size_t m;
        int j = 1;
        while (h->b[j].n == 0)
            j++;
        src = &h->b[j];
        h->last = src->v[0].key;
        for (m = 1; m < src->n; m++)
            if (src->v[m].key < h->last)
                h->last = src->v[m].key;
        for (m = 0; m < src->n; m++) { /* into lower buckets: no growth */
            rbucket *dst = &h->b[rbucket_of(src->v[m].key ^ h->last)];
            if (dst->n == dst->cap) {
                hnode e = src->v[m];
                if (rb_push(dst, e, NULL) != 0) /* rare: grow the target */
                    return UINT32_MAX;
            } else
                dst->v[dst->n++] = src->v[m];
        }
        src->n = 0;
    }
    h->n--;
    return h->b[0].v[--h->b[0].n].i;
}

/* Move every other entry at the level just popped into the FIFO: a flat
 * then grows breadth-first from all of its exits together. */
static int heap_drain_level(flood *f)
{
    rbucket *b0 = &f->heap.b[0];
    int rc = 0;
    while (b0->n > 0 && rc == 0) {
        rc = u32_push(&f->fifo, b0->v[--b0->n].i, f->g->cx);
        f->heap.n--;
    }
    return rc;
}

static void heap_free(flood *f)
{
    int b;
    for (b = 0; b < 33; b++)
        free(f->heap.b[b].v);
}

/* 1 when every unseen neighbour of i is higher than i (equal ones would
 * make a flat, which is left to the in-order FIFO so that it drains by
 * breadth-first search from all its exits at once). */
static int traceable(const fgrid *g, size_t i)
{
    const float *z = g->z, zi = g->z[i]; /* unseen cells: their heights */
    const uint8_t *code = g->code;
    int k;
    int low = 0;
    for (k = 0; k < 8; k++) { /* i is reached, not a seed: off the edge */
        size_t j = i + (size_t)g->off[k]; /* no early exit: loads overlap */
        low |= (code[j] == UNSEEN) & (z[j] <= zi);
    }
    return !low;
}

/* Steepest descent (drop / distance) from c over the neighbour in slot k
 * of jj: keeps the best in *best, *bs (d8 rule, first of equals). */
static void d8_try(float zc, float zj, int k, int *best, double *bs)
{
    double d = (double)zc - (double)zj;
    if (k & 1)
        d *= INV_SQRT2;
    if (d > *bs) {
        *bs = d;
        *best = k;
    }
}

/* Reach the unseen neighbours of c.  in_order: c is at the lowest level of
 * the whole frontier, so lower neighbours drain through c (fill them).
 * f->dirs (D8): every neighbour lower than c is already reached with its
 * final level (the flood never reaches a cell below the level it pops),
 * so c's steepest descent on the filled DEM is decided here, and its
 * receiver's upstream count (high nibble) is raised. */
static int flood_visit(flood *f, uint32_t c, int in_order)
{
    fgrid *g = f->g;
    float zc = g->z[c], zn[8];
    size_t jj[8], j;
    uint8_t cc = g->code[c], cn[8];
    unsigned m = (cc & 15) == ROOT ? nbrs(g, c, jj) : nbrs_in(g, c, jj);
    int k, rc = 0, best = -1;
    double bs = 0;
    /* all 16 loads first, none behind a branch: a popped cell's block is
     * often out of the cache, and so its misses overlap (only this cell's
     * visit writes these neighbours, each its own) */
    if (m == 0xFFu)
        for (k = 0; k < 8; k++)
            cn[k] = g->code[jj[k]], zn[k] = g->z[jj[k]];
    else
        for (k = 0; k < 8; k++)
            if (m >> k & 1)
                cn[k] = g->code[jj[k]], zn[k] = g->z[jj[k]];
            else
                cn[k] = NODATA, zn[k] = 0;
    for (k = 0; k < 8 && rc == 0; k++) {
        j = jj[k];
        if (cn[k] != UNSEEN) {
            if (f->dirs && (cn[k] & 15) != NODATA && zn[k] < zc)
                d8_try(zc, zn[k], k, &best, &bs); /* only lower ones count */
            continue;
        }
        g->code[j] = (uint8_t)((k + 4) & 7);
        if (in_order && zn[k] <= zc) { /* z[j] is still dem[j] */
            f->raised += zn[k] < zc;
            g->z[j] = zc;
            rc = u32_push(&f->fifo, (uint32_t)j, g->cx);
        } else {
            rc = traceable(g, j) ? u32_push(&f->stack, (uint32_t)j, g->cx)
                                 : heap_push(f, zn[k], (uint32_t)j);
        }
    }
    if (f->dirs && (cc & 15) != ROOT) {
        if (best >= 0) /* else the flood-tree direction (a flat) */
            g->code[c] = cc = (uint8_t)((cc & 0xF0) | best);
        g->code[c + (size_t)g->off[cc & 15]] += 16;
    }
    return rc;
}

/* Seeds: valid cells on the grid edge or next to nodata (raster order). */
static int flood_seeds(flood *f, int any_nodata)
{
    fgrid *g = f->g;
    size_t i, j[8];
    int x, y, k, rc = 0;
    for (y = 0, i = 0; y < g->h && rc == 0; y++)
        for (x = 0; x < g->w && rc == 0; x++, i++) {
            int seed = x == 0 || y == 0 || x == g->w - 1 || y == g->h - 1;
            if (g->code[i] == NODATA)
                continue;
            if (!seed && any_nodata) {
                nbrs_in(g, i, j);
                for (k = 0; k < 8 && !seed; k++)
                    seed = g->code[j[k]] == NODATA;
            }
            if (!seed)
                continue;
            g->code[i] = ROOT;
            rc = heap_push(f, g->z[i], (uint32_t)i);
        }
    return rc;
}

/* Fill g->z from g->dem; g->code: NODATA or UNSEEN on entry, flood-tree
 * directions on return.  g->z starts as a copy of the DEM and is raised in
 * place: an unseen cell's z is its DEM height, a reached cell's its final
 * level, so the flood reads one height array, not two (less memory
 * traffic).  Progress from p0 to p1. */
static int flood_run(fgrid *g, int dirs, double valid, double p0, double p1,
                     td_flow_stats *st)
{
    flood f;
    double seen = 0;
    int rc;
    memset(&f, 0, sizeof f);
    f.g = g;
    f.dirs = dirs;
    if (g->z != g->dem)
        memcpy(g->z, g->dem, g->n * sizeof *g->z);
    rc = flood_seeds(&f, valid < (double)g->n);
    while (rc == 0) {
        uint32_t c;
        int in_order = 1;
        size_t q = f.heap.n + f.stack.n + f.fifo.n - f.fhead;
        if ((double)q > f.peak)
            f.peak = (double)q;
        if (f.fhead < f.fifo.n)
            c = f.fifo.v[f.fhead++];
        else if (f.stack.n > 0) {
            c = f.stack.v[--f.stack.n];
            in_order = 0;
        } else if (f.heap.n > 0) {
            if ((c = heap_pop(&f)) == UINT32_MAX) {
                rc = td_seterr(g->cx, TD_ENOMEM, "flow: out of memory");
                break;
            }
            if ((rc = heap_drain_level(&f)) != 0)
                break;
        } else
            break;
        if (f.fhead == f.fifo.n)
            f.fhead = f.fifo.n = 0;
        rc = flood_visit(&f, c, in_order);
        if (rc == 0 && ((size_t)++seen & 0xFFFFF) == 0)
            rc = td_progress(g->cx, "flow", p0 + (p1 - p0) * seen / valid);
    }
    if (rc == 0 && seen != valid)
        rc = td_seterr(g->cx, TD_EINTERNAL, "flow: flood reached %.0f of "
                       "%.0f cells", seen, valid);
    if (st) {
        st->raised = f.raised;
        st->queue_peak = f.peak;
    }
    heap_free(&f);
    free(f.fifo.v);
    free(f.stack.v);
    return rc;
}

int td_flow_fill(const td_grid_f32 *dem, td_grid_f32 *filled, td_ctx *cx)
{
    fgrid g;
    double valid = 0.0;
    size_t i;
    int rc = fgrid_init(&g, dem, filled, UNSEEN, &valid, cx);
    if (rc == 0)
        rc = flood_run(&g, 0, valid, 0.0, 1.0, NULL);
    if (rc == 0)
        for (i = 0; i < g.n; i++)
            if (g.code[i] == NODATA)
                g.z[i] = dem->nodata;
    free(g.code);
    return rc;
}

/* ---- D8 -----------------------------------------------------------------
 * Seeds (edge cells, cells next to nodata) are outlets (ROOT): their water
 * leaves the grid.  Other cells: steepest descent (drop / distance) on the
 * filled DEM, decided while flooding (flood_visit); a cell with no lower
 * neighbour keeps its flood-tree direction (filled pits and flats drain
 * towards their spill point).  Every edge goes strictly down or along the
 * flood tree, so the graph has no cycles. */
/* D8 counts are uint32 stored in the float buffer g->z (after the filled
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

/* Follow one chain from a cell with nothing left upstream, adding counts
 * downstream until a cell that still waits for another upstream cell. */
static void d8_chain(fgrid *g, size_t c, td_flow_stats *st, double *done)
{
    for (;;) {
        int k = g->code[c] & 15;
        uint32_t a = getu(g, c);
        size_t r;
        g->code[c] = DONE;
        ++*done;
        if (k == ROOT) {
            st->outflow += a;
            st->outlets++;
            return;
        }
        r = c + (size_t)g->off[k];
        setu(g, r, getu(g, r) + a);
        g->code[r] = (uint8_t)(g->code[r] - 16);
        if (g->code[r] >> 4)
            return;
        c = r;
    }
}

static int d8_accumulate(fgrid *g, double valid, td_flow_stats *st)
{
    size_t i;
    double done = 0;
    for (i = 0; i < g->n; i++) /* upstream counts are in code already */
        setu(g, i, is_valid(g, i) ? 1u : 0u);
    for (i = 0; i < g->n; i++) {
        uint8_t c = g->code[i];
        if ((c & 15) <= ROOT && (c >> 4) == 0)
            d8_chain(g, i, st, &done);
        if ((i & 0xFFFFF) == 0 &&
            td_progress(g->cx, "flow", 0.8 + 0.2 * (double)i / g->n) != 0)
            return TD_ECANCEL;
    }
    if (done != valid)
        return td_seterr(g->cx, TD_EINTERNAL, "flow: D8 accumulated %.0f of "
                         "%.0f cells", done, valid);
    return 0;
}

/* ---- D-infinity (Tarboton 1997) -----------------------------------------
 * Eight triangular facets, each a cardinal neighbour e1 and the diagonal e2
 * next to it.  s1 = e0 - e1, s2 = e1 - e2 (unit spacing); direction
 * r = atan(s2 / s1) clamped to [0, pi/4] (slope s1 at 0, (e0 - e2)/sqrt 2 at
 * pi/4, else hypot(s1, s2)); the steepest facet's flow is split e1 : e2 =
 * (1 - r/(pi/4)) : r/(pi/4).  Every receiver with a share is strictly lower;
 * with no positive facet the flood-tree direction is used, as in D8. */
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
static void store(fgrid *g, const double *acc, float nodata,
                  td_flow_stats *st)
{
    size_t i;
    for (i = 0; i < g->n; i++) {
        double v = acc ? acc[i] : (double)getu(g, i);
        if (!is_valid(g, i)) {
            g->z[i] = nodata;
            continue;
        }
        g->z[i] = (float)v;
        if (v > st->max_pass)
            st->max_pass = v;
    }
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
        p->max_steps < 0) {
        rc = td_seterr(cx, TD_EINVAL, "flow: bad parameters");
        goto fail;
    }
    rc = fgrid_init(&g, dem, passes, p->method == TD_FLOW_SOBEL ? 0 : UNSEEN,
                    &s.cells, cx);
    if (rc == 0)
        rc = td_progress(cx, "flow", 0.0);
    if (rc != 0)
        goto fail;
    if (p->method == TD_FLOW_SOBEL) {
        long ms = p->max_steps ? p->max_steps : 4L * (g.w + g.h);
        rc = sobel_run(&g, ms, &s);
    } else if ((rc = flood_run(&g, p->method == TD_FLOW_D8, s.cells, 0.0,
                               p->method == TD_FLOW_D8 ? 0.8 : 0.6,
                               &s)) == 0) {
        if (p->method == TD_FLOW_D8)
            rc = d8_accumulate(&g, s.cells, &s);
        else if ((acc = td_malloc(g.n * sizeof *acc, cx)) == NULL)
            rc = TD_ENOMEM;
        else
            rc = dinf_accumulate(&g, acc, s.cells, &s);
    }
    if (rc != 0)
        goto fail;
    store(&g, acc, dem->nodata, &s);
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
