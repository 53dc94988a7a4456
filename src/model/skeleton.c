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

/* Draw the trapezoids swept by P's edges over dt into the DEM. */
static void sweep(sk *s, const spoly *P, double dt)
{
    size_t i;
    for (i = 0; s->dem && i < P->n; i++) {
        const svert *a = &P->v[i], *b = &P->v[(i + 1) % P->n];
        double x[4] = {a->x, b->x, b->x + dt * b->vx, a->x + dt * a->vx};
        double y[4] = {a->y, b->y, b->y + dt * b->vy, a->y + dt * a->vy};
        td_skeleton_quad(s->dem, x, y, a->nx, a->ny,
                         a->nx * a->x + a->ny * a->y - s->t, s->t, s->t + dt);
    }
}

/* See model_int.h. */
void td_skeleton_quad(td_grid_f32 *g, const double *x, const double *y,
                      double nx, double ny, double c, double t0, double t1)
{
    double y0 = fmin(fmin(y[0], y[1]), fmin(y[2], y[3]));
    double y1 = fmax(fmax(y[0], y[1]), fmax(y[2], y[3]));
    int row, r0 = (int)floor(y0), r1 = (int)ceil(y1), col, c0, c1;
    r0 = r0 < 0 ? 0 : r0, r1 = r1 >= g->h ? g->h - 1 : r1;
    for (row = r0; row <= r1; row++) {
        if (!td_convex_span(x, y, 4, row, 0, g->w - 1, &c0, &c1))
            continue;
        for (col = c0; col <= c1; col++) {
            double h = nx * (col + 0.5) + ny * (row + 0.5) - c;
            float *z = &g->data[(size_t)row * g->w + col];
            h = h < t0 ? t0 : h > t1 ? t1 : h;
            if (*z == g->nodata || h > *z)
                *z = (float)h;
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

/* Is reflex vertex r of P at one of its neighbours after time t?  Then
 * that is their edge event, not a split. */
static int at_end(const spoly *P, size_t r, double t, double eps)
{
    const svert *a = &P->v[(r + P->n - 1) % P->n], *b = &P->v[r];
    const svert *c = &P->v[(r + 1) % P->n];
    double bx = b->x + t * b->vx, by = b->y + t * b->vy;
    return hypot(a->x + t * a->vx - bx, a->y + t * a->vy - by) <= 1e3 * eps ||
           hypot(c->x + t * c->vx - bx, c->y + t * c->vy - by) <= 1e3 * eps;
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

/* Does point c lie on the segment a-b (o: the orientation of a, b, c)? */
static int on_segment(const double *a, const double *b, const double *c,
                      double o)
{
    return o == 0 && c[0] >= fmin(a[0], b[0]) && c[0] <= fmax(a[0], b[0]) &&
           c[1] >= fmin(a[1], b[1]) && c[1] <= fmax(a[1], b[1]);
}

/* Do edges i and j of the ring xy (n points) cross or touch?  Neighbours
 * (sharing a corner) only when one folds back along the other. */
static int edges_cross(const double *xy, size_t n, size_t i, size_t j)
{
    const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
    const double *c = xy + 2 * j, *d = xy + 2 * ((j + 1) % n);
    double o1, o2, o3, o4;
    if (j == (i + 1) % n || i == (j + 1) % n) {
        const double *p = j == (i + 1) % n ? a : c, *q = j == (i + 1) % n ? b : d;
        const double *r = j == (i + 1) % n ? d : b; /* p -> q -> r */
        return n > 3 && orient(p[0], p[1], q[0], q[1], r[0], r[1]) == 0 &&
               (r[0] - q[0]) * (q[0] - p[0]) + (r[1] - q[1]) * (q[1] - p[1]) <
                   0;
    }
    o1 = orient(a[0], a[1], b[0], b[1], c[0], c[1]);
    o2 = orient(a[0], a[1], b[0], b[1], d[0], d[1]);
    o3 = orient(c[0], c[1], d[0], d[1], a[0], a[1]);
    o4 = orient(c[0], c[1], d[0], d[1], b[0], b[1]);
    if (on_segment(a, b, c, o1) || on_segment(a, b, d, o2) ||
        on_segment(c, d, a, o3) || on_segment(c, d, b, o4))
        return 1; /* touching */
    return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
           ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

typedef struct xspan {
    double x0, x1;
    size_t i;
} xspan;

static int by_x0(const void *a, const void *b)
{
    double u = ((const xspan *)a)->x0, v = ((const xspan *)b)->x0;
    return (u > v) - (u < v);
}

/* Do two edges of the ring xy (n points) that are not neighbours meet?
 * The edges sorted by their left ends; each against those starting
 * before it ends.  -1: out of memory. */
static int self_crossing(const double *xy, size_t n)
{
    xspan *e = malloc(n * sizeof *e);
    size_t i, j;
    int hit = 0;
    if (!e)
        return -1;
    for (i = 0; i < n; i++) {
        double xa = xy[2 * i], xb = xy[2 * ((i + 1) % n)];
        e[i].x0 = fmin(xa, xb), e[i].x1 = fmax(xa, xb), e[i].i = i;
    }
    qsort(e, n, sizeof *e, by_x0);
    for (i = 0; i < n && !hit; i++)
        for (j = i + 1; j < n && e[j].x0 <= e[i].x1 && !hit; j++)
            hit = edges_cross(xy, n, e[i].i, e[j].i);
    free(e);
    return hit;
}

/* See model.h. */
td_skeleton_params td_skeleton_defaults(void)
{
    td_skeleton_params p;
    p.contour_step = 0;
    p.max_events = 1000000;
    p.nodes = NULL;
    p.construction = TD_SKEL_QUEUE;
    return p;
}

/* One step of the paper's construction: the first edge event, a split
 * before it, every polygon shrunk to it, the event applied. */
static int step(sk *s)
{
    double dt = HUGE_VAL, de;
    size_t i, k, bk = 0, br = 0, bj = 0;
    int split_first = 0, rc = 0;
    if (s->nevents++ >= s->prm->max_events) {
        return td_seterr(s->cx, TD_EINVAL, "skeleton: more than %zu events",
                         s->prm->max_events);
    }
    for (k = 0; k < s->np; k++) { /* the first edge event (eq. 1) */
        const spoly *P = &s->p[k];
        for (i = 0; i < P->n; i++)
            dt = fmin(dt, edge_event(P, i));
    }
    de = dt;
    for (k = 0; k < s->np; k++) { /* a split before it? */
        const spoly *P = &s->p[k];
        size_t r, j;
        for (r = 0; r < P->n; r++) {
            if (!is_reflex(P, r))
                continue;
            for (j = 0; j < P->n; j++) {
                double t;
                if (j == r || (j + 1) % P->n == r)
                    continue;
                t = split_event(P, r, j, s->eps);
                /* a split with an edge event elsewhere at the same time
                   goes first: after the edge event it would be now, and
                   no longer found */
                if (t < dt && (t < de - s->eps || !at_end(P, r, t, s->eps)))
                    dt = t, split_first = 1, bk = k, br = r, bj = j;
            }
        }
    }
    if (!(dt < HUGE_VAL)) { /* nothing shrinks: parallel sides only */
        prune(s);
        for (k = 0; k < s->np; k++)
            free(s->p[k].v);
        s->np = 0;
        return 0;
    }
    while (s->contours && s->next_level <= s->t + dt + s->eps && rc == 0) {
        rc = emit_contours(s, s->next_level, s->cx);
        s->next_level += s->prm->contour_step;
    }
    for (k = 0; k < s->np; k++) {
        spoly *P = &s->p[k];
        sweep(s, P, dt);
        for (i = 0; i < P->n; i++)
            P->v[i].x += dt * P->v[i].vx, P->v[i].y += dt * P->v[i].vy;
    }
    s->t += dt;
    if (rc)
        return rc;
    if (split_first)
        rc = split(s, bk, br, bj, s->cx);
    for (k = 0; k < s->np && rc == 0; k++)
        while (s->p[k].v && (collapse(s, &s->p[k], 1e3 * s->eps) +
                            despike(s, &s->p[k], 1e3 * s->eps)) > 0)
            ;
    prune(s);
    if (s->rc)
        rc = s->rc;
    return rc;
}

/* The paper's construction on a clean outline (counter-clockwise, no
 * repeated points). */
static int skeleton_paper(const double *xy, size_t n, double size,
                          const td_skeleton_params *prm, td_grid_f32 *dem,
                          td_lines *contours, td_lines *peaks,
                          td_skeleton_stats *st, td_ctx *cx)
{
    sk s;
    svert *v;
    size_t i;
    int rc = 0;
    memset(&s, 0, sizeof s);
    if (!(v = malloc(n * sizeof *v)))
        return td_seterr(cx, TD_ENOMEM, "skeleton: out of memory");
    for (i = 0; i < n; i++) {
        const double *a = xy + 2 * i, *b = xy + 2 * ((i + 1) % n);
        double dx = b[0] - a[0], dy = b[1] - a[1], L = hypot(dx, dy);
        v[i].x = a[0], v[i].y = a[1];
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
    while (s.np > 0 && rc == 0)
        rc = step(&s);
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

/* See model.h. */
int td_skeleton(const double *xy, size_t n, const td_skeleton_params *prm,
                td_grid_f32 *dem, td_lines *contours, td_lines *peaks,
                td_skeleton_stats *st, td_ctx *cx)
{
    double *v, a = 0, size, x0 = HUGE_VAL, x1 = -HUGE_VAL, y0 = HUGE_VAL,
               y1 = -HUGE_VAL;
    size_t i, m = 0;
    int rc;
    if (n < 3)
        return td_seterr(cx, TD_EINVAL, "skeleton: an outline needs 3 points "
                         "or more (got %zu)", n);
    if (n > (size_t)1 << 28)
        return td_seterr(cx, TD_EINVAL, "skeleton: too many points (%zu)", n);
    for (i = 0; i < 2 * n; i++)
        if (!isfinite(xy[i]) || fabs(xy[i]) > 1e8)
            return td_seterr(cx, TD_EINVAL, "skeleton: a non-finite or "
                             "far-off coordinate");
    for (i = 0; i < n; i++) {
        x0 = fmin(x0, xy[2 * i]), x1 = fmax(x1, xy[2 * i]);
        y0 = fmin(y0, xy[2 * i + 1]), y1 = fmax(y1, xy[2 * i + 1]);
    }
    size = fmax(x1 - x0, y1 - y0);
    if (!(v = malloc(2 * n * sizeof *v)))
        return td_seterr(cx, TD_ENOMEM, "skeleton: out of memory");
    for (i = 0; i < n; i++) /* drop repeated points */
        if (hypot(xy[2 * i] - xy[2 * ((i + 1) % n)],
                  xy[2 * i + 1] - xy[2 * ((i + 1) % n) + 1]) > 1e-12 * size) {
            v[2 * m] = xy[2 * i], v[2 * m + 1] = xy[2 * i + 1];
            m++;
        }
    for (i = 0; i < m; i++) {
        const double *p = v + 2 * i, *q = v + 2 * ((i + 1) % m);
        a += 0.5 * (p[0] * q[1] - q[0] * p[1]);
    }
    if (m >= 3 && (rc = self_crossing(v, m)) != 0) {
        free(v);
        return rc < 0 ? td_seterr(cx, TD_ENOMEM, "skeleton: out of memory")
                      : td_seterr(cx, TD_EINVAL, "skeleton: the outline "
                                  "crosses or touches itself");
    }
    if (m >= 3 && !(fabs(a) > 1e-12 * size * size)) {
        free(v);
        return td_seterr(cx, TD_EINVAL, "skeleton: the outline has no area");
    }
    for (i = 0; a < 0 && i < m / 2; i++) { /* the inside left of every edge */
        double tx = v[2 * i], ty = v[2 * i + 1];
        v[2 * i] = v[2 * (m - 1 - i)], v[2 * i + 1] = v[2 * (m - 1 - i) + 1];
        v[2 * (m - 1 - i)] = tx, v[2 * (m - 1 - i) + 1] = ty;
    }
    if (m < 3)
        rc = td_seterr(cx, TD_EINVAL, "skeleton: an outline needs 3 points "
                       "or more (got %zu distinct)", m);
    else if (prm->construction == TD_SKEL_PAPER)
        rc = skeleton_paper(v, m, size, prm, dem, contours, peaks, st, cx);
    else
        rc = td_skeleton_queue(v, m, size, prm, dem, contours, peaks, st, cx);
    free(v);
    return rc;
}
