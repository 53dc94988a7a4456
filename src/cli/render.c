/* topodig render: DEM -> shaded-relief picture (PNG). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/render/render.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static const char help[] =
    "usage: topodig render DEM.tif -o PICTURE.png [--style hillshade|tint]\n"
    "                      [--contours INTERVAL]\n"
    "\n"
    "Draw a DEM (GeoTIFF/TIFF or ESRI ASCII grid) as shaded relief: light\n"
    "from the north-west, Horn's gradient (as gdaldem hillshade).  Cells\n"
    "without data are pale blue-grey.\n"
    "\n"
    "options:\n"
    "  -o, --output FILE    PNG output (required)\n"
    "      --style S        hillshade (grey, default) | tint (coloured by\n"
    "                       height)\n"
    "      --contours I     draw contour lines every I height units\n"
    "      --base B         contours at B + k*I (default 0)\n"
    "      --azimuth DEG    light from (default 315)\n"
    "      --altitude DEG   light height (default 45)\n"
    "      --zfactor Z|auto vertical exaggeration (default auto: the\n"
    "                       steepest tenth of the slopes drawn at 45\n"
    "                       degrees or more; 1 = gdaldem's look)\n"
    "      --cellsize C     cell size in height units (default: from the\n"
    "                       DEM's georeferencing, else 1)\n"
    "  -q, --quiet          no progress\n"
    "  -h, --help           this help\n";

typedef struct rd_opts {
    const char *in, *out;
    int quiet, have_cell;
    td_render_params p;
} rd_opts;

enum { O_STYLE = 256, O_CONT, O_BASE, O_AZ, O_ALT, O_ZF, O_CELL };

static int parse_num(int c, const char *arg, rd_opts *o, td_ctx *cx)
{
    static const char *names[] = {"--contours", "--base", "--azimuth",
                                  "--altitude", "--zfactor", "--cellsize"};
    static const double lo[] = {0, -1e9, 0, 0, 1e-9, 1e-12};
    static const double hi[] = {1e9, 1e9, 360, 90, 1e6, 1e12};
    double *dst[] = {&o->p.interval, &o->p.base, &o->p.azimuth,
                     &o->p.altitude, &o->p.zfactor, &o->p.cellsize};
    int i = c - O_CONT;
    if (c == O_ZF && !strcmp(arg, "auto")) {
        o->p.zfactor = 0;
        return 0;
    }
    if (td_cli_parse_double(arg, lo[i], hi[i], dst[i]) != 0)
        return td_seterr(cx, TD_EINVAL, "%s: '%s' is not a number %g..%g",
                         names[i], arg, lo[i], hi[i]);
    o->have_cell |= c == O_CELL;
    return 0;
}

static int parse_args(int argc, char **argv, rd_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"style", 1, 0, O_STYLE},
        {"contours", 1, 0, O_CONT}, {"base", 1, 0, O_BASE},
        {"azimuth", 1, 0, O_AZ}, {"altitude", 1, 0, O_ALT},
        {"zfactor", 1, 0, O_ZF}, {"cellsize", 1, 0, O_CELL},
        {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    td_ctx cx;
    int c;
    td_ctx_init(&cx);
    opterr = 0;
    while ((c = getopt_long(argc, argv, "o:qh", lo, NULL)) != -1) {
        if (c == 'h') {
            fputs(help, stdout);
            return 2;
        }
        if (c == 'o')
            o->out = optarg;
        else if (c == 'q')
            o->quiet = 1;
        else if (c == O_STYLE) {
            if (td_render_parse_style(optarg, &o->p.style, &cx) != 0)
                return td_cli_fail("render", &cx);
        } else if (c >= O_CONT && c <= O_CELL) {
            if (parse_num(c, optarg, o, &cx) != 0)
                return td_cli_fail("render", &cx);
        } else
            return td_cli_failf("render", "bad or incomplete option '%s' "
                                "(see topodig render --help)",
                                argv[optind - 1]);
    }
    if (optind != argc - 1)
        return td_cli_failf("render", "expected one DEM file (see topodig "
                            "render --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("render", "no output: give -o PICTURE.png");
    if (td_cli_check_output("render", o->out, o->in) != 0)
        return 1;
    return 0;
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
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if ((rc = td_dem_read(o.in, &dem, &geo, &cx)) != 0)
        goto fail;
    if (!o.have_cell && geo.valid && !geo.pixel && fabs(geo.gt[1]) > 0)
        o.p.cellsize = fabs(geo.gt[1]);
    if ((rc = td_render_hillshade(dem, &o.p, &im, &cx)) != 0 ||
        (rc = td_png_write(o.out, im, &cx)) != 0)
        goto fail;
fail:
    td_image_free(im);
    td_grid_f32_free(dem);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("render", o.in, o.out, &cx);
}
