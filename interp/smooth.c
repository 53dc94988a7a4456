#include "interp/smooth.h"

#include <math.h>

/* The band margin: a cell stays within [lo + M I, lo + (1 - M) I], so
 * float rounding never moves it into the next band. */
#define TD_SMOOTH_MARGIN 1e-3

/* One Gauss-Seidel sweep of row y (cells left and above already hold this
 * sweep's values). */
static void sweep_row(td_grid_f32 *g, const uint8_t *fixed, int y,
                      double base, double I)
{
    float *row = g->data + (size_t)y * g->stride, nd = g->nodata;
    const float *up = y > 0 ? row - g->stride : NULL;
    const float *dn = y + 1 < g->h ? row + g->stride : NULL;
    const uint8_t *fx = fixed + (size_t)y * (size_t)g->w;
    int x, w = g->w;
    for (x = 0; x < w; x++) {
        float nb[4];
        double s = 0, z, lo;
        int k, c = 0;
        if (fx[x] || row[x] == nd || row[x] != row[x])
            continue;
        nb[0] = x > 0 ? row[x - 1] : nd;
        nb[1] = x + 1 < w ? row[x + 1] : nd;
        nb[2] = up ? up[x] : nd;
        nb[3] = dn ? dn[x] : nd;
        for (k = 0; k < 4; k++)
            if (nb[k] != nd && nb[k] == nb[k]) {
                s += nb[k];
                c++;
            }
        if (c == 0)
            continue;
        lo = base + I * floor((row[x] - base) / I);
        z = s / c;
        z = fmax(z, lo + TD_SMOOTH_MARGIN * I);
        z = fmin(z, lo + (1 - TD_SMOOTH_MARGIN) * I);
        row[x] = (float)z;
    }
}

/* Contract in smooth.h. */
int td_smooth_bands(td_grid_f32 *g, const uint8_t *fixed, double base,
                    double interval, int iters, td_ctx *cx)
{
    int it, y, rc;
    if (!(interval > 0) || !isfinite(interval) || !isfinite(base) ||
        iters < 0 || !fixed || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "smooth: bad parameters (interval "
                         "%g, %d sweeps)", interval, iters);
    for (it = 0; it < iters; it++) {
        for (y = 0; y < g->h; y++)
            sweep_row(g, fixed, y, base, interval);
        if ((rc = td_progress(cx, "smooth", (double)(it + 1) / iters)) != 0)
            return rc;
    }
    return 0;
}
