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
