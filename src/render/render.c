#include "src/render/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

td_render_params td_render_defaults(void)
{
    td_render_params p;
    p.style = TD_RENDER_HILLSHADE;
    p.azimuth = 315;
    p.altitude = 45;
    p.zfactor = 0; /* auto */
    p.cellsize = 1;
    p.interval = 0;
    p.base = 0;
    return p;
}

static int valid(const td_grid_f32 *g, float v)
{
    return isfinite(v) && !(g->has_nodata && v == g->nodata);
}

/* Height at (x,y) clamped to the grid; the centre's height when nodata. */
static double zat(const td_grid_f32 *g, int x, int y, double zc)
{
    float v;
    x = x < 0 ? 0 : x >= g->w ? g->w - 1 : x;
    y = y < 0 ? 0 : y >= g->h ? g->h - 1 : y;
    v = TD_AT(g, x, y);
    return valid(g, v) ? v : zc;
}

/* Horn's gradient at (x,y) (see render.h). */
static void horn(const td_grid_f32 *g, int x, int y, double cellsize,
                 double *dx, double *dy)
{
    double zc = TD_AT(g, x, y), n[9];
    int i;
    for (i = 0; i < 9; i++)
        n[i] = zat(g, x + i % 3 - 1, y + i / 3 - 1, zc);
    *dx = ((n[2] + 2 * n[5] + n[8]) - (n[0] + 2 * n[3] + n[6])) /
          (8 * cellsize);
    *dy = ((n[6] + 2 * n[7] + n[8]) - (n[0] + 2 * n[1] + n[2])) /
          (8 * cellsize);
}

/* See render.h: the z factor that draws the 90th percentile of the
 * nonzero slopes at 45 degrees, from about 65536 cells on a regular
 * lattice; 1 when nothing slopes. */
double td_render_auto_zfactor(const td_grid_f32 *dem, double cellsize)
{
    enum { NS = 65536 };
    double *v = malloc(NS * sizeof *v), dx, dy, z = 1;
    int step = 1, x, y;
    size_t n = 0;
    if (!v)
        return 1;
    while ((double)(dem->w / step) * (dem->h / step) > NS)
        step++;
    for (y = step / 2; y < dem->h; y += step)
        for (x = step / 2; x < dem->w && n < NS; x += step) {
            if (!valid(dem, TD_AT(dem, x, y)))
                continue;
            horn(dem, x, y, cellsize, &dx, &dy);
            if (hypot(dx, dy) > 0)
                v[n++] = hypot(dx, dy);
        }
    if (n > 0) {
        qsort(v, n, sizeof *v, td_cmp_double);
        z = 1.0 / v[(size_t)(0.9 * (double)(n - 1))];
    }
    free(v);
    return isfinite(z) && z > 0 ? z : 1;
}

static double shade(const td_grid_f32 *g, int x, int y,
                    const td_render_params *p)
{
    double dx, dy, slope, aspect, zen, az;
    horn(g, x, y, p->cellsize, &dx, &dy);
    slope = atan(p->zfactor * hypot(dx, dy));
    aspect = atan2(dy, -dx);
    zen = (90 - p->altitude) * M_PI / 180;
    az = (360 - p->azimuth + 90) * M_PI / 180;
    return fmax(0, cos(zen) * cos(slope) +
                   sin(zen) * sin(slope) * cos(az - aspect));
}

/* See render.h. */
void td_render_ramp(double t, double rgb[3])
{
    static const double stop[4][3] = {
        {0.35, 0.60, 0.35}, {0.90, 0.85, 0.50}, {0.65, 0.45, 0.30},
        {0.97, 0.97, 0.97}};
    double u = fmin(fmax(t, 0), 1) * 3;
    int i = u >= 3 ? 2 : (int)u, k;
    for (k = 0; k < 3; k++)
        rgb[k] = stop[i][k] + (stop[i + 1][k] - stop[i][k]) * (u - i);
}

static int contour_edge(const td_grid_f32 *g, int x, int y,
                        const td_render_params *p)
{
    double b = floor((TD_AT(g, x, y) - p->base) / p->interval);
    if (x + 1 < g->w && valid(g, TD_AT(g, x + 1, y)) &&
        floor((TD_AT(g, x + 1, y) - p->base) / p->interval) != b)
        return 1;
    return y + 1 < g->h && valid(g, TD_AT(g, x, y + 1)) &&
           floor((TD_AT(g, x, y + 1) - p->base) / p->interval) != b;
}

static void range(const td_grid_f32 *g, double *lo, double *hi)
{
    int x, y;
    *lo = INFINITY;
    *hi = -INFINITY;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            if (valid(g, TD_AT(g, x, y))) {
                *lo = fmin(*lo, TD_AT(g, x, y));
                *hi = fmax(*hi, TD_AT(g, x, y));
            }
}

int td_render_hillshade(const td_grid_f32 *dem, const td_render_params *p,
                        td_image **out, td_ctx *cx)
{
    td_image *im;
    td_render_params q = *p;
    double lo, hi;
    int x, y, k;
    *out = NULL;
    if (!(p->cellsize > 0) || !(p->zfactor >= 0) || !(p->interval >= 0) ||
        !(p->altitude >= 0 && p->altitude <= 90))
        return td_seterr(cx, TD_EINVAL, "render: cell size must be > 0, "
                         "z factor >= 0, altitude 0..90, interval >= 0");
    if (q.zfactor == 0)
        q.zfactor = td_render_auto_zfactor(dem, q.cellsize);
    p = &q;
    if (!(im = td_image_new(dem->w, dem->h, 3, cx)))
        return TD_ENOMEM;
    range(dem, &lo, &hi);
    for (y = 0; y < dem->h; y++) {
        uint8_t *px = im->data + (size_t)y * im->stride;
        for (x = 0; x < dem->w; x++, px += 3) {
            double s, c[3] = {1, 1, 1};
            if (!valid(dem, TD_AT(dem, x, y))) {
                px[0] = 205, px[1] = 215, px[2] = 225;
                continue;
            }
            if (p->interval > 0 && contour_edge(dem, x, y, p)) {
                px[0] = 140, px[1] = 70, px[2] = 20;
                continue;
            }
            s = shade(dem, x, y, p);
            if (p->style == TD_RENDER_TINT)
                td_render_ramp(hi > lo ? (TD_AT(dem, x, y) - lo) / (hi - lo) : 0, c);
            for (k = 0; k < 3; k++)
                px[k] = (uint8_t)lround(255 * c[k] *
                                        (p->style == TD_RENDER_TINT ? 0.35 + 0.65 * s : s));
        }
    }
    *out = im;
    return 0;
}
