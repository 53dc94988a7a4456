/* bench_dem: the DEM `topodig run` makes with no option at all (printed
 * labels read, interval inferred) from sheets drawn from the real DEMs
 * (tests/data/dems), against the DEM interpolated from the sheet's true
 * lines: RMSE of each against the true DEM and their ratio (the heights
 * issue's target: run within 10 % of the true lines), with the walls put
 * back and the breaks bridged as run does them, and each turned off; and
 * where the loss comes from: the lines run traced and labelled, given
 * their true heights (the median of the true DEM under each, to the
 * nearest level) and interpolated as the true lines are ("traced"; what
 * the tracing alone costs, with the lines run left without a height left
 * out), and every traced line so ("all").  Numbers for docs/label.md
 * ("Where the DEMs stand") and benchmarks.md.
 *
 *   bench_dem [--only NAME] [--dir TMPDIR] [--streams] [--stream-gap PX]
 *             [--keep] [--steps]
 *
 * --streams: the colour sheets' water from the terrain (tdgen --streams);
 * --stream-gap: the scan's joins across the water (0: off); --keep: each
 * sheet (bench_dem_NAME_K.png) stays in the folder, with its true DEM
 * beside it (bench_dem_NAME_K_truth.tif: `topodig run` the sheet and
 * `topodig compare --diff` against it shows where a DEM goes wrong);
 * --steps: `run --steps` (the labeller's step edges). */
#include "tests/util/bench.h"
#include "tests/util/hsheet.h"

#include "interp/interp.h"
#include "src/compare/compare.h"
#include "src/io/io.h"
#include "src/pipeline/pipeline.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* RMSE of dem against the true DEM, or -1. */
static double rmse_of(const td_grid_f32 *dem, const td_grid_f32 *truth)
{
    td_compare_stats st;
    td_ctx cx;
    td_ctx_init(&cx);
    return td_compare_grids(dem, truth, &st, &cx) == 0 ? st.rmse : -1.0;
}

/* run on the sheet at path with p; the DEM's RMSE, or -1 (message to
 * stdout).  *secs gets the wall time. */
static double run_rmse(const char *path, const td_run_params *p,
                       const td_grid_f32 *truth, size_t *walls, size_t *breaks,
                       double *secs)
{
    td_run_result r;
    td_ctx cx;
    double t0 = td_now(), e = -1.0;
    td_ctx_init(&cx);
    if (td_pipeline_run(path, p, &r, &cx) != 0)
        printf("   run failed: %s\n", td_errmsg(&cx));
    else {
        e = rmse_of(r.dem, truth);
        *walls = r.walls_back, *breaks = r.breaks_closed;
    }
    *secs = td_now() - t0;
    td_run_result_free(&r);
    return e;
}

/* on_labelled: a copy of the labelled lines (before the run drops those
 * without a height) into *(td_lines **)user. */
static int keep_lines(const td_run_result *r, void *user)
{
    td_lines **out = user;
    td_ctx cx;
    td_ctx_init(&cx);
    td_lines_free(*out);
    *out = td_lines_copy(r->lines, &cx);
    return *out ? 0 : TD_ENOMEM;
}

static int cmp_float(const void *pa, const void *pb)
{
    float a = *(const float *)pa, b = *(const float *)pb;
    return (a > b) - (a < b);
}

/* Every line of ls its true height: the median of the true DEM under its
 * vertices, to the nearest level base + k interval; with all 0 only the
 * lines the run gave a height (the others keep none). */
static void true_heights(td_lines *ls, const td_grid_f32 *dem, double base,
                         double interval, int all)
{
    size_t i, k;
    for (i = 0; i < ls->n; i++) {
        td_line *l = &ls->v[i];
        float *v;
        size_t n = 0;
        if ((!all && !l->has_height) || !(v = malloc(l->n * sizeof *v + 1)))
            continue;
        for (k = 0; k < l->n; k++) {
            long x = (long)l->xy[2 * k], y = (long)l->xy[2 * k + 1];
            if (x >= 0 && y >= 0 && x < dem->w && y < dem->h)
                v[n++] = dem->data[(size_t)y * dem->stride + (size_t)x];
        }
        if (n) {
            qsort(v, n, sizeof *v, cmp_float);
            l->has_height = 1;
            l->height =
                base + interval * floor((v[n / 2] - base) / interval + 0.5);
        }
        free(v);
    }
}

/* The traced lines ls with the true heights (the run's labelled ones, or
 * all), interpolated as the truth column is: RMSE against the true DEM,
 * or -1. */
static double traced_rmse(const td_lines *ls, const td_grid_f32 *dem,
                          const td_interp_params *ip, double base, int all,
                          int w, int h)
{
    td_ctx cx;
    td_lines *c;
    td_grid_f32 *g = NULL;
    double e = -1;
    size_t i;
    td_ctx_init(&cx);
    if (!ls || !(c = td_lines_copy(ls, &cx)))
        return -1;
    true_heights(c, dem, base, ip->interval, all);
    for (i = c->n; i-- > 0;) /* as run drops them */
        if (!c->v[i].has_height)
            td_lines_remove(c, i);
    if (td_interp_lines(c, w, h, ip, &g, &cx) == 0)
        e = rmse_of(g, dem);
    td_grid_f32_free(g);
    td_lines_free(c);
    return e;
}

static const char usage[] = "usage: bench_dem [--only NAME] [--dir TMPDIR] "
                            "[--streams] [--stream-gap PX] [--keep] [--steps]\n";

int main(int argc, char **argv)
{
    const char *only = NULL, *dir = "build-bench/data";
    static const int kinds[4] = {1, 2, 3, 4};
    size_t s;
    int a, k, streams = 0, keep = 0, steps = 0;
    double gap = -1;
    for (a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--only") && a + 1 < argc)
            only = argv[++a];
        else if (!strcmp(argv[a], "--dir") && a + 1 < argc)
            dir = argv[++a];
        else if (!strcmp(argv[a], "--streams"))
            streams = 1;
        else if (!strcmp(argv[a], "--keep"))
            keep = 1;
        else if (!strcmp(argv[a], "--steps"))
            steps = 1;
        else if (!strcmp(argv[a], "--stream-gap") && a + 1 < argc)
            gap = atof(argv[++a]);
        else if (!strcmp(argv[a], "--topodig") && a + 1 < argc)
            a++; /* make bench passes it to every benchmark */
        else
            return td_bench_usage("bench_dem", argv[a], usage);
    }
    if (td_bench_outdir("bench_dem", dir) != 0)
        return 1;
    printf("run with no option (labels read, interval inferred), DEM RMSE "
           "against the true DEM; traced: the lines run labelled with their "
           "true\nheights, all: every traced line so, both interpolated as "
           "the truth is\n%-12s %-8s %8s %8s %8s %8s %8s %8s %7s %6s %6s "
           "%6s\n",
           "sheet", "scan", "run", "no-walls", "no-bridge", "traced", "all",
           "truth", "ratio", "walls", "breaks", "secs");
    for (s = 0; s < sizeof td_real_sheets / sizeof *td_real_sheets; s++) {
        const td_real_sheet *rs = &td_real_sheets[s];
        if (only && strcmp(only, rs->name))
            continue;
        for (k = 0; k < 4; k++) {
            td_gen_params gp;
            td_image *im = NULL;
            td_lines *tl = NULL;
            td_grid_f32 *tdem = NULL, *tli = NULL, *src;
            td_lines *lab = NULL;
            td_interp_params ip = td_interp_defaults();
            td_run_params p = td_run_defaults();
            td_ctx cx;
            char path[512];
            double e[5], et = -1, secs, sx;
            size_t walls = 0, breaks = 0, wx, bx;
            td_ctx_init(&cx);
            if (!(src = td_hsheet_dem_sheet(rs->dem, rs->scale, &gp, &cx))) {
                printf("%-12s %s\n", rs->name, td_errmsg(&cx));
                break;
            }
            gp.interval = rs->interval;
            td_hsheet_defects(&gp, kinds[k]);
            gp.streams = streams && gp.colour;
            if (gap >= 0)
                p.scan.join.cross_gap = gap;
            p.steps = steps;
            snprintf(path, sizeof path, "%s/bench_dem_%s_%d.png", dir, rs->name,
                     kinds[k]);
            if (td_gen_sheet(&gp, &im, &tl, &tdem, &cx) != 0 ||
                td_png_write(path, im, &cx) != 0) {
                printf("%-12s %s\n", rs->name, td_errmsg(&cx));
                goto next;
            }
            if (keep) {
                char tp[540];
                snprintf(tp, sizeof tp, "%s/bench_dem_%s_%d_truth.tif", dir,
                         rs->name, kinds[k]);
                if (td_geotiff_write_f32(tp, tdem, NULL, &cx) != 0) {
                    printf("%-12s %s\n", rs->name, td_errmsg(&cx));
                    td_ctx_clear(&cx);
                }
            }
            ip.interval = td_gen_auto_interval(&gp, tdem);
            if (td_interp_lines(tl, im->w, im->h, &ip, &tli, &cx) == 0)
                et = rmse_of(tli, tdem);
            p.on_labelled = keep_lines, p.user = &lab;
            e[0] = run_rmse(path, &p, tdem, &walls, &breaks, &secs);
            p.on_labelled = NULL;
            e[3] = traced_rmse(lab, tdem, &ip, gp.base, 0, im->w, im->h);
            e[4] = traced_rmse(lab, tdem, &ip, gp.base, 1, im->w, im->h);
            p.walls_back = 0;
            e[1] = run_rmse(path, &p, tdem, &wx, &bx, &sx);
            p.walls_back = 1, p.bridge = 0;
            e[2] = run_rmse(path, &p, tdem, &wx, &bx, &sx);
            printf("%-12s %-8s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %6.1f%% "
                   "%6zu %6zu %6.2f\n",
                   rs->name, td_defect_names[kinds[k]], e[0], e[1], e[2], e[3],
                   e[4], et, et > 0 ? 100.0 * (e[0] / et - 1) : 0.0, walls,
                   breaks, secs);
            fflush(stdout);
        next:
            if (!keep)
                remove(path);
            td_image_free(im);
            td_lines_free(tl);
            td_lines_free(lab);
            td_grid_f32_free(tdem);
            td_grid_f32_free(tli);
            td_grid_f32_free(src);
        }
    }
    return 0;
}
