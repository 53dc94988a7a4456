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
 * line joined to itself) is closed. */
#include "join.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct jend {
    double x, y, tx, ty;
    size_t line;
    int at_end;   /* 0: the line's first point, 1: its last */
    long partner; /* index of the joined end, -1 when free */
} jend;

typedef struct jpair {
    double cost;
    size_t a, b;
} jpair;

td_join_params td_join_defaults(int w, int h)
{
    td_join_params p;
    p.max_gap = 16.0;
    p.max_angle = 40.0;
    p.tangent = 8.0;
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
    e->partner = -1;
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

/* Cost of joining ends a and b, or a negative value when not allowed. */
static double pair_cost(const td_lines *ls, const jend *a, const jend *b,
                        const td_join_params *p)
{
    double gx = b->x - a->x, gy = b->y - a->y, d = hypot(gx, gy), ga, gb;
    if (d > p->max_gap)
        return -1.0;
    if (a->line == b->line &&
        (ls->v[a->line].n < 4 || td_line_length(&ls->v[a->line]) < 4 * d))
        return -1.0;
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

/* Candidate pairs through a bucket grid of cell max_gap. */
static int find_pairs(const td_lines *ls, const jend *e, size_t ne,
                      const td_join_params *p, jpair **out, size_t *nout,
                      td_ctx *cx)
{
    double cs = p->max_gap > 1 ? p->max_gap : 1;
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
                    if (j <= i || (c = pair_cost(ls, &e[i], &e[j], p)) < 0)
                        continue;
                    if (np == cap) {
                        jpair *q = realloc(pairs, (cap = cap ? 2 * cap : 256) * sizeof *q);
                        if (!q)
                            goto fail;
                        pairs = q;
                    }
                    pairs[np].cost = c;
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

/* Append line src to dst, reversed when rev, skipping nothing. */
static int append(td_line *dst, const td_line *src, int rev, td_ctx *cx)
{
    size_t i;
    for (i = 0; i < src->n; i++) {
        size_t k = rev ? src->n - 1 - i : i;
        if (td_line_push(dst, src->xy[2 * k], src->xy[2 * k + 1], cx) != 0)
            return TD_ENOMEM;
    }
    dst->bridged += src->bridged;
    dst->edge |= src->edge;
    return 0;
}

/* Build one chain starting at line i entered through end `first` (0: its
 * start, so it is walked forward).  Marks used lines. */
static int build_chain(const td_lines *ls, const jend *e, const long *end_of_line,
                       uint8_t *used, size_t i, int first, td_lines *out,
                       td_ctx *cx)
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
            if (used[to->line]) { /* back where the chain began: a ring */
                d->closed = 1;
                return 0;
            }
            line = to->line;
            enter = to->at_end;
        }
    }
}

static int assemble(const td_lines *ls, const jend *e, const long *eol,
                    td_lines *out, td_ctx *cx)
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
            rc = build_chain(ls, e, eol, used, i, 0, out, cx);
        else if (t < 0 || e[t].partner < 0)
            rc = build_chain(ls, e, eol, used, i, 1, out, cx);
    }
    for (i = 0; i < ls->n && rc == 0; i++) {
        if (used[i])
            continue;
        if (ls->v[i].closed) {
            td_line *d = td_lines_add(out, cx);
            rc = d ? append(d, &ls->v[i], 0, cx) : TD_ENOMEM;
            if (d)
                d->closed = 1;
        } else {
            rc = build_chain(ls, e, eol, used, i, 0, out, cx);
        }
    }
    free(used);
    return rc;
}

static int collect_ends(const td_lines *ls, const td_join_params *p,
                        jend **out, size_t *nout, long **eol_out, td_ctx *cx)
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
            end_of(l, k, p->tangent, &e[n]);
            if (on_border(p, e[n].x, e[n].y))
                continue;
            e[n].line = i;
            eol[2 * i + k] = (long)n++;
        }
    *out = e;
    *nout = n;
    *eol_out = eol;
    return 0;
}

int td_join(td_lines **lsp, const td_join_params *p, td_join_stats *st,
            td_ctx *cx)
{
    td_lines *ls = *lsp, *out = NULL;
    jend *e = NULL;
    long *eol = NULL;
    jpair *pairs = NULL;
    size_t ne = 0, np = 0, i;
    td_join_stats local;
    int rc;
    if (!st)
        st = &local;
    memset(st, 0, sizeof *st);
    if ((rc = collect_ends(ls, p, &e, &ne, &eol, cx)) != 0)
        goto fail;
    if ((rc = find_pairs(ls, e, ne, p, &pairs, &np, cx)) != 0)
        goto fail;
    if (np > 0)
        qsort(pairs, np, sizeof *pairs, cmp_pair);
    for (i = 0; i < np; i++) {
        jend *a = &e[pairs[i].a], *b = &e[pairs[i].b];
        if (a->partner >= 0 || b->partner >= 0)
            continue;
        a->partner = (long)pairs[i].b;
        b->partner = (long)pairs[i].a;
        st->joins++;
        st->closures += a->line == b->line;
    }
    for (i = 0; i < ne; i++)
        st->ends_open += e[i].partner < 0;
    rc = TD_ENOMEM;
    if (!(out = td_lines_new(cx)) || (rc = assemble(ls, e, eol, out, cx)) != 0)
        goto fail;
    td_lines_free(ls);
    *lsp = out;
    out = NULL;
fail:
    td_lines_free(out);
    free(e);
    free(eol);
    free(pairs);
    return rc;
}
