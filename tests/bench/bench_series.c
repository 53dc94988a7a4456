/* bench_series: the joint steps of `topodig batch` on a large map series
 * (issue 18: "the edge matching of a 100 x 100 series (simulated from one
 * DEM) takes under 10 s and memory linear in the number of edge
 * crossings"; numbers for docs/batch.md).
 *
 * One RIDGES terrain of N*P x N*P cells; its true contours cut into N x N
 * georeferenced sheets of P x P cells, written as the outputs their runs
 * would leave (DIR/series/out/<sheet>/lines.geojson with heights, the
 * index contours as read from labels, a dem.tif, summary.json), then
 *  - `batch --joint-only --no-joint --no-seams`: placing the sheets,
 *    finding the neighbours and the edge matching alone;
 *  - `batch --joint-only` (the default joint steps): the joint solve (in
 *    blocks of up to 1e8 cells when the series is larger), the edge
 *    matching and the sheets' DEMs cut from one interpolation (when the
 *    series is at most 3e8 cells);
 * each timed with its peak memory (the child's maximum resident set).
 * Options: --topodig PATH --dir DIR --sheets N (100) --px P (60). */
#include "samples/gen/gen.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define RES 30.0 /* m per cell */
#define X0 500000.0
#define Y1 4500000.0

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Sheet (row, column) of a point of the series (clamped). */
static size_t sheet_of(double x, double y, int N, int P)
{
    long c = (long)floor(x / P), r = (long)floor(y / P);
    c = c < 0 ? 0 : c >= N ? N - 1 : c;
    r = r < 0 ? 0 : r >= N ? N - 1 : r;
    return (size_t)r * (size_t)N + (size_t)c;
}

/* Close piece cur (series coordinates) into sheet s's lines, in the
 * sheet's own pixel frame. */
static int flush(td_line *cur, size_t s, int N, int P, td_lines **sh,
                 td_ctx *cx)
{
    size_t k;
    int rc = 0;
    if (cur->n >= 2) {
        double ox = (double)(s % (size_t)N) * P, oy = (double)(s / (size_t)N) * P;
        for (k = 0; k < cur->n; k++)
            cur->xy[2 * k] -= ox, cur->xy[2 * k + 1] -= oy;
        rc = td_lines_append_copy(sh[s], cur, cx);
    }
    cur->n = 0;
    return rc;
}

/* Cut line l at the sheet edges into the sheets' lists. */
static int cut_line(const td_line *l, int N, int P, td_lines **sh,
                    td_ctx *cx)
{
    td_line cur = *l;
    size_t k, n = l->n + (l->closed ? 1 : 0), s;
    int rc = 0;
    cur.xy = NULL, cur.n = 0, cur.cap = 0, cur.closed = 0, cur.edge = 1;
    if (l->n < 2)
        return 0;
    s = sheet_of(l->xy[0], l->xy[1], N, P);
    if ((rc = td_line_push(&cur, l->xy[0], l->xy[1], cx)) != 0)
        goto done;
    for (k = 1; k < n && rc == 0; k++) {
        const double *q = l->xy + 2 * (k % l->n);
        double px = cur.xy[2 * cur.n - 2], py = cur.xy[2 * cur.n - 1];
        int guard = 0;
        while (sheet_of(q[0], q[1], N, P) != s && guard++ < 4) {
            /* the first sheet edge the segment crosses */
            double cx0 = (double)(s % (size_t)N) * P, cy0 = (double)(s / (size_t)N) * P;
            double dx = q[0] - px, dy = q[1] - py, t = 1.0, ex, ey;
            if (dx > 0)
                t = fmin(t, (cx0 + P - px) / dx);
            else if (dx < 0)
                t = fmin(t, (cx0 - px) / dx);
            if (dy > 0)
                t = fmin(t, (cy0 + P - py) / dy);
            else if (dy < 0)
                t = fmin(t, (cy0 - py) / dy);
            t = fmax(0.0, t);
            ex = px + t * dx, ey = py + t * dy;
            if ((rc = td_line_push(&cur, ex, ey, cx)) != 0 ||
                (rc = flush(&cur, s, N, P, sh, cx)) != 0)
                goto done;
            s = sheet_of(ex + 1e-6 * dx, ey + 1e-6 * dy, N, P);
            if ((rc = td_line_push(&cur, ex, ey, cx)) != 0)
                goto done;
            px = ex, py = ey;
        }
        rc = td_line_push(&cur, q[0], q[1], cx);
    }
    if (rc == 0)
        rc = flush(&cur, s, N, P, sh, cx);
done:
    free(cur.xy);
    return rc;
}

/* Run cmd under /usr/bin/time: its wall seconds and peak resident set
 * (kB, 0 when /usr/bin/time is missing) in *rss. */
static double timed(const char *cmd, const char *base, long *rss)
{
    char full[20000], path[1024];
    FILE *f;
    double t0, t;
    int st;
    snprintf(path, sizeof path, "%s/time.txt", base);
    snprintf(full, sizeof full,
             "if [ -x /usr/bin/time ]; then /usr/bin/time -f %%M -o '%s' sh "
             "-c \"%s\"; else %s; fi", path, cmd, cmd);
    t0 = now();
    st = system(full);
    t = now() - t0;
    *rss = 0;
    if ((f = fopen(path, "r")) != NULL) {
        if (fscanf(f, "%ld", rss) != 1)
            *rss = 0;
        fclose(f);
    }
    return st == -1 ? -1 : t;
}

/* The sum of "key": N over the lines of path holding tag. */
static long sum_field(const char *path, const char *tag, const char *key)
{
    FILE *f = fopen(path, "r");
    char line[1 << 16];
    long s = 0;
    size_t kl = strlen(key);
    while (f && fgets(line, sizeof line, f))
        if (strstr(line, tag)) {
            char *p = strstr(line, key);
            if (p)
                s += atol(p + kl);
        }
    if (f)
        fclose(f);
    return s;
}

/* `batch --joint-only EXTRA` on the series in base, timed; one line. */
static void step(const char *base, const char *td, const char *extra,
                 const char *what)
{
    char cmd[8192], path[1024];
    long rss;
    double t;
    snprintf(cmd, sizeof cmd,
             "cd '%s' && '%s' batch manifest.csv --out out --joint-only %s "
             "-q 2>/dev/null",
             base, td, extra);
    t = timed(cmd, base, &rss);
    snprintf(path, sizeof path, "%s/out/batch.log", base);
    printf("%-40s %7.2f s %7.0f MB  %ld crossings paired, %ld with two "
           "heights, %ld lines changed height\n",
           what, t, rss / 1024.0,
           sum_field(path, "\"edge\"", "\"crossings\": "),
           sum_field(path, "\"edge\"", "\"conflicting\": "),
           sum_field(path, "\"step\": \"joint\"", "\"changed\": "));
}

int main(int argc, char **argv)
{
    const char *td = NULL, *dir = "build-bench/data";
    char tdabs[4096];
    int N = 100, P = 60, a, r, c;
    td_gen_params gp = td_gen_defaults();
    td_grid_f32 *dem = NULL, *tiny = NULL;
    td_grid_u8 *paper = NULL;
    td_lines *truth = NULL, **sh = NULL;
    td_ctx cx;
    double interval, t0;
    char path[1024], cmd[2048], base[512];
    size_t i, nsh, pieces = 0;
    FILE *man;
    td_ctx_init(&cx);
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--topodig") && a + 1 < argc)
            td = argv[++a];
        else if (!strcmp(argv[a], "--dir") && a + 1 < argc)
            dir = argv[++a];
        else if (!strcmp(argv[a], "--sheets") && a + 1 < argc)
            N = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--px") && a + 1 < argc)
            P = atoi(argv[++a]);
    }
    if (!td || N < 2 || P < 16) {
        printf("bench_series: needs --topodig PATH (and --sheets >= 2, --px "
               ">= 16)\n");
        return 0;
    }
    if (!realpath(td, tdabs)) {
        printf("bench_series: %s: not found\n", td);
        return 0;
    }
    nsh = (size_t)N * (size_t)N;
    snprintf(base, sizeof base, "%s/series%dx%d", dir, N, P);
    snprintf(cmd, sizeof cmd, "rm -rf '%s' && mkdir -p '%s/sheets' '%s/out'",
             base, base, base);
    if (system(cmd) != 0)
        return 0;
    t0 = now();
    gp.terrain = TD_GEN_RIDGES;
    gp.w = gp.h = N * P;
    if (td_gen_terrain(&gp, &dem, &cx) != 0 ||
        (interval = td_gen_auto_interval(&gp, dem)) <= 0 ||
        td_gen_contours(dem, 0.0, interval, &truth, &cx) != 0) {
        printf("bench_series: %s\n", td_errmsg(&cx));
        return 0;
    }
    td_grid_f32_free(dem);
    if (!(sh = calloc(nsh, sizeof *sh)) ||
        !(tiny = td_grid_f32_new(P, P, &cx)) ||
        !(paper = td_grid_u8_new(P, P, &cx)))
        return 0;
    for (i = 0; i < nsh; i++)
        if (!(sh[i] = td_lines_new(&cx)))
            return 0;
    for (i = 0; i < truth->n; i++) {
        td_line *l = &truth->v[i];
        int idx = fabs(fmod(l->height / interval, 5.0)) < 1e-6;
        l->has_height = 1;
        l->hsource = idx ? TD_HS_LABEL : TD_HS_SOLVED;
        l->confidence = idx ? 0.96 : 0.8;
        if (cut_line(l, N, P, sh, &cx) != 0)
            return 0;
    }
    snprintf(path, sizeof path, "%s/manifest.csv", base);
    if (!(man = fopen(path, "w")))
        return 0;
    fputs("sheet,options\n", man);
    for (r = 0; r < N; r++)
        for (c = 0; c < N; c++) {
            td_georef g;
            FILE *f;
            size_t s = (size_t)r * (size_t)N + (size_t)c;
            td_georef_init(&g);
            g.valid = 1;
            g.gt[0] = X0 + c * P * RES, g.gt[1] = RES, g.gt[2] = 0;
            g.gt[3] = Y1 - r * P * RES, g.gt[4] = 0, g.gt[5] = -RES;
            g.epsg = 32613;
            pieces += sh[s]->n;
            snprintf(path, sizeof path, "%s/sheets/t%03d%03d.tif", base, r, c);
            if (td_geotiff_write_u8(path, paper, &g, &cx) != 0)
                return 0;
            fprintf(man, "sheets/t%03d%03d.tif,\n", r, c);
            snprintf(path, sizeof path, "%s/out/t%03d%03d", base, r, c);
            mkdir(path, 0777);
            snprintf(path, sizeof path, "%s/out/t%03d%03d/dem.tif", base, r, c);
            if (td_dem_write(path, tiny, &g, &cx) != 0)
                return 0;
            snprintf(path, sizeof path, "%s/out/t%03d%03d/lines.geojson", base,
                     r, c);
            if (td_vector_write_lines(path, sh[s], &g, &cx) != 0)
                return 0;
            snprintf(path, sizeof path, "%s/out/t%03d%03d/summary.json", base,
                     r, c);
            if ((f = fopen(path, "w")) != NULL) {
                fprintf(f, "{\"interval\": %g}\n", interval);
                fclose(f);
            }
            td_georef_clear(&g);
            td_lines_free(sh[s]);
        }
    fclose(man);
    printf("series: %d x %d sheets of %d x %d cells (%.3g cells), %zu true "
           "contours cut into %zu pieces, interval %g; written in %.1f s\n",
           N, N, P, P, (double)N * P * N * P, truth->n, pieces, interval,
           now() - t0);
    td_lines_free(truth);
    td_grid_f32_free(tiny);
    td_grid_u8_free(paper);
    free(sh);
    step(base, tdabs, "--no-joint --no-seams",
         "placing + neighbours + edge matching");
    step(base, tdabs, "", "the joint steps (solve, edges, DEMs)");
    return 0;
}
