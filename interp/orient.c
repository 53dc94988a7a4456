/* orient.c: contour orientation (003 §4: "contours are given a direction,
 * higher ground on the left") and the band label grid.
 *
 * Which side of a line is higher comes from the containment tree
 * (src/core/contain.h): a child at a different height says whether the
 * inside of the line's region is higher; without one, the parent does
 * (a parent below: the region is a summit).  The direction then follows
 * from the sign of the region's area (its ring is the line followed by
 * the border back to the start, so ring and line run the same way):
 *
 *   y-up frame (printed map)        pixel frame (y down)
 *   summit ring counterclockwise    summit ring clockwise: area < 0
 *                                   by the shoelace sum in pixel units */
#include "interp/homotopy_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Shoelace sum of a closed ring, pixel units (y down). */
static double signed_area(const td_line *r)
{
    double a = 0;
    size_t i;
    for (i = 0; i < r->n; i++) {
        size_t j = (i + 1) % r->n;
        a += r->xy[2 * i] * r->xy[2 * j + 1] - r->xy[2 * j] * r->xy[2 * i + 1];
    }
    return a / 2;
}

/* +1 when the region of line i is higher inside, -1 lower, 0 unknown. */
static int inside_higher(const td_lines *ls, const td_contain *ct, size_t i)
{
    double z = ls->v[i].height;
    long vote = 0, p = ct->parent[i];
    size_t j;
    for (j = 0; j < ct->n; j++)
        if (ct->parent[j] == (long)i && ls->v[j].height != z)
            vote += ls->v[j].height > z ? 1 : -1;
    if (vote)
        return vote > 0 ? 1 : -1;
    if (p >= 0 && ls->v[p].height != z)
        return ls->v[p].height < z ? 1 : -1;
    return 0;
}

void hm_orient(const td_lines *ls, const td_contain *ct, int *orient)
{
    size_t i;
    for (i = 0; i < ls->n; i++) {
        int up = ct->parent[i] == -2 ? 0 : inside_higher(ls, ct, i);
        double a = up ? signed_area(&ct->rings->v[i]) : 0;
        /* want: higher inside <=> area < 0 (clockwise in pixel rows) */
        orient[i] = a == 0 ? 0 : (up > 0) == (a < 0) ? 1 : -1;
    }
}

/* Ring edges crossing the row centres, bucketed by row: c[off[r] ..
 * off[r+1]) holds the row's (x, ring) pairs. */
typedef struct xing {
    double x;
    int32_t ring;
} xing;

typedef struct xrow {
    size_t *off;
    xing *c;
} xrow;

static void edge_rows(const double *a, const double *b, int h, long *r0,
                      long *r1)
{
    double lo = fmin(fmax(fmin(a[1], b[1]), -1), h + 1.0);
    double hi = fmin(fmax(fmax(a[1], b[1]), -1), h + 1.0);
    *r0 = (long)ceil(lo - 0.5); /* first row centre >= lo */
    *r1 = (long)ceil(hi - 0.5); /* rows [r0, r1): centre in [lo, hi) */
    if (*r0 < 0)
        *r0 = 0;
    if (*r1 > h)
        *r1 = h;
}

/* Two passes over every edge: count, then fill. */
static void cross_pass(const td_contain *ct, int w, int h, double scale,
                       xrow *xr, size_t *fill)
{
    size_t i, k;
    for (i = 0; i < ct->n; i++) {
        const td_line *r = &ct->rings->v[i];
        if (ct->parent[i] == -2 || r->n < 3)
            continue;
        for (k = 0; k < r->n; k++) {
            size_t k2 = (k + 1) % r->n;
            double a[2] = {r->xy[2 * k] / scale, r->xy[2 * k + 1] / scale};
            double b[2] = {r->xy[2 * k2] / scale, r->xy[2 * k2 + 1] / scale};
            long y, y0, y1;
            edge_rows(a, b, h, &y0, &y1);
            if (a[0] >= w - 0.5 && b[0] >= w - 0.5)
                continue; /* right of every cell centre: toggles nothing */
            for (y = y0; y < y1; y++) {
                double yc = y + 0.5, t = (yc - a[1]) / (b[1] - a[1]);
                if (!fill) {
                    xr->off[y + 1]++;
                    continue;
                }
                xr->c[fill[y]].x = a[0] + t * (b[0] - a[0]);
                xr->c[fill[y]++].ring = (int32_t)i;
            }
        }
    }
}

static int cmp_xing(const void *a, const void *b)
{
    double u = ((const xing *)a)->x, v = ((const xing *)b)->x;
    return (u > v) - (u < v);
}

/* One row: walk the cells, toggling ring membership at each crossing; the
 * label is the deepest ring the cell is inside (rings do not cross, so
 * the rings a cell is inside form one chain of parents). */
static void label_row(const td_contain *ct, const int *depth, char *in,
                      const xing *xc, size_t n, int w, int32_t *out)
{
    size_t k = 0, j;
    long cur = -1;
    int c;
    for (c = 0; c < w; c++) {
        size_t k0 = k;
        while (k < n && xc[k].x < c + 0.5)
            in[xc[k].ring] ^= 1, k++;
        if (k != k0) {
            while (cur >= 0 && !in[cur])
                cur = ct->parent[cur];
            for (j = k0; j < k; j++)
                if (in[xc[j].ring] &&
                    (cur < 0 || depth[xc[j].ring] > depth[cur]))
                    cur = xc[j].ring;
        }
        out[c] = (int32_t)cur;
    }
    for (j = 0; j < n; j++)
        in[xc[j].ring] = 0;
}

/* Sort the crossings of every row (those left of every cell centre need
 * no order) and label it; rows in parallel, each thread its own flags. */
static int label_rows(const td_contain *ct, const int *depth, xrow *xr,
                      int w, int h, int32_t *lab)
{
    int bad = 0;
#pragma omp parallel reduction(| : bad)
    {
        char *in = calloc(ct->n + 1, 1);
        long r;
        bad |= in == NULL;
#pragma omp for schedule(dynamic, 32)
        for (r = 0; r < h; r++) {
            size_t o = xr->off[r], n = xr->off[r + 1] - o, k, lo = 0;
            if (!in)
                continue;
            for (k = 0; k < n; k++)
                if (xr->c[o + k].x < 0.5) {
                    xing t = xr->c[o + k];
                    xr->c[o + k] = xr->c[o + lo];
                    xr->c[o + lo++] = t;
                }
            qsort(xr->c + o + lo, n - lo, sizeof *xr->c, cmp_xing);
            label_row(ct, depth, in, xr->c + o, n, w, lab + (size_t)r * w);
        }
        free(in);
    }
    return bad ? TD_ENOMEM : 0;
}

int hm_label(const td_contain *ct, int w, int h, double scale, int32_t *lab,
             td_ctx *cx)
{
    xrow xr = {NULL, NULL};
    size_t *fill = NULL, i, tot;
    int *depth = NULL, r, rc = TD_ENOMEM;
    if (!(xr.off = td_calloc((size_t)h + 1, sizeof *xr.off, cx)) ||
        !(fill = td_malloc(((size_t)h + 1) * sizeof *fill, cx)) ||
        !(depth = td_calloc(ct->n + 1, sizeof *depth, cx)))
        goto fail;
    for (i = 0; i < ct->n; i++) {
        long p = (long)i;
        while (p >= 0 && (p = ct->parent[p]) >= 0)
            depth[i]++;
    }
    cross_pass(ct, w, h, scale, &xr, NULL);
    for (r = 0; r < h; r++)
        xr.off[r + 1] += xr.off[r];
    tot = xr.off[h];
    if (!(xr.c = td_malloc((tot + 1) * sizeof *xr.c, cx)))
        goto fail;
    memcpy(fill, xr.off, ((size_t)h + 1) * sizeof *fill);
    cross_pass(ct, w, h, scale, &xr, fill);
    if ((rc = label_rows(ct, depth, &xr, w, h, lab)) != 0)
        td_seterr(cx, rc, "out of memory");
fail:
    free(xr.off);
    free(xr.c);
    free(fill);
    free(depth);
    return rc;
}
