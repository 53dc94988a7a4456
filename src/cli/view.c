/* topodig view: DEM -> a perspective 3-D view (PNG), the paper's quad
 * patches (001 §2.6; src/render/view.c). */
#include "src/cli/cli.h"

#include "src/io/io.h"
#include "src/render/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct vw_opts {
    const char *in, *out, *drape;
    int quiet, wh[2], turntable;
    td_opt_points lights;
    td_view_params p;
} vw_opts;

/* "auto" -> 0, else a number in range. */
static int parse_auto(const char *arg, void *t, td_ctx *cx)
{
    if (!strcmp(arg, "auto")) {
        *(double *)t = 0;
        return 0;
    }
    if (td_cli_parse_double(arg, 1e-9, 1e9, t) == 0)
        return 0;
    return td_seterr(cx, TD_EINVAL, "'%s' is neither auto nor a number "
                     "1e-09..1e+09", arg);
}

static int parse_args(int argc, char **argv, vw_opts *o)
{
    const td_opt opts[] = {
        {"style", 0, TD_OPT_CHOICE, &o->p.style, .choices = "shaded|wire|both",
         .help = "flat-shaded patches, their edges (hidden\nlines removed), "
         "or both"},
        {"drape", 0, TD_OPT_STRING, &o->drape, .meta = "D",
         .help = "hillshade (grey), tint (coloured by height)\nor an IMAGE "
         "over the DEM (the scanned sheet)\n(default hillshade)"},
        {"azimuth", 0, TD_OPT_DOUBLE, &o->p.azimuth, 0, 360, .meta = "DEG",
         .help = "where the camera stands, seen from the\nDEM's centre "
         "(clockwise from north)"},
        {"elevation", 0, TD_OPT_DOUBLE, &o->p.elevation, 1, 89.9,
         .meta = "DEG", .help = "camera above the horizon"},
        {"fov", 0, TD_OPT_DOUBLE, &o->p.fov, 1, 150, .meta = "DEG",
         .help = "horizontal field of view"},
        {"distance", 0, TD_OPT_FUNC, &o->p.distance, .fn = parse_auto,
         .meta = "D|auto", .help = "camera to the DEM's centre in cells "
         "(auto:\nthe whole DEM in the picture)", .no_default = 1},
        {"exaggeration", 0, TD_OPT_FUNC, &o->p.exaggeration, .fn = parse_auto,
         .meta = "Z|auto", .help = "vertical exaggeration (auto: the true "
         "relief\nkept within 15-50 % of the longest side)", .no_default = 1},
        {"cellsize", 0, TD_OPT_DOUBLE, &o->p.cellsize, 1e-12, 1e12,
         .meta = "C", .help = "cell size in height units (default: from the\n"
         "DEM's georeferencing, else 1)", .no_default = 1},
        {"patch", 0, TD_OPT_INT, &o->p.patch, 1, 1000, .meta = "N",
         .help = "cells per quad patch side (the paper's 3)"},
        {"light", 0, TD_OPT_POINTS, &o->lights, .n = 2, .meta = "AZ,ALT",
         .help = "a light from azimuth AZ, ALT degrees up;\nrepeat for up "
         "to 4 (default 315,45)"},
        {"hidden", 0, TD_OPT_CHOICE, &o->p.zbuffer, .choices = "painter|zbuffer",
         .meta = "H", .help = "hidden surfaces: painter (the paper's: the\n"
         "farthest patch first) | zbuffer (ours: the\nnearest per pixel)"},
        {"turntable", 0, TD_OPT_INT, &o->turntable, 2, 720, .meta = "N",
         .help = "N views around the DEM from --azimuth on,\nas an "
         "animated GIF (-o NAME.gif)", .no_default = 1},
        {"size", 0, TD_OPT_FUNC, o->wh, .fn = td_cli_parse_size, .meta = "WxH",
         .help = "the picture (default 1200x900)", .no_default = 1},
        {NULL}};
    const td_cmd c = {
        "view", "DEM.tif -o VIEW.png [--style shaded|wire|both]\n"
        "                      [--azimuth DEG] [--elevation DEG] [--drape D]\n"
        "                      [--turntable N -o SPIN.gif]",
        "A perspective view of a DEM for teaching material, drawn as the\n"
        "reconstruction paper draws its surfaces: quad patches of N x N cells,\n"
        "painted from the farthest to the nearest, each flat-shaded by the\n"
        "lights (Lambert).  Cells without data are left out.\n",
        NULL, opts, "one DEM file", 1, 1, &o->in, &o->out, "VIEW.png",
        &o->quiet};
    size_t i;
    int rc = td_opt_parse(&c, argc, argv);
    if (rc)
        return rc;
    if (o->lights.n > TD_VIEW_MAX_LIGHTS)
        return td_cli_failf("view", "--light: at most %d lights",
                            TD_VIEW_MAX_LIGHTS);
    for (i = 0; i < o->lights.n; i++)
        if (o->lights.v[2 * i + 1] < 0 || o->lights.v[2 * i + 1] > 90)
            return td_cli_failf("view", "--light: the altitude %g is not "
                                "0..90", o->lights.v[2 * i + 1]);
    {
        size_t l = strlen(o->out);
        int gif = l >= 4 && !strcasecmp(o->out + l - 4, ".gif");
        if (o->turntable && !gif)
            return td_cli_failf("view", "--turntable writes an animated GIF: "
                                "give -o NAME.gif");
        if (!o->turntable && gif)
            return td_cli_failf("view", "a GIF is for --turntable N; give -o "
                                "NAME.png");
    }
    return 0;
}

/* n views at azimuths azimuth + k 360 / n, all from the distance that
 * fits the widest of them, as a looping GIF (10 frames a second). */
static int turntable(const td_grid_f32 *dem, const td_image *drape,
                     const td_view_params *p0, int w, int h, int n,
                     const char *out, td_ctx *cx)
{
    td_image **fr = calloc((size_t)n, sizeof *fr);
    td_view_params p = *p0;
    double far = p0->distance;
    int k, rc = 0;
    if (!fr)
        return td_seterr(cx, TD_ENOMEM, "out of memory");
    for (k = 0; k < n && !(p0->distance > 0); k++) { /* one distance */
        td_view_camera cam;
        double t[3] = {dem->w / 2.0, -dem->h / 2.0, 0}, d;
        p.azimuth = fmod(p0->azimuth + 360.0 * k / n, 360);
        if ((rc = td_view_camera_of(dem, &p, w, h, &cam, cx)) != 0)
            goto done;
        t[2] = cam.ztop / 2;
        d = sqrt((cam.c[0] - t[0]) * (cam.c[0] - t[0]) +
                 (cam.c[1] - t[1]) * (cam.c[1] - t[1]) +
                 (cam.c[2] - t[2]) * (cam.c[2] - t[2]));
        far = d > far ? d : far;
    }
    p.distance = far;
    for (k = 0; k < n && rc == 0; k++) {
        p.azimuth = fmod(p0->azimuth + 360.0 * k / n, 360);
        if (!(fr[k] = td_image_new(w, h, 3, cx)))
            rc = cx->code ? cx->code : TD_ENOMEM;
        else
            rc = td_view_render(dem, drape, &p, fr[k], cx);
    }
    if (rc == 0)
        rc = td_gif_write(out, fr, (size_t)n, 10, cx);
done:
    for (k = 0; k < n; k++)
        td_image_free(fr[k]);
    free(fr);
    return rc;
}

int td_cmd_view(int argc, char **argv)
{
    vw_opts o;
    td_ctx cx;
    td_grid_f32 *dem = NULL;
    td_image *im = NULL, *drape = NULL;
    td_georef geo;
    double t0 = td_now();
    size_t i;
    int rc;
    memset(&o, 0, sizeof o);
    o.p = td_view_defaults();
    o.p.cellsize = 0; /* unless given: from the georeferencing, else 1 */
    if ((rc = parse_args(argc, argv, &o)) != 0) {
        free(o.lights.v);
        return rc == 2 ? 0 : 1;
    }
    td_ctx_init(&cx);
    td_georef_init(&geo);
    if (o.lights.n > 0) {
        o.p.nlights = (int)o.lights.n;
        for (i = 0; i < o.lights.n; i++)
            o.p.light[i][0] = o.lights.v[2 * i],
            o.p.light[i][1] = o.lights.v[2 * i + 1];
    }
    if ((rc = td_cli_read_dem(o.in, &dem, &geo, &o.p.cellsize, &cx)) != 0)
        goto fail;
    if (!o.drape || !strcmp(o.drape, "hillshade")) {
        o.p.drape = TD_DRAPE_HILLSHADE;
    } else if (!strcmp(o.drape, "tint")) {
        o.p.drape = TD_DRAPE_TINT;
    } else {
        td_georef dg;
        td_georef_init(&dg);
        o.p.drape = TD_DRAPE_IMAGE;
        rc = td_image_read(o.drape, &drape, &dg, &cx);
        td_georef_clear(&dg);
        if (rc != 0)
            goto fail;
    }
    if (!(im = td_image_new(o.wh[0] ? o.wh[0] : 1200, o.wh[0] ? o.wh[1] : 900,
                            3, &cx))) {
        rc = cx.code ? cx.code : TD_ENOMEM;
        goto fail;
    }
    if (o.turntable) {
        if ((rc = turntable(dem, drape, &o.p, im->w, im->h, o.turntable,
                            o.out, &cx)) != 0)
            goto fail;
    } else if ((rc = td_view_render(dem, drape, &o.p, im, &cx)) != 0 ||
               (rc = td_png_write(o.out, im, &cx)) != 0) {
        goto fail;
    }
    if (!o.quiet) {
        fprintf(stderr, "view: %d x %d cells in %d x %d-cell patches, %d x %d "
                "picture", dem->w, dem->h, o.p.patch, o.p.patch, im->w, im->h);
        if (o.turntable)
            fprintf(stderr, ", %d views", o.turntable);
        fprintf(stderr, ", %.2f s\n", td_now() - t0);
    }
fail:
    free(o.lights.v);
    td_image_free(im);
    td_image_free(drape);
    td_grid_f32_free(dem);
    td_georef_clear(&geo);
    return rc == 0 ? 0 : td_cli_fail_on("view", o.in, o.out, &cx);
}
