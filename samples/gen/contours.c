/* contours.c: true contour polylines of a DEM by marching squares.
 *
 * Cells join four pixel centres; a DEM value (i,j) sits at x = j + 0.5,
 * y = i + 0.5.  Corners and edges of cell (i,j), in cyclic order:
 *
 *        a (i,j) ----T(0)---- b (i,j+1)
 *          |                    |
 *        L(3)                 R(1)
 *          |                    |
 *      d (i+1,j) ---B(2)--- c (i+1,j+1)
 *
 * Each sample gets a band index k, the largest with base + k * interval <= v;
 * a sample is "above" level k when its band >= k, i.e. a sample exactly on a
 * level counts as above it (the level is nudged down by an infinitesimal), and
 * crossing points are kept 1e-7 px inside their edge, so no vertex sits on
 * a sample and no segment has zero length (a ring around a peak exactly on
 * its level is a point and is dropped).  A cell whose corners' bands
 * differ is crossed by every level between them; for each, an edge whose
 * cyclic order goes above -> below starts a segment and one going below ->
 * above ends one, so every segment keeps the higher ground on its right (on
 * screen, y down) and segments chain head to tail.  Saddles (two starts)
 * are resolved by the mean of the four corners: centre above -> each start
 * joins the next edge (the above corners connect), else the previous one.
 *
 * Linking: a crossing (edge, level) is shared by the two cells beside the
 * edge.  Open chain ends wait in a hash keyed by crossing; a chain whose
 * tail meets its own head is a ring and leaves memory at once.  The hash
 * holds only the frontier (the chains crossing the current row), so memory
 * beyond the DEM is O(output). */
#include "samples/gen/gen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define EMPTY UINT64_MAX
#define NONE UINT32_MAX
#define T_EPS 1e-7

typedef struct chain {
    double *buf;         /* points lo..hi-1, x,y interleaved */
    size_t lo, hi, cap;  /* in points */
    uint64_t head, tail; /* crossing ids of the first and last point */
    long k;              /* level index */
} chain;

typedef struct endmap {
    uint64_t *key;
    uint32_t *val;
    size_t cap, n;
} endmap;

typedef struct ms {
    const td_grid_f32 *dem;
    double base, interval;
    long kfirst; /* lowest level index that can occur */
    uint64_t nlev;
    chain *ch;
    size_t nch, capch;
    uint32_t *freel; /* free chain slots */
    size_t nfree;
    endmap m;
    td_lines *out;
    td_ctx *cx;
} ms;

/* ---- hash of chain ends: open addressing, linear probing ---- */

static size_t hmix(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return (size_t)k;
}

static uint32_t map_get(const endmap *m, uint64_t k)
{
    size_t mask = m->cap - 1, i = hmix(k) & mask;
    while (m->key[i] != EMPTY) {
        if (m->key[i] == k)
            return m->val[i];
        i = (i + 1) & mask;
    }
    return NONE;
}

static int map_put(endmap *m, uint64_t k, uint32_t v, td_ctx *cx);

static int map_grow(endmap *m, td_ctx *cx)
{
    endmap old = *m;
    size_t i, cap = old.cap ? old.cap * 2 : 1024;
    m->key = td_malloc(cap * sizeof *m->key, cx);
    m->val = td_malloc(cap * sizeof *m->val, cx);
    if (!m->key || !m->val) {
        free(m->key);
        free(m->val);
        *m = old;
        return TD_ENOMEM;
    }
    for (i = 0; i < cap; i++)
        m->key[i] = EMPTY;
    m->cap = cap;
    m->n = 0;
    for (i = 0; i < old.cap; i++)
        if (old.key[i] != EMPTY)
            map_put(m, old.key[i], old.val[i], cx);
    free(old.key);
    free(old.val);
    return 0;
}

static int map_put(endmap *m, uint64_t k, uint32_t v, td_ctx *cx)
{
    size_t mask, i;
    if (2 * (m->n + 1) > m->cap && map_grow(m, cx) != 0)
        return TD_ENOMEM;
    mask = m->cap - 1;
    i = hmix(k) & mask;
    while (m->key[i] != EMPTY && m->key[i] != k)
        i = (i + 1) & mask;
    if (m->key[i] == EMPTY)
        m->n++;
    m->key[i] = k;
    m->val[i] = v;
    return 0;
}

/* Remove k (backward-shift deletion keeps probe chains intact). */
static void map_del(endmap *m, uint64_t k)
{
    size_t mask = m->cap - 1, i = hmix(k) & mask, j;
    while (m->key[i] != k) {
        if (m->key[i] == EMPTY)
            return;
        i = (i + 1) & mask;
    }
    j = i;
    for (;;) {
        size_t home;
        j = (j + 1) & mask;
        if (m->key[j] == EMPTY)
            break;
        home = hmix(m->key[j]) & mask;
        /* move j back to i unless its home lies cyclically in (i, j] */
        if ((i <= j) ? (home <= i || home > j) : (home <= i && home > j)) {
            m->key[i] = m->key[j];
            m->val[i] = m->val[j];
            i = j;
        }
    }
    m->key[i] = EMPTY;
    m->n--;
}

/* ---- chains: double-ended point buffers ---- */

/* Make room for `front` points before and `back` points after the data. */
static int chain_reserve(chain *c, size_t front, size_t back, td_ctx *cx)
{
    size_t n = c->hi - c->lo, cap, lo;
    double *nb;
    if (c->lo >= front && c->cap - c->hi >= back)
        return 0;
    cap = 2 * (n + front + back) + 16;
    lo = front + (cap - n - front - back) / 2;
    nb = td_malloc(cap * 2 * sizeof(double), cx);
    if (!nb)
        return TD_ENOMEM;
    if (n)
        memcpy(nb + 2 * lo, c->buf + 2 * c->lo, n * 2 * sizeof(double));
    free(c->buf);
    c->buf = nb;
    c->lo = lo;
    c->hi = lo + n;
    c->cap = cap;
    return 0;
}

static uint32_t chain_new(ms *s)
{
    uint32_t id;
    if (s->nfree)
        return s->freel[--s->nfree];
    if (s->nch == s->capch) {
        size_t cap = s->capch ? 2 * s->capch : 256;
        chain *nc = realloc(s->ch, cap * sizeof *nc);
        uint32_t *nf = realloc(s->freel, cap * sizeof *nf);
        if (nc)
            s->ch = nc;
        if (nf)
            s->freel = nf;
        if (!nc || !nf || cap >= NONE) {
            td_seterr(s->cx, TD_ENOMEM, "contours: out of memory");
            return NONE;
        }
        s->capch = cap;
    }
    id = (uint32_t)s->nch++;
    memset(&s->ch[id], 0, sizeof s->ch[id]);
    return id;
}

static void chain_release(ms *s, uint32_t id)
{
    free(s->ch[id].buf);
    memset(&s->ch[id], 0, sizeof s->ch[id]);
    s->freel[s->nfree++] = id;
}

/* Extent of a chain's points (max of width and height of its box). */
static double chain_extent(const chain *c)
{
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    size_t i;
    for (i = c->lo; i < c->hi; i++) {
        x0 = fmin(x0, c->buf[2 * i]);
        x1 = fmax(x1, c->buf[2 * i]);
        y0 = fmin(y0, c->buf[2 * i + 1]);
        y1 = fmax(y1, c->buf[2 * i + 1]);
    }
    return fmax(x1 - x0, y1 - y0);
}

/* Move a finished chain into the output as a td_line.  A ring around a
 * single sample lying exactly on its level (extent ~1e-7 px: the contour is
 * that point) is dropped. */
static int chain_emit(ms *s, uint32_t id, int closed)
{
    chain *c = &s->ch[id];
    td_line *l;
    size_t i;
    if (closed && chain_extent(c) < 1e-3) {
        chain_release(s, id);
        return 0;
    }
    if (!(l = td_lines_add(s->out, s->cx)))
        return TD_ENOMEM;
    l->closed = closed;
    l->edge = !closed;
    l->has_height = 1;
    l->height = s->base + (double)c->k * s->interval;
    for (i = c->lo; i < c->hi; i++)
        if (td_line_push(l, c->buf[2 * i], c->buf[2 * i + 1], s->cx) != 0)
            return TD_ENOMEM;
    /* higher ground on the right: a ring run anticlockwise on the screen
       (negative area, y down) has it outside */
    l->depression = closed && td_line_signed_area(l) < 0;
    chain_release(s, id);
    return 0;
}

/* Join chain a (tail meets the segment) and chain b (head meets it): the
 * shorter one's points move into the longer one. */
static int chain_merge(ms *s, uint32_t a, uint32_t b)
{
    chain *A = &s->ch[a], *B = &s->ch[b];
    size_t na = A->hi - A->lo, nb = B->hi - B->lo;
    if (na >= nb) {
        if (chain_reserve(A, 0, nb, s->cx) != 0)
            return TD_ENOMEM;
        memcpy(A->buf + 2 * A->hi, B->buf + 2 * B->lo, nb * 2 * sizeof(double));
        A->hi += nb;
        A->tail = B->tail;
        if (map_put(&s->m, 2 * A->tail + 1, a, s->cx) != 0)
            return TD_ENOMEM;
        chain_release(s, b);
    } else {
        if (chain_reserve(B, na, 0, s->cx) != 0)
            return TD_ENOMEM;
        B->lo -= na;
        memcpy(B->buf + 2 * B->lo, A->buf + 2 * A->lo, na * 2 * sizeof(double));
        B->head = A->head;
        if (map_put(&s->m, 2 * B->head, b, s->cx) != 0)
            return TD_ENOMEM;
        chain_release(s, a);
    }
    return 0;
}

/* Add segment p -> q (crossing ids and points) of level k.  Map keys:
 * 2*id for a chain head waiting at crossing id, 2*id+1 for a tail. */
static int link_seg(ms *s, uint64_t p, const double *pp, uint64_t q,
                    const double *qp, long k)
{
    uint32_t a = map_get(&s->m, 2 * p + 1), b = map_get(&s->m, 2 * q);
    chain *c;
    if (a != NONE)
        map_del(&s->m, 2 * p + 1);
    if (b != NONE)
        map_del(&s->m, 2 * q);
    if (a != NONE && b != NONE)
        return a == b ? chain_emit(s, a, 1) : chain_merge(s, a, b);
    if (a != NONE) {
        c = &s->ch[a];
        if (chain_reserve(c, 0, 1, s->cx) != 0)
            return TD_ENOMEM;
        c->buf[2 * c->hi] = qp[0];
        c->buf[2 * c->hi + 1] = qp[1];
        c->hi++;
        c->tail = q;
        return map_put(&s->m, 2 * q + 1, a, s->cx);
    }
    if (b != NONE) {
        c = &s->ch[b];
        if (chain_reserve(c, 1, 0, s->cx) != 0)
            return TD_ENOMEM;
        c->lo--;
        c->buf[2 * c->lo] = pp[0];
        c->buf[2 * c->lo + 1] = pp[1];
        c->head = p;
        return map_put(&s->m, 2 * p, b, s->cx);
    }
    if ((a = chain_new(s)) == NONE)
        return TD_ENOMEM;
    c = &s->ch[a];
    c->k = k;
    if (chain_reserve(c, 2, 2, s->cx) != 0)
        return TD_ENOMEM;
    c->buf[2 * c->hi] = pp[0];
    c->buf[2 * c->hi + 1] = pp[1];
    c->buf[2 * c->hi + 2] = qp[0];
    c->buf[2 * c->hi + 3] = qp[1];
    c->hi += 2;
    c->head = p;
    c->tail = q;
    if (map_put(&s->m, 2 * p, a, s->cx) != 0)
        return TD_ENOMEM;
    return map_put(&s->m, 2 * q + 1, a, s->cx);
}

static double dem_at(const td_grid_f32 *g, long r, long c)
{
    return g->data[(size_t)r * g->stride + (size_t)c];
}

/* Crossing of level k on edge e of cell (i,j): its id and point. */
static uint64_t crossing(const ms *s, int e, long i, long j, long k, double *pt)
{
    static const int dr[4] = {0, 0, 1, 0}, dc[4] = {0, 1, 0, 0};
    long r = i + dr[e], c = j + dc[e];
    int vert = e & 1;
    double L = s->base + (double)k * s->interval;
    double v0 = dem_at(s->dem, r, c);
    double v1 = vert ? dem_at(s->dem, r + 1, c) : dem_at(s->dem, r, c + 1);
    double t = (L - v0) / (v1 - v0);
    uint64_t eid = 2 * ((uint64_t)r * (uint64_t)s->dem->w + (uint64_t)c) + vert;
    if (!(t > T_EPS))
        t = T_EPS;
    if (t > 1.0 - T_EPS)
        t = 1.0 - T_EPS;
    pt[0] = c + 0.5 + (vert ? 0.0 : t);
    pt[1] = r + 0.5 + (vert ? t : 0.0);
    return eid * s->nlev + (uint64_t)(k - s->kfirst);
}

/* Segments of level k in cell (i,j); up[] = corners a,b,c,d above k. */
static int cell_level(ms *s, long i, long j, long k, const int *up,
                      const double *v)
{
    int e, start[4], n = 0, rc;
    for (e = 0; e < 4; e++)
        if (up[e] && !up[(e + 1) & 3])
            start[n++] = e;
    for (e = 0; e < n; e++) {
        int st = start[e], en;
        double pp[2], qp[2];
        uint64_t p, q;
        if (n == 1) {
            for (en = 0; en < 4; en++)
                if (!up[en] && up[(en + 1) & 3])
                    break;
        } else {
            double mean = 0.25 * (v[0] + v[1] + v[2] + v[3]);
            int centre_up = mean >= s->base + (double)k * s->interval;
            en = centre_up ? (st + 1) & 3 : (st + 3) & 3;
        }
        p = crossing(s, st, i, j, k, pp);
        q = crossing(s, en, i, j, k, qp);
        if ((rc = link_seg(s, p, pp, q, qp, k)) != 0)
            return rc;
    }
    return 0;
}

/* band = the largest k with base + k * interval <= v, found from the
 * quotient and corrected against the level values themselves, so that the
 * "above" test is exactly v >= level (and no libm floor call per sample). */
static void row_bands(const ms *s, long i, int *band)
{
    const float *r = s->dem->data + (size_t)i * s->dem->stride;
    double inv = 1.0 / s->interval;
    long j;
    for (j = 0; j < s->dem->w; j++) {
        double v = r[j], q = (v - s->base) * inv;
        int k = (int)q;
        k -= q < (double)k;
        k -= s->base + (double)k * s->interval > v;
        k += s->base + (double)(k + 1) * s->interval <= v;
        band[j] = k;
    }
}

static int cell_row(ms *s, long i, const int *b0, const int *b1)
{
    long j, k;
    for (j = 0; j + 1 < s->dem->w; j++) {
        int bd[4] = {b0[j], b0[j + 1], b1[j + 1], b1[j]};
        int lo = bd[0], hi = bd[0], e, rc;
        double v[4];
        if (bd[0] == bd[1] && bd[0] == bd[2] && bd[0] == bd[3])
            continue;
        for (e = 1; e < 4; e++) {
            lo = bd[e] < lo ? bd[e] : lo;
            hi = bd[e] > hi ? bd[e] : hi;
        }
        if (lo == hi)
            continue;
        v[0] = dem_at(s->dem, i, j);
        v[1] = dem_at(s->dem, i, j + 1);
        v[2] = dem_at(s->dem, i + 1, j + 1);
        v[3] = dem_at(s->dem, i + 1, j);
        for (k = (long)lo + 1; k <= hi; k++) {
            int up[4] = {bd[0] >= k, bd[1] >= k, bd[2] >= k, bd[3] >= k};
            if ((rc = cell_level(s, i, j, k, up, v)) != 0)
                return rc;
        }
    }
    return 0;
}

/* Level range of the DEM; rejects NaN and more than 10^7 levels. */
static int level_range(ms *s)
{
    const td_grid_f32 *g = s->dem;
    double lo = INFINITY, hi = -INFINITY, klo, khi;
    long i, j;
    for (i = 0; i < g->h; i++)
        for (j = 0; j < g->w; j++) {
            double v = dem_at(g, i, j);
            if (v != v)
                return td_seterr(s->cx, TD_EINVAL,
                                 "contours: DEM has NaN at (%ld,%ld)", j, i);
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    klo = floor((lo - s->base) / s->interval) - 1; /* margin for rounding */
    khi = floor((hi - s->base) / s->interval) + 1;
    if (khi - klo > 1e7 || fabs(klo) > 1e9 || fabs(khi) > 1e9)
        return td_seterr(s->cx, TD_EINVAL,
                         "contours: interval %g gives too many levels over "
                         "heights %g..%g",
                         s->interval, lo, hi);
    s->kfirst = (long)klo + 1;
    s->nlev = (uint64_t)(khi - klo) + 1;
    return 0;
}

/* Chains still open at the end must run border to border. */
static int is_border(const ms *s, uint64_t id)
{
    uint64_t eid = id / s->nlev, idx = eid >> 1;
    uint64_t r = idx / (uint64_t)s->dem->w, c = idx % (uint64_t)s->dem->w;
    if (eid & 1)
        return c == 0 || c == (uint64_t)s->dem->w - 1;
    return r == 0 || r == (uint64_t)s->dem->h - 1;
}

static int emit_open(ms *s)
{
    size_t id;
    int rc;
    for (id = 0; id < s->nch; id++) {
        chain *c = &s->ch[id];
        if (!c->buf)
            continue;
        if (!is_border(s, c->head) || !is_border(s, c->tail))
            return td_seterr(s->cx, TD_EINTERNAL,
                             "contours: open line ends inside the grid");
        if ((rc = chain_emit(s, (uint32_t)id, 0)) != 0)
            return rc;
    }
    return 0;
}

static int run_rows(ms *s)
{
    const td_grid_f32 *g = s->dem;
    int *b0 = td_malloc((size_t)g->w * sizeof(int), s->cx);
    int *b1 = td_malloc((size_t)g->w * sizeof(int), s->cx);
    long i;
    int rc = TD_ENOMEM;
    if (!b0 || !b1)
        goto fail;
    row_bands(s, 0, b0);
    for (i = 0; i + 1 < g->h; i++) {
        int *t;
        row_bands(s, i + 1, b1);
        if ((rc = cell_row(s, i, b0, b1)) != 0)
            goto fail;
        t = b0, b0 = b1, b1 = t;
        if ((i & 255) == 0 &&
            (rc = td_progress(s->cx, "contours", (double)i / g->h)) != 0)
            goto fail;
    }
    rc = emit_open(s);
fail:
    free(b0);
    free(b1);
    return rc;
}

/* Contract in gen.h.  Lines come out rings first (in the order they close),
 * then the open lines; every line keeps the higher ground on its right as
 * seen on screen (x right, y down). */
int td_gen_contours(const td_grid_f32 *dem, double base, double interval,
                    td_lines **out, td_ctx *cx)
{
    ms s;
    size_t i;
    int rc;
    memset(&s, 0, sizeof s);
    *out = NULL;
    if (!(interval > 0.0) || !isfinite(base) || !isfinite(interval))
        return td_seterr(cx, TD_EINVAL, "contours: bad interval %g", interval);
    if ((rc = td_check_dims(dem->w, dem->h, "contours: DEM", cx)) != 0)
        return rc;
    s.dem = dem;
    s.base = base;
    s.interval = interval;
    s.cx = cx;
    if ((rc = level_range(&s)) != 0)
        return rc;
    if (!(s.out = td_lines_new(cx)) || map_grow(&s.m, cx) != 0) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if (dem->w >= 2 && dem->h >= 2 && (rc = run_rows(&s)) != 0)
        goto fail;
    *out = s.out;
    s.out = NULL;
fail:
    for (i = 0; i < s.nch; i++)
        free(s.ch[i].buf);
    free(s.ch);
    free(s.freel);
    free(s.m.key);
    free(s.m.val);
    td_lines_free(s.out);
    return rc;
}
