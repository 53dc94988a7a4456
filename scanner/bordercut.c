/* Traced lines cut where they turn back at the sheet's border between
 * their ends (ours; contract and picture in bordercut.h, measured in
 * docs/scanner.md "Lines that turn back at the border"). */
#include "scanner/bordercut.h"

#include <math.h>
#include <stdlib.h>

/* Distance of point k of l from the middle of the nearest border pixels
 * (0 on them), and in *side which border: 0 left, 1 top, 2 right, 3
 * bottom. */
static double border_dist(const td_line *l, size_t k, int w, int h, int *side)
{
    double x = l->xy[2 * k], y = l->xy[2 * k + 1];
    double d[4] = {x - 0.5, y - 0.5, w - 0.5 - x, h - 0.5 - y}, m = d[0];
    int s = 0, j;
    for (j = 1; j < 4; j++)
        if (d[j] < m)
            m = d[j], s = j;
    if (side)
        *side = s;
    return m > 0 ? m : 0;
}

/* The point TD_BORDER_ARM px of arc from point m of l, walking by step
 * (+1, -1; round a closed line), or the line's end. */
static size_t arm(const td_line *l, size_t m, int step)
{
    size_t n = l->n, k = m, j;
    double s = 0;
    for (j = 1; j < n; j++) {
        size_t q;
        if (!l->closed && (step > 0 ? k + 1 >= n : k == 0))
            break;
        q = (k + n + (size_t)(step > 0 ? 1 : n - 1)) % n;
        s += hypot(l->xy[2 * q] - l->xy[2 * k],
                   l->xy[2 * q + 1] - l->xy[2 * k + 1]);
        k = q;
        if (s >= TD_BORDER_ARM)
            break;
    }
    return k;
}

/* Whether l turns back at point m: the arms' chords within TD_BORDER_TURN
 * degrees of each other. */
static int turns_back(const td_line *l, size_t m)
{
    size_t a = arm(l, m, -1), b = arm(l, m, 1);
    double ax = l->xy[2 * a] - l->xy[2 * m],
           ay = l->xy[2 * a + 1] - l->xy[2 * m + 1];
    double bx = l->xy[2 * b] - l->xy[2 * m],
           by = l->xy[2 * b + 1] - l->xy[2 * m + 1];
    double la = hypot(ax, ay), lb = hypot(bx, by);
    if (a == m || b == m || !(la > 0) || !(lb > 0))
        return 0;
    return ax * bx + ay * by >= cos(TD_BORDER_TURN * M_PI / 180.0) * la * lb;
}

/* The points where l turns back at the border (at most one per run of
 * points within TD_BORDER_NEAR px of it, none holding an open line's
 * end), in their order along the line (round a closed line from its
 * first point off the border), into cut[] (room for l->n).  Returns
 * their number. */
static size_t turns(const td_line *l, int w, int h, size_t *cut)
{
    size_t n = l->n, k, m = 0, s0 = 0;
    int closed = l->closed && n >= 3;
    if (n < 3 || (closed && td_line_length(l) < TD_BORDER_RING))
        return 0;
    if (closed) { /* start the walk off the border */
        while (s0 < n && border_dist(l, s0, w, h, NULL) <= TD_BORDER_NEAR)
            s0++;
        if (s0 == n)
            return 0;
    }
    for (k = 0; k < n;) {
        size_t len = 0, best = 0, j;
        double bd = HUGE_VAL;
        while (k + len < n) {
            size_t q = (s0 + k + len) % n;
            double d = border_dist(l, q, w, h, NULL);
            if (d > TD_BORDER_NEAR)
                break;
            if (d < bd)
                bd = d, best = q;
            len++;
        }
        if (len == 0) {
            k++;
            continue;
        }
        j = k, k += len;
        if (!closed && (j == 0 || k >= n))
            continue; /* an open line's end: it leaves the sheet there */
        if (turns_back(l, best))
            cut[m++] = best;
    }
    return m;
}

/* Point k of l moved onto the border pixels it is nearest. */
static void onto_border(const td_line *l, size_t k, int w, int h, double *p)
{
    int side;
    p[0] = l->xy[2 * k], p[1] = l->xy[2 * k + 1];
    border_dist(l, k, w, h, &side);
    if (side == 0)
        p[0] = 0.5;
    else if (side == 1)
        p[1] = 0.5;
    else if (side == 2)
        p[0] = w - 0.5;
    else
        p[1] = h - 0.5;
}

/* Append to out the points of l from a to b (on past the last point of a
 * closed line; once round when a == b), as an open line with l's
 * properties; an end at a cut (ca, cb) runs on to the border. */
static int add_piece(td_lines *out, const td_line *l, size_t a, size_t b,
                     int ca, int cb, int w, int h, td_ctx *cx)
{
    size_t n = l->n, k, m = l->closed && a == b ? n + 1 : (b + n - a) % n + 1;
    double p[2];
    td_line *c;
    if (m < 2)
        return 0;
    if (!(c = td_lines_add_piece(out, l, cx)))
        return TD_ENOMEM;
    c->junc =
        (unsigned char)((ca ? 0u : l->junc & 1u) | (cb ? 0u : l->junc & 2u));
    onto_border(l, a, w, h, p);
    if (ca && border_dist(l, a, w, h, NULL) > 0 &&
        td_line_push(c, p[0], p[1], cx) != 0)
        return TD_ENOMEM;
    for (k = 0; k < m; k++) {
        size_t q = (a + k) % n;
        if (td_line_push(c, l->xy[2 * q], l->xy[2 * q + 1], cx) != 0)
            return TD_ENOMEM;
    }
    onto_border(l, b, w, h, p);
    if (cb && border_dist(l, b, w, h, NULL) > 0 &&
        td_line_push(c, p[0], p[1], cx) != 0)
        return TD_ENOMEM;
    c->edge = td_line_on_border(c, w, h);
    return 0;
}

/* Contract in bordercut.h.  Most lines have no turn and stay where they
 * are (no copy: the 10000 x 10000 benchmark sheet's lines hold about 70
 * MB of points); a cut line's first piece takes its place, the others
 * go at the end. */
long td_border_cut(td_lines *ls, int w, int h, td_ctx *cx)
{
    size_t i, n0 = ls->n, cap = 0, *cut = NULL;
    long cuts = 0;
    int rc = 0;
    for (i = 0; i < n0 && rc == 0; i++) {
        td_line l;
        size_t m, j, start;
        if (ls->v[i].n > cap) {
            size_t *t = realloc(cut, ls->v[i].n * sizeof *cut);
            if (!t) {
                rc = td_seterr(cx, TD_ENOMEM, "border cut: out of memory");
                break;
            }
            cut = t, cap = ls->v[i].n;
        }
        if ((m = turns(&ls->v[i], w, h, cut)) == 0)
            continue;
        cuts += (long)m;
        l = ls->v[i]; /* (td_lines_add may move ls->v, not l's points) */
        start = ls->n;
        if (l.closed) /* from each cut round to the next */
            for (j = 0; j < m && rc == 0; j++)
                rc =
                    add_piece(ls, &l, cut[j], cut[(j + 1) % m], 1, 1, w, h, cx);
        else
            for (j = 0; j <= m && rc == 0; j++)
                rc =
                    add_piece(ls, &l, j ? cut[j - 1] : 0,
                              j < m ? cut[j] : l.n - 1, j > 0, j < m, w, h, cx);
        if (rc != 0)
            break;
        if (ls->n == start) { /* (no piece of 2 points: left whole) */
            cuts -= (long)m;
            continue;
        }
        free(l.xy);
        ls->v[i] = ls->v[start]; /* the first piece in its place */
        ls->v[start] = ls->v[--ls->n];
    }
    free(cut);
    if (rc != 0)
        return rc;
    if (cuts > 0)
        for (i = 0; i < ls->n; i++)
            ls->v[i].id = (long)i;
    return cuts;
}
