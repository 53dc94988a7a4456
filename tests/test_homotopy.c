/* test_homotopy.c: ridge and valley lines from contour curvature and the
 * homotopy interpolation (interp/homotopy.h: orient.c, spline.c,
 * curvature.c, ridgelink.c, ridges.c, homotopy.c) on analytic surfaces
 * with a known thalweg / crest: a V-shaped valley, a ridge, a spur
 * joining a main ridge; orientation; curvature of a circle; the DEM
 * against the truth and against the scanline method. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/compare/compare.h"
#include "interp/homotopy.h"
#include "interp/interp.h"
#include "samples/gen/gen.h"

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
 *   spur:   the ridge, and a steeper-sided spur whose crest is the ray
 *           from (X0, 60) at 30 degrees to the right of straight down,
 *           falling 0.5 m/px along it (the spur surface falls behind its
 *           start, under the main ridge); a smooth maximum of the two */
#define SPUR_DX 0.5
#define SPUR_DY 0.8660254037844386
static double surface(int kind, double x, double y)
{
    double r1 = -0.4 * sqrt((x - X0) * (x - X0) + 100), r2, t, k = 4;
    switch (kind) {
    case S_VALLEY: return 150 - r1 - 0.5 * y;
    case S_RIDGE: return 300 + r1 - 0.5 * y;
    default:
        t = (x - X0) * SPUR_DX + (y - 60) * SPUR_DY;
        r2 = (x - X0) * SPUR_DY - (y - 60) * SPUR_DX; /* across the spur */
        r2 = 270 - 0.8 * sqrt(r2 * r2 + 25) - 0.5 * t + (t < 0 ? t : 0);
        r1 += 300 - 0.5 * y;
        return k * log(exp(r1 / k) + exp(r2 / k));
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

/* Ridge points of the spur: near its crest (the ray from (X0, 60)) below
 * y = 140, where the smooth maximum no longer bends it; all in one tree
 * with the main ridge. */
static void test_spur_tree(void)
{
    td_grid_f32 *g = truth(S_SPUR);
    td_lines *ls = contours(g, 5);
    td_homotopy_params p = td_homotopy_defaults();
    td_ridges *r = NULL;
    size_t i, nspur = 0, nmain = 0;
    double worst = 0;
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, NULL) == 0);
    if (!r)
        goto done;
    for (i = 0; i < r->npt; i++) {
        const td_rv_point *q = &r->pt[i];
        double d = ray_dist(q->x, q->y, X0, 60, SPUR_DX, SPUR_DY);
        if (q->kind != TD_RV_RIDGE || q->y < 140 || q->y > H - 10 ||
            q->x > W - 10)
            continue;
        if (fabs(q->x - X0) < 3)
            nmain++;
        else if (d < 10) {
            nspur++;
            worst = fmax(worst, d);
        }
    }
    TT_CHECKF(nspur >= 8, "%zu spur ridge points", nspur);
    TT_CHECKF(nmain >= 10, "%zu main ridge points", nmain);
    TT_CHECKF(worst <= 2.0, "spur ridge point %.2f px from its crest", worst);
    TT_CHECKF(r->nridge == 1, "%ld ridge trees (spur and main: one)",
              r->nridge);
done:
    td_ridges_free(r);
    td_lines_free(ls);
    td_grid_f32_free(g);
}

/* RMSE of the DEM by method m against the truth; *vfloor: the RMSE along
 * the thalweg (x = X0, 20 < y < H - 20). */
static double dem_rmse(const td_grid_f32 *t, const td_lines *ls, int m,
                       double *vfloor, td_homotopy_stats *hs)
{
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *d = NULL;
    td_compare_stats cs;
    double e = 0;
    int y, n = 0;
    p.method = (td_interp_method)m;
    p.hstats = hs;
    if (td_interp_lines(ls, W, H, &p, &d, NULL) != 0)
        return INFINITY;
    td_compare_grids(d, t, &cs, NULL);
    for (y = 20; y < H - 20; y++, n++) {
        double v = TD_AT(d, (int)X0, y) - TD_AT(t, (int)X0, y);
        e += v * v;
    }
    *vfloor = sqrt(e / n);
    td_grid_f32_free(d);
    return cs.coverage > 0.9 ? cs.rmse : INFINITY;
}

static void test_valley_dem(void)
{
    td_grid_f32 *t = truth(S_VALLEY);
    td_lines *ls = contours(t, 5);
    td_homotopy_stats hs;
    double vh, vs, vm;
    double rh = dem_rmse(t, ls, TD_INTERP_HOMOTOPY, &vh, &hs);
    double rs = dem_rmse(t, ls, TD_INTERP_SCANLINE, &vs, NULL);
    double rm = dem_rmse(t, ls, TD_INTERP_MULTIDIR, &vm, NULL);
    fprintf(stderr, "  valley: rmse homotopy %.3f scanline %.3f multidir %.3f;"
            " thalweg %.3f %.3f %.3f; cells homotopy %zu fallback %zu\n",
            rh, rs, rm, vh, vs, vm, hs.cells_homotopy, hs.cells_fallback);
    TT_CHECKF(rh < 0.15, "homotopy RMSE %.3f m (interval 5; measured 0.110)",
              rh);
    TT_CHECKF(rh < rs, "homotopy %.3f vs scanline %.3f", rh, rs);
    TT_CHECKF(vh < 0.7 * vs, "thalweg %.3f vs scanline %.3f", vh, vs);
    td_lines_free(ls);
    td_grid_f32_free(t);
}

/* A ring of radius rad about the sheet centre at height z, n points,
 * clockwise in pixel rows when cw. */
static void ring(td_lines *ls, double rad, double z, int cw)
{
    td_line *l = td_lines_add(ls, NULL);
    int k, n = 400;
    for (k = 0; k < n; k++) {
        double a = 2 * M_PI * k / n * (cw ? 1 : -1);
        td_line_push(l, W / 2.0 + rad * cos(a), H / 2.0 + rad * sin(a), NULL);
    }
    l->closed = 1, l->has_height = 1, l->height = z;
}

/* Shoelace sum of a curve's samples, pixel rows (< 0: clockwise). */
static double curve_area(const td_rv_curve *c)
{
    double a = 0;
    size_t i;
    for (i = 0; i < c->n; i++) {
        size_t j = (i + 1) % c->n;
        a += c->x[i] * c->y[j] - c->x[j] * c->y[i];
    }
    return a / 2;
}

/* Summit rings run clockwise in pixel rows with kappa = +1/R; pit rings
 * the other way with kappa = -1/R, whatever the input direction. */
static void test_orient_circle(void)
{
    int pit;
    for (pit = 0; pit < 2; pit++) {
        td_lines *ls = td_lines_new(NULL);
        td_homotopy_params p = td_homotopy_defaults();
        td_ridges *r = NULL;
        size_t i, k;
        ring(ls, 80, 100, 0);
        ring(ls, 40, pit ? 90 : 110, 1);
        TT_CHECK(td_ridges_find(ls, W, H, &p, &r, NULL) == 0);
        for (i = 0; r && i < 2; i++) {
            const td_rv_curve *c = &r->curve[i];
            double rad = i ? 40 : 80, worst = 0;
            TT_CHECKF(pit ? curve_area(c) > 0 : curve_area(c) < 0,
                      "ring %zu (%s) runs the wrong way", i,
                      pit ? "pit" : "summit");
            for (k = 0; k < c->n; k++)
                worst = fmax(worst, fabs(c->kappa[k] - (pit ? -1 : 1) / rad));
            TT_CHECKF(worst < 0.05 / rad, "kappa off 1/R by %g (R %g)", worst,
                      rad);
        }
        for (i = 0; r && i < r->npt; i++)
            TT_CHECK(r->pt[i].kind == (pit ? TD_RV_VALLEY : TD_RV_RIDGE));
        td_ridges_free(r);
        td_lines_free(ls);
    }
}

/* A cone's rings: homotopy between rings without links; with the apex
 * near the top edge (cy = 60) the outer contours leave the sheet, so one
 * band is an open line around a ring. */
static void cone_case(double cy, double *rmse, td_homotopy_stats *hs)
{
    td_grid_f32 *t = td_grid_f32_new(W, H, NULL), *d = NULL;
    td_interp_params p = td_interp_defaults();
    td_compare_stats cs;
    td_lines *ls;
    int x, y;
    for (y = 0; y < H; y++)
        for (x = 0; x < W; x++)
            TD_AT(t, x, y) = (float)(200 - 0.8 * hypot(x + 0.5 - W / 2.0,
                                                      y + 0.5 - cy));
    ls = contours(t, 10);
    p.method = TD_INTERP_HOMOTOPY;
    p.hstats = hs;
    *rmse = INFINITY;
    if (td_interp_lines(ls, W, H, &p, &d, NULL) == 0 &&
        td_compare_grids(d, t, &cs, NULL) == 0)
        *rmse = cs.rmse;
    td_grid_f32_free(d);
    td_lines_free(ls);
    td_grid_f32_free(t);
}

static void test_cone_dem(void)
{
    td_homotopy_stats hs;
    double v;
    cone_case(H / 2.0, &v, &hs);
    TT_CHECKF(v < 0.3, "cone RMSE %.3f m (interval 10)", v);
    TT_CHECKF(hs.bands_homotopy >= 10 && hs.cells_homotopy > 50000,
              "%zu bands, %zu cells by the homotopy", hs.bands_homotopy,
              hs.cells_homotopy);
    cone_case(60, &v, &hs);
    TT_CHECKF(v < 0.27, "edge cone RMSE %.3f m (interval 10)", v);
    /* measured 9597 (10.7 %), 13368 without the open-around-ring bands */
    TT_CHECKF(hs.cells_fallback < 0.12 * W * H, "%zu cells by the fallback",
              hs.cells_fallback);
}

static void test_bad_input(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_homotopy_params p = td_homotopy_defaults();
    td_ridges *r = NULL;
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, &cx) == TD_EINVAL && !r);
    ring(ls, 30, 10, 1);
    ls->v[0].has_height = 0;
    td_ctx_clear(&cx);
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, &cx) == TD_EINVAL && !r);
    TT_CHECK(strstr(td_errmsg(&cx), "label") != NULL);
    ls->v[0].has_height = 1;
    p.spacing = 0;
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, &cx) == TD_EINVAL && !r);
    p = td_homotopy_defaults(); /* one ring alone: no points, no links */
    TT_CHECK(td_ridges_find(ls, W, H, &p, &r, NULL) == 0 && r &&
             r->nlink == 0);
    td_ridges_free(r);
    td_lines_free(ls);
}

int main(void)
{
    TT_RUN(test_valley_line);
    TT_RUN(test_ridge_line);
    TT_RUN(test_spur_tree);
    TT_RUN(test_valley_dem);
    TT_RUN(test_orient_circle);
    TT_RUN(test_cone_dem);
    TT_RUN(test_bad_input);
    return tt_summary();
}
