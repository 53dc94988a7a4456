/* Free ends that continue each other across a gap: endpair.h. */
#include "scanner/endpair.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct fend {
    double x, y, tx, ty; /* the end and its outward unit tangent */
    size_t line;
    int last;
    long best; /* index of the best partner, -1 */
    double cost;
} fend;

/* End `last` of l and its outward tangent over TD_ENDPAIR_TANGENT px;
 * 0 when the line is too short to have one. */
static int end_of(const td_line *l, int last, fend *e)
{
    size_t k = last ? l->n - 1 : 0;
    e->x = l->xy[2 * k], e->y = l->xy[2 * k + 1];
    return td_line_end_dir(l, last, TD_ENDPAIR_TANGENT, &e->tx, &e->ty);
}

/* Degrees between unit vector (tx, ty) and vector (gx, gy) of length g. */
static double angle(double tx, double ty, double gx, double gy, double g)
{
    double c = (tx * gx + ty * gy) / g;
    return acos(c > 1 ? 1 : c < -1 ? -1 : c) * 180.0 / M_PI;
}

/* The cost of pairing ends a and b, or a negative value when they do not
 * face each other within reach. */
static double pair_cost(const fend *a, const fend *b, const td_lines *ls,
                        double max_gap)
{
    double gx = b->x - a->x, gy = b->y - a->y, g = hypot(gx, gy), aa, ab;
    if (g > max_gap)
        return -1;
    if (g < 0.5) /* touching: they continue whatever their tangents */
        return 0;
    aa = angle(a->tx, a->ty, gx, gy, g);
    ab = angle(b->tx, b->ty, -gx, -gy, g);
    if (aa > TD_ENDPAIR_ANGLE || ab > TD_ENDPAIR_ANGLE)
        return -1;
    /* a line closing on itself: only across a gap short against it */
    if (a->line == b->line && td_line_length(&ls->v[a->line]) < 4.0 * g)
        return -1;
    return g / max_gap + (aa + ab) / 180.0;
}

static int cmp_pair(const void *pa, const void *pb)
{
    const td_end_pair *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return a->alast - b->alast;
}

/* Contract in endpair.h. */
int td_end_pairs(const td_lines *ls, int (*keep)(size_t i, const void *u),
                 const void *u, int w, int h, double max_gap, td_end_pair **out,
                 size_t *n, td_ctx *cx)
{
    fend *e = NULL;
    long *head = NULL, *next = NULL;
    td_end_pair *p = NULL;
    size_t ne = 0, i, np = 0;
    int gw, gh, cell = (int)ceil(max_gap > 1 ? max_gap : 1);
    *out = NULL, *n = 0;
    if (!(e = td_malloc((2 * ls->n + 1) * sizeof *e, cx)))
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        int last;
        if (l->closed || l->n < 2 || (keep && !keep(i, u)))
            continue;
        for (last = 0; last < 2; last++) {
            fend *f = &e[ne];
            if ((l->junc >> last & 1u) || !end_of(l, last, f) || f->x < 2 ||
                f->y < 2 || f->x > w - 3 || f->y > h - 3)
                continue;
            f->line = i, f->last = last, f->best = -1, f->cost = INFINITY;
            ne++;
        }
    }
    gw = w / cell + 1, gh = h / cell + 1;
    if (!(head = td_malloc((size_t)gw * gh * sizeof *head, cx)) ||
        !(next = td_malloc((ne + 1) * sizeof *next, cx))) {
        free(e), free(head);
        return TD_ENOMEM;
    }
    for (i = 0; i < (size_t)gw * gh; i++)
        head[i] = -1;
    for (i = 0; i < ne; i++) {
        int cx0 = (int)(e[i].x / cell), cy0 = (int)(e[i].y / cell);
        size_t c = (size_t)(cy0 < 0     ? 0
                            : cy0 >= gh ? gh - 1
                                        : cy0) *
                       gw +
                   (size_t)(cx0 < 0     ? 0
                            : cx0 >= gw ? gw - 1
                                        : cx0);
        next[i] = head[c];
        head[c] = (long)i;
    }
    for (i = 0; i < ne; i++) { /* each end's best partner */
        int cx0 = (int)(e[i].x / cell), cy0 = (int)(e[i].y / cell), dx, dy;
        for (dy = -1; dy <= 1; dy++)
            for (dx = -1; dx <= 1; dx++) {
                long j;
                if (cx0 + dx < 0 || cx0 + dx >= gw || cy0 + dy < 0 ||
                    cy0 + dy >= gh)
                    continue;
                for (j = head[(size_t)(cy0 + dy) * gw + (cx0 + dx)]; j >= 0;
                     j = next[j]) {
                    double c;
                    if ((size_t)j == i)
                        continue;
                    c = pair_cost(&e[i], &e[j], ls, max_gap);
                    if (c >= 0 &&
                        (c < e[i].cost || (c == e[i].cost && j < e[i].best)))
                        e[i].cost = c, e[i].best = j;
                }
            }
    }
    if (!(p = td_malloc((ne / 2 + 1) * sizeof *p, cx))) {
        free(e), free(head), free(next);
        return TD_ENOMEM;
    }
    for (i = 0; i < ne; i++) { /* mutual bests, each pair once */
        long j = e[i].best;
        if (j > (long)i && e[j].best == (long)i) {
            p[np].a = e[i].line, p[np].alast = e[i].last;
            p[np].b = e[j].line, p[np].blast = e[j].last;
            p[np].ax = e[i].x, p[np].ay = e[i].y;
            p[np].bx = e[j].x, p[np].by = e[j].y;
            p[np].d = hypot(e[j].x - e[i].x, e[j].y - e[i].y);
            p[np++].cost = e[i].cost;
        }
    }
    qsort(p, np, sizeof *p, cmp_pair);
    free(e), free(head), free(next);
    *out = p, *n = np;
    return 0;
}
