/* bench_flow: flow accumulation throughput (cells per second) of D8 and
 * D-infinity (priority-flood filling included) on two generated 4000x4000
 * terrains (td_gen_terrain HILLS: smooth, and with 0.5 m white noise on
 * every cell, a stress case where 9% of the cells are pits and almost no
 * cell drains without climbing), D8 on 1 thread and on all cores, the
 * paper's Sobel drop tracing on 1000x1000 (its cost grows with the path
 * length), and, where GRASS is installed, r.watershed -s on the same DEM
 * files in the same run, with the ratios.  Times are wall clock and
 * process CPU time (on a shared machine the wall clock also counts the
 * time other programs held the core); the ratio is given for both.
 *
 *   bench_flow [--topodig PATH] [--dir DIR] [--size N] [--no-grass]
 *              [--noise M]   (only that terrain: M metres of noise)
 *              [--reps R]    (runs of each; the best is printed [3];
 *                             r.watershed: the best of 2)
 *
 * Never fails the build. */
#include "samples/gen/gen.h"
#include "src/flow/flow.h"
#include "src/io/io.h"
#include "src/model/model.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <omp.h>

/* CPU seconds of this process. */
static double cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double noise_m = -1; /* < 0: both terrains */
static int reps = 3;        /* runs of each; the best counts */

static td_grid_f32 *terrain(int n, td_ctx *cx)
{
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *dem = NULL;
    gp.w = gp.h = n;
    if (td_gen_terrain(&gp, &dem, cx) != 0)
        return NULL;
    if (noise_m > 0)
        td_terrain_noise(dem, noise_m, 1, cx);
    return dem;
}

/* Seconds of one run, -1 on failure, its CPU seconds into *cpu; prints
 * one line. */
static double one(const td_grid_f32 *dem, td_flow_method m, int threads,
                  const char *name, double *cpu)
{
    td_flow_params p = td_flow_defaults();
    td_flow_stats st;
    td_ctx cx;
    double s = -1, c = 0, n = (double)dem->w * dem->h;
    int r;
    td_ctx_init(&cx);
    p.method = m;
    p.threads = threads;
    for (r = 0; r < reps; r++) { /* the best of reps (a shared VM drifts) */
        td_grid_f32 *out = td_grid_f32_new(dem->w, dem->h, NULL);
        double t0 = td_now(), c0 = cpu_now(), t1;
        if (!out)
            return -1;
        if (td_flow_run(dem, &p, out, &st, &cx) != 0) {
            printf("  %s: %s\n", name, td_errmsg(&cx));
            td_grid_f32_free(out);
            return -1;
        }
        t1 = td_now() - t0;
        if (s < 0 || t1 < s) {
            s = t1;
            c = cpu_now() - c0;
        }
        td_grid_f32_free(out);
    }
    printf("  %-5s %dx%d %d thr  %7.2f s (cpu %7.2f s)  %7.2f M cells/s "
           "(%.2f per cpu-s)  outflow %.0f of %.0f  raised %.0f  pits "
           "%.0f\n", name, dem->w, dem->h, threads, s, c, n / s / 1e6,
           c > 0 ? n / c / 1e6 : 0.0, st.outflow, st.cells, st.raised,
           st.pit_stops);
    if (cpu)
        *cpu = c;
    return s;
}

/* r.watershed -s on path; seconds of r.watershed alone, or -1; its CPU
 * seconds (user + system, from /usr/bin/time where installed, else 0)
 * into *cpu. */
static double grass(const char *path, const char *dir, double *cpu)
{
    char cmd[16384], tf[4200], cf[4200];
    double a = 0, b = 0, u = 0, y = 0;
    int tm = system("test -x /usr/bin/time") == 0;
    FILE *f;
    snprintf(cf, sizeof cf, "%s/rwatershed.cpu", dir);
    remove(cf);
    *cpu = 0;
    snprintf(tf, sizeof tf, "%s/rwatershed.time", dir);
    remove(tf);
    snprintf(cmd, sizeof cmd,
             "grass --tmp-location XY --exec sh -c 'r.in.gdal -o input=%s "
             "output=dem --quiet && g.region raster=dem && "
             "s=$(date +%%s.%%N) && %s%s r.watershed -s elevation=dem "
             "accumulation=acc --quiet && e=$(date +%%s.%%N) && "
             "echo $s $e > %s' >%s/rwatershed.log 2>&1",
             path, tm ? "/usr/bin/time -f \"%U %S\" -o " : "",
             tm ? cf : "", tf, dir);
    if (system(cmd) != 0 || !(f = fopen(tf, "r")))
        return -1;
    if (fscanf(f, "%lf %lf", &a, &b) != 2)
        b = a - 1;
    fclose(f);
    if (tm && (f = fopen(cf, "r")) != NULL) {
        if (fscanf(f, "%lf %lf", &u, &y) == 2)
            *cpu = u + y;
        fclose(f);
    }
    return b > a ? b - a : -1;
}

/* r.watershed twice: the best run (seconds, -1 on failure), its CPU. */
static double grass2(const char *path, const char *dir, double *cpu)
{
    double c1 = 0, c2 = 0, a = grass(path, dir, &c1), b;
    if (a < 0)
        return -1;
    b = grass(path, dir, &c2);
    *cpu = b >= 0 && b < a ? c2 : c1;
    return b >= 0 && b < a ? b : a;
}

/* D8 on 1 thread and on all cores, then r.watershed -s on the same DEM. */
static void terrain_run(const td_grid_f32 *dem, const char *label,
                        const char *dir, int use_grass)
{
    char path[4200];
    double d8, d8c = 0, dn, dnc = 0, gs, gc = 0;
    int nth = omp_get_max_threads(), n = dem->w;
    td_ctx cx;
    td_ctx_init(&cx);
    printf("  %s\n", label);
    d8 = one(dem, TD_FLOW_D8, 1, "d8", &d8c);
    dn = nth > 1 ? one(dem, TD_FLOW_D8, nth, "d8", &dnc) : d8;
    if (nth <= 1)
        dnc = d8c;
    snprintf(path, sizeof path, "%s/flow_dem.tif", dir);
    if (!use_grass || system("command -v grass >/dev/null 2>&1") != 0)
        printf("  GRASS not installed: no r.watershed ratio\n");
    else if (td_geotiff_write_f32(path, dem, NULL, &cx) != 0)
        printf("  %s\n", td_errmsg(&cx));
    else if ((gs = grass2(path, dir, &gc)) < 0)
        printf("  r.watershed failed (see %s/rwatershed.log)\n", dir);
    else
        printf("  r.watershed -s %dx%d  %7.2f s (cpu %7.2f s)  %7.2f M "
               "cells/s\n  => d8 on 1 thread is %.1fx faster by the wall "
               "clock (%.1fx by cpu time); on %d threads %.1fx by the wall "
               "clock\n", n, n, gs, gc, (double)n * n / gs / 1e6,
               d8 > 0 ? gs / d8 : 0.0, d8c > 0 && gc > 0 ? gc / d8c : 0.0,
               nth, dn > 0 ? gs / dn : 0.0);
}

int main(int argc, char **argv)
{
    const char *dir = "build-bench/data";
    int n = 4000, i, use_grass = 1;
    td_grid_f32 *dem, *small;
    td_ctx cx;
    char label[200];
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--dir") && i + 1 < argc)
            dir = argv[++i];
        else if (!strcmp(argv[i], "--size") && i + 1 < argc)
            n = atoi(argv[++i]) > 16 ? atoi(argv[i]) : 16;
        else if (!strcmp(argv[i], "--noise") && i + 1 < argc)
            noise_m = atof(argv[++i]);
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc)
            reps = atoi(argv[++i]) > 0 ? atoi(argv[i]) : 1;
        else if (!strcmp(argv[i], "--no-grass"))
            use_grass = 0;
        else if (!strcmp(argv[i], "--topodig") && i + 1 < argc)
            i++;
    }
    td_ctx_init(&cx);
    mkdir(dir, 0777);
    for (i = noise_m >= 0 ? 1 : 0; i < 2; i++) {
        double keep = noise_m;
        if (noise_m < 0)
            noise_m = i == 0 ? 0.0 : 0.5;
        if (!(dem = terrain(n, &cx))) {
            printf("  terrain: %s\n", td_errmsg(&cx));
            return 0;
        }
        snprintf(label, sizeof label, "generated hills + %g m white noise%s",
                 noise_m, noise_m > 0 ? "" : " (smooth)");
        terrain_run(dem, label, dir, use_grass);
        if (i == 1) {
            one(dem, TD_FLOW_DINF, 1, "dinf", NULL);
            if ((small = terrain(1000, &cx)) != NULL) {
                one(small, TD_FLOW_SOBEL, 1, "sobel", NULL);
                one(small, TD_FLOW_D8, 1, "d8", NULL);
                td_grid_f32_free(small);
            }
        }
        td_grid_f32_free(dem);
        noise_m = keep;
    }
    return 0;
}
