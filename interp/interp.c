/* interp.c: the interpolation driver (interp/interp.h): options, then
 * rasterise -> fill by the chosen method -> smooth -> nodata. */
#include "interp/interp.h"

#include "interp/smooth.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

td_interp_params td_interp_defaults(void)
{
    td_interp_params p;
    memset(&p, 0, sizeof p);
    p.method = TD_INTERP_MULTIDIR;
    p.step = 1;
    p.nodata = -9999.0f;
    p.scanline = td_scanline_defaults();
    p.multidir = td_multidir_defaults();
    p.homotopy = td_homotopy_defaults();
    return p;
}

static int fill(td_grid_f32 *g, const td_lines *ls, int w, int h,
                const td_interp_params *p, double interval, td_ctx *cx)
{
    if (p->method == TD_INTERP_HOMOTOPY) {
        return td_homotopy_fill(g, ls, w, h, p->step < 1 ? 1 : p->step,
                                &p->homotopy, interval, p->scanline.summit,
                                p->scanline.peninsula, p->hstats, cx);
    } else if (p->method == TD_INTERP_SCANLINE) {
        td_scanline_params sp = p->scanline;
        sp.interval = interval;
        return td_scanline_fill(g, &sp, cx);
    } else {
        td_multidir_params mp = p->multidir;
        mp.interval = interval;
        return td_multidir_fill(g, &mp, cx);
    }
}

/* The rasterised line cells of g (1 byte per cell, rows of g->w). */
static uint8_t *line_mask(const td_grid_f32 *g, td_ctx *cx)
{
    uint8_t *m = td_malloc((size_t)g->w * (size_t)g->h, cx);
    int x, y;
    for (y = 0; m && y < g->h; y++)
        for (x = 0; x < g->w; x++)
            m[(size_t)y * g->w + x] = TD_AT(g, x, y) == TD_AT(g, x, y);
    return m;
}

/* The base the lines' heights are multiples of the interval from. */
static double band_base(const td_lines *ls, double interval)
{
    size_t i;
    for (i = 0; i < ls->n; i++)
        if (ls->v[i].has_height)
            return ls->v[i].height -
                   interval * floor(ls->v[i].height / interval);
    return 0;
}

/* td_interp_lines; with take set, *take (the same lines as ls) is freed
 * and set NULL as soon as the method needs them no more. */
static int interp_core(const td_lines *ls, td_lines **take, int w, int h,
                       const td_interp_params *p, td_grid_f32 **out,
                       td_ctx *cx)
{
    td_grid_f32 *g = NULL;
    uint8_t *fixed = NULL;
    double interval, base;
    size_t i, n;
    int rc, step = p->step < 1 ? 1 : p->step;
    *out = NULL;
    if ((rc = td_check_dims(w, h, "scan", cx)) != 0)
        return rc;
    if (!(g = td_grid_f32_new((w + step - 1) / step, (h + step - 1) / step,
                              cx)))
        return TD_ENOMEM;
    if ((rc = td_rasterise_lines(ls, step, g, cx)) != 0)
        goto fail;
    interval = p->interval > 0 ? p->interval : td_interp_interval(ls);
    if (interval <= 0)
        interval = 1e30; /* one height only: nothing to cap against */
    base = band_base(ls, interval);
    if (take && p->method != TD_INTERP_HOMOTOPY) { /* rasterised: done */
        td_lines_free(*take);
        *take = NULL;
        ls = NULL;
        td_trim_memory(); /* before the fill's own peak */
    }
    if (p->smooth > 0 && interval < 1e30 &&
        !(fixed = line_mask(g, cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if ((rc = fill(g, ls, w, h, p, interval, cx)) != 0)
        goto fail;
    if (take && *take) {
        td_lines_free(*take);
        *take = NULL;
    }
    if (fixed && (rc = td_smooth_bands(g, fixed, base, interval, p->smooth,
                                       cx)) != 0)
        goto fail;
    free(fixed);
    fixed = NULL;
    n = (size_t)g->w * g->h;
    {
        size_t none = 0;
#pragma omp parallel for schedule(static) reduction(+ : none)
        for (i = 0; i < n; i++)
            if (g->data[i] != g->data[i])
                g->data[i] = p->nodata, none++;
        if (p->undetermined)
            *p->undetermined = none;
    }
    g->nodata = p->nodata;
    g->has_nodata = 1;
    *out = g;
    return 0;
fail:
    free(fixed);
    td_grid_f32_free(g);
    return rc;
}

int td_interp_lines(const td_lines *ls, int w, int h,
                    const td_interp_params *p, td_grid_f32 **out,
                    td_ctx *cx)
{
    return interp_core(ls, NULL, w, h, p, out, cx);
}

/* Contract in interp.h. */
int td_interp_lines_take(td_lines **ls, int w, int h,
                         const td_interp_params *p, td_grid_f32 **out,
                         td_ctx *cx)
{
    return interp_core(*ls, ls, w, h, p, out, cx);
}

/* (x,y) in the band of width m around the w x h sheet. */
static int in_band(const double *q, double m, int w, int h)
{
    int out = q[0] >= -m && q[0] < w + m && q[1] >= -m && q[1] < h + m;
    return out && !(q[0] >= 0 && q[0] < w && q[1] >= 0 && q[1] < h);
}

/* The runs of l in the band of width m around the sheet, shifted by
 * (m, m), as open lines of ls; a run goes one point on where it leaves
 * the band outwards (the rasteriser clips), never into the sheet.  0 or
 * TD_ENOMEM. */
static int add_beside(td_lines *ls, const td_line *l, double m, int w,
                      int h, td_ctx *cx)
{
    size_t n = l->n + (l->closed && l->n > 2), k = 0, a, b, j;
    while (k < n) {
        const double *q;
        td_line *c;
        if (!in_band(&l->xy[2 * (k % l->n)], m, w, h)) {
            k++;
            continue;
        }
        for (b = k; b + 1 < n && in_band(&l->xy[2 * ((b + 1) % l->n)], m,
                                         w, h); b++)
            ;
        a = k;
        if (a > 0 && (q = &l->xy[2 * ((a - 1) % l->n)]) &&
            !(q[0] >= 0 && q[0] < w && q[1] >= 0 && q[1] < h))
            a--;
        j = b;
        if (b + 1 < n && (q = &l->xy[2 * ((b + 1) % l->n)]) &&
            !(q[0] >= 0 && q[0] < w && q[1] >= 0 && q[1] < h))
            b++;
        k = j + 1;
        if (!(c = td_lines_add(ls, cx)))
            return TD_ENOMEM;
        c->has_height = 1, c->height = l->height, c->width = l->width;
        for (j = a; j <= b; j++)
            if (td_line_push(c, l->xy[2 * (j % l->n)] + m,
                             l->xy[2 * (j % l->n) + 1] + m, cx) != 0)
                return TD_ENOMEM;
    }
    return 0;
}

int td_interp_lines_beside(const td_lines *ls, const td_lines *beside,
                           int margin, int w, int h,
                           const td_interp_params *p, td_grid_f32 **out,
                           td_ctx *cx)
{
    td_interp_params q = *p;
    td_lines *all = NULL;
    td_grid_f32 *big = NULL, *g = NULL;
    int rc, step = p->step < 1 ? 1 : p->step, m, y, gw, gh, mc;
    size_t i, k;
    *out = NULL;
    if (!beside || beside->n == 0 || margin <= 0)
        return td_interp_lines(ls, w, h, p, out, cx);
    if ((rc = td_check_dims(w, h, "scan", cx)) != 0)
        return rc;
    m = (margin + step - 1) / step * step;
    if (m > TD_MAX_DIM || w > TD_MAX_DIM - 2 * m || h > TD_MAX_DIM - 2 * m)
        return td_seterr(cx, TD_ETOOBIG, "the sheet with a margin of %d "
                         "px is too big", m);
    if (!(q.interval > 0))
        q.interval = td_interp_interval(ls);
    if (!(all = td_lines_new(cx)))
        return TD_ENOMEM;
    for (i = 0; i < ls->n; i++) {
        td_line *c;
        if ((rc = td_lines_append_copy(all, &ls->v[i], cx)) != 0)
            goto done;
        c = &all->v[all->n - 1];
        for (k = 0; k < c->n; k++)
            c->xy[2 * k] += m, c->xy[2 * k + 1] += m;
    }
    for (i = 0; i < beside->n; i++)
        if (beside->v[i].has_height && isfinite(beside->v[i].height) &&
            (rc = add_beside(all, &beside->v[i], m, w, h, cx)) != 0)
            goto done;
    if ((rc = td_interp_lines(all, w + 2 * m, h + 2 * m, &q, &big, cx)) != 0)
        goto done;
    gw = (w + step - 1) / step, gh = (h + step - 1) / step, mc = m / step;
    if (!(g = td_grid_f32_new(gw, gh, cx))) {
        rc = TD_ENOMEM;
        goto done;
    }
    for (y = 0; y < gh; y++)
        memcpy(&g->data[(size_t)y * g->stride],
               &big->data[(size_t)(y + mc) * big->stride + mc],
               (size_t)gw * sizeof *g->data);
    g->nodata = big->nodata, g->has_nodata = big->has_nodata;
    if (p->undetermined) { /* of the sheet, not of its margin */
        size_t none = 0, c;
        for (c = 0; c < (size_t)gw * gh; c++)
            none += g->data[c] == g->nodata;
        *p->undetermined = none;
    }
    *out = g;
done:
    td_grid_f32_free(big);
    td_lines_free(all);
    return rc;
}
