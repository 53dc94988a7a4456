/* Containment tree of contour lines (ALGORITHMS.md A.5 (b); the paper,
 * 001 §2.3, names the containment relation as what automatic labelling of
 * several summits needs, and leaves it out).
 *
 * Border closing: the border is a perimeter parameter t, clockwise from the
 * top-left corner (t = 0):
 *
 *        t=0 ----------> t=w
 *         ^               |        an open line from end E (t_e) to start
 *         |   sheet       |        S (t_s) is closed from E to S along the
 *         |               v        border in the direction that does not
 *    t=2w+2h <-------- t=w+h       cross t = 0: increasing t when t_e < t_s,
 *                                  decreasing otherwise.
 *
 * Parent of a line: among the regions whose bounding box holds the line's
 * box and whose outline contains the line's middle point (even-odd ray
 * test), the one of smallest area. */
#include "src/core/core.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* Perimeter parameter of the border point nearest (x,y). */
static double perim_t(double x, double y, int w, int h)
{
    double dt = y, db = h - y, dl = x, dr = w - x;
    double m = fmin(fmin(dt, db), fmin(dl, dr));
    if (m == dt)
        return fmin(fmax(x, 0), w);
    if (m == dr)
        return w + fmin(fmax(y, 0), h);
    if (m == db)
        return w + h + (w - fmin(fmax(x, 0), w));
    return 2.0 * w + h + (h - fmin(fmax(y, 0), h));
}

/* Border point at perimeter parameter t. */
static void perim_xy(double t, int w, int h, double *x, double *y)
{
    if (t <= w) {
        *x = t, *y = 0;
    } else if (t <= w + h) {
        *x = w, *y = t - w;
    } else if (t <= 2.0 * w + h) {
        *x = w - (t - w - h), *y = h;
    } else {
        *x = 0, *y = h - (t - 2.0 * w - h);
    }
}

static int on_border(double x, double y, int w, int h)
{
    return x <= TD_CONTAIN_BORDER || y <= TD_CONTAIN_BORDER ||
           x >= w - TD_CONTAIN_BORDER || y >= h - TD_CONTAIN_BORDER;
}

/* Copy l into r and, for a border-to-border open line, walk the border
 * from its end back to its start (see the diagram).  0 when r bounds a
 * region, 1 when l is dangling, or TD_ENOMEM. */
static int make_ring(const td_line *l, int w, int h, td_line *r, td_ctx *cx)
{
    double xs, ys, xe, ye, ts, te, c[3];
    size_t i;
    int k;
    for (i = 0; i < l->n; i++)
        if (td_line_push(r, l->xy[2 * i], l->xy[2 * i + 1], cx) != 0)
            return TD_ENOMEM;
    r->closed = 1;
    if (l->closed)
        return l->n >= 1 ? 0 : 1;
    if (l->n < 2)
        return 1;
    xs = l->xy[0], ys = l->xy[1];
    xe = l->xy[2 * l->n - 2], ye = l->xy[2 * l->n - 1];
    if (!on_border(xs, ys, w, h) || !on_border(xe, ye, w, h))
        return 1;
    ts = perim_t(xs, ys, w, h);
    te = perim_t(xe, ye, w, h);
    c[0] = w, c[1] = (double)w + h, c[2] = 2.0 * w + h; /* corners */
    perim_xy(te, w, h, &xe, &ye);
    if (td_line_push(r, xe, ye, cx) != 0)
        return TD_ENOMEM;
    for (k = 0; k < 3; k++) { /* the corners passed on the way */
        int k2 = te < ts ? k : 2 - k;
        double x, y;
        if (!((te < ts && c[k2] > te && c[k2] < ts) ||
              (te > ts && c[k2] < te && c[k2] > ts)))
            continue;
        perim_xy(c[k2], w, h, &x, &y);
        if (td_line_push(r, x, y, cx) != 0)
            return TD_ENOMEM;
    }
    perim_xy(ts, w, h, &xs, &ys);
    return td_line_push(r, xs, ys, cx) != 0 ? TD_ENOMEM : 0;
}

/* Smallest region other than `self` holding (x,y) within box q. */
static long smallest_holding(const td_contain *ct, const double *boxes,
                             long self, const double q[4], double x, double y)
{
    long best = -1;
    size_t j;
    for (j = 0; j < ct->n; j++) {
        const double *b = &boxes[4 * j];
        if ((long)j == self || ct->parent[j] == -2 || ct->area[j] <= 0)
            continue;
        if (b[0] > q[0] || b[1] > q[1] || b[2] < q[2] || b[3] < q[3])
            continue;
        if (self >= 0 && ct->area[j] <= ct->area[self])
            continue;
        if (best >= 0 && ct->area[j] >= ct->area[best])
            continue;
        if (td_line_encloses(&ct->rings->v[j], x, y))
            best = (long)j;
    }
    return best;
}

/* Contract in contain.h. */
int td_contain_build(const td_lines *ls, int w, int h, td_contain *ct,
                     td_ctx *cx)
{
    double *boxes = NULL;
    size_t i;
    int rc = TD_ENOMEM;
    memset(ct, 0, sizeof *ct);
    if (w < 1 || h < 1)
        return td_seterr(cx, TD_EINVAL, "containment: sheet size %dx%d", w, h);
    ct->n = ls->n;
    ct->parent = td_calloc(ls->n + 1, sizeof *ct->parent, cx);
    ct->area = td_calloc(ls->n + 1, sizeof *ct->area, cx);
    boxes = td_calloc(4 * ls->n + 4, sizeof *boxes, cx);
    if (!ct->parent || !ct->area || !boxes || !(ct->rings = td_lines_new(cx)))
        goto fail;
    for (i = 0; i < ls->n; i++) {
        td_line *r = td_lines_add(ct->rings, cx);
        int k = r ? make_ring(&ls->v[i], w, h, r, cx) : TD_ENOMEM;
        if (k < 0)
            goto fail;
        ct->parent[i] = k ? -2 : -1;
        ct->area[i] = k ? 0 : fabs(td_line_signed_area(r));
        td_line_box(r, &boxes[4 * i]);
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t m = l->n / 2;
        if (ct->parent[i] == -2 || l->n == 0)
            continue;
        ct->parent[i] = smallest_holding(ct, boxes, (long)i, &boxes[4 * i],
                                         l->xy[2 * m], l->xy[2 * m + 1]);
    }
    rc = 0;
fail:
    free(boxes);
    if (rc)
        td_contain_free(ct);
    return rc;
}

void td_contain_free(td_contain *ct)
{
    free(ct->parent);
    free(ct->area);
    td_lines_free(ct->rings);
    memset(ct, 0, sizeof *ct);
}

/* Contract in contain.h. */
long td_contain_locate(const td_contain *ct, double x, double y)
{
    long best = -1;
    size_t j;
    for (j = 0; j < ct->n; j++) {
        if (ct->parent[j] == -2 || ct->area[j] <= 0)
            continue;
        if (best >= 0 && ct->area[j] >= ct->area[best])
            continue;
        if (td_line_encloses(&ct->rings->v[j], x, y))
            best = (long)j;
    }
    return best;
}

/* Contract in contain.h. */
double td_contain_dist(const td_line *l, double x, double y)
{
    double best = INFINITY;
    size_t i, ns = l->closed ? l->n : (l->n ? l->n - 1 : 0);
    if (l->n == 1)
        return hypot(l->xy[0] - x, l->xy[1] - y);
    for (i = 0; i < ns; i++) {
        size_t j = (i + 1) % l->n;
        double ax = l->xy[2 * i], ay = l->xy[2 * i + 1];
        double dx = l->xy[2 * j] - ax, dy = l->xy[2 * j + 1] - ay;
        double L = dx * dx + dy * dy, t = 0;
        if (L > 0)
            t = fmin(1, fmax(0, ((x - ax) * dx + (y - ay) * dy) / L));
        best = fmin(best, hypot(ax + t * dx - x, ay + t * dy - y));
    }
    return best;
}

/* ---- crossings ---------------------------------------------------------- */

typedef struct xseg {
    uint32_t line, k; /* segment k of line (point k to point k+1, wrapping;
                         8 bytes: the grid holds one per piece) */
} xseg;

static const double *seg_pt(const td_lines *ls, const xseg *s, int end)
{
    const td_line *l = &ls->v[s->line];
    size_t k = (size_t)s->k + (size_t)end;
    return l->xy + 2 * (k < l->n ? k : 0);
}

/* ab and cd cross; the point in *x, *y.  Half-open segments ([a,b) and
 * [c,d)), so a line passing exactly through a vertex of the other (pixel
 * centres make that common) is found once; parallel segments never. */
static int proper_cross(const double *a, const double *b, const double *c,
                        const double *d, double *x, double *y)
{
    double t, u;
    if (!td_seg_meet_at(a, b, c, d, &t, &u) || t < 0 || t >= 1 || u < 0 ||
        u >= 1)
        return 0;
    *x = a[0] + t * (b[0] - a[0]), *y = a[1] + t * (b[1] - a[1]);
    return 1;
}

/* Contract in core.h. */
int td_seg_meet_at(const double *a, const double *b, const double *c,
                   const double *d, double *t, double *u)
{
    double r0 = b[0] - a[0], r1 = b[1] - a[1], s0 = d[0] - c[0], s1 = d[1] - c[1];
    double den = r0 * s1 - r1 * s0;
    if (den == 0)
        return 0;
    *t = ((c[0] - a[0]) * s1 - (c[1] - a[1]) * s0) / den;
    *u = ((c[0] - a[0]) * r1 - (c[1] - a[1]) * r0) / den;
    return 1;
}

static int cmp_cross(const void *pa, const void *pb)
{
    const td_crossing *a = pa, *b = pb;
    if (a->a != b->a)
        return (a->a > b->a) - (a->a < b->a);
    if (a->b != b->b)
        return (a->b > b->b) - (a->b < b->b);
    if (a->y != b->y) /* a total order: the same result from any thread */
        return (a->y > b->y) - (a->y < b->y);
    return (a->x > b->x) - (a->x < b->x);
}

/* A bucket grid of segment pieces: every segment goes into each cell its
 * pieces (at most one cell long) cover.  Cells are 16 px, or coarser when
 * the lines' extent is large and the lines few, so memory follows what
 * the lines contain, not the coordinates they claim. */
typedef struct xgrid {
    double x0, y0, cs, inv; /* cell size and 1 / it */
    long cw, ch;
    size_t *start; /* cw*ch + 1 offsets into segs */
    xseg *segs;
} xgrid;

#define XCELLS_MIN 4000000

static long xcell(const xgrid *g, double v, double o, long lim)
{
    /* cs is 16 times a power of two: times its inverse is the division;
       the cast truncates, and below o where it differs from floor the
       clamp makes both 0 (floor was a call) */
    long c = (long)((v - o) * g->inv);
    return c < 0 ? 0 : c >= lim ? lim - 1 : c;
}

/* Visit the cells of segment s: pass 0 counts it in cnt[c], pass 1
 * places it at segs[cnt[c]++]. */
static void xvisit(const xgrid *g, const td_lines *ls, xseg s, size_t *cnt,
                   xseg *segs, int pass)
{
    const double *a = seg_pt(ls, &s, 0), *b = seg_pt(ls, &s, 1);
    double dx = fabs(b[0] - a[0]), dy = fabs(b[1] - a[1]);
    /* one piece when surely no longer than a cell (most: traced lines
       step 1 px), else pieces of at most a cell */
    long m = dx + dy <= g->cs ? 1 : (long)ceil(hypot(dx, dy) / g->cs), k, cx,
         cy, lastc = -1;
    m = m < 1 ? 1 : m;
    for (k = 0; k < m; k++) {
        double t0 = (double)k / m, t1 = (double)(k + 1) / m;
        double xa = a[0] + t0 * (b[0] - a[0]), xb = a[0] + t1 * (b[0] - a[0]);
        double ya = a[1] + t0 * (b[1] - a[1]), yb = a[1] + t1 * (b[1] - a[1]);
        long x0 = xcell(g, xa < xb ? xa : xb, g->x0, g->cw);
        long x1 = xcell(g, xa < xb ? xb : xa, g->x0, g->cw);
        long y0 = xcell(g, ya < yb ? ya : yb, g->y0, g->ch);
        long y1 = xcell(g, ya < yb ? yb : ya, g->y0, g->ch);
        for (cy = y0; cy <= y1; cy++)
            for (cx = x0; cx <= x1; cx++) {
                long c = cy * g->cw + cx;
                if (c == lastc) /* consecutive pieces share a cell */
                    continue;
                if (pass == 0)
                    cnt[c]++;
                else
                    segs[cnt[c]++] = s;
                if (x0 == x1 && y0 == y1)
                    lastc = c;
            }
    }
}

/* xvisit every segment of lines [q0, q1), in order. */
static void xvisit_run(const xgrid *g, const td_lines *ls, size_t q0, size_t q1,
                       size_t *cnt, xseg *segs, int pass)
{
    size_t q, j;
    for (q = q0; q < q1; q++) {
        const td_line *l = &ls->v[q];
        size_t ns = l->n < 2 ? 0 : l->closed ? l->n : l->n - 1;
        for (j = 0; j < ns; j++) {
            xseg s = {(uint32_t)q, (uint32_t)j};
            xvisit(g, ls, s, cnt, segs, pass);
        }
    }
}

/* The lines in P runs of about equal vertex counts (a run per thread, at
 * most XG_PARTS: 8 bytes per cell each), each counted
 * and placed on its own thread into its own share of every cell, the
 * runs in line order: a cell's pieces come in line order as from one
 * pass over the lines (10000^2 benchmark sheet: 0.45 -> 0.25 s). */
#define XG_PARTS 8

static int xgrid_build(const td_lines *ls, xgrid *g, td_ctx *cx)
{
    double x1 = -INFINITY, y1 = -INFINITY;
    size_t i, k, n = 0, *cnt = NULL, cap, nc, cut[XG_PARTS + 1], done = 0;
    int t, P = omp_get_max_threads();
    P = P < 1 ? 1 : P > XG_PARTS ? XG_PARTS : P;
    memset(g, 0, sizeof *g);
    g->x0 = g->y0 = INFINITY;
    for (i = 0; i < ls->n; i++) { /* (comparisons: fmin is a call) */
        const double *xy = ls->v[i].xy;
        for (k = 0; k < ls->v[i].n; k++) {
            double x = xy[2 * k], y = xy[2 * k + 1];
            g->x0 = x < g->x0 ? x : g->x0, x1 = x > x1 ? x : x1;
            g->y0 = y < g->y0 ? y : g->y0, y1 = y > y1 ? y : y1;
        }
        n += ls->v[i].n;
    }
    if (n == 0)
        return 0;
    if (ls->n > UINT32_MAX || n > UINT32_MAX)
        return td_seterr(cx, TD_ETOOBIG, "crossings: %zu lines, %zu points: "
                         "too many", ls->n, n);
    cap = n < XCELLS_MIN / 16 ? XCELLS_MIN : 16 * n;
    for (g->cs = 16.0;
         ((x1 - g->x0) / g->cs + 1) * ((y1 - g->y0) / g->cs + 1) > (double)cap;
         g->cs *= 2)
        ;
    g->inv = 1.0 / g->cs;
    g->cw = (long)((x1 - g->x0) / g->cs) + 1, g->ch = (long)((y1 - g->y0) / g->cs) + 1;
    nc = (size_t)g->cw * g->ch;
    for (i = 0, t = 0, cut[0] = 0; i < ls->n; i++) { /* the runs */
        done += ls->v[i].n;
        while (t + 1 < P && done * P >= (size_t)(t + 1) * n)
            cut[++t] = i + 1;
    }
    while (t < P)
        cut[++t] = ls->n;
    if (!(g->start = calloc(nc + 1, sizeof *g->start)) ||
        !(cnt = calloc((size_t)P * nc + 1, sizeof *cnt)))
        goto nomem;
#pragma omp parallel for schedule(dynamic)
    for (t = 0; t < P; t++) /* count */
        xvisit_run(g, ls, cut[t], cut[t + 1], cnt + (size_t)t * nc, NULL, 0);
    for (i = 0, k = 0; i < nc; i++) { /* each run's first slot per cell */
        g->start[i] = k;
        for (t = 0; t < P; t++) {
            size_t c = cnt[(size_t)t * nc + i];
            cnt[(size_t)t * nc + i] = k;
            k += c;
        }
    }
    g->start[nc] = k;
    if (!(g->segs = malloc((k + 1) * sizeof *g->segs)))
        goto nomem;
#pragma omp parallel for schedule(dynamic)
    for (t = 0; t < P; t++) /* place */
        xvisit_run(g, ls, cut[t], cut[t + 1], cnt + (size_t)t * nc, g->segs, 1);
    free(cnt);
    return 0;
nomem:
    free(cnt);
    return td_seterr(cx, TD_ENOMEM, "crossings: out of memory");
}

static int add_cross(td_crossing **v, size_t *n, size_t *cap, long a, long b,
                     double x, double y)
{
    if (*n == *cap) {
        size_t c = *cap ? 2 * *cap : 16;
        td_crossing *p = realloc(*v, c * sizeof *p);
        if (!p)
            return TD_ENOMEM;
        *v = p, *cap = c;
    }
    (*v)[*n].a = a < b ? a : b, (*v)[*n].b = a < b ? b : a;
    (*v)[*n].x = x, (*v)[*n].y = y;
    ++*n;
    return 0;
}

/* Contract in contain.h. */
int td_contain_crossings(const td_lines *ls, td_crossing **out, size_t *nout,
                         td_ctx *cx)
{
    xgrid g;
    td_crossing *v = NULL;
    size_t n = 0, cap = 0, i, w, nc;
    int rc = xgrid_build(ls, &g, cx), fail = 0;
    *out = NULL, *nout = 0;
    if (rc || !g.segs)
        goto done;
    nc = (size_t)g.cw * g.ch;
#pragma omp parallel
    { /* cells on threads, each its own list; sorted after, so the
         result does not depend on the threads */
        td_crossing *tv = NULL;
        size_t tn = 0, tcap = 0, c, a, b, be;
        int tfail = 0;
#pragma omp for schedule(dynamic, 256) nowait
        for (c = 0; c < nc; c++)
            for (a = g.start[c], be = a; a < g.start[c + 1] && !tfail; a++) {
                const xseg *s = &g.segs[a];
                const double *p = seg_pt(ls, s, 0), *q = seg_pt(ls, s, 1);
                double x0 = fmin(p[0], q[0]), x1 = fmax(p[0], q[0]);
                double y0 = fmin(p[1], q[1]), y1 = fmax(p[1], q[1]);
                /* a cell's pieces come in line order: the pieces of
                   later lines start at be */
                while (be < g.start[c + 1] && g.segs[be].line == s->line)
                    be++;
                for (b = be; b < g.start[c + 1]; b++) {
                    const xseg *t = &g.segs[b];
                    const double *e = seg_pt(ls, t, 0), *f = seg_pt(ls, t, 1);
                    double x, y;
                    /* boxes apart: no crossing (exact: comparisons only) */
                    if (fmax(e[0], f[0]) < x0 || fmin(e[0], f[0]) > x1 ||
                        fmax(e[1], f[1]) < y0 || fmin(e[1], f[1]) > y1 ||
                        !proper_cross(p, q, e, f, &x, &y))
                        continue;
                    /* each crossing once: in the cell that holds it */
                    if ((size_t)(xcell(&g, y, g.y0, g.ch) * g.cw +
                                 xcell(&g, x, g.x0, g.cw)) != c)
                        continue;
                    if (add_cross(&tv, &tn, &tcap, ls->v[s->line].id,
                                  ls->v[t->line].id, x, y) != 0) {
                        tfail = 1;
                        break;
                    }
                }
            }
#pragma omp critical(td_crossings)
        {
            if (tfail || (tn && td_grow((void **)&v, &cap, n + tn,
                                        sizeof *v, NULL) != 0))
                fail = 1;
            else if (tn)
                memcpy(v + n, tv, tn * sizeof *v), n += tn;
        }
        free(tv);
    }
    if (fail) {
        rc = td_seterr(cx, TD_ENOMEM, "crossings: out of memory");
        goto done;
    }
    if (n > 1) /* one per pair */
        qsort(v, n, sizeof *v, cmp_cross);
    for (i = 0, w = 0; i < n; i++)
        if (w == 0 || v[w - 1].a != v[i].a || v[w - 1].b != v[i].b)
            v[w++] = v[i];
    *out = v, *nout = w;
    v = NULL;
done:
    free(v);
    free(g.start);
    free(g.segs);
    return rc;
}

/* ---- does a segment cross a line ---------------------------------------- */

struct td_seggrid {
    const td_lines *ls;
    xgrid g;
};

/* Contract in core.h. */
td_seggrid *td_seggrid_new(const td_lines *ls, td_ctx *cx)
{
    td_seggrid *s = td_calloc(1, sizeof *s, cx);
    if (!s)
        return NULL;
    s->ls = ls;
    if (xgrid_build(ls, &s->g, cx) != 0) {
        td_seggrid_free(s);
        return NULL;
    }
    return s;
}

void td_seggrid_free(td_seggrid *s)
{
    if (!s)
        return;
    free(s->g.start);
    free(s->g.segs);
    free(s);
}

/* Contract in core.h. */
int td_seggrid_crosses(const td_seggrid *s, const double *a, const double *b)
{
    const xgrid *g = &s->g;
    double bx0 = fmin(a[0], b[0]), bx1 = fmax(a[0], b[0]);
    double by0 = fmin(a[1], b[1]), by1 = fmax(a[1], b[1]);
    long cx0, cx1, cy0, cy1, cx, cy;
    if (!g->segs)
        return 0;
    cx0 = xcell(g, bx0, g->x0, g->cw), cx1 = xcell(g, bx1, g->x0, g->cw);
    cy0 = xcell(g, by0, g->y0, g->ch), cy1 = xcell(g, by1, g->y0, g->ch);
    for (cy = cy0; cy <= cy1; cy++)
        for (cx = cx0; cx <= cx1; cx++) {
            long c = cy * g->cw + cx;
            size_t k;
            for (k = g->start[c]; k < g->start[c + 1]; k++) {
                const double *e = seg_pt(s->ls, &g->segs[k], 0);
                const double *f = seg_pt(s->ls, &g->segs[k], 1);
                double t, u;
                if (fmax(e[0], f[0]) < bx0 || fmin(e[0], f[0]) > bx1 ||
                    fmax(e[1], f[1]) < by0 || fmin(e[1], f[1]) > by1 ||
                    !td_seg_meet_at(a, b, e, f, &t, &u))
                    continue;
                /* inside ab (its ends may lie on lines), anywhere on ef */
                if (t > 1e-9 && t < 1 - 1e-9 && u >= 0 && u <= 1)
                    return 1;
            }
        }
    return 0;
}
