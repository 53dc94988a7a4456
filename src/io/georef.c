/* georef.c: the td_georef value type (geotransform, EPSG code and the
 * verbatim GeoTIFF key directory). */
#include "src/io/io_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <xtiffio.h>

enum { KEY_MODELTYPE = 1024, KEY_RASTERTYPE = 1025, KEY_CITATION = 1026,
       KEY_GEOGRAPHIC = 2048,
       KEY_PROJECTED = 3072, RASTER_PIXELISPOINT = 2 };

/* An invalid georef with no keys. */
void td_georef_init(td_georef *g)
{
    memset(g, 0, sizeof *g);
    g->gt[1] = 1.0;
    g->gt[5] = 1.0;
}

/* Free the verbatim keys and re-initialise; NULL is a no-op. */
void td_georef_clear(td_georef *g)
{
    if (!g)
        return;
    free(g->geokeys);
    free(g->geodoubles);
    free(g->geoascii);
    td_georef_init(g);
}

/* Deep copy src into dst (dst is cleared first; src == dst is a no-op).
 * Returns 0 or TD_ENOMEM, leaving dst initialised either way. */
int td_georef_copy(td_georef *dst, const td_georef *src, td_ctx *cx)
{
    td_georef t;
    if (dst == src)
        return 0;
    td_georef_init(&t);
    t.valid = src->valid;
    t.pixel = src->pixel;
    t.epsg = src->epsg;
    memcpy(t.gt, src->gt, sizeof t.gt);
    if (src->geokeys && src->n_geokeys) {
        t.geokeys = td_malloc(src->n_geokeys * sizeof *t.geokeys, cx);
        if (!t.geokeys)
            goto fail;
        memcpy(t.geokeys, src->geokeys, src->n_geokeys * sizeof *t.geokeys);
        t.n_geokeys = src->n_geokeys;
    }
    if (src->geodoubles && src->n_geodoubles) {
        t.geodoubles = td_malloc(src->n_geodoubles * sizeof *t.geodoubles, cx);
        if (!t.geodoubles)
            goto fail;
        memcpy(t.geodoubles, src->geodoubles,
               src->n_geodoubles * sizeof *t.geodoubles);
        t.n_geodoubles = src->n_geodoubles;
    }
    if (src->geoascii) {
        size_t n = strlen(src->geoascii) + 1;
        t.geoascii = td_malloc(n, cx);
        if (!t.geoascii)
            goto fail;
        memcpy(t.geoascii, src->geoascii, n);
    }
    td_georef_clear(dst);
    *dst = t;
    return 0;
fail:
    td_georef_clear(&t);
    td_georef_clear(dst);
    return TD_ENOMEM;
}

/* See io.h. */
void td_georef_pixel_frame(td_georef *g)
{
    td_georef_clear(g);
    g->valid = 1;
    g->pixel = 1;
    g->gt[1] = 1.0;
    g->gt[5] = -1.0;
}

/* Pixel corner coordinates to map coordinates (the pixel frame when
 * invalid). */
void td_georef_apply(const td_georef *g, double col, double row, double *X,
                     double *Y)
{
    if (!g || !g->valid) {
        *X = col;
        *Y = -row;
        return;
    }
    *X = g->gt[0] + col * g->gt[1] + row * g->gt[2];
    *Y = g->gt[3] + col * g->gt[4] + row * g->gt[5];
}

/* See io.h. */
int td_georef_to_cells(const td_georef *g, double X, double Y, double *col,
                       double *row)
{
    double a, b, c, d, det;
    if (!g || !g->valid) {
        *col = X;
        *row = -Y;
        return 0;
    }
    a = g->gt[1], b = g->gt[2], c = g->gt[4], d = g->gt[5];
    det = a * d - b * c;
    if (det == 0 || !isfinite(det))
        return -1;
    X -= g->gt[0], Y -= g->gt[3];
    *col = (d * X - b * Y) / det;
    *row = (-c * X + a * Y) / det;
    return 0;
}

/* Look a SHORT-valued key up in the verbatim key directory (header of 4
 * shorts, then entries {id, location, count, value}; location 0 means the
 * value is inline).  Returns 1 and *val when found, else 0. */
int td_georef_geokey(const td_georef *g, int key, int *val)
{
    size_t i, nkeys;
    if (!g || !g->geokeys || g->n_geokeys < 4)
        return 0;
    nkeys = g->geokeys[3];
    for (i = 0; i < nkeys && 4 + 4 * i + 3 < g->n_geokeys; i++) {
        const uint16_t *e = g->geokeys + 4 + 4 * i;
        if (e[0] == key && e[1] == 0 && e[2] == 1) {
            *val = e[3];
            return 1;
        }
    }
    return 0;
}

/* A counted array tag; the count's width depends on how the tag was
 * registered (TIFF_VARIABLE: uint16, TIFF_VARIABLE2: uint32). */
static int get_array(TIFF *tif, uint32_t tag, void *ptr, uint32_t *n)
{
    const TIFFField *f = TIFFFindField(tif, tag, TIFF_ANY);
    *n = 0;
    if (!f || !TIFFFieldPassCount(f))
        return 0;
    if (TIFFFieldReadCount(f) == TIFF_VARIABLE2) {
        uint32_t c = 0;
        if (!TIFFGetField(tif, tag, &c, ptr))
            return 0;
        *n = c;
    } else {
        uint16_t c = 0;
        if (!TIFFGetField(tif, tag, &c, ptr))
            return 0;
        *n = c;
    }
    return *n > 0;
}

/* Copy the verbatim key directory, double and ASCII parameters. */
static int keep_keys(TIFF *tif, td_georef *g, td_ctx *cx)
{
    uint16_t *keys = NULL;
    double *dbl = NULL;
    char *asc = NULL;
    uint32_t n;
    const TIFFField *f;
    if (get_array(tif, TIFFTAG_GEOKEYDIRECTORY, &keys, &n) && keys) {
        if (!(g->geokeys = td_malloc(n * sizeof *keys, cx)))
            return TD_ENOMEM;
        memcpy(g->geokeys, keys, n * sizeof *keys);
        g->n_geokeys = n;
    }
    if (get_array(tif, TIFFTAG_GEODOUBLEPARAMS, &dbl, &n) && dbl) {
        if (!(g->geodoubles = td_malloc(n * sizeof *dbl, cx)))
            return TD_ENOMEM;
        memcpy(g->geodoubles, dbl, n * sizeof *dbl);
        g->n_geodoubles = n;
    }
    f = TIFFFindField(tif, TIFFTAG_GEOASCIIPARAMS, TIFF_ANY);
    if (f && !TIFFFieldPassCount(f) &&
        TIFFGetField(tif, TIFFTAG_GEOASCIIPARAMS, &asc) && asc) {
        size_t len = strlen(asc) + 1;
        if (!(g->geoascii = td_malloc(len, cx)))
            return TD_ENOMEM;
        memcpy(g->geoascii, asc, len);
    }
    return 0;
}

/* gt from ModelTiepoint + ModelPixelScale, else ModelTransformation. */
static void read_transform(TIFF *tif, td_georef *g)
{
    double *tp = NULL, *sc = NULL, *m = NULL;
    uint32_t ntp = 0, nsc = 0, nm = 0;
    get_array(tif, TIFFTAG_GEOTIEPOINTS, &tp, &ntp);
    get_array(tif, TIFFTAG_GEOPIXELSCALE, &sc, &nsc);
    get_array(tif, TIFFTAG_GEOTRANSMATRIX, &m, &nm);
    if (tp && sc && ntp >= 6 && nsc >= 2) {
        g->gt[1] = sc[0];
        g->gt[2] = 0.0;
        g->gt[4] = 0.0;
        g->gt[5] = -sc[1];
        g->gt[0] = tp[3] - tp[0] * sc[0];
        g->gt[3] = tp[4] + tp[1] * sc[1];
        g->valid = 1;
    } else if (m && nm >= 16) {
        g->gt[0] = m[3];
        g->gt[1] = m[0];
        g->gt[2] = m[1];
        g->gt[3] = m[7];
        g->gt[4] = m[4];
        g->gt[5] = m[5];
        g->valid = 1;
    }
    if (g->valid && (!isfinite(g->gt[0]) || !isfinite(g->gt[3]) ||
                     g->gt[1] * g->gt[5] - g->gt[2] * g->gt[4] == 0.0 ||
                     !isfinite(g->gt[1] * g->gt[5] - g->gt[2] * g->gt[4])))
        g->valid = 0;
}

/* See io_int.h.  PixelIsPoint rasters are shifted by half a pixel so
 * gt describes pixel corners, as GDAL does. */
int td_georef_from_tiff(TIFF *tif, td_georef *g, td_ctx *cx)
{
    int v, rc;
    td_georef_clear(g);
    if ((rc = keep_keys(tif, g, cx)) != 0)
        goto fail;
    read_transform(tif, g);
    if (g->valid && td_georef_geokey(g, KEY_RASTERTYPE, &v) &&
        v == RASTER_PIXELISPOINT) {
        g->gt[0] -= 0.5 * g->gt[1] + 0.5 * g->gt[2];
        g->gt[3] -= 0.5 * g->gt[4] + 0.5 * g->gt[5];
    }
    if (g->valid && g->geoascii && strstr(g->geoascii, TD_PIXEL_CRS) &&
        g->gt[0] == 0.0 && g->gt[3] == 0.0 && g->gt[2] == 0.0 &&
        g->gt[4] == 0.0 && g->gt[1] == -g->gt[5])
        g->pixel = 1; /* a piece cut from such a sheet (gdal_translate
                         -srcwin) keeps the sheet's frame: map units */
    if (td_georef_geokey(g, KEY_PROJECTED, &v) && v >= 1 && v <= 32766)
        g->epsg = v;
    else if (td_georef_geokey(g, KEY_GEOGRAPHIC, &v) && v >= 1 && v <= 32766)
        g->epsg = v;
    return 0;
fail:
    td_georef_clear(g);
    return rc;
}

/* A minimal key directory for an EPSG code (codes 4000..4999 are taken as
 * geographic CRSs, the rest as projected) or, with epsg 0, the raster type
 * only. */
static void write_epsg_keys(TIFF *tif, int epsg)
{
    uint16_t k[16] = {1, 1, 0, 1, KEY_RASTERTYPE, 0, 1, 1};
    int geographic = epsg >= 4000 && epsg <= 4999;
    if (epsg > 0 && epsg <= 32766) {
        uint16_t e[12] = {KEY_MODELTYPE, 0, 1, (uint16_t)(geographic ? 2 : 1),
                          KEY_RASTERTYPE, 0, 1, 1,
                          (uint16_t)(geographic ? KEY_GEOGRAPHIC
                                                : KEY_PROJECTED),
                          0, 1, (uint16_t)epsg};
        k[3] = 3;
        memcpy(k + 4, e, sizeof e);
    }
    TIFFSetField(tif, TIFFTAG_GEOKEYDIRECTORY, (int)(4 + 4 * k[3]), k);
}

/* The pixel frame's keys: PixelIsArea and the engineering CRS's name as
 * the citation (GDAL reads it as ENGCRS["topodig scan pixels"]). */
static void write_pixel_keys(TIFF *tif)
{
    static const char cit[] = TD_PIXEL_CRS "|";
    uint16_t k[12] = {1, 1, 0, 2, KEY_RASTERTYPE, 0, 1, 1,
                      KEY_CITATION, TIFFTAG_GEOASCIIPARAMS,
                      (uint16_t)(sizeof cit - 1), 0};
    TIFFSetField(tif, TIFFTAG_GEOKEYDIRECTORY, 12, k);
    TIFFSetField(tif, TIFFTAG_GEOASCIIPARAMS, cit);
}

/* See io_int.h.  Keys are written verbatim when present; the
 * transform as scale + tiepoint when it is north-up without rotation,
 * else as a matrix
 * (undoing the PixelIsPoint half-pixel shift of the reader). */
int td_georef_to_tiff(TIFF *tif, const td_georef *g, td_ctx *cx)
{
    double gt[6];
    int v;
    td_georef pf;
    if (!g || !g->valid) {
        td_georef_init(&pf);
        td_georef_pixel_frame(&pf);
        g = &pf;
    }
    memcpy(gt, g->gt, sizeof gt);
    if (td_georef_geokey(g, KEY_RASTERTYPE, &v) && v == RASTER_PIXELISPOINT) {
        gt[0] += 0.5 * gt[1] + 0.5 * gt[2];
        gt[3] += 0.5 * gt[4] + 0.5 * gt[5];
    }
    if (g->valid && gt[2] == 0.0 && gt[4] == 0.0 && gt[1] > 0.0 &&
        gt[5] < 0.0) {
        double sc[3] = {gt[1], -gt[5], 0.0};
        double tp[6] = {0.0, 0.0, 0.0, gt[0], gt[3], 0.0};
        TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, 3, sc);
        TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, 6, tp);
    } else if (g->valid) {
        double m[16] = {gt[1], gt[2], 0, gt[0], gt[4], gt[5], 0, gt[3],
                        0,     0,     0, 0,     0,     0,     0, 1};
        TIFFSetField(tif, TIFFTAG_GEOTRANSMATRIX, 16, m);
    }
    if (g->geokeys && g->n_geokeys >= 4 && g->n_geokeys <= 65535) {
        TIFFSetField(tif, TIFFTAG_GEOKEYDIRECTORY, (int)g->n_geokeys,
                     g->geokeys);
        if (g->geodoubles && g->n_geodoubles && g->n_geodoubles <= 65535)
            TIFFSetField(tif, TIFFTAG_GEODOUBLEPARAMS, (int)g->n_geodoubles,
                         g->geodoubles);
        if (g->geoascii && *g->geoascii)
            TIFFSetField(tif, TIFFTAG_GEOASCIIPARAMS, g->geoascii);
    } else if (g->pixel) {
        write_pixel_keys(tif);
    } else {
        write_epsg_keys(tif, g->epsg);
    }
    return 0;
}

/* See imageio.h. */
int td_georef_read(const char *path, td_georef *g, td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    TIFF *tif;
    int rc;
    td_georef_init(g);
    if (!path)
        return td_seterr(cx, TD_EINVAL, "no input file name given");
    tif = td_tiff_open(path, -1, "rm", &e);
    if (!tif)
        return td_tiff_fail(cx, TD_EFORMAT, path, "not a readable TIFF", &e);
    rc = td_georef_from_tiff(tif, g, cx);
    TIFFClose(tif);
    return rc;
}

/* See imageio.h. */
void td_georef_scale(td_georef *g, int step)
{
    int k;
    if (!g->valid)
        td_georef_pixel_frame(g);
    if (step <= 1)
        return;
    for (k = 1; k < 6; k++)
        if (k != 3)
            g->gt[k] *= step;
}

/* See io.h. */
void td_georef_crs_json(const td_georef *g, char *buf, size_t n)
{
    static const char head[] = "\"crs\":{\"type\":\"name\",\"properties\":"
                               "{\"name\":";
    if (g && g->valid && !g->pixel && g->epsg > 0)
        snprintf(buf, n, "%s\"urn:ogc:def:crs:EPSG::%d\"}}", head, g->epsg);
    else
        snprintf(buf, n, "%s\"LOCAL_CS[\\\"%s\\\",UNIT[\\\"%s\\\",1],"
                 "AXIS[\\\"X\\\",EAST],AXIS[\\\"Y\\\",NORTH]]\"}}", head,
                 g && g->valid && !g->pixel ? "the scan's CRS (not named in it)"
                                            : TD_PIXEL_CRS,
                 g && g->valid && !g->pixel ? "unknown" : "pixel");
}

/* See io.h. */
double td_georef_cell_size(const td_georef *g, int w, int h, int *geographic)
{
    const double deg = 111319.49; /* metres per degree on the equator */
    double sx, sy, X, lat;
    int model = 0;
    if (geographic)
        *geographic = 0;
    if (!g || !g->valid || g->pixel)
        return 0.0;
    sx = hypot(g->gt[1], g->gt[4]);
    sy = hypot(g->gt[2], g->gt[5]);
    if (!(sx > 0) || !(sy > 0) || !isfinite(sx) || !isfinite(sy))
        return 0.0;
    if (td_georef_geokey(g, KEY_MODELTYPE, &model) && model == 2) {
        td_georef_apply(g, 0.5 * w, 0.5 * h, &X, &lat);
        if (!(fabs(lat) < 90.0))
            return 0.0;
        sx *= deg * cos(lat * M_PI / 180.0);
        sy *= deg;
        if (geographic)
            *geographic = 1;
    }
    return 0.5 * (sx + sy);
}
