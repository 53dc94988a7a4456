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

int td_interp_parse_method(const char *s, td_interp_method *m, td_ctx *cx)
{
    if (!strcmp(s, "scanline"))
        *m = TD_INTERP_SCANLINE;
    else if (!strcmp(s, "multidir"))
        *m = TD_INTERP_MULTIDIR;
    else if (!strcmp(s, "homotopy"))
        *m = TD_INTERP_HOMOTOPY;
    else
        return td_seterr(cx, TD_EINVAL, "--method: '%s' is not one of "
                         "scanline, multidir, homotopy", s);
    return 0;
}

static int choose(const char *key, const char *val, const char *const *names,
                  int n, int *out, td_ctx *cx)
{
    int i;
    for (i = 0; i < n; i++)
        if (!strcmp(val, names[i])) {
            *out = i;
            return 0;
        }
    return td_seterr(cx, TD_EINVAL, "--%s: '%s' is not one of %s%s%s%s%s",
                     key, val, names[0], n > 1 ? ", " : "",
                     n > 1 ? names[1] : "", n > 2 ? ", " : "",
                     n > 2 ? names[2] : "");
}

static int number(const char *key, const char *val, double lo, double hi,
                  double *out, td_ctx *cx)
{
    char *end;
    double v = strtod(val, &end);
    if (end == val || *end || !isfinite(v) || v < lo || v > hi)
        return td_seterr(cx, TD_EINVAL, "--%s: '%s' is not a number %g..%g",
                         key, val, lo, hi);
    *out = v;
    return 0;
}

static int whole(const char *key, const char *val, int lo, int hi, int *out,
                 td_ctx *cx)
{
    double v = 0;
    int rc = number(key, val, lo, hi, &v, cx);
    if (rc == 0 && v != floor(v))
        rc = td_seterr(cx, TD_EINVAL, "--%s: '%s' is not a whole number",
                       key, val);
    if (rc == 0)
        *out = (int)v;
    return rc;
}

int td_interp_set(td_interp_params *p, const char *key, const char *val,
                  td_ctx *cx)
{
    static const char *const methods[] = {"scanline", "multidir",
                                          "homotopy"};
    static const char *const summit[] = {"flat", "extrapolate"};
    static const char *const pen[] = {"flat", "diagonal"};
    static const char *const weights[] = {"prod", "span", "span2"}; /* enum order */
    double v = 0;
    int i = 0, rc;
    if (!strcmp(key, "method")) {
        rc = choose(key, val, methods, 3, &i, cx);
        p->method = rc == 0 ? (td_interp_method)i : p->method;
    } else if (!strcmp(key, "summit")) {
        if ((rc = choose(key, val, summit, 2, &i, cx)) == 0)
            p->scanline.summit = p->multidir.summit = i;
    } else if (!strcmp(key, "peninsula")) {
        rc = choose(key, val, pen, 2, &i, cx);
        p->scanline.peninsula = rc == 0 ? i : p->scanline.peninsula;
    } else if (!strcmp(key, "weight")) {
        if ((rc = choose(key, val, weights, 3, &i, cx)) == 0)
            p->multidir.weight = (td_multidir_weight)i;
    } else if (!strcmp(key, "step")) {
        rc = whole(key, val, 1, 4096, &p->step, cx);
    } else if (!strcmp(key, "smooth")) {
        rc = whole(key, val, 0, 10000, &p->smooth, cx);
    } else if (!strcmp(key, "dirs")) {
        if ((rc = whole(key, val, 2, 4, &i, cx)) == 0 && i == 3)
            rc = td_seterr(cx, TD_EINVAL, "--dirs: 2 or 4");
        p->multidir.ndir = rc == 0 ? i : p->multidir.ndir;
    } else if (!strcmp(key, "fallback")) {
        if ((rc = choose(key, val, methods, 2, &i, cx)) == 0)
            p->homotopy.fallback = i == 1 ? TD_HM_FALLBACK_MULTIDIR
                                          : TD_HM_FALLBACK_SCANLINE;
    } else if (!strcmp(key, "epsilon")) {
        rc = number(key, val, 0, 180, &p->homotopy.epsilon, cx);
    } else if (!strcmp(key, "interval")) {
        rc = number(key, val, 1e-9, 1e9, &p->interval, cx);
    } else if (!strcmp(key, "nodata")) {
        if ((rc = number(key, val, -3e38, 3e38, &v, cx)) == 0)
            p->nodata = (float)v;
    } else
        return 1;
    return rc;
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
