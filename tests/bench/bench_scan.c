/* bench_scan: throughput of each scanner step on a generated sheet, the
 * whole `topodig scan` with its peak memory, and OpenCV ximgproc's
 * Zhang-Suen thinning on the same mask for a ratio measured in the same run.
 *
 *   bench_scan [--size N] [--dir DIR] [--topodig PATH]
 *
 * Prints one line per measurement; never fails the build (exit 0 unless the
 * set-up itself fails). */
#include "samples/gen/gen.h"
#include "scanner/scan.h"
#include "src/io/io.h"
#include "tests/util/bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#ifdef _OPENMP
#include <omp.h>
#endif

static double mpx(int w, int h, double s)
{
    return s > 0 ? (double)w * h / 1e6 / s : 0.0;
}

static void row(const char *what, int w, int h, double s)
{
    printf("  %-28s %8.3f s  %8.1f Mpx/s\n", what, s, mpx(w, h, s));
}

/* Make (or reuse) a 6000 x 6000 pair: the same sheet as a printed colour
 * map (tdgen --print) and in grey, both with blur 0.8 and noise 6, PNG. */
static int make_pair(const char *colour, const char *grey, int size,
                     td_ctx *cx)
{
    int k, rc = 0;
    for (k = 0; k < 2 && rc == 0; k++) {
        const char *path = k ? grey : colour;
        td_gen_params gp = td_gen_defaults();
        td_image *im = NULL;
        struct stat sb;
        if (stat(path, &sb) == 0)
            continue;
        gp.w = gp.h = size;
        gp.terrain = TD_GEN_RIDGES;
        gp.line_width = 2.0;
        gp.seed = 7;
        gp.blur = 0.8;
        gp.noise = 6;
        gp.colour = gp.distractors = gp.print = !k;
        fprintf(stderr, "generating %dx%d sheet %s ...\n", size, size, path);
        if ((rc = td_gen_sheet(&gp, &im, NULL, NULL, cx)) == 0)
            rc = td_png_write(path, im, cx);
        td_image_free(im);
    }
    return rc;
}

/* Run the CLI's scan once; wall seconds and peak RSS (bytes). */
static int run_cli(const char *exe, const char *sheet, const char *out,
                   double *secs, double *peak)
{
    char *argv[] = {(char *)exe, "scan", (char *)sheet, "-o", (char *)out,
                    "--quiet", NULL};
    return td_bench_child(argv, NULL, secs, peak, NULL);
}

static int stages(const char *sheet, td_ctx *cx)
{
    td_scan_params sp = td_scan_defaults();
    td_image *im = NULL;
    td_grid_u8 *m = NULL, *zs = NULL;
    td_lines *ls = NULL;
    td_join_params jp;
    double t;
    size_t ink = 0, i, n;
    int rc;
    t = td_now();
    if ((rc = td_image_read(sheet, &im, NULL, cx)) != 0)
        return rc;
    row("read (TIFF, Deflate)", im->w, im->h, td_now() - t);
    if (!(m = td_grid_u8_new(im->w, im->h, cx)))
        return TD_ENOMEM;
    t = td_now();
    if ((rc = td_binarise(im, &sp.bin, m, cx)) != 0)
        goto done;
    row("binarise (dark, otsu)", im->w, im->h, td_now() - t);
    n = (size_t)m->w * m->h;
    for (i = 0; i < n; i++)
        ink += m->data[i];
    printf("  ink fraction %.1f %%\n", 100.0 * ink / n);
    if (!(zs = td_grid_u8_dup(m, cx)))
        goto done;
    t = td_now();
    if ((rc = td_thin_hilditch(m, NULL, cx)) != 0)
        goto done;
    {
        double th = td_now() - t, tz;
        row("thin (Hilditch)", m->w, m->h, th);
        t = td_now();
        if (td_cv_thin_zhangsuen(zs, cx) == 0) {
            tz = td_now() - t;
            row("thin (ximgproc Zhang-Suen)", m->w, m->h, tz);
            printf("  Hilditch / ximgproc speed ratio: %.1fx\n", tz / th);
        } else {
            printf("  ximgproc not available: %s\n", td_errmsg(cx));
            td_ctx_clear(cx);
        }
    }
    t = td_now();
    if ((rc = td_despur(m, &sp.spur, NULL, cx)) != 0)
        goto done;
    row("despur (length)", m->w, m->h, td_now() - t);
    t = td_now();
    if ((rc = td_trace(m, &sp.trace, &ls, NULL, cx)) != 0)
        goto done;
    row("trace (3x3 + 5x5)", m->w, m->h, td_now() - t);
    jp = td_join_defaults(m->w, m->h);
    t = td_now();
    if ((rc = td_join(&ls, &jp, NULL, cx)) != 0)
        goto done;
    row("join", m->w, m->h, td_now() - t);
    printf("  %zu lines\n", ls->n);
done:
    td_lines_free(ls);
    td_grid_u8_free(m);
    td_grid_u8_free(zs);
    td_image_free(im);
    return rc;
}

int main(int argc, char **argv)
{
    const char *dir = "build-bench/data", *exe = "build-bench/topodig";
    char sheet[1024], out[1024];
    int size = 10000, i;
    double secs, peak;
    td_ctx cx;
    td_ctx_init(&cx);
    for (i = 1; i + 1 < argc; i += 2)
        td_bench_option(argc, argv, i, &size, &dir, &exe);
    mkdir(dir, 0777);
    snprintf(sheet, sizeof sheet, "%s/ridges%d.tif", dir, size);
    snprintf(out, sizeof out, "%s/ridges%d.geojson", dir, size);
    if (td_bench_ridges_sheet(sheet, size, NULL, &cx) != 0) {
        fprintf(stderr, "bench_scan: %s\n", td_errmsg(&cx));
        return 1;
    }
#ifdef _OPENMP
    printf("scan benchmark, %dx%d sheet (3-px lines), %d threads\n", size,
           size, omp_get_max_threads());
#else
    printf("scan benchmark, %dx%d sheet (3-px lines), one thread\n", size,
           size);
#endif
    if (stages(sheet, &cx) != 0)
        printf("  stage failed: %s\n", td_errmsg(&cx));
    if (run_cli(exe, sheet, out, &secs, &peak) == 0) {
        row("topodig scan (whole, CLI)", size, size, secs);
        printf("  peak memory %.0f MB = %.2f bytes/pixel\n", peak / 1e6,
               peak / ((double)size * size));
    } else {
        printf("  topodig scan failed (%s)\n", exe);
    }
    { /* colour (--ink auto: the palette) against grey, same sheet */
        char col[1024], grey[1024];
        double sc, sg, pc, pg;
        int cs = size < 6000 ? size : 6000;
        snprintf(col, sizeof col, "%s/print%d.png", dir, cs);
        snprintf(grey, sizeof grey, "%s/grey%d.png", dir, cs);
        if (make_pair(col, grey, cs, &cx) != 0) {
            printf("  colour pair: %s\n", td_errmsg(&cx));
        } else if (run_cli(exe, grey, out, &sg, &pg) == 0 &&
                   run_cli(exe, col, out, &sc, &pc) == 0) {
            printf("printed colour map vs the same sheet in grey, %dx%d PNG, "
                   "whole CLI scan\n", cs, cs);
            row("grey (--ink auto = dark)", cs, cs, sg);
            row("colour (--ink auto: palette)", cs, cs, sc);
            printf("  colour / grey %.2fx (target <= 2); peak %.2f / %.2f "
                   "bytes/pixel\n", sc / sg, pc / ((double)cs * cs),
                   pg / ((double)cs * cs));
        } else {
            printf("  colour pair: topodig scan failed\n");
        }
    }
    return 0;
}
