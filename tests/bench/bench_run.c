/* bench_run: the whole `topodig run` on the 10000 x 10000 benchmark sheet
 * (bench.h; three known points on its longest index contours, the
 * interval given) against `gdal_translate` of the same sheet to a
 * Deflate-compressed, tiled float32 GeoTIFF on all cores (issue 19's
 * reference: reading the sheet and writing a DEM-sized raster, the I/O a
 * run cannot avoid), run alternately; the medians, their ratio, the run's
 * stages from its summary line and its peak memory.
 *
 *   bench_run [--size N] [--dir DIR] [--topodig PATH] [--runs N]
 *
 * Prints numbers; never fails the build (exit 0 unless the set-up fails). */
#include "tests/util/bench.h"
#include "tests/util/hsheet.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define MAX_RUNS 9

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The known points and interval of the sheet, from `cache` or else from
 * its truth lines (then cached): 3 points as "x,y,h" into kp[3][64]. */
static int known_points(const char *sheet, const char *cache, int size,
                        char kp[3][64], double *interval, td_ctx *cx)
{
    FILE *f = fopen(cache, "r");
    td_lines *tl = NULL;
    td_label_point p[3];
    double *h = NULL;
    size_t i, n = 0;
    int k, got, rc;
    if (f) {
        got = fscanf(f, "%lf %63s %63s %63s", interval, kp[0], kp[1], kp[2]);
        fclose(f);
        if (got == 4)
            return 0;
    }
    if ((rc = td_bench_ridges_sheet(sheet, size, &tl, cx)) != 0)
        return rc;
    if (!(h = malloc((tl->n + 1) * sizeof *h))) {
        td_lines_free(tl);
        return TD_ENOMEM;
    }
    for (i = 0; i < tl->n; i++)
        h[n++] = tl->v[i].height;
    qsort(h, n, sizeof *h, cmp_d);
    *interval = HUGE_VAL;
    for (i = 1; i < n; i++)
        if (h[i] > h[i - 1] && h[i] - h[i - 1] < *interval)
            *interval = h[i] - h[i - 1];
    free(h);
    got = td_hsheet_pick_known(tl, *interval, 3, p);
    td_lines_free(tl);
    if (got < 3)
        return td_seterr(cx, TD_EINVAL, "%s: fewer than 3 index contours",
                         sheet);
    for (k = 0; k < 3; k++)
        snprintf(kp[k], sizeof kp[k], "%.1f,%.1f,%g", p[k].x, p[k].y,
                 p[k].height);
    if ((f = fopen(cache, "w"))) {
        fprintf(f, "%g %s %s %s\n", *interval, kp[0], kp[1], kp[2]);
        fclose(f);
    }
    return 0;
}

/* The stage seconds from the run's summary line in err (stderr). */
static int stages(const char *err, double st[4])
{
    FILE *f = fopen(err, "r");
    char line[4096];
    int ok = 0;
    if (!f)
        return 0;
    while (fgets(line, sizeof line, f)) {
        const char *s = strstr(line, "read+scan ");
        if (s && sscanf(s,
                        "read+scan %lf s, label %lf s, interp %lf s, "
                        "write %lf s",
                        &st[0], &st[1], &st[2], &st[3]) == 4)
            ok = 1;
    }
    fclose(f);
    return ok;
}

int main(int argc, char **argv)
{
    const char *dir = "build-bench/data", *exe = "build-bench/topodig";
    char sheet[1024], cache[1024], dem[1024], gt[1024], err[1024], iv[64];
    char kp[3][64];
    double interval, tr[MAX_RUNS], tg[MAX_RUNS], st[MAX_RUNS][4], peak = 0;
    int size = 10000, runs = 3, i, r, ok = 1, have_gdal = 1;
    td_ctx cx;
    td_ctx_init(&cx);
    for (i = 1; i + 1 < argc; i += 2)
        if (!td_bench_option(argc, argv, i, &size, &dir, &exe) &&
            !strcmp(argv[i], "--runs"))
            runs = atoi(argv[i + 1]);
    runs = runs < 1 ? 1 : runs > MAX_RUNS ? MAX_RUNS : runs;
    mkdir(dir, 0777);
    snprintf(sheet, sizeof sheet, "%s/ridges%d.tif", dir, size);
    snprintf(cache, sizeof cache, "%s/ridges%d.known", dir, size);
    snprintf(dem, sizeof dem, "%s/run_dem.tif", dir);
    snprintf(gt, sizeof gt, "%s/gdal_translate.tif", dir);
    snprintf(err, sizeof err, "%s/run.err", dir);
    if (td_bench_ridges_sheet(sheet, size, NULL, &cx) != 0 ||
        known_points(sheet, cache, size, kp, &interval, &cx) != 0) {
        fprintf(stderr, "bench_run: %s\n", td_errmsg(&cx));
        return 1;
    }
    snprintf(iv, sizeof iv, "%g", interval);
    printf("whole run, %dx%d sheet (3-px lines), interval %s, known %s %s "
           "%s; %d alternating runs\n",
           size, size, iv, kp[0], kp[1], kp[2], runs);
    for (r = 0; r < runs && ok; r++) {
        char *rv[] = {(char *)exe,  "run",     sheet,     "-o",  dem,
                      "--interval", iv,        "--known", kp[0], "--known",
                      kp[1],        "--known", kp[2],     NULL};
        char *gv[] = {"gdal_translate",
                      "-q",
                      "-ot",
                      "Float32",
                      "-co",
                      "COMPRESS=DEFLATE",
                      "-co",
                      "PREDICTOR=3",
                      "-co",
                      "TILED=YES",
                      "-co",
                      "NUM_THREADS=ALL_CPUS",
                      sheet,
                      gt,
                      NULL};
        double pk;
        ok = td_bench_child(rv, err, &tr[r], &pk, NULL) == 0 &&
             stages(err, st[r]);
        peak = pk > peak ? pk : peak;
        if (have_gdal && td_bench_child(gv, NULL, &tg[r], NULL, NULL) != 0)
            have_gdal = 0;
    }
    if (!ok) {
        printf("  topodig run failed (%s; see %s)\n", exe, err);
        return 0;
    }
    {
        double s[4], col[MAX_RUNS], run = median(tr, runs);
        int k;
        for (k = 0; k < 4; k++) {
            for (r = 0; r < runs; r++)
                col[r] = st[r][k];
            s[k] = median(col, runs);
        }
        printf("  topodig run                  %8.2f s  (median; read+scan "
               "%.2f, label %.2f, interp %.2f, write %.2f)\n",
               run, s[0], s[1], s[2], s[3]);
        printf("  peak memory %.0f MB = %.2f bytes/pixel (target <= 8)\n",
               peak / 1e6, peak / ((double)size * size));
        if (have_gdal) {
            double g = median(tg, runs);
            printf("  gdal_translate (reference)   %8.2f s  (median)\n", g);
            printf("  run / gdal_translate %.2fx (target <= 1.0)\n", run / g);
        } else {
            printf("  gdal_translate not found: no ratio\n");
        }
    }
    return 0;
}
