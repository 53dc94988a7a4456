/* bench_insolation: a whole day's insolation (40N, day 172, 10-minute
 * steps) on a generated N x N DEM (default 1000, 10 m cells) with the
 * horizon method and 36 directions; horizon against hidden-surface at
 * equal accuracy on a rugged 200 x 200 DEM (1 m cells, ~280 m relief;
 * errors against a 360-direction horizon reference); and, where GRASS is installed, r.slope.aspect +
 * r.sun with its own shadowing on the same DEM file in the same run.
 *
 *   bench_insolation [--topodig PATH] [--dir DIR] [--size N] [--no-grass]
 *
 * Never fails the build. */
#include "samples/gen/gen.h"
#include "src/sun/sun.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static td_grid_f32 *terrain(int n, td_ctx *cx)
{
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    gp.w = gp.h = n;
    if (td_gen_terrain(&gp, &dem, cx) != 0)
        return NULL;
    return dem;
}

/* One run; seconds or -1; *r kept when r is not NULL. */
static double run(const td_grid_f32 *dem, td_insol_method m, int k_or_m,
                  double cs, td_insol_result **r)
{
    td_insol_params p = td_insol_defaults();
    td_insol_result *res = NULL;
    td_ctx cx;
    double t0 = td_now(), s;
    td_ctx_init(&cx);
    p.latitude = 40.0;
    p.day = 172;
    p.cell_size = cs;
    p.method = m;
    p.directions = k_or_m;
    p.viewpoints = k_or_m;
    if (td_insolation_run(dem, &p, &res, &cx) != 0) {
        printf("  failed: %s\n", td_errmsg(&cx));
        return -1;
    }
    s = td_now() - t0;
    if (r)
        *r = res;
    else
        td_insol_result_free(res);
    return s;
}

/* Mean |a - b| of the sky view and mean relative |a - b| of the total. */
static void errors(const td_insol_result *a, const td_insol_result *b,
                   double *sv, double *tot)
{
    size_t i, n = (size_t)a->total->w * a->total->h;
    *sv = *tot = 0;
    for (i = 0; i < n; i++) {
        *sv += fabs(a->skyview->data[i] - b->skyview->data[i]);
        *tot += fabs(a->total->data[i] - b->total->data[i]) /
                fmax(1.0, b->total->data[i]);
    }
    *sv /= n;
    *tot /= n;
}

static void accuracy(void)
{
    static const int ms[] = {144, 576, 1296};
    td_ctx cx;
    td_grid_f32 *dem;
    td_insol_result *ref = NULL, *r = NULL;
    double s, sv, tot, hsv = 0, hs = 0;
    int i;
    td_ctx_init(&cx);
    if (!(dem = terrain(200, &cx)) ||
        run(dem, TD_INSOL_HORIZON, 360, 1.0, &ref) < 0)
        return;
    if ((hs = run(dem, TD_INSOL_HORIZON, 36, 1.0, &r)) > 0) {
        errors(r, ref, &hsv, &tot);
        printf("  200x200 horizon k=36            %6.2f s  sky view err %.4f  "
               "total err %.2f%%\n", hs, hsv, 100 * tot);
        td_insol_result_free(r);
    }
    for (i = 0; i < 3; i++) {
        r = NULL;
        if ((s = run(dem, TD_INSOL_HIDDEN_SURFACE, ms[i], 1.0, &r)) < 0)
            continue;
        errors(r, ref, &sv, &tot);
        printf("  200x200 hidden-surface m=%-4d %6.2f s  sky view err %.4f  "
               "total err %.2f%%  (%.1fx the horizon time%s)\n", ms[i], s, sv,
               100 * tot, s / hs, sv <= hsv ? ", as accurate or better" : "");
        td_insol_result_free(r);
    }
    td_insol_result_free(ref);
    td_grid_f32_free(dem);
}

/* r.slope.aspect + r.sun (shadowing, 10-minute step, 2 threads); seconds
 * of those two, or -1. */
static double grass(const char *path, const char *dir)
{
    char cmd[16384], tf[4200];
    double a = 0, b = 0;
    FILE *f;
    snprintf(tf, sizeof tf, "%s/rsun.time", dir);
    remove(tf);
    snprintf(cmd, sizeof cmd,
             "grass --tmp-location EPSG:32633 --exec sh -c 'r.in.gdal -o "
             "input=%s output=dem --quiet && g.region raster=dem && "
             "s=$(date +%%s.%%N) && r.slope.aspect elevation=dem slope=sl "
             "aspect=as --quiet && r.sun elevation=dem aspect=as slope=sl "
             "day=172 step=0.1667 nprocs=2 glob_rad=g --quiet && "
             "e=$(date +%%s.%%N) && echo $s $e > %s' >%s/rsun.log 2>&1",
             path, tf, dir);
    if (system(cmd) != 0 || !(f = fopen(tf, "r")))
        return -1;
    if (fscanf(f, "%lf %lf", &a, &b) != 2)
        b = a - 1;
    fclose(f);
    return b > a ? b - a : -1;
}

int main(int argc, char **argv)
{
    const char *dir = "build-bench/data";
    int n = 1000, i, use_grass = 1;
    td_grid_f32 *dem;
    td_georef geo;
    td_ctx cx;
    char path[4200];
    double s, gs;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--dir") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            n = atoi(argv[++i]) > 16 ? atoi(argv[i]) : 16;
        else if (!strcmp(argv[i], "--no-grass"))
            use_grass = 0;
        else if (!strcmp(argv[i], "--topodig") && i + 1 < argc)
            i++;
    }
    td_ctx_init(&cx);
    mkdir(dir, 0777);
    if (!(dem = terrain(n, &cx))) {
        printf("  terrain: %s\n", td_errmsg(&cx));
        return 0;
    }
    s = run(dem, TD_INSOL_HORIZON, 36, 10.0, NULL);
    if (s > 0)
        printf("  %dx%d horizon k=36 whole day  %7.2f s  %.2f M "
               "cell-directions/s\n", n, n, s, 36.0 * n * n / s / 1e6);
    accuracy();
    td_georef_init(&geo);
    geo.valid = 1;
    geo.epsg = 32633; /* UTM 33N; the grid sits near 40N */
    geo.gt[0] = 500000.0;
    geo.gt[1] = 10.0;
    geo.gt[3] = 4430000.0;
    geo.gt[5] = -10.0;
    snprintf(path, sizeof path, "%s/insol_dem.tif", dir);
    if (!use_grass || system("command -v grass >/dev/null 2>&1") != 0)
        printf("  GRASS not installed: no r.sun ratio\n");
    else if (td_geotiff_write_f32(path, dem, &geo, &cx) != 0)
        printf("  %s\n", td_errmsg(&cx));
    else if ((gs = grass(path, dir)) < 0)
        printf("  r.sun failed (see %s/rsun.log)\n", dir);
    else
        printf("  r.slope.aspect + r.sun %dx%d (own shadowing, 2 threads) "
               "%7.2f s; horizon k=36 is %.1fx faster\n", n, n, gs,
               s > 0 ? gs / s : 0.0);
    td_georef_clear(&geo);
    td_grid_f32_free(dem);
    return 0;
}
