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

/* Join the label's two lines: a's end ka, the middle, b's end kb. */
static int join(td_line *a, int ka, td_line *b, int kb, const td_ocr_read *r,
                td_ctx *cx)
{
    unsigned char junc = (unsigned char)(((a->junc >> (1 - ka)) & 1) |
                                         (((b->junc >> (1 - kb)) & 1) << 1));
    if (ka == 0)
        td_line_reverse(a);
    if (td_line_push(a, r->x, r->y, cx) != 0 ||
        td_line_append(a, b, kb == 1, cx) != 0)
        return TD_ENOMEM;
    a->junc = junc;
    a->edge |= b->edge;
    a->bridged += b->bridged + 1;
    a->width = fmax(a->width, b->width);
    a->confidence = fmax(a->confidence, b->confidence);
    return 0;
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
    /* drop the lines joined into others; the reads follow */
    for (i = n; i-- > 0;)
        if (gone[i])
            td_lines_remove(ls, i);
    {
        size_t k = 0;
        for (i = 0; i < n; i++)
            map[i] = gone[i] ? SIZE_MAX : k++;
    }
    for (i = 0; i < nreads; i++) {
        int j;
        for (j = 0; j < 2; j++)
            if (reads[i].line[j] >= 0 && (size_t)reads[i].line[j] < n)
                reads[i].line[j] =
                    (long)map[root(own, (size_t)reads[i].line[j])];
    }
    free(own), free(map), free(gone);
    return 0;
}
