/* bench_horizon: the horizon sweep (src/sun/horizon.c) in cell-directions per
 * second on a generated 2000 x 2000 DEM (10 m cells) with 36 directions,
 * its growth from 1000^2 to 2000^2 (linear in cells x directions means a
 * time ratio of 4), its speed-up over the hidden-surface reference at equal
 * accuracy (sky-view error of both against a 360-direction exact ray march
 * on 160 x 160), and, where GRASS is installed, r.horizon with the same 36
 * directions on the same 1000 x 1000 DEM file in the same run, with the
 * ratio.  Times are the best of --repeat runs (the machine may be shared).
 *
 *   bench_horizon [--topodig PATH] [--dir DIR] [--size N] [--grass-size N]
 *                 [--repeat R] [--no-grass]
 *
 * Never fails the build. */
#include "samples/gen/gen.h"
#include "src/sun/sun.h"
#include "src/io/io.h"
#include "tests/util/raymarch.h"

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

/* Best seconds of `repeat` sweeps with k directions, or -1. */
static double sweep_time(const td_grid_f32 *dem, int k, double cs, int repeat)
{
    td_horizon_params p = td_horizon_defaults();
    td_grid_f32 **b = calloc((size_t)k, sizeof *b);
    td_ctx cx;
    double best = -1;
    int i, r;
    td_ctx_init(&cx);
    p.directions = k;
    p.cell_size = cs;
    for (i = 0; b && i < k; i++)
        if (!(b[i] = td_grid_f32_new(dem->w, dem->h, NULL)))
            repeat = 0;
    for (r = 0; b && r < repeat; r++) {
        double t0 = td_now(), s;
        if (td_horizon_sweep(dem, &p, b, &cx) != 0) {
            printf("  sweep failed: %s\n", td_errmsg(&cx));
            break;
        }
        s = td_now() - t0;
        best = best < 0 || s < best ? s : best;
    }
    for (i = 0; b && i < k; i++)
        td_grid_f32_free(b[i]);
    free(b);
    return best;
}

/* Sky view (1/k sum cos^2 h, as insolation.c) from k exact ray marches. */
static td_grid_f32 *reference_skyview(const td_grid_f32 *dem, int k, double cs)
{
    td_grid_f32 *sv = td_grid_f32_new(dem->w, dem->h, NULL);
    int y;
    if (!sv)
        return NULL;
#pragma omp parallel for schedule(dynamic, 2)
    for (y = 0; y < dem->h; y++) {
        int x, d;
        for (x = 0; x < dem->w; x++) {
            double v = 0;
            for (d = 0; d < k; d++) {
                double c = cos(tr_exact_march(dem, x, y, 360.0 * d / k, cs) *
                               M_PI / 180);
                v += c * c;
            }
            TD_AT(sv, x, y) = (float)(v / k);
        }
    }
    return sv;
}

/* Seconds of one td_insolation_run and its mean |sky view - ref|. */
static double skyview_run(const td_grid_f32 *dem, td_insol_method m, int km,
                          const td_grid_f32 *ref, double *err)
{
    td_insol_params p = td_insol_defaults();
    td_insol_result *r = NULL;
    td_ctx cx;
    double t0, s;
    size_t i, n = (size_t)dem->w * dem->h;
    td_ctx_init(&cx);
    p.latitude = 40.0;
    p.cell_size = 10.0;
    p.method = m;
    p.directions = km;
    p.viewpoints = km;
    p.step_minutes = 60.0; /* the sky view is what is compared */
    t0 = td_now();
    if (td_insolation_run(dem, &p, &r, &cx) != 0) {
        printf("  failed: %s\n", td_errmsg(&cx));
        return -1;
    }
    s = td_now() - t0;
    for (i = 0, *err = 0; i < n; i++)
        *err += fabs(r->skyview->data[i] - ref->data[i]);
    *err /= n;
    td_insol_result_free(r);
    return s;
}

/* Horizon sweep against hidden-surface at equal sky-view accuracy: for
 * every hidden-surface run, the cheapest sweep at least as accurate. */
static void versus_hidden_surface(void)
{
    static const int ks[] = {8, 16, 36, 64}, ms[] = {64, 256, 1024};
    td_ctx cx;
    td_grid_f32 *dem, *ref;
    double hs[4], he[4], s, e;
    int i, j;
    td_ctx_init(&cx);
    if (!(dem = terrain(160, &cx)) || !(ref = reference_skyview(dem, 360,
                                                                 10.0))) {
        td_grid_f32_free(dem);
        return;
    }
    printf("  sky view on 160x160 (10 m cells) against 360 exact ray "
           "marches per cell:\n");
    for (i = 0; i < 4; i++) {
        hs[i] = skyview_run(dem, TD_INSOL_HORIZON, ks[i], ref, &he[i]);
        if (hs[i] >= 0)
            printf("    horizon k=%-4d        %7.3f s  mean |error| %.5f\n",
                   ks[i], hs[i], he[i]);
    }
    for (i = 0; i < 3; i++) {
        if ((s = skyview_run(dem, TD_INSOL_HIDDEN_SURFACE, ms[i], ref, &e)) < 0)
            continue;
        printf("    hidden-surface m=%-4d %7.3f s  mean |error| %.5f", ms[i], s,
               e);
        for (j = 0; j < 4 && !(hs[j] > 0 && he[j] <= e); j++)
            ;
        if (j < 4)
            printf("; horizon k=%d is as accurate and %.0fx faster", ks[j],
                   s / hs[j]);
        printf("\n");
    }
    td_grid_f32_free(ref);
    td_grid_f32_free(dem);
}

/* r.horizon with 36 directions (step 10 from east, the same azimuths) on
 * path; seconds of r.horizon alone, or -1. */
static double grass(const char *path, const char *dir)
{
    char cmd[16384], tf[4200];
    double a = 0, b = 0;
    FILE *f;
    snprintf(tf, sizeof tf, "%s/rhorizon.time", dir);
    remove(tf);
    snprintf(cmd, sizeof cmd,
             "grass --tmp-location EPSG:32633 --exec sh -c 'r.in.gdal -o "
             "input=%s "
             "output=dem --quiet && g.region raster=dem && "
             "s=$(date +%%s.%%N) && r.horizon -d elevation=dem step=10 "
             "output=hor --quiet && e=$(date +%%s.%%N) && "
             "echo $s $e > %s' >%s/rhorizon.log 2>&1",
             path, tf, dir);
    if (system(cmd) != 0 || !(f = fopen(tf, "r")))
        return -1;
    if (fscanf(f, "%lf %lf", &a, &b) != 2)
        b = a - 1;
    fclose(f);
    return b > a ? b - a : -1;
}

/* The sweep on n x n and (n/2) x (n/2): times and their ratio; the
 * (n/2)^2 time (or -1) is returned for the r.horizon ratio. */
static double growth(int n, int repeat, td_ctx *cx)
{
    td_grid_f32 *dem = terrain(n, cx), *half = terrain(n / 2, cx);
    double s = -1, sh = -1;
    if (dem && half) {
        s = sweep_time(dem, 36, 10.0, repeat);
        sh = sweep_time(half, 36, 10.0, repeat);
    } else {
        printf("  terrain: %s\n", td_errmsg(cx));
    }
    if (s > 0)
        printf("  sweep %dx%d k=36     %7.2f s  %7.2f M cell-directions/s\n",
               n, n, s, 36.0 * n * n / s / 1e6);
    if (sh > 0)
        printf("  sweep %dx%d k=36     %7.2f s  %7.2f M cell-directions/s\n",
               n / 2, n / 2, sh, 36.0 * (n / 2) * (n / 2) / sh / 1e6);
    if (s > 0 && sh > 0)
        printf("  growth %d^2 -> %d^2: time x%.2f for cells x%.2f (linear: "
               "equal)\n", n / 2, n, s / sh,
               (double)n * n / ((double)(n / 2) * (n / 2)));
    td_grid_f32_free(dem);
    td_grid_f32_free(half);
    return sh;
}

/* r.horizon against the sweep (s seconds, or -1: measure) on gn x gn. */
static void versus_grass(int gn, double s, int repeat, const char *dir,
                         td_ctx *cx)
{
    td_grid_f32 *dem = terrain(gn, cx);
    td_georef geo;
    char path[4200];
    double gs;
    if (!dem)
        return;
    if (s < 0)
        s = sweep_time(dem, 36, 10.0, repeat);
    td_georef_init(&geo);
    geo.valid = 1;
    geo.epsg = 32633; /* UTM 33N, as bench_insolation (r.horizon needs a
                         projected location) */
    geo.gt[0] = 500000.0;
    geo.gt[1] = 10.0;
    geo.gt[3] = 4430000.0;
    geo.gt[5] = -10.0;
    snprintf(path, sizeof path, "%s/horizon_dem.tif", dir);
    if (td_geotiff_write_f32(path, dem, &geo, cx) != 0)
        printf("  %s\n", td_errmsg(cx));
    else if ((gs = grass(path, dir)) < 0)
        printf("  r.horizon failed (see %s/rhorizon.log)\n", dir);
    else
        printf("  r.horizon %dx%d k=36   %7.2f s  %7.2f M cell-directions/s; "
               "the sweep (%.2f s) is %.1fx faster\n", gn, gn, gs,
               36.0 * gn * gn / gs / 1e6, s, s > 0 ? gs / s : 0.0);
    td_georef_clear(&geo);
    td_grid_f32_free(dem);
}

int main(int argc, char **argv)
{
    const char *dir = "build-bench/data";
    int n = 2000, gn = 1000, repeat = 2, i, use_grass = 1;
    td_ctx cx;
    double sh;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--dir") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            n = atoi(argv[++i]) > 32 ? atoi(argv[i]) : 32;
        else if (!strcmp(argv[i], "--grass-size") && i + 1 < argc)
            gn = atoi(argv[++i]) > 32 ? atoi(argv[i]) : 32;
        else if (!strcmp(argv[i], "--repeat") && i + 1 < argc)
            repeat = atoi(argv[++i]) > 1 ? atoi(argv[i]) : 1;
        else if (!strcmp(argv[i], "--no-grass"))
            use_grass = 0;
        else if (!strcmp(argv[i], "--topodig") && i + 1 < argc)
            i++;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* lines as they come */
    td_ctx_init(&cx);
    mkdir(dir, 0777);
    sh = growth(n, repeat, &cx);
    versus_hidden_surface();
    if (!use_grass || system("command -v grass >/dev/null 2>&1") != 0)
        printf("  GRASS not installed: no r.horizon ratio\n");
    else
        versus_grass(gn, gn == n / 2 ? sh : -1.0, repeat, dir, &cx);
    return 0;
}
