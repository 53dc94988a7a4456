/* topodig skeleton: a key outline -> DEM and contours by the straight
 * skeleton (paper 004; src/model/skeleton.c). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/model/model.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sk_opts {
    const char *in, *out, *like, *contours, *strata_out;
    int wh[2], quiet, surface, strata, construction;
    double height, slope, interval, base, cell;
} sk_opts;

static int parse_args(int argc, char **argv, sk_opts *o)
{
    const td_opt opts[] = {
        TD_CLI_GRID_OPTS(&o->like, o->wh),
        {"height", 0, TD_OPT_DOUBLE, &o->height, 1e-9, 1e7, .meta = "H",
         .help = "the summit's height above --base (the last\npoint to "
         "shrink away)", .no_default = 1},
        {"slope", 0, TD_OPT_DOUBLE, &o->slope, 0.01, 89.99, .meta = "DEG",
         .help = "or: every side rises at this slope", .no_default = 1},
        {"interval", 0, TD_OPT_DOUBLE, &o->interval, 1e-9, 1e7, .meta = "I",
         .help = "contour interval (heights)", .no_default = 1},
        {"base", 0, TD_OPT_DOUBLE, &o->base, -1e6, 1e6, .meta = "B",
         .help = "the outline's height"},
        {"cell", 0, TD_OPT_DOUBLE, &o->cell, 1e-9, 1e9, .meta = "M",
         .help = "horizontal size of a cell in the heights'\nunits, for "
         "--slope (default: from --like's\ngeoreferencing, else 1)",
         .no_default = 1},
        {"surface", 0, TD_OPT_CHOICE, &o->surface, .choices = "tin|roof",
         .meta = "S", .help = "tin (the paper's): the contours as closed\n"
         "B-splines, Delaunay-triangulated with the\noutline and the "
         "summits | roof (ours): the\nexact straight-skeleton roof"},
        {"construction", 0, TD_OPT_CHOICE, &o->construction,
         .choices = "queue|paper", .meta = "C",
         .help = "queue (ours): the same events taken from a\nqueue, "
         "10,000 corners in well under a\nsecond | paper: the paper's "
         "search of\nevery edge and reflex corner each step,\nO(n^3)"},
        {"strata", 0, TD_OPT_INT, &o->strata, 1, 100000, .meta = "N",
         .help = "N layers for a model with inner structure:\nthe outline "
         "shrunk at N equal steps from\nthe base to the summit, to "
         "--strata-out", .no_default = 1},
        {"strata-out", 0, TD_OPT_OUTPUT, &o->strata_out, .meta = "S.geojson",
         .help = "the strata's rings (closed lines, height =\nthe layer's "
         "top)"},
        {"contours-out", 0, TD_OPT_OUTPUT, &o->contours, .meta = "C.geojson",
         .help = "the shrunk outlines every --interval, with\ntheir heights "
         "(.geojson, .gpkg, .shp, .dxf)"},
        {NULL}};
    const td_cmd c = {
        "skeleton", "OUTLINE.geojson -o DEM.tif (--like SHEET | --size WxH)\n"
        "                      (--height H | --slope DEG) --interval I\n"
        "                      [--contours-out C.geojson]\n"
        "                      [--strata N --strata-out S.geojson]",
        "A terrain from one key outline by the straight skeleton (Murase &\n"
        "Sugihara): every side of the outline moves inward at one speed,\n"
        "edges vanish (edge events) and reflex corners split the polygon\n"
        "(split events) until it has shrunk away; the height of a point is\n"
        "how far the front had moved when it passed (the outline's roof),\n"
        "scaled by --slope or to --height.  The shrunk outlines every\n"
        "--interval are the contours; the DEM is their B-splines and the\n"
        "summits triangulated (the paper's; --surface roof: the roof).  OUTLINE: the first Polygon (its\n"
        "outer ring) or closed LineString, any vector format GDAL reads.\n"
        "Cells outside the outline are nodata.\n",
        "Summary on stderr: corners, events (splits), summit height,\n"
        "contours, cells, seconds.\n",
        opts, "one OUTLINE file", 1, 1, &o->in, &o->out, "DEM.tif",
        &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc)
        return rc;
    if (!o->like == !o->wh[0])
        return td_cli_failf("skeleton", "give the grid: --like SHEET or "
                            "--size WxH (one of them)");
    if (!(o->height > 0) == !(o->slope > 0))
        return td_cli_failf("skeleton", "give --height H or --slope DEG (one "
                            "of them)");
    if (!(o->interval > 0))
        return td_cli_failf("skeleton", "give --interval I (the contour "
                            "interval)");
    if (!o->strata != !o->strata_out)
        return td_cli_failf("skeleton", "--strata N and --strata-out FILE go "
                            "together");
    return 0;
}

int td_cmd_skeleton(int argc, char **argv)
{
    sk_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_georef geo;
    td_lines *ls = NULL, *con = NULL, *peaks = NULL, *strata = NULL;
    double *z = NULL, *xy = NULL, k, t0 = td_now();
    td_grid_f32 *dem = NULL;
    td_skeleton_params p = td_skeleton_defaults();
    td_skeleton_stats st;
    const td_line *ol = NULL;
    size_t i, cells = 0;
    int rc, w, h;
    memset(&o, 0, sizeof o);
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    p.construction = o.construction == 1 ? TD_SKEL_PAPER : TD_SKEL_QUEUE;
    if ((rc = td_cli_grid(o.like, o.wh, &w, &h, &geo, &o.cell, &cx)) != 0)
        goto fail;
    if ((rc = td_vector_read_lines_z(o.in, &geo, NULL, &ls, &z, NULL, NULL,
                                     &cx)) != 0)
        goto fail;
    for (i = 0; i < ls->n && !ol; i++)
        if (ls->v[i].closed || (ls->v[i].n >= 4 &&
                                ls->v[i].xy[0] == ls->v[i].xy[2 * ls->v[i].n - 2] &&
                                ls->v[i].xy[1] == ls->v[i].xy[2 * ls->v[i].n - 1]))
            ol = &ls->v[i];
    if (!ol) {
        rc = td_seterr(&cx, TD_EINVAL, "%s: no Polygon or closed LineString",
                       o.in);
        goto fail;
    }
    if (!(xy = malloc(2 * ol->n * sizeof *xy))) {
        rc = td_seterr(&cx, TD_ENOMEM, "out of memory");
        goto fail;
    }
    memcpy(xy, ol->xy, 2 * ol->n * sizeof *xy);
    i = ol->n;
    if (!ol->closed) /* the repeated first point */
        i--;
    /* first the summit's time (for --height), then the DEM and contours */
    if ((rc = td_skeleton(xy, i, &p, NULL, NULL, NULL, &st, &cx)) != 0)
        goto fail;
    k = o.slope > 0 ? tan(o.slope * M_PI / 180.0) * o.cell
                    : o.height / (st.max_time > 0 ? st.max_time : 1);
    p.contour_step = o.interval / k;
    if (!(dem = td_grid_f32_new(w, h, &cx)) || !(con = td_lines_new(&cx)) ||
        !(peaks = td_lines_new(&cx))) {
        rc = TD_ENOMEM;
        goto fail;
    }
    dem->has_nodata = 1, dem->nodata = -9999.0f;
    for (i = 0; i < (size_t)w * h; i++)
        dem->data[i] = dem->nodata;
    if ((rc = td_skeleton(xy, ol->closed ? ol->n : ol->n - 1, &p, dem, con,
                          peaks, &st, &cx)) != 0)
        goto fail;
    for (i = 0; i < (size_t)w * h; i++)
        if (dem->data[i] != dem->nodata) {
            dem->data[i] = (float)(o.base + k * dem->data[i]);
            cells++;
        }
    for (i = 0; con && i < con->n; i++) {
        con->v[i].height = o.base + k * con->v[i].height;
        con->v[i].id = (long)i;
    }
    for (i = 0; i < peaks->n; i++)
        peaks->v[i].height = o.base + k * peaks->v[i].height;
    if (o.surface == 0 && /* the paper's: B-splines, Delaunay, the TIN */
        (rc = td_skeleton_tin(xy, ol->closed ? ol->n : ol->n - 1, o.base,
                              con, peaks, 2.0, dem, &cx)) != 0)
        goto fail;
    if (o.strata > 0) { /* N layers: rings at N equal steps of the time */
        td_skeleton_params q = p;
        q.contour_step = st.max_time / (o.strata + 1);
        if (!(strata = td_lines_new(&cx)) ||
            (rc = td_skeleton(xy, ol->closed ? ol->n : ol->n - 1, &q, NULL,
                              strata, NULL, NULL, &cx)) != 0)
            goto fail;
        for (i = 0; i < strata->n; i++) {
            strata->v[i].height = o.base + k * strata->v[i].height;
            strata->v[i].id = (long)i;
        }
        if ((rc = td_vector_write_lines(o.strata_out, strata, &geo, &cx)) != 0)
            goto fail;
    }
    if ((rc = td_dem_write(o.out, dem, &geo, &cx)) != 0 ||
        (o.contours &&
         (rc = td_vector_write_lines(o.contours, con, &geo, &cx)) != 0))
        goto fail;
    td_cli_progress_done(&pr);
    if (!o.quiet)
        fprintf(stderr, "skeleton: %zu corners, %zu events (%zu splits), "
                "summit %.6g, %zu contours, %zu strata rings, %zu cells, "
                "%.2f s\n",
                ol->closed ? ol->n : ol->n - 1, st.events, st.splits,
                o.base + k * st.max_time, o.contours ? con->n : 0,
                strata ? strata->n : 0, cells, td_now() - t0);
fail:
    td_cli_progress_done(&pr);
    td_grid_f32_free(dem);
    td_lines_free(ls);
    td_lines_free(con);
    td_lines_free(peaks);
    td_lines_free(strata);
    free(z);
    free(xy);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("skeleton", o.in, o.out, &cx);
}
