/* topodig render: DEM -> shaded-relief picture (PNG). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/render/render.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct rd_opts {
    const char *in, *out;
    int quiet;
    td_render_params p;
} rd_opts;

static int parse_zfactor(const char *arg, void *t, td_ctx *cx)
{
    if (!strcmp(arg, "auto")) {
        *(double *)t = 0;
        return 0;
    }
    if (td_cli_parse_double(arg, 1e-9, 1e6, t) == 0)
        return 0;
    return td_seterr(cx, TD_EINVAL, "--zfactor: '%s' is neither auto nor a "
                     "number 1e-09..1e+06", arg);
}

static int parse_args(int argc, char **argv, rd_opts *o)
{
    const td_opt opts[] = {
        {"style", 0, TD_OPT_CHOICE, &o->p.style, .choices = "hillshade|tint",
         .help = "grey shaded relief, or coloured by height"},
        {"contours", 0, TD_OPT_DOUBLE, &o->p.interval, 0, 1e9, .meta = "I",
         .help = "draw contour lines every I height units\n(0: none)"},
        {"base", 0, TD_OPT_DOUBLE, &o->p.base, -1e9, 1e9, .meta = "B",
         .help = "contours at B + k*I"},
        {"azimuth", 0, TD_OPT_DOUBLE, &o->p.azimuth, 0, 360, .meta = "DEG",
         .help = "light from"},
        {"altitude", 0, TD_OPT_DOUBLE, &o->p.altitude, 0, 90, .meta = "DEG",
         .help = "light height"},
        {"zfactor", 0, TD_OPT_FUNC, &o->p.zfactor, .meta = "Z|auto", .help =
         "vertical exaggeration (default auto: the\nsteepest tenth of the "
         "slopes drawn at 45\ndegrees or more; 1 = gdaldem's look)",
         .fn = parse_zfactor},
        {"cellsize", 0, TD_OPT_DOUBLE, &o->p.cellsize, 1e-12, 1e12, .meta = "C",
         .help = "cell size in height units (default: from the\nDEM's "
         "georeferencing, else 1)", .no_default = 1},
        {NULL}};
    const td_cmd c = {
        "render", "DEM.tif -o PICTURE.png [--style hillshade|tint]\n"
        "                      [--contours INTERVAL]",
        "Draw a DEM (GeoTIFF/TIFF or ESRI ASCII grid) as shaded relief: light\n"
        "from the north-west, Horn's gradient (as gdaldem hillshade).  Cells\n"
        "without data are pale blue-grey.\n",
        NULL, opts, "one DEM file", 1, 1, &o->in, &o->out, "PICTURE.png",
        &o->quiet};
    return td_opt_parse(&c, argc, argv);
}

int td_cmd_render(int argc, char **argv)
{
    rd_opts o;
    td_ctx cx;
    td_grid_f32 *dem = NULL;
    td_image *im = NULL;
    td_georef geo;
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_render_defaults();
    o.p.cellsize = 0; /* unless given: from the georeferencing, else 1 */
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if ((rc = td_cli_read_dem(o.in, &dem, &geo, &o.p.cellsize, &cx)) != 0)
        goto fail;
    if ((rc = td_render_hillshade(dem, &o.p, &im, &cx)) != 0 ||
        (rc = td_png_write(o.out, im, &cx)) != 0)
        goto fail;
fail:
    td_image_free(im);
    td_grid_f32_free(dem);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("render", o.in, o.out, &cx);
}
