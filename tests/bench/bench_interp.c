/* bench_interp: accuracy and speed of contour interpolation on generated
 * sheets with a known surface (numbers for docs/benchmarks-interp.md).
 *
 * For each shape (hills, cone, ridges) at 1000 x 1000 and at --big N
 * (default 5000; there without the anchors and with the paper's method and
 * the default only):
 *  - from the TRUE contour lines: every method variant (the paper's
 *    scanline exactly, scanline with the diagonal peninsula passes,
 *    multidir with 2 or 4 directions and each weight), RMSE / MAE / max
 *    |d| against the true DEM in contour intervals, coverage, seconds;
 *  - END TO END from the rendered noisy sheet (2 px lines, breaks, specks,
 *    blur, noise, every 5th contour 4 px wide): td_scan, td_label_auto with
 *    one known point (a vertex of a true thin line), the index contours'
 *    widths (--index-every 5) and the depression marks (centres of the
 *    true rings that enclose lower ground), then the default and the
 *    paper's method;
 *  - anchors on the same true lines, in the same run, when installed:
 *    GRASS r.surf.contour (on the rasterised lines, `grass --tmp-location
 *    XY --exec`) and `gdal_grid -a linear` (the lines' vertices), with
 *    their own timings (r.surf.contour timed alone, inside GRASS);
 *  - `topodig run` on a --huge N sheet (default 10000) through the CLI,
 *    wall time and peak memory from /usr/bin/time, when --topodig is given.
 *  - the default with N sweeps of band-constrained smoothing (--smooth).
 * Options: --topodig PATH --dir DIR --big N --huge N --no-anchors
 * --sweeps-only (the smoothing table alone). */
#define _POSIX_C_SOURCE 200809L
#include "interp/interp.h"
#include "samples/gen/gen.h"
#include "scanner/label.h"
#include "scanner/scan.h"
#include "src/compare/compare.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct variant {
    const char *name;
    td_interp_method m;
    int peninsula, ndir, weight;
} variant;

static const variant variants[] = {
    {"scanline, paper (x, y, summit; peninsula flat)", TD_INTERP_SCANLINE, 0, 4, 0},
    {"scanline + diagonal peninsula passes", TD_INTERP_SCANLINE, 1, 4, 0},
    {"multidir 2 dirs, 1/(d1+d2)", TD_INTERP_MULTIDIR, 1, 2, 1},
    {"multidir 4 dirs, 1/(d1 d2)", TD_INTERP_MULTIDIR, 1, 4, 0},
    {"multidir 4 dirs, 1/(d1+d2)^2", TD_INTERP_MULTIDIR, 1, 4, 2},
    {"multidir 4 dirs, 1/(d1+d2) (default)", TD_INTERP_MULTIDIR, 1, 4, 1},
};
#define NVAR (sizeof variants / sizeof *variants)

typedef struct opts {
    const char *topodig, *dir;
    int big, huge, anchors, smooth_only;
} opts;

static void row(const char *what, const td_compare_stats *st, double I,
                double secs, size_t cells)
{
    printf("  %-48s rmse %.4f  mae %.4f  max %.3f  cov %.3f  %7.3f s  %6.1f Mpx/s\n",
           what, st->rmse / I, st->mae / I, st->max_abs / I, st->coverage,
           secs, secs > 0 ? cells / secs / 1e6 : 0);
}

static int interp_and_compare(const td_lines *ls, const td_grid_f32 *dem,
                              double I, const variant *v, const char *name,
                              td_ctx *cx)
{
    td_interp_params p = td_interp_defaults();
    td_grid_f32 *g = NULL;
    td_compare_stats st;
    double t0;
    int rc;
    p.method = v->m;
    p.scanline.peninsula = v->peninsula;
    p.multidir.ndir = v->ndir;
    p.multidir.weight = v->weight;
    p.interval = I;
    t0 = td_now();
    if ((rc = td_interp_lines(ls, dem->w, dem->h, &p, &g, cx)) != 0)
        return rc;
    t0 = td_now() - t0;
    td_compare_grids(g, dem, &st, cx);
    row(name ? name : v->name, &st, I, t0, (size_t)dem->w * dem->h);
    td_grid_f32_free(g);
    return 0;
}

/* Centres of the true rings that hold lower ground: the depression marks a
 * user would give. */
static size_t depressions(const td_lines *tl, const td_grid_f32 *dem,
                          double *xy, size_t max)
{
    size_t i, k, n = 0;
    for (i = 0; i < tl->n && n < max; i++) {
        const td_line *l = &tl->v[i];
        double cx = 0, cy = 0;
        int x, y;
        if (!l->closed || l->n < 8)
            continue;
        for (k = 0; k < l->n; k++)
            cx += l->xy[2 * k], cy += l->xy[2 * k + 1];
        x = (int)(cx / l->n), y = (int)(cy / l->n);
        if (x < 0 || y < 0 || x >= dem->w || y >= dem->h ||
            TD_AT(dem, x, y) >= l->height)
            continue;
        xy[2 * n] = cx / l->n;
        xy[2 * n + 1] = cy / l->n;
        n++;
    }
    return n;
}

/* Scan the sheet and label the traced lines from one known point. */
static int scan_and_label(const td_image *im, const td_lines *tl,
                          const td_grid_f32 *dem, double I, td_lines **out,
                          double *secs, td_ctx *cx)
{
    td_scan_params sp = td_scan_defaults();
    td_scan_result res;
    td_label_params lp = td_label_defaults();
    td_label_report rep;
    td_label_point kp;
    double dep[2 * 16], t0 = td_now();
    size_t i;
    int rc;
    memset(&rep, 0, sizeof rep);
    if ((rc = td_scan(im, &sp, &res, cx)) != 0)
        return rc;
    *out = res.lines;
    res.lines = NULL;
    td_scan_result_free(&res);
    for (i = 0; i + 1 < tl->n && fmod(fabs(tl->v[i].height / I), 5.0) == 0;)
        i++; /* a point on a thin line: on an index line the widths could
                not tell a slope from its mirror */
    kp.x = tl->v[i].xy[2 * (tl->v[i].n / 2)];
    kp.y = tl->v[i].xy[2 * (tl->v[i].n / 2) + 1];
    kp.height = tl->v[i].height;
    kp.id = -1;
    lp.interval = I;
    lp.w = im->w;
    lp.h = im->h;
    lp.known = &kp;
    lp.nknown = 1;
    lp.index_every = 5;
    lp.depressions = dep;
    lp.ndepressions = depressions(tl, dem, dep, 16);
    rc = td_label_auto(*out, &lp, &rep, cx);
    td_label_report_free(&rep);
    for (i = (*out)->n; rc == 0 && i-- > 0;)
        if (!(*out)->v[i].has_height)
            td_lines_remove(*out, i);
    *secs = td_now() - t0;
    return rc;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The height of the true line nearest (within 3 px) to most of a traced
 * line's vertices, or NAN. */
static float vote(const td_line *l, const td_grid_f32 *t, float *buf)
{
    size_t k, n = 0, i, best = 0, run = 0;
    float h = NAN;
    for (k = 0; k < l->n; k++) {
        int x0 = (int)l->xy[2 * k], y0 = (int)l->xy[2 * k + 1], r, dx, dy;
        float z = NAN;
        for (r = 0; r <= 3 && z != z; r++)
            for (dy = -r; dy <= r; dy++)
                for (dx = -r; dx <= r; dx++) {
                    int x = x0 + dx, y = y0 + dy;
                    if (x >= 0 && y >= 0 && x < t->w && y < t->h &&
                        z != z && TD_AT(t, x, y) == TD_AT(t, x, y))
                        z = TD_AT(t, x, y);
                }
        if (z == z)
            buf[n++] = z;
    }
    qsort(buf, n, sizeof *buf, cmp_float);
    for (i = 0; i < n; i++) {
        run = i > 0 && buf[i] == buf[i - 1] ? run + 1 : 1;
        if (run > best)
            best = run, h = buf[i];
    }
    return h;
}

/* Heights for traced lines from the truth (isolates interpolation from
 * labelling); lines matching no true line are dropped. */
static int truth_labels(td_lines *traced, const td_lines *tl, int w, int h,
                        td_ctx *cx)
{
    td_grid_f32 *t = td_grid_f32_new(w, h, cx);
    size_t i, maxn = 1;
    float *buf = NULL;
    int rc = TD_ENOMEM;
    for (i = 0; i < traced->n; i++)
        maxn = traced->v[i].n > maxn ? traced->v[i].n : maxn;
    if (!t || !(buf = td_malloc(maxn * sizeof *buf, cx)) ||
        (rc = td_rasterise_lines(tl, 1, t, cx)) != 0)
        goto done;
    for (i = traced->n; i-- > 0;) {
        float z = vote(&traced->v[i], t, buf);
        traced->v[i].has_height = z == z;
        traced->v[i].height = z;
        if (z != z)
            td_lines_remove(traced, i);
    }
done:
    free(buf);
    td_grid_f32_free(t);
    return rc;
}

static double read_time_pair(const char *path)
{
    FILE *f = fopen(path, "r");
    double a = 0, b = 0;
    if (!f)
        return -1;
    if (fscanf(f, "%lf %lf", &a, &b) != 2)
        a = b = 0, b = -1;
    fclose(f);
    return b - a;
}

static void anchor_result(const char *name, const char *tif,
                          const td_grid_f32 *dem, double I, double secs)
{
    td_grid_f32 *g = NULL;
    td_compare_stats st;
    td_ctx cx;
    td_ctx_init(&cx);
    if (td_dem_read(tif, &g, NULL, &cx) != 0) {
        printf("  %-48s failed: %s\n", name, td_errmsg(&cx));
        return;
    }
    if (!g->has_nodata) {
        g->has_nodata = 1;
        g->nodata = -9999;
    }
    if (td_compare_grids(g, dem, &st, &cx) == 0)
        row(name, &st, I, secs, (size_t)dem->w * dem->h);
    else
        printf("  %-48s %s\n", name, td_errmsg(&cx));
    td_grid_f32_free(g);
}

/* GRASS r.surf.contour on the rasterised true lines, timed inside GRASS. */
static void anchor_grass(const opts *o, const td_lines *tl,
                         const td_grid_f32 *dem, double I, td_ctx *cx)
{
    char path[1024], cmd[4096];
    td_grid_f32 *c = td_grid_f32_new(dem->w, dem->h, cx);
    size_t i, n = (size_t)dem->w * dem->h;
    if (!c || td_rasterise_lines(tl, 1, c, cx) != 0)
        goto done;
    for (i = 0; i < n; i++)
        if (c->data[i] != c->data[i])
            c->data[i] = -9999;
    c->has_nodata = 1;
    c->nodata = -9999;
    snprintf(path, sizeof path, "%s/contours.tif", o->dir);
    if (td_geotiff_write_f32(path, c, NULL, cx) != 0)
        goto done;
    snprintf(cmd, sizeof cmd,
             "rm -f '%s/grass.tif' '%s/grass.time'; grass --tmp-location XY "
             "--exec sh -c \"r.in.gdal -o --quiet input='%s' output=c && "
             "g.region raster=c && t0=\\$(date +%%s.%%N) && "
             "r.surf.contour --quiet input=c output=s && "
             "t1=\\$(date +%%s.%%N) && echo \\$t0 \\$t1 > '%s/grass.time' && "
             "r.out.gdal --quiet -c -f input=s output='%s/grass.tif' "
             "type=Float32\" >/dev/null 2>&1",
             o->dir, o->dir, path, o->dir, o->dir);
    /* GRASS exits nonzero on a harmless "unable to set projection"
     * warning in an XY location: judge by the output file */
    if (system(cmd) < 0 || (snprintf(path, sizeof path, "%s/grass.tif",
                                     o->dir), access(path, R_OK) != 0)) {
        printf("  %-48s failed (see grass)\n", "GRASS r.surf.contour");
        goto done;
    }
    snprintf(path, sizeof path, "%s/grass.time", o->dir);
    {
        double secs = read_time_pair(path);
        snprintf(path, sizeof path, "%s/grass.tif", o->dir);
        anchor_result("anchor: GRASS r.surf.contour", path, dem, I, secs);
    }
done:
    td_grid_f32_free(c);
}

/* gdal_grid -a linear (Delaunay TIN) on the true lines' vertices. */
static void anchor_gdal_grid(const opts *o, const td_lines *tl,
                             const td_grid_f32 *dem, double I, td_ctx *cx)
{
    char path[1024], out[1024], cmd[4096];
    double t0;
    int rc;
    /* gdal_grid writes north-up rasters: the lines in the pixel frame
     * (Y = -row) make its first row the sheet's top row */
    snprintf(path, sizeof path, "%s/lines.geojson", o->dir);
    snprintf(out, sizeof out, "%s/gdal_grid.tif", o->dir);
    rc = td_geojson_write_lines(path, tl, NULL, cx);
    if (rc != 0)
        return;
    snprintf(cmd, sizeof cmd,
             "gdal_grid -q -a linear:nodata=-9999 -zfield height -txe 0 %d "
             "-tye -%d 0 -outsize %d %d -ot Float32 -of GTiff '%s' '%s' "
             ">/dev/null 2>&1", dem->w, dem->h, dem->w, dem->h, path, out);
    t0 = td_now();
    if (system(cmd) != 0) {
        printf("  %-48s failed\n", "gdal_grid -a linear");
        return;
    }
    anchor_result("anchor: gdal_grid -a linear (incl. I/O)", out, dem, I,
                  td_now() - t0);
}

static int have(const char *tool)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "command -v %s >/dev/null 2>&1", tool);
    return system(cmd) == 0;
}

static td_gen_params sheet_params(td_gen_terrain_kind kind, int size)
{
    td_gen_params gp = td_gen_defaults();
    gp.w = gp.h = size;
    gp.terrain = kind;
    gp.seed = 7;
    gp.line_width = 2;
    gp.breaks = 6 * size / 600;
    gp.break_min = 1;
    gp.break_max = 3;
    gp.blur = 0.6;
    gp.noise = 6;
    gp.specks = 12 * size / 600;
    gp.index_width = 4; /* every 5th contour thicker, as printed sheets */
    return gp;
}

static int one_sheet(const opts *o, td_gen_terrain_kind kind,
                     const char *name, int size, int all, td_ctx *cx)
{
    td_gen_params gp = sheet_params(kind, size);
    td_image *im = NULL;
    td_lines *tl = NULL, *traced = NULL;
    td_grid_f32 *dem = NULL;
    double I, secs;
    size_t v;
    int rc;
    if ((rc = td_gen_sheet(&gp, &im, &tl, &dem, cx)) != 0)
        return rc;
    I = td_interp_interval(tl);
    printf("%s %d x %d, interval %g, %zu true lines "
           "(errors in intervals)\n", name, size, size, I, tl->n);
    printf(" from the true lines:\n");
    for (v = 0; v < NVAR && rc == 0; v++)
        if (all || v == 0 || v == NVAR - 1)
            rc = interp_and_compare(tl, dem, I, &variants[v], NULL, cx);
    if (rc == 0 && o->anchors && all && have("grass"))
        anchor_grass(o, tl, dem, I, cx);
    if (rc == 0 && o->anchors && all && have("gdal_grid"))
        anchor_gdal_grid(o, tl, dem, I, cx);
    if (rc == 0 && (rc = scan_and_label(im, tl, dem, I, &traced, &secs,
                                        cx)) == 0) {
        printf(" end to end from the noisy sheet (scan + label %.2f s, "
               "%zu labelled lines):\n", secs, traced->n);
        rc = interp_and_compare(traced, dem, I, &variants[0], NULL, cx);
        if (rc == 0)
            rc = interp_and_compare(traced, dem, I, &variants[NVAR - 1],
                                    NULL, cx);
    }
    if (rc != 0 && traced) {
        printf("  labelling failed: %s\n", td_errmsg(cx));
        td_ctx_clear(cx);
        rc = 0;
    }
    if (rc == 0 && (rc = truth_labels(traced, tl, dem->w, dem->h, cx)) == 0) {
        printf(" end to end, traced lines labelled from the truth (%zu "
               "lines):\n", traced->n);
        rc = interp_and_compare(traced, dem, I, &variants[0], NULL, cx);
        if (rc == 0)
            rc = interp_and_compare(traced, dem, I, &variants[NVAR - 1],
                                    NULL, cx);
    }
    if (rc != 0)
        printf("  failed: %s\n", td_errmsg(cx));
    td_ctx_clear(cx);
    td_lines_free(traced);
    td_lines_free(tl);
    td_grid_f32_free(dem);
    td_image_free(im);
    return 0;
}

static void parse_time(const char *path, double *wall, long *kb)
{
    FILE *f = fopen(path, "r");
    char line[512];
    *wall = -1;
    *kb = -1;
    if (!f)
        return;
    while (fgets(line, sizeof line, f)) {
        double h = 0, m = 0, s = 0;
        char *p = strstr(line, "Elapsed (wall clock) time");
        if (p && (p = strrchr(line, ' '))) {
            if (sscanf(p, " %lf:%lf:%lf", &h, &m, &s) == 3)
                *wall = h * 3600 + m * 60 + s;
            else if (sscanf(p, " %lf:%lf", &m, &s) == 2)
                *wall = m * 60 + s;
        }
        sscanf(line, " Maximum resident set size (kbytes): %ld", kb);
    }
    fclose(f);
}

/* The true lines and DEM of one seed sheet of the sweeps (800 x 800). */
static int sweep_sheet(td_gen_terrain_kind kind, int seed, td_lines **tl,
                       td_grid_f32 **dem, td_ctx *cx)
{
    td_gen_params gp = td_gen_defaults();
    gp.terrain = kind;
    gp.seed = (unsigned)seed;
    gp.w = gp.h = 800;
    *tl = NULL;
    *dem = NULL;
    return td_gen_sheet(&gp, NULL, tl, dem, cx);
}

/* RMSE (intervals) of the paper's method and three multidir settings from
 * the true lines, averaged over 6 seeds per shape at 800 x 800. */
static void seed_sweep(td_ctx *cx)
{
    static const td_gen_terrain_kind kinds[3] = {TD_GEN_HILLS, TD_GEN_CONE,
                                                 TD_GEN_RIDGES};
    static const int var[4] = {0, 2, 3, 5};
    double sum[4][3] = {{0}};
    int k, s, v;
    for (k = 0; k < 3; k++)
        for (s = 1; s <= 6; s++) {
            td_lines *tl;
            td_grid_f32 *dem;
            if (sweep_sheet(kinds[k], s, &tl, &dem, cx) != 0)
                return;
            for (v = 0; v < 4; v++) {
                const variant *vv = &variants[var[v]];
                td_interp_params p = td_interp_defaults();
                td_grid_f32 *g = NULL;
                td_compare_stats st;
                p.method = vv->m, p.scanline.peninsula = vv->peninsula;
                p.multidir.ndir = vv->ndir, p.multidir.weight = vv->weight;
                if (td_interp_lines(tl, 800, 800, &p, &g, cx) == 0 &&
                    td_compare_grids(g, dem, &st, cx) == 0)
                    sum[v][k] += st.rmse / td_interp_interval(tl) / 6;
                td_grid_f32_free(g);
            }
            td_lines_free(tl);
            td_grid_f32_free(dem);
        }
    printf("mean RMSE over seeds 1-6, 800 x 800, true lines (intervals):\n"
           "  %-48s %8s %8s %8s\n", "", "hills", "cone", "ridges");
    for (v = 0; v < 4; v++)
        printf("  %-48s %8.4f %8.4f %8.4f\n", variants[var[v]].name,
               sum[v][0], sum[v][1], sum[v][2]);
}

/* `topodig run` on a huge sheet through the CLI, one thread. */
/* RMSE (intervals) of the default with N sweeps of band-constrained
 * smoothing (--smooth N), mean of seeds 1-6 at 800 x 800, and its time. */
static void smooth_sweep(td_ctx *cx)
{
    static const td_gen_terrain_kind kinds[3] = {TD_GEN_HILLS, TD_GEN_CONE,
                                                 TD_GEN_RIDGES};
    static const int sweeps[5] = {0, 10, 30, 100, 300};
    double sum[5][3] = {{0}}, secs[5] = {0};
    int k, s, v;
    for (k = 0; k < 3; k++)
        for (s = 1; s <= 6; s++) {
            td_lines *tl;
            td_grid_f32 *dem;
            if (sweep_sheet(kinds[k], s, &tl, &dem, cx) != 0)
                return;
            for (v = 0; v < 5; v++) {
                td_interp_params p = td_interp_defaults();
                td_grid_f32 *g = NULL;
                td_compare_stats st;
                double t0 = td_now();
                p.smooth = sweeps[v];
                if (td_interp_lines(tl, 800, 800, &p, &g, cx) == 0 &&
                    td_compare_grids(g, dem, &st, cx) == 0)
                    sum[v][k] += st.rmse / td_interp_interval(tl) / 6;
                secs[v] += (td_now() - t0) / 18;
                td_grid_f32_free(g);
            }
            td_lines_free(tl);
            td_grid_f32_free(dem);
        }
    printf("default + --smooth N, mean RMSE over seeds 1-6, 800 x 800, true "
           "lines (intervals):\n  %-10s %8s %8s %8s %8s %10s\n", "sweeps",
           "hills", "cone", "ridges", "mean", "s / 0.64 Mpx");
    for (v = 0; v < 5; v++)
        printf("  %-10d %8.4f %8.4f %8.4f %8.4f %10.3f\n", sweeps[v],
               sum[v][0], sum[v][1], sum[v][2],
               (sum[v][0] + sum[v][1] + sum[v][2]) / 3, secs[v]);
}

static int huge_run(const opts *o, int size, td_ctx *cx)
{
    td_gen_params gp = sheet_params(TD_GEN_HILLS, size);
    td_image *im = NULL;
    td_lines *tl = NULL;
    td_grid_f32 *dem = NULL;
    char sheet[1024], out[1024], tfile[1024], cmd[8192];
    double dep[2 * 16], I, wall, t0 = td_now();
    size_t nd, k, pos;
    long kb;
    int rc;
    if ((rc = td_gen_sheet(&gp, &im, &tl, &dem, cx)) != 0)
        return rc;
    I = td_interp_interval(tl);
    snprintf(sheet, sizeof sheet, "%s/huge.png", o->dir);
    snprintf(out, sizeof out, "%s/huge_dem.tif", o->dir);
    snprintf(tfile, sizeof tfile, "%s/huge.time", o->dir);
    if ((rc = td_png_write(sheet, im, cx)) != 0)
        goto done;
    printf("topodig run on a %d x %d hills sheet (interval %g; sheet made "
           "and written in %.1f s), OMP_NUM_THREADS=1:\n", size, size, I,
           td_now() - t0);
    td_image_free(im);
    im = NULL;
    nd = depressions(tl, dem, dep, 16);
    pos = tl->v[0].n / 2;
    pos = (size_t)snprintf(cmd, sizeof cmd,
                           "OMP_NUM_THREADS=1 /usr/bin/time -v '%s' run '%s' "
                           "-o '%s' -q --interval %g --known %.3f,%.3f,%g",
                           o->topodig, sheet, out, I, tl->v[0].xy[2 * pos],
                           tl->v[0].xy[2 * pos + 1], tl->v[0].height);
    for (k = 0; k < nd && pos < sizeof cmd - 64; k++)
        pos += (size_t)snprintf(cmd + pos, sizeof cmd - pos,
                                " --depressions %.1f,%.1f", dep[2 * k],
                                dep[2 * k + 1]);
    snprintf(cmd + pos, sizeof cmd - pos, " 2>'%s'", tfile);
    if (system(cmd) != 0) {
        printf("  run failed (see %s)\n", tfile);
        goto done;
    }
    parse_time(tfile, &wall, &kb);
    printf("  wall %.2f s, peak %.1f MB = %.2f bytes per pixel\n", wall,
           kb / 1024.0, kb * 1024.0 / ((double)size * size));
    anchor_result("run, default method, vs truth", out, dem, I, wall);
done:
    td_image_free(im);
    td_lines_free(tl);
    td_grid_f32_free(dem);
    return rc;
}

int main(int argc, char **argv)
{
    opts o = {NULL, "build-bench/data", 5000, 10000, 1, 0};
    td_ctx cx;
    int i;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--topodig") && i + 1 < argc)
            o.topodig = argv[++i];
        else if (!strcmp(argv[i], "--dir") && i + 1 < argc)
            o.dir = argv[++i];
        else if (!strcmp(argv[i], "--big") && i + 1 < argc)
            o.big = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--huge") && i + 1 < argc)
            o.huge = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--no-anchors"))
            o.anchors = 0;
        else if (!strcmp(argv[i], "--sweeps-only"))
            o.smooth_only = 1;
    }
    mkdir(o.dir, 0777);
    td_ctx_init(&cx);
    printf("interpolation accuracy and speed (errors in contour intervals; "
           "cov = share of the true grid determined)\n");
    if (!o.smooth_only) {
        one_sheet(&o, TD_GEN_HILLS, "hills", 1000, 1, &cx);
        one_sheet(&o, TD_GEN_CONE, "cone", 1000, 1, &cx);
        one_sheet(&o, TD_GEN_RIDGES, "ridges", 1000, 1, &cx);
        seed_sweep(&cx);
    }
    smooth_sweep(&cx);
    if (o.smooth_only)
        return 0;
    if (o.big > 0) { /* no anchors: r.surf.contour takes minutes at 1000 */
        one_sheet(&o, TD_GEN_HILLS, "hills", o.big, 0, &cx);
        one_sheet(&o, TD_GEN_CONE, "cone", o.big, 0, &cx);
        one_sheet(&o, TD_GEN_RIDGES, "ridges", o.big, 0, &cx);
    }
    if (o.huge > 0 && o.topodig && huge_run(&o, o.huge, &cx) != 0)
        printf("  huge run failed: %s\n", td_errmsg(&cx));
    return 0;
}
