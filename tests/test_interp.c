/* test_interp.c: the driver (interp/interp.c), rasterising labelled lines
 * and the two interpolation methods (the paper's scanline, multidir) on surfaces with a known truth:
 * planes, a cone, Gaussian hills, a saddle; summit extrapolation against
 * flat filling; multidir's one-pass sweep (interp/multidir_sweep.c) and walk
 * against a brute force; band smoothing (interp/smooth.c); GeoTIFF round
 * trip through gdalinfo; bad input. */
#define _POSIX_C_SOURCE 200809L
#include "tests/tt.h"

#include "src/compare/compare.h"
#include "src/io/io.h"
#include "interp/multidir.h"
#include "interp/multidir_int.h"
#include "interp/interp.h"
#include "interp/scanline.h"
#include "samples/gen/gen.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

enum { S_CONE, S_HILLS, S_SADDLE };

/* Analytic truth at pixel centres (x = col + 0.5). */
static double surface(int kind, double x, double y, int w, int h)
{
    double cx = w / 2.0, cy = h / 2.0, s = w < h ? w : h;
    double u = (x - cx) / s, v = (y - cy) / s;
    switch (kind) {
    case S_CONE: return 200.0 * (1.0 - sqrt(u * u + v * v) / 0.45);
    case S_SADDLE: return 100.0 + 300.0 * (u * u - v * v);
    default:
        return 120 * exp(-((u + 0.2) * (u + 0.2) + (v + 0.15) * (v + 0.15)) / 0.02) +
               90 * exp(-((u - 0.22) * (u - 0.22) + (v - 0.1) * (v - 0.1)) / 0.015) +
               60 * exp(-((u - 0.05) * (u - 0.05) + (v - 0.3) * (v - 0.3)) / 0.01) +
               20 * u;
    }
}

static td_grid_f32 *truth(int kind, int w, int h)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)surface(kind, x + 0.5, y + 0.5, w, h);
    return g;
}

/* Interpolate the true contours of dem at interval I; compare with dem. */
static int run(const td_grid_f32 *dem, double I, td_interp_params p,
               td_compare_stats *st, td_grid_f32 **keep)
{
    td_lines *ls = NULL;
    td_grid_f32 *out = NULL;
    td_ctx cx;
    int rc;
    td_ctx_init(&cx);
    p.interval = I;
    rc = td_gen_contours(dem, 0, I, &ls, &cx);
    if (rc == 0)
        rc = td_interp_lines(ls, dem->w, dem->h, &p, &out, &cx);
    if (rc == 0)
        rc = td_compare_grids(out, dem, st, &cx);
    if (rc != 0)
        fprintf(stderr, "  error: %s\n", td_errmsg(&cx));
    if (keep)
        *keep = out;
    else
        td_grid_f32_free(out);
    td_lines_free(ls);
    return rc;
}

static td_interp_params method(td_interp_method m)
{
    td_interp_params p = td_interp_defaults();
    p.method = m;
    return p;
}

/* Straight lines through cell centres at x = 10k + 0.5 (vertical, the
 * plane z = col) or y = 10k + 0.5 (horizontal, z = row). */
static td_lines *plane_lines(int w, int h, int vertical)
{
    td_lines *ls = td_lines_new(NULL);
    int k, n = vertical ? w : h;
    for (k = 0; 10 * k < n; k++) {
        td_line *l = td_lines_add(ls, NULL);
        double c = 10 * k + 0.5;
        l->has_height = 1;
        l->height = 10 * k;
        if (vertical) {
            td_line_push(l, c, 0.2, NULL);
            td_line_push(l, c, h - 0.2, NULL);
        } else {
            td_line_push(l, 0.2, c, NULL);
            td_line_push(l, w - 0.2, c, NULL);
        }
    }
    return ls;
}

static void check_plane(td_interp_method m, int vertical)
{
    int w = 203, h = 157, x, y;
    td_lines *ls = plane_lines(w, h, vertical);
    td_interp_params p = method(m);
    td_grid_f32 *g = NULL;
    td_ctx cx;
    double worst = 0;
    long valid = 0, inside = 0;
    td_ctx_init(&cx);
    TT_CHECK(td_interp_lines(ls, w, h, &p, &g, &cx) == 0);
    if (!g)
        goto done;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            float v = TD_AT(g, x, y);
            int t = vertical ? x : y, last = vertical ? 200 : 150;
            inside += t <= last;
            if (v == g->nodata)
                continue;
            valid++;
            worst = fmax(worst, fabs(v - t));
        }
    /* exact between contours: max error 1e-4 interval, every cell
     * between the first and last line determined */
    TT_CHECKF(worst <= 1e-4 * 10, "max error %g", worst);
    TT_CHECKF(valid == inside, "%ld cells valid, %ld between the lines",
              valid, inside);
done:
    td_grid_f32_free(g);
    td_lines_free(ls);
}

static void test_plane_exact(void)
{
    check_plane(TD_INTERP_SCANLINE, 1);
    check_plane(TD_INTERP_SCANLINE, 0);
    check_plane(TD_INTERP_MULTIDIR, 1);
    check_plane(TD_INTERP_MULTIDIR, 0);
}

/* A plane in a general direction: contours do not pass through cell
 * centres, so cells on a line carry its height up to ~0.7 px away from it;
 * the error stays under that quantisation (slope x 0.75 px). */
static void test_plane_tilted(void)
{
    int w = 300, h = 240, x, y, m;
    td_grid_f32 *dem = td_grid_f32_new(w, h, NULL);
    td_compare_stats st;
    double slope = hypot(0.8, 0.5);
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(dem, x, y) = (float)(0.8 * (x + 0.5) + 0.5 * (y + 0.5));
    for (m = 0; m < 2; m++) {
        TT_CHECK(run(dem, 10, method(m), &st, NULL) == 0);
        TT_CHECKF(st.max_abs <= 0.75 * slope, "method %d: max %g", m,
                  st.max_abs);
        TT_CHECKF(st.rmse <= 0.03 * 10, "method %d: rmse %g", m, st.rmse);
        TT_CHECKF(st.coverage >= 0.9, "method %d: coverage %g", m,
                  st.coverage);
    }
    td_grid_f32_free(dem);
}

static void test_cone(void)
{
    td_grid_f32 *dem = truth(S_CONE, 360, 360);
    td_compare_stats sl, md;
    TT_CHECK(run(dem, 20, method(TD_INTERP_SCANLINE), &sl, NULL) == 0);
    TT_CHECK(run(dem, 20, method(TD_INTERP_MULTIDIR), &md, NULL) == 0);
    fprintf(stderr, "  cone: scanline rmse %.3f max %.2f cov %.3f; multidir "
            "rmse %.3f max %.2f cov %.3f\n", sl.rmse, sl.max_abs, sl.coverage,
            md.rmse, md.max_abs, md.coverage);
    /* a cone is linear between rings: well under a tenth of an interval */
    TT_CHECKF(sl.rmse < 0.1 * 20, "scanline rmse %g", sl.rmse);
    TT_CHECKF(md.rmse < 0.1 * 20, "multidir rmse %g", md.rmse);
    TT_CHECKF(md.max_abs < 20, "multidir max %g", md.max_abs);
    TT_CHECK(md.coverage > 0.6 && sl.coverage > 0.6);
    td_grid_f32_free(dem);
}

static void test_hills_multidir_beats_scanline(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 400, 400);
    td_compare_stats sl, md;
    TT_CHECK(run(dem, 10, method(TD_INTERP_SCANLINE), &sl, NULL) == 0);
    TT_CHECK(run(dem, 10, method(TD_INTERP_MULTIDIR), &md, NULL) == 0);
    fprintf(stderr, "  hills: scanline rmse %.3f max %.2f cov %.3f; multidir "
            "rmse %.3f max %.2f cov %.3f\n", sl.rmse, sl.max_abs, sl.coverage,
            md.rmse, md.max_abs, md.coverage);
    TT_CHECKF(md.rmse < sl.rmse, "multidir %g vs scanline %g", md.rmse,
              sl.rmse);
    TT_CHECKF(md.rmse < 0.15 * 10, "multidir rmse %g", md.rmse);
    TT_CHECKF(sl.rmse < 0.4 * 10, "scanline rmse %g", sl.rmse);
    td_grid_f32_free(dem);
}

/* Mean |second difference| along x and y over cells valid in g: the
 * creases a hillshade shows. */
static double roughness(const td_grid_f32 *g)
{
    double sum = 0;
    long n = 0;
    int x, y;
    for (y = 1; y + 1 < g->h; y++)
        for (x = 1; x + 1 < g->w; x++) {
            float c = TD_AT(g, x, y), l = TD_AT(g, x - 1, y),
                  r = TD_AT(g, x + 1, y), u = TD_AT(g, x, y - 1),
                  d = TD_AT(g, x, y + 1);
            if (c == g->nodata || l == g->nodata || r == g->nodata ||
                u == g->nodata || d == g->nodata)
                continue;
            sum += fabs(l + r - 2.0 * c) + fabs(u + d - 2.0 * c);
            n++;
        }
    return n ? sum / n : 0;
}

/* --smooth 30 on Gaussian hills: lower RMSE and half the creases, every
 * line cell unchanged, every other cell still between its two contours. */
static void test_smooth_bands(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 400, 400), *a = NULL, *b = NULL;
    td_interp_params p = method(TD_INTERP_MULTIDIR);
    td_compare_stats sa, sb;
    td_lines *ls = NULL;
    td_grid_f32 *lines = td_grid_f32_new(400, 400, NULL);
    long moved_line = 0, out_band = 0;
    size_t i;
    TT_CHECK(td_gen_contours(dem, 0, 10, &ls, NULL) == 0 &&
             td_rasterise_lines(ls, 1, lines, NULL) == 0);
    TT_CHECK(run(dem, 10, p, &sa, &a) == 0);
    p.smooth = 30;
    TT_CHECK(run(dem, 10, p, &sb, &b) == 0);
    if (!a || !b)
        goto done;
    for (i = 0; i < (size_t)a->w * a->h; i++) {
        float z0 = a->data[i], z1 = b->data[i];
        if (z0 == a->nodata)
            continue;
        if (lines->data[i] == lines->data[i])
            moved_line += z1 != z0;
        else /* 0.001 interval margin: cells exactly on a height move */
            out_band += fabsf(z1 - z0) > 0.011f &&
                        floorf(z1 / 10) != floorf(z0 / 10);
    }
    fprintf(stderr, "  smooth 30: rmse %.3f -> %.3f, roughness %.4f -> "
            "%.4f\n", sa.rmse, sb.rmse, roughness(a), roughness(b));
    TT_CHECKF(sb.rmse < 1.01 * sa.rmse, "rmse %g vs %g", sb.rmse, sa.rmse);
    TT_CHECKF(roughness(b) < 0.5 * roughness(a), "roughness %g vs %g",
              roughness(b), roughness(a));
    TT_CHECKF(moved_line == 0 && out_band == 0, "%ld line cells moved, %ld "
              "cells left their band", moved_line, out_band);
done:
    td_lines_free(ls);
    td_grid_f32_free(lines);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    td_grid_f32_free(dem);
}

static void test_saddle(void)
{
    td_grid_f32 *dem = truth(S_SADDLE, 320, 300);
    td_compare_stats sl, md;
    TT_CHECK(run(dem, 5, method(TD_INTERP_SCANLINE), &sl, NULL) == 0);
    TT_CHECK(run(dem, 5, method(TD_INTERP_MULTIDIR), &md, NULL) == 0);
    fprintf(stderr, "  saddle: scanline rmse %.3f max %.2f; multidir rmse "
            "%.3f max %.2f\n", sl.rmse, sl.max_abs, md.rmse, md.max_abs);
    TT_CHECKF(sl.rmse < 0.3 * 5, "scanline rmse %g", sl.rmse);
    TT_CHECKF(md.rmse < 0.2 * 5, "multidir rmse %g", md.rmse);
    TT_CHECK(md.coverage > 0.9);
    td_grid_f32_free(dem);
}

/* RMSE over the cells above the highest contour (the summit ring). */
static double summit_rmse(const td_grid_f32 *dem, const td_grid_f32 *g,
                          double top, long *n)
{
    double s = 0;
    int x, y;
    *n = 0;
    for (y = 0; y < dem->h; y++)
        for (x = 0; x < dem->w; x++) {
            double d;
            if (TD_AT(dem, x, y) <= top || TD_AT(g, x, y) == g->nodata)
                continue;
            d = TD_AT(g, x, y) - TD_AT(dem, x, y);
            s += d * d;
            (*n)++;
        }
    return *n ? sqrt(s / *n) : 0;
}

static void check_summit(td_interp_method m)
{
    td_grid_f32 *dem = truth(S_CONE, 300, 300), *a = NULL, *b = NULL;
    td_interp_params p = method(m);
    td_compare_stats st;
    double ea, eb;
    long na, nb;
    TT_CHECK(run(dem, 30, p, &st, &a) == 0);
    p.scanline.summit = p.multidir.summit = 0;
    TT_CHECK(run(dem, 30, p, &st, &b) == 0);
    if (!a || !b)
        goto done;
    ea = summit_rmse(dem, a, 180, &na);
    eb = summit_rmse(dem, b, 180, &nb);
    fprintf(stderr, "  summit (method %d): extrapolated rmse %.2f, flat %.2f "
            "(%ld cells)\n", m, ea, eb, na);
    TT_CHECK(na > 100 && na == nb);
    /* the cone rises 20 m above the top ring; flat filling misses by ~10 */
    TT_CHECKF(ea < 0.6 * eb, "extrapolated %g, flat %g", ea, eb);
    TT_CHECKF(ea < 5, "extrapolated %g", ea);
done:
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    td_grid_f32_free(dem);
}

static void test_summit_beats_flat(void)
{
    check_summit(TD_INTERP_SCANLINE);
    check_summit(TD_INTERP_MULTIDIR);
}

/* The summit is capped: never more than one interval above the top
 * contour, even where the slopes would go higher (a steep narrow ridge). */
static void test_summit_capped(void)
{
    td_grid_f32 *dem = truth(S_CONE, 300, 300), *g = NULL;
    td_compare_stats st;
    int m;
    for (m = 0; m < 2; m++) {
        float top = -1e30f;
        size_t i;
        TT_CHECK(run(dem, 30, method(m), &st, &g) == 0);
        if (!g)
            continue;
        for (i = 0; i < (size_t)g->w * g->h; i++)
            top = fmaxf(top, g->data[i]);
        TT_CHECKF(top <= 180 + 30 + 1e-3, "method %d: top %g", m, top);
        TT_CHECKF(top > 185, "method %d: top %g (not extrapolated)", m, top);
        td_grid_f32_free(g);
        g = NULL;
    }
    td_grid_f32_free(dem);
}

/* Multidir on the hills with 1 and 2 threads: the same bytes (the summit
 * phase runs its direction pairs on two threads, each into its own sums). */
static void test_multidir_threads(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 400, 300), *g[2] = {NULL, NULL};
    td_compare_stats st;
    int t;
    for (t = 0; t < 2; t++) {
        omp_set_num_threads(t + 1);
        TT_CHECK(run(dem, 10, method(TD_INTERP_MULTIDIR), &st, &g[t]) == 0);
    }
    omp_set_num_threads(omp_get_num_procs());
    TT_CHECK(g[0] && g[1] &&
             memcmp(g[0]->data, g[1]->data,
                    (size_t)g[0]->h * g[0]->stride * sizeof *g[0]->data) == 0);
    td_grid_f32_free(g[0]);
    td_grid_f32_free(g[1]);
    td_grid_f32_free(dem);
}

/* td_interp_lines_take: the DEM of td_interp_lines, the lines gone. */
static void test_take(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 300, 200), *a = NULL, *b = NULL;
    td_lines *ls = NULL, *copy = NULL;
    td_interp_params p;
    int m;
    for (m = 0; m < 2; m++) {
        p = method(m ? TD_INTERP_HOMOTOPY : TD_INTERP_MULTIDIR);
        p.interval = 10;
        TT_CHECK(td_gen_contours(dem, 0, 10, &ls, NULL) == 0);
        TT_CHECK((copy = td_lines_copy(ls, NULL)) != NULL);
        TT_CHECK(td_interp_lines(ls, dem->w, dem->h, &p, &a, NULL) == 0);
        TT_CHECK(td_interp_lines_take(&copy, dem->w, dem->h, &p, &b, NULL) ==
                 0);
        TT_CHECKF(copy == NULL, "method %d: lines kept", m);
        TT_CHECKF(a && b &&
                      memcmp(a->data, b->data,
                             (size_t)a->h * a->stride * sizeof *a->data) == 0,
                  "method %d: DEMs differ", m);
        td_grid_f32_free(a);
        td_grid_f32_free(b);
        td_lines_free(ls);
        td_lines_free(copy);
        a = b = NULL, ls = copy = NULL;
    }
    td_grid_f32_free(dem);
}

/* --step 2: half-size grid, about the same accuracy against the truth
 * sampled at the coarse cells' centres. */
static void test_step(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 401, 400), *g = NULL, *coarse;
    td_lines *ls = NULL;
    td_interp_params p = td_interp_defaults();
    td_compare_stats st;
    td_ctx cx;
    int x, y;
    td_ctx_init(&cx);
    p.step = 2;
    p.interval = 10;
    TT_CHECK(td_gen_contours(dem, 0, 10, &ls, &cx) == 0);
    TT_CHECK(td_interp_lines(ls, 401, 400, &p, &g, &cx) == 0);
    if (!g)
        goto done;
    TT_CHECK(g->w == 201 && g->h == 200);
    coarse = td_grid_f32_new(g->w, g->h, NULL);
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++)
            TD_AT(coarse, x, y) = (float)surface(S_HILLS, 2 * x + 1.0,
                                                 2 * y + 1.0, 401, 400);
    td_compare_grids(g, coarse, &st, NULL);
    TT_CHECKF(st.rmse < 0.2 * 10, "rmse %g", st.rmse);
    td_grid_f32_free(coarse);
done:
    td_grid_f32_free(g);
    td_lines_free(ls);
    td_grid_f32_free(dem);
}

/* The lines are drawn in bands of rows on threads, one band per thread:
 * 300 random lines of 2-40 vertices, each its own height, crossing and
 * overlapping all over a 157 x 211 grid (open, closed, single points, some
 * reaching past the edges), give the same grid on 1, 2 and 3 threads (one
 * thread is one pass in line order: the last line over a cell wins), and
 * a cell where two lines cross gets the later one. */
static void test_rasterise_bands(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_grid_f32 *g[3];
    unsigned seed = 11;
    int i, k, t;
    for (i = 0; i < 300; i++) {
        td_line *l = td_lines_add(ls, NULL);
        int n = i % 7 == 0 ? 1 : 2 + rand_r(&seed) % 39;
        double x = rand_r(&seed) % 1560 / 10.0,
               y = rand_r(&seed) % 2100 / 10.0; /* starts inside */
        l->has_height = 1;
        l->height = i;
        l->closed = n > 2 && i % 3 == 0;
        for (k = 0; k < n; k++) {
            td_line_push(l, x, y, NULL);
            x += rand_r(&seed) % 61 / 10.0 - 3,
                y += rand_r(&seed) % 81 / 10.0 - 4;
        }
    }
    { /* two crossing lines last: the later one wins where they cross */
        td_line *a = td_lines_add(ls, NULL), *b = td_lines_add(ls, NULL);
        a->has_height = b->has_height = 1;
        a->height = 1000, b->height = 1001;
        td_line_push(a, 10.5, 105.5, NULL), td_line_push(a, 150.5, 105.5, NULL);
        td_line_push(b, 80.5, 2.5, NULL), td_line_push(b, 80.5, 200.5, NULL);
    }
    for (t = 0; t < 3; t++) {
        g[t] = td_grid_f32_new(157, 211, NULL);
        omp_set_num_threads(t + 1);
        TT_CHECK(td_rasterise_lines(ls, 1, g[t], NULL) == 0);
    }
    omp_set_num_threads(omp_get_num_procs());
    for (t = 1; t < 3; t++)
        TT_CHECKF(memcmp(g[0]->data, g[t]->data,
                         (size_t)g[0]->h * g[0]->stride * sizeof *g[0]->data) ==
                      0,
                  "%d threads", t + 1);
    TT_CHECK(TD_AT(g[0], 80, 105) == 1001 && TD_AT(g[0], 20, 105) == 1000);
    for (t = 0; t < 3; t++)
        td_grid_f32_free(g[t]);
    td_lines_free(ls);
}

/* Rasterised lines are 4-connected: a diagonal line leaves no gap that a
 * diagonal scan could slip through. */
static void test_rasterise_4connected(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_line *l = td_lines_add(ls, NULL);
    td_grid_f32 *g = td_grid_f32_new(40, 30, NULL);
    int x, y, gaps = 0, cells = 0;
    l->has_height = 1;
    l->height = 7;
    td_line_push(l, 1.3, 2.7, NULL);
    td_line_push(l, 37.9, 25.1, NULL);
    TT_CHECK(td_rasterise_lines(ls, 1, g, NULL) == 0);
    for (y = 0; y < 30; y++)
        for (x = 0; x < 40; x++) {
            int on = TD_AT(g, x, y) == 7;
            cells += on;
            /* a diagonal step without a shared side neighbour is a gap */
            if (on && x + 1 < 40 && y + 1 < 30 && TD_AT(g, x + 1, y + 1) == 7 &&
                TD_AT(g, x + 1, y) != 7 && TD_AT(g, x, y + 1) != 7)
                gaps++;
        }
    TT_CHECK(gaps == 0);
    TT_CHECKF(cells >= 36 + 22 && cells <= 36 + 23 + 2, "%d cells", cells);
    TT_CHECK(TD_AT(g, 1, 2) == 7 && TD_AT(g, 37, 25) == 7);
    TT_CHECK(isnan(TD_AT(g, 30, 2)));
    td_grid_f32_free(g);
    td_lines_free(ls);
}

static void test_interval(void)
{
    td_lines *ls = td_lines_new(NULL);
    double z[] = {50, 30, 40, 30, 35};
    size_t i;
    for (i = 0; i < 5; i++) {
        td_line *l = td_lines_add(ls, NULL);
        l->has_height = 1;
        l->height = z[i];
    }
    TT_NEAR(td_interp_interval(ls), 5, 1e-12);
    td_lines_free(ls);
}

static int bad(td_lines *ls, const char *needle)
{
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *g = NULL;
    td_ctx cx;
    int rc;
    td_ctx_init(&cx);
    rc = td_interp_lines(ls, 100, 80, &p, &g, &cx);
    td_grid_f32_free(g);
    if (rc == 0 || g || !strstr(td_errmsg(&cx), needle)) {
        fprintf(stderr, "  rc %d, message '%s'\n", rc, td_errmsg(&cx));
        return 0;
    }
    return 1;
}

static void test_bad_input(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_line *l;
    TT_CHECK(bad(ls, "no contour lines"));
    l = td_lines_add(ls, NULL);
    td_line_push(l, 10, 10, NULL);
    td_line_push(l, 50, 10, NULL);
    TT_CHECK(bad(ls, "line 0 has no height"));
    l->has_height = 1;
    l->height = 10;
    l = td_lines_add(ls, NULL);
    l->has_height = 1;
    l->height = 20;
    td_line_push(l, 500, 10, NULL);
    td_line_push(l, 900, 10, NULL);
    TT_CHECK(bad(ls, "line 1 lies outside the 100 x 80 grid"));
    l->xy[0] = NAN;
    TT_CHECK(bad(ls, "not a finite number"));
    td_lines_free(ls);
}

/* A line whose vertices all lie off the grid but whose segment crosses it
 * (a contour clipped by the sheet, edited in QGIS) is drawn, not refused. */
static void test_line_across(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_line *l = td_lines_add(ls, NULL);
    td_grid_f32 *g = td_grid_f32_new(100, 80, NULL);
    td_ctx cx;
    int x, n = 0;
    td_ctx_init(&cx);
    l->has_height = 1;
    l->height = 30;
    td_line_push(l, -50, 40.5, NULL);
    td_line_push(l, 700, 40.5, NULL);
    TT_CHECKF(td_rasterise_lines(ls, 1.0, g, &cx) == 0, "%s", td_errmsg(&cx));
    for (x = 0; x < 100; x++)
        n += TD_AT(g, x, 40) == 30.0f;
    TT_CHECKF(n == 100, "%d of 100 cells of row 40 drawn", n);
    td_grid_f32_free(g);
    td_lines_free(ls);
}

/* One height only: nothing to interpolate between; the flat inside is
 * filled, the outside is nodata, nothing crashes. */
static void test_single_ring(void)
{
    td_lines *ls = td_lines_new(NULL);
    td_line *l = td_lines_add(ls, NULL);
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *g = NULL;
    int m, k;
    l->has_height = 1;
    l->height = 42;
    l->closed = 1;
    for (k = 0; k < 64; k++)
        td_line_push(l, 50 + 20 * cos(k * M_PI / 32), 40 + 20 * sin(k * M_PI / 32), NULL);
    for (m = 0; m < 2; m++) {
        p.method = m;
        TT_CHECK(td_interp_lines(ls, 100, 80, &p, &g, NULL) == 0);
        if (!g)
            continue;
        TT_CHECKF(fabs(TD_AT(g, 50, 40) - 42) < 1e-4, "method %d: %g", m, TD_AT(g, 50, 40));
        TT_CHECK(TD_AT(g, 2, 2) == g->nodata);
        td_grid_f32_free(g);
        g = NULL;
    }
    td_lines_free(ls);
}

/* The DEM written as GeoTIFF opens in GDAL with the same statistics and
 * the nodata value. */
static void test_gdalinfo_stats(void)
{
    td_grid_f32 *dem = truth(S_HILLS, 300, 200), *g = NULL;
    td_compare_stats st;
    char path[600], cmd[1400], line[512];
    double gmin = 1e30, gmax = -1e30, fmin_ = NAN, fmax_ = NAN;
    int nodata_ok = 0;
    size_t i;
    FILE *f;
    if (system("command -v gdalinfo >/dev/null 2>&1") != 0) {
        fprintf(stderr, "  gdalinfo not installed: skipped\n");
        goto done;
    }
    TT_CHECK(run(dem, 10, td_interp_defaults(), &st, &g) == 0);
    if (!g)
        goto done;
    for (i = 0; i < (size_t)g->w * g->h; i++)
        if (g->data[i] != g->nodata) {
            gmin = fmin(gmin, g->data[i]);
            gmax = fmax(gmax, g->data[i]);
        }
    snprintf(path, sizeof path, "%s/dem.tif", tt_tmpdir());
    TT_CHECK(td_geotiff_write_f32(path, g, NULL, NULL) == 0);
    snprintf(cmd, sizeof cmd, "gdalinfo -stats '%s' 2>&1", path);
    if (!(f = popen(cmd, "r")))
        goto done;
    while (fgets(line, sizeof line, f)) {
        sscanf(line, " STATISTICS_MINIMUM=%lf", &fmin_);
        sscanf(line, " STATISTICS_MAXIMUM=%lf", &fmax_);
        nodata_ok |= strstr(line, "NoData Value=-9999") != NULL;
    }
    pclose(f);
    snprintf(cmd, sizeof cmd, "rm -f '%s.aux.xml'", path);
    if (system(cmd) != 0)
        fprintf(stderr, "  could not remove the .aux.xml\n");
    TT_CHECK(nodata_ok);
    TT_NEAR(fmin_, gmin, 1e-3);
    TT_NEAR(fmax_, gmax, 1e-3);
done:
    td_grid_f32_free(g);
    td_grid_f32_free(dem);
}

/* Brute force for phase 1 of multidir: for each undetermined cell, along
 * each direction, the nearest anchor on both sides; lines whose anchors
 * differ give the linear estimate, blended with the method's weight. */
static double brute_weight(td_multidir_weight m, double d1, double d2)
{
    return m == TD_MULTIDIR_SPAN    ? 1.0 / (d1 + d2)
           : m == TD_MULTIDIR_SPAN2 ? 1.0 / ((d1 + d2) * (d1 + d2))
                                    : 1.0 / (d1 * d2);
}

static const int bdx[4] = {1, 0, 1, -1}, bdy[4] = {0, 1, 1, 1};

/* The run of undetermined cells through (x, y) along direction d: the
 * steps k1 back and k2 on to the determined cells A and B; 0 when the run
 * leaves the grid first. */
static int brute_run(const td_grid_f32 *a, int x, int y, int d, int *k1,
                     int *k2)
{
    const int *dx = bdx, *dy = bdy;
    *k1 = *k2 = 1;
    while (x - *k1 * dx[d] >= 0 && x - *k1 * dx[d] < a->w &&
           y - *k1 * dy[d] >= 0 &&
           isnan(TD_AT(a, x - *k1 * dx[d], y - *k1 * dy[d])))
        (*k1)++;
    while (x + *k2 * dx[d] >= 0 && x + *k2 * dx[d] < a->w &&
           y + *k2 * dy[d] < a->h &&
           isnan(TD_AT(a, x + *k2 * dx[d], y + *k2 * dy[d])))
        (*k2)++;
    return !(x - *k1 * dx[d] < 0 || x - *k1 * dx[d] >= a->w ||
             y - *k1 * dy[d] < 0 || x + *k2 * dx[d] < 0 ||
             x + *k2 * dx[d] >= a->w || y + *k2 * dy[d] >= a->h);
}

static int brute_cell(const td_grid_f32 *a, int x, int y, int ndir,
                      td_multidir_weight m, double *z)
{
    const int *dx = bdx, *dy = bdy;
    double sw = 0, swz = 0;
    int d;
    for (d = 0; d < ndir; d++) {
        double sl = d < 2 ? 1.0 : sqrt(2.0), w;
        int k1, k2;
        float za, zb;
        if (!brute_run(a, x, y, d, &k1, &k2))
            continue;
        za = TD_AT(a, x - k1 * dx[d], y - k1 * dy[d]);
        zb = TD_AT(a, x + k2 * dx[d], y + k2 * dy[d]);
        if (za == zb)
            continue;
        w = brute_weight(m, k1 * sl, k2 * sl);
        sw += w;
        swz += w * (za + (zb - za) * k1 / (double)(k1 + k2));
    }
    if (sw <= 0)
        return 0;
    *z = swz / sw;
    return 1;
}

/* The one-pass sweep (span weights) and the per-direction walk (prod)
 * give every cell a linear estimate can reach the same value as the
 * brute force, on random anchors with heights in 5 levels. */
static void test_multidir_brute(void)
{
    int w = 97, h = 83, x, y, m, nd;
    td_grid_f32 *a = td_grid_f32_new(w, h, NULL), *g;
    unsigned s = 12345;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            s = s * 1103515245u + 12345u;
            TD_AT(a, x, y) = (s >> 16) % 100 < 4 ? (float)(10 * ((s >> 8) % 5))
                                                 : NAN;
        }
    for (m = 0; m < 3; m++)
        for (nd = 2; nd <= 4; nd += 2) {
            td_multidir_params p = td_multidir_defaults();
            td_ctx cx;
            double worst = 0, z;
            long cells = 0;
            td_ctx_init(&cx);
            p.interval = 10;
            p.weight = (td_multidir_weight)m;
            p.ndir = nd;
            g = td_grid_f32_new(w, h, NULL);
            memcpy(g->data, a->data, (size_t)h * a->stride * sizeof *g->data);
            TT_CHECK(td_multidir_fill(g, &p, &cx) == 0);
            for (y = 0; y < h; y++)
                for (x = 0; x < w; x++) {
                    if (!isnan(TD_AT(a, x, y)))
                        TT_CHECK(TD_AT(g, x, y) == TD_AT(a, x, y));
                    else if (brute_cell(a, x, y, nd, p.weight, &z)) {
                        cells++;
                        worst = fmax(worst, fabs(TD_AT(g, x, y) - z));
                    }
                }
            TT_CHECKF(worst < 1e-3, "weight %d, %d dirs: max |d| %g over %ld "
                      "cells", m, nd, worst, cells);
            TT_CHECK(cells > w * h / 2);
            td_grid_f32_free(g);
        }
    td_grid_f32_free(a);
}

/* Brute force for phase 2 (the summit phase) at the undetermined cell
 * (x, y) of a: per direction, the run of undetermined cells through it,
 * its anchors A and B n steps apart; unequal: the linear estimate, with
 * the span weight; equal: the paper's tent with the slopes read outwards
 * from A and B (the farthest determined cell within kmax with none
 * undetermined before it), weighted by the cell's own distances. */
static double slope_out(const td_grid_f32 *a, int x, int y, int dx, int dy,
                        int kmax, double sl, int *ok)
{
    int k, best = 0;
    float zb = 0;
    for (k = 1; k <= kmax; k++) {
        int u = x + k * dx, v = y + k * dy;
        if (u < 0 || v < 0 || u >= a->w || v >= a->h || isnan(TD_AT(a, u, v)))
            break;
        best = k, zb = TD_AT(a, u, v);
    }
    *ok = best > 0;
    return best ? ((double)TD_AT(a, x, y) - zb) / (best * sl) : 0;
}

static int brute_summit(const td_grid_f32 *a, int x, int y,
                        const td_multidir_params *p, double *z)
{
    const int *dx = bdx, *dy = bdy;
    double sw = 0, swz = 0;
    int d;
    for (d = 0; d < p->ndir; d++) {
        double sl = d < 2 ? 1.0 : sqrt(2.0), s1 = 0, s2 = 0, w, v;
        int k1, k2, ax, ay, bx, by, o1, o2;
        float za, zb;
        if (!brute_run(a, x, y, d, &k1, &k2))
            continue;
        ax = x - k1 * dx[d], ay = y - k1 * dy[d];
        bx = x + k2 * dx[d], by = y + k2 * dy[d];
        za = TD_AT(a, ax, ay), zb = TD_AT(a, bx, by);
        w = brute_weight(p->weight, k1 * sl, k2 * sl);
        if (za != zb) {
            v = za + (zb - za) * k1 / (double)(k1 + k2);
        } else {
            if (p->summit) {
                s1 = slope_out(a, ax, ay, -dx[d], -dy[d], p->slope_cells, sl,
                               &o1);
                s2 =
                    slope_out(a, bx, by, dx[d], dy[d], p->slope_cells, sl, &o2);
                if (!o1 || !o2)
                    s1 = s2 = 0;
            }
            v = za;
            if (s1 > 0 && s2 > 0)
                v = za +
                    fmin(fmin(s1 * k1 * sl, s2 * k2 * sl), 0.99 * p->interval);
            else if (s1 < 0 && s2 < 0)
                v = za - fmin(fmin(-s1 * k1 * sl, -s2 * k2 * sl),
                              0.99 * p->interval);
        }
        sw += w;
        swz += w * v;
    }
    if (sw <= 0)
        return 0;
    *z = swz / sw;
    return 1;
}

/* Phase 2 (interp/multidir_summit.c, one pass down the rows) against the
 * brute force, on random anchors in 3 levels (many runs between equal
 * heights: tents) on a tall grid (runs far longer than the rows it
 * holds back): every weight, 2 and 4 directions, summit on and off; the
 * determined cells untouched; the same bytes on one thread and two. */
static void test_multidir_summit(void)
{
    int w = 71, h = 1100, x, y, m, nd, su, t;
    td_grid_f32 *a = td_grid_f32_new(w, h, NULL), *g, *g1;
    unsigned s = 4242;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            s = s * 1103515245u + 12345u;
            TD_AT(a, x, y) =
                (s >> 16) % 100 < 12 ? (float)(10 * ((s >> 8) % 3)) : NAN;
        }
    for (m = 0; m < 3; m++)
        for (nd = 2; nd <= 4; nd += 2)
            for (su = 0; su < 2; su++) {
                td_multidir_params p = td_multidir_defaults();
                td_ctx cx;
                double worst = 0, z;
                long cells = 0, tents = 0;
                td_ctx_init(&cx);
                p.interval = 10;
                p.weight = (td_multidir_weight)m;
                p.ndir = nd;
                p.summit = su;
                g = td_grid_f32_new(w, h, NULL);
                g1 = td_grid_f32_new(w, h, NULL);
                for (t = 0; t < 2; t++) {
                    td_grid_f32 *o = t ? g : g1;
                    omp_set_num_threads(t + 1);
                    memcpy(o->data, a->data,
                           (size_t)h * a->stride * sizeof *o->data);
                    TT_CHECK(td_multidir_summit(o, &p, NULL, &cx) == 0);
                }
                omp_set_num_threads(omp_get_num_procs());
                TT_CHECK(memcmp(g->data, g1->data,
                                (size_t)h * a->stride * sizeof *g->data) == 0);
                td_grid_f32_free(g1);
                for (y = 0; y < h; y++)
                    for (x = 0; x < w; x++) {
                        if (!isnan(TD_AT(a, x, y)))
                            TT_CHECK(TD_AT(g, x, y) == TD_AT(a, x, y));
                        else if (brute_summit(a, x, y, &p, &z)) {
                            cells++;
                            worst = fmax(worst, fabs(TD_AT(g, x, y) - z));
                            tents += fmod(z, 10.0) != 0;
                        } else
                            TT_CHECK(isnan(TD_AT(g, x, y)));
                    }
                TT_CHECKF(worst < 1e-3 && cells > w * h / 2 &&
                              (!su || tents > 100),
                          "weight %d, %d dirs, summit %d: max |d| %g over "
                          "%ld cells (%ld off the levels)",
                          m, nd, su, worst, cells, tents);
                td_grid_f32_free(g);
            }
    td_grid_f32_free(a);
}

/* A grid tall enough for the sweep's row bands (multidir_sweep.c: 16 bands
 * from 1024 rows), anchors sparse enough that spans cross the bands'
 * edges: every cell as the brute force has it, and the same bytes on one
 * thread and two. */
static void test_multidir_bands(void)
{
    int w = 61, h = 1100, x, y, nd, t;
    td_grid_f32 *a = td_grid_f32_new(w, h, NULL), *g[2];
    unsigned s = 777;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            s = s * 1103515245u + 12345u;
            TD_AT(a, x, y) = (s >> 16) % 1000 < 15
                                 ? (float)(10 * ((s >> 8) % 7))
                                 : NAN;
        }
    for (nd = 2; nd <= 4; nd += 2) {
        td_multidir_params p = td_multidir_defaults();
        double worst = 0, z;
        long cells = 0;
        p.interval = 10;
        p.ndir = nd;
        p.summit = 0;
        for (t = 0; t < 2; t++) {
            omp_set_num_threads(t + 1);
            g[t] = td_grid_f32_new(w, h, NULL);
            memcpy(g[t]->data, a->data,
                   (size_t)h * a->stride * sizeof *a->data);
            TT_CHECK(td_multidir_sweep(g[t], &p, NULL, NULL) == 0);
        }
        omp_set_num_threads(omp_get_num_procs());
        TT_CHECK(memcmp(g[0]->data, g[1]->data,
                        (size_t)h * a->stride * sizeof *a->data) == 0);
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++)
                if (isnan(TD_AT(a, x, y)) &&
                    brute_cell(a, x, y, nd, p.weight, &z)) {
                    cells++;
                    worst = fmax(worst, fabs(TD_AT(g[1], x, y) - z));
                }
        TT_CHECKF(worst < 1e-3 && cells > w * h / 2,
                  "%d dirs: max |d| %g over %ld cells", nd, worst, cells);
        td_grid_f32_free(g[0]);
        td_grid_f32_free(g[1]);
    }
    td_grid_f32_free(a);
}

/* td_interp_lines_beside: a plane z = x cut into two sheets at x = 100.
 * Alone, the left sheet ends 9 columns past its last line (nodata or a
 * guess); with the right sheet's lines beside it, those columns are the
 * plane, exactly, and the right sheet's first columns likewise: the two
 * DEMs meet at the cut. */
static void test_beside(void)
{
    int w = 203, h = 157, cut = 100, x, y, s;
    td_lines *all = plane_lines(w, h, 1), *side[2];
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *g[2] = {NULL, NULL}, *alone = NULL;
    td_ctx cx;
    size_t i, k;
    double worst = 0, worst_alone = 0;
    td_ctx_init(&cx);
    for (s = 0; s < 2; s++) { /* each sheet's own lines, in its frame */
        side[s] = td_lines_new(NULL);
        for (i = 0; i < all->n; i++)
            if ((all->v[i].xy[0] < cut) == (s == 0)) {
                td_lines_append_copy(side[s], &all->v[i], NULL);
                for (k = 0; s && k < side[s]->v[side[s]->n - 1].n; k++)
                    side[s]->v[side[s]->n - 1].xy[2 * k] -= cut;
            }
    }
    {   /* the other sheet's lines in each sheet's frame; one line without
           a height and one far beyond the margin are left out */
        td_lines *b0 = td_lines_copy(side[1], NULL), *b1 = td_lines_copy(side[0], NULL);
        td_line *l;
        for (i = 0; i < b0->n; i++)
            for (k = 0; k < b0->v[i].n; k++)
                b0->v[i].xy[2 * k] += cut;
        for (i = 0; i < b1->n; i++)
            for (k = 0; k < b1->v[i].n; k++)
                b1->v[i].xy[2 * k] -= cut;
        l = td_lines_add(b0, NULL);
        td_line_push(l, 150.5, 1, NULL), td_line_push(l, 150.5, h - 1, NULL);
        l = td_lines_add(b0, NULL);
        l->has_height = 1, l->height = 1e4;
        td_line_push(l, 5000, 1, NULL), td_line_push(l, 5000, h - 1, NULL);
        TT_CHECK(td_interp_lines_beside(side[0], b0, 64, cut, h, &p, &g[0],
                                        &cx) == 0);
        TT_CHECK(td_interp_lines_beside(side[1], b1, 64, w - cut, h, &p,
                                        &g[1], &cx) == 0);
        TT_CHECK(td_interp_lines(side[0], cut, h, &p, &alone, &cx) == 0);
        td_lines_free(b0), td_lines_free(b1);
    }
    if (!g[0] || !g[1] || !alone)
        goto done;
    TT_CHECK(g[0]->w == cut && g[0]->h == h && g[1]->w == w - cut);
    for (y = 0; y < h; y++)
        for (x = 91; x < cut; x++) { /* past the left sheet's last line */
            float a = TD_AT(alone, x, y), b = TD_AT(g[0], x, y);
            worst_alone = fmax(worst_alone, a == alone->nodata ? INFINITY
                                                               : fabs(a - x));
            worst = fmax(worst, b == g[0]->nodata ? INFINITY : fabs(b - x));
        }
    for (y = 0; y < h; y++)
        for (x = 0; x < 10; x++) {
            float b = TD_AT(g[1], x, y);
            worst = fmax(worst, b == g[1]->nodata ? INFINITY
                                                  : fabs(b - (x + cut)));
        }
    TT_CHECKF(worst < 1e-3, "with the neighbour beside: max error %g", worst);
    TT_CHECKF(worst_alone > 1, "alone: max error %g (the test sees nothing)",
              worst_alone);
done:
    td_grid_f32_free(g[0]), td_grid_f32_free(g[1]), td_grid_f32_free(alone);
    td_lines_free(side[0]), td_lines_free(side[1]), td_lines_free(all);
}

int main(void)
{
    TT_RUN(test_rasterise_4connected);
    TT_RUN(test_interval);
    TT_RUN(test_beside);
    TT_RUN(test_plane_exact);
    TT_RUN(test_plane_tilted);
    TT_RUN(test_cone);
    TT_RUN(test_hills_multidir_beats_scanline);
    TT_RUN(test_saddle);
    TT_RUN(test_smooth_bands);
    TT_RUN(test_multidir_brute);
    TT_RUN(test_summit_beats_flat);
    TT_RUN(test_summit_capped);
    TT_RUN(test_multidir_threads);
    TT_RUN(test_rasterise_bands);
    TT_RUN(test_multidir_bands);
    TT_RUN(test_multidir_summit);
    TT_RUN(test_take);
    TT_RUN(test_step);
    TT_RUN(test_single_ring);
    TT_RUN(test_bad_input);
    TT_RUN(test_line_across);
    TT_RUN(test_gdalinfo_stats);
    return tt_summary();
}
