/* test_insolation.c: the insolation stage (src/sun/insolation.c) against known
 * truths: the analytic clear-sky day on a flat plane, a wall's exact
 * shadow, south faces against north faces (north = row 0), the horizon
 * method against the hidden-surface reference, and the reference
 * converging as its viewpoint count m grows. */
#include "tests/tt.h"

#include "src/sun/sun.h"
#include "src/io/io.h"

#include <tiffio.h>

#include <stdlib.h>
#include <string.h>

#define DEG (M_PI / 180.0)

static td_grid_f32 *flat(int w, int h, float z)
{
    td_grid_f32 *g = td_grid_f32_new(w, h, NULL);
    size_t i;
    for (i = 0; i < (size_t)w * h; i++)
        g->data[i] = z;
    return g;
}

/* Two Gaussian hills and a rim on a 1-cell grid: smooth relief for
 * comparing the methods. */
static td_grid_f32 *hills(int n)
{
    td_grid_f32 *g = flat(n, n, 0.0f);
    int x, y;
    for (y = 0; y < n; y++)
        for (x = 0; x < n; x++) {
            double a = (x - 0.35 * n) / (0.12 * n), b = (y - 0.4 * n) / (0.15 * n);
            double c = (x - 0.7 * n) / (0.1 * n), d = (y - 0.65 * n) / (0.2 * n);
            double r = hypot(x - 0.5 * n, y - 0.5 * n) / (0.45 * n);
            TD_AT(g, x, y) = (float)(0.3 * n * exp(-(a * a + b * b)) +
                                     0.2 * n * exp(-(c * c + d * d)) +
                                     0.1 * n * exp(-(r - 1) * (r - 1) * 40));
        }
    return g;
}

/* The flat plane's day, integrated independently of the stage: the same
 * clear-sky model written out in the hour angle w (sin e = sin phi sin d +
 * cos phi cos d cos w), Simpson's rule with 200000 intervals between
 * sunrise and sunset (cos w0 = -tan phi tan d).  Wh/m^2. */
static double flat_truth(double lat, int day)
{
    double phi = lat * DEG, d = 23.45 * sin(2 * M_PI * (284.0 + day) / 365.0);
    double i0 = 1367.0 * (1 + 0.033 * cos(2 * M_PI * day / 365.0));
    double cw0 = -tan(phi) * tan(d * DEG), w0, sum = 0.0, hstep;
    int n = 200000, k;
    d *= DEG;
    w0 = cw0 <= -1 ? M_PI : cw0 >= 1 ? 0.0 : acos(cw0);
    hstep = 2 * w0 / n;
    for (k = 0; k <= n; k++) {
        double w = -w0 + k * hstep;
        double se = sin(phi) * sin(d) + cos(phi) * cos(d) * cos(w), g = 0.0;
        if (se > 0) {
            double t = pow(0.7, 1.0 / se);
            g = i0 * t * se + 0.3 * (1 - t) * i0 * se;
        }
        sum += g * (k == 0 || k == n ? 1 : k % 2 ? 4 : 2);
    }
    /* radians of hour angle -> hours: 24 h per 2 pi */
    return sum * hstep / 3.0 * 24.0 / (2 * M_PI);
}

static td_insol_result *run(const td_grid_f32 *dem, td_insol_params *p)
{
    td_insol_result *r = NULL;
    td_ctx cx;
    td_ctx_init(&cx);
    if (td_insolation_run(dem, p, &r, &cx) != 0)
        fprintf(stderr, "  run failed: %s\n", td_errmsg(&cx));
    return r;
}

static void test_sun_path(void)
{
    double s[3];
    TT_NEAR(td_sun_declination(172), 23.45, 0.01);
    TT_NEAR(td_sun_declination(355), -23.45, 0.02);
    td_sun_vector(40.0, 172, 12.0, s); /* noon: due south, e = 90-40+23.45 */
    TT_NEAR(s[0], 0.0, 1e-12);
    TT_CHECK(s[1] < 0);
    TT_NEAR(asin(s[2]) / DEG, 90 - 40 + td_sun_declination(172), 1e-9);
    td_sun_vector(40.0, 172, 8.0, s);  /* morning: in the east */
    TT_CHECK(s[0] > 0 && s[2] > 0);
    td_sun_vector(-40.0, 172, 12.0, s); /* southern winter: due north */
    TT_CHECK(s[1] > 0);
    TT_NEAR(s[0] * s[0] + s[1] * s[1] + s[2] * s[2], 1.0, 1e-12);
}

/* Flat plane: every cell equals the analytic day within 0.5 %, sky view
 * is 1, for both methods, several latitudes and days. */
static void test_flat_plane(void)
{
    static const double lat[] = {40.0, 40.0, 0.0, -65.0, 39.5};
    static const int day[] = {172, 355, 80, 10, 172};
    td_grid_f32 *dem = flat(32, 24, 100.0f);
    int c, m;
    for (c = 0; c < 5; c++)
        for (m = 0; m < 2; m++) {
            td_insol_params p = td_insol_defaults();
            td_insol_result *r;
            double truth = flat_truth(lat[c], day[c]), worst = 0, sv = 0;
            size_t i;
            p.latitude = lat[c];
            p.day = day[c];
            p.method = m ? TD_INSOL_HIDDEN_SURFACE : TD_INSOL_HORIZON;
            p.viewpoints = 256;
            if (!(r = run(dem, &p))) {
                TT_CHECK(0);
                continue;
            }
            for (i = 0; i < 32 * 24; i++) {
                worst = fmax(worst, fabs(r->total->data[i] - truth) / truth);
                sv = fmax(sv, fabs(r->skyview->data[i] - 1.0));
            }
            TT_CHECKF(worst < 0.005, "lat %g day %d method %d: worst %.4f%% "
                      "of %.1f Wh/m2", lat[c], day[c], m, 100 * worst, truth);
            TT_CHECKF(sv < 1e-6, "sky view off by %g", sv);
            td_insol_result_free(r);
        }
    td_grid_f32_free(dem);
}

/* A north-south wall of height 10 at column 40 on flat ground; sun from
 * azimuth 90 and 120 at elevation 35: a cell at d columns west of the
 * wall is in shadow exactly when 10 / (d / sin az) > tan 35. */
static void test_wall_shadow(void)
{
    static const double azs[] = {90.0, 120.0};
    td_grid_f32 *dem = flat(64, 64, 0.0f), *bands[36];
    td_grid_u8 *vis = td_grid_u8_new(64, 64, NULL);
    td_horizon_params hp = td_horizon_defaults();
    td_ctx cx;
    int i, x, y, a, bad_h = 0, bad_z = 0, checked = 0;
    td_ctx_init(&cx);
    for (y = 0; y < 64; y++)
        TD_AT(dem, 40, y) = 10.0f;
    for (i = 0; i < 36; i++)
        bands[i] = td_grid_f32_new(64, 64, NULL);
    TT_CHECK(td_horizon_sweep(dem, &hp, bands, &cx) == 0);
    for (a = 0; a < 2; a++) {
        double sa = sin(azs[a] * DEG), ca = cos(azs[a] * DEG);
        TT_CHECK(td_insol_visibility(dem, 1.0, azs[a], 35.0, vis, &cx) == 0);
        for (y = 0; y < 64; y++)
            for (x = 0; x < 40; x++) {
                double d = 40 - x, run_ = d / sa;
                int shadow = 10.0 / run_ > tan(35 * DEG), hs;
                if (y + d * (-ca / sa) > 62) /* ray leaves at the bottom */
                    continue;
                checked++;
                hs = 35.0 <= td_insol_horizon_at(bands, 36,
                                                 (size_t)y * 64 + x, azs[a]);
                bad_h += hs != shadow;
                bad_z += (!TD_AT(vis, x, y)) != shadow;
            }
        for (y = 0; y < 64; y++)    /* east of the wall: always lit */
            for (x = 41; x < 64; x++)
                bad_z += !TD_AT(vis, x, y);
    }
    TT_CHECK(checked > 3000);
    TT_CHECKF(bad_h == 0, "horizon: %d cells wrong", bad_h);
    TT_CHECKF(bad_z == 0, "hidden-surface: %d cells wrong", bad_z);
    for (i = 0; i < 36; i++)
        td_grid_f32_free(bands[i]);
    td_grid_f32_free(dem);
    td_grid_u8_free(vis);
}

/* An east-west ridge, asymmetric (crest at row 24: short north face, long
 * south face, both of slope 0.6; north = row 0): at 40N on days 172 and
 * 355 the south face gets more direct sun than the north face, at 40S
 * less.  A north/south swap anywhere between the horizon and the sun code
 * fails this. */
static void test_south_face(void)
{
    static const double lat[] = {40.0, 40.0, -40.0, -40.0};
    static const int day[] = {172, 355, 172, 355};
    td_grid_f32 *dem = flat(48, 64, 0.0f);
    int x, y, c, m;
    for (y = 0; y < 64; y++)
        for (x = 0; x < 48; x++)
            TD_AT(dem, x, y) = (float)(y <= 24 ? 0.6 * y : 0.6 * (48 - y));
    for (c = 0; c < 4; c++)
        for (m = 0; m < 2; m++) {
            td_insol_params p = td_insol_defaults();
            td_insol_result *r;
            double north, south;
            p.latitude = lat[c];
            p.day = day[c];
            p.method = m ? TD_INSOL_HIDDEN_SURFACE : TD_INSOL_HORIZON;
            p.viewpoints = 256;
            if (!(r = run(dem, &p))) {
                TT_CHECK(0);
                continue;
            }
            north = TD_AT(r->direct, 24, 12); /* north face, mid-slope */
            south = TD_AT(r->direct, 24, 40); /* south face */
            TT_CHECKF(lat[c] > 0 ? south > 1.1 * north : north > 1.1 * south,
                      "lat %g day %d method %d: north %.0f south %.0f",
                      lat[c], day[c], m, north, south);
            td_insol_result_free(r);
        }
    td_grid_f32_free(dem);
}

/* Statistics of a against b over the grid: mean and max |a - b|, and the
 * mean relative difference. */
static void diff_stats(const td_grid_f32 *a, const td_grid_f32 *b,
                       double *mean, double *max, double *rel)
{
    size_t i, n = (size_t)a->w * a->h;
    *mean = *max = *rel = 0.0;
    for (i = 0; i < n; i++) {
        double d = fabs((double)a->data[i] - b->data[i]);
        *mean += d;
        *max = fmax(*max, d);
        *rel += d / fmax(1e-9, fabs(b->data[i]));
    }
    *mean /= n;
    *rel /= n;
}

/* Horizon (k = 64) against hidden-surface (m = 1024) on 48 x 48 hills:
 * sky view within 0.03 (mean and 99th percentile proxy: max 0.08), the
 * day's total within 3 % on average. */
static void test_methods_agree(void)
{
    td_grid_f32 *dem = hills(48);
    td_insol_params p = td_insol_defaults();
    td_insol_result *h, *z;
    double mean, max, rel;
    p.latitude = 40.0;
    p.day = 100;
    p.directions = 64;
    h = run(dem, &p);
    p.method = TD_INSOL_HIDDEN_SURFACE;
    p.viewpoints = 1024;
    z = run(dem, &p);
    TT_CHECK(h && z);
    if (h && z) {
        TT_CHECK(z->az_count == 64 && z->el_count == 16);
        diff_stats(z->skyview, h->skyview, &mean, &max, &rel);
        fprintf(stderr, "  sky view: mean |d| %.4f max %.4f\n", mean, max);
        TT_CHECKF(mean < 0.03 && max < 0.1, "mean %g max %g", mean, max);
        diff_stats(z->total, h->total, &mean, &max, &rel);
        fprintf(stderr, "  total: mean rel %.3f%% max %.1f Wh/m2\n",
                100 * rel, max);
        TT_CHECKF(rel < 0.03, "mean relative %g", rel);
    }
    td_insol_result_free(h);
    td_insol_result_free(z);
    td_grid_f32_free(dem);
}

/* The reference converges: with m = 64, 256, 1024 viewpoints its mean
 * sky-view error against a fine horizon sweep (k = 180) falls. */
static void test_convergence(void)
{
    static const int ms[] = {64, 256, 1024};
    td_grid_f32 *dem = hills(40);
    td_insol_params p = td_insol_defaults();
    td_insol_result *ref, *z;
    double mean, max, rel, err[3] = {0, 0, 0};
    int i;
    p.latitude = 40.0;
    p.directions = 180;
    ref = run(dem, &p);
    TT_CHECK(ref != NULL);
    p.method = TD_INSOL_HIDDEN_SURFACE;
    for (i = 0; ref && i < 3; i++) {
        p.viewpoints = ms[i];
        if (!(z = run(dem, &p)))
            continue;
        diff_stats(z->skyview, ref->skyview, &mean, &max, &rel);
        err[i] = mean;
        fprintf(stderr, "  m = %4d: sky view mean |d| %.4f\n", ms[i], mean);
        td_insol_result_free(z);
    }
    TT_CHECKF(err[1] < err[0] && err[2] < err[1], "%g %g %g", err[0],
              err[1], err[2]);
    TT_CHECK(err[2] < 0.02);
    td_insol_result_free(ref);
    td_grid_f32_free(dem);
}

static void test_nodata_and_bad_params(void)
{
    td_grid_f32 *dem = hills(24);
    td_insol_params p = td_insol_defaults();
    td_insol_result *r = NULL;
    td_ctx cx;
    int m;
    dem->has_nodata = 1;
    dem->nodata = -1.0f;
    TD_AT(dem, 5, 7) = -1.0f;
    for (m = 0; m < 2; m++) {
        p.method = m ? TD_INSOL_HIDDEN_SURFACE : TD_INSOL_HORIZON;
        p.viewpoints = 64;
        if (!(r = run(dem, &p))) {
            TT_CHECK(0);
            continue;
        }
        TT_CHECK(TD_AT(r->total, 5, 7) == -1.0f);
        TT_CHECK(TD_AT(r->skyview, 5, 7) == -1.0f);
        TT_CHECK(TD_AT(r->total, 6, 7) > 0 && TD_AT(r->total, 4, 7) > 0);
        td_insol_result_free(r);
    }
    td_ctx_init(&cx);
    p = td_insol_defaults();
    p.latitude = 91;
    TT_CHECK(td_insolation_run(dem, &p, &r, &cx) == TD_EINVAL && !r);
    TT_CHECK(strstr(td_errmsg(&cx), "latitude") != NULL);
    p = td_insol_defaults();
    p.day = 367;
    td_ctx_clear(&cx);
    TT_CHECK(td_insolation_run(dem, &p, &r, &cx) == TD_EINVAL);
    p.day = 0;
    td_ctx_clear(&cx);
    TT_CHECK(td_insolation_run(dem, &p, &r, &cx) == TD_EINVAL);
    p = td_insol_defaults();
    p.step_minutes = 0;
    td_ctx_clear(&cx);
    TT_CHECK(td_insolation_run(dem, &p, &r, &cx) == TD_EINVAL);
    td_grid_f32_free(dem);
}

/* A finer time step changes the flat day by under 0.1 %; the polar night
 * is dark and the polar day is lit around the clock. */
static void test_steps_and_poles(void)
{
    td_grid_f32 *dem = flat(8, 8, 0.0f);
    td_insol_params p = td_insol_defaults();
    td_insol_result *a, *b;
    p.latitude = 50;
    p.step_minutes = 30;
    a = run(dem, &p);
    p.step_minutes = 2;
    b = run(dem, &p);
    TT_CHECK(a && b);
    if (a && b)
        TT_NEAR(a->total->data[0] / b->total->data[0], 1.0, 0.002);
    td_insol_result_free(a);
    td_insol_result_free(b);
    p.latitude = 80;
    p.day = 355;
    a = run(dem, &p);
    p.day = 172;
    b = run(dem, &p);
    TT_CHECK(a && b);
    if (a && b) {
        TT_CHECK(a->total->data[0] == 0.0f);
        TT_NEAR(b->total->data[0] / flat_truth(80, 172), 1.0, 0.005);
    }
    td_insol_result_free(a);
    td_insol_result_free(b);
    td_grid_f32_free(dem);
}

/* --horizons' writer: three bands read back through
 * libtiff as three separate float32 planes, values and nodata intact; a
 * size mismatch fails and leaves nothing. */
static void test_bands_writer(void)
{
    td_grid_f32 *b[3];
    char path[512], bad[512];
    td_ctx cx;
    TIFF *tif;
    uint16_t spp = 0, planar = 0, fmt = 0;
    float row[7];
    int i, x, y, same = 1;
    td_ctx_init(&cx);
    for (i = 0; i < 3; i++) {
        b[i] = flat(7, 5, 0.0f);
        b[i]->has_nodata = 1;
        b[i]->nodata = -9999.0f;
        for (y = 0; y < 5; y++)
            for (x = 0; x < 7; x++)
                TD_AT(b[i], x, y) = (float)(100 * i + 10 * y + x);
    }
    TD_AT(b[1], 3, 2) = -9999.0f;
    snprintf(path, sizeof path, "%s/h.tif", tt_tmpdir());
    TIFFSetWarningHandler(NULL); /* GDAL_NODATA is unknown to libtiff */
    TT_CHECK(td_geotiff_write_bands_f32(path, b, 3, NULL, &cx) == 0);
    tif = TIFFOpen(path, "r");
    TT_CHECK(tif != NULL);
    if (tif) {
        TIFFGetField(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
        TIFFGetField(tif, TIFFTAG_PLANARCONFIG, &planar);
        TIFFGetField(tif, TIFFTAG_SAMPLEFORMAT, &fmt);
        TT_CHECK(spp == 3 && planar == PLANARCONFIG_SEPARATE &&
                 fmt == SAMPLEFORMAT_IEEEFP);
        for (i = 0; i < 3; i++)
            for (y = 0; y < 5; y++) {
                TT_CHECK(TIFFReadScanline(tif, row, (uint32_t)y,
                                          (uint16_t)i) == 1);
                for (x = 0; x < 7; x++)
                    same &= row[x] == TD_AT(b[i], x, y);
            }
        TT_CHECK(same);
        TIFFClose(tif);
    }
    td_grid_f32_free(b[2]);
    b[2] = flat(6, 5, 0.0f);
    snprintf(bad, sizeof bad, "%s/bad.tif", tt_tmpdir());
    TT_CHECK(td_geotiff_write_bands_f32(bad, b, 3, NULL, &cx) == TD_EINVAL);
    TT_CHECK(fopen(bad, "rb") == NULL);
    for (i = 0; i < 3; i++)
        td_grid_f32_free(b[i]);
}

int main(void)
{
    TT_RUN(test_sun_path);
    TT_RUN(test_flat_plane);
    TT_RUN(test_wall_shadow);
    TT_RUN(test_south_face);
    TT_RUN(test_methods_agree);
    TT_RUN(test_convergence);
    TT_RUN(test_nodata_and_bad_params);
    TT_RUN(test_steps_and_poles);
    TT_RUN(test_bands_writer);
    return tt_summary();
}
