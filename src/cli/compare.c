/* topodig compare: two DEMs -> RMSE, MAE, max |d|, bias, coverage. */
#include "src/cli/cli.h"

#include "src/compare/compare.h"
#include "src/io/io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct cmp_opts {
    const char *in[2], *diff, *profile_out;
    int json, quiet, psize[2];
    double range;
    td_opt_points profile;
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
        {"profile", 0, TD_OPT_POINTS, &o->profile, .n = 4,
         .meta = "X0,Y0,X1,Y1", .help = "a cross-section of both DEMs along "
         "the line\nfrom X0,Y0 to X1,Y1 (map coordinates of A)\ndrawn to "
         "the -o picture (PNG): B in black,\nA in red"},
        {"output", 'o', TD_OPT_OUTPUT, &o->profile_out, .meta = "PROFILE.png",
         .help = "the --profile picture"},
        {"profile-size", 0, TD_OPT_FUNC, o->psize, .fn = td_cli_parse_size,
         .meta = "WxH", .help = "the --profile picture's size (default "
         "800x400)", .no_default = 1},
        {NULL}};
    const td_cmd c = {
        "compare", "A.tif B.tif [--json] [--diff DIFF.png]\n"
        "                      [--profile X0,Y0,X1,Y1 -o PROFILE.png]",
        "Compare DEM A (a result) with DEM B (the reference) cell by cell,\n"
        "d = A - B, over the cells with data in both, and print RMSE, MAE,\n"
        "max |d| (and where), bias (mean d) and coverage (cells with data in\n"
        "both / cells with data in B).  A and B: GeoTIFF/TIFF DEMs or ESRI\n"
        "ASCII grids of the same size.  --profile draws both along one line\n"
        "(a cross-section, as a handout shows a reconstruction beside the\n"
        "terrain) and prints the RMSE and largest |d| along it.\n",
        NULL, opts, "two DEM files A and B", 2, 2, o->in, NULL, NULL,
        &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc == 0 && (o->profile.n > 1 || !o->profile.n != !o->profile_out))
        return td_cli_failf("compare", "--profile X0,Y0,X1,Y1 and -o "
                            "PROFILE.png go together (one line)");
    return rc;
}

/* --profile: sample, draw, write; RMSE and max |d| along it to stdout. */
static int profile(const cmp_opts *o, const td_grid_f32 *a,
                   const td_grid_f32 *b, const td_georef *g, td_ctx *cx)
{
    const double *q = o->profile.v;
    double x0, y0, x1, y1, len, s2 = 0, mx = 0;
    double *va, *vb;
    size_t n, i, m = 0;
    td_image *im = NULL;
    int rc;
    if (td_georef_to_cells(g, q[0], q[1], &x0, &y0) != 0 ||
        td_georef_to_cells(g, q[2], q[3], &x1, &y1) != 0)
        return td_seterr(cx, TD_EINVAL, "%s: its georeferencing cannot be "
                         "inverted", o->in[0]);
    n = (size_t)ceil(2 * hypot(x1 - x0, y1 - y0)) + 2;
    if (n > 1000000)
        n = 1000000;
    len = hypot(q[2] - q[0], q[3] - q[1]);
    va = malloc(n * sizeof *va), vb = malloc(n * sizeof *vb);
    if (!va || !vb) {
        free(va), free(vb);
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    }
    if ((rc = td_compare_profile(a, b, x0, y0, x1, y1, n, va, vb, cx)) == 0 &&
        (rc = td_compare_profile_image(va, vb, n, len,
                                       o->psize[0] ? o->psize[0] : 800,
                                       o->psize[0] ? o->psize[1] : 400, &im,
                                       cx)) == 0 &&
        (rc = td_png_write(o->profile_out, im, cx)) == 0) {
        for (i = 0; i < n; i++)
            if (isfinite(va[i]) && isfinite(vb[i])) {
                double d = va[i] - vb[i];
                s2 += d * d, m++;
                mx = fabs(d) > mx ? fabs(d) : mx;
            }
        if (!o->quiet)
            printf("profile   length %.6g, %zu samples with data in both, "
                   "rmse %.6g, max |d| %.6g\n", len, m, m ? sqrt(s2 / m) : 0.0,
                   mx);
    }
    td_image_free(im);
    free(va), free(vb);
    return rc;
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
    td_georef geo;
    int rc;
    memset(&o, 0, sizeof o);
    if ((rc = parse_args(argc, argv, &o)) != 0) {
        td_opt_points_free(&o.profile);
        return rc == 2 ? 0 : 1;
    }
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if ((rc = td_dem_read(o.in[0], &a, &geo, &cx)) != 0 ||
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
    if (o.profile_out && (rc = profile(&o, a, b, &geo, &cx)) != 0)
        goto fail;
fail:
    td_opt_points_free(&o.profile);
    td_georef_clear(&geo);
    td_image_free(im);
    td_grid_f32_free(a);
    td_grid_f32_free(b);
    return rc == 0 ? 0 : td_cli_fail("compare", &cx);
}
