/* Contour tracing (paper 001 §2.3, Fig. 3; ALGORITHMS.md A.4).
 *
 *  1. Scan the skeleton row by row from the top left; the first pixel not
 *     yet visited starts a line.
 *  2. Search the 3x3 neighbourhood of the current pixel counter-clockwise,
 *     starting east, for a pixel not yet visited; the first one found is the
 *     next point.  The current pixel is marked visited.
 *
 *        3x3 order          5x5 ring order
 *         3 2 1            6  5  4  3  2
 *         4 p 0            7  .  .  .  1
 *         5 6 7            8  .  p  .  0
 *                          9  .  .  .  15
 *                          10 11 12 13 14
 *
 *  3. With no such pixel in the 3x3, search the 5x5 ring the same way: a
 *     pixel found there is a break in the line; bridge it and go on
 *     (TD_BRIDGE_PAPER; ours, TD_BRIDGE_AHEAD, the default: the ring's
 *     pixel most nearly straight ahead, within 50 degrees, or none).
 *  4. With none in the 5x5 either, the line ends.
 *
 * Decisions where the paper is silent (ALGORITHMS.md A.4):
 *  - a line is closed when its end comes back next to its start (3x3), or
 *    within the 5x5 ring (a bridged closure), with >= min_closed points;
 *    this test comes before the 5x5 search, so a finished ring does not
 *    jump to a neighbouring contour;
 *  - a start pixel in the middle of an open line (the first pixel in raster
 *    order of an arch) leaves the other half unvisited: when the first leg
 *    ends, the line is reversed and traced on from its start, so one open
 *    contour gives one line;
 *  - a junction (touching contours) is passed along one branch; the others
 *    start lines of their own, so no pixel is lost (the paper, cut 0);
 *    ours (cut 1, the default): junction pixels are left out, every branch
 *    ends next to the junction (no 5x5 bridge from there: it is no break)
 *    and td_join pairs the branches by direction, so a line does not turn
 *    onto a touching contour; nor does a diagonal step round the corner of
 *    a junction pixel carry it from one branch onto the next (corner_cut);
 *  - open lines ending within edge_dist px of the border are extended to it
 *    (along their direction) and flagged edge;
 *  - a line fitting in a 3x3 window off the border is a ring smaller than
 *    the line width (filled in, thinned to a dot): it is closed. */
#include "scanner/trace.h"

#include "scanner/skel.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define VISITED 0x02
#define JUNCTION 0x04 /* cut: a junction pixel, traced by no line */

static const int R5X[16] = {2, 2, 2, 1, 0, -1, -2, -2, -2, -2, -2, -1, 0, 1, 2, 2};
static const int R5Y[16] = {0, -1, -2, -2, -2, -2, -2, -1, 0, 1, 2, 2, 2, 2, 2, 1};

td_trace_params td_trace_defaults(void)
{
    td_trace_params p;
    p.bridge = TD_BRIDGE_AHEAD;
    p.edge_dist = 3;
    p.min_closed = 4;
    p.cut = 1;
    return p;
}

static int unvisited(const td_grid_u8 *g, int x, int y)
{
    return x >= 0 && y >= 0 && x < g->w && y < g->h && TD_AT(g, x, y) == 1;
}

/* Does the diagonal step k from (x,y) cut the corner of a junction pixel
 * (cut) onto another of its branches?  The step's two corner pixels are
 * both 4-neighbours of (x,y) and of the pixel stepped to: when one is a
 * junction and the other is paper, the two pixels sit on two branches of
 * that junction (its crossing number counts them apart), and the step
 * would pass the junction by:
 *
 *      . J .        J: junction, traced by no line; a and b are on two
 *      a . .        of its branches; the step a -> b would carry the line
 *      . b .        from one branch onto the next without a cut there. */
static int corner_cut(const td_grid_u8 *g, int x, int y, int k)
{
    int c1, c2;
    if (!(k & 1))
        return 0;
    c1 = TD_AT(g, x + TD_DX[k], y);
    c2 = TD_AT(g, x, y + TD_DY[k]);
    return ((c1 & JUNCTION) && c2 == 0) || ((c2 & JUNCTION) && c1 == 0);
}

/* The next pixel from (x,y): 3x3 first, then (if bridge) the 5x5 ring.
 * Returns 0 none, 1 found in 3x3, 2 found in the 5x5 ring. */
static int search_next(const td_grid_u8 *g, int x, int y, int bridge, int *nx,
                       int *ny)
{
    int k;
    if (x > 0 && y > 0 && x + 1 < g->w && y + 1 < g->h) {
        const uint8_t *p = g->data + (size_t)y * g->stride + (size_t)x;
        const ptrdiff_t s = (ptrdiff_t)g->stride;
        const ptrdiff_t off[8] = {1, 1 - s, -s, -1 - s, -1, s - 1, s, s + 1};
        for (k = 0; k < 8; k++)
            if (p[off[k]] == 1 && !corner_cut(g, x, y, k)) {
                *nx = x + TD_DX[k];
                *ny = y + TD_DY[k];
                return 1;
            }
        if (!bridge)
            return 0;
        goto ring;
    }
    for (k = 0; k < 8; k++)
        if (unvisited(g, x + TD_DX[k], y + TD_DY[k]) &&
            !corner_cut(g, x, y, k)) {
            *nx = x + TD_DX[k];
            *ny = y + TD_DY[k];
            return 1;
        }
    if (!bridge)
        return 0;
ring:
    for (k = 0; k < 16; k++)
        if (unvisited(g, x + R5X[k], y + R5Y[k])) {
            *nx = x + R5X[k];
            *ny = y + R5Y[k];
            return 2;
        }
    return 0;
}

static int visit(td_grid_u8 *g, td_line *l, int x, int y, td_ctx *cx)
{
    TD_AT(g, x, y) |= VISITED;
    return td_line_push(l, x + 0.5, y + 0.5, cx);
}

/* Chebyshev distance between two points of l. */
static int cheb(const td_line *l, size_t a, size_t b)
{
    int dx = abs((int)(l->xy[2 * a] - l->xy[2 * b]));
    int dy = abs((int)(l->xy[2 * a + 1] - l->xy[2 * b + 1]));
    return dx > dy ? dx : dy;
}

/* Is a junction pixel (cut) among the 8 neighbours of (x,y)? */
static int at_junction(const td_grid_u8 *g, int x, int y)
{
    int k;
    for (k = 0; k < 8; k++) {
        int u = x + TD_DX[k], v = y + TD_DY[k];
        if (u >= 0 && v >= 0 && u < g->w && v < g->h &&
            (TD_AT(g, u, v) & JUNCTION))
            return 1;
    }
    return 0;
}

/* Ours (TD_BRIDGE_AHEAD): the unvisited pixel of the 5x5 ring that goes
 * on most nearly straight along the line's last AHEAD_BACK px, within
 * AHEAD_TURN degrees; 0 when none does.  The paper takes the first one
 * counter-clockwise, which where contours run 3-5 px apart is as often
 * the neighbouring contour beside the break as the line's own far side. */
#define AHEAD_BACK 6
#define AHEAD_TURN 50.0
static int bridge_ahead(const td_grid_u8 *g, const td_line *l, int *nx,
                        int *ny)
{
    size_t last = l->n - 1, back = last >= AHEAD_BACK ? last - AHEAD_BACK : 0;
    double dx = l->xy[2 * last] - l->xy[2 * back];
    double dy = l->xy[2 * last + 1] - l->xy[2 * back + 1];
    double d = hypot(dx, dy), best = cos(AHEAD_TURN * M_PI / 180.0);
    int x = (int)l->xy[2 * last], y = (int)l->xy[2 * last + 1], k, found = 0;
    if (last < 2 || !(d > 0))
        return 0; /* no direction yet */
    for (k = 0; k < 16; k++) {
        double c = (R5X[k] * dx + R5Y[k] * dy) / (d * hypot(R5X[k], R5Y[k]));
        if (c >= best && unvisited(g, x + R5X[k], y + R5Y[k])) {
            best = c, found = 1;
            *nx = x + R5X[k], *ny = y + R5Y[k];
        }
    }
    return found;
}

/* Follow the line from its last point (already visited) until it ends or
 * closes on its first point.  Returns 0 or an error. */
static int follow(td_grid_u8 *g, td_line *l, const td_trace_params *p,
                  td_ctx *cx)
{
    for (;;) {
        size_t last = l->n - 1;
        int x = (int)l->xy[2 * last], y = (int)l->xy[2 * last + 1], nx, ny;
        int found = search_next(g, x, y, 0, &nx, &ny);
        if (!found) {
            if (l->n >= (size_t)p->min_closed && cheb(l, 0, last) <= 1) {
                l->closed = 1;
                return 0;
            }
            if (p->bridge == TD_BRIDGE_AHEAD)
                found = !at_junction(g, x, y) && bridge_ahead(g, l, &nx, &ny);
            else
                found = search_next(g, x, y,
                                    p->bridge && !at_junction(g, x, y), &nx,
                                    &ny);
            if (!found)
                return 0;
            l->bridged++;
        }
        if (visit(g, l, nx, ny, cx) != 0)
            return TD_ENOMEM;
    }
}

/* Distance along (dx,dy) (a unit vector) from (x,y) to the line through
 * the border pixel centres, or a huge value when it points away. */
static double ray_to_border(double x, double y, double dx, double dy, int w,
                            int h)
{
    double t = 1e300;
    if (dx < -1e-9) t = fmin(t, (0.5 - x) / dx);
    if (dx > 1e-9) t = fmin(t, (w - 0.5 - x) / dx);
    if (dy < -1e-9) t = fmin(t, (0.5 - y) / dy);
    if (dy > 1e-9) t = fmin(t, (h - 0.5 - y) / dy);
    return t;
}

/* Extend an open line's end to the border when within d px: along the
 * end's direction (over its last 4 points) when that reaches the border
 * within 2d px, else straight to the nearest border. */
static int extend_end(td_line *l, int at_start, int w, int h, int d,
                      td_ctx *cx)
{
    size_t i = at_start ? 0 : l->n - 1, k;
    double x = l->xy[2 * i], y = l->xy[2 * i + 1], bx = x, by = y;
    double dl = x - 0.5, dr = w - 0.5 - x, dt = y - 0.5, db = h - 0.5 - y;
    double m = fmin(fmin(dl, dr), fmin(dt, db)), tx, ty, tl, t;
    if (m > d)
        return 0;
    l->edge = 1;
    if (m <= 0.0)
        return 0;
    k = at_start ? (l->n > 4 ? 4 : l->n - 1) : (l->n > 4 ? l->n - 5 : 0);
    tx = x - l->xy[2 * k];
    ty = y - l->xy[2 * k + 1];
    tl = hypot(tx, ty);
    t = tl > 0 ? ray_to_border(x, y, tx / tl, ty / tl, w, h) : 1e300;
    if (t <= 2.0 * d) {
        bx = x + t * tx / tl;
        by = y + t * ty / tl;
    } else if (m == dl) bx = 0.5;
    else if (m == dr) bx = w - 0.5;
    else if (m == dt) by = 0.5;
    else by = h - 0.5;
    if (at_start)
        td_line_reverse(l);
    if (td_line_push(l, bx, by, cx) != 0)
        return TD_ENOMEM;
    if (at_start)
        td_line_reverse(l);
    return 0;
}

/* A contour ring smaller than the line is wide fills in and thins to a dot
 * (or a 2-3 px stub): a line that fits in a 3x3 window away from the
 * border is a degenerate closed ring, not an open line. */
static void close_dot(td_line *l)
{
    double b[4];
    td_line_box(l, b);
    if (b[2] - b[0] <= 2.0 && b[3] - b[1] <= 2.0)
        l->closed = 1;
}

/* Trace the line starting at (x,y): forward leg, then backward leg. */
static int trace_line(td_grid_u8 *g, td_lines *ls, int x, int y,
                      const td_trace_params *p, td_ctx *cx)
{
    td_line *l = td_lines_add(ls, cx);
    int nx, ny;
    if (!l || visit(g, l, x, y, cx) != 0 || follow(g, l, p, cx) != 0)
        return TD_ENOMEM;
    if (!l->closed &&
        search_next(g, x, y, p->bridge && !at_junction(g, x, y), &nx, &ny)) {
        td_line_reverse(l);
        if (follow(g, l, p, cx) != 0)
            return TD_ENOMEM;
    }
    if (!l->closed && l->n >= (size_t)p->min_closed &&
        cheb(l, 0, l->n - 1) <= 2 && p->bridge) {
        l->closed = 1;
        l->bridged++;
    }
    if (!l->closed && p->cut) {
        size_t e = l->n - 1;
        l->junc = (unsigned char)(
            at_junction(g, (int)l->xy[0], (int)l->xy[1]) |
            at_junction(g, (int)l->xy[2 * e], (int)l->xy[2 * e + 1]) << 1);
    }
    if (!l->edge)
        l->edge = td_line_on_border(l, g->w, g->h);
    if (!l->closed && !l->edge)
        close_dot(l);
    if (!l->closed && p->edge_dist > 0 &&
        (extend_end(l, 1, g->w, g->h, p->edge_dist, cx) != 0 ||
         extend_end(l, 0, g->w, g->h, p->edge_dist, cx) != 0))
        return TD_ENOMEM;
    return 0;
}

/* Count junction pixels; with mark, flag them JUNCTION once all are
 * found (read on the unflagged skeleton).  Rows on threads, each thread
 * listing its junctions; -1 when out of memory. */
static long count_junctions(td_grid_u8 *g, int mark)
{
    size_t n = 0;
    int fail = 0;
#pragma omp parallel reduction(+ : n) reduction(| : fail)
    {
        td_szvec js = {NULL, 0, 0};
        int y;
#pragma omp for schedule(dynamic, 64)
        for (y = 0; y < g->h; y++) {
            const uint8_t *r = g->data + (size_t)y * g->stride;
            int x;
            for (x = td_skel_next_ink(r, 0, g->w); x < g->w;
                 x = td_skel_next_ink(r, x + 1, g->w))
                if (td_skel_crossings(td_skel_nbits(g, x, y)) >= 3) {
                    n++;
                    if (mark && td_szvec_push(&js, (size_t)y * g->stride +
                                                       (size_t)x, NULL))
                        fail = 1;
                }
        } /* the loop's barrier: every row is read before any flag is set */
        if (mark && !fail) {
            size_t i;
            for (i = 0; i < js.n; i++) /* each thread its own pixels */
                g->data[js.v[i]] |= JUNCTION;
        }
        td_szvec_free(&js);
    }
    return fail ? -1 : (long)n;
}

static void fill_stats(const td_lines *ls, td_trace_stats *st)
{
    size_t i;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        st->lines++;
        st->closed += l->closed != 0;
        st->open += l->closed == 0;
        st->edge += l->edge != 0;
        st->bridged += (size_t)l->bridged;
    }
}

int td_trace(td_grid_u8 *g, const td_trace_params *p, td_lines **out,
             td_trace_stats *st, td_ctx *cx)
{
    td_trace_stats local;
    td_lines *ls = td_lines_new(cx);
    int x, y, rc = 0;
    size_t npts = 0, i;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    *out = NULL;
    if (!ls)
        return TD_ENOMEM;
    {
        long nj = count_junctions(g, p->cut);
        if (nj < 0) {
            td_lines_free(ls);
            return td_seterr(cx, TD_ENOMEM, "trace: out of memory");
        }
        st->junctions = (size_t)nj;
    }
    for (y = 0; y < g->h && rc == 0; y++) {
        const uint8_t *r = g->data + (size_t)y * g->stride;
        for (x = td_skel_next_ink(r, 0, g->w); x < g->w && rc == 0;
             x = td_skel_next_ink(r, x + 1, g->w))
            if (r[x] == 1)
                rc = trace_line(g, ls, x, y, p, cx);
        if (rc == 0 && (y & 255) == 0)
            rc = td_progress(cx, "trace", (double)y / g->h);
    }
#pragma omp parallel for schedule(static)
    for (y = 0; y < g->h; y++) {
        uint8_t *r = g->data + (size_t)y * g->stride;
        int c;
        for (c = td_skel_next_ink(r, 0, g->w); c < g->w;
             c = td_skel_next_ink(r, c + 1, g->w))
            r[c] &= 1;
    }
    if (rc != 0) {
        td_lines_free(ls);
        return rc;
    }
    fill_stats(ls, st);
    for (i = 0; i < ls->n; i++)
        npts += ls->v[i].n;
    st->points = npts;
    *out = ls;
    return 0;
}
