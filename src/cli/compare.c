/* topodig compare: two DEMs -> RMSE, MAE, max |d|, bias, coverage. */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/compare/compare.h"
#include "src/io/io.h"

#include <getopt.h>
#include <stdio.h>
#include <string.h>

static const char help[] =
    "usage: topodig compare A.tif B.tif [--json] [--diff DIFF.png]\n"
    "\n"
    "Compare DEM A (a result) with DEM B (the reference) cell by cell,\n"
    "d = A - B, over the cells with data in both, and print RMSE, MAE,\n"
    "max |d| (and where), bias (mean d) and coverage (cells with data in\n"
    "both / cells with data in B).  A and B: GeoTIFF/TIFF DEMs or ESRI\n"
    "ASCII grids of the same size.\n"
    "\n"
    "options:\n"
    "      --json          print one JSON object instead of text\n"
    "      --diff FILE     write a difference picture (PNG): blue where A\n"
    "                      is below B, red above, white equal; grey where\n"
    "                      only one has data\n"
    "      --range R       |d| at which the picture saturates (default\n"
    "                      3 x RMSE)\n"
    "  -q, --quiet         no progress\n"
    "  -h, --help          this help\n";

typedef struct cmp_opts {
    const char *a, *b, *diff;
    int json, quiet;
    double range;
} cmp_opts;

enum { O_JSON = 256, O_DIFF, O_RANGE };

static int parse_args(int argc, char **argv, cmp_opts *o)
{
    static const struct option lo[] = {
        {"json", 0, 0, O_JSON}, {"diff", 1, 0, O_DIFF}, {"range", 1, 0, O_RANGE},
        {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    int c;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "qh", lo, NULL)) != -1) {
        switch (c) {
        case 'h': fputs(help, stdout); return 2;
        case 'q': o->quiet = 1; break;
        case O_JSON: o->json = 1; break;
        case O_DIFF: o->diff = optarg; break;
        case O_RANGE:
            if (td_cli_parse_double(optarg, 1e-12, 1e12, &o->range) != 0)
                return td_cli_failf("compare", "--range: '%s' is not a "
                                    "positive number", optarg);
            break;
        default:
            return td_cli_failf("compare", "bad or incomplete option '%s' "
                                "(see topodig compare --help)",
                                argv[optind - 1]);
        }
    }
    if (optind != argc - 2)
        return td_cli_failf("compare", "expected two DEM files A and B (see "
                            "topodig compare --help)");
    o->a = argv[optind];
    o->b = argv[optind + 1];
    return 0;
}

static void print(const cmp_opts *o, const td_grid_f32 *a,
                  const td_compare_stats *s)
{
    if (o->json) {
        printf("{\"a\": \"%s\", \"b\": \"%s\", \"width\": %d, \"height\": %d, "
               "\"cells\": %zu, \"rmse\": %.6g, \"mae\": %.6g, "
               "\"max_abs\": %.6g, \"max_x\": %d, \"max_y\": %d, "
               "\"bias\": %.6g, \"coverage\": %.6f, \"cells_a\": %zu, "
               "\"cells_b\": %zu}\n", o->a, o->b, a->w, a->h, s->n_both,
               s->rmse, s->mae, s->max_abs, s->max_x, s->max_y, s->bias,
               s->coverage, s->n_a, s->n_b);
        return;
    }
    printf("compare %s with %s (%d x %d)\n", o->a, o->b, a->w, a->h);
    printf("cells     %zu with data in both (A %zu, B %zu)\n", s->n_both,
           s->n_a, s->n_b);
    printf("coverage  %.4f\n", s->coverage);
    printf("rmse      %.6g\n", s->rmse);
    printf("mae       %.6g\n", s->mae);
    printf("max |d|   %.6g at column %d, row %d\n", s->max_abs, s->max_x,
           s->max_y);
    printf("bias      %.6g\n", s->bias);
}

int td_cmd_compare(int argc, char **argv)
{
    cmp_opts o;
    td_ctx cx;
    td_grid_f32 *a = NULL, *b = NULL;
    td_image *im = NULL;
    td_compare_stats st;
    int rc;
    memset(&o, 0, sizeof o);
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    if ((rc = td_dem_read(o.a, &a, NULL, &cx)) != 0 ||
        (rc = td_dem_read(o.b, &b, NULL, &cx)) != 0)
        goto fail;
    if ((rc = td_compare_grids(a, b, &st, &cx)) != 0) {
        td_ctx_clear(&cx);
        rc = td_seterr(&cx, TD_EINVAL, "%s is %d x %d but %s is %d x %d",
                       o.a, a->w, a->h, o.b, b->w, b->h);
        goto fail;
    }
    if (st.n_both == 0) { /* no statistic means anything */
        rc = td_seterr(&cx, TD_EFORMAT,
                       "%s and %s have no cell with data in both", o.a, o.b);
        goto fail;
    }
    if (o.diff &&
        ((rc = td_compare_diff_image(a, b, o.range, &im, &cx)) != 0 ||
         (rc = td_png_write(o.diff, im, &cx)) != 0))
        goto fail;
    print(&o, a, &st);
fail:
    td_image_free(im);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    return rc == 0 ? 0 : td_cli_fail("compare", &cx);
}
