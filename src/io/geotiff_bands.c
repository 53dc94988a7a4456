/* geotiff_bands.c: a multi-band float32 GeoTIFF writer on the core's
 * libtiff wrapper (io_int.h) and atomic files (imageio.h). */
#define _POSIX_C_SOURCE 200809L
#include "src/io/io.h"

#include "src/io/io_int.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static TIFFFieldInfo bands_nodata_field[] = {
    {42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, "GDALNoDataValue"}};

/* Baseline tags for n separate float32 planes of w x h, rps rows a strip,
 * and GDAL_NODATA. */
static int set_tags(TIFF *tif, const td_grid_f32 *b0, int n, uint32_t rps)
{
    int ok = 1;
    ok &= TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, (uint32_t)b0->w);
    ok &= TIFFSetField(tif, TIFFTAG_IMAGELENGTH, (uint32_t)b0->h);
    ok &= TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, (uint16_t)n);
    ok &= TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 32);
    ok &= TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
    ok &= TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    ok &= TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_SEPARATE);
    ok &= TIFFSetField(tif, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
    ok &= TIFFSetField(tif, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);
    ok &= TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, rps);
    if (n > 1) {
        uint16_t *ex = calloc((size_t)n - 1, sizeof *ex);
        if (!ex)
            return -1;
        ok &= TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, (uint16_t)(n - 1), ex);
        free(ex);
    }
    if (b0->has_nodata) {
        char s[64];
        if (isnan(b0->nodata))
            snprintf(s, sizeof s, "nan");
        else
            snprintf(s, sizeof s, "%.9g", (double)b0->nodata);
        ok &= TIFFMergeFieldInfo(tif, bands_nodata_field, 1) == 0;
        ok &= TIFFSetField(tif, 42113, s);
    }
    return ok ? 0 : -1;
}

/* Encode every strip of every plane. */
static int write_planes(TIFF *tif, td_grid_f32 *const *bands, int n,
                        int rps, float *buf, td_ctx *cx)
{
    int b, y, r, rc;
    for (b = 0; b < n; b++) {
        const td_grid_f32 *g = bands[b];
        for (y = 0; y < g->h; y += rps) {
            int rows = g->h - y < rps ? g->h - y : rps;
            for (r = 0; r < rows; r++)
                memcpy(buf + (size_t)r * g->w,
                       g->data + (size_t)(y + r) * g->stride,
                       sizeof(float) * (size_t)g->w);
            if (TIFFWriteEncodedStrip(tif, TIFFComputeStrip(tif, (uint32_t)y,
                                                            (uint16_t)b),
                                      buf, (tmsize_t)rows * g->w * 4) < 0)
                return TD_EIO;
        }
        if ((rc = td_progress(cx, "write", (double)(b + 1) / n)) != 0)
            return rc;
    }
    return 0;
}

static int check_bands(const char *path, td_grid_f32 *const *bands, int n,
                       td_ctx *cx)
{
    int i;
    if (!path || !bands || n < 1 || n > 65535)
        return td_seterr(cx, TD_EINVAL, "%s: no bands to write",
                         path ? path : "(null)");
    for (i = 0; i < n; i++)
        if (!bands[i] || !bands[i]->data || bands[i]->w != bands[0]->w ||
            bands[i]->h != bands[0]->h || bands[i]->stride < (size_t)bands[i]->w)
            return td_seterr(cx, TD_EINVAL, "%s: band %d missing or of "
                             "another size", path, i + 1);
    return td_check_dims(bands[0]->w, bands[0]->h, path, cx);
}

/* See geotiff_bands.h. */
int td_geotiff_write_bands_f32(const char *path, td_grid_f32 *const *bands,
                               int n, const td_georef *georef, td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    char *tmp = NULL;
    size_t tmpsize;
    FILE *f = NULL;
    TIFF *tif = NULL;
    float *buf = NULL;
    int rc, rps, fd, big;
    if ((rc = check_bands(path, bands, n, cx)) != 0)
        return rc;
    big = (double)bands[0]->w * bands[0]->h * 4.0 * n > 2e9;
    rps = (int)(262144 / ((size_t)bands[0]->w * 4));
    rps = rps < 1 ? 1 : rps > bands[0]->h ? bands[0]->h : rps;
    tmpsize = strlen(path) + 32;
    rc = TD_ENOMEM;
    if (!(tmp = td_malloc(tmpsize, cx)) ||
        !(buf = td_malloc(sizeof(float) * (size_t)rps * bands[0]->w, cx)))
        goto fail;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto fail;
    }
    rc = TD_EIO;
    fd = dup(fileno(f));
    if (!(tif = fd < 0 ? NULL : td_tiff_open(path, fd, big ? "w8" : "w", &e))) {
        td_tiff_fail(cx, rc, path, "cannot write TIFF", &e);
        goto fail;
    }
    if (set_tags(tif, bands[0], n, (uint32_t)rps) != 0 ||
        td_georef_to_tiff(tif, georef, cx) != 0 ||
        (rc = write_planes(tif, bands, n, rps, buf, cx)) != 0 ||
        !TIFFWriteDirectory(tif) || e.count) {
        rc = rc ? rc : TD_EIO;
        td_tiff_fail(cx, rc, path, "cannot write TIFF", &e);
        goto fail;
    }
    TIFFClose(tif);
    tif = NULL;
    rc = e.count ? td_tiff_fail(cx, TD_EIO, path, "cannot write TIFF", &e)
                 : td_atomic_commit(f, tmp, path, cx);
    f = NULL;
    if (rc != 0)
        remove(tmp);
fail:
    if (tif)
        TIFFClose(tif);
    if (f)
        td_atomic_abort(f, tmp);
    free(buf);
    free(tmp);
    return rc;
}
