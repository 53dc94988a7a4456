/* skeleton_queue.c: the straight skeleton by an event queue (ours, beside
 * the paper's construction in skeleton.c; td_skeleton_params.construction
 * TD_SKEL_QUEUE, the default).  The same wavefront and the same events as
 * the paper's (004 §3): every edge keeps its line and moves inward at
 * speed 1, every vertex with v . n = 1 for its two edges' normals; edge
 * events, split events, the same merging of vertices that meet and the
 * same spike rule.  What changes is how the next event is found:
 *
 *   paper    each step: every edge's event, every reflex vertex against
 *            every edge, every vertex moved: O(n^2) a step, O(n^3) in all;
 *   queue    a vertex never moves: it keeps where and when it was born
 *            (x, y, t) and its velocity, and is replaced by a new one when
 *            either of its edges changes.  Edge events sit in a heap; a
 *            reflex vertex's split candidates are the times it crosses
 *            each edge line (fixed lines: fixed times), taken in order a
 *            few at a time, and one is checked only when the heap reaches
 *            its time (does the crossing point lie on a piece of that line
 *            then?), so every check is made against the front as it is.
 *
 *            r --->  | line L, moving at speed 1 along its normal
 *                    |  the piece of L between its two vertices at time t
 *
 * Work is local: an event touches the few vertices around it.  The DEM is
 * swept edge by edge between the times an edge's ends change.  Nodes,
 * contours, peaks and the roof are those of the paper's construction
 * (tests/test_skeleton.c, tests/test_skeleton_cgal.cpp). */
#include "src/model/model.h"
#include "src/model/model_int.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define NCAND 8      /* split candidates taken at a time per reflex vertex */
#define RING_WALK 64 /* rings up to this size are checked for area */

typedef struct qv {
    double x, y, t;           /* position at birth time t */
    double vx, vy;            /* velocity */
    double drawn;             /* outgoing edge swept into the DEM up to here */
    uint32_t prev, next;      /* ring neighbours */
    uint32_t lin, line;       /* lines of the incoming and outgoing edges */
    uint32_t mark;            /* last contour level walked */
    int32_t cand;             /* candidate buffer (reflex), or -1 */
    uint8_t alive, reflex;
} qv;

typedef struct qline {
    double nx, ny, c;         /* n . x = c + t at time t */
    uint32_t *piece;          /* vertices born with this outgoing line */
    size_t npiece, cpiece, live;
} qline;

typedef struct qcand {
    double t[NCAND];
    uint32_t line[NCAND];
    int n, pos, full;         /* held, next to use, batch was full */
} qcand;

enum { EV_EDGE, EV_SPLIT };

typedef struct qev {
    double t;
    uint32_t a, b; /* EDGE: a -> b;  SPLIT: reflex vertex a, line b */
    int kind;
} qev;

typedef struct qs {
    qv *v;
    size_t nv, cv;
    qline *ln;
    size_t nl;
    qcand *cd;
    size_t ncd, ccd;
    qev *h;
    size_t nh, ch;
    uint32_t *work;
    size_t nwork, cwork;
    uint32_t *born;           /* vertices made in this step */
    size_t nborn, cborn;
    double *lnx, *lny, *lc;   /* the lines with a piece (and some gone):  */
    uint32_t *lid;            /* compacted when half are gone, for the  */
    size_t nlid, nlive;       /* candidates' scan */
    double t, eps, tol, tmax;
    const td_skeleton_params *prm;
    td_grid_f32 *dem;
    td_lines *peaks;
    td_ctx *cx;
    int rc;
    uint32_t level;
    size_t nevents, nsplits;
} qs;

/* td_grow, the error kept in s->rc. */
static int grow(void **p, size_t *cap, size_t need, size_t sz, qs *s)
{
    int rc = td_grow(p, cap, need, sz, s->cx);
    if (rc)
        s->rc = rc;
    return rc;
}

static void pos(const qs *s, uint32_t i, double T, double *x, double *y)
{
    const qv *v = &s->v[i];
    *x = v->x + (T - v->t) * v->vx, *y = v->y + (T - v->t) * v->vy;
}

/* ---- the heap of events ---- */

static void heap_push(qs *s, double t, uint32_t a, uint32_t b, int kind)
{
    size_t i;
    if (s->rc || grow((void **)&s->h, &s->ch, s->nh + 1, sizeof *s->h, s))
        return;
    i = s->nh++;
    while (i > 0 && s->h[(i - 1) / 2].t > t) {
        s->h[i] = s->h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    s->h[i].t = t, s->h[i].a = a, s->h[i].b = b, s->h[i].kind = kind;
}

static qev heap_pop(qs *s)
{
    qev top = s->h[0], last = s->h[--s->nh];
    size_t i = 0, c;
    while ((c = 2 * i + 1) < s->nh) {
        if (c + 1 < s->nh && s->h[c + 1].t < s->h[c].t)
            c++;
        if (!(s->h[c].t < last.t))
            break;
        s->h[i] = s->h[c];
        i = c;
    }
    if (s->nh > 0)
        s->h[i] = last;
    return top;
}

/* ---- vertices ---- */

/* A vertex born now at (x, y) between lines lin (incoming) and line. */
static uint32_t vert_new(qs *s, double x, double y, uint32_t lin,
                         uint32_t line)
{
    const qline *a = &s->ln[lin], *b = &s->ln[line];
    qline *L = &s->ln[line];
    qv *v;
    double d = 1 + a->nx * b->nx + a->ny * b->ny;
    if (grow((void **)&s->v, &s->cv, s->nv + 1, sizeof *s->v, s) ||
        grow((void **)&L->piece, &L->cpiece, L->npiece + 1, sizeof *L->piece,
             s) ||
        grow((void **)&s->born, &s->cborn, s->nborn + 1, sizeof *s->born, s))
        return 0;
    v = &s->v[s->nv];
    memset(v, 0, sizeof *v);
    v->x = x, v->y = y, v->t = s->t, v->drawn = s->t;
    if (d >= 1e-12) /* else antiparallel edges: a spike, it stays */
        v->vx = (a->nx + b->nx) / d, v->vy = (a->ny + b->ny) / d;
    v->lin = lin, v->line = line;
    v->cand = -1;
    v->alive = 1;
    v->reflex = a->nx * b->ny - a->ny * b->nx < -1e-12;
    L->piece[L->npiece++] = (uint32_t)s->nv;
    L->live++;
    s->born[s->nborn++] = (uint32_t)s->nv;
    return (uint32_t)s->nv++;
}

static void link2(qs *s, uint32_t a, uint32_t b)
{
    s->v[a].next = b, s->v[b].prev = a;
}

/* Sweep the edge leaving i into the DEM from when it was last swept to
 * now: a trapezoid, each cell the time the edge's line passed it. */
static void flush(qs *s, uint32_t i)
{
    qv *a = &s->v[i];
    const qline *L = &s->ln[a->line];
    double x[4], y[4];
    if (!s->dem || !(s->t > a->drawn)) {
        a->drawn = s->t;
        return;
    }
    pos(s, i, a->drawn, &x[0], &y[0]);
    pos(s, a->next, a->drawn, &x[1], &y[1]);
    pos(s, a->next, s->t, &x[2], &y[2]);
    pos(s, i, s->t, &x[3], &y[3]);
    td_skeleton_quad(s->dem, x, y, L->nx, L->ny, L->c, a->drawn, s->t);
    a->drawn = s->t;
}

static void kill(qs *s, uint32_t i)
{
    if (s->v[i].alive) {
        s->v[i].alive = 0;
        if (--s->ln[s->v[i].line].live == 0)
            s->nlive--;
    }
}

/* Keep only the lines that still have a piece in the scan arrays. */
static void compact_lines(qs *s)
{
    size_t k, m = 0;
    for (k = 0; k < s->nlid; k++)
        if (s->ln[s->lid[k]].live) {
            s->lid[m] = s->lid[k];
            s->lnx[m] = s->lnx[k], s->lny[m] = s->lny[k], s->lc[m] = s->lc[k];
            m++;
        }
    s->nlid = m;
}

static void node(qs *s, uint32_t i)
{
    td_line *l;
    double x, y;
    if (!s->prm->nodes || s->rc)
        return;
    pos(s, i, s->t, &x, &y);
    if (!(l = td_lines_add(s->prm->nodes, s->cx)) ||
        td_line_push(l, x, y, s->cx) != 0) {
        s->rc = TD_ENOMEM;
        return;
    }
    l->has_height = 1, l->height = s->t;
}

static void work(qs *s, uint32_t i)
{
    if (grow((void **)&s->work, &s->cwork, s->nwork + 1, sizeof *s->work, s))
        return;
    s->work[s->nwork++] = i;
}

/* ---- events ---- */

static void push_edge(qs *s, uint32_t a)
{
    uint32_t b = s->v[a].next;
    double ax, ay, bx, by, dx, dy, L, rate;
    pos(s, a, s->t, &ax, &ay);
    pos(s, b, s->t, &bx, &by);
    dx = bx - ax, dy = by - ay, L = hypot(dx, dy);
    if (!(L > 0)) {
        heap_push(s, s->t, a, b, EV_EDGE);
        return;
    }
    rate = ((s->v[b].vx - s->v[a].vx) * dx + (s->v[b].vy - s->v[a].vy) * dy) /
           L;
    if (rate < -1e-12)
        heap_push(s, s->t + L / -rate, a, b, EV_EDGE);
}

/* The next NCAND crossings of reflex vertex i with the lines that still
 * have a piece, after (t, line) of the last one taken; the first goes on
 * the heap. */
static void cand_batch(qs *s, uint32_t i)
{
    const qv *v = &s->v[i];
    qcand *c;
    double ct = -HUGE_VAL;
    uint32_t cl = 0, l;
    int k, first = v->cand < 0;
    if (first) {
        if (grow((void **)&s->cd, &s->ccd, s->ncd + 1, sizeof *s->cd, s))
            return;
        s->v[i].cand = (int32_t)s->ncd++;
    }
    c = &s->cd[s->v[i].cand];
    if (!first) {
        if (!c->full)
            return;
        ct = c->t[c->n - 1], cl = c->line[c->n - 1];
    }
    c->n = c->pos = 0;
    if (2 * s->nlive < s->nlid)
        compact_lines(s);
    for (k = 0; k < (int)s->nlid; k++) {
        double nw = s->lnx[k] * v->vx + s->lny[k] * v->vy, t;
        int j;
        if (!(nw - 1 < -1e-12))
            continue; /* not closing in */
        t = (s->lc[k] - s->lnx[k] * v->x - s->lny[k] * v->y + v->t * nw) /
            (nw - 1);
        l = s->lid[k];
        if (!(t > s->t + s->eps) || t > s->tmax ||
            t < ct || (t == ct && l <= cl))
            continue;
        if (c->n == NCAND && !(t < c->t[NCAND - 1] ||
                               (t == c->t[NCAND - 1] && l < c->line[NCAND - 1])))
            continue;
        if (!s->ln[l].live || l == v->lin || l == v->line)
            continue;
        j = c->n < NCAND ? c->n++ : NCAND - 1;
        while (j > 0 && (c->t[j - 1] > t || (c->t[j - 1] == t &&
                                              c->line[j - 1] > l))) {
            c->t[j] = c->t[j - 1], c->line[j] = c->line[j - 1];
            j--;
        }
        c->t[j] = t, c->line[j] = l;
    }
    c->full = c->n == NCAND;
    if (c->n > 0)
        heap_push(s, c->t[0], i, c->line[0], EV_SPLIT);
}

/* Reflex vertex i's next candidate onto the heap. */
static void cand_next(qs *s, uint32_t i)
{
    qcand *c = &s->cd[s->v[i].cand];
    if (++c->pos < c->n)
        heap_push(s, c->t[c->pos], i, c->line[c->pos], EV_SPLIT);
    else
        cand_batch(s, i);
}

/* Is r at one of its neighbours now?  Then it is their edge event (the
 * paper's: an edge event wins a tie with a split). */
static int at_neighbour(const qs *s, uint32_t r)
{
    double x, y, px, py, nx, ny;
    pos(s, r, s->t, &x, &y);
    pos(s, s->v[r].prev, s->t, &px, &py);
    pos(s, s->v[r].next, s->t, &nx, &ny);
    return hypot(px - x, py - y) <= s->tol || hypot(nx - x, ny - y) <= s->tol;
}

/* The piece of line l that reflex vertex r lands on now, or UINT32_MAX. */
static uint32_t split_target(qs *s, uint32_t r, uint32_t l)
{
    qline *L = &s->ln[l];
    double hx, hy;
    size_t k = 0;
    uint32_t hit = UINT32_MAX;
    if (at_neighbour(s, r))
        return UINT32_MAX;
    pos(s, r, s->t, &hx, &hy);
    while (k < L->npiece) {
        uint32_t e = L->piece[k];
        double ax, ay, bx, by, ex, ey, L2, u;
        if (!s->v[e].alive) { /* gone for good: drop it */
            L->piece[k] = L->piece[--L->npiece];
            continue;
        }
        k++;
        if (hit != UINT32_MAX || e == r || s->v[e].next == r)
            continue;
        pos(s, e, s->t, &ax, &ay);
        pos(s, s->v[e].next, s->t, &bx, &by);
        ex = bx - ax, ey = by - ay, L2 = ex * ex + ey * ey;
        if (!(L2 > 0))
            continue;
        u = ((hx - ax) * ex + (hy - ay) * ey) / L2;
        if (u >= -1e-9 && u <= 1 + 1e-9)
            hit = e;
    }
    return hit;
}

/* Reflex vertex r lands on the edge e -> f: two rings, r's copy in each
 * (as the paper's split in skeleton.c). */
static void split_at(qs *s, uint32_t r, uint32_t e)
{
    uint32_t p = s->v[r].prev, n = s->v[r].next, f = s->v[e].next;
    uint32_t L = s->v[e].line, rl = s->v[r].line, plin = s->v[r].lin, r1, r2;
    double x, y;
    pos(s, r, s->t, &x, &y);
    node(s, r);
    flush(s, p), flush(s, r), flush(s, e);
    r1 = vert_new(s, x, y, plin, L); /* p -> r1 -> f ... */
    r2 = vert_new(s, x, y, L, rl);   /* e -> r2 -> n ... */
    if (s->rc)
        return;
    kill(s, r);
    link2(s, p, r1), link2(s, r1, f);
    link2(s, e, r2), link2(s, r2, n);
    s->nsplits++;
    work(s, r1), work(s, r2), work(s, e), work(s, f), work(s, p), work(s, n);
}

/* ---- the local clean-up after an event (skeleton.c: collapse, despike,
 * prune) ---- */

/* The ring through i is done: nodes at its corners, a peak at their mean. */
static void ring_done(qs *s, uint32_t i)
{
    uint32_t j = i;
    double mx = 0, my = 0, x, y;
    size_t n = 0;
    do {
        flush(s, j);
        node(s, j);
        pos(s, j, s->t, &x, &y);
        mx += x, my += y, n++;
        kill(s, j);
        j = s->v[j].next;
    } while (j != i && n < s->nv);
    if (s->peaks && s->rc == 0) {
        td_line *l = td_lines_add(s->peaks, s->cx);
        if (!l || td_line_push(l, mx / n, my / n, s->cx) != 0)
            s->rc = TD_ENOMEM;
        else
            l->has_height = 1, l->height = s->t;
    }
}

/* 1: the ring through i is done (under 3 corners or no area); 0: not, or
 * too long to tell cheaply (long rings end through their events). */
static int ring_small(qs *s, uint32_t i)
{
    uint32_t j = i;
    double a = 0, x0, y0, x1, y1;
    int n = 0;
    do {
        pos(s, j, s->t, &x0, &y0);
        pos(s, s->v[j].next, s->t, &x1, &y1);
        a += x0 * y1 - x1 * y0;
        j = s->v[j].next;
        n++;
    } while (j != i && n < RING_WALK);
    if (j != i)
        return 0;
    return n < 3 || fabs(0.5 * a) <= s->eps * s->eps;
}

/* Edge a -> next shorter than tol (or force: its edge event is now): one
 * vertex at the middle, taking the next's outgoing line. */
static int collapse_at(qs *s, uint32_t a, int force)
{
    uint32_t b = s->v[a].next, p = s->v[a].prev, n = s->v[b].next, m;
    double ax, ay, bx, by;
    pos(s, a, s->t, &ax, &ay);
    pos(s, b, s->t, &bx, &by);
    if (!force && hypot(bx - ax, by - ay) > s->tol)
        return 0;
    flush(s, p), flush(s, a), flush(s, b);
    m = vert_new(s, 0.5 * (ax + bx), 0.5 * (ay + by), s->v[a].lin,
                 s->v[b].line);
    if (s->rc)
        return 1;
    node(s, m);
    kill(s, a), kill(s, b);
    if (n == a) { /* a ring of two: m alone */
        link2(s, m, m);
    } else {
        link2(s, p, m), link2(s, m, n);
    }
    work(s, m), work(s, p), work(s, n);
    return 1;
}

/* A spike with its tip at i (its two sides run back along each other):
 * the tip goes, the shorter side with it, the longer goes on. */
static int despike_at(qs *s, uint32_t i)
{
    uint32_t p = s->v[i].prev, n = s->v[i].next, r;
    const qline *A = &s->ln[s->v[i].lin], *B = &s->ln[s->v[i].line];
    double px, py, tx, ty, nx, ny, la, lb, cr;
    if (A->nx * B->nx + A->ny * B->ny > -1 + 1e-9 || p == n)
        return 0;
    pos(s, p, s->t, &px, &py);
    pos(s, i, s->t, &tx, &ty);
    pos(s, n, s->t, &nx, &ny);
    la = hypot(tx - px, ty - py), lb = hypot(nx - tx, ny - ty);
    cr = (tx - px) * (ny - ty) - (ty - py) * (nx - tx);
    if (fabs(cr) > s->tol * (la + lb + s->tol))
        return 0;
    node(s, i);
    node(s, la < lb ? p : n);
    flush(s, s->v[p].prev), flush(s, p), flush(s, i), flush(s, n);
    if (la < lb) { /* p takes the tip's outgoing line */
        uint32_t pp = s->v[p].prev;
        r = vert_new(s, px, py, s->v[p].lin, s->v[i].line);
        if (s->rc)
            return 1;
        kill(s, p), kill(s, i);
        if (pp == n) /* the ring had three corners */
            link2(s, r, n), link2(s, n, r);
        else
            link2(s, pp, r), link2(s, r, n);
        work(s, r), work(s, pp), work(s, n);
    } else { /* the tip goes; n now follows p's line */
        uint32_t nn = s->v[n].next;
        r = vert_new(s, nx, ny, s->v[p].line, s->v[n].line);
        if (s->rc)
            return 1;
        kill(s, i), kill(s, n);
        if (nn == p)
            link2(s, p, r), link2(s, r, p);
        else
            link2(s, p, r), link2(s, r, nn);
        work(s, r), work(s, p), work(s, nn);
    }
    return 1;
}

static void cleanup(qs *s)
{
    size_t k;
    while (s->nwork > 0 && s->rc == 0) {
        uint32_t i = s->work[--s->nwork];
        if (!s->v[i].alive)
            continue;
        if (ring_small(s, i)) {
            ring_done(s, i);
            continue;
        }
        if (collapse_at(s, i, 0) || despike_at(s, i))
            continue;
    }
    for (k = 0; k < s->nborn && s->rc == 0; k++) { /* their events */
        uint32_t i = s->born[k];
        if (!s->v[i].alive)
            continue;
        push_edge(s, i);
        push_edge(s, s->v[i].prev);
        if (s->v[i].reflex)
            cand_batch(s, i);
    }
    s->nborn = 0;
}

/* ---- contours ---- */

static int emit_contours(qs *s, td_lines *out, double T)
{
    size_t i, k;
    s->level++;
    for (i = 0; i < s->nv; i++) {
        uint32_t j = (uint32_t)i;
        td_line *l;
        double a = 0;
        if (!s->v[i].alive || s->v[i].mark == s->level)
            continue;
        if (!(l = td_lines_add(out, s->cx)))
            return TD_ENOMEM;
        do {
            double x, y;
            pos(s, j, T, &x, &y);
            s->v[j].mark = s->level;
            if (td_line_push(l, x, y, s->cx) != 0)
                return TD_ENOMEM;
            j = s->v[j].next;
        } while (j != i);
        for (k = 0; k < l->n; k++) {
            size_t q = (k + 1) % l->n;
            a += l->xy[2 * k] * l->xy[2 * q + 1] -
                 l->xy[2 * q] * l->xy[2 * k + 1];
        }
        if (l->n < 3 || fabs(0.5 * a) <= 1e6 * s->eps * s->eps) {
            td_lines_remove(out, out->n - 1);
            continue;
        }
        l->closed = 1;
        l->has_height = 1;
        l->height = T;
    }
    return 0;
}

/* ---- the run ---- */

static int setup(qs *s, const double *xy, size_t n)
{
    size_t i;
    if (!(s->ln = calloc(n, sizeof *s->ln)) ||
        !(s->lnx = malloc(n * sizeof *s->lnx)) ||
        !(s->lny = malloc(n * sizeof *s->lny)) ||
        !(s->lc = malloc(n * sizeof *s->lc)) ||
        !(s->lid = malloc(n * sizeof *s->lid)))
        return td_seterr(s->cx, TD_ENOMEM, "skeleton: out of memory");
    s->nl = s->nlid = s->nlive = n;
    for (i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        double dx = b[0] - a[0], dy = b[1] - a[1], L = hypot(dx, dy);
        s->ln[i].nx = -dy / L, s->ln[i].ny = dx / L;
        s->ln[i].c = s->ln[i].nx * a[0] + s->ln[i].ny * a[1];
        s->lnx[i] = s->ln[i].nx, s->lny[i] = s->ln[i].ny, s->lc[i] = s->ln[i].c;
        s->lid[i] = (uint32_t)i;
    }
    for (i = 0; i < n; i++)
        vert_new(s, xy[2 * i], xy[2 * i + 1], (uint32_t)((i + n - 1) % n),
                 (uint32_t)i);
    if (s->rc)
        return s->rc;
    for (i = 0; i < n; i++)
        link2(s, (uint32_t)i, (uint32_t)((i + 1) % n));
    return 0;
}

/* A popped event still stands: the edge's two ends alive and joined, the
 * split's vertex alive (its landing is checked by split_target). */
static int stands(const qs *s, const qev *e)
{
    if (e->kind == EV_EDGE)
        return s->v[e->a].alive && s->v[e->b].alive &&
               s->v[e->a].next == e->b;
    return s->v[e->a].alive;
}

static int run(qs *s, td_lines *contours, double *next_level)
{
    while (s->nh > 0 && s->rc == 0) {
        qev e = heap_pop(s);
        uint32_t tgt = UINT32_MAX;
        double T;
        if (!stands(s, &e))
            continue;
        T = e.t > s->t ? e.t : s->t;
        if (e.kind == EV_SPLIT) { /* check it against the front at T */
            double keep = s->t;
            s->t = T;
            tgt = split_target(s, e.a, e.b);
            s->t = keep;
            if (tgt == UINT32_MAX) {
                cand_next(s, e.a);
                continue;
            }
        }
        if (s->nevents++ >= s->prm->max_events)
            return td_seterr(s->cx, TD_EINVAL, "skeleton: more than %zu "
                             "events", s->prm->max_events);
        while (contours && *next_level <= T + s->eps && s->rc == 0) {
            if (emit_contours(s, contours, *next_level) != 0)
                return TD_ENOMEM;
            *next_level += s->prm->contour_step;
        }
        s->t = T;
        if (e.kind == EV_SPLIT) {
            split_at(s, e.a, tgt);
        } else if (!ring_small(s, e.a)) { /* they meet: one vertex */
            collapse_at(s, e.a, 1);
        } else {
            work(s, e.a);
        }
        cleanup(s);
    }
    return s->rc;
}

/* See model_int.h. */
int td_skeleton_queue(const double *xy, size_t n, double size,
                      const td_skeleton_params *prm, td_grid_f32 *dem,
                      td_lines *contours, td_lines *peaks,
                      td_skeleton_stats *st, td_ctx *cx)
{
    qs s;
    double next_level = prm->contour_step > 0 ? prm->contour_step : HUGE_VAL;
    size_t i;
    int rc;
    memset(&s, 0, sizeof s);
    s.prm = prm, s.dem = dem, s.peaks = peaks, s.cx = cx;
    s.eps = 1e-9 * size;
    s.tol = 1e3 * s.eps;
    s.tmax = size; /* no point is further inside than the outline's size */
    if ((rc = setup(&s, xy, n)) == 0) {
        for (i = 0; i < n && s.rc == 0; i++)
            work(&s, (uint32_t)i);
        cleanup(&s);
        rc = run(&s, contours, &next_level);
    }
    for (i = 0; i < s.nv && rc == 0; i++) /* what never shrinks: parallel */
        if (s.v[i].alive)                  /* sides only; as the paper's */
            kill(&s, (uint32_t)i);
    if (st) {
        st->events = s.nevents;
        st->splits = s.nsplits;
        st->max_time = s.t;
    }
    for (i = 0; i < s.nl; i++)
        free(s.ln[i].piece);
    free(s.ln), free(s.lnx), free(s.lny), free(s.lc), free(s.lid), free(s.v), free(s.cd), free(s.h), free(s.work), free(s.born);
    return rc;
}
