/* topodig flow: DEM -> rain-flow pass counts (paper 000 §3.1) and a
 * ridge / slope / valley class raster. */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/flow/flow.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int td_cmd_flow(int argc, char **argv);

static const char help[] =
    "usage: topodig flow DEM -o PASSES.tif [options]\n"
    "\n"
    "Rain falls evenly on every cell and flows downhill; PASSES.tif (float32\n"
    "GeoTIFF) holds how many cells' rain passes each cell (its own included,\n"
    "so >= 1).  Frequently passed cells are valleys, rarely passed ridges.\n"
    "Nodata cells get no rain and act like the grid edge: water may leave\n"
    "the grid there.  DEM: GeoTIFF/TIFF or ESRI ASCII grid.\n"
    "\n"
    "options (defaults in brackets; see docs/flow.md):\n"
    "  -o, --output FILE     pass counts, float32 GeoTIFF\n"
    "      --method M        sobel: the paper's method, every drop traced\n"
    "                        along the Sobel gradient of the raw DEM (stops\n"
    "                        in pits); d8: depression-filled (priority-flood)\n"
    "                        steepest descent, linear time; dinf: as d8 with\n"
    "                        Tarboton's D-infinity split [sobel]\n"
    "      --log             write log10(count) instead of the count\n"
    "      --classes FILE    uint8 GeoTIFF: 1 ridge, 2 slope, 3 valley,\n"
    "                        0 nodata\n"
    "      --ridge-q Q       ridge: count <= the Q-quantile of counts [0.2]\n"
    "      --valley-q Q      valley: count >= the Q-quantile [0.9]\n"
    "      --max-steps N     sobel: moves per drop, 0 = 4 (w + h) [0]\n"
    "      --threads N       d8, dinf: threads, 0 = all cores; the result\n"
    "                        is the same for any count [0]\n"
    "  -q, --quiet           no progress and no summary\n"
    "  -h, --help            this help\n"
    "\n"
    "Summary on stderr: method, cells, outflow, pits (sobel), seconds.\n";

typedef struct flow_opts {
    const char *in, *out, *classes;
    int quiet, log;
    double ridge_q, valley_q;
    td_flow_params p;
} flow_opts;

enum { O_METHOD = 256, O_LOG, O_CLASSES, O_RQ, O_VQ, O_MAXSTEPS, O_THREADS };

static int parse_opt(int c, const char *arg, flow_opts *o, td_ctx *cx)
{
    long v;
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_LOG: o->log = 1; return 0;
    case O_CLASSES: o->classes = arg; return 0;
    case O_METHOD:
        if (!strcmp(arg, "sobel")) o->p.method = TD_FLOW_SOBEL;
        else if (!strcmp(arg, "d8")) o->p.method = TD_FLOW_D8;
        else if (!strcmp(arg, "dinf")) o->p.method = TD_FLOW_DINF;
        else return td_seterr(cx, TD_EINVAL, "--method: '%s' is not sobel, "
                              "d8 or dinf", arg);
        return 0;
    case O_RQ: case O_VQ:
        if (td_cli_parse_double(arg, 0, 1, c == O_RQ ? &o->ridge_q
                                                     : &o->valley_q) != 0)
            return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a number in "
                             "0..1", c == O_RQ ? "--ridge-q" : "--valley-q",
                             arg);
        return 0;
    case O_MAXSTEPS:
        if (td_cli_parse_int(arg, 0, 2147483647L, &v) != 0)
            return td_seterr(cx, TD_EINVAL, "--max-steps: '%s' is not a "
                             "whole number >= 0", arg);
        o->p.max_steps = v;
        return 0;
    case O_THREADS:
        if (td_cli_parse_int(arg, 0, 1024, &v) != 0)
            return td_seterr(cx, TD_EINVAL, "--threads: '%s' is not a "
                             "whole number in 0..1024", arg);
        o->p.threads = (int)v;
        return 0;
    }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig flow "
                     "--help)");
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, flow_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"method", 1, 0, O_METHOD}, {"log", 0, 0, O_LOG},
        {"classes", 1, 0, O_CLASSES}, {"ridge-q", 1, 0, O_RQ},
        {"valley-q", 1, 0, O_VQ}, {"max-steps", 1, 0, O_MAXSTEPS},
        {"threads", 1, 0, O_THREADS}, {0, 0, 0, 0}};
    td_ctx cx;
    int c;
    td_ctx_init(&cx);
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        }
        if (c == '?' || c == ':')
            return td_cli_failf("flow", "bad or incomplete option '%s' (see "
                                "topodig flow --help)", argv[optind - 1]);
        if (parse_opt(c, optarg, o, &cx) != 0)
            return td_cli_fail("flow", &cx);
    }
    if (optind != argc - 1)
        return td_cli_failf("flow", "expected one DEM file (see topodig "
                            "flow --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("flow", "no output: give -o PASSES.tif");
    if (td_cli_check_output("flow", o->out, o->in) != 0)
        return 1;
    if (!(o->ridge_q < o->valley_q))
        return td_cli_failf("flow", "--ridge-q %g must be below --valley-q "
                            "%g", o->ridge_q, o->valley_q);
    return 0;
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
