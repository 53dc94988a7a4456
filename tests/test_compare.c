/* test_compare.c: DEM comparison statistics, the difference picture and
 * the profile (cross-section) on hand-made grids with known answers; the shaded-relief renderer (flat and
 * tilted planes, contour overlay, nodata). */
#include "tests/tt.h"

#include "src/compare/compare.h"
#include "src/render/render.h"

#include <math.h>
#include <string.h>

static td_grid_f32 *grid(int w, int h, double (*f)(int, int))
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++)
            TD_AT(g, x, y) = (float)f(x, y);
    return g;
}

static double ramp(int x, int y) { return 0.5 * x + 0.25 * y; }
static double flat(int x, int y) { (void)x; (void)y; return 100; }

static void test_stats_known(void)
{
    td_grid_f32 *a = grid(40, 30, ramp), *b = grid(40, 30, ramp);
    td_compare_stats st;
    int x, y;
    /* a = b + 1 on the left half, b - 1 on the right; one spike of +5 */
    for (y = 0; y < 30; y++)
        for (x = 0; x < 40; x++)
            TD_AT(a, x, y) += x < 20 ? 1 : -1;
    TD_AT(a, 33, 7) = TD_AT(b, 33, 7) + 5;
    TT_CHECK(td_compare_grids(a, b, &st, NULL) == 0);
    TT_CHECK(st.n_both == 1200 && st.n_a == 1200 && st.n_b == 1200);
    TT_NEAR(st.coverage, 1, 1e-12);
    TT_NEAR(st.mae, (1199 + 5) / 1200.0, 1e-6);
    TT_NEAR(st.rmse, sqrt((1199 + 25) / 1200.0), 1e-6);
    TT_NEAR(st.bias, (600 - 599 + 5) / 1200.0, 1e-6);
    TT_NEAR(st.max_abs, 5, 1e-5);
    TT_CHECK(st.max_x == 33 && st.max_y == 7);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

/* Nodata in either grid leaves the cell out; coverage counts the
 * reference's cells that the result covers; NaN counts as no data. */
static void test_nodata_and_coverage(void)
{
    td_grid_f32 *a = grid(10, 10, flat), *b = grid(10, 10, flat);
    td_compare_stats st;
    int x;
    a->has_nodata = b->has_nodata = 1;
    a->nodata = -9999;
    b->nodata = -1;
    for (x = 0; x < 10; x++) {
        TD_AT(a, x, 0) = -9999;  /* result misses row 0 */
        TD_AT(b, x, 9) = -1;     /* reference has no row 9 */
        TD_AT(a, x, 9) = 1e6;    /* so this error never counts */
    }
    TD_AT(a, 4, 4) = NAN;
    TD_AT(a, 5, 5) = 103;
    TT_CHECK(td_compare_grids(a, b, &st, NULL) == 0);
    TT_CHECK(st.n_b == 90 && st.n_a == 89 && st.n_both == 79);
    TT_NEAR(st.coverage, 79.0 / 90, 1e-12);
    TT_NEAR(st.max_abs, 3, 1e-6);
    TT_NEAR(st.bias, 3.0 / 79, 1e-6);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

static void test_size_mismatch(void)
{
    td_grid_f32 *a = grid(10, 10, flat), *b = grid(10, 11, flat);
    td_compare_stats st;
    td_image *im = NULL;
    td_ctx cx;
    td_ctx_init(&cx);
    TT_CHECK(td_compare_grids(a, b, &st, &cx) == TD_EINVAL);
    TT_CHECK(strstr(td_errmsg(&cx), "10 x 10 and 10 x 11") != NULL);
    TT_CHECK(td_compare_diff_image(a, b, 0, &im, NULL) == TD_EINVAL && !im);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

static void test_diff_colours(void)
{
    td_grid_f32 *a = grid(4, 1, flat), *b = grid(4, 1, flat);
    td_image *im = NULL;
    const uint8_t *p;
    a->has_nodata = 1;
    a->nodata = -9999;
    TD_AT(a, 0, 0) = 110;   /* above: red */
    TD_AT(a, 1, 0) = 90;    /* below: blue */
    TD_AT(a, 3, 0) = -9999; /* no data in a: dark grey */
    TT_CHECK(td_compare_diff_image(a, b, 10, &im, NULL) == 0);
    if (!im)
        goto done;
    p = im->data;
    TT_CHECK(p[0] == 255 && p[1] == 0 && p[2] == 0);
    TT_CHECK(p[3] == 0 && p[4] == 0 && p[5] == 255);
    TT_CHECK(p[6] == 255 && p[7] == 255 && p[8] == 255);
    TT_CHECK(p[9] == 90 && p[10] == 90 && p[11] == 90);
done:
    td_image_free(im);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

static double tilt_east(int x, int y) { (void)y; return 2.0 * x; }
static double tilt_west(int x, int y) { (void)y; return -2.0 * x; }

/* Flat ground under a 45 degree sun: cos(45) everywhere.  A slope facing
 * the north-west light is brighter than one facing away. */
static void test_hillshade(void)
{
    td_grid_f32 *f = grid(20, 20, flat), *e = grid(20, 20, tilt_east),
                *w = grid(20, 20, tilt_west);
    td_render_params p = td_render_defaults();
    td_image *a = NULL, *b = NULL, *c = NULL;
    TT_CHECK(td_render_hillshade(f, &p, &a, NULL) == 0);
    TT_CHECK(td_render_hillshade(e, &p, &b, NULL) == 0);
    TT_CHECK(td_render_hillshade(w, &p, &c, NULL) == 0);
    if (a && b && c) {
        size_t mid = 10 * a->stride + 30;
        TT_NEAR(a->data[mid], 255 * cos(M_PI / 4), 1.0);
        TT_CHECK(a->data[mid] == a->data[mid + 1]); /* grey */
        /* east-rising ground faces west, towards the light */
        TT_CHECKF(b->data[mid] > c->data[mid] + 50, "%d vs %d", b->data[mid],
                  c->data[mid]);
    }
    td_image_free(a);
    td_image_free(b);
    td_image_free(c);
    td_grid_f32_free(f);
    td_grid_f32_free(e);
    td_grid_f32_free(w);
}

static double tilt_gentle(int x, int y) { (void)y; return 0.01 * x; }

/* Auto z factor: the 90th percentile slope drawn at 45 degrees, so a
 * steep plane (2 per cell) gets 1/2, a gentle one (0.01) 100, flat 1. */
static void test_auto_zfactor(void)
{
    td_grid_f32 *f = grid(40, 30, flat), *e = grid(40, 30, tilt_east),
                *g = grid(40, 30, tilt_gentle);
    TT_NEAR(td_render_auto_zfactor(e, 1.0), 0.5, 1e-6);
    TT_NEAR(td_render_auto_zfactor(e, 4.0), 2.0, 1e-6);
    TT_NEAR(td_render_auto_zfactor(g, 1.0), 100.0, 1e-3);
    TT_NEAR(td_render_auto_zfactor(f, 1.0), 1.0, 0);
    td_grid_f32_free(f);
    td_grid_f32_free(e);
    td_grid_f32_free(g);
}

/* Contours every 10 on z = 2x: a brown column every 5 cells; nodata pale. */
static void test_contour_overlay_nodata(void)
{
    td_grid_f32 *g = grid(30, 8, tilt_east);
    td_render_params p = td_render_defaults();
    td_image *im = NULL;
    int x, brown = 0;
    g->has_nodata = 1;
    g->nodata = -9999;
    TD_AT(g, 29, 7) = -9999;
    p.interval = 10;
    TT_CHECK(td_render_hillshade(g, &p, &im, NULL) == 0);
    if (!im)
        goto done;
    for (x = 0; x < 29; x++)
        brown += im->data[3 * x] == 140 &&
                 im->data[3 * x + 1] == 70;
    TT_CHECKF(brown == 5, "%d contour cells in row 0", brown);
    TT_CHECK(im->data[7 * im->stride + 3 * 29] == 205);
    p.cellsize = 0;
    td_image_free(im);
    im = NULL;
    TT_CHECK(td_render_hillshade(g, &p, &im, NULL) == TD_EINVAL && !im);
done:
    td_image_free(im);
    td_grid_f32_free(g);
}

static double ramp_x(int x, int y) { (void)y; return 10.0 * x; }
static double ramp_2x(int x, int y) { (void)y; return 20.0 * x; }

/* A profile across two planes (10 x and 20 x per cell): samples at the
 * heights of the cell centres they pass; the picture draws B black and A
 * red where the plot's axes put them; no data along the line: refused. */
static void test_profile(void)
{
    td_grid_f32 *a = grid(50, 20, ramp_x), *b = grid(50, 20, ramp_2x);
    double va[11], vb[11];
    td_image *im = NULL;
    int red = 0, black = 0;
    size_t i;
    TT_CHECK(td_compare_profile(a, b, 5.5, 10.5, 45.5, 10.5, 11, va, vb,
                                NULL) == 0);
    TT_NEAR(va[0], 50, 1e-4);
    TT_NEAR(vb[10], 900, 1e-4);
    TT_NEAR(va[5], 250, 1e-4); /* halfway, x = 25.5: the centre of 25 */
    TT_CHECK(td_compare_profile_image(va, vb, 11, 40, 400, 200, &im, NULL) ==
             0);
    for (i = 0; im && i < (size_t)im->w * im->h; i++) {
        const uint8_t *q = im->data + 3 * i;
        red += q[0] == 200 && q[1] == 30;
        black += q[0] == 0 && q[1] == 0 && q[2] == 0;
    }
    TT_CHECK(red > 300 && black > 300);
    td_image_free(im);
    for (i = 0; i < 11; i++)
        va[i] = vb[i] = NAN;
    TT_CHECK(td_compare_profile_image(va, vb, 11, 40, 400, 200, &im, NULL) ==
             TD_EINVAL);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
}

int main(void)
{
    TT_RUN(test_stats_known);
    TT_RUN(test_profile);
    TT_RUN(test_nodata_and_coverage);
    TT_RUN(test_size_mismatch);
    TT_RUN(test_diff_colours);
    TT_RUN(test_hillshade);
    TT_RUN(test_auto_zfactor);
    TT_RUN(test_contour_overlay_nodata);
    return tt_summary();
}
