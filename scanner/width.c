/* Ink width of traced lines (width.h).  At a sample point P with unit
 * normal n, the run is the ink on both sides of P along n:
 *
 *        paper . . . . . . .
 *        ink   ####^#######     run = a + b, stepped in 1/8 px, each
 *        ink   ####P#######     step read from the pixel it falls in
 *        ink   ####v#######
 *        paper . . . . . . .
 */
#include "width.h"

#include <math.h>
#include <stdlib.h>

#define W_STEP 2.0   /* px between samples along the line */
#define W_CHORD 3.0  /* px either side for the local direction */
#define W_END 4.0    /* px skipped at an open line's ends */
#define W_MAX 24.0   /* longer runs are not a line's width */
#define W_MIN_RUNS 5

/* The mask: bytes (a td_grid_u8) or bits (packed rows, bit c & 7 of byte
 * c >> 3 is column c). */
typedef struct wmask {
    int w, h;
    size_t stride;
    const uint8_t *bytes, *bits;
} wmask;

static int ink_at(const wmask *m, double x, double y)
{
    long c = (long)floor(x), r = (long)floor(y);
    if (c < 0 || r < 0 || c >= m->w || r >= m->h)
        return 0;
    if (m->bits)
        return m->bits[(size_t)r * m->stride + (size_t)(c >> 3)] >> (c & 7) & 1;
    return m->bytes[(size_t)r * m->stride + (size_t)c] != 0;
}

/* Distance from (x,y) along (dx,dy) to the first paper, at most W_MAX. */
static double run(const wmask *m, double x, double y, double dx,
                  double dy)
{
    double t;
    for (t = 0.0; t <= W_MAX; t += 0.125)
        if (!ink_at(m, x + t * dx, y + t * dy))
            return t;
    return W_MAX + 1.0;
}

/* Point at arc length s of l (cum: cumulative lengths, n + 1 entries). */
static void at(const td_line *l, const double *cum, double s, double *x,
               double *y)
{
    size_t n = l->n, lo = 0, hi = l->closed ? n : n - 1, k, k1;
    double t, len = cum[hi];
    if (l->closed)
        s = fmod(fmod(s, len) + len, len);
    s = s < 0 ? 0 : s > len ? len : s;
    while (hi - lo > 1) {
        size_t mid = (lo + hi) / 2;
        *(cum[mid] <= s ? &lo : &hi) = mid;
    }
    k = lo, k1 = (k + 1) % n;
    t = cum[k + 1] > cum[k] ? (s - cum[k]) / (cum[k + 1] - cum[k]) : 0;
    *x = l->xy[2 * k] + t * (l->xy[2 * k1] - l->xy[2 * k]);
    *y = l->xy[2 * k + 1] + t * (l->xy[2 * k1 + 1] - l->xy[2 * k + 1]);
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median run of one line, 0 when fewer than W_MIN_RUNS. */
static double line_width(const wmask *m, const td_line *l, double *cum,
                         double *runs, size_t maxruns)
{
    size_t n = l->n, k, nr = 0;
    double len, s, lo, hi, step;
    cum[0] = 0;
    for (k = 1; k <= n; k++) {
        size_t j = k % n;
        cum[k] = cum[k - 1];
        if (k < n || l->closed)
            cum[k] += hypot(l->xy[2 * j] - l->xy[2 * k - 2],
                            l->xy[2 * j + 1] - l->xy[2 * k - 1]);
    }
    len = cum[l->closed ? n : n - 1];
    lo = l->closed ? 0 : W_END, hi = l->closed ? len : len - W_END;
    step = fmax(W_STEP, (hi - lo) / (double)(maxruns - 1));
    for (s = lo; s <= hi && nr < maxruns; s += step) {
        double x, y, ax, ay, bx, by, dx, dy, d, r;
        at(l, cum, s, &x, &y);
        at(l, cum, s - W_CHORD, &ax, &ay);
        at(l, cum, s + W_CHORD, &bx, &by);
        dx = bx - ax, dy = by - ay, d = hypot(dx, dy);
        if (d < 1.0 || !ink_at(m, x, y))
            continue;
        r = run(m, x, y, -dy / d, dx / d) + run(m, x, y, dy / d, -dx / d);
        if (r <= W_MAX)
            runs[nr++] = r;
    }
    if (nr < W_MIN_RUNS)
        return 0.0;
    qsort(runs, nr, sizeof *runs, cmp_d);
    return nr % 2 ? runs[nr / 2] : 0.5 * (runs[nr / 2 - 1] + runs[nr / 2]);
}

static int widths(const wmask *mask, td_lines *ls, td_ctx *cx)
{
    size_t i, maxn = 1, maxruns = 4096;
    double *cum = NULL, *runs = NULL;
    int rc = TD_ENOMEM;
    for (i = 0; i < ls->n; i++)
        maxn = ls->v[i].n > maxn ? ls->v[i].n : maxn;
    if (!(cum = td_calloc(maxn + 1, sizeof *cum, cx)) ||
        !(runs = td_calloc(maxruns, sizeof *runs, cx)))
        goto fail;
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        l->width = l->n < 2 ? 0.0 : line_width(mask, l, cum, runs, maxruns);
    }
    rc = 0;
fail:
    free(cum);
    free(runs);
    return rc;
}

/* Contract in width.h. */
int td_line_widths(const td_grid_u8 *mask, td_lines *ls, td_ctx *cx)
{
    wmask m = {mask->w, mask->h, mask->stride, mask->data, NULL};
    return widths(&m, ls, cx);
}

/* Contract in width.h. */
uint8_t *td_width_pack(const td_grid_u8 *mask, td_ctx *cx)
{
    size_t bs = ((size_t)mask->w + 7) / 8, r, c;
    uint8_t *bits = td_calloc((size_t)mask->h * bs + 1, 1, cx);
    if (!bits)
        return NULL;
    for (r = 0; r < (size_t)mask->h; r++)
        for (c = 0; c < (size_t)mask->w; c++)
            if (mask->data[r * mask->stride + c])
                bits[r * bs + (c >> 3)] |= (uint8_t)(1u << (c & 7));
    return bits;
}

/* Contract in width.h. */
int td_line_widths_packed(const uint8_t *bits, int w, int h, td_lines *ls,
                          td_ctx *cx)
{
    wmask m = {w, h, ((size_t)w + 7) / 8, NULL, bits};
    return widths(&m, ls, cx);
}
