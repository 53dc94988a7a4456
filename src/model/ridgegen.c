/* ridgegen.c: recursive ridge generation (paper 000 §2.4, Algorithm 2.5;
 * ALGORITHMS.md D1): from a few main ridges, rounds of
 *
 *   1. the DEM of all ridges so far at this round's slope (Algorithm 2.1);
 *   2. on a random side of every ridge segment, "water drops" every d
 *      cells along it; each runs down the DEM (steepest descent between
 *      the 8 neighbours) and its path becomes a new ridge, starting on the
 *      segment, with the DEM's heights along it;
 *
 * the slope rising and d falling from round to round.  The paper leaves
 * the numbers open: here the slope rises by p->slope_step degrees a round
 * (capped at 80), d shrinks by p->spacing_factor, a drop starts 2 cells off
 * the ridge, a path stops at a pit, a flat, the sheet's edge, the base
 * height or p->max_path cells, and one shorter than 2 d is dropped (it
 * would add nothing but noise).  The new ridges lie on the gentler
 * surface of their round; rendered with the next round's steeper slope
 * they stand out of it as spurs.  Every random number comes from p->seed. */
#include "src/model/model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DROP_OFFSET 2.0 /* cells beside the ridge where a drop starts */
#define PATH_STEP 4     /* cells between the vertices of a new ridge */

td_ridgegen_params td_ridgegen_defaults(void)
{
    td_ridgegen_params p;
    p.rounds = 2;
    p.seed = 1;
    p.spacing = 40.0;
    p.spacing_factor = 0.5;
    p.slope_step = 10.0;
    p.max_path = 400.0;
    return p;
}

static uint64_t next_rand(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
}

/* The DEM of segments v[0..n) (6 numbers each) at slope `slope`. */
static td_grid_f32 *dem_of(const double *v, size_t n, int w, int h,
                           const td_ridge_params *rp, double slope,
                           td_ctx *cx)
{
    td_ridge_params q = *rp;
    td_ridgemodel *m;
    td_grid_f32 *g = NULL;
    size_t i;
    q.slope = slope;
    if (!(m = td_ridgemodel_new(w, h, &q, cx)))
        return NULL;
    for (i = 0; i < n; i++)
        if (td_ridgemodel_add(m, v[6 * i], v[6 * i + 1], v[6 * i + 2],
                              v[6 * i + 3], v[6 * i + 4], v[6 * i + 5],
                              cx) < 0)
            goto done;
    if (td_ridgemodel_render(m, cx) == 0)
        g = td_ridgemodel_dem(m, cx);
done:
    td_ridgemodel_free(m);
    return g;
}

static int push(double **v, size_t *n, size_t *cap, const double s[6],
                td_ctx *cx)
{
    if (*n == *cap) {
        size_t nc = *cap ? 2 * *cap : 256;
        double *t = realloc(*v, nc * 6 * sizeof *t);
        if (!t)
            return td_seterr(cx, TD_ENOMEM, "ridgegen: out of memory");
        *v = t, *cap = nc;
    }
    memcpy(*v + 6 * *n, s, 6 * sizeof *s);
    (*n)++;
    return 0;
}

/* Steepest descent on g from cell (x, y) into path (cells, at most max
 * of them): returns how many. */
static size_t descend(const td_grid_f32 *g, int x, int y, double base,
                      int *path, size_t max)
{
    static const int dx[8] = {1, 1, 0, -1, -1, -1, 0, 1};
    static const int dy[8] = {0, -1, -1, -1, 0, 1, 1, 1};
    size_t n = 0;
    while (n < max) {
        double here = g->data[(size_t)y * g->w + x], best = 0;
        int k, bx = -1, by = -1;
        path[2 * n] = x, path[2 * n + 1] = y, n++;
        if (here <= base)
            break;
        for (k = 0; k < 8; k++) {
            int X = x + dx[k], Y = y + dy[k];
            double drop;
            if (X < 0 || Y < 0 || X >= g->w || Y >= g->h)
                continue;
            drop = (here - g->data[(size_t)Y * g->w + X]) /
                   (k & 1 ? M_SQRT2 : 1.0);
            if (drop > best)
                best = drop, bx = X, by = Y;
        }
        if (bx < 0)
            break; /* a pit or a flat */
        x = bx, y = by;
    }
    return n;
}

int td_ridgegen(double **segs, size_t *n, int w, int h,
                const td_ridge_params *rp, const td_ridgegen_params *p,
                double *final_slope, td_ctx *cx)
{
    size_t cap = *n, n0, i, maxp;
    uint64_t rs = p->seed;
    double d = p->spacing, slope = rp->slope;
    int *path = NULL, r, rc = 0;
    if (p->rounds < 0 || !(p->spacing >= 1) || !(p->spacing_factor > 0) ||
        !(p->spacing_factor <= 1) || !(p->slope_step >= 0) ||
        !(p->max_path >= 1) || p->max_path > 1e7)
        return td_seterr(cx, TD_EINVAL, "ridgegen: bad parameters (spacing "
                         ">= 1, factor in (0, 1], step >= 0)");
    maxp = (size_t)p->max_path + 1;
    if (!(path = malloc(2 * maxp * sizeof *path)))
        return td_seterr(cx, TD_ENOMEM, "ridgegen: out of memory");
    for (r = 0; r < p->rounds && rc == 0; r++) {
        td_grid_f32 *g = dem_of(*segs, *n, w, h, rp, slope, cx);
        if (!g) {
            rc = cx && cx->code ? cx->code : TD_ENOMEM;
            break;
        }
        n0 = *n;
        for (i = 0; i < n0 && rc == 0; i++) {
            double s[6], L, t; /* a copy: push() moves *segs */
            memcpy(s, *segs + 6 * i, sizeof s);
            L = hypot(s[3] - s[0], s[4] - s[1]);
            double side = (next_rand(&rs) & 1) ? 1.0 : -1.0;
            double nx, ny;
            if (!(L > 0))
                continue;
            nx = -(s[4] - s[1]) / L * side, ny = (s[3] - s[0]) / L * side;
            for (t = 0.5 * d; t < L && rc == 0; t += d) {
                double px = s[0] + (s[3] - s[0]) * t / L;
                double py = s[1] + (s[4] - s[1]) * t / L;
                double pz = s[2] + (s[5] - s[2]) * t / L;
                int x = (int)floor(px + nx * DROP_OFFSET);
                int y = (int)floor(py + ny * DROP_OFFSET);
                size_t m, k;
                double prev[3] = {px, py, pz};
                if (x < 0 || y < 0 || x >= w || y >= h)
                    continue;
                m = descend(g, x, y, rp->base, path, maxp);
                if ((double)m < 2 * d / 1.5 || m < 2 * PATH_STEP)
                    continue; /* too short to be a ridge */
                for (k = PATH_STEP; k < m && rc == 0; k += PATH_STEP) {
                    double q[6];
                    q[0] = prev[0], q[1] = prev[1], q[2] = prev[2];
                    q[3] = path[2 * k] + 0.5, q[4] = path[2 * k + 1] + 0.5;
                    q[5] = g->data[(size_t)path[2 * k + 1] * w + path[2 * k]];
                    if (q[5] > q[2])
                        q[5] = q[2]; /* a spur never rises */
                    rc = push(segs, n, &cap, q, cx);
                    prev[0] = q[3], prev[1] = q[4], prev[2] = q[5];
                }
            }
        }
        td_grid_f32_free(g);
        slope = fmin(slope + p->slope_step, 80.0);
        d = fmax(d * p->spacing_factor, 1.0);
    }
    free(path);
    if (final_slope)
        *final_slope = slope;
    return rc;
}
