/* ridgemodel.c: the ridgeline terrain model (paper 000 §2.1-2.2,
 * ALGORITHMS.md D1): Algorithm 2.1 (ridge segments -> skirts and gap
 * triangles -> z-buffer keeping the highest -> low-pass filter) and the
 * two deletion algorithms, 2.2 (per-cell lists of (polygon, height)
 * sorted by height) and 2.3 (a grid of the winning polygon per cell,
 * re-rendering only the affected region).
 *
 *                 skirt (quad, side +)
 *        P0' +--------------------------+ P1'      height z(s) - t k at
 *            |                          |          distance t (cells) from
 *        P0  o==========================o P1       the segment, k = tan(slope)
 *            |                          |          x cell size; the outer
 *            +--------------------------+          edge where it reaches the
 *                 skirt (quad, side -)             base height
 *
 * Around a node the segments' skirts leave wedge-shaped gaps on the outer
 * side of every bend (and a half-plane beyond a free end): each gap wider
 * than nothing is closed by a fan of triangles (apex at the node at its
 * height, the far corners at the base height), at most 45 degrees each.
 * Decisions where the paper is silent: nodes are end points closer than
 * p->snap cells; a node's height is the highest of the heights given for
 * it; a free end is capped like any other gap (its neighbour around the
 * node is itself); cells no polygon reaches get the base height; the
 * low-pass filter is the 3 x 3 mean, p->smooth passes.
 *
 * Every change renders through one rasteriser (cell centres inside a
 * convex polygon, the height from its plane), so an edited model and a
 * full render of the same segments agree bit for bit. */
#include "src/model/model.h"
#include "src/model/model_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FAN_STEP (M_PI / 4.0) /* widest triangle of a gap's fan */
#define PBLOCK 64             /* cells per side of a polygon index block */

typedef struct rnode {
    double x, y, z;    /* cells; z NaN: not known yet */
    size_t tri0, ntri; /* its gap triangles: polys tri0.. */
    size_t *seg;       /* its segments (alive ones: deg of them) */
    int deg, cap;
    int32_t next;      /* next node in its hash bucket */
} rnode;

typedef struct rseg {
    size_t a, b; /* nodes */
    long q[2];   /* its two skirts (polys), -1 none */
    int alive;
} rseg;

typedef struct rpoly {
    double vx[4], vy[4], c0, c1, c2; /* corners, plane h = c0+c1 x+c2 y */
    int nv, alive, bx0, by0, bx1, by1;
} rpoly;

typedef struct lcell { /* Algorithm 2.2: one (polygon, height) of a cell */
    int32_t poly, next;
    float h;
} lcell;

struct td_ridgemodel {
    int w, h;
    td_ridge_params p;
    double k; /* height lost per cell of distance */
    rnode *nd;
    size_t nn, cn;
    rseg *sg;
    size_t ns, cs;
    rpoly *pl;
    size_t np, cp;
    int32_t *bucket;    /* node hash: cells of HASH_CELL x snap */
    size_t nbucket;
    /* polygons by grid block (PBLOCK x PBLOCK cells): the ones whose box
       meets it, to find those overlapping a deleted polygon (2.3) */
    int32_t **pb;
    size_t *pbn, *pbc;
    int pbw, pbh;
    uint32_t *stamp, tick;
    size_t nstamp;
    int dx0, dy0, dx1, dy1; /* the box of the cells marked dirty */
    td_grid_f32 *z;     /* the z-buffer M */
    int rendered;
    /* 2.2 */
    int32_t *head;
    lcell *pool;
    size_t npool, cpool;
    int32_t free_cell;
    /* 2.3 */
    int32_t *win;
    unsigned char *dirty;
};

td_ridge_params td_ridge_defaults(void)
{
    td_ridge_params p;
    p.slope = 30.0;
    p.cell = 1.0;
    p.base = 0.0;
    p.smooth = 1;
    p.method = TD_RM_WINNERS;
    p.snap = 0.5;
    return p;
}

td_ridgemodel *td_ridgemodel_new(int w, int h, const td_ridge_params *p,
                                 td_ctx *cx)
{
    td_ridgemodel *m;
    size_t n, i;
    if (w < 1 || h < 1 || !p || !(p->slope > 0 && p->slope < 90) ||
        !(p->cell > 0) || !isfinite(p->base) || p->smooth < 0 ||
        !(p->snap >= 0)) {
        td_seterr(cx, TD_EINVAL, "ridgemodel: bad grid size or parameters "
                  "(slope strictly between 0 and 90 degrees, cell > 0)");
        return NULL;
    }
    if ((size_t)w * (size_t)h > (size_t)INT32_MAX) {
        td_seterr(cx, TD_EINVAL, "ridgemodel: grid %d x %d too large", w, h);
        return NULL;
    }
    if (!(m = td_calloc(1, sizeof *m, cx)))
        return NULL;
    m->w = w, m->h = h, m->p = *p;
    m->k = tan(p->slope * M_PI / 180.0) * p->cell;
    n = (size_t)w * (size_t)h;
    if (!(m->z = td_grid_f32_new(w, h, cx)))
        goto fail;
    for (i = 0; i < n; i++)
        m->z->data[i] = (float)p->base;
    if (p->method == TD_RM_LISTS) {
        if (!(m->head = td_malloc(n * sizeof *m->head, cx)))
            goto fail;
        for (i = 0; i < n; i++)
            m->head[i] = -1;
        m->free_cell = -1;
    } else {
        m->pbw = (w + PBLOCK - 1) / PBLOCK, m->pbh = (h + PBLOCK - 1) / PBLOCK;
        if (!(m->win = td_malloc(n * sizeof *m->win, cx)) ||
            !(m->dirty = td_calloc(n, 1, cx)) ||
            !(m->pb = td_calloc((size_t)m->pbw * m->pbh, sizeof *m->pb, cx)) ||
            !(m->pbn = td_calloc((size_t)m->pbw * m->pbh, sizeof *m->pbn,
                                 cx)) ||
            !(m->pbc = td_calloc((size_t)m->pbw * m->pbh, sizeof *m->pbc,
                                 cx)))
            goto fail;
        for (i = 0; i < n; i++)
            m->win[i] = -1;
    }
    return m;
fail:
    td_ridgemodel_free(m);
    return NULL;
}

void td_ridgemodel_free(td_ridgemodel *m)
{
    if (!m)
        return;
    size_t i;
    if (m->nd)
        for (i = 0; i < m->nn; i++)
            free(m->nd[i].seg);
    if (m->pb)
        for (i = 0; i < (size_t)m->pbw * m->pbh; i++)
            free(m->pb[i]);
    free(m->pb), free(m->pbn), free(m->pbc), free(m->stamp);
    free(m->nd), free(m->sg), free(m->pl), free(m->bucket);
    td_grid_f32_free(m->z);
    free(m->head), free(m->pool), free(m->win), free(m->dirty);
    free(m);
}

/* The node hash: buckets of cells of side max(snap, 1) cells. */
static size_t hash_of(const td_ridgemodel *m, long cx0, long cy0)
{
    uint64_t h = (uint64_t)cx0 * 0x9E3779B97F4A7C15u ^
                 (uint64_t)cy0 * 0xC2B2AE3D27D4EB4Fu;
    return (size_t)(h >> 17) & (m->nbucket - 1);
}

static double hash_side(const td_ridgemodel *m)
{
    return m->p.snap > 1 ? m->p.snap : 1.0;
}

static void hash_put(td_ridgemodel *m, size_t i)
{
    double c = hash_side(m);
    size_t b = hash_of(m, (long)floor(m->nd[i].x / c),
                       (long)floor(m->nd[i].y / c));
    m->nd[i].next = m->bucket[b];
    m->bucket[b] = (int32_t)i;
}

static int rehash(td_ridgemodel *m, td_ctx *cx)
{
    size_t nb = m->nbucket ? 2 * m->nbucket : 1024, i;
    int32_t *t = td_malloc(nb * sizeof *t, cx);
    if (!t)
        return TD_ENOMEM;
    free(m->bucket);
    m->bucket = t, m->nbucket = nb;
    for (i = 0; i < nb; i++)
        t[i] = -1;
    for (i = 0; i < m->nn; i++)
        hash_put(m, i);
    return 0;
}

/* The node at (x, y) (within p->snap), or a new one; -1: no memory. */
static long node_at(td_ridgemodel *m, double x, double y, double z,
                    td_ctx *cx)
{
    double c = hash_side(m);
    long gx = (long)floor(x / c), gy = (long)floor(y / c), dx, dy;
    if (m->nn >= (size_t)INT32_MAX - 1) {
        td_seterr(cx, TD_EINVAL, "ridgemodel: too many nodes");
        return -1;
    }
    for (dy = -1; m->nbucket && dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++) {
            int32_t i = m->bucket[hash_of(m, gx + dx, gy + dy)];
            for (; i >= 0; i = m->nd[i].next)
                if (hypot(m->nd[i].x - x, m->nd[i].y - y) <= m->p.snap) {
                    if (isfinite(z) && !(m->nd[i].z >= z))
                        m->nd[i].z = z;
                    return (long)i;
                }
        }
    if (td_grow((void **)&m->nd, &m->cn, m->nn + 1, sizeof *m->nd, cx) != 0)
        return -1;
    memset(&m->nd[m->nn], 0, sizeof *m->nd);
    m->nd[m->nn].x = x, m->nd[m->nn].y = y;
    m->nd[m->nn].z = isfinite(z) ? z : NAN;
    m->nn++;
    if (m->nn * 2 > m->nbucket) {
        if (rehash(m, cx) != 0)
            return -1;
    } else {
        hash_put(m, m->nn - 1);
    }
    return (long)(m->nn - 1);
}

/* Node v gains (on) or loses segment s. */
static int node_link(td_ridgemodel *m, size_t v, size_t s, int on,
                     td_ctx *cx)
{
    rnode *V = &m->nd[v];
    int i;
    if (!on) {
        for (i = 0; i < V->deg; i++)
            if (V->seg[i] == s) {
                V->seg[i] = V->seg[--V->deg];
                break;
            }
        return 0;
    }
    if (V->deg == V->cap) {
        int nc = V->cap ? 2 * V->cap : 4;
        size_t *t = realloc(V->seg, (size_t)nc * sizeof *t);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
        V->seg = t, V->cap = nc;
    }
    V->seg[V->deg++] = s;
    return 0;
}

/* ---- polygons and the rasteriser ---- */

static long new_poly(td_ridgemodel *m, const double *x, const double *y,
                     const double *hz, int nv, td_ctx *cx)
{
    rpoly *q;
    double ax = x[1] - x[0], ay = y[1] - y[0], bx, by, det;
    int i, j = 2;
    if (td_grow((void **)&m->pl, &m->cp, m->np + 1, sizeof *m->pl, cx) != 0)
        return -2;
    /* the plane through vertices 0, 1 and the first not on their line */
    for (; j < nv; j++) {
        bx = x[j] - x[0], by = y[j] - y[0];
        det = ax * by - ay * bx;
        if (fabs(det) > 1e-9)
            break;
    }
    if (j == nv)
        return -1; /* degenerate: covers nothing */
    q = &m->pl[m->np];
    memset(q, 0, sizeof *q);
    {
        double dh1 = hz[1] - hz[0], dh2 = hz[j] - hz[0];
        q->c1 = (dh1 * by - dh2 * ay) / det;
        q->c2 = (ax * dh2 - bx * dh1) / det;
        q->c0 = hz[0] - q->c1 * x[0] - q->c2 * y[0];
    }
    q->nv = nv, q->alive = 1;
    q->bx0 = m->w, q->by0 = m->h, q->bx1 = -1, q->by1 = -1;
    for (i = 0; i < nv; i++) {
        int a = (int)floor(x[i]), b = (int)floor(y[i]);
        q->vx[i] = x[i], q->vy[i] = y[i];
        q->bx0 = a < q->bx0 ? a : q->bx0, q->bx1 = a > q->bx1 ? a : q->bx1;
        q->by0 = b < q->by0 ? b : q->by0, q->by1 = b > q->by1 ? b : q->by1;
    }
    q->bx0 = q->bx0 < 0 ? 0 : q->bx0, q->by0 = q->by0 < 0 ? 0 : q->by0;
    q->bx1 = q->bx1 >= m->w ? m->w - 1 : q->bx1;
    q->by1 = q->by1 >= m->h ? m->h - 1 : q->by1;
    if (m->pb && q->bx0 <= q->bx1 && q->by0 <= q->by1) {
        int kx, ky;
        for (ky = q->by0 / PBLOCK; ky <= q->by1 / PBLOCK; ky++)
            for (kx = q->bx0 / PBLOCK; kx <= q->bx1 / PBLOCK; kx++) {
                size_t b = (size_t)ky * m->pbw + kx;
                if (td_grow((void **)&m->pb[b], &m->pbc[b], m->pbn[b] + 1,
                         sizeof **m->pb, cx) != 0)
                    return -2;
                m->pb[b][m->pbn[b]++] = (int32_t)m->np;
            }
    }
    return (long)m->np++;
}

enum { R_ADD, R_UNLIST, R_MARK, R_REDO };

/* 2.2: insert (poly, h) into cell c's list, highest first. */
static int list_insert(td_ridgemodel *m, size_t c, int32_t poly, float h)
{
    int32_t e, *at = &m->head[c];
    if (m->free_cell >= 0) {
        e = m->free_cell;
        m->free_cell = m->pool[e].next;
    } else {
        if (m->npool >= (size_t)INT32_MAX ||
            td_grow((void **)&m->pool, &m->cpool, m->npool + 1, sizeof *m->pool,
                 NULL) != 0)
            return -1;
        e = (int32_t)m->npool++;
    }
    while (*at >= 0 && (m->pool[*at].h > h ||
                        (m->pool[*at].h == h && m->pool[*at].poly < poly)))
        at = &m->pool[*at].next;
    m->pool[e].poly = poly, m->pool[e].h = h, m->pool[e].next = *at;
    *at = e;
    return 0;
}

static void list_remove(td_ridgemodel *m, size_t c, int32_t poly)
{
    int32_t *at = &m->head[c];
    while (*at >= 0 && m->pool[*at].poly != poly)
        at = &m->pool[*at].next;
    if (*at >= 0) {
        int32_t e = *at;
        *at = m->pool[e].next;
        m->pool[e].next = m->free_cell;
        m->free_cell = e;
    }
    m->z->data[c] = m->head[c] >= 0 ? m->pool[m->head[c]].h
                                    : (float)m->p.base;
}

/* Visit the cells whose centres lie in polygon i (rows by the crossings
 * of the centre line with its edges) and apply `mode`; -1: no memory. */
static int raster_in(td_ridgemodel *m, size_t i, int mode, int cx0, int cy0,
                     int cx1, int cy1)
{
    const rpoly *q = &m->pl[i];
    int row, col, r0 = q->by0 > cy0 ? q->by0 : cy0;
    int r1 = q->by1 < cy1 ? q->by1 : cy1;
    for (row = r0; row <= r1; row++) {
        double yc = row + 0.5;
        int c0, c1;
        if (!td_convex_span(q->vx, q->vy, q->nv, row, q->bx0 > cx0 ? q->bx0 : cx0,
                            q->bx1 < cx1 ? q->bx1 : cx1, &c0, &c1))
            continue;
        for (col = c0; col <= c1; col++) {
            size_t c = (size_t)row * m->w + col;
            double hv = q->c0 + q->c1 * (col + 0.5) + q->c2 * yc;
            float h = (float)(hv > m->p.base ? hv : m->p.base);
            float *z = &m->z->data[c];
            switch (mode) {
            case R_ADD:
                if (m->head) {
                    if (list_insert(m, c, (int32_t)i, h) != 0)
                        return -1;
                    *z = m->pool[m->head[c]].h;
                } else if (h > *z || (h == *z && m->win[c] < 0)) {
                    *z = h, m->win[c] = (int32_t)i;
                }
                break;
            case R_UNLIST:
                list_remove(m, c, (int32_t)i);
                break;
            case R_MARK: /* 2.3: the cells this polygon wins are redone */
                if (m->win[c] == (int32_t)i) {
                    m->dirty[c] = 1;
                    *z = (float)m->p.base, m->win[c] = -1;
                    m->dx0 = col < m->dx0 ? col : m->dx0;
                    m->dx1 = col > m->dx1 ? col : m->dx1;
                    m->dy0 = row < m->dy0 ? row : m->dy0;
                    m->dy1 = row > m->dy1 ? row : m->dy1;
                }
                break;
            case R_REDO:
                if (m->dirty[c] &&
                    (h > *z || (h == *z && m->win[c] < 0)))
                    *z = h, m->win[c] = (int32_t)i;
                break;
            }
        }
    }
    return 0;
}

static int raster(td_ridgemodel *m, size_t i, int mode)
{
    return raster_in(m, i, mode, 0, 0, m->w - 1, m->h - 1);
}

/* Take polygons [from, to) off the grid (they are no longer alive):
 * Algorithm 2.2 removes them from their cells' lists; 2.3 marks the cells
 * they win and re-renders those cells from the polygons that overlap. */
static int take_off(td_ridgemodel *m, const long *ids, size_t n)
{
    size_t i;
    int x0 = m->w, y0 = m->h, x1 = -1, y1 = -1, row, col;
    for (i = 0; i < n; i++)
        m->pl[ids[i]].alive = 0;
    if (!m->rendered)
        return 0;
    if (m->head) {
        for (i = 0; i < n; i++)
            raster(m, (size_t)ids[i], R_UNLIST);
        return 0;
    }
    m->dx0 = m->w, m->dy0 = m->h, m->dx1 = -1, m->dy1 = -1;
    for (i = 0; i < n; i++) /* the box of the cells they won */
        raster(m, (size_t)ids[i], R_MARK);
    x0 = m->dx0, y0 = m->dy0, x1 = m->dx1, y1 = m->dy1;
    if (x0 > x1)
        return 0;
    if (m->nstamp < m->np || m->tick == UINT32_MAX) { /* one visit each */
        free(m->stamp);
        m->nstamp = m->cp + 1;
        if (!(m->stamp = calloc(m->nstamp, sizeof *m->stamp))) {
            m->nstamp = 0;
            return -1;
        }
        m->tick = 0;
    }
    m->tick++;
    for (row = y0 / PBLOCK; row <= y1 / PBLOCK; row++)
        for (col = x0 / PBLOCK; col <= x1 / PBLOCK; col++) {
            size_t b = (size_t)row * m->pbw + col, j;
            for (j = 0; j < m->pbn[b]; j++) {
                int32_t k = m->pb[b][j];
                const rpoly *q = &m->pl[k];
                if (m->stamp[k] == m->tick || !q->alive)
                    continue;
                m->stamp[k] = m->tick;
                if (q->bx0 <= x1 && q->bx1 >= x0 && q->by0 <= y1 &&
                    q->by1 >= y0)
                    raster_in(m, (size_t)k, R_REDO, x0, y0, x1, y1);
            }
        }
    for (row = y0; row <= y1; row++)
        for (col = x0; col <= x1; col++)
            m->dirty[(size_t)row * m->w + col] = 0;
    return 0;
}

/* ---- polygons of segments and nodes ---- */

/* The skirt of segment s on side sd (+1: left of a->b as x right, y
 * down... any fixed side; -1 the other). */
static int make_skirt(td_ridgemodel *m, size_t s, int sd, td_ctx *cx)
{
    rseg *g = &m->sg[s];
    const rnode *A = &m->nd[g->a], *B = &m->nd[g->b];
    double ax = A->x, ay = A->y, az = A->z, bx = B->x, by = B->y, bz = B->z;
    double L = hypot(bx - ax, by - ay), nx, ny, x[4], y[4], hz[4], Da, Db;
    long id;
    int nv = 0;
    g->q[sd > 0 ? 0 : 1] = -1;
    if (!(L > 0) || (az <= m->p.base && bz <= m->p.base))
        return 0;
    if (az < m->p.base || bz < m->p.base) { /* clip to where z > base */
        double t = (m->p.base - az) / (bz - az);
        if (az < m->p.base)
            ax += t * (bx - ax), ay += t * (by - ay), az = m->p.base;
        else
            bx = ax + t * (bx - ax), by = ay + t * (by - ay), bz = m->p.base;
    }
    nx = -(by - ay) / L * sd, ny = (bx - ax) / L * sd;
    Da = (az - m->p.base) / m->k, Db = (bz - m->p.base) / m->k;
    x[nv] = ax, y[nv] = ay, hz[nv++] = az;
    x[nv] = bx, y[nv] = by, hz[nv++] = bz;
    if (Db > 0)
        x[nv] = bx + nx * Db, y[nv] = by + ny * Db, hz[nv++] = m->p.base;
    if (Da > 0)
        x[nv] = ax + nx * Da, y[nv] = ay + ny * Da, hz[nv++] = m->p.base;
    if ((id = new_poly(m, x, y, hz, nv, cx)) == -2)
        return TD_ENOMEM;
    g->q[sd > 0 ? 0 : 1] = id;
    return 0;
}

static int cmp_ang(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    return (a[0] > b[0]) - (a[0] < b[0]);
}

/* Node v's gap triangles (new polygons from m->np on). */
static int make_fan(td_ridgemodel *m, size_t v, td_ctx *cx)
{
    rnode *V = &m->nd[v];
    double (*ang)[1] = NULL, D = (V->z - m->p.base) / m->k;
    size_t i, n = 0;
    int rc = 0;
    V->tri0 = m->np, V->ntri = 0;
    if (!(D > 0) || V->deg == 0)
        return 0;
    if (!(ang = malloc((size_t)V->deg * sizeof *ang)))
        return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
    for (i = 0; i < (size_t)V->deg; i++) {
        const rseg *g = &m->sg[V->seg[i]];
        const rnode *o = &m->nd[g->a == v ? g->b : g->a];
        if (o->x == V->x && o->y == V->y)
            continue;
        ang[n++][0] = atan2(o->y - V->y, o->x - V->x);
    }
    qsort(ang, n, sizeof *ang, cmp_ang);
    for (i = 0; i < n && rc == 0; i++) {
        double t0 = ang[i][0], t1 = n > 1 ? ang[(i + 1) % n][0] : t0;
        double gap = t1 - t0, a0, W;
        int k, parts;
        if (gap <= 0)
            gap += 2 * M_PI; /* the last to the first (or itself) */
        W = gap - M_PI;
        if (W <= 1e-9)
            continue; /* the skirts overlap: no gap */
        a0 = t0 + M_PI / 2;
        parts = (int)ceil(W / FAN_STEP - 1e-9);
        for (k = 0; k < parts; k++) {
            double p0 = a0 + W * k / parts, p1 = a0 + W * (k + 1) / parts;
            double x[3] = {V->x, V->x + D * cos(p0), V->x + D * cos(p1)};
            double y[3] = {V->y, V->y + D * sin(p0), V->y + D * sin(p1)};
            double hz[3] = {V->z, m->p.base, m->p.base};
            long id = new_poly(m, x, y, hz, 3, cx);
            if (id == -2)
                rc = TD_ENOMEM;
        }
    }
    V->ntri = m->np - V->tri0;
    free(ang);
    return rc;
}

/* Render polygons [from, m->np). */
static int render_from(td_ridgemodel *m, size_t from, td_ctx *cx)
{
    size_t i;
    for (i = from; i < m->np; i++)
        if (m->pl[i].alive && raster(m, i, R_ADD) != 0)
            return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
    return 0;
}

/* The triangles of nodes a and b and polygons extra[0..nx) off the grid
 * at once (one re-render of the cells they won), then new fans for a and
 * b drawn. */
static int refan(td_ridgemodel *m, size_t a, size_t b, const long *extra,
                 size_t nx, td_ctx *cx)
{
    size_t n = m->nd[a].ntri + (b != a ? m->nd[b].ntri : 0) + nx, i, k = 0;
    size_t from;
    long *ids = malloc((n + 1) * sizeof *ids);
    if (!ids)
        return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
    for (i = 0; i < nx; i++)
        ids[k++] = extra[i];
    for (i = 0; i < m->nd[a].ntri; i++)
        ids[k++] = (long)(m->nd[a].tri0 + i);
    for (i = 0; b != a && i < m->nd[b].ntri; i++)
        ids[k++] = (long)(m->nd[b].tri0 + i);
    if (take_off(m, ids, k) != 0) {
        free(ids);
        return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
    }
    free(ids);
    from = m->np;
    if (make_fan(m, a, cx) != 0 || (b != a && make_fan(m, b, cx) != 0))
        return TD_ENOMEM;
    return m->rendered ? render_from(m, from, cx) : 0;
}

/* ---- the public operations ---- */

long td_ridgemodel_add(td_ridgemodel *m, double x0, double y0, double z0,
                       double x1, double y1, double z1, td_ctx *cx)
{
    long a, b;
    size_t s, from;
    if (!isfinite(x0) || !isfinite(y0) || !isfinite(x1) || !isfinite(y1) ||
        fabs(x0) > 1e8 || fabs(y0) > 1e8 || fabs(x1) > 1e8 ||
        fabs(y1) > 1e8 || isinf(z0) || isinf(z1)) {
        td_seterr(cx, TD_EINVAL, "ridgemodel: a non-finite or far-off "
                  "coordinate");
        return -1;
    }
    if ((a = node_at(m, x0, y0, z0, cx)) < 0 ||
        (b = node_at(m, x1, y1, z1, cx)) < 0 ||
        td_grow((void **)&m->sg, &m->cs, m->ns + 1, sizeof *m->sg, cx) != 0)
        return -1;
    s = m->ns++;
    m->sg[s] = (rseg){(size_t)a, (size_t)b, {-1, -1}, 1};
    if (a == b) /* shorter than the snap: a point, nothing to draw */
        return (long)s;
    if (node_link(m, (size_t)a, s, 1, cx) != 0 ||
        node_link(m, (size_t)b, s, 1, cx) != 0)
        return -1;
    if (!m->rendered)
        return (long)s;
    if (!isfinite(m->nd[a].z) || !isfinite(m->nd[b].z)) {
        td_seterr(cx, TD_EINVAL, "ridgemodel: a segment added without "
                  "heights");
        return -1;
    }
    from = m->np;
    if (make_skirt(m, s, 1, cx) != 0 || make_skirt(m, s, -1, cx) != 0 ||
        render_from(m, from, cx) != 0 ||
        refan(m, (size_t)a, (size_t)b, NULL, 0, cx) != 0)
        return -1;
    return (long)s;
}

int td_ridgemodel_delete(td_ridgemodel *m, long s, td_ctx *cx)
{
    rseg *g;
    long ids[2];
    size_t n = 0, i;
    if (s < 0 || (size_t)s >= m->ns || !m->sg[s].alive)
        return td_seterr(cx, TD_EINVAL, "ridgemodel: no segment %ld", s);
    g = &m->sg[s];
    g->alive = 0;
    if (g->a == g->b)
        return 0;
    node_link(m, g->a, (size_t)s, 0, cx);
    node_link(m, g->b, (size_t)s, 0, cx);
    for (i = 0; i < 2; i++)
        if (g->q[i] >= 0)
            ids[n++] = g->q[i];
    return refan(m, g->a, g->b, ids, n, cx);
}

long td_ridgemodel_find(const td_ridgemodel *m, double x0, double y0,
                        double x1, double y1)
{
    size_t s;
    double tol = m->p.snap > 0 ? m->p.snap : 1e-9;
    for (s = 0; s < m->ns; s++) {
        const rseg *g = &m->sg[s];
        const rnode *A = &m->nd[g->a], *B = &m->nd[g->b];
        if (!g->alive)
            continue;
        if ((hypot(A->x - x0, A->y - y0) <= tol &&
             hypot(B->x - x1, B->y - y1) <= tol) ||
            (hypot(A->x - x1, A->y - y1) <= tol &&
             hypot(B->x - x0, B->y - y0) <= tol))
            return (long)s;
    }
    return -1;
}

int td_ridgemodel_render(td_ridgemodel *m, td_ctx *cx)
{
    size_t s, v;
    int rc = 0;
    if (m->rendered)
        return 0;
    for (v = 0; v < m->nn; v++)
        if (m->nd[v].deg > 0 && !isfinite(m->nd[v].z))
            return td_seterr(cx, TD_EINVAL, "ridgemodel: node at (%.1f, "
                             "%.1f) has no height (give heights per vertex, "
                             "or leaf heights for a 2-D tree)",
                             m->nd[v].x, m->nd[v].y);
    for (s = 0; s < m->ns && rc == 0; s++)
        if (m->sg[s].alive && m->sg[s].a != m->sg[s].b)
            rc = make_skirt(m, s, 1, cx) || make_skirt(m, s, -1, cx);
    for (v = 0; v < m->nn && rc == 0; v++)
        rc = make_fan(m, v, cx);
    if (rc)
        return td_seterr(cx, TD_ENOMEM, "ridgemodel: out of memory");
    m->rendered = 1;
    return render_from(m, 0, cx);
}

const td_grid_f32 *td_ridgemodel_zbuffer(const td_ridgemodel *m)
{
    return m->z;
}

td_grid_f32 *td_ridgemodel_dem(const td_ridgemodel *m, td_ctx *cx)
{
    int w = m->w, h = m->h, pass, x, y;
    td_grid_f32 *a = td_grid_f32_new(w, h, cx), *b = NULL;
    if (!a)
        return NULL;
    memcpy(a->data, m->z->data, (size_t)w * h * sizeof *a->data);
    if (m->p.smooth > 0 && !(b = td_grid_f32_new(w, h, cx))) {
        td_grid_f32_free(a);
        return NULL;
    }
    for (pass = 0; pass < m->p.smooth; pass++) { /* the 3 x 3 mean */
        td_grid_f32 *t;
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                double s = 0;
                int n = 0, dx, dy;
                for (dy = -1; dy <= 1; dy++)
                    for (dx = -1; dx <= 1; dx++) {
                        int X = x + dx, Y = y + dy;
                        if (X < 0 || Y < 0 || X >= w || Y >= h)
                            continue;
                        s += a->data[(size_t)Y * w + X], n++;
                    }
                b->data[(size_t)y * w + x] = (float)(s / n);
            }
        t = a, a = b, b = t;
    }
    td_grid_f32_free(b);
    return a;
}

size_t td_ridgemodel_nodes(const td_ridgemodel *m, double *xyz, size_t cap)
{
    size_t i, n = 0;
    for (i = 0; i < m->nn; i++) {
        if (m->nd[i].deg <= 0)
            continue;
        if (n < cap) {
            xyz[3 * n] = m->nd[i].x, xyz[3 * n + 1] = m->nd[i].y;
            xyz[3 * n + 2] = m->nd[i].z;
        }
        n++;
    }
    return n;
}

size_t td_ridgemodel_segments(const td_ridgemodel *m, double *v, size_t cap)
{
    size_t s, n = 0;
    for (s = 0; s < m->ns; s++) {
        const rseg *g = &m->sg[s];
        if (!g->alive || g->a == g->b)
            continue;
        if (n < cap) {
            double *q = v + 6 * n;
            q[0] = m->nd[g->a].x, q[1] = m->nd[g->a].y, q[2] = m->nd[g->a].z;
            q[3] = m->nd[g->b].x, q[4] = m->nd[g->b].y, q[5] = m->nd[g->b].z;
        }
        n++;
    }
    return n;
}

/* ---- Algorithm 2.4: heights for 2-D ridge trees ---- */

static double seg_len(const td_ridgemodel *m, size_t u, size_t q)
{
    return hypot(m->nd[u].x - m->nd[q].x, m->nd[u].y - m->nd[q].y);
}

/* Hang the component of r from a node that is not a leaf (the paper hangs
 * the tree from any node; a leaf as the root would lose its own distance
 * 0): order (breadth first from the root) and parents; *n nodes.  An edge
 * to a node already hung, other than the parent, closes a cycle. */
static int hang(td_ridgemodel *m, size_t r, size_t *order, size_t *par,
                unsigned char *hung, size_t *n, td_ctx *cx)
{
    size_t head = 0, tail = 0, root = r, i;
    int k;
    order[tail++] = r, hung[r] = 1; /* find a root: any inner node */
    while (head < tail) {
        size_t u = order[head++];
        if (m->nd[u].deg >= 2 && m->nd[root].deg < 2)
            root = u;
        for (k = 0; k < m->nd[u].deg; k++) {
            const rseg *g = &m->sg[m->nd[u].seg[k]];
            size_t o = g->a == u ? g->b : g->a;
            if (!hung[o])
                hung[o] = 1, order[tail++] = o;
        }
    }
    for (i = 0; i < tail; i++)
        hung[order[i]] = 0;
    head = tail = 0;
    order[tail++] = root, par[root] = SIZE_MAX, hung[root] = 1;
    while (head < tail) {
        size_t u = order[head++];
        int up = 0;
        for (k = 0; k < m->nd[u].deg; k++) {
            const rseg *g = &m->sg[m->nd[u].seg[k]];
            size_t o = g->a == u ? g->b : g->a;
            if (o == par[u] && !up) {
                up = 1; /* the edge to the parent, once */
                continue;
            }
            if (hung[o])
                return td_seterr(cx, TD_EINVAL, "ridgemodel: the ridge lines "
                                 "are not a tree: they close a cycle at "
                                 "(%.1f, %.1f)", m->nd[o].x, m->nd[o].y);
            hung[o] = 1, par[o] = u, order[tail++] = o;
        }
    }
    *n = tail;
    return 0;
}

int td_ridgemodel_tree_heights(td_ridgemodel *m, double leaf, td_ctx *cx)
{
    size_t *order, *par, r, n = 0, i;
    double *dist;
    unsigned char *hung;
    int rc = 0;
    if (!isfinite(leaf))
        return td_seterr(cx, TD_EINVAL, "ridgemodel: leaf height not finite");
    order = td_malloc((m->nn + 1) * sizeof *order, cx);
    par = td_malloc((m->nn + 1) * sizeof *par, cx);
    dist = td_malloc((m->nn + 1) * sizeof *dist, cx);
    hung = td_calloc(m->nn + 1, 1, cx);
    if (!order || !par || !dist || !hung) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (r = 0; r < m->nn && rc == 0; r++) {
        size_t root;
        if (hung[r] || m->nd[r].deg == 0)
            continue;
        if ((rc = hang(m, r, order, par, hung, &n, cx)) != 0)
            break;
        root = order[0];
        /* step 1: leaves inward; every leaf 0, each parent the least of
           its children's distances plus the edge */
        for (i = 0; i < n; i++)
            dist[order[i]] = HUGE_VAL;
        for (i = n; i-- > 0;) {
            size_t u = order[i], q = par[u];
            if (m->nd[u].deg == 1 && u != root)
                dist[u] = 0.0;
            if (q != SIZE_MAX && dist[u] + seg_len(m, u, q) < dist[q])
                dist[q] = dist[u] + seg_len(m, u, q);
        }
        if (m->nd[root].deg == 1)
            dist[root] = 0.0; /* one segment: two leaves */
        /* step 2: root outward, each child relaxed from its parent */
        for (i = 1; i < n; i++) {
            size_t u = order[i], q = par[u];
            if (dist[q] + seg_len(m, u, q) < dist[u])
                dist[u] = dist[q] + seg_len(m, u, q);
        }
        for (i = 0; i < n; i++)
            m->nd[order[i]].z = leaf + m->k * dist[order[i]];
    }
done:
    free(order), free(par), free(dist), free(hung);
    return rc;
}
