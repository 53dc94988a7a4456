/* test_homotopy.c: ridge and valley lines from contour curvature and the
 * homotopy interpolation (interp/homotopy.h: orient.c, spline.c,
 * curvature.c, ridgelink.c, ridges.c, homotopy.c) on analytic surfaces
 * with a known thalweg / crest: a V-shaped valley, a ridge, a spur
 * joining a main ridge; orientation; curvature of a circle; the DEM
 * against the truth and against the scanline method. */
#define _POSIX_C_SOURCE 200809L
#include "tt.h"

#include "compare.h"
#include "../interp/homotopy.h"
#include "../interp/rasterise.h"
#include "../samples/gen/gen.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { W = 300, H = 300 };
#define X0 150.3 /* thalweg / crest column */

enum { S_VALLEY, S_RIDGE, S_SPUR };

/* Distance from (x,y) to the ray from (ox,oy) along unit (dx,dy). */
static double ray_dist(double x, double y, double ox, double oy, double dx,
                       double dy)
{
    double t = (x - ox) * dx + (y - oy) * dy;
    t = t < 0 ? 0 : t;
    return hypot(x - ox - t * dx, y - oy - t * dy);
}

/* Analytic surfaces, heights in m, x,y in px (y down the sheet).
 *   valley: z = 150 + 0.4 sqrt((x-X0)^2 + 100) - 0.5 y   thalweg x = X0
 *   ridge:  z = 300 - 0.4 sqrt((x-X0)^2 + 100) - 0.5 y   crest   x = X0
 *   spur:   the ridge, and a second crest from (X0, 80) down towards
 *           the lower right at 45 degrees, joined by a smooth maximum */
static double surface(int kind, double x, double y)
{
    double r1 = -0.4 * sqrt((x - X0) * (x - X0) + 100), r2, k = 8;
    switch (kind) {
    case S_VALLEY: return 150 - r1 - 0.5 * y;
    case S_RIDGE: return 300 + r1 - 0.5 * y;
    default:
        r2 = -0.4 * sqrt(pow(ray_dist(x, y, X0, 80, M_SQRT1_2, M_SQRT1_2), 2) +
                         100);
        return 300 - 0.5 * y + k * log(exp(r1 / k) + exp(r2 / k));
    }
}

static td_grid_f32 *truth(int kind)
{
    td_grid_f32 *g = td_grid_f32_new(W, H, NULL);
    int x, y;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            TD_AT(g, x, y) = (float)surface(kind, x + 0.5, y + 0.5);
    return g;
}

static td_lines *contours(const td_grid_f32 *g, double interval)
{
    td_lines *ls = NULL;
    if (td_gen_contours(g, 0, interval, &ls, NULL) != 0)
        return NULL;
    return ls;
}

/* Largest |x - X0| over the points of one kind with y in [y0, y1], and how
 * many there are. */
static double worst_dx(const td_ridges *r, int kind, double y0, double y1,
                       size_t *n)
{
    double worst = 0;
    size_t i;
    *n = 0;
    for (i = 0; i < r->npt; i++) {
        const td_rv_point *q = &r->pt[i];
        if (q->kind != kind || q->y < y0 || q->y > y1)
            continue;
        if (fabs(q->x - X0) > 60) /* far from the line: other features */
            continue;
        (*n)++;
        worst = fmax(worst, fabs(q->x - X0));
    }
    return worst;
}

/* Contour levels (interval iv) crossing the line x = X0 for y in [y0, y1]:
 * how many points of the line's kind a perfect detector finds. */
static size_t levels_on_line(int kind, double iv, double y0, double y1)
{
    double a = surface(kind, X0, y0), b = surface(kind, X0, y1);
    return (size_t)(floor(fmax(a, b) / iv) - floor(fmin(a, b) / iv));
}

static void test_valley_line(void)
{
    td_grid_f32 *g = truth(S_VALLEY);
    td_lines *ls = contours(g, 5);
    td_homotopy_params p = td_homotopy_defaults();
    td_ridges *r = NULL;
    size_t n, nr;
    double d;
    TT_CHECK(ls && ls->n > 20);
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, NULL) == 0);
    if (!r)
        goto done;
    d = worst_dx(r, TD_RV_VALLEY, 20, H - 20, &n);
    worst_dx(r, TD_RV_RIDGE, 20, H - 20, &nr);
    TT_CHECKF(n + 1 >= levels_on_line(S_VALLEY, 5, 20, H - 20) &&
              n <= levels_on_line(S_VALLEY, 5, 20, H - 20),
              "%zu valley points near the thalweg for %zu contours", n,
              levels_on_line(S_VALLEY, 5, 20, H - 20));
    TT_CHECKF(d <= 2.0, "valley point %.2f px from the thalweg", d);
    TT_CHECKF(nr == 0, "%zu ridge points in a valley", nr);
    TT_CHECKF(r->nvalley == 1, "%ld valley trees", r->nvalley);
done:
    td_ridges_free(r);
    td_lines_free(ls);
    td_grid_f32_free(g);
}

static void test_ridge_line(void)
{
    td_grid_f32 *g = truth(S_RIDGE);
    td_lines *ls = contours(g, 5);
    td_homotopy_params p = td_homotopy_defaults();
    td_ridges *r = NULL;
    size_t n, nv;
    double d;
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, NULL) == 0);
    if (!r)
        goto done;
    d = worst_dx(r, TD_RV_RIDGE, 20, H - 20, &n);
    worst_dx(r, TD_RV_VALLEY, 20, H - 20, &nv);
    TT_CHECKF(n + 1 >= levels_on_line(S_RIDGE, 5, 20, H - 20) &&
              n <= levels_on_line(S_RIDGE, 5, 20, H - 20),
              "%zu ridge points near the crest for %zu contours", n,
              levels_on_line(S_RIDGE, 5, 20, H - 20));
    TT_CHECKF(d <= 2.0, "ridge point %.2f px from the crest", d);
    TT_CHECKF(nv == 0, "%zu valley points on a ridge", nv);
    TT_CHECKF(r->nridge == 1, "%ld ridge trees", r->nridge);
done:
    td_ridges_free(r);
    td_lines_free(ls);
    td_grid_f32_free(g);
}

int main(void)
{
    TT_RUN(test_valley_line);
    TT_RUN(test_ridge_line);
    return tt_summary();
}
