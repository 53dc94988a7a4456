/* demio.c: DEM grids from and to files.
 *
 * Readers: single-band TIFF/GeoTIFF of any integer or float sample type
 * (through libtiff, block by block, converted to float32 as they come) and
 * ESRI ASCII grids (a streaming tokenizer, so a grid is never held twice).
 * Writers: ESRI ASCII grid, 16-bit PNG, float32 GeoTIFF (tiffio.c). */
#include "src/io/io.h"
#include "src/io/io_int.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

enum { ND_DEFAULT = -9999, ASC_BUF = 1 << 20, TOK_MAX = 128 };

/* ---- numbers ------------------------------------------------------------ */

static const double pow10d[23] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

/* Parse the whole NUL-terminated token s as a number into *v: a fast exact
 * path for plain decimals (at most 15 digits, so < 2^53; at most 22 decimals: one
 * correctly rounded division, as strtod would give), strtod otherwise
 * (exponents, "nan", "inf").  Returns 0, or -1 when s is not a number. */
static int parse_num(const char *s, double *v)
{
    const char *p = s;
    uint64_t m = 0;
    int neg = 0, nd = 0, dec = 0;
    char *end;
    if (*p == '-' || *p == '+')
        neg = *p++ == '-';
    for (; *p >= '0' && *p <= '9' && nd < 15; p++, nd++)
        m = m * 10 + (uint64_t)(*p - '0');
    if (*p == '.')
        for (p++; *p >= '0' && *p <= '9' && nd < 15; p++, nd++, dec++)
            m = m * 10 + (uint64_t)(*p - '0');
    if (*p == '\0' && nd > 0 && dec <= 22) {
        double d = (double)m / pow10d[dec];
        *v = neg ? -d : d;
        return 0;
    }
    errno = 0;
    *v = strtod(s, &end);
    return end == s || *end != '\0' ? -1 : 0;
}

/* ---- TIFF --------------------------------------------------------------- */

/* Sample layout of a DEM TIFF. */
typedef struct dem_tiff {
    uint32_t w, h;
    uint16_t bps, fmt;   /* bits per sample, SAMPLEFORMAT_* */
    int has_nd;          /* the GDAL_NODATA tag is present */
    double nd;           /* its value (may be NaN) */
    float out_nd;        /* what nodata cells become in the grid */
    int saw_nan;
} dem_tiff;

/* The GDAL_NODATA tag (ASCII): libtiff registers unknown tags as counted
 * anonymous fields, a writer that merged the tag as uncounted. */
static int read_nodata(TIFF *tif, dem_tiff *D, const char *path, td_ctx *cx)
{
    const TIFFField *f = TIFFFindField(tif, TIFFTAG_GDAL_NODATA, TIFF_ANY);
    char *s = NULL, tok[TOK_MAX];
    size_t n;
    int ok = 0;
    if (!f)
        return 0;
    if (!TIFFFieldPassCount(f)) {
        ok = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &s);
        n = s ? strlen(s) : 0;
    } else if (TIFFFieldReadCount(f) == TIFF_VARIABLE2) {
        uint32_t c = 0;
        ok = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &c, &s);
        n = c;
    } else {
        uint16_t c = 0;
        ok = TIFFGetField(tif, TIFFTAG_GDAL_NODATA, &c, &s);
        n = c;
    }
    if (!ok || !s)
        return 0;
    while (n > 0 && isspace((unsigned char)*s))
        s++, n--;
    while (n > 0 && (s[n - 1] == '\0' || isspace((unsigned char)s[n - 1])))
        n--;
    if (n == 0 || n >= sizeof tok)
        return td_seterr(cx, TD_EFORMAT, "%s: bad GDAL_NODATA tag", path);
    memcpy(tok, s, n);
    tok[n] = '\0';
    if (parse_num(tok, &D->nd) != 0)
        return td_seterr(cx, TD_EFORMAT, "%s: bad GDAL_NODATA value '%s'",
                         path, tok);
    D->has_nd = 1;
    return 0;
}

/* Size, band count and sample type; errors for anything but one band of
 * a supported type. */
static int dem_layout(TIFF *tif, dem_tiff *D, const char *path, td_ctx *cx)
{
    uint16_t spp = 1, photo = PHOTOMETRIC_MINISBLACK;
    int rc, ok;
    memset(D, 0, sizeof *D);
    if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &D->w) ||
        !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &D->h))
        return td_seterr(cx, TD_EFORMAT, "%s: TIFF without image size", path);
    if ((rc = td_check_dims((long)D->w, (long)D->h, path, cx)) != 0)
        return rc;
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
    TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &D->bps);
    TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &D->fmt);
    TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photo);
    if (spp != 1)
        return td_seterr(cx, TD_EFORMAT, "%s: %u bands; a DEM has one", path,
                         (unsigned)spp);
    if (photo == PHOTOMETRIC_PALETTE)
        return td_seterr(cx, TD_EFORMAT, "%s: a palette (colour) image is "
                         "not a DEM", path);
    if (D->fmt == SAMPLEFORMAT_VOID)
        D->fmt = SAMPLEFORMAT_UINT;
    ok = D->fmt == SAMPLEFORMAT_IEEEFP
             ? D->bps == 32 || D->bps == 64
             : (D->fmt == SAMPLEFORMAT_UINT || D->fmt == SAMPLEFORMAT_INT) &&
                   (D->bps == 8 || D->bps == 16 || D->bps == 32);
    if (!ok)
        return td_seterr(cx, TD_EFORMAT, "%s: unsupported DEM sample type "
                         "(%u-bit, sample format %u)", path, (unsigned)D->bps,
                         (unsigned)D->fmt);
    if ((rc = read_nodata(tif, D, path, cx)) != 0)
        return rc;
    D->out_nd = D->has_nd && isfinite(D->nd) && fabs(D->nd) <= FLT_MAX
                    ? (float)D->nd : (float)ND_DEFAULT;
    return 0;
}

/* Sample i of a decoded row as a double (native byte order). */
static double sample_at(const dem_tiff *D, const uint8_t *row, size_t i)
{
    switch (D->bps * 4 + D->fmt) {
#define S(bits, f, T)                                                        \
    case bits * 4 + f: {                                                     \
        T v;                                                                 \
        memcpy(&v, row + i * sizeof v, sizeof v);                            \
        return (double)v;                                                    \
    }
        S(8, SAMPLEFORMAT_UINT, uint8_t)
        S(8, SAMPLEFORMAT_INT, int8_t)
        S(16, SAMPLEFORMAT_UINT, uint16_t)
        S(16, SAMPLEFORMAT_INT, int16_t)
        S(32, SAMPLEFORMAT_UINT, uint32_t)
        S(32, SAMPLEFORMAT_INT, int32_t)
        S(32, SAMPLEFORMAT_IEEEFP, float)
        S(64, SAMPLEFORMAT_IEEEFP, double)
#undef S
    }
    return NAN;
}

/* One decoded row of n samples into out; nodata and NaN -> D->out_nd. */
static void convert_row(dem_tiff *D, const uint8_t *src, float *out, size_t n)
{
    size_t i;
    int f32 = D->bps == 32 && D->fmt == SAMPLEFORMAT_IEEEFP;
    float ndf = (float)D->nd;
    for (i = 0; i < n; i++) {
        double v = sample_at(D, src, i);
        if (isnan(v)) {
            D->saw_nan = 1;
            out[i] = D->out_nd;
        } else if (D->has_nd && (v == D->nd || (f32 && (float)v == ndf))) {
            out[i] = D->out_nd;
        } else {
            out[i] = (float)v;
        }
    }
}

/* Decode every strip or tile into g. */
static int dem_pixels(TIFF *tif, dem_tiff *D, td_grid_f32 *g,
                      const char *path, td_tiff_err *e, td_ctx *cx)
{
    int tiled = TIFFIsTiled(tif), rc = 0;
    uint32_t bw = D->w, bh = D->h, x, y, r;
    tmsize_t rowbytes, size;
    uint8_t *buf = NULL;
    if (tiled) {
        if (!TIFFGetField(tif, TIFFTAG_TILEWIDTH, &bw) ||
            !TIFFGetField(tif, TIFFTAG_TILELENGTH, &bh))
            bw = bh = 0;
        rowbytes = TIFFTileRowSize(tif);
        size = TIFFTileSize(tif);
    } else {
        TIFFGetFieldDefaulted(tif, TIFFTAG_ROWSPERSTRIP, &bh);
        bh = bh == 0 || bh > D->h ? D->h : bh;
        rowbytes = TIFFScanlineSize(tif);
        size = TIFFStripSize(tif);
    }
    if (bw == 0 || bh == 0 || rowbytes <= 0 || size <= 0 ||
        size / rowbytes < (tmsize_t)bh ||
        (uint64_t)rowbytes < (uint64_t)bw * (D->bps / 8))
        return td_seterr(cx, TD_EFORMAT, "%s: inconsistent TIFF block "
                         "layout", path);
    if (!(buf = td_calloc((size_t)size, 1, cx)))
        return TD_ENOMEM;
    for (y = 0; y < D->h; y += bh) {
        uint32_t rows = D->h - y < bh ? D->h - y : bh;
        for (x = 0; x < D->w; x += bw) {
            uint32_t cols = D->w - x < bw ? D->w - x : bw;
            tmsize_t got = tiled
                ? TIFFReadEncodedTile(tif, TIFFComputeTile(tif, x, y, 0, 0),
                                      buf, size)
                : TIFFReadEncodedStrip(tif, TIFFComputeStrip(tif, y, 0), buf,
                                       size);
            if (got < 0) {
                rc = td_tiff_fail(cx, TD_EFORMAT, path,
                                  "corrupt or truncated image data", e);
                goto fail;
            }
            for (r = 0; r < rows; r++)
                convert_row(D, buf + (size_t)r * (size_t)rowbytes,
                            &TD_AT(g, x, y + r), cols);
        }
        if ((rc = td_progress(cx, "read", (double)(y + rows) / D->h)) != 0)
            goto fail;
    }
fail:
    free(buf);
    return rc;
}

/* A TIFF DEM; georef (initialised by the caller) is filled on success. */
static int tiff_dem_read(const char *path, td_grid_f32 **out,
                         td_georef *georef, td_ctx *cx)
{
    td_tiff_err e = {{0}, 0};
    td_grid_f32 *g = NULL;
    td_georef gr;
    dem_tiff D;
    int rc;
    TIFF *tif = td_tiff_open(path, -1, "rm", &e);
    td_georef_init(&gr);
    if (!tif)
        return td_tiff_fail(cx, TD_EFORMAT, path, "corrupt or truncated TIFF",
                            &e);
    if ((rc = dem_layout(tif, &D, path, cx)) != 0)
        goto fail;
    if ((georef && (rc = td_georef_from_tiff(tif, &gr, cx)) != 0) ||
        (rc = td_tiff_check_data(tif, path, cx)) != 0)
        goto fail;
    if (!(g = td_grid_f32_new((int)D.w, (int)D.h, cx))) {
        rc = cx && cx->code ? cx->code : TD_ENOMEM;
        goto fail;
    }
    if ((rc = dem_pixels(tif, &D, g, path, &e, cx)) != 0)
        goto fail;
    g->nodata = D.out_nd;
    g->has_nodata = D.has_nd || D.saw_nan;
    TIFFClose(tif);
    if (georef)
        *georef = gr;
    *out = g;
    return 0;
fail:
    TIFFClose(tif);
    td_grid_f32_free(g);
    td_georef_clear(&gr);
    return rc;
}

/* ---- ESRI ASCII grid: reading ------------------------------------------ */

/* A whitespace tokenizer over a FILE with a line count. */
typedef struct asc_in {
    FILE *f;
    char *buf;
    size_t pos, len;
    long line;
    int eof;
    char tok[TOK_MAX];
    long tok_line;
    int pushed;     /* tok holds a token to be returned again */
} asc_in;

static int asc_fill(asc_in *a)
{
    if (a->eof)
        return 0;
    a->len = fread(a->buf, 1, ASC_BUF, a->f);
    a->pos = 0;
    if (a->len == 0)
        a->eof = 1;
    return a->len > 0;
}

/* The next token into a->tok: 1, 0 at the end of the file, -1 when a
 * token is longer than TOK_MAX - 1. */
static int asc_next(asc_in *a)
{
    size_t n = 0;
    if (a->pushed) {
        a->pushed = 0;
        return 1;
    }
    for (;;) {
        if (a->pos == a->len && !asc_fill(a))
            return 0;
        if (a->buf[a->pos] == '\n')
            a->line++;
        else if (!isspace((unsigned char)a->buf[a->pos]))
            break;
        a->pos++;
    }
    a->tok_line = a->line;
    for (;;) {
        char c;
        if (a->pos == a->len && !asc_fill(a))
            break;
        c = a->buf[a->pos];
        if (isspace((unsigned char)c))
            break;
        if (n + 1 >= TOK_MAX)
            return -1;
        a->tok[n++] = c;
        a->pos++;
    }
    a->tok[n] = '\0';
    return 1;
}

/* The header values of an ESRI ASCII grid. */
typedef struct asc_head {
    long ncols, nrows;
    double xll, yll, dx, dy, nodata;
    int has_x, has_y, x_center, y_center, has_nodata;
} asc_head;

/* Store the value of header key `key` (lower case). */
static int asc_key(asc_head *H, const char *key, double v)
{
    if (!strcmp(key, "ncols") || !strcmp(key, "nrows")) {
        long n = v >= 0 && v <= 2e9 && v == floor(v) ? (long)v : -1;
        *(key[1] == 'c' ? &H->ncols : &H->nrows) = n;
    } else if (!strcmp(key, "xllcorner") || !strcmp(key, "xllcenter")) {
        H->xll = v, H->has_x = 1, H->x_center = key[4] == 'e';
    } else if (!strcmp(key, "yllcorner") || !strcmp(key, "yllcenter")) {
        H->yll = v, H->has_y = 1, H->y_center = key[4] == 'e';
    } else if (!strcmp(key, "cellsize")) {
        H->dx = H->dy = v;
    } else if (!strcmp(key, "dx")) {
        H->dx = v;
    } else if (!strcmp(key, "dy")) {
        H->dy = v;
    } else if (!strcmp(key, "nodata_value")) {
        H->nodata = v, H->has_nodata = 1;
    } else {
        return -1;
    }
    return 0;
}

/* Header lines up to the first value (left pushed back in a). */
static int asc_header(asc_in *a, asc_head *H, const char *path, td_ctx *cx)
{
    int r, i;
    memset(H, 0, sizeof *H);
    H->ncols = H->nrows = -1;
    while ((r = asc_next(a)) == 1 && isalpha((unsigned char)a->tok[0]) &&
           strcasecmp(a->tok, "nan") != 0) {
        char key[TOK_MAX];
        double v;
        long kl = a->tok_line;
        for (i = 0; a->tok[i]; i++)
            key[i] = (char)tolower((unsigned char)a->tok[i]);
        key[i] = '\0';
        if (asc_next(a) != 1 || parse_num(a->tok, &v) != 0 || !isfinite(v))
            return td_seterr(cx, TD_EFORMAT, "%s: line %ld: header key '%s' "
                             "without a number", path, kl + 1, key);
        if (asc_key(H, key, v) != 0)
            return td_seterr(cx, TD_EFORMAT, "%s: line %ld: unknown header "
                             "key '%s'", path, kl + 1, key);
    }
    if (r == -1)
        return td_seterr(cx, TD_EFORMAT, "%s: line %ld: token too long",
                         path, a->line + 1);
    a->pushed = r == 1;
    if (H->ncols < 0 || H->nrows < 0 || !H->has_x || !H->has_y ||
        !(H->dx > 0) || !(H->dy > 0))
        return td_seterr(cx, TD_EFORMAT, "%s: incomplete ESRI ASCII grid "
                         "header (needs ncols, nrows, xllcorner, yllcorner, "
                         "cellsize > 0)", path);
    return td_check_dims(H->ncols, H->nrows, path, cx);
}

/* Every value, row 0 first (the top row). */
static int asc_values(asc_in *a, const asc_head *H, td_grid_f32 *g,
                      const char *path, td_ctx *cx)
{
    size_t i, n = (size_t)H->ncols * (size_t)H->nrows;
    float nd = H->has_nodata ? (float)H->nodata : (float)ND_DEFAULT;
    int r, saw_nan = 0, rc;
    for (i = 0; i < n; i++) {
        double v;
        if ((r = asc_next(a)) != 1)
            return r == 0 ? td_seterr(cx, TD_EFORMAT, "%s: line %ld: "
                                      "truncated: %zu of %zu values", path,
                                      a->tok_line + 1, i, n)
                          : td_seterr(cx, TD_EFORMAT, "%s: line %ld: token "
                                      "too long", path, a->line + 1);
        if (parse_num(a->tok, &v) != 0)
            return td_seterr(cx, TD_EFORMAT, "%s: line %ld: '%s' is not a "
                             "number", path, a->tok_line + 1, a->tok);
        if (isnan(v) || (H->has_nodata && v == H->nodata)) {
            saw_nan |= isnan(v);
            g->data[i] = nd;
        } else {
            g->data[i] = (float)v;
        }
        if ((i & 0xfffff) == 0xfffff &&
            (rc = td_progress(cx, "read", (double)i / n)) != 0)
            return rc;
    }
    if ((r = asc_next(a)) == 1) /* more values than the header says */
        return td_seterr(cx, TD_EFORMAT, "%s: line %ld: more than the %zu "
                         "values ncols x nrows give ('%s')", path,
                         a->tok_line + 1, n, a->tok);
    g->nodata = nd;
    g->has_nodata = H->has_nodata || saw_nan;
    return 0;
}

/* An ESRI ASCII grid (f is open at its start; closed by the caller). */
static int asc_read(FILE *f, const char *path, td_grid_f32 **out,
                    td_georef *georef, td_ctx *cx)
{
    asc_in a;
    asc_head H;
    td_grid_f32 *g = NULL;
    int rc;
    memset(&a, 0, sizeof a);
    a.f = f;
    if (!(a.buf = td_malloc(ASC_BUF, cx)))
        return TD_ENOMEM;
    if ((rc = asc_header(&a, &H, path, cx)) != 0)
        goto fail;
    if (!(g = td_grid_f32_new((int)H.ncols, (int)H.nrows, cx))) {
        rc = cx && cx->code ? cx->code : TD_ENOMEM;
        goto fail;
    }
    if ((rc = asc_values(&a, &H, g, path, cx)) != 0)
        goto fail;
    if (ferror(f)) {
        rc = td_seterr(cx, TD_EIO, "%s: read error", path);
        goto fail;
    }
    if (georef) {
        georef->valid = 1;
        georef->gt[1] = H.dx;
        georef->gt[5] = -H.dy;
        georef->gt[0] = H.xll - (H.x_center ? 0.5 * H.dx : 0.0);
        georef->gt[3] = H.yll - (H.y_center ? 0.5 * H.dy : 0.0) +
                        (double)H.nrows * H.dy;
        /* the pixel frame as td_dem_write puts it: a plain scan's DEM */
        georef->pixel = georef->gt[0] == 0.0 && georef->gt[3] == 0.0 &&
                        georef->gt[1] == -georef->gt[5];
    }
    *out = g;
    g = NULL;
fail:
    td_grid_f32_free(g);
    free(a.buf);
    return rc;
}

/* See demio.h.  The format is found from the first bytes: a TIFF magic
 * number, else a header key of an ESRI ASCII grid. */
int td_dem_read(const char *path, td_grid_f32 **out, td_georef *georef,
                td_ctx *cx)
{
    unsigned char m[16];
    char word[16];
    size_t n, i = 0, k = 0;
    FILE *f;
    int rc;
    if (georef)
        td_georef_init(georef);
    if (!path || !out)
        return td_seterr(cx, TD_EINVAL, "no DEM file name given");
    *out = NULL;
    if ((rc = td_check_input(path, cx)) != 0)
        return rc;
    if (!(f = fopen(path, "rb")))
        return td_seterr(cx, TD_EIO, "%s: cannot open: %s", path,
                         strerror(errno));
    n = fread(m, 1, sizeof m, f);
    if (n >= 4 && ((m[0] == 'I' && m[1] == 'I' && (m[2] == 42 || m[2] == 43)
                    && m[3] == 0) ||
                   (m[0] == 'M' && m[1] == 'M' && m[2] == 0 &&
                    (m[3] == 42 || m[3] == 43)))) {
        fclose(f);
        return tiff_dem_read(path, out, georef, cx);
    }
    while (i < n && isspace(m[i]))
        i++;
    while (i < n && k + 1 < sizeof word && (isalpha(m[i]) || m[i] == '_'))
        word[k++] = (char)tolower(m[i++]);
    word[k] = '\0';
    if (k < 2 || !(!strcmp(word, "ncols") || !strcmp(word, "nrows") ||
                   !strncmp(word, "xll", 3) || !strncmp(word, "yll", 3) ||
                   !strcmp(word, "cellsize"))) {
        fclose(f);
        return td_seterr(cx, TD_EFORMAT, "%s: not a DEM (neither TIFF nor "
                         "ESRI ASCII grid)", path);
    }
    rewind(f);
    rc = asc_read(f, path, out, georef, cx);
    fclose(f);
    return rc;
}

/* ---- ESRI ASCII grid: writing ------------------------------------------ */

/* The shortest fixed-point decimal that reads back as the same float
 * (%.9g as a fallback for very large or small magnitudes) into p. */
static int fmt_float(char *p, float f)
{
    double a = fabs((double)f);
    int d;
    if (!isfinite(f) || a >= 1e15 || (a < 1e-4 && a != 0.0))
        return snprintf(p, 32, "%.9g", (double)f);
    for (d = 0; d <= 9 && a * pow10d[d] < 4e15; d++) {
        double s = pow10d[d], q = nearbyint((double)f * s);
        if ((float)(q / s) == f) {
            char *o = p;
            uint64_t u = (uint64_t)fabs(q), ip = u, fp;
            char dig[24];
            int k = 0, i;
            ip = u / (uint64_t)s;
            fp = u % (uint64_t)s;
            if (f < 0 && u)
                *o++ = '-';
            do
                dig[k++] = (char)('0' + ip % 10);
            while ((ip /= 10) != 0);
            while (k)
                *o++ = dig[--k];
            if (d > 0) {
                *o++ = '.';
                for (i = d - 1; i >= 0; i--, fp /= 10)
                    o[i] = (char)('0' + fp % 10);
                o += d;
            }
            return (int)(o - p);
        }
    }
    return snprintf(p, 32, "%.9g", (double)f);
}

/* A double as the shortest of %.15g, %.16g, %.17g that reads back. */
static void fmt_double(char *p, double v)
{
    int prec;
    for (prec = 15; prec < 17; prec++) {
        snprintf(p, 32, "%.*g", prec, v);
        if (strtod(p, NULL) == v)
            return;
    }
    snprintf(p, 32, "%.17g", v);
}

/* Header; nodata (or NaN cells without one) as NODATA_value. */
static void asc_put_header(FILE *f, const td_grid_f32 *g,
                           const td_georef *gr, int nd, float ndv)
{
    /* without georeferencing: the pixel frame (X = col, Y = -row) */
    double cs = 1.0, dy = 1.0, x0 = 0.0, y0 = -(double)g->h;
    if (gr && gr->valid && gr->gt[2] == 0.0 && gr->gt[4] == 0.0 &&
        gr->gt[1] > 0.0 && gr->gt[5] < 0.0) {
        cs = gr->gt[1];
        dy = -gr->gt[5];
        x0 = gr->gt[0];
        y0 = gr->gt[3] + (double)g->h * gr->gt[5];
    }
    char a[32], b[32];
    fmt_double(a, x0);
    fmt_double(b, y0);
    fprintf(f, "ncols %d\nnrows %d\nxllcorner %s\nyllcorner %s\n", g->w,
            g->h, a, b);
    fmt_double(a, cs);
    fmt_double(b, dy);
    if (cs == dy)
        fprintf(f, "cellsize %s\n", a);
    else
        fprintf(f, "dx %s\ndy %s\n", a, b);
    if (nd) {
        char s[40];
        s[fmt_float(s, ndv)] = '\0';
        fprintf(f, "NODATA_value %s\n", s);
    }
}

/* The rows, through a row buffer of 16 bytes per cell. */
static int asc_put_rows(FILE *f, const td_grid_f32 *g, int nd, float ndv,
                        char *line, td_ctx *cx)
{
    int x, y, rc;
    for (y = 0; y < g->h; y++) {
        const float *s = g->data + (size_t)y * g->stride;
        char *p = line;
        for (x = 0; x < g->w; x++) {
            float v = s[x];
            if (nd && (isnan(v) || (g->has_nodata && v == g->nodata)))
                v = ndv;
            if (x)
                *p++ = ' ';
            p += fmt_float(p, v);
        }
        *p++ = '\n';
        if (fwrite(line, 1, (size_t)(p - line), f) != (size_t)(p - line))
            return -1;
        if ((y & 63) == 63 &&
            (rc = td_progress(cx, "write", (double)y / g->h)) != 0)
            return rc;
    }
    return 0;
}

/* See demio.h.  Values are written as the shortest decimal that reads back
 * as the same float32; NaN cells are written as the nodata value (-9999
 * when the grid has none). */
int td_asc_write(const char *path, const td_grid_f32 *g,
                 const td_georef *georef, td_ctx *cx)
{
    char *tmp = NULL, *line = NULL;
    size_t tmpsize = (path ? strlen(path) : 0) + 32, i;
    FILE *f = NULL;
    int rc = TD_ENOMEM, nd, y;
    float ndv;
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: nothing to write",
                         path ? path : "(null)");
    if ((rc = td_check_dims(g->w, g->h, path, cx)) != 0)
        return rc;
    nd = g->has_nodata;
    for (y = 0; y < g->h && !nd; y++)
        for (i = 0; i < (size_t)g->w; i++)
            nd |= isnan(g->data[(size_t)y * g->stride + i]);
    ndv = g->has_nodata && !isnan(g->nodata) ? g->nodata : (float)ND_DEFAULT;
    rc = TD_ENOMEM;
    if (!(tmp = td_malloc(tmpsize, cx)) ||
        !(line = td_malloc((size_t)g->w * 40 + 2, cx)))
        goto fail;
    if (!(f = td_atomic_open(path, tmp, tmpsize, cx))) {
        rc = cx && cx->code ? cx->code : TD_EIO;
        goto fail;
    }
    asc_put_header(f, g, georef, nd, ndv);
    if ((rc = asc_put_rows(f, g, nd, ndv, line, cx)) != 0) {
        if (rc == -1)
            rc = td_seterr(cx, TD_EIO, "%s: write failed: %s", path,
                           strerror(errno));
        goto fail;
    }
    rc = td_atomic_commit(f, tmp, path, cx);
    f = NULL;
fail:
    if (f)
        td_atomic_abort(f, tmp);
    free(line);
    free(tmp);
    return rc;
}

/* ---- dispatch ------------------------------------------------------------ */

/* A 16-bit grey PNG: valid cells scaled linearly from min..max onto
 * 1..65535 when there are nodata cells (which become 0), else 0..65535.
 * The mapping back to heights goes into a tEXt "Comment" chunk:
 * "topodig DEM: height = LO + (value - BASE) * STEP; value 0 = nodata". */
static int png_dem_write(const char *path, const td_grid_f32 *g, td_ctx *cx)
{
    td_grid_u16 *o;
    double lo = INFINITY, hi = -INFINITY, s;
    int x, y, any_nd = 0, rc, base;
    char note[200];
    if (!(o = td_grid_u16_new(g->w, g->h, cx)))
        return cx && cx->code ? cx->code : TD_ENOMEM;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            float v = TD_AT(g, x, y);
            if (!isfinite(v) || (g->has_nodata && v == g->nodata)) {
                any_nd = 1;
                continue;
            }
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    base = any_nd ? 1 : 0;
    s = hi > lo ? (65535.0 - base) / (hi - lo) : 0.0;
    for (y = 0; y < g->h; y++)
        for (x = 0; x < g->w; x++) {
            float v = TD_AT(g, x, y);
            if (!isfinite(v) || (g->has_nodata && v == g->nodata))
                TD_AT(o, x, y) = 0;
            else
                TD_AT(o, x, y) = (uint16_t)(base + floor((v - lo) * s + 0.5));
        }
    if (lo > hi)
        lo = hi = 0;
    snprintf(note, sizeof note, "topodig DEM: height = %.9g + (value - %d) "
             "* %.9g%s", lo, base, s > 0 ? 1.0 / s : 0.0,
             any_nd ? "; value 0 = nodata" : "");
    rc = td_png_write_u16(path, o, note, cx);
    td_grid_u16_free(o);
    return rc;
}

/* Nonzero when path ends in ext (case-insensitive). */
static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), k = strlen(ext);
    return n > k && strcasecmp(path + n - k, ext) == 0;
}

/* See demio.h. */
int td_dem_write(const char *path, const td_grid_f32 *g,
                 const td_georef *georef, td_ctx *cx)
{
    if (!path || !g || !g->data || g->stride < (size_t)g->w)
        return td_seterr(cx, TD_EINVAL, "%s: nothing to write",
                         path ? path : "(null)");
    if (has_ext(path, ".asc"))
        return td_asc_write(path, g, georef, cx);
    if (has_ext(path, ".png"))
        return png_dem_write(path, g, cx);
    return td_geotiff_write_f32(path, g, georef, cx);
}
