/* Gap joining of traced lines (ALGORITHMS.md A.4 "beyond").
 *
 *        a.t -->   gap g   <-- b.t         joined when |g| <= max_gap,
 *   ======a  . . . . . . . .  b=======     angle(a.t, g) and angle(b.t, -g)
 *                                          are <= max_angle (or the other
 *   end lies within 2.5 px of the tangent line and the angle is under 75,
 *   for short gaps whose ends are offset sideways by skeleton noise).
 *
 * Each open end gets an outward tangent (the chord from `tangent` + 2 px
 * back along the line to 2 px back).  Candidate pairs come from a bucket grid of
 * ends; pairs are accepted cheapest first, each end once; accepted pairs
 * chain lines together, and a chain that returns to where it started (or a
 * line joined to itself) is closed.
 *
 * Stage 0 (fragments) and stage 2 (label gaps, ALGORITHMS.md A.4 "beyond":
 * printed elevation labels cut index contours over 20-60 px):
 *
 *   =====a   3 5 0   b=====     the digits trace as short, bent fragments
 *         '---------'           (removed unless both their ends continue
 *        the join a-b           lines) and small rings (0, 6, 8, 9: kept as
 *                               rings, removed once a join passes through);
 *   a-b is joined when both tangents face the gap, the two ends' sideways
 *   shift is at most max(2.5, 0.15 |ab|) px and their common bend at most
 *   0.3 |ab| (long_cost), and the segment a-b meets no other line (a
 *   bucket grid of line segments). */
#include "scanner/join.h"
#include "scanner/flank.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Two ends at one skeleton junction are joined only when the line goes on
 * within this many degrees of straight (touching contours cross or run
 * together there; a contour does not turn onto its neighbour). */
#define JUNC_TURN 75.0
#define JUNC_LEAVE 25.0 /* cost of leaving a junction end open */
#define JUNC_SELF_TURN 135.0 /* a line's two ends closing it at a junction */
#define JUNC_MAX 8      /* ends in one junction zone searched exhaustively */
#define JUNC_NEAR 3.0 /* px: two junction ends this near meet at one junction */
#define NET_LONG                                                               \
    3.0 /* min_lengths: junction pieces this long together are a contour's */

typedef struct jend {
    double x, y, tx, ty;
    double k, ux, uy; /* stage 2: curvature towards the end (1/px, turning
                         as cross(t, t') > 0) and the tangent at the end */
    double k2;        /* the curvature over a shorter stretch (ARC_L2) */
    size_t line;
    int at_end;   /* 0: the line's first point, 1: its last */
    int junc;     /* the end is next to a skeleton junction (tracer cut) */
    long partner; /* index of the joined end, -1 when free */
    long path;    /* stage 2 arc joins: index of the join's path, -1 */
    int path_from; /* the path runs from this end */
} jend;

typedef struct jpair {
    double cost;
    size_t a, b;
    int arc; /* stage 2: accepted by the curve rule (arc_cost) */
} jpair;

td_join_params td_join_defaults(int w, int h)
{
    td_join_params p;
    memset(&p, 0, sizeof p); /* other, water: none */
    p.max_gap = 16.0;
    p.max_angle = 40.0;
    p.tangent = 8.0;
    p.min_length = 25.0;
    p.straight_keep = 0.8;
    p.curl_keep = 1.0;
    p.chains = 1;
    p.bridge_max = 12.0;
    p.chain_max = 80.0;
    p.junc_ratio = 1.5;
    p.gap_ratio = 1.5;
    p.gap_near = 0.5;
    p.long_gap = 70.0;
    p.long_tangent = 20.0;
    p.cross_gap = 16.0;
    p.water_turns = 1;
    p.gap_room = 0.5;
    p.curves = 1;
    p.record = 0;
    p.w = w;
    p.h = h;
    return p;
}

/* The point reached walking `dist` px along l from its start (at_end 0)
 * or its end (at_end 1); returns its index. */
static size_t walk_back(const td_line *l, int at_end, double dist)
{
    size_t n = l->n, k = at_end ? n - 1 : 0;
    double len = 0.0;
    while (len < dist) {
        size_t nk = at_end ? (k == 0 ? 0 : k - 1) : (k + 1 < n ? k + 1 : k);
        if (nk == k)
            break;
        len += hypot(l->xy[2 * nk] - l->xy[2 * k],
                     l->xy[2 * nk + 1] - l->xy[2 * k + 1]);
        k = nk;
    }
    return k;
}

/* An end and its outward tangent: the chord from `tangent` + 2 px back to
 * 2 px back, so a one- or two-pixel hook at the very end (thinning of a
 * ragged line end) does not turn it. */
static void end_of(const td_line *l, int at_end, double tangent, jend *e)
{
    size_t i0 = at_end ? l->n - 1 : 0;
    size_t near = walk_back(l, at_end, 2.0);
    size_t far = walk_back(l, at_end, tangent + 2.0);
    double dx = l->xy[2 * near] - l->xy[2 * far];
    double dy = l->xy[2 * near + 1] - l->xy[2 * far + 1], d;
    if (near == far) { /* a line shorter than 2 px */
        dx = l->xy[2 * i0] - l->xy[2 * far];
        dy = l->xy[2 * i0 + 1] - l->xy[2 * far + 1];
    }
    d = hypot(dx, dy);
    e->x = l->xy[2 * i0];
    e->y = l->xy[2 * i0 + 1];
    e->tx = d > 0 ? dx / d : 0.0;
    e->ty = d > 0 ? dy / d : 0.0;
    e->at_end = at_end;
    e->junc = (l->junc >> at_end) & 1;
    e->partner = -1;
    e->path = -1;
    e->k = e->k2 = 0.0;
    e->ux = e->tx, e->uy = e->ty;
}

/* The curvature of the circle through the points 2, 2 + L/2 and 2 + L px
 * back from an end (P0, P1, P2), with |P0 - P1| in *lb; 0 when the line is
 * too short (then *lb = 0).
 *
 *    P2 . . . P1 . . . P0 ..end      k = 2 cross(P1-P2, P0-P1) /
 *                                        (|P1-P2| |P0-P1| |P0-P2|)  */
static double curve_over(const td_line *l, int at_end, double L,
                         size_t *i0_, size_t *i1_, double *lb_)
{
    size_t i0 = walk_back(l, at_end, 2.0);
    size_t i1 = walk_back(l, at_end, 2.0 + 0.5 * L);
    size_t i2 = walk_back(l, at_end, 2.0 + L);
    const double *p0 = l->xy + 2 * i0, *p1 = l->xy + 2 * i1,
                 *p2 = l->xy + 2 * i2;
    double ax = p1[0] - p2[0], ay = p1[1] - p2[1];
    double bx = p0[0] - p1[0], by = p0[1] - p1[1];
    double la = hypot(ax, ay), lb = hypot(bx, by);
    double lc = hypot(p0[0] - p2[0], p0[1] - p2[1]);
    *i0_ = i0, *i1_ = i1, *lb_ = 0.0;
    if (la < 0.4 * L || lb < 0.4 * L || lc <= 0)
        return 0.0;
    *lb_ = lb;
    return 2.0 * (ax * by - ay * bx) / (la * lb * lc);
}

/* Stage 2: the end's curvature over ARC_L and ARC_L2 px (curve_over), and
 * its tangent at the end: the chord P1-P0 (over ARC_L) turned on along
 * that circle.  Lines too short keep k = 0 and the chord tangent. */
#define ARC_L 30.0
#define ARC_L2 16.0
static void end_curve(const td_line *l, int at_end, jend *e)
{
    size_t i0, i1, j0, j1;
    double lb, lb2, bx, by, th;
    e->k = curve_over(l, at_end, ARC_L, &i0, &i1, &lb);
    e->k2 = curve_over(l, at_end, ARC_L2, &j0, &j1, &lb2);
    if (lb2 <= 0)
        e->k2 = e->k;
    if (lb <= 0)
        return;
    bx = l->xy[2 * i0] - l->xy[2 * i1], by = l->xy[2 * i0 + 1] - l->xy[2 * i1 + 1];
    th = e->k * (0.5 * lb + hypot(e->x - l->xy[2 * i0], e->y - l->xy[2 * i0 + 1]));
    e->ux = (bx * cos(th) - by * sin(th)) / lb;
    e->uy = (bx * sin(th) + by * cos(th)) / lb;
}


static int on_border(const td_join_params *p, double x, double y)
{
    return x < 1 || y < 1 || x > p->w - 1 || y > p->h - 1;
}

/* Angle in degrees between unit tangent (tx,ty) and vector (gx,gy). */
static double angle_to(double tx, double ty, double gx, double gy)
{
    double g = hypot(gx, gy), c;
    if (g <= 0 || (tx == 0 && ty == 0))
        return 180.0;
    c = (tx * gx + ty * gy) / g;
    c = c > 1 ? 1 : c < -1 ? -1 : c;
    return acos(c) * (180.0 / M_PI);
}

/* Whether end (tx,ty) at one side of gap (gx,gy) points across it: within
 * max_angle, or, for ends offset sideways by skeleton noise, passing within
 * TD_JOIN_SIDE px of the other end while still facing it. */
#define TD_JOIN_SIDE 2.5
static int faces(double tx, double ty, double gx, double gy, double ang,
                 double max_angle)
{
    double side = fabs(tx * gy - ty * gx);
    return ang <= max_angle || (side <= TD_JOIN_SIDE && ang < 75.0);
}

/* Stage 2 cost.  Signed offsets oa, ob of each end from the other's
 * tangent line split into a sideways shift |oa - ob| / 2 (two different
 * lines side by side: ob = -oa) and a bend |oa + ob| / 2 (one line curving
 * through the gap: ob = oa).  Joined when both tangents face the gap, the
 * shift is at most max(2.5, 0.15 d) px and the bend at most 0.3 d (about
 * 17 degrees of turn at each end); else negative. */
static double long_cost(const jend *a, const jend *b, double gx, double gy,
                        double d)
{
    double tol = fmax(TD_JOIN_SIDE, 0.15 * d);
    double oa = a->tx * gy - a->ty * gx, ob = b->tx * gy - b->ty * gx;
    double shift = 0.5 * fabs(oa - ob), bend = 0.5 * fabs(oa + ob);
    if (a->tx * gx + a->ty * gy <= 0 || -(b->tx * gx + b->ty * gy) <= 0)
        return -1.0;
    if (shift > tol || bend > 0.3 * d)
        return -1.0;
    return d * (1.0 + shift / tol + bend / (0.3 * d));
}

/* Stage 2 on a curve: the bend is over 0.3 d, but one circle fits the
 * ends.  With pa the signed turn from a's end tangent to the gap and pb
 * from the gap to b's arriving direction (-b.u), a circle through both
 * ends has pa = pb (the sideways shift d |sin pa - sin pb| / 2 at most
 * max(2.5, 0.15 d)) and curvature kj = (sin pa + sin pb) / d; each end's
 * own curvature (over 30 or 16 px) must agree with it: within half of it
 * + ARC_K0, or turning the same way within a factor of 3 (a contour
 * curving through a label gap keeps curving; two contours' ends do not
 * line up like that), and neither turn may pass ARC_TURN. */
#define ARC_TURN (60.0 * M_PI / 180.0)
#define ARC_K0 0.006

/* How far an end's curvature k is from the join's kj: |k - kj| when
 * within tk; tk when it turns the same way within a factor of 3 (a
 * contour's curvature varies along it); else infinite. */
static double k_err(double k, double kj, double tk)
{
    double r = kj != 0 ? k / kj : 0;
    if (fabs(k - kj) <= tk)
        return fabs(k - kj);
    return r >= 1.0 / 3.0 && r <= 3.0 ? tk : INFINITY;
}
static double arc_cost(const jend *a, const jend *b, double gx, double gy,
                       double d)
{
    double ux = gx / d, uy = gy / d, tol = fmax(TD_JOIN_SIDE, 0.15 * d);
    double pa = atan2(a->ux * uy - a->uy * ux, a->ux * ux + a->uy * uy);
    double pb = atan2(-ux * b->uy + uy * b->ux, -ux * b->ux - uy * b->uy);
    double shift = 0.5 * d * fabs(sin(pa) - sin(pb)), kj, tk, ea, eb;
    if (fabs(pa) > ARC_TURN || fabs(pb) > ARC_TURN || pa * pb <= 0 ||
        shift > tol)
        return -1.0;
    kj = (sin(pa) + sin(pb)) / d;
    tk = 0.5 * fabs(kj) + ARC_K0;
    ea = fmin(k_err(a->k, kj, tk), k_err(a->k2, kj, tk));
    eb = fmin(k_err(-b->k, kj, tk), k_err(-b->k2, kj, tk));
    if (!(ea <= tk && eb <= tk))
        return -1.0;
    return d * (1.0 + shift / tol + 0.5 * (ea + eb) / tk);
}

/* Cost of joining ends a and b in stage 1 or 2, or a negative value when
 * not allowed. */
static double cross_cost(const td_join_params *p, const jend *a, const jend *b,
                         double gx, double gy, double d);

/* ---- stage 4 (ours, td_join_params.alone_gaps): short gaps alone ----- */
#define ALONE_MIN                                                              \
    3.5                  /* px: a gap from this long (shorter ones stage 1     \
                            refused for crossing) ... */
#define ALONE_MAX 8.0    /* ... to this long */
#define ALONE_ANGLE 60.0 /* degrees: each end's course off the gap */
#define ALONE_TURN 90.0  /* degrees: the two ends' courses off head on */
#define ALONE_CLEAR 2.0  /* gaps: no other open end this near either end */

/* A contour whose faded ink broke where it bends, its ends a few px apart
 * and askew (stage 1's angle and side limits refuse them), nothing else
 * near: the cost of joining ends a and b, the gap (-1: not such a pair). */
static double alone_cost(const jend *a, const jend *b, double gx, double gy,
                         double d)
{
    if (d < ALONE_MIN || d > ALONE_MAX ||
        angle_to(a->tx, a->ty, gx, gy) > ALONE_ANGLE ||
        angle_to(b->tx, b->ty, -gx, -gy) > ALONE_ANGLE ||
        angle_to(a->tx, a->ty, -b->tx, -b->ty) > ALONE_TURN)
        return -1.0;
    return d;
}

static double pair_cost(const td_lines *ls, const jend *a, const jend *b,
                        const td_join_params *p, int stage, int *arc)
{
    double gx = b->x - a->x, gy = b->y - a->y, d = hypot(gx, gy), ga, gb;
    if (d > (stage == 3 ? p->cross_gap : stage == 2 ? p->long_gap : p->max_gap))
        return -1.0;
    if (a->line == b->line &&
        (ls->v[a->line].n < 4 || td_line_length(&ls->v[a->line]) < 4 * d))
        return -1.0;
    if (stage == 3)
        return a->line == b->line ? -1.0 : cross_cost(p, a, b, gx, gy, d);
    if (stage == 4)
        return alone_cost(a, b, gx, gy, d);
    if (a->junc && b->junc) { /* across a junction: go on straight */
        double turn = angle_to(a->tx, a->ty, -b->tx, -b->ty);
        /* a small ring cut open where it touches a line: its two ends
           both head into the contact */
        int self = a->line == b->line;
        /* two ends next to one junction pixel: a hairpin, kept to zones
           of two ends (junction_zones) */
        int hair = d <= JUNC_NEAR;
        if (turn > (self || hair ? JUNC_SELF_TURN : JUNC_TURN) ||
            (!self && d > JUNC_NEAR &&
             (!faces(a->tx, a->ty, gx, gy, angle_to(a->tx, a->ty, gx, gy),
                     p->max_angle) ||
              !faces(b->tx, b->ty, -gx, -gy, angle_to(b->tx, b->ty, -gx, -gy),
                     p->max_angle))))
            return -1.0;
        if (stage == 2)
            return -1.0; /* stage 1 pairs junction ends */
        return (d > 1 ? d : 1) * (1.0 + turn / JUNC_TURN);
    }
    if (stage == 2 && d <= 0)
        return 0.0;
    if (stage == 2) {
        double c = long_cost(a, b, gx, gy, d);
        *arc = c < 0;
        return c >= 0 || !p->curves ? c : arc_cost(a, b, gx, gy, d);
    }
    if (d <= 3.0) /* too short for a direction: any two ends that close */
        return d;
    ga = angle_to(a->tx, a->ty, gx, gy);
    gb = angle_to(b->tx, b->ty, -gx, -gy);
    if (!faces(a->tx, a->ty, gx, gy, ga, p->max_angle) ||
        !faces(b->tx, b->ty, -gx, -gy, gb, p->max_angle))
        return -1.0;
    return d * (1.0 + (fmin(ga, p->max_angle) + fmin(gb, p->max_angle)) /
                          p->max_angle);
}

static int cmp_pair(const void *pa, const void *pb)
{
    const jpair *a = pa, *b = pb;
    return (a->cost > b->cost) - (a->cost < b->cost);
}

/* Candidate pairs of a stage through a bucket grid of cell = its gap. */
static int find_pairs(const td_lines *ls, const jend *e, size_t ne,
                      const td_join_params *p, int stage, jpair **out,
                      size_t *nout, td_ctx *cx)
{
    double gap = stage == 3   ? p->cross_gap
                 : stage == 2 ? p->long_gap
                              : p->max_gap;
    double cs = gap > 1 ? gap : 1;
    int cw = (int)(p->w / cs) + 1, ch = (int)(p->h / cs) + 1;
    size_t *head = NULL, *nxt = NULL, i, np = 0, cap = 0;
    jpair *pairs = NULL;
    int rc = TD_ENOMEM;
    head = malloc((size_t)cw * (size_t)ch * sizeof *head);
    nxt = malloc((ne + 1) * sizeof *nxt);
    if (!head || !nxt)
        goto fail;
    for (i = 0; i < (size_t)cw * (size_t)ch; i++)
        head[i] = SIZE_MAX;
    for (i = 0; i < ne; i++) {
        int bx = (int)(e[i].x / cs), by = (int)(e[i].y / cs);
        size_t b = (size_t)by * (size_t)cw + (size_t)bx;
        nxt[i] = head[b];
        head[b] = i;
    }
    for (i = 0; i < ne; i++) {
        int bx0 = (int)(e[i].x / cs), by0 = (int)(e[i].y / cs), bx, by;
        for (by = by0 - 1; by <= by0 + 1; by++)
            for (bx = bx0 - 1; bx <= bx0 + 1; bx++) {
                size_t j;
                if (bx < 0 || by < 0 || bx >= cw || by >= ch)
                    continue;
                for (j = head[(size_t)by * cw + bx]; j != SIZE_MAX; j = nxt[j]) {
                    double c;
                    int arc = 0;
                    if (j <= i ||
                        (c = pair_cost(ls, &e[i], &e[j], p, stage, &arc)) < 0)
                        continue;
                    if (np == cap) {
                        jpair *q = realloc(pairs, (cap = cap ? 2 * cap : 256) * sizeof *q);
                        if (!q)
                            goto fail;
                        pairs = q;
                    }
                    pairs[np].cost = c;
                    pairs[np].arc = arc;
                    pairs[np].a = i;
                    pairs[np++].b = j;
                }
            }
    }
    *out = pairs;
    *nout = np;
    pairs = NULL;
    rc = 0;
fail:
    if (rc)
        td_seterr(cx, TD_ENOMEM, "join: out of memory");
    free(head);
    free(nxt);
    free(pairs);
    return rc;
}

/* Append line src to dst, reversed when rev, skipping nothing; its
 * bridges and edge flag go with it.  An empty dst takes src's points
 * over (src is left without them): most chains are one line. */
static int append(td_line *dst, td_line *src, int rev, td_ctx *cx)
{
    if (dst->n == 0 && !dst->xy) {
        if (rev)
            td_line_reverse(src);
        dst->xy = src->xy, dst->n = src->n, dst->cap = src->cap;
        src->xy = NULL, src->n = src->cap = 0;
    } else if (td_line_append(dst, src, rev, cx) != 0)
        return TD_ENOMEM;
    dst->bridged += src->bridged;
    dst->edge |= src->edge;
    return 0;
}

/* Append the inner points of a join's path (forward when it runs from the
 * end the chain leaves by). */
static int path_inside(td_line *d, const td_line *path, int forward,
                       td_ctx *cx)
{
    size_t k;
    for (k = 1; k + 1 < path->n; k++) {
        size_t j = forward ? k : path->n - 1 - k;
        if (td_line_push(d, path->xy[2 * j], path->xy[2 * j + 1], cx) != 0)
            return TD_ENOMEM;
    }
    return 0;
}

/* Build one chain starting at line i entered through end `first` (0: its
 * start, so it is walked forward).  Marks used lines. */
static int build_chain(td_lines *ls, const jend *e, const long *end_of_line,
                       const td_lines *paths, uint8_t *used, size_t i,
                       int first, td_lines *out, td_ctx *cx)
{
    td_line *d = td_lines_add(out, cx);
    size_t line = i;
    int enter = first;
    if (!d)
        return TD_ENOMEM;
    for (;;) {
        long exit_end = end_of_line[2 * line + (enter ? 0 : 1)];
        used[line] = 1;
        if (append(d, &ls->v[line], enter == 1, cx) != 0)
            return TD_ENOMEM;
        if (exit_end < 0 || e[exit_end].partner < 0)
            return 0;
        {
            const jend *to = &e[e[exit_end].partner];
            d->bridged++;
            if (e[exit_end].path >= 0 &&
                path_inside(d, &paths->v[e[exit_end].path],
                            e[exit_end].path_from, cx) != 0)
                return TD_ENOMEM;
            if (used[to->line]) { /* back where the chain began: a ring */
                d->closed = 1;
                return 0;
            }
            line = to->line;
            enter = to->at_end;
        }
    }
}

/* Chains of joined lines into out; closed lines flagged in drop (may be
 * NULL) are left out.  The lines' points move into out: ls is only fit
 * to be freed after. */
static int assemble(td_lines *ls, const jend *e, const long *eol,
                    const td_lines *paths, const uint8_t *drop, td_lines *out,
                    td_ctx *cx)
{
    uint8_t *used = calloc(ls->n + 1, 1);
    size_t i;
    int rc = 0;
    if (!used)
        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
    /* chains with a free end first, then what is left are rings */
    for (i = 0; i < ls->n && rc == 0; i++) {
        long s = eol[2 * i], t = eol[2 * i + 1];
        if (used[i] || ls->v[i].closed)
            continue;
        if (s < 0 || e[s].partner < 0)
            rc = build_chain(ls, e, eol, paths, used, i, 0, out, cx);
        else if (t < 0 || e[t].partner < 0)
            rc = build_chain(ls, e, eol, paths, used, i, 1, out, cx);
    }
    for (i = 0; i < ls->n && rc == 0; i++) {
        if (used[i] || (drop && drop[i]))
            continue;
        if (ls->v[i].closed) {
            td_line *d = td_lines_add(out, cx);
            rc = d ? append(d, &ls->v[i], 0, cx) : TD_ENOMEM;
            if (d)
                d->closed = 1;
        } else {
            rc = build_chain(ls, e, eol, paths, used, i, 0, out, cx);
        }
    }
    free(used);
    return rc;
}

/* The open ends of ls off the border, with tangents over `tangent` px;
 * eol[2i + k] is the index of line i's end k, or -1. */
static int collect_ends(const td_lines *ls, const td_join_params *p,
                        double tangent, int stage, jend **out, size_t *nout,
                        long **eol_out, td_ctx *cx)
{
    jend *e = td_calloc(2 * ls->n + 1, sizeof *e, cx);
    long *eol = td_calloc(2 * ls->n + 1, sizeof *eol, cx);
    size_t i, n = 0;
    int k;
    if (!e || !eol) {
        free(e);
        free(eol);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < 2; k++) {
            const td_line *l = &ls->v[i];
            eol[2 * i + k] = -1;
            if (l->closed || l->n == 0)
                continue;
            end_of(l, k, tangent, &e[n]);
            if (on_border(p, e[n].x, e[n].y))
                continue;
            if (stage >= 2)
                end_curve(l, k, &e[n]);
            e[n].line = i;
            eol[2 * i + k] = (long)n++;
        }
    *out = e;
    *nout = n;
    *eol_out = eol;
    return 0;
}

/* ---- stage 2: crossing test ------------------------------------------ */

/* Whether l fits in a box of side min_length (a digit's size). */
static int compact(const td_line *l, double min_length)
{
    double b[4];
    td_line_box(l, b);
    return b[2] - b[0] < min_length && b[3] - b[1] < min_length;
}

/* Small closed rings (fitting in min_length): digits of a label when a
 * join passes through them; a join may cross them. */
static int small_ring(const td_line *l, double min_length)
{
    return l->closed && min_length > 0 && compact(l, min_length);
}

static double orient(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Proper crossing of segments ab and cd (touching or collinear: no). */
static int seg_cross(const double *a, const double *b, const double *c,
                     const double *d)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d);
    double o3 = orient(c, d, a), o4 = orient(c, d, b);
    return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) &&
           ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

/* Segments ab and cd meet: cross, touch, or overlap (pixel-centre
 * coordinates put another line's vertex exactly on a join). */
static int seg_meet(const double *a, const double *b, const double *c,
                    const double *d)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d);
    double o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (o1 == 0 && o2 == 0) /* collinear: overlap of the projections */
        return fmax(fmin(a[0], b[0]), fmin(c[0], d[0])) <=
                   fmin(fmax(a[0], b[0]), fmax(c[0], d[0])) &&
               fmax(fmin(a[1], b[1]), fmin(c[1], d[1])) <=
                   fmin(fmax(a[1], b[1]), fmax(c[1], d[1]));
    return o1 * o2 <= 0 && o3 * o4 <= 0;
}

/* Bucket grid of line segments: entry i is segment seg[i] of line line[i]
 * (segment k runs from point k to point k+1, wrapping for closed lines). */
typedef struct sgrid {
    double cs;
    int cw, ch;
    size_t *head, *next, *line, *seg, n, cap;
} sgrid;

static void sgrid_free(sgrid *g)
{
    free(g->head), free(g->next), free(g->line), free(g->seg);
}

static int sgrid_put(sgrid *g, size_t cell, size_t line, size_t seg)
{
    if (g->n == g->cap) {
        size_t cap = g->cap ? 2 * g->cap : 4096, *a, *b, *c;
        a = realloc(g->next, cap * sizeof *a);
        if (a)
            g->next = a;
        b = realloc(g->line, cap * sizeof *b);
        if (b)
            g->line = b;
        c = realloc(g->seg, cap * sizeof *c);
        if (c)
            g->seg = c;
        if (!a || !b || !c)
            return TD_ENOMEM;
        g->cap = cap;
    }
    g->line[g->n] = line, g->seg[g->n] = seg;
    g->next[g->n] = g->head[cell];
    g->head[cell] = g->n++;
    return 0;
}

/* The cell of coordinate v in cells of side cs, clamped to 0 .. lim - 1. */
static int cell_of_xy(double cs, double v, int lim)
{
    int c = (int)floor(v / cs);
    return c < 0 ? 0 : c >= lim ? lim - 1 : c;
}

static int cell_of(const sgrid *g, double v, int lim)
{
    return cell_of_xy(g->cs, v, lim);
}

/* Every segment of every line except small rings, in each cell its
 * bounding box touches, for the cells a candidate join passes (so memory
 * follows the ends, not the sheet's ink). */
static int sgrid_build(sgrid *g, const td_lines *ls, const td_join_params *p,
                       const jend *e, const jpair *pairs, size_t np,
                       td_ctx *cx)
{
    size_t i, k, c;
    memset(g, 0, sizeof *g);
    g->cs = 32.0;
    g->cw = (int)(p->w / g->cs) + 1, g->ch = (int)(p->h / g->cs) + 1;
    if (!(g->head = malloc((size_t)g->cw * (size_t)g->ch * sizeof *g->head)))
        goto fail;
    for (c = 0; c < (size_t)g->cw * (size_t)g->ch; c++)
        g->head[c] = SIZE_MAX - 1; /* not needed */
    for (i = 0; i < np; i++) {
        const jend *a = &e[pairs[i].a], *b = &e[pairs[i].b];
        double m = hypot(b->x - a->x, b->y - a->y); /* the curve's bulge */
        int x0 = cell_of(g, fmin(a->x, b->x) - m, g->cw);
        int x1 = cell_of(g, fmax(a->x, b->x) + m, g->cw);
        int y0 = cell_of(g, fmin(a->y, b->y) - m, g->ch);
        int y1 = cell_of(g, fmax(a->y, b->y) + m, g->ch), x, y;
        for (y = y0; y <= y1; y++)
            for (x = x0; x <= x1; x++)
                g->head[(size_t)y * g->cw + x] = SIZE_MAX;
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t nseg = l->n < 2 ? 0 : l->closed ? l->n : l->n - 1;
        if (small_ring(l, p->min_length))
            continue;
        for (k = 0; k < nseg; k++) {
            const double *a = l->xy + 2 * k, *b = l->xy + 2 * ((k + 1) % l->n);
            int x0 = cell_of(g, fmin(a[0], b[0]), g->cw);
            int x1 = cell_of(g, fmax(a[0], b[0]), g->cw);
            int y0 = cell_of(g, fmin(a[1], b[1]), g->ch);
            int y1 = cell_of(g, fmax(a[1], b[1]), g->ch), x, y;
            for (y = y0; y <= y1; y++)
                for (x = x0; x <= x1; x++)
                    if (g->head[(size_t)y * g->cw + x] != SIZE_MAX - 1 &&
                        sgrid_put(g, (size_t)y * g->cw + x, i, k) != 0)
                        goto fail;
        }
    }
    return 0;
fail:
    sgrid_free(g);
    memset(g, 0, sizeof *g);
    return td_seterr(cx, TD_ENOMEM, "join: out of memory");
}

/* Whether segment k of line i is one of the last 3 at end e (the line's
 * own end, which the join starts from). */
static int near_end(const td_lines *ls, size_t i, size_t k, const jend *e)
{
    size_t nseg = ls->v[i].n - 1;
    if (e->line != i)
        return 0;
    return e->at_end ? k + 3 >= nseg : k < 3;
}

/* Whether the piece pa-pb of the join a-b meets a line of the grid (other
 * than the last 3 segments at the join's own two ends) or an accepted
 * join's piece (acc). */
static int crosses(const sgrid *g, const td_lines *ls, const jend *a,
                   const jend *b, const double *pa, const double *pb,
                   const double *acc, size_t nacc)
{
    int x0 = cell_of(g, fmin(pa[0], pb[0]), g->cw);
    int x1 = cell_of(g, fmax(pa[0], pb[0]), g->cw);
    int y0 = cell_of(g, fmin(pa[1], pb[1]), g->ch);
    int y1 = cell_of(g, fmax(pa[1], pb[1]), g->ch), x, y;
    size_t j;
    for (j = 0; j < nacc; j++)
        if (seg_meet(pa, pb, acc + 4 * j, acc + 4 * j + 2))
            return 1;
    for (y = y0; y <= y1; y++)
        for (x = x0; x <= x1; x++)
            for (j = g->head[(size_t)y * g->cw + x]; j < g->n;
                 j = g->next[j]) {
                const td_line *l = &ls->v[g->line[j]];
                size_t k = g->seg[j];
                if (near_end(ls, g->line[j], k, a) ||
                    near_end(ls, g->line[j], k, b))
                    continue;
                if (seg_meet(pa, pb, l->xy + 2 * k,
                             l->xy + 2 * ((k + 1) % l->n)))
                    return 1;
            }
    return 0;
}

/* Distance from point c to segment ab. */
static double seg_dist(const double *a, const double *b, const double *c)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], L2 = dx * dx + dy * dy, t = 0;
    if (L2 > 0)
        t = ((c[0] - a[0]) * dx + (c[1] - a[1]) * dy) / L2;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(c[0] - a[0] - t * dx, c[1] - a[1] - t * dy);
}

/* Small rings that an accepted stage-2 join passes through (crosses, or
 * touches within 1 px): flagged in drop and counted. */
static void mark_glyphs(const td_lines *ls, const td_join_params *p,
                        const double *acc, size_t nacc, uint8_t *drop,
                        td_join_stats *st)
{
    size_t i, j, k;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (!nacc || !small_ring(l, p->min_length))
            continue;
        for (j = 0; j < nacc && !drop[i]; j++)
            for (k = 0; k < l->n && !drop[i]; k++)
                if (seg_dist(acc + 4 * j, acc + 4 * j + 2, l->xy + 2 * k) < 1.0 ||
                    seg_cross(acc + 4 * j, acc + 4 * j + 2, l->xy + 2 * k,
                              l->xy + 2 * ((k + 1) % l->n)))
                    drop[i] = 1;
        st->glyphs += drop[i];
    }
}

/* ---- the passes ------------------------------------------------------- */

/* The path of a stage-2 join from a to b into pts (x,y pairs): the
 * quadratic Bezier through the crossing C of the two end tangents (so it
 * leaves a and reaches b along their lines), a point about every ARC_STEP
 * px; when C is not ahead of both ends within the gap's length (straight
 * or S-shaped), the chord.  Returns the number of points (2..ARC_MAXPTS).
 *
 *            C             Q(t) = (1-t)^2 a + 2t(1-t) C + t^2 b
 *        .-'   '-.
 *   ===a           b===                                              */
#define ARC_STEP 4.0
#define ARC_MAXPTS 32
static size_t join_path(const jend *a, const jend *b, double *pts)
{
    double gx = b->x - a->x, gy = b->y - a->y, d = hypot(gx, gy);
    double den = a->ux * b->uy - a->uy * b->ux, sa = -1, sb = -1, cx, cy;
    size_t n = 1, k;
    pts[0] = a->x, pts[1] = a->y;
    if (fabs(den) > 1e-9) {
        sa = (gx * b->uy - gy * b->ux) / den; /* a + sa u_a = b + sb u_b */
        sb = (gx * a->uy - gy * a->ux) / den;
    }
    if (sa > 0 && sb > 0 && sa < d && sb < d) {
        cx = a->x + sa * a->ux, cy = a->y + sa * a->uy;
        n = (size_t)ceil((sa + sb) / ARC_STEP);
        n = n < 2 ? 2 : n > ARC_MAXPTS - 1 ? ARC_MAXPTS - 1 : n;
        for (k = 1; k < n; k++) {
            double t = (double)k / (double)n, u = 1.0 - t;
            pts[2 * k] = u * u * a->x + 2 * t * u * cx + t * t * b->x;
            pts[2 * k + 1] = u * u * a->y + 2 * t * u * cy + t * t * b->y;
        }
    }
    pts[2 * n] = b->x, pts[2 * n + 1] = b->y;
    return n + 1;
}

/* Whether the path pts (np points) of join a-b meets a line or an
 * accepted join. */
static int path_crosses(const sgrid *g, const td_lines *ls, const jend *a,
                        const jend *b, const double *pts, size_t np,
                        const double *acc, size_t nacc)
{
    size_t k;
    for (k = 0; k + 1 < np; k++)
        if (crosses(g, ls, a, b, pts + 2 * k, pts + 2 * k + 2, acc, nacc))
            return 1;
    return 0;
}

/* Keep an accepted stage-2 join: its pieces in acc (x0,y0,x1,y1, grown
 * as needed) and its path in paths, linked from both ends. */
static int keep_path(jend *a, jend *b, const double *pts, size_t np,
                     double **acc, size_t *nacc, size_t *cap,
                     td_lines *paths, td_ctx *cx)
{
    td_line *l;
    size_t k;
    if (*nacc + np > *cap) {
        size_t c = 2 * (*nacc + np) + 64;
        double *v = realloc(*acc, 4 * c * sizeof *v);
        if (!v)
            return td_seterr(cx, TD_ENOMEM, "join: out of memory");
        *acc = v, *cap = c;
    }
    for (k = 0; k + 1 < np; k++, ++*nacc)
        memcpy(*acc + 4 * *nacc, pts + 2 * k, 4 * sizeof **acc);
    if (!(l = td_lines_add(paths, cx)))
        return TD_ENOMEM;
    for (k = 0; k < np; k++)
        if (td_line_push(l, pts[2 * k], pts[2 * k + 1], cx) != 0)
            return TD_ENOMEM;
    a->path = b->path = (long)paths->n - 1;
    a->path_from = 1, b->path_from = 0;
    return 0;
}

/* Whether the packed mask m (p's size) is set at (x, y) or a pixel next
 * to it. */
static int bits_at(const td_join_params *p, const uint8_t *m, double x,
                   double y)
{
    size_t stride = ((size_t)p->w + 7) / 8;
    int X = (int)floor(x), Y = (int)floor(y), dx, dy;
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++) {
            int u = X + dx, v = Y + dy;
            if (u >= 0 && v >= 0 && u < p->w && v < p->h &&
                (m[(size_t)v * stride + (size_t)(u >> 3)] >> (u & 7)) & 1)
                return 1;
        }
    return 0;
}

/* Whether another ink covers (x, y) or a pixel next to it. */
static int other_at(const td_join_params *p, double x, double y)
{
    return bits_at(p, p->other, x, y);
}

/* Whether the water covers (x, y) or a pixel next to it. */
static int water_at(const td_join_params *p, double x, double y)
{
    return bits_at(p, p->water, x, y);
}

/* The path pts (np points) runs over another ink (p->other) for more than
 * OTHER_MIN px and OTHER_SHARE of its length: a contour hidden under a
 * road, whose ends could be any two of the contours it crosses. */
#define OTHER_MIN 8.0
#define OTHER_SHARE 0.33
static int under_other(const td_join_params *p, const double *pts, size_t np)
{
    double len = 0, over = 0;
    size_t k;
    if (!p->other)
        return 0;
    for (k = 0; k + 1 < np; k++) {
        double dx = pts[2 * k + 2] - pts[2 * k],
               dy = pts[2 * k + 3] - pts[2 * k + 1];
        double d = hypot(dx, dy);
        int m = (int)ceil(d), j;
        for (j = 0; j < m; j++) {
            double t = (j + 0.5) / m;
            over += other_at(p, pts[2 * k] + t * dx, pts[2 * k + 1] + t * dy)
                        ? d / m
                        : 0;
        }
        len += d;
    }
    return over > OTHER_MIN && over > OTHER_SHARE * len;
}

/* ---- stage 3: across a stream ----------------------------------------
 *
 *        a \   P   / b        a stream printed over a contour hides it
 *           \  #  /           where they cross, and binarisation clears
 *            \ # /            the other ink's pixels: at the bottom of a
 *              #              V the two ends then point into the stream.
 *   Ends a, b (at most cross_gap apart, each within CROSS_NEAR px of the
 *   water) whose tangents meet within CROSS_MEET px of the water, no
 *   farther from either than the gap, are joined a-P-b; ends that point
 *   the same way side by side across the water (a narrow V whose tip it
 *   hid) by the cap of a U; ends that face each other straight across it
 *   (within max_angle) by their chord.  Roads are left out: across a
 *   road the ends of two contours line up as often as one's.  (A rule
 *   that the path run over the water for at most 60 % of its length
 *   refused the V's whose tip lies in the stream: all of a short path is
 *   within a pixel of it.) */
#define CROSS_NEAR 5       /* px: an end this near the water */
#define CROSS_MEET 3       /* px: the tangents meet this near it */
#define U_COS 0.87         /* a U's two ends within 30 deg of one way */
#define STREAM_R 6         /* px about P for the water's direction */
#define STREAM_CROSS 0.64  /* |cos|: the gap at least 50 deg off it */
#define STREAM_BISECT 0.77 /* |cos|: a V's bisector within 40 deg of it */
#define U_LEVEL 0.7        /* and level: the gap's share along that way */

/* Another ink within r px of (x, y). */
static int water_near(const td_join_params *p, double x, double y, int r)
{
    int dx, dy;
    for (dy = 1 - r; dy <= r - 1; dy += 2) /* other_at looks 1 px about */
        for (dx = 1 - r; dx <= r - 1; dx += 2)
            if (dx * dx + dy * dy <= r * r && water_at(p, x + dx, y + dy))
                return 1;
    return 0;
}

/* The water's direction about (x, y): the main axis of its pixels within
 * STREAM_R px (*sx, *sy, unit); 0 when there are too few. */
static int stream_dir(const td_join_params *p, double x, double y, double *sx,
                      double *sy)
{
    return td_flank_axis(p->water, p->w, p->h, x, y, STREAM_R, 1, sx, sy) >=
           STREAM_R;
}

/* The stream about P runs across the gap a-b (at least STREAM_CROSS from
 * along it) and, for a V (bend: its two arms' tangents meet at P), along
 * the V's bisector: two contours ending on either side of a stream that
 * hides a third between them line up across it as well, but their gap
 * runs along the stream. */
static int stream_fits(const td_join_params *p, const jend *a, const jend *b,
                       double px, double py, int bend)
{
    double sx, sy, gx = b->x - a->x, gy = b->y - a->y, g = hypot(gx, gy);
    if (!stream_dir(p, px, py, &sx, &sy) || g <= 0)
        return 0;
    if (fabs(sx * gx + sy * gy) / g > STREAM_CROSS)
        return 0;
    if (bend) {
        double bx = a->ux + b->ux, by = a->uy + b->uy, bl = hypot(bx, by);
        if (bl > 0.2 && fabs(sx * bx + sy * by) / bl < STREAM_BISECT)
            return 0;
    }
    return 1;
}

/* Where the tangent rays of a and b meet (a + sa u_a = b + sb u_b), with
 * sa, sb in (0, limit]: 1 and *px, *py; else 0. */
static int rays_meet(const jend *a, const jend *b, double limit, double *px,
                     double *py)
{
    double gx = b->x - a->x, gy = b->y - a->y;
    double den = a->ux * b->uy - a->uy * b->ux, sa, sb;
    if (fabs(den) < 1e-6)
        return 0;
    sa = (gx * b->uy - gy * b->ux) / den;
    sb = (gx * a->uy - gy * a->ux) / den;
    if (!(sa > 0 && sb > 0 && sa <= limit && sb <= limit))
        return 0;
    *px = a->x + sa * a->ux, *py = a->y + sa * a->uy;
    return 1;
}

/* a and b point the same way, side by side across the other ink (a
 * narrow V whose tip the ink hid): the cap of a U joins them. */
static int u_pair(const td_join_params *p, const jend *a, const jend *b,
                  double gx, double gy, double d)
{
    return a->ux * b->ux + a->uy * b->uy > U_COS &&
           fabs(gx * a->ux + gy * a->uy) < U_LEVEL * d &&
           fabs(gx * b->ux + gy * b->uy) < U_LEVEL * d &&
           water_near(p, a->x + 0.5 * gx, a->y + 0.5 * gy, 2);
}

static double cross_cost(const td_join_params *p, const jend *a, const jend *b,
                         double gx, double gy, double d)
{
    double px, py;
    if (!water_near(p, a->x, a->y, CROSS_NEAR) ||
        !water_near(p, b->x, b->y, CROSS_NEAR))
        return -1.0;
    if (rays_meet(a, b, d, &px, &py))
        return water_near(p, px, py, CROSS_MEET) &&
                       stream_fits(p, a, b, px, py, 1)
                   ? hypot(px - a->x, py - a->y) + hypot(px - b->x, py - b->y)
                   : -1.0;
    if (u_pair(p, a, b, gx, gy, d))
        return stream_fits(p, a, b, a->x + 0.5 * gx, a->y + 0.5 * gy, 1)
                   ? 2.0 * d
                   : -1.0;
    if (!faces(a->tx, a->ty, gx, gy, angle_to(a->tx, a->ty, gx, gy),
               p->max_angle) ||
        !faces(b->tx, b->ty, -gx, -gy, angle_to(b->tx, b->ty, -gx, -gy),
               p->max_angle) ||
        !water_at(p, a->x + 0.5 * gx, a->y + 0.5 * gy) ||
        !stream_fits(p, a, b, a->x + 0.5 * gx, a->y + 0.5 * gy, 0))
        return -1.0;
    return d;
}

/* Stage 3's path: a, P (where the tangents meet, when they do), b; or a
 * U's cap half the gap beyond the ends (u_pair). */
static size_t cross_path(const td_join_params *p, const jend *a, const jend *b,
                         double *pts)
{
    double gx = b->x - a->x, gy = b->y - a->y, d = hypot(gx, gy), px, py;
    size_t n = 0;
    pts[2 * n] = a->x, pts[2 * n + 1] = a->y, n++;
    if (rays_meet(a, b, d, &px, &py)) {
        pts[2 * n] = px, pts[2 * n + 1] = py, n++;
    } else if (u_pair(p, a, b, gx, gy, d)) {
        double ux = a->ux + b->ux, uy = a->uy + b->uy, u = hypot(ux, uy);
        ux *= 0.5 * d / u, uy *= 0.5 * d / u;
        pts[2 * n] = a->x + ux, pts[2 * n + 1] = a->y + uy, n++;
        pts[2 * n] = a->x + 0.5 * gx + 1.5 * ux;
        pts[2 * n + 1] = a->y + 0.5 * gy + 1.5 * uy, n++;
        pts[2 * n] = b->x + ux, pts[2 * n + 1] = b->y + uy, n++;
    }
    pts[2 * n] = b->x, pts[2 * n + 1] = b->y, n++;
    return n;
}

/* Keep where stage-3 join pts (np points) crosses the water: its middle
 * point, in st->cross_at. */
static int keep_cross(td_join_stats *st, const double *pts, size_t np,
                      td_ctx *cx)
{
    size_t n = st->cross_joins, m = np / 2;
    double *v = realloc(st->cross_at, 2 * (n + 1) * sizeof *v);
    if (!v)
        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
    st->cross_at = v;
    if (np % 2) { /* a, P, b or a, U, cap, U, b: the middle point */
        v[2 * n] = pts[2 * m], v[2 * n + 1] = pts[2 * m + 1];
    } else { /* the chord */
        v[2 * n] = 0.5 * (pts[0] + pts[2 * np - 2]);
        v[2 * n + 1] = 0.5 * (pts[1] + pts[2 * np - 1]);
    }
    return 0;
}

/* Greedy acceptance, cheapest first; stage 2 also rejects joins whose path
 * meets a line or an accepted join, or runs under another ink, and keeps
 * the accepted paths (pieces in *acc, polylines in paths). */
/* ---- stage 1: junction zones ------------------------------------------
 *
 * Where contours touch, the tracer cut the skeleton at the junction and
 * 2-8 ends meet there.  Contours touch but never cross, so the ends are
 * paired as a whole: the pairing with the least cost (turning, gap; an end
 * left open costs JUNC_LEAVE) among those whose joins do not cross:
 *
 *      a \   / b        a-d and b-c would cross (an X): never;
 *         ) (           a-b and c-d turn back (U): only when nothing
 *      c /   \ d        better; a-c and b-d: the two contours touching.
 *
 * Two ends of a zone of two, next to one junction pixel (a contour's
 * hairpin whose apex touched a speck the fragments stage removed), are
 * joined however sharply the line turns there (up to JUNC_SELF_TURN); in
 * a larger zone, a pair turning more than JUNC_TURN is no candidate. */

static int segs_cross(const jend *a, const jend *b, const jend *c,
                      const jend *d)
{
    double d1 = (b->x - a->x) * (c->y - a->y) - (b->y - a->y) * (c->x - a->x);
    double d2 = (b->x - a->x) * (d->y - a->y) - (b->y - a->y) * (d->x - a->x);
    double d3 = (d->x - c->x) * (a->y - c->y) - (d->y - c->y) * (a->x - c->x);
    double d4 = (d->x - c->x) * (b->y - c->y) - (d->y - c->y) * (b->x - c->x);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) &&
           ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

typedef struct zsearch {
    const jend *e;
    const size_t *ends; /* the zone's ends (indices into e) */
    size_t n;
    const double *cost; /* n x n pair costs, < 0: no pair */
    int mate[JUNC_MAX], best_mate[JUNC_MAX];
    double best;
} zsearch;

static void zone_search(zsearch *z, double sofar)
{
    size_t i, j, k;
    if (sofar >= z->best)
        return;
    for (i = 0; i < z->n && z->mate[i] != -2; i++)
        ;
    if (i == z->n) {
        z->best = sofar;
        memcpy(z->best_mate, z->mate, sizeof z->mate);
        return;
    }
    z->mate[i] = -1; /* left open */
    zone_search(z, sofar + JUNC_LEAVE);
    for (j = i + 1; j < z->n; j++) {
        double c = z->cost[i * z->n + j];
        int ok = c >= 0 && z->mate[j] == -2;
        for (k = 0; ok && k < z->n; k++)
            if (z->mate[k] > (int)k)
                ok = !segs_cross(&z->e[z->ends[i]], &z->e[z->ends[j]],
                                 &z->e[z->ends[k]],
                                 &z->e[z->ends[z->mate[k]]]);
        if (!ok)
            continue;
        z->mate[i] = (int)j;
        z->mate[j] = (int)i;
        zone_search(z, sofar + c);
        z->mate[j] = -2;
    }
    z->mate[i] = -2;
}

/* Where two contours run into one stretch of ink, both come in nearly
 * straight and either could go on along it: a pair (a, b) of the best
 * pairing whose end has another partner, on another line than its mate,
 * costing under `ratio` times as much is undone (both ends left open).
 * A ring closing on itself where it touches a line stays closed. */
static void zone_ambiguous(zsearch *z, double ratio)
{
    int keep[JUNC_MAX];
    size_t a, c;
    for (a = 0; a < z->n; a++) {
        int b = z->best_mate[a];
        double cab;
        keep[a] = 1;
        if (b < 0 || z->e[z->ends[a]].line == z->e[z->ends[b]].line)
            continue;
        cab = fmax(z->cost[a * z->n + (size_t)b], 1.0);
        for (c = 0; c < z->n; c++) {
            double cac = z->cost[a * z->n + c];
            if (c == a || (int)c == b || cac < 0 ||
                z->e[z->ends[c]].line == z->e[z->ends[b]].line)
                continue;
            if (cac < ratio * cab)
                keep[a] = 0;
        }
    }
    for (a = 0; a < z->n; a++) {
        int b = z->best_mate[a];
        if (b > (int)a && (!keep[a] || !keep[b]))
            z->best_mate[a] = z->best_mate[b] = -1;
    }
}

static size_t zfind(size_t *uf, size_t a)
{
    while (uf[a] != a)
        a = uf[a] = uf[uf[a]];
    return a;
}

/* Choose each junction zone's pairing: its pairs get cost -1 (accepted
 * first), the zone's other junction-to-junction pairs are dropped. */
static int junction_zones(const jend *e, size_t ne, const td_join_params *p,
                          jpair *pairs, size_t *np,
                          td_join_stats *st, td_ctx *cx)
{
    size_t *uf = td_malloc((ne + 1) * sizeof *uf, cx), i, j, n = *np, m = 0;
    size_t ends[JUNC_MAX];
    double cost[JUNC_MAX * JUNC_MAX];
    unsigned char *zone_done = td_calloc(ne + 1, 1, cx);
    if (!uf || !zone_done) {
        free(uf);
        free(zone_done);
        return TD_ENOMEM;
    }
    for (i = 0; i < ne; i++)
        uf[i] = i;
    for (i = 0; i < n; i++)
        if (e[pairs[i].a].junc && e[pairs[i].b].junc)
            uf[zfind(uf, pairs[i].a)] = zfind(uf, pairs[i].b);
    for (i = 0; i < ne; i++) {
        size_t r = zfind(uf, i), k, a, b;
        zsearch z;
        if (!e[i].junc || zone_done[r])
            continue;
        zone_done[r] = 1;
        for (k = i, z.n = 0; k < ne; k++)
            if (e[k].junc && zfind(uf, k) == r && z.n < JUNC_MAX)
                ends[z.n++] = k;
        if (z.n < 2)
            continue;
        for (a = 0; a < z.n * z.n; a++)
            cost[a] = -1.0;
        for (j = 0; j < n; j++)
            for (a = 0; a < z.n; a++)
                for (b = 0; b < z.n; b++)
                    if (pairs[j].a == ends[a] && pairs[j].b == ends[b])
                        cost[a * z.n + b] = cost[b * z.n + a] = pairs[j].cost;
        for (a = 0; z.n > 2 && a < z.n; a++) /* hairpins: two ends alone */
            for (b = 0; b < z.n; b++) {
                const jend *ea = &e[ends[a]], *eb = &e[ends[b]];
                if (ea->line != eb->line &&
                    angle_to(ea->tx, ea->ty, -eb->tx, -eb->ty) > JUNC_TURN)
                    cost[a * z.n + b] = -1.0;
            }
        z.e = e, z.ends = ends, z.cost = cost, z.best = HUGE_VAL;
        for (a = 0; a < JUNC_MAX; a++)
            z.mate[a] = -2, z.best_mate[a] = -1;
        zone_search(&z, 0.0);
        if (p->junc_ratio > 1)
            zone_ambiguous(&z, p->junc_ratio);
        st->merges++;
        for (a = 0; a < z.n && z.best_mate[a] >= 0; a++)
            ;
        st->merges_open += a < z.n;
        for (j = 0; j < n; j++)
            for (a = 0; a < z.n; a++)
                for (b = 0; b < z.n; b++)
                    if (pairs[j].a == ends[a] && pairs[j].b == ends[b])
                        pairs[j].cost = z.best_mate[a] == (int)b ? -1.0
                                                                 : -2.0;
    }
    for (i = 0; i < n; i++) /* drop the pairs marked -2 */
        if (pairs[i].cost != -2.0)
            pairs[m++] = pairs[i];
    *np = m;
    free(uf);
    free(zone_done);
    return 0;
}

/* Where line l was cut at the water (cut_water_turns, below), at its
 * vertex k, into st->water_at: that vertex and the two ends it leaves
 * (its neighbours; cut_at drops the vertex). */
static int keep_water_cut(td_join_stats *st, const td_line *l, size_t k,
                          td_ctx *cx)
{
    size_t n = st->water_turns, j;
    size_t at[3] = {k, (k + l->n - 1) % l->n, (k + 1) % l->n};
    double *v = realloc(st->water_at, 6 * (n + 1) * sizeof *v);
    if (!v)
        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
    st->water_at = v;
    for (j = 0; j < 3; j++)
        v[6 * n + 2 * j] = l->xy[2 * at[j]],
                      v[6 * n + 2 * j + 1] = l->xy[2 * at[j] + 1];
    st->water_turns++;
    return 0;
}

/* Whether (x, y) is the point q (an end of a cut: the same vertex). */
static int same_point(const double *q, double x, double y)
{
    return fabs(q[0] - x) < 1e-9 && fabs(q[1] - y) < 1e-9;
}

/* Whether a and b are the two ends of one cut at the water: no stage
 * joins them to each other again (stage 3's U cap did, and undid the
 * cut: docs/scanner.md); undo_water_cuts does when neither found
 * another.  Other ends near the cut may be joined to them (until
 * 2026-12-05 every pair within 8 px of the cut was refused, and with it
 * a contour's own continuation 2 px across the water). */
static int water_cut_pair(const td_join_stats *st, const jend *a, const jend *b)
{
    size_t j;
    for (j = 0; j < st->water_turns; j++) {
        const double *q = st->water_at + 6 * j;
        if ((same_point(q + 2, a->x, a->y) && same_point(q + 4, b->x, b->y)) ||
            (same_point(q + 2, b->x, b->y) && same_point(q + 4, a->x, a->y)))
            return 1;
    }
    return 0;
}

/* Whether another open line than a's and b's ends within room x the gap
 * of a or b (not on the border): the gap is one of several side by side,
 * a faded patch of crowded contours where each end could be joined to
 * any neighbour's. */
static int ends_beside(const sgrid *g, const td_lines *ls,
                       const td_join_params *p, const jend *a, const jend *b,
                       double room)
{
    double r = room * hypot(b->x - a->x, b->y - a->y);
    const jend *s[2] = {a, b};
    int q;
    for (q = 0; q < 2; q++) {
        int x0 = cell_of(g, s[q]->x - r, g->cw),
            x1 = cell_of(g, s[q]->x + r, g->cw);
        int y0 = cell_of(g, s[q]->y - r, g->ch),
            y1 = cell_of(g, s[q]->y + r, g->ch);
        int x, y;
        size_t j;
        for (y = y0; y <= y1; y++)
            for (x = x0; x <= x1; x++)
                for (j = g->head[(size_t)y * g->cw + x]; j < g->n;
                     j = g->next[j]) {
                    const td_line *l = &ls->v[g->line[j]];
                    size_t k = g->seg[j], nseg = l->n - 1, v;
                    if (g->line[j] == a->line || g->line[j] == b->line ||
                        l->closed || (k != 0 && k + 1 != nseg))
                        continue;
                    for (v = 0; v < 2; v++) {
                        size_t i = v ? l->n - 1 : 0;
                        double ex = l->xy[2 * i], ey = l->xy[2 * i + 1];
                        if ((v ? k + 1 == nseg : k == 0) && ex > 2 && ey > 2 &&
                            ex < p->w - 3 && ey < p->h - 3 &&
                            hypot(ex - s[q]->x, ey - s[q]->y) < r)
                            return 1;
                    }
                }
    }
    return 0;
}

/* Stage 1's joins accepted so far, binned by their midpoints in cells at
 * least as wide as the longest candidate: two joins that cross have
 * their midpoints within one such length, so a join is checked against
 * the 3 x 3 cells about its own.  Two small-gap joins never cross
 * (contours do not; ours): at a road across two nested hairpins the
 * cheapest pairs of the four ends took one contour onto the other. */
typedef struct chords {
    double cs;
    int cw, ch;
    size_t *head, *next, n, cap;
    double *xy; /* 4 per join */
} chords;

static void chords_free(chords *c)
{
    free(c->head), free(c->next), free(c->xy);
}

static int chords_init(chords *c, const td_join_params *p, const jend *e,
                       const jpair *pairs, size_t np)
{
    size_t i, nc;
    double L = 8;
    for (i = 0; i < np; i++)
        L = fmax(L, hypot(e[pairs[i].a].x - e[pairs[i].b].x,
                          e[pairs[i].a].y - e[pairs[i].b].y));
    c->cs = L;
    c->cw = (int)(p->w / L) + 1, c->ch = (int)(p->h / L) + 1;
    nc = (size_t)c->cw * (size_t)c->ch;
    if (!(c->head = malloc(nc * sizeof *c->head)))
        return -1;
    for (i = 0; i < nc; i++)
        c->head[i] = SIZE_MAX;
    return 0;
}

/* 1 when the join a-b crosses one accepted before (else it is added), 0,
 * or -1 when out of memory. */
static int chords_cross(chords *c, const jend *a, const jend *b)
{
    double pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y};
    int cx = cell_of_xy(c->cs, 0.5 * (a->x + b->x), c->cw);
    int cy = cell_of_xy(c->cs, 0.5 * (a->y + b->y), c->ch), x, y;
    size_t j;
    for (y = cy - 1; y <= cy + 1; y++)
        for (x = cx - 1; x <= cx + 1; x++) {
            if (x < 0 || y < 0 || x >= c->cw || y >= c->ch)
                continue;
            for (j = c->head[(size_t)y * c->cw + x]; j != SIZE_MAX;
                 j = c->next[j])
                if (seg_cross(pa, pb, c->xy + 4 * j, c->xy + 4 * j + 2))
                    return 1;
        }
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 256, *nx;
        double *xy;
        if (!(nx = realloc(c->next, cap * sizeof *nx)))
            return -1;
        c->next = nx;
        if (!(xy = realloc(c->xy, 4 * cap * sizeof *xy)))
            return -1;
        c->xy = xy, c->cap = cap;
    }
    c->xy[4 * c->n] = a->x, c->xy[4 * c->n + 1] = a->y;
    c->xy[4 * c->n + 2] = b->x, c->xy[4 * c->n + 3] = b->y;
    c->next[c->n] = c->head[(size_t)cy * c->cw + cx];
    c->head[(size_t)cy * c->cw + cx] = c->n++;
    return 0;
}

#define GAP_SIDESTEP 1.5 /* px off the other end's course */
/* td_join_params.gap_near: gaps shorter than this (px) are not tested */
#define GAP_NEAR_MIN 6.0

/* Whether a is one of the two ends a cut at the water left. */
static int water_cut_end(const td_join_stats *st, const jend *a)
{
    size_t j;
    for (j = 0; j < st->water_turns; j++)
        if (same_point(st->water_at + 6 * j + 2, a->x, a->y) ||
            same_point(st->water_at + 6 * j + 4, a->x, a->y))
            return 1;
    return 0;
}

/* Whether the chord from (ax, ay) to (bx, by) passes over the water. */
static int chord_wet(const td_join_params *p, double ax, double ay, double bx,
                     double by)
{
    int m = (int)ceil(hypot(bx - ax, by - ay)), j;
    for (j = 1; j < m; j++) {
        double t = (double)j / m;
        if (water_at(p, ax + t * (bx - ax), ay + t * (by - ay)))
            return 1;
    }
    return 0;
}

/* Whether q is among a's candidate partners (ends indexed by e; first,
 * next: each end's list of pair slots, as in gap_alternatives). */
static int is_candidate(const jend *e, const jpair *pairs, const size_t *first,
                        const size_t *next, const jend *a, const jend *q)
{
    size_t j;
    for (j = first[a - e]; j != SIZE_MAX; j = next[j]) {
        const jpair *pr = &pairs[j / 2];
        if (&e[j % 2 ? pr->a : pr->b] == q)
            return 1;
    }
    return 0;
}

/* Whether an end of a third line (not a's, not b's) lies within r px of
 * end a, other than a's candidate partners (those are the side-step
 * rule's); ix: the ends by x. */
static int third_end_near(const jend *e, const td_dkey *ix, size_t ne,
                          const jpair *pairs, const size_t *first,
                          const size_t *next, const jend *a, const jend *b,
                          double r)
{
    size_t lo = 0, hi = ne, k;
    while (lo < hi) { /* the first end at x >= a->x - r */
        size_t mid = lo + (hi - lo) / 2;
        if (ix[mid].key < a->x - r)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (k = lo; k < ne && ix[k].key <= a->x + r; k++) {
        const jend *q = &e[ix[k].i];
        double dq = hypot(a->x - q->x, a->y - q->y);
        if (q->line != a->line && q->line != b->line && dq <= r &&
            !is_candidate(e, pairs, first, next, a, q))
            return 1;
    }
    return 0;
}

/* Stage 1 (ours, docs/scanner.md "Small gaps that step sideways"): a gap
 * pair (not a junction zone's: cost >= 0) that steps sideways (either end
 * GAP_SIDESTEP px or more off the other's course) and one of whose ends
 * has another candidate on a third line costing under p->gap_ratio times
 * as much is dropped from pairs (*npp updated) and its ends marked in
 * amb: breaks side by side where contours crowd, an end that could as
 * well be its neighbour's; the ends stay open rather than join two
 * contours.  So is a pair of GAP_NEAR_MIN px or more with an end of a
 * third line within p->gap_near of its length of either end, whatever
 * that end's direction (docs/scanner.md "A third line's end near the
 * gap"): where contours crowd their breaks come side by side, and where
 * one turns sharply its ink breaks at the turn, its own continuation
 * fails the angle test and the end straight ahead is another contour's.
 * Water-turn cut ends are left to stage 3 by both rules; chords over the
 * water are not (docs/scanner.md "Chords over the water": where a stream
 * hides the Vs of crowded contours the straightest chord is a neighbour's
 * as often as its own). */
static int gap_alternatives(const td_join_params *p, const td_join_stats *st,
                            const jend *e, size_t ne, jpair *pairs, size_t *npp,
                            unsigned char *amb, td_ctx *cx)
{
    size_t i, j, *first, *next, np = *npp;
    td_dkey *ix;
    unsigned char *drop;
    first = td_malloc((ne + 1) * sizeof *first, cx);
    next = td_malloc((2 * np + 1) * sizeof *next, cx);
    ix = td_malloc((ne + 1) * sizeof *ix, cx);
    drop = td_calloc(np + 1, 1, cx);
    if (!first || !next || !drop || !ix) {
        free(first), free(next), free(drop), free(ix);
        return TD_ENOMEM;
    }
    for (i = 0; i < ne; i++)
        ix[i] = (td_dkey){e[i].x, i};
    qsort(ix, ne, sizeof *ix, td_dkey_cmp);
    for (i = 0; i < ne; i++)
        first[i] = SIZE_MAX;
    for (i = np; i-- > 0;) { /* slot 2i: end a's list, 2i + 1: end b's */
        next[2 * i] = first[pairs[i].a], first[pairs[i].a] = 2 * i;
        next[2 * i + 1] = first[pairs[i].b], first[pairs[i].b] = 2 * i + 1;
    }
    for (i = 0; i < np; i++) {
        const jend *ea = &e[pairs[i].a], *eb = &e[pairs[i].b];
        double gx = eb->x - ea->x, gy = eb->y - ea->y, d = hypot(gx, gy);
        int side;
        if (pairs[i].cost < 0 || ea->line == eb->line ||
            water_cut_end(st, ea) || water_cut_end(st, eb))
            continue; /* a closure, or a line cut where it turned back at
                         the water (its arms' ends are the cap's, askew) */
        if (p->gap_near > 0 && d >= GAP_NEAR_MIN &&
            (third_end_near(e, ix, ne, pairs, first, next, ea, eb,
                            p->gap_near * d) ||
             third_end_near(e, ix, ne, pairs, first, next, eb, ea,
                            p->gap_near * d))) {
            drop[i] = 1; /* a third line's end nearer than half the gap */
            continue;
        }
        if (p->gap_ratio <= 1 ||
            fmax(fabs(gx * ea->ty - gy * ea->tx),
                 fabs(gx * eb->ty - gy * eb->tx)) < GAP_SIDESTEP)
            continue; /* ends on one straight course */
        for (side = 0; side < 2 && !drop[i]; side++) {
            size_t me = side ? pairs[i].b : pairs[i].a;
            size_t mate = side ? pairs[i].a : pairs[i].b;
            for (j = first[me]; j != SIZE_MAX; j = next[j]) {
                const jpair *q = &pairs[j / 2];
                size_t other = j % 2 ? q->a : q->b;
                if (j / 2 == i || q->cost < 0 ||
                    e[other].line == e[mate].line ||
                    e[other].line == e[me].line)
                    continue;
                if (q->cost < p->gap_ratio * fmax(pairs[i].cost, 1.0)) {
                    drop[i] = 1;
                    break;
                }
            }
        }
    }
    for (i = j = 0; i < np; i++)
        if (!drop[i])
            pairs[j++] = pairs[i];
        else
            amb[pairs[i].a] = amb[pairs[i].b] = 1;
    *npp = j;
    free(first), free(next), free(drop), free(ix);
    return 0;
}

/* Points (x, y pairs) by x, then y. */
static int cmp_xy(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    if (a[0] != b[0])
        return a[0] < b[0] ? -1 : 1;
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* The ends amb marks that stage 1 left free, into st->gaps_at (sorted). */
static int keep_gaps_open(td_join_stats *st, const jend *e, size_t ne,
                          const unsigned char *amb, td_ctx *cx)
{
    size_t i, n = st->gaps_open;
    double *t;
    for (i = 0; i < ne; i++)
        n += amb[i] && e[i].partner < 0;
    if (n == st->gaps_open)
        return 0;
    if (!(t = realloc(st->gaps_at, 2 * n * sizeof *t)))
        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
    st->gaps_at = t;
    for (i = 0; i < ne; i++)
        if (amb[i] && e[i].partner < 0) {
            t[2 * st->gaps_open] = e[i].x;
            t[2 * st->gaps_open++ + 1] = e[i].y;
        }
    qsort(t, n, 2 * sizeof *t, cmp_xy);
    return 0;
}

/* Whether end a is one stage 1 left open (st->gaps_at). */
static int gap_open(const td_join_stats *st, const jend *a)
{
    double q[2] = {a->x, a->y};
    return st->gaps_open &&
           bsearch(q, st->gaps_at, st->gaps_open, 2 * sizeof *q, cmp_xy);
}

static int accept_pairs(const td_lines *ls, const td_join_params *p, int stage,
                        jend *e, size_t ne, jpair *pairs, size_t np,
                        double **acc, size_t *nacc, td_lines *paths,
                        td_join_stats *st, td_ctx *cx)
{
    unsigned char *amb = NULL;
    sgrid g;
    chords cg;
    size_t i, cap = 0;
    int rc = 0;
    memset(&g, 0, sizeof g);
    memset(&cg, 0, sizeof cg);
    if (np > 0)
        qsort(pairs, np, sizeof *pairs, cmp_pair);
    if (stage == 1 && np > 0 && (p->gap_ratio > 1 || p->gap_near > 0)) {
        if (!(amb = td_calloc(ne + 1, 1, cx)))
            return TD_ENOMEM;
        if ((rc = gap_alternatives(p, st, e, ne, pairs, &np, amb, cx)) != 0) {
            free(amb);
            return rc;
        }
    }
    if (stage == 1 && np > 0 && chords_init(&cg, p, e, pairs, np) != 0)
        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
    if (stage >= 2 && np > 0 && sgrid_build(&g, ls, p, e, pairs, np, cx) != 0)
        return TD_ENOMEM;
    for (i = 0; i < np && rc == 0; i++) {
        jend *a = &e[pairs[i].a], *b = &e[pairs[i].b];
        double pts[2 * ARC_MAXPTS];
        size_t n;
        if (a->partner >= 0 || b->partner >= 0 || water_cut_pair(st, a, b) ||
            (stage >= 2 && (gap_open(st, a) || gap_open(st, b))))
            continue;
        if (stage == 2 && p->gap_room > 0 &&
            ends_beside(&g, ls, p, a, b, p->gap_room))
            continue;
        if (stage == 2) {
            n = join_path(a, b, pts);
            if (!p->curves) /* the chord */
                pts[2] = b->x, pts[3] = b->y, n = 2;
            if (path_crosses(&g, ls, a, b, pts, n, *acc, *nacc) ||
                under_other(p, pts, n))
                continue;
            if ((rc = keep_path(a, b, pts, n, acc, nacc, &cap, paths,
                                cx)) != 0)
                break;
            st->long_joins++;
        } else if (stage == 4) {
            pts[0] = a->x, pts[1] = a->y, pts[2] = b->x, pts[3] = b->y, n = 2;
            if (path_crosses(&g, ls, a, b, pts, n, *acc, *nacc))
                continue;
            if ((rc = keep_path(a, b, pts, n, acc, nacc, &cap, paths, cx)) != 0)
                break;
            st->alone_joins++;
        } else if (stage == 3) {
            n = cross_path(p, a, b, pts);
            if (path_crosses(&g, ls, a, b, pts, n, *acc, *nacc))
                continue;
            if ((rc = keep_path(a, b, pts, n, acc, nacc, &cap, paths, cx)) !=
                    0 ||
                (rc = keep_cross(st, pts, n, cx)) != 0)
                break;
            st->cross_joins++;
        }
        if (stage == 1) {
            int cr = chords_cross(&cg, a, b);
            if (cr < 0) {
                rc = td_seterr(cx, TD_ENOMEM, "join: out of memory");
                break;
            }
            if (cr)
                continue;
        }
        a->partner = (long)pairs[i].b;
        b->partner = (long)pairs[i].a;
        st->joins++;
        st->closures += a->line == b->line;
    }
    chords_free(&cg);
    if (stage >= 2 && np > 0)
        sgrid_free(&g);
    if (amb && rc == 0)
        rc = keep_gaps_open(st, e, ne, amb, cx);
    free(amb);
    return rc;
}

/* Stage 2's joins as lines (their paths) in st->segments. */
/* A copy of l in st->text (p->record): text the joiner removed. */
static int keep_text(td_join_stats *st, const td_line *l, td_ctx *cx)
{
    if (!st->text && !(st->text = td_lines_new(cx)))
        return TD_ENOMEM;
    return td_lines_append_copy(st->text, l, cx);
}

static int record(td_join_stats *st, const td_lines *paths, td_ctx *cx)
{
    size_t j, k;
    if (!st->segments && !(st->segments = td_lines_new(cx)))
        return TD_ENOMEM;
    for (j = 0; j < paths->n; j++) {
        td_line *l = td_lines_add(st->segments, cx);
        for (k = 0; l && k < paths->v[j].n; k++)
            if (td_line_push(l, paths->v[j].xy[2 * k],
                             paths->v[j].xy[2 * k + 1], cx) != 0)
                return TD_ENOMEM;
        if (!l)
            return TD_ENOMEM;
    }
    return 0;
}

/* Stage 4: whether a point of iso (niso (x, y) pairs sorted by x) other
 * than a's and b's own lies within r px of end a. */
static int iso_near(const double *iso, size_t niso, const jend *a,
                    const jend *b, double r)
{
    size_t lo = 0, hi = niso, k;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (iso[2 * mid] < a->x - r)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (k = lo; k < niso && iso[2 * k] <= a->x + r; k++) {
        double qx = iso[2 * k], qy = iso[2 * k + 1];
        if ((qx == a->x && qy == a->y) || (qx == b->x && qy == b->y))
            continue;
        if (hypot(qx - a->x, qy - a->y) <= r)
            return 1;
    }
    return 0;
}

/* Stage 4: the pairs with no other open end (of those before stage 1,
 * iso) within ALONE_CLEAR gaps of either end; *npp updated. */
static void alone_only(const jend *e, jpair *pairs, size_t *npp,
                       const double *iso, size_t niso)
{
    size_t i, m = 0;
    for (i = 0; i < *npp; i++) {
        const jend *a = &e[pairs[i].a], *b = &e[pairs[i].b];
        double r = ALONE_CLEAR * hypot(b->x - a->x, b->y - a->y);
        if (!iso_near(iso, niso, a, b, r) && !iso_near(iso, niso, b, a, r))
            pairs[m++] = pairs[i];
    }
    *npp = m;
}

/* One joining pass (stage 1-4) over *lsp; iso, niso: stage 4's open
 * ends before stage 1 (alone_only). */
static int join_pass(td_lines **lsp, const td_join_params *p, int stage,
                     const double *iso, size_t niso, td_join_stats *st,
                     td_ctx *cx)
{
    td_lines *ls = *lsp, *out = NULL, *paths = NULL;
    jend *e = NULL;
    long *eol = NULL;
    jpair *pairs = NULL;
    double *acc = NULL;
    uint8_t *drop = NULL;
    size_t ne = 0, np = 0, nacc = 0;
    int rc = TD_ENOMEM;
    if (!(paths = td_lines_new(cx)))
        goto fail;
    if ((rc = collect_ends(ls, p, stage == 2 ? p->long_tangent : p->tangent,
                           stage, &e, &ne, &eol, cx)) != 0 ||
        (rc = find_pairs(ls, e, ne, p, stage, &pairs, &np, cx)) != 0 ||
        (stage == 1 &&
         (rc = junction_zones(e, ne, p, pairs, &np, st, cx)) != 0) ||
        (stage == 4 && (alone_only(e, pairs, &np, iso, niso), 0)) ||
        (rc = accept_pairs(ls, p, stage, e, ne, pairs, np, &acc, &nacc, paths,
                           st, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (!(drop = td_calloc(ls->n + 1, 1, cx)))
        goto fail;
    if (stage == 2)
        mark_glyphs(ls, p, acc, nacc, drop, st);
    if (stage == 2 && p->record) {
        size_t i;
        for (i = 0; i < ls->n; i++)
            if (drop[i] && (rc = keep_text(st, &ls->v[i], cx)) != 0)
                goto fail;
    }
    if (stage == 2 && p->record && (rc = record(st, paths, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (!(out = td_lines_new(cx)) ||
        (rc = assemble(ls, e, eol, paths, drop, out, cx)) != 0)
        goto fail;
    td_lines_free(ls);
    *lsp = out;
    out = NULL;
fail:
    td_lines_free(out);
    td_lines_free(paths);
    free(e);
    free(eol);
    free(pairs);
    free(acc);
    free(drop);
    return rc;
}

/* ---- stage 0: fragments ----------------------------------------------- */

#define MAX_TEXT_BOXES 65536
#define TEXT_GAP 4.0 /* px between a digit ring and the next glyph */
/* keep_pieces: junction pieces from this share of min_length (10 px) */
#define KEEP_JUNC 0.4
#define TEXT_NEAR 12.0 /* a straight piece this near a curled one is text */

/* The gap between boxes a and b (0 when they overlap). */
static double box_gap(const double *a, const double *b)
{
    double dx = fmax(0.0, fmax(a[0] - b[2], b[0] - a[2]));
    double dy = fmax(0.0, fmax(a[1] - b[3], b[1] - a[3]));
    return hypot(dx, dy);
}

/* Whether l is straight: its chord at least straight_keep of its length. */
static int straight_piece(const td_line *l, double keep)
{
    double len = td_line_length(l);
    return l->n >= 2 && len > 0 &&
           hypot(l->xy[0] - l->xy[2 * l->n - 2],
                 l->xy[1] - l->xy[2 * l->n - 1]) >= keep * len;
}

/* Straight candidates with no curled piece (a candidate or a small ring:
 * the digits of a label) within TEXT_NEAR px are pieces of a faded or
 * broken contour, not text: no longer candidates.  (Ours; measured with
 * bench_fragments: of the pieces stage 0 removed on the printed sheets 1735
 * lay on contours and 290 did not; digits curl, contour pieces run
 * straight.) */
static int keep_straight(const td_lines *ls, const td_join_params *p,
                         uint8_t *cand, td_ctx *cx)
{
    size_t i, j, m = 0;
    double(*cb)[4];
    uint8_t *keep;
    if (!(cb = td_malloc((ls->n + 1) * sizeof *cb, cx)))
        return TD_ENOMEM;
    if (!(keep = td_calloc(ls->n + 1, 1, cx))) {
        free(cb);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++) /* the curled pieces */
        if ((cand[i] && !straight_piece(&ls->v[i], p->straight_keep)) ||
            small_ring(&ls->v[i], p->min_length))
            td_line_box(&ls->v[i], cb[m++]);
    for (i = 0; i < ls->n; i++) {
        double b[4];
        if (!cand[i] || !straight_piece(&ls->v[i], p->straight_keep))
            continue;
        td_line_box(&ls->v[i], b);
        for (j = 0; j < m && box_gap(b, cb[j]) > TEXT_NEAR; j++)
            ;
        keep[i] = j == m;
    }
    for (i = 0; i < ls->n; i++)
        cand[i] &= !keep[i];
    free(cb);
    free(keep);
    return 0;
}

/* Candidate pieces at least piece_min long (min_length: longer than a
 * digit's stroke; keep_pieces: KEEP_JUNC of it) with both ends at
 * skeleton junctions that join them,
 * through other such pieces, to a line that is no candidate are pieces of
 * a contour network (a narrow finger of a contour pinched where its sides
 * touch: the pieces between the pinch and the junctions), not a label's
 * glyphs, which stand apart from the contours in their gap: each of their
 * junction ends counts as continuing.  (Ours: bench_scanreal, Elkhorn.)
 * So are they when the candidates of their network, with both ends at
 * junctions, are NET_LONG * min_length long together: a small ring that
 * touches itself (SRTM's square artefacts), cut at every contact since the
 * tracer stops at each junction, more ink than one digit's strokes. */
static int junction_attached(const td_lines *ls, const jend *e, size_t ne,
                             const uint8_t *cand, double min_length,
                             double piece_min, uint8_t *cont, td_ctx *cx)
{
    size_t *uf = td_malloc((ls->n + 1) * sizeof *uf, cx), i, j, n = 0;
    td_dkey *k = td_malloc((ne + 1) * sizeof *k, cx);
    uint8_t *lng = td_calloc(ls->n + 1, 1, cx);
    double *net = td_calloc(ls->n + 1, sizeof *net, cx);
    if (!uf || !k || !lng || !net) {
        free(uf), free(k), free(lng), free(net);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++)
        uf[i] = i;
    for (i = 0; i < ne; i++)
        if (e[i].junc)
            k[n].key = e[i].x, k[n++].i = i;
    qsort(k, n, sizeof *k, td_dkey_cmp);
    for (i = 0; i < n; i++)
        for (j = i + 1; j < n && k[j].key - k[i].key <= JUNC_NEAR; j++)
            if (hypot(k[j].key - k[i].key, e[k[j].i].y - e[k[i].i].y) <=
                JUNC_NEAR)
                uf[zfind(uf, e[k[i].i].line)] = zfind(uf, e[k[j].i].line);
    for (i = 0; i < n; i++)
        if (!cand[e[k[i].i].line])
            lng[zfind(uf, e[k[i].i].line)] = 1;
    for (i = 0; i < ls->n; i++)
        if (cand[i] && ls->v[i].junc == 3)
            net[zfind(uf, i)] += td_line_length(&ls->v[i]);
    for (i = 0; i < ls->n; i++)
        if (net[i] >= NET_LONG * min_length)
            lng[i] = 1;
    for (i = 0; i < n; i++) {
        size_t li = e[k[i].i].line;
        if (cand[li] && ls->v[li].junc == 3 &&
            td_line_length(&ls->v[li]) >= piece_min && lng[zfind(uf, li)])
            cont[k[i].i] = 1;
    }
    free(uf), free(k), free(lng), free(net);
    return 0;
}

/* A compact piece as long as min_length or longer, with neither end at
 * a skeleton junction: too long for a digit's stroke, and no rung between
 * two touching contours (test_kiss_corner); one end continuing a longer
 * line makes it that line's hook (a contour bending sharply beside its
 * label gap, cut off there at a thin neck: Orkhon 50 scanned, the 1500
 * line at 920,1600). */
static int hooked(const td_line *l, double min_length)
{
    return !l->junc && td_line_length(l) >= min_length;
}

#define CURL_APART                                                             \
    4.0 /* px between a curled piece's ends: nearer, a ring                    \
           cut open where it touches (a digit's 0, 6, 9) */
#define CURL_NEAR                                                              \
    8.0 /* px: a curled piece this near another candidate                      \
           or a small ring is a glyph of a label */

/* Whether l is curled (td_join_params.curl_keep): open, curl_keep *
 * min_length long or longer, its ends CURL_APART px apart or more (it is
 * a compact piece: a candidate). */
static int curled(const td_line *l, const td_join_params *p)
{
    return p->curl_keep > 0 && !l->closed && l->n >= 2 &&
           td_line_length(l) >= p->curl_keep * p->min_length &&
           hypot(l->xy[0] - l->xy[2 * l->n - 2],
                 l->xy[1] - l->xy[2 * l->n - 1]) >= CURL_APART;
}

/* The curled candidates with no other candidate or small ring within
 * CURL_NEAR px (a label's digits stand side by side) into curl[]: a
 * stretch of contour curled round a small summit or pit, or between two
 * faded breaks it pairs across with nothing (ours; docs/scanner.md,
 * "Curled pieces"). */
static int keep_curled(const td_lines *ls, const td_join_params *p,
                       const uint8_t *cand, uint8_t *curl, td_ctx *cx)
{
    size_t i, j, m = 0;
    double(*cb)[4];
    long *who;
    if (p->curl_keep <= 0)
        return 0;
    if (!(cb = td_malloc((ls->n + 1) * sizeof *cb, cx)))
        return TD_ENOMEM;
    if (!(who = td_malloc((ls->n + 1) * sizeof *who, cx))) {
        free(cb);
        return TD_ENOMEM;
    }
    for (i = 0; i < ls->n; i++)
        if (cand[i] || small_ring(&ls->v[i], p->min_length)) {
            td_line_box(&ls->v[i], cb[m]);
            who[m++] = (long)i;
        }
    for (i = 0; i < ls->n; i++) {
        double b[4];
        if (!cand[i] || !curled(&ls->v[i], p))
            continue;
        td_line_box(&ls->v[i], b);
        for (j = 0; j < m; j++)
            if (who[j] != (long)i && box_gap(b, cb[j]) <= CURL_NEAR)
                break;
        curl[i] = j == m;
    }
    free(cb);
    free(who);
    return 0;
}

/* Ours: a short piece whose end pairs with an end of another short piece
 * continues a longer line when that piece's other end does, through any
 * number of short pieces: a contour broken several times in a row (a faded
 * stretch) comes in pieces that pair only with each other, yet the chain
 * runs from one longer line's end to another's.  A chain with a free end
 * (the glyphs of a label next to a contour end) stays ungrounded on that
 * side, and so does one grounded on a longer line's end that pairs with
 * another longer line's end itself (a stroke beside a small break: the
 * line joins across the break; bench_heights 13 rows down without the
 * exceptions, 9 with this one, Elkhorn colour 0.959 -> 0.968, 2 with
 * both).  Ends at
 * skeleton junctions do not chain (a small loop hanging at the junction
 * of a line's break, bench_heights' scanned Elkhorn 20 sheet at 1582,200,
 * pairs with the line's ends on both sides of it: kept, it takes the
 * line's join there; junction pieces have their own rule,
 * junction_attached).  The least fixpoint: chain[] only grows from the
 * ends that pair with longer lines. */
static int chain_continue(const td_lines *ls, const jend *e, size_t ne,
                          const long *eol, const jpair *pairs, size_t np,
                          const uint8_t *cand, uint8_t *cont, td_ctx *cx)
{
    uint8_t *direct = td_calloc(ne + 1, 1, cx),
            *chain = td_calloc(ne + 1, 1, cx);
    size_t i;
    int again = 1;
    if (!direct || !chain) {
        free(direct), free(chain);
        return TD_ENOMEM;
    }
    for (i = 0; i < np; i++) {
        size_t a = pairs[i].a, b = pairs[i].b;
        if (e[a].line != e[b].line && !cand[e[a].line] && !cand[e[b].line])
            direct[a] = direct[b] = 1;
    }
    while (again) {
        again = 0;
        for (i = 0; i < np; i++) {
            size_t a = pairs[i].a, b = pairs[i].b, k;
            if (e[a].line == e[b].line)
                continue;
            for (k = 0; k < 2; k++) {
                size_t x = k ? b : a, y = k ? a : b, ly = e[y].line;
                long oy = eol[2 * ly + (1 - e[y].at_end)];
                if (chain[x] || !cand[e[x].line] || e[x].junc || e[y].junc)
                    continue;
                if (cand[ly] ? oy >= 0 && chain[oy] : !direct[y])
                    chain[x] = 1, again = 1;
            }
        }
    }
    for (i = 0; i < ls->n; i++) {
        long s0 = eol[2 * i], s1 = eol[2 * i + 1];
        if (cand[i] && s0 >= 0 && s1 >= 0 && chain[s0] && chain[s1])
            cont[s0] = cont[s1] = 1;
    }
    free(direct), free(chain);
    return 0;
}

/* Whether half of l's points or more lie on another ink (within 1 px):
 * a dash of a road the mask took, whose end meets a contour's where the
 * road crosses it. */
static int on_other(const td_join_params *p, const td_line *l)
{
    size_t k, on = 0;
    if (!p->other)
        return 0;
    for (k = 0; k < l->n; k++)
        on += (size_t)other_at(p, l->xy[2 * k], l->xy[2 * k + 1]);
    return 2 * on >= l->n;
}

/* Short open lines (shorter than min_length, or fitting in a box of that
 * side: a bent digit such as 2 or 5) with both ends inside the sheet are
 * label or text fragments unless both ends continue longer lines (a stage-1
 * pair with an end of a line that is not itself such a candidate), or one does
 * and the piece is a hook (hooked): a short piece of a contour between two
 * breaks is kept; so is a compact piece at least twice min_length long with
 * both ends at skeleton junctions (a small ring cut open where it touches a
 * line).  Small closed rings within TEXT_GAP px of a removed fragment are the
 * 0, 6, 8 and 9 of the same label and go too.  With p->keep_pieces, more
 * stay (join.h). */
static int remove_fragments(td_lines *ls, const td_join_params *p,
                            td_join_stats *st, td_lines *late, td_ctx *cx)
{
    jend *e = NULL;
    long *eol = NULL;
    jpair *pairs = NULL;
    uint8_t *cand = NULL, *cont = NULL, *pale = NULL, *kcont = NULL,
            *curl = NULL;
    int joined = p->keep_pieces == TD_PIECES_JOINED;
    size_t ne = 0, np = 0, i, nbox = 0;
    double(*box)[4] = NULL;
    int rc, again;
    if (!(box = td_malloc(MAX_TEXT_BOXES * sizeof *box, cx)))
        return TD_ENOMEM;
    if ((rc = collect_ends(ls, p, p->tangent, 1, &e, &ne, &eol, cx)) != 0 ||
        (rc = find_pairs(ls, e, ne, p, 1, &pairs, &np, cx)) != 0)
        goto fail;
    rc = TD_ENOMEM;
    if (!(cand = td_calloc(ls->n + 1, 1, cx)) ||
        !(cont = td_calloc(ne + 1, 1, cx)) ||
        !(pale = td_calloc(ls->n + 1, 1, cx)) ||
        !(curl = td_calloc(ls->n + 1, 1, cx)))
        goto fail;
    for (i = 0; i < ls->n; i++) {
        double len = td_line_length(&ls->v[i]);
        cand[i] = !ls->v[i].closed && !ls->v[i].edge && eol[2 * i] >= 0 &&
                  eol[2 * i + 1] >= 0 &&
                  (len < p->min_length || compact(&ls->v[i], p->min_length));
        /* a small ring of a contour that touches another line (or itself)
           is cut open at the junction: both ends there, and longer than a
           digit's outline */
        if (cand[i] && ls->v[i].junc == 3 && len >= 2 * p->min_length)
            cand[i] = 0;
        if (p->keep_pieces && ls->v[i].pale) { /* no glyph: clear of the ink */
            pale[i] = cand[i];
            cand[i] &= !joined;
        }
    }
    if (p->straight_keep > 0 && (rc = keep_straight(ls, p, cand, cx)) != 0)
        goto fail;
    if ((rc = keep_curled(ls, p, cand, curl, cx)) != 0)
        goto fail;
    for (i = 0; i < np; i++) {
        size_t a = pairs[i].a, b = pairs[i].b;
        if (e[a].line == e[b].line)
            continue;
        cont[a] |= !cand[e[b].line];
        cont[b] |= !cand[e[a].line];
    }
    if (p->chains &&
        (rc = chain_continue(ls, e, ne, eol, pairs, np, cand, cont, cx)) != 0)
        goto fail;
    if (p->keep_pieces == TD_PIECES_LATE) { /* what the pieces' rule
                                               would keep, set aside */
        rc = TD_ENOMEM;
        if (!(kcont = td_malloc(ne + 1, cx)))
            goto fail;
        memcpy(kcont, cont, ne);
        if ((rc = junction_attached(ls, e, ne, cand, p->min_length,
                                    KEEP_JUNC * p->min_length, kcont, cx)) != 0)
            goto fail;
    }
    if ((rc = junction_attached(
             ls, e, ne, cand, p->min_length,
             joined ? KEEP_JUNC * p->min_length : p->min_length, cont, cx)) !=
        0)
        goto fail;
    for (i = ls->n; i-- > 0;) {
        int c0, c1; /* eol is -1 off the candidates */
        if (!cand[i])
            continue;
        c0 = cont[eol[2 * i]], c1 = cont[eol[2 * i + 1]];
        if (curl[i] && !on_other(p, &ls->v[i])) {
            st->curls++;
            continue;
        }
        if (!(c0 && c1) && !(hooked(&ls->v[i], p->min_length) && (c0 || c1)) &&
            !(joined && (c0 || c1) && !on_other(p, &ls->v[i]))) {
            int k0 = kcont ? kcont[eol[2 * i]] : 0,
                k1 = kcont ? kcont[eol[2 * i + 1]] : 0;
            /* what the pieces' rule keeps goes aside, still a text
               candidate for the label reader and for the small rings next
               to it (so the other lines come out as the default's) */
            int aside = late && kcont &&
                        (pale[i] || (k0 && k1) ||
                         ((k0 || k1) && !on_other(p, &ls->v[i])));
            if (nbox < MAX_TEXT_BOXES)
                td_line_box(&ls->v[i], box[nbox++]);
            if ((p->record && keep_text(st, &ls->v[i], cx) != 0) ||
                (aside && td_lines_append_copy(late, &ls->v[i], cx) != 0)) {
                rc = TD_ENOMEM;
                goto fail;
            }
            td_lines_remove(ls, i);
            if (aside)
                st->late_pieces++;
            else
                st->fragments++;
        }
    }
    /* the rings of 0, 6, 8, 9 next to the other digits of a label whose
       gap was not joined (no join passed through them) */
    for (again = nbox > 0; again;) { /* a ring next to a removed ring too */
        again = 0;
        for (i = ls->n; i-- > 0;) {
            double b[4];
            size_t k;
            int near = 0;
            if (!small_ring(&ls->v[i], p->min_length) || ls->v[i].edge)
                continue;
            td_line_box(&ls->v[i], b);
            for (k = 0; k < nbox && !near; k++) {
                /* one label's glyphs: side by side, of one size */
                double sr = fmax(b[2] - b[0], b[3] - b[1]);
                double sf = fmax(box[k][2] - box[k][0], box[k][3] - box[k][1]);
                near = b[0] - box[k][2] <= TEXT_GAP &&
                       box[k][0] - b[2] <= TEXT_GAP &&
                       b[1] - box[k][3] <= TEXT_GAP &&
                       box[k][1] - b[3] <= TEXT_GAP && sr > 0.7 * sf &&
                       sr < 1.4 * sf;
            }
            if (!near)
                continue;
            if (p->record && keep_text(st, &ls->v[i], cx) != 0)
                goto fail;
            if (nbox < MAX_TEXT_BOXES) {
                memcpy(box[nbox++], b, sizeof b);
                again = 1;
            }
            td_lines_remove(ls, i);
            st->glyphs++;
        }
    }
    rc = 0;
fail:
    free(e);
    free(eol);
    free(pairs);
    free(cand);
    free(cont);
    free(pale);
    free(curl);
    free(kcont);
    free(box);
    return rc;
}

/* Short pieces between two skeleton junctions (the tracer cut there):
 * where two contours touch along a stretch, the stretch is one skeleton
 * piece that belongs to both; removed, so the joiner pairs the branches
 * on either side by direction. */
static void remove_bridges(td_lines *ls, const td_join_params *p,
                           td_join_stats *st)
{
    size_t i;
    for (i = ls->n; i-- > 0;) {
        const td_line *l = &ls->v[i];
        if (!l->closed && l->junc == 3 &&
            td_line_length(l) <= p->bridge_max) {
            td_lines_remove(ls, i);
            st->bridges++;
        }
    }
}

/* ---- road chains: a road's stretches between the contours it crosses ---
 *
 *        ======+=====+======+=====     a straight road the mask took with
 *              |     |      |          the contours where no ink tells it
 *        ======+     +======+=====     apart (a red road over the green
 *              |     |      |          tint), cut at every contour it
 *                                      crosses: a chain of short straight
 *   pieces, each lined up with the next across the contour between.
 *   Traced, each piece is a "contour" stepping from one level to the next
 *   (labelled, on the new Orkhon 50 print, three intervals off).  Before
 *   the joins, open pieces off the border, their chord 8 to chain_max px
 *   long and every vertex within CHAIN_DEV px of it, are linked when an end
 *   of one lies within CHAIN_GAP px of an end of the other, on its line
 *   (within CHAIN_LAT px of the longer one's line, the two directions within
 *   CHAIN_ANGLE degrees) and another line comes within CHAIN_NEAR px of
 *   the gap running across it, 30 degrees or more off the chain (the
 *   contour the road crosses there: a contour broken where its ink faded
 *   leaves its gaps empty, or its neighbours run alongside); chains of
 *   CHAIN_MIN pieces or more are removed (ours).  A contour is not
 *   straight from one crossing to the next three times in a row. */
#define CHAIN_DEV 2.0
#define CHAIN_GAP 40.0
#define CHAIN_LAT 2.5
#define CHAIN_ANGLE 20.0
#define CHAIN_COS 0.93969 /* cos(CHAIN_ANGLE) */
#define CHAIN_MIN 3
#define CHAIN_NEAR 3.0
#define CHAIN_ACROSS 0.5 /* sin 30 degrees */
#define CHAIN_CELL 8.0

typedef struct chain_piece {
    size_t line;
    double e[2][2]; /* its first and last point */
    double u[2];    /* unit chord, first to last */
    double len;     /* the chord's length */
} chain_piece;

static int chain_shape(const td_line *l, double max_len)
{
    double dx, dy, d;
    size_t k;
    if (l->closed || l->edge || l->n < 2)
        return 0;
    dx = l->xy[2 * l->n - 2] - l->xy[0], dy = l->xy[2 * l->n - 1] - l->xy[1];
    d = hypot(dx, dy);
    if (d < 8.0 || d > max_len)
        return 0;
    for (k = 1; k + 1 < l->n; k++) /* within CHAIN_DEV of its chord */
        if (fabs(dx * (l->xy[2 * k + 1] - l->xy[1]) -
                 dy * (l->xy[2 * k] - l->xy[0])) > CHAIN_DEV * d)
            return 0;
    return 1;
}

/* Whether end ka of a and end kb of b line up across the gap between. */
static int chain_link(const chain_piece *a, int ka, const chain_piece *b,
                      int kb)
{
    double gx = b->e[kb][0] - a->e[ka][0], gy = b->e[kb][1] - a->e[ka][1];
    double g = hypot(gx, gy), c = CHAIN_COS;
    double ua[2] = {ka ? a->u[0] : -a->u[0], ka ? a->u[1] : -a->u[1]};
    double ub[2] = {kb ? -b->u[0] : b->u[0], kb ? -b->u[1] : b->u[1]};
    if (g > CHAIN_GAP || ua[0] * ub[0] + ua[1] * ub[1] < c)
        return 0; /* ua: out of a; ub: into b, away from the gap */
    if (g < 1.0)
        return 1;
    if (a->len < b->len) /* the longer piece's direction is the surer */
        ua[0] = ub[0], ua[1] = ub[1];
    return fabs(ua[0] * gy - ua[1] * gx) <= CHAIN_LAT &&
           ua[0] * gx + ua[1] * gy > 0;
}

typedef struct chain_lk {
    size_t i, j; /* pieces */
    int ki, kj;  /* their ends */
    int crossed; /* another line comes within CHAIN_NEAR of the gap */
} chain_lk;

/* Mark the links whose gap another line crosses or touches: the vertices
 * of every line in the cells the gaps' boxes touch, against those gaps. */
static int chain_crossed(const td_lines *ls, const td_join_params *p,
                         const chain_piece *c, chain_lk *lk, size_t nl,
                         td_ctx *cx)
{
    int cw = (int)(p->w / CHAIN_CELL) + 1, ch = (int)(p->h / CHAIN_CELL) + 1;
    size_t q, i, k, *head = td_malloc((size_t)cw * ch * sizeof *head, cx),
                    *next = td_malloc((4 * nl + 1) * sizeof *next, cx),
                    *who = td_malloc((4 * nl + 1) * sizeof *who, cx), m = 0;
    if (!head || !next || !who) {
        free(head), free(next), free(who);
        return TD_ENOMEM;
    }
    for (q = 0; q < (size_t)cw * ch; q++)
        head[q] = SIZE_MAX;
    for (q = 0; q < nl; q++) { /* each gap in the cells of its box */
        const double *A = c[lk[q].i].e[lk[q].ki], *B = c[lk[q].j].e[lk[q].kj];
        int x0 = cell_of_xy(CHAIN_CELL, fmin(A[0], B[0]) - CHAIN_NEAR, cw),
            x1 = cell_of_xy(CHAIN_CELL, fmax(A[0], B[0]) + CHAIN_NEAR, cw),
            y0 = cell_of_xy(CHAIN_CELL, fmin(A[1], B[1]) - CHAIN_NEAR, ch),
            y1 = cell_of_xy(CHAIN_CELL, fmax(A[1], B[1]) + CHAIN_NEAR, ch), x,
            y;
        for (y = y0; y <= y1; y++)
            for (x = x0; x <= x1; x++) {
                size_t *nx, *nw;
                if (m % (4 * nl) == 0 && m > 0) { /* grow (long gaps) */
                    if (!(nx = realloc(next, (m + 4 * nl + 1) * sizeof *nx))) {
                        free(head), free(next), free(who);
                        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
                    }
                    next = nx;
                    if (!(nw = realloc(who, (m + 4 * nl + 1) * sizeof *nw))) {
                        free(head), free(next), free(who);
                        return td_seterr(cx, TD_ENOMEM, "join: out of memory");
                    }
                    who = nw;
                }
                who[m] = q;
                next[m] = head[(size_t)y * cw + x];
                head[(size_t)y * cw + x] = m++;
            }
    }
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        for (k = 0; k < l->n; k++) {
            double x = l->xy[2 * k], y = l->xy[2 * k + 1];
            size_t e = head[(size_t)cell_of_xy(CHAIN_CELL, y, ch) * cw +
                            (size_t)cell_of_xy(CHAIN_CELL, x, cw)];
            for (; e != SIZE_MAX; e = next[e]) {
                chain_lk *L = &lk[who[e]];
                size_t k0 = k >= 2 ? k - 2 : 0,
                       k1 = k + 2 < l->n ? k + 2 : l->n - 1;
                double tx = l->xy[2 * k1] - l->xy[2 * k0],
                       ty = l->xy[2 * k1 + 1] - l->xy[2 * k0 + 1];
                const double *u = c[L->i].u;
                if (L->crossed || i == c[L->i].line || i == c[L->j].line ||
                    seg_dist(c[L->i].e[L->ki], c[L->j].e[L->kj],
                             l->xy + 2 * k) > CHAIN_NEAR)
                    continue;
                /* across the road, not alongside it (crowded contours
                   beside a broken one) */
                L->crossed = k1 > k0 && fabs(u[0] * ty - u[1] * tx) >=
                                            CHAIN_ACROSS * hypot(tx, ty);
            }
        }
    }
    free(head), free(next), free(who);
    return 0;
}

static int remove_road_chains(td_lines *ls, const td_join_params *p,
                              td_join_stats *st, td_ctx *cx)
{
    size_t i, j, n = 0, nl = 0, cap = 0, *uf = NULL, *size = NULL;
    size_t *head = NULL, *next = NULL;
    chain_piece *c = NULL;
    chain_lk *lk = NULL;
    int ka, kb, cw, ch, rc = 0;
    for (i = 0; i < ls->n; i++)
        n += chain_shape(&ls->v[i], p->chain_max);
    if (n < CHAIN_MIN)
        return 0;
    c = td_malloc(n * sizeof *c, cx);
    uf = td_malloc(n * sizeof *uf, cx);
    size = td_calloc(n, sizeof *size, cx);
    if (!c || !uf || !size) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (i = 0, n = 0; i < ls->n; i++)
        if (chain_shape(&ls->v[i], p->chain_max)) {
            const td_line *l = &ls->v[i];
            double dx = l->xy[2 * l->n - 2] - l->xy[0],
                   dy = l->xy[2 * l->n - 1] - l->xy[1], d = hypot(dx, dy);
            c[n].line = i;
            c[n].e[0][0] = l->xy[0], c[n].e[0][1] = l->xy[1];
            c[n].e[1][0] = l->xy[2 * l->n - 2];
            c[n].e[1][1] = l->xy[2 * l->n - 1];
            c[n].u[0] = dx / d, c[n].u[1] = dy / d;
            c[n].len = d;
            uf[n] = n;
            n++;
        }
    cw = (int)(p->w / CHAIN_GAP) + 1, ch = (int)(p->h / CHAIN_GAP) + 1;
    if (!(head = td_malloc((size_t)cw * ch * sizeof *head, cx)) ||
        !(next = td_malloc(2 * n * sizeof *next, cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (i = 0; i < (size_t)cw * ch; i++)
        head[i] = SIZE_MAX;
    for (i = 0; i < 2 * n; i++) { /* the ends in cells of CHAIN_GAP */
        const double *q = c[i / 2].e[i & 1];
        size_t cell = (size_t)cell_of_xy(CHAIN_GAP, q[1], ch) * cw +
                      (size_t)cell_of_xy(CHAIN_GAP, q[0], cw);
        next[i] = head[cell];
        head[cell] = i;
    }
    for (i = 0; i < 2 * n; i++) { /* each end against the ends near it */
        const double *q = c[i / 2].e[i & 1];
        int gx0 = cell_of_xy(CHAIN_GAP, q[0], cw) - 1,
            gy0 = cell_of_xy(CHAIN_GAP, q[1], ch) - 1, gx, gy;
        for (gy = gy0 < 0 ? 0 : gy0; gy <= gy0 + 2 && gy < ch; gy++)
            for (gx = gx0 < 0 ? 0 : gx0; gx <= gx0 + 2 && gx < cw; gx++)
                for (j = head[(size_t)gy * cw + gx]; j != SIZE_MAX;
                     j = next[j]) {
                    ka = (int)(i & 1), kb = (int)(j & 1);
                    if (j / 2 <= i / 2 ||
                        !chain_link(&c[i / 2], ka, &c[j / 2], kb))
                        continue; /* (chain_link is symmetric) */
                    if (nl == cap) {
                        chain_lk *t;
                        cap = cap ? 2 * cap : 64;
                        if (!(t = realloc(lk, cap * sizeof *t))) {
                            rc =
                                td_seterr(cx, TD_ENOMEM, "join: out of memory");
                            goto done;
                        }
                        lk = t;
                    }
                    lk[nl++] = (chain_lk){i / 2, j / 2, ka, kb, 0};
                }
    }
    if (nl + 1 < CHAIN_MIN || (rc = chain_crossed(ls, p, c, lk, nl, cx)) != 0)
        goto done;
    for (i = 0; i < nl; i++) /* a contour runs through the gap */
        if (lk[i].crossed)
            uf[zfind(uf, lk[i].i)] = zfind(uf, lk[i].j);
    for (i = 0; i < n; i++)
        size[zfind(uf, i)]++;
    for (i = n; i-- > 0;) /* lines ascending: remove from the back */
        if (size[zfind(uf, i)] >= CHAIN_MIN) {
            td_lines_remove(ls, c[i].line);
            st->road_pieces++;
        }
done:
    free(c), free(uf), free(size), free(lk), free(head), free(next);
    return rc;
}

/* The end points of ls's open lines, sorted (x, y pairs): with p, those
 * inside the sheet (stage 4's open ends); without, those at skeleton
 * junctions (for junc_restore). */
static int end_points(const td_lines *ls, const td_join_params *p, double **out,
                      size_t *n, td_ctx *cx)
{
    size_t i, m = 0;
    double *v = td_malloc((4 * ls->n + 2) * sizeof *v, cx);
    int k;
    if (!v)
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n == 0)
            continue;
        for (k = 0; k < 2; k++) {
            size_t q = k ? l->n - 1 : 0;
            if (p ? on_border(p, l->xy[2 * q], l->xy[2 * q + 1])
                  : !(l->junc & (1u << k)))
                continue;
            v[2 * m] = l->xy[2 * q], v[2 * m + 1] = l->xy[2 * q + 1], m++;
        }
    }
    qsort(v, m, 2 * sizeof *v, cmp_xy);
    *out = v;
    *n = m;
    return 0;
}

/* The joined lines are new lines: their ends at junctions are found again
 * by position (joins keep the end points as they were). */
static void junc_restore(td_lines *ls, const double *pts, size_t n)
{
    size_t i;
    int k;
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        l->junc = 0;
        if (l->closed || l->n == 0)
            continue;
        for (k = 0; k < 2; k++) {
            double q[2];
            q[0] = l->xy[k ? 2 * l->n - 2 : 0];
            q[1] = l->xy[k ? 2 * l->n - 1 : 1];
            if (n && bsearch(q, pts, n, 2 * sizeof *pts, cmp_xy))
                l->junc |= (unsigned char)(1 << k);
        }
    }
}

static size_t count_open_ends(const td_lines *ls, const td_join_params *p)
{
    size_t i, n = 0;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        if (l->closed || l->n == 0)
            continue;
        n += !on_border(p, l->xy[0], l->xy[1]);
        n += !on_border(p, l->xy[2 * l->n - 2], l->xy[2 * l->n - 1]);
    }
    return n;
}

void td_join_stats_free(td_join_stats *st)
{
    if (!st)
        return;
    td_lines_free(st->segments);
    st->segments = NULL;
    td_lines_free(st->text);
    st->text = NULL;
    td_lines_free(st->late);
    st->late = NULL;
    free(st->cross_at);
    st->cross_at = NULL;
    free(st->water_at);
    st->water_at = NULL;
    free(st->gaps_at);
    st->gaps_at = NULL;
}

/* ---- after stage 0: lines turned back at the water -----------------
 *
 *      |   |          Where a stream crosses two neighbouring contours,
 *      |   |          the colour fringe of its bank can leave a few ink
 *      \___/          pixels that link the two cut ends on one bank: the
 *   ~~~~~~~~~~~~~     skeleton runs down one contour and back up the next
 *                     (a line carrying two heights).  A contour meets a
 * stream only to cross it, so a line that turns back by more than
 * WATER_TURN within WATER_ARM px either side of a vertex next to the
 * water, with the water not between its two arms (a V crossing the
 * stream has the stream between its arms), is cut at its sharpest such
 * vertex; stage 3 then joins each end across the water (ours). */
#define WATER_ARM 8.0   /* px of line either side of the turn */
#define WATER_TURN -0.5 /* cos of the turn: more than 120 degrees */
#define WATER_NEAR 4    /* px: the turn's vertex this near the water */
#define WATER_SIDE 0.8  /* cos: the arms beyond leave within 37 degrees */
#define WATER_APART 12.0 /* px: and stay this near each other */

/* The vertex at arc length t along l (cum: arc length at each vertex,
 * closed lines wrapping), or -1 past an open line's end. */
static long vertex_at(const td_line *l, const double *cum, double t)
{
    double tot = cum[l->n];
    size_t lo = 0, hi = l->n;
    if (l->closed)
        t = fmod(fmod(t, tot) + tot, tot);
    else if (t < 0 || t > cum[l->n - 1])
        return -1;
    while (lo + 1 < hi) {
        size_t mid = (lo + hi) / 2;
        if (cum[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    return (long)lo;
}

/* The cosine of l's turn at vertex k over WATER_ARM px either side (2
 * when the arms do not fit or the water lies between them). */
static double water_turn(const td_join_params *p, const td_line *l,
                         const double *cum, size_t k)
{
    long a = vertex_at(l, cum, cum[k] - WATER_ARM),
         b = vertex_at(l, cum, cum[k] + WATER_ARM);
    double x = l->xy[2 * k], y = l->xy[2 * k + 1], ux, uy, vx, vy, uu, vv;
    if (a < 0 || b < 0 || (size_t)a == k || (size_t)b == k)
        return 2.0;
    ux = x - l->xy[2 * a], uy = y - l->xy[2 * a + 1];
    vx = l->xy[2 * b] - x, vy = l->xy[2 * b + 1] - y;
    uu = hypot(ux, uy), vv = hypot(vx, vy);
    if (uu <= 0 || vv <= 0 ||
        chord_wet(p, l->xy[2 * a], l->xy[2 * a + 1], l->xy[2 * b],
                  l->xy[2 * b + 1]))
        return 2.0;
    { /* two arms side by side: beyond, they leave the same way, near */
        long a2 = vertex_at(l, cum, cum[k] - 2 * WATER_ARM),
             b2 = vertex_at(l, cum, cum[k] + 2 * WATER_ARM);
        double px, py, qx, qy, pp, qq;
        if (a2 < 0 || b2 < 0)
            return 2.0;
        px = l->xy[2 * a2] - l->xy[2 * a],
        py = l->xy[2 * a2 + 1] - l->xy[2 * a + 1];
        qx = l->xy[2 * b2] - l->xy[2 * b],
        qy = l->xy[2 * b2 + 1] - l->xy[2 * b + 1];
        pp = hypot(px, py), qq = hypot(qx, qy);
        if (pp <= 0 || qq <= 0 ||
            (px * qx + py * qy) / (pp * qq) < WATER_SIDE ||
            hypot(l->xy[2 * a2] - l->xy[2 * b2],
                  l->xy[2 * a2 + 1] - l->xy[2 * b2 + 1]) > WATER_APART)
            return 2.0;
    }
    return (ux * vx + uy * vy) / (uu * vv);
}

/* Line l cut at the vertices flagged in f (each dropped), the pieces of 2
 * vertices or more appended to out. */
static int cut_at(const td_join_params *p, const td_line *l,
                  const unsigned char *f, long *next_id, td_lines *out,
                  td_ctx *cx)
{
    size_t n = l->n, start = 0, s, e, k;
    int first = 1;
    if (l->closed) /* start just after a cut */
        for (k = 0; k < n; k++)
            if (f[k]) {
                start = (k + 1) % n;
                break;
            }
    for (s = 0; s < n; s = e + 1) {
        for (e = s; e < n && !f[(start + e) % n]; e++)
            ;
        if (e - s >= 2) {
            td_line *c = td_lines_add_piece(out, l, cx);
            if (!c)
                return TD_ENOMEM;
            c->id = first ? l->id : (*next_id)++;
            c->junc = (unsigned char)((s > 0 || l->closed ? 0 : l->junc & 1) |
                                      (e < n || l->closed ? 0 : l->junc & 2));
            first = 0;
            for (k = s; k < e; k++)
                if (td_line_push(c, l->xy[2 * ((start + k) % n)],
                                 l->xy[2 * ((start + k) % n) + 1], cx) != 0)
                    return TD_ENOMEM;
            c->edge = td_line_on_border(c, p->w, p->h);
        }
    }
    return 0;
}

/* Water tiles: one byte per WT_TILE px square, set where the water
 * covers a pixel of the tile or of one beside it (so a vertex WATER_NEAR
 * + 1 px from the water lies in a set tile): most vertices are far from
 * any stream and need no look at the pixels.  NULL when out of memory. */
#define WT_TILE 8
static unsigned char *water_tiles(const td_join_params *p, int *tw, td_ctx *cx)
{
    size_t stride = ((size_t)p->w + 7) / 8;
    int th = p->h / WT_TILE + 1, x, y;
    unsigned char *t;
    *tw = p->w / WT_TILE + 1;
    if (!(t = td_calloc((size_t)*tw * (size_t)th, 1, cx)))
        return NULL;
    for (y = 0; y < p->h; y++)
        for (x = 0; x < (int)stride; x++) {
            int ty = y / WT_TILE, tx = x * 8 / WT_TILE, dx, dy;
            if (!p->water[(size_t)y * stride + (size_t)x])
                continue;
            for (dy = -1; dy <= 1; dy++)
                for (dx = -1; dx <= 1; dx++)
                    if (ty + dy >= 0 && ty + dy < th && tx + dx >= 0 &&
                        tx + dx < *tw)
                        t[(size_t)(ty + dy) * *tw + (size_t)(tx + dx)] = 1;
        }
    return t;
}

/* Flag in f the turns of l back at the water (tiles: water_tiles, tw
 * wide): the sharpest vertex of each run of vertices next to it that
 * turn back.  Returns the count. */
static size_t flag_water_turns(const td_join_params *p, const td_line *l,
                               const unsigned char *tiles, int tw, double *cum,
                               unsigned char *f)
{
    size_t k, n = l->n, cuts = 0, best = 0;
    double bc = 2.0;
    cum[0] = 0;
    for (k = 1; k <= n; k++) /* cum[n]: the closing segment too */
        cum[k] =
            cum[k - 1] + hypot(l->xy[2 * (k % n)] - l->xy[2 * (k - 1)],
                               l->xy[2 * (k % n) + 1] - l->xy[2 * (k - 1) + 1]);
    if (!l->closed)
        cum[n] = cum[n - 1];
    for (k = 0; k <= n; k++) {
        double c = 2.0;
        if (k < n) {
            double x = l->xy[2 * k], y = l->xy[2 * k + 1];
            int tx = (int)(x / WT_TILE), ty = (int)(y / WT_TILE);
            if (x >= 0 && y >= 0 && x < p->w && y < p->h &&
                tiles[(size_t)ty * tw + (size_t)tx] &&
                water_near(p, x, y, WATER_NEAR))
                c = water_turn(p, l, cum, k);
        }
        if (c < WATER_TURN && c < bc)
            bc = c, best = k;
        else if (c >= WATER_TURN && bc < WATER_TURN) { /* a run ends */
            f[best] = 1, cuts++;
            bc = 2.0;
        }
    }
    return cuts;
}

static int cut_water_turns(td_lines **lsp, const td_join_params *p,
                           td_join_stats *st, td_ctx *cx)
{
    td_lines *ls = *lsp, *out = NULL;
    size_t i, maxn = 0;
    long next_id = 0;
    double *cum = NULL;
    unsigned char *f = NULL, *tiles = NULL;
    int rc = TD_ENOMEM, tw;
    for (i = 0; i < ls->n; i++) {
        maxn = ls->v[i].n > maxn ? ls->v[i].n : maxn;
        next_id = ls->v[i].id >= next_id ? ls->v[i].id + 1 : next_id;
    }
    if (!(cum = td_malloc((maxn + 1) * sizeof *cum, cx)) ||
        !(f = td_malloc(maxn + 1, cx)) || !(out = td_lines_new(cx)) ||
        !(tiles = water_tiles(p, &tw, cx)))
        goto fail;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        size_t c = 0, k;
        if (l->n >= 5) {
            memset(f, 0, l->n + 1);
            c = flag_water_turns(p, l, tiles, tw, cum, f);
        }
        for (k = 0; c && k < l->n; k++)
            if (f[k] && (rc = keep_water_cut(st, l, k, cx)) != 0)
                goto fail;
        if ((rc = c ? cut_at(p, l, f, &next_id, out, cx)
                    : td_lines_append_copy(out, l, cx)) != 0)
            goto fail;
    }
    td_lines_free(ls);
    *lsp = out;
    out = NULL;
    rc = 0;
fail:
    td_lines_free(out);
    free(cum);
    free(f);
    free(tiles);
    return rc;
}

/* After stage 3: a cut at the water whose two ends are both still free
 * (no continuation across the water for either: a loop of one contour
 * whose tip touches the water, as SRTM noise draws them) is joined again.
 * Counts the cuts kept in st->water_turns. */
static int undo_water_cuts(td_lines *ls, td_join_stats *st, td_ctx *cx)
{
    size_t j, i, kept = 0;
    for (j = 0; j < st->water_turns; j++) {
        const double *q = st->water_at + 6 * j;
        size_t li[2], nf = 0;
        int last[2];
        for (i = 0; i < ls->n && nf < 2; i++) {
            const td_line *l = &ls->v[i];
            int e;
            if (l->closed || l->n < 2)
                continue;
            for (e = 0; e < 2 && nf < 2; e++) {
                size_t k = e ? l->n - 1 : 0;
                double x = l->xy[2 * k], y = l->xy[2 * k + 1];
                if (same_point(q + 2, x, y) || same_point(q + 4, x, y))
                    li[nf] = i, last[nf++] = e;
            }
        }
        if (nf != 2) { /* one end (or none) went on across the water */
            kept++;
            continue;
        }
        if (li[0] == li[1]) { /* both ends of one line: a ring again */
            ls->v[li[0]].closed = 1;
            ls->v[li[0]].junc = 0;
            continue;
        }
        {
            td_line *a = &ls->v[li[0]], *b = &ls->v[li[1]];
            unsigned char ja = a->junc, jb = b->junc;
            /* a runs up to the cut, b on from it */
            unsigned char a0 = last[0] ? (ja & 1) : (ja >> 1 & 1);
            unsigned char b1 = last[1] ? (jb & 1) : (jb >> 1 & 1);
            if (!last[0])
                td_line_reverse(a);
            if (td_line_append(a, b, last[1], cx) != 0)
                return TD_ENOMEM;
            a->junc = (unsigned char)(a0 | b1 << 1);
            a->edge = a->edge || b->edge;
            a->bridged += b->bridged;
            td_lines_remove(ls, li[1]);
        }
    }
    st->water_turns = kept;
    return 0;
}

int td_join(td_lines **lsp, const td_join_params *p, td_join_stats *st,
            td_ctx *cx)
{
    td_join_stats local;
    td_lines *late = NULL;
    double *jpts = NULL, *iso = NULL;
    size_t njpts = 0, niso = 0;
    int rc;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    if (p->bridge_max > 0)
        remove_bridges(*lsp, p, st);
    if (p->keep_pieces == TD_PIECES_LATE && !(late = td_lines_new(cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if (p->min_length > 0 &&
        (rc = remove_fragments(*lsp, p, st, late, cx)) != 0)
        goto fail;
    if (p->water && p->cross_gap > 0 && p->water_turns &&
        (rc = cut_water_turns(lsp, p, st, cx)) != 0)
        goto fail;
    if (p->chain_max > 0 && (rc = remove_road_chains(*lsp, p, st, cx)) != 0)
        goto fail;
    if (p->alone_gaps && (rc = end_points(*lsp, p, &iso, &niso, cx)) != 0)
        goto fail;
    if ((rc = end_points(*lsp, NULL, &jpts, &njpts, cx)) != 0 ||
        (rc = join_pass(lsp, p, 1, NULL, 0, st, cx)) != 0)
        goto fail;
    junc_restore(*lsp, jpts, njpts);
    if (p->long_gap > p->max_gap &&
        (rc = join_pass(lsp, p, 2, NULL, 0, st, cx)) != 0)
        goto fail;
    if (p->water && p->cross_gap > 0 &&
        (rc = join_pass(lsp, p, 3, NULL, 0, st, cx)) != 0)
        goto fail;
    if (p->alone_gaps && (rc = join_pass(lsp, p, 4, iso, niso, st, cx)) != 0)
        goto fail;
    if (st->water_turns > 0 && (rc = undo_water_cuts(*lsp, st, cx)) != 0)
        goto fail;
    if (late) { /* the pieces set aside, for the caller */
        size_t i;
        for (i = 0; i < late->n; i++)
            late->v[i].piece = 1;
        st->late = late;
        late = NULL;
    }
    st->ends_open = count_open_ends(*lsp, p);
fail:
    td_lines_free(late);
    free(jpts);
    free(iso);
    if (st == &local)
        td_join_stats_free(&local);
    return rc;
}
