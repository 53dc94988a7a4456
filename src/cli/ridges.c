/* topodig ridges: labelled contour lines -> ridge, valley and inflection
 * lines (GeoJSON), optionally the signed curvature per contour sample. */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/core/core.h"
#include "interp/homotopy.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct rg_opts {
    const char *in, *out, *csv, *like;
    int quiet;
    td_homotopy_params p;
} rg_opts;

static int parse_args(int argc, char **argv, rg_opts *o)
{
    const td_opt opts[] = {
        {"curvature-csv", 0, TD_OPT_OUTPUT, &o->csv, .meta = "F", .help =
         "signed curvature per contour sample: line,\ni, x, y, s, kappa "
         "(1/px, > 0 convex)"},
        {"epsilon", 0, TD_OPT_DOUBLE, &o->p.epsilon, 0, 180, .meta = "DEG",
         .help = "turning-angle threshold: a stretch between\ninflections "
         "that turns less is dropped"},
        {"smooth", 0, TD_OPT_DOUBLE, &o->p.smooth, 0, 100, .meta = "PX",
         .help = "Gaussian smoothing along contours"},
        {"like", 0, TD_OPT_STRING, &o->like, .meta = "SCAN", .help = "the "
         "scan: sheet size and georeferencing\n(default: the lines' extent, "
         "the pixel frame)"},
        {NULL}};
    const td_cmd c = {
        "ridges", "LABELLED.geojson -o RIDGES.geojson\n"
        "                      [--curvature-csv FILE] [--epsilon DEG]\n"
        "                      [--like SCAN]",
        "Ridge and valley lines from the curvature of the labelled contours\n"
        "(the homotopy paper, 003 §4-5): each contour is oriented with higher\n"
        "ground on the left, smoothed and fitted with a C2 spline; ridge points\n"
        "sit at the curvature maxima of convex stretches, valley points at the\n"
        "minima of concave ones; points of one kind on adjacent contours are\n"
        "linked, and ridges (valleys) that merge form one tree.\n"
        "Output by extension: GeoJSON LineStrings with [x, y, height]\n"
        "positions (.gpkg, .shp: 3-D lines; .dxf: 3-D polylines) and\n"
        "properties kind (ridge, valley, inflection), tree (null for\n"
        "inflections) and heights, in the frame of the scan (README, Frames).\n",
        "Summary on stderr: contours, ridge/valley points and trees, links,\n"
        "suspended points, seconds.\n",
        opts, "one LABELLED.geojson file", 1, 1, &o->in, &o->out,
        "RIDGES.geojson", &o->quiet};
    return td_opt_parse(&c, argc, argv);
}

static int write_csv(const char *path, const td_ridges *r,
                     const td_lines *ls, td_ctx *cx)
{
    size_t i, k, tmpsize = strlen(path) + 32;
    char *tmp = malloc(tmpsize);
    FILE *f;
    int rc;
    if (!tmp)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        free(tmp);
        return cx->code ? cx->code : TD_EIO;
    }
    fputs("line,i,x,y,s,kappa\n", f);
    for (i = 0; i < r->ncurve; i++) {
        const td_rv_curve *c = &r->curve[i];
        for (k = 0; k < c->n; k++)
            fprintf(f, "%ld,%zu,%.3f,%.3f,%.3f,%.6g\n", ls->v[i].id, k,
                    c->x[k], c->y[k], c->s[k], c->kappa[k]);
    }
    rc = td_atomic_commit(f, tmp, path, cx);
    free(tmp);
    return rc;
}

static const char *kind_name(int k)
{
    return k == TD_RV_RIDGE ? "ridge" : k == TD_RV_VALLEY ? "valley"
                                                          : "inflection";
}

/* The paths as io's 3-D paths, written by the output's extension. */
static int write_paths(const char *path, const td_rv_path *v, size_t n,
                       const td_georef *georef, td_ctx *cx)
{
    td_path3 *q = calloc(n + 1, sizeof *q);
    td_paths3 P = {q, n};
    size_t i;
    int rc;
    if (!q)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (i = 0; i < n; i++) {
        q[i].xyz = v[i].xyz;
        q[i].n = v[i].n;
        q[i].kind = kind_name(v[i].kind);
        q[i].tree = v[i].tree;
    }
    rc = td_vector_write_paths(path, &P, georef, cx);
    free(q);
    return rc;
}

static void summary(const td_ridges *r, double secs)
{
    size_t i, n[3] = {0, 0, 0};
    for (i = 0; i < r->npt; i++)
        n[r->pt[i].kind]++;
    fprintf(stderr, "ridges: %zu contours, %zu ridge points in %ld trees, "
            "%zu valley points in %ld trees, %zu inflections, %zu links, "
            "%zu suspended, %.2f s\n", r->ncurve, n[0], r->nridge, n[1],
            r->nvalley, n[2], r->nlink, r->suspended, secs);
}

int td_cmd_ridges(int argc, char **argv)
{
    rg_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_georef geo;
    td_lines *ls = NULL;
    td_ridges *r = NULL;
    td_rv_path *paths = NULL;
    size_t np = 0;
    double t0 = td_now();
    int rc, w = 0, h = 0, ch;
    memset(&o, 0, sizeof o);
    o.p = td_homotopy_defaults();
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    if (o.like && (rc = td_image_info(o.like, &w, &h, &ch, &geo, &cx)) != 0)
        goto fail;
    if ((rc = td_vector_read_lines(o.in, &geo, &ls, NULL, NULL, &cx)) != 0)
        goto fail;
    if (!o.like && (rc = td_lines_extent(ls, &w, &h, &cx)) != 0)
        goto fail;
    if ((rc = td_ridges_find(ls, w, h, &o.p, &r, &cx)) != 0 ||
        (rc = td_ridges_paths(r, &paths, &np, &cx)) != 0 ||
        (o.csv && (rc = write_csv(o.csv, r, ls, &cx)) != 0) ||
        (rc = write_paths(o.out, paths, np, &geo, &cx)) != 0)
        goto fail;
    td_cli_progress_done(&pr);
    if (!o.quiet)
        summary(r, td_now() - t0);
fail:
    td_cli_progress_done(&pr);
    td_rv_paths_free(paths, np);
    td_ridges_free(r);
    td_lines_free(ls);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("ridges", o.in, o.out, &cx);
}
