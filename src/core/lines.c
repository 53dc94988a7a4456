/* lines.c: contour polylines in memory. */
#include "src/core/core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* See lines.h. */
td_lines *td_lines_new(td_ctx *cx)
{
    return td_calloc(1, sizeof(td_lines), cx);
}

/* See lines.h: frees every line's points, the array and ls. */
void td_lines_free(td_lines *ls)
{
    size_t i;
    if (!ls)
        return;
    for (i = 0; i < ls->n; i++)
        free(ls->v[i].xy);
    free(ls->v);
    free(ls);
}

/* See lines.h.  The id is the line's index; after td_lines_remove it is
 * one more than the last line's id when that is larger, so ids stay unique
 * and increasing. */
td_line *td_lines_add(td_lines *ls, td_ctx *cx)
{
    td_line *l;
    long id;
    if (ls->n == ls->cap) {
        size_t cap = ls->cap ? ls->cap * 2 : 64;
        td_line *v;
        if (cap > SIZE_MAX / sizeof *v ||
            !(v = realloc(ls->v, cap * sizeof *v))) {
            td_seterr(cx, TD_ENOMEM, "out of memory (%zu lines)", cap);
            return NULL;
        }
        ls->v = v;
        ls->cap = cap;
    }
    id = (long)ls->n;
    if (ls->n > 0 && ls->v[ls->n - 1].id >= id)
        id = ls->v[ls->n - 1].id + 1;
    l = &ls->v[ls->n++];
    memset(l, 0, sizeof *l);
    l->id = id;
    l->parent = -1;
    return l;
}

/* See lines.h. */
int td_line_push(td_line *l, double x, double y, td_ctx *cx)
{
    if (l->n == l->cap) {
        size_t cap = l->cap ? l->cap * 2 : 16;
        double *xy;
        if (cap > SIZE_MAX / (2 * sizeof *xy) ||
            !(xy = realloc(l->xy, cap * 2 * sizeof *xy)))
            return td_seterr(cx, TD_ENOMEM, "out of memory (%zu points)",
                             cap);
        l->xy = xy;
        l->cap = cap;
    }
    l->xy[2 * l->n] = x;
    l->xy[2 * l->n + 1] = y;
    l->n++;
    return 0;
}

/* See lines.h. */
void td_line_reverse(td_line *l)
{
    size_t i, j;
    if (l->n < 2)
        return;
    for (i = 0, j = l->n - 1; i < j; i++, j--) {
        double x = l->xy[2 * i], y = l->xy[2 * i + 1];
        l->xy[2 * i] = l->xy[2 * j];
        l->xy[2 * i + 1] = l->xy[2 * j + 1];
        l->xy[2 * j] = x;
        l->xy[2 * j + 1] = y;
    }
}

/* See lines.h; out-of-range i is ignored. */
void td_lines_remove(td_lines *ls, size_t i)
{
    if (i >= ls->n)
        return;
    free(ls->v[i].xy);
    memmove(ls->v + i, ls->v + i + 1, (ls->n - i - 1) * sizeof *ls->v);
    ls->n--;
}

/* See lines.h. */
int td_line_on_border(const td_line *l, int w, int h)
{
    size_t i;
    for (i = 0; i < l->n; i++) {
        double x = l->xy[2 * i], y = l->xy[2 * i + 1];
        if (x < 1 || y < 1 || x > w - 1 || y > h - 1)
            return 1;
    }
    return 0;
}

/* See lines.h. */
void td_line_box(const td_line *l, double b[4])
{
    double x0 = HUGE_VAL, y0 = HUGE_VAL, x1 = -HUGE_VAL, y1 = -HUGE_VAL;
    size_t k;
    for (k = 0; k < l->n; k++) {
        double x = l->xy[2 * k], y = l->xy[2 * k + 1];
        x0 = x < x0 ? x : x0, x1 = x > x1 ? x : x1;
        y0 = y < y0 ? y : y0, y1 = y > y1 ? y : y1;
    }
    b[0] = x0, b[1] = y0, b[2] = x1, b[3] = y1;
}

/* See core.h. */
int td_line_end_dir(const td_line *l, int last, double arc, double *ux,
                    double *uy)
{
    size_t n = l->n, k = last ? n - 1 : 0, i;
    double x, y, px, py, s = 0, d;
    if (n == 0)
        return 0;
    x = px = l->xy[2 * k], y = py = l->xy[2 * k + 1];
    for (i = 1; i < n && s < arc; i++) {
        size_t j = last ? n - 1 - i : i;
        s += hypot(l->xy[2 * j] - px, l->xy[2 * j + 1] - py);
        px = l->xy[2 * j], py = l->xy[2 * j + 1];
    }
    d = hypot(x - px, y - py);
    if (d < 1.0)
        return 0;
    *ux = (x - px) / d, *uy = (y - py) / d;
    return 1;
}

double td_line_length(const td_line *l)
{
    double len = 0.0;
    size_t i;
    /* sqrt, not hypot: pixel coordinates cannot overflow, and glibc's
     * hypot is several times slower (a tenth of labelling a big sheet) */
    for (i = 1; i < l->n; i++) {
        double dx = l->xy[2 * i] - l->xy[2 * i - 2];
        double dy = l->xy[2 * i + 1] - l->xy[2 * i - 1];
        len += sqrt(dx * dx + dy * dy);
    }
    if (l->closed && l->n >= 2) {
        double dx = l->xy[0] - l->xy[2 * l->n - 2];
        double dy = l->xy[1] - l->xy[2 * l->n - 1];
        len += sqrt(dx * dx + dy * dy);
    }
    return len;
}

/* See core.h. */
td_line *td_lines_add_piece(td_lines *ls, const td_line *l, td_ctx *cx)
{
    td_line *c = td_lines_add(ls, cx);
    long id;
    if (!c)
        return NULL;
    id = c->id;
    *c = *l;
    c->id = id;
    c->xy = NULL, c->n = c->cap = 0;
    c->closed = 0;
    return c;
}

/* See lines.h. */
int td_lines_append_copy(td_lines *ls, const td_line *l, td_ctx *cx)
{
    td_line *c = td_lines_add(ls, cx);
    size_t k;
    if (!c)
        return TD_ENOMEM;
    *c = *l;
    c->xy = NULL, c->n = c->cap = 0;
    for (k = 0; k < l->n; k++)
        if (td_line_push(c, l->xy[2 * k], l->xy[2 * k + 1], cx) != 0)
            return TD_ENOMEM;
    return 0;
}

/* See lines.h. */
td_lines *td_lines_copy(const td_lines *ls, td_ctx *cx)
{
    td_lines *c = td_lines_new(cx);
    size_t i;
    for (i = 0; c && i < ls->n; i++)
        if (td_lines_append_copy(c, &ls->v[i], cx) != 0) {
            td_lines_free(c);
            return NULL;
        }
    return c;
}

/* See lines.h. */
double td_line_signed_area(const td_line *l)
{
    double a = 0;
    size_t k;
    for (k = 0; k < l->n; k++) {
        size_t k1 = (k + 1) % l->n;
        a += l->xy[2 * k] * l->xy[2 * k1 + 1] - l->xy[2 * k1] * l->xy[2 * k + 1];
    }
    return 0.5 * a;
}

/* See lines.h. */
int td_line_encloses(const td_line *l, double x, double y)
{
    size_t i, j;
    int in = 0;
    if (l->n == 0)
        return 0;
    for (i = 0, j = l->n - 1; i < l->n; j = i++) {
        double xi = l->xy[2 * i], yi = l->xy[2 * i + 1];
        double xj = l->xy[2 * j], yj = l->xy[2 * j + 1];
        if ((yi > y) != (yj > y) && x < (xj - xi) * (y - yi) / (yj - yi) + xi)
            in = !in;
    }
    return in;
}

/* Squared distance of point p from the segment a-b. */
static double seg_dist2(const double *a, const double *b, const double *p)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], t = 0.0;
    double L = dx * dx + dy * dy, ex, ey;
    if (L > 0.0) {
        t = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / L;
        t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    }
    ex = a[0] + t * dx - p[0];
    ey = a[1] + t * dy - p[1];
    return ex * ex + ey * ey;
}

/* Mark the points of xy[i0..i1] that Douglas-Peucker keeps (keep[i0] and
 * keep[i1] set by the caller), with an explicit stack of spans. */
static void dp_span(const double *xy, size_t i0, size_t i1, double tol2,
                    unsigned char *keep, size_t *stack)
{
    size_t top = 0;
    stack[top++] = i0;
    stack[top++] = i1;
    while (top) {
        size_t b = stack[--top], a = stack[--top], i, far = a;
        double dmax = -1.0;
        for (i = a + 1; i < b; i++) {
            double d = seg_dist2(xy + 2 * a, xy + 2 * b, xy + 2 * i);
            if (d > dmax) {
                dmax = d;
                far = i;
            }
        }
        if (far > a && dmax > tol2) {
            keep[far] = 1;
            stack[top++] = a;
            stack[top++] = far;
            stack[top++] = far;
            stack[top++] = b;
        }
    }
}

/* See core.h. */
int td_line_simplify(td_line *l, double tol, td_ctx *cx)
{
    unsigned char *keep;
    size_t *stack, i, k, n = l->n, split = n - 1;
    if (!(tol > 0.0) || n < 3)
        return 0;
    keep = td_calloc(n, 1, cx);
    stack = td_malloc(2 * (n + 1) * sizeof *stack, cx);
    if (!keep || !stack) {
        free(keep);
        free(stack);
        return TD_ENOMEM;
    }
    if (l->closed) { /* the point farthest from the first */
        double dmax = -1.0;
        for (i = 1; i < n; i++) {
            double dx = l->xy[2 * i] - l->xy[0], dy = l->xy[2 * i + 1] - l->xy[1];
            if (dx * dx + dy * dy > dmax) {
                dmax = dx * dx + dy * dy;
                split = i;
            }
        }
    }
    keep[0] = keep[split] = keep[n - 1] = 1;
    dp_span(l->xy, 0, split, tol * tol, keep, stack);
    /* a ring's second half runs split .. n-1; its last point stays, so
       the closing segment back to the first is the traced one */
    if (l->closed && split < n - 1)
        dp_span(l->xy, split, n - 1, tol * tol, keep, stack);
    for (i = 0, k = 0; i < n; i++)
        if (keep[i]) {
            l->xy[2 * k] = l->xy[2 * i];
            l->xy[2 * k + 1] = l->xy[2 * i + 1];
            k++;
        }
    l->n = k;
    free(keep);
    free(stack);
    return 0;
}

/* See core.h.  Lines on threads: each is simplified alone. */
int td_lines_simplify(td_lines *ls, double tol, td_ctx *cx)
{
    long i, n = ls ? (long)ls->n : 0;
    int fail = 0;
#pragma omp parallel for schedule(dynamic, 16) reduction(| : fail)
    for (i = 0; i < n; i++)
        if (!fail)
            fail |= td_line_simplify(&ls->v[i], tol, NULL) != 0;
    return fail ? td_seterr(cx, TD_ENOMEM, "simplify: out of memory") : 0;
}

/* See core.h. */
int td_lines_extent(const td_lines *ls, int *w, int *h, td_ctx *cx)
{
    double mx = 1, my = 1;
    size_t i, k;
    for (i = 0; i < ls->n; i++)
        for (k = 0; k < ls->v[i].n; k++) {
            double x = ls->v[i].xy[2 * k], y = ls->v[i].xy[2 * k + 1];
            mx = x > mx ? x : mx, my = y > my ? y : my;
        }
    if (!(mx < TD_MAX_DIM) || !(my < TD_MAX_DIM))
        return td_seterr(cx, TD_ETOOBIG,
                         "the lines reach x = %g, y = %g, beyond any sheet "
                         "(%d px a side at most)", mx, my, TD_MAX_DIM);
    *w = (int)ceil(mx + 0.5 - 1e-9);
    *h = (int)ceil(my + 0.5 - 1e-9);
    return 0;
}

/* See core.h. */
int td_line_append(td_line *dst, const td_line *src, int rev, td_ctx *cx)
{
    size_t i, need = dst->n + src->n;
    double *o;
    if (src->n == 0)
        return 0;
    if (need > dst->cap) { /* at least double: chains grow piece by piece */
        size_t cap = need > 2 * dst->cap ? need : 2 * dst->cap;
        double *xy;
        if (cap > SIZE_MAX / (2 * sizeof *xy) ||
            !(xy = realloc(dst->xy, cap * 2 * sizeof *xy)))
            return td_seterr(cx, TD_ENOMEM, "out of memory (%zu points)", cap);
        dst->xy = xy;
        dst->cap = cap;
    }
    o = dst->xy + 2 * dst->n;
    if (!rev)
        memcpy(o, src->xy, src->n * 2 * sizeof *o);
    else
        for (i = 0; i < src->n; i++) {
            o[2 * i] = src->xy[2 * (src->n - 1 - i)];
            o[2 * i + 1] = src->xy[2 * (src->n - 1 - i) + 1];
        }
    dst->n = need;
    dst->piece = dst->piece && src->piece; /* a piece joined on a line: a
                                              line */
    return 0;
}

static int cmp_end(const void *pa, const void *pb)
{
    const td_line_end *a = pa, *b = pb;
    if (a->x != b->x)
        return (a->x > b->x) - (a->x < b->x);
    if (a->y != b->y)
        return (a->y > b->y) - (a->y < b->y);
    if (a->line != b->line)
        return (a->line > b->line) - (a->line < b->line);
    return a->last - b->last;
}

/* See core.h. */
int td_line_ends(const td_lines *ls, int (*keep)(size_t i, const void *u),
                 const void *u, td_line_end **out, size_t *n, td_ctx *cx)
{
    td_line_end *e = td_malloc((2 * ls->n + 1) * sizeof *e, cx);
    size_t i, m = 0;
    *out = NULL, *n = 0;
    if (!e)
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        const td_line *l = &ls->v[i];
        int k;
        if (l->closed || l->n == 0 || (keep && !keep(i, u)))
            continue;
        for (k = 0; k < 2; k++) {
            size_t q = k ? l->n - 1 : 0;
            e[m].x = l->xy[2 * q], e[m].y = l->xy[2 * q + 1];
            e[m].line = i, e[m++].last = k;
        }
    }
    qsort(e, m, sizeof *e, cmp_end);
    *out = e, *n = m;
    return 0;
}

/* See core.h. */
size_t td_line_ends_at(const td_line_end *e, size_t n, double x, double y)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if (e[mid].x < x || (e[mid].x == x && e[mid].y < y))
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < n && e[lo].x == x && e[lo].y == y ? lo : n;
}
