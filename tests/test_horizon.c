/* test_horizon.c: the profile sweep (src/sun/horizon.c) against a brute-force
 * ray march over the bilinear surface (exact on every bilinear piece, and
 * itself checked against a finely sampled march) on random and synthetic
 * DEMs up to 200 x 200 for 8 and 36 directions, and against shapes whose
 * horizons are known exactly (a wall, a tower beyond the Earth's
 * curvature, north = row 0). */
#include "tests/tt.h"

#include "src/sun/sun.h"
#include "tests/util/raymarch.h"

#include <stdlib.h>
#include <string.h>

/* ---- brute force: march a ray from the cell centre ------------------- */

static double bilinear(const td_grid_f32 *g, double x, double y)
{
    int x0 = (int)floor(x), y0 = (int)floor(y), x1, y1;
    double fx = x - x0, fy = y - y0;
    x1 = x0 + 1 < g->w ? x0 + 1 : x0;
    y1 = y0 + 1 < g->h ? y0 + 1 : y0;
    return (1 - fy) * ((1 - fx) * TD_AT(g, x0, y0) + fx * TD_AT(g, x1, y0)) +
           fy * ((1 - fx) * TD_AT(g, x0, y1) + fx * TD_AT(g, x1, y1));
}

/* Tangent from (x, y, z0) to the surface at ray parameter t (cells), or
 * -1e30 when that point is off the grid. */
static double ray_slope(const td_grid_f32 *g, int x, int y, double z0,
                        double dx, double dy, double t, double cs)
{
    double px = x + t * dx, py = y + t * dy;
    if (t <= 0 || px < -1e-9 || py < -1e-9 || px > g->w - 1 + 1e-9 ||
        py > g->h - 1 + 1e-9)
        return -1e30;
    px = px < 0 ? 0 : px;
    py = py < 0 ? 0 : py;
    return (bilinear(g, px, py) - z0) / (t * cs);
}

/* Sampled ray march (horizon angle, degrees >= 0, of cell (x, y) towards
 * azimuth az): samples at most `step` cells apart (closer near the cell)
 * plus every grid-line crossing.  Slow; used to check tr_exact_march. */
static double sampled_march(const td_grid_f32 *g, int x, int y, double az,
                            double cs, double step)
{
    double dx = sin(az * M_PI / 180), dy = -cos(az * M_PI / 180), t, best = 0;
    double z0 = TD_AT(g, x, y), s;
    int k, n = g->w > g->h ? g->w : g->h;
    for (t = 0.001; t < 2.0 * n; t += fmin(step, 0.002 + 0.1 * t))
        if ((s = ray_slope(g, x, y, z0, dx, dy, t, cs)) > best)
            best = s;
    for (k = -n; k <= n; k++) {
        if (fabs(dx) > 1e-12 &&
            (s = ray_slope(g, x, y, z0, dx, dy, k / dx, cs)) > best)
            best = s;
        if (fabs(dy) > 1e-12 &&
            (s = ray_slope(g, x, y, z0, dx, dy, k / dy, cs)) > best)
            best = s;
    }
    return atan(best) * 180 / M_PI;
}

/* ---- test terrains ----------------------------------------------------- */

static unsigned lcg(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* Smoothed white noise: box-blurred `passes` times, scaled to `relief`. */
static td_grid_f32 *random_dem(int w, int h, unsigned seed, int passes,
                               double relief)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    float *tmp = malloc(sizeof(float) * (size_t)w * h);
    int x, y, k;
    float lo = 1e30f, hi = -1e30f;
    for (k = 0; k < w * h; k++)
        g->data[k] = (float)(lcg(&seed) % 10000) / 10000.0f;
    for (k = 0; k < passes; k++) {
        for (y = 0; y < h; y++)
            for (x = 0; x < w; x++) {
                double s = 0;
                int n = 0, i, j;
                for (j = -2; j <= 2; j++)
                    for (i = -2; i <= 2; i++)
                        if (x + i >= 0 && x + i < w && y + j >= 0 &&
                            y + j < h) {
                            s += TD_AT(g, x + i, y + j);
                            n++;
                        }
                tmp[y * w + x] = (float)(s / n);
            }
        memcpy(g->data, tmp, sizeof(float) * (size_t)w * h);
    }
    for (k = 0; k < w * h; k++) {
        lo = g->data[k] < lo ? g->data[k] : lo;
        hi = g->data[k] > hi ? g->data[k] : hi;
    }
    for (k = 0; k < w * h; k++)
        g->data[k] = (float)((g->data[k] - lo) / (hi - lo) * relief);
    free(tmp);
    return g;
}

/* Two Gaussian hills and a crater rim on a tilt. */
static td_grid_f32 *synthetic_dem(int w, int h)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    int x, y;
    for (y = 0; y < h; y++)
        for (x = 0; x < w; x++) {
            double a = hypot(x - 0.3 * w, y - 0.4 * h), b = hypot(x - 0.7 * w,
                                                                 y - 0.6 * h);
            double r = hypot(x - 0.5 * w, y - 0.2 * h);
            TD_AT(g, x, y) = (float)(30 * exp(-a * a / 60.0) +
                                     20 * exp(-b * b / 120.0) +
                                     8 * exp(-(r - 8) * (r - 8) / 6.0) +
                                     0.1 * x);
        }
    return g;
}

/* Smooth-ish random terrain of a realistic size plus a mound: smoothed
 * noise (relief `relief`) and height `mound` * (1 - r^2)^2 within 0.3 n of
 * (0.55 n, 0.45 n). */
static td_grid_f32 *mound_dem(int n, unsigned seed, int passes, double relief,
                              double mound)
{
    td_grid_f32 *g = random_dem(n, n, seed, passes, relief);
    int x, y;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            double r = hypot(x - 0.55 * n, y - 0.45 * n) / (0.3 * n);
            if (r < 1)
                TD_AT(g, x, y) += (float)(mound * (1 - r * r) * (1 - r * r));
        }
    return g;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Sweep vs exact ray march over every cell and k directions: p95 and max
 * of the absolute angle difference. */
static void compare(const td_grid_f32 *g, int k, double cs, double *p95,
                    double *mx)
{
    td_horizon_params p = td_horizon_defaults();
    td_grid_f32 *out = td_grid_f32_new(g->w, g->h, NULL);
    size_t n = (size_t)g->w * g->h;
    double *err = malloc(sizeof(double) * n * k);
    int d;
    p.cell_size = cs;
    for (d = 0; d < k; d++) {
        double az = 360.0 * d / k;
        int y;
        TT_CHECK(td_horizon_direction(g, az, &p, out, NULL) == 0);
#pragma omp parallel for schedule(dynamic, 4)
        for (y = 0; y < g->h; y++) {
            int x;
            for (x = 0; x < g->w; x++)
                err[n * d + (size_t)y * g->w + x] = fabs(
                    TD_AT(out, x, y) - tr_exact_march(g, x, y, az, cs));
        }
    }
    qsort(err, n * k, sizeof *err, cmp_d);
    *p95 = err[(size_t)(0.95 * (n * k - 1))];
    *mx = err[n * k - 1];
    free(err);
    td_grid_f32_free(out);
}

/* Issue 7's targets: p95 < 0.5 deg and max < 2 deg for 8 and 36
 * directions. */
static void check_against_brute(td_grid_f32 *g, double cs, const char *what)
{
    static const int ks[] = {8, 36};
    int i;
    for (i = 0; i < 2; i++) {
        double p95, mx;
        compare(g, ks[i], cs, &p95, &mx);
        fprintf(stderr, "  %s, %d directions: p95 %.3f deg, max %.3f deg\n",
                what, ks[i], p95, mx);
        TT_CHECKF(p95 < 0.5, "%s k=%d p95 %.3f", what, ks[i], p95);
        TT_CHECKF(mx < 2.0, "%s k=%d max %.3f", what, ks[i], mx);
    }
}

/* The exact march is the reference: it must never be below a fine sampled
 * march of the same ray, and hardly above it. */
static void test_reference_march(void)
{
    td_grid_f32 *g = random_dem(30, 26, 5u, 2, 10.0);
    int x, y, d, low = 0, high = 0;
    for (d = 0; d < 12; d++)
        for (y = 0; y < g->h; y += 3)
            for (x = 0; x < g->w; x += 3) {
                double az = d * 30.0 + 7.0;
                double e = tr_exact_march(g, x, y, az, 1.0);
                double s = sampled_march(g, x, y, az, 1.0, 0.05);
                low += e < s - 1e-6;
                high += e > s + 0.05;
            }
    TT_CHECKF(low == 0 && high == 0, "%d below, %d above", low, high);
    td_grid_f32_free(g);
}

static void test_random_vs_brute_force(void)
{
    td_grid_f32 *g = random_dem(45, 37, 7u, 3, 12.0);
    check_against_brute(g, 1.0, "random 45x37");
    td_grid_f32_free(g);
    g = random_dem(36, 36, 99u, 2, 25.0);
    check_against_brute(g, 2.0, "rough random 36x36, cell 2");
    td_grid_f32_free(g);
}

/* Realistic sizes: 200 x 200 random terrain (relief 30, 6 smoothing
 * passes: slopes up to about 60 deg) plus a mound 40 high, and 150 x 120
 * hills and crater with 2 m cells. */
static void test_large_vs_brute_force(void)
{
    td_grid_f32 *g = mound_dem(200, 3u, 6, 30.0, 40.0);
    check_against_brute(g, 1.0, "random + mound 200x200");
    td_grid_f32_free(g);
    g = synthetic_dem(150, 120);
    check_against_brute(g, 2.0, "hills and crater 150x120, cell 2");
    td_grid_f32_free(g);
}

static void test_synthetic_vs_brute_force(void)
{
    td_grid_f32 *g = synthetic_dem(48, 42);
    check_against_brute(g, 1.0, "hills and crater 48x42");
    td_grid_f32_free(g);
}

/* Thin and tiny grids (one row, one column, 2 x 2, 3 x 9, 9 x 3) of white
 * noise (0..10 per cell: slopes up to 84 deg) in 24 directions: no
 * out-of-grid access (make check), and every ray lies in the near field,
 * which is exact (crossings and exact piece peaks): the brute force's
 * answer within 0.05 deg (midpoints instead of peaks: 2.2 deg). */
static void test_thin_grids(void)
{
    static const int sz[][2] = {{1, 7}, {7, 1}, {2, 2}, {3, 9}, {9, 3}, {1, 1}};
    unsigned seed = 11u;
    int i, d, x, y, bad = 0;
    double worst = 0;
    for (i = 0; i < 6; i++) {
        td_grid_f32 *g = td_grid_f32_new(sz[i][0], sz[i][1], NULL);
        td_grid_f32 *out = td_grid_f32_new(sz[i][0], sz[i][1], NULL);
        td_horizon_params p = td_horizon_defaults();
        for (x = 0; x < g->w * g->h; x++)
            g->data[x] = (float)(lcg(&seed) % 1000) / 100.0f;
        for (d = 0; d < 24; d++) {
            TT_CHECK(td_horizon_direction(g, d * 15.0, &p, out, NULL) == 0);
            for (y = 0; y < g->h; y++)
                for (x = 0; x < g->w; x++) {
                    double e = fabs(TD_AT(out, x, y) -
                                    tr_exact_march(g, x, y, d * 15.0, 1.0));
                    worst = e > worst ? e : worst;
                    bad += e > 0.05;
                }
        }
        td_grid_f32_free(out);
        td_grid_f32_free(g);
    }
    fprintf(stderr, "  thin white-noise grids: max %.3f deg\n", worst);
    TT_CHECKF(bad == 0, "%d cell-directions off by more than 0.05 deg", bad);
}

/* North = row 0: a wall along row 10 is the horizon of the cells south of
 * it looking north (band 0 of 4) and of those north of it looking south
 * (band 2); looking east or west they see nothing. */
static void test_north_is_row_0(void)
{
    td_grid_f32 *g = td_grid_f32_new(30, 30, NULL), *b[4];
    td_horizon_params p = td_horizon_defaults();
    int x, i;
    for (x = 0; x < 30; x++)
        TD_AT(g, x, 10) = 5.0f;
    p.directions = 4;
    for (i = 0; i < 4; i++)
        b[i] = td_grid_f32_new(30, 30, NULL);
    TT_CHECK(td_horizon_sweep(g, &p, b, NULL) == 0);
    TT_NEAR(TD_AT(b[0], 15, 20), atan(5.0 / 10) * 180 / M_PI, 1e-4);
    TT_NEAR(TD_AT(b[2], 15, 20), 0.0, 1e-6);
    TT_NEAR(TD_AT(b[2], 15, 5), atan(5.0 / 5) * 180 / M_PI, 1e-4);
    TT_NEAR(TD_AT(b[0], 15, 5), 0.0, 1e-6);
    TT_NEAR(TD_AT(b[1], 15, 20), 0.0, 1e-6);
    TT_NEAR(TD_AT(b[3], 15, 5), 0.0, 1e-6);
    for (i = 0; i < 4; i++)
        td_grid_f32_free(b[i]);
    td_grid_f32_free(g);
}

/* A north-south wall of height H in column 40 of a flat plane: looking
 * east, a cell d cells west of it sees exactly atan(H / d); the sun at
 * elevation e in the east leaves in shadow exactly the cells with
 * d < H / tan e (shadow length H / tan e). */
static void test_wall_shadow_length(void)
{
    const int w = 60, h = 9, wx = 40;
    const double H = 10.0, cs = 0.5, e = 35.0;
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL), *out;
    td_horizon_params p = td_horizon_defaults();
    int x, y, shadowed = 0, bad = 0;
    double len = H / tan(e * M_PI / 180);
    out = td_grid_f32_new(w, h, NULL);
    p.cell_size = cs;
    for (y = 0; y < h; y++)
        TD_AT(g, wx, y) = (float)H;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == 0);
    for (x = 0; x < wx; x++) {
        double d = (wx - x) * cs, want = atan(H / d) * 180 / M_PI;
        for (y = 0; y < h; y++)
            bad += fabs(TD_AT(out, x, y) - want) > 1e-3;
        shadowed += TD_AT(out, x, h / 2) > e;
    }
    for (x = wx + 1; x < w; x++)
        bad += TD_AT(out, x, h / 2) != 0.0f;
    TT_CHECKF(bad == 0, "%d cells off the exact angle", bad);
    TT_NEAR(shadowed * cs, len, cs);
    /* along the diagonal (azimuth 45: north-east) a cell of the bottom row
     * d columns west of the wall meets it d rows up, d * sqrt(2) * cs away */
    TT_CHECK(td_horizon_direction(g, 45.0, &p, out, NULL) == 0);
    for (x = wx - 8, bad = 0; x < wx; x++) {
        y = h - 1;
        {
            double d = (wx - x) * sqrt(2.0) * cs;
            bad += fabs(TD_AT(out, x, y) - atan(H / d) * 180 / M_PI) > 1e-3;
        }
    }
    TT_CHECKF(bad == 0, "diagonal: %d cells off", bad);
    td_grid_f32_free(out);
    td_grid_f32_free(g);
}

/* Flat planes see no horizon; so does any cell at the edge looking out. */
static void test_flat_and_edges(void)
{
    td_grid_f32 *g = td_grid_f32_new(20, 13, NULL), *out;
    td_horizon_params p = td_horizon_defaults();
    int d, k, bad = 0;
    out = td_grid_f32_new(20, 13, NULL);
    for (k = 0; k < 20 * 13; k++)
        g->data[k] = 123.0f;
    for (d = 0; d < 36; d++) {
        TT_CHECK(td_horizon_direction(g, d * 10.0, &p, out, NULL) == 0);
        for (k = 0; k < 20 * 13; k++)
            bad += fabs(out->data[k]) > 1e-6;
    }
    TT_CHECK(bad == 0);
    td_grid_f32_free(out);
    td_grid_f32_free(g);
    /* one cell, one row, one column */
    g = td_grid_f32_new(1, 1, NULL);
    out = td_grid_f32_new(1, 1, NULL);
    TT_CHECK(td_horizon_direction(g, 33.0, &p, out, NULL) == 0);
    TT_CHECK(out->data[0] == 0.0f);
    td_grid_f32_free(g);
    td_grid_f32_free(out);
    g = td_grid_f32_new(5, 1, NULL);
    out = td_grid_f32_new(5, 1, NULL);
    g->data[4] = 1.0f;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == 0);
    TT_NEAR(out->data[0], atan(1 / 4.0) * 180 / M_PI, 1e-4);
    TT_CHECK(td_horizon_direction(g, 80.0, &p, out, NULL) == 0);
    td_grid_f32_free(g);
    td_grid_f32_free(out);
}

/* A 1000 m tower 50 km away on a sea-level plane (cell 1 km): with
 * curvature it appears (1000 - d^2 / 2R) / d high. */
static void test_curvature(void)
{
    td_grid_f32 *g = td_grid_f32_new(60, 3, NULL), *out;
    td_horizon_params p = td_horizon_defaults();
    double d = 50000.0, want;
    out = td_grid_f32_new(60, 3, NULL);
    TD_AT(g, 55, 1) = 1000.0f;
    p.cell_size = 1000.0;
    p.curvature = 1;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == 0);
    want = atan((1000.0 - d * d / (2 * p.earth_radius)) / d) * 180 / M_PI;
    TT_NEAR(TD_AT(out, 5, 1), want, 1e-4);
    p.curvature = 0;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == 0);
    TT_NEAR(TD_AT(out, 5, 1), atan(1000.0 / d) * 180 / M_PI, 1e-4);
    td_grid_f32_free(out);
    td_grid_f32_free(g);
}

/* Nodata cells get nodata and cast no horizon; bad arguments fail cleanly. */
static void test_nodata_and_errors(void)
{
    td_grid_f32 *g = td_grid_f32_new(10, 10, NULL), *out, *small;
    td_horizon_params p = td_horizon_defaults();
    td_ctx cx;
    out = td_grid_f32_new(10, 10, NULL);
    small = td_grid_f32_new(9, 10, NULL);
    g->has_nodata = 1;
    g->nodata = -1.0f;
    TD_AT(g, 5, 5) = -1.0f;
    TD_AT(g, 7, 5) = 50.0f;
    TD_AT(g, 9, 5) = -1.0f;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == 0);
    TT_CHECK(TD_AT(out, 5, 5) == -1.0f && out->has_nodata);
    TT_NEAR(TD_AT(out, 3, 5), atan(50.0 / 4) * 180 / M_PI, 1e-4);
    TT_CHECK(TD_AT(out, 8, 5) == 0.0f);
    td_ctx_init(&cx);
    TT_CHECK(td_horizon_direction(g, 90.0, &p, small, &cx) == TD_EINVAL);
    TT_CHECK(strstr(td_errmsg(&cx), "horizon") != NULL);
    p.cell_size = 0;
    TT_CHECK(td_horizon_direction(g, 90.0, &p, out, NULL) == TD_EINVAL);
    td_grid_f32_free(small);
    td_grid_f32_free(out);
    td_grid_f32_free(g);
}

int main(void)
{
    TT_RUN(test_reference_march);
    TT_RUN(test_random_vs_brute_force);
    TT_RUN(test_synthetic_vs_brute_force);
    TT_RUN(test_large_vs_brute_force);
    TT_RUN(test_thin_grids);
    TT_RUN(test_north_is_row_0);
    TT_RUN(test_wall_shadow_length);
    TT_RUN(test_flat_and_edges);
    TT_RUN(test_curvature);
    TT_RUN(test_nodata_and_errors);
    return tt_summary();
}
