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
#include "contain.h"

#include <math.h>
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

static double ring_area(const td_line *r)
{
    double a = 0;
    size_t i;
    for (i = 0; i < r->n; i++) {
        size_t j = (i + 1) % r->n;
        a += r->xy[2 * i] * r->xy[2 * j + 1] - r->xy[2 * j] * r->xy[2 * i + 1];
    }
    return fabs(a) / 2;
}

/* Even-odd ray test of (x,y) against the closed outline r. */
static int inside(const td_line *r, double x, double y)
{
    size_t i, j;
    int in = 0;
    for (i = 0, j = r->n - 1; i < r->n; j = i++) {
        double xi = r->xy[2 * i], yi = r->xy[2 * i + 1];
        double xj = r->xy[2 * j], yj = r->xy[2 * j + 1];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
            in = !in;
    }
    return in;
}

static void bbox(const td_line *l, double b[4])
{
    size_t i;
    b[0] = b[1] = INFINITY;
    b[2] = b[3] = -INFINITY;
    for (i = 0; i < l->n; i++) {
        b[0] = fmin(b[0], l->xy[2 * i]);
        b[1] = fmin(b[1], l->xy[2 * i + 1]);
        b[2] = fmax(b[2], l->xy[2 * i]);
        b[3] = fmax(b[3], l->xy[2 * i + 1]);
    }
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
        if (inside(&ct->rings->v[j], x, y))
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
        ct->area[i] = k ? 0 : ring_area(r);
        bbox(r, &boxes[4 * i]);
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
        if (inside(&ct->rings->v[j], x, y))
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
