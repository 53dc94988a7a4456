/* topodig compare: two DEMs -> RMSE, MAE, max |d|, bias, coverage. */
#include "src/cli/cli.h"

#include "src/compare/compare.h"
#include "src/io/io.h"

#include <stdio.h>
#include <string.h>

typedef struct cmp_opts {
    const char *in[2], *diff;
    int json, quiet;
    double range;
} cmp_opts;

static int parse_args(int argc, char **argv, cmp_opts *o)
{
    const td_opt opts[] = {
        {"json", 0, TD_OPT_FLAG, &o->json, .help = "print one JSON object "
         "instead of text"},
        {"diff", 0, TD_OPT_OUTPUT, &o->diff, .meta = "FILE", .help =
         "write a difference picture (PNG): blue where A\nis below B, red "
         "above, white equal; grey where\nonly one has data"},
        {"range", 0, TD_OPT_DOUBLE, &o->range, 1e-12, 1e12, .meta = "R",
         .help = "|d| at "
         "which the picture saturates (default\n3 x RMSE)", .no_default = 1},
        {NULL}};
    const td_cmd c = {
        "compare", "A.tif B.tif [--json] [--diff DIFF.png]",
        "Compare DEM A (a result) with DEM B (the reference) cell by cell,\n"
        "d = A - B, over the cells with data in both, and print RMSE, MAE,\n"
        "max |d| (and where), bias (mean d) and coverage (cells with data in\n"
        "both / cells with data in B).  A and B: GeoTIFF/TIFF DEMs or ESRI\n"
        "ASCII grids of the same size.\n",
        NULL, opts, "two DEM files A and B", 2, 2, o->in, NULL, NULL,
        &o->quiet};
    return td_opt_parse(&c, argc, argv);
}

static void print(const cmp_opts *o, const td_grid_f32 *a,
                  const td_compare_stats *s)
{
    if (o->json) {
        printf("{\"a\": \"%s\", \"b\": \"%s\", \"width\": %d, \"height\": %d, "
               "\"cells\": %zu, \"rmse\": %.6g, \"mae\": %.6g, "
               "\"max_abs\": %.6g, \"max_x\": %d, \"max_y\": %d, "
               "\"bias\": %.6g, \"coverage\": %.6f, \"cells_a\": %zu, "
               "\"cells_b\": %zu}\n", o->in[0], o->in[1], a->w, a->h, s->n_both,
               s->rmse, s->mae, s->max_abs, s->max_x, s->max_y, s->bias,
               s->coverage, s->n_a, s->n_b);
        return;
    }
    printf("compare %s with %s (%d x %d)\n", o->in[0], o->in[1], a->w, a->h);
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
    if ((rc = td_dem_read(o.in[0], &a, NULL, &cx)) != 0 ||
        (rc = td_dem_read(o.in[1], &b, NULL, &cx)) != 0)
        goto fail;
    if ((rc = td_compare_grids(a, b, &st, &cx)) != 0) {
        td_ctx_clear(&cx);
        rc = td_seterr(&cx, TD_EINVAL, "%s is %d x %d but %s is %d x %d",
                       o.in[0], a->w, a->h, o.in[1], b->w, b->h);
        goto fail;
    }
    if (st.n_both == 0) { /* no statistic means anything */
        rc = td_seterr(&cx, TD_EFORMAT,
                       "%s and %s have no cell with data in both", o.in[0], o.in[1]);
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
