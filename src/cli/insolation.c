/* topodig insolation: DEM -> daily clear-sky irradiation (direct +
 * diffuse), horizon angles per direction and the sky-view factor (paper
 * 000 §3.2; docs/insolation.md). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/sun/sun.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sun_opts {
    const char *in, *out, *horizons, *skyview;
    int quiet;
    td_insol_params p;
} sun_opts;

/* 0: run, 1: error (printed), 2: --help shown. */
static int parse_args(int argc, char **argv, sun_opts *o)
{
    const td_opt opts[] = {
        {"lat", 0, TD_OPT_DOUBLE, &o->p.latitude, -90, 90, .meta = "DEG",
         .help = "latitude, north positive (required)", .no_default = 1},
        {"day", 0, TD_OPT_INT, &o->p.day, 1, 366, .meta = "N",
         .help = "day of the year (required)", .no_default = 1},
        {"method", 0, TD_OPT_CHOICE, &o->p.method, .meta = "M",
         .choices = "horizon|hidden-surface", .help = "horizon: the paper's "
         "fast method, horizon\nangles by profile sweeps, O(k n^2);\n"
         "hidden-surface: the paper's reference, a\nz-buffer pass per sky "
         "viewpoint, O(m n^2)"},
        {"directions", 0, TD_OPT_INT, &o->p.directions, 1, 3600, .meta = "K",
         .help = "horizon method: azimuths"},
        {"viewpoints", 0, TD_OPT_INT, &o->p.viewpoints, 4, 1000000,
         .meta = "M", .help = "hidden-surface: sky viewpoints, as about\n"
         "2 sqrt(M) azimuths x sqrt(M)/2 rings"},
        {"step-minutes", 0, TD_OPT_DOUBLE, &o->p.step_minutes, 0.1, 720,
         .meta = "S", .help = "time step of the day's sum"},
        {"cell-size", 0, TD_OPT_DOUBLE, &o->p.cell_size, 1e-9, 1e12,
         .meta = "C", .help = "ground size of a cell in height units\n"
         "(default: from the DEM's georeferencing, else 1)", .no_default = 1},
        {"transmittance", 0, TD_OPT_DOUBLE, &o->p.transmittance, 1e-6, 1,
         .meta = "T", .help = "clear-sky zenith transmittance"},
        {"earth-curvature", 0, TD_OPT_FLAG, &o->p.curvature, .help =
         "horizon method: distant terrain appears\nd^2 / (2 R) lower, R = "
         "6371000 height units\n(metres); matters for horizons tens of km\n"
         "away (default off)"},
        {"horizons", 0, TD_OPT_OUTPUT, &o->horizons, .meta = "FILE", .help =
         "horizon angles, degrees >= 0, float32 GeoTIFF,\none band per "
         "direction, band i at azimuth\ni * 360 / K"},
        {"skyview", 0, TD_OPT_OUTPUT, &o->skyview, .meta = "FILE", .help =
         "sky-view factor, float32 GeoTIFF: the\nradiative (cosine-weighted) "
         "one of a horizontal\nsurface, 1/K sum cos^2(horizon); 1 on open\n"
         "flat ground"},
        {NULL}};
    const td_cmd c = {
        "insolation", "DEM -o SUN.tif --lat DEG --day N [options]",
        "Daily clear-sky irradiation of every DEM cell, direct + diffuse, in\n"
        "Wh/m^2 (float32 GeoTIFF, nodata where the DEM has none).  Direct: the\n"
        "sun's beam on the cell's slope (Lambert) whenever the sun is above\n"
        "the cell's horizon in its azimuth.  Diffuse: the diffuse horizontal\n"
        "irradiance times the sky-view factor.  Clear sky: solar constant\n"
        "1367 W/m^2, beam = I0 * 0.7^airmass, diffuse = 0.3 (I0 - beam) sin e.\n"
        "Azimuths clockwise from north; north = up = towards row 0\n"
        "(docs/insolation.md).\n",
        "Summary on stderr: method, cells, mean daily total, seconds.\n",
        opts, "one DEM file", 1, 1, &o->in, &o->out, "SUN.tif", &o->quiet};
    int rc = td_opt_parse(&c, argc, argv);
    if (rc == 0 && !isfinite(o->p.latitude))
        rc = td_cli_failf("insolation", "no latitude: give --lat DEG "
                          "(-90..90)");
    if (rc == 0 && o->p.day == 0)
        rc = td_cli_failf("insolation", "no day: give --day N (1..366)");
    return rc;
}

/* Write every requested output, the secondary ones first: when one
 * fails, the main output (new or old) is left as it was. */
static int write_all(const sun_opts *o, const td_insol_result *r,
                     const td_georef *geo, td_ctx *cx)
{
    int rc = 0;
    if (o->horizons)
        rc = td_geotiff_write_bands_f32(o->horizons, r->horizons, r->k, geo,
                                        cx);
    if (rc == 0 && o->skyview)
        rc = td_geotiff_write_f32(o->skyview, r->skyview, geo, cx);
    return rc == 0 ? td_geotiff_write_f32(o->out, r->total, geo, cx) : rc;
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
    o.p.latitude = NAN; /* required */
    o.p.day = 0;
    o.p.cell_size = 0; /* unless given: from the georeferencing, else 1 */
    if ((rc = parse_args(argc, argv, &o)) != 0)
        return rc == 2 ? 0 : 1;
    td_ctx_init(&cx);
    td_georef_init(&geo);
    td_cli_progress_init(&pr, &cx, o.quiet);
    rc = td_cli_read_dem(o.in, &dem, &geo, &o.p.cell_size, &cx);
    if (rc == 0)
        rc = td_insolation_run(dem, &o.p, &r, &cx);
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
