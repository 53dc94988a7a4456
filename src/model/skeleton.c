/* skeleton.c: the straight skeleton of a key outline, as paper 004 §3
 * builds it (Murase & Sugihara; ALGORITHMS.md D2): every edge of the
 * polygon moves inward, parallel to itself, at one speed; the shrinking
 * goes on from event to event:
 *
 *   edge event   an edge shrinks to nothing (after e = L / (cot(a_i / 2)
 *                + cot(a_i+1 / 2)), a_i the interior angles at its ends):
 *                its two neighbours meet from then on;
 *   split event  a reflex vertex (interior angle over 180) runs into an
 *                edge across: the polygon splits in two there.
 *
 * The paper's own construction (it says Aichholzer et al. give none): take
 * the smallest edge-event distance e over the edges; look for a split
 * event within it; shrink every polygon by the first event's distance,
 * apply the event, and go on until every polygon has shrunk away.  The
 * vertices' paths are the skeleton; the shrunk polygons at equal steps
 * are the contours.  Each vertex moves with velocity v, v . n = 1 for the
 * inward normals n of both its edges; each edge keeps its original normal.
 *
 * What the paper leaves open, decided here: events closer in time than
 * 1e-9 of the outline's size happen together; a polygon whose area falls
 * below that (squared) or with fewer than three vertices is done; the
 * surface between two events is swept by each edge as a trapezoid, the
 * height in it the time at which the front passed (the roof of the
 * outline), which is the DEM (`td_skeleton_dem`). */
#include "src/model/model.h"
#include "src/model/model_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct svert {
    double x, y;   /* position at the current time */
    double nx, ny; /* inward unit normal of the edge leaving this vertex */
    double vx, vy; /* velocity (from the normals of its two edges) */
} svert;

typedef struct spoly {
    svert *v;
    size_t n;
} spoly;

typedef struct sk {
    spoly *p;
    size_t np, cp;
    double t, eps;
    const td_skeleton_params *prm;
    td_grid_f32 *dem; /* NULL: no DEM */
    td_lines *contours, *peaks;
    td_ctx *cx;
    int rc;
    double next_level; /* time of the next contour */
    size_t nevents, nsplits;
} sk;

static double area(const svert *v, size_t n)
{
    double a = 0;
    size_t i;
    for (i = 0; i < n; i++) {
        const svert *p = &v[i], *q = &v[(i + 1) % n];
        a += p->x * q->y - q->x * p->y;
    }
    return 0.5 * a;
}

/* Velocities from the normals: vertex i between edge i-1 and edge i. */
static void velocities(spoly *P)
{
    size_t i;
    for (i = 0; i < P->n; i++) {
        const svert *a = &P->v[(i + P->n - 1) % P->n];
        svert *b = &P->v[i];
        double d = 1 + a->nx * b->nx + a->ny * b->ny;
        if (d < 1e-12) { /* antiparallel edges: a spike; it collapses */
            b->vx = b->vy = 0;
            continue;
        }
        b->vx = (a->nx + b->nx) / d, b->vy = (a->ny + b->ny) / d;
    }
}

static int add_poly(sk *s, svert *v, size_t n, td_ctx *cx)
{
    if (s->np == s->cp) {
        size_t nc = s->cp ? 2 * s->cp : 8;
        spoly *t = realloc(s->p, nc * sizeof *t);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "skeleton: out of memory");
        s->p = t, s->cp = nc;
    }
    s->p[s->np].v = v, s->p[s->np].n = n;
    velocities(&s->p[s->np]);
    s->np++;
    return 0;
}

/* Edge i's (vertex i -> i+1) event time from now, or HUGE_VAL. */
static double edge_event(const spoly *P, size_t i)
{
    const svert *a = &P->v[i], *b = &P->v[(i + 1) % P->n];
    double dx = b->x - a->x, dy = b->y - a->y, L = hypot(dx, dy), rate;
    if (!(L > 0))
        return 0;
    rate = ((b->vx - a->vx) * dx + (b->vy - a->vy) * dy) / L;
    return rate < -1e-12 ? -L / rate : HUGE_VAL;
}

/* Reflex vertex r hitting edge j of the same polygon: the time from now,
 * or HUGE_VAL (vertices positions move with their velocities; the edge
 * line moves along its normal at speed 1). */
static double split_event(const spoly *P, size_t r, size_t j, double eps)
{
    const svert *R = &P->v[r], *A = &P->v[j], *B = &P->v[(j + 1) % P->n];
    double den = R->vx * A->nx + R->vy * A->ny - 1, t, hx, hy, ax, ay, bx, by;
    double ex, ey, L2, u;
    if (den > -1e-12)
        return HUGE_VAL; /* not closing in on the edge */
    t = ((A->x - R->x) * A->nx + (A->y - R->y) * A->ny) / den;
    if (!(t > eps))
        return HUGE_VAL;
    hx = R->x + t * R->vx, hy = R->y + t * R->vy;
    ax = A->x + t * A->vx, ay = A->y + t * A->vy;
    bx = B->x + t * B->vx, by = B->y + t * B->vy;
    ex = bx - ax, ey = by - ay;
    L2 = ex * ex + ey * ey;
    if (!(L2 > 0))
        return HUGE_VAL;
    u = ((hx - ax) * ex + (hy - ay) * ey) / L2;
    if (u < -1e-9 || u > 1 + 1e-9)
        return HUGE_VAL; /* passes beside the edge's ends */
    return t;
}

static int is_reflex(const spoly *P, size_t i)
{
    const svert *a = &P->v[(i + P->n - 1) % P->n], *b = &P->v[i];
    /* turning right (for a polygon of positive area): cross of the edge
       directions < 0, i.e. the normals turn clockwise */
    return a->nx * b->ny - a->ny * b->nx < -1e-12;
}

/* Draw the trapezoids swept by P's edges over dt into the DEM: height =
 * the time the front passes, t0 + distance from the edge's line at t0. */
static void sweep(sk *s, const spoly *P, double dt)
{
    td_grid_f32 *g = s->dem;
    size_t i;
    for (i = 0; g && i < P->n; i++) {
        const svert *a = &P->v[i], *b = &P->v[(i + 1) % P->n];
        double x[4] = {a->x, b->x, b->x + dt * b->vx, a->x + dt * a->vx};
        double y[4] = {a->y, b->y, b->y + dt * b->vy, a->y + dt * a->vy};
        double y0 = fmin(fmin(y[0], y[1]), fmin(y[2], y[3]));
        double y1 = fmax(fmax(y[0], y[1]), fmax(y[2], y[3]));
        int row, r0 = (int)floor(y0), r1 = (int)ceil(y1), col, c0, c1;
        r0 = r0 < 0 ? 0 : r0, r1 = r1 >= g->h ? g->h - 1 : r1;
        for (row = r0; row <= r1; row++) {
            if (!td_convex_span(x, y, 4, row, 0, g->w - 1, &c0, &c1))
                continue;
            for (col = c0; col <= c1; col++) {
                double h = s->t + (col + 0.5 - a->x) * a->nx +
                           (row + 0.5 - a->y) * a->ny;
                float *z = &g->data[(size_t)row * g->w + col];
                h = h < s->t ? s->t : h > s->t + dt ? s->t + dt : h;
                if (*z == g->nodata || h > *z)
                    *z = (float)h;
            }
        }
    }
}

/* The contour rings at time T (between now and now + dt). */
static int emit_contours(sk *s, double T, td_ctx *cx)
{
    size_t i, k;
    for (i = 0; i < s->np; i++) {
        const spoly *P = &s->p[i];
        td_line *l;
        if (!P->v || P->n < 3)
            continue;
        if (!(l = td_lines_add(s->contours, cx)))
            return TD_ENOMEM;
        for (k = 0; k < P->n; k++)
            if (td_line_push(l, P->v[k].x + (T - s->t) * P->v[k].vx,
                             P->v[k].y + (T - s->t) * P->v[k].vy, cx) != 0)
                return TD_ENOMEM;
        {
            double a = 0; /* a ring shrunk to a point or a line: none */
            for (k = 0; k < l->n; k++) {
                size_t q = (k + 1) % l->n;
                a += l->xy[2 * k] * l->xy[2 * q + 1] -
                     l->xy[2 * q] * l->xy[2 * k + 1];
            }
            if (fabs(0.5 * a) <= 1e6 * s->eps * s->eps) {
                td_lines_remove(s->contours, s->contours->n - 1);
                continue;
            }
        }
        l->closed = 1;
        l->has_height = 1;
        l->height = T; /* a time: the caller maps it to a height */
    }
    return 0;
}

/* A skeleton node at (x, y), now (prm->nodes). */
static void node(sk *s, double x, double y)
{
    td_line *l;
    if (!s->prm->nodes || s->rc)
        return;
    if (!(l = td_lines_add(s->prm->nodes, s->cx)) ||
        td_line_push(l, x, y, s->cx) != 0) {
        s->rc = TD_ENOMEM;
        return;
    }
    l->has_height = 1, l->height = s->t;
}

/* Merge the vertices at the ends of vanished edges (length <= eps) of P;
 * returns how many merged. */
static size_t collapse(sk *s, spoly *P, double eps)
{
    size_t merged = 0, i = 0;
    while (P->n >= 2 && i < P->n) {
        svert *a = &P->v[i], *b = &P->v[(i + 1) % P->n];
        if (hypot(b->x - a->x, b->y - a->y) <= eps) {
            size_t j = (i + 1) % P->n;
            /* a takes b's outgoing edge; b goes */
            a->x = 0.5 * (a->x + b->x), a->y = 0.5 * (a->y + b->y);
            a->nx = b->nx, a->ny = b->ny;
            node(s, a->x, a->y);
            memmove(&P->v[j], &P->v[j + 1], (P->n - j - 1) * sizeof *P->v);
            P->n--;
            if (j < i)
                i--;
            merged++;
            continue;
        }
        i++;
    }
    if (merged)
        velocities(P);
    return merged;
}

/* Spikes: where a part of the polygon has shrunk to nothing (an arm whose
 * two sides met, after its end's edge event) its two sides run back along
 * each other from a tip.  The tip goes; of the two sides the shorter one
 * goes with it, the longer one goes on from where the shorter ended. */
static size_t despike(sk *s, spoly *P, double eps)
{
    size_t i = 0, gone = 0, guard = 0;
    while (P->n >= 3 && i < P->n && guard++ < 4 * P->n + 16) {
        size_t a = (i + P->n - 1) % P->n, b = (i + 1) % P->n;
        svert *pa = &P->v[a], *tip = &P->v[i], *nb = &P->v[b];
        double dot = pa->nx * tip->nx + pa->ny * tip->ny;
        double la = hypot(tip->x - pa->x, tip->y - pa->y);
        double lb = hypot(nb->x - tip->x, nb->y - tip->y);
        double cr = (tip->x - pa->x) * (nb->y - tip->y) -
                    (tip->y - pa->y) * (nb->x - tip->x);
        if (dot > -1 + 1e-9 || fabs(cr) > eps * (la + lb + eps)) {
            i++;
            continue;
        }
        if (la < lb) { /* prev lies on the tip's outgoing side */
            pa->nx = tip->nx, pa->ny = tip->ny;
        }
        node(s, tip->x, tip->y);
        node(s, la < lb ? pa->x : nb->x, la < lb ? pa->y : nb->y);
        memmove(&P->v[i], &P->v[i + 1], (P->n - i - 1) * sizeof *P->v);
        P->n--;
        gone++;
        i = i > 0 ? i - 1 : 0;
    }
    if (gone)
        velocities(P);
    return gone;
}

/* Polygon k splits where its reflex vertex r meets edge j (r not an end
 * of j): two polygons, r's copy in each. */
static int split(sk *s, size_t k, size_t r, size_t j, td_ctx *cx)
{
    spoly P = s->p[k];
    size_t n = P.n, n1 = 0, n2 = 0, i;
    svert *v1 = malloc((n + 1) * sizeof *v1), *v2 = malloc((n + 1) * sizeof *v2);
    int rc;
    if (!v1 || !v2) {
        free(v1), free(v2);
        return td_seterr(cx, TD_ENOMEM, "skeleton: out of memory");
    }
    /* 1: r (leaving along edge j), j+1, ..., r-1 */
    v1[n1] = P.v[r];
    v1[n1].nx = P.v[j].nx, v1[n1++].ny = P.v[j].ny;
    for (i = (j + 1) % n; i != r; i = (i + 1) % n)
        v1[n1++] = P.v[i];
    /* 2: r (leaving along its own edge), r+1, ..., j (leaving along j) */
    for (i = r; ; i = (i + 1) % n) {
        v2[n2++] = P.v[i];
        if (i == j)
            break;
    }
    free(P.v);
    s->p[k].v = NULL, s->p[k].n = 0;
    s->nsplits++;
    node(s, v1[0].x, v1[0].y);
    if ((rc = add_poly(s, v1, n1, cx)) != 0) {
        free(v2);
        return rc;
    }
    return add_poly(s, v2, n2, cx);
}

/* Drop done polygons (fewer than 3 vertices, no area); where one shrank
 * away is a summit (s->peaks: the mean of its corners, height = now). */
static void prune(sk *s)
{
    size_t i, m = 0, k;
    for (i = 0; i < s->np; i++) {
        spoly *P = &s->p[i];
        if (!P->v || P->n < 3 || fabs(area(P->v, P->n)) <= s->eps * s->eps) {
            for (k = 0; P->v && k < P->n; k++)
                node(s, P->v[k].x, P->v[k].y);
            if (s->peaks && P->v && P->n > 0 && s->rc == 0) {
                td_line *l = td_lines_add(s->peaks, s->cx);
                double x = 0, y = 0;
                for (k = 0; k < P->n; k++)
                    x += P->v[k].x, y += P->v[k].y;
                if (!l || td_line_push(l, x / P->n, y / P->n, s->cx) != 0)
                    s->rc = TD_ENOMEM;
                else
                    l->has_height = 1, l->height = s->t;
            }
            free(P->v);
            continue;
        }
        s->p[m++] = *P;
    }
    s->np = m;
}

static double orient(double ax, double ay, double bx, double by, double cx,
                     double cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* Do two edges of the ring xy (n points) that are not neighbours meet? */
static int self_crossing(const double *xy, size_t n)
{
    size_t i, j;
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n; j++) {
            const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
            const double *c = xy + 2 * j, *d = xy + 2 * ((j + 1) % n);
            double o1, o2, o3, o4;
            if (j == i + 1 || (i == 0 && j == n - 1))
                continue; /* neighbours share a corner */
            o1 = orient(a[0], a[1], b[0], b[1], c[0], c[1]);
            o2 = orient(a[0], a[1], b[0], b[1], d[0], d[1]);
            o3 = orient(c[0], c[1], d[0], d[1], a[0], a[1]);
            o4 = orient(c[0], c[1], d[0], d[1], b[0], b[1]);
            if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
                ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
                return 1;
        }
    return 0;
}

/* See model.h. */
td_skeleton_params td_skeleton_defaults(void)
{
    td_skeleton_params p;
    p.contour_step = 0;
    p.max_events = 1000000;
    p.nodes = NULL;
    return p;
}

/* See model.h. */
int td_skeleton(const double *xy, size_t n, const td_skeleton_params *prm,
                td_grid_f32 *dem, td_lines *contours, td_lines *peaks,
                td_skeleton_stats *st, td_ctx *cx)
{
    sk s;
    svert *v;
    size_t i;
    double a, size = 0, x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL,
              y1 = -HUGE_VAL;
    int rc = 0;
    memset(&s, 0, sizeof s);
    if (n < 3)
        return td_seterr(cx, TD_EINVAL, "skeleton: an outline needs 3 points "
                         "or more (got %zu)", n);
    for (i = 0; i < 2 * n; i++)
        if (!isfinite(xy[i]) || fabs(xy[i]) > 1e8)
            return td_seterr(cx, TD_EINVAL, "skeleton: a non-finite or "
                             "far-off coordinate");
    if (self_crossing(xy, n))
        return td_seterr(cx, TD_EINVAL, "skeleton: the outline crosses "
                         "itself");
    if (!(v = malloc(n * sizeof *v)))
        return td_seterr(cx, TD_ENOMEM, "skeleton: out of memory");
    for (i = 0; i < n; i++) {
        v[i].x = xy[2 * i], v[i].y = xy[2 * i + 1];
        x0 = fmin(x0, v[i].x), x1 = fmax(x1, v[i].x);
        y0 = fmin(y0, v[i].y), y1 = fmax(y1, v[i].y);
    }
    size = fmax(x1 - x0, y1 - y0);
    a = area(v, n);
    if (!(fabs(a) > 1e-12 * size * size)) {
        free(v);
        return td_seterr(cx, TD_EINVAL, "skeleton: the outline has no area");
    }
    if (a < 0) /* make the inside lie left of every edge */
        for (i = 0; i < n / 2; i++) {
            svert t = v[i];
            v[i] = v[n - 1 - i], v[n - 1 - i] = t;
        }
    {
        size_t m = 0; /* drop repeated points */
        for (i = 0; i < n; i++)
            if (hypot(v[i].x - v[(i + 1) % n].x, v[i].y - v[(i + 1) % n].y) >
                1e-12 * size)
                v[m++] = v[i];
        n = m;
    }
    for (i = 0; i < n; i++) {
        const svert *b = &v[(i + 1) % n];
        double dx = b->x - v[i].x, dy = b->y - v[i].y, L = hypot(dx, dy);
        v[i].nx = -dy / L, v[i].ny = dx / L;
    }
    s.prm = prm, s.dem = dem, s.contours = contours, s.peaks = peaks;
    s.cx = cx;
    s.eps = 1e-9 * size;
    s.next_level = prm->contour_step > 0 ? prm->contour_step : HUGE_VAL;
    if ((rc = add_poly(&s, v, n, cx)) != 0) {
        free(v);
        return rc;
    }
    while (s.np > 0 && rc == 0) {
        double dt = HUGE_VAL;
        size_t k, bk = 0, br = 0, bj = 0;
        int split_first = 0;
        if (s.nevents++ >= prm->max_events) {
            rc = td_seterr(cx, TD_EINVAL, "skeleton: more than %zu events",
                           prm->max_events);
            break;
        }
        for (k = 0; k < s.np; k++) { /* the first edge event (eq. 1) */
            const spoly *P = &s.p[k];
            for (i = 0; i < P->n; i++)
                dt = fmin(dt, edge_event(P, i));
        }
        for (k = 0; k < s.np; k++) { /* a split before it? */
            const spoly *P = &s.p[k];
            size_t r, j;
            for (r = 0; r < P->n; r++) {
                if (!is_reflex(P, r))
                    continue;
                for (j = 0; j < P->n; j++) {
                    double t;
                    if (j == r || (j + 1) % P->n == r)
                        continue;
                    t = split_event(P, r, j, s.eps);
                    if (t < dt - s.eps)
                        dt = t, split_first = 1, bk = k, br = r, bj = j;
                }
            }
        }
        if (!(dt < HUGE_VAL)) { /* nothing shrinks: parallel sides only */
            prune(&s);
            for (k = 0; k < s.np; k++)
                free(s.p[k].v);
            s.np = 0;
            break;
        }
        while (contours && s.next_level <= s.t + dt + s.eps && rc == 0) {
            rc = emit_contours(&s, s.next_level, cx);
            s.next_level += prm->contour_step;
        }
        for (k = 0; k < s.np; k++) {
            spoly *P = &s.p[k];
            sweep(&s, P, dt);
            for (i = 0; i < P->n; i++)
                P->v[i].x += dt * P->v[i].vx, P->v[i].y += dt * P->v[i].vy;
        }
        s.t += dt;
        if (rc)
            break;
        if (split_first) {
            rc = split(&s, bk, br, bj, cx);
        }
        for (k = 0; k < s.np && rc == 0; k++)
            while (s.p[k].v && (collapse(&s, &s.p[k], 1e3 * s.eps) +
                                despike(&s, &s.p[k], 1e3 * s.eps)) > 0)
                ;
        prune(&s);
        if (s.rc)
            rc = s.rc;
    }
    for (i = 0; i < s.np; i++)
        free(s.p[i].v);
    free(s.p);
    if (st) {
        st->events = s.nevents;
        st->splits = s.nsplits;
        st->max_time = s.t;
    }
    return rc;
}
