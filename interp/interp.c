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

int td_interp_lines(const td_lines *ls, int w, int h,
                    const td_interp_params *p, td_grid_f32 **out,
                    td_ctx *cx)
{
    td_grid_f32 *g = NULL;
    uint8_t *fixed = NULL;
    double interval;
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
    if (p->smooth > 0 && interval < 1e30 &&
        !(fixed = line_mask(g, cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    if ((rc = fill(g, ls, w, h, p, interval, cx)) != 0)
        goto fail;
    if (fixed && (rc = td_smooth_bands(g, fixed, band_base(ls, interval),
                                       interval, p->smooth, cx)) != 0)
        goto fail;
    free(fixed);
    fixed = NULL;
    n = (size_t)g->w * g->h;
    for (i = 0; i < n; i++)
        if (g->data[i] != g->data[i])
            g->data[i] = p->nodata;
    g->nodata = p->nodata;
    g->has_nodata = 1;
    *out = g;
    return 0;
fail:
    free(fixed);
    td_grid_f32_free(g);
    return rc;
}
