/* topodig flow: DEM -> rain-flow pass counts (paper 000 §3.1) and a
 * ridge / slope / valley class raster. */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/flow/flow.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct flow_opts {
    const char *in, *out, *classes;
    int quiet, log;
    double ridge_q, valley_q;
    td_flow_params p;
} flow_opts;

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, flow_opts *o)
{
    const td_opt opts[] = {
        {"method", 0, TD_OPT_CHOICE, &o->p.method, .choices = "sobel|d8|dinf",
         .meta = "M", .help = "sobel: the paper's method, every drop traced\n"
         "along the Sobel gradient of the raw DEM (stops\nin pits); d8: "
         "depression-filled (priority-flood)\nsteepest descent, linear time; "
         "dinf: as d8 with\nTarboton's D-infinity split"},
        {"log", 0, TD_OPT_FLAG, &o->log, .help = "write log10(count) instead "
         "of the count"},
        {"classes", 0, TD_OPT_OUTPUT, &o->classes, .meta = "FILE",
         .help = "uint8 GeoTIFF: 1 ridge, 2 slope, 3 valley,\n0 nodata"},
        {"ridge-q", 0, TD_OPT_DOUBLE, &o->ridge_q, 0, 1, .meta = "Q",
         .help = "ridge: count <= the Q-quantile of counts"},
        {"valley-q", 0, TD_OPT_DOUBLE, &o->valley_q, 0, 1, .meta = "Q",
         .help = "valley: count >= the Q-quantile"},
        {"max-steps", 0, TD_OPT_LONG, &o->p.max_steps, 0, 2147483647.0,
         .meta = "N", .help = "sobel: moves per drop, 0 = 4 (w + h)"},
        {"threads", 0, TD_OPT_INT, &o->p.threads, 0, 1024, .meta = "N",
         .help = "d8, dinf: threads, 0 = all cores; the result\nis the same "
         "for any count"},
        {NULL}};
    const td_cmd c = {
        "flow", "DEM -o PASSES.tif [options]",
        "Rain falls evenly on every cell and flows downhill; PASSES.tif "
        "(float32\nGeoTIFF) holds how many cells' rain passes each cell (its "
        "own included,\nso >= 1).  Frequently passed cells are valleys, rarely "
        "passed ridges.\nNodata cells get no rain and act like the grid edge: "
        "water may leave\nthe grid there.  DEM: GeoTIFF/TIFF or ESRI ASCII "
        "grid (docs/flow.md).\n",
        "Summary on stderr: method, cells, outflow, pits (sobel), seconds.\n",
        opts, "one DEM file", 1, 1, &o->in, &o->out, "PASSES.tif", &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc == 0 && !(o->ridge_q < o->valley_q))
        rc = td_cli_failf("flow", "--ridge-q %g must be below --valley-q %g",
                          o->ridge_q, o->valley_q);
    return rc;
}

static void to_log10(td_grid_f32 *g)
{
    size_t i, n = (size_t)g->w * (size_t)g->h;
    for (i = 0; i < n; i++)
        if (!(g->has_nodata && g->data[i] == g->nodata) && g->data[i] > 0)
            g->data[i] = (float)log10(g->data[i]);
}

static const char *method_name(td_flow_method m)
{
    return m == TD_FLOW_SOBEL ? "sobel" : m == TD_FLOW_D8 ? "d8" : "dinf";
}

static void summary(const flow_opts *o, const td_flow_stats *s, double secs)
{
    fprintf(stderr, "flow: method %s, %.0f cells, outflow %.6g (%.3f%%), ",
            method_name(o->p.method), s->cells, s->outflow,
            s->cells > 0 ? 100.0 * s->outflow / s->cells : 0.0);
    if (o->p.method == TD_FLOW_SOBEL)
        fprintf(stderr, "%.0f drops stopped in pits, %.0f capped, ",
                s->pit_stops, s->capped);
    else
        fprintf(stderr, "%.0f cells raised by filling, ", s->raised);
    fprintf(stderr, "max count %.0f, %.2f s\n", s->max_pass, secs);
}

/* Run the stage and the classes; nothing is written here. */
static int compute(const flow_opts *o, const td_grid_f32 *dem,
                   td_grid_f32 **passes, td_grid_u8 **cls,
                   td_flow_stats *st, td_ctx *cx)
{
    int rc;
    if (!(*passes = td_grid_f32_new(dem->w, dem->h, cx)))
        return TD_ENOMEM;
    if ((rc = td_flow_run(dem, &o->p, *passes, st, cx)) != 0)
        return rc;
    if (st->cells == 0)
        return td_seterr(cx, TD_EINVAL, "DEM '%s' has no valid cells",
                         o->in);
    if (o->classes) {
        if (!(*cls = td_grid_u8_new(dem->w, dem->h, cx)))
            return TD_ENOMEM;
        rc = td_flow_classify(*passes, o->ridge_q, o->valley_q, *cls, cx);
    }
    if (rc == 0 && o->log)
        to_log10(*passes);
    return rc;
}

int td_cmd_flow(int argc, char **argv)
{
    flow_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_grid_f32 *dem = NULL, *passes = NULL;
    td_grid_u8 *cls = NULL;
    td_flow_stats st;
    td_georef geo;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    memset(&st, 0, sizeof st);
    o.p = td_flow_defaults();
    o.ridge_q = 0.2;
    o.valley_q = 0.9;
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_dem_read(o.in, &dem, &geo, &cx);
    if (rc == 0)
        rc = compute(&o, dem, &passes, &cls, &st, &cx);
    /* the secondary output first: when it fails, the main output (new or
       old) is left as it was */
    if (rc == 0 && cls)
        rc = td_geotiff_write_u8(o.classes, cls, &geo, &cx);
    if (rc == 0)
        rc = td_geotiff_write_f32(o.out, passes, &geo, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet)
        summary(&o, &st, td_now() - t0);
    td_grid_f32_free(dem);
    td_grid_f32_free(passes);
    td_grid_u8_free(cls);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("flow", o.in, o.out, &cx);
}
