#include "interp/rasterise.h"

#include "interp/interp_int.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Clip the segment to the box [lo, hi] (Liang-Barsky); 0 when nothing of
 * it lies inside. */
static int clip(double *x0, double *y0, double *x1, double *y1, double xlo,
                double ylo, double xhi, double yhi)
{
    double t0 = 0, t1 = 1, dx = *x1 - *x0, dy = *y1 - *y0;
    double p[4] = {-dx, dx, -dy, dy};
    double q[4] = {*x0 - xlo, xhi - *x0, *y0 - ylo, yhi - *y0};
    int i;
    for (i = 0; i < 4; i++) {
        double t;
        if (p[i] == 0) {
            if (q[i] < 0)
                return 0;
            continue;
        }
        t = q[i] / p[i];
        if (p[i] < 0 && t > t0)
            t0 = t;
        if (p[i] > 0 && t < t1)
            t1 = t;
    }
    if (t0 > t1)
        return 0;
    *x1 = *x0 + t1 * dx;
    *y1 = *y0 + t1 * dy;
    *x0 += t0 * dx;
    *y0 += t0 * dy;
    return 1;
}

/* Exact grid traversal (Amanatides & Woo): every cell the segment passes
 * through, stepping in x or y one at a time, so the chain is 4-connected:
 *
 *     . . # #          # = cells drawn for the segment from the
 *     . # # .              lower left to the upper right
 *     # # . .
 */
static void draw_segment(td_grid_f32 *g, double x0, double y0, double x1,
                         double y1, float z, long r0, long r1)
{
    long ix, iy, ex, ey, sx, sy, steps;
    double dx, dy, tmx, tmy, tdx, tdy;
    if (!clip(&x0, &y0, &x1, &y1, -1, -1, g->w + 1.0, g->h + 1.0))
        return;
    ix = (long)floor(x0), iy = (long)floor(y0);
    ex = (long)floor(x1), ey = (long)floor(y1);
    dx = x1 - x0, dy = y1 - y0;
    sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
    tdx = dx != 0 ? 1.0 / fabs(dx) : INFINITY;
    tdy = dy != 0 ? 1.0 / fabs(dy) : INFINITY;
    tmx = dx != 0 ? (sx > 0 ? ix + 1 - x0 : x0 - ix) * tdx : INFINITY;
    tmy = dy != 0 ? (sy > 0 ? iy + 1 - y0 : y0 - iy) * tdy : INFINITY;
    steps = labs(ex - ix) + labs(ey - iy);
    for (;;) {
        if (ix >= 0 && iy >= r0 && ix < g->w && iy < r1)
            TD_AT(g, ix, iy) = z;
        if ((ix == ex && iy == ey) || steps-- <= 0)
            break;
        if (tmx < tmy) {
            ix += sx;
            tmx += tdx;
        } else {
            iy += sy;
            tmy += tdy;
        }
    }
}

static int check_line(const td_line *l, double step, int w, int h,
                      td_ctx *cx)
{
    size_t k, inside = 0;
    if (!l->has_height)
        return td_seterr(cx, TD_EINVAL, "line %ld has no height (run "
                         "topodig label first)", l->id);
    if (!isfinite(l->height))
        return td_seterr(cx, TD_EINVAL, "line %ld: height is not a finite "
                         "number", l->id);
    if (l->n == 0)
        return td_seterr(cx, TD_EINVAL, "line %ld has no points", l->id);
    for (k = 0; k < l->n; k++) {
        double x = l->xy[2 * k] / step, y = l->xy[2 * k + 1] / step;
        if (!isfinite(x) || !isfinite(y))
            return td_seterr(cx, TD_EINVAL, "line %ld: point %zu is not a "
                             "finite number", l->id, k);
        inside += x >= 0 && y >= 0 && x < w && y < h;
    }
    for (k = 0; k + 1 < l->n && inside == 0; k++) { /* a segment across */
        double x0 = l->xy[2 * k] / step, y0 = l->xy[2 * k + 1] / step;
        double x1 = l->xy[2 * k + 2] / step, y1 = l->xy[2 * k + 3] / step;
        inside += clip(&x0, &y0, &x1, &y1, 0, 0, w, h);
    }
    if (inside == 0)
        return td_seterr(cx, TD_EINVAL, "line %ld lies outside the %d x %d "
                         "grid (coordinates must be scan pixels, or map "
                         "units of the scan's georeferencing)", l->id, w, h);
    return 0;
}

/* The lines drawn in bands of rows on threads, each band all the lines
 * that reach it in line order: a cell gets the last line over it, as
 * from one pass (the band layout does not change a cell).  10000^2
 * benchmark sheet: the checks and the drawing 0.25 -> 0.13 s. */
int td_rasterise_lines(const td_lines *ls, double step, td_grid_f32 *g,
                       td_ctx *cx)
{
    size_t i, k, bad = SIZE_MAX;
    long y, *span = NULL;
    int nb, b;
#pragma omp parallel for schedule(static) private(k)
    for (y = 0; y < (long)g->h; y++) /* first touch: pages cleared on both */
        for (k = 0; k < (size_t)g->w; k++)
            g->data[(size_t)y * g->stride + k] = NAN;
    if (!ls || ls->n == 0)
        return td_seterr(cx, TD_EINVAL, "no contour lines to interpolate");
    if (!(step >= 1))
        return td_seterr(cx, TD_EINVAL, "step must be >= 1");
    if (!(span = td_malloc(2 * ls->n * sizeof *span, cx)))
        return TD_ENOMEM;
#pragma omp parallel for schedule(dynamic, 64) reduction(min : bad)
    for (i = 0; i < ls->n; i++) { /* checked; each line's rows */
        const td_line *l = &ls->v[i];
        double lo = INFINITY, hi = -INFINITY;
        size_t j;
        if (check_line(l, step, g->w, g->h, NULL) != 0) {
            bad = i < bad ? i : bad;
            continue;
        }
        for (j = 0; j < l->n; j++) {
            double v = l->xy[2 * j + 1] / step;
            lo = v < lo ? v : lo, hi = v > hi ? v : hi;
        }
        span[2 * i] = (long)floor(lo) - 1,
                 span[2 * i + 1] = (long)floor(hi) + 1;
    }
    if (bad != SIZE_MAX) { /* the first in order, with its message */
        int rc = check_line(&ls->v[bad], step, g->w, g->h, cx);
        free(span);
        return rc;
    }
    nb = omp_get_max_threads();
    nb = nb < 1 ? 1 : nb > 16 ? 16 : nb;
#pragma omp parallel for schedule(static)
    for (b = 0; b < nb; b++) {
        long r0 = (long)g->h * b / nb, r1 = (long)g->h * (b + 1) / nb;
        size_t q, j;
        for (q = 0; q < ls->n; q++) {
            const td_line *l = &ls->v[q];
            const double *p = l->xy;
            float z = (float)l->height;
            if (span[2 * q + 1] < r0 || span[2 * q] >= r1)
                continue;
            if (l->n == 1)
                draw_segment(g, p[0] / step, p[1] / step, p[0] / step,
                             p[1] / step, z, r0, r1);
            for (j = 0; j + 1 < l->n; j++)
                draw_segment(g, p[2 * j] / step, p[2 * j + 1] / step,
                             p[2 * j + 2] / step, p[2 * j + 3] / step, z, r0,
                             r1);
            if (l->closed && l->n > 2)
                draw_segment(g, p[2 * l->n - 2] / step, p[2 * l->n - 1] / step,
                             p[0] / step, p[1] / step, z, r0, r1);
        }
    }
    free(span);
    return 0;
}

double td_interp_interval(const td_lines *ls)
{
    double *z, best = 0;
    size_t i, n = 0;
    if (!ls || ls->n == 0 || !(z = malloc(ls->n * sizeof *z)))
        return 0;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].has_height && isfinite(ls->v[i].height))
            z[n++] = ls->v[i].height;
    qsort(z, n, sizeof *z, td_cmp_double);
    for (i = 1; i < n; i++) {
        double d = z[i] - z[i - 1];
        if (d > 1e-6 * fmax(1.0, fabs(z[i])) && (best == 0 || d < best))
            best = d;
    }
    free(z);
    return best;
}

static void span_geometry(int dir, int w, td_span *s)
{
    static const int dc[4] = {1, 0, 1, -1}, dr[4] = {0, 1, 1, 1};
    s->dc = dc[dir];
    s->dr = dr[dir];
    s->di = (ptrdiff_t)dr[dir] * (ptrdiff_t)w + dc[dir];
    s->sl = dir >= TD_DIR_DIAG ? sqrt(2.0) : 1.0;
}

/* Scan lines are indexed so that walking rows top to bottom meets every
 * line's cells in order:
 *     x: line = row        y: line = column
 *     diag (down-right): line = col - row + h - 1
 *     anti (down-left):  line = col + row
 * last[line] keeps the position (row; column for x) of the last anchor.
 * For y and the diagonals the grid is walked in vertical strips of
 * WALK_STRIP columns, each from the top row to the bottom (strips left to
 * right; right to left for anti), which still meets every line's cells in
 * order but keeps the rows a span reaches back into in cache. */
#define WALK_STRIP 256

static void walk_strip(const td_grid_f32 *g, int dir, int c0, int c1,
                       int *last, td_span *s, td_span_fn fn, void *user,
                       int r)
{
    const float *row = g->data + (size_t)r * g->stride;
    int c;
    for (c = c0; c < c1; c++) {
        size_t id;
        int p;
        if (row[c] != row[c])
            continue;
        id = dir == TD_DIR_X ? 0 : dir == TD_DIR_Y ? (size_t)c
             : dir == TD_DIR_DIAG ? (size_t)(c - r + g->h - 1) : (size_t)(c + r);
        p = last[id];
        last[id] = dir == TD_DIR_X ? c : r;
        if (p < 0 || (s->n = dir == TD_DIR_X ? c - p : r - p) < 2)
            continue;
        s->ra = dir == TD_DIR_X ? r : p;
        s->ca = c - s->n * s->dc;
        s->ia = (size_t)s->ra * g->stride + (size_t)s->ca;
        s->za = g->data[s->ia];
        s->zb = row[c];
        fn(s, user);
    }
}

int td_interp_walk(const td_grid_f32 *g, int dir, td_span_fn fn, void *user,
                   const char *stage, td_ctx *cx)
{
    int w = g->w, h = g->h, r, si, rc = 0;
    int strip = dir == TD_DIR_X ? w : WALK_STRIP;
    int ns = (w + strip - 1) / strip;
    size_t nl = dir == TD_DIR_X ? 1 : dir == TD_DIR_Y ? (size_t)w
                                                        : (size_t)w + h - 1;
    int *last = td_malloc(nl * sizeof *last, cx);
    td_span s;
    if (!last)
        return TD_ENOMEM;
    memset(last, 0xff, nl * sizeof *last); /* -1 */
    memset(&s, 0, sizeof s);
    span_geometry(dir, (int)g->stride, &s);
    for (si = 0; si < ns && rc == 0; si++) {
        int k = dir == TD_DIR_ANTI ? ns - 1 - si : si;
        int c0 = k * strip, c1 = c0 + strip < w ? c0 + strip : w;
        for (r = 0; r < h && rc == 0; r++) {
            if (dir == TD_DIR_X)
                last[0] = -1;
            walk_strip(g, dir, c0, c1, last, &s, fn, user, r);
            if (stage && (r & 1023) == 1023)
                rc = td_progress(cx, stage, ((double)si * h + r) / ((double)ns * h));
        }
    }
    free(last);
    return rc;
}

/* Hand fn the x span of the NaN run [c0, c1) of row r, when a
 * determined cell lies at both ends. */
static void gap_x(const td_grid_f32 *g, int r, int c0, int c1, td_span *s,
                  td_span_fn fn, void *user)
{
    const float *row = g->data + (size_t)r * g->stride;
    if (c0 < 1 || c1 >= g->w)
        return;
    s->ca = c0 - 1;
    s->ra = r;
    s->n = c1 - c0 + 1;
    s->ia = (size_t)r * g->stride + (size_t)(c0 - 1);
    s->za = row[c0 - 1];
    s->zb = row[c1];
    fn(s, user);
}

/* Gaps along x: from each undetermined cell after a determined one,
 * along the row to the next determined cell. */
static void gaps_x(const td_grid_f32 *g, int r, td_span *s, td_span_fn fn,
                   void *user)
{
    const float *row = g->data + (size_t)r * g->stride;
    int w = g->w, c, e;
    for (c = td_row_find(row, 1, w, 1); c < w;
         c = td_row_find(row, c + 1, w, 1)) {
        if (row[c - 1] != row[c - 1])
            continue;
        if ((e = td_row_find(row, c + 1, w, 0)) >= w)
            break;
        gap_x(g, r, c, e, s, fn, user);
    }
}

/* Gaps along a direction that crosses rows, found row by row from the
 * undetermined cells and their neighbours on the line in the rows above
 * and below (no walk down a column): a run opens where the cell before is
 * determined (open[line] = that cell's row; -1 at the grid edge) and is
 * handed to fn where the cell after is determined.  This is the step for
 * the undetermined cell (c, r); base = line - c. */
static void gap_cross(const td_grid_f32 *g, int r, int c, int *open,
                      size_t base, td_span *s, td_span_fn fn, void *user)
{
    int *op = &open[(size_t)c + base], pc = c - s->dc, nc = c + s->dc;
    if (r == 0 || pc < 0 || pc >= g->w)
        *op = -1;
    else if (TD_AT(g, pc, r - 1) == TD_AT(g, pc, r - 1))
        *op = r - 1;
    if (r + 1 >= g->h || nc < 0 || nc >= g->w || *op < 0 ||
        TD_AT(g, nc, r + 1) != TD_AT(g, nc, r + 1))
        return;
    s->ra = *op;
    s->n = r + 1 - *op;
    s->ca = nc - s->n * s->dc;
    s->ia = (size_t)s->ra * g->stride + (size_t)s->ca;
    s->za = g->data[s->ia];
    s->zb = TD_AT(g, nc, r + 1);
    fn(s, user);
}

static size_t cross_base(const td_grid_f32 *g, const td_span *s, int r)
{
    return s->dc == 0 ? 0 : s->dc > 0 ? (size_t)(g->h - 1 - r) : (size_t)r;
}

/* Gaps along dir, row by row: x runs from the row's scan, the other
 * directions from the undetermined cells and the rows above and below. */
int td_interp_walk_gaps(const td_grid_f32 *g, int dir, td_span_fn fn,
                        void *user, const char *stage, td_ctx *cx)
{
    int h = g->h, r, c, e, rc = 0;
    int *open = NULL;
    td_span s;
    memset(&s, 0, sizeof s);
    span_geometry(dir, (int)g->stride, &s);
    if (dir != TD_DIR_X &&
        !(open = td_malloc(((size_t)g->w + h - 1) * sizeof *open, cx)))
        return TD_ENOMEM;
    for (r = 0; r < h && rc == 0; r++) {
        const float *row = g->data + (size_t)r * g->stride;
        size_t base = cross_base(g, &s, r);
        if (dir == TD_DIR_X)
            gaps_x(g, r, &s, fn, user);
        else
            for (c = td_row_find(row, 0, g->w, 1); c < g->w;
                 c = td_row_find(row, e, g->w, 1))
                for (e = td_row_find(row, c + 1, g->w, 0); c < e; c++)
                    gap_cross(g, r, c, open, base, &s, fn, user);
        if (stage && (r & 1023) == 1023)
            rc = td_progress(cx, stage, (double)r / h);
    }
    free(open);
    return rc;
}

int td_nan_runs_find(const td_grid_f32 *g, td_nan_runs *nr, td_ctx *cx)
{
    int r, c, e;
    if (!(nr->off = td_malloc(((size_t)g->h + 1) * sizeof *nr->off, cx)))
        return TD_ENOMEM;
    nr->off[0] = 0;
    for (r = 0; r < g->h; r++) {
        const float *row = g->data + (size_t)r * g->stride;
        for (c = td_row_find(row, 0, g->w, 1); c < g->w;
             c = td_row_find(row, e, g->w, 1)) {
            e = td_row_find(row, c + 1, g->w, 0);
            if (nr->n == nr->cap) {
                size_t cap = nr->cap + nr->cap / 2 + 1024;
                void *v = cap < SIZE_MAX / sizeof *nr->run
                              ? realloc(nr->run, cap * sizeof *nr->run)
                              : NULL;
                if (!v)
                    return td_seterr(cx, TD_ENOMEM, "out of memory");
                nr->run = v;
                nr->cap = cap;
            }
            nr->run[nr->n][0] = c;
            nr->run[nr->n++][1] = e;
        }
        nr->off[r + 1] = nr->n;
    }
    return 0;
}

void td_nan_runs_free(td_nan_runs *nr)
{
    free(nr->off);
    free(nr->run);
    memset(nr, 0, sizeof *nr);
}

int td_interp_slope(const td_grid_f32 *g, const td_span *s, int end,
                    int kmax, double *slope)
{
    int ox = end ? s->dc : -s->dc, oy = end ? s->dr : -s->dr;
    int ax = s->ca + (end ? s->n * s->dc : 0);
    int ay = s->ra + (end ? s->n * s->dr : 0);
    int k, best = 0;
    float z0 = TD_AT(g, ax, ay), zb = 0;
    for (k = 1; k <= kmax; k++) {
        int x = ax + k * ox, y = ay + k * oy;
        float v;
        if (x < 0 || y < 0 || x >= g->w || y >= g->h)
            break;
        v = TD_AT(g, x, y);
        if (v != v)
            break;
        best = k;
        zb = v;
    }
    if (best == 0)
        return -1;
    *slope = ((double)z0 - zb) / (best * s->sl);
    return 0;
}

double td_interp_tent(double z, double s1, double s2, double d1, double d2,
                      double interval)
{
    double v, u;
    interval *= 0.99; /* never reach the next contour's height */
    /* comparisons, not fmin (a library call, 70 million of them on a
       10000^2 sheet): no operand is NaN past the sign tests */
    if (s1 > 0 && s2 > 0) {
        v = s1 * d1, u = s2 * d2;
        v = u < v ? u : v;
        return z + (interval < v ? interval : v);
    }
    if (s1 < 0 && s2 < 0) {
        v = -s1 * d1, u = -s2 * d2;
        v = u < v ? u : v;
        return z - (interval < v ? interval : v);
    }
    return z;
}
