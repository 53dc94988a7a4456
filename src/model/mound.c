/* mound.c: the paper's initial terrain, a central mound with white
 * noise (Fujita, Muraoka, Chiba §3, Fig. 2a).
 *
 *   height
 *     |        ___
 *     |     .-'   '-.          h(r) = H (1 - (r/R)^2)^2, r < R
 *     |   .'         '.              + U(-a, a) H   (white noise)
 *     |__/_____________\__ r
 *           centre
 */
#include "src/model/model.h"

#include <math.h>

td_mound_params td_mound_defaults(void)
{
    td_mound_params p;
    p.w = p.h = 512;
    p.height = 512.0 / 8.0;
    p.radius = 0.9;
    p.noise = 0.02;
    p.seed = 1;
    return p;
}

/* splitmix64: a small, well-mixed generator with a 64-bit state. */
static uint64_t mix_next(uint64_t *st)
{
    uint64_t z = (*st += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Uniform in [-1, 1). */
static double mix_uniform(uint64_t *st)
{
    return (double)(mix_next(st) >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

int td_terrain_noise(td_grid_f32 *g, double amp, uint64_t seed, td_ctx *cx)
{
    uint64_t st = seed;
    size_t x, y;
    if (!g || !g->data || !(amp >= 0) || !isfinite(amp))
        return td_seterr(cx, TD_EINVAL, "noise: bad grid or amplitude");
    if (amp == 0)
        return 0;
    for (y = 0; y < (size_t)g->h; y++)
        for (x = 0; x < (size_t)g->w; x++) {
            float *v = &g->data[y * g->stride + x];
            double r = mix_uniform(&st); /* drawn for every cell: stable */
            if (!isfinite(*v) || (g->has_nodata && *v == g->nodata))
                continue;
            *v = (float)(*v + amp * r);
        }
    return 0;
}

int td_terrain_mound(td_grid_f32 *g, const td_mound_params *p, td_ctx *cx)
{
    double cxm, cym, R;
    size_t x, y;
    if (!g || !g->data || !p || !(p->height >= 0) || !isfinite(p->height) ||
        !(p->radius > 0) || !isfinite(p->radius) || !(p->noise >= 0) ||
        !isfinite(p->noise))
        return td_seterr(cx, TD_EINVAL, "mound: bad grid or parameters "
                         "(height >= 0, radius > 0, noise >= 0)");
    cxm = 0.5 * (g->w - 1);
    cym = 0.5 * (g->h - 1);
    R = p->radius * 0.5 * (g->w < g->h ? g->w : g->h);
    g->has_nodata = 0;
    g->nodata = -9999.0f;
    for (y = 0; y < (size_t)g->h; y++)
        for (x = 0; x < (size_t)g->w; x++) {
            double dx = (x - cxm) / R, dy = (y - cym) / R;
            double r2 = dx * dx + dy * dy, u = r2 < 1 ? 1 - r2 : 0;
            g->data[y * g->stride + x] = (float)(p->height * u * u);
        }
    return td_terrain_noise(g, p->noise * p->height, p->seed, cx);
}
