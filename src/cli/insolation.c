/* topodig insolation: DEM -> daily clear-sky irradiation (direct +
 * diffuse), horizon angles per direction and the sky-view factor (paper
 * 000 §3.2; docs/insolation.md). */
#define _GNU_SOURCE
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/sun/sun.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int td_cmd_insolation(int argc, char **argv);

static const char help[] =
    "usage: topodig insolation DEM -o SUN.tif --lat DEG --day N [options]\n"
    "\n"
    "Daily clear-sky irradiation of every DEM cell, direct + diffuse, in\n"
    "Wh/m^2 (float32 GeoTIFF, nodata where the DEM has none).  Direct: the\n"
    "sun's beam on the cell's slope (Lambert) whenever the sun is above\n"
    "the cell's horizon in its azimuth.  Diffuse: the diffuse horizontal\n"
    "irradiance times the sky-view factor.  Clear sky: solar constant\n"
    "1367 W/m^2, beam = I0 * 0.7^airmass, diffuse = 0.3 (I0 - beam) sin e.\n"
    "Azimuths clockwise from north; north = up = towards row 0.\n"
    "\n"
    "options (defaults in brackets; see docs/insolation.md):\n"
    "  -o, --output FILE     daily irradiation, Wh/m^2, float32 GeoTIFF\n"
    "      --lat DEG         latitude, -90..90 (north positive; required)\n"
    "      --day N           day of the year, 1..366 (required)\n"
    "      --method M        horizon: the paper's fast method, horizon\n"
    "                        angles by profile sweeps, O(k n^2);\n"
    "                        hidden-surface: the paper's reference, a\n"
    "                        z-buffer pass per sky viewpoint, O(m n^2)\n"
    "                        [horizon]\n"
    "      --directions K    horizon method: azimuths [36]\n"
    "      --viewpoints M    hidden-surface: sky viewpoints, as about\n"
    "                        2 sqrt(M) azimuths x sqrt(M)/2 rings [1024]\n"
    "      --step-minutes S  time step of the day's sum [10]\n"
    "      --cell-size C     ground size of a cell in height units\n"
    "                        [the DEM's pixel width, else 1]\n"
    "      --transmittance T clear-sky zenith transmittance, 0..1 [0.7]\n"
    "      --earth-curvature horizon method: distant terrain appears\n"
    "                        d^2 / (2 R) lower, R = 6371000 height units\n"
    "                        (metres); matters for horizons tens of km\n"
    "                        away [off]\n"
    "      --horizons FILE   horizon angles, degrees >= 0, float32 GeoTIFF,\n"
    "                        one band per direction, band i at azimuth\n"
    "                        i * 360 / K\n"
    "      --skyview FILE    sky-view factor, float32 GeoTIFF: the\n"
    "                        radiative (cosine-weighted) one of a horizontal\n"
    "                        surface, 1/K sum cos^2(horizon); 1 on open\n"
    "                        flat ground\n"
    "  -q, --quiet           no progress and no summary\n"
    "  -h, --help            this help\n"
    "\n"
    "Summary on stderr: method, cells, mean daily total, seconds.\n";

typedef struct sun_opts {
    const char *in, *out, *horizons, *skyview;
    int quiet, have_lat, have_day, have_cs;
    td_insol_params p;
} sun_opts;

enum { O_LAT = 256, O_DAY, O_METHOD, O_DIRS, O_VIEWS, O_STEP, O_CS, O_TAU,
       O_HOR, O_SKY, O_CURV };

static int parse_num(int c, const char *arg, sun_opts *o, td_ctx *cx)
{
    long v;
    switch (c) {
    case O_LAT:
        o->have_lat = 1;
        if (td_cli_parse_double(arg, -90, 90, &o->p.latitude) == 0)
            return 0;
        return td_seterr(cx, TD_EINVAL, "--lat: '%s' is not a latitude in "
                         "-90..90", arg);
    case O_DAY:
        o->have_day = 1;
        if (td_cli_parse_int(arg, 1, 366, &v) == 0 && (o->p.day = (int)v))
            return 0;
        return td_seterr(cx, TD_EINVAL, "--day: '%s' is not a day of the "
                         "year in 1..366", arg);
    case O_DIRS:
        if (td_cli_parse_int(arg, 1, 3600, &v) == 0 && (o->p.directions = (int)v))
            return 0;
        return td_seterr(cx, TD_EINVAL, "--directions: '%s' is not in "
                         "1..3600", arg);
    case O_VIEWS:
        if (td_cli_parse_int(arg, 4, 1000000, &v) == 0 &&
            (o->p.viewpoints = (int)v))
            return 0;
        return td_seterr(cx, TD_EINVAL, "--viewpoints: '%s' is not in "
                         "4..1000000", arg);
    case O_STEP:
        if (td_cli_parse_double(arg, 0.1, 720, &o->p.step_minutes) == 0)
            return 0;
        return td_seterr(cx, TD_EINVAL, "--step-minutes: '%s' is not in "
                         "0.1..720", arg);
    case O_CS:
        o->have_cs = 1;
        if (td_cli_parse_double(arg, 1e-9, 1e12, &o->p.cell_size) == 0)
            return 0;
        return td_seterr(cx, TD_EINVAL, "--cell-size: '%s' is not a number "
                         "> 0", arg);
    case O_TAU:
        if (td_cli_parse_double(arg, 1e-6, 1, &o->p.transmittance) == 0)
            return 0;
        return td_seterr(cx, TD_EINVAL, "--transmittance: '%s' is not in "
                         "(0, 1]", arg);
    }
    return td_seterr(cx, TD_EINVAL, "unknown option (see topodig "
                     "insolation --help)");
}

static int parse_opt(int c, const char *arg, sun_opts *o, td_ctx *cx)
{
    switch (c) {
    case 'o': o->out = arg; return 0;
    case 'q': o->quiet = 1; return 0;
    case O_HOR: o->horizons = arg; return 0;
    case O_SKY: o->skyview = arg; return 0;
    case O_CURV: o->p.curvature = 1; return 0;
    case O_METHOD:
        if (!strcmp(arg, "horizon"))
            o->p.method = TD_INSOL_HORIZON;
        else if (!strcmp(arg, "hidden-surface"))
            o->p.method = TD_INSOL_HIDDEN_SURFACE;
        else
            return td_seterr(cx, TD_EINVAL, "--method: '%s' is not horizon "
                             "or hidden-surface", arg);
        return 0;
    }
    return parse_num(c, arg, o, cx);
}

/* Fail before the (long) computation when an output's folder does not
 * exist or is not writable. */
static int check_folder(const char *path)
{
    char dir[4096];
    const char *slash = strrchr(path, '/');
    struct stat st;
    size_t n = slash ? (size_t)(slash - path) : 0;
    if (!slash)
        return access(".", W_OK) == 0 ? 0 : td_cli_failf("insolation",
                      "%s: cannot create: folder not writable", path);
    if (n == 0)
        n = 1; /* "/file" */
    if (n >= sizeof dir)
        return td_cli_failf("insolation", "%s: file name too long", path);
    memcpy(dir, path, n);
    dir[n] = 0;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return td_cli_failf("insolation", "%s: cannot create: no folder "
                            "'%s'", path, dir);
    if (access(dir, W_OK) != 0)
        return td_cli_failf("insolation", "%s: cannot create: folder not "
                            "writable", path);
    return 0;
}

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, sun_opts *o)
{
    static const struct option lo[] = {
        {"output", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'},
        {"lat", 1, 0, O_LAT}, {"day", 1, 0, O_DAY},
        {"method", 1, 0, O_METHOD}, {"directions", 1, 0, O_DIRS},
        {"viewpoints", 1, 0, O_VIEWS}, {"step-minutes", 1, 0, O_STEP},
        {"cell-size", 1, 0, O_CS}, {"transmittance", 1, 0, O_TAU},
        {"horizons", 1, 0, O_HOR}, {"skyview", 1, 0, O_SKY},
        {"earth-curvature", 0, 0, O_CURV}, {0, 0, 0, 0}};
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
            return td_cli_failf("insolation", "bad or incomplete option '%s' "
                                "(see topodig insolation --help)",
                                argv[optind - 1]);
        if (parse_opt(c, optarg, o, &cx) != 0)
            return td_cli_fail("insolation", &cx);
    }
    if (optind != argc - 1)
        return td_cli_failf("insolation", "expected one DEM file (see "
                            "topodig insolation --help)");
    o->in = argv[optind];
    if (!o->out)
        return td_cli_failf("insolation", "no output: give -o SUN.tif");
    if (td_cli_check_output("insolation", o->out, o->in) != 0)
        return 1;
    if (!o->have_lat)
        return td_cli_failf("insolation", "no latitude: give --lat DEG "
                            "(-90..90)");
    if (!o->have_day)
        return td_cli_failf("insolation", "no day: give --day N (1..366)");
    if (check_folder(o->out) || (o->horizons && check_folder(o->horizons)) ||
        (o->skyview && check_folder(o->skyview)))
        return 1;
    return 0;
}

/* Cell size: --cell-size, else the DEM's pixel width, else 1. */
static void pick_cell_size(sun_opts *o, const td_georef *geo)
{
    if (o->have_cs)
        return;
    o->p.cell_size = 1.0;
    if (geo->valid && !geo->pixel && geo->gt[2] == 0.0 && geo->gt[4] == 0.0 &&
        fabs(geo->gt[1]) > 0.0 && isfinite(geo->gt[1]))
        o->p.cell_size = fabs(geo->gt[1]);
}

/* Write every requested output; on failure remove what was written (all
 * or nothing). */
static int write_all(const sun_opts *o, const td_insol_result *r,
                     const td_georef *geo, td_ctx *cx)
{
    int rc = td_geotiff_write_f32(o->out, r->total, geo, cx);
    if (rc == 0 && o->horizons &&
        (rc = td_geotiff_write_bands_f32(o->horizons, r->horizons, r->k, geo,
                                         cx)) != 0)
        remove(o->out);
    if (rc == 0 && o->skyview &&
        (rc = td_geotiff_write_f32(o->skyview, r->skyview, geo, cx)) != 0) {
        remove(o->out);
        if (o->horizons)
            remove(o->horizons);
    }
    return rc;
}

static void summary(const sun_opts *o, const td_insol_result *r,
                    double secs)
{
    double sum = 0.0, n = 0.0;
    size_t i, cells = (size_t)r->total->w * r->total->h;
    for (i = 0; i < cells; i++)
        if (r->total->data[i] != r->total->nodata) {
            sum += r->total->data[i];
            n += 1.0;
        }
    if (o->p.method == TD_INSOL_HIDDEN_SURFACE)
        fprintf(stderr, "insolation: method hidden-surface, %d viewpoints "
                "(%d azimuths x %d rings), ", r->az_count * r->el_count,
                r->az_count, r->el_count);
    else
        fprintf(stderr, "insolation: method horizon, %d directions, ", r->k);
    fprintf(stderr, "%.0f cells, cell size %g, mean daily total %.1f Wh/m^2, "
            "%.2f s\n", n, o->p.cell_size, n > 0 ? sum / n : 0.0, secs);
}

int td_cmd_insolation(int argc, char **argv)
{
    sun_opts o;
    td_ctx cx;
    td_cli_progress pr;
    td_grid_f32 *dem = NULL;
    td_insol_result *r = NULL;
    td_georef geo;
    double t0 = td_now();
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_insol_defaults();
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_dem_read(o.in, &dem, &geo, &cx);
    if (rc == 0) {
        pick_cell_size(&o, &geo);
        rc = td_insolation_run(dem, &o.p, &r, &cx);
    }
    if (rc == 0)
        rc = write_all(&o, r, &geo, &cx);
    td_cli_progress_done(&pr);
    if (rc == 0 && !o.quiet)
        summary(&o, r, td_now() - t0);
    td_insol_result_free(r);
    td_grid_f32_free(dem);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("insolation", o.in, o.out, &cx);
}
