/* Short traced lines printed in another ink: foreign.h. */
#include "scanner/foreign.h"

#include "scanner/flank.h"

#include <stdlib.h>
#include <string.h>

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The darkest pixel (least sum of its channels) of the 3 x 3 about (x,
 * y), or NULL off the image's inside. */
static const uint8_t *core_px(const td_image *im, double x, double y)
{
    int X = (int)(x + 0.5), Y = (int)(y + 0.5), dx, dy, best = 1 << 30;
    const uint8_t *c = NULL;
    if (X < 1 || Y < 1 || X >= im->w - 1 || Y >= im->h - 1)
        return NULL;
    for (dy = -1; dy <= 1; dy++)
        for (dx = -1; dx <= 1; dx++) {
            const uint8_t *p =
                im->data + (size_t)(Y + dy) * im->stride + 3 * (size_t)(X + dx);
            int s = p[0] + p[1] + p[2];
            if (s < best)
                best = s, c = p;
        }
    return c;
}

/* td_foreign_residual; r: room for l->n residuals. */
static double residual(const td_image *im, const td_palette *pal,
                       const td_line *l, double *r)
{
    size_t k, n = 0;
    for (k = 0; k < l->n; k++) {
        const uint8_t *c = core_px(im, l->xy[2 * k], l->xy[2 * k + 1]);
        if (c)
            r[n++] = td_palette_contour_residual(pal, c[0], c[1], c[2]);
    }
    if (n == 0)
        return -1.0;
    qsort(r, n, sizeof *r, cmp_d);
    return r[n / 2];
}

/* Contract in foreign.h. */
double td_foreign_residual(const td_image *im, const td_palette *pal,
                           const td_line *l)
{
    double *r = malloc((l->n + 1) * sizeof *r), v;
    if (!r)
        return -1.0;
    v = residual(im, pal, l, r);
    free(r);
    return v;
}

/* Whether line l crosses the other inks: within TD_FLANK_NEAR px of their
 * strokes at some of its vertices, fewer than half (a line near them
 * all along is a road's flank, not a contour across it). */
static int near_other(const td_line *l, const uint8_t *other, int w, int h)
{
    size_t k, m = 0;
    for (k = 0; other && k < l->n; k++)
        m += td_flank_near(other, w, h, l->xy[2 * k], l->xy[2 * k + 1]) != 0;
    return m > 0 && 2 * m < l->n;
}

/* Contract in foreign.h. */
long td_foreign_cut(td_lines *ls, const td_image *im, const td_palette *pal,
                    const uint8_t *other, td_ctx *cx)
{
    uint8_t *drop;
    long n = (long)ls->n, i, nd = 0;
    int fail = 0;
    if (!pal || pal->n == 0 || pal->chosen < 0 || im->channels != 3 || n == 0)
        return 0;
    if (!(drop = td_calloc((size_t)n + 1, 1, cx)))
        return TD_ENOMEM;
#pragma omp parallel reduction(| : fail)
    {
        size_t cap = 0;
        double *r = NULL;
#pragma omp for schedule(dynamic, 16)
        for (i = 0; i < n; i++) {
            const td_line *l = &ls->v[i];
            if (fail || l->n < 2 || td_line_length(l) >= TD_FOREIGN_LEN)
                continue;
            if (l->n > cap) {
                double *t = realloc(r, l->n * sizeof *r);
                if (!t) {
                    fail = 1;
                    continue;
                }
                r = t, cap = l->n;
            }
            drop[i] = residual(im, pal, l, r) >= TD_FOREIGN_RES &&
                      !near_other(l, other, im->w, im->h);
        }
        free(r);
    }
    if (fail) {
        free(drop);
        return td_seterr(cx, TD_ENOMEM, "foreign: out of memory");
    }
    { /* one pass, not a removal each: thousands on a big sheet */
        size_t m = 0;
        for (i = 0; i < n; i++)
            if (drop[i]) {
                free(ls->v[i].xy);
                nd++;
            } else {
                ls->v[m++] = ls->v[i];
            }
        ls->n = m;
    }
    free(drop);
    return nd;
}
