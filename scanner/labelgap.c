/* Lines joined across the printed labels read between their ends (ours;
 * contract in label.h, measured in docs/label.md "Label gaps closed").
 *
 *   =====a   2 0 0   b=====      a label cuts an index contour; the
 *          '--m--'               joiner leaves the gap open when the line
 *                                bends under the label; the reader finds
 *   the text, the solve gives the lines ending on either side of it the
 *   label's height: then a, the label's middle m and b are one line.
 *   Without it the interpolation leaks through the gap. */
#include "scanner/label.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static size_t root(size_t *own, size_t i)
{
    while (own[i] != i)
        i = own[i] = own[own[i]];
    return i;
}

/* The end of open line l (0 first, 1 last) nearest the label's middle
 * within reach px, on side `side` of it along the reading direction (+1
 * ahead, -1 behind), heading towards it (the chord over the last 6
 * vertices within 70 degrees of the way to the middle), or -1; *dist
 * gets its distance. */
static int end_at(const td_line *l, const td_ocr_read *r, double reach,
                  int side, double *dist)
{
    int k, best = -1;
    double bd = reach;
    if (l->closed || l->n < 2)
        return -1;
    for (k = 0; k < 2; k++) {
        size_t v = k ? l->n - 1 : 0,
               w = k ? (l->n > 6 ? l->n - 7 : 0) : (l->n > 6 ? 6 : l->n - 1);
        double dx = r->x - l->xy[2 * v], dy = r->y - l->xy[2 * v + 1];
        double tx = l->xy[2 * v] - l->xy[2 * w];
        double ty = l->xy[2 * v + 1] - l->xy[2 * w + 1];
        double d = hypot(dx, dy), t = hypot(tx, ty);
        if (!(d <= bd) || -(dx * r->ux + dy * r->uy) * side <= 0)
            continue;
        if (d > 2.0 && t > 0 && (dx * tx + dy * ty) < 0.34 * d * t)
            continue;
        bd = d, best = k;
    }
    if (best >= 0)
        *dist = bd;
    return best;
}

/* Join two lines: a's end ka, the label's middle r (or none), b's end kb. */
static int join(td_line *a, int ka, td_line *b, int kb, const td_ocr_read *r,
                td_ctx *cx)
{
    unsigned char junc = (unsigned char)(((a->junc >> (1 - ka)) & 1) |
                                         (((b->junc >> (1 - kb)) & 1) << 1));
    if (ka == 0)
        td_line_reverse(a);
    if ((r && td_line_push(a, r->x, r->y, cx) != 0) ||
        td_line_append(a, b, kb == 1, cx) != 0)
        return TD_ENOMEM;
    a->junc = junc;
    a->edge |= b->edge;
    a->bridged += b->bridged + 1;
    a->width = fmax(a->width, b->width);
    a->ink = fmax(a->ink, b->ink);
    if (r)
        a->confidence = fmax(a->confidence, b->confidence);
    else if (b->confidence < a->confidence) { /* the less sure piece's */
        a->confidence = b->confidence;
        a->hsource = b->hsource;
    }
    return 0;
}

/* Drop the lines joined into others (gone; own: the line each went
 * into); the reads' line indexes follow.  map: n scratch slots. */
static void drop_joined(td_lines *ls, size_t n, size_t *own, size_t *map,
                        const unsigned char *gone, td_ocr_read *reads,
                        size_t nreads)
{
    size_t i, k = 0;
    for (i = n; i-- > 0;)
        if (gone[i])
            td_lines_remove(ls, i);
    for (i = 0; i < n; i++)
        map[i] = gone[i] ? SIZE_MAX : k++;
    for (i = 0; i < nreads; i++) {
        int j;
        for (j = 0; j < 2; j++)
            if (reads[i].line[j] >= 0 && (size_t)reads[i].line[j] < n)
                reads[i].line[j] =
                    (long)map[root(own, (size_t)reads[i].line[j])];
    }
}

/* Contract in label.h. */
int td_label_close_gaps(td_lines *ls, td_ocr_read *reads, size_t nreads,
                        size_t *closed, td_ctx *cx)
{
    size_t i, n = ls->n, *own, *map;
    unsigned char *gone;
    *closed = 0;
    if (!n || !nreads)
        return 0;
    own = td_malloc(n * sizeof *own, cx);
    map = td_malloc(n * sizeof *map, cx);
    gone = td_calloc(n, 1, cx);
    if (!own || !map || !gone) {
        free(own), free(map), free(gone);
        return TD_ENOMEM;
    }
    for (i = 0; i < n; i++)
        own[i] = i;
    for (i = 0; i < nreads; i++) {
        td_ocr_read *r = &reads[i];
        double reach = 0.5 * r->len + 2.0 * r->digit_px;
        size_t e[2] = {0, 0}, j;
        int ke[2] = {-1, -1}, side;
        if (!r->used || r->spot)
            continue;
        /* the nearest end on each side of the text, of a line at the
           label's height (the reader's lines, or any other) */
        for (side = 0; side < 2; side++) {
            double bd = INFINITY;
            for (j = 0; j < n; j++) {
                double d;
                int k;
                if (gone[j] || !ls->v[j].has_height ||
                    ls->v[j].height != r->value ||
                    (k = end_at(&ls->v[j], r, reach, side ? 1 : -1, &d)) < 0 ||
                    !(d < bd))
                    continue;
                bd = d, e[side] = j, ke[side] = k;
            }
        }
        if (ke[0] < 0 || ke[1] < 0)
            continue;
        if (e[0] == e[1]) { /* a ring the label cut open: closed there */
            td_line *l = &ls->v[e[0]];
            if (ke[0] == ke[1] || td_line_length(l) < 3 * reach)
                continue;
            if (td_line_push(l, r->x, r->y, cx) != 0) {
                free(own), free(map), free(gone);
                return TD_ENOMEM;
            }
            l->closed = 1;
            l->bridged++;
            l->junc = 0;
            ++*closed;
            continue;
        }
        if (join(&ls->v[e[0]], ke[0], &ls->v[e[1]], ke[1], r, cx) != 0) {
            free(own), free(map), free(gone);
            return TD_ENOMEM;
        }
        own[e[1]] = e[0];
        gone[e[1]] = 1;
        ++*closed;
    }
    drop_joined(ls, n, own, map, gone, reads, nreads);
    free(own), free(map), free(gone);
    return 0;
}

/* ---- breaks between lines of one height ---------------------------------
 *
 *      200 -------a    b------- 200     a line broken where contours crowd
 *                   \\  //                 (the scanner cut the blob out, or
 *      210 ----------  ------- 210      the tracer stopped at a junction):
 *                                       a and b face each other, nothing
 *   lies between them, and the solve gave both lines 200: they are one
 *   contour.  Joined, the interpolation no longer sees 210 through the
 *   break. */

typedef struct brk_end {
    double x, y, tx, ty; /* the end, and the way the line leaves by it */
    size_t line;
    int last;
    long best; /* the nearest end it may join, or -1 */
} brk_end;

typedef struct brk {
    size_t a, b; /* two ends */
    double d;
} brk;

static int brk_keep(size_t i, const void *u)
{
    const td_lines *ls = u;
    return ls->v[i].has_height && ls->v[i].n >= 2;
}

static int cmp_brk(const void *pa, const void *pb)
{
    const brk *a = pa, *b = pb;
    if (a->d != b->d)
        return (a->d > b->d) - (a->d < b->d);
    return (a->a > b->a) - (a->a < b->a);
}

/* The end of a line e may join: the nearest end within reach of another
 * line (or the other end of its own) of the same height that e heads
 * towards (within 90 degrees).  Ends are sorted by x. */
static long brk_best(const td_lines *ls, const brk_end *e, size_t n, size_t a,
                     double reach)
{
    size_t lo = 0, hi = a, j;
    double bd = reach, h = ls->v[e[a].line].height;
    long best = -1;
    while (lo < hi) { /* the first end at x >= x_a - reach */
        size_t mid = lo + (hi - lo) / 2;
        if (e[mid].x < e[a].x - reach)
            lo = mid + 1;
        else
            hi = mid;
    }
    for (j = lo; j < n && e[j].x <= e[a].x + reach; j++) {
        double dx = e[j].x - e[a].x, dy = e[j].y - e[a].y, d = hypot(dx, dy);
        if (j == a || !(d < bd) || ls->v[e[j].line].height != h ||
            (d > 2.0 && dx * e[a].tx + dy * e[a].ty < 0))
            continue;
        bd = d, best = (long)j;
    }
    return best;
}

/* Which end of l lies at (x, y): 0 first, 1 last, -1 neither. */
static int end_of(const td_line *l, double x, double y)
{
    if (l->xy[2 * (l->n - 1)] == x && l->xy[2 * (l->n - 1) + 1] == y)
        return 1;
    return l->xy[0] == x && l->xy[1] == y ? 0 : -1;
}

/* Two bridges cross (inside both). */
static int brk_cross(const brk_end *e, const brk *p, const brk *q)
{
    const double a[2] = {e[p->a].x, e[p->a].y}, b[2] = {e[p->b].x, e[p->b].y};
    const double c[2] = {e[q->a].x, e[q->a].y}, d[2] = {e[q->b].x, e[q->b].y};
    double t, u;
    return td_seg_meet_at(a, b, c, d, &t, &u) && t > 1e-9 && t < 1 - 1e-9 &&
           u > 1e-9 && u < 1 - 1e-9;
}

/* Whether (x, y) lies within 2 px of the w x h sheet's border: a line
 * ending there leaves the sheet, no break to bridge. */
static int on_border(double x, double y, int w, int h)
{
    return x < 2 || y < 2 || x > w - 3 || y > h - 3;
}

/* Find the breaks: mutual nearest ends, bridges crossing no line and no
 * shorter bridge.  *out (free()), *nout. */
static int find_breaks(const td_lines *ls, int w, int h, double reach,
                       brk_end **ends, brk **out, size_t *nout, td_ctx *cx)
{
    td_line_end *le = NULL;
    brk_end *e = NULL;
    brk *b = NULL;
    td_seggrid *g = NULL;
    td_lines walls = {NULL, 0, 0}; /* what a bridge may not cross */
    size_t n, i, nb = 0, k;
    int rc = td_line_ends(ls, brk_keep, ls, &le, &n, cx);
    *ends = NULL, *out = NULL, *nout = 0;
    if (rc)
        return rc;
    e = td_calloc(n + 1, sizeof *e, cx);
    b = td_calloc(n / 2 + 1, sizeof *b, cx);
    walls.v = td_malloc((ls->n + 1) * sizeof *walls.v, cx);
    if (!e || !b || !walls.v) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (i = 0; i < ls->n; i++) /* not the scanner's pieces left without a
                                   height (the lines as without them) */
        if (!ls->v[i].piece || ls->v[i].has_height)
            walls.v[walls.n++] = ls->v[i];
    walls.cap = walls.n;
    if (!(g = td_seggrid_new(&walls, cx))) {
        rc = cx && cx->code ? cx->code : TD_ENOMEM;
        goto done;
    }
    for (i = 0; i < n; i++) {
        const td_line *l = &ls->v[le[i].line];
        size_t v = le[i].last ? l->n - 1 : 0;
        size_t u =
            le[i].last ? (l->n > 6 ? l->n - 7 : 0) : (l->n > 6 ? 6 : l->n - 1);
        e[i].x = le[i].x, e[i].y = le[i].y;
        e[i].tx = l->xy[2 * v] - l->xy[2 * u];
        e[i].ty = l->xy[2 * v + 1] - l->xy[2 * u + 1];
        e[i].line = le[i].line, e[i].last = le[i].last;
    }
    for (i = 0; i < n; i++) /* an end on the border leaves the sheet */
        e[i].best =
            on_border(e[i].x, e[i].y, w, h) ? -1 : brk_best(ls, e, n, i, reach);
    for (i = 0; i < n; i++) {
        long j = e[i].best;
        if (j > (long)i && e[j].best == (long)i &&
            !on_border(e[j].x, e[j].y, w, h)) {
            b[nb].a = i, b[nb].b = (size_t)j;
            b[nb++].d = hypot(e[j].x - e[i].x, e[j].y - e[i].y);
        }
    }
    qsort(b, nb, sizeof *b, cmp_brk);
    for (i = 0, k = 0; i < nb; i++) {
        const double pa[2] = {e[b[i].a].x, e[b[i].a].y};
        const double pb[2] = {e[b[i].b].x, e[b[i].b].y};
        size_t q;
        int bad = td_seggrid_crosses(g, pa, pb);
        for (q = 0; q < k && !bad; q++)
            bad = brk_cross(e, &b[q], &b[i]);
        if (!bad)
            b[k++] = b[i];
    }
    *ends = e, *out = b, *nout = k;
    e = NULL, b = NULL;
done:
    td_seggrid_free(g);
    free(walls.v);
    free(le), free(e), free(b);
    return rc;
}

/* Contract in label.h. */
int td_label_close_breaks(td_lines *ls, int w, int h, double reach,
                          td_ocr_read *reads, size_t nreads, size_t *closed,
                          td_ctx *cx)
{
    brk_end *e = NULL;
    brk *b = NULL;
    size_t nb, i, n = ls->n, *own = NULL, *map = NULL;
    unsigned char *gone = NULL;
    int rc;
    *closed = 0;
    if (!n || !(reach > 0))
        return 0;
    if ((rc = find_breaks(ls, w, h, reach, &e, &b, &nb, cx)) != 0)
        return rc;
    own = td_malloc(n * sizeof *own, cx);
    map = td_malloc(n * sizeof *map, cx);
    gone = td_calloc(n, 1, cx);
    if (!own || !map || !gone) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (i = 0; i < n; i++)
        own[i] = i;
    for (i = 0; i < nb; i++) {
        const brk_end *p = &e[b[i].a], *q = &e[b[i].b];
        size_t la = root(own, p->line), lb = root(own, q->line);
        td_line *A = &ls->v[la], *B = &ls->v[lb];
        int ka = end_of(A, p->x, p->y), kb = end_of(B, q->x, q->y);
        if (ka < 0 || kb < 0 || A->closed || B->closed)
            continue;
        if (la == lb) { /* the two ends of one line (or chain): a ring */
            if (ka == kb || td_line_length(A) < 3 * b[i].d)
                continue;
            A->closed = 1;
            A->bridged++;
            A->junc = 0;
        } else {
            if ((rc = join(A, ka, B, kb, NULL, cx)) != 0)
                goto done;
            own[lb] = la;
            gone[lb] = 1;
        }
        ++*closed;
    }
    drop_joined(ls, n, own, map, gone, reads, nreads);
done:
    free(e), free(b), free(own), free(map), free(gone);
    return rc;
}

/* Contract in label.h. */
int td_label_inner_ends(const td_lines *ls, int w, int h)
{
    size_t i;
    int k;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        for (k = 0; !l->closed && l->n && k < 2; k++) {
            const double *p = l->xy + (k ? 2 * (l->n - 1) : 0);
            if (!on_border(p[0], p[1], w, h))
                return 1;
        }
    }
    return 0;
}

/* Contract in label.h. */
double td_label_bridge_reach(double spacing)
{
    double r = TD_BRIDGE_SPACINGS * spacing;
    return r < TD_BRIDGE_MIN   ? TD_BRIDGE_MIN
           : r > TD_BRIDGE_MAX ? TD_BRIDGE_MAX
                               : r;
}
